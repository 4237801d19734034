"""CadRobot_Weld: a weld over the selected segments of a path, or over a whole path,
with its schedule, weave and tracking chosen in the weld panel."""

from . import selection
from .base import QT_TRANSLATE_NOOP, DocumentCommand
from .risk_area import consecutive_range

NAME = "CadRobot_Weld"


def what_is_selected(items):
    """Where the weld goes, from the selection.

    Returns
    -------
    tuple or None
        ``(path, [k, ...])`` for edges of one RobotPath (EdgeK = segment K),
        ``(path, [])`` for a path alone, ``(None, [])`` for the cell alone or
        nothing (the panel offers the cell's paths); None for anything else.
    """
    rest = [i for i in items if not (i.cad_type == "Cell" and not i.sub)]
    if not rest:
        return (None, [])
    if all(i.kind == "Edge" and i.cad_type == "RobotPath" for i in rest):
        paths = {i.obj.Name for i in rest}
        if len(paths) == 1:
            return (rest[0].obj, sorted({int(i.sub[4:]) for i in rest}))
        return None
    if len(rest) == 1 and rest[0].cad_type == "RobotPath" and not rest[0].sub:
        return (rest[0].obj, [])
    return None


class WeldCommand(DocumentCommand):
    """Open the weld panel on the selected path segments, path or cell."""

    NAME = NAME
    MENU_TEXT = QT_TRANSLATE_NOOP("CadRobot_Weld", "Weld")
    TOOLTIP = QT_TRANSLATE_NOOP(
        "CadRobot_Weld", "Make a weld over the selected consecutive segments (edges) of a path, or "
        "over a whole path: its schedule (from the library for the joint the faces show, or your "
        "own), its weave and its seam tracking. The woven path is previewed in the 3D view.")
    STATUS_TIP = QT_TRANSLATE_NOOP(
        "CadRobot_Weld", "Weld the selected segments or path: schedule, weave, tracking")

    def fits(self, doc):
        cell = selection.find_cell()
        return cell is not None and what_is_selected(selection.selected(doc)) is not None

    def run(self, doc):
        cell = selection.find_cell()
        what = what_is_selected(selection.selected(doc))
        if cell is None or what is None:
            return
        path, segments = what
        first, last = consecutive_range(path, segments) if segments else (None, None)
        from ..gui import weld_panel      # the panel imports this package
        weld_panel.open_panel(cell, path=path, first_segment=first, last_segment=last)
