"""What a weld is, as plain data: the schedule, the weave and the tracking.

A weld is the arc-on stretch of a path (issue 22). Its data is written by the
App layer (``objects/weld.py``) or the scripting API from a dict, carried by
the program IR (:class:`.program.WeldRun`) and read by the posts, the checks
and the through-arc tracking simulation.

Units at this surface are the welder's: mm, mm/s, m/min of wire, V, A, s, Hz,
degrees. Every value left out takes the default stated in the tables
:data:`SCHEDULE_FIELDS` and :data:`WEAVE_FIELDS` (the README prints them).

Pure Python; never imports FreeCAD.
"""

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Optional

from ..errors import InputError

PROCESSES = ("GMAW",)
ZIGZAG, TRIANGLE, CIRCLE, L_SHAPE = "zigzag", "triangle", "circle", "l"
WEAVE_PATTERNS = (ZIGZAG, TRIANGLE, CIRCLE, L_SHAPE)
NO_TRACKING, ARC_TRACKING, LASER_TRACKING = "none", "arc", "laser"
TRACKING_SENSORS = (NO_TRACKING, ARC_TRACKING, LASER_TRACKING)

#: Wire feed per ampere of welding current, (m/min)/A, by wire diameter (mm): Miller's rule
#: for solid steel wire (Renegade 180 manual OM-228 042 section 12-2: 0.030 in 2 in/min per A,
#: 0.035 in 1.6, 0.045 in 1.0), used only when a schedule gives the current and no wire feed.
WIRE_FEED_PER_AMPERE = {0.8: 2.0 * 0.0254, 0.9: 1.6 * 0.0254, 1.2: 1.0 * 0.0254}

# name: (default, lowest, highest, unit, what) -- None as a default means "not given".
# unverified: the defaults of gas pre-/post-flow, crater fill (time, 0.7 x current, 0.8 x voltage,
# 0.7 x wire feed) and burn-back are typical starting values, not read from a procedure table
# (plan (c) note 4); the library's rows say so in their notes.
SCHEDULE_FIELDS = {
    "wire_mm": (1.2, 0.6, 2.4, "mm", "wire diameter"),
    "wire_feed_m_min": (None, 0.5, 30.0, "m/min", "wire feed speed (derived from the current "
                                                   "when left out)"),
    "voltage_v": (None, 10.0, 50.0, "V", "arc voltage"),
    "current_a": (None, 20.0, 600.0, "A", "welding current"),
    "travel_speed_mm_s": (None, 0.5, 50.0, "mm/s", "travel speed along the seam"),
    "gas_preflow_s": (0.2, 0.0, 10.0, "s", "gas pre-flow before ignition"),
    "gas_postflow_s": (0.5, 0.0, 10.0, "s", "gas post-flow after the arc goes out"),
    "crater_fill_s": (0.3, 0.0, 10.0, "s", "crater fill time at the end"),
    "crater_current_a": (None, 10.0, 600.0, "A", "crater current (0.7 x current when left out)"),
    "crater_voltage_v": (None, 8.0, 50.0, "V", "crater voltage (0.8 x voltage when left out)"),
    "crater_wire_feed_m_min": (None, 0.3, 30.0, "m/min", "crater wire feed (0.7 x wire feed "
                                                          "when left out)"),
    "burnback_s": (0.05, 0.0, 2.0, "s", "burn-back time"),
    "ctwd_mm": (15.0, 5.0, 40.0, "mm", "contact-tip-to-work distance"),
    "job_number": (0, 0, 1000, "", "power-source job (program) number; 0 = none"),
}
SCHEDULE_TEXT_FIELDS = {"name": "Custom", "process": "GMAW", "gas": "CO2", "source": ""}

WEAVE_FIELDS = {
    "width_mm": (4.0, 0.2, 30.0, "mm", "full width across the seam, peak to peak"),
    "length_mm": (None, 0.2, 50.0, "mm", "travel per weave cycle (give this or frequency_hz)"),
    "frequency_hz": (None, 0.1, 5.0, "Hz", "weave cycles per second (2 Hz when neither "
                                           "length_mm nor frequency_hz is given)"),
    "dwell_left_s": (0.0, 0.0, 2.0, "s", "dwell at the left end"),
    "dwell_center_s": (0.0, 0.0, 2.0, "s", "dwell at the centre (half at each crossing)"),
    "dwell_right_s": (0.0, 0.0, 2.0, "s", "dwell at the right end"),
    "angle_deg": (0.0, -90.0, 90.0, "deg", "weave plane turned about the travel, from the "
                                            "lateral toward the tool axis"),
    "height_mm": (None, 0.0, 30.0, "mm", "triangle apex / L leg height back along the tool "
                                         "axis (width_mm / 2 when left out)"),
}
DEFAULT_FREQUENCY_HZ = 2.0

TRACKING_FIELDS = {
    "lateral_gain": (0.5, 0.0, 1.0, "", "share of the measured lateral error corrected per "
                                        "weave cycle"),
    "height_gain": (0.5, 0.0, 1.0, "", "share of the measured height error corrected per cycle"),
    "max_correction_mm": (15.0, 0.5, 50.0, "mm", "largest correction before the run stops"),
}
TRACKING_REFERENCES = ("schedule", "learned")


def _number(value, key, spec, what):
    default, low, high, unit, _ = spec
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(f"{what}: {key} is {value!r}: give a number from {low:g} to "
                         f"{high:g} {unit}".rstrip() + ".")
    if not low <= value <= high:
        raise InputError(f"{what}: {key} {value:g} {unit} is outside {low:g} to {high:g} "
                         f"{unit}: give a value in that range.".replace("  ", " "))
    return float(value)


def _fields_from_dict(values, numbers, texts, what):
    """Check `values` (a dict) against the field tables; unknown keys are refused."""
    if not isinstance(values, dict):
        raise InputError(f"{what} must be a dict of {', '.join(sorted(numbers))}, not "
                         f"{type(values).__name__}.")
    known = set(numbers) | set(texts)
    unknown = sorted(str(k) for k in values if k not in known)
    if unknown:
        raise InputError(f"{what}: unknown key {unknown[0]!r}: use "
                         f"{', '.join(sorted(known))}.")
    out = {}
    for key, value in values.items():
        if key in texts:
            if not isinstance(value, str):
                raise InputError(f"{what}: {key} must be text, not {type(value).__name__}.")
            out[key] = value
        elif value is not None:
            out[key] = _number(value, key, numbers[key], what)
    return out


@dataclass(frozen=True)
class WeldSchedule:
    """The process values of one weld (GMAW/MAG).

    Attributes are in the units their names say; see :data:`SCHEDULE_FIELDS`
    for ranges and defaults. ``current_a`` may be None when the power source is
    set by wire feed and voltage (the current then follows from the arc);
    ``wire_feed_m_min`` is derived from the current when not given, and
    ``wire_feed_estimated`` says so. ``source`` cites the procedure table a
    library schedule comes from; ``ranges`` keeps its published ranges.
    """

    name: str = "Custom"
    process: str = "GMAW"
    wire_mm: float = 1.2
    wire_feed_m_min: float = 0.0
    voltage_v: float = 0.0
    current_a: Optional[float] = None
    travel_speed_mm_s: float = 0.0
    gas_preflow_s: float = 0.2
    gas_postflow_s: float = 0.5
    crater_fill_s: float = 0.3
    crater_current_a: Optional[float] = None
    crater_voltage_v: Optional[float] = None
    crater_wire_feed_m_min: Optional[float] = None
    burnback_s: float = 0.05
    ctwd_mm: float = 15.0
    gas: str = "CO2"
    job_number: int = 0
    source: str = ""
    wire_feed_estimated: bool = False
    ranges: dict = field(default_factory=dict, compare=False)

    @classmethod
    def from_dict(cls, values, base=None, what="Weld schedule"):
        """A schedule from the API dict `values`, keys left out taken from
        `base` (a WeldSchedule) or the stated defaults.

        Raises
        ------
        InputError
            An unknown key, a value out of its range, or a schedule that
            lacks voltage, travel speed, or both wire feed and current.

        Notes
        -----
        ``wire_feed_estimated`` (written by :meth:`as_dict`) is accepted: it
        stays True only when the wire feed given is the one derived from the
        current (else the wire feed is the user's own value).
        """
        estimated = False
        if isinstance(values, dict) and "wire_feed_estimated" in values:
            values = dict(values)
            estimated = values.pop("wire_feed_estimated")
            if not isinstance(estimated, bool):
                raise InputError(f"{what}: wire_feed_estimated must be True or False, not "
                                 f"{estimated!r}.")
        given = _fields_from_dict(values, SCHEDULE_FIELDS, SCHEDULE_TEXT_FIELDS, what)
        if "job_number" in given:
            given["job_number"] = int(given["job_number"])
        if base is not None:
            merged = dataclasses.replace(base, **given)
            if "wire_feed_m_min" not in given and base.wire_feed_estimated:
                merged = dataclasses.replace(merged, wire_feed_m_min=0.0,
                                             wire_feed_estimated=False)
            if "name" not in given and given:
                merged = dataclasses.replace(merged, name=f"{base.name} (changed)")
            return _with_estimate_flag(merged.validated(what), estimated)
        return _with_estimate_flag(cls(**given).validated(what), estimated)

    def validated(self, what="Weld schedule"):
        """This schedule with the derived values filled in, after checking it.

        Returns
        -------
        WeldSchedule
            ``wire_feed_m_min`` derived from the current if it was 0 (and
            ``wire_feed_estimated`` set); crater values filled as stated in
            :data:`SCHEDULE_FIELDS`.
        """
        if self.process not in PROCESSES:
            raise InputError(f"{what}: process {self.process!r} is not supported: use "
                             f"{', '.join(PROCESSES)}.")
        for key in ("voltage_v", "travel_speed_mm_s"):   # 0: not given (the dataclass default)
            if not getattr(self, key):
                raise InputError(f"{what}: {key} is missing: give the "
                                 f"{SCHEDULE_FIELDS[key][4]} in {SCHEDULE_FIELDS[key][3]}.")
        for key in SCHEDULE_FIELDS:
            value = getattr(self, key)
            if value is not None and not (key == "wire_feed_m_min" and value == 0):
                _number(value, key, SCHEDULE_FIELDS[key], what)
        schedule = self
        if not self.wire_feed_m_min:
            derived = derived_wire_feed_m_min(self.current_a, self.wire_mm)
            if derived is None:
                raise InputError(f"{what}: give wire_feed_m_min (the wire feed can be derived "
                                 "from current_a only for 0.8, 0.9 and 1.2 mm wire).")
            schedule = dataclasses.replace(schedule, wire_feed_estimated=True,
                                           wire_feed_m_min=derived)
        crater = {}
        if schedule.crater_current_a is None and schedule.current_a is not None:
            crater["crater_current_a"] = float(round(0.7 * schedule.current_a))
        if schedule.crater_voltage_v is None:
            crater["crater_voltage_v"] = round(0.8 * schedule.voltage_v, 1)
        if schedule.crater_wire_feed_m_min is None:
            crater["crater_wire_feed_m_min"] = round(0.7 * schedule.wire_feed_m_min, 1)
        return dataclasses.replace(schedule, **crater)

    def as_dict(self):
        """The API dict of this schedule (every field but ``ranges``)."""
        out = dataclasses.asdict(self)
        out.pop("ranges")
        return out


def derived_wire_feed_m_min(current_a, wire_mm):
    """float or None: the wire feed Miller's rule gives for `current_a` on `wire_mm` wire,
    m/min rounded to 0.1 (:data:`WIRE_FEED_PER_AMPERE`); None for another wire."""
    per_ampere = WIRE_FEED_PER_AMPERE.get(round(wire_mm, 2))
    if current_a is None or per_ampere is None:
        return None
    return round(current_a * per_ampere, 1)


def _with_estimate_flag(schedule, estimated):
    """`schedule` with ``wire_feed_estimated`` also set when the dict said so and its
    wire feed is the derived one."""
    if estimated and not schedule.wire_feed_estimated and schedule.wire_feed_m_min == \
            derived_wire_feed_m_min(schedule.current_a, schedule.wire_mm):
        return dataclasses.replace(schedule, wire_feed_estimated=True)
    return schedule


@dataclass(frozen=True)
class Weave:
    """The weave superimposed on the travel along the seam (geometric weave:
    the torch's orientation does not weave).

    Attributes
    ----------
    pattern : {"zigzag", "triangle", "circle", "l"}
    width_mm : float
        Full width across the seam, peak to peak, mm (the circle's diameter).
    length_mm, frequency_hz : float or None
        Travel per cycle (mm) or cycles per second; exactly one is set after
        :meth:`validated` (frequency 2 Hz when neither was given).
    dwell_left_s, dwell_center_s, dwell_right_s : float
        Time the weave holds still at each end and at the centre, s; the
        travel goes on meanwhile. The dwells are inside the cycle time.
    angle_deg : float
        The weave plane turned about the travel axis from the lateral axis
        toward the tool axis, degrees.
    height_mm : float or None
        Triangle: apex; l: height of each leg; back along the tool axis, mm.
        None: half the width (legs at 45 degrees).
    """

    pattern: str = ZIGZAG
    width_mm: float = 4.0
    length_mm: Optional[float] = None
    frequency_hz: Optional[float] = None
    dwell_left_s: float = 0.0
    dwell_center_s: float = 0.0
    dwell_right_s: float = 0.0
    angle_deg: float = 0.0
    height_mm: Optional[float] = None

    @classmethod
    def from_dict(cls, values, base=None, what="Weave"):
        """A weave from the API dict `values` (keys of :data:`WEAVE_FIELDS` and
        ``pattern``); keys left out from `base` or the stated defaults."""
        given = _fields_from_dict(values, WEAVE_FIELDS, {"pattern": ZIGZAG}, what)
        if base is not None and ({"length_mm", "frequency_hz"} & set(given)):
            base = dataclasses.replace(base, length_mm=None, frequency_hz=None)
        weave = dataclasses.replace(base, **given) if base is not None else cls(**given)
        return weave.validated(what)

    def validated(self, what="Weave"):
        """This weave after checking it, the frequency defaulted."""
        if self.pattern not in WEAVE_PATTERNS:
            raise InputError(f"{what}: pattern {self.pattern!r} is unknown: use "
                             f"{', '.join(WEAVE_PATTERNS)}.")
        for key in WEAVE_FIELDS:
            if getattr(self, key) is not None:
                _number(getattr(self, key), key, WEAVE_FIELDS[key], what)
        if self.length_mm is not None and self.frequency_hz is not None:
            raise InputError(f"{what}: give length_mm or frequency_hz, not both.")
        if self.pattern == CIRCLE and self.dwells_s:
            raise InputError(f"{what}: a circle weave has no dwells: set the dwells to 0 or "
                             "use zigzag.")
        weave = self
        if self.length_mm is None and self.frequency_hz is None:
            weave = dataclasses.replace(self, frequency_hz=DEFAULT_FREQUENCY_HZ)
        if weave.frequency_hz is not None and weave.dwells_s >= 0.999 / weave.frequency_hz:
            raise InputError(f"{what}: its dwells ({weave.dwells_s:g} s) fill the whole weave "
                             f"cycle ({1 / weave.frequency_hz:g} s): lower the frequency or "
                             "shorten the dwells.")
        return weave

    @property
    def dwells_s(self):
        """float: the dwells of one cycle together, s."""
        return self.dwell_left_s + self.dwell_center_s + self.dwell_right_s

    @property
    def height(self):
        """float: the triangle's apex / the L's leg height, mm."""
        return self.width_mm / 2 if self.height_mm is None else self.height_mm

    def cycle_time_s(self, travel_speed_mm_s):
        """float: duration of one weave cycle at this travel speed, s."""
        if self.frequency_hz is not None:
            return 1.0 / self.frequency_hz
        return self.length_mm / travel_speed_mm_s

    def cycle_length_mm(self, travel_speed_mm_s):
        """float: travel along the seam during one cycle, mm."""
        return self.cycle_time_s(travel_speed_mm_s) * travel_speed_mm_s

    def frequency(self, travel_speed_mm_s):
        """float: weave cycles per second at this travel speed, Hz."""
        return 1.0 / self.cycle_time_s(travel_speed_mm_s)

    def as_dict(self):
        return dataclasses.asdict(self)


@dataclass(frozen=True)
class Tracking:
    """How the weld follows the real seam while welding.

    Attributes
    ----------
    sensor : {"none", "arc", "laser"}
        ``"arc"``: through-arc tracking (needs a weave; ABB ``\\Track``, FANUC
        TAST, KUKA ArcSense, Yaskawa COM-ARC); ``"laser"``: the laser seam
        tracker (ABB ``\\Corr``).
    lateral_gain, height_gain : float
        Share of the measured error corrected per weave cycle.
    reference : {"schedule", "learned"}
        Height reference current: the schedule's, at the nominal CTWD (corrects
        an absolute height error), or the one measured over the first cycles
        (FANUC's FEEDBACK; a height error present at the start stays).
    max_correction_mm : float
        Largest total correction; beyond it the run stops.
    """

    sensor: str = NO_TRACKING
    lateral_gain: float = 0.5
    height_gain: float = 0.5
    reference: str = "schedule"
    max_correction_mm: float = 15.0

    @classmethod
    def from_dict(cls, values, what="Tracking"):
        if isinstance(values, str):
            values = {"sensor": values}
        given = _fields_from_dict(values, TRACKING_FIELDS,
                                  {"sensor": NO_TRACKING, "reference": "schedule"}, what)
        return cls(**given).validated(what)

    def validated(self, what="Tracking"):
        if self.sensor not in TRACKING_SENSORS:
            raise InputError(f"{what}: sensor {self.sensor!r} is unknown: use "
                             f"{', '.join(TRACKING_SENSORS)}.")
        if self.reference not in TRACKING_REFERENCES:
            raise InputError(f"{what}: reference {self.reference!r} is unknown: use "
                             f"{', '.join(TRACKING_REFERENCES)}.")
        for key in TRACKING_FIELDS:
            _number(getattr(self, key), key, TRACKING_FIELDS[key], what)
        return self


#: Welding positions (ISO 6947) a positioner can keep a seam in: flat, horizontal-vertical.
POSITIONS = ("PA", "PB")


@dataclass
class WeldSpec:
    """A weld as read from the document, input of :func:`.generate.generate`.

    Attributes
    ----------
    name, label : str
        Internal name and user-visible label of the Weld object.
    schedule : WeldSchedule
    weave : Weave or None
    tracking : Tracking
    first_segment, last_segment : int or None
        1-based, inclusive segments of the path welded; None: from the first /
        to the last segment.
    position : str
        The welding position a positioner keeps the seam in (``WeldRun.position``):
        ``"PA"`` flat or ``"PB"`` horizontal-vertical.
    """

    name: str
    label: str
    schedule: WeldSchedule
    weave: Optional[Weave] = None
    tracking: Tracking = field(default_factory=Tracking)
    first_segment: Optional[int] = None
    last_segment: Optional[int] = None
    position: str = "PA"
