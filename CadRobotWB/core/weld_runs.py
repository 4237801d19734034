"""The rules a program's weld runs keep (issue 22), checked in one place.

:func:`.generate.generate` calls :func:`check_runs` on every program it
makes; a post calls it on the program it is given, so a hand-built or edited
program with a broken run is refused with one line naming the run and the
rule, before any file is written. The rules are those of
:class:`.program.WeldRun`.

Pure Python; never imports FreeCAD.
"""

import numbers
import re

from ..errors import InputError
from .program import CIRCULAR, LINEAR, ROLE_PATH, ROLE_RISK
from .welding import WeldSchedule

#: Words in the comment of a welded move that runs slower than the schedule's travel speed
#: because the tool turns through a corner area (generate.CORNER_TURN_DEG_S).
CORNER_SLOWDOWN = "corner slow-down"
#: Two speeds closer than this are the same, mm/s.
SPEED_TOL_MM_S = 1e-9
_IDENTIFIER = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")


def check_runs(program):
    """Check every weld run of `program` against the rules of WeldRun.

    Parameters
    ----------
    program : program.Program

    Raises
    ------
    InputError
        One line naming the run (its name, label and path) and the rule it
        breaks: its name is not an identifier or not unique in the program;
        it has no schedule; not ``0 <= start < end < len(moves)``; it starts
        before the previous run on its path ends; a welded move (``start + 1
        .. end``) is not linear or circular, not a path or risk-area move (so
        an approach, entry or reorientation never welds), or its ``weld`` is
        not the run's name; a move outside every run names a weld; the start
        or end move does not stop exactly (zone 0); a welded move's speed is
        not the schedule's travel speed (only a corner slow-down may be
        slower).
    """
    used = set()
    for path in program.paths:
        _check_path_runs(path, used)


def _check_path_runs(path, used):
    """The rules for the runs of one ProgramPath; `used` collects lower-case names."""
    welded = {}
    previous = None
    for run in path.welds:
        what = _what(run, path)
        _check_name(run, what, used)
        if not isinstance(run.schedule, WeldSchedule):
            raise InputError("%s has no schedule: give it a welding.WeldSchedule." % what)
        _check_indices(run, path, what, previous)
        for k in range(run.start + 1, run.end + 1):
            _check_welded_move(run, path.moves[k], k, what)
            welded[k] = run.name
        _check_fine_ends(run, path, what)
        previous = run
    for k, move in enumerate(path.moves):
        if move.weld is not None and welded.get(k) != move.weld:
            raise InputError("Path '%s': move %d names weld %r but lies outside that weld's run: "
                             "mark only the moves start+1..end of a run." % (path.label, k, move.weld))


def _what(run, path):
    return "Weld run '%s' ('%s', part %d) on path '%s'" % (run.name, run.label, run.part, path.label)


def _check_name(run, what, used):
    if not isinstance(run.name, str) or not _IDENTIFIER.match(run.name):
        raise InputError("%s: its name must be an identifier of letters, digits and _ starting "
                         "with a letter (posts derive data names from it)." % what)
    if run.name.lower() in used:
        raise InputError("%s: another weld run of the program has the same name: give each run "
                         "a unique name." % what)
    used.add(run.name.lower())


def _check_indices(run, path, what, previous):
    if not (_is_index(run.start) and _is_index(run.end)
            and 0 <= run.start < run.end < len(path.moves)):
        raise InputError("%s: start %r and end %r must be move indices with start < end < %d "
                         "(the path's moves)." % (what, run.start, run.end, len(path.moves)))
    if previous is not None and run.start < previous.end:
        raise InputError("%s: it starts at move %d, before run '%s' ends (move %d): runs must be "
                         "in path order and must not overlap." % (what, run.start, previous.name,
                                                                  previous.end))


def _is_index(value):
    return isinstance(value, numbers.Integral) and not isinstance(value, bool)


def _check_welded_move(run, move, k, what):
    if move.kind not in (LINEAR, CIRCULAR):
        raise InputError("%s: welded move %d is a %s move: the arc burns only along linear and "
                         "circular moves." % (what, k, move.kind))
    if move.role not in (ROLE_PATH, ROLE_RISK):
        raise InputError("%s: welded move %d is an %s move: only path and risk-area moves weld, so "
                         "the approach ends at the seam start, never in the air." % (what, k, move.role))
    if move.weld != run.name:
        raise InputError("%s: welded move %d is marked weld=%r: every move start+1..end must name "
                         "its run." % (what, k, move.weld))
    travel = run.schedule.travel_speed_mm_s
    if abs(move.speed_mm_s - travel) <= SPEED_TOL_MM_S:
        return
    if move.speed_mm_s < travel and move.role == ROLE_RISK and CORNER_SLOWDOWN in move.comment:
        return
    raise InputError("%s: welded move %d runs at %g mm/s, not the schedule's travel speed %g mm/s "
                     "(only a corner slow-down may be slower)." % (what, k, move.speed_mm_s, travel))


def _check_fine_ends(run, path, what):
    for k, where in ((run.start, "start (ignition)"), (run.end, "end (crater)")):
        zone = path.moves[k].zone_mm
        if zone != 0.0:
            raise InputError("%s: its %s move %d has zone %g mm: the arc's start and end moves "
                             "must stop exactly (zone 0)." % (what, where, k, zone))
