"""Finding a path's edges again when a recompute renumbers its object's edges.

A path links edges by name (``Pocket011.Edge37``). FreeCAD may give the same
edge another number when it recomputes the object: an older file whose
PartDesign body recomputes on every recompute in FreeCAD 1.x renumbered 11 of
the 15 edges of Drilling_1's top face in 7 of 11 runs here. The path keeps
where each edge was when it was linked (start, middle and end, in its object's
own frame); an edge no longer there under its name is looked for among the
object's edges by those points. An edge edited on purpose (a sketch dimension
changed) matches no edge of the old points and is read under its name, as
before.
"""

import FreeCAD

from .convert import array_from_vector

#: Two edge points closer than this are the same point, mm.
SAME_POINT_MM = 1e-4


def _local_shape(obj):
    shape = obj.Shape.copy()
    shape.Placement = FreeCAD.Placement()
    return shape


def edge_points(edge):
    """[[x, y, z]] * 3: the edge's start, middle and end, mm."""
    first, last = edge.FirstParameter, edge.LastParameter
    return [list(map(float, array_from_vector(edge.valueAt(t))))
            for t in (first, (first + last) / 2.0, last)]


def remembered_points(links, known=None):
    """{"<object name>.EdgeN": edge_points} of the edges named in `links`
    (a path's Source), in each object's own frame; edges that cannot be read
    are left out. An edge already in `known` (the path's record) keeps its
    record: FreeCAD 1.1 signals a change of Source when the linked object's
    shape changes, with the same names, and the record must stay the one made
    when the edge was linked."""
    known = known or {}
    out = {}
    for obj, subs in links:
        shape = getattr(obj, "Shape", None)
        if shape is None or shape.isNull():
            continue
        local = _local_shape(obj)
        for sub in subs or []:
            key = "%s.%s" % (obj.Name, sub)
            if key in known:
                out[key] = known[key]
            elif sub.startswith("Edge"):
                try:
                    out[key] = edge_points(local.getElement(sub))
                except Exception:  # noqa: BLE001 -- a stale name: nothing to remember
                    continue
    return out


def same_points(points, other):
    """bool: two edge_points lists give the same edge (in either direction)."""
    def close(a, b):
        return all(abs(x - y) <= SAME_POINT_MM for x, y in zip(a, b))
    return (all(close(a, b) for a, b in zip(points, other))
            or all(close(a, b) for a, b in zip(points, reversed(other))))


def current_name(path, obj, sub):
    """The name `sub` of `obj`'s edge the path linked, now: `sub` itself when the
    edge is still there (or when the path remembers nothing of it, or its
    geometry was edited), else the name of the edge at the remembered points.
    FreeCAD 1.x marks an element its element map lost with a leading "?"
    (``?Edge2``): the name without it is looked for the same way."""
    sub = sub.lstrip("?")
    remembered = (getattr(path, "SourceEdgePoints", None) or {}).get("%s.%s" % (obj.Name, sub))
    if not remembered:
        return sub
    local = _local_shape(obj)
    try:
        if same_points(edge_points(local.getElement(sub)), remembered):
            return sub
    except Exception:  # noqa: BLE001 -- the name is gone: look for the edge by its points
        pass
    for k, edge in enumerate(local.Edges, 1):
        if same_points(edge_points(edge), remembered):
            return "Edge%d" % k
    return sub
