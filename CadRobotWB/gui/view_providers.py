"""View providers: how CadRobot objects look in the 3D view and the tree.

Attached when an object is made with the GUI up, and when a document saved
without the GUI (FreeCADCmd, the CLI) is opened in it. The class path is
saved in every GuiDocument.xml: do not move or rename it without a shim.

By type:

- CalibrationFrame: its edges in X red / Y green / Z blue, arrow heads and
  labels, and the taught frame when it has one (:mod:`frame_display`);
  double-click opens the teaching panel.
- RobotPath: direction arrows and segment numbers (:mod:`path_display`),
  and the cell's generated targets as small triads (:mod:`target_display`).
- ToolMarker: the tool, semi-transparent; FreeCAD's Transform (edit mode 1)
  turns it with the dragger. While markers are selected, the path segments
  they govern are drawn thick in orange (:mod:`path_display`).
- RiskArea: its segments in red, thick.
- Weld: its woven centre line (the torch's path with the weave) in amber.
- Positioner, Track: their solids at ShowAt, steel grey.
- Cell: groups the others; its robot stands at its base in its start pose
  (:mod:`robot_display`, ``ShowRobot``); ``ShowTargets`` switches its
  targets on and off.
"""

import os

from .. import compat

# Per CadRobot type: (line colour, line width, shape colour, transparency %).
STYLES = {
    "CalibrationFrame": ((0.0, 0.0, 0.0), 3.0, None, 0),
    "RobotPath": ((0.0, 0.33, 1.0), 4.0, None, 0),
    "ToolMarker": ((0.2, 0.2, 0.2), 1.0, (1.0, 0.55, 0.0), 40),
    "RiskArea": ((1.0, 0.0, 0.0), 7.0, None, 0),
    "Weld": ((1.0, 0.75, 0.0), 3.0, None, 0),
    "Positioner": ((0.2, 0.2, 0.2), 1.0, (0.45, 0.5, 0.55), 0),
    "Track": ((0.2, 0.2, 0.2), 1.0, (0.45, 0.5, 0.55), 0),
}

# View properties per type: (name, tooltip, default).
VIEW_PROPERTIES = {
    "Cell": (("ShowTargets", "Draw the generated targets as small triads along the paths", True),
             ("ShowRobot", "Draw the robot at its base, in its start pose (StartJoints)", True)),
    "RobotPath": (("ShowArrows", "Draw an arrow in the travel direction on every segment", True),
                  ("ShowSegmentNumbers", "Write each segment's number (1-based) beside it", True)),
}
VIEW_GROUP = "CadRobot"

ICON_DIR = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                        "resources", "icons")

# Edit modes (Gui::ViewProvider::EditMode): 0 Default (double-click), 1 Transform.
EDIT_DEFAULT = 0


def icon_path(type_name):
    """The tree icon of CadRobot type `type_name` (the workbench icon for unknown types)."""
    path = os.path.join(ICON_DIR, "tree", "%s.svg" % type_name)
    return path if os.path.isfile(path) else os.path.join(ICON_DIR, "CadRobot.svg")


class ViewProvider:
    """The view provider of every CadRobot object (look and behaviour by the object's type).

    Attributes
    ----------
    frame_display : frame_display.FrameDisplay or None
        For calibration frames.
    path_display : path_display.PathDisplay or None
        For paths.
    robot_display : robot_display.CellRobotDisplay or None
        For cells.
    """

    def __init__(self, vobj):
        vobj.Proxy = self
        self.apply_style(vobj)

    def attach(self, vobj):
        from ..objects.base import type_of
        from . import path_display, target_display
        self.Object = vobj.Object
        self.ViewObject = vobj
        for display in self._displays():      # attached again: drop the old nodes
            if vobj.RootNode.findChild(display.switch) >= 0:
                vobj.RootNode.removeChild(display.switch)
        self.frame_display = self.path_display = self.robot_display = None
        kind = type_of(vobj.Object)
        for name, tooltip, default in VIEW_PROPERTIES.get(kind, ()):
            if name not in vobj.PropertiesList:
                vobj.addProperty("App::PropertyBool", name, VIEW_GROUP, tooltip)
                setattr(vobj, name, default)
        if kind == "CalibrationFrame":
            from .frame_display import FrameDisplay
            self.frame_display = FrameDisplay(vobj.RootNode)
        elif kind == "RobotPath":
            self.path_display = path_display.PathDisplay(vobj.RootNode)
            self.path_display.show_arrows(getattr(vobj, "ShowArrows", True))
            self.path_display.show_numbers(getattr(vobj, "ShowSegmentNumbers", True))
        elif kind == "Cell":
            from .robot_display import CellRobotDisplay
            self.robot_display = CellRobotDisplay(vobj.RootNode)
            self.robot_display.show_robot(getattr(vobj, "ShowRobot", True))
        target_display.install()
        path_display.install()
        self._redraw(vobj.Object)
        self._set_visible(vobj)
        if kind == "Cell":          # a cell opened from a file shows its targets at once
            target_display.refresh_soon(vobj.Object)

    def apply_style(self, vobj):
        from ..objects.base import type_of
        from .triad_display import AXIS_COLORS
        kind = type_of(vobj.Object)
        style = STYLES.get(kind)
        if style is None:
            return
        line_color, line_width, shape_color, transparency = style
        for prop, value in (("LineColor", line_color), ("PointColor", line_color),
                            ("LineWidth", line_width)):
            if hasattr(vobj, prop):
                setattr(vobj, prop, value)
        if shape_color is not None:
            compat.set_shape_material(vobj, shape_color, transparency)
        if kind == "CalibrationFrame":
            _color_axes(vobj, AXIS_COLORS)

    # --- keeping the drawing up to date -------------------------------------------------

    def _displays(self):
        return [d for d in (getattr(self, name, None)
                            for name in ("frame_display", "path_display", "robot_display"))
                if d is not None]

    def _redraw(self, obj):
        for display in self._displays():
            display.update(obj)

    def _set_visible(self, vobj):
        for display in self._displays():
            display.set_visible(bool(vobj.Visibility))

    def updateData(self, obj, prop):
        from ..objects.base import type_of
        kind = type_of(obj)
        if kind == "CalibrationFrame":
            if prop == "Shape":
                _color_axes_soon(obj)
            if prop in ("Shape", "Label", "AxisLength", "Placement", "UseTaught", "CadPoints",
                        "MeasuredPoints", "TaughtPlacement"):
                self._redraw(obj)
            if prop in ("Placement", "UseTaught", "TaughtPlacement"):
                _redraw_cell_robot(obj)      # a taught frame moves the robot (api.robot_base)
        elif kind == "RobotPath" and prop == "Shape":
            self._redraw(obj)
        elif kind == "Cell" and prop in ("Placement", "Robot", "StartJoints", "ToolTCP"):
            self._redraw(obj)
        if kind == "Cell" and prop == "Placement":
            # The taught frames of the cell are placed by the robot base T_u_r.
            from ..objects.reader import cell_members
            for member in cell_members(obj):
                proxy = getattr(getattr(member, "ViewObject", None), "Proxy", None)
                if isinstance(proxy, ViewProvider) and proxy.frame_display is not None:
                    proxy.frame_display.update(member)

    def onChanged(self, vobj, prop):
        if prop == "Visibility":
            self._set_visible(vobj)
        display = getattr(self, "path_display", None)
        if display is not None and prop == "ShowArrows":
            display.show_arrows(vobj.ShowArrows)
        elif display is not None and prop == "ShowSegmentNumbers":
            display.show_numbers(vobj.ShowSegmentNumbers)
        elif prop == "ShowRobot" and getattr(self, "robot_display", None) is not None:
            self.robot_display.show_robot(vobj.ShowRobot)
        elif prop == "ShowTargets" and hasattr(self, "Object") and not _restoring(self.Object):
            from . import target_display
            target_display.refresh_cell(self.Object)

    # --- tree ---------------------------------------------------------------------------

    def getIcon(self):
        from ..objects.base import type_of
        return icon_path(type_of(self.Object) if hasattr(self, "Object") else "")

    def claimChildren(self):
        return list(getattr(self.Object, "Group", []) or [])

    # --- editing ------------------------------------------------------------------------

    def setEdit(self, vobj, mode=0):
        """Double-click on a calibration frame opens its teaching panel.

        Returns
        -------
        bool or None
            True when the panel opened, False when it could not (another
            panel is open, or this version has none); None for every other
            mode and type, which leaves FreeCAD's own behaviour (e.g. the
            Transform dragger for mode 1). False there would refuse it.
        """
        from ..objects.base import type_of
        if mode != EDIT_DEFAULT or type_of(vobj.Object) != "CalibrationFrame":
            return None
        try:
            from . import calibration_panel
        except ImportError:
            return False
        return calibration_panel.edit(vobj.Object) is not None

    def unsetEdit(self, vobj, mode=0):
        """Leaving a calibration frame's edit mode closes its teaching panel."""
        from ..objects.base import type_of
        if mode != EDIT_DEFAULT or type_of(vobj.Object) != "CalibrationFrame":
            return None
        import FreeCADGui
        try:
            from . import calibration_panel
            close = calibration_panel.close_panel
        except (ImportError, AttributeError):
            FreeCADGui.Control.closeDialog()
        else:
            close(reset_edit=False)     # also forgets the panel; the edit mode is ending already
        return True

    # --- no state of our own ------------------------------------------------------------

    def dumps(self):
        return None

    def loads(self, state):
        return None

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None


def _redraw_cell_robot(frame):
    """Redraw the robot of the cell `frame` belongs to (not while restoring)."""
    if _restoring(frame):
        return
    from .frame_display import cell_of
    from .robot_display import display_of
    cell = cell_of(frame)
    display = display_of(cell) if cell is not None else None
    if display is not None:
        display.update(cell)


def _restoring(obj):
    """bool: `obj`'s document is being read from a file (it is not complete yet)."""
    return "Restore" in getattr(obj, "State", []) or bool(getattr(obj.Document, "Restoring", False))


def _color_axes(vobj, colors):
    """Colour a calibration frame's three edges X, Y, Z.

    Assigned again whenever the shape changes: FreeCAD applies the colours
    only to a shape that already has that many edges.
    """
    if vobj is not None and "LineColorArray" in vobj.PropertiesList:
        vobj.LineColorArray = [tuple(c) for c in colors]


def _color_axes_soon(obj):
    """Colour a frame's edges once FreeCAD has drawn its new shape (after this call returns)."""
    from .soon import call_soon
    from .triad_display import AXIS_COLORS
    call_soon(obj, lambda frame: _color_axes(getattr(frame, "ViewObject", None), AXIS_COLORS))


def attach(obj):
    """Give `obj` a CadRobot view provider unless it has one already."""
    vobj = getattr(obj, "ViewObject", None)
    if vobj is not None and not isinstance(getattr(vobj, "Proxy", None), ViewProvider):
        ViewProvider(vobj)
