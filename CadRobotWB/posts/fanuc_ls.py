"""Fanuc LS post-processor: teach-pendant programs in ASCII form (``.LS``).

Layout of the program written by :func:`export`::

    /PROG  CELL
    /ATTR
    OWNER       = MNEDITOR;
    COMMENT     = "CadRobot";
    ...                                  (PROG_SIZE, CREATE, ..., LINE_COUNT, TCD)
    DEFAULT_GROUP   = 1,*,*,*,*;
    CONTROL_CODE    = 00000000 00000000;
    /MN
       1:  !CadRobot post fanuc_ls ;     comments: source, units, frames, tool
      ..:  UFRAME_NUM=1 ;
      ..:  UTOOL_NUM=1 ;
      ..:J P[1] 10% CNT10    ;
      ..:L P[2] 75cm/min FINE    ;
      ..:C P[5]    
        :  P[6] 75cm/min FINE    ;      circular: via, then end (one line)
    /POS
    P[1]{                                joint position (joint move, joints solved)
       GP1:
        UF : 1, UT : 1,
        J1=   -2.5880 deg,  J2=    4.7954 deg,  J3=  -32.4754 deg,
        J4=   36.4808 deg,  J5=   32.8482 deg,  J6=   71.1327 deg
    };
    P[2]{                                Cartesian position
       GP1:
        UF : 1, UT : 1,     CONFIG : 'N U T, 0, 0, 0',
        X =     0.000  mm,  Y =     0.000  mm,  Z =     0.000  mm,
        W =   180.0000 deg, P =     0.0000 deg, R =     0.0000 deg
    };
    /END

``LINE_COUNT`` is the number of numbered ``/MN`` lines (a circular move is
one line written on two).  Every motion instruction has its own ``P[n]``,
numbered in the order of use; ``UFRAME_NUM`` is set again before a move in
another work frame, so that each position's ``UF`` is the active one.

Long programs
-------------
A program of more than ``max_lines`` numbered lines (default 9999: line
numbers have four digits, and RoboDK's Fanuc posts split at
``MAX_LINES_X_PROG = 9999``) or more than ``max_positions`` positions
(default 9999, CadRobot's bound: no Fanuc document at hand gives the
controller's limit) is split.  The main program keeps the name, the header
comments, UFRAME_NUM, UTOOL_NUM (and PAYLOAD) and calls each part in
order (``CALL NAME_1 ;``); parts are named ``NAME_1`` .. ``NAME_n``
(:func:`part_names`), each opens with a comment, the UFRAME_NUM active
where it starts and UTOOL_NUM, and numbers its lines and positions from 1.

Units and conventions
---------------------
* Positions in the user frame: X, Y, Z in mm (3 decimals, as the controller
  writes them), W, P, R in degrees with 4 decimals - one more than the
  controller writes, so that the orientation survives to 1e-4 degree; the
  ASCII loader reads them as real numbers (not verified on a controller;
  ``angle_decimals=3`` writes the controller's own form).  ``R = Rz(R)
  Ry(P) Rx(W)`` (fixed axes X, then Y, then Z).
* Linear and circular speeds: ``mm/sec`` when the speed is a whole number
  of mm/s, otherwise ``cm/min`` (whole numbers: 1 cm/min = 0.1667 mm/s, so
  12.5 mm/s is exactly ``75cm/min``), since teach-pendant speeds are
  integers.
* Joint moves: ``%`` of the maximum joint speeds, a whole number 1..100:
  ``100 * speed_mm_s / joint_speed_reference_mm_s`` (default 1000 mm/s),
  or option ``joint_speed_percent`` for every joint move.
* Termination from the move's zone: ``CNTn`` with ``n = min(100,
  floor(zone_mm / cnt_mm))`` (option ``cnt_mm``, default 0.01 mm per step:
  CNT100 for a zone of 1 mm or more, the automatic zone of points 2 mm
  apart), ``FINE`` when n is 0 (zone 0, or below one step).  CNT is not a distance: it sets how much
  of the deceleration is cut, so the real rounding grows with speed;
  ``cnt_mm`` mm per CNT step is CadRobot's rule, not Fanuc's.
* Joint moves whose target has solved joints go to a joint position
  (``J1= .. J6=`` in the controller's convention,
  :func:`~CadRobotWB.posts.common.controller_joints_deg`: J3 against the
  horizontal on Fanuc arms), so the controller cannot pick another arm
  configuration; option ``joint_targets=false`` writes Cartesian positions.
* ``CONFIG`` from ``Target.joints_deg`` with
  :func:`~CadRobotWB.robots.motion.configuration_data.fanuc_configs` (for all
  positions at once; not verified against a Fanuc manual, see
  ``fanuc_config``'s docstring); a target without joints gets
  ``'N U T, 0, 0, 0'`` (no flip, up, toward, no turns), the usual
  configuration, and the program's comments say so.

Frames and tool
---------------
Positions are in user frame ``user_frame`` (option; default 1; several work
frames take consecutive numbers, or a dict ``{frame name: number}``) with
tool ``tool`` (default 1).  Their values - the work frame in the robot's
world frame, taken as its base frame (``WorkFrame.T_r_b``), and the tool in
the faceplate frame (``ToolData.T_f_t``) - are written as comments for
direct entry on the frame setup screens.  The tool's mass and centre of
gravity are comments too, for the payload screen; option
``payload_schedule`` = n adds a ``PAYLOAD[n]`` instruction after
UTOOL_NUM (syntax not checked against a Fanuc manual, see
docs/controllers.md).

Program names are upper case ``A-Z``, ``0-9``, ``_``, starting with a
letter, at most ``max_name_length`` characters: 8 by default, which every
controller takes (older R-J3 controllers allow no more; R-30iA/R-30iB
accept longer names, up to 36, as commonly documented - not verified
here).  A longer name is cut and ends with three characters of a hash of
the whole name.

Welds
-----
A path with weld runs (issue 22) is written as an ArcTool program: ``/APPL``
with ``ARC : TRUE``, ``Arc Start[n]`` as the continuation line of the move
ending at the seam start, inline ``Weave Sine[Hz, mm, s, s]``, ``Track
TAST[n]`` for through-arc tracking, ``WELD_SPEED`` on the welded moves,
``Arc End[n]``, ``Weave End``, ``Track End`` after the last; options
``weld_schedule`` and ``weld_speed``.  A split never cuts a weld.  What is
written and what is not verified: docs/controllers.md, FANUC, Welding.

External axes
--------------
A program with external axes (issue 23) writes a positioner as motion
group 2 (``DEFAULT_GROUP = 1,1,*,*,*;``, a ``GP2:`` block with ``J1..`` in
degrees in every position), a track as ``E1..`` (mm) of group 1, and
``COORD`` on the path's linear and circular moves; positions are in the
work frame as drawn (:func:`common.pose_in_drawn_frame`).  Sources and what
is not verified: docs/controllers.md, External axes.

The output is deterministic: ``CREATE``/``MODIFIED`` come from
``options["date"]`` (a ``datetime``) or 2000-01-01 00:00:00.  Lines end
with CR LF.

Pure Python/numpy: never imports FreeCAD.
"""

import datetime
import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from ..core import program as ir
from ..core import rotations
from ..errors import PostError
from ..robots.motion import configuration_data
from . import common
from .common import compact, fixed, round_half_up

NAME = "fanuc_ls"
DESCRIPTION = "Fanuc teach pendant program in ASCII form for R-30iA / R-30iB controllers (.LS)"
FILE_EXTENSIONS = (".LS",)

NEWLINE = "\r\n"
DEFAULT_NAME_LENGTH = 8
MAX_NAME_LENGTH = 36
#: Characters of a ``!`` comment we write per line.
COMMENT_WIDTH = 32
#: User frames 0 (world) .. 9 and tools 1 .. 10 of a standard controller.
USER_FRAMES = (0, 9)
TOOLS = (1, 10)
#: Payload schedules PAYLOAD[1] .. PAYLOAD[10].
PAYLOAD_SCHEDULES = (1, 10)
DEFAULT_CONFIG = "N U T, 0, 0, 0"
DEFAULT_JOINT_REFERENCE_MM_S = 1000.0
DEFAULT_DATE = datetime.datetime(2000, 1, 1, 0, 0, 0)
#: Numbered /MN lines of one program: line numbers have 4 digits (RoboDK's
#: Fanuc posts split at ``MAX_LINES_X_PROG = 9999``).
MAX_LINES = 9999
#: Positions P[n] of one program (CadRobot's bound, see the module docstring).
MAX_POSITIONS = 9999
#: Fewest lines a split program may have: a part's 3 opening lines and a move.
MIN_LINES = 4
#: Millimetres of zone per CNT step (CadRobot's rule, see :func:`termination`).
DEFAULT_CNT_MM = 0.01

OPTIONS = {
    "program_name": "program (and file) name, A-Z 0-9 _ starting with a letter; default "
                    "from the program",
    "max_name_length": "longest program name, 1..36 (default 8, which every controller takes)",
    "user_frame": "UF number of the first work frame (0..9, default 1), or {frame: number}",
    "tool": "UT number, 1..10 (default 1)",
    "joint_speed_percent": "speed of every joint move, 1..100 % (default: from the move's speed)",
    "joint_speed_reference_mm_s": "speed that is 100 % for a joint move, mm/s (default 1000)",
    "angle_decimals": "decimals of W, P, R and of joint values: 4 (default) or 3",
    "joint_targets": "true (default): joint moves with solved joints go to joint positions "
                     "J1..J6; false: Cartesian positions with CONFIG",
    "max_lines": "numbered lines per program, 4..9999 (default 9999): a longer program is "
                 "split into parts CALLed by a main program",
    "max_positions": "positions P[n] per program, 2..9999 (default 9999)",
    "cnt_mm": "mm of zone per CNT step (default 0.01: CNT100 from 1 mm): CNTn with "
              "n = floor(zone / cnt_mm), FINE below one step",
    "payload_schedule": "PAYLOAD[n] instruction before the motion, n = 1..10 (default: none)",
    "weld_schedule": "weld schedule n of Arc Start[n]/Arc End[n] (and TAST[n]) of the first "
                     "weld schedule, 1..99 (default 1); other schedules take the next numbers",
    "weld_speed": "schedule (default): welded moves at WELD_SPEED, the weld schedule's travel "
                  "speed (a corner slow-down keeps its own speed); explicit: every welded "
                  "move's speed written on it",
}

#: Weld schedules Arc Start[1] .. Arc Start[99] (CadRobot's bound; the controller's number of
#: schedules was not verified).
WELD_SCHEDULES = (1, 99)
WELD_SPEEDS = ("schedule", "explicit")
#: A welded move within this of its schedule's travel speed runs at ``WELD_SPEED``; a slower
#: one (a corner slow-down, core/weld_runs) keeps its own speed, mm/s.
SPEED_TOL_MM_S = 1e-9
#: Weave pattern -> ArcTool's name, for the inline ``Weave <name>[Hz, mm, s, s]``.
#: Sine with inline values: public LS programs (docs/controllers.md, FANUC Welding).
#: unverified: Circle and L take the same four inline values (seen only as ``Weave Circle[n]``,
#: ``Weave L[n]`` with a schedule number). Triangle: not written (what ArcTool's
#: ``Sine 2`` is was not found).
WEAVE_PATTERNS = {"zigzag": "Sine", "circle": "Circle", "l": "L", "triangle": None}
#: The /APPL section of an ArcTool program (between /ATTR and /MN, as the controller writes it).
APPL_LINES = ("/APPL", "  ARC : TRUE ;", "  ARC Welding Equipment : 1,*,*,*,*;", "")

_MOTION = {ir.JOINT: "J", ir.LINEAR: "L", ir.CIRCULAR: "C"}


def export(program, options=None):
    """Write a program as LS programs: one, or a main and its parts.

    Parameters
    ----------
    program : CadRobotWB.core.program.Program
        Targets in their work frames {B}, mm.
    options : dict, optional
        See :data:`OPTIONS`; also ``"date"`` (``datetime.datetime``, for
        CREATE and MODIFIED).  Other keys are ignored here
        (:func:`CadRobotWB.posts.run` refuses them).

    Returns
    -------
    list of (str, str)
        ``[(f"{name}.LS", text)]`` when the program fits in ``max_lines``
        lines and ``max_positions`` positions; else the main program first,
        then its parts in the order it calls them.

    Raises
    ------
    PostError
        The program or an option cannot be expressed in LS.
    """
    settings = _Settings.from_options(dict(options or {}), program)
    for move in program.moves():
        common.check_move(move, program, _MOTION, NAME,
                          kinds_text="joint, linear and circular")
    common.check_weld_runs(program, "FANUC ArcTool", tracking=("none", "arc"))
    name = _program_name(program, settings)
    moves = program.moves()
    first_frame = settings.users[moves[0].frame] if moves else None
    head = [("text", "!" + line) for line in _header_comments(program, settings)]
    head += _setup_lines(first_frame, settings)
    motion = _motion_entries(program, settings)
    if _fits(head + motion, settings):
        return [_file(name, head + motion, settings)]
    return _split_files(name, head, motion, first_frame, settings)


# --- program body ----------------------------------------------------------------------------

def _setup_lines(first_frame, settings):
    """UFRAME_NUM (of the first move's frame), UTOOL_NUM and PAYLOAD[n]."""
    lines = []
    if first_frame is not None:
        lines.append(("frame", first_frame))
    lines.append(("text", f"UTOOL_NUM={settings.tool}"))
    if settings.payload is not None:
        lines.append(("text", f"PAYLOAD[{settings.payload}]"))
    return lines


def _motion_entries(program, settings):
    """The /MN entries of the paths: ``("text", body)``, ``("frame", UF number)``
    and ``("move", move)``, in order; a frame entry where the work frame changes."""
    entries = []
    moves = program.moves()
    frame = moves[0].frame if moves else None
    for path in program.paths:
        if path.moves and path.moves[0].frame != frame:
            frame = path.moves[0].frame
            entries.append(("frame", settings.users[frame]))
        for line in _wrap("Path: " + common.path_label(path)):
            entries.append(("text", "!" + line))
        last_comment = None
        out = entries
        for index, move in enumerate(path.moves):
            starting = common.weld_run_starting(path, index)
            if starting is not None and out is entries:     # a weld (or touching welds) opens
                out, block_run = [], starting
            if move.frame != frame:
                frame = move.frame
                out.append(("frame", settings.users[frame]))
            text = _comment_text(move.comment)
            if text and text != last_comment:
                out += [("text", "!" + line) for line in _wrap(text)]
            last_comment = text
            out += _weld_move_entries(move, index, path, settings)
            if common.weld_run_ending(path, index) is not None and starting is None:
                entries.append(("run", out, block_run))
                out = entries
    return entries


def _weld_move_entries(move, index, path, settings):
    """The entries of one move: the move (with ``Arc Start[n]`` or ``Arc End[n]``
    as its continuation line at a weld's start or end), then the weave and
    tracking lines that follow it.  Where two welds touch, the move ends the
    first (``Arc End[n]``, ``Weave End``, ``Track End``) and the second
    strikes with ``Arc Start[m]`` on a line of its own."""
    options, after = [], []
    ending = common.weld_run_ending(path, index)
    if ending is not None:
        options.append(f"Arc End[{settings.schedule_numbers[ending.name]}]")
        after += [] if ending.weave is None else [("text", "Weave End")]
        after += [("text", "Track End")] if ending.tracking.sensor == "arc" else []
    starting = common.weld_run_starting(path, index)
    if starting is not None:
        n = settings.schedule_numbers[starting.name]
        if options:
            after.append(("text", f"Arc Start[{n}]"))
        else:
            options.append(f"Arc Start[{n}]")
        after += [] if starting.weave is None else [("text", _weave_text(starting))]
        after += [("text", f"Track TAST[{n}]")] if starting.tracking.sensor == "arc" else []
    return [("move", move, *options)] + after


def _weave_text(run):
    """``Weave Sine[f Hz, amplitude mm, right dwell s, left dwell s]`` of a run.

    The amplitude is half the weave's full width (unverified, see
    docs/controllers.md); the frequency at the schedule's travel speed.
    """
    weave = run.weave
    pattern = common.weave_pattern_for("FANUC ArcTool", run, WEAVE_PATTERNS)
    what = f"Weld {run.name!r} ({run.label})"
    if weave.dwell_center_s:
        raise PostError(f"{what}: FANUC's inline weave has no centre dwell: set "
                        "dwell_center_s to 0.")
    if weave.angle_deg:
        raise PostError(f"{what}: FANUC's inline weave has no angle (it is set in the weave "
                        "schedule): set angle_deg to 0.")
    frequency = weave.frequency(run.schedule.travel_speed_mm_s)
    return (f"Weave {pattern}[{fixed(frequency, 1)}Hz,{fixed(weave.width_mm / 2, 1)}mm,"
            f"{fixed(weave.dwell_right_s, 3)}s,{fixed(weave.dwell_left_s, 3)}s]")


def _flat(entries):
    """Entries with each weld run's entries in its place."""
    out = []
    for entry in entries:
        out += entry[1] if entry[0] == "run" else [entry]
    return out


def _lines_of(entry):
    """Numbered /MN lines of an entry: those of a weld run's entries, else 1."""
    return len(entry[1]) if entry[0] == "run" else 1


def _positions_of(entry):
    """Positions P[n] an entry uses: 2 for a circular move, 1 for another move,
    those of its moves for a weld run, else 0."""
    if entry[0] == "run":
        return sum(map(_positions_of, entry[1]))
    if entry[0] != "move":
        return 0
    return 2 if entry[1].kind == ir.CIRCULAR else 1


def _fits(entries, settings):
    return (sum(map(_lines_of, entries)) <= settings.max_lines
            and sum(map(_positions_of, entries)) <= settings.max_positions)


# --- long programs ---------------------------------------------------------------------------

def split_entries(entries, max_lines, max_positions, opening_lines):
    """Cut /MN entries into parts within a program's limits.

    Parameters
    ----------
    entries : list of tuple
        From :func:`_motion_entries`.
    max_lines, max_positions : int
        Limits of one program.
    opening_lines : int
        Lines every part starts with before its entries.

    Returns
    -------
    list of list
        Consecutive parts, each of at most ``max_lines - opening_lines``
        lines using at most ``max_positions`` positions; a weld run's
        entries stay in one part (it is cut before the run's start move).

    Raises
    ------
    PostError
        A weld run longer than one part.
    """
    room = max_lines - opening_lines
    parts, part, lines, used = [], [], 0, 0
    for entry in entries:
        cost, length = _positions_of(entry), _lines_of(entry)
        if entry[0] == "run" and (length > room or cost > max_positions):
            run = entry[2]
            raise PostError(f"Weld {run.name!r} ({run.label}) needs {length} lines and {cost} "
                            f"positions, more than one program holds (max_lines={max_lines}, "
                            f"max_positions={max_positions}); raise max_lines or "
                            "max_positions so the arc is not cut.")
        if part and (lines + length > room or used + cost > max_positions):
            parts.append(part)
            part, lines, used = [], 0, 0
        part.append(entry)
        lines += length
        used += cost
    return parts + [part] if part else parts


def part_names(main, count, max_length):
    """Names of the parts of program `main`: ``MAIN_1`` .. ``MAIN_n``.

    Parameters
    ----------
    main : str
        The main program's name.
    count : int
        Number of parts.
    max_length : int
        Longest name.

    Returns
    -------
    list of str
        Unique, different from `main`, all of one length: the digits have
        the width of `count`, the stem is `main` cut to fit; the separator
        is ``_``, or ``P`` when ``_`` would repeat `main`'s own name.

    Raises
    ------
    PostError
        `max_length` leaves no room for a letter, a separator and the digits.
    """
    width = len(str(count))
    stem_length = min(len(main), max_length - 1 - width)
    if stem_length < 1:
        raise PostError(f"A program split into {count} parts needs part names of at least "
                        f"{width + 2} characters; raise max_name_length (now {max_length}) "
                        "or max_lines.")
    for separator in ("_", "P"):
        names = [f"{main[:stem_length]}{separator}{k:0{width}d}" for k in range(1, count + 1)]
        if main not in names:
            return names
    raise AssertionError("unreachable: main matches at most one separator")


def _split_files(name, head, motion, first_frame, settings):
    """The main program (head, then a CALL of each part) and its parts.

    Each part opens with a comment naming it, UFRAME_NUM of the frame active
    where it starts, and UTOOL_NUM, so it also runs on its own.
    """
    chunks = split_entries(motion, settings.max_lines, settings.max_positions, 3)
    names = part_names(name, len(chunks), settings.name_length)
    main = head + [("text", f"CALL {part}") for part in names]
    if len(main) > settings.max_lines:
        raise PostError(f"The main program calling {len(chunks)} parts needs {len(main)} lines, "
                        f"more than max_lines {settings.max_lines}; raise max_lines.")
    files = [_file(name, main, settings)]
    frame = first_frame
    for number, (part, chunk) in enumerate(zip(names, chunks), start=1):
        comment = _wrap(f"Part {number} of {len(names)} of {name}")[0]
        opening = [("text", "!" + comment), ("frame", frame),
                   ("text", f"UTOOL_NUM={settings.tool}")]
        files.append(_file(part, opening + chunk, settings))
        frame = next((e[1] for e in reversed(_flat(chunk)) if e[0] == "frame"), frame)
    return files


# --- text of one program ---------------------------------------------------------------------

def _file(name, entries, settings):
    """``(file name, text)`` of one LS program with these /MN entries; with
    the /APPL section of ArcTool when it holds a weld run."""
    welds = any(entry[0] == "run" for entry in entries)
    entries = _flat(entries)
    lines, positions = [], []
    for number, entry in enumerate(entries, start=1):
        if entry[0] == "text":
            lines.append(f"{number:4d}:  {entry[1]} ;")
        elif entry[0] == "frame":
            lines.append(f"{number:4d}:  UFRAME_NUM={entry[1]} ;")
        else:
            lines += _move_lines(number, entry, positions, settings)
    text = [f"/PROG  {name}", "/ATTR"]
    text += _attributes(settings, line_count=len(entries))
    text += list(APPL_LINES) if welds else []
    text += ["/MN"] + lines + ["/POS"]
    text += _position_records(positions, settings)
    text.append("/END")
    return common.file_name(name, ".LS"), NEWLINE.join(text) + NEWLINE


def _move_lines(number, entry, positions, settings):
    """The line(s) of one ``("move", move[, option])`` entry; appends its
    positions ``(target, frame, joint)``.  An option (``Arc Start[1]``) is a
    continuation line of its own, as the controller writes it."""
    move = entry[1]
    speed = _speed_text(move, settings)
    term = termination(move.zone_mm, settings.cnt_mm)
    if _positioner(settings) and common.is_coordinated_move(move):
        term += " COORD"
    if move.kind == ir.CIRCULAR:
        positions += [(move.via, move.frame, False), (move.target, move.frame, False)]
        n = len(positions)
        lines = [f"{number:4d}:C P[{n - 1}]    ", f"    :  P[{n}] {speed} {term}    ;"]
    else:
        joint = common.is_joint_target_move(move, settings.joint_targets)
        positions.append((move.target, move.frame, joint))
        lines = [f"{number:4d}:{_MOTION[move.kind]} P[{len(positions)}] {speed} {term}    ;"]
    if len(entry) > 2:
        lines[-1] = lines[-1][:-len("    ;")]
        lines.append(f"    :  {entry[2]}    ;")
    return lines


# --- names -----------------------------------------------------------------------------------

def program_name(text, max_length=DEFAULT_NAME_LENGTH):
    """A valid program name made from any text.

    Parameters
    ----------
    text : str
    max_length : int

    Returns
    -------
    str
        Upper case ``A-Z``, ``0-9``, ``_``, starting with a letter (``P``
        is put in front otherwise).  A longer name is cut to
        ``max_length - 3`` characters followed by three characters of a
        hash of the whole name.
    """
    return common.upper_name(text, max_length, prefix="P", empty="PROG")


def is_program_name(text, max_length=DEFAULT_NAME_LENGTH):
    """True for 1 to ``max_length`` characters ``[A-Z][A-Z0-9_]*``."""
    return common.is_upper_name(text, max_length)


def _program_name(program, settings):
    requested = settings.requested_name
    if requested is None:   # the program's name is its file's name
        return program_name(common.file_stem(program.name), settings.name_length)
    if not isinstance(requested, str) or not is_program_name(requested.upper(),
                                                             settings.name_length):
        raise PostError(f"Program name {requested!r} is not valid: use 1 to "
                        f"{settings.name_length} letters, digits or '_', starting with a "
                        "letter (max_name_length allows up to 36 on R-30iA/B).")
    common.check_file_stem(requested.upper(), "program_name")
    return requested.upper()


# --- options ---------------------------------------------------------------------------------

def _frame_numbers(program, user_frame):
    """UF number of each work frame (see the module docstring)."""
    return common.frame_numbers(
        program, user_frame, *USER_FRAMES,
        overflow="{count} work frames need user frames {first} to {last}, beyond UF {high}; "
                 "pass a smaller user_frame or a dict.")


@dataclass
class _Settings:
    requested_name: Optional[str]
    name_length: int
    users: dict
    tool: int
    joint_percent: Optional[int]
    joint_reference_mm_s: float
    angle_decimals: int
    joint_targets: bool
    max_lines: int
    max_positions: int
    cnt_mm: float
    payload: Optional[int]
    date: datetime.datetime
    spec: object
    program: object
    weld_speed: str
    schedule_numbers: dict
    travel_speeds: dict

    @classmethod
    def from_options(cls, options, program):
        """Every option read and checked (see :data:`OPTIONS`)."""
        return cls(
            requested_name=options.get("program_name"),
            name_length=common.whole_option(options, "max_name_length", DEFAULT_NAME_LENGTH,
                                            1, MAX_NAME_LENGTH),
            users=_frame_numbers(program, options.get("user_frame", 1)),
            tool=common.whole_option(options, "tool", 1, *TOOLS),
            joint_percent=_optional_whole(options, "joint_speed_percent", 1, 100),
            joint_reference_mm_s=common.positive_number(options, "joint_speed_reference_mm_s",
                                                        DEFAULT_JOINT_REFERENCE_MM_S),
            angle_decimals=common.whole_option(options, "angle_decimals", 4, 3, 4),
            joint_targets=common.joint_targets_option(options),
            max_lines=common.whole_option(options, "max_lines", MAX_LINES, MIN_LINES, MAX_LINES),
            max_positions=common.whole_option(options, "max_positions", MAX_POSITIONS, 2,
                                              MAX_POSITIONS),
            cnt_mm=common.positive_number(options, "cnt_mm", DEFAULT_CNT_MM),
            payload=_optional_whole(options, "payload_schedule", *PAYLOAD_SCHEDULES),
            date=common.date_option(options, DEFAULT_DATE),
            spec=common.opw_robot_spec(program),
            program=program,
            weld_speed=common.choice_option(options, "weld_speed", "schedule", WELD_SPEEDS),
            schedule_numbers=_schedule_numbers(
                program, common.whole_option(options, "weld_schedule", 1, *WELD_SCHEDULES)),
            travel_speeds={run.name: run.schedule.travel_speed_mm_s
                           for _, run in program.weld_runs()})


def _schedule_numbers(program, first):
    """Weld schedule number of each weld run, by run name: `first` for the
    first schedule, the next numbers for other schedules in order of use.

    Raises
    ------
    PostError
        More schedules than numbers from `first` to :data:`WELD_SCHEDULES`' end.
    """
    numbers, by_schedule = {}, {}
    for _, run in program.weld_runs():
        number = by_schedule.setdefault(run.schedule, first + len(by_schedule))
        if number > WELD_SCHEDULES[1]:
            raise PostError(f"Weld {run.name!r} ({run.label}) would use weld schedule "
                            f"{number}, beyond {WELD_SCHEDULES[1]}; pass a smaller "
                            "weld_schedule.")
        numbers[run.name] = number
    return numbers


def _optional_whole(options, key, low, high):
    """A whole-number option that may be left out (None)."""
    return common.whole_option(options, key, None, low, high) if key in options else None


# --- motion values ---------------------------------------------------------------------------

def termination(zone_mm, cnt_mm=DEFAULT_CNT_MM):
    """Termination type of a move's zone: ``FINE`` or ``CNTn``.

    Parameters
    ----------
    zone_mm : float
        The zone asked for, mm (0: stop at the point).
    cnt_mm : float, optional
        Millimetres of zone per CNT step (CadRobot's rule; CNT is not a
        distance on the controller).

    Returns
    -------
    str
        ``CNTn`` with ``n = min(100, floor(zone_mm / cnt_mm))``, rounded
        down so the rule never gives more rounding than asked; ``FINE``
        when ``n`` is 0 (a zone below one step).
    """
    steps = min(100, math.floor(zone_mm / cnt_mm + 1e-9))
    return "FINE" if steps < 1 else f"CNT{steps}"


def linear_speed(speed_mm_s):
    """Speed text of a linear or circular move.

    Returns
    -------
    str
        ``"100mm/sec"`` for a whole number of mm/s, else the nearest whole
        ``cm/min`` (``"75cm/min"`` for 12.5 mm/s).

    Raises
    ------
    PostError
        Below 1 cm/min.
    """
    whole = round_half_up(speed_mm_s)
    if whole >= 1 and abs(speed_mm_s - whole) < 1e-9:
        return f"{whole:d}mm/sec"
    cm_min = round_half_up(speed_mm_s * 6.0)
    if cm_min < 1:
        raise PostError(f"Speed {speed_mm_s} mm/s is below 1 cm/min, the slowest speed a "
                        "Fanuc linear move takes.")
    return f"{cm_min:d}cm/min"


def joint_speed_percent(speed_mm_s, fixed_percent=None,
                        reference_mm_s=DEFAULT_JOINT_REFERENCE_MM_S):
    """Joint move speed, whole percent 1..100: ``fixed_percent`` or
    ``round(100 * speed / reference)``."""
    value = fixed_percent if fixed_percent is not None else 100.0 * speed_mm_s / reference_mm_s
    return min(100, max(1, round_half_up(value)))


def _speed_text(move, settings):
    if settings.weld_speed == "schedule" and move.weld is not None and \
            abs(move.speed_mm_s - settings.travel_speeds[move.weld]) <= SPEED_TOL_MM_S:
        return "WELD_SPEED"
    if move.kind == ir.JOINT:
        percent = joint_speed_percent(move.speed_mm_s, settings.joint_percent,
                                      settings.joint_reference_mm_s)
        return f"{percent}%"
    return linear_speed(move.speed_mm_s)


def pose_values(T, angle_decimals=4):
    """X, Y, Z (mm, 3 decimals) and W, P, R (deg) of a pose.

    Parameters
    ----------
    T : array_like, shape (4, 4)
    angle_decimals : int

    Returns
    -------
    list of 6 str
        ``R = Rz(R) Ry(P) Rx(W)``; W, R in (-180, 180], P in [-90, 90];
        no ``-0.000``.
    """
    return common.xyz_fixed_angles(T, angle_decimals)


def _configs(positions, settings):
    """CONFIG of each ``(target, frame, joint)`` position; the default where a
    target has no joints or the robot is not an OPW catalog robot."""
    out = [DEFAULT_CONFIG] * len(positions)
    if settings.spec is None:
        return out
    solved = [i for i, (target, _, _) in enumerate(positions) if target.joints_deg is not None]
    if solved:
        found = configuration_data.fanuc_configs(
            [positions[i][0].joints_deg for i in solved], settings.spec)
        for i, config in zip(solved, found):
            out[i] = config
    return out


def _position_records(positions, settings):
    """The ``P[n]{...};`` records of ``(target, frame name, joint)`` positions, n from 1.

    Cartesian values of every position come from one vectorised conversion.
    """
    if not positions:
        return []
    T = np.array([common.pose_in_drawn_frame(settings.program, frame_name, target)
                  for target, frame_name, _ in positions], dtype=float)
    angles = np.degrees(rotations.euler_xyz_fixed_from_matrix(T[:, :3, :3]))
    lines = []
    for number, ((target, frame_name, joint), xyz, wpr, config) in enumerate(
            zip(positions, T[:, :3, 3], angles, _configs(positions, settings)), start=1):
        head = f"\tUF : {settings.users[frame_name]}, UT : {settings.tool},"
        track, turned = _external_texts(target, settings)
        if joint:
            group1 = [head + "\t"] + _joint_lines(target, settings)
        else:
            x, y, z = (fixed(v, 3).rjust(9) for v in xyz)
            w, p, r = (fixed(v, settings.angle_decimals).rjust(9) for v in wpr)
            group1 = [f"{head}\t\tCONFIG : '{config}',",
                      f"\tX = {x}  mm,\tY = {y}  mm,\tZ = {z}  mm,",
                      f"\tW = {w} deg,\tP = {p} deg,\tR = {r} deg"]
        if track:
            group1[-1] += ","
            group1.append(",\t".join(f"\tE{k}= {v}  mm" for k, v in enumerate(track, 1)))
        lines += [f"P[{number}]{{", "   GP1:"] + group1
        if turned:
            lines += ["   GP2:", head + "\t",
                      ",".join(f"\tJ{k}= {v} deg" for k, v in enumerate(turned, 1))]
        lines.append("};")
    return lines


# --- external axes ---------------------------------------------------------------------------

def _positioner(settings):
    """The program's positioner (motion group 2), or None."""
    external = settings.program.external
    return None if external is None else external.positioner


def _external_texts(target, settings):
    """(track values in mm, positioner values in deg) of a position, as text
    (``E1..`` of group 1, ``J1..`` of group 2); empty lists where absent."""
    program = settings.program
    if program.external is None:
        return [], []
    track, turned = program.external.split(common.target_external_values(program, target))
    track_text = [] if track is None else [fixed(v, 3).rjust(9) for v in track]
    turned_text = [] if turned is None else [fixed(v, settings.angle_decimals).rjust(9)
                                             for v in turned]
    return track_text, turned_text


def _joint_lines(target, settings):
    """The two lines ``J1= ... deg, ... J6= ... deg`` of a joint position (controller joints)."""
    values = [fixed(v, settings.angle_decimals).rjust(9)
              for v in common.controller_joints_deg(settings.program, target)]
    return [f"\tJ1= {values[0]} deg,\tJ2= {values[1]} deg,\tJ3= {values[2]} deg,",
            f"\tJ4= {values[3]} deg,\tJ5= {values[4]} deg,\tJ6= {values[5]} deg"]


# --- text ------------------------------------------------------------------------------------

def _attributes(settings, line_count):
    """The ``/ATTR`` section; ``DEFAULT_GROUP = 1,1,*,*,*`` with a positioner (group 2)."""
    date = settings.date.strftime("DATE %y-%m-%d  TIME %H:%M:%S")
    return [
        "OWNER\t\t= MNEDITOR;",
        'COMMENT\t\t= "CadRobot";',
        "PROG_SIZE\t= 0;",
        f"CREATE\t\t= {date};",
        f"MODIFIED\t= {date};",
        "FILE_NAME\t= ;",
        "VERSION\t\t= 0;",
        f"LINE_COUNT\t= {line_count};",
        "MEMORY_SIZE\t= 0;",
        "PROTECT\t\t= READ_WRITE;",
        "TCD:  STACK_SIZE\t= 0,",
        "      TASK_PRIORITY\t= 50,",
        "      TIME_SLICE\t= 0,",
        "      BUSY_LAMP_OFF\t= 0,",
        "      ABORT_REQUEST\t= 0,",
        "      PAUSE_REQUEST\t= 0;",
        f"DEFAULT_GROUP\t= {'1,1' if _positioner(settings) else '1,*'},*,*,*;",
        "CONTROL_CODE\t= 00000000 00000000;",
    ]


def _comment_text(text):
    """One line of plain printable ASCII for a ``!`` comment; ``;`` (the end of
    an instruction) and ``"`` become spaces."""
    return common.comment_text(text, blanks=';"')


def _wrap(text, width=COMMENT_WIDTH):
    """Comment lines of at most ``width`` characters, cut at spaces where possible."""
    return common.wrap_words(_comment_text(text), width)


def _pose_comments(T, decimals):
    x, y, z, w, p, r = pose_values(T, decimals)
    return [f"X={x} Y={y}", f"Z={z} W={w}", f"P={p} R={r}"]


def _header_comments(program, settings):
    """Comment lines at the top of ``/MN``: origin, units, rules, frames and tool."""
    if settings.joint_percent is not None:
        joint = [f"J speed: {settings.joint_percent}% on every move"]
    else:
        joint = ["J % = 100 * speed /", f"      {compact(settings.joint_reference_mm_s)} mm/s"]
    out = [f"CadRobot post {NAME}"]
    source, robot = common.source_and_robot(program, _comment_text)
    out += _wrap(f"Source: {source}")
    out += _wrap(f"Robot: {robot}")
    out += _wrap(common.other_maker_note(program.robot, NAME, "FANUC R-30iA/R-30iB"))
    out += ["Units: mm, deg", "W,P,R: R = Rz(R)*Ry(P)*Rx(W)"] + joint
    out += [f"CNTn: n = zone / {compact(settings.cnt_mm)} mm", "rounded down (max 100)",
            "FINE: zone below one CNT step"]
    if settings.joint_targets:
        out += ["J moves with solved joints:", "joint positions J1..J6"]
    out += ["Set UFRAME and UTOOL first", "(UFRAME in world = robot base):"]
    for frame_name, number in settings.users.items():
        frame = program.frames[frame_name]
        out += _wrap(f"UFRAME {number} = {_comment_text(frame_name)}")
        out += _pose_comments(frame.T_r_b, settings.angle_decimals)
    tool = program.tool
    out += _wrap(f"UTOOL {settings.tool} = {_comment_text(tool.name)} (faceplate)")
    out += _pose_comments(tool.T_f_t, settings.angle_decimals)
    cog = [fixed(v, 3) for v in np.asarray(tool.cog_mm, dtype=float)]
    schedule = "" if settings.payload is None else f"PAYLOAD[{settings.payload}]: "
    out += _wrap(f"{schedule}Payload {compact(tool.mass_kg)} kg")
    out += [f"CoG X={cog[0]} Y={cog[1]}", f"CoG Z={cog[2]}"]
    solved = settings.spec is not None and all(
        t.joints_deg is not None for t in program.targets())
    if solved:
        out.append("CONFIG: the checked arm config")
    else:
        out += ["CONFIG 'N U T, 0, 0, 0' where", "no joints were solved"]
    return out + _external_comments(program) + _weld_comments(program, settings)


def _external_comments(program):
    """What the external axes are and how they are written (none without)."""
    external = program.external
    if external is None:
        return []
    out = common.external_axes_comments(program, _wrap)
    if external.track is not None:
        out += _wrap("Track: E1.. of group 1 (mm), positions in the world frame (integrated "
                     "rail)")
    if external.positioner is not None:
        out += _wrap("Positioner: motion group 2, J1.. in deg, COORD on path moves")
        out += _wrap("UFRAME: the work frame with the positioner at its drawn values")
    return out


def _weld_comments(program, settings):
    """What to enter in DATA > Weld Schedule (and the TAST schedule) for each
    schedule number the program uses, and how the weave is written."""
    out, seen = [], set()
    tracked = {settings.schedule_numbers[run.name] for _, run in program.weld_runs()
               if run.tracking.sensor == "arc"}
    for _, run in program.weld_runs():
        n = settings.schedule_numbers[run.name]
        if n in seen:
            continue
        seen.add(n)
        out += _wrap(f"DATA > Weld Schedule {n} (Arc Start[{n}], Arc End[{n}]):")
        for line in common.schedule_comment_lines(run):
            out += _wrap(line)
        if n in tracked:
            out += _wrap(f"TAST[{n}]: set the TAST schedule's gains on the controller")
    if out and settings.weld_speed == "schedule":
        out += _wrap("WELD_SPEED = the weld schedule's travel speed")
    if any(run.weave is not None for _, run in program.weld_runs()):
        out += _wrap("Weave [Hz, mm, s, s]: frequency, half the full width, right and left "
                     "dwell")
    return out
