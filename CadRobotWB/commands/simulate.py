"""CadRobot_Simulate: play the cell's program with the robot in the 3D view."""

import os

import FreeCAD

from ..errors import CadRobotError
from ..gui import simulation_player
from .check import show_message
from .selection import find_cell

translate = FreeCAD.Qt.translate
QT_TRANSLATE_NOOP = FreeCAD.Qt.QT_TRANSLATE_NOOP

NAME = "CadRobot_Simulate"
ICON = os.path.join(os.path.dirname(os.path.dirname(__file__)), "resources", "icons",
                    NAME + ".svg")


class SimulateCommand:
    """Open the simulation player on the selected (or only) cell."""

    def GetResources(self):
        return {
            "Pixmap": ICON,
            "CmdType": "ForEdit",      # only views: usable while a task panel is open
            "MenuText": QT_TRANSLATE_NOOP(NAME, "Simulate"),
            "ToolTip": QT_TRANSLATE_NOOP(
                NAME, "Animate the robot along the selected cell's program in the 3D view, with "
                "its TCP trace and joint values; playback stops at the first target the robot "
                "cannot reach and says why."),
            "StatusTip": QT_TRANSLATE_NOOP(NAME, "Play the selected cell's program in the 3D view"),
        }

    def IsActive(self):
        return find_cell() is not None

    def Activated(self):
        cell = find_cell()
        if cell is None:
            return
        try:
            simulation_player.open_player(cell)
        except CadRobotError as exc:
            FreeCAD.Console.PrintError("%s\n" % exc)
            show_message(translate("CadRobot_Simulate", "Simulate"), str(exc), error=True)
