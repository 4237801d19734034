"""CadRobot_EditTool: change the tool of a cell (library tool or a document solid, TCP, mass)."""

from .base import QT_TRANSLATE_NOOP, CellCommand

NAME = "CadRobot_EditTool"


class EditToolCommand(CellCommand):
    """Open the Edit tool panel for the selected (or only) cell."""

    NAME = NAME
    CMD_TYPE = ""
    MENU_TEXT = QT_TRANSLATE_NOOP("CadRobot_EditTool", "Edit tool")
    TOOLTIP = QT_TRANSLATE_NOOP(
        "CadRobot_EditTool", "Change the selected cell's tool: a torch, the ball tool or the "
        "deburring spindle of the tool library, or a solid of the document; its TCP, mass and "
        "centre of gravity. Tool markers draw it and the collision check uses it.")
    STATUS_TIP = QT_TRANSLATE_NOOP("CadRobot_EditTool", "Change the tool of the selected cell")

    def run(self, cell):
        from ..gui import tool_group      # the panel imports this package
        tool_group.open_edit_panel(cell)
