"""ABB RAPID post-processor: one IRC5 program module (``.mod``).

Layout of the module written by :func:`export`::

    MODULE <name>
      ! header: source, robot, units, frame conventions
      PERS tooldata ...        the tool (program.tool)
      PERS wobjdata ...        one per work frame, uframe = {B} in {R}
      CONST speeddata ...      speeds that are not ABB predefined (v5 ... v7000)
      CONST zonedata ...       zones that are not ABB predefined (z0 ... z200)
      CONST robtarget ...      every target, in its work frame, mm
      PROC main()              ConfJ/ConfL, one call per path
      PROC <path>()            the moves of one path
    ENDMODULE

Robot configurations: when every target carries the joints the robot takes
there (``Target.joints_deg``, filled by
``robots.configuration.solve_program``), each robtarget's confdata is
computed from them (``robots.configuration.abb_confdata``: quadrants of axes
1, 4 and 6, and cfx) and the module monitors configurations
(``ConfJ \\On; ConfL \\On;``): the controller then takes exactly the arm
configuration CadRobot checked, or stops.  When some target has no joints (a
program built without a robot model, or a target no configuration reaches)
the module writes ``ConfJ \\Off; ConfL \\Off;`` and says so in its header;
targets with joints still get their confdata, the others ``[0,0,0,0]``.

Speeds and zones use ABB's predefined data when they match one exactly
(``v10`` = ``[10,500,5000,1000]``, ``z10`` = 10 mm, ``z0`` = 0.3 mm) and a
module constant otherwise, built the way ABB builds its own. Declaring a
second global ``v10`` would clash with the predefined one.

Quaternion signs follow :func:`~CadRobotWB.core.rotations.choose_quaternion_sign`:
each robtarget's is continuous with the robtarget declared before it, the
first one's and those of tooldata and wobjdata are canonical.

The output is deterministic (no dates, no sign that rounding noise decides:
the same on every FreeCAD and numpy version) and is checked in the tests by the
independent ``rapidchecker`` grammar and format checker.

Pure Python/numpy: never imports FreeCAD.
"""

import numpy as np

from ..core import program as ir
from ..core import rotations
from ..errors import PostError
from ..robots import configuration
from . import common
from .common import comment_text, compact, fixed

NAME = "abb_rapid"
DESCRIPTION = "ABB RAPID program module for IRC5 controllers (.mod)"
FILE_EXTENSIONS = (".mod",)

INDENT = "  "
MAX_IDENTIFIER = 32

#: RAPID reserved words (RAPID kernel reference), upper case.
RESERVED_WORDS = frozenset("""
    ALIAS AND BACKWARD CASE CONNECT CONST DEFAULT DIV DO ELSE ELSEIF ENDFOR
    ENDFUNC ENDIF ENDMODULE ENDPROC ENDRECORD ENDTEST ENDTRAP ENDWHILE ERROR
    EXIT FALSE FOR FROM FUNC GOTO IF INOUT LOCAL MOD MODULE NOSTEPIN NOT
    NOVIEW OR PERS PROC RAISE READONLY RECORD RETRY RETURN STEP SYSMODULE
    TASK TEST THEN TO TRAP TRUE TRYNEXT UNDO VAR VIEWONLY WHILE WITH XOR
""".split())

#: ABB predefined speeddata: vN = [N, 500, 5000, 1000].
PREDEFINED_SPEEDS_MM_S = (5, 10, 20, 30, 40, 50, 60, 80, 100, 150, 200, 300,
                          400, 500, 600, 800, 1000, 1500, 2000, 2500, 3000,
                          4000, 5000, 6000, 7000)

#: ABB predefined zonedata by TCP zone radius (mm). z0 is a 0.3 mm zone.
PREDEFINED_ZONES_MM = {0.3: "z0", 1: "z1", 5: "z5", 10: "z10", 15: "z15",
                       20: "z20", 30: "z30", 40: "z40", 50: "z50", 60: "z60",
                       80: "z80", 100: "z100", 150: "z150", 200: "z200"}

#: Names our module must not declare: predefined data and instructions used.
_PREDEFINED_NAMES = ({"main", "fine", "vmax", "tool0", "wobj0", "load0",
                      "MoveJ", "MoveL", "MoveC", "MoveAbsJ", "ConfJ", "ConfL",
                      "Off", "On", "WObj", "Corr", "CorrCon", "CorrDiscon", "CorrWrite",
                      "CONNECT", "ITimer", "IDelete", "cdSensor", "corrSensor", "irSensor",
                      "tSensorCorrection"}
                     | {f"v{v}" for v in PREDEFINED_SPEEDS_MM_S}
                     | set(PREDEFINED_ZONES_MM.values()))

_MOVE_INSTRUCTIONS = {ir.JOINT: "MoveJ", ir.LINEAR: "MoveL",
                      ir.CIRCULAR: "MoveC"}

#: Speed of the orientation, external linear and rotational axes in every
#: speeddata we declare (deg/s, mm/s, deg/s), as in ABB's predefined data.
_V_ORI_LEAX_REAX = "500,5000,1000"

_UNUSED_EXTERNAL_AXES = "[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]"


# Moves along the seam take the sensor's correction; approach, entry and retract do not.
_CORRECTED_ROLES = (ir.ROLE_PATH, ir.ROLE_RISK, ir.ROLE_REORIENT)


def export(program, options=None):
    """Write a program as one RAPID module.

    Parameters
    ----------
    program : CadRobotWB.core.program.Program
        Targets in their work frames {B}, mm.
    options : dict, optional
        ``"module_name"`` : str — module name instead of ``program.name``
        (must be a valid RAPID identifier).
        ``"path_correction"`` : bool — seam tracking on the controller: the
        moves along each path carry ``\\Corr`` under a correction generator
        (``CorrCon``), and a timed interrupt calls the TRAP
        ``tSensorCorrection`` where the user's sensor writes its offset with
        ``CorrWrite`` (paper 4.1: 5 Hz).
        ``"correction_rate_hz"`` : float — that interrupt's rate (default 5).
        Other keys are ignored.

    Returns
    -------
    list of (str, str)
        ``[(f"{program.name}.mod", text)]``.

    Raises
    ------
    PostError
        The program has a move, speed, tool or frame RAPID cannot express.
    """
    options = options or {}
    # RAPID is case-insensitive; predefined names the module uses are taken too.
    names = common.Namer(RESERVED_WORDS | _PREDEFINED_NAMES, MAX_IDENTIFIER)
    module_name = _module_name(program, options.get("module_name"), names)

    tool_name = names.add(program.tool.name, "tool")
    wobj_names = {key: names.add(key, "wobj") for key in program.frames}
    moves = program.moves()
    for move in moves:
        common.check_move(move, program, _MOVE_INSTRUCTIONS, "ABB RAPID", speed_decimals=4)

    speeds = _speed_names(moves, names)
    zones = _zone_names(moves, names)
    targets = common.target_names(program, names, "p")
    procs = [names.add(path.name, "path") for path in program.paths]
    spec = common.opw_robot_spec(program)
    monitored = spec is not None and all(
        target.joints_deg is not None for target, _ in targets.values())

    lines = [f"MODULE {module_name}"]
    lines += _header(program, monitored)
    lines.append("")
    lines.append(INDENT + f"PERS tooldata {tool_name} := "
                 f"{_tooldata(program.tool)};")
    for key in program.frames:
        lines.append(INDENT + f"PERS wobjdata {wobj_names[key]} := "
                     f"{_wobjdata(program.frames[key])};")
    declarations = [text for _, text in (*speeds.values(), *zones.values())
                    if text]
    if declarations:
        lines.append("")
    lines += [INDENT + text for text in declarations]
    if targets:
        lines.append("")
    # Each robtarget's quaternion sign continues from the one declared before.
    quaternions = rotations.quaternion_sequence_from_matrices(
        [target.T_b_t[:3, :3] for target, _ in targets.values()])
    for (target, name), q in zip(targets.values(), quaternions):
        lines.append(INDENT + f"CONST robtarget {name} := "
                     f"{_robtarget(target, q, spec)};")

    correction = bool(options.get("path_correction"))
    if correction:
        rate_hz = float(options.get("correction_rate_hz", 5.0))
        if not rate_hz > 0:
            raise PostError("correction_rate_hz must be > 0, got %r." % rate_hz)
        lines.append("")
        lines += [INDENT + text for text in (
            "! Path correction (seam tracking): the sensor's offset in path",
            "! coordinates, mm (y to the left of the travel, z up).",
            "VAR corrdescr cdSensor;",
            "VAR pos corrSensor := [0,0,0];",
            "VAR intnum irSensor;")]

    lines.append("")
    lines.append(INDENT + "PROC main()")
    state = "On" if monitored else "Off"
    lines.append(2 * INDENT + f"ConfJ \\{state};")
    lines.append(2 * INDENT + f"ConfL \\{state};")
    for proc in procs:
        lines.append(2 * INDENT + f"{proc};")
    lines.append(INDENT + "ENDPROC")

    for path, proc in zip(program.paths, procs):
        lines.append("")
        lines.append(INDENT + f"PROC {proc}()")
        label = comment_text(path.label or path.name)
        lines.append(2 * INDENT + f"! Path: {label}")
        previous_comment = None
        corrected = False
        for move in path.moves:
            on_seam = correction and move.role in _CORRECTED_ROLES
            if on_seam and not corrected:
                lines += [2 * INDENT + text for text in (
                    "CorrCon cdSensor;", "CONNECT irSensor WITH tSensorCorrection;",
                    f"ITimer {compact(1.0 / rate_hz)}, irSensor;")]
            elif corrected and not on_seam:
                lines += [2 * INDENT + text for text in ("IDelete irSensor;", "CorrDiscon cdSensor;")]
            corrected = on_seam
            comment = comment_text(move.comment)
            if comment and comment != previous_comment:
                lines.append(2 * INDENT + f"! {comment}")
            previous_comment = comment
            lines.append(2 * INDENT + _move_instruction(
                move, targets, speeds, zones, tool_name, wobj_names, on_seam))
        if corrected:
            lines += [2 * INDENT + text for text in ("IDelete irSensor;", "CorrDiscon cdSensor;")]
        lines.append(INDENT + "ENDPROC")

    if correction:
        lines.append("")
        lines += [INDENT + text for text in (
            "TRAP tSensorCorrection",
            "  ! CorrWrite hook: read the seam offset from your sensor into",
            "  ! corrSensor here (serial channel, group inputs, ...), then:",
            "  CorrWrite cdSensor, corrSensor;",
            "ENDTRAP")]

    lines.append("ENDMODULE")
    return [(common.file_name(program.name, ".mod"), "\n".join(lines) + "\n")]


# --- identifiers -------------------------------------------------------------

def is_identifier(text):
    """Tell whether ``text`` is a valid RAPID identifier we may declare.

    Parameters
    ----------
    text : str

    Returns
    -------
    bool
        True for 1 to 32 characters ``[A-Za-z][A-Za-z0-9_]*`` that are not
        a reserved word.
    """
    return common.is_identifier(text, MAX_IDENTIFIER, RESERVED_WORDS)


def _module_name(program, requested, names):
    """The module name: ``options["module_name"]`` or the program name."""
    if requested is None:
        return names.add(program.name, "M")
    if not isinstance(requested, str) or not is_identifier(requested):
        raise PostError(
            f"Module name {requested!r} is not a valid RAPID identifier "
            "(a letter, then up to 31 letters, digits or '_', not a "
            "reserved word); choose another module_name.")
    if names.is_taken(requested):
        raise PostError(f"Module name {requested!r} is a predefined RAPID "
                        "name; choose another module_name.")
    return names.add(requested, "M")


def _speed_names(moves, names):
    """Map each distinct speed (text, mm/s) to (name, declaration or "")."""
    out = {}
    for move in moves:
        value = compact(move.speed_mm_s)
        if value in out:
            continue
        if float(value) in PREDEFINED_SPEEDS_MM_S:
            out[value] = (f"v{value}", "")
        else:
            name = names.add("v" + value.replace(".", "_"), "v")
            out[value] = (name, f"CONST speeddata {name} := "
                                f"[{value},{_V_ORI_LEAX_REAX}];")
    return out


def _zone_names(moves, names):
    """Map each distinct zone (text, mm) to (name, declaration or "")."""
    out = {}
    for move in moves:
        value = compact(move.zone_mm)
        if value in out:
            continue
        radius = float(value)
        if radius == 0.0:
            out[value] = ("fine", "")
        elif radius in PREDEFINED_ZONES_MM:
            out[value] = (PREDEFINED_ZONES_MM[radius], "")
        else:
            name = names.add("z" + value.replace(".", "_"), "z")
            out[value] = (name, f"CONST zonedata {name} := "
                                f"{_zonedata(radius)};")
    return out


# --- data values -------------------------------------------------------------

def _tooldata(tool):
    """tooldata value: robot-held tool, TCP pose in the flange frame."""
    common.check_tool_mass(tool)
    pose = _pose(tool.T_f_t)
    cog = ",".join(compact(c) for c in np.asarray(tool.cog_mm, float))
    return (f"[TRUE,{pose},[{compact(tool.mass_kg)},[{cog}],"
            "[1,0,0,0],0,0,0]]")


def _wobjdata(frame):
    """wobjdata value: fixed user frame = {B} in {R}, identity object frame."""
    return f'[FALSE,TRUE,"",{_pose(frame.T_r_b)},[[0,0,0],[1,0,0,0]]]'


def _zonedata(radius_mm):
    """zonedata value built like ABB's predefined zones.

    ABB's zN uses pzone_ori = pzone_eax = zone_leax = 1.5 N (mm) and
    zone_ori = zone_reax = 0.15 N (degrees).
    """
    big = compact(1.5 * radius_mm)
    angle = compact(0.15 * radius_mm)
    return (f"[FALSE,{compact(radius_mm)},{big},{big},{angle},{big},"
            f"{angle}]")


def _robtarget(target, q, spec):
    """robtarget value: position, orientation q (w, x, y, z), confdata, no
    external axes.

    confdata comes from the target's joints when it has them (and the robot
    is known), else ``[0,0,0,0]``.
    """
    q = _unit(q)
    conf = "0,0,0,0"
    if spec is not None and target.joints_deg is not None:
        conf = ",".join(str(v) for v in
                        configuration.abb_confdata(target.joints_deg, spec))
    return (f"[{_position(target.position_mm)},{_quaternion(q)},"
            f"[{conf}],{_UNUSED_EXTERNAL_AXES}]")


def _pose(T):
    """``[[x,y,z],[q1,q2,q3,q4]]`` of a 4x4 transform."""
    q = _unit(rotations.quaternion_from_matrix(np.asarray(T)[:3, :3]))
    return f"[{_position(np.asarray(T)[:3, 3])},{_quaternion(q)}]"


def _unit(q):
    q = np.asarray(q, dtype=float)
    return q / np.linalg.norm(q)


def _position(p):
    return "[" + ",".join(fixed(v, 3) for v in p) + "]"


def _quaternion(q):
    return "[" + ",".join(fixed(v, 6) for v in q) + "]"


# --- instructions ------------------------------------------------------------

def _move_instruction(move, targets, speeds, zones, tool_name, wobj_names, corrected=False):
    """One MoveJ/MoveL/MoveC instruction line (without indentation); with
    ``\\Corr`` when the move takes the sensor's path correction."""
    points = [targets[move.target.name][1]]
    if move.kind == ir.CIRCULAR:
        points.insert(0, targets[move.via.name][1])
    speed = speeds[compact(move.speed_mm_s)][0]
    zone = zones[compact(move.zone_mm)][0]
    corr = " \\Corr" if corrected else ""
    return (f"{_MOVE_INSTRUCTIONS[move.kind]} {', '.join(points)}, {speed}, "
            f"{zone}, {tool_name} \\WObj:={wobj_names[move.frame]}{corr};")


def _header(program, monitored=False):
    """The ``!`` comment lines at the top of the module."""
    source, robot = common.source_and_robot(program)
    lines = [
        f"Generated by CadRobot (post-processor {NAME}) from {source}.",
        f"Robot: {robot}.",
        "Units: mm; orientations are unit quaternions [q1,q2,q3,q4], q1 = w.",
        "Each wobjdata uframe is the calibration frame {B} in the robot base",
        "frame; this assumes the robot's world frame is its base frame.",
    ]
    if monitored:
        lines += [
            "Robtargets are in their work object {B}; their confdata is the",
            "arm configuration CadRobot checked (one per path), so robot",
            "configurations are monitored (ConfJ \\On, ConfL \\On).",
        ]
    else:
        lines += [
            "Robtargets are in their work object {B}; robot configurations are",
            "not monitored (ConfJ \\Off, ConfL \\Off).",
        ]
    return [INDENT + "! " + line for line in lines]
