"""The weld schedules a user can pick: the library's and the user's own (issue 22).

Part of the scripting API: :mod:`CadRobotWB.api` re-exports its public names.
"""

from .. import preferences
from ..core import schedule_library
from ..core.welding import WeldSchedule
from .arguments import Arguments

_reported = set()


def weld_schedules():
    """Every weld schedule a user can pick, by name: the library's starting schedules
    (``core/schedule_library``: published fillet and butt tables), then the user's own
    from ``preferences.weld_schedule_folder()`` (a user schedule named like a library
    row replaces it).

    A user file that cannot be read is skipped with one warning naming it (in
    FreeCAD's report view in the GUI, a Python warning otherwise).

    Returns
    -------
    dict
        Name -> the API dict of the schedule (the keys of
        ``core.welding.SCHEDULE_FIELDS``, ``name``, ``process``, ``gas``,
        ``source`` and ``wire_feed_estimated``), library rows first.
    """
    problems = []
    schedules = schedule_library.load(preferences.weld_schedule_folder(), warn=problems.append)
    _report(problems)
    return {name: schedule.as_dict() for name, schedule in schedules.items()}


def _report(problems):
    import warnings

    import FreeCAD
    for problem in problems:
        if not FreeCAD.GuiUp:
            warnings.warn(problem, schedule_library.ScheduleFileWarning, stacklevel=3)
        elif problem not in _reported:
            _reported.add(problem)
            FreeCAD.Console.PrintWarning("CadRobot: %s\n" % problem)


def save_weld_schedule(name, values):
    """Keep a weld schedule of the user's own, by name, for later sessions.

    Parameters
    ----------
    name : str
        The schedule's name, also its file's (``<name>.json`` in
        ``preferences.weld_schedule_folder()``); the name of a library row
        makes it replace that row.
    values : dict
        The API dict of the schedule (keys of ``core.welding.SCHEDULE_FIELDS``
        and ``process``, ``gas``, ``source``); keys left out take the stated
        defaults; voltage, travel speed and the current or wire feed are
        required. A ``name`` in it must be `name`.

    Returns
    -------
    str
        The path of the file written.

    Raises
    ------
    ArgumentError
        `name` not a str, `values` not a dict.
    InputError
        A name that cannot be a file name, an unknown key, a value out of its
        range (one line naming the key and the range).
    """
    args = Arguments("save_weld_schedule")
    name = args.text("name", name, expected="a schedule name (a str)")
    if values is None:
        args.refuse("values", "a dict of schedule values (see core.welding.SCHEDULE_FIELDS)",
                    values)
    values = args.mapping("values", values)
    if values.setdefault("name", name) != name:
        args.fail("values['name'] is %r, not the name %r: leave it out or make them one."
                  % (values["name"], name))
    schedule = WeldSchedule.from_dict(values, what="save_weld_schedule: schedule '%s'" % name)
    return schedule_library.save(preferences.weld_schedule_folder(), schedule)
