"""How well the arm takes each target at given external-axis values, and the
track travel keeping the targets at a good reach.

Arm score of a target at values v: the best, over the IK branches within the
joint limits (each joint shifted by 360 degrees where its range allows), of

``min(1, limit margin / MARGIN_FULL_DEG) + sin(elbow) sin(wrist) min(1, shoulder / (reach / 2))``

(limit margin: the smallest distance of a joint to its nearer limit; elbow and
wrist: their angles from the stretched / folded and the straight wrist
singularities; shoulder: the wrist centre's distance from axis 1); -1 where no
branch is within the limits (out of reach, or a joint limit). Every pose is
solved in one ``model.ik`` call.

Pure numpy: never imports FreeCAD.
"""

import numpy as np

from ...core import frames as tf
from ..catalog import catalog
from ..kinematics.arm_families import arm_geometry
from ..motion.joint_shifts import fits_limits, limit_margin_deg
from ..motion.move_sampling import Margins

#: A joint this far (deg) or farther inside its limits counts as fully free.
MARGIN_FULL_DEG = 30.0
#: Score of a target no branch reaches within the joint limits.
NOT_REACHED = -1.0
#: The band of horizontal distance (TCP from the robot's axis 1), as fractions of
#: the robot's reach, that a track keeps each target in; the middle of the
#: wrist-centre annulus for a torch of a few hundred mm (a rule, not a maker's figure).
GOOD_REACH = (0.35, 0.75)


def arm_scores(model, T_r_f):
    """Arm score (module docstring) of flange poses.

    Parameters
    ----------
    model : RobotModel
    T_r_f : ndarray, shape (M, 4, 4)
        Flange poses in the robot base, mm.

    Returns
    -------
    ndarray, shape (M,)
        In [0, 2], or :data:`NOT_REACHED`.
    """
    if len(T_r_f) == 0:
        return np.zeros(0)
    Q = model.ik(T_r_f)                                        # (M, 8, 6)
    return _branch_scores(model, Q, fits_limits(Q, model), limit_margin_deg(model, Q)).max(axis=1)


def _branch_scores(model, Q, inside, margin_deg, clear_of=None):
    """(M, 8) score of each IK branch `Q` (M, 8, 6) deg, within the limits where `inside`
    (M, 8), `margin_deg` (M, 8) inside them; :data:`NOT_REACHED` outside, and where
    given, closer to a singularity than `clear_of` (shoulder mm, elbow deg, wrist deg)."""
    with np.errstate(invalid="ignore"):
        margin = np.minimum(1.0, margin_deg / MARGIN_FULL_DEG)
        shoulder, elbow, wrist = arm_geometry(Q, model).singularity_distances()
        if clear_of is not None:
            inside = inside & (shoulder >= clear_of[0]) & (elbow >= clear_of[1]) & (
                wrist >= clear_of[2])
        reach = catalog.reach_mm(model.spec) or 1000.0
        manip = (np.sin(np.radians(elbow)) * np.sin(np.radians(wrist))
                 * np.minimum(1.0, shoulder / (0.5 * reach)))
    return np.where(inside, np.nan_to_num(margin + manip, nan=0.0), NOT_REACHED)


def run_scores(model, T_r_f):
    """Arm scores of runs of flange poses, each run held in one IK branch with every joint
    continued along it (no flip, no 360 jump: as the configuration solver moves the arm).

    Along a run each branch's joints are continued pose to pose, each joint's sequence
    shifted as a whole by the multiple of 360 degrees least outside its limits; a pose
    is reached where every joint is then within its limits and the arm is as far from
    each singularity as Check asks (:class:`..motion.move_sampling.Margins`: there
    Check reports the pose, which the module's score alone ranks above a pose near a
    limit). Each run is scored on its
    best branch: fewest poses missed, then the best worst pose (a run is as good as its
    worst point), then the best sum.

    Parameters
    ----------
    model : RobotModel
    T_r_f : ndarray, shape (C, P, 4, 4)
        C runs of P flange poses in the robot base, mm.

    Returns
    -------
    missed : ndarray of int, shape (C,)
        Poses outside the limits, out of reach or near a singularity on the best branch.
    worst, total : ndarray, shape (C,)
        The lowest and the summed score (module docstring) of its poses reached; 0 and
        0 where none is.
    """
    c, p = T_r_f.shape[:2]
    Q = model.ik(T_r_f.reshape(-1, 4, 4)).reshape(c, p, 8, 6)
    q = _continued(model.controller_joints(Q), model.joint_min_deg, model.joint_max_deg)
    with np.errstate(invalid="ignore"):
        margin = np.minimum(q - model.joint_min_deg, model.joint_max_deg - q).min(axis=-1)
    inside = margin >= -1e-6                                   # NaN (out of reach): False
    checked = Margins()
    score = _branch_scores(model, Q.reshape(c * p, 8, 6), inside.reshape(c * p, 8),
                           margin.reshape(c * p, 8),
                           (checked.shoulder_mm, checked.elbow_deg, checked.wrist_deg)
                           ).reshape(c, p, 8)
    reached = score > NOT_REACHED
    missed = (~reached).sum(axis=1)                                    # (C, 8)
    worst = np.where(reached, score, np.inf).min(axis=1)
    worst = np.where(np.isfinite(worst), worst, 0.0)
    total = np.where(reached, score, 0.0).sum(axis=1)
    best = np.array([np.lexsort((-total[k], -worst[k], missed[k]))[0] for k in range(c)],
                    dtype=int)
    rows = np.arange(c)
    return missed[rows, best], worst[rows, best], total[rows, best]


def _continued(q, lower, upper):
    """Joints `q` (C, P, 8, 6) deg continued along P (steps wrapped into +-180; a pose out
    of reach (NaN) bridged by the one before it), each sequence then shifted by the
    multiple of 360 that leaves its span least outside [lower, upper] (6,)."""
    last_known = np.where(np.isnan(q), 0, np.arange(q.shape[1])[None, :, None, None])
    filled = np.nan_to_num(np.take_along_axis(q, np.maximum.accumulate(last_known, axis=1),
                                              axis=1), nan=0.0)
    step = (np.diff(filled, axis=1) + 180.0) % 360.0 - 180.0
    cont = np.concatenate([filled[:, :1], filled[:, :1] + np.cumsum(step, axis=1)], axis=1)
    shifts = 360.0 * np.arange(-2, 3)[:, None, None, None]                  # (5, 1, 1, 1)
    low, high = cont.min(axis=1)[None] + shifts, cont.max(axis=1)[None] + shifts
    excess = np.maximum(lower - low, 0.0) + np.maximum(high - upper, 0.0)  # (5, C, 8, 6)
    cont = cont + shifts[np.argmin(excess, axis=0), 0, 0, 0][:, None]
    return np.where(np.isnan(q), np.nan, cont)


def flange_poses(external, frames, T_b_t, T_f_t, values):
    """Flange poses in the robot base at the given external values.

    Parameters
    ----------
    external : core.mechanisms.ExternalAxes
    frames : list of WorkFrame, length M
    T_b_t : ndarray, shape (M, 4, 4)
    T_f_t : ndarray, shape (4, 4)
    values : ndarray, shape (M, K)

    Returns
    -------
    ndarray, shape (M, 4, 4)
    """
    out = np.empty((len(frames), 4, 4))
    T_t_f = tf.invert_transform(np.asarray(T_f_t, dtype=float))
    names = np.array([f.name for f in frames])
    for name in set(names):
        rows = np.flatnonzero(names == name)
        frame = frames[rows[0]]
        out[rows] = external.T_r_b(frame, values[rows]) @ T_b_t[rows] @ T_t_f
    return out


def reach_band(model):
    """(low, high) horizontal TCP distance from axis 1 a track keeps, mm."""
    reach = catalog.reach_mm(model.spec) or 1000.0
    return GOOD_REACH[0] * reach, GOOD_REACH[1] * reach


def travel_intervals(points_u, base_u, along_u, band, side):
    """Per point, the travel interval keeping it within the reach band on one side.

    The robot base moves along the line ``base_u + s along_u`` (mm per mm of
    travel); the horizontal distance from it to a point is
    ``|d - s a|`` with d, a the horizontal parts of ``point - base_u`` and
    ``along_u``, smallest at ``s* = d.a / |a|^2``.

    Parameters
    ----------
    points_u : ndarray, shape (N, 3)
        TCP positions in {U}, mm.
    base_u, along_u : ndarray, shape (3,)
        The robot base at travel 0 and its motion per unit of travel, in {U}.
    band : (float, float)
        Horizontal distances (mm) the robot keeps.
    side : float
        -1: the robot stays on the side of lower travel (``s < s*``), +1 above.

    Returns
    -------
    low, high : ndarray, shape (N,)
        Travel values; ``low == high == s*`` where the band is out of reach.
    """
    a = np.array([along_u[0], along_u[1], 0.0])
    d = points_u - base_u
    d[:, 2] = 0.0
    aa = float(a @ a)
    s_star = abreast_travel(points_u, base_u, along_u)
    perp2 = np.maximum(np.sum(d * d, axis=1) - aa * s_star ** 2, 0.0)
    near = np.sqrt(np.maximum(band[0] ** 2 - perp2, 0.0) / aa)
    far = np.sqrt(np.maximum(band[1] ** 2 - perp2, 0.0) / aa)
    one_interval = near == 0.0
    low = np.where(side < 0, s_star - far, np.where(one_interval, s_star - far, s_star + near))
    high = np.where(side < 0, np.where(one_interval, s_star + far, s_star - near), s_star + far)
    return low, high


def abreast_travel(points_u, base_u, along_u):
    """Per point, the travel putting the robot's axis 1 abreast of it: the foot of the
    horizontal perpendicular from the point to the line ``base_u + s along_u``,
    ``s* = d.a / |a|^2``.

    Parameters
    ----------
    points_u, base_u, along_u : ndarray
        As :func:`travel_intervals` takes them: (N, 3) TCP positions, (3,) the robot
        base at travel 0 and (3,) its motion per unit of travel, all in {U}, mm.

    Returns
    -------
    ndarray, shape (N,)
        Travel values.
    """
    a = np.array([along_u[0], along_u[1], 0.0])
    d = np.asarray(points_u, dtype=float) - base_u
    return (d[:, :2] @ a[:2]) / float(a @ a)


def lazy_travel(low, high, start):
    """Travel values staying put while they can: each target's value is the
    previous one clipped into its interval (the least total travel through the
    intervals from `start`).

    Parameters
    ----------
    low, high : ndarray, shape (N,)
    start : float

    Returns
    -------
    ndarray, shape (N,)
    """
    out = np.empty(len(low))
    s = start
    for k in range(len(low)):     # scalar clips only: no kinematics in this loop
        s = min(max(s, low[k]), high[k])
        out[k] = s
    return out
