"""The offset-wrist solutions the one-dimensional search cannot see, found by other means.

The search of :mod:`.offset_wrist` builds axis 4 as the direction across axis 2 and
axis 5. Where those two are parallel (joint 4 at the value :func:`aligned_q4_rad`
gives, 0 or 180 degrees on the CRX) that direction is undefined, and a solution lying
there is missed. Two common kinds of pose have such solutions:

* axis 6 parallel to axis 1 (:func:`upright`: the torch straight down on a straight
  neck): on the CRX, HC10s, CRB 15000 and M-430iA/2P every solution has either joint 4
  at the aligned value (the search sees none of them) or axis 4 parallel to axis 1 too;
* a wrist in the arm's plane (a seam straight ahead of the robot, the torch tilted in
  that plane).

Upright poses (within :data:`SUSPECT_DEG`) are solved in closed form: with joint 4
aligned, axes 2, 3 and 5 are parallel (:func:`upright_solutions`); with axis 4 upright,
axes 1, 4 and 6 are (:func:`axis4_upright_solutions`). Where these two families hold every
solution (:func:`upright_closed`: axes 1-2, 4-5 and 5-6 perpendicular) a pose upright to
rounding (:data:`SEARCH_FREE_DEG`) is not searched at all; otherwise their rows are added
to the search's. A pose slightly off upright gets the rows of the pose turned upright,
moved onto it by Newton steps on the arm's geometric Jacobian (:func:`polish`).

Any other pose whose solutions may be missed (:func:`suspect`: no solution, or one within
:data:`SUSPECT_DEG` of the aligned joint 4) is searched again turned by :data:`NUDGE_RAD`
about each of two fixed oblique axes of the flange, where the alignment is broken, and
every solution found there is polished back onto the pose. Only what reproduces the pose
to the search's own tolerances is added.

Measured against the numerical IK (``numeric_ik.solve``, 16 rows; scripts of this
project's issue-24 work, the tests keep a part): 24 torch-down poses each of the
CRX-10iA/L, HC10, CRB 15000 and M-430iA/2P at 0, 1e-6, 1e-4, 9e-4, 1.1e-3, 0.01, 0.03
and 0.049 degrees off, and 60 random poses (any turn about the vertical, a quarter of
them torch up) of those and the HC10DT B10 at 0, 1e-8, 1e-6, 5e-4, 0.005, 0.04 and 0.06
degrees off: no solution missed (the search alone missed 144, 144, 32 and 8 of the first
grid's exactly down). One nudge alone still missed 4 of the HC10's, next to its wrist
singularity. This is a repair around the search's blind spot, not a proof of completeness.

Cost, on this project's 2-core machine at load 1-2 (CPU time, one core): 20,000 straight-down
CRX poses in one call take 22 microseconds a pose, most of it the numpy of the closed forms
(the IRB 2400's closed form 0.3); 0.01 degrees off down 89 (the search of the poses turned
upright and the polish of their rows); one pose a call about 5 ms, most of it the numpy
calls of the closed forms (numba would remove that: not done).
:mod:`.offset_wrist_polish_kernel` compiles the Newton polish (:func:`polish`'s steps,
row by row) and the merge; the screening (:func:`screened`: which poses are upright or
suspect) runs in the search's compiled pass (:func:`screen_vector`,
``offset_wrist.inverse_screened``), so that a random pose costs no numpy over its rows.
On 50,000 random poses the repair of the suspect ones (0.3 %) then costs 0.3 microseconds
a pose on the CRX (1.4 with numpy's batched pinv), about half of it the search of their
nudged poses.

Pure numpy (numba optional): never imports FreeCAD.
"""

import numpy as np

from ...core.rotations import matrix_from_axis_angle
from . import offset_wrist_kernel as search_kernel
from . import offset_wrist_polish_kernel as kernel
from . import poe

#: The turn (rad) of the nudged pose: far enough from the alignment for the search
#: (0.01 degrees off, it missed nothing on the CRX's torch-down poses), near enough for
#: Newton's steps (2e-3 lost solutions next to the HC10's wrist singularity).
NUDGE_RAD = 3e-4
#: The flange axes it turns about, one after the other (fixed oblique directions, no CAD
#: pose's special one): next to a wrist singularity one turn can land on another branch.
NUDGE_AXES = (np.array([0.48, -0.36, 0.8]), np.array([-0.6, 0.64, 0.48]))
#: A pose is suspect when a solution's joint 4 is this close to the aligned value.
SUSPECT_DEG = 0.05
#: Newton steps, and what a polished solution must reproduce (as offset_wrist's own check).
STEPS = 8
#: After this many steps a row still more than GIVE_UP_TOL times the tolerances off is
#: dropped (a regular root is at rounding after three steps from NUDGE_RAD).
GIVE_UP_STEP = 3
GIVE_UP_TOL = 1e4
POSITION_TOL_MM = 1e-6
ROTATION_TOL_RAD = 1e-9
#: The steps' pseudo-inverse drops singular values under this times the largest (the
#: polish also steps where the Jacobian is singular).
PINV_RCOND = 1e-10
#: Solutions this close on every joint (rad, modulo 2 pi) are one.
SAME_RAD = 1e-6
#: Poses this close to upright (to rounding) are not searched where the closed forms hold
#: every solution (:func:`upright_closed`). Not farther: next to the HC10's wrist
#: singularity a pose 0.0005 deg off upright has two pairs of solutions 0.25 deg apart
#: in joint 4 where the upright pose has one of each, and polishing finds one per pair.
SEARCH_FREE_DEG = 1e-7
#: Axes this close to perpendicular (|cos|) are (as offset_wrist.DIRECTION_TOL).
PERPENDICULAR_TOL = 1e-9
#: Poses repaired at a time, so that the arrays of 8 to 32 rows per pose stay small (in
#: one piece, bench_check's CRX took 0.34 s per 1,000 targets at 100,000 against 0.21
#: at 10,000; in pieces 0.28 and 0.29, under the same load).
CHUNK_POSES = 2048


def aligned_q4_rad(params):
    """Joint 4 values where axis 5 is parallel to axis 2 (none on an oblique wrist).

    Parameters
    ----------
    params : poe.ChainParameters

    Returns
    -------
    ndarray, shape (0,) or (2,)
    """
    h2, h4, h5 = params.H[1], params.H[3], params.H[4]
    if abs(abs(h4 @ h5) - abs(h4 @ h2)) > 1e-9:
        return np.zeros(0)
    u = h5 - (h5 @ h4) * h4               # the parts across axis 4
    v = h2 - (h2 @ h4) * h4
    if np.linalg.norm(u) < 1e-9:
        return np.zeros(0)
    angle = np.arctan2(h4 @ np.cross(u, v), u @ v)
    return np.array([angle, angle + np.pi])


def suspect(q_rad, aligned):
    """(N,) bool: poses with no solution or with one near the aligned joint 4, where the
    search may have missed some (poses with axis 6 upright are :func:`upright`'s)."""
    small = np.sin(np.radians(SUSPECT_DEG))
    found = ~np.isnan(q_rad[..., 0])
    near = np.zeros(found.shape, bool)
    for a in aligned:
        near |= np.abs(np.sin(q_rad[..., 3] - a)) < small
    return ~found.any(axis=1) | (near & found).any(axis=1)


def beyond_reach(params, T_0T):
    """(N,) bool: poses whose axis 6 point is farther from axis 1's than the links between
    them are long together (``|P1| + ... + |P5|``): no joint values reach them, so a pose
    turned a little is not searched for them (most of Place robot's poses)."""
    x = T_0T[:, :3, 3] - T_0T[:, :3, :3] @ (params.R_6T.T @ params.P[6]) - params.P[0]
    links = np.linalg.norm(np.asarray(params.P, float)[1:6], axis=1).sum()
    return np.linalg.norm(x, axis=1) > links + 1e-6


def upright(params, T_0T, within_deg=SUSPECT_DEG):
    """(N,) bool: poses with axis 6 within `within_deg` of parallel to axis 1 (the torch
    straight down or up), whose solutions lie at the alignment or next to it."""
    h6 = T_0T[:, :3, :3] @ (params.R_6T.T @ params.H[5])
    return np.linalg.norm(np.cross(h6, params.H[0]), axis=1) < np.sin(np.radians(within_deg))


# ------------------------------------------------------------------ axis 6 upright

def _rotate(axis, angle, v):
    """(S, 3): rot(axis, angle) v by Rodrigues; `axis` (3,) unit, `angle` (S,) rad,
    `v` (S, 3) or (3,)."""
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    v = np.broadcast_to(v, (len(angle), 3))
    return v * c + (v @ _cross_matrix(axis).T) * s + np.outer(v @ axis, axis) * (1.0 - c)


def _angle_about(axis, u, v):
    """(S,) rad: the turn about `axis` (3,) taking `u` to `v` (S, 3), measured on their
    parts across the axis (subproblem 1)."""
    u_cross_v_along = -(u * (v @ _cross_matrix(axis).T)).sum(axis=-1)     # (u x v) . axis
    return np.arctan2(u_cross_v_along, (u * v).sum(axis=-1) - (u @ axis) * (v @ axis))


def _cross_matrix(axis):
    """(3, 3) K with ``K v = axis x v`` (cheaper than np.cross on small arrays)."""
    return np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]],
                     [-axis[1], axis[0], 0.0]])


def _cos_sin_roots(alpha, beta, c):
    """(2, S) rad: the two angles x with ``alpha cos x + beta sin x = c`` (subproblems 3
    and 4); NaN where there is none (beyond rounding: 1e-12 of sqrt(alpha^2 + beta^2))."""
    r = np.hypot(alpha, beta)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = c / r
    ratio = np.where(np.abs(ratio) <= 1.0 + 1e-12, np.clip(ratio, -1.0, 1.0), np.nan)
    middle, half = np.arctan2(beta, alpha), np.arccos(ratio)
    return np.stack([middle + half, middle - half])


def _across(v, axis):
    """`v` (..., 3) without its part along the unit `axis` (3,)."""
    return v - (v @ axis)[..., None] * axis


def _upright_terms(params, T_0T):
    """What both upright closed forms start from: ``R_06`` (S, 3, 3); e (S,), +1 where
    axis 6 points along h1, -1 against it; the point of axis 6 from that of axis 1 (S, 3),
    mm; a fixed unit direction across axis 1 (3,), for the turn about it."""
    h1, h2, h6 = params.H[0], params.H[1], params.H[5]
    R_06 = T_0T[:, :3, :3] @ params.R_6T.T
    e = np.where(R_06 @ h6 @ h1 < 0.0, -1.0, 1.0)
    x = T_0T[:, :3, 3] - R_06 @ params.P[6] - params.P[0]
    across_1 = np.cross(h1, h2) / np.linalg.norm(np.cross(h1, h2))
    return R_06, e, x, across_1


def upright_solutions(params, T_0T, aligned):
    """The solutions with joint 4 at an aligned value of poses whose axis 6 is parallel
    to axis 1, in closed form.

    At joint 4 = ``a`` (:func:`aligned_q4_rad`) axes 2, 3 and 5 are parallel, so
    ``R_06 = rot(h1, q1) rot(h2, psi) A rot(h6, q6)`` with ``A = rot(h4, a)`` and
    ``psi = q2 + sigma3 q3 + s q5`` (``A h5 = s h2``). Axis 6 along ``e h1`` (e = +-1)
    fixes psi (subproblem 1) and ``phi = q1 + e q6`` (the turn about axis 1); the point of
    axis 6 keeps its distance along axis 2 from axis 1, which gives two q1 (subproblem
    4); the planar 2R of axes 2 and 3 to axis 5 gives two q3 (subproblem 3), then q2
    (subproblem 1), q5 and q6. For a pose a little off upright these are the solutions
    of the pose turned upright: :func:`polish` moves them onto it.

    Parameters
    ----------
    params : poe.ChainParameters
    T_0T : ndarray, shape (S, 4, 4)
        Flange poses, mm, axis 6 (``R_0T R_6T^T h6``) along +-h1.
    aligned : ndarray, shape (2,)
        rad, :func:`aligned_q4_rad`.

    Returns
    -------
    ndarray, shape (S, 4 * len(aligned), 6)
        rad, not wrapped; NaN rows where a subproblem has no root.
    """
    H, P = np.asarray(params.H, float), np.asarray(params.P, float)
    h1, h2, h3, h4, h5, h6 = H
    n = len(T_0T)
    R_06, e, x, across_1 = _upright_terms(params, T_0T)
    rows = []
    for a in aligned:
        A = matrix_from_axis_angle(h4, a)
        s = 1.0 if (A @ h5) @ h2 > 0.0 else -1.0
        psi = _angle_about(h2, np.broadcast_to(A @ h6, (n, 3)), e[:, None] * h1)
        G_across = np.einsum("ij,nj->ni", A.T, _rotate(h2, -psi, across_1))
        phi = _angle_about(h1, np.broadcast_to(across_1, (n, 3)),
                           np.einsum("nij,nj->ni", R_06, G_across))
        w = _rotate(h2, psi, A @ P[5])                          # axis 5 to axis 6, frame 1
        L = P[3] + A @ P[4]                                     # axis 3 to axis 5, frame 3
        d = (P[1] + w + P[2] + L) @ h2
        q1s = _cos_sin_roots(_across(x, h1) @ h2, -(x @ (_cross_matrix(h1).T @ h2)),
                             d - (x @ h1) * (h1 @ h2))
        P2, L_ = _across(P[2], h2), _across(L, h2)
        for q1 in q1s:
            y = _across(_rotate(h1, -q1, x) - P[1] - w, h2)     # axis 2 to axis 5, frame 1
            q3s = _cos_sin_roots(np.full(n, P2 @ L_), np.full(n, P2 @ np.cross(h2, L_)),
                                 0.5 * ((y * y).sum(axis=1) - P2 @ P2 - L_ @ L_))
            for t3 in q3s:
                q2 = _angle_about(h2, P2 + _rotate(h2, t3, L_), y)
                rows.append(np.stack([q1, q2, np.sign(h3 @ h2) * t3, np.full(n, a),
                                      s * (psi - q2 - t3), e * (phi - q1)], axis=1))
    q = np.stack(rows, axis=1)
    q[~np.isfinite(q).all(axis=2)] = np.nan
    return q



def axis4_upright_solutions(params, T_0T):
    """The solutions with axis 4 parallel to axis 1 of poses whose axis 6 is, in closed form.

    With axis 4 along ``eps h1`` (eps = +-1), ``psi = q2 + sigma3 q3`` is the constant
    turning h4 to ``eps h1`` about h2 (``B = rot(h2, psi)``) and q5 the one turning h6 to
    ``e eps h4`` about h5 (``C = rot(h5, q5)``), so ``R_06 = rot(h1, q1 + eps q4 + e q6) B C``
    (subproblem 1 gives that turn, ``phi``). The point of axis 6 is
    ``rot(h1, q1) (P1 + rot(h2, q2) P2 + B P3 + rot(h1, eps q4) m)``, ``m = B (P4 + C P5)``:
    its height along h1 gives two q2, its distance from axis 1 two q1 (both
    ``alpha cos + beta sin = c``), then q4 (subproblem 1) and q6.

    Parameters
    ----------
    params : poe.ChainParameters
    T_0T : ndarray, shape (S, 4, 4)
        Flange poses, mm, axis 6 along +-h1.

    Returns
    -------
    ndarray, shape (S, 8, 6)
        rad, not wrapped; NaN rows where a subproblem has no root.
    """
    H, P = np.asarray(params.H, float), np.asarray(params.P, float)
    h1, h2, h3, h4, h5, h6 = H
    n = len(T_0T)
    R_06, e, x, across_1 = _upright_terms(params, T_0T)
    X = _across(x, h1)
    P2 = _across(P[2], h2)
    rows = []
    for eps in (1.0, -1.0):
        psi = _angle_about(h2, h4[None], eps * h1[None])[0]
        B = matrix_from_axis_angle(h2, psi)
        q5 = _angle_about(h5, np.broadcast_to(h6, (n, 3)), (e * eps)[:, None] * h4)
        m = (P[4] + _rotate(h5, q5, P[5])) @ B.T                # axis 4's point to axis 6's
        BC_across = _rotate(h5, -q5, B.T @ across_1)            # (B C)^T across_1
        phi = _angle_about(h1, np.broadcast_to(across_1, (n, 3)),
                           np.einsum("nij,nj->ni", R_06, BC_across))
        height = x @ h1 - (P[1] + B @ P[3]) @ h1 - m @ h1 - (h1 @ h2) * (h2 @ P[2])
        q2s = _cos_sin_roots(np.full(n, h1 @ P2), np.full(n, h1 @ np.cross(h2, P2)), height)
        m_across = _across(m, h1)
        for q2 in q2s:
            g = _across(P[1] + _rotate(h2, q2, P[2]) + B @ P[3], h1)   # axis 1 to axis 4, frame 1
            q1s = _cos_sin_roots((X * g).sum(axis=1), (X * (g @ _cross_matrix(h1).T)).sum(axis=1),
                                 0.5 * ((X * X).sum(axis=1) + (g * g).sum(axis=1)
                                        - (m_across * m_across).sum(axis=1)))
            for q1 in q1s:
                t4 = _angle_about(h1, m_across, _rotate(h1, -q1, X) - g)     # eps q4
                rows.append(np.stack([q1, q2, np.sign(h3 @ h2) * (psi - q2), eps * t4, q5,
                                      e * (phi - q1 - t4)], axis=1))
    q = np.stack(rows, axis=1)
    q[~np.isfinite(q).all(axis=2)] = np.nan
    return q

def _errors(params, q, T):
    """(M, 6) position (mm) and rotation (rad) errors of `q` against `T` in the base frame;
    (M,) bool: the rotation error is under a quarter turn (where the rotation part,
    the axis times the sine of the angle, measures it); (M, 3) the flange's position, mm."""
    F = poe.fk(params, q)
    E = T[:, :3, :3] @ np.transpose(F[:, :3, :3], (0, 2, 1))
    e_r = 0.5 * np.stack([E[:, 2, 1] - E[:, 1, 2], E[:, 0, 2] - E[:, 2, 0],
                          E[:, 1, 0] - E[:, 0, 1]], axis=1)
    near = np.trace(E, axis1=1, axis2=2) > 1.0
    return np.hstack([T[:, :3, 3] - F[:, :3, 3], e_r]), near, F[:, :3, 3]


def _jacobian(params, q, p_flange):
    """(M, 6, 6) geometric Jacobian: columns (h_i x (p - o_i), h_i) in the base frame."""
    R = poe.rotations(params, q)                                  # R_0i, i = 1..6
    n = q.shape[0]
    R_prev = np.concatenate([np.broadcast_to(np.eye(3), (n, 1, 3, 3)), R[:, :5]], axis=1)
    h = np.einsum("nkij,kj->nki", R_prev, params.H)
    steps = np.einsum("nkij,kj->nki", R_prev, params.P[:6])      # base->1, 1->2, ... in R_0(i-1)
    origins = np.cumsum(steps, axis=1)
    J = np.empty((n, 6, 6))
    J[:, :3] = np.transpose(np.cross(h, p_flange[:, None, :] - origins), (0, 2, 1))
    J[:, 3:] = np.transpose(h, (0, 2, 1))
    return J


def polish(params, q_rad, T_0T):
    """Newton steps moving joint sets onto their poses (the compiled
    ``offset_wrist_polish_kernel.polished_onto`` takes the same steps row by row).

    Parameters
    ----------
    params : poe.ChainParameters
    q_rad : ndarray, shape (M, 6)
    T_0T : ndarray, shape (M, 4, 4)

    Returns
    -------
    q : ndarray, shape (M, 6)
        rad, wrapped into (-pi, pi].
    good : ndarray of bool, shape (M,)
        Where the pose is reproduced to :data:`POSITION_TOL_MM` and :data:`ROTATION_TOL_RAD`.
    """
    q = q_rad.copy()
    alive = np.ones(len(q), bool)
    for step in range(STEPS + 1):
        e, near, p_flange = _errors(params, q, T_0T)
        if step == STEPS:
            break
        size = np.maximum(np.abs(e[:, :3]).max(axis=1) / POSITION_TOL_MM,
                          np.abs(e[:, 3:]).max(axis=1) / ROTATION_TOL_RAD)
        if step >= GIVE_UP_STEP:            # Newton's steps from NUDGE_RAD are there by now
            alive &= near & (size < GIVE_UP_TOL)
        moving = alive & ((size > 0.01) | ~near)
        if not moving.any():
            break
        J = _jacobian(params, q[moving], p_flange[moving])
        q[moving] += (np.linalg.pinv(J, rcond=PINV_RCOND) @ e[moving, :, None])[..., 0]
    good = (near & (np.linalg.norm(e[:, :3], axis=1) <= POSITION_TOL_MM)
            & (np.linalg.norm(e[:, 3:], axis=1) <= ROTATION_TOL_RAD) & np.isfinite(q).all(1))
    return _wrap(q), good


def _same(a, b):
    """(S, M, K) bool: rows of `a` (S, M, 6) equal to rows of `b` (S, K, 6), modulo 2 pi
    (both wrapped into (-pi, pi], so a difference is within a turn)."""
    d = np.abs(a[:, :, None, :] - b[:, None, :, :])
    return (np.minimum(d, 2.0 * np.pi - d) <= SAME_RAD).all(axis=-1)


def _wrap(angle):
    """Angles (rad) into (-pi, pi]."""
    return np.pi - (np.pi - angle) % (2.0 * np.pi)


def _live_first(rows):
    """`rows` (S, K, 6) with NaN rows last, cut to the most live rows of any pose."""
    dead = np.isnan(rows[..., 0])
    order = np.argsort(dead, axis=1, kind="stable")
    width = int((~dead).sum(axis=1).max(initial=0))
    return np.take_along_axis(rows, order[:, :width, None], axis=1)


def _merged(rows, extra):
    """(S, K, 6): `rows` (S, K, 6) plus the rows of `extra` (S, M, 6) found neither there
    nor earlier in `extra`, NaN rows last (at most K)."""
    if kernel.available():
        return kernel.merged(rows, extra, SAME_RAD)
    return _merged_numpy(rows, extra)


def _merged_numpy(rows, extra):
    """:func:`_merged` in numpy: the reference and the fallback without numba."""
    count = rows.shape[1]
    rows, extra = _live_first(rows), _live_first(extra)
    fresh = ~np.isnan(extra[..., 0]) & ~_same(extra, rows).any(axis=2)
    earlier = np.tril(_same(extra, extra), k=-1) & fresh[:, None, :]
    fresh &= ~earlier.any(axis=2)
    both = _live_first(np.concatenate([rows, np.where(fresh[..., None], extra, np.nan)], axis=1))
    out = np.full((len(rows), count, 6), np.nan)
    out[:, :min(count, both.shape[1])] = both[:, :count]
    return out


def _flange_turn(axis, angle_rad):
    """(4, 4): the turn by `angle_rad` about the flange's `axis` (3,), unit."""
    turn = np.eye(4)
    turn[:3, :3] = matrix_from_axis_angle(axis, angle_rad)
    return turn


#: The turns of :data:`NUDGE_AXES` by :data:`NUDGE_RAD` (computed once: 0.13 ms a call).
_NUDGES = tuple(_flange_turn(axis, NUDGE_RAD) for axis in NUDGE_AXES)


def _nudged_solutions(params, inverse, T_0T):
    """(S, K * len(NUDGE_AXES), 6) rad: the solutions of each pose `T_0T` (S, 4, 4) turned
    by NUDGE_RAD about each of the flange's NUDGE_AXES (first axis's rows first), polished
    back onto the pose; NaN where they do not reproduce it. One search and one polish
    for all turns."""
    turned = np.concatenate([T_0T @ nudge for nudge in _NUDGES])       # (axes * S, 4, 4)
    found = inverse(turned).reshape(len(_NUDGES), len(T_0T), -1, 6)
    return _polished_onto(params, np.concatenate(found, axis=1), T_0T)


def _polished_onto(params, found, T_0T):
    """(S, K, 6) rad: the rows `found` (S, K, 6) polished onto their pose `T_0T` (S, 4, 4);
    NaN where they do not reproduce it."""
    if kernel.available():
        return kernel.polished_onto(params.H, params.P, params.R_6T, found, T_0T, STEPS,
                                    GIVE_UP_STEP, GIVE_UP_TOL, POSITION_TOL_MM,
                                    ROTATION_TOL_RAD, PINV_RCOND)
    return _polished_onto_numpy(params, found, T_0T)


def _polished_onto_numpy(params, found, T_0T):
    """:func:`_polished_onto` in numpy (:func:`polish`): the reference and the fallback
    without numba."""
    flat = found.reshape(-1, 6)
    live = ~np.isnan(flat[:, 0])
    targets = np.repeat(T_0T, found.shape[1], axis=0)
    q_new = np.full_like(flat, np.nan)
    if live.any():
        q_fit, good = polish(params, flat[live], targets[live])
        q_new[np.flatnonzero(live)[good]] = q_fit[good]
    return q_new.reshape(found.shape)


def solve(params, search, T_0T, rows, screened_search=None, aligned=None):
    """Every solution: the search's, with what it misses next to an alignment (the module).

    Parameters
    ----------
    params : poe.ChainParameters
    search : callable
        The search, ``(N, 4, 4) -> (N, rows, 6)`` rad.
    T_0T : ndarray, shape (N, 4, 4)
        Flange poses, mm.
    rows : int
        Rows per pose.
    screened_search : callable, optional
        The search and :func:`screened`'s screening in one pass, ``T_0T -> (q, upright,
        suspects)`` or None where it cannot (offset_wrist.inverse_screened with
        :func:`screen_vector`).
    aligned : ndarray, shape (0,) or (2,), optional
        :func:`aligned_q4_rad` of `params` where the caller keeps it (it costs 0.05 ms a
        call, as much as the search of one pose).

    Returns
    -------
    ndarray, shape (N, rows, 6)
        rad, wrapped into (-pi, pi], NaN rows last.
    """
    if aligned is None:
        aligned = aligned_q4_rad(params)
    if len(aligned) == 0:
        return search(T_0T)
    found = screened_search(T_0T) if screened_search is not None else None
    q, standing, suspects = found or screened(params, search, T_0T, rows, aligned)
    for poses in _chunks(np.flatnonzero(standing)):
        q[poses] = _merged(q[poses], _polished_onto(params, _upright_rows(params, T_0T[poses],
                                                                          aligned), T_0T[poses]))
    for poses in _chunks(suspects):
        q[poses] = _merged(q[poses], _nudged_solutions(params, search, T_0T[poses]))
    return q


def screened(params, search, T_0T, rows, aligned):
    """The search's rows and the poses to repair.

    Returns
    -------
    q_rad : ndarray, shape (N, rows, 6)
        The search's; NaN on poses upright to rounding (:data:`SEARCH_FREE_DEG`) where
        the closed forms hold every solution (:func:`upright_closed`): not searched.
    upright : ndarray of bool, shape (N,)
        :func:`upright`.
    suspects : ndarray of int, shape (S,)
        Poses :func:`suspect`, neither upright nor :func:`beyond_reach`.
    """
    standing = upright(params, T_0T)
    q = np.full((len(T_0T), rows, 6), np.nan)
    searched = np.arange(len(T_0T))
    if upright_closed(params):
        searched = np.flatnonzero(~upright(params, T_0T, SEARCH_FREE_DEG))
    if len(searched):
        q[searched] = search(T_0T[searched])
    suspects = np.flatnonzero(~standing & suspect(q, aligned)
                              & ~beyond_reach(params, T_0T))
    return q, standing, suspects


def screen_vector(params):
    """:func:`screened`'s numbers for the compiled pass (offset_wrist_kernel.SCREEN names).

    Returns
    -------
    ndarray, shape (offset_wrist_kernel.N_SCREEN,)
    """
    aligned = aligned_q4_rad(params)
    v = np.zeros(search_kernel.N_SCREEN)
    v[search_kernel.FREE_SIN] = np.sin(np.radians(SEARCH_FREE_DEG)) if upright_closed(params) \
        else -1.0
    v[search_kernel.UPRIGHT_SIN] = v[search_kernel.SUSPECT_SIN] = np.sin(np.radians(SUSPECT_DEG))
    v[search_kernel.N_ALIGNED] = len(aligned)
    v[search_kernel.ALIGNED:search_kernel.ALIGNED + len(aligned)] = aligned
    v[search_kernel.BASE:search_kernel.BASE + 3] = params.P[0]
    v[search_kernel.FLANGE:search_kernel.FLANGE + 3] = params.R_6T.T @ params.P[6]
    v[search_kernel.LINKS] = np.linalg.norm(np.asarray(params.P, float)[1:6], axis=1).sum() + 1e-6
    return v


def upright_closed(params):
    """True when every solution of a pose with axis 6 upright is one of the two closed
    forms' (:func:`upright_solutions`, :func:`axis4_upright_solutions`): axes 1 and 2, 4
    and 5, 5 and 6 perpendicular. Then with axis 6 upright, axes 2 and 5 both lie across
    it: either parallel (the alignment) or not, and then axis 4, perpendicular to both,
    is upright."""
    h1, h2, _, h4, h5, h6 = np.asarray(params.H, float)
    return max(abs(h1 @ h2), abs(h4 @ h5), abs(h5 @ h6)) < PERPENDICULAR_TOL


def _upright_rows(params, T_0T, aligned):
    """(S, 8 or 16, 6) rad: the closed forms' rows of upright poses (both where they
    hold every solution, else the aligned one beside the search's)."""
    found = upright_solutions(params, T_0T, aligned)
    if upright_closed(params):
        found = np.concatenate([found, axis4_upright_solutions(params, T_0T)], axis=1)
    return found


def _chunks(poses):
    """`poses` (indices) in pieces of at most :data:`CHUNK_POSES`."""
    return (poses[start:start + CHUNK_POSES] for start in range(0, len(poses), CHUNK_POSES))
