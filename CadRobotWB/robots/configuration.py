"""Robot configurations along a program, and the configuration data of each language.

A 6-axis arm reaches most poses in up to eight ways (the rows of
``model.ik``), and every joint whose range exceeds 360 degrees in total can
also take ``q +- 360``.  This module chooses one joint vector per target of a
:class:`~CadRobotWB.core.program.Program` and states that choice the way
each robot language wants it.

Configuration families
----------------------
A *family* is one of the eight arm configurations, numbered 0..7 by three
bits that are computed **from the joint values** (never from the IK row
index), with the robot's own geometry:

=====  ==================  ==============================================
value  name                set when
=====  ==================  ==============================================
4      shoulder back       the wrist centre is behind axis 1: its x in
                           the frame that turns with axis 1 is < 0
2      elbow down          the wrist centre is behind the lower arm (the
                           line through axes 2 and 3), i.e. the elbow
                           angle ``theta3 + atan2(a2, c3)`` of the OPW
                           model is < 0 (0 = stretched, +-180 = folded)
1      wrist flipped       the model's wrist angle ``theta5`` is < 0
=====  ==================  ==============================================

For an OPW robot (:mod:`.opw`) the eight IK rows are, in that numbering,
row ``r`` -> family ``4 * (r % 4 >= 2) + 2 * (r % 2) + (r >= 4)``
(front/back shoulder, the two elbows, the flipped wrist).  A Universal
Robots arm (:mod:`.ur`, non-spherical wrist) gets the same three bits from
its own singularities: the wrist point (frame 5) behind the plane of
axis 1 and axis 2, ``q3 < 0``, ``q5 < 0``.

Family 0 (front, elbow up, wrist not flipped) is what ABB calls ``cfx = 0``
and KUKA ``S = 'B010'`` (with A5 > 0).  The boundaries between families
are exactly the three singularities (:func:`arm_geometry` measures the
distance to each), so a move that must change family passes through one.

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

Configuration data
------------------
:func:`abb_confdata`, :func:`kuka_status_turn`, :func:`fanuc_config` and
:func:`motoman_rconf` are pure functions of one joint vector (degrees,
model joints) and the robot's geometry; their docstrings name the sources
and what could not be verified.

Pure numpy: never imports FreeCAD.
"""

import math
from dataclasses import dataclass, field
from typing import List, Optional, Tuple

import numpy as np

from ..core import frames as tf
from ..core import program as ir
from ..errors import InputError
from . import models, opw, ur

# --- families ------------------------------------------------------------------------------

SHOULDER_BACK = 4
ELBOW_DOWN = 2
WRIST_FLIPPED = 1

#: Status of a target in a :class:`JointSolution`.
OK = "ok"
CONFIG_CHANGE = "config_change"
JOINT_LIMIT = "joint_limit"
UNREACHABLE = "unreachable"

#: Multiples of 360 degrees tried when shifting a joint into its limits.
_TURNS = np.arange(-2, 3)


def family_name(family):
    """Plain words for a family number, e.g. ``"front, elbow up, wrist not flipped"``.

    Parameters
    ----------
    family : int
        0..7 (see the module docstring); anything else gives ``"none"``.

    Returns
    -------
    str
    """
    if family is None or not 0 <= int(family) <= 7:
        return "none"
    family = int(family)
    return "%s, %s, %s" % ("shoulder back" if family & SHOULDER_BACK else "front",
                           "elbow down" if family & ELBOW_DOWN else "elbow up",
                           "wrist flipped" if family & WRIST_FLIPPED else "wrist not flipped")


def _spec(robot):
    """The RobotSpec of a RobotModel or RobotSpec."""
    return getattr(robot, "spec", robot)


def _wrap(angle_deg):
    return opw.wrap_deg(angle_deg)


def _on_angle_grid(angle_deg):
    """Angles (deg) rounded to the grid of ``opw.ANGLE_TOLERANCE_DEG``, -0 made 0:
    rounding noise then cannot tell two equal values apart (two turns of a joint
    equally far from where it should be tie exactly, and ``argmin`` takes the first)."""
    tol = opw.ANGLE_TOLERANCE_DEG
    return np.round(np.asarray(angle_deg, dtype=float) / tol) * tol + 0.0


@dataclass
class ArmGeometry:
    """Where an arm stands relative to its three singularities (arrays, shape (...)).

    Attributes
    ----------
    shoulder_mm : ndarray
        Signed distance of the wrist centre from axis 1, measured along the
        arm's forward direction (x of the frame turning with axis 1), mm.
        Negative: the wrist centre is behind axis 1 (reaching over the
        shoulder).  0 is the shoulder singularity.
    elbow_deg : ndarray
        Elbow angle in (-180, 180] degrees: 0 with the arm stretched (wrist
        centre on the line of the lower arm, outwards), +-180 folded;
        positive with the wrist centre in front of the lower arm.
    wrist_deg : ndarray
        The model's wrist bend ``theta5`` in (-180, 180] degrees; 0 and 180
        are the wrist singularity (axes 4 and 6 in line).
    """

    shoulder_mm: np.ndarray
    elbow_deg: np.ndarray
    wrist_deg: np.ndarray

    def family(self):
        """ndarray of int, shape (...): 0..7, -1 where the joints are NaN."""
        with np.errstate(invalid="ignore"):
            fam = (SHOULDER_BACK * (self.shoulder_mm < 0)
                   + ELBOW_DOWN * (self.elbow_deg < 0)
                   + WRIST_FLIPPED * (self.wrist_deg < 0)).astype(int)
        nan = np.isnan(self.shoulder_mm) | np.isnan(self.elbow_deg) | np.isnan(self.wrist_deg)
        return np.where(nan, -1, fam)

    def singularity_distances(self):
        """Distances to the three singularities.

        Returns
        -------
        shoulder_mm, elbow_deg, wrist_deg : ndarray, shape (...)
            ``|shoulder_mm|``; the elbow's angle from stretched or folded,
            ``min(|e|, 180 - |e|)``; the wrist's angle from 0 or 180 degrees.
        """
        e, w = np.abs(self.elbow_deg), np.abs(self.wrist_deg)
        return np.abs(self.shoulder_mm), np.minimum(e, 180.0 - e), np.minimum(w, 180.0 - w)


def arm_geometry(q_deg, robot):
    """Shoulder, elbow and wrist measures of joint vectors (see :class:`ArmGeometry`).

    Parameters
    ----------
    q_deg : array_like, shape (..., 6)
        Model joints, degrees (NaN rows allowed).
    robot : RobotModel or RobotSpec
        OPW robots (``spec.opw``) and Universal Robots (``spec.ur``).

    Returns
    -------
    ArmGeometry
        Arrays of shape (...).
    """
    spec = _spec(robot)
    q_deg = np.asarray(q_deg, dtype=float)
    if spec.ur is not None:
        return _ur_geometry(spec.ur, q_deg)
    if spec.opw is None:
        raise ValueError("robot %s has no OPW or UR parameters" % spec.name)
    p = spec.opw
    signs = np.asarray(p.signs, dtype=float)
    q = np.radians(q_deg) * signs - np.radians(np.asarray(p.offsets_deg, dtype=float))
    psi3 = np.arctan2(p.a2, p.c3)
    k = np.hypot(p.a2, p.c3)
    q2, q3, q5 = q[..., 1], q[..., 2], q[..., 4]
    # Same expressions as opw.forward: the wrist centre in the arm's own plane.
    shoulder = p.c2 * np.sin(q2) + k * np.sin(q2 + q3 + psi3) + p.a1
    elbow = _wrap(np.degrees(q3 + psi3))
    wrist = _wrap(np.degrees(q5))
    return ArmGeometry(shoulder, elbow, wrist)


def _ur_geometry(params, q_deg):
    shape = q_deg.shape[:-1]
    q = q_deg.reshape(-1, 6)
    T = ur.forward(params, np.nan_to_num(q))
    p05 = T[:, :3, 3] - params.d6 * T[:, :3, 2]      # wrist point, frame 5 origin
    q1 = np.radians(q[:, 0])
    # x of the wrist point in frame 1: ±sqrt(r² - d4²); 0 is the shoulder singularity.
    shoulder = np.cos(q1) * p05[:, 0] + np.sin(q1) * p05[:, 1]
    shoulder = np.where(np.isnan(q).any(axis=1), np.nan, shoulder)
    return ArmGeometry(shoulder.reshape(shape), _wrap(q[:, 2]).reshape(shape),
                       _wrap(q[:, 4]).reshape(shape))


def family(q_deg, robot):
    """Configuration family of joint vectors (see the module docstring).

    Parameters
    ----------
    q_deg : array_like, shape (..., 6)
        Model joints, degrees.
    robot : RobotModel or RobotSpec

    Returns
    -------
    ndarray of int, shape (...)
        0..7; -1 for NaN rows.
    """
    return arm_geometry(q_deg, robot).family()


# --- joint shifts by 360 degrees -----------------------------------------------------------

def _turned(model, q_deg):
    """The controller joints of `q_deg`, each shifted by every multiple of 360 degrees in
    ``_TURNS``: shape (..., 5, 6)."""
    return model.controller_joints(q_deg)[..., None, :] + 360.0 * _TURNS[:, None]


def unwrap_joints(q_deg, q_ref_deg, robot):
    """Shift each joint by the multiple of 360 degrees that best fits the limits.

    Per joint, the candidates ``q + 360 k`` (k = -2..2) inside the limits
    are considered and the one closest to ``q_ref`` taken; when none is
    inside, the one least outside (closest to the range) is taken.

    The shifts are made on the controller's joints
    (:meth:`~.models.RobotModel.controller_joints`), where the limits
    apply, and the result is converted back: the same for a serial robot;
    on a parallel-arm robot (J3 = q2 + q3) a turn of J3 is a turn of q3,
    and J2 and J3, whose ranges are narrower than 360 degrees, can only
    take one turn within them - in practice J1, J4 and J6 are unwrapped.

    Parameters
    ----------
    q_deg : array_like, shape (..., 6)
        Model joints, degrees.
    q_ref_deg : array_like, shape (..., 6) or (6,)
        Joints to stay close to (e.g. the previous target's).
    robot : RobotModel or RobotSpec
        Its joint limits are used.

    Returns
    -------
    ndarray, shape (..., 6)
        Model joints.
    """
    model = models.as_model(robot)
    cand = _turned(model, q_deg)                                     # (..., 5, 6)
    ref = model.controller_joints(q_ref_deg)[..., None, :]
    excess = model.limit_excess(cand, controller=True)
    cost = np.where(excess > 0.0, 1e9 + excess, _on_angle_grid(np.abs(cand - ref)))
    best = np.argmin(np.nan_to_num(cost, nan=np.inf), axis=-2)       # (..., 6)
    return model.model_joints(np.take_along_axis(cand, best[..., None, :], axis=-2)[..., 0, :])


def fits_limits(q_deg, robot):
    """Whether each joint, shifted by some multiple of 360 degrees, is within its limits.

    Parameters
    ----------
    q_deg : array_like, shape (..., 6)
        Model joints, degrees.
    robot : RobotModel or RobotSpec
        Its joint limits apply to the controller's joints (see
        :func:`unwrap_joints`).

    Returns
    -------
    ndarray of bool, shape (...)
        False for NaN rows.
    """
    model = models.as_model(robot)
    q = model.controller_joints(q_deg)
    tol = opw.ANGLE_TOLERANCE_DEG          # as model.limit_excess forgives
    low, high = model.joint_min_deg - tol, model.joint_max_deg + tol
    # The fewest turns that bring each joint up to its lower limit, then whether that
    # stays under the upper one (the turns tried: _TURNS).
    turns = np.maximum(np.ceil((low - q) / 360.0), _TURNS[0])
    with np.errstate(invalid="ignore"):
        inside = (turns <= _TURNS[-1]) & (q + 360.0 * turns <= high)
    return inside.all(axis=-1)


def travel_time_s(q_from_deg, q_to_deg, speeds_deg_s):
    """Time of a synchronised joint move at full joint speed, no acceleration.

    The distance measure used to tell which solution is "closest":
    ``max_i |q_to_i - q_from_i| / speed_i``.

    Parameters
    ----------
    q_from_deg, q_to_deg : array_like, shape (..., 6)
        In the convention of the speeds (the controller's: see
        :func:`joint_travel_s`).
    speeds_deg_s : array_like, shape (6,)

    Returns
    -------
    ndarray or float, shape (...), seconds.
    """
    d = np.abs(np.asarray(q_to_deg, float) - np.asarray(q_from_deg, float))
    return np.max(d / np.asarray(speeds_deg_s, float), axis=-1)


def joint_travel_s(robot, q_from_deg, q_to_deg):
    """:func:`travel_time_s` between model joints, on the controller's joints and speeds.

    On a parallel-arm robot J3's speed limits the rate of ``q2 + q3``.

    Parameters
    ----------
    robot : RobotModel or RobotSpec
    q_from_deg, q_to_deg : array_like, shape (..., 6)
        Model joints, degrees.

    Returns
    -------
    ndarray or float, shape (...), seconds.
    """
    model = models.as_model(robot)
    return travel_time_s(model.controller_joints(q_from_deg), model.controller_joints(q_to_deg),
                         model.spec.joint_speed_deg_s)


def reference_joints(robot):
    """The middle of each controller joint's range, wrapped into (-180, 180], as model
    joints: the joints a program is assumed to start from when no start is given.

    Returns
    -------
    ndarray, shape (6,), degrees
    """
    model = models.as_model(robot)
    return model.model_joints(_wrap(0.5 * (model.joint_min_deg + model.joint_max_deg)))


def pick_in_family(solutions_deg, families, wanted, q_prev_deg, robot):
    """The solution of one family closest to the previous joints.

    Parameters
    ----------
    solutions_deg : array_like, shape (8, 6)
        IK rows of one pose (NaN rows where missing).
    families : array_like of int, shape (8,)
        :func:`family` of those rows.
    wanted : int
        Family to pick.
    q_prev_deg : array_like, shape (6,)
        Previous joints (unwrapping and tie-break between rows of the same
        family, which only happens at a singularity).
    robot : RobotModel or RobotSpec

    Returns
    -------
    q_deg : ndarray, shape (6,) or None
        Unwrapped towards ``q_prev_deg``; None if no row has that family.
    inside : bool
        Whether it is within the joint limits.
    """
    model = models.as_model(robot)
    rows = np.flatnonzero(np.asarray(families) == wanted)
    if rows.size == 0:
        return None, False
    q = unwrap_joints(np.asarray(solutions_deg, float)[rows], q_prev_deg, model)
    inside = model.within_limits(q)
    cost = joint_travel_s(model, q_prev_deg, q) + np.where(inside, 0.0, 1e9)
    best = int(np.argmin(cost))
    return q[best], bool(inside[best])


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
                T_r_b.append(frame.T_r_b)
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


def solve_program(program, model, q_start_deg=None, assign=True):
    """Choose the joints of every target: one configuration per run, J4/J6 unwrapped.

    See the module docstring for the rules.

    Parameters
    ----------
    program : Program
    model : RobotModel
        ``robots.models.model(program.robot)``.
    q_start_deg : array_like, shape (6,), optional
        Joints the robot starts from, degrees.  Without it the first run's
        ties are broken towards the middle of the joint ranges.
    assign : bool
        Write each target's joints into ``Target.joints_deg`` (None where
        there is no solution within the limits).  Default True.

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

    Q = model.ik(np.array([e.T_r_f for e in entries]))              # (N, 8, 6)
    fams = family(Q, spec)                                           # (N, 8)
    row_valid = fits_limits(Q, model)                                # (N, 8)
    valid = np.zeros((len(entries), 8), dtype=bool)                  # (N, family)
    for f in range(8):
        valid[:, f] = (row_valid & (fams == f)).any(axis=1)
    reachable = ~np.isnan(Q).any(axis=2)                             # (N, 8)

    runs = _runs(entries)
    q_prev = q_start
    for run_index, indices in enumerate(runs):
        continues = entries[indices[0]].move.kind != ir.JOINT and q_prev is not None
        q_ref = q_prev if q_prev is not None else reference
        if continues:
            chosen = int(family(q_prev, spec))        # a linear move cannot change family
        else:
            chosen = _choose_family(indices, Q, fams, valid, q_ref, model)
        solution.run_families.append(chosen)
        track = _run_track(indices, Q, fams, valid, chosen, q_ref, continues, model)
        for i in indices:
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


def continue_joints(q_prev_deg, q_deg):
    """``q`` shifted joint by joint by multiples of 360 degrees to be within 180 degrees of
    ``q_prev`` (the value a continuous motion reaches), shape (..., 6)."""
    q_prev = np.asarray(q_prev_deg, dtype=float)
    return q_prev + _wrap(np.asarray(q_deg, dtype=float) - q_prev)


def continue_sequence(q_prev_deg, q_deg):
    """Joints along a sequence, each joint continued from the one before (the first
    from ``q_prev``): :func:`continue_joints` applied in turn, as one cumulative sum.

    Parameters
    ----------
    q_prev_deg : array_like, shape (6,)
    q_deg : array_like, shape (M, 6)

    Returns
    -------
    ndarray, shape (M, 6)
    """
    q = np.asarray(q_deg, dtype=float)
    previous = np.empty_like(q)
    previous[0] = q_prev_deg
    previous[1:] = q[:-1]
    return previous[0] + np.cumsum(continue_joints(previous, q) - previous, axis=0)


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


# --- configuration data of each language ----------------------------------------------------

def _joints(q_deg):
    """The 6 joints (deg) the configuration data is read from, on the 1e-9 deg grid
    (:func:`_on_angle_grid`) so rounding noise never moves a joint across a boundary
    (J4 = -1e-14 must not be quadrant -1 one time and 0 the next)."""
    q = np.asarray(q_deg, dtype=float).reshape(-1)
    if q.shape != (6,) or not np.all(np.isfinite(q)):
        raise ValueError("need 6 finite joint values in degrees, got %r" % (q_deg,))
    return _on_angle_grid(q)


def _opw_spec(robot, language):
    spec = _spec(robot)
    if spec.opw is None:
        raise ValueError("%s configuration data needs an OPW robot; %s has none"
                         % (language, spec.name))
    return spec


def _axis5_from_straight(q, spec):
    """Axis 5 (deg, the controller's direction) measured from the straight wrist.

    The configuration data of ABB, KUKA and Fanuc read the sign of axis 5,
    which on their arms is 0 with the wrist straight (axes 4 and 6 in line,
    the wrist singularity).  On an arm whose axis 5 has another zero (the
    HP6's B is 0 with the flange pointing down and +90 with the wrist
    straight) the sign is read from the straight wrist, so the bit still
    tells the two wrist solutions apart: ``q5 - q5_straight``, where
    ``q5_straight = offset5 * sign5`` is the controller value at which the
    OPW model's theta5 is 0.  The same as ``q5`` on every arm whose offset5
    is 0.
    """
    p = spec.opw
    return _wrap(q[4] - p.offsets_deg[4] * p.signs[4])


def quadrant(angle_deg):
    """ABB quadrant number of an axis angle: ``floor(angle / 90)``.

    0 for [0, 90), 1 for [90, 180), ..., -1 for [-90, 0), -2 for [-180, -90), ...

    Parameters
    ----------
    angle_deg : float

    Returns
    -------
    int
    """
    return int(math.floor(float(angle_deg) / 90.0))


def abb_confdata(q_deg, robot):
    """ABB RAPID ``confdata`` ``[cf1, cf4, cf6, cfx]`` of a joint vector.

    Definition (ABB, "Technical reference manual - RAPID Instructions,
    Functions and Data types", data type *confdata*, section for serial
    robots with a spherical wrist: IRB 140, 1400, 1600, 2400, 2600, 4400,
    4600, 6400, 6600, 6700, 7600 ...), as reproduced in the
    CEAD-group/py-opw-kinematics documentation (AXIS_CONFIGURATION.md) and
    ABB RobotStudio API ("ConfigurationData: Cf1 the quadrant of axis 1"):

    * ``cf1``, ``cf4``, ``cf6``: quadrant of axes 1, 4 and 6,
      ``floor(angle / 90 deg)`` (0 for 0..90, -1 for -90..0, ...);
    * ``cfx`` 0..7, one of the eight arm configurations::

          cfx  wrist centre vs axis 1   wrist centre vs lower arm   axis 5
          0    in front of              in front of                 positive
          1    in front of              in front of                 negative
          2    in front of              behind                      positive
          3    in front of              behind                      negative
          4    behind                   in front of                 positive
          5    behind                   in front of                 negative
          6    behind                   behind                      positive
          7    behind                   behind                      negative

      so ``cfx = 4 * behind_axis1 + 2 * behind_lower_arm + (axis5 < 0)``.
      "Lower arm" is the line through axes 2 and 3; on the parallel-arm
      IRB 2400 that is the link driven by axis 2 whatever the convention
      of axis 3, and it is measured here geometrically (OPW model), so the
      controller's axis-3 convention does not enter.  Axis 5 exactly 0
      counts as positive; axis 5 is measured from the straight wrist
      (:func:`_axis5_from_straight`: itself on ABB's arms).

    Parameters
    ----------
    q_deg : array_like, shape (6,)
        Model joints, degrees (axes 1, 4, 5 and 6 are the controller's on
        every robot).
    robot : RobotModel or RobotSpec
        An OPW robot (``spec.opw``).

    Returns
    -------
    tuple of 4 int
        ``(cf1, cf4, cf6, cfx)``.
    """
    q = _joints(q_deg)
    spec = _opw_spec(robot, "ABB")
    g = arm_geometry(q, spec)
    a5 = _axis5_from_straight(q, spec)
    cfx = 4 * int(g.shoulder_mm < 0) + 2 * int(g.elbow_deg < 0) + int(a5 < 0)
    return quadrant(q[0]), quadrant(q[3]), quadrant(q[5]), cfx


def kuka_status_turn(q_deg, robot):
    """KUKA KRL Status and Turn (``S``, ``T`` of a POS/E6POS) of a joint vector.

    Definition (KUKA System Software 8.x, "Operating and Programming
    Instructions for System Integrators", section Status and Turn; the bit-0
    text is quoted in robot-forum.com thread 7173, "x-value of wrist root
    point"):

    * Status bit 0: 1 when the wrist root point (intersection of A4, A5, A6)
      is in the *overhead area*, i.e. its x in the A1 coordinate system
      (``$ROBROOT`` turned with A1) is negative; 0 in the basic area.
    * Status bit 1: 1 when A3 is at or beyond the angle where the arm is
      stretched (``A3 >= phi``; phi = 0 when A3 and A4 intersect, otherwise
      set by the offset), i.e. the wrist root point is in front of the lower
      arm; 0 behind it.  Measured here geometrically with the OPW model.
    * Status bit 2: 1 when A5 <= 0, 0 when A5 > 0 (A5 from the straight
      wrist, :func:`_axis5_from_straight`: A5 itself on KUKA's arms).
    * Turn bit i (i = 0..5): 1 when axis A(i+1) < 0, 0 when >= 0.

    Checked against typical taught data: ``S 2, T 2`` (basic area, elbow
    up, A5 > 0, only A2 < 0) and ``S 6, T 18`` (A5 < 0).  Not verified on a
    controller; a forum thread (robot-forum.com 45777) reports bit 2 can
    disagree with the sign of A5 on robots with an A3/A4 offset.

    Parameters
    ----------
    q_deg : array_like, shape (6,)
        Model joints A1..A6, degrees (the turn bits use the controller's values).
    robot : RobotModel or RobotSpec
        An OPW robot.

    Returns
    -------
    (int, int)
        ``(S, T)``: S in 0..7, T in 0..63.
    """
    q = _joints(q_deg)
    spec = _opw_spec(robot, "KUKA")
    g = arm_geometry(q, spec)
    a5 = _axis5_from_straight(q, spec)
    status = int(g.shoulder_mm < 0) + 2 * int(g.elbow_deg >= 0) + 4 * int(a5 <= 0)
    q_ctrl = models.as_model(robot).controller_joints(q)
    turn = sum(1 << i for i in range(6) if q_ctrl[i] < 0)
    return status, turn


def _turn_number(angle_deg):
    """Fanuc turn number: 0 for (-180, 180], 1 for (180, 540], -1 for (-540, -180], ..."""
    return int(math.ceil((float(angle_deg) - 180.0) / 360.0))


def fanuc_config(q_deg, robot):
    """Fanuc LS position configuration string, e.g. ``'N U T, 0, 0, 0'``.

    Fields: wrist ``F`` (flip) / ``N`` (no flip), arm ``U`` (up) / ``D``
    (down), ``T`` (front) / ``B`` (back), then the turn numbers of J1, J4
    and J6 (0 for -180 < angle <= 180, 1 for 180 < angle <= 540, -1 for
    -540 < angle <= -180).

    ``U``/``D`` and ``T``/``B`` are the elbow and shoulder of
    :func:`arm_geometry` (``U``: wrist centre in front of the lower arm;
    ``T``: wrist centre in front of axis 1).  ``F``/``N``: ``F`` when J5 > 0
    (J5 from the straight wrist, :func:`_axis5_from_straight`).
    NOT verified against a Fanuc manual (none was at hand): the choice rests
    on the Fanuc joint convention of ROS-Industrial's Fanuc descriptions
    (J5 turns about -Y, so the usual tool-down pose has J5 = -90 and is
    ``N U T``, as most Fanuc programs show).  No catalog robot uses it yet.

    Parameters
    ----------
    q_deg : array_like, shape (6,)
        Model joints J1..J6, degrees (J1, J4, J5 and J6 are read as they are;
        J2 and J3 only through the arm's geometry, :func:`arm_geometry`).
    robot : RobotModel or RobotSpec
        An OPW robot.

    Returns
    -------
    str
    """
    q = _joints(q_deg)
    spec = _opw_spec(robot, "Fanuc")
    g = arm_geometry(q, spec)
    flip = "F" if _axis5_from_straight(q, spec) > 0 else "N"
    up = "D" if g.elbow_deg < 0 else "U"
    front = "B" if g.shoulder_mm < 0 else "T"
    return "%s %s %s, %d, %d, %d" % (flip, up, front, _turn_number(q[0]),
                                     _turn_number(q[3]), _turn_number(q[5]))


def motoman_rconf(q_deg, robot):
    """Yaskawa Motoman ``///RCONF l,m,n,o,p,q`` fields of a joint vector.

    From the NX100 manual "Interface with an easy offline teaching system"
    (HW0481924, 4.1 Job Data Format, RCONF; the DX100 edition adds 18
    unused fields ``r1..r18``)::

        l  0: Flip,       1: No-flip
        m  0: Upper arm,  1: Lower arm
        n  0: Front,      1: Rear
        o  0: R < 180,    1: R >= 180
        p  0: T < 180,    1: T >= 180
        q  0: S < 180,    1: S >= 180

    and the NX100 operator's manual (RE-CSO-A031, 3.9 "Manipulator Types"):
    Flip/No flip is the *R-axis position*: Flip for -90 < R <= 90 (and
    270 < R <= 360, -360 < R <= -270), No flip for 90 < R <= 270 and
    -270 < R <= -90; "Front/Back" relates the S axis and the TCP;
    "Upper arm/Lower arm" is the configuration of the L and U axes.

    Here: ``l`` from R as above; ``m`` = 1 when the wrist centre is behind
    the lower arm (:func:`arm_geometry` elbow < 0); ``n`` = 1 when the wrist
    centre (not the TCP: the wrist centre is what separates the IK
    solutions) is behind the S axis; ``o``, ``p``, ``q`` = 1 when
    ``|angle| >= 180`` (the only reading that tells R = 300 from R = -60).
    Not verified: the manuals' figures (which side is "Flip", the exact
    front/back and upper/lower criteria) were not available; only the
    texts were.

    Parameters
    ----------
    q_deg : array_like, shape (6,)
        Model joints S, L, U, R, B, T in degrees (S, R and T are the controller's).
    robot : RobotModel or RobotSpec
        An OPW robot.

    Returns
    -------
    tuple of 6 int
        ``(l, m, n, o, p, q)``; a DX100/DX200 post appends its unused zeros.
    """
    q = _joints(q_deg)
    g = arm_geometry(q, _opw_spec(robot, "Motoman"))
    r = float(q[3])
    r_near_zero = -90.0 < _wrap(r) <= 90.0     # same test for R and R +- 360
    flip = 0 if r_near_zero else 1
    return (flip, int(g.elbow_deg < 0), int(g.shoulder_mm < 0),
            int(abs(q[3]) >= 180.0), int(abs(q[5]) >= 180.0), int(abs(q[0]) >= 180.0))
