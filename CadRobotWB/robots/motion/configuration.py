"""Robot configurations along a program: one joint vector per target.

A 6-axis arm reaches most poses in up to eight ways (the rows of
``model.ik``; up to sixteen on an offset wrist, whose families can then
hold two to four of them: :mod:`.arm_families`), and every joint whose
range exceeds 360 degrees in total can also take ``q +- 360``.  This module chooses one joint vector per target of a
:class:`~CadRobotWB.core.program.Program`.  Its parts live in modules of their
own, and their names are importable from here too: the families
(:mod:`.arm_families`), joints shifted by 360 degrees (:mod:`.joint_shifts`),
sampling along a move (:mod:`.move_sampling`) and the configuration data each
language states (:mod:`.configuration_data`).

Families: see :mod:`.arm_families`.

Choosing the joints (:func:`solve_program`)
-------------------------------------------
Moves are grouped in *runs*: a run starts at each joint move (and at the
first move of the program) and goes on through the linear and circular
moves after it.  A generated path is one run (its approach is a joint
move).  A joint move may change configuration; linear and circular moves
may not, so each run keeps one family:

1. each target's flange pose ``T_r_f = T_r_b @ T_b_t @ inv(T_f_t)``
   (:func:`flange_poses`) and its eight IK solutions;
2. a family is *valid* at a target when its solution exists and every joint,
   shifted by some multiple of 360 degrees, lies within the joint limits
   (limits, speeds and shifts are the controller's: see "Joint values");
3. the run takes the family valid at the most targets; ties go to the
   family whose solution at the run's first valid target is quickest to
   reach from the previous joints (``q_start_deg``, or the end of the
   previous run, or the middle of the joint ranges for the very first run);
   a run that does not start with a joint move keeps the family the robot
   is already in;
4. target by target, the family's solution continued from the previous
   target, every joint within 180 degrees of its previous value (a linear
   move cannot unwind a joint by 360 degrees), so J4/J6 (and J1 of a KUKA,
   any joint whose range exceeds 360 degrees in total) run on past +-180;
5. one shift by a multiple of 360 degrees per joint for the whole run
   (only after a joint move, which can unwind): the shift that keeps every
   target within the limits, nearest the previous joints.  When no shift
   fits, the targets where the continued joint is out of its range get
   status ``"joint_limit"`` (the path winds the wrist up).

A target where the run's family is not valid but another one is gets that
other family's closest solution and status ``"config_change"``; a target
no family reaches within the limits gets no joints (status
``"joint_limit"`` or ``"unreachable"``).  :mod:`.checks` turns these into
findings, and samples the moves in between the same way
(:mod:`.move_sampling`).

Joint values
------------
Joints here (``joints_deg``, ``attempt_deg``, ``Target.joints_deg``) are
the model's (:mod:`.models`: what ``fk`` takes).  The joint limits and
joint speeds are the controller's, which differ on a parallel-arm robot
(``spec.j23_coupled``, the IRB 2400: the controller's J3 is ``q2 + q3``),
so every limit test goes through
:meth:`~.models.RobotModel.limit_excess` /
:meth:`~.models.RobotModel.within_limits`, the 360-degree shifts are made
on the controller's joints (:func:`unwrap_joints`) and "quickest" is timed
on them (:func:`joint_travel_s`).

Pure numpy: never imports FreeCAD.
"""

from dataclasses import dataclass, field
from typing import List, Optional, Tuple

import numpy as np

from ...core import frames as tf
from ...core import program as ir
from ...core.mechanisms import frame_in_base
from ...core.progress import Steps, report_now, stage
from ...errors import InputError
from ..kinematics.arm_families import _on_angle_grid
from .joint_shifts import _turned
# Re-exported: callers use configuration.<name> for these.
from ..kinematics.arm_families import (ELBOW_DOWN, SHOULDER_BACK, WRIST_FLIPPED,  # noqa: F401
                           ArmGeometry, arm_geometry, family, family_name,
                           singular_on_jacobian)
from .configuration_data import (abb_confdata, fanuc_config, kuka_status_turn,  # noqa: F401
                                 motoman_rconf, quadrant)
from .joint_shifts import (continue_joints, continue_sequence, fits_limits,  # noqa: F401
                           joint_travel_s, pick_in_family, reference_joints, travel_time_s,
                           unwrap_joints)

#: Status of a target in a :class:`JointSolution`.
OK = "ok"
CONFIG_CHANGE = "config_change"
JOINT_LIMIT = "joint_limit"
UNREACHABLE = "unreachable"


# --- the program's targets -----------------------------------------------------------------

@dataclass
class TargetSolution:
    """The joints chosen for one target (a move's end or a circular move's via).

    Attributes
    ----------
    target : Target
    move : Move
        The move that goes to (or through, for a via) this target.
    move_index : int
        0-based index of the move in ``program.moves()``.
    path_index : int
        0-based index of the path in ``program.paths``.
    path_label : str
    is_via : bool
        True for the intermediate point of a circular move.
    T_r_f : ndarray, shape (4, 4)
        Flange pose in the robot base frame {R}, mm.
    run : int
        Index of the run (see the module docstring) in ``JointSolution.run_families``.
    status : str
        ``"ok"``, ``"config_change"``, ``"joint_limit"`` or ``"unreachable"``.
    joints_deg : ndarray, shape (6,), or None
        The joints the robot takes here, degrees (within the limits); None
        for ``"joint_limit"`` and ``"unreachable"``.
    family : int or None
        Family of ``joints_deg``.
    valid_families : tuple of int
        Every family valid at this target.
    attempt_deg : ndarray, shape (6,), or None
        For ``"joint_limit"``: the solution closest to the limits (the run's
        family when it reaches the pose), to say which joint is out and by
        how much.
    """

    target: ir.Target
    move: ir.Move
    move_index: int
    path_index: int
    path_label: str
    is_via: bool
    T_r_f: np.ndarray
    run: int = 0
    status: str = UNREACHABLE
    joints_deg: Optional[np.ndarray] = None
    family: Optional[int] = None
    valid_families: Tuple[int, ...] = ()
    attempt_deg: Optional[np.ndarray] = None


@dataclass
class JointSolution:
    """Joints of every target of a program, in execution order.

    Attributes
    ----------
    robot : str
        Catalog name.
    entries : list of TargetSolution
        One per target occurrence (a circular move's via comes before its target).
    run_families : list of (int or None)
        Family kept by each run; None when no family is valid anywhere in it.
    q_start_deg : ndarray, shape (6,), or None
        Where the robot starts, if given.
    reference_deg : ndarray, shape (6,)
        ``q_start_deg``, or :func:`reference_joints` when it was not given.
    """

    robot: str
    entries: List[TargetSolution] = field(default_factory=list)
    run_families: List[Optional[int]] = field(default_factory=list)
    q_start_deg: Optional[np.ndarray] = None
    reference_deg: Optional[np.ndarray] = None

    @property
    def ok(self):
        """bool: every target has joints in its run's family."""
        return all(e.status == OK for e in self.entries)

    def joints(self):
        """ndarray, shape (N, 6): the joints of every entry, NaN where there are none."""
        out = np.full((len(self.entries), 6), np.nan)
        for i, entry in enumerate(self.entries):
            if entry.joints_deg is not None:
                out[i] = entry.joints_deg
        return out


def target_entries(program):
    """Every target of a program in execution order, with its move and path.

    Parameters
    ----------
    program : Program

    Returns
    -------
    list of TargetSolution
        Unsolved (status ``"unreachable"``, no joints); ``T_r_f`` filled.

    Raises
    ------
    InputError
        A move names a work frame the program does not define.
    """
    T_t_f = tf.invert_transform(np.asarray(program.tool.T_f_t, dtype=float))
    out, T_r_b, T_b_t = [], [], []
    move_index = 0
    for path_index, path in enumerate(program.paths):
        for move in path.moves:
            frame = program.frames.get(move.frame)
            if frame is None:
                raise InputError("Move to target '%s' in path '%s' uses work frame '%s', which "
                                 "the program does not define; regenerate the program."
                                 % (move.target.name, path.label or path.name, move.frame))
            for target, is_via in ((move.via, True), (move.target, False)):
                if target is None:
                    continue
                out.append(TargetSolution(target=target, move=move, move_index=move_index,
                                          path_index=path_index,
                                          path_label=path.label or path.name,
                                          is_via=is_via, T_r_f=None))
                T_r_b.append(frame_in_base(program, move, target))
                T_b_t.append(target.T_b_t)
            move_index += 1
    if out:
        T_r_f = (np.asarray(T_r_b, dtype=float) @ np.asarray(T_b_t, dtype=float)) @ T_t_f
        for entry, T in zip(out, T_r_f):
            entry.T_r_f = T
    return out


def flange_poses(program):
    """Flange pose in the robot base {R} of every target, in execution order.

    ``T_r_f = T_r_b @ T_b_t @ inv(T_f_t)`` with the move's work frame
    (``WorkFrame.T_r_b``) and the program's tool (``ToolData.T_f_t``);
    a circular move's via comes before its target.

    Parameters
    ----------
    program : Program

    Returns
    -------
    ndarray, shape (N, 4, 4)
        mm.
    """
    entries = target_entries(program)
    if not entries:
        return np.zeros((0, 4, 4))
    return np.array([e.T_r_f for e in entries])


def solve_program(program, model, q_start_deg=None, assign=True, progress=None):
    """Choose the joints of every target: one configuration per run, J4/J6 unwrapped.

    See the module docstring for the rules.

    Parameters
    ----------
    program : Program
    model : RobotModel
        ``robots.kinematics.models.model(program.robot)``.
    q_start_deg : array_like, shape (6,), optional
        Joints the robot starts from, degrees.  Without it the first run's
        ties are broken towards the middle of the joint ranges.
    assign : bool
        Write each target's joints into ``Target.joints_deg`` (None where
        there is no solution within the limits).  Default True.
    progress : callable, optional
        ``progress(fraction, text)`` (:mod:`..core.progress`); returning
        False raises :class:`..core.progress.Cancelled` (nothing assigned).

    Returns
    -------
    JointSolution
    """
    spec = model.spec
    entries = target_entries(program)
    q_start = None if q_start_deg is None else np.asarray(q_start_deg, dtype=float).reshape(6)
    reference = q_start if q_start is not None else reference_joints(model)
    solution = JointSolution(robot=spec.name, entries=entries, q_start_deg=q_start,
                             reference_deg=reference)
    if not entries:
        return solution

    report_now(progress, 0.0, "solving joints")
    Q = model.ik(np.array([e.T_r_f for e in entries]))              # (N, 8, 6)
    fams = family(Q, model)                                          # (N, rows)
    row_valid = fits_limits(Q, model)                                # (N, 8)
    valid = np.zeros((len(entries), 8), dtype=bool)                  # (N, family)
    for f in range(8):
        valid[:, f] = (row_valid & (fams == f)).any(axis=1)
    reachable = ~np.isnan(Q).any(axis=2)                             # (N, 8)

    runs = _runs(entries)
    q_prev = q_start
    steps = Steps(stage(progress, 0.5, 1.0), len(entries), "solving joints")
    report_now(progress, 0.5, "solving joints")
    for run_index, indices in enumerate(runs):
        continues = entries[indices[0]].move.kind != ir.JOINT and q_prev is not None
        q_ref = q_prev if q_prev is not None else reference
        if continues:
            chosen = int(family(q_prev, model))       # a linear move cannot change family
        else:
            chosen = _choose_family(indices, Q, fams, valid, q_ref, model)
        solution.run_families.append(chosen)
        track = _run_track(indices, Q, fams, valid, chosen, q_ref, continues, model)
        for i in indices:
            steps(i)
            entry = entries[i]
            entry.run = run_index
            entry.valid_families = tuple(int(f) for f in np.flatnonzero(valid[i]))
            q_last = q_prev if q_prev is not None else reference
            if i in track:
                q, inside = track[i]
                entry.family = chosen
                if inside:
                    entry.status, entry.joints_deg = OK, q
                else:                  # the path winds a joint out of its range
                    entry.status, entry.attempt_deg = JOINT_LIMIT, q
            else:
                _solve_off_family(entry, Q[i], fams[i], valid[i], reachable[i], chosen, q_last,
                                  model)
            if entry.joints_deg is not None:
                q_prev = entry.joints_deg

    if assign:
        for entry in entries:
            entry.target.joints_deg = (None if entry.joints_deg is None
                                       else np.array(entry.joints_deg, dtype=float))
    return solution


def _runs(entries):
    """Lists of entry indices; a new run starts at each joint move."""
    runs = []
    for i, entry in enumerate(entries):
        if not runs or (entry.move.kind == ir.JOINT and not entry.is_via
                        and entries[i - 1].move is not entry.move):
            runs.append([])
        runs[-1].append(i)
    return runs


#: Travel times closer than this, seconds, are equal (a tie between two families).
TIE_S = 1e-9


def _choose_family(indices, Q, fams, valid, q_ref, model):
    """The family valid at most targets of a run; ties: quickest from q_ref."""
    counts = valid[indices].sum(axis=0)
    best = counts.max()
    if best == 0:
        return None
    families = np.flatnonzero(counts == best)
    travel_s = []
    for f in families:
        first = next(i for i in indices if valid[i, f])
        q, _ = pick_in_family(Q[first], fams[first], f, q_ref, model)
        travel_s.append(float(joint_travel_s(model, q_ref, q)))
    # Equal travel times (to rounding, which differs between IK solvers) go to the
    # lowest family number.
    quick = np.asarray(travel_s) <= min(travel_s) + TIE_S
    return int(families[np.flatnonzero(quick)[0]])


def _run_track(indices, Q, fams, valid, chosen, q_ref, continues, model):
    """Joints of a run's targets in its family, as one continuous motion.

    The family's solution at each target where it is valid, each joint
    continued from the previous target (:func:`continue_joints`); then one
    shift by a multiple of 360 degrees per joint for the whole run (none when
    the run continues from ``q_ref`` without a joint move): the shift that
    keeps every target within the limits, nearest ``q_ref``; failing that,
    the one that keeps most targets within them.  Shifts and limits are on
    the controller's joints (see :func:`unwrap_joints`).

    Returns
    -------
    dict
        Entry index -> (q (6,), inside_limits bool).
    """
    if chosen is None:
        return {}
    order = np.array([i for i in indices if valid[i, chosen]], dtype=int)
    if not order.size:
        return {}
    match = fams[order] == chosen                                  # (M, 8)
    if (match.sum(axis=1) == 1).all():
        track = continue_sequence(q_ref, Q[order, np.argmax(match, axis=1)])
    else:                      # two rows of the family somewhere (a singularity)
        track, prev = [], q_ref
        for i in order:
            candidates = continue_joints(prev, Q[i, fams[i] == chosen])
            prev = candidates[int(np.argmin(joint_travel_s(model, prev, candidates)))]
            track.append(prev)
        track = np.array(track)                                    # (M, 6)
    if not continues:
        cand = _turned(model, track)                               # (M, 5, 6)
        inside = (model.limit_excess(cand, controller=True) == 0.0).sum(axis=0)      # (5, 6)
        near = _on_angle_grid(np.abs(cand[0] - model.controller_joints(q_ref)))          # (5, 6)
        # Per joint: the turn with most targets inside; among those, the first target nearest.
        best = np.argmin(np.where(inside == inside.max(axis=0), near, np.inf), axis=0)
        track = model.model_joints(cand[:, best, np.arange(6)])
    inside = model.within_limits(track)
    return {int(i): (track[m], bool(inside[m])) for m, i in enumerate(order)}


def _solve_off_family(entry, Q, fams, valid, reachable, chosen, q_ref, model):
    """Status of a target where the run's family is not valid (Q: (8, 6), fams,
    reachable: (8,), valid: (family,))."""
    if valid.any():
        options = [(pick_in_family(Q, fams, f, q_ref, model)[0], int(f))
                   for f in np.flatnonzero(valid)]
        q, f = min(options, key=lambda o: float(joint_travel_s(model, q_ref, o[0])))
        entry.status, entry.joints_deg, entry.family = CONFIG_CHANGE, q, f
        return
    if reachable.any():
        entry.status = JOINT_LIMIT
        rows = np.flatnonzero(reachable)
        if chosen is not None and (fams[rows] == chosen).any():
            rows = rows[fams[rows] == chosen]
        q = unwrap_joints(Q[rows], q_ref, model)
        best = int(np.argmin(model.limit_excess(q).sum(axis=1)))
        entry.attempt_deg = q[best]
        entry.family = int(fams[rows[best]])
        return
    entry.status = UNREACHABLE
