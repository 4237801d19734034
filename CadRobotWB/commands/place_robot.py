"""CadRobot_PlaceRobot: search where the cell's robot can stand, in a task panel."""

from . import selection
from .base import QT_TRANSLATE_NOOP, CellCommand

NAME = "CadRobot_PlaceRobot"


def selected_face():
    """(object, "FaceN") of the first selected face, or None."""
    for item in selection.selected():
        if item.kind == "Face":
            return (item.obj, item.sub)
    return None


class PlaceRobotCommand(CellCommand):
    """Search base placements of the robot that reach every target: heat map, preview, apply."""

    NAME = NAME
    CMD_TYPE = "NoTransaction"     # the panel's Apply is its own undo step
    MENU_TEXT = QT_TRANSLATE_NOOP("CadRobot_PlaceRobot", "Place robot")
    TOOLTIP = QT_TRANSLATE_NOOP(
        "CadRobot_PlaceRobot", "Search where the selected cell's robot can stand: every target of "
        "every path reachable in one arm configuration per path, within the joint limits with a "
        "margin, away from singularities and without collisions. Give a rectangle of the floor or "
        "select a horizontal face; the result is drawn as a heat map, and Apply stands the robot "
        "at the placement you pick.")
    STATUS_TIP = QT_TRANSLATE_NOOP(
        "CadRobot_PlaceRobot", "Search placements of the cell's robot and stand it at one")

    def run(self, cell):
        from ..gui import place_panel      # the panel imports this package
        place_panel.open_panel(cell, face=selected_face())
