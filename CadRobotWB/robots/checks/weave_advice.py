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

Each is found between today's value and the end of the value's range
(:data:`~...core.welding.WEAVE_FIELDS`; the travel down to 0.5 mm/s) by false
position (the Illinois variant, :func:`_root`), re-sampling the run's moves
with the changed weave or travel (``move_sampling.sample_moves(...,
replace=...)``) and taking the peak of
:func:`~..motion.move_sampling.peak_joint_speeds` over every joint against its
limit: the same measure as the check's. The value found is rounded to 0.1
toward the range's end and sampled once more; it is kept only if the run then
stays within every joint speed limit, else the next value of that grid is
tried (up to :data:`EXTRA_STEPS`: the sampled peak wobbles by a few tenths of
a percent with the sampling phase, so it is not exactly monotonic). A fix that
no value in its range achieves is None. The bound
:func:`~...core.weave.peak_tcp_speed_mm_s` is not used: the joint speeds are
measured on the woven samples themselves.

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
#: Most samplings of the run per fix while closing in on the value (false position).
MAX_ITERATIONS = 12
#: Rounded values tried past the one found, one step further each, before giving up.
EXTRA_STEPS = 5


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


def _root(excess, good, e_good, bad, e_bad, tolerance):
    """The value nearest `bad` where ``excess(value) <= 0``, between `good` (it holds:
    ``excess(good) = e_good``) and `bad` (it does not: ``e_bad``), by the Illinois
    variant of false position: the speed over its limit is nearly linear in each
    value, so a few samplings of the run find it to `tolerance`."""
    kept = 0
    for _ in range(MAX_ITERATIONS):
        if abs(bad - good) <= tolerance:
            break
        value = (good * e_bad - bad * e_good) / (e_bad - e_good)
        e_value = excess(value)
        if e_value <= 0.0:
            good, e_good = value, e_value
            e_bad, kept = (e_bad / 2.0 if kept == -1 else e_bad), -1
        else:
            bad, e_bad = value, e_value
            e_good, kept = (e_good / 2.0 if kept == 1 else e_good), 1
    return good


def _fix(excess, today, excess_today, end, step):
    """The value between `today` and `end`, on the grid of `step`, nearest `today`
    whose ``excess`` is <= 0: the root's, rounded toward `end`, or up to
    :data:`EXTRA_STEPS` steps further. None when `end` itself is too fast, or none
    of those values is slow enough."""
    excess_end = excess(end)
    if excess_end > 0.0:
        return None
    found = _root(excess, end, excess_end, today, excess_today, step / 4.0)
    toward_end = -step if end < today else step
    rounding = math.floor if end < today else math.ceil
    first = rounding(round(found / step, 6)) * step
    for k in range(EXTRA_STEPS + 1):
        value = round(first + k * toward_end, 6)
        if (value - end) * toward_end > 1e-9:        # past the end of the range
            return None
        if value != today and excess(value) <= 0.0:
            return value
    return None


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

    def excess(key):
        def over(value):
            changed = weave if key == "travel" else dataclasses.replace(weave, **{key: value})
            return speed_ratio(program, model, moves, margins, clock.run.name, changed,
                               value if key == "travel" else travel) - 1.0
        return over

    today = excess("width_mm")(weave.width_mm)
    fix = WeaveFix(width_mm=_fix(excess("width_mm"), weave.width_mm, today,
                                 WEAVE_FIELDS["width_mm"][1], 0.1))
    if weave.frequency_hz is not None:
        fix.frequency_hz = _fix(excess("frequency_hz"), weave.frequency_hz, today,
                                WEAVE_FIELDS["frequency_hz"][1], 0.1)
    else:
        fix.length_mm = _fix(excess("length_mm"), weave.length_mm, today,
                             WEAVE_FIELDS["length_mm"][2], 0.1)
    fix.travel_speed_mm_s = _fix(excess("travel"), travel, today, MIN_TRAVEL_MM_S, 0.1)
    return fix
