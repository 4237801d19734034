"""Choose the external axes at every target (issue 23).

:func:`choose_external` is what the App layer calls after
``core.generate.generate`` and before ``robots.motion.configuration.solve_program``.
It returns a :class:`Choice` (the first interface returned the (N, K) array that is
now ``Choice.values``) and takes ``tolerance_deg``.

How (plan issue 23, section 1 for the frames and the gravity angle):

1. **Seam position.** A welded target (a weld run's start target and every target
   of its welded moves) keeps its seam in the run's ``WeldRun.position``: PA, the
   weld frame's Z straight down (gravity angle 0); PB, Z 45 degrees from gravity
   with the seam horizontal (:func:`.seams.down_vectors`: one part vector per
   side to turn straight down). A two-axis positioner does it in closed form
   (:func:`.positioner_solve.two_axis_down`, two branches); one axis (a
   turntable, or a tilt-and-turn with an axis fixed) turns the vector as near
   down as it goes. A path without welds keeps each target's tool axis as near
   straight down as it goes (the same forms with the tool axis). Where the
   position does not depend on an axis (a vertical turntable: it cannot change
   a gravity angle), that axis brings the seam point to face the robot (nearest
   it, horizontally).
2. **Arm.** Each weld run (each path without welds) takes the branch and side
   with the best total arm score (:mod:`.arm_fit`: reach, joint limits,
   singularities; every candidate's IK in one call) and keeps it along the run:
   no flips (fewest targets missed first, then the best score). Where facing
   the robot leaves targets of a run out of the arm's reach, a free axis (a
   turntable) tries offsets of the whole run in :data:`FREE_OFFSETS_DEG`. A
   target the arm still cannot take tries values within ``tolerance_deg`` of the
   seam position (:data:`TOLERANCE_DEG`), and for a track other travel values.
   **A track rides abreast of the torch**: along each weld run (each path
   without welds) the travel is ``s*(target) - c``, ``s*`` the travel putting
   the robot's axis 1 abreast of the target (:func:`.arm_fit.abreast_travel`)
   and ``c`` ONE offset for the run, clamped to the travel; along a straight
   seam parallel to the track the arm then holds one pose and the carriage
   does the travel. ``c`` is the best of :data:`ABREAST_OFFSETS` (0: every
   target abreast), each run scored at its targets and between them
   (:data:`BETWEEN_FRACTIONS`) with the arm held in one IK branch, its joints
   continued (:func:`.arm_fit.run_scores`: fewest points missed, a point
   within Check's singularity margins counting as missed, then the best worst
   point, then the best sum: the arm's winding up between targets counts,
   which a target's own score does not see). Where the lazy travel ranks
   better (e.g. a seam across the track, where abreast is one travel for the
   whole seam), or the abreast travel needs the track beyond its speed or
   acceleration (which the speed pass of step 3 may fix for the lazy travel
   only, within the reach band), the run keeps it: each target's TCP within the
   horizontal reach band :data:`.arm_fit.GOOD_REACH`, moving only when a target
   leaves it (:func:`.arm_fit.lazy_travel`), clamped to the travel. Given
   values stay. With a track and a positioner, the positioner is chosen with
   the track as drawn, the travel for it, then both once more with that
   travel.
3. **Smooth.** Rotary values are continued target to target (never a 360 jump)
   and the whole program shifted by 360 degrees into the axis limits (least
   outside them where the seam needs more turn than they allow), nearest the
   drawn values. Targets off the seam (approach, entry, retract, moves
   between runs) take the values of the nearest seam target before them in
   their path (the first one after for the approach and entry).
   **Speeds and accelerations** (:mod:`.axis_motion`): where those exact values
   need a positioner axis faster than its ``max_speed``, or a blended corner
   needing more than its ``max_accel``, at the programmed TCP speed
   (coordinated: each move lasts its path length in the work frame over its
   speed), that axis's values along the weld run are moved least (an L1 linear
   programme) within a band per target that keeps the seam within
   ``tolerance_deg`` of its position (the band from how the gravity angle
   depends on each axis, the slack shared by the axes moved). The result is
   verified (every welded target's position measured as :func:`weld_positions`
   does, and the arm's reach) and kept only if it holds; where the limits cannot
   be met within the tolerance the exact values stay and Check reports the axis
   (``external_speed``, ``external_accel``). A path without welds goes through
   the same step, stretch by stretch of its linear and circular moves, its
   tool axes leaving the direction nearest straight down they were given by at
   most ``tolerance_deg`` (:func:`_allowed_deviation`). **The track** goes
   through it after the positioner: at each target the travel may move within
   the interval keeping that target's TCP within the reach band on the robot's
   side and within the travel (:func:`_travel_bands`; only the chosen value
   where it lies outside that interval, clamped or moved for the arm, or was
   given), least in L1 (:func:`.axis_motion.limit_axis_between`): the track
   starts earlier and moves more evenly than step 2's lazy travel, which moves
   only when a target leaves the band. It is kept only if the arm still takes every target
   it took (its IK); otherwise the travel stays and Check reports it.
4. **Overrides.** ``Axis.fixed`` fixes an axis everywhere; a target whose
   ``external`` arrives holding numbers keeps them (only NaN entries are chosen).

Pure numpy: never imports FreeCAD.
"""

from dataclasses import dataclass, field
from typing import Dict, List

import numpy as np
from scipy.spatial.transform import Rotation

from ...core import frames as tf
from ...core import mechanisms as mech
from ...core.progress import report_now
from ...errors import InputError
from . import arm_fit, axis_motion
from .positioner_solve import best_angle, two_axis_down, unwrap_near, unwrap_sequence
from .seams import (POSITION_GRAVITY_DEG, TOOL_DOWN, down_vectors, gravity_and_slope,
                    seam_table)

#: How far (deg) the chooser may leave the exact seam position to help the arm:
#: ISO 6947:2011 clause 3.3 allows a test weld +-10 degrees of rotation (and +-5 of
#: slope) from the main welding position (freestandardsintroduction.com/iso-6947-pdf-download.html).
TOLERANCE_DEG = 10.0
#: Offsets (deg) of a whole run tried on an axis the seam position leaves free.
FREE_OFFSETS_DEG = np.arange(-180.0, 180.0, 15.0)
GRAVITY_U = np.array([0.0, 0.0, -1.0])
#: What a target the arm misses costs a candidate, against arm scores in [0, 2]:
#: fewer missed targets always wins.
UNREACHED_COST = 100.0
#: A track moved this far (mm) counts as much as a positioner axis moved by the tolerance
#: when the values of a target the arm misses are looked for nearby.
TRAVEL_SCALE_MM = 100.0
#: A long run's candidates are ranked on this many of its targets, spread along it,
#: and the FINALISTS best of them scored on every target.
SAMPLE_TARGETS = 64
FINALISTS = 4
#: Offsets of a run's travel from abreast of each target tried, as fractions of the
#: reach band's outer radius (:func:`.arm_fit.reach_band`): 0 keeps every target abreast
#: of the robot's axis 1; at +-0.5 a seam up to 0.87 of that radius from the track stays
#: within it (a rule, not a maker's figure: unverified against a welding cell's practice).
ABREAST_OFFSETS = np.linspace(-0.5, 0.5, 11)
#: Fractions of the way between two consecutive targets of a run where a travel is
#: scored too (the arm may wind up between targets it takes well).
BETWEEN_FRACTIONS = (0.25, 0.5, 0.75)


@dataclass
class Choice:
    """What :func:`choose_external` chose.

    Attributes
    ----------
    values : ndarray, shape (N, K)
        External values per target (``Program.targets()`` order), mm / deg.
    gravity_deg, slope_deg : ndarray, shape (N,)
        Gravity angle and slope of each welded target at those values (NaN off the seam).
    worst_gravity_deg : dict of str to float
        Per weld run: the gravity angle farthest from the one its position asks for.
    unhelped : list of str
        Names of the targets the arm takes at no value tried (out of reach or a
        joint limit).
    tolerance_deg : float
    limited : dict of str to list of str
        Per weld run, the axes (``"E2"``) whose values were moved within the
        tolerance to keep their speeds and accelerations within the limits.
    """

    values: np.ndarray
    gravity_deg: np.ndarray
    slope_deg: np.ndarray
    worst_gravity_deg: Dict[str, float] = field(default_factory=dict)
    unhelped: List[str] = field(default_factory=list)
    tolerance_deg: float = TOLERANCE_DEG
    limited: Dict[str, List[str]] = field(default_factory=dict)


def choose_external(program, model, q_start_deg=None, progress=None,
                    tolerance_deg=TOLERANCE_DEG):
    """Set ``Target.external`` of every target of `program` (in place).

    Parameters
    ----------
    program : core.program.Program
        With ``program.external`` set (a program without one gets an empty Choice).
    model : robots.kinematics.models.RobotModel
    q_start_deg : array_like, shape (6,), optional
        Not used yet (the arm's configuration is solved afterwards).
    progress : callable, optional
        ``progress(fraction, text)`` (:mod:`...core.progress`); returning False
        raises ``Cancelled`` before any target is changed.
    tolerance_deg : float
        How far the seam may leave its position to help the arm, deg.

    Returns
    -------
    Choice

    Raises
    ------
    InputError
        A target gives a number of values other than the cell's axis count, or a
        weld asks for a position other than PA and PB.
    """
    external = program.external
    if external is None:
        return Choice(np.zeros((0, 0)), np.zeros(0), np.zeros(0))
    report_now(progress, 0.0, "choosing external axes")
    table = seam_table(program)
    ctx = _Context(program, model, table, tolerance_deg)
    given = _given_values(table, external)
    values = given.copy()
    n_track = len(external.track.axes) if external.track is not None else 0
    values[:, :n_track] = np.where(np.isnan(given[:, :n_track]),
                                   external.drawn_at()[:n_track], given[:, :n_track])
    # With both, a second pass scores the positioner's branches at the travel chosen.
    passes = 2 if external.positioner is not None and external.track is not None else 1
    for done in range(passes):
        if external.positioner is not None:
            values[:, n_track:] = _positioner_values(ctx, values, given[:, n_track:], n_track)
        if external.track is not None:
            values[:, :n_track] = _track_values(ctx, values, given[:, :n_track])
        report_now(progress, 0.8 * (done + 1) / passes, "choosing external axes")
    values = _copy_anchors(table, values, given)
    ctx.allowed_deg = _allowed_deviation(ctx, values)
    unhelped = _help_arm(ctx, values, given, n_track)
    ctx.copies = _plain_copies(table, values, given)
    limited = _limit_speeds(ctx, values, given, n_track)
    report_now(progress, 1.0, "external axes chosen")
    for target, v in zip(table.targets, values):
        target.external = v.copy()
    gravity, slope = gravity_and_slope(table, _R_u_b(program, table.frames, values))
    return Choice(values, gravity, slope, _worst_per_run(table, gravity), unhelped,
                  tolerance_deg, limited)


def gravity_angles(program):
    """Gravity angle (deg) of every welded target at its ``Target.external``.

    Parameters
    ----------
    program : core.program.Program

    Returns
    -------
    ndarray, shape (N,)
        ``Program.targets()`` order; NaN off the seam. A target without values
        is taken as drawn.
    """
    return _set_positions(program)[1]


def _set_positions(program):
    """(seam table, gravity (N,), slope (N,)) at the values already set (drawn where none)."""
    table = seam_table(program)
    external = program.external
    drawn = np.zeros(0) if external is None else external.drawn_at()
    values = np.array([drawn if external is None or t.external is None else t.external
                       for t in table.targets], dtype=float).reshape(len(table.targets), len(drawn))
    return (table,) + gravity_and_slope(table, _R_u_b(program, table.frames, values))


@dataclass
class WeldPosition:
    """How far one weld run's seam is from the position its weld asks for.

    Attributes
    ----------
    run : str
        ``WeldRun.name``.
    label : str
        ``WeldRun.label`` (the Weld object's label).
    position : str
        ``"PA"`` or ``"PB"``.
    worst_deg : float
        Over the run's welded targets: the largest of |gravity angle - asked|
        and, for PB, the slope (deg).
    target : str
        The target where it is worst.
    gravity_deg, slope_deg : float
        Gravity angle and slope there.
    targets : int
        Welded targets of the run.
    """

    run: str
    label: str
    position: str
    worst_deg: float
    target: str
    gravity_deg: float
    slope_deg: float
    targets: int


def weld_positions(program):
    """The seam position of every weld run at the external values already set.

    Parameters
    ----------
    program : core.program.Program

    Returns
    -------
    list of WeldPosition
        One per weld run with welded targets, in program order.
    """
    table, gravity, slope = _set_positions(program)
    offsets = _position_offsets(table, gravity, slope)
    labels = {run.name: run.label for _, run in program.weld_runs()}
    out = []
    for g, name in enumerate(table.group_names):
        rows = np.flatnonzero(table.welded & (table.group == g))
        if len(rows) == 0:
            continue
        position = table.group_positions[g]
        off = offsets[rows]
        k = rows[int(np.argmax(off))]
        out.append(WeldPosition(name, labels.get(name, name), position, float(off.max()),
                                table.targets[k].name,
                                float(gravity[k]), float(slope[k]), len(rows)))
    return out


def _position_offsets(table, gravity, slope):
    """(N,) how far each welded target is from its weld's position, deg: |gravity angle -
    asked| and, for PB, the slope where larger; NaN off the seam."""
    asked = np.array([POSITION_GRAVITY_DEG[table.group_positions[g]] if g >= 0 else np.nan
                      for g in table.group])
    pb = np.array([g >= 0 and table.group_positions[g] == "PB" for g in table.group], dtype=bool)
    off = np.abs(gravity - asked)
    return np.where(pb, np.maximum(off, slope), off)


# --- what is known before choosing -------------------------------------------------------

class _Context:
    """What every step reads: the program, the arm, the seam table."""

    def __init__(self, program, model, table, tolerance_deg):
        self.program, self.model, self.table = program, model, table
        self.external = program.external
        self.tolerance_deg = tolerance_deg
        self.frames = [program.frames[name] for name in table.frames]
        self.moving = np.array([name in self.external.moving_frames for name in table.frames],
                               dtype=bool)
        #: (N,) how far (deg) each target's part vector may be from straight down
        #: (:func:`_allowed_deviation`); the tolerance until the exact values are known.
        self.allowed_deg = np.full(len(table.targets), float(tolerance_deg))
        #: (N,) bool: off-seam targets following their anchor's values (:func:`_plain_copies`).
        self.copies = np.zeros(len(table.targets), dtype=bool)

    def scores(self, rows, values):
        """Arm scores of targets `rows` at `values` (M, K)."""
        frames = [self.frames[i] for i in rows]
        T_r_f = arm_fit.flange_poses(self.external, frames, self.table.T_b_t[rows],
                                     self.program.tool.T_f_t, values)
        return arm_fit.arm_scores(self.model, T_r_f)


def _given_values(table, external):
    """(N, K) values the user gave: per-target numbers, ``Axis.fixed`` over them; NaN: choose."""
    k = len(external.axes())
    given = np.full((len(table.targets), k), np.nan)
    for i, target in enumerate(table.targets):
        if target.external is None:
            continue
        numbers = np.asarray(target.external, dtype=float).reshape(-1)
        if len(numbers) != k:
            raise InputError("Target '%s' gives %d external axis values, but the cell has %d "
                             "(%s): give %d numbers (NaN to let CadRobot choose one) or none."
                             % (target.name, len(numbers), k, ", ".join(external.axis_names()),
                                k))
        given[i] = numbers
    for j, (_, axis) in enumerate(external.axes()):
        if axis.fixed is not None:
            given[:, j] = float(axis.fixed)
    return given


def _copy_anchors(table, values, given):
    """Off-seam targets take their anchor's values (drawn where no anchor); given numbers stay."""
    out = values.copy()
    has = table.anchor >= 0
    out[has] = values[table.anchor[has]]
    return np.where(np.isnan(given), out, given)


def _R_u_b(program, frame_names, values):
    """(M, 3, 3) work frame orientations in {U} at `values` (M, K), one per frame name."""
    external = program.external
    R = np.array([program.frames[name].T_u_b[:3, :3] for name in frame_names],
                 dtype=float).reshape(-1, 3, 3)
    if external is None or external.positioner is None:
        return R
    moving = np.array([name in external.moving_frames for name in frame_names], dtype=bool)
    _, positioner_values = external.split(values)
    if moving.any():
        motion = external.positioner.motion(positioner_values[moving])
        R[moving] = motion[:, :3, :3] @ R[moving]
    return R


def _down_in_u(ctx, rows, values):
    """(M, S, 3) the down vectors (both sides) of targets `rows` in {U} at `values` (M, K)."""
    names = [ctx.table.frames[i] for i in rows]
    return np.einsum("mij,msj->msi", _R_u_b(ctx.program, names, values),
                     down_vectors(ctx.table)[rows])


def _position_deviation(ctx, rows, values):
    """(M,) angle (deg) between each target's down vector (either side) and gravity at
    `values` (M, K): how far it is from its seam position; 0 off the seam."""
    d_u = _down_in_u(ctx, rows, values)
    angle = np.degrees(np.arccos(np.clip(d_u @ GRAVITY_U, -1.0, 1.0))).min(axis=1)
    return np.nan_to_num(angle, nan=0.0)


def _allowed_deviation(ctx, values):
    """(N,) how far (deg) each target's down vector may be from gravity: the tolerance
    for a welded target (from its position); for a tool-down target the tolerance
    beyond its deviation at the exact `values` (N, K), as near straight down as the
    axes turn it."""
    rows = np.arange(len(ctx.table.targets))
    exact = np.where(ctx.table.role == TOOL_DOWN, _position_deviation(ctx, rows, values), 0.0)
    return ctx.tolerance_deg + exact


def _worst_per_run(table, gravity):
    """{run name: gravity angle farthest from the asked one} over its welded targets."""
    out = {}
    for g, name in enumerate(table.group_names):
        rows = np.flatnonzero(table.welded & (table.group == g))
        if len(rows) == 0 or np.all(np.isnan(gravity[rows])):
            continue
        asked = POSITION_GRAVITY_DEG[table.group_positions[g]]
        worst = rows[np.nanargmax(np.abs(gravity[rows] - asked))]
        out[name] = float(gravity[worst])
    return out


# --- the positioner -----------------------------------------------------------------------

def _chain(positioner):
    """(R_base, [R_joint...], R_flange) rotations of the positioner's chain."""
    return (positioner.T_u_base[:3, :3], [a.T_prev_joint[:3, :3] for a in positioner.axes],
            positioner.T_last_flange[:3, :3])


def _rz(deg):
    """(M, 3, 3) rotations about Z by `deg` (M,)."""
    return mech._joint_transforms(mech.ROTARY, np.asarray(deg, dtype=float))[:, :3, :3]


def _flange_vectors(ctx, rows, d_b):
    """Part vectors (M, S, 3) of work-frame vectors at targets `rows`, in the positioner flange."""
    positioner = ctx.external.positioner
    R_p_u = positioner.T_u_p(positioner.drawn_at)[:3, :3].T
    R_u_b = np.array([ctx.frames[i].T_u_b[:3, :3] for i in rows], dtype=float).reshape(-1, 3, 3)
    return np.einsum("ij,mjk,msk->msi", R_p_u, R_u_b, d_b)


def _positioner_candidates(ctx, rows, given):
    """Candidate positioner values at targets `rows`: (M, C, k).

    Two axes (C = 4): (side, branch) of the closed form, or with one axis given
    the other's best angle per side. One axis (C = 2): its best angle per side.
    NaN where an axis is free (the seam position does not depend on it).
    """
    positioner = ctx.external.positioner
    R_base, R_joint, R_flange = _chain(positioner)
    w = _flange_vectors(ctx, rows, down_vectors(ctx.table)[rows]) @ R_flange.T   # (M, S, 3)
    g1 = R_joint[0].T @ R_base.T @ GRAVITY_U
    m = len(rows)
    if len(R_joint) == 1:
        angle, _ = best_angle(np.broadcast_to(g1, w.shape), w)                     # (M, S)
        return angle[..., None]
    out = np.empty((m, 4, 2))
    for side in range(2):
        out[:, 2 * side:2 * side + 2] = two_axis_down(R_joint[1], w[:, side], g1)
    first_given, second_given = ~np.isnan(given[:, 0]), ~np.isnan(given[:, 1])
    if first_given.any():          # the turn's best angle at the given tilt
        R_1 = R_joint[0] @ _rz(given[first_given, 0]) @ R_joint[1]             # (M1, 3, 3)
        h = np.einsum("mji,j->mi", R_1, R_base.T @ GRAVITY_U)
        turn, _ = best_angle(h[:, None, :], w[first_given])                  # (M1, S)
        out[first_given, :, 0] = given[first_given, None, 0]
        out[first_given, :, 1] = np.repeat(turn, 2, axis=1)
    only_second = second_given & ~first_given
    if only_second.any():          # the tilt's best angle at the given turn
        w2 = np.einsum("ij,mjk,msk->msi", R_joint[1], _rz(given[only_second, 1]),
                       w[only_second])
        tilt, _ = best_angle(np.broadcast_to(g1, w2.shape), w2)
        out[only_second, :, 0] = np.repeat(tilt, 2, axis=1)
        out[only_second, :, 1] = given[only_second, None, 1]
    return out


def _face_robot(ctx, rows, values_pos, robot_u):
    """The last positioner axis's angle bringing each target's TCP nearest the
    robot base `robot_u` (M, 3) horizontally, the other axes at `values_pos` (M, k)."""
    positioner = ctx.external.positioner
    axes = positioner.axes
    T_p_u = tf.invert_transform(positioner.T_u_p(positioner.drawn_at))
    T_u_b = np.array([ctx.frames[i].T_u_b for i in rows], dtype=float).reshape(-1, 4, 4)
    p_u = np.einsum("mij,mj->mi", T_u_b, ctx.table.T_b_t[rows, :, 3])
    x = np.einsum("ij,mj->mi", positioner.T_last_flange @ T_p_u, p_u)[:, :3]
    T = np.broadcast_to(positioner.T_u_base, (len(rows), 4, 4)).copy()
    for k, axis in enumerate(axes[:-1]):
        T = T @ axis.T_prev_joint @ mech._joint_transforms(axis.kind, values_pos[:, k])
    T = T @ axes[-1].T_prev_joint
    toward = robot_u - T[:, :3, 3]
    toward[:, 2] = 0.0
    h = np.einsum("mji,mj->mi", T[:, :3, :3], toward)
    angle, _ = best_angle(h, x)
    return np.nan_to_num(angle, nan=0.0)


def _positioner_values(ctx, values, given, n_track):
    """(N, k) positioner values: per group the candidate with the best arm score,
    free axes facing the robot (offsets tried), continued and fitted to the limits."""
    table = ctx.table
    positioner = ctx.external.positioner
    k = len(positioner.axes)
    out = np.tile(positioner.drawn_at, (len(table.targets), 1))
    solved = np.flatnonzero(table.on_seam & ctx.moving)
    if len(solved) == 0:
        return np.where(np.isnan(given), out, given)
    cand = _positioner_candidates(ctx, solved, given[solved])              # (M, C, k)
    m, c = cand.shape[:2]
    free = np.isnan(cand[..., -1])
    if free.any():
        flat = cand.reshape(-1, k)
        flat_free = free.reshape(-1)
        rows = np.repeat(solved, c)[flat_free]
        robot_u = ctx.external.T_u_r_at(values[rows])[:, :3, 3]
        flat[flat_free, -1] = _face_robot(ctx, rows, flat[flat_free], robot_u)
        cand = flat.reshape(m, c, k)
    cand = np.where(np.isnan(given[solved])[:, None, :], cand, given[solved][:, None, :])
    groups = table.group[solved]
    chosen = np.empty((m, k))
    for g in np.unique(groups):
        in_group = np.flatnonzero(groups == g)
        rows = solved[in_group]
        args = (ctx, values, rows, cand[in_group], free[in_group], np.isnan(given[rows, -1]),
                n_track)
        chosen[in_group], missed = _best_candidate(*args, np.zeros(1))
        if missed and free[in_group].any():        # facing the robot misses: turn the run
            chosen[in_group], _ = _best_candidate(*args, FREE_OFFSETS_DEG)
    out[solved] = chosen
    out = _continue_rotary(positioner, out, solved)
    return np.where(np.isnan(given), out, given)


def _best_candidate(ctx, values, rows, cand, free, last_open, n_track, offsets):
    """The candidate (and offset of the free axis) over a group's targets `rows`
    with the fewest targets the arm misses, then the best total arm score.

    Many candidates on a long run are first ranked on :data:`SAMPLE_TARGETS`
    targets spread along it; the :data:`FINALISTS` best are then scored on all.

    Parameters
    ----------
    cand : ndarray, shape (M, C, k)
        Positioner candidates per target.
    free : ndarray of bool, shape (M, C)
        Where the last axis is free (offsets apply there, unless given: `last_open`).
    offsets : ndarray, shape (O,)
        Offsets (deg) of the free axis tried.

    Returns
    -------
    values : ndarray, shape (M, k)
    missed : int
        Targets the arm does not take (or out of the positioner's limits) there.
    """
    m, c, k = cand.shape
    trials = np.repeat(cand[:, :, None, :], len(offsets), axis=2)          # (M, C, O, k)
    shift = free[:, :, None] & last_open[:, None, None]
    trials[..., -1] += np.where(shift, offsets[None, None, :], 0.0)
    trials = trials.reshape(m, -1, k)                                      # (M, C * O, k)
    finalists = np.arange(trials.shape[1])
    if m > SAMPLE_TARGETS and len(finalists) > FINALISTS:
        sample = np.unique(np.linspace(0, m - 1, SAMPLE_TARGETS).round().astype(int))
        total, _ = _run_totals(ctx, values, rows[sample], trials[sample], n_track)
        finalists = np.argsort(-total, kind="stable")[:FINALISTS]
    total, missed = _run_totals(ctx, values, rows, trials[:, finalists], n_track)
    best = int(np.argmax(total))
    return trials[:, finalists[best]], int(missed[best])


def _run_totals(ctx, values, rows, trials, n_track):
    """Per candidate (M, C, k) over targets `rows`: (total score less
    UNREACHED_COST per missed target, missed targets), each shape (C,)."""
    m, c, k = trials.shape
    full = np.repeat(values[rows][:, None, :], c, axis=1)
    full[..., n_track:] = trials
    score = ctx.scores(np.repeat(rows, c), full.reshape(m * c, -1)).reshape(m, c)
    reached = (score > arm_fit.NOT_REACHED) & _within_limits(ctx.external.positioner, trials)
    missed = (~reached).sum(axis=0)
    return np.where(reached, score, 0.0).sum(axis=0) - UNREACHED_COST * missed, missed


def _within_limits(positioner, trials):
    """(...) bool: every axis within its limits (rotary ones at some 360 shift)."""
    lower, upper = positioner.lower, positioner.upper
    rotary = np.array([a.kind == mech.ROTARY for a in positioner.axes])
    v = np.where(rotary, unwrap_near(trials, 0.5 * (lower + upper)), trials)
    return ((v >= lower - 1e-9) & (v <= upper + 1e-9)).all(axis=-1)


def _continue_rotary(mechanism, values, rows):
    """Rotary axes continued along the solved targets `rows` (no 360 jump), then
    the whole sequence shifted by the multiple of 360 that leaves it least
    outside the axis limits (summed over the targets), nearest the drawn value
    among equals. A sequence spanning more than the limits stays partly outside
    them: the checks report it."""
    out = values.copy()
    shifts = 360.0 * np.array([0.0, -1.0, 1.0, -2.0, 2.0])
    for j, axis in enumerate(mechanism.axes):
        if axis.kind != mech.ROTARY or len(rows) == 0:
            continue
        seq = unwrap_sequence(out[rows, j])
        seq += unwrap_near(seq[0], mechanism.drawn_at[j]) - seq[0]
        shifted = seq[None, :] + shifts[:, None]
        excess = (np.maximum(axis.lower - shifted, 0.0)
                  + np.maximum(shifted - axis.upper, 0.0)).sum(axis=1)
        out[rows, j] = shifted[int(np.argmin(excess.round(6)))]
    return out


# --- speeds and accelerations along each weld --------------------------------------------

def _plain_copies(table, values, given):
    """(N,) bool: off-seam targets holding exactly their anchor's values (none given):
    they follow it when the speed pass moves it."""
    anchored = (table.anchor >= 0) & ~table.on_seam & np.isnan(given).all(axis=1)
    same = (values == values[np.maximum(table.anchor, 0)]).all(axis=1)
    return anchored & same


def _limit_speeds(ctx, values, given, n_track):
    """Move the positioner's values, then the track's, along each weld run (each
    stretch of a path without welds) within their bands, where they need an axis
    beyond its speed or acceleration (in place; :mod:`.axis_motion`).

    Returns
    -------
    dict of str to list of str
        Per weld run (``"path:<name>"``) changed, the axes moved (``"E2"``).
    """
    names = ctx.external.axis_names()
    out = {}
    for motion in axis_motion.run_motions(ctx.program, ctx.table):
        moved = (_limit_positioner(ctx, values, given, motion, n_track)
                 + _limit_track(ctx, values, given, motion, n_track))
        for j in moved:
            out.setdefault(motion.run, [])
            if names[j] not in out[motion.run]:
                out[motion.run].append(names[j])
    return out


def _over_limits(ctx, values, motion, j):
    """Whether axis `j` needs more than its speed or acceleration along `motion`."""
    axis = ctx.external.axes()[j][1]
    return axis_motion.over_limits(values[motion.knots, j], motion, axis.max_speed,
                                   axis.max_accel)


def _limit_positioner(ctx, values, given, motion, n_track):
    """The rotary positioner axes over their limits along `motion`, moved within the
    tolerance where that holds (in place). Returns the axes moved (list of int)."""
    axes = ctx.external.axes()
    over = [j for j in range(n_track, len(axes))
            if axes[j][1].kind == mech.ROTARY and _over_limits(ctx, values, motion, j)]
    if not over:
        return []
    new, moved = _limited_run(ctx, values, given, motion, over, n_track)
    return moved if moved and _keep_if_good(ctx, values, motion.rows, new) else []


def _limit_track(ctx, values, given, motion, n_track):
    """The travel along `motion`, where over its limits, moved least within each
    target's reach band (:func:`_travel_bands`) and kept where the arm still takes
    every target it took (in place). Returns ``[0]`` when moved, else ``[]``."""
    if n_track == 0 or not _over_limits(ctx, values, motion, 0):
        return []
    axis = ctx.external.track.axes[0]
    low, high = _travel_bands(ctx, values, given, motion.rows)
    n = len(motion.knots)
    x = values[motion.knots, 0]
    y = axis_motion.limit_axis_between(x, low[:n], high[:n], low[n:], high[n:], motion,
                                       axis.max_speed, axis.max_accel)
    if y is None or np.abs(y - x).max() <= 1e-9:
        return []
    new = values[motion.rows].copy()
    new[:n, 0], new[n:, 0] = y, motion.via_values(y)
    return [0] if _keep_if_good(ctx, values, motion.rows, new) else []


def _keep_if_good(ctx, values, rows, new):
    """Set `new` (M, K) at targets `rows`, and at the off-seam targets copying one of
    them (approach, retract: ``ctx.copies``), if :func:`_still_good` holds for all
    (in place). Returns whether it did."""
    followers = np.flatnonzero(ctx.copies & np.isin(ctx.table.anchor, rows))
    position = {row: i for i, row in enumerate(rows)}
    rows = np.concatenate([rows, followers])
    new = np.vstack([new, new[[position[a] for a in ctx.table.anchor[followers]]]])
    if not _still_good(ctx, values, rows, new):
        return False
    values[rows] = new
    return True


def _limited_run(ctx, values, given, motion, axes_over, n_track):
    """The run's values (``motion.rows``) with each axis of `axes_over` limited within
    its share of the tolerance; an axis that cannot be keeps its values.

    Returns
    -------
    new : ndarray, shape (M, K)
    moved : list of int
        The axes changed.
    """
    rows = motion.rows
    new, moved = values[rows].copy(), []
    slack = ctx.allowed_deg[rows] - _position_deviation(ctx, rows, values[rows])
    sines = _axis_sines(ctx, rows, values[rows])
    n = len(motion.knots)
    for j in axes_over:
        axis = ctx.external.axes()[j][1]
        band = axis_motion.band_deg(sines[:, j - n_track], slack / len(axes_over))
        band[~np.isnan(given[rows, j])] = 0.0
        y = axis_motion.limit_axis(values[motion.knots, j], band[:n], values[motion.vias, j],
                                   band[n:], motion, axis.max_speed, axis.max_accel,
                                   axis.lower, axis.upper)
        if y is not None and np.abs(y - values[motion.knots, j]).max() > 1e-9:
            new[:n, j], new[n:, j] = y, motion.via_values(y)
            moved.append(j)
    return new, moved


def _axis_sines(ctx, rows, values):
    """(M, k) sine of the angle between each positioner axis and each target's down
    vector (the side nearest gravity), both in {U} at `values` (M, K); 0 where the
    target's frame does not ride on the positioner."""
    positioner = ctx.external.positioner
    _, pos = ctx.external.split(values)
    d_u = _down_in_u(ctx, rows, values)
    side = np.argmax(d_u @ GRAVITY_U, axis=1)
    d = d_u[np.arange(len(rows)), side]
    T = np.broadcast_to(positioner.T_u_base, (len(rows), 4, 4))
    out = np.empty((len(rows), len(positioner.axes)))
    for k, axis in enumerate(positioner.axes):
        T = T @ axis.T_prev_joint
        out[:, k] = np.linalg.norm(np.cross(T[:, :3, 2], d), axis=1)
        T = T @ mech._joint_transforms(axis.kind, pos[:, k])
    return np.where(ctx.moving[rows][:, None], out, 0.0)


def _still_good(ctx, values, rows, new):
    """Whether `new` (M, K) at targets `rows` keeps every welded one within the tolerance
    of its position, every tool-down one within its allowance (:func:`_allowed_deviation`),
    each no farther than before where it was, and within the arm's reach where it was."""
    trial = values.copy()
    trial[rows] = new
    table = ctx.table
    before = _position_offsets(table, *gravity_and_slope(table, _R_u_b(
        ctx.program, table.frames, values)))[rows]
    after = _position_offsets(table, *gravity_and_slope(table, _R_u_b(
        ctx.program, table.frames, trial)))[rows]
    allowed = np.maximum(ctx.tolerance_deg, np.nan_to_num(before, nan=0.0)) + 1e-6
    if np.any(np.nan_to_num(after, nan=0.0) > allowed):
        return False
    down = rows[table.role[rows] == TOOL_DOWN]
    if len(down):
        tilt_before = _position_deviation(ctx, down, values[down])
        tilt_after = _position_deviation(ctx, down, trial[down])
        if np.any(tilt_after > np.maximum(ctx.allowed_deg[down], tilt_before) + 1e-6):
            return False
    reached = ctx.scores(rows, values[rows]) > arm_fit.NOT_REACHED
    return bool(np.all(ctx.scores(rows, new)[reached] > arm_fit.NOT_REACHED))


# --- the track ----------------------------------------------------------------------------

def _track_motion(external):
    """(robot base at travel 0, its motion per mm of travel) in {U}."""
    track = external.track
    T0 = track.motion(np.zeros((1, 1))) @ external.T_u_r
    T1 = track.motion(np.ones((1, 1))) @ external.T_u_r
    return T0[0, :3, 3], T1[0, :3, 3] - T0[0, :3, 3]


def _tcp_in_u(ctx, values):
    """(N, 3) each target's TCP in {U} at `values` (the positioner moving its frames)."""
    table = ctx.table
    T_u_b = np.array([f.T_u_b for f in ctx.frames], dtype=float).reshape(-1, 4, 4)
    if ctx.external.positioner is not None and ctx.moving.any():
        _, pos = ctx.external.split(values)
        T_u_b[ctx.moving] = ctx.external.positioner.motion(pos[ctx.moving]) @ T_u_b[ctx.moving]
    return np.einsum("nij,nj->ni", T_u_b, table.T_b_t[:, :, 3])[:, :3]


def _travel_intervals(ctx, values, rows):
    """(low, high), each (M,): the travel keeping the TCP of each target of `rows` within
    the reach band at `values` (N, K), on the robot's drawn side of the first seam
    target (:func:`.arm_fit.travel_intervals`); None for a track moving the robot only
    up and down, or without seam targets."""
    seam = np.flatnonzero(ctx.table.on_seam)
    base_u, along_u = _track_motion(ctx.external)
    a = np.array([along_u[0], along_u[1], 0.0])
    if len(seam) == 0 or a @ a < 1e-12:
        return None
    points = _tcp_in_u(ctx, values)
    first = points[seam[0]] - base_u
    side = -1.0 if ctx.external.track.drawn_at[0] <= (first[:2] @ a[:2]) / (a @ a) else 1.0
    return arm_fit.travel_intervals(points[rows], base_u, along_u,
                                    arm_fit.reach_band(ctx.model), side)


def _track_values(ctx, values, given):
    """(N, 1) travel of the seam targets, run by run: abreast of each target less one
    offset per run, or each target within the reach band, moving only when it must,
    on the robot's drawn side of the first target, where that ranks better
    (:func:`_run_travel`); clamped to the travel (a track moving the robot only up and
    down stays as drawn)."""
    track = ctx.external.track
    out = np.tile(track.drawn_at, (len(ctx.table.targets), 1))
    rows = np.flatnonzero(ctx.table.on_seam)
    intervals = _travel_intervals(ctx, values, rows)
    if intervals is None:        # nothing to follow, or a lift: not moved
        return np.where(np.isnan(given), out, given)
    lazy = np.clip(arm_fit.lazy_travel(*intervals, float(track.drawn_at[0])),
                   track.lower[0], track.upper[0])
    base_u, along_u = _track_motion(ctx.external)
    abreast = arm_fit.abreast_travel(_tcp_in_u(ctx, values)[rows], base_u, along_u)
    group = ctx.table.group[rows]
    motions = axis_motion.run_motions(ctx.program, ctx.table)
    for g in np.unique(group):
        run = np.flatnonzero(group == g)
        out[rows[run], 0] = _run_travel(ctx, values, given, rows[run], lazy[run], abreast[run],
                                        [m for m in motions if m.run == ctx.table.group_names[g]])
    return np.where(np.isnan(given), out, given)


def _run_travel(ctx, values, given, rows, lazy, abreast, motions):
    """(M,) travel of one run's seam targets `rows`: abreast of each target (`abreast`,
    (M,)) less the one offset of :data:`ABREAST_OFFSETS` the arm takes best along the
    run (:func:`_travel_scores`), clamped to the travel; the `lazy` travel (M,) where
    the best of those misses more points, or has a worse worst point, or (the same)
    a worse sum, or needs the track faster than its speed or acceleration along
    `motions` (the run's :class:`.axis_motion.RunMotion`: the speed pass may then
    move the lazy travel within the reach band, not the abreast one)."""
    track = ctx.external.track
    offsets = ABREAST_OFFSETS * arm_fit.reach_band(ctx.model)[1]
    candidates = np.vstack([lazy, np.clip(abreast[None, :] - offsets[:, None],
                                          track.lower[0], track.upper[0])])      # (C, M)
    candidates = np.where(np.isnan(given[rows, 0]), candidates, given[rows, 0])
    missed, worst, total = _travel_scores(ctx, values, rows, candidates)
    best = 1 + int(np.lexsort((-total[1:], -worst[1:], missed[1:]))[0])
    ranks = [(missed[k], -round(worst[k], 9), -total[k]) for k in (best, 0)]
    if ranks[0] > ranks[1] or _track_too_slow(ctx, rows, candidates[best], motions):
        return lazy
    return candidates[best]


def _track_too_slow(ctx, rows, travel, motions):
    """Whether the `travel` (M,) of targets `rows` needs the track beyond its speed or
    acceleration along any of `motions` (list of RunMotion)."""
    axis = ctx.external.track.axes[0]
    position = {row: i for i, row in enumerate(rows)}
    for motion in motions:
        if all(knot in position for knot in motion.knots):
            knots = travel[[position[knot] for knot in motion.knots]]
            if axis_motion.over_limits(knots, motion, axis.max_speed, axis.max_accel):
                return True
    return False


def _travel_scores(ctx, values, rows, candidates):
    """(points missed, worst score, summed score), each (C,), of the travel `candidates`
    (C, M) of targets `rows` along the run (:func:`_run_samples`), the arm held in one
    branch (:func:`.arm_fit.run_scores`)."""
    frame_rows, T_b_t, weights = _run_samples(ctx, rows)
    c, p = len(candidates), len(frame_rows)
    trial = np.repeat((weights @ values[rows])[None], c, axis=0)             # (C, P, K)
    trial[..., 0] = candidates @ weights.T
    frames = [ctx.frames[i] for i in np.tile(frame_rows, c)]
    T_r_f = arm_fit.flange_poses(ctx.external, frames, np.tile(T_b_t, (c, 1, 1)),
                                 ctx.program.tool.T_f_t, trial.reshape(c * p, -1))
    return arm_fit.run_scores(ctx.model, T_r_f.reshape(c, p, 4, 4))


def _run_samples(ctx, rows):
    """Points along one run where a travel is scored: its targets `rows` (M,) and, between
    consecutive ones in the same frame, :data:`BETWEEN_FRACTIONS` of the way (position
    linear, orientation turned at a constant rate; the chord of an arc), where the arm
    may wind up between targets it takes well; at most :data:`SAMPLE_TARGETS` pairs,
    spread along it.

    Returns
    -------
    frame_rows : ndarray of int, shape (P,)
        A target in each point's frame.
    T_b_t : ndarray, shape (P, 4, 4)
    weights : ndarray, shape (P, M)
        Each point's values from the targets' (linear, as the coordinated move goes).
    """
    m = len(rows)
    pick = np.unique(np.linspace(0, m - 1, min(m, SAMPLE_TARGETS + 1)).round().astype(int))
    frames = np.array(ctx.table.frames, dtype=object)[rows]
    start = pick[(pick + 1 < m)]
    start = start[frames[start] == frames[np.minimum(start + 1, m - 1)]]
    f = np.tile(np.asarray(BETWEEN_FRACTIONS, dtype=float), len(start))
    first = np.concatenate([pick, np.repeat(start, len(BETWEEN_FRACTIONS))])
    second = np.concatenate([pick, np.repeat(start + 1, len(BETWEEN_FRACTIONS))])
    fraction = np.concatenate([np.zeros(len(pick)), f])
    along = np.argsort(first + fraction, kind="stable")      # in the run's order
    first, second, fraction = first[along], second[along], fraction[along]
    T0, T1 = ctx.table.T_b_t[rows[first]], ctx.table.T_b_t[rows[second]]
    turn = Rotation.from_matrix(np.einsum("pji,pjk->pik", T0[:, :3, :3], T1[:, :3, :3]))
    T = T0.copy()
    T[:, :3, :3] = T0[:, :3, :3] @ Rotation.from_rotvec(
        turn.as_rotvec() * fraction[:, None]).as_matrix()
    T[:, :3, 3] = (1.0 - fraction[:, None]) * T0[:, :3, 3] + fraction[:, None] * T1[:, :3, 3]
    weights = np.zeros((len(first), m))
    points = np.arange(len(first))
    weights[points, first] += 1.0 - fraction
    weights[points, second] += fraction
    return rows[first], T, weights


def _travel_bands(ctx, values, given, rows):
    """(low, high), each (M,): where the speed pass may move the travel of targets
    `rows`: the reach band's interval within the track's travel where the chosen
    value lies in it; the chosen value alone where it does not (clamped to the
    track's end, moved there for the arm by :func:`_help_arm`) or was given."""
    x = values[rows, 0]
    intervals = _travel_intervals(ctx, values, rows)
    if intervals is None:
        return x, x
    track = ctx.external.track
    low = np.maximum(intervals[0], track.lower[0])
    high = np.minimum(intervals[1], track.upper[0])
    free = (low - 1e-9 <= x) & (x <= high + 1e-9) & np.isnan(given[rows, 0])
    return np.where(free, np.minimum(low, x), x), np.where(free, np.maximum(high, x), x)


# --- targets the arm does not take --------------------------------------------------------

def _help_arm(ctx, values, given, n_track):
    """Where the arm takes no branch, try values near the chosen ones (in place):
    positioner axes moved within the tolerance of the seam position, the track
    over its travel; seam targets first, then the targets copying them (an
    approach or a retract the arm misses at its seam target's values).

    Returns
    -------
    list of str
        The names of the targets the arm still does not take.
    """
    table = ctx.table
    _retry(ctx, values, given, n_track, np.flatnonzero(table.on_seam))
    values[:] = _copy_anchors(table, values, given)
    _retry(ctx, values, given, n_track, np.flatnonzero(~table.on_seam & (table.anchor >= 0)))
    rows = np.flatnonzero(table.anchor >= 0)
    missed = rows[ctx.scores(rows, values[rows]) <= arm_fit.NOT_REACHED]
    return [table.targets[i].name for i in missed]


def _retry(ctx, values, given, n_track, rows):
    """Targets `rows` the arm misses take the nearby values it takes that change
    least (mm / :data:`TRAVEL_SCALE_MM` + deg / tolerance), then score best (in place)."""
    bad = rows[ctx.scores(rows, values[rows]) <= arm_fit.NOT_REACHED]
    if len(bad) == 0:
        return
    trials = _nearby_values(ctx, values[bad], given[bad], n_track)         # (B, P, K)
    b, p, k = trials.shape
    flat_rows, flat = np.repeat(bad, p), trials.reshape(-1, k)
    score = ctx.scores(flat_rows, flat)
    reached = (score > arm_fit.NOT_REACHED) & (
        _position_deviation(ctx, flat_rows, flat) <= ctx.tolerance_deg + 1e-9)
    scale = np.where(np.arange(k) < n_track, TRAVEL_SCALE_MM, max(ctx.tolerance_deg, 1e-9))
    change = (np.abs(trials - values[bad][:, None, :]) / scale).sum(axis=2)
    cost = np.where(reached.reshape(b, p), change - 1e-3 * score.reshape(b, p), np.inf)
    best = np.argmin(cost, axis=1)
    taken = np.isfinite(cost[np.arange(b), best])
    values[bad[taken]] = trials[np.arange(b), best][taken]


def _nearby_values(ctx, values, given, n_track):
    """(B, P, K) trial values around `values` (B, K): positioner axes moved by up
    to the tolerance, the travel over its whole range; given entries kept."""
    external = ctx.external
    steps = [np.zeros(1)] * values.shape[1]
    if external.track is not None:
        track = external.track
        steps[0] = np.linspace(track.lower[0], track.upper[0], 21)
    tol = ctx.tolerance_deg
    for j in range(n_track, values.shape[1]):
        steps[j] = np.linspace(-tol, tol, 5)
    grid = np.stack(np.meshgrid(*steps, indexing="ij"), axis=-1).reshape(-1, values.shape[1])
    trials = values[:, None, :] + grid[None]
    if external.track is not None:
        trials[..., 0] = grid[None, :, 0]
    return np.where(np.isnan(given)[:, None, :], trials, given[:, None, :])
