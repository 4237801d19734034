"""KUKA KRL post-processor: a ``.src`` program and its ``.dat`` data list.

Files written by :func:`export` (``<name>`` = the program name, which KRL
requires to be the file name too)::

    <name>.src
      DEF <name>( )              header comments, explicit setup, BCO run,
                                 one call per path
      DEF <path>( )              local subprogram: the moves of one path
    <name>.dat
      DEFDAT <name>              DECL FRAME (tool, work frames),
                                 DECL E6POS (Cartesian points) and
                                 DECL E6AXIS (joint targets), ENDDAT

A program whose ``.src`` or ``.dat`` would have more than ``max_lines``
lines (default :data:`MAX_LINES`) is split instead::

    <name>.src / <name>.dat      main program: setup, then calls
                                 <name>_1( ) ... <name>_N( ) in order;
                                 its data list declares the tool and
                                 EXT <name>_k( ) of every part
    <name>_k.src / <name>_k.dat  part k: consecutive moves (a path may run
                                 over several parts) and the frames and
                                 points those moves use

Every file of a split program has at most ``max_lines`` lines, and every
point a part's motion refers to is declared in that part's own data list
(module data lists are not GLOBAL, so parts never clash).

Conventions (KUKA System Software):

* E6POS ``{X, Y, Z, A, B, C, S, T}``: millimetres and degrees, ``A`` about
  Z, ``B`` about the new Y, ``C`` about the newest X, i.e.
  ``R = Rz(A) Ry(B) Rx(C)`` (:func:`~CadRobotWB.core.rotations.euler_zyx_from_matrix`).
  Positions are written with 4 decimals (about the resolution of the
  controller's single-precision REAL at a metre) and angles with 5, so that
  a point composed with its rounded base frame is still within 1e-3 mm /
  1e-4 deg of the program's pose.
* ``S`` and ``T`` (Status, Turn) come from ``Target.joints_deg`` through
  :func:`~CadRobotWB.robots.motion.configuration.kuka_status_turn` when the target
  has joints and the robot is an OPW robot of the catalog; otherwise they
  are left out (the point then has no S/T, and the .src header says so).
  Without external axes no E1..E6 are written in an E6POS: components left
  out of a point keep their current values on the controller.
* Joint targets (option ``joint_targets``, default on): a joint move whose
  target has solved joints is a ``PTP`` to an ``E6AXIS`` ``{A1..A6, E1..E6}``
  (degrees, :func:`~CadRobotWB.posts.common.controller_joints_deg`; KUKA's
  A1..A6 are the model's joints, no coupling or sign change, see
  ``robots/catalog/makers.py``), so the controller cannot choose another arm
  configuration than the one CadRobot checked.  ``E1..E6`` are 0 (no
  external axes), as the pendant writes them.  Off: a ``PTP`` to the E6POS.
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
  > 0 carries ``C_DIS``; zone 0 is an exact stop.  ``$APO.CDIS`` is the
  zone rounded *down* to 0.0001 mm (:func:`zone_text`): never more
  approximation than asked; a zone below 0.0001 mm is an exact stop.

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

Limits (docs/controllers.md, section KUKA, says where each comes from):
KUKA publishes no line limit for a KRL file; :data:`MAX_LINES` = 2500 lines
per file is what RoboDK's current KUKA KRC2/KRC4 posts split at.

Welds (``ProgramPath.welds``, issue 22): KUKA ArcTech inline forms on a KR C4, as the
pendant writes them: ``ARCON`` on the run's start move (exact stop at the seam start),
``ARCSWI`` on its welded moves, ``ARCOFF`` on the last (exact stop: crater), each with
its ``stArcDat_T`` WDAT, WP, FDAT and LDAT in the data list. The folds call KUKA's
``BAS``, which takes tool and base from numbered data, so a program with welds uses
``TOOL_DATA``/``BASE_DATA`` (``tool_number`` 1 and ``base_number`` 1, 2, ... unless
given). docs/controllers.md (KUKA, Welding) gives every field and what is not verified.
KR C2 (ArcTech Analog) is refused. A program without welds is written as before.

External axes (``Program.external``, issue 23): every E6POS and E6AXIS carries
E1..E6 (the track mm, then the positioner deg; 0 after the last), a work frame on
the positioner is its frame in the positioner's flange, coupled with
``$BASE = EK(MACHINE_DEF[m].ROOT, MACHINE_DEF[m].MECH_TYPE, base)``, the setup sets
``$ACT_EX_AX``, and the header gives the machine data CadRobot's model of the
mechanisms implies. docs/controllers.md ("External axes: ABB and KUKA") cites each
syntax and lists what is not verified.

Not verified on a controller: there is no independent KRL syntax checker
here; the tests check the layout, the numbers and the conventions.

Pure Python/numpy: never imports FreeCAD.
"""

import dataclasses
import re
import textwrap
from collections import namedtuple

import numpy as np

from ..core import program as ir
from ..core import rotations
from ..errors import PostError
from ..robots.motion import configuration_data
from . import common
from .common import comment_text, compact, fixed

NAME = "kuka_krl"
DESCRIPTION = "KUKA KRL program for KR C4 (KR C2 option): .src and .dat"
FILE_EXTENSIONS = (".src", ".dat")

CONTROLLERS = ("krc4", "krc2")
MAX_NAME = 24
INDENT = "  "
NEWLINE = "\r\n"   # KUKA controllers run on Windows; their own files use CR LF

#: Default most lines in one ``.src`` or ``.dat`` file (option ``max_lines``):
#: RoboDK's KUKA_KRC4 and KUKA_KRC2_Config posts split at 2500 lines.
MAX_LINES = 2500
#: Range of the ``max_lines`` option: a part must hold its header and a move.
MAX_LINES_RANGE = (100, 10_000_000)

#: Every option :func:`export` reads (``posts.run`` refuses any other).
OPTIONS = {
    "controller": "krc4 (KR C4, KSS 8.x; default) or krc2 (KR C2, KSS 5.x)",
    "program_name": "name of the program and its files: a KRL name of at most 24 characters",
    "base_number": "BASE_DATA number 1-32 (or {work frame: number}) instead of writing the frame",
    "tool_number": "TOOL_DATA (and on a KR C4 LOAD_DATA) number 1-16 instead of writing the tool",
    "ptp_speed_percent": "PTP speed, % of each axis's maximum, whole number 1-100 (default 20)",
    "ptp_approx_percent": "KR C2 only: $APO.CPTP of approximated PTP moves, 1-100 (default 50)",
    "ori_speed_deg_s": "$VEL.ORI1/2, deg/s (default 200)",
    "cp_accel_m_s2": "$ACC.CP, m/s^2 (default 2)",
    "ori_accel_deg_s2": "$ACC.ORI1/2, deg/s^2 (default 100)",
    "joint_targets": "true (default): a joint move with solved joints is a PTP to an E6AXIS; "
                     "false: a PTP to the E6POS",
    "max_lines": f"most lines in one .src or .dat (default {MAX_LINES}); a longer program is "
                 "split into parts that a main program calls in order",
    "arctech_version": "welds: the ArcTech.Basic version the inline forms name (default "
                       "3.4.3.1264, the version of your controller's ArcTech package)",
    "channels": "welds: {channel 1-8: job_number, wire_feed_m_min, voltage_v or current_a} "
                "written to the ArcTech channels, or as text 1:job_number,2:wire_feed_m_min "
                "(the default; the others 0)",
    "positioner_machine": "external axes: the MACHINE_DEF index of the positioner, the "
                          "external kinematic its bases are coupled to with EK (default 2)",
}

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

#: Lines of a file around its body: ``&ACCESS``, ``&REL``, ``DEF``/``DEFDAT``
#: and ``END``/``ENDDAT``.
_FRAME_LINES = 4


def export(program, options=None):
    """Write a program as a KRL ``.src`` file and its ``.dat`` data list.

    Parameters
    ----------
    program : CadRobotWB.core.program.Program
        Targets in their work frames {B}, mm.
    options : dict, optional
        The keys of :data:`OPTIONS`:
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
        ``"joint_targets"`` : bool — joint moves with solved joints go to
        an E6AXIS (default True).
        ``"max_lines"`` : int — most lines per file (default
        :data:`MAX_LINES`); a longer program is split into parts.

    Returns
    -------
    list of (str, str)
        ``[(f"{name}.src", text), (f"{name}.dat", text)]``, CR LF line
        ends; for a split program the parts follow, ``.src`` then ``.dat``
        of each, in calling order.

    Raises
    ------
    PostError
        The program has a move, speed, zone, name or option KRL cannot
        express.
    """
    options = options or {}
    settings = _settings(options)
    names = common.Namer(RESERVED_WORDS, MAX_NAME)
    name = _program_name(program, options.get("program_name"), names)
    moves = program.moves()
    for move in moves:
        common.check_move(move, program, _INSTRUCTIONS, "KUKA KRL",
                          speed_decimals=6, speed_unit_mm_s=1000.0)
    used_frames = list(dict.fromkeys(move.frame for move in moves))
    welding = _check_welds(program, settings)
    base_numbers = _base_numbers(_weld_default(options, "base_number", welding, {
        key: number for number, key in enumerate(used_frames, start=1)}), used_frames)
    tool_number = _tool_number(_weld_default(options, "tool_number", welding, 1))
    common.check_tool_mass(program.tool)

    tool = ("TOOL_DATA[%d]" % tool_number if tool_number
            else names.add(program.tool.name, "T"))
    bases = {key: ("BASE_DATA[%d]" % base_numbers[key] if base_numbers
                   else names.add(key, "B")) for key in used_frames}
    points = _Points(program, names, settings["joint_targets"], _fold_targets(program))
    subprograms = [names.add(path.name, "P") for path in program.paths]
    frame_lines = {} if base_numbers else {
        bases[key]: INDENT + f"DECL FRAME {bases[key]}="
                             f"{_frame(common.frame_for_controller(program, key))}"
        for key in used_frames}
    welds = _Welds(program, points, names, (program.tool.name, tool_number), base_numbers,
                   settings)
    writer = _MotionWriter(points, bases, frame_lines, settings["controller"], welds,
                           _coupled_bases(program, bases, settings))
    notes = _frame_notes(program, used_frames, bases, tool, tool_number, base_numbers,
                         settings["controller"])
    main = _Main(_comments(_header(program, settings["controller"], points) + notes
                           + welds.header() + _external_header(program, settings)),
                 _setup(program, settings["controller"], tool, tool_number, settings),
                 [] if tool_number else
                 [INDENT + f"DECL FRAME {tool}={_frame(program.tool.T_f_t)}"])
    max_lines = settings["max_lines"]
    if max(len(moves), len(points.lines)) + 2 <= max_lines:   # else one line each is too many
        files = _single_program(program, name, subprograms, writer, main)
        if max(text.count(NEWLINE) for _, text in files) <= max_lines:
            return files
    return _split_program(program, name, names, writer, main, max_lines)


class _Main(namedtuple("_Main", "header setup tool_line")):
    """The lines of the main program the layouts share.

    Attributes
    ----------
    header : list of str
        Comment lines after ``DEF``.
    setup : list of str
        Setup lines (speeds, tool, load, BCO run).
    tool_line : list of str
        The tool's ``DECL FRAME`` for the main data list, or none.
    """


def _single_program(program, name, subprograms, writer, main):
    """``[.src, .dat]`` of a program in one module: one local subprogram per path."""
    src = [f"DEF {name}( )"] + main.header + [""] + main.setup + [""]
    src += [INDENT + f"{sub}( )" for sub in subprograms]
    src.append("END")
    for path, sub in zip(program.paths, subprograms):
        src.append("")
        src += _subprogram(path, sub, writer)
    points = writer.points
    dat = [f"DEFDAT {name}"] + _dat_legend(name, points) + main.tool_line
    dat += list(writer.frame_lines.values()) + points.notes()
    dat += [line for krl_name in points.declared() for line in points.lines[krl_name]]
    dat += [line for lines in writer.welds.lines.values() for line in lines]
    dat.append("ENDDAT")
    return [_file(name, ".src", src), _file(name, ".dat", dat)]


# --- options -----------------------------------------------------------------

def _settings(options):
    """Every option but the names and numbers of data, read and checked."""
    return {
        "controller": common.choice_option(options, "controller", "krc4", CONTROLLERS),
        "ptp_speed": common.whole_option(options, "ptp_speed_percent", 20, 1, 100),
        "ptp_approx": common.whole_option(options, "ptp_approx_percent", 50, 1, 100),
        "ori_speed": common.number_option(options, "ori_speed_deg_s", 200, 1e-3),
        "cp_accel": common.number_option(options, "cp_accel_m_s2", 2.0, 1e-3),
        "ori_accel": common.number_option(options, "ori_accel_deg_s2", 100, 1e-3),
        "joint_targets": common.joint_targets_option(options),
        "max_lines": common.whole_option(options, "max_lines", MAX_LINES, *MAX_LINES_RANGE),
        "arctech_version": _arctech_version(options.get("arctech_version", ARCTECH_VERSION)),
        "channels": _channels(options.get("channels", DEFAULT_CHANNELS)),
        "positioner_machine": common.whole_option(options, "positioner_machine",
                                                  POSITIONER_MACHINE, *MACHINE_DEF_RANGE),
    }


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
    return {key: common.whole_number(numbers[key], f"base_number of work frame '{key}'",
                                     BASE_NUMBERS[0], BASE_NUMBERS[-1])
            for key in used_frames}


def _tool_number(option):
    """The TOOL_DATA number of the ``tool_number`` option, or None."""
    if option is None:
        return None
    return common.whole_number(option, "tool_number", TOOL_NUMBERS[0], TOOL_NUMBERS[-1])


# --- points ------------------------------------------------------------------

class _Points:
    """The point data of a program: a name and declaration lines per point.

    A target a Cartesian move uses (or a circle's via point) is an E6POS;
    a target a joint-target move uses
    (:func:`~CadRobotWB.posts.common.is_joint_target_move`) is an E6AXIS,
    named ``<point>_J`` when the same target is also an E6POS.

    Parameters
    ----------
    program : CadRobotWB.core.program.Program
    names : CadRobotWB.posts.common.Namer
    joint_targets : bool
        The ``joint_targets`` option.
    fold_targets : set of str, optional
        Targets of ArcTech inline forms: their E6POS is named ``X<point>``
        (the pendant's convention), the point ``<point>`` in :attr:`plain`.
    """

    def __init__(self, program, names, joint_targets, fold_targets=frozenset()):
        self.joint_targets = joint_targets
        self.external = {} if program.external is None else {
            key: common.external_texts(program, values, 4, 5) for key, values in
            common.external_values(program, MAX_EXTERNAL_AXES, "KUKA KRL").items()}
        targets = common.target_names(program, names, "X")
        cartesian, joint = set(), set()
        for move in program.moves():
            if common.is_joint_target_move(move, joint_targets):
                joint.add(move.target.name)
            else:
                cartesian.add(move.target.name)
            if move.via is not None:
                cartesian.add(move.via.name)
        self.cartesian = {key: krl for key, (_, krl) in targets.items() if key in cartesian}
        self.plain = {key: self.cartesian[key] for key in self.cartesian if key in fold_targets}
        self.cartesian.update((key, names.add("X" + krl, "X")) for key, krl in self.plain.items())
        self.axis = {key: (krl if key not in cartesian else names.add(krl + "_J", "X"))
                     for key, (_, krl) in targets.items() if key in joint}
        cart_targets = [targets[key][0] for key in self.cartesian]
        self.spec = common.opw_robot_spec(program)
        self.status_turn = dict(zip(self.cartesian, status_turn_of(cart_targets, self.spec)))
        self.lines = {}
        self._e6pos_lines(cart_targets)
        for key, krl in self.axis.items():
            joints = common.controller_joints_deg(program, targets[key][0])
            if joints.shape != (6,) or not np.all(np.isfinite(joints)):
                raise PostError(f"Target '{key}' has joint values {list(joints)} that are not "
                                "6 finite numbers; check the program with the robot again.")
            self.lines[krl] = [INDENT + f"DECL E6AXIS {krl}="
                                        f"{_e6axis(joints, self.external.get(key, ()))}"]
        order = [krl for key in targets
                 for krl in (self.cartesian.get(key), self.axis.get(key)) if krl]
        self.lines = {krl: self.lines[krl] for krl in order}

    def _e6pos_lines(self, cart_targets):
        """Declaration lines of every E6POS (angles of all points at once)."""
        values = self.status_turn.values()
        some_missing = None in values and any(values)
        if not cart_targets:
            return
        T = np.array([target.T_b_t for target in cart_targets], dtype=float)
        abc = np.degrees(rotations.euler_zyx_from_matrix(T[:, :3, :3]))
        for (key, krl), T_b_t, angles in zip(self.cartesian.items(), T, abc):
            status_turn = self.status_turn[key]
            lines = []
            if some_missing and status_turn is None:
                lines.append(INDENT + f"; {krl}: no S and T (no joint values for this target)")
            text = _xyzabc_text(T_b_t[:3, 3], angles)
            if status_turn is not None:
                text += ",S %d,T %d" % status_turn
            if key in self.external:
                text += "," + _e_values(self.external[key])
            lines.append(INDENT + f"DECL E6POS {krl}={{{text}}}")
            self.lines[krl] = lines

    def notes(self):
        """Data list comments about the points: none, or that no point has S and T."""
        if self.cartesian and not any(self.status_turn.values()):
            return _comments(["No point has S and T (see the header of the .src)."])
        return []

    def declared(self):
        """Every point name, in the order of first use."""
        return list(self.lines)

    def refs(self, move):
        """Names of the points a move refers to: ``[target]`` or ``[via, target]``."""
        if common.is_joint_target_move(move, self.joint_targets):
            return [self.axis[move.target.name]]
        target = self.cartesian[move.target.name]
        return [target] if move.via is None else [self.cartesian[move.via.name], target]


def status_turn_of(targets, spec):
    """KUKA Status and Turn of many targets at once.

    :func:`CadRobotWB.robots.motion.configuration_data.kuka_status_turns` (the
    docstring of ``kuka_status_turn`` gives the sources) of every target
    with joints, in one call: a 50,000-move program has 62,500 targets.

    Parameters
    ----------
    targets : list of CadRobotWB.core.program.Target
    spec : RobotSpec or None
        The catalog entry of an OPW robot (:func:`common.opw_robot_spec`).

    Returns
    -------
    list of (int, int) or None
        ``(S, T)`` per target; None for a target without joints, and for
        every target without an OPW robot.
    """
    rows = [i for i, target in enumerate(targets) if target.joints_deg is not None]
    out = [None] * len(targets)
    if spec is None or not rows:
        return out
    q = np.array([np.asarray(targets[i].joints_deg, dtype=float).reshape(6) for i in rows])
    bad = np.flatnonzero(~np.all(np.isfinite(q), axis=1))
    if bad.size:
        raise PostError(f"Target '{targets[rows[bad[0]]].name}' has joint values that are not "
                        "finite numbers; check the program with the robot again.")
    status, turn = configuration_data.kuka_status_turns(q, spec)
    for i, s, t in zip(rows, status.tolist(), turn.tolist()):
        out[i] = (s, t)
    return out


# --- data values -------------------------------------------------------------

def _abc_deg(R):
    """KUKA A, B, C in degrees of a rotation matrix."""
    return np.degrees(rotations.euler_zyx_from_matrix(np.asarray(R, dtype=float)))


def _xyzabc_text(xyz_mm, abc_deg):
    """``X x,Y y,Z z,A a,B b,C c`` (4 decimals of mm, 5 of degrees)."""
    x, y, z = (fixed(v, 4) for v in xyz_mm)
    a, b, c = (fixed(v, 5) for v in abc_deg)
    return f"X {x},Y {y},Z {z},A {a},B {b},C {c}"


def _xyzabc(T):
    """``X x,Y y,Z z,A a,B b,C c`` of a 4x4 transform (mm, degrees)."""
    T = np.asarray(T, dtype=float)
    return _xyzabc_text(T[:3, 3], _abc_deg(T[:3, :3]))


def _frame(T):
    """FRAME aggregate of a 4x4 transform."""
    return "{" + _xyzabc(T) + "}"


def _e6axis(joints_deg, external=()):
    """E6AXIS aggregate: A1..A6 in degrees (5 decimals), E1..E6 the external
    axes' texts `external` (0 where none)."""
    axes = ",".join(f"A{i} {fixed(v, 5)}" for i, v in enumerate(joints_deg, start=1))
    return "{" + axes + "," + _e_values(external) + "}"


def _e_values(external):
    """``E1 v1,...,E6 v6``: the external axes' texts, 0 after the last."""
    texts = list(external) + ["0"] * (MAX_EXTERNAL_AXES - len(external))
    return ",".join(f"E{i} {text}" for i, text in enumerate(texts, start=1))


def zone_text(zone_mm):
    """``$APO.CDIS`` text of a zone: rounded down to 0.0001 mm, never up.

    Parameters
    ----------
    zone_mm : float
        At least 0.

    Returns
    -------
    str or None
        The shortest text (``"0.3"``, ``"0.1234"`` for 0.12345); None when
        it rounds down to 0 (the move is then an exact stop).
    """
    text = compact(common.floor_decimals(zone_mm, 4))
    return None if text == "0" else text


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




# --- motions -----------------------------------------------------------------

class _MotionWriter:
    """Writes the lines of each move, given what the lines before it set.

    The state is a tuple ``(path, comment, base, speed, cdis)``: the path
    whose ``; Path:`` comment was written, the last move comment, and the
    ``$BASE``, ``$VEL.CP`` and ``$APO.CDIS`` texts in force.  A new
    subprogram or part starts from :meth:`start`, so it sets everything
    itself.

    Parameters
    ----------
    points : _Points
    bases : dict of str to str
        KRL name of each work frame.
    frame_lines : dict of str to str
        The ``DECL FRAME`` line of each base name; empty with ``base_number``.
    controller : str
    welds : _Welds
    coupled : dict of str to str, optional
        ``$BASE`` expression of each base name coupled to the positioner
        (:func:`_coupled_bases`).
    """

    def __init__(self, points, bases, frame_lines, controller, welds, coupled=None):
        self.points = points
        self.bases = bases
        self.frame_lines = frame_lines
        self.controller = controller
        self.welds = welds
        self.coupled = coupled or {}

    def needed(self, move):
        """Names a move's lines refer to that a data list declares."""
        return [self.bases[move.frame]] + self.points.refs(move) + self.welds.names(move)

    def declaration(self, krl_name):
        """The data list lines of a frame, point or weld datum."""
        frame = self.frame_lines.get(krl_name)
        if frame is not None:
            return [frame]
        return self.points.lines.get(krl_name) or self.welds.lines.get(krl_name, [])

    @staticmethod
    def start(path=None):
        """The state at the start of a subprogram (of `path`) or a part."""
        return (path, None, None, None, None)

    def lines(self, state, path, move, following):
        """The lines of one move.

        Parameters
        ----------
        state : tuple
            From :meth:`start` or the previous call.
        path : CadRobotWB.core.program.ProgramPath
            The path of `move`.
        move : CadRobotWB.core.program.Move
        following : Move or None
            The next move of the path (KR C2 PTP approximation).

        Returns
        -------
        (list of str, tuple)
            The lines and the state after them.
        """
        current, comment, base, speed, cdis = state
        lines = []
        if path is not current:
            lines.append(INDENT + f"; Path: {common.path_label(path)}")
            comment = None
        text = comment_text(move.comment)
        if text and text != comment:
            lines.append(INDENT + f"; {text}")
        folds = self.welds.folds(move)
        if folds is not None and folds[0] is not None:
            # BAS sets speed, zone and frames from the fold's data
            return lines + folds[0] + folds[1], (path, text, None, None, None)
        if self.bases[move.frame] != base:
            base = self.bases[move.frame]
            lines.append(INDENT + f"$BASE = {self.coupled.get(base, base)}")
        if move.kind != ir.JOINT and compact(move.speed_mm_s / 1000.0, 6) != speed:
            speed = compact(move.speed_mm_s / 1000.0, 6)
            lines.append(INDENT + f"$VEL.CP = {speed}")
        approx = ""
        zone = zone_text(move.zone_mm) if move.zone_mm > 0 else None
        if zone is not None:
            if zone != cdis:
                cdis = zone
                lines.append(INDENT + f"$APO.CDIS = {cdis}")
            approx = " C_DIS"
            if move.kind == ir.JOINT and self.controller == "krc2":
                cp_next = following is not None and following.kind != ir.JOINT
                approx = " C_PTP C_DIS" if cp_next else " C_PTP"
        point = ", ".join(self.points.refs(move))
        lines.append(INDENT + f"{_INSTRUCTIONS[move.kind]} {point}{approx}")
        if folds is not None:   # an arc start after the move (a restart)
            return lines + folds[1], (path, text, None, None, None)
        return lines, (path, text, base, speed, cdis)


def _path_moves(path):
    """``(move, following move or None)`` of every move of a path."""
    return zip(path.moves, path.moves[1:] + [None])


def _subprogram(path, sub, writer):
    """The local subprogram of one path."""
    lines = [f"DEF {sub}( )", INDENT + f"; Path: {common.path_label(path)}"]
    state = writer.start(path)
    for move, following in _path_moves(path):
        more, state = writer.lines(state, path, move, following)
        lines += more
    lines.append("END")
    return lines


# --- long programs -------------------------------------------------------------

class _Part:
    """The moves of one part of a split program, within the line limit.

    Parameters
    ----------
    writer : _MotionWriter
    src_room, dat_room : int
        Lines the part's ``.src`` body and ``.dat`` declarations may take.
    """

    def __init__(self, writer, src_room, dat_room):
        self.writer = writer
        self.src_room = src_room
        self.dat_room = dat_room
        self.body = []
        self.names = {}          # frames and points declared, in order
        self.state = writer.start()

    def add(self, path, unit):
        """Append a unit of moves (one move, or a whole weld run: list of
        ``(move, following)``) if it fits; tell whether it did."""
        lines, needed, state = [], [], self.state
        for move, following in unit:
            more, state = self.writer.lines(state, path, move, following)
            lines += more
            needed += self.writer.needed(move)
        new = [n for n in dict.fromkeys(needed) if n not in self.names]
        declarations = [line for n in new for line in self._declaration(n)]
        if len(lines) > self.src_room or len(declarations) > self.dat_room:
            return False
        self.body += lines
        self.src_room -= len(lines)
        self.dat_room -= len(declarations)
        self.names.update((n, declarations) for n in new)
        self.state = state
        return True

    def _declaration(self, krl_name):
        return self.writer.declaration(krl_name)

    def declarations(self):
        """The part's data list lines: frames first, then points."""
        frames = [n for n in self.names if n in self.writer.frame_lines]
        return ([self.writer.frame_lines[n] for n in frames]
                + [line for n in self.names if n not in self.writer.frame_lines
                   for line in self._declaration(n)])


def _pack(program, writer, max_lines, dat_fixed):
    """Cut the moves of all paths into parts of at most `max_lines` lines per file.

    Parameters
    ----------
    program : CadRobotWB.core.program.Program
    writer : _MotionWriter
    max_lines : int
    dat_fixed : int
        Comment lines of every part's data list.

    Returns
    -------
    list of _Part
        Consecutive moves, in execution order, as many as fit in each.
    """
    parts, part = [], None
    src_room = max_lines - _FRAME_LINES - 1          # the part's comment line
    dat_room = max_lines - _FRAME_LINES - dat_fixed
    for path in program.paths:
        for unit, run in _path_units(path):
            if part is not None and part.add(path, unit):
                continue
            part = _Part(writer, src_room, dat_room)
            parts.append(part)
            if not part.add(path, unit):
                if run is not None:
                    raise PostError(f"{common.weld_what(path, run)} needs more than max_lines "
                                    f"{max_lines} lines in one part, and a weld is never split "
                                    "across parts: raise max_lines.")
                raise PostError(f"max_lines {max_lines} is too small for one move and the "
                                "lines every part needs; raise max_lines.")
    return parts


def _path_units(path):
    """``(unit, run)`` of a path in order: the moves of each weld run, or of runs
    that meet (:func:`common.weld_spans`; ``run`` the first WeldRun), and every other
    move alone (``run`` None); a unit is a list of ``(move, following)``."""
    moves = list(_path_moves(path))
    spans = {start: (run, end) for run, start, end in common.weld_spans(path)}
    index = 0
    while index < len(moves):
        run, end = spans.get(index, (None, index))
        yield moves[index:end + 1], run
        index = end + 1


def _part_names(name, count, names):
    """``<name>_1`` ... ``<name>_<count>``, cut to 24 characters, no name taken."""
    for separator in ("_", "_P", "_PART_"):
        candidates = []
        for number in range(1, count + 1):
            suffix = f"{separator}{number}"
            candidates.append(name[:MAX_NAME - len(suffix)] + suffix)
        unique = len({c.upper() for c in candidates}) == count
        if unique and not any(names.is_taken(c) for c in candidates):
            return [names.add(c, "P") for c in candidates]
    raise PostError(f"The names of the parts of program {name} are taken by its points or "
                    "frames; choose another program_name.")


def _split_program(program, name, names, writer, main, max_lines):
    """The files of a program split into parts (see the module docstring).

    Parameters
    ----------
    program : CadRobotWB.core.program.Program
    name : str
        The main program's name.
    names : CadRobotWB.posts.common.Namer
    writer : _MotionWriter
    main : _Main
    max_lines : int

    Returns
    -------
    list of (str, str)
        The main ``.src`` and ``.dat``, then each part's.
    """
    notes = writer.points.notes()
    parts = _pack(program, writer, max_lines, len(_dat_legend(name, writer.points)) + len(notes))
    part_names = _part_names(name, len(parts), names)
    split_note = textwrap.wrap(
        f"This program is split into {len(parts)} parts of at most {max_lines} lines per "
        f"file (option max_lines): {part_names[0]} to {part_names[-1]}, called below in "
        f"order. Copy all {2 * len(parts) + 2} files into one folder of the controller.", 72)
    src = [f"DEF {name}( )"] + main.header + _comments([""] + split_note) + [""] + main.setup
    src.append("")
    src += [INDENT + f"{part}( )" for part in part_names] + ["END"]
    dat = [f"DEFDAT {name}"] + _comments([
        f"Data of {name}.src, generated by CadRobot (post-processor {NAME}).",
        "Its points are in the data lists of its parts."])
    dat += [INDENT + f"EXT {part}( )" for part in part_names] + main.tool_line + ["ENDDAT"]
    if max(len(src), len(dat)) + 2 > max_lines:
        raise PostError(f"The main program of {len(parts)} parts needs "
                        f"{max(len(src), len(dat)) + 2} lines, more than max_lines "
                        f"{max_lines}; raise max_lines.")
    files = [_file(name, ".src", src), _file(name, ".dat", dat)]
    for number, (part, part_name) in enumerate(zip(parts, part_names), start=1):
        comment = (f"; Part {number} of {len(parts)} of {name}, called by {name}.src; "
                   "it needs the tool and load set there.")
        files.append(_file(part_name, ".src",
                           [f"DEF {part_name}( )", INDENT + comment] + part.body + ["END"]))
        files.append(_file(part_name, ".dat",
                           [f"DEFDAT {part_name}"] + _dat_legend(part_name, writer.points)
                           + notes + part.declarations() + ["ENDDAT"]))
    return files


def _file(name, extension, lines):
    """``(file name, text)`` of a module file: KUKA's two header lines, CR LF."""
    return (common.file_name(name, extension),
            NEWLINE.join(["&ACCESS RVP", "&REL 1"] + lines) + NEWLINE)


# --- program text ------------------------------------------------------------

def _comments(lines):
    return [INDENT + "; " + line if line else INDENT + ";" for line in lines]


def _dat_legend(module, points):
    """The comment lines at the top of a data list."""
    lines = [
        f"Data of {module}.src, generated by CadRobot (post-processor {NAME}).",
        "E6POS: X, Y, Z in mm in the point's base frame; A, B, C in degrees,",
        "R = Rz(A) Ry(B) Rx(C); S, T = Status, Turn (left out when unknown).",
    ]
    if points.external:
        lines.append("E1..E6: the external axes, mm or degrees (see the header of the .src).")
    if points.axis:
        lines.append("E6AXIS: A1..A6 in degrees, the solved joints; E1..E6 "
                     + ("the external axes." if points.external else "0 (no external axes)."))
    return _comments(lines)


def _header(program, controller, points):
    """The comment lines at the top of the main program."""
    source, robot = common.source_and_robot(program)
    system = "KR C4 (KSS 8.x)" if controller == "krc4" else "KR C2 (KSS 5.x)"
    lines = [
        f"Generated by CadRobot (post-processor {NAME}) from {source}.",
        f"Robot: {robot}. Controller: {system}.",
        *textwrap.wrap(common.other_maker_note(program.robot, NAME, "KUKA " + system[:5]), 72),
        "Units: mm and degrees; $VEL.CP in m/s, $APO.CDIS in mm.",
        "Points (see the .dat): E6POS in their base frame, R = Rz(A) Ry(B) Rx(C).",
        *(("$BASE is the calibration frame {B} in the robot base frame; this",
           "assumes $ROBROOT = $NULLFRAME (world frame = robot base frame).")
          if program.external is None else
          ("A fixed $BASE is its calibration frame {B} in the world frame; a base",
           "on the positioner is coupled with EK (see External axes below).")),
    ]
    if points.axis:
        count = (f"{len(points.axis)} points of PTP moves are E6AXIS" if len(points.axis) > 1
                 else "1 point of a PTP move is an E6AXIS")
        lines += textwrap.wrap(
            f"{count}: the joints CadRobot solved and checked, so the controller cannot "
            "choose another arm configuration.", 72)
    missing = [key for key, st in points.status_turn.items() if st is None]
    if not missing:
        lines += ["S and T of every point are the arm configuration CadRobot checked."]
    else:
        why = ("the robot is not an OPW robot of CadRobot's catalog" if points.spec is None
               else "they have no joint values (the program was not solved for the robot, "
               "or no solution reaches them)")
        lines += textwrap.wrap(
            f"{len(missing)} of {len(points.status_turn)} points have no S and T, as {why}. "
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
        source = comment_text(frame.source) or comment_text(key)
        if base_numbers:
            lines.append(f"Work frame {comment_text(key)} ({source}): {bases[key]} must hold "
                         f"{_frame(common.frame_for_controller(program, key))}")
        else:
            lines.append(f"Work frame {comment_text(key)} ({source}): $BASE = {bases[key]}.")
        if common.is_moving_frame(program, key):
            lines[-1] += "; it rides on the positioner: see External axes."
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
    lines += _external_setup(program, settings)
    lines.append("PTP $AXIS_ACT ; BCO run where the robot stands")
    return [INDENT + line for line in lines]


# --- arc welding (KUKA ArcTech, KR C4) ------------------------------------------
# The inline forms (folds) as the pendant writes them: docs/controllers.md, KUKA,
# "Welding" (plan issue22 b.2, public programs S9-S12).

#: Default of the ``arctech_version`` option (the ``ArcTech.Basic=`` of public programs, S10).
ARCTECH_VERSION = "3.4.3.1264"
#: Quantities the ``channels`` option may send to an ArcTech channel: (weld/strike
#: value, crater value) of the schedule, by name.
CHANNEL_QUANTITIES = {
    "job_number": ("job_number", "job_number"),
    "wire_feed_m_min": ("wire_feed_m_min", "crater_wire_feed_m_min"),
    "voltage_v": ("voltage_v", "crater_voltage_v"),
    "current_a": ("current_a", "crater_current_a"),
}
DEFAULT_CHANNELS = {1: "job_number", 2: "wire_feed_m_min"}
#: ArcTech Weave.Pattern of each weave pattern. Verified names: #None, #Triangle (S11);
#: the other patterns' names were not found, so they are refused.
WEAVE_PATTERNS = {"zigzag": "#Triangle"}
#: Unverified: Weave.Amplitude as half the width (the plan's reading), the delays in s.
AMPLITUDE_PER_WIDTH = 0.5
#: ArcSense (through-arc tracking) block of S11, written as found there.
ARCSENSE_TRACK = ("Track {IsArcSenseEnabled TRUE,ControlEnabled TRUE,KeepOffset TRUE,"
                  "TeachNew FALSE,FindSeamMiddle TRUE,TrackingDelay 0.2,ControlSensibility 25.0,"
                  "MaxDeviation 100,ControlSensibilityHeight 25.0,Bias 0.0,WeaveOffset 0.0,"
                  "HeightCorrValue 0.0}")
_ARC_INSTRUCTIONS = {common.WELD_START: "ARCON", common.WELD_ON: "ARCSWI",
                     common.WELD_END: "ARCOFF"}
_LDAT_REST = ("APO_FAC 50.0,AXIS_VEL 100.0,AXIS_ACC 100.0,ORI_TYP #VAR,"
              "CIRC_TYP #BASE,JERK_FAC 50.0,GEAR_JERK 50.0,EXAX_IGN 0")


def _arctech_version(value):
    """The ``arctech_version`` option: dotted numbers, e.g. 3.4.3.1264 (a number such
    as 3.4, as the command line reads it, is taken as its text)."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        value = str(value)
    if not isinstance(value, str) or not re.fullmatch(r"\d+(\.\d+){1,4}", value):
        raise PostError(f"arctech_version must be dotted numbers such as {ARCTECH_VERSION} "
                        f"(your controller's ArcTech package), got {value!r}.")
    return value


def _channels(value):
    """The ``channels`` option: ``{channel 1-8: quantity}`` (keys int or digit text), or
    its text ``1:job_number,2:wire_feed_m_min`` (the command line's form)."""
    usage = (f"channels must map channel numbers 1-8 to {', '.join(CHANNEL_QUANTITIES)}, "
             f"e.g. {{1: 'job_number', 2: 'wire_feed_m_min'}} or 1:job_number,2:wire_feed_m_min, "
             f"got {value!r}.")
    if isinstance(value, str):
        pairs = [item.partition(":") for item in value.split(",")]
        if not all(sep for _, sep, _ in pairs):
            raise PostError(usage)
        value = {key.strip(): quantity.strip() for key, _, quantity in pairs}
    if not isinstance(value, dict):
        raise PostError(usage)
    out = {}
    for key, quantity in value.items():
        number = int(key) if isinstance(key, str) and key.isdigit() else key
        if (isinstance(number, bool) or not isinstance(number, int) or not 1 <= number <= 8
                or quantity not in CHANNEL_QUANTITIES):
            raise PostError(usage)
        out[number] = quantity
    return dict(sorted(out.items()))


def _weld_default(options, key, welding, default):
    """Option `key`, or `default` in a program with welds: the inline forms take
    the tool and base from numbered data (FDAT TOOL_NO, BASE_NO)."""
    value = options.get(key)
    return default if value is None and welding else value


def _check_welds(program, settings):
    """Refuse welds ArcTech inline forms cannot carry; tell whether there are any.

    Raises
    ------
    PostError
        One line naming the weld and the fix.
    """
    for path, run, what in common.checked_weld_runs(program):
        if settings["controller"] == "krc2":
            raise PostError(f"{what}: ArcTech Analog on KR C2 is not supported: use "
                            "controller=krc4 (ArcTech) or remove the weld.")
        common.check_weld_basics(path, run, "KUKA ArcTech", WEAVE_PATTERNS, {
            "start": "ARCON's LIN", "arc": "ArcSense", "laser": "SeamTech"})
        if run.weave is not None and run.weave.dwell_center_s:
            raise PostError(f"{what}: KUKA ArcTech's weave has no centre dwell: set "
                            "dwell_center_s to 0.")
    return bool(program.weld_runs())


def _fold_targets(program):
    """Names of the targets (and circle points) of every weld run's moves."""
    out = set()
    for path, run in program.weld_runs():
        for move in path.moves[run.start:run.end + 1]:
            out.add(move.target.name)
            if move.via is not None:
                out.add(move.via.name)
    return out


def _real(value, decimals=4):
    """A REAL as the pendant writes it: ``6.7``, ``0.0``, ``100.0``."""
    text = compact(value, decimals)
    return text if "." in text else text + ".0"


class _Welds:
    """The ArcTech inline forms of a program's weld runs and their data.

    Parameters
    ----------
    program : Program
    points : _Points
        Built with the fold targets (:func:`_fold_targets`).
    names : common.Namer
    tool : (str, int)
        The tool's name and TOOL_DATA number.
    base_numbers : dict of str to int
        The BASE_DATA number of each work frame.
    settings : dict

    Attributes
    ----------
    lines : dict of str to list of str
        Data list lines by KRL name (WDAT, W-record, FDAT, LDAT), in order.
    """

    def __init__(self, program, points, names, tool, base_numbers, settings):
        self.points = points
        self.settings = settings
        self.lines = {}
        self._folds = {}      # id(move) -> (own fold or None, folds after it, names declared)
        self._runs = [run for _, run in program.weld_runs()]
        number = 0
        for path in program.paths:
            for move, (step, restarts) in zip(path.moves, common.weld_steps(path)):
                folds = []
                # a restart ignites where the move ended: ARCON LIN to the same point
                restart_move = dataclasses.replace(move, kind=ir.LINEAR, via=None)
                for arc_move, (role, run) in ([(move, step)] if step else []) + [
                        (restart_move, (common.WELD_START, r)) for r in restarts]:
                    number += 1
                    folds.append(self._fold(arc_move, role, run, number, names, tool,
                                            base_numbers))
                if folds:
                    used = [name for _, fold_names in folds for name in fold_names]
                    own = folds.pop(0)[0] if step else None
                    self._folds[id(move)] = (own, [line for lines, _ in folds for line in lines],
                                             used)

    def folds(self, move):
        """``(own, after)``: the fold lines that write a move (None: the move is
        written as usual) and the fold lines after it (a restart); None for a
        move without arc."""
        entry = self._folds.get(id(move))
        return None if entry is None else entry[:2]

    def names(self, move):
        """The weld data a move's folds refer to (none for other moves)."""
        entry = self._folds.get(id(move))
        return [] if entry is None else entry[2]

    def _fold(self, move, role, run, number, names, tool, base_numbers):
        """The src lines of one inline form and the names of its data (declared in
        :attr:`lines`)."""
        fold = self._fold_names(move, number, names)
        self._declare(fold, role, run, move, tool[1], base_numbers[move.frame])
        return self._fold_lines(fold, role, move, tool, base_numbers[move.frame]), (
            [fold.wdat] + fold.wps + [fold.fdat, fold.ldat])

    def _fold_names(self, move, number, names):
        """The names of one fold: its data as the pendant names them, and its points."""
        point = self.points.plain[move.target.name]
        helper = None if move.via is None else self.points.plain[move.via.name]
        cpdat = names.add(f"CPDAT{number}", "C")
        return _FoldNames(
            wdat=names.add(f"WDAT{number}", "W"), cpdat=cpdat, ldat=names.add("L" + cpdat, "L"),
            fdat=names.add("F" + point, "F"), point=point, helper=helper,
            wps=[names.add("W" + p, "W") for p in (point, helper) if p is not None])

    def _declare(self, fold, role, run, move, tool_number, base_number):
        """The data list lines of one fold: WDAT, the W-records, FDAT and LDAT."""
        zone = zone_text(move.zone_mm) if move.zone_mm > 0 else None
        records = [("stArcDat_T", fold.wdat, self._wdat(fold.wdat, role, run, move))]
        records += [("stArcDat_T", wp, '{Strike {SeamName[] " ",SeamNumber -1},'
                     'Advanced {BitCodedRobotMark 0}}') for wp in fold.wps]
        records += [("FDAT", fold.fdat, f'{{TOOL_NO {tool_number},BASE_NO {base_number},'
                     'IPO_FRAME #BASE,POINT2[] " "}'),
                    ("LDAT", fold.ldat, f"{{VEL {_real(move.speed_mm_s / 1000.0, 6)},ACC 100.0,"
                     f"APO_DIST {_real(float(zone or 0))},{_LDAT_REST}}}")]
        for data_type, name, value in records:
            self.lines[name] = [INDENT + f"DECL {data_type} {name}={value}"]

    def _fold_lines(self, fold, role, move, tool, base_number):
        """The src lines of one fold, from ``;FOLD`` to ``;ENDFOLD``."""
        instruction = _ARC_INSTRUCTIONS[role]
        kind = "CIRC" if fold.helper else "LIN"
        velocity = compact(move.speed_mm_s / 1000.0, 6)
        blending = move.zone_mm > 0 and zone_text(move.zone_mm) is not None
        shown = f"{fold.helper} {fold.point}" if fold.helper else fold.point
        header = (f";FOLD {instruction} {fold.wdat} {kind} {shown}"
                  + (f" Vel={velocity} m/s" if role == common.WELD_START else "")
                  + f" {fold.cpdat} Tool[{tool[1]}]:{comment_text(tool[0])} "
                  f"Base[{base_number}]:{comment_text(move.frame)} ;%{{PE}}")
        params = (f";Params IlfProvider=kukaroboter.arctech.{instruction.lower()}{kind.lower()}; "
                  f"Kuka.IsGlobalPoint=False; Kuka.PointName={fold.point};"
                  + (f" Kuka.HelpPointName={fold.helper};" if fold.helper else "")
                  + f" Kuka.BlendingEnabled={blending}; Kuka.MoveDataName={fold.cpdat}; "
                  f"Kuka.VelocityPath={velocity}; Kuka.CurrentCDSetIndex=0; "
                  "Kuka.MovementParameterFieldEnabled=True; "
                  f"ArcTech.WdatVarName={fold.wdat}; "
                  f"ArcTech.Basic={self.settings['arctech_version']}")
        args = ", ".join([fold.wdat] + fold.wps)
        speed = velocity if role == common.WELD_START else "gArcBasVelDefinition"
        lines = [header, ";FOLD Parameters ;%{h}", params, ";ENDFOLD",
                 "$BWDSTART = FALSE", f"LDAT_ACT = {fold.ldat}", f"FDAT_ACT = {fold.fdat}",
                 f"BAS(#CP_PARAMS, {speed})", "SET_CD_PARAMS (0)"]
        lines += [line.format(args=args, wdat=fold.wdat) for line in _TRIGGERS[role]]
        step = {common.WELD_START: "ArcOn", common.WELD_ON: "ArcSwi",
                common.WELD_END: "ArcOff"}[role]
        motion = ", ".join(self.points.refs(move))
        lines += [f"ArcMainNG(#{step}BeforeMoveStd, {args})",
                  f"{kind} {motion}" + (" C_DIS" if blending and role == common.WELD_ON else ""),
                  f"ArcMainNG(#{step}AfterMoveStd, {args})", ";ENDFOLD"]
        return lines

    def _wdat(self, name, role, run, move):
        """The stArcDat_T record of a fold: ARCON Strike + Weld + Weave (+ Track),
        ARCSWI Weld + Weave, ARCOFF Crater."""
        s = run.schedule
        parts = [f'WdatId[] "{name}"']
        if role == common.WELD_START:
            parts.append(f'Strike {{JobModeId[] "Job mode",ParamSetId[] "Set1",StartTime 0.0,'
                         f'PreFlowTime {_real(s.gas_preflow_s, 3)},{self._channels(s, 0)},'
                         'PurgeTime 0.0}')
        if role in (common.WELD_START, common.WELD_ON):
            # an ARCSWI move runs at its Weld.Velocity: a corner slow-down keeps its speed
            speed = move.speed_mm_s if role == common.WELD_ON else s.travel_speed_mm_s
            parts.append(f'Weld {{JobModeId[] "Job mode",ParamSetId[] "Set1",Velocity '
                         f'{_real(speed / 1000.0, 6)},{self._channels(s, 0)}}}')
            parts.append(_weave_record(run))
        if role == common.WELD_START and run.tracking.sensor == "arc":
            parts.append(ARCSENSE_TRACK)
        if role == common.WELD_END:
            parts.append(f'Crater {{JobModeId[] "Job mode",ParamSetId[] "Set2",CraterTime '
                         f'{_real(s.crater_fill_s, 3)},PostflowTime {_real(s.gas_postflow_s, 3)},'
                         f'{self._channels(s, 1)},BurnBackTime {_real(s.burnback_s, 3)}}}')
        return "{" + ",".join(parts) + "}"

    def _channels(self, schedule, crater):
        """``Channel1 v,...,Channel8 v`` of the ``channels`` option (crater: 1)."""
        values = []
        for number in range(1, 9):
            quantity = self.settings["channels"].get(number)
            value = (getattr(schedule, CHANNEL_QUANTITIES[quantity][crater]) if quantity
                     else 0.0)
            values.append(f"Channel{number} {_real(value or 0.0, 2)}")
        return ",".join(values)

    def header(self):
        """Header comment lines of a program with welds (none without)."""
        if not self._runs:
            return []
        given = ", ".join(f"Channel{n} = {q}" for n, q in self.settings["channels"].items())
        lines = [
            "",
            *textwrap.wrap(
                "Arc welding: KUKA ArcTech (Basic) inline forms ARCON / ARCSWI / ARCOFF, "
                f"ArcTech.Basic={self.settings['arctech_version']} (option arctech_version). "
                "They need KUKA's BAS package (every KR C4 has it): BAS(#CP_PARAMS) sets "
                "$VEL, $ACC, $APO and $TOOL, $BASE, $LOAD from the fold's LDAT and FDAT, so "
                "tool and bases are numbered data here (TOOL_DATA, BASE_DATA). The arc "
                "strikes at the end of ARCON's LIN (the seam start) and goes out at the end "
                "of ARCOFF's move.", 72),
            *textwrap.wrap(
                f"ArcTech channels (option channels): {given}, the others 0; the crater "
                "gets the crater values. What each channel means is set per power source "
                "in WorkVisual: check it.", 72),
        ]
        for run in self._runs:
            lines += common.run_comment_lines(run, 72)
        return lines


#: The names of one fold: WDAT, CPDAT (its LDAT is L + CPDAT), FDAT, the point and the
#: circle's help point as the fold shows them (the E6POS is X + point), the W-records.
_FoldNames = namedtuple("_FoldNames", "wdat cpdat ldat fdat point helper wps")

#: The TRIGGER lines of each inline form (plan b.2: S10, S11, S12).
_TRIGGERS = {
    common.WELD_START: (
        "TRIGGER WHEN DISTANCE = 1 DELAY = ArcGetDelay(#PreDefinition, {wdat}) "
        "DO ArcMainNG(#PreDefinition, {args}) PRIO = -1",
        "TRIGGER WHEN PATH = ArcGetPath(#OnTheFlyArcOn, {wdat}) DELAY = "
        "ArcGetDelay(#GasPreflow, {wdat}) DO ArcMainNG(#GasPreflow, {args}) PRIO = -1",
        "TRIGGER WHEN PATH = ArcGetPath(#OnTheFlyArcOn, {wdat}) DELAY = 0 "
        "DO ArcMainNG(#ArcOnMoveStd, {args}) PRIO = -1"),
    common.WELD_ON: (
        "TRIGGER WHEN DISTANCE = 1 DELAY = 0 DO ArcMainNG(#ArcSwiMoveStd, {args}) PRIO = -1",),
    common.WELD_END: (
        "TRIGGER WHEN PATH = ArcGetPath(#ArcOffBefore, {wdat}) DELAY = 0 "
        "DO ArcMainNG(#ArcOffBeforeOffStd, {args}) PRIO = -1",
        "TRIGGER WHEN PATH = ArcGetPath(#OnTheFlyArcOff, {wdat}) DELAY = 0 "
        "DO ArcMainNG(#ArcOffMoveStd, {args}) PRIO = -1"),
}


def _weave_record(run):
    """``Weave {...}`` of a run: #None without a weave."""
    weave = run.weave
    if weave is None:
        return ("Weave {Pattern #None,Length 0.0,Amplitude 0.0,Angle 0.0,LeftSideDelay 0.0,"
                "RightSideDelay 0.0}")
    length = weave.cycle_length_mm(run.schedule.travel_speed_mm_s)
    return (f"Weave {{Pattern {WEAVE_PATTERNS[weave.pattern]},Length {_real(length, 3)},"
            f"Amplitude {_real(weave.width_mm * AMPLITUDE_PER_WIDTH, 3)},"
            f"Angle {_real(weave.angle_deg, 2)},LeftSideDelay {_real(weave.dwell_left_s, 3)},"
            f"RightSideDelay {_real(weave.dwell_right_s, 3)}}}")


# --- external axes (issue 23) -------------------------------------------------------
# Syntax and sources: docs/controllers.md, "External axes: ABB and KUKA"; what is not
# verified is listed there and written as such in the program's header.

#: External axes an E6POS / E6AXIS carries (E1..E6).
MAX_EXTERNAL_AXES = 6
#: Unverified (third-party readings, docs/controllers.md): the default MACHINE_DEF index of
#: the positioner (MACHINE_DEF[1] is the robot) and the range the option takes.
POSITIONER_MACHINE = 2
MACHINE_DEF_RANGE = (2, 16)
#: Unverified (third-party readings of $machine.dat): the machine data holding each
#: axis's frame of an external kinematic ``$ET<n>_<name>``, base to flange; then TFLA3.
MACHINE_DATA_CHAIN = ("TA1KR", "TA2A1", "TA3A2")


def _ek(settings, base):
    """``EK(...)``: base `base` (a FRAME: the work frame in the positioner's flange)
    coupled to the positioner's external kinematic."""
    machine = f"MACHINE_DEF[{settings['positioner_machine']}]"
    return f"EK({machine}.ROOT, {machine}.MECH_TYPE, {base})"


def _coupled_bases(program, bases, settings):
    """``{base name: $BASE expression}`` of the work frames on the positioner."""
    return {name: _ek(settings, name) for key, name in bases.items()
            if common.is_moving_frame(program, key)}


def _external_setup(program, settings):
    """Setup lines for the external axes: how many are active, their PTP speed
    and acceleration (none without external axes)."""
    if program.external is None:
        return []
    count = len(program.external.axes())
    lines = [f"$ACT_EX_AX = {count}"]
    lines += [f"$VEL_EXTAX[{i}] = {settings['ptp_speed']}" for i in range(1, count + 1)]
    lines += [f"$ACC_EXTAX[{i}] = 100" for i in range(1, count + 1)]
    return lines


def _external_header(program, settings):
    """Header comment lines of a program with external axes: the axes, the
    coupling, and the machine data CadRobot's model of the mechanisms gives
    (none without external axes)."""
    external = program.external
    if external is None:
        return []
    names = [f"E{i}" for i in range(1, MAX_EXTERNAL_AXES + 1)]
    lines = ["", "External axes, in every E6POS and E6AXIS (E after the last: 0):"]
    lines += ["  " + line for line in common.external_axis_lines(program, names)]
    text = [f"$ACT_EX_AX = {len(external.axes())} in the setup; PTP moves run the external "
            "axes at the PTP speed ($VEL_EXTAX)."]
    kinematics = []
    if external.track is not None:
        text.append(f"The track {external.track.label} carries the robot (external kinematic "
                    "#ERSYS): the world frame is the robot base with the track at 0, and fixed "
                    "bases are in it.")
        kinematics.append(("#ERSYS", external.track))
    if external.positioner is not None:
        positioner = external.positioner
        text.append(f"The positioner {positioner.label} carries the part (external kinematic "
                    f"#EASYS, MACHINE_DEF[{settings['positioner_machine']}], option "
                    "positioner_machine): a base on it is the work frame in the positioner's "
                    f"flange, coupled with $BASE = {_ek(settings, '<base>')} so that the TCP "
                    "moves relative to the part.")
        kinematics.append(("#EASYS", positioner))
        text.append("A numbered base on the positioner (BASE_DATA[n], the ArcTech folds' "
                    "BASE_NO) must be a base of that kinematic, MACHINE_FRAME_DAT[n] = "
                    f"{{MACH_DEF_INDEX {settings['positioner_machine']},...}}, so that BAS "
                    "couples it as EK does.")
    text.append("Not verified (docs/controllers.md): the machine data below as CadRobot's model "
                "gives them; they must match the controller's (WorkVisual), which a program "
                "cannot set.")
    lines += [line for paragraph in text for line in textwrap.wrap(paragraph, 72)]
    first_axis = 1
    ek_names = []
    for number, (kind, mechanism) in enumerate(kinematics, start=1):
        ek_names.append(f"ET{number} {kind}")
        lines += _machine_data_lines(number, mechanism, common.in_world(
            external, mechanism.T_u_base), first_axis)
        first_axis += len(mechanism.axes)
    ek_names += [f"ET{number} #NONE" for number in range(len(ek_names) + 1, 7)]
    lines.append("$EX_KIN = {" + ",".join(ek_names) + "}")
    return lines


def _machine_data_lines(number, mechanism, root, first_axis):
    """The machine data of one external kinematic ``ET<number>`` as CadRobot models it:
    its `root` (its base in the world, 4x4), its axes from ``E<first_axis>``, and the
    chain ``TA1KR (E) : TA2A1 (E) : TFLA3`` (each axis turns about / runs along the Z
    of its frame, as in core.mechanisms)."""
    et = f"$ET{number}"
    axes = [f"TR_A{i} #E{first_axis + i - 1}" for i in range(1, len(mechanism.axes) + 1)]
    axes += [f"TR_A{i} #NONE" for i in range(len(mechanism.axes) + 1, 4)]
    lines = [f"{et}: {comment_text(mechanism.label)}, root (base in the world) {_frame(root)}",
             f"{et}_AX = {{{','.join(axes)}}}"]
    for name, axis in zip(MACHINE_DATA_CHAIN, mechanism.axes):
        lines.append(f"{et}_{name} = {_frame(axis.T_prev_joint)} ({axis.name}, {axis.unit})")
    lines.append(f"{et}_TFLA3 = {_frame(mechanism.T_last_flange)}")
    return lines
