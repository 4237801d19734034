"""Universal Robots URScript post-processor: ``<name>.script`` files.

Layout of the file written by :func:`export`::

    def <name>():
      # header: source, robot, units, conventions
      set_tcp(p[...])             the tool (program.tool), flange -> TCP
      set_payload(m, [cog])       or set_target_payload (option payload_function)
      <frame> = p[...]            one per work frame: {B} in the robot base
      <target> = p[...]           every target of a Cartesian move, in its work frame
      movej([q1, ..., q6], ...)   a joint move to solved joints (rad)
      movej/movel/movec(pose_trans(<frame>, <target>), a=..., v=..., r=...)
    end
    <name>()

The call after ``end`` is written by default (option ``call``, default
True): a file loaded as a script (a PolyScope Script node, or the file
run on its own) only defines the function, and nothing moves without the
call.  ``call=False`` leaves it out, for a script sent to URControl's port
30002 ("the script must start from a function definition ... all other
script lines must be indented ... the last line of script must be an end
keyword", URScript manual, Connecting to URControl); there the function
runs without a call.

Conventions:

* Poses ``p[x, y, z, rx, ry, rz]``: metres and a rotation vector (axis times
  angle, radians), both with 7 decimals.  With 6 (0.5 um per coordinate) a
  target composed with its frame's rounded pose could miss the program's
  pose by more than 1e-3 mm; with 7 it stays within 1e-3 mm / 1e-4 deg.
  The rotation vector is
  :func:`~CadRobotWB.core.rotations.rotvec_from_matrix` (angle in [0, pi];
  at pi the axis sign is canonical, never decided by rounding noise).
* The robot base frame {R} is the controller's ``base`` frame.  A target
  is written in its work frame {B} and moved to as
  ``pose_trans(frame, target)`` with ``frame`` = WorkFrame.T_r_b, i.e. the
  pose of the TCP in the base frame.
* Joint moves (approach and other air moves): with ``joint_targets`` on
  (default) and solved joints, ``movej([q1, ..., q6], a, v, r)`` with the
  joints of :func:`~CadRobotWB.posts.common.controller_joints_deg` in
  radians (7 decimals): the arm configuration CadRobot checked.  Without
  solved joints, or with ``joint_targets=False``, ``movej(pose)``: the
  controller solves the inverse kinematics itself and takes the solution
  nearest its current joints.  ``v`` and ``a`` are the leading joint's
  speed (rad/s) and acceleration (rad/s^2): a TCP speed cannot be given to
  movej (options ``joint_speed_rad_s``, default 1.05, and
  ``joint_accel_rad_s2``, default 1.4, URScript's own defaults).
* ``movel`` / ``movec``: ``v`` = the move's speed in m/s, ``a`` = option
  ``linear_accel_m_s2`` (default 1.2, URScript's default).  ``movec`` uses
  ``mode=0`` (orientation interpolated from the start to the end pose; the
  via point's orientation is not used), as CadRobot interpolates it.
* Blend radius ``r`` = the move's zone in metres, rounded *down* to 1e-6 m
  (:func:`blend_text`), so never larger than the zone; 0 = stop at the
  target.  The controller refuses a blend radius that overlaps the next
  blend or is longer than the move; CadRobot does not check that here.
* Payload: ``set_payload(m, cog)`` by default, accepted by CB3 (3.x) and
  e-Series (5.x) software and documented as deprecated, in favour of
  ``set_target_payload(m, cog, inertia, transition_time)``, from PolyScope
  5.10 on (URScript manual of software 10.6, set_target_payload).  Option
  ``payload_function="set_target_payload"`` writes that (mass and CoG;
  inertia zero, as the manual's default).

Long programs
-------------
Universal Robots documents no limit on the size of a script.  Users report
a 200,000-line (18 MB) script crashing the controller when loaded, and
socket streams of more than 1,000 to 2,500 targets not running; RoboDK's
UR post sends a long program to the controller in parts of 5,000 lines
(``MAX_LINES_X_PROG``).  So a program of more than ``max_moves`` moves
(option, default 5000; 0 = never split) is written as ``<name>_1.script``,
``<name>_2.script``, ..., each a complete program (tool, payload, the
frames and targets it uses, its own call) to run in that order, sent one
after the other over the socket or as consecutive Script nodes.  URScript
has no way for one file to call another, so there is no main file; the
robot stops at the end of each part (the last move of a part has
``r=0``).

External axes
--------------
URScript has none: a program with a track or a positioner is refused in one
line naming it (issue 23).

Welds
-----
URScript has no arc instructions: a weld run (issue 22) switches the arc
with a standard digital output and sets wire feed and voltage with the
standard analogue outputs (options ``arc_output``, ``wire_feed_output``,
``voltage_output``, their full scales, ``arc_ok_input``), waits the gas
pre-flow, crater and post-flow, and writes the weave as motion: ``movep``
through the woven points of :mod:`~CadRobotWB.core.weave`
(:func:`woven_points`), each at the speed that covers the seam at the
travel speed.  A split never cuts a weld.  Details: docs/controllers.md,
Universal Robots, Welding.

Not verified on a controller: there is no independent URScript parser
here; the tests check the layout, the numbers and the conventions.

Pure Python/numpy: never imports FreeCAD.
"""

import textwrap
from dataclasses import dataclass

import numpy as np

from ..core import program as ir
from ..core import rotations
from ..core import weave as weave_geometry
from ..errors import PostError
from . import common
from .common import comment_text, compact, fixed

NAME = "ur_script"
DESCRIPTION = "Universal Robots URScript program (.script)"
FILE_EXTENSIONS = (".script",)

INDENT = "  "
#: Decimals of the numbers in a pose (metres, radians).
DECIMALS = 7
#: CadRobot's own cap on name length (URScript states none that we know of).
MAX_NAME = 32

#: URScript keywords, the pose literal ``p`` and the built-in functions this
#: post calls or that a program commonly calls (lower case).
RESERVED_WORDS = frozenset("""
    and or xor not def end if elif else while for return thread run join kill
    halt break continue sec global local true false pass p
    movej movel movec movep servoj speedj speedl stopj stopl pose_trans
    pose_inv pose_add pose_sub set_tcp set_payload get_inverse_kin
    get_actual_tcp_pose get_actual_joint_pos sleep sync textmsg popup
    set_standard_analog_out set_standard_digital_out get_standard_digital_in arc_wait
""".split())

_INSTRUCTIONS = {ir.JOINT: "movej", ir.LINEAR: "movel", ir.CIRCULAR: "movec"}

#: Moves per file before a program is split (RoboDK's UR post sends a program
#: to the controller in parts of ``MAX_LINES_X_PROG = 5000`` lines, about one
#: move each; not a limit documented by Universal Robots).
DEFAULT_MAX_MOVES = 5000

#: The payload functions this post can write (see the module docstring).
PAYLOAD_FUNCTIONS = ("set_payload", "set_target_payload")

#: Every option :func:`export` reads, with one line of help.
OPTIONS = {
    "program_name": "function and file name instead of the program's (a URScript name)",
    "call": "true (default): call the function after 'end', so the file runs when "
            "loaded; false: no call (for port 30002)",
    "linear_accel_m_s2": "acceleration of movel/movec, m/s^2 (default 1.2)",
    "joint_accel_rad_s2": "acceleration of movej, rad/s^2 (default 1.4)",
    "joint_speed_rad_s": "speed of movej, rad/s (default 1.05)",
    "joint_targets": "true (default): joint moves with solved joints write movej([q] rad); "
                     "false: movej(pose)",
    "payload_function": "set_payload (default, CB3 3.x and e-Series 5.x; deprecated "
                        "from 5.10) or set_target_payload (PolyScope 5.10+)",
    "max_moves": "moves per file before the program is split into runnable parts "
                 "(default 5000; 0: never split)",
    "arc_output": "standard digital output 0..7 that switches the arc (True = arc on; "
                  "default 0)",
    "wire_feed_output": "standard analogue output 0..1 of the wire feed set-point (default 0), "
                        "or none",
    "voltage_output": "standard analogue output 0..1 of the voltage set-point (default 1), "
                      "or none",
    "wire_feed_full_scale_m_min": "wire feed at analogue level 1.0, m/min (default 20)",
    "voltage_full_scale_v": "voltage at analogue level 1.0, V (default 50)",
    "arc_ok_input": "standard digital input 0..7 that is True while the arc burns: the "
                    "program waits for it after arc on (default: none, no wait)",
    "arc_ok_timeout_s": "longest wait for arc_ok_input, s (default 2): then arc off and halt",
}

#: Standard digital outputs/inputs 0..7 and analogue outputs 0..1 (URScript manual,
#: set_standard_digital_out, get_standard_digital_in, set_standard_analog_out).
DIGITAL_PINS = (0, 7)
ANALOG_PINS = (0, 1)
#: Woven points per circle weave cycle.
CIRCLE_POINTS = 8
#: Blend radius of a woven point as a share of its shorter neighbouring segment (within
#: half, so two neighbouring blends never overlap).
WOVEN_BLEND_SHARE = 0.4
#: A welded move shorter than this does not travel (it turns in place), mm.
MIN_TRAVEL_MM = 1e-6
#: Woven points closer in time than this are one point, s.
TIME_TOLERANCE_S = 1e-6
#: Step of the wait for the arc-ok input, s.
ARC_OK_POLL_S = 0.01


@dataclass
class _Settings:
    """The options, read and checked once."""

    call: bool
    linear_accel: float
    joint_accel: float
    joint_speed: float
    joint_targets: bool
    payload_function: str
    max_moves: int
    arc: "_ArcIO" = None

    @classmethod
    def from_options(cls, options):
        return cls(common.bool_option(options, "call", True),
                   _number_option(options, "linear_accel_m_s2", 1.2),
                   _number_option(options, "joint_accel_rad_s2", 1.4),
                   _number_option(options, "joint_speed_rad_s", 1.05),
                   common.joint_targets_option(options),
                   common.choice_option(options, "payload_function", "set_payload",
                                        PAYLOAD_FUNCTIONS),
                   common.whole_option(options, "max_moves", DEFAULT_MAX_MOVES, 0, 10 ** 9),
                   _ArcIO.from_options(options))


@dataclass
class _ArcIO:
    """The welder's wiring: which pins switch and set the arc (see :data:`OPTIONS`)."""

    arc_output: int
    wire_feed_output: object     # int or None
    voltage_output: object       # int or None
    wire_feed_full_scale_m_min: float
    voltage_full_scale_v: float
    arc_ok_input: object         # int or None
    arc_ok_timeout_s: float

    @classmethod
    def from_options(cls, options):
        return cls(common.whole_option(options, "arc_output", 0, *DIGITAL_PINS),
                   _pin_or_none(options, "wire_feed_output", 0, ANALOG_PINS),
                   _pin_or_none(options, "voltage_output", 1, ANALOG_PINS),
                   common.positive_number(options, "wire_feed_full_scale_m_min", 20.0),
                   common.positive_number(options, "voltage_full_scale_v", 50.0),
                   _pin_or_none(options, "arc_ok_input", None, DIGITAL_PINS),
                   _number_option(options, "arc_ok_timeout_s", 2.0))


def _pin_or_none(options, key, default, pins):
    """A pin number option that may be ``None`` / ``"none"`` (not wired)."""
    value = options.get(key, default)
    if value is None or (isinstance(value, str) and value.strip().lower() == "none"):
        return None
    return common.whole_option({key: value}, key, default, *pins)


def export(program, options=None):
    """Write a program as one URScript file, or as runnable parts.

    Parameters
    ----------
    program : CadRobotWB.core.program.Program
        Targets in their work frames {B}, mm.
    options : dict, optional
        See :data:`OPTIONS`: ``"program_name"`` (str), ``"call"`` (bool,
        default True), ``"linear_accel_m_s2"`` (default 1.2),
        ``"joint_accel_rad_s2"`` (default 1.4), ``"joint_speed_rad_s"``
        (default 1.05), ``"joint_targets"`` (bool, default True),
        ``"payload_function"`` (default ``"set_payload"``), ``"max_moves"``
        (int, default 5000, 0 = never split).
        :func:`CadRobotWB.posts.run` refuses other names.

    Returns
    -------
    list of (str, str)
        ``[(f"{name}.script", text)]``; a program of more than
        ``max_moves`` moves gives ``{name}_1.script``, ``{name}_2.script``,
        ... to run in that order (see the module docstring).

    Raises
    ------
    PostError
        The program has external axes, or a move, speed, zone, name or option
        URScript cannot express.
    """
    _refuse_external_axes(program)
    options = options or {}
    settings = _Settings.from_options(options)
    names = common.Namer(RESERVED_WORDS, MAX_NAME, separator="_")
    name = _program_name(program, options.get("program_name"), names)
    moves = program.moves()
    for move in moves:
        common.check_move(move, program, _INSTRUCTIONS, "URScript",
                          speed_decimals=6, speed_unit_mm_s=1000.0)
    common.check_tool_mass(program.tool)
    common.check_weld_runs(program, "URScript")
    joints = {id(m): _joint_list(program, m) for m in moves
              if common.is_joint_target_move(m, settings.joint_targets)}
    welds = {id(path.moves[run.start]): _weld_block(path, run, settings)
             for path, run in program.weld_runs()}
    parts = _split([(path, move) for path in program.paths for move in path.moves],
                   settings.max_moves, welds)
    functions = _part_names(name, len(parts), names)
    used_frames = list(dict.fromkeys(move.frame for move in moves))
    frames = {key: names.add(key, "frame") for key in used_frames}
    targets = common.target_names(program, names, "t")
    texts = dict(zip(targets, _poses([target.T_b_t for target, _ in targets.values()])))
    context = (program, settings, frames, targets, texts, joints, welds)
    return [(common.file_name(function, ".script"),
             _file_text(function, part, k, len(parts), context))
            for k, (function, part) in enumerate(zip(functions, parts), start=1)]


def _refuse_external_axes(program):
    """URScript has no external axes (no track, no positioner).

    Raises
    ------
    PostError
        One line naming the program's mechanisms and what to do.
    """
    external = program.external
    if external is None:
        return
    mechanisms = external.mechanisms()
    named = " and ".join(f"{'track' if m.kind == 'track' else 'positioner'} '{m.label}'"
                         for m in mechanisms)
    them = "it" if len(mechanisms) == 1 else "them"
    raise PostError(f"URScript has no external axes: the cell's {named} cannot be written "
                    f"for a UR robot; remove {them} from the cell and place the part where "
                    "the arm alone reaches it, or export with abb_rapid, kuka_krl, fanuc_ls "
                    "or motoman_inform.")


def _split(items, max_moves, welds=None):
    """(path, move) items in parts of at most `max_moves` (0: one part); a weld
    (its start move to its end move, touching welds together) is never cut.

    Raises
    ------
    PostError
        A weld of more moves than `max_moves`.
    """
    if not max_moves:
        return [items]
    units = []
    for item in items:
        if item[1].weld is not None and units:
            units[-1].append(item)
        else:
            units.append([item])
    parts, part = [], []
    for unit in units:
        if len(unit) > max_moves:
            run = welds[id(unit[0][1])].run
            raise PostError(f"Weld {run.name!r} ({run.label}) has {len(unit)} moves, more than "
                            f"max_moves={max_moves}; raise max_moves so the arc is not cut.")
        if part and len(part) + len(unit) > max_moves:
            parts.append(part)
            part = []
        part += unit
    return parts + [part] if part else [[]]


def _part_names(name, count, names):
    """The function (and file) name of each part: `name` for one part, else
    ``name_1``, ``name_2``, ... (the name cut to fit :data:`MAX_NAME`)."""
    if count == 1:
        return [name]
    width = len(str(count)) + 1
    return [names.add(f"{name[:MAX_NAME - width]}_{k}", "prog") for k in range(1, count + 1)]


def _file_text(function, part, k, count, context):
    """The text of one file: ``def function(): ... end`` and the call."""
    program, settings, frames, targets, texts, joints, welds = context
    tool = program.tool
    body = _header(program, settings, k, count)
    body += ["", f"set_tcp({_pose(tool.T_f_t)})", _payload_line(tool, settings)]
    body += ["", "# Work frames: the calibration frame {B} in the robot base frame"]
    for key in dict.fromkeys(move.frame for _, move in part):
        frame = program.frames[key]
        source = comment_text(frame.source)
        body.append(f"# {comment_text(key)}" + (f" ({source})" if source else ""))
        body.append(f"{frames[key]} = {_pose(frame.T_r_b)}")
    body += ["", "# Targets, each in its work frame"]
    declared = set()
    for _, move in part:
        if id(move) in joints:
            continue
        for target in (move.via, move.target):
            if target is not None and target.name not in declared:
                declared.add(target.name)
                body.append(f"{targets[target.name][1]} = {texts[target.name]}")
    path = comment = None
    skip = 0
    for index, (move_path, move) in enumerate(part):
        if skip:
            skip -= 1
            continue
        if move_path is not path:
            path, comment = move_path, None
            cont = " (continued)" if index == 0 and move is not move_path.moves[0] else ""
            body += ["", f"# Path: {common.path_label(path)}{cont}"]
        text = comment_text(move.comment)
        if text and text != comment:
            body.append(f"# {text}")
        comment = text
        last_of_part = k < count and index == len(part) - 1
        body.append(_move(move, targets, frames, settings, joints.get(id(move)),
                          stop=last_of_part))
        block = welds.get(id(move))
        while block is not None:        # a weld, and the next if it strikes where this ends
            body += block.lines(frames[move.frame], targets, frames, settings)
            skip += block.run.end - block.run.start
            comment = None
            block = welds.get(id(block.path.moves[block.run.end]))
    lines = [f"def {function}():"]
    lines += [INDENT + (line or "#") for line in body]
    lines.append("end")
    if settings.call:
        lines.append(f"{function}()")
    return "\n".join(lines) + "\n"


# --- names -------------------------------------------------------------------

def is_name(text):
    """Tell whether ``text`` is a URScript name this post may declare.

    Parameters
    ----------
    text : str

    Returns
    -------
    bool
        True for 1 to 32 characters ``[A-Za-z][A-Za-z0-9_]*`` that are not
        a keyword or a built-in this post avoids.
    """
    return common.is_identifier(text, MAX_NAME, RESERVED_WORDS)


def _program_name(program, requested, names):
    """The function name: ``options["program_name"]`` or the program's."""
    if requested is None:
        return names.add(program.name, "prog")
    if not isinstance(requested, str) or not is_name(requested):
        raise PostError(
            f"Program name {requested!r} is not a valid URScript name (a letter, then up "
            "to 31 letters, digits or '_', not a keyword or built-in); choose another "
            "program_name.")
    return names.add(requested, "prog")


# --- options -----------------------------------------------------------------

def _number_option(options, key, default):
    """A finite number > 0 that stays > 0 at the 6 decimals it is written with."""
    number = common.positive_number(options, key, default)
    if float(_compact(number)) <= 0:
        raise PostError(f"{key} is {number!r}; it must be at least 0.000001.")
    return number


# --- values ------------------------------------------------------------------

def _pose(T):
    """``p[x, y, z, rx, ry, rz]`` of a 4x4 transform in mm: metres and a
    rotation vector in radians, 7 decimals."""
    return _poses([T])[0]


def _poses(transforms):
    """:func:`_pose` of many transforms at once (list of str)."""
    if not len(transforms):
        return []
    T = np.asarray(transforms, dtype=float)
    values = np.concatenate([T[:, :3, 3] / 1000.0, rotations.rotvec_from_matrix(T[:, :3, :3])],
                            axis=1)
    return ["p[" + ", ".join([fixed(v, DECIMALS) for v in row]) + "]" for row in values.tolist()]


def _cog(cog_mm):
    """Centre of gravity ``[x, y, z]`` in metres."""
    return "[" + ", ".join(_compact(v / 1000.0) for v in np.asarray(cog_mm, float)) + "]"


def _compact(value):
    """Shortest text of a value to 6 decimals: 1.2, 0.0125, 0."""
    return common.compact(value, 6)


# --- program text ------------------------------------------------------------

def _header(program, settings, k=1, count=1):
    """The comment lines at the top of the function."""
    source, robot = common.source_and_robot(program)
    lines = [
        f"Generated by CadRobot (post-processor {NAME}) from {source}.",
        f"Robot: {robot}.",
        *textwrap.wrap(common.other_maker_note(program.robot, NAME, "Universal Robots"), 70),
        "Units: m, rad, s. Poses p[x, y, z, rx, ry, rz]: position in m and a",
        "rotation vector (axis times angle) in rad.",
        "Targets are in their work frame; pose_trans(frame, target) is the",
        "TCP pose in the robot base frame.",
    ]
    if settings.joint_targets:
        lines += ["movej([q1, ..., q6]) goes to the joints CadRobot solved and checked",
                  "(rad); movej(pose), for a target without solved joints, lets the",
                  "controller choose the inverse kinematics solution nearest its",
                  "current joints: check the arm configuration at reduced speed."]
    else:
        lines += ["movej(pose) lets the controller choose the inverse kinematics",
                  "solution nearest its current joints (joint_targets=false): check",
                  "the arm configuration of the first move at reduced speed."]
    lines += ["movej: v rad/s, a rad/s^2; movel, movec: v m/s, a m/s^2;",
              "r = blend radius in m (0 = stop), never larger than the zone."]
    lines += _weld_header(program, settings.arc)
    if count > 1:
        lines += [f"Part {k} of {count}: run the parts in order; the robot stops at the",
                  f"end of each part (max_moves={settings.max_moves})."]
    return ["# " + line for line in lines]


def _payload_line(tool, settings):
    """``set_payload(m, cog)`` or ``set_target_payload(m, cog)`` (kg, m)."""
    return f"{settings.payload_function}({_compact(tool.mass_kg)}, {_cog(tool.cog_mm)})"


def _joint_list(program, move):
    """``[q1, ..., q6]`` in radians of a move's solved joints (controller convention)."""
    q = np.radians(common.controller_joints_deg(program, move.target))
    return "[" + ", ".join(fixed(v, DECIMALS) for v in q) + "]"


def blend_text(zone_mm):
    """The blend radius in metres, rounded down to 1e-6 m: never more than the zone.

    Parameters
    ----------
    zone_mm : float
        >= 0.

    Returns
    -------
    str
        Shortest text, e.g. ``0.0003`` for 0.3 mm, ``0`` for 0.
    """
    return _compact(common.floor_decimals(zone_mm, 3) / 1000.0)


def _move(move, targets, frames, settings, joints=None, stop=False):
    """One movej/movel/movec line (without indentation)."""
    frame = frames[move.frame]
    to = joints or f"pose_trans({frame}, {targets[move.target.name][1]})"
    blend = "0" if stop else blend_text(move.zone_mm)
    if move.kind == ir.JOINT:
        return (f"movej({to}, a={_compact(settings.joint_accel)}, "
                f"v={_compact(settings.joint_speed)}, r={blend})")
    speed = _compact(move.speed_mm_s / 1000.0)
    accel = _compact(settings.linear_accel)
    if move.kind == ir.LINEAR:
        return f"movel({to}, a={accel}, v={speed}, r={blend})"
    via = f"pose_trans({frame}, {targets[move.via.name][1]})"
    return f"movec({via}, {to}, a={accel}, v={speed}, r={blend}, mode=0)"


# --- welds -------------------------------------------------------------------

def woven_points(seam_poses, weave, travel_speed_mm_s, speeds_mm_s=None):
    """The points a woven weld's motion goes through, and when it reaches them.

    Parameters
    ----------
    seam_poses : ndarray, shape (K, 4, 4)
        The seam: the run's start target, then each welded move's target, in
        the work frame {B}, mm (at least 2, distinct positions).
    weave : welding.Weave or None
    travel_speed_mm_s : float
        Scheduled travel speed along the seam (it sets the cycle of a weave
        given as length per cycle).
    speeds_mm_s : array_like, shape (K - 1,), optional
        Speed along each segment of the seam (a corner slow-down is slower
        than the travel speed); default the travel speed on every segment.

    Returns
    -------
    times_s : ndarray, shape (N,)
        Arc time at each point, increasing, from 0 (the seam start) to the
        arc time of the whole seam.
    poses : ndarray, shape (N, 4, 4)
        The TCP at each time: the seam point (the travel at each segment's
        speed along the polyline) plus the weave's offset (core.weave.woven_offsets,
        in the weave frame of the segment: X travel, Z the tool axis), the
        orientation interpolated along the segment (slerp).  The points are
        the weave's vertices and dwell ends (8 per cycle for a circle), the
        ends of the ramps, and the seam's corners.
    """
    seam_poses = np.asarray(seam_poses, dtype=float)
    positions = seam_poses[:, :3, 3]
    lengths = np.linalg.norm(np.diff(positions, axis=0), axis=1)
    speeds = np.broadcast_to(travel_speed_mm_s if speeds_mm_s is None else
                             np.asarray(speeds_mm_s, dtype=float), lengths.shape)
    corners = np.concatenate([[0.0], np.cumsum(lengths / speeds)])
    duration = corners[-1]
    times = [corners]
    if weave is not None:
        cycle = weave.cycle_time_s(travel_speed_mm_s)
        ramp = min(weave_geometry.ramp_time_s(weave, travel_speed_mm_s), duration / 2)
        starts = np.arange(0.0, duration, cycle)
        times += [(starts[:, None] + _cycle_knots_s(weave, travel_speed_mm_s)).ravel(),
                  [ramp, duration - ramp]]
    t = np.unique(np.clip(np.concatenate(times), 0.0, duration))
    t = t[np.concatenate([[True], np.diff(t) > TIME_TOLERANCE_S])]
    t[-1] = duration
    segment = np.clip(np.searchsorted(corners, t, side="right") - 1, 0, len(lengths) - 1)
    fraction = (t - corners[segment]) / (corners[segment + 1] - corners[segment])
    poses = np.repeat(np.eye(4)[None], len(t), axis=0)
    start, end = positions[segment], positions[segment + 1]
    poses[:, :3, 3] = start + fraction[:, None] * (end - start)
    quaternions = rotations.quaternion_sequence_from_matrices(seam_poses[:, :3, :3])
    for i, (k, f) in enumerate(zip(segment, fraction)):
        q = rotations.quaternion_slerp(quaternions[k], quaternions[k + 1], f)
        poses[i, :3, :3] = rotations.matrix_from_quaternion(q)
    if weave is not None:
        X, Y, Z = weave_geometry.frame_axes(end - start, poses[:, :3, 2])
        offsets = weave_geometry.woven_offsets(t, duration, weave, travel_speed_mm_s)
        poses[:, :3, 3] += offsets[:, :1] * X + offsets[:, 1:2] * Y + offsets[:, 2:] * Z
    return t, poses


def _cycle_knots_s(weave, travel_speed_mm_s):
    """Times within one weave cycle where the weave's motion turns: arrival at
    and departure from each vertex (after its dwell), or 8 points of a circle."""
    cycle = weave.cycle_time_s(travel_speed_mm_s)
    if weave.pattern == "circle":
        return np.arange(CIRCLE_POINTS) * cycle / CIRCLE_POINTS
    points, dwell = weave_geometry.vertices(weave)
    legs = np.linalg.norm(np.roll(points, -1, axis=0) - points, axis=1)
    leg_time = legs / legs.sum() * weave_geometry.moving_time_s(weave, travel_speed_mm_s)
    return np.concatenate([[0.0], np.cumsum(np.ravel(np.column_stack([dwell, leg_time])))])


@dataclass
class _WeldBlock:
    """A weld run as URScript: arc on, the welded motion, crater, arc off."""

    run: object
    path: object
    times_s: np.ndarray
    poses: np.ndarray
    io: _ArcIO

    def lines(self, frame, targets, frames, settings):
        """Body lines after the run's start move (the robot is at the seam start)."""
        return (self._arc_on() + self._motion(frame, targets, frames, settings)
                + self._arc_off())

    def _set_points(self, wire_feed_m_min, voltage_v, what):
        io, out = self.io, []
        for pin, value, scale, unit, name in (
                (io.wire_feed_output, wire_feed_m_min, io.wire_feed_full_scale_m_min,
                 "m/min", "wire feed"),
                (io.voltage_output, voltage_v, io.voltage_full_scale_v, "V", "voltage")):
            if pin is None:
                continue
            level = value / scale
            if level > 1.0:
                key = "wire_feed_full_scale_m_min" if unit == "m/min" else "voltage_full_scale_v"
                raise PostError(f"Weld {self.run.name!r} ({self.run.label}): {what} {name} "
                                f"{compact(value, 2)} {unit} is beyond the analogue full "
                                f"scale {compact(scale, 2)} {unit}; raise {key}.")
            out.append(f"set_standard_analog_out({pin}, {fixed(level, 4)})  # {what} {name} "
                       f"{compact(value, 2)} {unit} of {compact(scale, 2)}")
        return out

    def _arc_on(self):
        s, io = self.run.schedule, self.io
        out = [f"# Weld {self.run.name} ({comment_text(self.run.label)}): arc on at the seam "
               "start"]
        out += self._set_points(s.wire_feed_m_min, s.voltage_v, "weld")
        out.append(f"set_standard_digital_out({io.arc_output}, True)  # arc on")
        out.append(f"sleep({compact(s.gas_preflow_s, 3)})  # gas pre-flow and ignition")
        if io.arc_ok_input is not None:
            steps = int(np.ceil(io.arc_ok_timeout_s / ARC_OK_POLL_S))
            out += ["arc_wait = 0",
                    f"while not get_standard_digital_in({io.arc_ok_input}):",
                    f"{INDENT}sleep({ARC_OK_POLL_S})",
                    f"{INDENT}arc_wait = arc_wait + 1",
                    f"{INDENT}if arc_wait > {steps}:",
                    f"{INDENT * 2}set_standard_digital_out({io.arc_output}, False)",
                    f'{INDENT * 2}textmsg("Weld {self.run.name}: no arc after '
                    f'{compact(io.arc_ok_timeout_s, 3)} s")',
                    f"{INDENT * 2}halt",
                    f"{INDENT}end",
                    "end"]
        return out

    def _motion(self, frame, targets, frames, settings):
        """movep through the woven points (or movel along the seam without a weave)."""
        run = self.run
        accel = _compact(settings.linear_accel)
        if run.weave is None:
            return [_move(m, targets, frames, settings)
                    for m in self.path.moves[run.start + 1:run.end + 1]]
        times, positions = self.times_s, self.poses[:, :3, 3]
        lengths = np.linalg.norm(np.diff(positions, axis=0), axis=1)
        speeds = lengths / np.diff(times)
        blends = WOVEN_BLEND_SHARE * np.minimum(lengths, np.append(lengths[1:], 0.0))
        out = [f"# woven: {run.weave.pattern} {compact(run.weave.width_mm, 2)} mm at "
               f"{compact(run.weave.frequency(run.schedule.travel_speed_mm_s), 3)} Hz, "
               f"{len(lengths)} movep, each at its own speed so the seam is covered at the "
               f"moves' speeds ({compact(run.schedule.travel_speed_mm_s, 2)} mm/s travel)"]
        for pose, speed, blend in zip(_poses(self.poses[1:]), speeds, blends):
            out.append(f"movep(pose_trans({frame}, {pose}), a={accel}, "
                       f"v={_compact(speed / 1000.0)}, r={blend_text(blend)})")
        return out

    def _arc_off(self):
        s, io = self.run.schedule, self.io
        out = [f"# Weld {self.run.name}: crater fill at the seam end, arc off"]
        out += self._set_points(s.crater_wire_feed_m_min, s.crater_voltage_v, "crater")
        out.append(f"sleep({compact(s.crater_fill_s, 3)})  # crater fill")
        out.append(f"set_standard_digital_out({io.arc_output}, False)  # arc off "
                   f"(burn-back {compact(s.burnback_s, 3)} s: the power source's)")
        out.append(f"sleep({compact(s.gas_postflow_s, 3)})  # gas post-flow")
        return out


def _weld_block(path, run, settings):
    """The :class:`_WeldBlock` of a run, its woven points computed.

    Raises
    ------
    PostError
        A woven run with a circular move (the weave is written along lines).
    """
    moves = path.moves[run.start:run.end + 1]
    if run.weave is not None and any(m.kind == ir.CIRCULAR for m in moves[1:]):
        raise PostError(f"Weld {run.name!r} ({run.label}) weaves along a circular move: this "
                        "post writes the weave along straight moves; generate the path as "
                        "lines (a polyline) or weld it without a weave.")
    positions = np.array([m.target.T_b_t for m in moves], dtype=float)[:, :3, 3]
    still = np.flatnonzero(np.linalg.norm(np.diff(positions, axis=0), axis=1) < MIN_TRAVEL_MM)
    if run.weave is not None and len(still):
        move = moves[still[0] + 1]
        raise PostError(f"Weld {run.name!r} ({run.label}) turns in place while weaving (target "
                        f"'{move.target.name}'): the weave needs travel; stop the weld at the "
                        "turn (a corner stop) or weld it without a weave.")
    frames = {m.frame for m in moves}
    if len(frames) > 1:
        raise PostError(f"Weld {run.name!r} ({run.label}) changes work frame: keep a weld in "
                        "one work frame.")
    seam = np.array([m.target.T_b_t for m in moves], dtype=float)
    times, poses = woven_points(seam, run.weave, run.schedule.travel_speed_mm_s,
                                [m.speed_mm_s for m in moves[1:]])
    return _WeldBlock(run, path, times, poses, settings.arc)


def _weld_header(program, io):
    """Header lines of a program that welds: how the arc is switched and set."""
    if not program.weld_runs():
        return []
    set_points = []
    if io.wire_feed_output is not None:
        set_points.append(f"wire feed on analogue out {io.wire_feed_output} "
                          f"(1.0 = {compact(io.wire_feed_full_scale_m_min, 2)} m/min)")
    if io.voltage_output is not None:
        set_points.append(f"voltage on analogue out {io.voltage_output} "
                          f"(1.0 = {compact(io.voltage_full_scale_v, 2)} V)")
    text = (f"Welding: URScript has no arc instructions. The arc is switched by standard "
            f"digital output {io.arc_output} (True = arc on)"
            + (" and set by " + " and ".join(set_points) if set_points else "")
            + ", relative levels 0..1 of the full scale. ")
    if io.arc_ok_input is not None:
        text += (f"After arc on the program waits for standard digital input "
                 f"{io.arc_ok_input} (arc ok) up to {compact(io.arc_ok_timeout_s, 3)} s, "
                 "else switches the arc off and halts. ")
    text += ("Gas pre-flow, crater fill and post-flow are sleeps. The weave is written as "
             "motion: movep through the woven points, each at the speed that covers the "
             "seam at the scheduled travel speed.")
    lines = textwrap.wrap(text, 70)
    for _, run in program.weld_runs():
        lines += textwrap.wrap(f"Weld {run.name} ({comment_text(run.label)}): "
                               + "; ".join(common.schedule_comment_lines(run)) + ".", 70)
    return lines
