"""Weld: the arc-on stretch of a path, with its schedule, weave and tracking (issue 22).

A Weld covers segments FirstSegment..LastSegment (1-based, inclusive; 0 = from
the first / to the last) of its Path. Its schedule is kept as properties, one
per field of :data:`core.welding.SCHEDULE_FIELDS`, so the user can change any
value in the property editor; ``Schedule`` says which library row they came
from ("Custom" for the user's own) and ``ScheduleSource`` / ``ScheduleNote``
cite the table and why that row was picked. A value of 0 in a property whose
field has no default (Current, the crater values) means "not given".

Its Shape is the woven centre line (the torch's path with the weave of
:mod:`core.weave`), shown in the 3D view.

App layer: FreeCAD and Part, no GUI. The module path is saved in documents:
never move it.
"""

import numpy as np
import Part

from ..core import weave as weave_geometry
from ..core.welding import (ARC_TRACKING, NO_TRACKING, POSITIONS, SCHEDULE_FIELDS,
                            TRACKING_SENSORS, WEAVE_FIELDS, WEAVE_PATTERNS, Tracking, Weave,
                            WeldSchedule, WeldSpec)
from ..errors import CadRobotError, InputError
from .base import Proxy, describe, restoring, type_of
from .convert import vector_from_array

#: Schedule properties: (property, schedule key, property type). Tooltips and
#: defaults come from SCHEDULE_FIELDS.
SCHEDULE_PROPERTIES = (
    ("WireDiameter", "wire_mm", "App::PropertyLength"),
    ("WireFeed", "wire_feed_m_min", "App::PropertyFloat"),
    ("Voltage", "voltage_v", "App::PropertyFloat"),
    ("Current", "current_a", "App::PropertyFloat"),
    ("TravelSpeed", "travel_speed_mm_s", "App::PropertySpeed"),
    ("GasPreflow", "gas_preflow_s", "App::PropertyFloat"),
    ("GasPostflow", "gas_postflow_s", "App::PropertyFloat"),
    ("CraterFill", "crater_fill_s", "App::PropertyFloat"),
    ("CraterCurrent", "crater_current_a", "App::PropertyFloat"),
    ("CraterVoltage", "crater_voltage_v", "App::PropertyFloat"),
    ("CraterWireFeed", "crater_wire_feed_m_min", "App::PropertyFloat"),
    ("BurnBack", "burnback_s", "App::PropertyFloat"),
    ("CTWD", "ctwd_mm", "App::PropertyLength"),
    ("JobNumber", "job_number", "App::PropertyInteger"),
)
#: Schedule text properties: (property, schedule key).
SCHEDULE_TEXTS = (("Process", "process"), ("Gas", "gas"))

#: Weave properties: (property, weave key, property type); 0 in WeaveLength,
#: WeaveFrequency and WeaveHeight means "not given".
WEAVE_PROPERTIES = (
    ("WeaveWidth", "width_mm", "App::PropertyLength"),
    ("WeaveLength", "length_mm", "App::PropertyLength"),
    ("WeaveFrequency", "frequency_hz", "App::PropertyFrequency"),
    ("DwellLeft", "dwell_left_s", "App::PropertyFloat"),
    ("DwellCenter", "dwell_center_s", "App::PropertyFloat"),
    ("DwellRight", "dwell_right_s", "App::PropertyFloat"),
    ("WeaveAngle", "angle_deg", "App::PropertyAngle"),
    ("WeaveHeight", "height_mm", "App::PropertyLength"),
)

NO_WEAVE = "None"
#: The WeavePattern choices: "None" and the patterns as core.welding names them.
WEAVE_CHOICES = [NO_WEAVE] + list(WEAVE_PATTERNS)
#: The Tracking choices, in the order of core.welding.TRACKING_SENSORS.
TRACKING_CHOICES = [s.capitalize() for s in TRACKING_SENSORS]
CUSTOM = "Custom"
#: What a library or user schedule's name gets when one of its values is changed in the
#: property editor: the values are no longer that row's.
CHANGED = " (changed)"

#: Weave cycles' samples in the preview wire, and the most samples of one weld.
PREVIEW_SAMPLES_PER_CYCLE = 24
PREVIEW_MAX_SAMPLES = 20000


def _tooltip(table, key):
    default, low, high, unit, what = table[key]
    unit = " (%s)" % unit if unit else ""
    return "%s%s, %g..%g" % (what[0].upper() + what[1:], unit, low, high)


def _property_rows():
    rows = [
        ("App::PropertyLink", "Path", "Weld", "The path this weld belongs to", None),
        ("App::PropertyString", "PathRef", "Weld",
         "Internal name of the last path linked (to report a deleted one)", ""),
        ("App::PropertyInteger", "FirstSegment", "Weld",
         "First segment welded (1-based); 0: from the path's first", 0),
        ("App::PropertyInteger", "LastSegment", "Weld",
         "Last segment welded (1-based); 0: to the path's last", 0),
        ("App::PropertyString", "Schedule", "Schedule",
         "The library schedule these values come from, or Custom", CUSTOM),
        ("App::PropertyString", "ScheduleSource", "Schedule",
         "The procedure table the schedule comes from (read-only)", ""),
        ("App::PropertyString", "ScheduleNote", "Schedule",
         "Why this schedule was picked (read-only)", ""),
        ("App::PropertyBool", "WireFeedEstimated", "Schedule",
         "The wire feed was derived from the current (Miller's rule), not given (read-only)", False),
    ]
    rows += [("App::PropertyString", prop, "Schedule", key.capitalize(), None)
             for prop, key in SCHEDULE_TEXTS]
    rows += [(kind, prop, "Schedule", _tooltip(SCHEDULE_FIELDS, key)
              + ("; 0: not given" if SCHEDULE_FIELDS[key][0] is None else ""),
              SCHEDULE_FIELDS[key][0] or 0)
             for prop, key, kind in SCHEDULE_PROPERTIES]
    rows.append(("App::PropertyEnumeration", "WeavePattern", "Weave",
                 "The weave pattern; None: no weave", WEAVE_CHOICES))
    rows += [(kind, prop, "Weave", _tooltip(WEAVE_FIELDS, key)
              + ("; 0: not given" if WEAVE_FIELDS[key][0] is None else ""),
              WEAVE_FIELDS[key][0] or 0)
             for prop, key, kind in WEAVE_PROPERTIES]
    rows.append(("App::PropertyEnumeration", "Tracking", "Weld",
                 "Seam tracking while welding: Arc (through the arc, needs a weave) or Laser",
                 TRACKING_CHOICES))
    rows.append(("App::PropertyEnumeration", "Position", "Weld",
                 "The welding position a positioner keeps the seam in (ISO 6947): PA flat, PB "
                 "horizontal-vertical (a fillet); without a positioner nothing turns the part",
                 list(POSITIONS)))
    return tuple(rows)


class Weld(Proxy):
    """Proxy of a ``Part::FeaturePython`` welding segments FirstSegment..LastSegment of Path."""

    TYPE = "Weld"
    PROPERTIES = _property_rows()
    READ_ONLY = ("ScheduleSource", "ScheduleNote", "WireFeedEstimated")

    def setup(self, obj):
        obj.setEditorMode("PathRef", 2)
        obj.setEditorMode("Placement", 2)
        for name in self.READ_ONLY:
            obj.setEditorMode(name, 1)

    def onChanged(self, obj, prop):
        if prop == "Path" and getattr(obj, "Path", None) is not None:
            if obj.PathRef != obj.Path.Name:
                obj.PathRef = obj.Path.Name
        if prop in _SCHEDULE_VALUES and not restoring(obj):
            name = str(getattr(obj, "Schedule", ""))
            if name and name != CUSTOM and not name.endswith(CHANGED):
                obj.Schedule = name + CHANGED

    def execute(self, obj):
        try:
            obj.Shape = preview_shape(obj)
        except CadRobotError:   # reported when generating; display nothing here
            obj.Shape = Part.Shape()


_SCHEDULE_VALUES = {prop for prop, _, _ in SCHEDULE_PROPERTIES} | {p for p, _ in SCHEDULE_TEXTS}


def make(doc, name):
    obj = doc.addObject("Part::FeaturePython", name)
    Weld(obj)
    return obj


# --- properties <-> core data --------------------------------------------------------------

def what(obj):
    """How messages name the weld: ``"Weld 'Weld'"``."""
    return "Weld %s" % describe(obj)


def _given(value, default):
    """None for a 0 in a property whose field has no default (0 = not given)."""
    return None if default is None and not value else value


def schedule_of(obj):
    """The WeldSchedule the properties of `obj` hold, checked (the WireFeed written
    when the weld was made stays as it is when the Current is changed).

    Raises
    ------
    InputError
        A value out of range or missing, naming the weld and the field.
    """
    values = {key: _given(float(getattr(obj, prop)), SCHEDULE_FIELDS[key][0])
              for prop, key, _ in SCHEDULE_PROPERTIES}
    values = {k: v for k, v in values.items() if v is not None}
    values["job_number"] = int(obj.JobNumber)
    texts = {key: str(getattr(obj, prop)) for prop, key in SCHEDULE_TEXTS}
    schedule = WeldSchedule(name=str(obj.Schedule) or CUSTOM, source=str(obj.ScheduleSource),
                            wire_feed_estimated=bool(obj.WireFeedEstimated), **texts, **values)
    return _naming(obj, schedule.validated, what(obj))


def _naming(obj, check, *args):
    """`check(*args)`, its InputError carrying the weld (selected in the tree)."""
    try:
        return check(*args)
    except InputError as err:
        if err.obj_name:
            raise
        raise InputError(str(err), obj.Name) from None


def set_schedule(obj, schedule, note=""):
    """Write the (validated) `schedule` into the properties of `obj`."""
    for prop, key, _ in SCHEDULE_PROPERTIES:
        value = getattr(schedule, key)
        setattr(obj, prop, int(value) if key == "job_number" else float(value or 0.0))
    for prop, key in SCHEDULE_TEXTS:
        setattr(obj, prop, str(getattr(schedule, key)))
    obj.Schedule = schedule.name or CUSTOM
    obj.ScheduleSource = schedule.source
    obj.ScheduleNote = note
    obj.WireFeedEstimated = bool(schedule.wire_feed_estimated)


def weave_of(obj):
    """The Weave of `obj` (checked), or None when WeavePattern is "None"."""
    if str(obj.WeavePattern) == NO_WEAVE:
        return None
    values = {key: _given(float(getattr(obj, prop)), WEAVE_FIELDS[key][0])
              for prop, key, _ in WEAVE_PROPERTIES}
    return _naming(obj, Weave(pattern=str(obj.WeavePattern), **values).validated, what(obj))


def set_weave(obj, weave):
    """Write `weave` (a Weave or None) into the properties of `obj`."""
    obj.WeavePattern = NO_WEAVE if weave is None else weave.pattern
    shown = Weave() if weave is None else weave     # no weave: the defaults, to start from
    for prop, key, _ in WEAVE_PROPERTIES:
        setattr(obj, prop, float(getattr(shown, key) or 0.0))


def tracking_of(obj):
    """The Tracking of `obj`."""
    return Tracking(sensor=str(obj.Tracking).lower()).validated(what(obj))


def set_tracking(obj, tracking):
    obj.Tracking = (tracking.sensor if tracking is not None else NO_TRACKING).capitalize()


def check_path(obj):
    """InputError naming the weld when its path was deleted (or never linked)."""
    if obj.Path is None:
        was = " '%s'" % obj.PathRef if obj.PathRef else ""
        raise InputError("%s refers to a path%s that was deleted. Link it to a path in its Path "
                         "property or delete it." % (what(obj), was), obj.Name)


def segment_range(obj, n_segments):
    """(first, last), 1-based inclusive, of the segments `obj` welds on a path of
    `n_segments`; InputError naming the weld when they are not on the path."""
    first = int(obj.FirstSegment) or 1
    last = int(obj.LastSegment) or n_segments
    if not 1 <= first <= last <= n_segments:
        raise InputError(
            "%s welds segments %d-%d, but path %s has segments 1-%d: set FirstSegment and "
            "LastSegment within that range (0: the whole path)."
            % (what(obj), first, last, describe(obj.Path) if obj.Path is not None else "''",
               n_segments), obj.Name)
    return first, last


def check_tracking(tracking, weave, what_weld):
    """InputError naming `what_weld` when through-arc `tracking` has no `weave` to sense with."""
    if tracking.sensor == ARC_TRACKING and weave is None:
        raise InputError("%s: through-arc tracking needs a weave: give it a weave (weave={...}, "
                         "WeavePattern) or track with the laser." % what_weld)


def spec_of(obj, n_segments):
    """The :class:`core.welding.WeldSpec` of `obj` on a path of `n_segments`."""
    first, last = segment_range(obj, n_segments)
    weave, tracking = weave_of(obj), tracking_of(obj)
    _naming(obj, check_tracking, tracking, weave, what(obj))
    return WeldSpec(name=obj.Name, label=obj.Label, schedule=schedule_of(obj), weave=weave,
                    tracking=tracking,
                    first_segment=None if int(obj.FirstSegment) == 0 else first,
                    last_segment=None if int(obj.LastSegment) == 0 else last,
                    position=str(obj.Position))


# --- the woven centre line -----------------------------------------------------------------

def cell_of(obj):
    """The cell whose group holds `obj` (directly or nested), or None."""
    todo, seen = list(obj.InList), set()
    while todo:
        parent = todo.pop()
        if parent.Name in seen:
            continue
        seen.add(parent.Name)
        if type_of(parent) == "Cell":
            return parent
        todo.extend(parent.InList)
    return None


def path_tool_axes(cell, path, n_segments):
    """Tool +Z per segment of `path`, {U}: from the tool markers of `cell`, else
    straight down (for the preview only: generating reports missing markers)."""
    from . import reader
    if cell is not None:
        try:
            for entry in reader.path_tool_orientations(cell):
                if entry.path.Name == path.Name:
                    return [np.asarray(R, float)[:, 2] for R in entry.R_u_t]
        except CadRobotError:
            pass
    return [np.array([0.0, 0.0, -1.0])] * n_segments


def _samples(segments, tool_axes, step_mm):
    """Distance along `segments` (s_mm, (N,)), points, travel directions and tool
    axes ((N, 3) each, {U}) about `step_mm` apart, each segment's ends included."""
    s_all, points, travel, tool_z, start = [], [], [], [], 0.0
    for segment, axis in zip(segments, tool_axes):
        count = max(2, int(np.ceil(segment.length / step_mm)) + 1)
        s = np.linspace(0.0, segment.length, count)
        s_all.append(start + s)
        points.append(np.asarray(segment.points_at(s), float))
        travel.append(np.array([segment.tangent_at(x) for x in s], float))
        tool_z.append(np.tile(axis, (count, 1)))
        start += segment.length
    return tuple(np.concatenate(a) for a in (s_all, points, travel, tool_z))


def woven_path(cell, path, segments, travel_speed_mm_s, weave):
    """The torch's woven path along segments (first, last) (1-based) of `path`.

    Parameters
    ----------
    cell : App.DocumentObject or None
        The cell whose tool markers orient the path.
    travel_speed_mm_s : float
    weave : welding.Weave or None

    Returns
    -------
    ndarray, shape (N, 3)
        {U}, mm: the seam's points moved by :func:`core.weave.woven_offsets`
        in the weave frame (the seam itself without a weave).
    """
    from . import reader
    all_segments = reader.path_geometry(path)[0]
    first, last = segments
    welded = all_segments[first - 1:last]
    axes = path_tool_axes(cell, path, len(all_segments))[first - 1:last]
    step = 5.0 if weave is None else (weave.cycle_length_mm(travel_speed_mm_s)
                                      / PREVIEW_SAMPLES_PER_CYCLE)
    step = max(step, sum(seg.length for seg in welded) / PREVIEW_MAX_SAMPLES)
    s, points, travel, tool_z = _samples(welded, axes, step)
    if weave is None:
        return points
    t = s / travel_speed_mm_s
    offsets = weave_geometry.woven_offsets(t, t[-1], weave, travel_speed_mm_s)
    X, Y, Z = weave_geometry.frame_axes(travel, tool_z)
    return points + offsets[:, :1] * X + offsets[:, 1:2] * Y + offsets[:, 2:] * Z


def woven_points(obj):
    """:func:`woven_path` of the Weld `obj`."""
    from . import reader
    segments = segment_range(obj, len(reader.path_geometry(obj.Path)[0]))
    return woven_path(cell_of(obj), obj.Path, segments, schedule_of(obj).travel_speed_mm_s,
                      weave_of(obj))


def polygon(points):
    """A Part wire through `points` (N, 3), repeated points left out."""
    keep = np.concatenate([[True], np.linalg.norm(np.diff(points, axis=0), axis=1) > 1e-6])
    return Part.makePolygon([vector_from_array(p) for p in points[keep]])


def welded_length_mm(obj):
    """float: length of the seam the weld covers, mm."""
    from . import reader
    segments = reader.path_geometry(obj.Path)[0]
    first, last = segment_range(obj, len(segments))
    return float(sum(seg.length for seg in segments[first - 1:last]))


def preview_shape(obj):
    """The wire of :func:`woven_points` (an empty shape without a path)."""
    if obj.Path is None:
        return Part.Shape()
    return polygon(woven_points(obj))
