"""Closed forms turning a part vector straight down with a positioner's axes.

A positioner of one or two rotary axes turns a vector ``d`` fixed in its flange
{P} to ``R(v) d`` in {U}, with

``R(v) = R_base R_1 Rz(v1) [R_2 Rz(v2)] R_flange``

(``R_k`` the rotation part of axis k's ``T_prev_joint``). Two axes: the two
angles bringing ``d`` onto a wanted direction ``g`` follow from the component
of the intermediate vector along each axis (Paden-Kahan subproblem 2, e.g.
Murray, Li, Sastry, *A Mathematical Introduction to Robotic Manipulation*,
1994, section 3.2): two branches (``+-``), which meet where the intermediate
vector lies in the plane of the two axes; where no exact solution exists the
nearest one is returned. One axis: the angle maximising ``g . R(v) d`` (a
cosine in ``v``), degenerate where the axis is along ``g`` or ``d`` (a vertical
turntable cannot change the gravity angle).

Angles in degrees at this module's surface. Pure numpy: never imports FreeCAD.
"""

import numpy as np

#: Below this (unit vectors' cross-component norms), an angle is free: NaN.
FREE_EPS = 1e-9


def best_angle(h, w):
    """The rotation about Z bringing `w` closest to `h` (maximising ``h . Rz(a) w``).

    Parameters
    ----------
    h, w : ndarray, shape (..., 3)

    Returns
    -------
    angle_deg : ndarray, shape (...)
        NaN where the result does not depend on the angle.
    gain : ndarray, shape (...)
        The amplitude of the cosine (``|h_xy| |w_xy|``): how much the angle matters.
    """
    cos_part = h[..., 0] * w[..., 0] + h[..., 1] * w[..., 1]
    sin_part = h[..., 1] * w[..., 0] - h[..., 0] * w[..., 1]
    gain = np.hypot(cos_part, sin_part)
    angle = np.degrees(np.arctan2(sin_part, cos_part))
    return np.where(gain > FREE_EPS, angle, np.nan), gain


def two_axis_down(R_2, w, g):
    """Both branches of the two angles with ``Rz(v1) R_2 Rz(v2) w = g``.

    Parameters
    ----------
    R_2 : ndarray, shape (3, 3)
        The second joint frame in the first (after ``Rz(v1)``).
    w : ndarray, shape (N, 3)
        The part vector in the second joint frame (after ``Rz(v2)``), unit.
    g : ndarray, shape (3,)
        The wanted direction in the first joint frame (before ``Rz(v1)``), unit.

    Returns
    -------
    ndarray, shape (N, 2, 2)
        ``[branch, (v1, v2)]`` in degrees, branch 0 with ``+gamma``; an angle is
        NaN where it is free (``g`` along axis 1, or ``w`` along axis 2).
    """
    e = np.array([0.0, 0.0, 1.0])
    a2 = R_2[:, 2]
    c = float(a2[2])
    p, q = float(g[2]), w[:, 2]
    sin2 = max(1.0 - c * c, FREE_EPS)
    alpha = (p - c * q) / sin2
    beta = (q - c * p) / sin2
    gamma2 = (1.0 - (alpha ** 2 + beta ** 2 + 2.0 * alpha * beta * c)) / sin2
    gamma = np.sqrt(np.maximum(gamma2, 0.0))
    cross = np.cross(e, a2)
    out = np.empty((len(w), 2, 2))
    for branch, sign in enumerate((1.0, -1.0)):
        u = alpha[:, None] * e + beta[:, None] * a2 + sign * gamma[:, None] * cross
        # Rz(v1) u = g: the angle from u's azimuth to g's.
        v1, _ = best_angle(np.broadcast_to(g, u.shape), u)
        # Rz(v2) w = R_2^T u.
        v2, _ = best_angle(u @ R_2, w)
        out[:, branch, 0], out[:, branch, 1] = v1, v2
    return out


def unwrap_near(angle_deg, reference_deg):
    """`angle_deg` plus the multiple of 360 putting it nearest `reference_deg`."""
    return angle_deg - 360.0 * np.round((angle_deg - reference_deg) / 360.0)


def unwrap_sequence(angle_deg):
    """Angles made continuous along axis 0 (no step above 180 deg); NaN kept.

    Parameters
    ----------
    angle_deg : ndarray, shape (N, ...)

    Returns
    -------
    ndarray, shape (N, ...)
    """
    a = np.array(angle_deg, dtype=float)
    if len(a) < 2:
        return a
    step = np.diff(a, axis=0)
    step = step - 360.0 * np.round(step / 360.0)
    return a[:1] + np.concatenate([np.zeros_like(a[:1]), np.cumsum(step, axis=0)])
