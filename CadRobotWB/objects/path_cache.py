"""The last reading of each path, kept until something it was read from changes.

Reading a path (FreeCAD edges into core segments, then one chain) takes about
a second for a 20,000-edge polyline, and one recompute needs it several
times: the path's own shape, its risk areas, the cell's tool markers
(``Governs``), the 3D view's targets and highlights.  Each path's reading is
kept here with a fingerprint of everything it depends on: the path's
tolerances and direction, and per source object its name, label, picked
edges, global placement and shape.  The shape is compared with
``TopoShape.isEqual`` (the same OCC shape, location and orientation); the
fingerprint holds the old shape, so its memory cannot be reused by a new one.
"""

from collections import OrderedDict

from .base import global_placement

#: Paths whose reading is kept (the least recently used is dropped first).
CACHE_SIZE = 16

_readings = OrderedDict()      # (document name, path name) -> _Kept


def fingerprint(path):
    """What reading `path` depends on.

    Returns
    -------
    tuple
        ``(chord_tol_mm, connect_tol_mm, reversed, sources)`` with one
        ``(document, name, label, sub-elements, placement matrix, Shape or
        None)`` per source link.
    """
    sources = tuple((obj.Document.Name, obj.Name, obj.Label, tuple(subs or ()),
                     tuple(global_placement(obj).toMatrix().A), getattr(obj, "Shape", None))
                    for obj, subs in path.Source or [])
    return float(path.ChordTolerance), float(path.ConnectTolerance), bool(path.Reversed), sources


def _same_shape(a, b):
    if a is None or b is None:
        return a is b
    return a.isEqual(b)


def same_fingerprint(a, b):
    """bool: fingerprints `a` and `b` describe the same input."""
    if a[:3] != b[:3] or len(a[3]) != len(b[3]):
        return False
    return all(x[:5] == y[:5] and _same_shape(x[5], y[5]) for x, y in zip(a[3], b[3]))


class _Kept:
    """One path's reading, its fingerprint, and what was derived from it."""

    def __init__(self, fingerprint, reading):
        self.fingerprint = fingerprint
        self.reading = reading
        self.derived = {}


def reading(path, read):
    """``read(path)``, or its kept result when nothing it depends on changed.

    Parameters
    ----------
    path : RobotPath object
    read : callable
        ``read(path) -> (segments, closed, edges)`` (``reader``'s own
        reading); what it raises is passed on and nothing is kept.

    Returns
    -------
    segments : list
    closed : bool
    edges : dict
        New list and dict each call (the segments themselves are shared and
        never changed by their users).
    """
    key = (path.Document.Name, path.Name)
    now = fingerprint(path)
    kept = _readings.get(key)
    if kept is not None and same_fingerprint(kept.fingerprint, now):
        _readings.move_to_end(key)
    else:
        kept = _Kept(now, read(path))
        _readings[key] = kept
        while len(_readings) > CACHE_SIZE:
            _readings.popitem(last=False)
    segments, closed, edges = kept.reading
    return list(segments), closed, dict(edges)


def derived(path, segments, name, make):
    """``make()``, kept with `path`'s reading while that reading lasts.

    Parameters
    ----------
    path : RobotPath object
    segments : list
        The segments :func:`reading` just gave for `path`; when the kept
        reading is another one (changed or dropped since), ``make()`` is
        returned without being kept.
    name : hashable
        What is derived (e.g. ``("locator", tolerance)``).
    make : callable
        ``make() -> object`` computed from `segments`.
    """
    kept = _readings.get((path.Document.Name, path.Name))
    kept_segments = kept.reading[0] if kept is not None else None
    if kept_segments is None or len(kept_segments) != len(segments) or \
            any(a is not b for a, b in zip(kept_segments[:1], segments[:1])):
        return make()
    if name not in kept.derived:
        kept.derived[name] = make()
    return kept.derived[name]


def forget():
    """Drop every kept reading (tests, benchmarks)."""
    _readings.clear()
