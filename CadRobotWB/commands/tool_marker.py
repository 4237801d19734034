"""CadRobot_ToolMarker: a tool marker on the selected edge, at the picked point."""

from ..errors import CadRobotError
from . import selection
from .base import QT_TRANSLATE_NOOP, Code, DocumentCommand, call, run_journaled, select_in_tree

NAME = "CadRobot_ToolMarker"


def edge_and_face(items):
    """(edge, face or None) when the selection is one edge, optionally with one
    face (the cell itself may be selected too), else None.

    Parameters
    ----------
    items : list of selection.Picked
    """
    items = [i for i in items if not (i.cad_type == "Cell" and not i.sub)]
    edges = [i for i in items if i.kind == "Edge"]
    faces = [i for i in items if i.kind == "Face"]
    if len(edges) != 1 or len(faces) > 1 or len(edges) + len(faces) != len(items):
        return None
    return edges[0], (faces[0] if faces else None)


def placement_arguments(cell, edge, face):
    """(args, kwargs) of api.edge_tool_placement for the picked `edge` and `face`."""
    point = selection.point_on(edge.obj, edge.sub, edge.point)
    path = edge.obj if edge.cad_type == "RobotPath" else selection.path_using_edge(cell, edge.obj, edge.sub)
    return (edge.obj, edge.sub), dict(
        point=point, face=(face.obj, face.sub) if face is not None else None,
        work_angle_deg=float(getattr(cell, "WorkAngle", 90.0)),
        travel_angle_deg=float(getattr(cell, "TravelAngle", 0.0)), path=path)


def marker_lines(doc, cell, edge, face, on_conflict=None):
    """The journal lines that place the marker (see api.edge_tool_placement);
    `on_conflict` (the user's answer to a conflict) is passed to api.make_tool_marker."""
    args, kwargs = placement_arguments(cell, edge, face)
    extra = {} if on_conflict is None else {"on_conflict": on_conflict}
    return ["placement = " + call("api.edge_tool_placement", *args, **kwargs),
            "marker = " + call("api.make_tool_marker", doc, cell, Code("placement"), **extra)]


def conflict_answer(cell, edge, face):
    """(go on, on_conflict): ask the user when the new marker would land on a segment
    another marker sets with another orientation (see gui.marker_conflicts)."""
    from .. import api
    from ..gui import marker_conflicts
    args, kwargs = placement_arguments(cell, edge, face)
    try:
        placement = api.edge_tool_placement(*args, **kwargs)
    except CadRobotError:
        return True, None               # the journaled line reports it
    conflict = api.tool_marker_conflict(cell, placement=placement)
    if conflict is None:
        return True, None
    answer = marker_conflicts.ask_user(conflict)
    return answer is not None, answer


class ToolMarkerCommand(DocumentCommand):
    """Insert a tool marker on the selected edge, oriented from the edge and its faces."""

    NAME = NAME
    MENU_TEXT = QT_TRANSLATE_NOOP("CadRobot_ToolMarker", "Tool marker")
    TOOLTIP = QT_TRANSLATE_NOOP(
        "CadRobot_ToolMarker", "Insert a tool marker on the selected edge at the picked point: "
        "+X along the edge (the path's travel direction), the tool tilted from the faces meeting "
        "at the edge (or the one face selected too) by the cell's work and travel angles. "
        "Turn it afterwards with Transform. It sets the tool's orientation on that segment and "
        "on the following ones up to the next marker.")
    STATUS_TIP = QT_TRANSLATE_NOOP(
        "CadRobot_ToolMarker", "Insert a tool marker on the selected edge at the picked point")

    def __init__(self):
        super().__init__()
        # Markers moved later (dragged, or Placement / Path / Segment edited) are
        # checked by the document observer the same way.
        from ..gui import marker_conflicts
        marker_conflicts.install()

    def fits(self, doc):
        return selection.find_cell() is not None and edge_and_face(selection.selected(doc)) is not None

    def run(self, doc):
        cell = selection.find_cell()
        picked = edge_and_face(selection.selected(doc))
        if cell is None or picked is None:
            return
        go_on, on_conflict = conflict_answer(cell, *picked)
        if not go_on:
            return
        done = run_journaled(doc, self.title(), marker_lines(doc, cell, *picked, on_conflict=on_conflict),
                             results=["marker"])
        if done:
            select_in_tree(doc, done[0].Name)      # ready for Transform
