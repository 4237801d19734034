"""Closed-form kinematics of Universal Robots arms (UR3/UR5/UR10, e-Series too).

A UR arm is not an OPW robot: its wrist is not spherical (the three wrist axes
do not meet in one point), so it has its own closed form.  The model is UR's
published standard Denavit-Hartenberg table (``Rz(theta) Tz(d) Tx(a) Rx(alpha)``
per joint, ``theta = q``: UR's own arms have no offsets; an arm imported from a
URDF may have ``theta = q * sign - offset``, see ``URParameters``) with::

    a     = [0, a2, a3, 0, 0, 0]           (a2, a3 < 0 on every UR)
    d     = [d1, 0, 0, d4, d5, d6]
    alpha = [pi/2, 0, 0, pi/2, -pi/2, 0]

Frame 0 is the controller's ``base`` frame and frame 6 the tool flange, so
:func:`forward` gives the flange pose a URScript ``get_actual_tool_flange_pose()``
reports (in mm, not m).  The inverse follows the classic derivation
(K. P. Hawkins, "Analytic inverse kinematics for the Universal Robots UR-5/UR-10
arms", 2013), written for arrays of poses.

Branch order (rows of :func:`inverse`): ``row = 4 * shoulder + 2 * wrist + elbow``
with ``shoulder`` selecting ``theta1 = phi + asin(d4/r)`` (0) or
``phi + 180 - asin(d4/r)`` (1), ``wrist`` selecting ``theta5 >= 0`` (0) or
``theta5 <= 0`` (1), ``elbow`` selecting ``theta3 >= 0`` (0) or ``theta3 <= 0`` (1).

Pure numpy: never imports FreeCAD.
"""

import numpy as np

from .dh import dh_transforms
from .opw import safe_arccos, wrap_deg

#: Below this |sin(theta5)| the wrist is singular (axes 2, 3, 4 and 6
#: parallel): theta6 is chosen, not computed (see :func:`_singular_theta6`).
WRIST_SINGULAR_SIN = 1e-12

_ALPHA = np.array([np.pi / 2, 0.0, 0.0, np.pi / 2, -np.pi / 2, 0.0])


def _lengths(params):
    a = np.array([0.0, params.a2, params.a3, 0.0, 0.0, 0.0])
    d = np.array([params.d1, 0.0, 0.0, params.d4, params.d5, params.d6])
    return a, d


def _invert(T):
    """Inverse of rigid transforms (..., 4, 4): ``[[R^T, -R^T p], [0, 1]]``."""
    Ti = np.zeros_like(T)
    Rt = np.swapaxes(T[..., :3, :3], -1, -2)
    Ti[..., :3, :3] = Rt
    Ti[..., :3, 3] = -(Rt @ T[..., :3, 3:4])[..., 0]
    Ti[..., 3, 3] = 1.0
    return Ti


def _joint(params, i, theta_rad):
    a, d = _lengths(params)
    return dh_transforms(a[i], _ALPHA[i], d[i], theta_rad)


def _singular_theta6(p, T, theta1):
    """theta6 where sin(theta5) = 0, (N, 2, 2); the last axis is the wrist branch.

    Axes 2, 3, 4 and 6 are then parallel and theta6 is free, but it decides
    where frame 4's origin lies: on a circle of radius d5 about frame 5's
    origin, in the arm plane (``z4 = -(s6 X + c6 Y)``).  theta6 is chosen so
    that this origin is at mid-reach of the planar arm (|a2| + |a3|) / 2 from
    joint 2 (or as near as the circle allows), on either side of the circle
    for the two wrist branches, so a reachable pose gets a solution.
    """
    s1, c1 = np.sin(theta1), np.cos(theta1)  # (N, 2)
    X, Y, Z = T[:, None, :3, 0], T[:, None, :3, 1], T[:, None, :3, 2]
    p05 = T[:, None, :3, 3] - p.d6 * Z

    def in_plane(v, z=0.0):  # x and y of frame 1 (x1 = (c1, s1, 0), y1 = base z)
        return c1 * v[..., 0] + s1 * v[..., 1], v[..., 2] - z

    px, py = in_plane(p05, p.d1)
    r = np.hypot(px, py)
    mid = 0.5 * (abs(p.a2) + abs(p.a3))
    with np.errstate(invalid="ignore", divide="ignore"):
        psi = np.arccos(np.clip((r * r + p.d5 * p.d5 - mid * mid) / (2.0 * p.d5 * r), -1.0, 1.0))
    psi = np.stack([psi, -psi], axis=2)                     # (N, 2, 2)
    angle = np.arctan2(py, px)[..., None] + psi             # direction of z4 in the plane
    ux, uy = np.cos(angle), np.sin(angle)
    Xx, Xy = in_plane(X)
    Yx, Yy = in_plane(Y)
    return np.arctan2(-(ux * Xx[..., None] + uy * Xy[..., None]),
                      -(ux * Yx[..., None] + uy * Yy[..., None]))


def forward(params, q_deg):
    """Flange pose of a UR arm.

    Parameters
    ----------
    params : URParameters
        ``d1, a2, a3, d4, d5, d6`` in mm.
    q_deg : array_like, shape (N, 6) or (6,)
        Joint values in degrees, as on the teach pendant.

    Returns
    -------
    T_r_f : ndarray, shape (N, 4, 4) or (4, 4)
        Flange frame {F} in the controller's base frame {R}, mm.
    """
    q_deg = np.asarray(q_deg, dtype=float)
    single = q_deg.ndim == 1
    q_deg = np.atleast_2d(q_deg)
    if q_deg.shape[-1] != 6:
        raise ValueError("q_deg must have shape (N, 6), got %s" % (q_deg.shape,))
    q = np.radians(q_deg) * np.asarray(params.signs) - np.radians(params.offsets_deg)
    T_r_f = _joint(params, 0, q[:, 0])
    for i in range(1, 6):
        T_r_f = T_r_f @ _joint(params, i, q[:, i])
    return T_r_f[0] if single else T_r_f


def inverse(params, T_r_f):
    """All eight closed-form inverse kinematic solutions of a UR arm.

    Parameters
    ----------
    params : URParameters
        ``d1, a2, a3, d4, d5, d6`` in mm.
    T_r_f : array_like, shape (N, 4, 4) or (4, 4)
        Flange poses in the base frame, mm (proper rotation matrices).

    Returns
    -------
    q_deg : ndarray, shape (N, 8, 6) or (8, 6)
        Joint values in degrees, each in (-180, 180]; row order in the module
        docstring; a row is all NaN where that branch does not exist.  At a
        wrist singularity (theta5 = 0 or 180 deg) theta6 is free; it is
        chosen so the planar arm reaches (see ``_singular_theta6``) and every
        row still reproduces the pose.
    """
    T = np.asarray(T_r_f, dtype=float)
    single = T.ndim == 2
    T = T.reshape((-1, 4, 4))
    n = T.shape[0]
    p = params
    X, Y, Z = T[:, :3, 0], T[:, :3, 1], T[:, :3, 2]
    p06 = T[:, :3, 3]

    # theta1: frame 5's origin lies d4 off the arm plane, along z1 = (s1, -c1, 0).
    p05 = p06 - p.d6 * Z
    r = np.hypot(p05[:, 0], p05[:, 1])
    phi = np.arctan2(p05[:, 1], p05[:, 0])
    with np.errstate(invalid="ignore", divide="ignore"):
        lean = np.pi / 2 - safe_arccos(p.d4 / r)  # asin(d4 / r), NaN inside the d4 cylinder
    theta1 = np.stack([phi + lean, phi + np.pi - lean], axis=1)  # (N, 2)
    s1, c1 = np.sin(theta1), np.cos(theta1)

    # theta5 and theta6: z1 = (s1, -c1, 0) seen from the flange is (s5 c6, -s5 s6, c5).
    # (z1 . Z = c5 is Hawkins' (z1 . p06 - d4) / d6, as theta1 puts z1 . p05 = d4,
    # but the atan2 form stays accurate where theta5 -> 0.)
    z1_x = X[:, None, 0] * s1 - X[:, None, 1] * c1  # (N, 2)
    z1_y = Y[:, None, 0] * s1 - Y[:, None, 1] * c1
    z1_z = Z[:, None, 0] * s1 - Z[:, None, 1] * c1
    sin5_abs = np.hypot(z1_x, z1_y)
    theta5_abs = np.arctan2(sin5_abs, z1_z)
    theta5 = np.stack([theta5_abs, -theta5_abs], axis=2)  # (N, 2, 2)
    theta6_pos = np.arctan2(-z1_y, z1_x)
    theta6 = np.stack([theta6_pos, theta6_pos + np.pi], axis=2)  # s5 < 0 turns theta6 by 180
    singular = (sin5_abs < WRIST_SINGULAR_SIN)[..., None]
    if singular.any():
        theta6 = np.where(singular, _singular_theta6(p, T, theta1), theta6)

    # Frame 4 in frame 1: T14 = T01^-1 T06 T56^-1 T45^-1; the planar 2R arm gives theta2, theta3.
    T01 = _joint(p, 0, theta1)[:, :, None]                    # (N, 2, 1, 4, 4)
    T45 = _joint(p, 4, theta5)                                # (N, 2, 2, 4, 4)
    T56 = _joint(p, 5, theta6)
    T14 = _invert(T01) @ T[:, None, None] @ _invert(T56) @ _invert(T45)
    x, y = T14[..., 0, 3], T14[..., 1, 3]
    with np.errstate(invalid="ignore"):
        theta3_abs = safe_arccos((x * x + y * y - p.a2 * p.a2 - p.a3 * p.a3) / (2.0 * p.a2 * p.a3))
    theta3 = np.stack([theta3_abs, -theta3_abs], axis=3)      # (N, 2, 2, 2)
    theta2 = (np.arctan2(y, x)[..., None]
              - np.arctan2(p.a3 * np.sin(theta3), p.a2 + p.a3 * np.cos(theta3)))
    theta234 = np.arctan2(T14[..., 1, 0], T14[..., 0, 0])[..., None]
    theta4 = theta234 - theta2 - theta3

    q = np.empty((n, 2, 2, 2, 6))
    q[..., 0] = theta1[:, :, None, None]
    q[..., 1] = theta2
    q[..., 2] = theta3
    q[..., 3] = theta4
    q[..., 4] = theta5[..., None]
    q[..., 5] = theta6[..., None]
    q_deg = wrap_deg((np.degrees(q.reshape(n, 8, 6)) + params.offsets_deg) * np.asarray(params.signs))
    q_deg[np.isnan(q_deg).any(axis=-1)] = np.nan
    return q_deg[0] if single else q_deg
