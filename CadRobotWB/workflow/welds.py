"""Welds: make them (the schedule from the library for the joint the faces show) and
list them. The schedules to pick from are :mod:`.weld_schedules`'.

Part of the scripting API: :mod:`CadRobotWB.api` re-exports its public names.
"""

import numpy as np

from .. import preferences
from ..core.welding import POSITIONS, TRACKING_SENSORS, Tracking, Weave, WeldSchedule
from ..errors import CadRobotError, InputError
from ..objects import base, joint_faces, reader
from ..objects import weld as weld_object
from ..sensors.joint_detection import classify_sample, detect_joint
from .arguments import Arguments

#: What `schedule` may be, in messages.
SCHEDULE_TEXT = "None, a library schedule name (a str, see api.weld_schedules()) or a dict of schedule fields"
#: How far from the joint the plate thickness is measured, mm (inside the face).
THICKNESS_PROBE_MM = 2.0


def make_weld(doc, cell, path, schedule=None, weave=None, first_segment=None, last_segment=None,
              name="Weld", tracking=None, position="PA"):
    """Add a weld over segments `first_segment`..`last_segment` (1-based) of `path`.

    Parameters
    ----------
    schedule : str or dict, optional
        A library schedule name (``api.weld_schedules()``), or a dict of the
        keys of ``core.welding.SCHEDULE_FIELDS`` (``voltage_v`` and
        ``wire_feed_m_min`` or ``current_a`` needed; ``travel_speed_mm_s``
        defaults to the path's speed, the others to the stated defaults).
        None: the library's schedule for the joint the faces along the
        welded segments show and the thinner plate's thickness; the
        sentence why is kept in the weld's ScheduleNote.
    weave : dict, optional
        Keys of ``core.welding.WEAVE_FIELDS`` and ``pattern`` ("zigzag",
        "triangle", "circle", "l"); keys left out take the stated defaults.
        None: no weave.
    first_segment, last_segment : int, optional
        1-based, inclusive; None: from the path's first / to its last.
    tracking : {"none", "arc", "laser"}, optional
        Seam tracking while welding; "arc" needs a weave. Default "none".
    position : {"PA", "PB"}, optional
        The welding position a positioner keeps the seam in (ISO 6947): "PA"
        flat (the default) or "PB" horizontal-vertical.

    Returns
    -------
    App.DocumentObject
        The Weld, in the cell's group.
    """
    args = Arguments("make_weld")
    args.open_document("doc", doc)
    args.cell(cell)
    args.document_object("path", path, "RobotPath")
    first_given = args.whole_number("first_segment", first_segment, optional=True,
                                    expected="None or a segment number (a whole number)")
    last_given = args.whole_number("last_segment", last_segment, optional=True,
                                   expected="None or a segment number (a whole number)")
    args.text("name", name)
    if schedule is not None and not isinstance(schedule, str) and not hasattr(schedule, "keys"):
        args.refuse("schedule", SCHEDULE_TEXT, schedule)
    weave_values = args.mapping("weave", weave)
    args.choice("tracking", tracking, TRACKING_SENSORS, optional=True)
    args.choice("position", position, POSITIONS)
    what = "Weld '%s'" % name
    if path not in reader.cell_paths(cell):
        raise InputError("%s: path %s is not in cell %s: give a path of the cell."
                         % (what, base.describe(path), base.describe(cell)), path.Name)
    segments = segment_range(path, first_given, last_given, what)
    welded_schedule, note = _schedule(cell, path, schedule, segments, what)
    welded_weave = Weave.from_dict(weave_values, what=what) if weave is not None else None
    welded_tracking = Tracking.from_dict(tracking or "none", what=what)
    weld_object.check_tracking(welded_tracking, welded_weave, what)
    obj = weld_object.make(doc, name)
    obj.Path = path
    obj.FirstSegment = first_given or 0
    obj.LastSegment = last_given or 0
    obj.Position = position
    weld_object.set_schedule(obj, welded_schedule, note)
    weld_object.set_weave(obj, welded_weave)
    weld_object.set_tracking(obj, welded_tracking)
    cell.addObject(obj)
    doc.recompute()
    return obj


def segment_range(path, first, last, what):
    """(first, last), 1-based, of the segments `first`..`last` of `path` (None: the
    path's first / last); InputError naming `what` (the weld) off the path."""
    count = len(reader.path_geometry(path)[0])
    first_number, last_number = first or 1, last or count
    if not 1 <= first_number <= last_number <= count:
        raise InputError("%s: segments %s-%s are not on path %s, which has segments 1-%d: give "
                         "1 <= first_segment <= last_segment <= %d (None: the path's ends)."
                         % (what, first_number, last_number, base.describe(path), count, count),
                         path.Name)
    return first_number, last_number


# --- the schedule ----------------------------------------------------------------------------

def _library():
    """Name -> WeldSchedule: the library's and the user's (api.weld_schedules as objects)."""
    from ..core import schedule_library
    return schedule_library.load(preferences.weld_schedule_folder())


def _schedule(cell, path, schedule, segments, what):
    """(WeldSchedule, note) for the `schedule` argument of :func:`make_weld`."""
    if isinstance(schedule, str):
        schedules = _library()
        if schedule not in schedules:
            raise InputError("%s: schedule '%s' is not in the library: use one of %s "
                             "(api.weld_schedules())." % (what, schedule, ", ".join(sorted(schedules))))
        return schedules[schedule].validated(what), ""
    if schedule is not None:
        values = dict(schedule)
        values.setdefault("travel_speed_mm_s", float(path.Speed))
        return WeldSchedule.from_dict(values, what=what), ""
    return library_pick(cell, path, segments, what)


def library_pick(cell, path, segments, what="The weld"):
    """(WeldSchedule, note): the library's schedule for the joint the faces along
    `segments` (first, last) of `path` show, at the thinner plate's thickness.

    Raises
    ------
    InputError
        No joint the library has schedules for, naming the weld and the faces.
    """
    from ..core import schedule_library
    first, last = segments
    _, samples = joint_faces.path_samples(cell, path.Name)
    samples = [s for s in samples if first <= s.segment <= last]
    detection = detect_joint(samples, path.Label)
    example = _example_sample(samples, detection.kind)
    thickness = plate_thickness_mm(cell, *example) if example is not None else None
    schedules = _library()
    try:
        schedule, sentence = schedule_library.lookup(schedules, detection.kind, thickness_mm=thickness)
    except CadRobotError as err:
        raise InputError("%s: the library has no schedule for it: %s %s Give schedule= a library "
                         "name or a dict." % (what, detection.reason, err), path.Name) from None
    measured = "" if thickness is None else " The thinner plate is %.1f mm thick." % thickness
    return schedule.validated(what), "%s%s %s." % (detection.reason, measured,
                                                   sentence[:1].upper() + sentence[1:])


def _example_sample(samples, kind):
    """(PathSample, faces) of the middle sample of `kind`, or None."""
    found = [(s, k.faces) for s, k in ((s, classify_sample(s)) for s in samples) if k.kind == kind]
    return found[len(found) // 2] if found and kind != "none" else None


def plate_thickness_mm(cell, sample, faces):
    """The thinner of the plates under `faces` at `sample`, mm: the length of a
    line through each face's solid along the face's inward normal, starting
    :data:`THICKNESS_PROBE_MM` into the face from the joint, up to where it first
    leaves the solid (a tube's wall, not both walls across its bore); None when
    no line crosses a solid."""
    import Part
    from ..objects.convert import vector_from_array
    shapes = {obj.Label: shape for obj, shape in joint_faces.workpiece_solids(cell)}
    lengths = []
    for face in faces:
        shape = shapes.get(face.solid)
        if shape is None:
            continue
        into = min(THICKNESS_PROBE_MM, face.extent_mm / 2)
        start = np.asarray(sample.point, float) + into * np.asarray(face.into, float)
        normal = np.asarray(face.normal, float)
        entry = vector_from_array(start + 1e-3 * normal)
        line = Part.makeLine(entry, vector_from_array(start - 1000.0 * normal))
        length = _first_piece_mm(shape.common(line), entry)
        if length > 1e-3:
            lengths.append(length)
    return min(lengths) if lengths else None


def _first_piece_mm(pieces, entry):
    """Length (mm) of the edge of `pieces` (a line cut by a solid) that starts at `entry`
    (FreeCAD.Vector), the face the line enters by; 0 when none does."""
    starting = [e.Length for e in pieces.Edges
                if min((v.Point - entry).Length for v in e.Vertexes) < 1e-2]
    return max(starting, default=0.0)


# --- listing -----------------------------------------------------------------------------------

def list_welds(doc):
    """Every Weld of `doc` as plain values (the CLI's ``welds`` command).

    Returns
    -------
    list of dict
        In document order: ``name``, ``label``, ``cell``, ``path``,
        ``segments`` ([first, last], 1-based; null for a path's end),
        ``schedule`` (the API dict), ``weave`` (dict or None), ``tracking``,
        ``length_mm`` (the seam welded), ``arc_time_s`` (length / travel
        speed + crater fill), or ``problem`` (one line) for a weld that cannot
        be read.
    """
    args = Arguments("list_welds")
    args.open_document("doc", doc)
    return [_weld_row(obj) for obj in base.objects_of_type(doc, "Weld")]


def _weld_row(obj):
    cell = weld_object.cell_of(obj)
    row = {"name": obj.Name, "label": obj.Label, "cell": cell.Label if cell is not None else None,
           "path": obj.Path.Label if obj.Path is not None else None,
           "segments": [int(obj.FirstSegment) or None, int(obj.LastSegment) or None]}
    try:
        weld_object.check_path(obj)
        schedule = weld_object.schedule_of(obj)
        weave = weld_object.weave_of(obj)
        length = weld_object.welded_length_mm(obj)
    except CadRobotError as problem:
        row["problem"] = " ".join(str(problem).split())
        return row
    row.update(schedule=schedule.as_dict(), weave=None if weave is None else weave.as_dict(),
               tracking=weld_object.tracking_of(obj).sensor, length_mm=round(length, 3),
               arc_time_s=round(length / schedule.travel_speed_mm_s + schedule.crater_fill_s, 3))
    return row
