"""Universal Robots URScript post-processor: one ``<name>.script`` file.

Layout of the file written by :func:`export`::

    def <name>():
      # header: source, robot, units, conventions
      set_tcp(p[...])             the tool (program.tool), flange -> TCP
      set_payload(m, [cog])
      <frame> = p[...]            one per work frame: {B} in the robot base
      <target> = p[...]           every target, in its work frame
      movej/movel/movec(pose_trans(<frame>, <target>), a=..., v=..., r=...)
    end

Every line but the first and the last is indented and the file ends with
``end``: the form URControl requires of a script sent to its port 30002
("the script must start from a function definition ... all other script
lines must be indented ... the last line of script must be an end keyword",
URScript manual, Connecting to URControl).  Sent there, the function runs.
To use the file elsewhere (a PolyScope Script node, another script) the
function must also be called: the option ``{"call": True}`` adds the line
``<name>()`` after ``end``, which breaks the port-30002 form above.

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
* ``movej(pose, ...)``: the controller solves the inverse kinematics itself
  and takes the solution nearest its current joints; ``v`` and ``a`` are
  the leading joint's speed (rad/s) and acceleration (rad/s^2): a TCP speed
  cannot be given to movej (options ``joint_speed_rad_s``, default 1.05,
  and ``joint_accel_rad_s2``, default 1.4, URScript's own defaults).
* ``movel`` / ``movec``: ``v`` = the move's speed in m/s, ``a`` = option
  ``linear_accel_m_s2`` (default 1.2, URScript's default).  ``movec`` uses
  ``mode=0`` (orientation interpolated from the start to the end pose; the
  via point's orientation is not used), as CadRobot interpolates it.
* Blend radius ``r`` = the move's zone in metres, 0 = stop at the target.
  The controller refuses a blend radius that overlaps the next blend or is
  longer than the move; CadRobot does not check that here.

Not verified on a controller: there is no independent URScript parser
here; the tests check the layout, the numbers and the conventions.

Pure Python/numpy: never imports FreeCAD.
"""

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


def export(program, options=None):
    """Write a program as one URScript file.

    Parameters
    ----------
    program : CadRobotWB.core.program.Program
        Targets in their work frames {B}, mm.
    options : dict, optional
        ``"program_name"`` : str — name of the function (and file) instead
        of ``program.name``; must be a valid URScript name.
        ``"call"`` : bool — add ``<name>()`` after ``end`` (default False;
        see the module docstring).
        ``"linear_accel_m_s2"`` (default 1.2), ``"joint_accel_rad_s2"``
        (default 1.4), ``"joint_speed_rad_s"`` (default 1.05).
        Other keys are ignored.

    Returns
    -------
    list of (str, str)
        ``[(f"{name}.script", text)]``.

    Raises
    ------
    PostError
        The program has a move, speed, zone, name or option URScript cannot
        express.
    """
    options = options or {}
    linear_accel = _number_option(options, "linear_accel_m_s2", 1.2)
    joint_accel = _number_option(options, "joint_accel_rad_s2", 1.4)
    joint_speed = _number_option(options, "joint_speed_rad_s", 1.05)

    names = common.Namer(RESERVED_WORDS, MAX_NAME, separator="_")
    name = _program_name(program, options.get("program_name"), names)
    moves = program.moves()
    for move in moves:
        common.check_move(move, program, _INSTRUCTIONS, "URScript",
                          speed_decimals=6, speed_unit_mm_s=1000.0)
    common.check_tool_mass(program.tool)
    used_frames = list(dict.fromkeys(move.frame for move in moves))
    frames = {key: names.add(key, "frame") for key in used_frames}
    targets = common.target_names(program, names, "t")

    body = _header(program)
    body += ["", f"set_tcp({_pose(program.tool.T_f_t)})",
             f"set_payload({_compact(program.tool.mass_kg)}, {_cog(program.tool.cog_mm)})"]
    body += ["", "# Work frames: the calibration frame {B} in the robot base frame"]
    for key in used_frames:
        frame = program.frames[key]
        source = comment_text(frame.source)
        body.append(f"# {comment_text(key)}" + (f" ({source})" if source else ""))
        body.append(f"{frames[key]} = {_pose(frame.T_r_b)}")
    body += ["", "# Targets, each in its work frame"]
    for target, ur_name in targets.values():
        body.append(f"{ur_name} = {_pose(target.T_b_t)}")

    for path in program.paths:
        body += ["", f"# Path: {comment_text(path.label or path.name)}"]
        comment = None
        for move in path.moves:
            text = comment_text(move.comment)
            if text and text != comment:
                body.append(f"# {text}")
            comment = text
            body.append(_move(move, targets, frames, linear_accel, joint_accel, joint_speed))

    lines = [f"def {name}():"]
    lines += [INDENT + (line or "#") for line in body]
    lines.append("end")
    if options.get("call"):
        lines.append(f"{name}()")
    return [(common.file_name(name, ".script"), "\n".join(lines) + "\n")]


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
    """A positive numeric option."""
    value = options.get(key, default)
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise PostError(f"Option {key} must be a number, got {value!r}.") from None
    if not np.isfinite(number) or float(_compact(number)) <= 0:
        raise PostError(f"Option {key} is {value!r}; it must be greater than 0.")
    return number


# --- values ------------------------------------------------------------------

def _pose(T):
    """``p[x, y, z, rx, ry, rz]`` of a 4x4 transform in mm: metres and a
    rotation vector in radians, 7 decimals."""
    T = np.asarray(T, dtype=float)
    values = list(T[:3, 3] / 1000.0) + list(rotations.rotvec_from_matrix(T[:3, :3]))
    return "p[" + ", ".join(fixed(v, DECIMALS) for v in values) + "]"


def _cog(cog_mm):
    """Centre of gravity ``[x, y, z]`` in metres."""
    return "[" + ", ".join(_compact(v / 1000.0) for v in np.asarray(cog_mm, float)) + "]"


def _compact(value):
    """Shortest text of a value to 6 decimals: 1.2, 0.0125, 0."""
    return common.compact(value, 6)


# --- program text ------------------------------------------------------------

def _header(program):
    """The comment lines at the top of the function."""
    source, robot = common.source_and_robot(program)
    return ["# " + line for line in (
        f"Generated by CadRobot (post-processor {NAME}) from {source}.",
        f"Robot: {robot}.",
        "Units: m, rad, s. Poses p[x, y, z, rx, ry, rz]: position in m and a",
        "rotation vector (axis times angle) in rad.",
        "Targets are in their work frame; pose_trans(frame, target) is the",
        "TCP pose in the robot base frame.",
        "movej(pose) lets the controller choose the inverse kinematics",
        "solution nearest its current joints: check the arm configuration",
        "of the first move at reduced speed. movej: v rad/s, a rad/s^2;",
        "movel, movec: v m/s, a m/s^2; r = blend radius in m (0 = stop).",
    )]


def _move(move, targets, frames, linear_accel, joint_accel, joint_speed):
    """One movej/movel/movec line (without indentation)."""
    frame = frames[move.frame]
    to = f"pose_trans({frame}, {targets[move.target.name][1]})"
    blend = _compact(move.zone_mm / 1000.0)
    if move.kind == ir.JOINT:
        return (f"movej({to}, a={_compact(joint_accel)}, v={_compact(joint_speed)}, "
                f"r={blend})")
    speed = _compact(move.speed_mm_s / 1000.0)
    if move.kind == ir.LINEAR:
        return f"movel({to}, a={_compact(linear_accel)}, v={speed}, r={blend})"
    via = f"pose_trans({frame}, {targets[move.via.name][1]})"
    return f"movec({via}, {to}, a={_compact(linear_accel)}, v={speed}, r={blend}, mode=0)"
