"""CadRobot_RiskArea: a risk area over the selected segments, between two selected
tool markers, or chosen from the suggested sharp turns of a path or cell."""

from .. import api
from ..errors import CadRobotError, RiskAreaError
from ..objects import base as objects_base
from . import selection
from .base import QT_TRANSLATE_NOOP, DocumentCommand, call, run_journaled, select_in_tree, translate

NAME = "CadRobot_RiskArea"


def _without_cell(items):
    return [i for i in items if not (i.cad_type == "Cell" and not i.sub)]


def what_is_selected(items):
    """How the selection says where the risk area goes.

    Returns
    -------
    tuple or None
        ``("segments", path, [k, ...])`` for edges of one RobotPath (EdgeK =
        segment K), ``("markers", marker1, marker2)`` for two tool markers,
        ``("suggest", path or None)`` for a path alone, the cell alone or
        nothing; None for anything else.
    """
    rest = _without_cell(items)
    if not rest:
        return ("suggest", None)
    if all(i.kind == "Edge" and i.cad_type == "RobotPath" for i in rest):
        paths = {i.obj for i in rest}
        if len(paths) == 1:
            return ("segments", rest[0].obj, sorted({int(i.sub[4:]) for i in rest}))
        return None
    if len(rest) == 2 and all(i.cad_type == "ToolMarker" and not i.sub for i in rest):
        return ("markers", rest[0].obj, rest[1].obj)
    if len(rest) == 1 and rest[0].cad_type == "RobotPath" and not rest[0].sub:
        return ("suggest", rest[0].obj)
    return None


def consecutive_range(path, segments):
    """(first, last) of 1-based `segments` that follow each other; on a closed path the last
    and the first segment give (n, 1), the corner where the loop closes. RiskAreaError otherwise."""
    first, last = min(segments), max(segments)
    if len(segments) == 2 and first == 1 and last == int(path.SegmentCount) > 2 and _closed(path):
        return last, first
    if list(segments) != list(range(first, last + 1)):
        raise RiskAreaError(
            translate("CadRobot_RiskArea", "Path {0}: segments {1} do not follow each other; select "
                      "consecutive segments (edges) of the path.").format(
                objects_base.describe(path), ", ".join(str(k) for k in segments)), path.Name)
    return first, last


def _closed(path):
    """True when `path` ends where it starts (read as generate reads it)."""
    from ..objects import reader
    try:
        return bool(reader.path_geometry(path)[1])
    except CadRobotError:
        return False


def between_markers(cell, marker1, marker2):
    """(path, first, last): the segments from one marker's to the other's, both included."""
    path1, seg1 = api.marker_segment(cell, marker1)
    path2, seg2 = api.marker_segment(cell, marker2)
    if path1 != path2:
        raise RiskAreaError(
            translate("CadRobot_RiskArea", "Tool markers {0} and {1} set segments of different paths; "
                      "select two markers of one path.").format(
                objects_base.describe(marker1), objects_base.describe(marker2)), marker2.Name)
    if seg1 == seg2:
        raise RiskAreaError(
            translate("CadRobot_RiskArea", "Tool markers {0} and {1} both set segment {2}; select "
                      "markers of two different segments.").format(
                objects_base.describe(marker1), objects_base.describe(marker2), seg1), marker2.Name)
    return path1, min(seg1, seg2), max(seg1, seg2)


def default_step(cell, path, first, last):
    """``{"step_mm": step}`` of api.risk_area_step (the suggestions' rule), or {} when it
    cannot be computed (the journaled make_risk_area then reports what is wrong)."""
    try:
        return {"step_mm": float(api.risk_area_step(cell, path, first, last)[0])}
    except CadRobotError:
        return {}


class RiskAreaCommand(DocumentCommand):
    """Mark consecutive path segments where the tool turns sharply as a risk area."""

    NAME = NAME
    MENU_TEXT = QT_TRANSLATE_NOOP("CadRobot_RiskArea", "Risk area")
    TOOLTIP = QT_TRANSLATE_NOOP(
        "CadRobot_RiskArea", "Make a risk area over the selected consecutive segments (edges) of a "
        "path, or over the segments between two selected tool markers: there the tool's "
        "orientation is spread smoothly over the segments. With a path or the cell selected, "
        "choose from the places where the tool turns more than the risk threshold.")
    STATUS_TIP = QT_TRANSLATE_NOOP(
        "CadRobot_RiskArea", "Make a risk area over the selected segments, or choose from suggestions")

    def fits(self, doc):
        return selection.find_cell() is not None and what_is_selected(selection.selected(doc)) is not None

    def run(self, doc):
        cell = selection.find_cell()
        what = what_is_selected(selection.selected(doc))
        if cell is None or what is None:
            return
        if what[0] == "suggest":
            from ..gui import risk_area_panel      # the panel imports this package
            risk_area_panel.open_panel(cell, path=what[1])
            return
        if what[0] == "segments":
            path = what[1]
            first, last = consecutive_range(path, what[2])
        else:
            path, first, last = between_markers(cell, what[1], what[2])
        line = "risk = " + call("api.make_risk_area", doc, cell, path, first, last,
                                **default_step(cell, path, first, last))
        done = run_journaled(doc, self.title(), [line], results=["risk"])
        if done:
            select_in_tree(doc, done[0].Name)
