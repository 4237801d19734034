"""How fast the external axes move along a weld (or a path without welds), and the pass
that bounds it (issue 23).

**The motion.** A coordinated linear or circular move interpolates the external
axes linearly from its start target's values to its end target's, while the TCP
runs at the programmed speed relative to the part (plan issue 23, section 1;
:mod:`..motion.move_sampling`). A move's duration therefore does not depend on
the axis values: it is ``T = max(L / v, angle / v_ori)``, with ``L`` the path
length in the work frame, ``v`` the programmed speed, ``angle`` the tool's
rotation and ``v_ori`` the orientation speed (500 deg/s by default), exactly as
the sampler and Check time it. Over move ``k`` an axis moves at ``delta_k / T_k``.

**Acceleration at a corner.** At a target between two moves whose zone is
``r > 0`` the TCP is inside the zone from ``r`` before the target to ``r`` after
it, for ``B = r T_in / L_in + r T_out / L_out`` seconds (each half at its move's
TCP speed; :func:`corner_time_s`); the axis changes speed from ``v_in`` to
``v_out`` within that time, so it needs at least ``|v_out - v_in| / B`` (the mean
over the blend: no speed profile gets by with a lower peak; :func:`corner_accels`).
At a fine target (zone 0) the TCP stops and the axes stop with it, each on its
own trapezoid at ``max_accel`` (``..motion.timing.axis_move_time``): no limit is
broken there, the cycle time counts it. Unverified: that a controller spreads
the axes' change of speed over the TCP's zone. ABB's zonedata has zones of its
own for the external axes (``pzone_eax`` in mm of TCP travel, ``zone_leax``,
``zone_reax``; RobotComponents' zonedata documentation), taken here as the TCP's;
no KUKA, FANUC or Yaskawa manual was reachable from here.

**The pass** (:func:`limit_axis`, called by ``choose.choose_external``). The
chooser first puts every welded target exactly in its position. Where those
values need an axis faster than its ``max_speed`` or a corner needing more than
its ``max_accel``, the values of that axis along the weld run are moved, within
a band per target, to the nearest values (least total change, an L1 norm: only
where needed) whose speeds and corner accelerations are within the limits: a
linear programme (speeds, accelerations and the bands are all linear in the
values, the durations being fixed), solved with ``scipy.optimize.linprog``
(HiGHS). Via points of circular moves are not knots of the motion (the axes run
linearly from a move's start to its end): a changed run's via takes the
interpolated value at its fraction of the move, and that value is held in its
own band. A run starts and ends at fine points (``core.generate`` gives the
arc's start and end zone 0), so its ends have no acceleration limit; the
targets copying a run's first or last values (approach, retract) follow them.
The band comes from the positioner's gravity-angle tolerance (:func:`band_deg`):
turning an axis by ``delta`` turns the part vector held down (the weld frame's
Z for PA, :func:`.seams.down_vectors`) by ``2 asin(sin(alpha) sin(delta / 2))``,
``alpha`` the angle between the axis and that vector; the turns of several
axes add at most (triangle inequality on the sphere), so the slack left at each
target (tolerance minus its deviation at the exact values) is shared equally by
the axes the pass moves. A PB seam stays within the slack too: its gravity
angle and its slope each move by at most the vector's turn. A path without
welds is limited over each stretch of its linear and circular moves in one
work frame (:func:`run_motions`), its tool axis held as a PA seam's vector is,
within the tolerance of where the chooser turned it. A stretch's ends have no
acceleration limit: next to a joint move or at the path's end Check sees no
corner either (it times linear and circular moves only); a blended corner
into a move changing work frame is left to Check. A track moves no seam: its
values may move within an interval per target (the travel keeping the target
within the reach band the chooser keeps, ``choose._travel_bands``), which
:func:`limit_axis_between` takes as bounds.

Pure numpy / scipy: never imports FreeCAD.
"""

from dataclasses import dataclass

import numpy as np

from ...core import program as ir
from ..motion.move_sampling import Margins

#: The pass aims this much inside the limits, so a check at the same numbers passes.
LIMIT_MARGIN = 1e-6


@dataclass
class RunMotion:
    """One weld run's welded motion (or a stretch of a path without welds), as the
    external axes see it.

    Knot ``i`` is the end target of the run's move ``i`` (knot 0: the run's start
    target, where the arc strikes); move ``k`` of the motion runs from knot ``k``
    to knot ``k + 1``.

    Attributes
    ----------
    run : str
        ``WeldRun.name`` (``"path:<name>"`` for a path without welds).
    knots : ndarray of int, shape (n,)
        Their rows in the seam table (``Program.targets()`` order).
    time_s : ndarray, shape (n - 1,)
        Each move's duration at its programmed speed, s.
    corner_s : ndarray, shape (n,)
        Time the TCP spends in each knot's zone (:func:`corner_time_s`); 0 at
        the ends and at fine targets: no acceleration limit there.
    vias : ndarray of int, shape (m,)
        Rows of the via points of the run's circular moves.
    via_move : ndarray of int, shape (m,)
        The move (0 .. n - 2) each via belongs to.
    via_fraction : ndarray, shape (m,)
        Where along its move the via is (its share of the arc), 0 to 1.
    """

    run: str
    knots: np.ndarray
    time_s: np.ndarray
    corner_s: np.ndarray
    vias: np.ndarray
    via_move: np.ndarray
    via_fraction: np.ndarray

    @property
    def rows(self):
        """ndarray of int: knots and vias, the run's welded targets."""
        return np.concatenate([self.knots, self.vias])

    def via_values(self, knot_values):
        """Values (m,) or (m, E) at the vias when the axes run linearly between knots."""
        x = np.asarray(knot_values, dtype=float)
        f = self.via_fraction.reshape((-1,) + (1,) * (x.ndim - 1))
        return (1.0 - f) * x[self.via_move] + f * x[self.via_move + 1]


def corner_time_s(zone_mm, length_in_mm, time_in_s, length_out_mm, time_out_s):
    """Time the TCP spends within a blended target's zone, s (0 where it stops).

    Parameters
    ----------
    zone_mm : array_like, shape (J,)
        The zone of the target ending the incoming move (0: a fine point).
    length_in_mm, time_in_s, length_out_mm, time_out_s : array_like, shape (J,)
        Path length (work frame) and duration of the moves into and out of it.

    Returns
    -------
    ndarray, shape (J,)
        ``r T_in / L_in + r T_out / L_out``; 0 where the zone is 0 or a move
        does not travel.
    """
    r = np.asarray(zone_mm, dtype=float)
    l_in, l_out = np.asarray(length_in_mm, float), np.asarray(length_out_mm, float)
    blended = (r > 0.0) & (l_in > 0.0) & (l_out > 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = r * np.asarray(time_in_s, float) / l_in + r * np.asarray(time_out_s, float) / l_out
    return np.where(blended, out, 0.0)


def corner_accels(delta, time_s, corner_s):
    """The acceleration each axis needs at each corner between consecutive moves.

    Parameters
    ----------
    delta : ndarray, shape (K, E)
        Each move's change of the axis values (mm / deg).
    time_s : ndarray, shape (K,)
        Each move's duration, s (> 0).
    corner_s : ndarray, shape (K - 1,)
        Time in the zone between move k and move k + 1 (:func:`corner_time_s`).

    Returns
    -------
    ndarray, shape (K - 1, E)
        ``|v_out - v_in| / corner_s``, mm/s^2 or deg/s^2; 0 where the TCP stops.
    """
    corner = np.asarray(corner_s, dtype=float)[:, None]
    with np.errstate(divide="ignore", invalid="ignore"):   # a move that does not travel
        speed = np.asarray(delta, dtype=float) / np.asarray(time_s, dtype=float)[:, None]
        return np.where(corner > 0.0, np.abs(np.diff(speed, axis=0)) / corner, 0.0)


def over_limits(knot_values, motion, max_speed, max_accel):
    """Whether one axis's values along a run need more than its speed or acceleration.

    Parameters
    ----------
    knot_values : ndarray, shape (n,)
    motion : RunMotion
    max_speed, max_accel : float

    Returns
    -------
    bool
    """
    delta = np.diff(knot_values)[:, None]
    speed = np.abs(delta[:, 0]) / motion.time_s
    accel = corner_accels(delta, motion.time_s, motion.corner_s[1:-1])[:, 0]
    return bool(np.any(speed > max_speed) or np.any(accel > max_accel))


def band_deg(sin_alpha, slack_deg):
    """How far a rotary axis may turn a part vector held within `slack_deg` of where it is.

    Parameters
    ----------
    sin_alpha : array_like, shape (M,)
        Sine of the angle between the axis and the part vector (in {U}).
    slack_deg : array_like, shape (M,)
        Deviation the vector may still take, deg (>= 0).

    Returns
    -------
    ndarray, shape (M,)
        The largest ``|delta|`` with ``2 asin(sin_alpha sin(|delta| / 2)) <= slack``,
        deg; 180 where any turn stays within it (an axis along the vector); 0
        where no slack is left.
    """
    s = np.sin(np.radians(np.clip(slack_deg, 0.0, 180.0)) / 2.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(s > 0.0, s / np.asarray(sin_alpha, dtype=float), 0.0)
    return np.where(ratio >= 1.0, 180.0, 2.0 * np.degrees(np.arcsin(np.clip(ratio, 0.0, 1.0))))


def run_motions(program, table):
    """The :class:`RunMotion` of every weld run of `program` with a welded move, and of
    every stretch of coordinated moves of a path without welds.

    Parameters
    ----------
    program : Program
    table : seams.SeamTable
        Of `program` (row order ``Program.targets()``).

    Returns
    -------
    list of RunMotion
        A weld run's welded moves (named by the run; runs whose moves change work
        frame are left out: their durations would depend on the axes). A path
        without welds (named ``"path:<name>"``, as its seam-table group): each
        stretch of linear and circular moves staying in one work frame, from the
        target before its first move (a joint move breaks it, as Check samples
        only linear and circular moves).
    """
    row_of = {id(target): i for i, target in enumerate(table.targets)}
    v_ori = Margins().orientation_speed_deg_s
    out = []
    for path in program.paths:
        if path.welds:
            for run in path.welds:
                moves = path.moves[run.start:run.end + 1]
                if len(moves) >= 2 and len({m.frame for m in moves}) == 1:
                    out.append(_motion(run.name, moves, row_of, v_ori))
        else:
            out += [_motion("path:%s" % path.name, path.moves[start:end], row_of, v_ori)
                    for start, end in _coordinated_stretches(path.moves)]
    return out


def _coordinated_stretches(moves):
    """(start, end) slices of `moves`: ``moves[start]`` the target a stretch leaves from,
    ``moves[start + 1:end]`` its linear and circular moves within that target's frame."""
    timed = [k > 0 and m.kind in (ir.LINEAR, ir.CIRCULAR) and m.frame == moves[k - 1].frame
             for k, m in enumerate(moves)]
    out, k = [], 0
    while k < len(moves):
        if not timed[k]:
            k += 1
            continue
        end = k
        while end < len(moves) and timed[end]:
            end += 1
        out.append((k - 1, end))
        k = end
    return out


def _motion(name, moves, row_of, v_ori):
    """The :class:`RunMotion` of `moves` (the first one's target is knot 0: only its
    target counts), each later move lasting its path length over its speed."""
    timed = moves[1:]
    T0 = np.array([m.target.T_b_t for m in moves[:-1]], dtype=float)
    T1 = np.array([m.target.T_b_t for m in timed], dtype=float)
    vias = np.array([m.via.T_b_t[:3, 3] if m.via is not None and m.kind == ir.CIRCULAR
                     else (np.nan,) * 3 for m in timed], dtype=float)
    length, fraction = _path_lengths(T0[:, :3, 3], vias, T1[:, :3, 3])
    speed = np.array([float(m.speed_mm_s) for m in timed])
    w = np.array([float(getattr(m, "orientation_speed_deg_s", None) or v_ori) for m in timed])
    time_s = np.maximum(length / speed, _rotation_deg(T0, T1) / w)
    zones = np.array([float(m.zone_mm) for m in moves])
    corner = np.zeros(len(moves))
    corner[1:-1] = corner_time_s(zones[1:-1], length[:-1], time_s[:-1], length[1:], time_s[1:])
    has_via = np.flatnonzero(~np.isnan(fraction))
    return RunMotion(
        run=name, knots=np.array([row_of[id(m.target)] for m in moves]), time_s=time_s,
        corner_s=corner, vias=np.array([row_of[id(timed[k].via)] for k in has_via], dtype=int),
        via_move=has_via, via_fraction=fraction[has_via])


def _path_lengths(start, via, end):
    """Path lengths (K,) of linear moves (NaN `via`) and circular ones through `via`,
    and the via's share (K,) of its arc (NaN without one). All (K, 3) mm.

    A circle's arc from start to via subtends twice the inscribed angle at the
    end (which is not on that arc), and from via to end twice the angle at the start."""
    chord = np.linalg.norm(end - start, axis=1)
    fraction = np.full(len(start), np.nan)
    circ = ~np.isnan(via[:, 0])
    if not circ.any():
        return chord, fraction
    s, v, e = start[circ], via[circ], end[circ]
    at_end = _angle(s - e, v - e)              # half the arc start -> via
    at_start = _angle(v - s, e - s)            # half the arc via -> end
    at_via = _angle(s - v, e - v)
    with np.errstate(divide="ignore", invalid="ignore"):
        radius = np.linalg.norm(e - s, axis=1) / (2.0 * np.sin(at_via))
    arc = 2.0 * radius * (at_end + at_start)
    polyline = np.linalg.norm(v - s, axis=1) + np.linalg.norm(e - v, axis=1)
    straight = ~np.isfinite(arc) | (np.sin(at_via) < 1e-12)
    length = chord.copy()
    length[circ] = np.where(straight, polyline, arc)
    with np.errstate(divide="ignore", invalid="ignore"):
        fraction[circ] = np.where(straight, np.linalg.norm(v - s, axis=1) / polyline,
                                  at_end / (at_end + at_start))
    return length, fraction


def _angle(a, b):
    """Angles (M,) between rows of `a` and `b`, rad."""
    cos = np.sum(a * b, axis=1) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1))
    return np.arccos(np.clip(cos, -1.0, 1.0))


def _rotation_deg(T0, T1):
    """Rotation angles (K,) from each T0's orientation to T1's, deg."""
    trace = np.einsum("kji,kji->k", T0[:, :3, :3], T1[:, :3, :3])
    return np.degrees(np.arccos(np.clip((trace - 1.0) / 2.0, -1.0, 1.0)))


def limit_axis(knot_values, band, via_values, via_band, motion, max_speed, max_accel,
               lower=-np.inf, upper=np.inf):
    """One axis's values along a run moved least (L1) so its speeds and corner
    accelerations are within its limits, each value within its band.

    Parameters
    ----------
    knot_values : ndarray, shape (n,)
        The exact values at the knots, mm / deg.
    band : ndarray, shape (n,)
        How far each knot's value may move (>= 0).
    via_values, via_band : ndarray, shape (m,)
        The exact values at the run's vias, and how far the interpolated value
        there may be from them.
    motion : RunMotion
    max_speed, max_accel : float
    lower, upper : float
        The axis limits: a value inside them stays inside.

    Returns
    -------
    ndarray, shape (n,), or None
        None where no values within the bands meet the limits.
    """
    x = np.asarray(knot_values, dtype=float)
    via_x, via_b = np.asarray(via_values, float), np.asarray(via_band, float)
    low = np.maximum(x - band, np.minimum(lower, x))
    high = np.minimum(x + band, np.maximum(upper, x))
    return limit_axis_between(x, low, high, via_x - via_b, via_x + via_b, motion, max_speed,
                              max_accel)


def limit_axis_between(knot_values, low, high, via_low, via_high, motion, max_speed, max_accel):
    """One axis's values along a run moved least (L1) so its speeds and corner
    accelerations are within its limits, each value within its interval.

    Parameters
    ----------
    knot_values : ndarray, shape (n,)
        The values at the knots, mm / deg.
    low, high : ndarray, shape (n,)
        The interval each knot's value must end in (holding `knot_values`).
    via_low, via_high : ndarray, shape (m,)
        The interval the interpolated value at each of the run's vias must be in.
    motion : RunMotion
    max_speed, max_accel : float

    Returns
    -------
    ndarray, shape (n,), or None
        None where no values within the intervals meet the limits.
    """
    from scipy import sparse              # here: only a run over the limits needs scipy.optimize,
    from scipy.optimize import linprog    # which takes a noticeable time to import

    x = np.asarray(knot_values, dtype=float)
    n = len(x)
    rows, bound = _constraint_rows(motion, n, max_speed * (1.0 - LIMIT_MARGIN),
                                   max_accel * (1.0 - LIMIT_MARGIN))
    V = _via_matrix(motion, n)
    G = sparse.vstack(rows + [V, -V]).tocsr()
    h = np.concatenate(bound + [np.asarray(via_high, float), -np.asarray(via_low, float)])
    # y = x + p - m with p, m >= 0: minimise sum(p + m), G y <= h.
    A_ub = sparse.hstack([G, -G]).tocsr()
    b_ub = h - G @ x
    bounds = np.concatenate([np.column_stack([np.zeros(n), high - x]),
                             np.column_stack([np.zeros(n), x - low])])
    result = linprog(np.ones(2 * n), A_ub=A_ub, b_ub=b_ub, bounds=bounds, method="highs")
    if result.status != 0:
        return None
    return x + result.x[:n] - result.x[n:]


def _constraint_rows(motion, n, max_speed, max_accel):
    """Rows ``G y <= h`` bounding the speeds (both signs) and the corner accelerations."""
    from scipy import sparse
    k = np.arange(n - 1)
    D = sparse.csr_matrix((np.concatenate([-np.ones(n - 1), np.ones(n - 1)]),
                           (np.concatenate([k, k]), np.concatenate([k, k + 1]))), shape=(n - 1, n))
    speed_cap = max_speed * motion.time_s
    corners = np.flatnonzero(motion.corner_s[1:-1] > 0.0)        # between move c and c + 1
    # a_c = (y[c+2] - y[c+1]) / T[c+1] - (y[c+1] - y[c]) / T[c], over corner time B[c+1].
    S = sparse.diags(1.0 / motion.time_s) @ D                    # move speeds
    A = (S[corners + 1] - S[corners])
    accel_cap = max_accel * motion.corner_s[1:-1][corners]
    return [D, -D, A, -A], [speed_cap, speed_cap, accel_cap, accel_cap]


def _via_matrix(motion, n):
    """(m, n) rows giving each via's interpolated value from the knot values."""
    from scipy import sparse
    m = len(motion.vias)
    rows = np.concatenate([np.arange(m), np.arange(m)])
    cols = np.concatenate([motion.via_move, motion.via_move + 1])
    vals = np.concatenate([1.0 - motion.via_fraction, motion.via_fraction])
    return sparse.csr_matrix((vals, (rows, cols)), shape=(m, n))
