"""The library of starting weld schedules, and the user's own schedules.

The library (``resources/weld_schedules.json``) holds published procedure
tables for GMAW of carbon steel with CO2 (issue 22, plan section (c)):
horizontal fillets by plate thickness and leg (Daihen OTC, rows
``fillet_t1.2`` ... ``fillet_t12``) and square-groove butts by thickness
(Panasonic, cross-checked with Daihen, rows ``butt_t0.8`` ... ``butt_t9``).
Each value is the midpoint of the published range; each row keeps its
source, its ranges and notes on what is not from the table.

The user keeps schedules in a folder (``preferences.weld_schedule_folder()``,
passed in by the App layer), one ``<name>.json`` per schedule as
:func:`save` writes it, or a file holding a list of them. A user schedule
with a library row's name replaces that row.

Pure Python; never imports FreeCAD.
"""

import copy
import dataclasses
import json
import math
import os
import re
import warnings

from ..errors import InputError
from .welding import WeldSchedule

_PACKAGE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
#: The library's table.
LIBRARY_PATH = os.path.join(_PACKAGE, "resources", "weld_schedules.json")
#: Joints the library has rows for.
LIBRARY_JOINTS = ("fillet", "butt")
#: Keys of a row that describe it, beside the schedule's own fields.
ROW_FACTS = ("joint", "plate_mm", "leg_mm", "root_gap_mm", "two_sided", "source_url", "notes")
#: A user schedule file larger than this is refused unread (bytes).
MAX_USER_FILE_BYTES = 1_000_000

_library = {}


class ScheduleFileWarning(UserWarning):
    """A user schedule file was skipped (its text names the file and the fix)."""


def library_rows():
    """The library's rows as read from its JSON table (cached; do not change them).

    Returns
    -------
    dict
        Name -> row: the schedule's fields, ``source``, ``ranges`` and the
        facts of :data:`ROW_FACTS`, in the table's order.
    """
    if not _library:
        with open(LIBRARY_PATH, encoding="utf-8") as f:
            _library.update(json.load(f)["schedules"])
    return _library


def _schedule_of_row(name, row, what):
    """The WeldSchedule of one row (a library row or a user file's): the API dict of
    the schedule, its ``ranges`` and the facts of :data:`ROW_FACTS`."""
    values = {k: v for k, v in row.items() if k not in ROW_FACTS + ("ranges",)}
    values.setdefault("name", name)
    ranges = row.get("ranges", {})
    if not isinstance(ranges, dict):
        raise InputError(f"{what}: ranges must be a dict of [lowest, highest] by field.")
    schedule = WeldSchedule.from_dict(values, what=what)
    return dataclasses.replace(schedule, ranges=copy.deepcopy(ranges))   # not the cache's lists


def load(user_folder=None, warn=None):
    """Every schedule a user can pick: the library's, then the user folder's.

    Parameters
    ----------
    user_folder : str, optional
        The user's schedule folder; each ``*.json`` in it holds one schedule
        (the API dict of :data:`.welding.SCHEDULE_FIELDS`, ``name`` defaulting
        to the file's name) or a list of them (each with its ``name``). A
        missing folder has no schedules.
    warn : callable, optional
        ``warn(text)`` is called once per user file skipped, with one line
        naming the file, what is wrong and the fix; default: a
        :class:`ScheduleFileWarning` by :func:`warnings.warn`.

    Returns
    -------
    dict
        Name -> :class:`.welding.WeldSchedule`, the library's rows in their
        order, then the user's by file name; a user schedule named like a
        library row replaces it. A broken user file (not JSON, an unknown key,
        a value out of its range) is skipped, never raised.
    """
    schedules = {name: _schedule_of_row(name, row, f"Library weld schedule {name}")
                 for name, row in library_rows().items()}
    if user_folder and os.path.isdir(user_folder):
        for entry in sorted(os.listdir(user_folder)):
            if entry.endswith(".json") and not entry.startswith("."):
                path = os.path.join(user_folder, entry)
                try:
                    schedules.update(_user_file(path))
                except InputError as exc:
                    _warn(warn, f"Weld schedule file '{path}' skipped: {exc} Fix the file or "
                                "delete it.")
    return schedules


def _warn(warn, text):
    text = " ".join(text.split())
    if warn is None:
        warnings.warn(text, ScheduleFileWarning, stacklevel=3)
    else:
        warn(text)


def _user_file(path):
    """name -> WeldSchedule of one user file; InputError saying what is wrong."""
    try:
        if os.path.getsize(path) > MAX_USER_FILE_BYTES:
            raise InputError(f"it is larger than {MAX_USER_FILE_BYTES} bytes.")
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"it cannot be read ({exc.__class__.__name__}: "
                         f"{getattr(exc, 'strerror', None) or exc}).") from None
    except json.JSONDecodeError as exc:
        raise InputError(f"it is not valid JSON (line {exc.lineno}, column {exc.colno}: "
                         f"{exc.msg}).") from None
    stem = os.path.basename(path)[:-len(".json")]
    rows = data if isinstance(data, list) else [data]
    found = {}
    for k, row in enumerate(rows):
        if not isinstance(row, dict):
            raise InputError("it must hold one schedule (a JSON object) or a list of them.")
        name = row.get("name", stem if not isinstance(data, list) else None)
        if not isinstance(name, str) or not name:
            raise InputError(f"its schedule {k + 1} has no name: give each schedule of a list "
                             "its \"name\" (a text).")
        found[name] = _schedule_of_row(name, row, f"Weld schedule '{name}'")
    return found


def _positive(value, argument):
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) \
            or not math.isfinite(value) or value <= 0:
        raise InputError(f"Weld schedule lookup: {argument} is {value!r}: give a positive "
                         "number of mm.")
    return float(value)


def _candidates(schedules, joint):
    """(name, row) of the library's rows of `joint` present in `schedules`."""
    return [(name, row) for name, row in library_rows().items()
            if row["joint"] == joint and name in schedules]


def _gap(value, low_high):
    """Distance of `value` from the interval `low_high` (0 inside)."""
    low, high = low_high
    return max(low - value, 0.0, value - high)


def lookup(schedules, joint_kind, thickness_mm=None, leg_mm=None):
    """The library schedule for a joint, and a sentence saying why it was picked.

    Rules: a fillet is picked by its leg when `leg_mm` is given (the rows
    whose leg range is nearest the leg -- containing it, if any; of several,
    the one whose plate is nearest `thickness_mm` if given, else the thinner
    plate's), otherwise by plate thickness; a butt by plate thickness. By
    thickness, the row of the nearest plate; on a tie, the thinner plate's
    (the lower heat input). Only library rows are picked (a user schedule
    that replaces a library row is picked in its place); the user picks any
    other schedule by name.

    Parameters
    ----------
    schedules : dict
        Name -> WeldSchedule, as :func:`load` returns it.
    joint_kind : str
        A joint kind of :mod:`..sensors.joint_detection` ("fillet", "butt",
        "lap", "v_groove", ...).
    thickness_mm, leg_mm : float, optional
        Plate thickness and fillet leg, mm.

    Returns
    -------
    schedule : WeldSchedule
    sentence : str
        E.g. "picked fillet_t6 (plate 6 mm, leg 5-6 mm) for a 6 mm plate".

    Raises
    ------
    InputError
        A joint the library has no rows for, no measure to pick by, or a
        measure that is not a positive number.
    """
    thickness_mm = _positive(thickness_mm, "thickness_mm")
    leg_mm = _positive(leg_mm, "leg_mm")
    if joint_kind not in LIBRARY_JOINTS:
        raise InputError(f"The weld schedule library has no rows for a {joint_kind!r} joint "
                         "(only fillet and butt): pick a schedule by name (api.weld_schedules()).")
    rows = _candidates(schedules, joint_kind)
    if not rows:
        raise InputError(f"No {joint_kind} schedule is left in the library: pick a schedule by "
                         "name (api.weld_schedules()).")
    if joint_kind == "fillet" and leg_mm is not None:
        name, row = _by_leg(rows, leg_mm, thickness_mm)
        why = f"for {_a_mm(leg_mm)} leg" + (f" on {_a_mm(thickness_mm)} plate"
                                             if thickness_mm is not None else "")
    elif thickness_mm is not None:
        name, row = min(rows, key=lambda r: (abs(r[1]["plate_mm"] - thickness_mm),
                                             r[1]["plate_mm"]))
        why = f"for {_a_mm(thickness_mm)} plate" + _outside_note(rows, thickness_mm)
    else:
        measure = "plate thickness_mm or leg_mm" if joint_kind == "fillet" else "thickness_mm"
        raise InputError(f"Weld schedule lookup for a {joint_kind} joint: give the {measure} "
                         "to pick a schedule by.")
    sentence = f"picked {name} ({_row_facts(row)}) {why}"
    if row.get("two_sided"):
        sentence += (f"; the table welds a {row['plate_mm']:g} mm plate from both sides (front, "
                     "then back): one pass from one side does not penetrate it fully -- weld the "
                     "back too or prepare a groove")
    if schedules[name] != _schedule_of_row(name, row, name):
        sentence += "; your own schedule of that name replaces the library's"
    return schedules[name], sentence


def _a_mm(value):
    """The measure with its article as the number is spoken: a 6 mm, an 8 mm, an 11 mm."""
    text = f"{value:g}"
    spoken_vowel = text.startswith("8") or re.match(r"1[18](\.|$)", text)
    return f"{'an' if spoken_vowel else 'a'} {text} mm"


def _by_leg(rows, leg_mm, thickness_mm):
    nearest = min(_gap(leg_mm, row["leg_mm"]) for _, row in rows)
    closest = [(name, row) for name, row in rows if _gap(leg_mm, row["leg_mm"]) == nearest]
    if thickness_mm is None:
        return closest[0]
    return min(closest, key=lambda r: (abs(r[1]["plate_mm"] - thickness_mm), r[1]["plate_mm"]))


def _outside_note(rows, thickness_mm):
    plates = [row["plate_mm"] for _, row in rows]
    if min(plates) <= thickness_mm <= max(plates):
        return ""
    return f" (outside the table's {min(plates):g}-{max(plates):g} mm: its nearest row)"


def _span(low_high):
    low, high = low_high
    return f"{low:g} mm" if low == high else f"{low:g}-{high:g} mm"


def _row_facts(row):
    if row["joint"] == "fillet":
        return f"plate {row['plate_mm']:g} mm, leg {_span(row['leg_mm'])}"
    return f"plate {row['plate_mm']:g} mm, root gap {_span(row['root_gap_mm'])}"


def save(user_folder, schedule):
    """Write `schedule` into the user folder as ``<name>.json``, atomically.

    Parameters
    ----------
    user_folder : str
        Created if missing.
    schedule : WeldSchedule
        Checked (:meth:`.welding.WeldSchedule.validated`) before anything is
        written; its name becomes the file's.

    Returns
    -------
    str
        The path written.

    Raises
    ------
    InputError
        A name that cannot be a file name, an invalid schedule, a folder that
        cannot be written.
    """
    from ..fileio import write_files_atomically
    from ..posts.output_check import file_name_problem

    name = schedule.name
    problem = ("it is empty" if not name else "it starts with '.'" if name.startswith(".")
               else file_name_problem(name + ".json"))
    if problem:
        raise InputError(f"Weld schedule name {name!r} cannot name its file ({problem}): use "
                         "letters, digits, '_', '-' and '.'.")
    schedule = schedule.validated(f"Weld schedule '{name}'")
    row = schedule.as_dict()
    if schedule.ranges:
        row["ranges"] = schedule.ranges
    text = json.dumps(row, indent=1, ensure_ascii=False) + "\n"
    return write_files_atomically(user_folder, [(name + ".json", text)])[0]


#: Columns of :func:`schedule_table`.
TABLE_COLUMNS = ("name", "joint", "plate mm", "leg/gap mm", "A", "V", "mm/s", "m/min", "source")


def schedule_table(schedules=None):
    """Rows of the schedule table for the README and ``cadrobot welds --schedules``.

    Parameters
    ----------
    schedules : dict, optional
        Name -> WeldSchedule (default: the library, :func:`load`). Rows not in
        the library show "-" for joint, plate and leg/gap.

    Returns
    -------
    list of tuple of str
        One row per schedule, the columns of :data:`TABLE_COLUMNS`; numbers
        written with ``:g`` (never a numpy repr); "-" for a value not given;
        a wire feed derived from the current ends in "*".
    """
    schedules = load() if schedules is None else schedules
    facts = library_rows()
    table = []
    for name, schedule in schedules.items():
        row = facts.get(name)
        if row is None:
            joint = plate = leg_or_gap = "-"
        else:
            joint, plate = row["joint"], f"{row['plate_mm']:g}"
            leg_or_gap = _span(row.get("leg_mm") or row["root_gap_mm"])[:-len(" mm")]
        table.append((name, joint, plate, leg_or_gap, _g(schedule.current_a),
                      _g(schedule.voltage_v), _g(schedule.travel_speed_mm_s),
                      _g(schedule.wire_feed_m_min) + ("*" if schedule.wire_feed_estimated else ""),
                      schedule.source.split(", row ")[0] or "-"))
    return table


def _g(value):
    return "-" if value is None else f"{float(value):g}"
