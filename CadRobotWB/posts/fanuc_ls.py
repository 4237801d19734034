"""Fanuc LS post-processor: one teach-pendant program in ASCII form (``.LS``).

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
      ..:L P[2] 75cm/min CNT1    ;
      ..:C P[5]    
        :  P[6] 75cm/min FINE    ;      circular: via, then end (one line)
    /POS
    P[1]{
       GP1:
        UF : 1, UT : 1,     CONFIG : 'N U T, 0, 0, 0',
        X =     0.000  mm,  Y =     0.000  mm,  Z =    50.000  mm,
        W =   180.0000 deg, P =     0.0000 deg, R =     0.0000 deg
    };
    /END

``LINE_COUNT`` is the number of numbered ``/MN`` lines (a circular move is
one line written on two).  Every motion instruction has its own ``P[n]``,
numbered in the order of use; ``UFRAME_NUM`` is set again before a move in
another work frame, so that each position's ``UF`` is the active one.

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
* Termination from the move's zone: ``FINE`` for zone 0; otherwise
  ``CNTn`` with ``n = min(100, max(1, round(zone_mm)))`` (halves up).
  CNT is not a distance: it sets how much of the deceleration is cut, so
  the real rounding grows with speed; 1 mm of zone = CNT1 is CadRobot's
  rule.
* ``CONFIG`` from ``Target.joints_deg`` with
  :func:`~CadRobotWB.robots.configuration.fanuc_config` (not verified
  against a Fanuc manual, see its docstring); a target without joints gets
  ``'N U T, 0, 0, 0'`` (no flip, up, toward, no turns), the usual
  configuration, and the program's comments say so.

Frames and tool
---------------
Positions are in user frame ``user_frame`` (option; default 1; several work
frames take consecutive numbers, or a dict ``{frame name: number}``) with
tool ``tool`` (default 1).  Their values - the work frame in the robot's
world frame, taken as its base frame (``WorkFrame.T_r_b``), and the tool in
the faceplate frame (``ToolData.T_f_t``) - are written as comments for
direct entry on the frame setup screens.

Program names are upper case ``A-Z``, ``0-9``, ``_``, starting with a
letter, at most ``max_name_length`` characters: 8 by default, which every
controller takes (older R-J3 controllers allow no more; R-30iA/R-30iB
accept longer names, up to 36, as commonly documented - not verified
here).  A longer name is cut and ends with three characters of a hash of
the whole name.

The output is deterministic: ``CREATE``/``MODIFIED`` come from
``options["date"]`` (a ``datetime``) or 2000-01-01 00:00:00.  Lines end
with CR LF.

Pure Python/numpy: never imports FreeCAD.
"""

import datetime
from dataclasses import dataclass
from typing import Optional

import numpy as np

from ..core import program as ir
from ..errors import PostError
from ..robots import configuration
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
DEFAULT_CONFIG = "N U T, 0, 0, 0"
DEFAULT_JOINT_REFERENCE_MM_S = 1000.0
DEFAULT_DATE = datetime.datetime(2000, 1, 1, 0, 0, 0)

_MOTION = {ir.JOINT: "J", ir.LINEAR: "L", ir.CIRCULAR: "C"}


def export(program, options=None):
    """Write a program as one LS program.

    Parameters
    ----------
    program : CadRobotWB.core.program.Program
        Targets in their work frames {B}, mm.
    options : dict, optional
        ``"program_name"`` : str - instead of a name made from
        ``program.name``; ``A-Z``, ``0-9``, ``_``, starting with a letter.
        ``"max_name_length"`` : int - 8 (default) to 36.
        ``"user_frame"`` : int or dict of str to int - UF number of the
        first work frame (the next frames take the next numbers), or one
        per frame name.  Default 1.
        ``"tool"`` : int - UT number, default 1.
        ``"joint_speed_percent"`` : int - speed of every joint move.
        ``"joint_speed_reference_mm_s"`` : float - the speed that is 100 %
        when ``joint_speed_percent`` is not given, default 1000.
        ``"angle_decimals"`` : int - decimals of W, P, R: 4 (default) or 3.
        ``"date"`` : datetime.datetime - for CREATE and MODIFIED.
        Other keys are ignored.

    Returns
    -------
    list of (str, str)
        ``[(f"{NAME}.LS", text)]``.

    Raises
    ------
    PostError
        The program or an option cannot be expressed in LS.
    """
    settings = _Settings.from_options(dict(options or {}), program)
    for move in program.moves():
        common.check_move(move, program, _MOTION, NAME,
                          kinds_text="joint, linear and circular")

    body = [("text", "!" + line) for line in _header_comments(program, settings)]
    positions = []
    moves = program.moves()
    frame = moves[0].frame if moves else None
    if frame is not None:
        body.append(("text", f"UFRAME_NUM={settings.users[frame]}"))
    body.append(("text", f"UTOOL_NUM={settings.tool}"))
    for path in program.paths:
        if path.moves and path.moves[0].frame != frame:
            body.append(("text", f"UFRAME_NUM={settings.users[path.moves[0].frame]}"))
            frame = path.moves[0].frame
        for line in _wrap("Path: " + (_comment_text(path.label or path.name) or path.name)):
            body.append(("text", "!" + line))
        last_comment = None
        for move in path.moves:
            if move.frame != frame:
                body.append(("text", f"UFRAME_NUM={settings.users[move.frame]}"))
                frame = move.frame
            text = _comment_text(move.comment)
            if text and text != last_comment:
                body += [("text", "!" + line) for line in _wrap(text)]
            last_comment = text
            speed = _speed_text(move, settings)
            term = termination(move.zone_mm)
            if move.kind == ir.CIRCULAR:
                positions += [(move.via, move.frame), (move.target, move.frame)]
                n = len(positions)
                body.append(("circle", f"C P[{n - 1}]", f"P[{n}] {speed} {term}"))
            else:
                positions.append((move.target, move.frame))
                body.append(("motion", f"{_MOTION[move.kind]} P[{len(positions)}] {speed} {term}"))

    name = _program_name(program, settings)
    lines = [f"/PROG  {name}", "/ATTR"]
    lines += _attributes(settings, line_count=len(body))
    lines.append("/MN")
    for number, entry in enumerate(body, start=1):
        if entry[0] == "text":
            lines.append(f"{number:4d}:  {entry[1]} ;")
        elif entry[0] == "motion":
            lines.append(f"{number:4d}:{entry[1]}    ;")
        else:
            lines.append(f"{number:4d}:{entry[1]}    ")
            lines.append(f"    :  {entry[2]}    ;")
    lines.append("/POS")
    for number, (target, frame_name) in enumerate(positions, start=1):
        lines += _position(number, target, frame_name, settings)
    lines.append("/END")
    return [(common.file_name(name, ".LS"), NEWLINE.join(lines) + NEWLINE)]


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
    date: datetime.datetime
    spec: object

    @classmethod
    def from_options(cls, options, program):
        length = common.whole_number(options.get("max_name_length", DEFAULT_NAME_LENGTH),
                                     "max_name_length", 1, MAX_NAME_LENGTH)
        tool = common.whole_number(options.get("tool", 1), "tool", *TOOLS)
        percent = options.get("joint_speed_percent")
        if percent is not None:
            percent = common.whole_number(percent, "joint_speed_percent", 1, 100)
        reference = common.positive_number(options, "joint_speed_reference_mm_s",
                                           DEFAULT_JOINT_REFERENCE_MM_S)
        decimals = common.whole_number(options.get("angle_decimals", 4), "angle_decimals", 3, 4)
        date = common.date_option(options, DEFAULT_DATE)
        return cls(options.get("program_name"), length,
                   _frame_numbers(program, options.get("user_frame", 1)), tool, percent,
                   reference, decimals, date, common.opw_robot_spec(program))


# --- motion values ---------------------------------------------------------------------------

def termination(zone_mm):
    """``FINE`` for zone 0, else ``CNTn``, n = min(100, max(1, round(zone_mm)))."""
    if zone_mm <= 0:
        return "FINE"
    return f"CNT{min(100, max(1, round_half_up(zone_mm)))}"


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


def _config(target, settings):
    if target.joints_deg is None or settings.spec is None:
        return DEFAULT_CONFIG
    return configuration.fanuc_config(target.joints_deg, settings.spec)


def _position(number, target, frame_name, settings):
    """The lines of one ``P[n]{...};`` record."""
    x, y, z, w, p, r = (v.rjust(9) for v in pose_values(target.T_b_t, settings.angle_decimals))
    return [
        f"P[{number}]{{",
        "   GP1:",
        f"\tUF : {settings.users[frame_name]}, UT : {settings.tool},\t\t"
        f"CONFIG : '{_config(target, settings)}',",
        f"\tX = {x}  mm,\tY = {y}  mm,\tZ = {z}  mm,",
        f"\tW = {w} deg,\tP = {p} deg,\tR = {r} deg",
        "};",
    ]


# --- text ------------------------------------------------------------------------------------

def _attributes(settings, line_count):
    """The ``/ATTR`` section."""
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
        "DEFAULT_GROUP\t= 1,*,*,*,*;",
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
    out += ["Units: mm, deg", "W,P,R: R = Rz(R)*Ry(P)*Rx(W)"] + joint
    out += ["CNTn: n = zone in mm (1..100)", "FINE: zone 0",
            "Set UFRAME and UTOOL first", "(UFRAME in world = robot base):"]
    for frame_name, number in settings.users.items():
        frame = program.frames[frame_name]
        out += _wrap(f"UFRAME {number} = {_comment_text(frame_name)}")
        out += _pose_comments(frame.T_r_b, settings.angle_decimals)
    tool = program.tool
    out += _wrap(f"UTOOL {settings.tool} = {_comment_text(tool.name)} (faceplate)")
    out += _pose_comments(tool.T_f_t, settings.angle_decimals)
    cog = [fixed(v, 3) for v in np.asarray(tool.cog_mm, dtype=float)]
    out += [f"Payload {compact(tool.mass_kg)} kg", f"CoG X={cog[0]} Y={cog[1]}", f"CoG Z={cog[2]}"]
    solved = settings.spec is not None and all(
        t.joints_deg is not None for t in program.targets())
    if solved:
        out.append("CONFIG: the checked arm config")
    else:
        out += ["CONFIG 'N U T, 0, 0, 0' where", "no joints were solved"]
    return out
