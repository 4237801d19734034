"""CadRobot_SensorRun: run the cell's path with a seam-tracking laser or a force sensor."""

import os

import FreeCAD

from ..errors import CadRobotError
from ..gui import sensor_run_panel
from .check import show_message
from .selection import find_cell

translate = FreeCAD.Qt.translate
QT_TRANSLATE_NOOP = FreeCAD.Qt.QT_TRANSLATE_NOOP

NAME = "CadRobot_SensorRun"
ICON = os.path.join(os.path.dirname(os.path.dirname(__file__)), "resources", "icons",
                    NAME + ".svg")


class SensorRunCommand:
    """Open the sensor run panel on the selected (or only) cell."""

    def GetResources(self):
        return {
            "Pixmap": ICON,
            "CmdType": "ForEdit",      # only views: usable while a task panel is open
            "MenuText": QT_TRANSLATE_NOOP(NAME, "Sensor run"),
            "ToolTip": QT_TRANSLATE_NOOP(
                NAME, "Simulate the selected cell's path with a seam-tracking laser or a force "
                "sensor correcting it, in a real part moved and turned from the drawing: see "
                "the corrections and forces, and play the nominal and corrected paths in the "
                "3D view."),
            "StatusTip": QT_TRANSLATE_NOOP(
                NAME, "Simulate the selected cell's path with a sensor in a deviated part"),
        }

    def IsActive(self):
        return find_cell() is not None

    def Activated(self):
        cell = find_cell()
        if cell is None:
            return
        try:
            sensor_run_panel.open_panel(cell)
        except CadRobotError as exc:
            FreeCAD.Console.PrintError("%s\n" % exc)
            show_message(translate("CadRobot_SensorRun", "Sensor run"), str(exc), error=True)
