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

Not verified on a controller: there is no independent URScript parser
here; the tests check the layout, the numbers and the conventions.

Pure Python/numpy: never imports FreeCAD.
"""

import textwrap
from dataclasses import dataclass

import numpy as np

from ..core import program as ir
from ..core import rotations
from ..errors import PostError
from . import common
from .common import comment_text, fixed

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
}


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

    @classmethod
    def from_options(cls, options):
        return cls(common.bool_option(options, "call", True),
                   _number_option(options, "linear_accel_m_s2", 1.2),
                   _number_option(options, "joint_accel_rad_s2", 1.4),
                   _number_option(options, "joint_speed_rad_s", 1.05),
                   common.joint_targets_option(options),
                   common.choice_option(options, "payload_function", "set_payload",
                                        PAYLOAD_FUNCTIONS),
                   common.whole_option(options, "max_moves", DEFAULT_MAX_MOVES, 0, 10 ** 9))


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
        The program has a move, speed, zone, name or option URScript cannot
        express.
    """
    options = options or {}
    settings = _Settings.from_options(options)
    names = common.Namer(RESERVED_WORDS, MAX_NAME, separator="_")
    name = _program_name(program, options.get("program_name"), names)
    moves = program.moves()
    for move in moves:
        common.check_move(move, program, _INSTRUCTIONS, "URScript",
                          speed_decimals=6, speed_unit_mm_s=1000.0)
    common.check_tool_mass(program.tool)
    joints = {id(m): _joint_list(program, m) for m in moves
              if common.is_joint_target_move(m, settings.joint_targets)}
    parts = _split([(path, move) for path in program.paths for move in path.moves],
                   settings.max_moves)
    functions = _part_names(name, len(parts), names)
    used_frames = list(dict.fromkeys(move.frame for move in moves))
    frames = {key: names.add(key, "frame") for key in used_frames}
    targets = common.target_names(program, names, "t")
    texts = dict(zip(targets, _poses([target.T_b_t for target, _ in targets.values()])))
    context = (program, settings, frames, targets, texts, joints)
    return [(common.file_name(function, ".script"),
             _file_text(function, part, k, len(parts), context))
            for k, (function, part) in enumerate(zip(functions, parts), start=1)]


def _split(items, max_moves):
    """(path, move) items in parts of at most `max_moves` (0: one part)."""
    return common.parts(items, max_moves) if max_moves else [items]


def _part_names(name, count, names):
    """The function (and file) name of each part: `name` for one part, else
    ``name_1``, ``name_2``, ... (the name cut to fit :data:`MAX_NAME`)."""
    if count == 1:
        return [name]
    width = len(str(count)) + 1
    return [names.add(f"{name[:MAX_NAME - width]}_{k}", "prog") for k in range(1, count + 1)]


def _file_text(function, part, k, count, context):
    """The text of one file: ``def function(): ... end`` and the call."""
    program, settings, frames, targets, texts, joints = context
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
    for index, (move_path, move) in enumerate(part):
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
