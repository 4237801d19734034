"""The public scripting API (stable contract, see DESIGN.md).

Every toolbar command and every CLI subcommand is one call of this module,
so a macro recorded in the GUI replays in FreeCADCmd::

    from CadRobotWB import api
    cell   = api.make_cell(doc, robot="ABB_IRB2400", name="Cell")
    frame  = api.make_calibration_frame(doc, cell, placement)
    path   = api.make_path(doc, cell, sketch, speed_mm_s=10.0)
    marker = api.make_tool_marker(doc, cell, placement)
    risk   = api.make_risk_area(doc, cell, path, 2, 3)
    weld   = api.make_weld(doc, cell, path, weave={"pattern": "zigzag"})
    prog   = api.generate(cell)
    files  = api.export(cell, post="abb_rapid", output_dir="out")

Placements may be given as ``FreeCAD.Placement`` or as 4x4 arrays (mm).

This module is the face only, as FreeCAD's ``Draft.py`` is over ``draftmake/``:
the functions live in :mod:`CadRobotWB.workflow`, one module per job -- ``cell``
(cells, tools, where the robot stands), ``calibration`` (calibration frames),
``paths``, ``markers`` (tool markers), ``risk`` (risk areas), ``welds``, ``mechanisms``
(a positioner, a track), ``program``
(generate), ``check``, ``export`` (posts and program files), ``place`` (Place
robot), ``simulate`` (sensor runs), ``robot_catalog`` (robots to pick, import,
edit) and ``weld_schedules`` (weld schedules to pick, the user's own saved).  A
test that replaces a function other functions call patches it there.
"""

from . import posts, preferences  # noqa: F401  (api.posts: the CLI and macros list posts)
from .core import progress as core_progress
from .core import risk_suggestions
from .errors import (CadRobotError, FindingError, FrameError, InputError, MarkerError,  # noqa: F401
                     NameTakenError, RiskAreaError)
from .objects.convert import matrix_from_placement, placement_from_matrix  # noqa: F401

# --- the API, by job -------------------------------------------------------------------------
from .workflow.calibration import (frame_placement_from_points, frame_placement_from_selection,  # noqa: F401
                                   make_calibration_frame, taught_frame, teach_calibration_frame)
from .workflow.cell import (find_cells, make_cell, robot_base, set_robot_placement, set_tool,  # noqa: F401
                            taught_frame_labels, taught_frame_note, tool_names)
from .workflow.check import CellCheck, check  # noqa: F401
from .workflow.common import ROBOT_BASE  # noqa: F401
from .workflow.export import (default_post_name, export, other_maker_note,  # noqa: F401
                              post_names, program_files, user_post_dirs)
from .workflow.markers import (auto_marker_conflicts, edge_tool_placement,  # noqa: F401
                               make_tool_markers_auto, make_tool_marker, marker_segment,
                               resolve_marker_conflict, tool_marker_conflict, tool_placement)
from .workflow.mechanisms import add_positioner, add_track  # noqa: F401
from .workflow.paths import make_path  # noqa: F401
from .workflow.place import SearchCancelled, place_robot  # noqa: F401
from .workflow.program import generate  # noqa: F401
from .workflow.risk import (make_risk_area, program_move_count, risk_area_step,  # noqa: F401
                            suggest_risk_areas)
from .workflow.robot_catalog import edit_robot, import_robot, robot, robot_names  # noqa: F401
from .workflow.robot_catalog import mechanism_names  # noqa: F401
from .workflow.simulate import sensor_fit, simulate  # noqa: F401
from .workflow.weld_schedules import save_weld_schedule, weld_schedules  # noqa: F401
from .workflow.welds import list_welds, make_weld  # noqa: F401

RiskSuggestion = risk_suggestions.RiskSuggestion
PREFERENCES = preferences.PATH   # kept for older macros

#: Raised by every long call when its ``progress`` callback returns False
#: (``core.progress.Cancelled``, an error with exit code 130).
Cancelled = core_progress.Cancelled
#: :data:`SearchCancelled` is the same class (older name, from :func:`place_robot`).


__all__ = [
    "make_cell", "set_tool", "tool_names", "make_calibration_frame", "make_path", "make_tool_marker",
    "make_risk_area",
    "tool_placement", "find_cells", "generate", "check", "simulate", "export", "post_names", "robot_names", "robot",
    "default_post_name", "other_maker_note",
    "import_robot", "edit_robot",
    "user_post_dirs", "matrix_from_placement", "placement_from_matrix",
    "frame_placement_from_points", "frame_placement_from_selection", "teach_calibration_frame",
    "taught_frame", "edge_tool_placement", "make_tool_markers_auto", "marker_segment",
    "suggest_risk_areas", "RiskSuggestion", "program_files",
    "place_robot", "set_robot_placement", "SearchCancelled", "Cancelled",
    "weld_schedules", "save_weld_schedule", "make_weld", "list_welds",
    "mechanism_names", "add_positioner", "add_track",
]
