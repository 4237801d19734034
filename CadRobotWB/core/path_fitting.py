"""Fewest lines and circular arcs through a densely sampled TCP path.

A sensor run gives the corrected TCP path as thousands of samples (one per
control period).  A controller runs it best as a few long moves: this module
fits straight lines and 3D circular arcs to the samples, greedily from the
first one, each move as long as the tolerance allows.

What a fitted move promises (checked on every sample it covers, with the
controller's own interpolation, the one :mod:`core.trajectory` samples):

- position: every sample lies within ``tolerance_mm`` of the move (of the
  segment for a line, of the arc between its ends for an arc);
- orientation: at the sample's place along the move (its fraction of the
  length), the orientation slerped from the move's start to its end is
  within ``angle_tolerance_deg`` of the sample's.

Moves start and end on samples, so consecutive moves join exactly.  Arcs are
fitted with both ends on their end samples: the circle's plane and centre
(two parameters) are fitted by Gauss-Newton least squares from the circle
through the end samples and the sample farthest from their chord.  An arc
sweeps at most 180 degrees (what ``core.generate`` writes too) and sags at
least the tolerance from its chord (a flatter one is a line to a controller:
near-collinear circle points make its circle uncertain).

Pure numpy; no FreeCAD.
"""

from dataclasses import dataclass
from typing import Optional

import numpy as np

from ..errors import InputError
from . import rotations

LINE = "line"
ARC = "arc"
MAX_ARC_SWEEP_RAD = np.pi
_GAUSS_NEWTON_STEPS = 6


def _cross(a, b):
    """Cross product of two 3-vectors (np.cross is slow on single vectors)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


@dataclass
class FittedMove:
    """One move of a fitted path, from the previous move's end sample.

    Attributes
    ----------
    kind : str
        ``"line"`` or ``"arc"``.
    start : int
        Index of the sample the move starts on.
    end : int
        Index of the sample the move ends on (> start).
    via_mm : ndarray, shape (3,), or None
        Arcs: the point halfway along the arc, mm (same frame as the samples).
    """

    kind: str
    start: int
    end: int
    via_mm: Optional[np.ndarray] = None


def _checked(points_mm, R, tolerance_mm, angle_tolerance_deg):
    points = np.asarray(points_mm, dtype=float)
    if points.ndim != 2 or points.shape[1] != 3 or len(points) < 2:
        raise InputError("A path to fit needs at least 2 points of 3 coordinates; got shape %s."
                         % (points.shape,))
    if not np.isfinite(points).all():
        raise InputError("A path to fit has a coordinate that is not a finite number.")
    for name, value in (("tolerance_mm", tolerance_mm), ("angle_tolerance_deg", angle_tolerance_deg)):
        if not (np.isfinite(value) and value > 0):
            raise InputError("The fitting %s must be a finite number > 0, got %r." % (name, value))
    if R is None:
        R = np.repeat(np.eye(3)[None], len(points), axis=0)
    R = np.asarray(R, dtype=float)
    if R.shape != (len(points), 3, 3) or not np.isfinite(R).all():
        raise InputError("A path to fit needs one finite 3x3 rotation per point; got shape %s."
                         % (R.shape,))
    return points, R


def _angle_errors_rad(q, a, b, fractions):
    """Angles between the samples a+1..b-1 and the slerp from a to b at `fractions`."""
    inner = q[a + 1:b]
    interpolated = rotations.quaternion_slerp(q[a], q[b], fractions)
    dot = np.abs(np.sum(inner * interpolated, axis=1))
    return 2.0 * np.arccos(np.clip(dot, -1.0, 1.0))


def _line_fit(points, a, b):
    """(max distance of samples a..b to the segment, their fractions along it)."""
    chord = points[b] - points[a]
    inner = points[a + 1:b] - points[a]
    length2 = float(chord @ chord)
    if length2 == 0.0:
        fractions = np.zeros(len(inner))
    else:
        fractions = np.clip(inner @ chord / length2, 0.0, 1.0)
    distance = np.linalg.norm(inner - fractions[:, None] * chord, axis=1)
    return (float(distance.max()) if len(distance) else 0.0), fractions


class _ArcFrame:
    """Circles through two fixed points A and B, by (theta, t).

    The plane's normal is ``cos(theta) e1 + sin(theta) e2`` (e1, e2 orthogonal
    to AB), the centre ``M + t m`` with M the chord's midpoint and
    ``m = normal x d`` (d the chord's direction) in the plane.
    """

    def __init__(self, A, B):
        self.A, self.B = A, B
        self.M = 0.5 * (A + B)
        self.half = 0.5 * float(np.linalg.norm(B - A))
        self.d = (B - A) / (2.0 * self.half)
        helper = np.eye(3)[int(np.argmin(np.abs(self.d)))]
        self.e1 = _cross(self.d, helper)
        self.e1 /= np.linalg.norm(self.e1)
        self.e2 = _cross(self.d, self.e1)

    def circle(self, theta, t):
        """(centre, unit normal, radius, u, v): point at angle phi = c + r (cos phi u + sin phi v)."""
        normal = np.cos(theta) * self.e1 + np.sin(theta) * self.e2
        m = _cross(normal, self.d)
        centre = self.M + t * m
        radius = float(np.hypot(self.half, t))
        u = (self.A - centre) / radius
        return centre, normal, radius, u, _cross(normal, u)

    def parameters_through(self, P):
        """(theta, t) of the circle through A, P and B, or None if they are collinear."""
        w = _cross(self.B - self.A, P - self.A)
        if np.linalg.norm(w) <= 1e-12 * max(1.0, 4.0 * self.half * self.half):
            return None
        normal = w / np.linalg.norm(w)
        theta = float(np.arctan2(normal @ self.e2, normal @ self.e1))
        # centre on the bisector in the plane: |c - A| = |c - P|
        m = _cross(normal, self.d)
        q = P - self.M
        denominator = 2.0 * float(q @ m)
        t = (float(q @ q) - self.half ** 2) / denominator
        return theta, t

    def residuals(self, theta, t, inner):
        """Signed radial and axial errors of `inner` (K, 3): shape (2K,)."""
        centre, normal, radius, _u, _v = self.circle(theta, t)
        q = inner - centre
        axial = q @ normal
        radial = np.linalg.norm(q - axial[:, None] * normal, axis=1) - radius
        return np.concatenate([radial, axial])


def _arc_fit(points, a, b, tolerance_mm):
    """Fit an arc to samples a..b with its ends on samples a and b.

    Returns
    -------
    (max distance mm, fractions (b-a-1,), via (3,)) or None
        None when no arc within the limits fits (collinear samples, a sweep
        over 180 degrees).
    """
    if b - a < 2 or np.array_equal(points[a], points[b]):
        return None
    frame = _ArcFrame(points[a], points[b])
    inner = points[a + 1:b]
    _, fractions = _line_fit(points, a, b)
    off_chord = np.linalg.norm(inner - points[a] - fractions[:, None] * (points[b] - points[a]), axis=1)
    start = frame.parameters_through(inner[int(np.argmax(off_chord))])
    if start is None:
        return None
    x = np.array(start)
    found = _arc_errors(frame, x, inner)
    if found is not None and found[0] <= tolerance_mm:
        return found          # the circle through the ends and the farthest sample will do
    for _ in range(_GAUSS_NEWTON_STEPS):
        r0 = frame.residuals(x[0], x[1], inner)
        step = 1e-7 * max(1.0, abs(x[1]))
        J = np.column_stack([(frame.residuals(x[0] + 1e-7, x[1], inner) - r0) / 1e-7,
                             (frame.residuals(x[0], x[1] + step, inner) - r0) / step])
        delta = np.linalg.lstsq(J, -r0, rcond=None)[0]
        x = x + delta
        if abs(delta[0]) < 1e-7 and abs(delta[1]) < 1e-7 * max(1.0, abs(x[1])):
            break
    return _arc_errors(frame, x, inner)


def _arc_errors(frame, x, inner):
    centre, _normal, radius, u, v = frame.circle(*x)
    q_end, q_mid = frame.B - centre, inner[len(inner) // 2] - centre
    sweep = float(np.mod(np.arctan2(q_end @ v, q_end @ u), 2.0 * np.pi))
    if np.mod(np.arctan2(q_mid @ v, q_mid @ u), 2.0 * np.pi) > sweep:   # travel the other way round
        v = -v
        sweep = 2.0 * np.pi - sweep
    if not 0.0 < sweep <= MAX_ARC_SWEEP_RAD or not np.isfinite(radius):
        return None
    q = inner - centre
    phi = np.mod(np.arctan2(q @ v, q @ u), 2.0 * np.pi)
    # beyond the sweep: closer to whichever end is nearer in angle
    past = phi > sweep
    phi = np.where(past, np.where(phi - sweep < 2.0 * np.pi - phi, sweep, 0.0), phi)
    nearest = centre + radius * (np.cos(phi)[:, None] * u + np.sin(phi)[:, None] * v)
    distance = np.linalg.norm(inner - nearest, axis=1)
    half = 0.5 * sweep
    via = centre + radius * (np.cos(half) * u + np.sin(half) * v)
    return (float(distance.max()) if len(distance) else 0.0), phi / sweep, via


def _fit(kind, points, q, a, b, tolerance_mm, angle_tolerance_rad):
    """The move of `kind` from sample a to b, or None if it leaves a tolerance."""
    if kind == LINE:
        distance, fractions = _line_fit(points, a, b)
        via = None
    else:
        found = _arc_fit(points, a, b, tolerance_mm)
        if found is None:
            return None
        distance, fractions, via = found
    if distance > tolerance_mm:
        return None
    if b - a > 1 and _angle_errors_rad(q, a, b, fractions).max() > angle_tolerance_rad:
        return None
    return FittedMove(kind, a, b, via)


def _longest(kind, points, q, a, last, tolerance_mm, angle_tolerance_rad, after=0):
    """The longest move of `kind` from sample a ending at or before `last`
    (doubling, then bisection), or None if even the shortest fails: a..a+1 for a
    line, a..after+1 for an arc (an arc is only worth it past the line's end
    `after`; shorter, it sags less than the tolerance)."""
    shortest = a + 1 if kind == LINE else max(a + 2, after + 1)
    if shortest > last:
        return None
    best = _fit(kind, points, q, a, shortest, tolerance_mm, angle_tolerance_rad)
    if best is None:
        return None
    good, span = shortest, 2 * (shortest - a)
    bad = None
    while bad is None:
        b = min(a + span, last)
        if b <= good:
            break
        found = _fit(kind, points, q, a, b, tolerance_mm, angle_tolerance_rad)
        if found is None:
            bad = b
        else:
            good, best = b, found
            if b == last:
                break
        span *= 2
    while bad is not None and bad - good > 1:
        b = (good + bad) // 2
        found = _fit(kind, points, q, a, b, tolerance_mm, angle_tolerance_rad)
        if found is None:
            bad = b
        else:
            good, best = b, found
    return best


def _sag_mm(points, arc):
    """How far an arc's middle (its via point) lies from its chord, mm."""
    return float(np.linalg.norm(arc.via_mm - 0.5 * (points[arc.start] + points[arc.end])))


def _better_arc(arc, line, points, tolerance_mm):
    """True if `arc` goes further than `line` and sags at least the tolerance."""
    return (arc is not None and (line is None or arc.end > line.end)
            and _sag_mm(points, arc) >= tolerance_mm)


def fit_path(points_mm, R=None, tolerance_mm=0.05, angle_tolerance_deg=0.5, breaks=()):
    """Fewest lines and arcs (greedily) within tolerance of sampled TCP poses.

    Parameters
    ----------
    points_mm : array_like, shape (N, 3)
        TCP positions in travel order, mm (N >= 2).
    R : array_like, shape (N, 3, 3), optional
        TCP orientations; default: all the same.
    tolerance_mm : float
        Largest distance of a sample from its fitted move, mm (> 0).
    angle_tolerance_deg : float
        Largest angle between a sample's orientation and the orientation
        slerped along its move, degrees (> 0).
    breaks : sequence of int, optional
        Sample indices where a move must end (e.g. a corner to stop at).

    Returns
    -------
    list of FittedMove
        Consecutive moves from sample 0 to sample N-1: ``moves[0].start == 0``,
        ``moves[k].start == moves[k-1].end``, ``moves[-1].end == N - 1``.

    Raises
    ------
    InputError
        Fewer than 2 points, a coordinate or rotation that is not finite, or
        a tolerance that is not a finite number > 0.
    """
    points, R = _checked(points_mm, R, tolerance_mm, angle_tolerance_deg)
    q = rotations.quaternion_from_matrix(R)     # signs do not matter: compared by |q1 . q2|
    angle_tolerance_rad = np.radians(angle_tolerance_deg)
    stops = sorted({int(i) for i in breaks if 0 < int(i) < len(points) - 1} | {len(points) - 1})
    moves, a = [], 0
    for last in stops:
        while a < last:
            line = _longest(LINE, points, q, a, last, tolerance_mm, angle_tolerance_rad)
            arc = _longest(ARC, points, q, a, last, tolerance_mm, angle_tolerance_rad,
                           after=line.end if line is not None else a)
            move = arc if _better_arc(arc, line, points, tolerance_mm) else line
            if move is None:   # two samples apart by more than the angle tolerance: a line anyway
                move = FittedMove(LINE, a, a + 1)
            moves.append(move)
            a = move.end
    return moves
