"""Canonical subproblems of IK-Geo, vectorised over poses.

A. J. Elias, J. T. Wen, "IK-Geo: Unified robot inverse kinematics using subproblem
decomposition", Mechanism and Machine Theory 209, 2025 (arXiv:2211.05737, section 3).
``rot(k, theta)`` is the rotation by ``theta`` about the unit axis ``k`` (right hand):

* SP1: ``rot(k, theta) p1 = p2``                      -> one theta;
* SP3: ``|| p2 - rot(k, theta) p1 || = d``            -> up to two;
* SP4: ``h . rot(k, theta) p = d``                    -> up to two;
  :func:`sp4_unit` is SP4 for unit vectors with ``d = h . x``, solved through half angles
  so that it stays exact at its double root (a wrist singularity).

Every function broadcasts over leading axes: vectors are ``(..., 3)``, axes ``(3,)`` or
``(..., 3)``, scalars ``(...)``.  A root that does not exist is reported in the mask
``valid``; its angle is then the least-squares one (as IK-Geo's), always finite.

Pure numpy: never imports FreeCAD.
"""

import numpy as np

#: SP3/SP4 equations whose cosine lands this far beyond +-1 (rounding at the edge of
#: reach) are clipped to a double root; further out there is no root.
COS_TOLERANCE = 1e-12

#: SP1 with ``|k x p1|`` at or below this times ``|p1|`` has no unique angle (p1 lies on
#: the axis).
DEGENERATE_NORM = 1e-14


def rotate(k, theta, v):
    """``rot(k, theta) v`` (Rodrigues).

    Parameters
    ----------
    k : array_like, shape (3,) or (..., 3)
        Unit axis.
    theta : array_like, shape (...)
        Radians.
    v : array_like, shape (..., 3)

    Returns
    -------
    ndarray, shape (..., 3)
    """
    k = np.asarray(k, dtype=float)
    v = np.asarray(v, dtype=float)
    c = np.cos(theta)[..., None]
    s = np.sin(theta)[..., None]
    along = np.sum(k * v, axis=-1, keepdims=True) * k
    return c * v + s * np.cross(k, v) + (1.0 - c) * along


def sp1(p1, p2, k):
    """Subproblem 1: the angle that turns ``p1`` onto ``p2`` about ``k``.

    Least squares when no exact angle exists (the components along ``k`` or the
    lengths differ).

    Parameters
    ----------
    p1, p2 : array_like, shape (..., 3)
    k : array_like, shape (3,) or (..., 3)
        Unit axis.

    Returns
    -------
    theta : ndarray, shape (...)
        Radians in [-pi, pi]; 0 where ``p1`` lies on the axis.
    valid : ndarray of bool, shape (...)
        False where ``p1`` lies on the axis (every angle fits): ``|k x p1|`` at most
        :data:`DEGENERATE_NORM` times ``|p1|``.
    """
    k_x_p1 = np.cross(k, p1)
    p1_perp = -np.cross(k, k_x_p1)
    theta = np.arctan2(np.sum(k_x_p1 * p2, axis=-1), np.sum(p1_perp * p2, axis=-1))
    valid = np.linalg.norm(k_x_p1, axis=-1) > DEGENERATE_NORM * np.linalg.norm(p1, axis=-1)
    return np.where(valid, theta, 0.0), valid


def sp4(h, p, k, d):
    """Subproblem 4: the angles with ``h . rot(k, theta) p = d``.

    Parameters
    ----------
    h, p : array_like, shape (3,) or (..., 3)
        ``h`` need not be a unit vector.
    k : array_like, shape (3,) or (..., 3)
        Unit axis.
    d : array_like, shape (...)

    Returns
    -------
    theta : ndarray, shape (..., 2)
        The two roots, radians (equal at a double root; where there is no root, both
        are the angle that brings ``h . rot(k, theta) p`` nearest to d).
    valid : ndarray of bool, shape (...)
        False where ``|cos| > 1 +`` :data:`COS_TOLERANCE` (no root) or ``h . rot(k,
        theta) p`` does not depend on theta.
    """
    h = np.asarray(h, dtype=float)
    k_x_p = np.cross(k, p)
    a_sin = np.sum(h * k_x_p, axis=-1)                         # h . (k x p)
    a_cos = -np.sum(h * np.cross(k, k_x_p), axis=-1)           # h . p_perp
    b = d - np.sum(k * p, axis=-1) * np.sum(h * k, axis=-1)
    amplitude = np.hypot(a_sin, a_cos)
    with np.errstate(invalid="ignore", divide="ignore"):
        cosine = b / amplitude
    valid = (np.abs(cosine) <= 1.0 + COS_TOLERANCE) & (amplitude > 0.0)
    spread = np.arccos(np.clip(np.where(amplitude > 0.0, cosine, 0.0), -1.0, 1.0))
    phase = np.arctan2(a_sin, a_cos)
    return np.stack([phase + spread, phase - spread], axis=-1), valid


def _norm(v):
    return np.linalg.norm(v, axis=-1)


def sp4_unit(h, p, k, x):
    """Subproblem 4 for unit vectors: the angles with ``h . rot(k, theta) p = h . x``.

    ``theta = phase +- spread`` as in :func:`sp4`, but ``spread`` comes from the angles
    alpha = (h, k), beta = (k, p) and theta_x = (h, x), each from its half angle
    (``sin(a / 2) = |u - v| / 2`` for unit u, v): with
    ``u = sin((theta_x + alpha - beta) / 2) sin((theta_x - alpha + beta) / 2)`` and
    ``v = sin((alpha + beta + theta_x) / 2) sin((alpha + beta - theta_x) / 2)``,
    ``cos(spread) = (v - u) / (u + v)`` and ``sin(spread) = 2 sqrt(u v) / (u + v)``.
    At a double root (u or v = 0) the spread is then exact to rounding, where the cosine
    form of :func:`sp4` leaves ``sqrt(2e-16) = 1.5e-8`` rad.

    Parameters
    ----------
    h, p, k : array_like, shape (3,) or (..., 3)
        Unit vectors; ``k`` the axis.
    x : array_like, shape (..., 3)
        Unit vector.

    Returns
    -------
    theta : ndarray, shape (..., 2)
    valid : ndarray of bool, shape (...)
        As :func:`sp4` (the least-squares angle where there is no root).
    """
    h, p, k, x = (np.asarray(v, dtype=float) for v in (h, p, k, x))
    k_x_p = np.cross(k, p)
    phase = np.arctan2(np.sum(h * k_x_p, axis=-1), -np.sum(h * np.cross(k, k_x_p), axis=-1))
    sin_d, cos_d, sin_e, cos_e = half_angle_sums(h, k, p)
    sin_x, cos_x = 0.5 * _norm(h - x), 0.5 * _norm(h + x)
    u = (sin_x * cos_d + cos_x * sin_d) * (sin_x * cos_d - cos_x * sin_d)
    v = (sin_e * cos_x + cos_e * sin_x) * (sin_e * cos_x - cos_e * sin_x)
    total = u + v                                           # sin(alpha) sin(beta)
    valid = (np.minimum(u, v) >= -COS_TOLERANCE * total) & (total > 0.0)
    spread = np.arctan2(2.0 * np.sqrt(np.maximum(u, 0.0) * np.maximum(v, 0.0)), v - u)
    return np.stack([phase + spread, phase - spread], axis=-1), valid


def half_angle_sums(h, k, p):
    """sin and cos of (alpha - beta) / 2 and of (alpha + beta) / 2, alpha = angle (h, k),
    beta = angle (k, p), for unit vectors (see :func:`sp4_unit`)."""
    sin_a, cos_a = 0.5 * _norm(h - k), 0.5 * _norm(h + k)
    sin_b, cos_b = 0.5 * _norm(k - p), 0.5 * _norm(k + p)
    return (sin_a * cos_b - cos_a * sin_b, cos_a * cos_b + sin_a * sin_b,
            sin_a * cos_b + cos_a * sin_b, cos_a * cos_b - sin_a * sin_b)


def sp3(p1, p2, k, d):
    """Subproblem 3: the angles with ``|| p2 - rot(k, theta) p1 || = d``.

    Squared, it is SP4 with ``h = p2``: ``p2 . rot(k, theta) p1 = (|p1|^2 + |p2|^2 - d^2) / 2``.

    Parameters
    ----------
    p1, p2 : array_like, shape (..., 3)
    k : array_like, shape (3,) or (..., 3)
        Unit axis.
    d : array_like, shape (...)
        Distance, >= 0.

    Returns
    -------
    theta : ndarray, shape (..., 2)
    valid : ndarray of bool, shape (...)
        As :func:`sp4`.
    """
    p1 = np.asarray(p1, dtype=float)
    p2 = np.asarray(p2, dtype=float)
    d = np.asarray(d, dtype=float)
    half = 0.5 * (np.sum(p1 * p1, axis=-1) + np.sum(p2 * p2, axis=-1) - d * d)
    return sp4(p2, p1, k, half)
