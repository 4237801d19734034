"""Weave geometry: where the torch is across the seam at each moment of a weld.

One module for the posts (UR writes the weave as motion), the checks (they run
on the woven path), the player and the through-arc tracking simulation.

The weave frame at a point of the seam is the path frame of the seam tracker:
X the travel direction, Z the tool axis (pointing into the work) with its X
part removed, Y = Z x X: to the right of the travel seen from the torch. The
weave moves the TCP in the Y-Z plane turned by ``angle_deg`` about X (the
circle also along X); the orientation of the torch does not weave (the
controllers' geometric weave).

A cycle visits the pattern's vertices at constant weave speed and holds at
each for its dwell while the travel goes on (names of the vertices:
C centre, L left, R right, A apex)::

    zigzag    C -> L -> C -> R -> C      (dwell_center split over the two C)
    l         C -> L' -> C -> R' -> C    L', R' = the ends raised by height_mm
    triangle  C -> R -> A -> L -> C      C in the middle of the base L-R
    circle    a circle of diameter width_mm in the X-Y plane (no dwells)

Left is -Y, right is +Y, "raised" is -Z (back along the tool axis). At the
start and the end of a weld the weave ramps in and out over half a cycle
(:func:`envelope`), so every weld starts and ends on the seam.

Pure numpy; never imports FreeCAD.
"""

from collections import namedtuple
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .trajectory import Trajectory, move_durations_s
from .welding import CIRCLE, L_SHAPE, TRIANGLE, ZIGZAG


def frame_axes(travel, tool_z):
    """Path frame axes from travel directions and tool axes.

    Parameters
    ----------
    travel, tool_z : ndarray, shape (N, 3)
        Travel directions and tool +Z axes (any length).

    Returns
    -------
    X, Y, Z : ndarray, shape (N, 3) each
        Unit travel, lateral (right) and tool axes, orthonormal.
    """
    X = travel / np.linalg.norm(travel, axis=1)[:, None]
    Z = tool_z - np.sum(tool_z * X, axis=1)[:, None] * X
    norm = np.linalg.norm(Z, axis=1)
    if np.any(norm < 1e-9):
        raise InputError("The tool axis runs along the travel somewhere on the path: the "
                         "lateral direction is undefined there.")
    Z /= norm[:, None]
    return X, np.cross(Z, X), Z


def vertices(weave):
    """The pattern's vertices and the dwell at each, in the unturned weave frame.

    Returns
    -------
    points_mm : ndarray, shape (K, 3)
        x (travel), y (lateral), z (tool axis) offsets, mm; the first is the
        centre (0, 0, 0) and the cycle returns to it.
    dwell_s : ndarray, shape (K,)
        Hold time at each vertex, s.
    """
    a = weave.width_mm / 2
    h = weave.height
    dl, dc, dr = weave.dwell_left_s, weave.dwell_center_s, weave.dwell_right_s
    if weave.pattern in (ZIGZAG, L_SHAPE):
        z = 0.0 if weave.pattern == ZIGZAG else -h
        points = [(0, 0, 0), (0, -a, z), (0, 0, 0), (0, a, z)]
        dwell = [dc / 2, dl, dc / 2, dr]
    elif weave.pattern == TRIANGLE:
        points = [(0, 0, 0), (0, a, 0), (0, 0, -h), (0, -a, 0)]
        dwell = [0.0, dr, dc, dl]
    else:
        raise InputError(f"A {weave.pattern} weave has no vertices.")
    return np.array(points, dtype=float), np.array(dwell, dtype=float)


def _turn(offsets, angle_deg):
    """Turn (N, 3) offsets about X by `angle_deg`, from Y toward Z."""
    c, s = np.cos(np.radians(angle_deg)), np.sin(np.radians(angle_deg))
    y, z = offsets[:, 1].copy(), offsets[:, 2].copy()
    offsets[:, 1] = c * y - s * z
    offsets[:, 2] = s * y + c * z
    return offsets


def moving_time_s(weave, travel_speed_mm_s, what="The weave"):
    """float: the time of one cycle the weave moves (the cycle less its dwells), s.

    Raises
    ------
    InputError
        The dwells take the whole cycle.
    """
    cycle = weave.cycle_time_s(travel_speed_mm_s)
    moving = cycle - weave.dwells_s
    if moving <= 1e-3 * cycle:
        raise InputError(f"{what}: its dwells ({weave.dwells_s:g} s) fill the whole weave "
                         f"cycle ({cycle:g} s): lower the frequency or shorten the dwells.")
    return moving


def weave_offsets(t_s, weave, travel_speed_mm_s):
    """Offsets of the TCP from the seam at times `t_s` of a weld, without the
    ramps of :func:`envelope`.

    Parameters
    ----------
    t_s : ndarray, shape (N,)
        Time since the arc started, s.
    weave : welding.Weave
    travel_speed_mm_s : float

    Returns
    -------
    ndarray, shape (N, 3)
        x, y, z offsets in the weave frame, mm (periodic in the cycle time).
    """
    t_s = np.asarray(t_s, dtype=float)
    cycle = weave.cycle_time_s(travel_speed_mm_s)
    phase = np.mod(t_s, cycle) / cycle
    if weave.pattern == CIRCLE:
        angle = 2 * np.pi * phase
        a = weave.width_mm / 2
        offsets = np.stack([a * np.sin(angle), -a * np.cos(angle), np.zeros_like(angle)], axis=1)
    else:
        offsets = _vertex_offsets(phase * cycle, weave, travel_speed_mm_s)
    return _turn(offsets, weave.angle_deg)


def _vertex_offsets(t_in_cycle, weave, travel_speed_mm_s):
    """Offsets at times within one cycle, for the vertex patterns; (N, 3) mm."""
    points, dwell = vertices(weave)
    legs = np.linalg.norm(np.roll(points, -1, axis=0) - points, axis=1)
    leg_time = legs / legs.sum() * moving_time_s(weave, travel_speed_mm_s)
    # Knots: hold at vertex k from its arrival for dwell[k], then move along leg k.
    knot_t = np.cumsum(np.ravel(np.column_stack([dwell, leg_time])))
    knot_t = np.concatenate([[0.0], knot_t])
    knot_p = np.repeat(np.vstack([points, points[:1]]), 2, axis=0)[:-1]
    return np.stack([np.interp(t_in_cycle, knot_t, knot_p[:, i]) for i in range(3)], axis=1)


def envelope(t_s, duration_s, ramp_s):
    """Weave amplitude factor in [0, 1]: rises from 0 over the first `ramp_s`
    of the weld and falls to 0 over its last `ramp_s`, linearly.

    Parameters
    ----------
    t_s : ndarray, shape (N,)
        Time since the arc started, s.
    duration_s : float
        Arc time of the weld, s.
    ramp_s : float
        Ramp time (half a weave cycle), s; shortened to half the weld when
        the weld is shorter than a cycle.
    """
    ramp_s = min(ramp_s, duration_s / 2)
    t_s = np.asarray(t_s, dtype=float)
    return np.clip(np.minimum(t_s, duration_s - t_s) / ramp_s, 0.0, 1.0)


def ramp_time_s(weave, travel_speed_mm_s):
    """float: the ramp of :func:`envelope` for this weave, half a cycle, s."""
    return weave.cycle_time_s(travel_speed_mm_s) / 2


def woven_offsets(t_s, duration_s, weave, travel_speed_mm_s):
    """Offsets of the TCP from the seam at times `t_s` of a weld lasting
    `duration_s`, ramps included; ndarray (N, 3), mm, in the weave frame."""
    factor = envelope(t_s, duration_s, ramp_time_s(weave, travel_speed_mm_s))
    return weave_offsets(t_s, weave, travel_speed_mm_s) * factor[:, None]


#: What :func:`measure` finds in a sampled weave.
WeaveMeasure = namedtuple("WeaveMeasure", "width_mm period_s cycles")


def measure(t_s, lateral_mm):
    """The width and the period of a weave, measured on its samples (the check
    of a woven path against its weave data, issue 22 test 5.3).

    Parameters
    ----------
    t_s : ndarray, shape (N,)
        Sample times, increasing, s.
    lateral_mm : ndarray, shape (N,)
        The signed offset across the seam in the weave plane, mm, over the
        steady part of a weld (whole cycles, ramps left out).

    Returns
    -------
    WeaveMeasure
        ``width_mm``: peak to peak; ``period_s``: the mean time between the
        rises through three quarters of the way from the lowest to the highest
        offset (linearly interpolated; NaN with fewer than two rises);
        ``cycles``: how many rises.
    """
    t_s, lateral_mm = np.asarray(t_s, dtype=float), np.asarray(lateral_mm, dtype=float)
    low, high = lateral_mm.min(), lateral_mm.max()
    level = low + 0.75 * (high - low)
    rise = np.nonzero((lateral_mm[:-1] < level) & (lateral_mm[1:] >= level))[0]
    share = (level - lateral_mm[rise]) / (lateral_mm[rise + 1] - lateral_mm[rise])
    times = t_s[rise] + share * (t_s[rise + 1] - t_s[rise])
    period = float(np.mean(np.diff(times))) if len(times) > 1 else float("nan")
    return WeaveMeasure(float(high - low), period, len(times))


def weave_speed_mm_s(weave, travel_speed_mm_s):
    """float: the largest speed of the weave motion alone (no travel), mm/s."""
    if weave.pattern == CIRCLE:
        return np.pi * weave.width_mm / weave.cycle_time_s(travel_speed_mm_s)
    points, _ = vertices(weave)
    path = np.linalg.norm(np.roll(points, -1, axis=0) - points, axis=1).sum()
    return path / moving_time_s(weave, travel_speed_mm_s)


def peak_tcp_speed_mm_s(weave, travel_speed_mm_s):
    """float: an upper bound of the TCP speed on the woven path, mm/s.

    The travel and the weave add as vectors: orthogonal for the vertex
    patterns (their offsets have no X part), along one line at worst for the
    circle. The ramps of :func:`envelope` add at most the largest offset per
    ramp time; the largest offset is a vertex's (a leg's points lie between
    two vertices), for the l pattern its raised end, sqrt(a^2 + h^2).
    """
    v_weave = weave_speed_mm_s(weave, travel_speed_mm_s)
    if weave.pattern == CIRCLE:
        v = travel_speed_mm_s + v_weave
        largest_offset = weave.width_mm / 2
    else:
        v = float(np.hypot(travel_speed_mm_s, v_weave))
        largest_offset = float(np.linalg.norm(vertices(weave)[0], axis=1).max())
    return v + largest_offset / ramp_time_s(weave, travel_speed_mm_s)


# --- the woven path of a program (issue 22, the checks and the player) ----------------------

#: Samples per weave cycle wherever the woven path is sampled for the checks and the
#: player: a step of at most cycle / 40 (a zigzag leg of a quarter cycle gets 10 steps).
SAMPLES_PER_CYCLE = 40


@dataclass
class RunClock:
    """The arc clock of one woven weld run: when each of its welded moves happens.

    The arc time starts (0) when the run's start move ends, at the seam start,
    and runs to ``duration_s`` at the target of its last welded move; moves take
    the time :func:`.trajectory.tcp_trajectory` gives them.

    Attributes
    ----------
    run : program.WeldRun
    path_label : str
    weave : welding.Weave
    travel_speed_mm_s : float
        The travel the weave is timed by (the schedule's, unless replaced).
    moves : ndarray of int, shape (M,)
        Indices in ``program.moves()`` of the welded moves, ``start + 1 .. end``.
    move_start_s : ndarray, shape (M,)
        Arc time at the start of each welded move, s.
    duration_s : float
        Arc time of the run, s.
    """

    run: object
    path_label: str
    weave: object
    travel_speed_mm_s: float
    moves: np.ndarray
    move_start_s: np.ndarray
    duration_s: float

    @property
    def step_s(self):
        """float: the longest sampling step of this woven path, s (cycle / 40)."""
        return self.weave.cycle_time_s(self.travel_speed_mm_s) / SAMPLES_PER_CYCLE

    def offsets_mm(self, move_index, local_s, travel, tool_z):
        """The weave's offsets of samples of the welded moves, in the frame of
        `travel` and `tool_z` (the robot's or {U}).

        Parameters
        ----------
        move_index : ndarray of int, shape (N,)
            Index in ``program.moves()`` of each sample's move (one of :attr:`moves`).
        local_s : ndarray, shape (N,)
            Time since the start of that move, s.
        travel, tool_z : ndarray, shape (N, 3)
            Travel direction of the unwoven path and tool axis at each sample;
            where the path does not travel the offset is 0.

        Returns
        -------
        ndarray, shape (N, 3)
            mm, to add to the unwoven TCP positions.

        Raises
        ------
        InputError
            The tool axis runs along the travel: the weave has no lateral direction.
        """
        arc_s = self.move_start_s[np.searchsorted(self.moves, move_index)] + local_s
        in_frame = woven_offsets(arc_s, self.duration_s, self.weave, self.travel_speed_mm_s)
        travels = np.linalg.norm(travel, axis=1) > 1e-12
        out = np.zeros_like(in_frame)
        try:
            X, Y, Z = frame_axes(travel[travels], tool_z[travels])
        except InputError:
            raise InputError(f"Weld '{self.run.label}' (path '{self.path_label}'): the torch "
                             "points along the travel somewhere, so the weave has no lateral "
                             "direction: tilt the torch.") from None
        f = in_frame[travels]
        out[travels] = f[:, :1] * X + f[:, 1:2] * Y + f[:, 2:] * Z
        return out


def run_clocks(program, replace=None):
    """The arc clocks of a program's woven weld runs, by welded move.

    Parameters
    ----------
    program : Program
    replace : dict, optional
        ``{run name: (weave, travel_speed_mm_s)}``: time that run with another
        weave and travel speed (its welded moves at that speed), to try a fix.

    Returns
    -------
    dict of int to RunClock
        For every welded move of a run with a weave, its index in
        ``program.moves()``; runs without a weave have no clock.
    """
    replace = replace or {}
    spans, speeds, first = [], {}, 0
    for path in program.paths:
        for run in path.welds:
            weave, travel = replace.get(run.name, (run.weave, run.schedule.travel_speed_mm_s))
            if weave is not None:
                moves = np.arange(first + run.start + 1, first + run.end + 1)
                spans.append((path.label, run, weave, travel, moves))
                if run.name in replace:
                    speeds.update({int(i): travel for i in moves})
        first += len(path.moves)
    clocks = {}
    for label, run, weave, travel, moves in spans:
        starts = np.concatenate([[0.0], np.cumsum(move_durations_s(program, speeds, moves))])
        clock = RunClock(run, label, weave, float(travel), moves, starts[:-1], float(starts[-1]))
        clocks.update({int(i): clock for i in moves})
    return clocks


def travel_directions(positions):
    """ndarray (N, 3): the local travel direction along sampled positions (N, 3),
    by central differences (not normalised; 0 where the path stands still)."""
    positions = np.asarray(positions, dtype=float)
    if len(positions) < 2:
        return np.zeros_like(positions)
    return np.gradient(positions, axis=0)


def woven_trajectory(program, trajectory):
    """The TCP trajectory with the weave of each weld run added inside the run.

    Parameters
    ----------
    program : Program
        The program `trajectory` samples.
    trajectory : trajectory.Trajectory
        From :func:`.trajectory.tcp_trajectory` of `program` (any move range and
        sampling time; sample finer than a weave cycle / :data:`SAMPLES_PER_CYCLE`
        to see the weave's corners).

    Returns
    -------
    trajectory.Trajectory
        The same samples; on the welded moves of runs with a weave the TCP
        positions are moved by :func:`woven_offsets` (time since the run's start
        move ended, the run's arc time) turned into {U} by the weave frame of
        :func:`frame_axes` (travel: the trajectory's local direction; tool Z: the
        pose's). Orientations, times, ``s_mm`` (the distance along the seam) and
        ``move_index`` are unchanged. `trajectory` itself when no run weaves.
    """
    clocks = run_clocks(program)
    index = np.asarray(trajectory.move_index, dtype=int)
    woven = np.isin(index, list(clocks))
    if not woven.any():
        return trajectory
    first = int(index[0])
    move_start = trajectory.time_s[0] + np.concatenate(
        [[0.0], np.cumsum(move_durations_s(program)[first:])])
    local = trajectory.time_s - move_start[index - first]
    travel = travel_directions(trajectory.position_mm)
    poses = np.array(trajectory.T_u_t, dtype=float, copy=True)
    for clock in {id(c): c for c in clocks.values()}.values():
        rows = np.isin(index, clock.moves)
        poses[rows, :3, 3] += clock.offsets_mm(index[rows], local[rows], travel[rows],
                                               poses[rows, :3, 2])
    return Trajectory(trajectory.time_s, poses, trajectory.s_mm, index)
