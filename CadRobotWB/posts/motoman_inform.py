"""Yaskawa Motoman INFORM post-processor: jobs (``.JBI``) for NX100, DX100, DX200, YRC1000.

Layout of one job written by :func:`export` (the file format of the NX100
manual "Interface with an easy offline teaching system", HW0481924, 4.1
"Job Data Format"; DX100 edition HW0482494)::

    /JOB
    //NAME CELL                    job name, upper case
    //POS
    ///NPOS 7,0,0,0,0,0            C, BC, EC, P, BP, EX: only C positions
    ///USER 1                      user frame of the positions after it
    ///TOOL 0
    ///POSTYPE USER
    ///RECTAN                       Cartesian: X,Y,Z mm, Rx,Ry,Rz deg
    ///RCONF 0,0,0,0,0,0            arm configuration of the positions after it
    C00000=0.000,0.000,50.000,180.0000,0.0000,0.0000
    ...
    //INST
    ///DATE 2000/01/01 00:00
    ///COMM CadRobot Cell
    ///ATTR SC,RW
    ///GROUP1 RB1
    NOP
    'comments: source, units, user frame and tool values to teach
    MOVJ C00000 VJ=10.00 PL=0
    MOVL C00001 V=12.5 PL=0
    MOVC C00002 V=12.5              arc start (where the robot already is)
    MOVC C00003 V=12.5              arc via
    MOVC C00004 V=12.5 PL=0         arc end, with the move's PL
    END

``///USER`` and ``///RCONF`` are repeated before a position whose work frame
or arm configuration differs from the previous one (they apply "during and
after" the pseudo instruction).  Every C position is used by exactly one
move instruction, numbered in the order of use.

Units and conventions
---------------------
* Positions in the user frame (``///POSTYPE USER``): X, Y, Z in mm (3
  decimals), Rx, Ry, Rz in degrees (4 decimals), as the controller writes
  them.  The angles are fixed-axis rotations about X, then Y, then Z:
  ``R = Rz(Rz) Ry(Ry) Rx(Rx)``.
* ``MOVL``/``MOVC`` speed ``V=``: **mm/s** by default, 0.1 mm/s resolution
  (``V=12.5``).  Some controllers are set to cm/min instead (a controller
  parameter): option ``linear_speed_unit="cm/min"`` writes ``V`` in cm/min,
  whole numbers (1 cm/min = 0.1667 mm/s).  The unit is stated in the job's
  comments.
* ``MOVJ`` speed ``VJ=``: percent of the maximum joint speeds (0.01 ..
  100.00).  A TCP speed has no exact joint-speed equivalent: ``VJ = 100 *
  speed_mm_s / joint_speed_reference_mm_s`` (default 1000 mm/s, so the
  usual 100 mm/s approach runs at 10 %), or option ``joint_speed_percent``
  for every joint move.
* Position level ``PL=`` (0 to 8) on every move's last step.  A level is
  not a distance: the rounding of PL=1..8 is set by controller parameters
  (and grows with speed), so CadRobot cannot know it.  Without option
  ``pl_radii_mm`` a move with a zone (a path's interior target,
  :mod:`~CadRobotWB.core.zones`) ends ``PL=1``, the least rounding short of
  a stop, so the robot does not stop at every point; zone 0 is ``PL=0``
  (the robot reaches the point).  With ``pl_radii_mm`` = the controller's
  radii of PL=1, 2, ... (mm, increasing, 1 to 8 values) a move takes the
  highest level whose radius does not exceed its zone (never more rounding
  than asked), else PL=0.
    ``PL=0`` is written and not left out: as we
  read Yaskawa's operator's manual, without a PL tag the approach to the
  point depends on the speed (not re-checked against a manual here).
  The arc's start and via steps and the ``MOVL`` between two arcs have no
  PL.
* Circular moves: INFORM needs three consecutive ``MOVC`` steps, start, via
  and end.  The start is the previous target (the robot is already there,
  so it does not move).  Two arcs in a row are separated by a ``MOVL`` to
  their common point, as the manual asks for arcs of different curvature
  (otherwise the controller would fit one circle through the points of
  both).
* ``///RCONF`` from ``Target.joints_deg`` with
  :func:`~CadRobotWB.robots.motion.configuration.motoman_rconf` (see its docstring
  for what is not verified).  A target without joints (no robot model has
  solved the program, or the robot is not an OPW robot of the catalog) gets
  ``0,0,0,0,0,0``: flip, upper arm, front, R, T, S below 180 degrees - the
  usual arm configuration - and the job's comments say so.

User frame and tool
-------------------
The positions are in user frame ``user_frame`` (option; default 1; with
several work frames, the first takes this number and the next ones the
following numbers, or pass a dict ``{frame name: number}``) with tool
``tool`` (default 0).  The job cannot set them: teach the user frame
(ORG, XX, XY points) and enter the tool on the pendant **before loading
the job** - a standard job keeps its positions as pulses, converted with
the user frame and tool known at loading time.  Their values, computed
from the program's work frames (``WorkFrame.T_r_b``, the frame in robot
coordinates, assuming no base axis) and tool (``ToolData``), are written
in the comments at the top of the job.

Joint targets (PULSE positions)
-------------------------------
INFORM's joint positions are pulse positions (``///POSTYPE PULSE``,
``///PULSE``, ``C00000=s,l,u,r,b,t`` in encoder pulses).  Pulses need each
axis's pulses per degree and the angle at 0 pulses; they differ per robot
and are not in the catalog, and CadRobot does not invent them.  So:

* with option ``pulses_per_degree`` (6 numbers from the controller's
  parameters, the sign giving the counting direction) and
  ``joint_targets`` on (default), a joint move whose target has solved
  joints goes to a PULSE position ``round(ppd * (q - zero))``, ``q`` the
  joints of :func:`~CadRobotWB.posts.common.controller_joints_deg` and
  ``zero`` option ``pulse_zero_deg`` (default 0: 0 pulses where the
  catalog model's joint is 0 - **not verified** for any robot; the
  HP6's joint directions and zero are derived, not published);
* otherwise (the default, as no robot's pulses are known) joint moves go
  to Cartesian positions with ``///RCONF``, which fixes the arm
  configuration the controller uses.

The job's comments say which was written.

Long programs
-------------
A job holds at most ``max_positions`` positions (option, default 999: a
conservative choice; the limit the controller enforces was not verified -
the C index itself allows 5 digits, C00000-C99999) and ``max_lines``
instruction lines between ``NOP`` and ``END`` (option, default 2000:
RoboDK's Motoman post's default ``MAX_LINES_X_PROG``; not a limit stated
by Yaskawa).  A longer program becomes a main job with no positions that
``CALL JOB:`` s its sub-jobs in order (``<NAME>_1``, ``<NAME>_2``, ...;
when these do not fit the name length, the main name is cut with three
characters of its hash and the numbers are zero-padded); an arc (its three
or four steps) is never split between two jobs.  The controller's total
job memory (steps and instructions over all jobs) is not checked: see
docs/controllers.md.

Controllers (option ``controller``)
-----------------------------------
==========  ==========  ==============  ==============  ================
controller  job name    ///RCONF        USER / TOOL     source
==========  ==========  ==============  ==============  ================
nx100       8 chars     6 fields        0-23 / 0-23     HW0481924 4.1
dx100       32 chars    6 + 18 unused   0-63 / 0-63     HW0482494 4.1
dx200       32 chars    6 + 18 unused   0-63 / 0-63     assumed = DX100
yrc1000     32 chars    6 + 18 unused   0-63 / 0-63     assumed = DX100
==========  ==========  ==============  ==============  ================

The DX100 name length and the frame/tool counts of the DX controllers
come from Yaskawa's operator documentation as commonly quoted, not from
the file-format chapter; DX200 and YRC1000 were not checked at all.
``relative_job=True`` (DX100 and later only) writes a relative job,
``///ATTR SC,RW,RJ`` with ``////FRAME USER n``: the positions stay
Cartesian in the user frame (every position of a job must then be in one
user frame).  Job names are made of ``A-Z``, ``0-9`` and ``_``; a longer
program name is cut and ends with three characters of a hash of the full
name, so that two long names do not collide.

Welds
-----
A path with weld runs (issue 22) gets ``ARCON`` (and ``WVON``) after the step
ending at the seam start and ``WVOF``, ``ARCOF`` after the weld's last step:
in-line tags (``AC= AV=``, ``AMP= FREQ= ANGL= DIR=``, ``AC= AV= T=``) or,
with ``conditions="files"``, condition file numbers ``ASF#(n)``, ``WEV#(n)``,
``AEF#(n)`` and a ``<JOB>_CONDITIONS.txt`` sheet of the values to enter.  A
weld stays in one job.  Through-arc tracking (COM-ARC) is refused.  Details
and what is not verified: docs/controllers.md, Yaskawa, Welding.

External axes
--------------
A program with external axes (issue 23) gives every step a base position
``BC`` (the track's travel, mm, ``///POSTYPE BASE``) and a station position
``EC`` (the positioner, encoder pulses from the required option
``station_pulses_per_degree``), ``///GROUP1 RB1,BS1`` and ``///GROUP2 ST1``,
and moves the path synchronised: ``SMOVL C.. BC.. V=.. +MOVJ EC..``.  C
positions are in the work frame as drawn (:func:`common.pose_in_drawn_frame`).
Sources and what is not verified: docs/controllers.md, External axes.

The output is deterministic: the job date is ``options["date"]`` (a
``datetime``) or 2000/01/01 00:00.  Lines end with CR LF, as the controller
writes them.

Pure Python/numpy: never imports FreeCAD.
"""

import datetime
from dataclasses import dataclass, field
from typing import List, Optional

import numpy as np

from ..core import frames as tf
from ..core import mechanisms
from ..core import program as ir
from ..core import weave as weave_geometry
from ..errors import PostError
from ..core import rotations
from ..robots.motion import configuration_data
from . import common
from .common import (comment_text, compact, fixed, frame_numbers, pose_in_drawn_frame,
                     round_half_up)

NAME = "motoman_inform"
DESCRIPTION = ("Yaskawa Motoman INFORM job for NX100 / DX100 / DX200 / YRC1000 "
               "controllers (.JBI)")
FILE_EXTENSIONS = (".JBI",)

NEWLINE = "\r\n"


@dataclass(frozen=True)
class Controller:
    """What differs between the controllers this post writes for."""

    name: str
    max_name: int          # job name length
    rconf_unused: int      # unused fields after l,m,n,o,p,q in ///RCONF
    max_user: int          # highest ///USER number
    max_tool: int          # highest ///TOOL number
    relative_jobs: bool    # can write ///ATTR ...,RJ with ////FRAME USER n


CONTROLLERS = {
    "nx100": Controller("NX100", 8, 0, 23, 23, False),
    "dx100": Controller("DX100", 32, 18, 63, 63, True),
    "dx200": Controller("DX200", 32, 18, 63, 63, True),
    "yrc1000": Controller("YRC1000", 32, 18, 63, 63, True),
}

#: Characters per comment line (the ``'`` instruction takes 32 on NX100).
COMMENT_WIDTH = 32

DEFAULT_MAX_POSITIONS = 999
#: Instruction lines (between NOP and END) per job: RoboDK's Motoman post
#: default (``MAX_LINES_X_PROG = 2000``), not a limit stated by Yaskawa.
DEFAULT_MAX_LINES = 2000
#: Highest position number: ``C00000`` .. ``C99999`` (5 digits).
MAX_C_POSITIONS = 99999
DEFAULT_JOINT_REFERENCE_MM_S = 1000.0
DEFAULT_DATE = datetime.datetime(2000, 1, 1, 0, 0)
LINEAR_SPEED_UNITS = ("mm/s", "cm/min")

#: The usual arm configuration, written for targets without joints.
DEFAULT_RCONF = (0, 0, 0, 0, 0, 0)

_INSTRUCTIONS = {ir.JOINT: "MOVJ", ir.LINEAR: "MOVL", ir.CIRCULAR: "MOVC"}

#: Every option :func:`export` reads, with one line of help.
OPTIONS = {
    "controller": "nx100 (default), dx100, dx200 or yrc1000",
    "job_name": "main job name (A-Z, 0-9, _; 8 chars on NX100, 32 on DX100 and later)",
    "user_frame": "user frame number of the first work frame (default 1), or {frame: number}",
    "tool": "tool number (default 0)",
    "max_positions": "C positions per job before the program is split (default 999)",
    "max_lines": "instruction lines per job before the program is split (default 2000)",
    "linear_speed_unit": "unit of V= on MOVL/MOVC: mm/s (default) or cm/min",
    "joint_speed_percent": "VJ= of every joint move, 0.01 to 100 %",
    "joint_speed_reference_mm_s": "TCP speed that is VJ=100 % (default 1000 mm/s)",
    "relative_job": "true: relative job in the user frame (DX100 and later; default false)",
    "joint_targets": "true (default): joint moves go to PULSE positions when "
                     "pulses_per_degree is given",
    "pulses_per_degree": "6 numbers: encoder pulses per degree of S,L,U,R,B,T "
                         "(the controller's parameters); enables PULSE positions",
    "pulse_zero_deg": "6 numbers: joint angles (deg) where each axis reads 0 pulses (default 0)",
    "pl_radii_mm": "1 to 8 increasing numbers: the rounding (mm) of PL=1..; without it "
                   "a move with a zone ends PL=1, zone 0 PL=0",
    "conditions": "inline (default): ARCON AC= AV=, WVON AMP= FREQ= ANGL= DIR=, ARCOF AC= "
                  "AV= T=; files: ARCON ASF#(n), WVON WEV#(n), ARCOF AEF#(n) and a "
                  "<JOB>_CONDITIONS.txt sheet of the values to enter on the pendant",
    "condition_file": "first condition file number n of ASF#(n), AEF#(n) and WEV#(n), "
                      "1..255 (default 1); other schedules and weaves take the next numbers",
    "station_pulses_per_degree": "with a positioner (required): encoder pulses per degree "
                                 "of each station axis, tilt then turn (the controller's "
                                 "parameters, sign = direction)",
    "station_pulse_zero_deg": "with a positioner: the station axes' angles (deg) at 0 pulses "
                              "(default 0)",
}

CONDITIONS = ("inline", "files")
#: Condition files ASF#/AEF# 1..1000 and WEV# 1..255 (S18 of the plan: a digest of the
#: INFORM manual); one bound for all three.
CONDITION_FILES = (1, 255)
#: Weave pattern -> the WEAV condition file's MODE (S19: a digest of the DX100/YRC1000
#: manual); the in-line WVON tags are Single mode only, without dwells. Circle: no such mode.
WEAVE_MODES = {"zigzag": "Single", "triangle": "Triangular", "l": "L-type", "circle": None}


def export(program, options=None):
    """Write a program as one INFORM job, or a main job and its sub-jobs.

    Parameters
    ----------
    program : CadRobotWB.core.program.Program
        Targets in their work frames {B}, mm.
    options : dict, optional
        ``"controller"`` : ``"nx100"`` (default), ``"dx100"``, ``"dx200"``
        or ``"yrc1000"``.
        ``"job_name"`` : str - the (main) job name instead of one made from
        ``program.name``; ``A-Z``, ``0-9``, ``_``, starting with a letter,
        within the controller's length.
        ``"user_frame"`` : int or dict of str to int - user frame number of
        the first work frame (the next frames take the next numbers), or
        one number per frame name.  Default 1.
        ``"tool"`` : int - tool number, default 0.
        ``"max_positions"`` : int - positions per job, default 999 (at
        least 4, the steps of the longest arc).
        ``"max_lines"`` : int - instruction lines per job, default 2000.
        ``"linear_speed_unit"`` : ``"mm/s"`` (default) or ``"cm/min"``.
        ``"joint_speed_percent"`` : float - VJ of every joint move.
        ``"joint_speed_reference_mm_s"`` : float - the speed that is 100 %
        VJ when ``joint_speed_percent`` is not given, default 1000.
        ``"relative_job"`` : bool - write relative jobs (DX100 and later).
        ``"joint_targets"`` : bool - default True: joint moves with solved
        joints go to PULSE positions when ``pulses_per_degree`` is given.
        ``"pulses_per_degree"`` : 6 numbers (or ``"a,b,c,d,e,f"``) - pulses
        per degree of each axis; no default (see the module docstring).
        ``"pulse_zero_deg"`` : 6 numbers - the joint angles (deg, the
        catalog model's controller convention) at 0 pulses; default 0.
        ``"pl_radii_mm"`` : 1 to 8 increasing numbers - the rounding of
        PL=1, 2, ... in mm, as set on the controller; default none (PL=1
        for a zone > 0, PL=0 for zone 0).
        ``"date"`` : datetime.datetime - for ``///DATE``.
        See :data:`OPTIONS`; :func:`CadRobotWB.posts.run` refuses others.

    Returns
    -------
    list of (str, str)
        ``[(f"{JOB}.JBI", text)]`` for one job; the main job first, then
        its sub-jobs in call order, when the program is split.

    Raises
    ------
    PostError
        The program or an option cannot be expressed in INFORM.
    """
    options = dict(options or {})
    controller = _controller(options)
    settings = _Settings.from_options(options, controller, program)
    for move in program.moves():
        common.check_move(move, program, _INSTRUCTIONS, NAME)
    _check_tracking(program)
    common.check_weld_runs(program, "Yaskawa INFORM")

    groups = _groups(program, settings)
    main = _main_name(program, options.get("job_name"), controller)
    header = (_header_comments(program, settings) + _external_comments(program, settings)
              + _weld_comments(main, program, settings))
    if _fits_one_job(groups, header, settings):
        return ([_job_file(main, header, groups, settings, program)]
                + _conditions_files(main, program, settings))
    parts = _split(groups, settings.max_positions,
                   settings.max_lines - len(_part_comments(main, 99999, 99999)))
    names = sub_job_names(main, len(parts), controller.max_name)
    calls = [f"CALL JOB:{name}" for name in names]
    note = _wrap(f"Split into {len(parts)} jobs of at most {settings.max_positions} "
                 f"positions and {settings.max_lines} lines.")
    if len(header) + len(note) + len(calls) > settings.max_lines:
        raise PostError(f"The main job {main} would need {len(calls)} CALL lines, more than "
                        f"max_lines={settings.max_lines} allows; raise max_positions or "
                        "max_lines.")
    files = [_job_file(main, header + note, [], settings, program, calls)]
    for k, (name, part) in enumerate(zip(names, parts), start=1):
        files.append(_job_file(name, _part_comments(main, k, len(parts)), part, settings,
                               program))
    return files + _conditions_files(main, program, settings)


def _fits_one_job(groups, header, settings):
    """True when the whole program fits one job's positions and lines."""
    positions = sum(len(g.steps) for g in groups)
    lines = len(header) + sum(_group_lines(g) for g in groups)
    return positions <= settings.max_positions and lines <= settings.max_lines


def _part_comments(main, k, count):
    """The comment lines at the top of sub-job `k` of `count`."""
    return _wrap(f"Part {k} of {count} of job {main} (CadRobot post {NAME}); "
                 f"user frames, tool and units: see {main}.")


def sub_job_names(main, count, max_length):
    """Names of the `count` sub-jobs of job `main`, in call order.

    Parameters
    ----------
    main : str
        The main job's name.
    count : int
    max_length : int
        The controller's job name length.

    Returns
    -------
    list of str
        ``MAIN_1``, ``MAIN_2``, ... when they fit; otherwise the main name
        is cut (with three characters of its hash, :func:`job_name`) and
        the numbers are zero-padded, so the names are always distinct and
        differ from the main job's.
    """
    width = len(str(count))
    if len(main) + 1 + width <= max_length:
        return [f"{main}_{k}" for k in range(1, count + 1)]
    base = job_name(main, max_length - 1 - width)
    return [f"{base}_{k:0{width}d}" for k in range(1, count + 1)]


# --- names -----------------------------------------------------------------------------------

def job_name(text, max_length=8):
    """A valid job name made from any text.

    Parameters
    ----------
    text : str
    max_length : int
        The controller's limit (8 on NX100, 32 on DX100 and later).

    Returns
    -------
    str
        Upper case, ``A-Z``, ``0-9`` and ``_``, starting with a letter
        (``J`` is put in front otherwise).  A longer name is cut to
        ``max_length - 3`` characters followed by three characters of a
        hash of the whole name.
    """
    return common.upper_name(text, max_length, prefix="J", empty="JOB")


def is_job_name(text, max_length=8):
    """Tell whether ``text`` is a job name this post writes as it is.

    Returns
    -------
    bool
        True for 1 to ``max_length`` characters ``[A-Z][A-Z0-9_]*``.
    """
    return common.is_upper_name(text, max_length)


def _main_name(program, requested, controller):
    if requested is None:   # a job's name is its file's name
        return job_name(common.file_stem(program.name), controller.max_name)
    if not isinstance(requested, str) or not is_job_name(requested.upper(), controller.max_name):
        raise PostError(
            f"Job name {requested!r} is not valid on the {controller.name}: use 1 to "
            f"{controller.max_name} letters, digits or '_', starting with a letter.")
    common.check_file_stem(requested.upper(), "job_name")
    return requested.upper()


# --- options -----------------------------------------------------------------------------------

def _controller(options):
    """The :class:`Controller` named by option ``controller`` (any case)."""
    value = options.get("controller", "nx100")
    key = value.lower() if isinstance(value, str) else value
    try:
        return CONTROLLERS[common.choice_option({"controller": key}, "controller", "nx100",
                                                tuple(CONTROLLERS))]
    except PostError:
        raise PostError(f"Unknown controller {value!r} for the {NAME} post; choose one of "
                        f"{', '.join(CONTROLLERS)}.") from None


def number_list_option(options, key, counts, check=None, what="numbers"):
    """A list of finite numbers, given as a sequence or as ``"a,b,c"`` text.

    Parameters
    ----------
    options : dict
    key : str
    counts : tuple of int
        The allowed list lengths.
    check : callable, optional
        ``check(values) -> bool``; a further rule the list must pass.
    what : str, optional
        The rule in words, for the message.

    Returns
    -------
    tuple of float or None
        None when the option is not given.

    Raises
    ------
    PostError
        Names the option and what it takes.
    """
    value = options.get(key)
    if value is None:
        return None
    if isinstance(value, str):
        items = value.split(",")
    elif isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool):
        items = [value]                     # one number (the CLI's pl_radii_mm=2)
    else:
        items = value
    try:
        values = tuple(_finite(item) for item in items)
    except (TypeError, ValueError):
        values = None
    if values is None or len(values) not in counts or (check and not check(values)):
        span = " or ".join(str(n) for n in counts) if len(counts) < 3 else \
            f"{counts[0]} to {counts[-1]}"
        raise PostError(f"{key} must be {span} {what} separated by commas, got {value!r}.")
    return values


def _finite(item):
    """A finite float of a number or a number's text (not a bool)."""
    if isinstance(item, bool):
        raise TypeError("a bool is not a number")
    number = float(item)
    if not np.isfinite(number):
        raise ValueError("not finite")
    return number


@dataclass
class _Settings:
    controller: Controller
    users: dict
    tool: int
    max_positions: int
    max_lines: int
    speed_unit: str
    joint_percent: Optional[float]
    joint_reference_mm_s: float
    relative: bool
    date: datetime.datetime
    spec: object
    joint_targets: bool
    pulses_per_degree: Optional[tuple]
    pulse_zero_deg: tuple
    pl_radii_mm: Optional[tuple]
    conditions: str = "inline"
    condition_numbers: dict = field(default_factory=dict)
    station: Optional["_Station"] = None

    @classmethod
    def from_options(cls, options, controller, program):
        users = frame_numbers(program, options.get("user_frame", 1), 0, controller.max_user)
        tool = common.whole_option(options, "tool", 0, 0, controller.max_tool)
        max_positions = common.whole_option(options, "max_positions", DEFAULT_MAX_POSITIONS,
                                            4, MAX_C_POSITIONS)
        max_lines = common.whole_option(options, "max_lines", DEFAULT_MAX_LINES, 50, 10 ** 6)
        unit = common.choice_option(options, "linear_speed_unit", "mm/s", LINEAR_SPEED_UNITS)
        percent = None
        if options.get("joint_speed_percent") is not None:
            percent = common.number_option(options, "joint_speed_percent", None, 0.01, 100)
        reference = common.positive_number(options, "joint_speed_reference_mm_s",
                                           DEFAULT_JOINT_REFERENCE_MM_S)
        relative = common.bool_option(options, "relative_job", False)
        if relative and not controller.relative_jobs:
            raise PostError(f"relative_job is written for DX100 and later controllers in "
                            f"this post, not for the {controller.name}.")
        date = common.date_option(options, DEFAULT_DATE)
        joint_targets = common.joint_targets_option(options)
        pulses = number_list_option(options, "pulses_per_degree", (6,),
                                    lambda v: all(x != 0 for x in v), "non-zero numbers")
        zero = number_list_option(options, "pulse_zero_deg", (6,)) or (0.0,) * 6
        if options.get("pulse_zero_deg") is not None and pulses is None:
            raise PostError("pulse_zero_deg is used only with pulses_per_degree; give both.")
        radii = number_list_option(options, "pl_radii_mm", tuple(range(1, 9)),
                                   _increasing_positive, "increasing numbers > 0")
        conditions = common.choice_option(options, "conditions", "inline", CONDITIONS)
        first_file = common.whole_option(options, "condition_file", 1, *CONDITION_FILES)
        station = _Station.from_options(options, program)
        if relative and program.external is not None:
            raise PostError("relative_job is not written with external axes (base BC, station "
                            "EC) by this post: export without relative_job.")
        return cls(controller, users, tool, max_positions, max_lines, unit, percent,
                   reference, relative, date, common.opw_robot_spec(program), joint_targets,
                   pulses, zero, radii, conditions, _condition_numbers(program, first_file),
                   station)


@dataclass
class _Station:
    """How the positioner's degrees become station pulses (EC positions)."""

    pulses_per_degree: tuple
    zero_deg: tuple

    @classmethod
    def from_options(cls, options, program):
        """The station options, checked against the program's positioner.

        Returns
        -------
        _Station or None
            None for a program without a positioner.

        Raises
        ------
        PostError
            A positioner without ``station_pulses_per_degree`` (pulses cannot be
            guessed), station options without a positioner, or lists of the
            wrong length.
        """
        external = program.external
        positioner = None if external is None else external.positioner
        keys = ("station_pulses_per_degree", "station_pulse_zero_deg")
        if positioner is None:
            given = [key for key in keys if options.get(key) is not None]
            if given:
                raise PostError(f"{given[0]} is for a program with a positioner; this one has "
                                "none: leave it out.")
            return None
        count = len(positioner.axes)
        pulses = number_list_option(options, keys[0], (count,),
                                    lambda v: all(x != 0 for x in v), "non-zero numbers")
        if pulses is None:
            names = ",".join(axis.name for axis in positioner.axes)
            raise PostError(f"The positioner '{positioner.label}' is written as station "
                            "positions (EC) in encoder pulses, which need its pulses per "
                            f"degree: give option station_pulses_per_degree, {count} numbers "
                            f"({names}) from the controller's parameters, sign = direction "
                            f"(--option station_pulses_per_degree=...).")
        zero = number_list_option(options, keys[1], (count,)) or (0.0,) * count
        return cls(pulses, zero)


def _increasing_positive(values):
    return values[0] > 0 and all(b > a for a, b in zip(values, values[1:]))


# --- steps and jobs ----------------------------------------------------------------------------

@dataclass
class _Step:
    """One move instruction and its C position."""

    instruction: str            # MOVJ, MOVL, MOVC
    T_b_t: np.ndarray           # pose in the work frame, mm
    frame: str                  # work frame name
    joints_deg: Optional[np.ndarray]
    speed: str                  # "VJ=10.00" / "V=12.5"
    level: Optional[int]        # PL, None for none
    pulses: Optional[tuple] = None   # a PULSE position instead of a Cartesian one
    external: Optional[np.ndarray] = None   # external axis values (track mm, positioner deg)
    synchronized: bool = False  # SMOVL/SMOVC: the robot follows the station (ST1)
    station_speed: str = ""     # "VJ=.." of the station's +MOVJ on a move that is not synchronized


@dataclass
class _Group:
    """Steps that must stay in one job (one move; an arc's 3 or 4 steps), with
    the comments written before them."""

    comments: List[str]
    steps: List[_Step] = field(default_factory=list)
    after: List[str] = field(default_factory=list)   # ARCON/WVON.. lines after the steps
    run: Optional[ir.WeldRun] = None                 # the weld run that strikes after it
    welded: bool = False                             # welded: stays in its weld's job


def _groups(program, settings):
    """The program's moves as groups of steps, in execution order."""
    groups = []
    previous = None        # (move, T_r_t) of the last move written
    for path in program.paths:
        pending = _wrap("Path: " + common.path_label(path))
        last_comment = None
        for index, move in enumerate(path.moves):
            comments, pending = pending, []
            text = comment_text(move.comment)
            if text and text != last_comment:
                comments += _wrap(text)
            last_comment = text
            speed = _speed_text(move, settings)
            level = position_level(move.zone_mm, settings.pl_radii_mm)
            target = move.target
            group = _Group(comments)
            moving = _external_step_fields(program, move, settings)
            if move.kind == ir.CIRCULAR:
                if previous is None:
                    raise PostError(f"The circular move to target '{target.name}' is the "
                                    "first move: INFORM needs the arc's start point; start "
                                    "the program with a joint or linear move.")
                prev_move, T_r_prev = previous
                if prev_move.frame == move.frame:
                    T_b_start = pose_in_drawn_frame(program, prev_move.frame, prev_move.target)
                else:
                    T_b_start = _in_frame(T_r_prev, move.frame, program)
                start_joints = prev_move.target.joints_deg
                start = _external_values(program, prev_move.target)
                if prev_move.kind == ir.CIRCULAR:      # separate two arcs
                    group.steps.append(_Step("MOVL", T_b_start, move.frame, start_joints,
                                             speed, None, None, start, **moving))
                group.steps.append(_Step("MOVC", T_b_start, move.frame, start_joints,
                                         speed, None, None, start, **moving))
                via = move.via
                group.steps.append(_Step("MOVC", pose_in_drawn_frame(program, move.frame, via),
                                         move.frame, via.joints_deg, speed, None, None,
                                         _external_values(program, via), **moving))
            group.steps.append(_Step(_INSTRUCTIONS[move.kind],
                                     pose_in_drawn_frame(program, move.frame, target), move.frame,
                                     target.joints_deg, speed, level,
                                     _pulses(move, program, settings),
                                     _external_values(program, target), **moving))
            group.run = common.weld_run_starting(path, index)
            group.welded = move.weld is not None
            group.after = _weld_lines(program, path, index, settings)
            groups.append(group)
            T_r_b = np.asarray(program.frames[move.frame].T_r_b, dtype=float)
            previous = (move, T_r_b @ pose_in_drawn_frame(program, move.frame, target))
    return groups


# --- external axes -----------------------------------------------------------------------------

def _external_values(program, target):
    """A target's external axis values, or None without external axes."""
    return None if program.external is None else common.target_external_values(program, target)


def _external_step_fields(program, move, settings):
    """``synchronized`` and ``station_speed`` of a move's steps: with a positioner,
    the path's linear and circular moves are SMOVL/SMOVC and the others move the
    station at the move's joint speed (VJ)."""
    if program.external is None or program.external.positioner is None:
        return {}
    percent = joint_speed_percent(move.speed_mm_s, settings.joint_percent,
                                  settings.joint_reference_mm_s)
    return {"synchronized": common.is_coordinated_move(move),
            "station_speed": f"VJ={percent:.2f}"}


def _step_line(step, number, program):
    """The instruction of one step: ``MOVL C00001 V=7.5 PL=0``; with a track
    ``BC00001`` after the C position, with a positioner ``+MOVJ EC00001`` (and the
    station's ``VJ=`` where the move is not synchronized, ``SMOVL``/``SMOVC`` where
    it is)."""
    level = "" if step.level is None else f" PL={step.level}"
    external = program.external
    if external is None:
        return f"{step.instruction} C{number:05d} {step.speed}{level}"
    instruction = "S" + step.instruction if step.synchronized else step.instruction
    base = "" if external.track is None else f" BC{number:05d}"
    line = f"{instruction} C{number:05d}{base} {step.speed}{level}"
    if external.positioner is not None:
        line += f" +MOVJ EC{number:05d}"
        line += "" if step.synchronized else f" {step.station_speed}"
    return line


def _external_positions(steps, settings, program, kind):
    """The BC (track, mm) and EC (station, pulses) lines of the //POS section,
    after the C positions (`kind`: the position type the C lines ended with)."""
    external = program.external
    if external is None or not steps:
        return []
    lines = []
    split = [external.split(step.external) for step in steps]
    if external.track is not None:
        lines += ["///POSTYPE BASE", "///RECTAN"]
        lines += [f"BC{n:05d}=" + ",".join(fixed(v, 3) for v in track)
                  for n, (track, _) in enumerate(split)]
        kind = "base"
    if external.positioner is not None:
        station = settings.station
        lines += [] if kind == "pulse" else ["///POSTYPE PULSE", "///PULSE"]
        lines += [f"EC{n:05d}=" + ",".join(str(v) for v in pulse_values(
                      turned, station.pulses_per_degree, station.zero_deg))
                  for n, (_, turned) in enumerate(split)]
    return lines


def _group_lines_of_job(program):
    """``///GROUP1 RB1`` (``,BS1`` with a track), ``///GROUP2 ST1`` with a positioner."""
    external = program.external
    if external is None:
        return ["///GROUP1 RB1"]
    lines = ["///GROUP1 RB1" + ("" if external.track is None else ",BS1")]
    return lines + ([] if external.positioner is None else ["///GROUP2 ST1"])


def _external_comments(program, settings):
    """Header comment lines: the external axes and how they are written."""
    external = program.external
    if external is None:
        return []
    out = common.external_axes_comments(program, _wrap)
    if external.track is not None:
        out += _wrap("Track: base axis BS1, BC positions = travel in mm (POSTYPE BASE)")
    station = settings.station
    if station is not None:
        ppd = ",".join(compact(v) for v in station.pulses_per_degree)
        zero = ",".join(compact(v) for v in station.zero_deg)
        out += _wrap(f"Positioner: station ST1, EC pulses = ppd*(deg - zero); ppd {ppd}; "
                     f"zero {zero}")
        out += _wrap("SMOVL/SMOVC: path moves synchronized with the station")
        out += _wrap("USER frame: teach it with the station at its drawn values")
    return out


def _in_frame(T_r_t, frame, program):
    """A pose in {R} expressed in work frame ``frame``."""
    T_r_b = np.asarray(program.frames[frame].T_r_b, dtype=float)
    return tf.invert_transform(T_r_b) @ T_r_t


def _pulses(move, program, settings):
    """The PULSE position of a joint move's target, or None for a Cartesian one."""
    if settings.pulses_per_degree is None or \
            not common.is_joint_target_move(move, settings.joint_targets):
        return None
    return pulse_values(common.controller_joints_deg(program, move.target),
                        settings.pulses_per_degree, settings.pulse_zero_deg)


def pulse_values(joints_deg, pulses_per_degree, zero_deg=(0.0,) * 6):
    """Encoder pulses of joint angles: ``round(ppd * (q - zero))`` per axis.

    Parameters
    ----------
    joints_deg : array_like, shape (6,)
        S, L, U, R, B, T in degrees (controller convention).
    pulses_per_degree : sequence of 6 float
        The controller's pulses per degree (sign = counting direction).
    zero_deg : sequence of 6 float, optional
        The angles at 0 pulses.

    Returns
    -------
    tuple of 6 int
        Halves rounded up.
    """
    return tuple(round_half_up(ppd * (q - zero)) for q, ppd, zero in
                 zip(np.asarray(joints_deg, dtype=float), pulses_per_degree, zero_deg))


def _group_lines(group):
    """Instruction lines of a group: its comments, one line per step and the
    arc and weave lines after them."""
    return len(group.comments) + len(group.steps) + len(group.after)


def _units(groups):
    """Groups in units that stay in one job: a move, or a weld's moves from
    its start move to its end move (touching welds together)."""
    units = []
    for group in groups:
        if group.welded and units:
            units[-1].append(group)
        else:
            units.append([group])
    return units


def _split(groups, max_positions, max_lines):
    """Groups into jobs of at most ``max_positions`` steps and ``max_lines``
    instruction lines (a group, or a weld run, is never split)."""
    parts, current, count, lines = [], [], 0, 0
    for unit in _units(groups):
        n = sum(len(g.steps) for g in unit)
        m = sum(_group_lines(g) for g in unit)
        if n > max_positions or m > max_lines:
            what = "One move" if unit[0].run is None else \
                f"Weld {unit[0].run.name!r} ({unit[0].run.label})"
            raise PostError(f"{what} needs {n} positions and {m} lines, more than one job "
                            f"takes (max_positions={max_positions}, max_lines={max_lines}); "
                            "raise max_positions or max_lines.")
        if current and (count + n > max_positions or lines + m > max_lines):
            parts.append(current)
            current, count, lines = [], 0, 0
        current += unit
        count += n
        lines += m
    parts.append(current)
    return parts


def _job_file(name, comments, groups, settings, program, calls=()):
    """(filename, text) of one job."""
    steps = [step for group in groups for step in group.steps]
    lines = ["/JOB", f"//NAME {name}", "//POS", "///NPOS " + _npos(steps, program)]
    lines += _positions(steps, settings, program)
    lines += ["//INST", "///DATE " + settings.date.strftime("%Y/%m/%d %H:%M"),
              "///COMM " + (comment_text(f"CadRobot {program.name}")[:COMMENT_WIDTH])]
    if settings.relative and steps:
        users = {settings.users[s.frame] for s in steps}
        if len(users) > 1:
            raise PostError(f"Job {name} has positions in user frames {sorted(users)}: a "
                            "relative job has one; export without relative_job or one frame "
                            "per program.")
        lines.append("///ATTR SC,RW,RJ")
        if users:
            lines.append(f"////FRAME USER {users.pop()}")
    else:
        lines.append("///ATTR SC,RW")
    lines += _group_lines_of_job(program) + ["NOP"]
    lines += ["'" + c for c in comments]
    number = 0
    for group in groups:
        lines += ["'" + c for c in group.comments]
        for step in group.steps:
            lines.append(_step_line(step, number, program))
            number += 1
        lines += group.after
    lines += list(calls)
    lines.append("END")
    return common.file_name(name, ".JBI"), NEWLINE.join(lines) + NEWLINE


def _npos(steps, program):
    """``C,BC,EC,P,BP,EX`` counts: one C (and BC with a track, EC with a
    positioner) per step."""
    external = program.external
    track = external is not None and external.track is not None
    station = external is not None and external.positioner is not None
    n = len(steps)
    return f"{n},{n if track else 0},{n if station else 0},0,0,0"


def _positions(steps, settings, program):
    """The pseudo instructions and C lines of the //POS section.

    ``///USER``, ``///TOOL``, ``///POSTYPE USER``, ``///RECTAN`` and
    ``///RCONF`` come before the first Cartesian position and again after
    PULSE positions; ``///POSTYPE PULSE`` and ``///PULSE`` before a PULSE
    position that follows a Cartesian one (or starts the job, after
    ``///TOOL``).
    """
    lines = []
    user = rconf = kind = None
    rconfs = _rconfs(steps, settings)
    poses = pose_texts([step.T_b_t for step in steps])
    for number, step in enumerate(steps):
        if step.pulses is not None:
            if kind != "pulse":
                if number == 0:
                    lines.append(f"///TOOL {settings.tool}")
                lines += ["///POSTYPE PULSE", "///PULSE"]
            kind, user, rconf = "pulse", None, None
            lines.append(f"C{number:05d}=" + ",".join(str(v) for v in step.pulses))
            continue
        step_user = settings.users[step.frame]
        step_rconf = rconfs[number]
        if kind != "user":
            lines += [f"///USER {step_user}", f"///TOOL {settings.tool}", "///POSTYPE USER",
                      "///RECTAN", f"///RCONF {step_rconf}"]
        else:
            if step_user != user:
                lines.append(f"///USER {step_user}")
            if step_rconf != rconf:
                lines.append(f"///RCONF {step_rconf}")
        kind, user, rconf = "user", step_user, step_rconf
        lines.append(f"C{number:05d}=" + poses[number])
    return lines + _external_positions(steps, settings, program, kind)


def pose_values(T):
    """X, Y, Z (mm, 3 decimals) and Rx, Ry, Rz (deg, 4 decimals) of a pose.

    Parameters
    ----------
    T : array_like, shape (4, 4)

    Returns
    -------
    list of 6 str
        ``R = Rz(Rz) Ry(Ry) Rx(Rx)``; Rx, Rz in (-180, 180], Ry in
        [-90, 90]; no ``-0.000``.
    """
    return common.xyz_fixed_angles(T, 4)


def pose_texts(poses):
    """``X,Y,Z,Rx,Ry,Rz`` text of many poses at once (see :func:`pose_values`).

    Parameters
    ----------
    poses : sequence of array_like, shape (4, 4)

    Returns
    -------
    list of str
    """
    if not len(poses):
        return []
    T = np.asarray(poses, dtype=float)
    angles = np.degrees(rotations.euler_xyz_fixed_from_matrix(T[:, :3, :3]))
    return [",".join([fixed(v, 3) for v in xyz] + [fixed(a, 4) for a in abc])
            for xyz, abc in zip(T[:, :3, 3].tolist(), angles.tolist())]


def _rconfs(steps, settings):
    """The ///RCONF fields (text) of every step; :data:`DEFAULT_RCONF` without joints."""
    fields = [DEFAULT_RCONF] * len(steps)
    solved = [k for k, step in enumerate(steps) if step.joints_deg is not None]
    if solved and settings.spec is not None:
        q = np.array([steps[k].joints_deg for k in solved], dtype=float)
        if not np.all(np.isfinite(q)):
            raise PostError("A target has joints that are not finite numbers; check the program.")
        for k, values in zip(solved, configuration_data.motoman_rconfs(q, settings.spec)):
            fields[k] = values
    tail = (0,) * settings.controller.rconf_unused
    return [",".join(str(int(v)) for v in tuple(f) + tail) for f in fields]


# --- speeds and levels -------------------------------------------------------------------------

def position_level(zone_mm, radii_mm=None):
    """The PL of a zone: never a rounding larger than the zone.

    Parameters
    ----------
    zone_mm : float
        >= 0.
    radii_mm : sequence of float, optional
        The rounding of PL=1, 2, ... on the controller (its parameters,
        option ``pl_radii_mm``), increasing.

    Returns
    -------
    int
        0 (reach the point) for zone 0. Without ``radii_mm``: 1, the least
        rounding short of a stop. With them: the highest level whose radius
        does not exceed the zone, 0 when it is smaller than PL=1's radius.
    """
    if not radii_mm:
        return 1 if zone_mm > 0.0 else 0
    return sum(1 for radius in radii_mm if radius <= zone_mm)


def joint_speed_percent(speed_mm_s, fixed_percent=None,
                        reference_mm_s=DEFAULT_JOINT_REFERENCE_MM_S):
    """VJ of a joint move: ``fixed_percent`` or ``100 * speed / reference``.

    Returns
    -------
    float
        Clamped to 0.01 .. 100.
    """
    value = fixed_percent if fixed_percent is not None else 100.0 * speed_mm_s / reference_mm_s
    return min(100.0, max(0.01, float(value)))


def _speed_text(move, settings):
    """``VJ=..`` of a joint move, ``V=..`` of a linear or circular one."""
    if move.kind == ir.JOINT:
        percent = joint_speed_percent(move.speed_mm_s, settings.joint_percent,
                                      settings.joint_reference_mm_s)
        return f"VJ={percent:.2f}"
    where = f"move to target '{move.target.name}'"
    if settings.speed_unit == "cm/min":
        value = round_half_up(move.speed_mm_s * 6.0)
        if not 1 <= value <= 99999:
            raise PostError(f"The {where} has speed {move.speed_mm_s} mm/s = "
                            f"{move.speed_mm_s * 6:g} cm/min, outside 1..99999 cm/min.")
        return f"V={value:d}"
    text = f"{move.speed_mm_s:.1f}"
    if not 0.1 <= float(text) <= 9999.9:
        raise PostError(f"The {where} has speed {move.speed_mm_s} mm/s; INFORM's V takes "
                        "0.1 to 9999.9 mm/s (0.1 mm/s resolution).")
    return f"V={text}"


# --- text --------------------------------------------------------------------------------------

def _wrap(text, width=COMMENT_WIDTH):
    """Comment lines of at most ``width`` characters, cut at spaces where possible."""
    return common.wrap_words(comment_text(text), width)


def _pose_comments(T):
    """Three comment lines with X, Y, Z, Rx, Ry, Rz of a pose."""
    x, y, z, rx, ry, rz = pose_values(T)
    return [f"X={x} Y={y}", f"Z={z} Rx={rx}", f"Ry={ry} Rz={rz}"]


def _header_comments(program, settings):
    """The comment lines at the top of a (main) job: origin, units, rules,
    and the user frame and tool values to teach."""
    if settings.speed_unit == "mm/s":
        speed = "V in mm/s (0.1 mm/s steps)"
    else:
        speed = "V in cm/min (1 cm/min steps)"
    if settings.joint_percent is not None:
        joint = [f"VJ={settings.joint_percent:.2f} on joint moves"]
    else:
        joint = ["VJ = 100 % * speed /", f"     {compact(settings.joint_reference_mm_s)} mm/s"]
    out = [f"CadRobot post {NAME}", f"Controller: {settings.controller.name}"]
    source, robot = common.source_and_robot(program)
    out += _wrap(f"Source: {source}")
    out += _wrap(f"Robot: {robot}")
    out += _wrap(common.other_maker_note(program.robot, NAME,
                                         "Yaskawa Motoman " + settings.controller.name))
    out += ["Units: mm, deg", speed] + joint
    out += ["Rx,Ry,Rz: R = Rz * Ry * Rx"] + _level_comments(settings)
    out += _joint_target_comments(program, settings)
    out += ["Teach USER and TOOL first:"]
    for frame_name, number in settings.users.items():
        frame = program.frames[frame_name]
        out += _wrap(f"USER {number} = {comment_text(frame_name)} (robot coords)")
        out += _pose_comments(frame.T_r_b)
        T = np.asarray(frame.T_r_b, dtype=float)
        for label, point in (("ORG", T[:3, 3]), ("XX", T[:3, 3] + 100.0 * T[:3, 0]),
                             ("XY", T[:3, 3] + 100.0 * T[:3, 1])):
            px, py, pz = (fixed(v, 3) for v in point)
            out += [f"{label} X={px} Y={py}", f"{label} Z={pz}"]
    tool = program.tool
    out += _wrap(f"TOOL {settings.tool} = {comment_text(tool.name)} (flange coords)")
    out += _pose_comments(tool.T_f_t)
    cog = [fixed(v, 3) for v in np.asarray(tool.cog_mm, dtype=float)]
    out += [f"W={compact(tool.mass_kg)} kg", f"Xg={cog[0]} Yg={cog[1]}", f"Zg={cog[2]}"]
    solved = settings.spec is not None and all(
        t.joints_deg is not None for t in program.targets())
    if solved:
        out += ["RCONF: the checked arm config"]
    else:
        out += ["RCONF 0,0,0,0,0,0 (flip, upper", "arm, front) without joints"]
    return out


def _level_comments(settings):
    """How zones became PL levels."""
    if not settings.pl_radii_mm:
        return ["PL=1 where the zone is > 0,", "PL=0 (reach point) at zone 0:",
                "no pl_radii_mm given"]
    radii = ",".join(compact(r) for r in settings.pl_radii_mm)
    return _wrap(f"PL=n: highest n with radius <= zone, else PL=0; PL1.. radii mm: {radii}")


def _joint_target_comments(program, settings):
    """What joint moves go to: PULSE positions or Cartesian ones."""
    if settings.pulses_per_degree is None or not settings.joint_targets:
        why = ("joint_targets off" if not settings.joint_targets
               else "no pulses_per_degree given")
        return _wrap(f"MOVJ to Cartesian C + RCONF ({why})")
    ppd = ",".join(compact(v) for v in settings.pulses_per_degree)
    zero = ",".join(compact(v) for v in settings.pulse_zero_deg)
    return _wrap(f"MOVJ with solved joints to PULSE C = ppd*(joint - zero deg); ppd {ppd}; "
                 f"zero {zero}")


# --- welds -------------------------------------------------------------------------------------

def _check_tracking(program):
    """Refuse through-arc tracking: COM-ARC's instruction arguments were not found."""
    for _, run in program.weld_runs():
        if run.tracking.sensor == "arc":
            raise PostError(f"Weld {run.name!r} ({run.label}) asks for through-arc tracking: "
                            "this post does not write Yaskawa COM-ARC yet (the arguments of "
                            "COMARCON were not found in a source); set its tracking to none.")


def _condition_numbers(program, first):
    """Condition file numbers of each weld run, by run name: ``(ASF/AEF n, WEV n)``,
    `first` for the first schedule (weave) and the next numbers for the others
    in order of use; WEV None without a weave.

    Raises
    ------
    PostError
        A number beyond :data:`CONDITION_FILES`.
    """
    schedules, weaves, numbers = {}, {}, {}
    for _, run in program.weld_runs():
        arc = schedules.setdefault(run.schedule, first + len(schedules))
        weave = None if run.weave is None else weaves.setdefault(run.weave,
                                                                first + len(weaves))
        if max(arc, weave or 0) > CONDITION_FILES[1]:
            raise PostError(f"Weld {run.name!r} ({run.label}) would use condition file "
                            f"{max(arc, weave)}, beyond {CONDITION_FILES[1]}; pass a smaller "
                            "condition_file.")
        numbers[run.name] = (arc, weave)
    return numbers


def _weld_lines(program, path, index, settings):
    """The arc and weave instructions after move `index`: (WVOF) ARCOF after a
    run's end move, ARCON (WVON) after a run's start move (both where two
    welds touch), else none."""
    files = settings.conditions == "files"
    lines = []
    ending = common.weld_run_ending(path, index)
    if ending is not None:
        arc, _ = settings.condition_numbers[ending.name]
        lines += ["WVOF"] if ending.weave is not None else []
        lines.append(f"ARCOF AEF#({arc})" if files else "ARCOF " + _crater_tags(ending))
    run = common.weld_run_starting(path, index)
    if run is None:
        return lines
    arc, wev = settings.condition_numbers[run.name]
    lines.append(f"ARCON ASF#({arc})" if files else "ARCON " + _arc_tags(run))
    if run.weave is not None:
        mode = common.weave_pattern_for("Yaskawa INFORM", run, WEAVE_MODES)
        lines.append(f"WVON WEV#({wev})" if files else
                     "WVON " + _weave_tags(run, mode, _weave_angle_deg(program, path, run)))
    return lines


def _current(run, current_a, what):
    """``AC=`` of a current (whole amperes, 1..999)."""
    if current_a is None:
        raise PostError(f"Weld {run.name!r} ({run.label}) has no {what}: INFORM's in-line "
                        f"ARCON/ARCOF need AC=; give the schedule's current_a or use "
                        "conditions=files.")
    return f"AC={min(999, max(1, round_half_up(current_a)))}"


def _arc_tags(run):
    """``AC=265 AV=27.5`` of a run's schedule."""
    s = run.schedule
    return f"{_current(run, s.current_a, 'current')} AV={fixed(s.voltage_v, 1)}"


def _crater_tags(run):
    """``AC=185 AV=22.0 T=0.30``: the crater current, voltage and time."""
    s = run.schedule
    return (f"{_current(run, s.crater_current_a, 'crater current')} "
            f"AV={fixed(s.crater_voltage_v, 1)} T={fixed(s.crater_fill_s, 2)}")


def _weave_tags(run, mode, angle_deg):
    """``AMP=2.0 FREQ=2.0 ANGL=45.0 DIR=0`` of a Single-mode weave without dwells.

    Raises
    ------
    PostError
        Another mode, or dwells: the in-line tags have neither (S19).
    """
    weave = run.weave
    if mode != "Single" or weave.dwells_s:
        what = f"{mode} mode ({weave.pattern} weave)" if mode != "Single" else "weave dwells"
        raise PostError(f"Weld {run.name!r} ({run.label}): INFORM's in-line WVON has no "
                        f"{what}: use conditions=files (WVON WEV#(n)) or a zigzag weave "
                        "without dwells.")
    frequency = weave.frequency(run.schedule.travel_speed_mm_s)
    return (f"AMP={fixed(weave.width_mm / 2, 1)} FREQ={fixed(frequency, 1)} "
            f"ANGL={fixed(angle_deg, 1)} DIR=0")


def _weave_angle_deg(program, path, run):
    """ANGL of a run's weave: the angle of the weave line, seen along the travel
    at the seam start, from the horizontal (the robot base's X-Y plane) up,
    0.1 to 180 degrees; with external axes, the travel along the part where
    they put it at the seam start (``core.mechanisms.frame_in_base``): a
    positioner turning the seam under a still torch.

    unverified: Yaskawa's reference of ANGL (horizontal, wall, REFP points) and
    its sense; see docs/controllers.md.

    Raises
    ------
    PostError
        The seam starts vertically (no horizontal reference: ANGL needs REFP
        points this post does not write).
    """
    start, first = path.moves[run.start], path.moves[run.start + 1]
    T_r_b = mechanisms.frame_in_base(program, start, start.target)
    T0, T1 = (T_r_b @ np.asarray(m.target.T_b_t, dtype=float) for m in (start, first))
    X, Y, Z = weave_geometry.frame_axes((T1[:3, 3] - T0[:3, 3])[None], T0[None, :3, 2])
    up = np.array([0.0, 0.0, 1.0])
    horizontal = np.cross(up, X[0])
    if np.linalg.norm(horizontal) < 1e-6:
        raise PostError(f"Weld {run.name!r} ({run.label}) starts on a vertical seam: the "
                        "weave angle ANGL needs REFP reference points, which this post does "
                        "not write; set the weave angle on the pendant with conditions=files.")
    horizontal /= np.linalg.norm(horizontal)
    vertical = np.cross(X[0], horizontal)
    turn = np.radians(run.weave.angle_deg)
    line = np.cos(turn) * Y[0] + np.sin(turn) * Z[0]
    angle = np.degrees(np.arctan2(line @ vertical, line @ horizontal)) % 180.0
    return 180.0 if angle < 0.05 else float(angle)


def _weld_comments(main, program, settings):
    """Header comment lines: how the arc is written and each schedule's values."""
    if not program.weld_runs():
        return []
    if settings.conditions == "files":
        out = _wrap(f"Arc and weave: condition files ASF, AEF, WEV; their values: "
                    f"{main}_CONDITIONS.txt")
    else:
        out = _wrap("Arc and weave: in-line tags; AMP = half the full weave width")
    seen = set()
    for _, run in program.weld_runs():
        if run.schedule in seen:
            continue
        seen.add(run.schedule)
        for line in common.schedule_comment_lines(run):
            out += _wrap(line)
    return out


def _conditions_files(main, program, settings):
    """``[(f"{main}_CONDITIONS.txt", text)]``: the values to enter in each
    condition file the jobs use, with ``conditions="files"``; else ``[]``.

    Not the controller's .CND files (their text format was not found): a
    sheet for the person who enters them on the pendant.
    """
    if settings.conditions != "files" or not program.weld_runs():
        return []
    lines = [f"CadRobot: condition files used by job {main} (post {NAME}, conditions=files).",
             "Enter these values on the pendant (ARC WELDING > ARC START COND. /",
             "ARC END COND. / WEAVING COND.) before running the job. CadRobot does not",
             "write the controller's condition files (.CND).", ""]
    written = set()
    for path, run in program.weld_runs():
        arc, wev = settings.condition_numbers[run.name]
        lines.append(f"Weld {run.name} ({comment_text(run.label)}), segments "
                     f"{run.first_segment}-{run.last_segment} of path {path.name}:")
        lines += _sheet_entry(("ASF", arc), written, _start_values(run))
        lines += _sheet_entry(("AEF", arc), written, _end_values(run))
        if wev is not None:
            lines += _sheet_entry(("WEV", wev), written, _weave_values(program, path, run))
        lines.append("")
    name = common.file_name(f"{main}_CONDITIONS", ".txt")
    return [(name, NEWLINE.join(lines) + NEWLINE)]


def _sheet_entry(key, written, values):
    """Lines of one condition file on the sheet, or a reference to where it
    was listed already."""
    kind, number = key
    title = {"ASF": "ARC START CONDITION", "AEF": "ARC END CONDITION",
             "WEV": "WEAVING CONDITION"}[kind]
    if key in written:
        return [f"  {kind}#({number}): as above"]
    written.add(key)
    return [f"  {kind}#({number}) {title}"] + [f"    {label:<22}{value}"
                                              for label, value in values]


def _start_values(run):
    s = run.schedule
    current = "-" if s.current_a is None else f"{compact(s.current_a, 1)} A"
    estimated = " (estimated from the current)" if s.wire_feed_estimated else ""
    return [("current", current), ("voltage", f"{fixed(s.voltage_v, 1)} V"),
            ("wire feed", f"{compact(s.wire_feed_m_min, 1)} m/min{estimated}"),
            ("gas pre-flow", f"{fixed(s.gas_preflow_s, 2)} s"),
            ("travel speed", f"{compact(s.travel_speed_mm_s, 2)} mm/s (on each MOVL V=)")]


def _end_values(run):
    s = run.schedule
    current = "-" if s.crater_current_a is None else f"{compact(s.crater_current_a, 1)} A"
    return [("crater current", current), ("crater voltage", f"{fixed(s.crater_voltage_v, 1)} V"),
            ("crater wire feed", f"{compact(s.crater_wire_feed_m_min, 1)} m/min"),
            ("crater time", f"{fixed(s.crater_fill_s, 2)} s"),
            ("burn-back", f"{fixed(s.burnback_s, 2)} s"),
            ("gas post-flow", f"{fixed(s.gas_postflow_s, 2)} s")]


def _weave_values(program, path, run):
    weave = run.weave
    try:
        angle = f"{fixed(_weave_angle_deg(program, path, run), 1)} deg"
    except PostError:
        angle = "set on the pendant (vertical seam: teach REFP points)"
    values = [("mode", common.weave_pattern_for("Yaskawa INFORM", run, WEAVE_MODES)),
              ("amplitude", f"{fixed(weave.width_mm / 2, 1)} mm (half the "
                            f"{compact(weave.width_mm, 2)} mm full width)"),
              ("frequency", f"{fixed(weave.frequency(run.schedule.travel_speed_mm_s), 2)} Hz"),
              ("angle", angle)]
    if weave.pattern in ("triangle", "l"):
        values.append(("height", f"{fixed(weave.height, 1)} mm"))
    values.append(("timer (weave stop)", f"left {fixed(weave.dwell_left_s, 2)} s, centre "
                                         f"{fixed(weave.dwell_center_s, 2)} s, right "
                                         f"{fixed(weave.dwell_right_s, 2)} s"))
    return values
