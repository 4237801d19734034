"""Calibration frames {B}: make them, place them from points or picked geometry, teach
them from points measured on the real part.

Part of the scripting API: :mod:`CadRobotWB.api` re-exports its public names.
"""

from ..core import frames
from ..errors import FrameError
from ..objects import base, calibration_frame, frame_picking
from ..objects.convert import placement_from_matrix, vector_from_array
from .arguments import Arguments
from .common import as_placement


def make_calibration_frame(doc, cell, placement, name="CalibrationFrame"):
    """Add a calibration frame {B} at `placement` (in {U}) to `cell`.

    It becomes the cell's calibration frame if the cell has none yet.
    """
    args = Arguments("make_calibration_frame")
    args.open_document("doc", doc)
    args.cell(cell)
    args.placement("placement", placement)
    args.text("name", name)
    pl = as_placement(placement, "Calibration frame '%s'" % name, FrameError)
    obj = calibration_frame.make(doc, name)
    obj.Placement = pl
    cell.addObject(obj)
    if cell.CalibrationFrame is None:
        cell.CalibrationFrame = obj
    doc.recompute()
    return obj


def frame_placement_from_points(origin, on_x, in_xy):
    """The frame taught by three points, as on a robot controller.

    Parameters
    ----------
    origin, on_x, in_xy : FreeCAD.Vector or sequence of 3 floats
        The origin, a point on +X and a point in the XY plane (+Y side), {U}, mm.

    Returns
    -------
    FreeCAD.Placement
        FrameError when the points coincide or are collinear.
    """
    args = Arguments("frame_placement_from_points")
    points = [args.point(argument, p) for argument, p in
              (("origin", origin), ("on_x", on_x), ("in_xy", in_xy))]
    return placement_from_matrix(frames.frame_from_three_points(*points))


def frame_placement_from_selection(items, near=None):
    """A frame from picked sub-elements, in {U}.

    Parameters
    ----------
    items : list of (App.DocumentObject, str)
        Exactly three ``"VertexN"`` (origin, on +X, in the XY plane), or one
        planar ``"FaceN"`` and one straight ``"EdgeN"`` lying in its plane,
        in any order: Z = the face's outward normal, X along the edge.
    near : FreeCAD.Vector or sequence of 3 floats, optional
        A picked point, mm: the origin is the edge end nearest it (default
        the edge's first vertex), X points to the other end.

    Returns
    -------
    FreeCAD.Placement
        InputError / FrameError saying what to select for anything else.
    """
    args = Arguments("frame_placement_from_selection")
    if not isinstance(items, (list, tuple)):
        args.refuse("items", "a list of (object, 'VertexN') pairs", items)
    for k, item in enumerate(items):
        args.sub_element("items[%d]" % k, item)
    args.point("near", near, optional=True)
    return placement_from_matrix(frame_picking.from_selection(items, near))


def teach_calibration_frame(frame, cad_points, measured_points):
    """Teach `frame` from points measured on the real part.

    Parameters
    ----------
    cad_points : sequence of N >= 3 points (FreeCAD.Vector or 3 floats)
        Points of the part as drawn, {U}, mm.
    measured_points : sequence of N points
        The same points measured with the robot, in its base frame {R}, mm.

    Returns
    -------
    list of float
        Distance of each measured point from its fitted CAD point, mm.

    Raises
    ------
    FrameError
        Counts differ, fewer than 3 pairs, or collinear points; the frame is unchanged.
    """
    args = Arguments("teach_calibration_frame")
    args.document_object("frame", frame, "CalibrationFrame", subject=True)
    cad = args.points("cad_points", cad_points)
    measured = args.points("measured_points", measured_points)
    if len(cad) != len(measured):
        raise FrameError("Calibration frame %s: %d CAD points but %d measured points; give one "
                         "measured point per CAD point." % (base.describe(frame), len(cad), len(measured)),
                         frame.Name)
    residuals = calibration_frame.fit_points(frame, cad, measured)[1]
    frame.CadPoints = [vector_from_array(p) for p in cad]
    frame.MeasuredPoints = [vector_from_array(p) for p in measured]
    frame.UseTaught = True
    frame.Document.recompute()
    return [float(r) for r in residuals]


def taught_frame(frame):
    """(T_r_b FreeCAD.Placement, residuals list mm) of a taught frame, or None when it is
    not taught (UseTaught off). T_r_b = fit(CAD points -> measured points) @ T_u_b;
    FrameError when its points cannot be fitted."""
    Arguments("taught_frame").document_object("frame", frame, "CalibrationFrame")
    taught = calibration_frame.taught_transform(frame)
    if taught is None:
        return None
    return placement_from_matrix(taught[0]), [float(r) for r in taught[1]]
