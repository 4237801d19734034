"""CadRobot_MarkPath: the selected sketches, Part objects or edges become a path at once."""

from .. import preferences
from ..objects import picking
from . import selection
from .base import QT_TRANSLATE_NOOP, DocumentCommand, call, run_journaled, select_in_tree

NAME = "CadRobot_MarkPath"


def path_sources(items):
    """The path's source from the selection: objects whole, or (object, [edges]).

    Parameters
    ----------
    items : list of selection.Picked

    Returns
    -------
    list
        ``obj`` or ``(obj, ["Edge1", ...])`` per selected object, in selection
        order; a selected face gives the edges of its outer boundary (the loop
        round a part's top, for deburring or a fillet weld round it). None when
        something selected cannot be a path's source (a vertex, a CadRobot
        object other than the cell, an object without edges).
    """
    sources = {}
    for item in items:
        if item.cad_type == "Cell" and not item.sub:
            continue
        if item.cad_type or not getattr(getattr(item.obj, "Shape", None), "Edges", None):
            return None
        if item.sub and item.kind not in ("Edge", "Face"):
            return None
        edges = sources.setdefault(item.obj, [])
        subs = picking.outer_edge_names(item.obj, item.sub) if item.kind == "Face" else [item.sub]
        if item.sub and subs is None:
            return None
        if item.sub:
            edges.extend(sub for sub in subs if sub not in edges)
        elif not item.sub:
            edges.append("")            # the whole object
    result = []
    for obj, edges in sources.items():
        result.append(obj if "" in edges or not edges else (obj, edges))
    return result or None


class MarkPathCommand(DocumentCommand):
    """Make a path of the cell from the selected sketches, Part objects or edges."""

    NAME = NAME
    MENU_TEXT = QT_TRANSLATE_NOOP("CadRobot_MarkPath", "Mark path")
    TOOLTIP = QT_TRANSLATE_NOOP(
        "CadRobot_MarkPath", "Make a robot path from the selected sketches, Part objects or edges "
        "(they must join end to end), or round the outer boundary of a selected face. The tool follows them in the order they join; speed, "
        "approach and the other options are in the path's properties.")
    STATUS_TIP = QT_TRANSLATE_NOOP(
        "CadRobot_MarkPath", "Turn the selected sketches or edges into a path of the cell")

    def fits(self, doc):
        return selection.find_cell() is not None and path_sources(selection.selected(doc)) is not None

    def run(self, doc):
        cell = selection.find_cell()
        sources = path_sources(selection.selected(doc))
        if cell is None or sources is None:
            return
        line = "path = " + call(
            "api.make_path", doc, cell, sources,
            ApproachDistance=preferences.get("ApproachDistance"),
            InterpolationStep=preferences.get("InterpolationStep"))
        done = run_journaled(doc, self.title(), [line], results=["path"])
        if done:
            select_in_tree(doc, done[0].Name)
