"""CadRobot_SensorRun: run the cell's path with a seam-tracking laser or a force sensor."""

from ..gui import sensor_run_panel
from .base import QT_TRANSLATE_NOOP, CellCommand

NAME = "CadRobot_SensorRun"


class SensorRunCommand(CellCommand):
    """Open the sensor run panel on the selected (or only) cell."""

    NAME = NAME
    MENU_TEXT = QT_TRANSLATE_NOOP("CadRobot_SensorRun", "Sensor run")
    TOOLTIP = QT_TRANSLATE_NOOP(
        "CadRobot_SensorRun", "Simulate the selected cell's path with a seam-tracking laser or a "
        "force sensor correcting it, in a real part moved and turned from the drawing: see the "
        "corrections and forces, and play the nominal and corrected paths in the 3D view.")
    STATUS_TIP = QT_TRANSLATE_NOOP(
        "CadRobot_SensorRun", "Simulate the selected cell's path with a sensor in a deviated part")

    def run(self, cell):
        sensor_run_panel.open_panel(cell)
