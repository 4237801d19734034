"""Checks of the numbers a user gives or a document holds: finite, in range, rigid.

Every check raises an :class:`~CadRobotWB.errors.InputError` (or the
subclass asked for) whose message names the object and says how to fix
it, never a numpy repr.  Pure Python and numpy: no FreeCAD here, so the
API, the document reader and the CLI share one copy.
"""

import math

import numpy as np

from ..errors import InputError

#: Largest deviation of R^T R from I, and of the last row from (0, 0, 0, 1),
#: that still counts as a rotation and a rigid transform (float round-off of
#: products of a few rotations stays far below it).
RIGID_TOLERANCE = 1e-6


def rigid_problem(T):
    """What keeps `T` from being a rigid transform, or None when it is one.

    Parameters
    ----------
    T : array_like, shape (4, 4)
        Homogeneous transform, mm.

    Returns
    -------
    str or None
        A short phrase ("its rotation block is a mirror (determinant -1)", ...)
        to follow "the placement is not rigid:".
    """
    T = np.asarray(T, dtype=float)
    if T.shape != (4, 4):
        return "it is not a 4x4 matrix (shape %s)" % (T.shape,)
    if not np.isfinite(T).all():
        return "it holds NaN or infinite values"
    if np.abs(T[3] - (0.0, 0.0, 0.0, 1.0)).max() > RIGID_TOLERANCE:
        return "its last row is %s, not 0 0 0 1" % " ".join("%g" % v for v in T[3])
    R = T[:3, :3]
    lengths = np.linalg.norm(R, axis=0)
    if lengths.min() < RIGID_TOLERANCE:
        return "its rotation block has a zero column"
    if np.abs(lengths - 1.0).max() > RIGID_TOLERANCE:
        return "its rotation block scales (column lengths %s, not 1)" % ", ".join(
            "%.6g" % v for v in lengths)
    if np.abs(R.T @ R - np.eye(3)).max() > RIGID_TOLERANCE:
        return "its rotation block shears (columns not perpendicular)"
    if np.linalg.det(R) < 0:
        return "its rotation block is a mirror (determinant -1)"
    return None


def check_rigid(T, what, error=InputError, obj_name=None, placement="placement"):
    """Return `T` as a float (4, 4) array if it is rigid, else raise.

    Parameters
    ----------
    T : array_like, shape (4, 4)
    what : str
        Names the object, e.g. ``"Tool marker 'ToolMarker'"``.
    error : type
        The InputError subclass to raise.
    obj_name : str, optional
        Internal name of the object at fault.
    placement : str
        What the transform is to the object (``"robot base placement"``).
    """
    problem = rigid_problem(T)
    if problem is not None:
        raise error("%s: the %s is not a rigid transform: %s. Give a rotation (orthonormal, "
                    "determinant +1) and a translation in mm." % (what, placement, problem), obj_name)
    return np.asarray(T, dtype=float)


def finite_values(values, what, error=InputError, obj_name=None):
    """Return `values` (floats) if every one is finite, else raise naming `what`.

    Parameters
    ----------
    values : float or sequence of float
    what : str
        Names the object and property, e.g. ``"Tool marker 'M' origin"``.
    """
    numbers = np.atleast_1d(np.asarray(values, dtype=float)).ravel()
    bad = np.flatnonzero(~np.isfinite(numbers))
    if bad.size:
        where = "" if numbers.size == 1 else " (value %d of %d)" % (bad[0] + 1, numbers.size)
        raise error("%s is not finite: %s%s; give real numbers, not NaN or infinity."
                    % (what, "%g" % numbers[bad[0]], where), obj_name)
    return values


def number_in_range(value, what, low=-math.inf, high=math.inf, low_open=False, error=InputError):
    """`value` as a float if finite and in [low, high] ((low, high] with `low_open`), else raise.

    Parameters
    ----------
    value : float or str
    what : str
        Names the option or property, e.g. ``"--rate"``.
    """
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise error("%s must be a number, not %r." % (what, value)) from None
    too_low = number <= low if low_open else number < low
    if not math.isfinite(number) or too_low or number > high:
        raise error("%s must be a finite number %s, not %r." % (what, range_text(low, high, low_open),
                                                                 value))
    return number


def whole_in_range(value, what, low, high=math.inf, error=InputError):
    """`value` as an int if it is a whole number in [low, high] (2 and 2.0 are, True
    and 2.5 are not), else raise naming `what`."""
    try:
        number = None if isinstance(value, (bool, str)) else float(value)
    except (TypeError, ValueError):
        number = None
    if number is None or not number.is_integer() or not low <= number <= high:
        raise error("%s must be a whole number %s, not %r." % (what, range_text(low, high, False), value))
    return int(number)


def range_text(low, high, low_open):
    """``">= 0 and <= 10"``: the bounds of a range in words (``"(not NaN or infinity)"`` for none)."""
    parts = []
    if low > -math.inf:
        parts.append("%s %s" % (">" if low_open else ">=", _shown(low)))
    if high < math.inf:
        parts.append("<= %s" % _shown(high))
    return " and ".join(parts) if parts else "(not NaN or infinity)"


def _shown(value):
    return "%d" % value if float(value).is_integer() and abs(value) < 1e16 else "%g" % value
