"""Sampling along Cartesian moves: the joints between a program's targets.

A controller runs a linear or circular move by interpolating the TCP: position
along the line or arc, orientation by slerp (eqs 14-15) in proportion to the
travelled fraction. Between the targets the arm keeps the configuration family
it starts in and every joint turns continuously (a linear move cannot unwind a
joint by 360 degrees). The checks (joint speeds, configuration changes and
singularities between targets), the collision check, the cycle time and the
playback all need those joints: one sampler, so Check, Place robot and the
player agree on where the arm goes.

:func:`sample_moves` samples every Cartesian move of a solved program at once:
one IK call for all samples, the joints continued by a cumulative sum per move,
the per-move measures by segment reductions. Only moves whose family has two
IK rows at some sample (at a singularity) are followed one sample at a time
(:func:`follow_family`).

Welds (issue 22): the welded moves of a weld run with a weave are sampled on
the woven path -- at least :data:`~...core.weave.SAMPLES_PER_CYCLE` samples per
weave cycle, each moved by the weave's offset at its arc time
(:meth:`~...core.weave.RunClock.offsets_mm`) -- so reach, joint limits,
singularities, joint speeds, collisions and the cycle time all see the woven
torch path. Other moves are sampled as before.

External axes (issue 23): with ``program.external`` every linear and circular
move is coordinated. The TCP is interpolated in the move's work frame {B}
(the speed is relative to the part: line, arc and slerp in {B}, the weave as
above), the external axis values linearly from the start target's to the end
target's (:func:`external_values`), and each sample is placed in {R} at its
own values: ``T_r_t(s) = ExternalAxes.T_r_b(frame, ext(s)) @ T_b_t(s)``. A move
gets at least one sample per ``sample_step_deg`` of a rotary axis and per
``sample_step_mm`` of a linear one; :attr:`SampledMoves.external` holds the
values per sample. Programs without external axes are sampled exactly as before.

Pure numpy: never imports FreeCAD.
"""

import math
from dataclasses import dataclass
from typing import List

import numpy as np

from ...core import frames as tf
from ...core import program as ir
from ...core import rotations
from ...core import weave as weaving
from ...core.mechanisms import ROTARY, frame_in_base
from ...core.geometry import Arc
from ...core.progress import report_now
from . import configuration as cfg

#: Status codes of :attr:`SampledMoves.status` and their names (configuration's).
OK, CONFIG_CHANGE, JOINT_LIMIT, UNREACHABLE = range(4)
STATUS_NAMES = (cfg.OK, cfg.CONFIG_CHANGE, cfg.JOINT_LIMIT, cfg.UNREACHABLE)


@dataclass
class Margins:
    """Margins and sampling of :func:`~CadRobotWB.robots.checks.checks.check_program`
    (also ``checks.Margins``); the sampling steps are :func:`sample_moves`'s.

    Attributes
    ----------
    wrist_deg : float
        Warn when the wrist bend (model axis 5) is within this angle of 0 or
        180 degrees.  Default 5.
    shoulder_mm : float
        Warn when the wrist centre is within this distance of axis 1.
        Default 50.
    elbow_deg : float
        Warn when the arm is within this angle of fully stretched or folded.
        Default 5.
    orientation_speed_deg_s : float
        Orientation speed of linear and circular moves, deg/s, unless a move
        has an ``orientation_speed_deg_s`` attribute.  Default 500 (ABB's
        predefined speed data).
    sample_step_mm, sample_step_deg : float
        Longest step, in TCP travel and in tool rotation, between two samples
        of a move.  Defaults 5 mm and 2 degrees.
    max_samples : int
        Most samples per move.  Default 200.
    """

    wrist_deg: float = 5.0
    shoulder_mm: float = 50.0
    elbow_deg: float = 5.0
    orientation_speed_deg_s: float = 500.0
    sample_step_mm: float = 5.0
    sample_step_deg: float = 2.0
    max_samples: int = 200


def tcp_pose_in_base(program, entry):
    """TCP pose of an entry's target in {R}: ``T_r_b @ T_b_t``, shape (4, 4)."""
    return frame_in_base(program, entry.move, entry.target) @ \
        np.asarray(entry.target.T_b_t, dtype=float)


def external_values(program, target):
    """A target's external axis values, shape (E,): its own, or the drawn ones
    (``ExternalAxes.drawn_at``) when none were chosen."""
    values = getattr(target, "external", None)
    if values is None:
        return program.external.drawn_at()
    return np.asarray(values, dtype=float).reshape(-1)


def tcp_pose_in_frame(program, entry, move):
    """TCP pose of an entry's target in the work frame {B} of `move`, shape (4, 4).

    A coordinated move runs in its own work frame: its start (the previous
    move's target, in that move's frame) is taken into this move's frame at
    the start's external axis values, so the TCP interpolates relative to
    the part (:mod:`..core.mechanisms`).
    """
    T_b_t = np.asarray(entry.target.T_b_t, dtype=float)
    if entry.move.frame == move.frame:
        return T_b_t
    T_r_b = program.external.T_r_b(program.frames[move.frame],
                                   external_values(program, entry.target))
    return tf.invert_transform(T_r_b) @ tcp_pose_in_base(program, entry)


def _external_steps(external, delta, margins):
    """Samples (K,) the external axes need: no axis more than a sampling step
    (``sample_step_deg`` rotary, ``sample_step_mm`` linear) between two samples."""
    steps = np.array([margins.sample_step_deg if axis.kind == ROTARY else margins.sample_step_mm
                      for _, axis in external.axes()])
    return np.ceil(np.abs(delta) / steps).max(axis=1, initial=0.0)


def _frames_in_base(program, groups, move_of, external):
    """Each sample's work frame in {R} at its external values, shape (S, 4, 4)."""
    frame_of = np.array([g[-1].move.frame for g in groups], dtype=object)[move_of]
    T_r_b = np.zeros((len(move_of), 4, 4))
    for name in set(frame_of):
        rows = frame_of == name
        T_r_b[rows] = program.external.T_r_b(program.frames[name], external[rows])
    return T_r_b


def move_path(T_r_t0, T_r_t1, kind, T_r_via=None):
    """Length and turned angle of a Cartesian move, and a function giving its poses.

    Positions go in a straight line (linear) or along the circle through the
    via point (circular); the orientation turns from the start to the end
    by slerp (eqs 14-15), in proportion to the travelled fraction, as
    controllers interpolate it.

    Parameters
    ----------
    T_r_t0, T_r_t1 : array_like, shape (4, 4)
        TCP poses at the start and at the end, mm.
    kind : str
        ``"linear"`` or ``"circular"``.
    T_r_via : array_like, shape (4, 4), optional
        TCP pose at the via point of a circular move.

    Returns
    -------
    length_mm : float
    angle_deg : float
    poses : callable
        ``poses(fractions (M,)) -> (M, 4, 4)`` TCP poses.
    """
    T0, T1 = np.asarray(T_r_t0, float), np.asarray(T_r_t1, float)
    arc = _arc(T0, T1, kind, T_r_via)
    p0, p1 = T0[:3, 3], T1[:3, 3]
    length = arc.length if arc is not None else float(np.linalg.norm(p1 - p0))
    angle = math.degrees(float(rotations.rotation_angle_between(T0[:3, :3], T1[:3, :3])))
    q0 = rotations.quaternion_from_matrix(T0[:3, :3])
    q1 = rotations.quaternion_from_matrix(T1[:3, :3])

    def poses(fractions):
        s = np.clip(np.asarray(fractions, dtype=float).reshape(-1), 0.0, 1.0)
        out = np.zeros((s.size, 4, 4))
        out[:, 3, 3] = 1.0
        if arc is not None:
            out[:, :3, 3] = arc.points_at(s * arc.length)
        else:
            out[:, :3, 3] = p0 + s[:, None] * (p1 - p0)
        out[:, :3, :3] = rotations.matrix_from_quaternion(
            np.reshape(rotations.quaternion_slerp(q0, q1, s), (-1, 4)))
        return out

    return length, angle, poses


def _arc(T0, T1, kind, T_via):
    """The arc of a circular move, or None (a linear move, or a degenerate circle: a line)."""
    if kind != ir.CIRCULAR or T_via is None:
        return None
    try:
        return Arc.from_three_points(T0[:3, 3], np.asarray(T_via, float)[:3, 3], T1[:3, 3])
    except Exception:   # degenerate circle: treat as a line
        return None


def follow_family(model, T_r_f, wanted, q_start_deg):
    """Joints along a sequence of flange poses: one family, one continuous motion.

    At each pose the family's solution with every joint continued from the
    previous pose (:func:`.configuration.continue_joints`: no jump of 360 degrees,
    as a linear move cannot unwind a joint).

    Parameters
    ----------
    model : RobotModel
    T_r_f : array_like, shape (M, 4, 4)
        Flange poses in {R}, in travel order.
    wanted : int
        The family to keep.
    q_start_deg : array_like, shape (6,)
        Joints before the first pose.

    Returns
    -------
    q_deg : ndarray, shape (M, 6)
        The continued joints; outside the limits where the status is
        ``"joint_limit"``; NaN rows where the family has no solution.
    status : list of str
        Per pose: ``"ok"``; ``"joint_limit"`` (the family reaches the pose but
        a joint is, or has wound, out of its range - or, with no solution of
        the family, some other solution only out of range); ``"config_change"``
        (only another family reaches it within the limits); ``"unreachable"``.
    """
    Q = model.ik(np.asarray(T_r_f, dtype=float).reshape(-1, 4, 4))
    fams = cfg.family(Q, model)
    row_valid = cfg.fits_limits(Q, model)
    q_prev = np.asarray(q_start_deg, dtype=float)
    out = np.full((Q.shape[0], 6), np.nan)
    status = []
    for m in range(Q.shape[0]):
        rows = Q[m, fams[m] == wanted]
        if rows.size:
            candidates = cfg.continue_joints(q_prev, rows)
            q = candidates[int(np.argmin(cfg.joint_travel_s(model, q_prev, candidates)))]
            out[m] = q
            q_prev = q
            status.append(cfg.OK if model.within_limits(q) else cfg.JOINT_LIMIT)
        elif row_valid[m].any():
            status.append(cfg.CONFIG_CHANGE)
        elif not np.isnan(Q[m]).all():
            status.append(cfg.JOINT_LIMIT)
        else:
            status.append(cfg.UNREACHABLE)
    return out, status


@dataclass
class SampledMoves:
    """The samples of a program's Cartesian moves (move k: samples ``offsets[k]`` to
    ``offsets[k + 1] - 1``, its start target first, its end target last).

    Attributes
    ----------
    starts, groups : list
        Per move: the entry it starts from, and its entries (``[via, target]`` for a
        circular move, ``[target]``), as :func:`sample_moves` got them.
    length_mm, angle_deg, time_s, v_ori_deg_s : ndarray, shape (K,)
        Travel, tool rotation, time at the programmed speeds, orientation speed.
    family : ndarray of int, shape (K,)
        The configuration family each move keeps (its start's).
    offsets : ndarray of int, shape (K + 1,)
    fractions : ndarray, shape (S,)
        Travelled fraction of each sample, 0 to 1 within its move.
    q_deg : ndarray, shape (S, 6)
        Model joints, continued along each move; NaN where the family has no solution.
    status : ndarray of int, shape (S,)
        :data:`OK`, :data:`CONFIG_CHANGE`, :data:`JOINT_LIMIT` or :data:`UNREACHABLE`
        (see :func:`follow_family`).
    move_group : ndarray of int, shape (K,), or None
        From :func:`sample_program`: each move's index in :func:`move_groups`.
    clocks : list of (core.weave.RunClock or None), length K, or None
        Per move, the arc clock of the woven weld run it welds in (its samples are
        on the woven path), else None; None when no move weaves.
    external : ndarray, shape (S, E), or None
        The external axis values at each sample (``Program.external`` order:
        track mm, then positioner deg), interpolated linearly from the move's
        start to its end; None for a program without external axes.
    external_delta : ndarray, shape (K, E), or None
        Each move's change of the external axis values (end minus start).
    """

    starts: List
    groups: List
    length_mm: np.ndarray
    angle_deg: np.ndarray
    time_s: np.ndarray
    v_ori_deg_s: np.ndarray
    family: np.ndarray
    offsets: np.ndarray
    fractions: np.ndarray
    q_deg: np.ndarray
    status: np.ndarray
    move_group: np.ndarray = None
    clocks: list = None
    external: np.ndarray = None
    external_delta: np.ndarray = None

    def __len__(self):
        return len(self.groups)

    def move(self, k):
        """Move k as a dict: ``length_mm``, ``angle_deg``, ``time_s``, ``v_ori``,
        ``family``, ``fractions`` (M,), ``q_deg`` (M, 6), ``status`` (list of M str)."""
        rows = slice(self.offsets[k], self.offsets[k + 1])
        return {"length_mm": float(self.length_mm[k]), "angle_deg": float(self.angle_deg[k]),
                "time_s": float(self.time_s[k]), "v_ori": float(self.v_ori_deg_s[k]),
                "fractions": self.fractions[rows], "q_deg": self.q_deg[rows],
                "status": [STATUS_NAMES[s] for s in self.status[rows]],
                "family": int(self.family[k])}


def move_groups(entries):
    """A solved program's entries by move: lists of consecutive entries with the same
    ``move_index`` (``[via, target]`` for a circular move, ``[target]``)."""
    groups = []
    for entry in entries:
        if groups and groups[-1][-1].move_index == entry.move_index:
            groups[-1].append(entry)
        else:
            groups.append([entry])
    return groups


def sample_program(program, model, solution, margins, progress=None):
    """:func:`sample_moves` of every linear and circular move of a solved program whose
    start has joints (what the checks, the collision check and the cycle time all need:
    sample once, pass the result to each).  `progress`: see :func:`sample_moves`.

    Returns
    -------
    SampledMoves
        With ``move_group`` set.
    """
    groups = move_groups(solution.entries)
    chosen = [k for k in range(1, len(groups))
              if groups[k][-1].move.kind in (ir.LINEAR, ir.CIRCULAR)
              and groups[k - 1][-1].joints_deg is not None]
    sampled = sample_moves(program, model, [(groups[k - 1][-1], groups[k]) for k in chosen],
                           margins, progress=progress)
    sampled.move_group = np.array(chosen, dtype=int)
    return sampled


def sample_moves(program, model, moves, margins, progress=None, replace=None):
    """Sample Cartesian moves and follow each one's start configuration.

    Parameters
    ----------
    program : Program
    model : RobotModel
    moves : list of (TargetSolution, list of TargetSolution)
        Per move, the entry it starts from (with joints) and its entries.
    margins : Margins
        ``sample_step_mm``, ``sample_step_deg``, ``max_samples`` and the default
        ``orientation_speed_deg_s``.
    progress : callable, optional
        ``progress(fraction, text)`` (:mod:`..core.progress`), told between the
        vectorised steps; returning False raises ``Cancelled``.
    replace : dict, optional
        ``{weld run name: (weave, travel_speed_mm_s)}``: sample that run as if it
        had this weave and travel speed (:func:`...core.weave.run_clocks`; the
        weave advice tries its fixes so).

    Returns
    -------
    SampledMoves
        The welded moves of a run with a weave on the woven path, at least
        ``SAMPLES_PER_CYCLE`` samples per cycle (``max_samples`` does not cap them).
    """
    report_now(progress, 0.0, "sampling moves")
    if not moves:
        none = np.zeros(0)
        return SampledMoves([], [], none, none, none, none, np.zeros(0, int), np.zeros(1, int),
                            none, np.zeros((0, 6)), np.zeros(0, int))
    poses = move_poses(program, moves, margins, replace, progress)
    starts = [start for start, _ in moves]
    q_start = np.array([s.joints_deg for s in starts], dtype=float).reshape(-1, 6)
    family = cfg.family(q_start, model).astype(int)
    q, status = _follow(model, poses.T_r_f, poses.offsets, poses.move_of, family, q_start)
    report_now(progress, 1.0, "sampling moves")
    return SampledMoves(starts, [group for _, group in moves], poses.length_mm, poses.angle_deg,
                        poses.time_s, poses.v_ori_deg_s, family, poses.offsets, poses.fractions,
                        q, status, clocks=poses.clocks, external=poses.external,
                        external_delta=poses.external_delta)


@dataclass
class MovePoses:
    """Where :func:`sample_moves` samples each move (its attributes of the same names
    mean the same), before any joints are chosen.

    Attributes
    ----------
    length_mm, angle_deg, time_s, v_ori_deg_s : ndarray, shape (K,)
    offsets : ndarray of int, shape (K + 1,)
    move_of : ndarray of int, shape (S,)
        The move each sample belongs to.
    fractions : ndarray, shape (S,)
    T_r_f : ndarray, shape (S, 4, 4)
        The flange pose of each sample in {R}, mm.
    clocks : list or None
    external : ndarray, shape (S, E), or None
    external_delta : ndarray, shape (K, E), or None
    """

    length_mm: np.ndarray
    angle_deg: np.ndarray
    time_s: np.ndarray
    v_ori_deg_s: np.ndarray
    offsets: np.ndarray
    move_of: np.ndarray
    fractions: np.ndarray
    T_r_f: np.ndarray
    clocks: list = None
    external: np.ndarray = None
    external_delta: np.ndarray = None


def move_poses(program, moves, margins, replace=None, progress=None):
    """The samples of :func:`sample_moves` (same parameters; at least one move): their
    flange poses and the per-move measures, whatever joints the moves start from.

    Returns
    -------
    MovePoses
    """
    starts = [start for start, _ in moves]
    groups = [group for _, group in moves]
    k_moves = len(moves)
    coordinated = getattr(program, "external", None) is not None
    pose_of = (lambda entry, end: tcp_pose_in_frame(program, entry, end.move)) if coordinated \
        else (lambda entry, end: tcp_pose_in_base(program, entry))
    T0 = np.array([pose_of(s, g[-1]) for s, g in zip(starts, groups)]).reshape(-1, 4, 4)
    T1 = np.array([pose_of(g[-1], g[-1]) for g in groups]).reshape(-1, 4, 4)
    arcs = [_arc(T0[k], T1[k], g[-1].move.kind, pose_of(g[0], g[-1]) if len(g) > 1 else None)
            for k, g in enumerate(groups)]
    length = np.linalg.norm(T1[:, :3, 3] - T0[:, :3, 3], axis=1)
    for k, arc in enumerate(arcs):
        if arc is not None:
            length[k] = arc.length
    angle = np.degrees(rotations.rotation_angle_between(T0[:, :3, :3], T1[:, :3, :3]))
    angle = np.reshape(angle, (k_moves,))
    n = np.maximum(np.ceil(length / margins.sample_step_mm),
                   np.ceil(angle / margins.sample_step_deg))
    if coordinated:
        ext0 = np.array([external_values(program, s.target) for s in starts])
        ext_delta = np.array([external_values(program, g[-1].target) for g in groups]) - ext0
        n = np.maximum(n, _external_steps(program.external, ext_delta, margins))
    n = np.clip(np.maximum(n, 1), 1, margins.max_samples).astype(int)
    replace = replace or {}
    run_clocks = weaving.run_clocks(program, replace)
    clocks = [run_clocks.get(g[-1].move_index) for g in groups]
    speed = np.array([c.travel_speed_mm_s if c is not None and c.run.name in replace
                      else float(g[-1].move.speed_mm_s) for c, g in zip(clocks, groups)])
    v_ori = np.array([float(getattr(g[-1].move, "orientation_speed_deg_s", None)
                            or margins.orientation_speed_deg_s) for g in groups])
    time_s = np.maximum(length / speed, angle / v_ori)
    for k, clock in enumerate(clocks):
        if clock is not None:
            n[k] = max(n[k], int(np.ceil(time_s[k] / clock.step_s - 1e-9)))
    offsets = np.concatenate([[0], np.cumsum(n + 1)])
    move_of = np.repeat(np.arange(k_moves), n + 1)                    # (S,)
    local = np.arange(offsets[-1]) - offsets[move_of]
    fractions = local / n[move_of]
    report_now(progress, 0.2, "sampling moves")
    T_r_t = _poses(T0, T1, arcs, fractions, offsets)
    _weave(T_r_t, clocks, groups, fractions * time_s[move_of], offsets)
    external = None
    if coordinated:     # the poses so far are in each move's work frame {B}
        external = ext0[move_of] + fractions[:, None] * ext_delta[move_of]
        T_r_t = _frames_in_base(program, groups, move_of, external) @ T_r_t
    report_now(progress, 0.4, "sampling moves")
    T_t_f = tf.invert_transform(np.asarray(program.tool.T_f_t, dtype=float))
    return MovePoses(length, angle, time_s, v_ori, offsets, move_of, fractions, T_r_t @ T_t_f,
                     clocks=clocks if any(c is not None for c in clocks) else None,
                     external=external, external_delta=ext_delta if coordinated else None)


def peak_joint_speeds(model, sampled):
    """The fastest each controller joint turns on each sampled move, at the
    programmed speed (samples spread evenly over ``time_s``), deg/s.

    Steps between two samples count where both have status OK; the step from
    one move's end to the next move's start does not (J3 of a parallel-arm
    robot turns at the rate of ``q2 + q3``).

    Returns
    -------
    needed : ndarray, shape (K, 6)
        deg/s (inf or NaN where a move takes no time).
    good_samples : ndarray of int, shape (K,)
        Samples of each move with status OK.
    """
    offsets = sampled.offsets
    starts = offsets[:-1]
    good = sampled.status == OK
    q = np.where(good[:, None], sampled.q_deg, np.nan)
    steps = np.zeros((len(good), 6))
    steps[:-1] = np.nan_to_num(np.abs(np.diff(model.controller_joints(q), axis=0)), nan=0.0)
    steps[offsets[1:] - 1] = 0.0                          # from one move to the next
    dt = sampled.time_s / (np.diff(offsets) - 1)
    with np.errstate(divide="ignore", invalid="ignore"):
        needed = np.maximum.reduceat(steps, starts, axis=0) / dt[:, None]
    return needed, np.add.reduceat(good.astype(int), starts)


def _weave(T_r_t, clocks, groups, local_s, offsets):
    """Move the samples (S, 4, 4) of the woven moves onto the woven path, in place.

    `local_s` (S,) is each sample's time since its move started; the travel
    direction is the unwoven path's, per move.
    """
    for k, clock in enumerate(clocks):
        if clock is None:
            continue
        rows = slice(offsets[k], offsets[k + 1])
        positions = T_r_t[rows, :3, 3]
        count = offsets[k + 1] - offsets[k]
        T_r_t[rows, :3, 3] += clock.offsets_mm(
            np.full(count, groups[k][-1].move_index), local_s[rows],
            weaving.travel_directions(positions), T_r_t[rows, :3, 2])


def _poses(T0, T1, arcs, fractions, offsets):
    """TCP poses (S, 4, 4) at the fractions of their moves (see :func:`move_path`)."""
    move_of = np.repeat(np.arange(len(arcs)), np.diff(offsets))
    out = np.zeros((fractions.size, 4, 4))
    out[:, 3, 3] = 1.0
    p0, p1 = T0[move_of, :3, 3], T1[move_of, :3, 3]
    out[:, :3, 3] = p0 + fractions[:, None] * (p1 - p0)
    for k, arc in enumerate(arcs):
        if arc is not None:
            rows = slice(offsets[k], offsets[k + 1])
            out[rows, :3, 3] = arc.points_at(fractions[rows] * arc.length)
    q0 = rotations.quaternion_from_matrix(T0[:, :3, :3]).reshape(-1, 4)
    q1 = rotations.quaternion_from_matrix(T1[:, :3, :3]).reshape(-1, 4)
    out[:, :3, :3] = rotations.matrix_from_quaternion(
        rotations.quaternion_slerp(q0[move_of], q1[move_of], fractions).reshape(-1, 4))
    return out


def _follow(model, T_r_f, offsets, move_of, family, q_start):
    """:func:`follow_family` for every move at once.

    Where the move's family has exactly one IK row (everywhere but at a
    singularity), continuing each joint from the previous sample is a cumulative
    sum of the wrapped steps between consecutive solutions, one sequence per move
    (:func:`.joint_shifts.continue_sequence`).  Moves with a sample where the family has two rows are followed
    sample by sample.

    Returns
    -------
    q_deg : ndarray, shape (S, 6)
    status : ndarray of int, shape (S,)
    """
    Q = model.ik(T_r_f)                                          # (S, 8, 6)
    fams = cfg.family(Q, model)                                  # (S, 8)
    match = fams == family[move_of][:, None]
    count = match.sum(axis=1)
    raw = Q[np.arange(len(Q)), np.argmax(match, axis=1)]        # (S, 6)

    # Continue over the samples the family reaches, per move from its start joints.
    has = np.flatnonzero(count > 0)
    m = move_of[has]
    first = np.ones(len(has), dtype=bool)
    first[1:] = m[1:] != m[:-1]
    q = np.full((len(Q), 6), np.nan)
    q[has] = cfg.continue_sequence(q_start[m[first]], raw[has], first)

    status = np.full(len(Q), UNREACHABLE)
    inside = model.within_limits(q)
    status[has] = np.where(inside[has], OK, JOINT_LIMIT)
    missing = np.flatnonzero(count == 0)
    reachable = ~np.isnan(Q[missing]).all(axis=(1, 2))
    other_family = cfg.fits_limits(Q[missing], model).any(axis=1)
    status[missing] = np.where(other_family, CONFIG_CHANGE,
                               np.where(reachable, JOINT_LIMIT, UNREACHABLE))

    for k in np.unique(move_of[count > 1]):                      # at a singularity
        rows = slice(offsets[k], offsets[k + 1])
        q[rows], names = follow_family(model, T_r_f[rows], family[k], q_start[k])
        status[rows] = [STATUS_NAMES.index(name) for name in names]
    return q, status
