"""CadRobot_AutoToolMarkers: one tool marker per segment of the selected path."""

from ..errors import CadRobotError
from . import selection
from .base import QT_TRANSLATE_NOOP, DocumentCommand, call, run_journaled

NAME = "CadRobot_AutoToolMarkers"


def selected_path(items):
    """The one RobotPath selected whole (the cell may be selected too), else None."""
    items = [i for i in items if not (i.cad_type == "Cell" and not i.sub)]
    if len(items) == 1 and items[0].cad_type == "RobotPath" and not items[0].sub:
        return items[0].obj
    return None


def existing_conflicts(cell, path):
    """{segment: Conflict} of the automatic markers with the markers already on `path`;
    {} when there are none or the automatic poses cannot be computed (the journaled
    call reports that)."""
    from .. import api
    try:
        return api.auto_marker_conflicts(cell, path)
    except CadRobotError:
        return {}


class AutoToolMarkersCommand(DocumentCommand):
    """Place a tool marker at mid-length of every segment of the selected path."""

    NAME = NAME
    MENU_TEXT = QT_TRANSLATE_NOOP("CadRobot_AutoToolMarkers", "Tool markers on every segment")
    TOOLTIP = QT_TRANSLATE_NOOP(
        "CadRobot_AutoToolMarkers", "Insert one tool marker at the middle of every segment of the "
        "selected path, tilted from the faces meeting there by the cell's work and travel angles. "
        "Nothing is added when a segment has no face next to it. (Where the tool keeps one "
        "orientation, one marker on the first segment is enough: a marker also sets the "
        "following segments up to the next marker.)")
    STATUS_TIP = QT_TRANSLATE_NOOP(
        "CadRobot_AutoToolMarkers", "Insert a tool marker on every segment of the selected path")

    def fits(self, doc):
        path = selected_path(selection.selected(doc))
        return path is not None and selection.find_cell() is not None

    def run(self, doc):
        path = selected_path(selection.selected(doc))
        cell = selection.find_cell()
        if path is None or cell is None:
            return
        extra = {}
        conflicts = existing_conflicts(cell, path)
        if conflicts:
            from ..gui import marker_conflicts
            answer = marker_conflicts.ask_user_auto(path, conflicts)
            if answer is None:
                return
            extra["on_conflict"] = answer
        line = "markers = " + call(
            "api.make_tool_markers_auto", doc, cell, path,
            work_angle_deg=float(getattr(cell, "WorkAngle", 90.0)),
            travel_angle_deg=float(getattr(cell, "TravelAngle", 0.0)), **extra)
        run_journaled(doc, self.title(), [line])
