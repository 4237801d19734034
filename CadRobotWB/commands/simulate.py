"""CadRobot_Simulate: play the cell's program with the robot in the 3D view."""

from ..gui import progress as gui_progress
from ..gui import simulation_player
from .base import QT_TRANSLATE_NOOP, CellCommand

NAME = "CadRobot_Simulate"


class SimulateCommand(CellCommand):
    """Open the simulation player on the selected (or only) cell."""

    NAME = NAME
    MENU_TEXT = QT_TRANSLATE_NOOP("CadRobot_Simulate", "Simulate")
    TOOLTIP = QT_TRANSLATE_NOOP(
        "CadRobot_Simulate", "Animate the robot along the selected cell's program in the 3D view, "
        "with its TCP trace and joint values; playback stops at the first target the robot "
        "cannot reach and says why.")
    STATUS_TIP = QT_TRANSLATE_NOOP("CadRobot_Simulate", "Play the selected cell's program in the 3D view")

    def run(self, cell):
        # The check before playing runs in a progress window with Cancel; the player
        # opens only once it has finished (a cancelled preparation changes nothing).
        if gui_progress.busy():
            gui_progress.say_busy(self.title())
            return
        try:
            gui_progress.run_with_dialog(self.title(), NAME, simulation_player.open_player, cell)
        except gui_progress.Cancelled:
            gui_progress.say_cancelled(self.title())
