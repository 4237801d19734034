"""CadRobot_AddPositioner and CadRobot_AddTrack: external axes for the cell, each
from its panel (:mod:`CadRobotWB.gui.mechanism_panel`): a positioner holding the
selected parts, a linear track carrying the robot."""

from .base import QT_TRANSLATE_NOOP, DocumentCommand
from .selection import find_cell

POSITIONER_NAME = "CadRobot_AddPositioner"
TRACK_NAME = "CadRobot_AddTrack"


class _MechanismCommand(DocumentCommand):
    """Open the mechanism panel on the selected (or only) cell."""

    WHAT = ""

    def fits(self, doc):
        return find_cell() is not None

    def run(self, doc):
        cell = find_cell()
        if cell is None:
            return
        from ..gui import mechanism_panel      # the panel imports this package
        mechanism_panel.open_panel(cell, self.WHAT)


class AddPositionerCommand(_MechanismCommand):
    """Add a turntable or a tilt-and-turn positioner holding the selected parts."""

    NAME = POSITIONER_NAME
    WHAT = "positioner"
    MENU_TEXT = QT_TRANSLATE_NOOP("CadRobot_AddPositioner", "Add positioner")
    TOOLTIP = QT_TRANSLATE_NOOP(
        "CadRobot_AddPositioner", "Add a positioner to the cell: a turntable or a tilt-and-turn "
        "positioner (generic, or a real one from the catalog) holding the selected parts, "
        "frames and tool markers. Its axes are chosen for every target so each seam is welded "
        "in the position its weld asks for (flat by default).")
    STATUS_TIP = QT_TRANSLATE_NOOP("CadRobot_AddPositioner",
                                   "Add a positioner holding the selected parts")


class AddTrackCommand(_MechanismCommand):
    """Add a linear track carrying the cell's robot."""

    NAME = TRACK_NAME
    WHAT = "track"
    MENU_TEXT = QT_TRANSLATE_NOOP("CadRobot_AddTrack", "Add track")
    TOOLTIP = QT_TRANSLATE_NOOP(
        "CadRobot_AddTrack", "Put the cell's robot on a linear track (generic, or a real one "
        "from the catalog): its carriage under the robot as placed; the travel is chosen for "
        "every target so the arm reaches long parts.")
    STATUS_TIP = QT_TRANSLATE_NOOP("CadRobot_AddTrack", "Put the robot on a linear track")
