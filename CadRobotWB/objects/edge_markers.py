"""TCP poses on picked edges: point, travel direction and the surface normal there."""


from ..core import surface_normals
from ..errors import InputError
from . import edge_identity, reader
from .base import describe
from .picking import adjacent_normals, element, global_shape, normal_at, point_of

# Chord tolerance used to turn a picked curved edge into a core segment, mm.
PICK_CHORD_TOL_MM = 0.01


def source_elements(path):
    """{source string: (obj, "EdgeN")} for the edges of `path` (keys as in its segments)."""
    out = {}
    for obj, subs in path.Source or []:
        subs = [s for s in (subs or []) if s]
        if not subs:
            subs = ["Edge%d" % (i + 1) for i in range(len(obj.Shape.Edges))]
        for sub in subs:
            sub = edge_identity.current_name(path, obj, sub)
            out["%s.%s" % (obj.Label, sub)] = (obj, sub)
    return out


def edge_point(obj, edge_name, point=None):
    """(shape {U}, edge, point (3,), tangent (3,)) on `obj`'s edge at the point nearest
    `point` ({U}), or at mid-length; the tangent follows the edge's own direction."""
    shape = global_shape(obj)
    if not edge_name.startswith("Edge"):
        raise InputError("%s.%s is not an edge; select an edge." % (obj.Label, edge_name), obj.Name)
    edge = element(shape, obj, edge_name)
    segment = reader.segment_from_edge(edge, "%s.%s" % (obj.Label, edge_name), PICK_CHORD_TOL_MM)
    s = segment.length / 2.0 if point is None else segment.closest(point_of(point))[1]
    return shape, edge, segment.point_at(s), segment.tangent_at(s)


def travel_tangent(path, point):
    """Unit travel direction (3,) of `path` at `point` (travel order, Reversed honoured)."""
    segments = reader.path_geometry(path)[0]
    distance, s, seg = min((seg.closest(point) + (seg,) for seg in segments), key=lambda c: c[0])
    tol = max(float(path.ConnectTolerance), float(path.MarkerTolerance))
    if distance > tol:
        raise InputError("The picked point is %.3f mm from path %s; pick an edge of that path."
                         % (distance, describe(path)), path.Name)
    return seg.tangent_at(s)


def surface_normal(doc, point, tangent, obj=None, shape=None, edge=None, face=None, what=""):
    """Unit normal (3,) the tool faces: `face`'s ((obj, "FaceN")) at `point`, or
    the bisector of the faces adjacent to the edge. InputError when there is none."""
    if face is not None:
        fobj, fname = face
        if not fname.startswith("Face"):
            raise InputError("%s.%s is not a face; select a face." % (fobj.Label, fname), fobj.Name)
        picked = element(global_shape(fobj), fobj, fname)
        return normal_at(picked, point)
    normals = adjacent_normals(doc, point, tangent, owner=obj, owner_shape=shape, edge=edge)
    if not normals:
        raise InputError("No face meets %s, so the tool direction is unknown: select a face too."
                         % (what or "the edge"), obj.Name if obj is not None else None)
    return surface_normals.bisector(normals)


def edge_pose(obj, edge_name, point=None, face=None, path=None):
    """(point (3,), travel direction (3,), surface normal (3,)) in {U} on an edge."""
    shape, edge, p, tangent = edge_point(obj, edge_name, point)
    if path is not None:
        tangent = travel_tangent(path, p)
    normal = surface_normal(obj.Document, p, tangent, obj, shape, edge, face,
                            what="%s.%s" % (describe(obj), edge_name))
    return p, tangent, normal


def segment_poses(path):
    """[(segment number, source, point, tangent, normal)] at every segment's mid-length.

    InputError naming the first segment without an adjacent face.
    """
    segments = reader.path_geometry(path)[0]
    sources = source_elements(path)
    out = []
    for k, seg in enumerate(segments, start=1):
        p = seg.point_at(seg.length / 2.0)
        tangent = seg.tangent_at(seg.length / 2.0)
        obj, edge_name = sources[seg.source]
        shape = global_shape(obj)
        edge = element(shape, obj, edge_name)
        try:
            normal = surface_normal(path.Document, p, tangent, obj, shape, edge,
                                    what="segment %d (%s) of path %s" % (k, seg.source, describe(path)))
        except InputError as err:
            raise InputError(str(err), path.Name) from None
        out.append((k, seg.source, p, tangent, normal))
    return out
