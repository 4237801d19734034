"""The stated limits of every count and size a user gives, and their checks.

One place for the ranges of the numbers that decide how much work a command
does (sweep runs, worker processes, Place robot's region, heights, turns and
placements, correction rates, seeds).  The CLI's options and the
scripting API check the same limits here, before any work starts; a value
out of range is an :class:`~CadRobotWB.errors.InputError` of one line naming
the option or argument and the range allowed.  The README's command line
section lists them.  No FreeCAD and no numpy at import: the CLI builds its
parser from these constants before it can say that a package is missing.
"""

import math
import os

from .errors import InputError

#: Most runs of one sweep: about an hour on one core for a 200 mm seam (0.4 s a
#: run); 10,000 runs measure a success rate within about 1 %.
MAX_SWEEP_RUNS = 10_000
#: Slowest correction rate of a sensor run, Hz (one correction every 10 s; the
#: Sensor run panel's lowest).  The fastest is the sensor's own (1 / its time step).
MIN_RATE_HZ = 0.1
#: Largest coordinate of Place robot's region and height range, mm (1 km either way,
#: the Place robot panel's range).
MAX_COORDINATE_MM = 1e6
#: Largest turn of Place robot's turn range, degrees either way (one full turn).
MAX_TURN_DEG = 360.0
#: Most placements one search finds (each one passes a full check; the panel's most).
MAX_PLACEMENTS = 100
#: Largest seed of the random numbers (noise, roughness, deviations).
MAX_SEED = 2 ** 31 - 1


def _validate():
    """:mod:`.objects.validate`, imported when a check runs (it needs numpy)."""
    from .objects import validate
    return validate


def cores():
    """int: the cores this process may run on (the most local worker processes)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):          # not Linux
        return max(1, os.cpu_count() or 1)


def workers(value, what="workers"):
    """`value` (None: every core) as an int in 1..:func:`cores`, else InputError naming `what`."""
    if value is None:
        return None
    most = cores()
    try:
        return _validate().whole_in_range(value, what, 1, most)
    except InputError:
        raise InputError("%s must be a whole number >= 1 and <= %d (the cores of this computer: "
                         "more processes only share them and need more memory), not %r."
                         % (what, most, value)) from None


def sweep_runs(value, what="runs"):
    """`value` as an int in 1..:data:`MAX_SWEEP_RUNS`, else InputError naming `what`."""
    return _validate().whole_in_range(value, what, 1, MAX_SWEEP_RUNS)


def placements(value, what="count"):
    """`value` as an int in 1..:data:`MAX_PLACEMENTS`, else InputError naming `what`."""
    return _validate().whole_in_range(value, what, 1, MAX_PLACEMENTS)


def rate_hz(value, what, highest):
    """`value` as a float in [:data:`MIN_RATE_HZ`, `highest`] Hz, else InputError naming `what`."""
    return _validate().number_in_range(value, what, MIN_RATE_HZ, highest)


def seed(value, what="seed"):
    """`value` as an int in 0..:data:`MAX_SEED`, else InputError naming `what`."""
    return _validate().whole_in_range(value, what, 0, MAX_SEED)


def numbers_within(values, what, bound, unit):
    """`values` (floats) if each is finite and within +-`bound`, else InputError naming `what`.

    Parameters
    ----------
    values : sequence of float
    what : str
        The option or argument, e.g. ``"the region (xmin, ymin, xmax, ymax)"``.
    bound : float
    unit : str
        ``"mm"`` or ``"deg"``, for the message.
    """
    try:
        values = list(values)
    except TypeError:                     # one number: its count is checked where it is used
        values = [values]
    numbers = []
    for value in values:
        try:
            numbers.append(float(value))
        except (TypeError, ValueError):
            numbers.append(math.nan)
    if not all(math.isfinite(v) and abs(v) <= bound for v in numbers):
        raise InputError("%s must hold numbers %s %s, not %s." % (
            what, _validate().range_text(-bound, bound, False), unit, ", ".join("%g" % v for v in numbers)))
    return numbers

