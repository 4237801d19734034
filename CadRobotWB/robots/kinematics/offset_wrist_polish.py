"""The offset-wrist solutions the one-dimensional search cannot see, found next door.

The search of :mod:`.offset_wrist` builds axis 4 as the direction across axis 2 and
axis 5. Where those two are parallel (joint 4 at the value :func:`aligned_q4_rad`
gives, 0 or 180 degrees on the CRX) that direction is undefined, and a solution lying
there is missed. Two common kinds of pose have such solutions:

* the flange's Z parallel to axis 1 (the torch straight down on a straight neck): every
  solution is there, so the search returns none;
* a wrist in the arm's plane (a seam straight ahead of the robot, the torch tilted in
  that plane).

For a pose whose solutions may be missed (:func:`suspect`: no solution, one within
:data:`SUSPECT_DEG` of the aligned joint 4, or axis 6 that close to parallel to axis 1),
the search is run again on the pose turned by :data:`NUDGE_RAD` about each of two fixed
oblique axes of the flange, where the alignment is broken, and every solution found
there is moved back onto the pose by Newton steps on the arm's geometric Jacobian
(:func:`polish`). What reproduces the pose to the search's own tolerances is added.

Measured against the numerical IK (``numeric_ik.solve``, 16 rows) on 24 torch-down poses
each of the CRX-10iA/L, M-430iA/2P, HC10 and CRB 15000, exactly down and 1e-6, 1e-4 and
0.01 degrees off: no solution missed (before: 144, 144, 32 and 8 missed exactly down).
One turn alone still missed 4 of the HC10's, next to its wrist singularity.
This is a repair around the search's blind spot, not a proof of completeness.

Pure numpy: never imports FreeCAD.
"""

import numpy as np

from ...core.rotations import matrix_from_axis_angle
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
#: Solutions this close on every joint (rad, modulo 2 pi) are one.
SAME_RAD = 1e-6


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


def suspect(params, T_0T, q_rad, aligned):
    """(N,) bool: poses with no solution, with one near the aligned joint 4, or with
    axis 6 near parallel to axis 1 (where the solutions lie at the alignment)."""
    small = np.sin(np.radians(SUSPECT_DEG))
    found = ~np.isnan(q_rad[..., 0])
    near = np.zeros(found.shape, bool)
    for a in aligned:
        near |= np.abs(np.sin(q_rad[..., 3] - a)) < small
    h6 = T_0T[:, :3, :3] @ (params.R_6T.T @ params.H[5])
    upright = np.linalg.norm(np.cross(h6, params.H[0]), axis=1) < small
    return ~found.any(axis=1) | (near & found).any(axis=1) | upright


def _errors(params, q, T):
    """(M, 6) position (mm) and rotation (rad) errors of `q` against `T` in the base frame,
    and (M,) bool: the rotation error is under a quarter turn (where the rotation part,
    the axis times the sine of the angle, measures it)."""
    F = poe.fk(params, q)
    E = T[:, :3, :3] @ np.transpose(F[:, :3, :3], (0, 2, 1))
    e_r = 0.5 * np.stack([E[:, 2, 1] - E[:, 1, 2], E[:, 0, 2] - E[:, 2, 0],
                          E[:, 1, 0] - E[:, 0, 1]], axis=1)
    near = np.trace(E, axis1=1, axis2=2) > 1.0
    return np.hstack([T[:, :3, 3] - F[:, :3, 3], e_r]), near, F


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
    """Newton steps moving joint sets onto their poses.

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
    for step in range(STEPS):
        e, near, F = _errors(params, q, T_0T)
        size = np.maximum(np.abs(e[:, :3]).max(axis=1) / POSITION_TOL_MM,
                          np.abs(e[:, 3:]).max(axis=1) / ROTATION_TOL_RAD)
        if step >= GIVE_UP_STEP:            # Newton's steps from NUDGE_RAD are there by now
            alive &= near & (size < GIVE_UP_TOL)
        moving = alive & ((size > 0.01) | ~near)
        if not moving.any():
            break
        J = _jacobian(params, q[moving], F[moving, :3, 3])
        q[moving] += (np.linalg.pinv(J, rcond=1e-10) @ e[moving, :, None])[..., 0]  # singular too
    e, near, _ = _errors(params, q, T_0T)
    good = (near & (np.linalg.norm(e[:, :3], axis=1) <= POSITION_TOL_MM)
            & (np.linalg.norm(e[:, 3:], axis=1) <= ROTATION_TOL_RAD) & np.isfinite(q).all(1))
    return _wrap(q), good


def _same(a, b):
    """(S, M, K) bool: rows of `a` (S, M, 6) equal to rows of `b` (S, K, 6), modulo 2 pi."""
    d = np.abs(_wrap(a[:, :, None, :] - b[:, None, :, :])).max(axis=-1)
    return d <= SAME_RAD


def _wrap(angle):
    """Angles (rad) into (-pi, pi]."""
    return np.pi - (np.pi - angle) % (2.0 * np.pi)


def _merged(rows, extra):
    """(S, K, 6): `rows` plus the rows of `extra` (S, M, 6) found neither there nor
    earlier in `extra`, NaN rows last (at most K)."""
    fresh = ~np.isnan(extra[..., 0]) & ~_same(extra, rows).any(axis=2)
    earlier = np.tril(_same(extra, extra), k=-1) & fresh[:, None, :]
    fresh &= ~earlier.any(axis=2)
    both = np.concatenate([rows, np.where(fresh[..., None], extra, np.nan)], axis=1)
    order = np.argsort(np.isnan(both[..., 0]), axis=1, kind="stable")
    return np.take_along_axis(both, order[..., None], axis=1)[:, :rows.shape[1]]


def _nudged_solutions(params, inverse, T_0T, axis):
    """(S, K, 6) rad: the solutions of each pose turned by NUDGE_RAD about the flange's
    `axis`, polished back onto the pose; NaN where they do not reproduce it."""
    nudge = np.eye(4)
    nudge[:3, :3] = matrix_from_axis_angle(axis, NUDGE_RAD)
    found = inverse(T_0T @ nudge)
    flat = found.reshape(-1, 6)
    live = ~np.isnan(flat[:, 0])
    targets = np.repeat(T_0T, found.shape[1], axis=0)
    q_new = np.full_like(flat, np.nan)
    if live.any():
        q_fit, good = polish(params, flat[live], targets[live])
        q_new[np.flatnonzero(live)[good]] = q_fit[good]
    return q_new.reshape(found.shape)


def complete(params, inverse, T_0T, q_rad):
    """Add the solutions the search missed next to an alignment (see the module).

    Parameters
    ----------
    params : poe.ChainParameters
    inverse : callable
        The search, ``(N, 4, 4) -> (N, K, 6)`` rad.
    T_0T : ndarray, shape (N, 4, 4)
    q_rad : ndarray, shape (N, K, 6)
        What the search found for `T_0T`.

    Returns
    -------
    ndarray, shape (N, K, 6)
        rad, NaN rows last.
    """
    aligned = aligned_q4_rad(params)
    if len(aligned) == 0:
        return q_rad
    poses = np.flatnonzero(suspect(params, T_0T, q_rad, aligned))
    if len(poses) == 0:
        return q_rad
    found = [_nudged_solutions(params, inverse, T_0T[poses], axis) for axis in NUDGE_AXES]
    q_new = np.concatenate(found, axis=1)                        # (S, K * axes, 6)
    out = q_rad.copy()
    out[poses] = _merged(q_rad[poses], q_new)
    return out
