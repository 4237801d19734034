"""The workbench's toolbar commands, one module per command.

Each command module exposes ``NAME`` (the FreeCAD command name) and one
command class; :data:`COMMAND_CLASSES` lists them, they are registered
with ``FreeCADGui.addCommand`` on import, and :data:`TOOLBARS` says where
they go (InitGui.py reads it).  A new command is a new module plus one line
in each table.
"""

import FreeCADGui

from . import check, sensor_run, simulate
from . import (auto_tool_markers, calibration_frame, edit_tool, mark_path, mechanism, new_cell,
               risk_area, tool_marker, weld)
from . import generate, place_robot

#: FreeCAD command name -> command class.
COMMAND_CLASSES = {
    new_cell.NAME: new_cell.NewCellCommand,
    edit_tool.NAME: edit_tool.EditToolCommand,
    calibration_frame.NAME: calibration_frame.CalibrationFrameCommand,
    mark_path.NAME: mark_path.MarkPathCommand,
    tool_marker.NAME: tool_marker.ToolMarkerCommand,
    auto_tool_markers.NAME: auto_tool_markers.AutoToolMarkersCommand,
    risk_area.NAME: risk_area.RiskAreaCommand,
    weld.NAME: weld.WeldCommand,
    mechanism.POSITIONER_NAME: mechanism.AddPositionerCommand,
    mechanism.TRACK_NAME: mechanism.AddTrackCommand,
    generate.NAME: generate.GenerateCommand,
    check.NAME: check.CheckCommand,
    simulate.NAME: simulate.SimulateCommand,
    sensor_run.NAME: sensor_run.SensorRunCommand,
    place_robot.NAME: place_robot.PlaceRobotCommand,
}

#: (toolbar title, [command names]); the CadRobot menu lists the same.
TOOLBARS = [("CadRobot", [new_cell.NAME, calibration_frame.NAME, mark_path.NAME, tool_marker.NAME,
                          auto_tool_markers.NAME, risk_area.NAME, weld.NAME, mechanism.POSITIONER_NAME,
                          mechanism.TRACK_NAME, edit_tool.NAME,
                          generate.NAME, check.NAME, place_robot.NAME, simulate.NAME, sensor_run.NAME])]


def register():
    """Add every command to FreeCAD (again: FreeCAD replaces a command of the same name)."""
    for name, command_class in COMMAND_CLASSES.items():
        FreeCADGui.addCommand(name, command_class())


register()
