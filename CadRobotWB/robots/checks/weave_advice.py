"""How to fix a weave that turns a joint faster than its limit (issue 22).

The checks sample a woven weld run on its woven path
(:mod:`..motion.move_sampling`); when a joint would have to turn faster than
its limit there, :func:`advise` finds the three fixes the welder can make,
each alone enough:

* the **widest weave** (``width_mm``, in 0.1 mm) no wider than today's;
* the **lowest frequency** (0.1 Hz) of a weave given by its frequency, or the
  **longest cycle** (0.1 mm) of one given by its length per cycle;
* the **fastest travel** (0.1 mm/s) slower than today's, the weave as given
  (a weave given by its frequency keeps it: slowing the travel then lowers
  only the travel's share, and may not be enough; one given by its length
  per cycle keeps the length, so its frequency falls with the travel).

Each is found by bisection between today's value and the end of the value's
range (:data:`~...core.welding.WEAVE_FIELDS`, the travel down to 0.5 mm/s),
re-sampling the run's moves with the changed weave or travel
(``move_sampling.sample_moves(..., replace=...)``) and taking the peak of
:func:`~..motion.move_sampling.peak_joint_speeds` over every joint against
its limit; the rounded value is sampled once more and kept only if the run
then stays within every joint speed limit (the peak need not be monotonic
near a singularity). A fix that no value in its range achieves is None.

Pure numpy: never imports FreeCAD.
"""

import dataclasses
import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from ...core.welding import WEAVE_FIELDS
from ..motion import move_sampling

#: Slowest travel suggested, mm/s (the schedule's range starts there).
MIN_TRAVEL_MM_S = 0.5
#: Bisection steps per fix (the range shrinks 2**-12: far below the rounding).
BISECTION_STEPS = 12


@dataclass
class WeaveFix:
    """Values that each alone keep every joint within its speed limit.

    Attributes
    ----------
    width_mm : float or None
        A narrower weave.
    frequency_hz : float or None
        A lower frequency (weaves given by their frequency).
    length_mm : float or None
        A longer cycle (weaves given by their length per cycle).
    travel_speed_mm_s : float or None
        A slower travel.
    """

    width_mm: Optional[float] = None
    frequency_hz: Optional[float] = None
    length_mm: Optional[float] = None
    travel_speed_mm_s: Optional[float] = None

    def phrases(self, weave, travel_speed_mm_s):
        """list of str: each fix as ``"narrow the weave (4 -> 3 mm)"``."""
        out = []
        if self.width_mm is not None:
            out.append("narrow the weave (%g -> %g mm)" % (weave.width_mm, self.width_mm))
        if self.frequency_hz is not None:
            out.append("lower its frequency (%g -> %g Hz)" % (weave.frequency_hz,
                                                              self.frequency_hz))
        if self.length_mm is not None:
            out.append("lengthen its cycle (%g -> %g mm)" % (weave.length_mm, self.length_mm))
        if self.travel_speed_mm_s is not None:
            out.append("slow the travel (%g -> %g mm/s)" % (travel_speed_mm_s,
                                                            self.travel_speed_mm_s))
        return out

    def to_dict(self):
        """dict of the fixes found (JSON)."""
        return {k: v for k, v in dataclasses.asdict(self).items() if v is not None}


def speed_ratio(program, model, moves, margins, run_name, weave, travel_speed_mm_s):
    """float: the largest joint speed over its limit on a run sampled with this
    weave and travel (> 1: too fast).

    Parameters
    ----------
    moves : list of (TargetSolution, list of TargetSolution)
        The run's welded moves, as :func:`.move_sampling.sample_moves` takes them.
    """
    sampled = move_sampling.sample_moves(program, model, moves, margins,
                                         replace={run_name: (weave, travel_speed_mm_s)})
    needed, _ = move_sampling.peak_joint_speeds(model, sampled)
    limits = np.asarray(model.spec.joint_speed_deg_s, dtype=float)
    return float(np.nanmax(np.where(np.isfinite(needed), needed, 0.0) / limits))


def _bisect(clears, good, bad):
    """The value nearest `bad` for which ``clears`` holds, between `good` (it holds)
    and `bad` (it does not)."""
    for _ in range(BISECTION_STEPS):
        middle = 0.5 * (good + bad)
        if clears(middle):
            good = middle
        else:
            bad = middle
    return good


def _fix(clears, today, end, step):
    """The value from `end` toward `today` (rounded to `step` toward `end`) nearest
    `today` that clears; None when `end` itself does not, or the rounded value does not."""
    if not clears(end):
        return None
    found = _bisect(clears, end, today)
    rounding = math.floor if end < today else math.ceil
    value = rounding(round(found / step, 6)) * step
    value = round(min(max(value, min(end, today)), max(end, today)), 6)
    return value if value != today and clears(value) else None


def advise(program, model, moves, margins, clock):
    """The three fixes of a woven run too fast for a joint.

    Parameters
    ----------
    program : Program
    model : RobotModel
    moves : list of (TargetSolution, list of TargetSolution)
        The run's welded moves (their entries as the check sampled them).
    margins : move_sampling.Margins
    clock : core.weave.RunClock
        The run's clock (its run, weave and travel speed).

    Returns
    -------
    WeaveFix
    """
    weave, travel = clock.weave, clock.travel_speed_mm_s

    def clears(key):
        def test(value):
            changed = weave if key == "travel" else dataclasses.replace(weave, **{key: value})
            return speed_ratio(program, model, moves, margins, clock.run.name, changed,
                               value if key == "travel" else travel) <= 1.0
        return test

    fix = WeaveFix(width_mm=_fix(clears("width_mm"), weave.width_mm,
                                 WEAVE_FIELDS["width_mm"][1], 0.1))
    if weave.frequency_hz is not None:
        fix.frequency_hz = _fix(clears("frequency_hz"), weave.frequency_hz,
                                WEAVE_FIELDS["frequency_hz"][1], 0.1)
    else:
        fix.length_mm = _fix(clears("length_mm"), weave.length_mm,
                             WEAVE_FIELDS["length_mm"][2], 0.1)
    fix.travel_speed_mm_s = _fix(clears("travel"), travel, MIN_TRAVEL_MM_S, 0.1)
    return fix
