"""The robot cell: one robot, its tool, its default calibration frame, and
the paths, markers and frames grouped under it in the tree."""

import contextlib

import FreeCAD

from .. import preferences
from ..robots.catalog import catalog, tools
from .base import Proxy, restoring
from .tool_marker import update_governs_safely

DEFAULT_ROBOT = "ABB_IRB2400"


class Cell(Proxy):
    """Proxy of a ``App::DocumentObjectGroupPython`` robot cell.

    ``Placement`` is the robot base frame {R} in the assembly frame {U}.
    """

    TYPE = "Cell"
    PROPERTIES = (
        ("App::PropertyEnumeration", "Robot", "Robot", "Robot model from the CadRobot catalog", None),
        ("App::PropertyPlacement", "Placement", "Robot",
         "Robot base frame {R} in the assembly frame {U}", None),
        ("App::PropertyFloatList", "StartJoints", "Robot",
         "Joint values (degrees, 6) the robot starts from; empty: mid-range of the joints", None),
        ("App::PropertyLinkGlobal", "CalibrationFrame", "Program",
         "Calibration frame {B} the paths use unless they name another", None),
        ("App::PropertyString", "CalibrationFrameRef", "Program",
         "Internal name of the last calibration frame linked (to report a deleted one)", ""),
        ("App::PropertyString", "ProgramName", "Program",
         "Name of the generated program / module (empty: the cell's label)", ""),
        ("App::PropertyString", "PostProcessor", "Program",
         "Post-processor used by Generate and 'cadrobot export' when none is given", "abb_rapid"),
        ("App::PropertyFloat", "SampleTime", "Program",
         "Sampling time Δt in s for the interpolation inside risk areas (step = speed × Δt)", 0.1),
        ("App::PropertyLinkListGlobal", "Workpiece", "Simulation",
         "Solids of the real workpiece a simulated deviation moves; empty: the solids near the paths",
         None),
        ("App::PropertyString", "ToolName", "Tool", "Name of the tool in the program", "tTool"),
        ("App::PropertyEnumeration", "ToolType", "Tool",
         "The tool: one of CadRobot's tool library, or 'Custom body' (the solid in ToolBody, or "
         "none: only the TCP and mass below). Change it with CadRobot_EditTool or api.set_tool",
         None),
        ("App::PropertyLinkGlobal", "ToolBody", "Tool",
         "Document solid that is the tool body when ToolType is 'Custom body': drawn with the "
         "flange at its own origin, ToolTCP given in its own coordinates", None),
        ("App::PropertyPlacement", "ToolTCP", "Tool",
         "TCP frame {T} in the robot flange frame {F}: +Z is the tool's approach direction", None),
        ("App::PropertyFloat", "ToolMass", "Tool", "Tool mass in kg", 2.0),
        ("App::PropertyVector", "ToolCenterOfGravity", "Tool",
         "Tool centre of gravity in the flange frame {F}, mm", None),
        ("App::PropertyAngle", "WorkAngle", "Tool",
         "Default angle between the tool axis and the surface for tool markers placed on edges "
         "(90°: square to it; on a fillet the surface is the bisector of its faces, so 90° is "
         "the 45° to each plate of GMAW practice)", tools.GMAW_WORK_ANGLE_DEG),
        ("App::PropertyAngle", "TravelAngle", "Tool",
         "Default tilt of the tool towards the travel direction for tool markers placed on edges "
         "(positive: pushing; 10°: the middle of GMAW's 5-15° push angle on steel)",
         tools.GMAW_TRAVEL_ANGLE_DEG),
    )

    def setup(self, obj):
        # The catalog may have grown since the file was saved: refresh the choices.
        preferences.use_user_robot_folder()
        names = catalog.names()
        current = obj.Robot or DEFAULT_ROBOT
        if list(obj.getEnumerationsOfProperty("Robot") or []) != names:
            # Keep an unknown saved name selectable, so generating reports it.
            obj.Robot = names if current in names else names + [current]
            obj.Robot = current
        obj.setEditorMode("CalibrationFrameRef", 2)
        setup_tool_type(obj)

    def execute(self, obj):
        """Runs after any member of the cell was recomputed (the group depends on
        them): every tool marker's Governs is brought up to date."""
        update_governs_safely(obj)

    def onChanged(self, obj, prop):
        if prop == "CalibrationFrame" and getattr(obj, "CalibrationFrame", None) is not None:
            if obj.CalibrationFrameRef != obj.CalibrationFrame.Name:
                obj.CalibrationFrameRef = obj.CalibrationFrame.Name
        if prop == "Placement":
            warn_taught_move(obj)
        if prop in TOOL_DRAWING:
            touch_tool_markers(obj)


# --- moving the robot of a cell whose part a taught frame fixes -----------------------------

#: (document name, cell name) already told this session.
_told = set()
#: Cells whose Placement CadRobot itself is writing (no warning): names.
_own_writes = set()


@contextlib.contextmanager
def own_write(cell):
    """Within this block, changing `cell`'s Placement is CadRobot's own write: no warning."""
    key = (cell.Document.Name, cell.Name)
    _own_writes.add(key)
    try:
        yield
    finally:
        _own_writes.discard(key)


def taught_frame_note(cell_label, frame_label):
    """What a taught frame means for moving a cell's robot, and how to plan with the drawn one."""
    return ("Calibration frame '%s' is taught (UseTaught): it fixes the part relative to the robot "
            "where the robot measured it, so moving the robot of cell '%s' changes nothing in its "
            "programs or checks. To plan the robot's place with the drawn frame instead: turn "
            "UseTaught off on '%s', place the robot (Place robot), then teach the frame again."
            % (frame_label, cell_label, frame_label))


def taught_frames_in_use(cell):
    """Calibration frames with UseTaught on that `cell` or its paths link (labels, tree order).

    Read without checking anything (it runs from ``onChanged``): missing links are skipped.
    """
    from .reader import cell_paths
    labels = []
    for owner in [cell] + list(cell_paths(cell)):
        frame = getattr(owner, "CalibrationFrame", None)
        if frame is not None and getattr(frame, "UseTaught", False) and frame.Label not in labels:
            labels.append(frame.Label)
    return labels


def warn_taught_move(cell):
    """Once per cell per session: moving the robot changes nothing while a taught frame is in use.

    Prints a warning in the Report view and, with the GUI up, shows it in the
    status bar.  Silent while the document is restored, during
    :func:`own_write`, and when no taught frame is in use.

    Returns
    -------
    str or None
        The text told, or None.
    """
    try:
        key = (cell.Document.Name, cell.Name)
        if key in _told or key in _own_writes or restoring(cell):
            return None
        labels = taught_frames_in_use(cell)
    except Exception:          # half-built or half-deleted objects: never break a property write
        return None
    if not labels:
        return None
    _told.add(key)
    text = taught_frame_note(cell.Label, labels[0])
    FreeCAD.Console.PrintWarning("CadRobot: %s\n" % text)
    if FreeCAD.GuiUp:
        import FreeCADGui
        window = FreeCADGui.getMainWindow()
        if window is not None and window.statusBar() is not None:
            window.statusBar().showMessage(text, 20000)
    return text



#: Cell properties the tool markers' "Cell tool" drawing depends on.
TOOL_DRAWING = ("ToolType", "ToolBody", "ToolTCP")


def touch_tool_markers(cell):
    """Mark the cell's tool markers for recompute (they draw its tool); not while
    the file is being read."""
    doc = getattr(cell, "Document", None)
    if doc is None or "Restore" in getattr(cell, "State", []) or getattr(doc, "Restoring", False):
        return
    from .tool_marker import cell_markers   # tool_marker reads cells; imported when used
    for marker in cell_markers(cell):
        if marker.ToolShape == "Cell tool":
            marker.touch()


def setup_tool_type(obj):
    """Offer the library's tools in ``ToolType``, keeping the saved choice.

    A cell saved before CadRobot had a tool library gains ``ToolType`` as
    "Custom body" without a body: its ToolTCP, ToolMass and
    ToolCenterOfGravity stay what they were (a file is never given another tool).
    """
    choices = tools.tool_types()
    if list(obj.getEnumerationsOfProperty("ToolType") or []) != choices:
        current = obj.ToolType if obj.getEnumerationsOfProperty("ToolType") else tools.CUSTOM
        obj.ToolType = choices
        obj.ToolType = current if current in choices else tools.CUSTOM
    obj.setEditorMode("ToolType", 1)       # a library choice also sets the TCP: api.set_tool


def make(doc, robot, name):
    """Create a cell in `doc` (robot already validated against the catalog)."""
    obj = doc.addObject("App::DocumentObjectGroupPython", name)
    Cell(obj)
    obj.Robot = robot
    return obj
