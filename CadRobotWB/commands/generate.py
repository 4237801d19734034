"""CadRobot_Generate: choose a post-processor and an output folder, see the program, write it."""

from ..gui import generate_panel
from ..gui import progress as gui_progress
from .base import QT_TRANSLATE_NOOP, CellCommand

NAME = "CadRobot_Generate"


class GenerateCommand(CellCommand):
    """Open the Generate panel on the selected (or only) cell."""

    NAME = NAME
    MENU_TEXT = QT_TRANSLATE_NOOP("CadRobot_Generate", "Generate program")
    TOOLTIP = QT_TRANSLATE_NOOP(
        "CadRobot_Generate", "Make the selected cell's robot program: choose the post-processor "
        "(ABB RAPID, Motoman INFORM, KUKA KRL, UR Script, Fanuc LS or your own *_post.py), see "
        "the program text, and write the files into the output folder.")
    STATUS_TIP = QT_TRANSLATE_NOOP(
        "CadRobot_Generate", "See and write the selected cell's robot program")

    def run(self, cell):
        if gui_progress.busy():      # a work under way (its window keeps the GUI live)
            gui_progress.say_busy(self.title())
            return
        generate_panel.open_panel(cell)
