"""CadRobot_CalibrationFrame: a calibration frame {B} from the selection, then its
teaching panel.

The selection gives the frame: three vertices (origin, a point on +X, a
point in the XY plane), or a planar face and a straight edge in it (Z = the
face's normal, X along the edge from its end nearest the picked point), or,
with nothing selected, the Draft working plane (the XY plane when Draft has
none). A selected calibration frame alone opens its teaching panel.
"""

import FreeCAD

from . import selection
from .base import (QT_TRANSLATE_NOOP, Code, DocumentCommand, call, literal, run_journaled,
                   select_in_tree)

NAME = "CadRobot_CalibrationFrame"


def working_plane_placement():
    """The current Draft working plane as a placement in {U} (the XY plane when
    Draft has none): ``WorkingPlane.get_working_plane()`` on FreeCAD 1.x,
    ``FreeCAD.DraftWorkingPlane`` on 0.20."""
    plane = None
    try:
        import WorkingPlane
        getter = getattr(WorkingPlane, "get_working_plane", None)
        if getter is not None:
            plane = getter(update=False)
    except Exception:  # noqa: BLE001 -- no Draft, or no 3D view: the XY plane
        plane = None
    if plane is None:
        plane = getattr(FreeCAD, "DraftWorkingPlane", None)
    for method in ("get_placement", "getPlacement"):
        if plane is not None and hasattr(plane, method):
            try:
                return FreeCAD.Placement(getattr(plane, method)())
            except Exception:  # noqa: BLE001 -- a half-set-up plane: the XY plane
                break
    return FreeCAD.Placement()


def frame_source(items):
    """How the selection gives the frame.

    Returns
    -------
    tuple or None
        ``("vertices", [Picked] * 3)``, ``("face_edge", [face, edge])``,
        ``("plane",)`` for nothing selected (the cell aside), ``("edit", frame)``
        for one calibration frame, None for anything else.
    """
    rest = [i for i in items if not (i.cad_type == "Cell" and not i.sub)]
    if not rest:
        return ("plane",)
    if len(rest) == 1 and rest[0].cad_type == "CalibrationFrame" and not rest[0].sub:
        return ("edit", rest[0].obj)
    found = selection.kinds(rest)
    if found == ["Vertex"] * 3:
        return ("vertices", rest)
    if found == ["Edge", "Face"]:
        return ("face_edge", sorted(rest, key=lambda i: i.kind != "Face"))
    return None


def frame_lines(doc, cell, source):
    """The journal lines that add the frame of `source` (see :func:`frame_source`)."""
    if source[0] == "plane":
        placement = "placement = " + literal(working_plane_placement())
    else:
        picked = source[1]
        near = None
        if source[0] == "face_edge":
            edge = picked[1]
            near = selection.point_on(edge.obj, edge.sub, edge.point)
        placement = "placement = " + call("api.frame_placement_from_selection",
                                          [(i.obj, i.sub) for i in picked], near=near)
    return [placement, "frame = " + call("api.make_calibration_frame", doc, cell, Code("placement"))]


class CalibrationFrameCommand(DocumentCommand):
    """Add a calibration frame from the selection and open its teaching panel."""

    NAME = NAME
    MENU_TEXT = QT_TRANSLATE_NOOP("CadRobot_CalibrationFrame", "Calibration frame")
    TOOLTIP = QT_TRANSLATE_NOOP(
        "CadRobot_CalibrationFrame", "Add a calibration frame (work object) to the cell: select "
        "three vertices (origin, a point on +X, a point in the XY plane), or a planar face and an "
        "edge in it, or nothing for the current working plane. Then teach it with points "
        "measured on the real part.")
    STATUS_TIP = QT_TRANSLATE_NOOP(
        "CadRobot_CalibrationFrame", "Add a calibration frame from three vertices, a face and an "
                                     "edge, or the working plane")

    def fits(self, doc):
        return selection.find_cell() is not None and frame_source(selection.selected(doc)) is not None

    def run(self, doc):
        from ..gui import calibration_panel      # the panel imports this package
        cell = selection.find_cell()
        source = frame_source(selection.selected(doc))
        if cell is None or source is None:
            return
        if source[0] == "edit":
            calibration_panel.edit(source[1])
            return
        done = run_journaled(doc, self.title(), frame_lines(doc, cell, source), results=["frame"])
        if done:
            select_in_tree(doc, done[0].Name)
            calibration_panel.edit(done[0])
