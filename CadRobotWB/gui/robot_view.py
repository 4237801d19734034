"""The robot drawn in the 3D view with Coin nodes, outside the document.

:class:`RobotView` hangs one ``SoSeparator`` under the view's scene graph::

    CadRobotRobotView (SoSeparator)
    +-- robot (SoSeparator)
    |   +-- base (SoTransform)            robot base {R} in {U}: the cell's Placement
    |   +-- link0 .. link6 (SoSeparator)  each: SoTransform (link frame in {R}) + solid
    |                                     (link6 also holds the tool solid)
    +-- traces (SoAnnotation)             drawn over everything, unlit
        +-- TCP trace (SoLineSet)
        +-- polylines (SoSeparator)       one SoLineSet per extra polyline

The link solids come from :func:`~CadRobotWB.robots.checks.links.link_solids`
(in their link frames) and are placed by
:func:`~CadRobotWB.robots.checks.links.link_frames`, so ``set_joints(q)`` puts
link i at ``T_u_r @ link_frames(model, q)[i]``.  Nothing is added to the
document, so nothing is saved into the .FCStd; :meth:`RobotView.remove`
takes the nodes out of the view again.
"""

import numpy as np
from pivy import coin

from ..core import rotations
from ..robots.checks import links

#: Colour of the moving links (CadRobot yellow), RGB 0..1.
ROBOT_COLOR = (1.0, 0.78, 0.0)
#: Colour of the fixed base and of the flange.
DARK_COLOR = (0.22, 0.24, 0.27)
#: Colour of the tool.
TOOL_COLOR = (0.62, 0.64, 0.68)
#: Colour of the TCP trace (what the robot has drawn so far).
TRACE_COLOR = (1.0, 0.0, 1.0)
#: Colours of extra polylines, in turn (cyan, blue-violet, brown, dark green).
POLYLINE_COLORS = ((0.0, 0.75, 0.75), (0.35, 0.2, 1.0), (0.6, 0.3, 0.0), (0.0, 0.45, 0.0))

_LINK_COLORS = (DARK_COLOR,) + (ROBOT_COLOR,) * 5 + (DARK_COLOR,)
_NODE_NAME = "CadRobotRobotView"


# --- conversions ---------------------------------------------------------------------------

def set_transform(node, T):
    """Set a ``SoTransform`` to the rigid 4x4 transform `T` (mm)."""
    T = np.asarray(T, dtype=float)
    w, x, y, z = rotations.quaternion_from_matrix(T[:3, :3])
    node.translation.setValue(*(float(v) for v in T[:3, 3]))
    node.rotation.setValue(float(x), float(y), float(z), float(w))


def remove_from_scene(scene, root):
    """Take `root` out of `scene` if it is there (nothing when the view is already gone)."""
    try:
        if scene.findChild(root) >= 0:
            scene.removeChild(root)
    except RuntimeError:    # the view and its scene graph are gone
        pass


def matrix_from_transform(node):
    """ndarray, shape (4, 4): the rigid transform a ``SoTransform`` holds (scale ignored)."""
    x, y, z, w = node.rotation.getValue().getValue()
    T = np.eye(4)
    T[:3, :3] = rotations.matrix_from_quaternion(np.array([w, x, y, z], dtype=float))
    T[:3, 3] = node.translation.getValue().getValue()
    return T


def mesh_node(mesh, color):
    """A ``SoSeparator`` drawing a trimesh mesh, smooth-shaded in one colour.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Faces counter-clockwise seen from outside, mm.
    color : tuple of 3 float
    """
    sep = coin.SoSeparator()
    material = coin.SoMaterial()
    material.diffuseColor.setValue(*color)
    material.ambientColor.setValue(0.2, 0.2, 0.2)      # every field set: no version's defaults
    material.specularColor.setValue(0.2, 0.2, 0.2)
    material.emissiveColor.setValue(0.0, 0.0, 0.0)
    material.shininess.setValue(0.3)
    material.transparency.setValue(0.0)
    hints = coin.SoShapeHints()
    hints.vertexOrdering = coin.SoShapeHints.COUNTERCLOCKWISE
    hints.shapeType = coin.SoShapeHints.SOLID
    hints.creaseAngle = 0.6
    coords = coin.SoCoordinate3()
    vertices = np.asarray(mesh.vertices, dtype=float)
    coords.point.setValues(0, len(vertices), vertices.tolist())
    faces = coin.SoIndexedFaceSet()
    index = np.column_stack([np.asarray(mesh.faces, dtype=int), -np.ones(len(mesh.faces), int)])
    faces.coordIndex.setValues(0, index.size, index.ravel().tolist())
    for node in (material, hints, coords, faces):
        sep.addChild(node)
    return sep


class _Polyline:
    """An unlit line strip: SoSwitch > (colour, width, coordinates, SoLineSet)."""

    def __init__(self, color, width):
        self.switch = coin.SoSwitch()
        sep = coin.SoSeparator()
        self.color = coin.SoBaseColor()
        self.color.rgb.setValue(*color)
        style = coin.SoDrawStyle()
        style.lineWidth = width
        self.coords = coin.SoCoordinate3()
        self.lines = coin.SoLineSet()
        for node in (self.color, style, self.coords, self.lines):
            sep.addChild(node)
        self.switch.addChild(sep)
        self.set_points(np.zeros((0, 3)))

    def set_points(self, points):
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        points = points[np.isfinite(points).all(axis=1)]
        if len(points) < 2:
            self.switch.whichChild = coin.SO_SWITCH_NONE
            return
        self.coords.point.setNum(len(points))
        self.coords.point.setValues(0, len(points), points.tolist())
        self.lines.numVertices.setValue(len(points))
        self.switch.whichChild = 0

    @property
    def visible(self):
        return self.switch.whichChild.getValue() == 0


# --- the robot -----------------------------------------------------------------------------

class RobotView:
    """A robot, its TCP trace and extra polylines in one 3D view.

    Parameters
    ----------
    view : Gui.View3DInventor or None
        The view to draw in (``FreeCADGui.ActiveDocument.ActiveView``);
        None with `parent`.
    model : RobotModel
        The robot's kinematic model (``api.robot(name)``).
    T_u_r : array_like, shape (4, 4)
        Robot base {R} in {U} (the cell's Placement), mm.
    T_f_t : array_like, shape (4, 4), optional
        TCP in the flange frame; a tool solid is drawn from the flange
        towards it.
    parent : coin.SoGroup, optional
        Where to add the nodes instead of the view's scene graph (e.g. a
        view provider's root, so the robot goes with its object).

    Attributes
    ----------
    root : coin.SoSeparator
        The node added to the view's scene graph (or to `parent`).
    base : coin.SoTransform
        {R} in {U}.
    link_transforms : list of 7 coin.SoTransform
        Link frames in {R} (base, links 1..6), as set by :meth:`set_joints`.
    """

    def __init__(self, view, model, T_u_r, T_f_t=None, parent=None):
        self.model = model
        self.scene = view.getSceneGraph() if parent is None else parent
        self.root = coin.SoSeparator()
        self.root.setName(_NODE_NAME)
        robot = coin.SoSeparator()
        self.base = coin.SoTransform()
        set_transform(self.base, T_u_r)
        robot.addChild(self.base)
        self.link_transforms = []
        self._link_nodes = []
        for i, solid in enumerate(links.link_solids(model)):
            sep = coin.SoSeparator()
            transform = coin.SoTransform()
            sep.addChild(transform)
            sep.addChild(mesh_node(solid, _LINK_COLORS[i]))
            robot.addChild(sep)
            self.link_transforms.append(transform)
            self._link_nodes.append(sep)
        if T_f_t is not None:
            tool = links.tool_solid(T_f_t, radius_mm=0.02 * self._arm_length(), clearance_mm=1.0)
            if tool is not None:
                self._link_nodes[6].addChild(mesh_node(tool, TOOL_COLOR))
        self.root.addChild(robot)

        traces = coin.SoAnnotation()
        light = coin.SoLightModel()
        light.model = coin.SoLightModel.BASE_COLOR
        traces.addChild(light)
        self.trace = _Polyline(TRACE_COLOR, 3.0)
        traces.addChild(self.trace.switch)
        self._polyline_group = coin.SoSeparator()
        traces.addChild(self._polyline_group)
        self.root.addChild(traces)
        self.polylines = []
        self.set_joints(np.zeros(6))
        self.scene.addChild(self.root)

    def _arm_length(self):
        frames = links.link_frames(self.model, np.zeros(6))
        return float(np.linalg.norm(frames[6, :3, 3] - frames[2, :3, 3]))

    def set_base(self, T_u_r):
        """Place the robot base {R} at `T_u_r` (4x4, in {U})."""
        set_transform(self.base, T_u_r)

    def set_joints(self, q_deg):
        """Pose the robot.

        Parameters
        ----------
        q_deg : array_like, shape (6,)
            Model joints, degrees (what ``model.fk`` takes).
        """
        frames = links.link_frames(self.model, np.asarray(q_deg, dtype=float))
        for transform, T in zip(self.link_transforms, frames):
            set_transform(transform, T)

    def link_matrices(self):
        """ndarray, shape (7, 4, 4): each link's frame in {U}, read back from the scene."""
        T_u_r = matrix_from_transform(self.base)
        return np.array([T_u_r @ matrix_from_transform(t) for t in self.link_transforms])

    def set_trace(self, points):
        """Draw the TCP trace through `points` ((M, 3) in {U}, mm; fewer than 2 hide it)."""
        self.trace.set_points(points)

    def add_polyline(self, points, color=None, width=2.0):
        """Draw one more polyline ((M, 3) in {U}, mm) in `color`, or the next of
        :data:`POLYLINE_COLORS`.

        Returns
        -------
        tuple of 3 float
            The colour used.
        """
        if color is None:
            color = POLYLINE_COLORS[len(self.polylines) % len(POLYLINE_COLORS)]
        line = _Polyline(color, width)
        line.set_points(points)
        self._polyline_group.addChild(line.switch)
        self.polylines.append(line)
        return tuple(color)

    def clear_polylines(self):
        """Remove every extra polyline."""
        self._polyline_group.removeAllChildren()
        self.polylines = []

    @property
    def shown(self):
        """bool: the nodes are in the view's scene graph."""
        return self.scene is not None and self.scene.findChild(self.root) >= 0

    def remove(self):
        """Take every node out of the view (safe to call twice, or after the view closed)."""
        if self.scene is not None:
            remove_from_scene(self.scene, self.root)
        self.scene = None
