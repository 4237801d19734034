"""The external axes in the player: the positioner turning its parts, the robot on its track.

The document shows each mechanism at its drawn values (``ShowAt``) and what it
carries drawn there (issue 23's plan, section 1). While the player shows a
sample with external values ``v``, :class:`MechanismView`

- draws each mechanism's bodies at ``v`` (``catalog.solids``) in place of its
  document object, whose own drawing is switched off;
- moves what the positioner carries by ``motion(v)``: the coin transform of
  the view provider of each of its Parts, and of the cell's paths, welds and
  risk areas on them, is set to ``motion(v) @ placement`` (their Placement,
  and so the document, never change);
- carries points drawn on the part (the TCP trace) to where the part is shown.

:meth:`MechanismView.restore` puts every transform and switch back as it was.
Only the view changes: nothing is written into the document.
"""

import numpy as np
from pivy import coin

from ..core import frames as tf
from ..objects import base as object_base
from ..objects.convert import matrix_from_placement
from ..robots.mechanisms import catalog
from . import robot_view

#: Colours of a mechanism's base (fixed) and of its moving bodies, RGB 0..1.
BASE_COLOR = (0.30, 0.33, 0.37)
BODY_COLOR = (0.55, 0.60, 0.66)
_NODE_NAME = "CadRobotMechanismView"
#: CadRobot objects of a cell drawn on a path (they ride with the path's part).
ON_A_PATH = ("Weld", "RiskArea")


def _apply(T, points):
    """Rigid 4x4 `T` applied to points (M, 3)."""
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    return points @ T[:3, :3].T + T[:3, 3]


def _first_child(node, node_class):
    """The first direct child of `node` that is a `node_class` (or derives from it: FreeCAD
    1.1 roots hold an ``SoFCTransform``), or None."""
    for k in range(node.getNumChildren()):
        child = node.getChild(k)
        if child.isOfType(node_class.getClassTypeId()):
            return child
    return None


def riding_objects(cell, positioner_object):
    """The document objects that move with the positioner: its Parts, and the cell's
    paths whose every source object rides, and the welds and risk areas on those paths.

    Returns
    -------
    list of App.DocumentObject
    """
    parts = list(getattr(positioner_object, "Parts", []) or [])
    names = {p.Name for p in parts}
    paths = []
    for member in getattr(cell, "Group", []) or []:
        if object_base.type_of(member) != "RobotPath":
            continue
        sources = [link[0] if isinstance(link, tuple) else link
                   for link in (getattr(member, "Source", []) or [])]
        if sources and all(s.Name in names for s in sources):
            paths.append(member)
    path_names = {p.Name for p in paths}
    on_paths = [m for m in getattr(cell, "Group", []) or []
                if object_base.type_of(m) in ON_A_PATH
                and getattr(getattr(m, "Path", None), "Name", None) in path_names]
    return parts + paths + on_paths


class _Riding:
    """One view provider's coin transform, moved with the positioner and restored after."""

    def __init__(self, obj):
        self.obj = obj
        root = obj.ViewObject.RootNode
        self.transform = _first_child(root, coin.SoTransform)
        self.T_u_obj = matrix_from_placement(object_base.global_placement(obj))
        # the placement of the object's container: the coin transform holds the local one
        self.T_u_parent = self.T_u_obj @ tf.invert_transform(matrix_from_placement(obj.Placement))
        self.saved = None if self.transform is None else (
            self.transform.translation.getValue().getValue(),
            self.transform.rotation.getValue().getValue())

    def move(self, motion):
        if self.transform is None:
            return
        local = tf.invert_transform(self.T_u_parent) @ motion @ self.T_u_obj
        robot_view.set_transform(self.transform, local)

    def restore(self):
        if self.transform is None:
            return
        self.transform.translation.setValue(*self.saved[0])
        self.transform.rotation.setValue(*self.saved[1])


class _Bodies:
    """A mechanism's bodies drawn at given values, in place of its document object."""

    def __init__(self, mechanism, obj):
        self.mechanism = mechanism
        self.switch = None
        self.saved_child = None
        self.root = coin.SoSeparator()
        self.meshes = []
        for k, (vertices, faces) in enumerate(catalog.solids(mechanism)):
            mesh = _Mesh(vertices, faces)
            node = robot_view.mesh_node(mesh, BASE_COLOR if k == 0 else BODY_COLOR)
            self.meshes.append(node.getChild(2))          # its SoCoordinate3
            self.root.addChild(node)
        view_object = getattr(obj, "ViewObject", None) if obj is not None else None
        if self.meshes and view_object is not None:
            self.switch = _first_child(view_object.RootNode, coin.SoSwitch)
            if self.switch is not None:
                self.saved_child = self.switch.whichChild.getValue()
                self.switch.whichChild = coin.SO_SWITCH_NONE

    def show(self, values):
        for coords, (vertices, _faces) in zip(self.meshes, catalog.solids(self.mechanism, values)):
            coords.point.setValues(0, len(vertices), np.asarray(vertices, float).tolist())

    def restore(self):
        if self.switch is not None:
            self.switch.whichChild = self.saved_child


class _Mesh:
    """What :func:`robot_view.mesh_node` reads of a mesh."""

    def __init__(self, vertices, faces):
        self.vertices, self.faces = vertices, faces


class MechanismView:
    """The external axes of a program, shown in a 3D view at a timeline's values.

    Parameters
    ----------
    view : Gui.View3DInventor
    external : core.mechanisms.ExternalAxes
    cell : App.DocumentObject

    Attributes
    ----------
    values : ndarray, shape (K,)
        The external values shown (program order: track, then positioner).
    riding : list of _Riding
        The view providers moved with the positioner.
    """

    def __init__(self, view, external, cell):
        self.external = external
        self.scene = view.getSceneGraph()
        self.root = coin.SoSeparator()
        self.root.setName(_NODE_NAME)
        objects = {object_base.type_of(m): m for m in getattr(cell, "Group", []) or []}
        self.bodies = [_Bodies(m, objects.get("Track" if m.kind == "track" else "Positioner"))
                       for m in external.mechanisms()]
        for bodies in self.bodies:
            self.root.addChild(bodies.root)
        self.riding = []
        if external.positioner is not None and "Positioner" in objects:
            self.riding = [_Riding(o) for o in riding_objects(cell, objects["Positioner"])
                           if getattr(o, "ViewObject", None) is not None]
        self.scene.addChild(self.root)
        self.values = external.drawn_at()

    def part_motion(self, values):
        """``T_u_u'`` of the positioner at program-order `values` (identity without one)."""
        _, positioner = self.external.split(values)
        if positioner is None:
            return np.eye(4)
        return self.external.positioner.motion(positioner)

    def show(self, values):
        """Show every mechanism, and what the positioner carries, at `values` (K,)."""
        self.values = np.asarray(values, dtype=float)
        track, positioner = self.external.split(self.values)
        for bodies, v in zip(self.bodies, [x for x in (track, positioner) if x is not None]):
            bodies.show(v)
        motion = self.part_motion(self.values)
        for riding in self.riding:
            riding.move(motion)

    def on_part(self, points_u, values):
        """Points in {U} drawn with the part at `values`, carried to where the part is shown.

        Parameters
        ----------
        points_u : array_like, shape (M, 3)
        values : array_like, shape (M, K) or (K,)
            The external values each point was drawn at.

        Returns
        -------
        ndarray, shape (M, 3)
        """
        points = np.asarray(points_u, dtype=float).reshape(-1, 3)
        now = self.part_motion(self.values)
        values = np.asarray(values, dtype=float)
        if values.ndim == 1:
            return _apply(now @ tf.invert_transform(self.part_motion(values)), points)
        back = np.linalg.inv(self.part_motion(values))          # (M, 4, 4)
        drawn = np.einsum("mij,mj->mi", back[:, :3, :3], points) + back[:, :3, 3]
        return _apply(now, drawn)

    def restore(self):
        """Every transform and switch back as it was, the bodies out of the view."""
        for riding in self.riding:
            riding.restore()
        for bodies in self.bodies:
            bodies.restore()
        robot_view.remove_from_scene(self.scene, self.root)
