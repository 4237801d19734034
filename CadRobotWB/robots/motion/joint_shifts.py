"""Joint values shifted by multiples of 360 degrees: into the limits, continued along a
motion, and the time a joint move between two joint vectors takes.

Joints here are the model's (:mod:`.models`: what ``fk`` takes); the limits and
speeds are the controller's, which differ on a parallel-arm robot
(``spec.j23_coupled``: the controller's J3 is ``q2 + q3``), so shifts are made on
the controller's joints and "quickest" is timed on them.

Pure numpy: never imports FreeCAD.
"""

import numpy as np

from ..kinematics import models, opw
from ..kinematics.arm_families import _on_angle_grid, _wrap

#: Multiples of 360 degrees tried when shifting a joint into its limits.
_TURNS = np.arange(-2, 3)


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


def limit_margin_deg(model, q_deg):
    """How far inside its limits each joint vector is, at its best shift by 360 degrees.

    Parameters
    ----------
    model : RobotModel
    q_deg : array_like, shape (..., 6)
        Model joints, degrees (NaN rows allowed).

    Returns
    -------
    ndarray, shape (...)
        The smallest over the six controller joints of the distance to the
        nearer limit, degrees, each joint shifted by the multiple of 360
        degrees that puts it nearest the middle of its range; negative when
        a joint is outside its limits at every shift; NaN for NaN rows.
    """
    q = model.controller_joints(q_deg)
    centre = 0.5 * (model.joint_min_deg + model.joint_max_deg)
    half = 0.5 * (model.joint_max_deg - model.joint_min_deg)
    off = np.abs(q - centre)
    off = np.abs(off - 360.0 * np.round(off / 360.0))
    return np.min(half - off, axis=-1)


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
    solutions_deg : array_like, shape (M, 6)
        IK rows of one pose (NaN rows where missing; M = 8, or 16 on an offset wrist).
    families : array_like of int, shape (M,)
        :func:`family` of those rows.
    wanted : int
        Family to pick.
    q_prev_deg : array_like, shape (6,)
        Previous joints (unwrapping and tie-break between rows of the same
        family: at a singularity, or, on an offset wrist, the two to four
        solutions its family can hold away from any).
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

def continue_joints(q_prev_deg, q_deg):
    """``q`` shifted joint by joint by multiples of 360 degrees to be within 180 degrees of
    ``q_prev`` (the value a continuous motion reaches), shape (..., 6)."""
    q_prev = np.asarray(q_prev_deg, dtype=float)
    return q_prev + _wrap(np.asarray(q_deg, dtype=float) - q_prev)


def continue_sequence(q_prev_deg, q_deg, starts=None):
    """Joints along sequences, each joint continued from the one before (the first of a
    sequence from its ``q_prev``): :func:`continue_joints` applied in turn, as one
    cumulative sum.

    Parameters
    ----------
    q_prev_deg : array_like, shape (6,) or (K, 6)
        The joints before each sequence.
    q_deg : array_like, shape (M, 6)
        The sequences one after the other.
    starts : ndarray of bool, shape (M,), optional
        True where a sequence starts (K of them); default: one sequence.

    Returns
    -------
    ndarray, shape (M, 6)
    """
    q = np.asarray(q_deg, dtype=float)
    if starts is None:
        starts = np.zeros(len(q), dtype=bool)
        starts[:1] = True
    previous = np.empty_like(q)
    previous[1:] = q[:-1]
    previous[starts] = np.reshape(q_prev_deg, (-1, 6))
    step = continue_joints(previous, q) - previous
    total = np.cumsum(step, axis=0)
    sequence = np.cumsum(starts) - 1
    before = (total - step)[starts]                  # the sum before each sequence
    return previous[starts][sequence] + (total - before[sequence])
