"""Position and orientation interpolation in risk areas (eqs 8-15).

Positions along a straight section ``[P_j, P_j+1]`` are generated at the
constant profiling speed ``|v|`` every sampling width ``Δt`` (eqs 8-13), i.e.
``step = |v| · Δt`` apart; orientations are slerped (eqs 14-15).

Lengths in mm, speeds in mm/s, times in s.  Pure numpy: no FreeCAD, no scipy.
"""

import math

import numpy as np

from ..errors import InputError
from .rotations import quaternion_slerp

# L / step within this (relative) of a whole number counts as that number, so
# that rounding in e.g. 30.1 / 4.3 does not add a last interval of ~1e-15 mm.
_REL_TOL = 1e-9


def _require_positive(value, name):
    if not (np.isfinite(value) and value > 0):
        raise InputError(f"{name} must be a positive number, got {value!r}.")


def stations(length_mm, step_mm):
    """Arc-length stations ``0, step, 2·step, …, length`` along a section.

    Parameters
    ----------
    length_mm : float
        Length of the section, mm, >= 0.
    step_mm : float
        Spacing, mm, > 0.

    Returns
    -------
    s : ndarray, shape (n + 1,)
        Stations in mm with ``n = ceil(length / step)``: all intervals equal
        ``step`` except the last, which is the remainder (``0 < last <= step``).
        ``[0.0]`` for a zero length.

    Raises
    ------
    CadRobotWB.errors.InputError
        If ``step_mm <= 0`` or ``length_mm < 0``.
    """
    _require_positive(step_mm, "Interpolation step (mm)")
    if not (np.isfinite(length_mm) and length_mm >= 0):
        raise InputError(f"Section length must be zero or positive (mm), got {length_mm!r}.")
    n = math.ceil(length_mm / step_mm * (1.0 - _REL_TOL))
    return np.append(step_mm * np.arange(n), float(length_mm))


def interpolate_positions(p_j, p_j1, speed_mm_s, dt_s):
    """Positions from ``P_j`` to ``P_j+1`` at constant speed, eqs 8-13.

    ``W = P_j+1 - P_j`` (eq 9), ``v = |v| · W / |W|`` (eq 10),
    ``r(0) = P_j`` (eq 11), ``r(k) = P_j + v · k · Δt`` for
    ``k = 1 … n-1`` (eq 13) and ``r(n) = P_j+1`` (eq 12), with
    ``n = ceil(|W| / (|v| Δt))``, so the last interval may be shorter.

    Parameters
    ----------
    p_j, p_j1 : array_like, shape (3,)
        Start and end points ``P_j`` and ``P_j+1``, mm.
    speed_mm_s : float
        Profiling speed ``|v|``, mm/s, > 0.
    dt_s : float
        Sampling width ``Δt``, s, > 0.

    Returns
    -------
    r : ndarray, shape (n + 1, 3)
        Interpolated positions, mm; ``r[0]`` and ``r[-1]`` are exactly
        ``P_j`` and ``P_j+1``.

    Raises
    ------
    CadRobotWB.errors.InputError
        If the speed or the sampling width is not positive, or the two
        points coincide (eq 10 needs a direction).
    """
    _require_positive(speed_mm_s, "Profiling speed (mm/s)")
    _require_positive(dt_s, "Sampling time (s)")
    p_j = np.asarray(p_j, dtype=float)
    p_j1 = np.asarray(p_j1, dtype=float)
    W = p_j1 - p_j                                      # eq 9
    length = np.linalg.norm(W)
    if length == 0.0:
        raise InputError(
            f"Cannot interpolate between coincident points {p_j.tolist()}: "
            "the section has no direction.")
    v = speed_mm_s * W / length                         # eq 10
    n = len(stations(length, speed_mm_s * dt_s)) - 1
    k = np.arange(n + 1)
    r = p_j + np.outer(k * dt_s, v)                     # eq 13
    r[0] = p_j                                          # eq 11
    r[-1] = p_j1                                        # eq 12
    return r


def interpolate_orientations(q0, qn, fractions):
    """Orientations slerped from ``Q_0`` to ``Q_n`` (eqs 14-15).

    The paper's eq 14 uses the fraction ``(k-1)/(n-1)``; here the caller
    gives the fractions (e.g. arc length travelled / risk-area length).

    Parameters
    ----------
    q0, qn : array_like, shape (4,)
        Unit quaternions ``(w, x, y, z)`` at the start and end of the area.
    fractions : array_like, shape (N,)
        Interpolation parameters in [0, 1].

    Returns
    -------
    q : ndarray, shape (N, 4)
        Unit quaternions, taking the short way from ``q0`` to ``qn``.
    """
    return quaternion_slerp(q0, qn, np.atleast_1d(np.asarray(fractions, dtype=float)))
