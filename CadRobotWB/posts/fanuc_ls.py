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
import hashlib
import math
import re
import unicodedata
from dataclasses import dataclass
from typing import Optional

import numpy as np

from ..core import program as ir
from ..core import rotations
from ..errors import PostError, UnknownNameError
from ..robots import catalog
from ..robots import configuration

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
        _check_move(move, program)

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
    return [(f"{name}.LS", NEWLINE.join(lines) + NEWLINE)]


# --- names -----------------------------------------------------------------------------------

def _ascii(text):
    """Plain ASCII of a text: accents dropped, other characters ``?``."""
    text = unicodedata.normalize("NFKD", str(text))
    text = "".join(c for c in text if not unicodedata.combining(c))
    return text.encode("ascii", "replace").decode("ascii")


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
    base = re.sub(r"[^A-Z0-9_]", "_", _ascii(text).upper()) or "PROG"
    if not base[0].isalpha():
        base = "P" + base
    if len(base) <= max_length:
        return base
    number = int(hashlib.sha1(base.encode("utf-8")).hexdigest(), 16)
    digits = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ"
    suffix = ""
    for _ in range(3):
        number, rest = divmod(number, 36)
        suffix += digits[rest]
    return base[:max_length - 3] + suffix


def is_program_name(text, max_length=DEFAULT_NAME_LENGTH):
    """True for 1 to ``max_length`` characters ``[A-Z][A-Z0-9_]*``."""
    return bool(re.fullmatch(r"[A-Z][A-Z0-9_]*", text or "")) and len(text) <= max_length


def _program_name(program, settings):
    requested = settings.requested_name
    if requested is None:
        return program_name(program.name, settings.name_length)
    if not isinstance(requested, str) or not is_program_name(requested.upper(),
                                                             settings.name_length):
        raise PostError(f"Program name {requested!r} is not valid: use 1 to "
                        f"{settings.name_length} letters, digits or '_', starting with a "
                        "letter (max_name_length allows up to 36 on R-30iA/B).")
    return requested.upper()


# --- options ---------------------------------------------------------------------------------

def _integer(value, what, low, high):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) \
            or not low <= int(value) <= high:
        raise PostError(f"{what} must be a whole number from {low} to {high}, got {value!r}.")
    return int(value)


def _frame_numbers(program, user_frame):
    """UF number of each work frame (see the module docstring)."""
    low, high = USER_FRAMES
    names = list(program.frames)
    if isinstance(user_frame, dict):
        missing = [n for n in names if n not in user_frame]
        if missing:
            raise PostError(f"Option user_frame gives no number for work frame(s) "
                            f"{', '.join(missing)}.")
        numbers = {n: _integer(user_frame[n], f"user_frame[{n!r}]", low, high) for n in names}
    else:
        first = _integer(user_frame, "user_frame", low, high)
        if first + len(names) - 1 > high:
            raise PostError(f"{len(names)} work frames need user frames {first} to "
                            f"{first + len(names) - 1}, beyond UF {high}; pass a smaller "
                            "user_frame or a dict.")
        numbers = {n: first + i for i, n in enumerate(names)}
    if len(set(numbers.values())) != len(numbers):
        raise PostError(f"Option user_frame gives two work frames the same number: {numbers}.")
    return numbers


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
        length = _integer(options.get("max_name_length", DEFAULT_NAME_LENGTH),
                          "max_name_length", 1, MAX_NAME_LENGTH)
        tool = _integer(options.get("tool", 1), "tool", *TOOLS)
        percent = options.get("joint_speed_percent")
        if percent is not None:
            percent = _integer(percent, "joint_speed_percent", 1, 100)
        reference = options.get("joint_speed_reference_mm_s", DEFAULT_JOINT_REFERENCE_MM_S)
        if not (isinstance(reference, (int, float)) and reference > 0):
            raise PostError(f"joint_speed_reference_mm_s must be > 0, got {reference!r}.")
        decimals = _integer(options.get("angle_decimals", 4), "angle_decimals", 3, 4)
        date = options.get("date", DEFAULT_DATE)
        if not isinstance(date, datetime.datetime):
            raise PostError(f"date must be a datetime.datetime, got {date!r}.")
        return cls(options.get("program_name"), length,
                   _frame_numbers(program, options.get("user_frame", 1)), tool, percent,
                   float(reference), decimals, date, _robot_spec(program))


def _robot_spec(program):
    """The catalog entry of the program's robot if CONFIG can be computed for
    it (an OPW robot), else None."""
    try:
        spec = catalog.get(program.robot)
    except UnknownNameError:
        return None
    return spec if spec.opw is not None else None


# --- checks ----------------------------------------------------------------------------------

def _check_move(move, program):
    """Raise PostError when LS cannot express this move."""
    where = f"move to target '{move.target.name}'"
    if move.kind not in _MOTION:
        raise PostError(f"The {where} is of kind '{move.kind}', which the {NAME} post cannot "
                        "write (it writes joint, linear and circular moves).")
    if move.kind == ir.CIRCULAR and move.via is None:
        raise PostError(f"The circular {where} has no via point; regenerate the program.")
    if move.frame not in program.frames:
        raise PostError(f"The {where} refers to work frame '{move.frame}', which the program "
                        "does not define.")
    if not np.isfinite(move.speed_mm_s) or move.speed_mm_s <= 0:
        raise PostError(f"The {where} has speed {move.speed_mm_s} mm/s; set a speed > 0.")
    if not np.isfinite(move.zone_mm) or move.zone_mm < 0:
        raise PostError(f"The {where} has zone {move.zone_mm} mm; set a zone of 0 (stop) "
                        "or more.")
    for target in (move.target, move.via):
        if target is not None and not np.all(np.isfinite(target.T_b_t)):
            raise PostError(f"Target '{target.name}' has a pose that is not a finite number; "
                            "check the path geometry.")


# --- motion values ---------------------------------------------------------------------------

def termination(zone_mm):
    """``FINE`` for zone 0, else ``CNTn``, n = min(100, max(1, round(zone_mm)))."""
    if zone_mm <= 0:
        return "FINE"
    return f"CNT{min(100, max(1, _round_half_up(zone_mm)))}"


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
    whole = _round_half_up(speed_mm_s)
    if whole >= 1 and abs(speed_mm_s - whole) < 1e-9:
        return f"{whole:d}mm/sec"
    cm_min = _round_half_up(speed_mm_s * 6.0)
    if cm_min < 1:
        raise PostError(f"Speed {speed_mm_s} mm/s is below 1 cm/min, the slowest speed a "
                        "Fanuc linear move takes.")
    return f"{cm_min:d}cm/min"


def joint_speed_percent(speed_mm_s, fixed_percent=None,
                        reference_mm_s=DEFAULT_JOINT_REFERENCE_MM_S):
    """Joint move speed, whole percent 1..100: ``fixed_percent`` or
    ``round(100 * speed / reference)``."""
    value = fixed_percent if fixed_percent is not None else 100.0 * speed_mm_s / reference_mm_s
    return min(100, max(1, _round_half_up(value)))


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
    T = np.asarray(T, dtype=float)
    angles = np.degrees(rotations.euler_xyz_fixed_from_matrix(T[:3, :3]))
    return [_fixed(v, 3) for v in T[:3, 3]] + [_fixed(a, angle_decimals) for a in angles]


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


def _round_half_up(value):
    """Nearest whole number, halves up (2.5 -> 3), as an int."""
    return int(math.floor(float(value) + 0.5))


def _fixed(value, decimals):
    """Fixed-point text, never ``-0.000``."""
    text = f"{float(value):.{decimals}f}"
    if float(text) == 0.0:
        text = text.lstrip("-")
    return text


def _compact(value):
    """Shortest text of a value to 4 decimals: 10, 12.5, 0.045."""
    text = f"{float(value):.4f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def _comment_text(text):
    """One line of plain printable ASCII for a ``!`` comment; ``;`` (the end of
    an instruction) and ``"`` become spaces."""
    text = _ascii(text).replace(";", " ").replace('"', " ")
    return " ".join(text.split())


def _wrap(text, width=COMMENT_WIDTH):
    """Comment lines of at most ``width`` characters, cut at spaces where possible."""
    lines, line = [], ""
    for word in _comment_text(text).split(" "):
        while len(word) > width:
            if line:
                lines.append(line)
                line = ""
            lines.append(word[:width])
            word = word[width:]
        if not line:
            line = word
        elif len(line) + 1 + len(word) <= width:
            line += " " + word
        else:
            lines.append(line)
            line = word
    if line:
        lines.append(line)
    return lines


def _pose_comments(T, decimals):
    x, y, z, w, p, r = pose_values(T, decimals)
    return [f"X={x} Y={y}", f"Z={z} W={w}", f"P={p} R={r}"]


def _header_comments(program, settings):
    """Comment lines at the top of ``/MN``: origin, units, rules, frames and tool."""
    if settings.joint_percent is not None:
        joint = [f"J speed: {settings.joint_percent}% on every move"]
    else:
        joint = ["J % = 100 * speed /", f"      {_compact(settings.joint_reference_mm_s)} mm/s"]
    out = [f"CadRobot post {NAME}"]
    out += _wrap(f"Source: {_comment_text(program.source) or '(unknown)'}")
    out += _wrap(f"Robot: {_comment_text(program.robot) or '(unknown)'}")
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
    cog = [_fixed(v, 3) for v in np.asarray(tool.cog_mm, dtype=float)]
    out += [f"Payload {_compact(tool.mass_kg)} kg", f"CoG X={cog[0]} Y={cog[1]}", f"CoG Z={cog[2]}"]
    solved = settings.spec is not None and all(
        t.joints_deg is not None for t in program.targets())
    if solved:
        out.append("CONFIG: the checked arm config")
    else:
        out += ["CONFIG 'N U T, 0, 0, 0' where", "no joints were solved"]
    return out
