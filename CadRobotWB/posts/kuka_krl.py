"""KUKA KRL post-processor: a ``.src`` program and its ``.dat`` data list.

Files written by :func:`export` (``<name>`` = the program name, which KRL
requires to be the file name too)::

    <name>.src
      DEF <name>( )              header comments, explicit setup, BCO run,
                                 one call per path
      DEF <path>( )              local subprogram: the moves of one path
    <name>.dat
      DEFDAT <name>              DECL FRAME (tool, work frames) and
                                 DECL E6POS (every target), ENDDAT

Conventions (KUKA System Software):

* E6POS ``{X, Y, Z, A, B, C, S, T}``: millimetres and degrees, ``A`` about
  Z, ``B`` about the new Y, ``C`` about the newest X, i.e.
  ``R = Rz(A) Ry(B) Rx(C)`` (:func:`~CadRobotWB.core.rotations.euler_zyx_from_matrix`).
  Positions are written with 4 decimals (about the resolution of the
  controller's single-precision REAL at a metre) and angles with 5, so that
  a point composed with its rounded base frame is still within 1e-3 mm /
  1e-4 deg of the program's pose.
* ``S`` and ``T`` (Status, Turn) come from ``Target.joints_deg`` through
  :func:`~CadRobotWB.robots.configuration.kuka_status_turn` when the target
  has joints and the robot is an OPW robot of the catalog; otherwise they
  are left out (the point then has no S/T, and the .src header says so).
  No external axes (E1..E6) are written: components left out of a point
  keep their current values on the controller.
* ``$BASE`` is the work frame {B} in the robot base frame (WorkFrame.T_r_b);
  this assumes ``$ROBROOT = $NULLFRAME`` (world = robot base), like the ABB
  post assumes world = base.  ``$TOOL`` is ToolData.T_f_t.  With the options
  ``base_number`` / ``tool_number`` the program uses ``BASE_DATA[n]`` /
  ``TOOL_DATA[m]`` instead and its comments give the values to teach there.
* Joint moves are ``PTP`` (speed: a percentage of every axis's maximum,
  ``$VEL_AXIS``; a TCP speed in mm/s cannot be given to PTP), linear moves
  ``LIN``, circular moves ``CIRC aux, end`` (the controller uses only the
  position of the auxiliary point, not its orientation).  ``$VEL.CP`` (m/s)
  is written whenever the programmed speed changes, ``$APO.CDIS`` (mm)
  whenever the zone of an approximated move changes, and a move with a zone
  > 0 carries ``C_DIS``; zone 0 is an exact stop.

Controllers (option ``"controller"``):

``"krc4"`` (default, KSS 8.x)
    PTP moves are approximated with ``C_DIS`` (what KSS 8 inline forms
    write for PTP CONT).  The tool load is set with ``$LOAD``.
``"krc2"`` (KSS 5.x)
    PTP moves are approximated with ``C_PTP`` and ``$APO.CPTP`` (a
    percentage, option ``ptp_approx_percent``, default 50: a zone in mm has
    no PTP equivalent), plus ``C_DIS`` when the next move is a LIN or CIRC
    (PTP-to-CP approximation needs both parameters).  ``$LOAD`` is not
    written (not verified on KSS 5.x): set the load on the pendant.
    Everything else is written the same; other differences between the
    two systems were not checked.

Names: at most 24 characters, letters, digits and ``_``, starting with a
letter, not a KRL keyword, unique without regard to case (KUKA KSS 8.x KRL
quick reference: "names can have a maximum length of 24 characters").

Not verified on a controller: there is no independent KRL syntax checker
here; the tests check the layout, the numbers and the conventions.

Pure Python/numpy: never imports FreeCAD.
"""

import textwrap

import numpy as np

from ..core import program as ir
from ..core import rotations
from ..errors import PostError
from ..robots import configuration
from . import common
from .common import comment_text, compact, fixed

NAME = "kuka_krl"
DESCRIPTION = "KUKA KRL program for KR C4 (KR C2 option): .src and .dat"
FILE_EXTENSIONS = (".src", ".dat")

CONTROLLERS = ("krc4", "krc2")
MAX_NAME = 24
INDENT = "  "
NEWLINE = "\r\n"   # KUKA controllers run on Windows; their own files use CR LF

#: Numbers of the tool and base data the KSS configuration holds by default.
TOOL_NUMBERS = range(1, 17)
BASE_NUMBERS = range(1, 33)

#: KRL keywords and names a program must not declare (upper case).
RESERVED_WORDS = frozenset("""
    AND ANIN ANOUT ASYCANCEL ASYCONT ASYPTP ASYSTOP AXIS B_AND B_EXOR B_NOT
    B_OR BOOL BRAKE BRAKE_F C_DIS C_ORI C_PTP C_SPL C_VEL CA CASE CAST_FROM
    CAST_TO CHAR CIRC CIRC_REL CONST CONTINUE DECL DEF DEFAULT DEFDAT DEFFCT
    DELAY DISABLE DISTANCE DO E6AXIS E6POS ELSE ENABLE END ENDDAT ENDFCT
    ENDFOR ENDIF ENDLOOP ENDSPLINE ENDSWITCH ENDWHILE ENUM EXIT EXOR EXT
    EXTFCT FALSE FOR FRAME GLOBAL GOTO HALT IF IMPORT INT INTERRUPT IS LIN
    LIN_REL LOOP MAXIMUM MINIMUM NOT OFF ON OR PATH POS PRIO PTP PTP_REL
    PUBLIC REAL REPEAT RESUME RETURN SCIRC SEC SIGNAL SLIN SPL SPLINE SPTP
    STEP STRUC SWITCH THEN TO TRIGGER TRUE UNTIL WAIT WHEN WHILE
    BAS IR_STOPM XHOME HOME TOOL_DATA BASE_DATA LOAD_DATA PDAT_ACT FDAT_ACT
    LDAT_ACT PDEFAULT LDEFAULT SUCCESS
""".split())

_INSTRUCTIONS = {ir.JOINT: "PTP", ir.LINEAR: "LIN", ir.CIRCULAR: "CIRC"}


def export(program, options=None):
    """Write a program as a KRL ``.src`` file and its ``.dat`` data list.

    Parameters
    ----------
    program : CadRobotWB.core.program.Program
        Targets in their work frames {B}, mm.
    options : dict, optional
        ``"controller"`` : ``"krc4"`` (default) or ``"krc2"``.
        ``"program_name"`` : str — name of the program (and files) instead
        of ``program.name``; must be a valid KRL name.
        ``"base_number"`` : int or dict — use ``BASE_DATA[n]`` (1..32) for
        the work frame(s) instead of writing the frame; an int when the
        program uses one work frame, else ``{frame name: n}``.
        ``"tool_number"`` : int — use ``TOOL_DATA[m]`` and (KR C4)
        ``LOAD_DATA[m]`` (1..16) instead of writing the tool.
        ``"ptp_speed_percent"`` : int — PTP speed, % of each axis's
        maximum (default 20).
        ``"ptp_approx_percent"`` : int — KR C2 only, ``$APO.CPTP`` of
        approximated PTP moves (default 50).
        ``"ori_speed_deg_s"`` (default 200), ``"cp_accel_m_s2"`` (default
        2.0), ``"ori_accel_deg_s2"`` (default 100): ``$VEL.ORI1/2``,
        ``$ACC.CP``, ``$ACC.ORI1/2``; they must stay within the robot's
        machine data (``$VEL_MA``, ``$ACC_MA``).
        Other keys are ignored.

    Returns
    -------
    list of (str, str)
        ``[(f"{name}.src", text), (f"{name}.dat", text)]``, CR LF line ends.

    Raises
    ------
    PostError
        The program has a move, speed, zone, name or option KRL cannot
        express.
    """
    options = options or {}
    controller = options.get("controller", "krc4")
    if controller not in CONTROLLERS:
        raise PostError(f"Unknown KUKA controller {controller!r}; choose one of "
                        f"{', '.join(CONTROLLERS)}.")
    settings = {
        "ptp_speed": _percent_option(options, "ptp_speed_percent", 20),
        "ptp_approx": _percent_option(options, "ptp_approx_percent", 50),
        "ori_speed": _number_option(options, "ori_speed_deg_s", 200, 1e-3, None),
        "cp_accel": _number_option(options, "cp_accel_m_s2", 2.0, 1e-3, None),
        "ori_accel": _number_option(options, "ori_accel_deg_s2", 100, 1e-3, None),
    }

    names = common.Namer(RESERVED_WORDS, MAX_NAME)
    name = _program_name(program, options.get("program_name"), names)
    moves = program.moves()
    for move in moves:
        common.check_move(move, program, _INSTRUCTIONS, "KUKA KRL",
                          speed_decimals=6, speed_unit_mm_s=1000.0)
    used_frames = list(dict.fromkeys(move.frame for move in moves))
    base_numbers = _base_numbers(options.get("base_number"), used_frames)
    tool_number = _tool_number(options.get("tool_number"))
    common.check_tool_mass(program.tool)

    tool = ("TOOL_DATA[%d]" % tool_number if tool_number
            else names.add(program.tool.name, "T"))
    bases = {key: ("BASE_DATA[%d]" % base_numbers[key] if base_numbers
                   else names.add(key, "B")) for key in used_frames}
    targets = common.target_names(program, names, "X")
    subprograms = [names.add(path.name, "P") for path in program.paths]
    spec = common.opw_robot_spec(program)
    status_turn = {key: _status_turn(target, spec) for key, (target, _) in targets.items()}

    src = [f"DEF {name}( )"]
    src += _comments(_header(program, controller, status_turn, spec))
    src += _comments(_frame_notes(program, used_frames, bases, tool, tool_number, base_numbers,
                                  controller))
    src.append("")
    src += _setup(program, controller, tool, tool_number, settings)
    src.append("")
    src += [INDENT + f"{sub}( )" for sub in subprograms]
    src.append("END")
    for path, sub in zip(program.paths, subprograms):
        src.append("")
        src += _subprogram(path, sub, targets, bases, controller, settings)

    dat = [f"DEFDAT {name}"]
    dat += _comments([
        f"Data of {name}.src, generated by CadRobot (post-processor {NAME}).",
        "E6POS: X, Y, Z in mm in the point's base frame; A, B, C in degrees,",
        "R = Rz(A) Ry(B) Rx(C); S, T = Status, Turn (left out when unknown).",
    ])
    if not tool_number:
        dat.append(INDENT + f"DECL FRAME {tool}={_frame(program.tool.T_f_t)}")
    if not base_numbers:
        for key in used_frames:
            dat.append(INDENT + f"DECL FRAME {bases[key]}={_frame(program.frames[key].T_r_b)}")
    some_missing = None in status_turn.values() and any(status_turn.values())
    if not any(status_turn.values()):
        dat += _comments(["No point has S and T (see the header of the .src)."])
    for key, (target, krl_name) in targets.items():
        if some_missing and status_turn[key] is None:
            dat.append(INDENT + f"; {krl_name}: no S and T (no joint values for this target)")
        dat.append(INDENT + f"DECL E6POS {krl_name}={_e6pos(target, status_turn[key])}")
    dat.append("ENDDAT")

    header = ["&ACCESS RVP", "&REL 1"]
    return [(common.file_name(name, ".src"), NEWLINE.join(header + src) + NEWLINE),
            (common.file_name(name, ".dat"), NEWLINE.join(header + dat) + NEWLINE)]


# --- names -------------------------------------------------------------------

def is_name(text):
    """Tell whether ``text`` is a KRL name this post may declare.

    Parameters
    ----------
    text : str

    Returns
    -------
    bool
        True for 1 to 24 characters ``[A-Za-z][A-Za-z0-9_]*`` that are not
        a keyword or a name of KUKA's system programs this post avoids.
    """
    return common.is_identifier(text, MAX_NAME, RESERVED_WORDS)


def _program_name(program, requested, names):
    """The program name: ``options["program_name"]`` or the program's (KRL wants
    it to be the file's name too)."""
    if requested is None:
        return names.add(common.file_stem(program.name), "P")
    if not isinstance(requested, str) or not is_name(requested):
        raise PostError(
            f"Program name {requested!r} is not a valid KRL name (a letter, then up to "
            "23 letters, digits or '_', not a keyword); choose another program_name.")
    common.check_file_stem(requested, "program_name")
    return names.add(requested, "P")


# --- options -----------------------------------------------------------------

def _number_option(options, key, default, low, high):
    """A numeric option within [low, high] (high None = no upper bound)."""
    value = options.get(key, default)
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise PostError(f"Option {key} must be a number, got {value!r}.") from None
    if not np.isfinite(value) or value < low or (high is not None and value > high):
        bounds = f"{compact(low)} to {compact(high)}" if high is not None else \
            f"at least {compact(low)}"
        raise PostError(f"Option {key} is {compact(value)}; it must be {bounds}.")
    return value


def _percent_option(options, key, default):
    """An integer percentage option, 1 to 100 (KRL declares these INT)."""
    value = options.get(key, default)
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) \
            or not 1 <= value <= 100:
        raise PostError(f"Option {key} is {value!r}; it must be an integer from 1 to 100.")
    return int(value)


def _base_numbers(option, used_frames):
    """``{frame: BASE_DATA number}`` from the ``base_number`` option, or None."""
    if option is None:
        return None
    if isinstance(option, dict):
        numbers = dict(option)
        missing = [key for key in used_frames if key not in numbers]
        if missing:
            raise PostError(f"Option base_number gives no BASE_DATA number for work "
                            f"frame(s) {', '.join(missing)}.")
    else:
        if len(used_frames) > 1:
            raise PostError(f"The program uses {len(used_frames)} work frames "
                            f"({', '.join(used_frames)}); give base_number as "
                            "{frame name: number}.")
        numbers = {key: option for key in used_frames}
    for key in used_frames:
        n = numbers[key]
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n not in BASE_NUMBERS:
            raise PostError(f"BASE_DATA number {n!r} for work frame '{key}' must be an "
                            "integer from 1 to 32.")
    return {key: int(numbers[key]) for key in used_frames}


def _tool_number(option):
    """The TOOL_DATA number of the ``tool_number`` option, or None."""
    if option is None:
        return None
    if isinstance(option, bool) or not isinstance(option, (int, np.integer)) \
            or option not in TOOL_NUMBERS:
        raise PostError(f"Option tool_number is {option!r}; it must be an integer from 1 to 16.")
    return int(option)


def _status_turn(target, spec):
    """(S, T) of a target, or None without joints or without an OPW robot."""
    if spec is None or target.joints_deg is None:
        return None
    return configuration.kuka_status_turn(target.joints_deg, spec)


# --- data values -------------------------------------------------------------

def _abc_deg(R):
    """KUKA A, B, C in degrees of a rotation matrix."""
    return np.degrees(rotations.euler_zyx_from_matrix(np.asarray(R, dtype=float)))


def _xyzabc(T):
    """``X x,Y y,Z z,A a,B b,C c`` of a 4x4 transform (mm, degrees)."""
    T = np.asarray(T, dtype=float)
    x, y, z = (fixed(v, 4) for v in T[:3, 3])
    a, b, c = (fixed(v, 5) for v in _abc_deg(T[:3, :3]))
    return f"X {x},Y {y},Z {z},A {a},B {b},C {c}"


def _frame(T):
    """FRAME aggregate of a 4x4 transform."""
    return "{" + _xyzabc(T) + "}"


def _e6pos(target, status_turn):
    """E6POS aggregate of a target, with S and T when known."""
    text = _xyzabc(target.T_b_t)
    if status_turn is not None:
        text += ",S %d,T %d" % status_turn
    return "{" + text + "}"


# --- program text ------------------------------------------------------------

def _comments(lines):
    return [INDENT + "; " + line if line else INDENT + ";" for line in lines]


def _header(program, controller, status_turn, spec):
    """The comment lines at the top of the main program."""
    source, robot = common.source_and_robot(program)
    system = "KR C4 (KSS 8.x)" if controller == "krc4" else "KR C2 (KSS 5.x)"
    lines = [
        f"Generated by CadRobot (post-processor {NAME}) from {source}.",
        f"Robot: {robot}. Controller: {system}.",
        "Units: mm and degrees; $VEL.CP in m/s, $APO.CDIS in mm.",
        "Points (see the .dat): E6POS in their base frame, R = Rz(A) Ry(B) Rx(C).",
        "$BASE is the calibration frame {B} in the robot base frame; this",
        "assumes $ROBROOT = $NULLFRAME (world frame = robot base frame).",
    ]
    missing = [key for key, st in status_turn.items() if st is None]
    if not missing:
        lines += ["S and T of every point are the arm configuration CadRobot checked."]
    else:
        why = ("the robot is not an OPW robot of CadRobot's catalog" if spec is None
               else "they have no joint values (the program was not solved for the robot, "
               "or no solution reaches them)")
        lines += textwrap.wrap(
            f"{len(missing)} of {len(status_turn)} points have no S and T, as {why}. "
            "For a PTP to such a point the controller chooses the arm configuration "
            "itself; check it in T1 before running in automatic.", 72)
    lines += [
        "",
        "Standalone program: it sets what KUKA's INI fold would (velocities,",
        "accelerations, frames) itself. On a real controller you may instead",
        "paste KUKA's template INI fold here (BAS (#INITMOV,0 ) and the",
        "stop-message interrupt IR_STOPM).",
    ]
    if controller == "krc2":
        lines.append("On a KR C2 the template also declares EXT BAS (BAS_COMMAND :IN,REAL :IN ).")
    return lines


def _frame_notes(program, used_frames, bases, tool, tool_number, base_numbers, controller):
    """Comments naming the frames, and the values to teach into numbered data."""
    lines = [""]
    name = comment_text(program.tool.name)
    if tool_number:
        lines.append(f"Tool {name}: {tool} must hold {_frame(program.tool.T_f_t)}")
    else:
        lines.append(f"Tool {name}: $TOOL = {tool} (TCP in the flange frame).")
    if controller == "krc2":
        lines.append(f"Load of the tool, to set on the pendant: {_load(program.tool)}")
    elif tool_number:
        lines.append(f"LOAD_DATA[{tool_number}] must hold {_load(program.tool)}")
    for key in used_frames:
        frame = program.frames[key]
        source = comment_text(frame.source) or key
        if base_numbers:
            lines.append(f"Work frame {comment_text(key)} ({source}): {bases[key]} must hold "
                         f"{_frame(frame.T_r_b)}")
        else:
            lines.append(f"Work frame {comment_text(key)} ({source}): $BASE = {bases[key]}.")
    return lines


def _load(tool):
    """LOAD aggregate of the tool: mass, centre of gravity in the flange
    frame, no inertia (unknown: zero)."""
    cog = ",".join(f"{axis} {compact(v)}" for axis, v in
                   zip("XYZ", np.asarray(tool.cog_mm, dtype=float)))
    return f"{{M {compact(tool.mass_kg)},CM {{{cog},A 0,B 0,C 0}},J {{X 0,Y 0,Z 0}}}}"


def _setup(program, controller, tool, tool_number, settings):
    """The explicit setup lines of the main program."""
    lines = [
        "; Setup (in place of KUKA's INI fold)",
        "$ADVANCE = 3",
        "$IPO_MODE = #BASE",
        "$ORI_TYPE = #VAR",
        "$CIRC_TYPE = #BASE",
        f"; PTP speed: {settings['ptp_speed']} % of each axis's maximum",
    ]
    lines += [f"$VEL_AXIS[{i}] = {settings['ptp_speed']}" for i in range(1, 7)]
    lines += [f"$ACC_AXIS[{i}] = 100" for i in range(1, 7)]
    lines += [
        f"$VEL.ORI1 = {compact(settings['ori_speed'])}",
        f"$VEL.ORI2 = {compact(settings['ori_speed'])}",
        f"$ACC.CP = {compact(settings['cp_accel'])}",
        f"$ACC.ORI1 = {compact(settings['ori_accel'])}",
        f"$ACC.ORI2 = {compact(settings['ori_accel'])}",
    ]
    if controller == "krc2":
        lines.append(f"$APO.CPTP = {settings['ptp_approx']}")
    lines.append(f"$TOOL = {tool}")
    if controller == "krc4":
        load = "LOAD_DATA[%d]" % tool_number if tool_number else _load(program.tool)
        lines.append(f"$LOAD = {load}")
    else:
        lines.append("; $LOAD is not written for a KR C2: set the load on the pendant")
    lines.append("PTP $AXIS_ACT ; BCO run where the robot stands")
    return [INDENT + line for line in lines]


def _subprogram(path, sub, targets, bases, controller, settings):
    """The local subprogram of one path."""
    lines = [f"DEF {sub}( )", INDENT + f"; Path: {comment_text(path.label or path.name)}"]
    base = speed = cdis = comment = None
    for index, move in enumerate(path.moves):
        text = comment_text(move.comment)
        if text and text != comment:
            lines.append(INDENT + f"; {text}")
        comment = text
        if bases[move.frame] != base:
            base = bases[move.frame]
            lines.append(INDENT + f"$BASE = {base}")
        if move.kind != ir.JOINT and compact(move.speed_mm_s / 1000.0, 6) != speed:
            speed = compact(move.speed_mm_s / 1000.0, 6)
            lines.append(INDENT + f"$VEL.CP = {speed}")
        approx = ""
        if move.zone_mm > 0:
            if compact(move.zone_mm) != cdis:
                cdis = compact(move.zone_mm)
                lines.append(INDENT + f"$APO.CDIS = {cdis}")
            approx = " C_DIS"
            if move.kind == ir.JOINT and controller == "krc2":
                following = path.moves[index + 1] if index + 1 < len(path.moves) else None
                cp_next = following is not None and following.kind != ir.JOINT
                approx = " C_PTP C_DIS" if cp_next else " C_PTP"
        point = targets[move.target.name][1]
        if move.kind == ir.CIRCULAR:
            point = f"{targets[move.via.name][1]}, {point}"
        lines.append(INDENT + f"{_INSTRUCTIONS[move.kind]} {point}{approx}")
    lines.append("END")
    return lines
