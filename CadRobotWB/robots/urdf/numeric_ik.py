"""Numerical inverse kinematics of any six-revolute URDF chain.

For arms whose kinematics has no closed form in CadRobot (neither OPW nor UR,
see :mod:`.identify`): offset wrists (FANUC CRX, Yaskawa HC10, ABB GoFa),
oblique wrists (painting arms), or an OPW arm whose file rounds pi/2 to
1.5708.

The method
----------
Damped least squares (Levenberg-Marquardt) on the six joint values, started
from many seeds per pose, every seed of every pose in one array:

* the error of a joint set is the flange's position error (mm, divided by
  the arm's length scale :func:`length_scale_mm` so it weighs like the
  rotation) and its rotation error (the rotation vector of
  ``R_target R^T``, rad), both in the root link's frame;
* the Jacobian is the analytic geometric one, from the joint axes z_i and
  origins o_i (the same frames as :func:`.urdf.chain_frames`, computed with
  each joint's turn about its frame's Z axis): column i is
  ``(z_i x (p - o_i), z_i)``, p the flange's origin;
* a step solves ``(J^T J + lambda I) dq = J^T e``; it is kept when it lowers
  the error, and lambda follows H. B. Nielsen's rule (Madsen, Nielsen,
  Tingleff, "Methods for non-linear least squares problems", 2004, sec.
  3.2): on a kept step ``lambda *= max(1/3, 1 - (2 rho - 1)^3)``, rho the
  actual over the predicted decrease, on a refused one ``lambda *= nu``,
  ``nu *= 2`` (nu back to 2 on a kept step).  (Plain x10 / /10 damping
  creeps for hundreds of iterations near a double singularity.)  Near a solution lambda falls to
  :data:`LAMBDA_MIN` and the step is Newton's, which converges
  quadratically down to rounding;
* a run stops when the flange is within a tenth of :data:`POSITION_TOL_MM`
  and :data:`ROTATION_TOL_RAD` of the target (converged) or when lambda passes
  :data:`LAMBDA_MAX` or :data:`MAX_ITERATIONS` are done (a local minimum or
  an unreachable pose: the run is rejected).

Seeds, the same for every pose (:func:`seeds_rad`): 32 grid joint sets --
the eight sign combinations of joint 2 at +-45, joint 3 at +-90 and joint 5
at +-90 degrees (shoulder, elbow and wrist-like flips), each at joint 1 =
+-45 and +-135 degrees -- and :data:`RANDOM_SEEDS` random joint sets from a
fixed generator seed.  Then up to :data:`ROUNDS` more rounds, each started
from the solutions the previous round found first (:func:`flips_rad`): the
wrist flipped, joint 1 turned half a turn, the arm mirrored through joint
1's axis, with and without the wrist flip (exact for a spherical wrist or
an arm whose axes 1 and 2 meet, close otherwise), and steps both ways along
the joint direction the flange follows least (:func:`twins_rad`: near a
singularity two solutions lie close together along it).  So the branches
that random seeds reach rarely are found too.

Each solution is finally checked with :func:`.urdf.chain_fk` itself.

How many solutions: a 6R arm has at most 16.  OPW and UR arms have at most
8; arms with an offset or oblique wrist have more for some poses (measured
on 100 random poses each: 16 for the FANUC CRX-10iA and M-430iA/2P, 14 for
the ABB CRB 15000, 12 for the Yaskawa HC10 family and MPX3500).
:func:`solve` returns the first ``max_solutions`` in the sort order (8 by
default, the closed forms' shape); pass 16 to get them all.

Solutions are wrapped into (-180, 180] degrees like the closed forms
(:func:`.opw.wrap_deg`); joint limits are NOT applied (callers do, as for the
closed forms).  Two solutions within :data:`DEDUP_TOL_DEG` of each other on
every joint (modulo 360) are one.  The distinct solutions of a pose are
sorted lexicographically by joint values (joint 1 first, each rounded to
:data:`SORT_DECIMALS` decimals of a degree), NaN rows last.

Vectorised over poses and seeds: no Python loop runs per pose.
Pure numpy: never imports FreeCAD.
"""

from dataclasses import dataclass

import numpy as np

from . import urdf
from ..kinematics.opw import wrap_deg

#: A solution's flange is at most this far from the target, mm.
POSITION_TOL_MM = 1e-9
#: ... and its rotation at most this far (angle of the relative rotation), rad.
ROTATION_TOL_RAD = 1e-10
#: A run stops at these fractions of the two tolerances, so that the final check with
#: :func:`.urdf.chain_fk` (rounded differently) never rejects a solution at the edge.
STOP_FRACTION = 0.1
#: Solutions this close on every joint (degrees, modulo 360) are the same one.
DEDUP_TOL_DEG = 1e-4
#: Solutions per pose returned by default (the closed forms' eight; a 6R arm has at most 16).
MAX_SOLUTIONS = 8
#: Levenberg-Marquardt damping lambda: start, floor (Newton steps), and give-up value.
LAMBDA_START = 1e-2
LAMBDA_MIN = 1e-14
LAMBDA_MAX = 1e6
#: Iterations of one round at most.
MAX_ITERATIONS = 100
#: Random seeds per pose (besides the 32 grid seeds), and their generator's seed.
RANDOM_SEEDS = 32
RANDOM_STATE = 20240611
#: Rounds of restarts from flipped solutions after the first.
ROUNDS = 3
#: Found solutions per pose a round restarts from, at most (a 6R arm has at most 16).
RESTARTS_PER_POSE = 16
#: Steps (rad) from a found solution along its least-moving joint direction, both ways, that
#: start the search for a nearby twin (:func:`twins_rad`).
TWIN_STEPS_RAD = (0.05, 0.3)
#: Decimals of a degree the sort key is rounded to.
SORT_DECIMALS = 6


# ------------------------------------------------------------------ pieces

def length_scale_mm(chain):
    """A length of the arm's size, mm: the sum of its link offsets.

    Position errors are divided by it so that a millimetre and a radian of
    rotation weigh alike in the least squares.

    Parameters
    ----------
    chain : urdf.Chain

    Returns
    -------
    float
    """
    lengths = np.linalg.norm(chain.T_prev_joint[:, :3, 3], axis=1).sum()
    lengths += np.linalg.norm(chain.T_joint6_tip[:3, 3])
    return float(max(lengths, 1.0))


def seeds_rad(count_random=RANDOM_SEEDS, random_state=RANDOM_STATE):
    """The fixed starting joint sets of the first round.

    Parameters
    ----------
    count_random : int
        Random joint sets added to the 32 grid ones.
    random_state : int
        Seed of numpy's generator: the same seeds every call.

    Returns
    -------
    ndarray, shape (32 + count_random, 6)
        Radians in [-pi, pi).
    """
    grid = [(q1, 45.0 * s2, 90.0 * s3, 0.0 if s2 == s3 else 90.0, 90.0 * s5, 0.0)
            for q1 in (-135.0, -45.0, 45.0, 135.0)
            for s2 in (-1, 1) for s3 in (-1, 1) for s5 in (-1, 1)]
    rng = np.random.default_rng(random_state)
    random = rng.uniform(-np.pi, np.pi, size=(count_random, 6))
    return np.vstack([np.radians(grid), random])


def rotation_error(R_target, R):
    """Rotation vector of ``R_target R^T`` (the turn from R to the target).

    Parameters
    ----------
    R_target, R : ndarray, shape (M, 3, 3)

    Returns
    -------
    ndarray, shape (M, 3)
        Axis times angle, rad, in the frame the matrices are given in; the
        angle is in [0, pi] and exact for small angles (no arccos).
    """
    E = R_target @ np.swapaxes(R, 1, 2)
    w = np.stack([E[:, 2, 1] - E[:, 1, 2], E[:, 0, 2] - E[:, 2, 0], E[:, 1, 0] - E[:, 0, 1]], -1)
    sin2 = np.linalg.norm(w, axis=1)                   # 2 sin(angle)
    cos2 = np.trace(E, axis1=1, axis2=2) - 1.0         # 2 cos(angle)
    angle = np.arctan2(sin2, cos2)
    with np.errstate(invalid="ignore", divide="ignore"):
        factor = np.where(sin2 > 1e-300, angle / sin2, 0.5)
    vector = w * factor[:, None]
    # Near a half turn w vanishes: the axis is the largest column of E + I.
    near_pi = (sin2 < 1e-6) & (cos2 < 0)
    if np.any(near_pi):
        S = E[near_pi] + np.eye(3)
        column = np.argmax(np.einsum("mii->mi", S), axis=1)
        axis = S[np.arange(len(S)), :, column]
        axis /= np.linalg.norm(axis, axis=1)[:, None]
        vector[near_pi] = axis * angle[near_pi][:, None]
    return vector


def _z_to(axis):
    """A rotation matrix (3, 3) taking +Z to the unit vector `axis`."""
    axis = np.asarray(axis, dtype=float)
    helper = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, axis)
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(axis, x), axis])


class _Kinematics:
    """The chain rewritten so every joint turns about its frame's Z axis.

    With ``A_i`` taking Z to joint i's axis, ``Rot(axis_i, q) = A_i Rz(q)
    A_i^T``; the ``A``'s fold into the fixed transforms, so a joint's turn
    only mixes two columns of the running rotation (cheaper than
    :func:`.urdf.chain_frames` and giving the axes and origins of the
    Jacobian on the way).
    """

    def __init__(self, chain):
        A = [np.eye(4) for _ in range(7)]
        for i in range(6):
            A[i + 1][:3, :3] = _z_to(chain.axes[i])
        fixed = [np.linalg.inv(A[i]) @ chain.T_prev_joint[i] @ A[i + 1] for i in range(6)]
        tip = np.linalg.inv(A[6]) @ chain.T_joint6_tip
        self.R_fixed = np.array([T[:3, :3] for T in fixed])        # (6, 3, 3)
        self.p_fixed = np.array([T[:3, 3] for T in fixed])         # (6, 3)
        self.R_tip, self.p_tip = tip[:3, :3], tip[:3, 3]
        self.scale = length_scale_mm(chain)

    def forward(self, q):
        """Flange (R (M, 3, 3), p (M, 3) mm), joint axes z (M, 6, 3) and origins o (M, 6, 3)."""
        m = len(q)
        R = np.tile(np.eye(3), (m, 1))              # (3M, 3): rows of the M rotations, stacked
        p = np.zeros((m, 3))
        z = np.empty((m, 6, 3))
        o = np.empty((m, 6, 3))
        c, s = np.cos(q), np.sin(q)
        for i in range(6):
            p += (R @ self.p_fixed[i]).reshape(m, 3)
            R = R @ self.R_fixed[i]                 # one matrix product for all M
            x, y = R[:, 0].reshape(m, 3), R[:, 1].reshape(m, 3)
            z[:, i], o[:, i] = R[:, 2].reshape(m, 3), p
            ci, si = c[:, i, None], s[:, i, None]
            R[:, 0], R[:, 1] = (ci * x + si * y).ravel(), (ci * y - si * x).ravel()
        p_tip = p + (R @ self.p_tip).reshape(m, 3)
        return (R @ self.R_tip).reshape(m, 3, 3), p_tip, z, o

    def error_and_jacobian(self, q, T_target):
        """Scaled error (M, 6), Jacobian (M, 6, 6), position error (M,) mm and
        rotation error (M,) rad of joint values q (M, 6) rad against poses (M, 4, 4) mm."""
        R, p, z, o = self.forward(q)
        e_pos = T_target[:, :3, 3] - p
        e_rot = rotation_error(T_target[:, :3, :3], R)
        r = p[:, None, :] - o                                            # (M, 6, 3)
        J = np.empty((len(q), 6, 6))
        J[:, 0, :] = (z[:, :, 1] * r[:, :, 2] - z[:, :, 2] * r[:, :, 1]) / self.scale
        J[:, 1, :] = (z[:, :, 2] * r[:, :, 0] - z[:, :, 0] * r[:, :, 2]) / self.scale
        J[:, 2, :] = (z[:, :, 0] * r[:, :, 1] - z[:, :, 1] * r[:, :, 0]) / self.scale
        J[:, 3:, :] = np.swapaxes(z, 1, 2)
        error = np.hstack([e_pos / self.scale, e_rot])
        return error, J, np.linalg.norm(e_pos, axis=1), np.linalg.norm(e_rot, axis=1)


def jacobian(chain, q_rad):
    """The geometric Jacobian of the flange, in the root link's frame.

    Parameters
    ----------
    chain : urdf.Chain
    q_rad : array_like, shape (N, 6)
        Joint values, radians.

    Returns
    -------
    ndarray, shape (N, 6, 6)
        Rows 0-2: flange velocity, mm/rad; rows 3-5: angular velocity,
        rad/rad; column i for joint i.
    """
    q = np.atleast_2d(np.asarray(q_rad, dtype=float))
    kinematics = _Kinematics(chain)
    J = kinematics.error_and_jacobian(q, np.broadcast_to(np.eye(4), (len(q), 4, 4)))[1]
    J[:, :3] *= kinematics.scale
    return J


def refine(chain, T_target, q_start, max_iterations=MAX_ITERATIONS):
    """Levenberg-Marquardt from each start to its target pose.

    Parameters
    ----------
    chain : urdf.Chain
        (Or its :class:`_Kinematics`, prepared once by :func:`solve`.)
    T_target : ndarray, shape (M, 4, 4)
        Flange poses in the root link's frame, mm; one per start.
    q_start : ndarray, shape (M, 6)
        Start joint values, rad.
    max_iterations : int

    Returns
    -------
    q : ndarray, shape (M, 6)
        Final joint values, rad, wrapped into [-pi, pi).
    converged : ndarray of bool, shape (M,)
        True where the flange is within :data:`STOP_FRACTION` of
        :data:`POSITION_TOL_MM` and of :data:`ROTATION_TOL_RAD` of the target.
    """
    kinematics = chain if isinstance(chain, _Kinematics) else _Kinematics(chain)
    q = np.array(q_start, dtype=float)
    error, J, pos, rot = kinematics.error_and_jacobian(q, T_target)
    cost = np.einsum("mi,mi->m", error, error)
    position_stop = STOP_FRACTION * POSITION_TOL_MM
    rotation_stop = STOP_FRACTION * ROTATION_TOL_RAD
    converged = (pos <= position_stop) & (rot <= rotation_stop)
    damping = np.full(len(q), LAMBDA_START)
    growth = np.full(len(q), 2.0)
    active = np.flatnonzero(~converged)
    eye = np.eye(6)
    for _ in range(max_iterations):
        if active.size == 0:
            break
        Ja, ea, lam = J[active], error[active], damping[active]
        JT = np.swapaxes(Ja, 1, 2)
        gradient = np.einsum("mij,mj->mi", JT, ea)
        step = np.linalg.solve(JT @ Ja + lam[:, None, None] * eye, gradient[..., None])[..., 0]
        predicted = np.einsum("mi,mi->m", step, lam[:, None] * step + gradient)
        q_try = (q[active] + step + np.pi) % (2 * np.pi) - np.pi
        e_try, J_try, pos_try, rot_try = kinematics.error_and_jacobian(q_try, T_target[active])
        cost_try = np.einsum("mi,mi->m", e_try, e_try)
        done = (pos_try <= position_stop) & (rot_try <= rotation_stop)
        with np.errstate(divide="ignore", invalid="ignore"):
            gain = (cost[active] - cost_try) / predicted
        better = (cost_try < cost[active]) | done
        keep = active[better]
        q[keep], error[keep], J[keep] = q_try[better], e_try[better], J_try[better]
        cost[keep] = cost_try[better]
        converged[active] = done
        # Nielsen's update: lambda follows how well the linear model predicted the gain.
        shrink = np.maximum(1.0 / 3.0, 1.0 - (2.0 * np.nan_to_num(gain, nan=1.0) - 1.0) ** 3)
        damping[active] = np.where(better, np.maximum(lam * shrink, LAMBDA_MIN),
                                   lam * growth[active])
        growth[active] = np.where(better, 2.0, growth[active] * 2.0)
        active = active[~done & (damping[active] <= LAMBDA_MAX)]
    return q, converged


def _distinct(q_deg, valid):
    """Per pose, one row of each group of rows that are the same solution.

    Parameters
    ----------
    q_deg : ndarray, shape (N, S, 6)
        Candidate solutions, degrees.
    valid : ndarray of bool, shape (N, S)

    Returns
    -------
    distinct : ndarray, shape (N, D, 6)
        The first row of each group of valid rows within
        :data:`DEDUP_TOL_DEG` of each other on every joint (modulo 360),
        wrapped into (-180, 180], in the order of their first rows; NaN rows
        after them.
    source : ndarray of int, shape (N, D)
        The index (in S) of each distinct row; S for a NaN row.
    """
    n, s, _ = q_deg.shape
    q_deg = wrap_deg(np.where(valid[..., None], q_deg, 0.0))
    poses = np.arange(n)
    remaining = valid.copy()
    distinct, source = [], []
    # One pass per distinct solution (a 6R arm has at most 16), all poses at once.
    while remaining.any():
        has = remaining.any(axis=1)
        index = np.argmax(remaining, axis=1)
        first = q_deg[poses, index]                                           # (N, 6)
        same = np.abs(wrap_deg(q_deg - first[:, None, :])).max(axis=2) <= DEDUP_TOL_DEG
        remaining &= ~same
        distinct.append(np.where(has[:, None], first, np.nan))
        source.append(np.where(has, index, s))
    if not distinct:
        return np.full((n, 0, 6), np.nan), np.zeros((n, 0), dtype=int)
    return np.stack(distinct, axis=1), np.stack(source, axis=1)


def _sorted(q_deg, max_solutions):
    """Rows sorted lexicographically (joint 1 first), NaN rows last; (N, D, 6) -> (N, K, 6)."""
    n, d, _ = q_deg.shape
    if d < max_solutions:
        q_deg = np.concatenate([q_deg, np.full((n, max_solutions - d, 6), np.nan)], axis=1)
    key = np.where(np.isnan(q_deg), np.inf, np.round(q_deg, SORT_DECIMALS))
    order = np.tile(np.arange(q_deg.shape[1]), (n, 1))
    for joint in range(5, -1, -1):           # stable sorts, the last key first
        column = np.take_along_axis(key[:, :, joint], order, axis=1)
        order = np.take_along_axis(order, np.argsort(column, axis=1, kind="stable"), axis=1)
    return np.take_along_axis(q_deg, order[:, :max_solutions, None], axis=1)


def flips_rad(q):
    """Starts near the other configurations of found solutions.

    For each joint set: the wrist flipped (``q4 + pi, -q5, q6 + pi``: exact
    for a spherical wrist), joint 1 turned half a turn, and the arm mirrored
    through joint 1's axis (``q1 + pi, -q2, -q3 or pi - q3, q4 + pi``: exact
    for an arm whose axes 1 and 2 meet, as the cobots' do, depending on where
    joint 3's zero is), each with and without the wrist flip.

    Parameters
    ----------
    q : ndarray, shape (M, 6)
        Radians.

    Returns
    -------
    ndarray, shape (7, M, 6)
        Radians (not wrapped).
    """
    pi = np.pi
    # Per variant: (add to q1, sign of q2, sign of q3, add to q3, add to q4).
    arms = [(0.0, 1, 1, 0.0, 0.0), (pi, 1, 1, 0.0, 0.0),
            (pi, -1, -1, 0.0, pi), (pi, -1, -1, pi, pi)]
    out = []
    for d1, s2, s3, d3, d4 in arms:
        arm = q * (1, s2, s3, 1, 1, 1) + (d1, 0.0, d3, d4, 0.0, 0.0)
        out.append(arm * (1, 1, 1, 1, -1, 1) + (0.0, 0.0, 0.0, pi, 0.0, pi))
        out.append(arm)
    return np.stack(out[:1] + out[2:])         # not the unchanged joint set


def twins_rad(kinematics, q):
    """Starts on both sides of found solutions along their least-moving joint direction.

    Near a singularity two solutions lie close together, along the joint
    direction the flange follows least (the right singular vector of the
    Jacobian with the smallest singular value); a start a little past the
    midpoint converges to the other one.

    Parameters
    ----------
    kinematics : _Kinematics
    q : ndarray, shape (M, 6)
        Radians.

    Returns
    -------
    ndarray, shape (2 * len(TWIN_STEPS_RAD), M, 6)
        Radians (not wrapped).
    """
    if not TWIN_STEPS_RAD:
        return np.empty((0,) + q.shape)
    J = kinematics.error_and_jacobian(q, np.broadcast_to(np.eye(4), (len(q), 4, 4)))[1]
    direction = np.linalg.svd(J)[2][:, -1, :]                                  # (M, 6)
    steps = np.concatenate([TWIN_STEPS_RAD, -np.asarray(TWIN_STEPS_RAD)])
    return q[None] + steps[:, None, None] * direction[None]


def solve(chain, T_root_tip, seeds=None, max_solutions=MAX_SOLUTIONS,
          max_iterations=MAX_ITERATIONS, rounds=ROUNDS):
    """Every joint solution of each flange pose, found numerically.

    Parameters
    ----------
    chain : urdf.Chain
    T_root_tip : array_like, shape (N, 4, 4) or (4, 4)
        Flange (tip link) poses in the root link's frame, mm.
    seeds : array_like, shape (S, 6), optional
        First-round starting joint values, rad, the same for every pose;
        default :func:`seeds_rad`.
    max_solutions : int
        K, the solutions returned per pose (the closed forms' 8; a 6R arm has
        at most 16).  When a pose has more than K, the first K in the sort
        order are returned.
    max_iterations : int
        Levenberg-Marquardt iterations per round at most.
    rounds : int
        Rounds after the first, each started from :func:`flips_rad` of the
        solutions the previous round found first.

    Returns
    -------
    ndarray, shape (N, K, 6)
        URDF joint values, degrees, each wrapped into (-180, 180]; distinct
        solutions sorted lexicographically (joint 1 first; each joint rounded
        to :data:`SORT_DECIMALS` decimals for the comparison), NaN rows after
        them.  Every row's flange is within :data:`POSITION_TOL_MM` and
        :data:`ROTATION_TOL_RAD` of its pose.  Joint limits are not applied.
        An unreachable pose (or one with NaN) has only NaN rows.  A singular
        pose with a continuum of solutions (a spherical wrist at q5 = 0) gets
        some points of it (the closed forms pick one, with q4 = 0).
    """
    T = np.asarray(T_root_tip, dtype=float)
    if T.ndim == 2:
        T = T[None]
    n = len(T)
    kinematics = _Kinematics(chain)
    starts = seeds_rad() if seeds is None else np.atleast_2d(np.asarray(seeds, dtype=float))
    s = len(starts)
    q, ok = refine(kinematics, np.repeat(T, s, axis=0), np.tile(starts, (n, 1)), max_iterations)
    known, source = _distinct(np.degrees(q).reshape(n, s, 6), ok.reshape(n, s))
    new = ~np.isnan(known[:, :, 0])
    for _ in range(rounds):
        # At most 16 restarts per pose: more solutions than a 6R arm has means a continuum (a
        # singular pose, e.g. a spherical wrist at q5 = 0), whose points need no more search.
        new[:, RESTARTS_PER_POSE:] = False
        pose, column = np.nonzero(new)
        if pose.size == 0:
            break
        q_known = np.radians(known[pose, column])
        starts = np.concatenate([flips_rad(q_known), twins_rad(kinematics, q_known)])  # (F, M, 6)
        f = len(starts)
        q, ok = refine(kinematics, np.tile(T[pose], (f, 1, 1)), starts.reshape(-1, 6),
                       max_iterations)
        # Back to one row per pose: rank of each start among its pose's, times f, plus variant.
        counts = np.bincount(pose, minlength=n)
        rank = np.arange(len(pose)) - np.repeat(np.cumsum(counts) - counts, counts)
        slot = (rank[None, :] * f + np.arange(f)[:, None]).reshape(-1)
        per_pose = counts.max() * f
        found = np.full((n, per_pose, 6), np.nan)
        valid = np.zeros((n, per_pose), dtype=bool)
        found[np.tile(pose, f), slot] = np.degrees(q)
        valid[np.tile(pose, f), slot] = ok
        d = known.shape[1]
        known_valid = ~np.isnan(known[:, :, 0])
        known, source = _distinct(np.concatenate([known, found], axis=1),
                                  np.concatenate([known_valid, valid], axis=1))
        new = (source >= d) & (source < d + per_pose)
    return _sorted(_checked(chain, T, known), max_solutions)


def _checked(chain, T, q_deg):
    """`q_deg` (N, D, 6) with NaN rows where the URDF chain's flange misses its pose."""
    n, d, _ = q_deg.shape
    if d == 0:
        return q_deg
    T_found = urdf.chain_fk(chain, np.radians(np.nan_to_num(q_deg.reshape(-1, 6))))
    T_want = np.repeat(T, d, axis=0)
    position = np.linalg.norm(T_found[:, :3, 3] - T_want[:, :3, 3], axis=1)
    rotation = np.linalg.norm(rotation_error(T_want[:, :3, :3], T_found[:, :3, :3]), axis=1)
    good = (position <= POSITION_TOL_MM) & (rotation <= ROTATION_TOL_RAD)
    good &= ~np.isnan(q_deg[..., 0].reshape(-1))
    return np.where(good.reshape(n, d)[..., None], q_deg, np.nan)


@dataclass(frozen=True)
class NumericModel:
    """A URDF chain with numerical inverse kinematics, used like :class:`.identify.Identified`.

    Attributes
    ----------
    chain : urdf.Chain
    max_solutions : int
        Rows of :meth:`ik` per pose: 8 like the closed forms; 16 never drops a
        solution (see the module docstring).
    kind : str
        ``"numeric"``.
    """

    chain: object
    max_solutions: int = MAX_SOLUTIONS
    kind: str = "numeric"

    def fk(self, q_deg):
        """Flange pose in the root link frame, (N, 6) deg -> (N, 4, 4) mm."""
        return urdf.chain_fk(self.chain, np.radians(np.atleast_2d(q_deg)))

    def ik(self, T_root_tip):
        """Every solution found, (N, 4, 4) mm -> (N, max_solutions, 6) deg (see :func:`solve`)."""
        return solve(self.chain, T_root_tip, max_solutions=self.max_solutions)
