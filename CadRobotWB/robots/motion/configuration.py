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
   previous run, or the middle of the joint ranges for the very first run)
   among the tied families that do not wind a joint out of its range: a
   family valid at every target alone can still do so once its joints are
   continued (steps 4 and 5), at the targets or between them, where the
   wrist may turn more than 180 degrees in one move.  This is judged on the
   run's moves sampled as :mod:`.move_sampling` samples them (default
   :class:`~.move_sampling.Margins`; :class:`RunSamples`), only when two
   families or more tie; when every tied family winds, the quickest is taken.
   A run that does not start with a joint move keeps the family the robot
   is already in;
4. target by target, the family's solution continued from the previous
   target, every joint within 180 degrees of its previous value (a linear
   move cannot unwind a joint by 360 degrees), so J4/J6 (and J1 of a KUKA,
   any joint whose range exceeds 360 degrees in total) run on past +-180;
   when step 3 sampled the run and the family stays within its range there,
   each target is continued from its sample instead, so the targets' joints
   are those the moves reach;
5. one shift by a multiple of 360 degrees per joint for the whole run
   (only after a joint move, which can unwind): the shift that keeps every
   target (every sample, when sampled) within the limits, nearest the
   previous joints.  When no shift fits, the targets where the continued
   joint is out of its range get status ``"joint_limit"`` (the path winds
   the wrist up).

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
        samples = None if continues else RunSamples(program, entries, indices, model, q_ref,
                                                    (Q, fams))
        if continues:
            chosen = int(family(q_prev, model))       # a linear move cannot change family
        else:
            chosen = _choose_family(indices, Q, fams, valid, q_ref, model, samples.winds)
        solution.run_families.append(chosen)
        track = _run_track(indices, Q, fams, valid, chosen, q_ref, continues, model,
                           samples if samples is not None and samples.solved else None)
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


def _choose_family(indices, Q, fams, valid, q_ref, model, winds=None):
    """The family valid at most targets of a run; ties: the quickest from q_ref among those
    that do not wind a joint out of its range (``winds(f)`` False), else the quickest."""
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
    order = sorted(range(len(families)),
                   key=lambda k: (not quick[k], 0.0 if quick[k] else travel_s[k], families[k]))
    if winds is not None and len(order) > 1:
        unwound = next((k for k in order if not winds(int(families[k]))), order[0])
        return int(families[unwound])
    return int(families[order[0]])


class RunSamples:
    """A run's Cartesian moves sampled as :func:`.move_sampling.sample_moves` samples them
    (default :class:`~.move_sampling.Margins`), solved at the first question asked.

    Parameters
    ----------
    program : Program
    entries : list of TargetSolution
        All of the program's (:func:`target_entries`).
    indices : list of int
        The run's entries.
    model : RobotModel
    q_ref_deg : ndarray, shape (6,)
        The joints before the run.
    solved : (ndarray, ndarray)
        The IK rows (N, rows, 6) and their families (N, rows) of every entry: a sample
        at a target's pose (a move's end, most samples of short moves) takes them.
    """

    def __init__(self, program, entries, indices, model, q_ref_deg, solved):
        self.program, self.entries, self.indices = program, entries, indices
        self.model, self.q_ref = model, q_ref_deg
        self._entry_Q, self._entry_fams = solved
        self.solved = False
        self._tracks = {}

    def _solve(self):
        """IK of every sample, and each target's sample (its move's end; a via's nearest)."""
        from . import move_sampling            # it imports this module
        groups = []                            # the run's entry indices by move
        for i in self.indices:
            if groups and self.entries[groups[-1][-1]].move_index == self.entries[i].move_index:
                groups[-1].append(i)
            else:
                groups.append([i])
        cartesian = [k for k in range(1, len(groups))
                     if self.entries[groups[k][-1]].move.kind in (ir.LINEAR, ir.CIRCULAR)]
        self.Q, self.fams, self.at = None, None, {}
        if cartesian:
            moves = [(self.entries[groups[k - 1][-1]], [self.entries[i] for i in groups[k]])
                     for k in cartesian]
            poses = move_sampling.move_poses(self.program, moves, move_sampling.Margins())
            T_r_f, starts, ends = _without_repeats(poses.T_r_f, poses.offsets)
            self.Q, self.fams = self._solve_poses(
                T_r_f, np.concatenate([starts, ends]),
                np.array([groups[k - 1][-1] for k in cartesian] + [groups[k][-1] for k in cartesian]))
            self.at[groups[cartesian[0] - 1][-1]] = int(starts[0])
            for j, k in enumerate(cartesian):
                self.at[groups[k][-1]] = int(ends[j])
                if len(groups[k]) > 1:         # a circular move's via: its nearest sample
                    via = self.entries[groups[k][0]].T_r_f[:3, 3]
                    gap = np.linalg.norm(T_r_f[starts[j]:ends[j] + 1, :3, 3] - via, axis=1)
                    self.at[groups[k][0]] = int(starts[j] + np.argmin(gap))
        self.solved = True

    def _solve_poses(self, T_r_f, sample, entry):
        """IK rows (S, rows, 6) and families (S, rows) of the samples' flange poses (S, 4, 4):
        at the moves' ends (samples `sample` at targets `entry`, (2K,)) the target's rows
        where the sample is at its pose (not on a woven path), the rest solved here."""
        T_target = np.array([self.entries[i].T_r_f for i in entry]).reshape(-1, 4, 4)
        same = np.abs(T_r_f[sample] - T_target).max(axis=(1, 2)) <= 1e-9
        Q = np.full((len(T_r_f),) + self._entry_Q.shape[1:], np.nan)
        fams = np.full((len(T_r_f), self._entry_Q.shape[1]), -1)
        Q[sample[same]], fams[sample[same]] = self._entry_Q[entry[same]], \
            self._entry_fams[entry[same]]
        rest = np.ones(len(T_r_f), dtype=bool)
        rest[sample[same]] = False
        if rest.any():
            Q[rest] = self.model.ik(T_r_f[rest])
            fams[rest] = family(Q[rest], self.model)
        return Q, fams

    def track(self, wanted):
        """The family's joints at every sample, each joint continued from the sample before
        (the first from ``q_ref``), shape (S, 6), NaN where the family has no solution;
        None when the run has no Cartesian move or the family no solution on it."""
        if not self.solved:
            self._solve()
        if wanted not in self._tracks:
            track = None
            if self.Q is not None:
                has = (self.fams == wanted).any(axis=1)
                if has.any():
                    track = np.full((len(self.Q), 6), np.nan)
                    track[has] = _continued(self.Q[has], self.fams[has], wanted, self.q_ref,
                                            self.model)
            self._tracks[wanted] = track
        return self._tracks[wanted]

    def winds(self, wanted):
        """Whether the family, continued through every sample and shifted by one multiple
        of 360 degrees per joint, leaves a joint's range somewhere (False without samples)."""
        track = self.track(wanted)
        if track is None:
            return False
        track = track[~np.isnan(track).any(axis=1)]
        inside = self.model.limit_excess(_turned(self.model, track), controller=True) == 0.0
        return not inside.all(axis=0).any(axis=0).all()


def _without_repeats(T_r_f, offsets):
    """The samples (S, 4, 4) of consecutive moves (move j: ``offsets[j]`` to
    ``offsets[j + 1] - 1``) without each move's first where it is the move before's last.

    Returns
    -------
    T_r_f : ndarray, shape (S', 4, 4)
    starts, ends : ndarray of int, shape (K,)
        Each move's first and last sample among them.
    """
    starts, ends = offsets[:-1], offsets[1:] - 1
    keep = np.ones(len(T_r_f), dtype=bool)
    keep[starts[1:]] = np.abs(T_r_f[starts[1:]] - T_r_f[ends[:-1]]).max(axis=(1, 2)) > 1e-9
    index = np.cumsum(keep) - 1            # a repeat's: the sample it repeats
    return T_r_f[keep], index[starts], index[ends]


def _continued(Q, fams, wanted, q_ref, model):
    """The family's solution at each pose, each joint continued from the pose before
    (the first from ``q_ref``): Q (M, rows, 6), fams (M, rows), the family at each pose;
    returns (M, 6)."""
    match = fams == wanted                                         # (M, rows)
    if (match.sum(axis=1) == 1).all():
        return continue_sequence(q_ref, Q[np.arange(len(Q)), np.argmax(match, axis=1)])
    track, prev = [], q_ref    # two rows of the family somewhere (a singularity)
    for rows, here in zip(Q, match):
        candidates = continue_joints(prev, rows[here])
        prev = candidates[int(np.argmin(joint_travel_s(model, prev, candidates)))]
        track.append(prev)
    return np.array(track)


def _run_track(indices, Q, fams, valid, chosen, q_ref, continues, model, samples=None):
    """Joints of a run's targets in its family, as one continuous motion.

    The family's solution at each target where it is valid, each joint
    continued from the previous target (:func:`continue_joints`), or, with
    `samples` (:class:`RunSamples`, solved), from the target's sample of the
    moves, which are continued sample to sample; then one shift by a multiple
    of 360 degrees per joint for the whole run (none when the run continues
    from ``q_ref`` without a joint move): the shift that keeps every target
    (every sample) within the limits, nearest ``q_ref``; failing that, the one
    that keeps most of them within.  Shifts and limits are on the controller's
    joints (see :func:`unwrap_joints`).

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
    base = _sampled_at(samples, chosen, order)
    if base is None:
        track = judged = _continued(Q[order], fams[order], chosen, q_ref, model)   # (M, 6)
    else:
        track = _continue_from(base, Q[order], fams[order] == chosen, model)
        judged = samples.track(chosen)
        judged = judged[~np.isnan(judged).any(axis=1)]
    if not continues:
        cand = _turned(model, judged)                              # (M, 5, 6)
        inside = (model.limit_excess(cand, controller=True) == 0.0).sum(axis=0)      # (5, 6)
        near = _on_angle_grid(np.abs(cand[0] - model.controller_joints(q_ref)))          # (5, 6)
        # Per joint: the turn with most targets inside; among those, the first target nearest.
        best = np.argmin(np.where(inside == inside.max(axis=0), near, np.inf), axis=0)
        track = model.model_joints(_turned(model, track)[:, best, np.arange(6)])
    inside = model.within_limits(track)
    return {int(i): (track[m], bool(inside[m])) for m, i in enumerate(order)}


def _sampled_at(samples, wanted, order):
    """The family's continued joints at the samples of targets `order` (M, 6); None when
    there are no samples, the family winds a joint out of its range on them (the targets
    are then continued target to target, and the checks find the move that winds it), or
    one of those targets has none of the family."""
    track = None if samples is None else samples.track(wanted)
    if track is None or samples.winds(wanted):
        return None
    at = [samples.at.get(int(i)) for i in order]
    if None in at or np.isnan(track[at]).any():
        return None
    return track[at]


def _continue_from(base, Q, match, model):
    """Per target, the family's solution (rows `match` (M, rows) of Q (M, rows, 6)) with
    each joint continued from ``base`` (M, 6); the quickest to reach where the family has
    two.  Returns (M, 6)."""
    candidates = continue_joints(base[:, None, :], Q)                   # (M, rows, 6)
    with np.errstate(invalid="ignore"):
        cost = np.where(match, joint_travel_s(model, base[:, None, :], candidates), np.inf)
    return candidates[np.arange(len(Q)), np.argmin(cost, axis=1)]


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
