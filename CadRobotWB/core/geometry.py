"""Path geometry: lines, arcs and sampled curves, and chaining them into one path.

Every segment lives in the CAD assembly frame {U}, in millimetres, and is
parametrised by its arc length ``s`` (mm) measured from ``start``. Every
segment class offers the same interface:

``kind``
    ``"line"``, ``"arc"`` or ``"spline"``; decides the robot move type.
``source``
    Where the segment comes from, e.g. ``"Sketch.Edge3"`` (used in messages).
``start``, ``end`` : ndarray, shape (3,)
``length`` : float, mm
``point_at(s)`` -> (3,), ``points_at(s)`` -> (N, 3), ``tangent_at(s)`` -> (3,) unit
``reversed()``, ``closest(p)`` -> ``(distance_mm, s_mm)``, ``transformed(T)``

:func:`chain_segments` orders edges drawn in any order and direction into one
continuous path; :func:`assign_point` finds the segment a tool marker lies on.

Pure numpy; never imports FreeCAD.
"""

import math

import numpy as np
from scipy.spatial import cKDTree

from ..errors import GeometryError
from . import frames

# Radius below which an arc is degenerate, mm.
_MIN_RADIUS_MM = 1e-9


def _vec3(p, what="point"):
    a = np.asarray(p, dtype=float).reshape(-1)
    if a.shape != (3,) or not (math.isfinite(a[0]) and math.isfinite(a[1])
                               and math.isfinite(a[2])):
        raise GeometryError("A %s must be 3 finite numbers (mm), got %r." % (what, p))
    return a


def _describe(seg, fallback):
    """Name of a segment in messages: its source, else ``fallback``."""
    return seg.source if getattr(seg, "source", "") else fallback


class Line:
    """A straight segment from ``start`` to ``end``.

    Parameters
    ----------
    start, end : array_like, shape (3,)
        End points in {U}, mm.
    source : str, optional
        Origin of the segment, e.g. ``"Sketch.Edge1"``.
    """

    kind = "line"

    def __init__(self, start, end, source=""):
        self.start = _vec3(start, "line start")
        self.end = _vec3(end, "line end")
        self.source = source
        step = self.end - self.start
        self.length = math.sqrt(float(step.dot(step)))
        self._direction = step / self.length if self.length > 0.0 else np.zeros(3)

    def __repr__(self):
        return "Line(%s -> %s, source=%r)" % (self.start, self.end, self.source)

    def point_at(self, s):
        """Point at arc length ``s`` (mm, clipped to [0, length]); shape (3,)."""
        return self.points_at(np.array([s], dtype=float))[0]

    def points_at(self, s):
        """Points at arc lengths ``s`` (mm), shape (N,) -> (N, 3)."""
        s = np.clip(np.asarray(s, dtype=float).reshape(-1), 0.0, self.length)
        return self.start + s[:, None] * self._direction

    def tangent_at(self, s):
        """Unit direction of travel at ``s`` (mm); shape (3,), the same everywhere."""
        return self._direction.copy()

    def reversed(self):
        """The same line travelled from ``end`` to ``start``."""
        return Line(self.end, self.start, self.source)

    def closest(self, p):
        """Closest point of the line to ``p``.

        Parameters
        ----------
        p : array_like, shape (3,)
            Point in {U}, mm.

        Returns
        -------
        distance_mm : float
        s_mm : float
            Arc length of the closest point, in [0, length].
        """
        p = _vec3(p)
        s = float(np.clip(np.dot(p - self.start, self._direction), 0.0, self.length))
        return float(np.linalg.norm(p - self.point_at(s))), s

    def transformed(self, T):
        """The line moved by the rigid transform ``T`` (4, 4)."""
        return Line(frames.transform_points(T, self.start),
                    frames.transform_points(T, self.end), self.source)


class Arc:
    """A circular arc, travelled counter-clockwise about ``normal``.

    The point at arc length ``s`` is ``c + r (cos(phi) u + sin(phi) v)`` with
    ``phi = s / r``, ``u = (start - c) / r`` and ``v = normal x u``.

    Parameters
    ----------
    center : array_like, shape (3,)
        Centre of the circle in {U}, mm. If it is not in the plane through
        ``start`` perpendicular to ``normal``, it is slid along the axis into
        that plane (any point of the axis describes the same circle).
    normal : array_like, shape (3,)
        Axis of the circle; normalised here. Travel is counter-clockwise
        seen from its tip.
    start : array_like, shape (3,)
        First point of the arc, mm.
    sweep_rad : float
        Swept angle in (0, 2*pi] radians; 2*pi is a full circle.
    source : str, optional

    Raises
    ------
    GeometryError
        Zero normal, zero radius, or a sweep outside (0, 2*pi].
    """

    kind = "arc"

    def __init__(self, center, normal, start, sweep_rad, source=""):
        self.source = source
        name = source or "an arc"
        normal = _vec3(normal, "arc normal")
        norm = np.linalg.norm(normal)
        if norm < 1e-12:
            raise GeometryError("%s has a zero normal vector; redraw it." % name)
        self.normal = normal / norm
        self.start = _vec3(start, "arc start")
        center = _vec3(center, "arc centre")
        self.center = center + np.dot(self.start - center, self.normal) * self.normal
        self.radius = float(np.linalg.norm(self.start - self.center))
        if self.radius <= _MIN_RADIUS_MM:
            raise GeometryError("%s has zero radius; redraw it." % name)
        self.sweep_rad = float(sweep_rad)
        if not (0.0 < self.sweep_rad <= 2.0 * np.pi + 1e-12):
            raise GeometryError(
                "%s sweeps %.6g rad; an arc must sweep more than 0 and at most 2*pi rad."
                % (name, self.sweep_rad))
        self.sweep_rad = min(self.sweep_rad, 2.0 * np.pi)
        self._u = (self.start - self.center) / self.radius
        self._v = np.cross(self.normal, self._u)
        self.length = self.radius * self.sweep_rad
        self.end = self.point_at(self.length)
        self.mid = self.point_at(0.5 * self.length)

    def __repr__(self):
        return ("Arc(center=%s, normal=%s, start=%s, sweep_rad=%.6g, source=%r)"
                % (self.center, self.normal, self.start, self.sweep_rad, self.source))

    @classmethod
    def from_three_points(cls, start, via, end, source=""):
        """The arc from ``start`` through ``via`` to ``end``.

        Parameters
        ----------
        start, via, end : array_like, shape (3,)
            Three distinct, non-collinear points in {U}, mm, in travel order.
        source : str, optional

        Returns
        -------
        Arc
            Sweep in (0, 2*pi); the normal is chosen so that travel from
            ``start`` through ``via`` to ``end`` is counter-clockwise.

        Raises
        ------
        GeometryError
            If the points are collinear or two of them coincide.
        """
        a, b, c = _vec3(start), _vec3(via), _vec3(end)
        ab, ac = b - a, c - a
        w = np.cross(ab, ac)
        w2 = float(np.dot(w, w))
        scale = max(np.dot(ab, ab), np.dot(ac, ac), 1e-300)
        if w2 <= 1e-24 * scale * scale:
            raise GeometryError(
                "%s: the three points %s, %s, %s are collinear or coincide, so they "
                "do not define an arc." % (source or "Arc", a, b, c))
        # Circumcentre: a + (|ab|^2 (ac x w) + |ac|^2 (w x ab)) / (2 |w|^2)
        center = a + (np.dot(ab, ab) * np.cross(ac, w)
                      + np.dot(ac, ac) * np.cross(w, ab)) / (2.0 * w2)
        normal = w / np.sqrt(w2)
        u = a - center
        v = np.cross(normal, u)
        d = c - center
        sweep = float(np.mod(np.arctan2(np.dot(d, v), np.dot(d, u)), 2.0 * np.pi))
        return cls(center, normal, a, sweep, source)

    def point_at(self, s):
        """Point at arc length ``s`` (mm, clipped to [0, length]); shape (3,)."""
        return self.points_at(np.array([s], dtype=float))[0]

    def points_at(self, s):
        """Points at arc lengths ``s`` (mm), shape (N,) -> (N, 3)."""
        s = np.clip(np.asarray(s, dtype=float).reshape(-1), 0.0, self.length)
        phi = s / self.radius
        return self.center + self.radius * (np.cos(phi)[:, None] * self._u
                                            + np.sin(phi)[:, None] * self._v)

    def tangent_at(self, s):
        """Unit direction of travel at arc length ``s`` (mm); shape (3,)."""
        phi = float(np.clip(s, 0.0, self.length)) / self.radius
        return -np.sin(phi) * self._u + np.cos(phi) * self._v

    def reversed(self):
        """The same arc travelled from ``end`` back to ``start`` (normal negated)."""
        return Arc(self.center, -self.normal, self.end, self.sweep_rad, self.source)

    def closest(self, p):
        """Closest point of the arc to ``p``.

        ``p`` is projected onto the arc's plane; its angle from ``start`` is
        used when it lies within the sweep, otherwise the nearer end point.

        Parameters
        ----------
        p : array_like, shape (3,)
            Point in {U}, mm.

        Returns
        -------
        distance_mm : float
        s_mm : float
            Arc length of the closest point, in [0, length].
        """
        p = _vec3(p)
        q = p - self.center
        phi = float(np.mod(np.arctan2(np.dot(q, self._v), np.dot(q, self._u)), 2.0 * np.pi))
        if phi >= 2.0 * np.pi:      # mod can round up to exactly 2*pi
            phi = 0.0
        if phi <= self.sweep_rad:
            s = phi * self.radius
        else:
            d_start = np.linalg.norm(p - self.start)
            d_end = np.linalg.norm(p - self.end)
            s = 0.0 if d_start <= d_end else self.length
        return float(np.linalg.norm(p - self.point_at(s))), float(s)

    def transformed(self, T):
        """The arc moved by the rigid transform ``T`` (4, 4)."""
        return Arc(frames.transform_points(T, self.center),
                   frames.transform_vectors(T, self.normal),
                   frames.transform_points(T, self.start), self.sweep_rad, self.source)


class Polyline:
    """A curve already sampled within the chord tolerance, arc-length parametrised.

    Used for B-splines, Bezier curves, ellipses: the robot follows it with
    linear moves through the samples (or a spline move where the language
    has one).

    Parameters
    ----------
    points : array_like, shape (N, 3)
        Samples in travel order in {U}, mm, N >= 2. Consecutive duplicates
        are dropped.
    kind : str, optional
        ``"spline"`` (default).
    source : str, optional
    """

    def __init__(self, points, kind="spline", source=""):
        pts = np.asarray(points, dtype=float)
        if pts.ndim != 2 or pts.shape[1] != 3 or len(pts) < 2 or not np.all(np.isfinite(pts)):
            raise GeometryError("%s needs at least 2 sample points of 3 finite "
                                "coordinates (mm)." % (source or "A polyline"))
        keep = np.ones(len(pts), dtype=bool)
        keep[1:] = np.linalg.norm(np.diff(pts, axis=0), axis=1) > 1e-12
        if keep.sum() < 2:
            keep[-1] = True     # all samples coincide: a zero-length curve
        self.points = pts[keep]
        self.kind = kind
        self.source = source
        chords = np.linalg.norm(np.diff(self.points, axis=0), axis=1)
        self._cum = np.concatenate([[0.0], np.cumsum(chords)])
        self.length = float(self._cum[-1])
        self.start = self.points[0].copy()
        self.end = self.points[-1].copy()

    def __repr__(self):
        return "Polyline(%d points, kind=%r, source=%r)" % (len(self.points), self.kind,
                                                            self.source)

    def point_at(self, s):
        """Point at arc length ``s`` (mm, clipped to [0, length]); shape (3,)."""
        return self.points_at(np.array([s], dtype=float))[0]

    def points_at(self, s):
        """Points at arc lengths ``s`` (mm), shape (N,) -> (N, 3)."""
        s = np.clip(np.asarray(s, dtype=float).reshape(-1), 0.0, self.length)
        return np.column_stack([np.interp(s, self._cum, self.points[:, i])
                                for i in range(3)])

    def tangent_at(self, s):
        """Unit direction of the chord containing ``s`` (the following chord
        at a sample point, the last chord at the end); shape (3,)."""
        i = int(np.searchsorted(self._cum, s, side="right")) - 1
        i = min(max(i, 0), len(self.points) - 2)
        d = self.points[i + 1] - self.points[i]
        n = np.linalg.norm(d)
        return d / n if n > 0 else np.zeros(3)

    def reversed(self):
        """The same curve travelled from ``end`` to ``start``."""
        return Polyline(self.points[::-1], self.kind, self.source)

    def closest(self, p):
        """Closest point of the polyline to ``p``.

        Parameters
        ----------
        p : array_like, shape (3,)
            Point in {U}, mm.

        Returns
        -------
        distance_mm : float
        s_mm : float
            Arc length of the closest point, in [0, length].
        """
        p = _vec3(p)
        a = self.points[:-1]
        d = self.points[1:] - a
        dd = np.einsum("ij,ij->i", d, d)
        t = np.einsum("ij,ij->i", p - a, d) / np.where(dd > 0, dd, 1.0)
        t = np.clip(t, 0.0, 1.0)
        q = a + t[:, None] * d
        dist = np.linalg.norm(p - q, axis=1)
        i = int(np.argmin(dist))
        return float(dist[i]), float(self._cum[i] + t[i] * np.sqrt(dd[i]))

    def transformed(self, T):
        """The polyline moved by the rigid transform ``T`` (4, 4)."""
        return Polyline(frames.transform_points(T, self.points), self.kind, self.source)


def chain_segments(segments, tol_mm, path_label=""):
    """Order segments into one continuous path.

    The chain starts from ``segments[0]`` in its own direction, extends
    forward from its end, then backward from its start; every other segment
    is reversed where needed so that each one starts where the previous one
    ends. The result is deterministic.

    Parameters
    ----------
    segments : sequence of Line, Arc or Polyline
        In any order and direction, in {U}, mm.
    tol_mm : float
        Largest gap between two segment ends that still counts as joined, mm.
    path_label : str, optional
        Label of the path, for messages.

    Returns
    -------
    ordered : list of segments
        In travel order; ``ordered[i].end`` meets ``ordered[i + 1].start``.
    closed : bool
        True when the end of the last segment meets the start of the first.

    Raises
    ------
    GeometryError
        No segments; a segment of length <= ``tol_mm``; three or more segment
        ends meeting at one point (a branch); a segment that does not connect
        (the message names both segments and the gap in mm).
    """
    where = "Path '%s'" % path_label if path_label else "The path"
    segments = list(segments)
    tol = float(tol_mm)
    if not segments:
        raise GeometryError("%s has no segments. Give it a sketch, wire or edges to follow."
                            % where)
    names = [_describe(seg, "segment %d" % (i + 1)) for i, seg in enumerate(segments)]
    for seg, name in zip(segments, names):
        if seg.length <= tol:
            raise GeometryError(
                "%s: %s has zero length (%.3f mm <= tolerance %.3f mm). Delete it from "
                "the drawing or the path." % (where, name, seg.length, tol))

    # Branch check: no point may be the end of more than two segment ends.
    ends = np.array([p for seg in segments for p in (seg.start, seg.end)])   # (2N, 3)
    tree = cKDTree(ends)                 # neighbour queries in O(log N), no (2N, 2N) matrix
    neighbours = tree.query_ball_point(ends, tol)
    for e in range(len(ends)):
        near = sorted(neighbours[e])
        if len(near) >= 3:
            involved = sorted(set(int(k) // 2 for k in near))
            raise GeometryError(
                "%s branches at (%.3f, %.3f, %.3f) mm: %s meet there. A path must be one "
                "chain without forks; split it into several paths."
                % (where, ends[e][0], ends[e][1], ends[e][2],
                   ", ".join(names[k] for k in involved)))

    # With no branch, an end meets at most one end of another segment: its mate.
    mate = {}
    for e, near in enumerate(neighbours):
        others = [k for k in near if k // 2 != e // 2]
        if others:
            mate[e] = others[0]

    def is_closed(first, last):
        return bool(np.linalg.norm(last.end - first.start) <= tol)

    ordered = [segments[0]]
    order_idx = [0]
    used = {0}
    closed = is_closed(ordered[0], ordered[-1])
    exit_end = 1                                            # forward from segment 0's end
    while not closed and exit_end in mate and mate[exit_end] // 2 not in used:
        e = mate[exit_end]
        k, is_start = e // 2, e % 2 == 0
        ordered.append(segments[k] if is_start else segments[k].reversed())
        order_idx.append(k)
        used.add(k)
        exit_end = e ^ 1                                    # the segment's other end
        closed = is_closed(ordered[0], ordered[-1])
    before, before_idx = [], []
    entry_end = 0                                           # backward from its start
    while not closed and entry_end in mate and mate[entry_end] // 2 not in used:
        e = mate[entry_end]
        k, is_start = e // 2, e % 2 == 0
        before.append(segments[k] if not is_start else segments[k].reversed())
        before_idx.append(k)
        used.add(k)
        entry_end = e ^ 1
    ordered = before[::-1] + ordered
    order_idx = before_idx[::-1] + order_idx

    if len(used) < len(segments):
        _raise_stray(where, names, ends, ordered, order_idx, used, closed, tol)
    return ordered, closed


def _raise_stray(where, names, ends, ordered, order_idx, used, closed, tol):
    """Report the segment left out of the chain nearest to the chain's free ends (or to
    any end of the chain when it is a closed loop), with the gap."""

    def nearest_unused(point):
        """(segment, is_start, gap) of the unused segment end nearest to point (the
        first in segment order, start before end, on a tie)."""
        candidates = np.array([e for e in range(len(ends)) if e // 2 not in used])
        gaps = np.linalg.norm(ends[candidates] - point, axis=1)
        best = min(range(len(candidates)), key=lambda i: (gaps[i], candidates[i]))
        e = int(candidates[best])
        return e // 2, e % 2 == 0, float(gaps[best])

    if closed:
        anchors = [(i, p) for i, seg in zip(order_idx, ordered) for p in (seg.start, seg.end)]
    else:
        anchors = [(order_idx[0], ordered[0].start), (order_idx[-1], ordered[-1].end)]
    best = None
    for i, point in anchors:
        k, _, gap = nearest_unused(point)
        if best is None or gap < best[2]:
            best = (i, k, gap)
    i, k, gap = best
    hint = ("Close the gap in the drawing or raise the path's ConnectTolerance."
            if not closed else
            "%s is not part of the closed loop: remove it from the path or close "
            "the gap in the drawing." % names[k])
    raise GeometryError(
        "%s: %s and %s do not connect (gap %.3f mm > tolerance %.3f mm). %s"
        % (where, names[i], names[k], gap, tol, hint))


def assign_point(ordered, p, tol_mm):
    """The segment a point (e.g. a tool marker's origin) lies on.

    Parameters
    ----------
    ordered : sequence of segments
        A chained path (see :func:`chain_segments`), {U}, mm.
    p : array_like, shape (3,)
        Point in {U}, mm.
    tol_mm : float
        Largest distance from a segment that still counts as on it, mm.

    Returns
    -------
    int or None
        0-based index into ``ordered``, or None when the point is on no
        segment. A point at a junction belongs to the segment that starts
        there (the last segment for the end of an open path); otherwise the
        nearest segment wins (the first one on a tie).
    """
    p = _vec3(p)
    best, best_dist = None, None
    for i, seg in enumerate(ordered):
        if np.linalg.norm(p - seg.start) <= tol_mm:
            return i
        dist, _ = seg.closest(p)
        if dist <= tol_mm and (best_dist is None or dist < best_dist):
            best, best_dist = i, dist
    return best
