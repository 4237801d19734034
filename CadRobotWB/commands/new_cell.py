"""CadRobot_NewCell: add a robot cell, choosing the robot and placing its base."""

from .base import QT_TRANSLATE_NOOP, DocumentCommand

NAME = "CadRobot_NewCell"


class NewCellCommand(DocumentCommand):
    """Open the new cell panel: the robot from the catalog, its base in the drawing."""

    NAME = NAME
    MENU_TEXT = QT_TRANSLATE_NOOP("CadRobot_NewCell", "New cell")
    TOOLTIP = QT_TRANSLATE_NOOP(
        "CadRobot_NewCell", "Add a robot cell: choose the robot from the catalog and place its base "
        "(beside the part, facing it, by default; or coordinates and a rotation about Z, or a "
        "selected vertex). Paths, tool markers and calibration frames are then added to the cell.")
    STATUS_TIP = QT_TRANSLATE_NOOP("CadRobot_NewCell", "Add a robot cell to the document")

    def fits(self, doc):
        return True

    def run(self, doc):
        from ..gui import new_cell_panel      # the panel imports this package
        new_cell_panel.open_panel(doc)
