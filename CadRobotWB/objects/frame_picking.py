"""Calibration frames from picked geometry: three vertices, or a face and an edge."""

import numpy as np
import Part

from ..core import frames, surface_normals
from ..errors import FrameError, InputError
from .base import describe
from .picking import element, global_shape, plane_of, point_of

WHAT_TO_SELECT = ("Select three vertices (origin, a point on +X, a point in the XY plane), "
                  "or one planar face and one straight edge lying in it.")


def _parse(items):
    """[(kind, obj, element in {U}, name)] of selection items (obj, "VertexN"|"EdgeN"|"FaceN")."""
    out = []
    for item in items or []:
        try:
            obj, name = item
        except (TypeError, ValueError):
            raise InputError("Selection items are (object, 'VertexN') pairs. " + WHAT_TO_SELECT) from None
        kind = name.rstrip("0123456789")
        if kind not in ("Vertex", "Edge", "Face"):
            raise InputError("%s.%s is not a vertex, edge or face. %s"
                         % (obj.Label, name, WHAT_TO_SELECT), obj.Name)
        out.append((kind, obj, element(global_shape(obj), obj, name), name))
    return out


def from_selection(items, near=None):
    """T_u_b (4, 4) of a frame from picked sub-elements (see api.frame_placement_from_selection)."""
    parsed = _parse(items)
    kinds = sorted(kind for kind, *_ in parsed)
    if kinds == ["Vertex"] * 3:
        points = [np.array(tuple(e.Point)) for _, _, e, _ in parsed]
        return frames.frame_from_three_points(*points)
    if kinds == ["Edge", "Face"]:
        (_, fobj, face, fname), = [p for p in parsed if p[0] == "Face"]
        (_, eobj, edge, ename), = [p for p in parsed if p[0] == "Edge"]
        return _from_face_and_edge(fobj, face, fname, eobj, edge, ename, near)
    raise InputError("%d item(s) selected (%s). %s"
                     % (len(parsed), ", ".join(kinds) or "nothing", WHAT_TO_SELECT))


def _from_face_and_edge(fobj, face, fname, eobj, edge, ename, near):
    plane = plane_of(face)
    if plane is None:
        raise FrameError("%s.%s is not planar; select a flat face." % (describe(fobj), fname), fobj.Name)
    if not isinstance(edge.Curve, (Part.Line, Part.LineSegment)):
        raise FrameError("%s.%s is not straight; select a straight edge."
                         % (describe(eobj), ename), eobj.Name)
    ends = [np.array(tuple(edge.valueAt(t))) for t in (edge.FirstParameter, edge.LastParameter)]
    plane_point, normal = plane
    offset = max(abs(float(np.dot(p - plane_point, normal))) for p in ends)
    if offset > 1e-3:
        raise FrameError("%s.%s lies %.3g mm off the plane of %s.%s; select an edge of that face."
                         % (describe(eobj), ename, offset, describe(fobj), fname), eobj.Name)
    if near is not None:
        near = point_of(near)
        if np.linalg.norm(ends[1] - near) < np.linalg.norm(ends[0] - near):
            ends.reverse()
    try:
        return surface_normals.frame_from_normal_and_edge(normal, ends[0], ends[1], tol_rad=1e-5)
    except FrameError as err:
        raise FrameError("%s.%s and %s.%s: %s" % (describe(fobj), fname, describe(eobj), ename, err),
                         eobj.Name) from None
