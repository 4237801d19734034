"""ABB RAPID post-processor: IRC5 program modules (``.mod``).

Layout of the module written by :func:`export`::

    MODULE <name>                  the file is <name>.mod
      ! header: source, robot, units, frame conventions
      LOCAL PERS tooldata ...      the tool (program.tool)
      LOCAL PERS wobjdata ...      one per work frame, uframe = {B} in {R}
      LOCAL CONST speeddata ...    speeds that are not ABB predefined (v5 ... v7000)
      LOCAL CONST zonedata ...     zones that are not ABB predefined (z0 ... z200)
      LOCAL CONST robtarget ...    every Cartesian target, in its work frame, mm
      LOCAL CONST jointtarget ...  the solved joints of air-move targets, deg
      PROC main()                  ConfJ/ConfL, one call per path
      PROC <path>()                the moves of one path
    ENDMODULE

Every declaration is ``LOCAL``: a global ``PERS`` of the same name in another
loaded module cannot shadow ours. A program longer than the ``max_lines``
option (default 20,000 lines, RoboDK's IRC5 value) is written as a main module
whose ``main()`` calls part modules ``<name>_1``, ``<name>_2``, ... in order;
each part declares what its moves use and is loaded with the main module.

Air moves: with the ``joint_targets`` option (default on), a joint move to a
target with solved joints is ``MoveAbsJ`` to a jointtarget in the controller's
joint convention (:func:`common.controller_joints_deg`).

Robot configurations: when every target carries the joints the robot takes
there (``Target.joints_deg``, filled by
``robots.motion.configuration.solve_program``), each robtarget's confdata is
computed from them (``robots.motion.configuration.abb_confdata``: quadrants of axes
1, 4 and 6, and cfx) and the module monitors configurations
(``ConfJ \\On; ConfL \\On;``): the controller then takes exactly the arm
configuration CadRobot checked, or stops.  When some target has no joints (a
program built without a robot model, or a target no configuration reaches)
the module writes ``ConfJ \\Off; ConfL \\Off;`` and says so in its header;
targets with joints still get their confdata, the others ``[0,0,0,0]``.

Speeds and zones use ABB's predefined data when they match one exactly
(``v10`` = ``[10,500,5000,1000]``, ``z10`` = 10 mm, ``z0`` = 0.3 mm) and a
module constant otherwise, built the way ABB builds its own; a zone radius is
rounded down to 0.0001 mm, never up. A module constant named ``v10`` would
clash with the predefined one.

Quaternion signs follow :func:`~CadRobotWB.core.rotations.choose_quaternion_sign`:
each robtarget's is continuous with the robtarget declared before it, the
first one's and those of tooldata and wobjdata are canonical.

Welds (``ProgramPath.welds``, issue 22): RobotWare Arc instructions for IRC5 with
RobotWare 6 and option 633-4 Arc. The run's start move is ``ArcLStart`` (fine: the arc
strikes at the seam start), its welded moves ``ArcL``/``ArcC``, the last one
``ArcLEnd``/``ArcCEnd`` (fine: crater); seamdata, welddata, weavedata and (through-arc
tracking) trackdata are ``LOCAL PERS``, one per distinct value, in the units of the
``arc_units`` option. docs/controllers.md (ABB, Welding) gives every field and what is
not verified. A program without welds is written as before.

External axes (``Program.external``, issue 23): robtargets and jointtargets carry
each target's values in ``extax`` (the track mm, then the positioner deg; 9E+09 for
axes not connected), a work frame on the positioner is a work object coordinated with
its mechanical unit (ufprog FALSE, ufmec ``positioner_unit``; its oframe the frame in
the positioner's flange), and ``main`` activates the units (``ActUnit``) before its
calls and deactivates them after. docs/controllers.md ("External axes: ABB and KUKA")
cites each syntax and lists what is not verified.

The output is deterministic (no dates, no sign that rounding noise decides:
the same on every FreeCAD and numpy version) and is checked in the tests by the
independent ``rapidchecker`` grammar and format checker.

Pure Python/numpy: never imports FreeCAD.
"""

import dataclasses
import textwrap
from dataclasses import dataclass, field

import numpy as np

from ..core import program as ir
from ..core import frames, rotations
from ..errors import PostError
from ..robots.motion import configuration
from . import common
from .common import comment_text, compact, fixed

NAME = "abb_rapid"
DESCRIPTION = "ABB RAPID program module for IRC5 controllers (.mod; a long program as a main and part modules)"
FILE_EXTENSIONS = (".mod",)

#: Lines in one module when the ``max_lines`` option is not given: RoboDK's
#: ABB_RAPID_IRC5 post splits at 20,000 lines ("recommended for IRC5"; 5,000
#: for S4). docs/controllers.md says where each limit comes from.
DEFAULT_MAX_LINES = 20000
MAX_LINES_RANGE = (50, 1000000)

#: Interrupt rates the ``correction_rate_hz`` option takes, Hz: ITimer
#: intervals of 0.01 s to 10 s (ITimer's shortest interval, 0.01 s, is from
#: memory of ABB's RAPID reference, not checked; see docs/controllers.md).
CORRECTION_RATE_RANGE_HZ = (0.1, 100.0)

OPTIONS = {
    "module_name": "module name, and so file name, instead of the program's (a RAPID identifier)",
    "path_correction": "true: moves along each seam take the sensor's correction (CorrCon, "
                       "\\Corr, a timed TRAP); default false",
    "correction_rate_hz": "rate of the path-correction interrupt, Hz, 0.1 to 100 (default 5)",
    "joint_targets": "true (default): joint moves to targets with solved joints are MoveAbsJ "
                     "to jointtargets; false: MoveJ to robtargets",
    "max_lines": "most lines in one module, %d to %d (default %d); a longer program is split "
                 "into part modules its main module calls" % (*MAX_LINES_RANGE, DEFAULT_MAX_LINES),
    "part_folder": "controller folder of the part modules of a split program, e.g. "
                   "HOME:/CadRobot: main then loads, runs and unloads one part at a time "
                   "(default: all modules are loaded together)",
    "arc_units": "welds: the controller's RobotWare Arc ARC_UNITS, SI_UNITS (default: mm, "
                 "mm/s, wire feed mm/s), WELD_UNITS (mm, mm/s, m/min) or US_UNITS (in, ipm, ipm)",
    "arc_data": "welds: arcdata components written, voltage_wirefeed (default: voltage and "
                "wire feed) or job (sched = the schedule's job number)",
    "positioner_unit": "external axes: the positioner's mechanical unit as the controller names "
                       "it, the ufmec of its work objects (default STN1)",
    "track_unit": "external axes: the track's mechanical unit as the controller names it "
                  "(default TRACK_1)",
}

#: Longest RAPID string (characters).
MAX_STRING = 80

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

#: Names our module must not declare: predefined data and instructions used,
#: and names no file may have on Windows (a module's name is its file's).
_PREDEFINED_NAMES = ({"main", "fine", "vmax", "tool0", "wobj0", "load0",
                      "MoveJ", "MoveL", "MoveC", "MoveAbsJ", "ConfJ", "ConfL",
                      "Off", "On", "WObj", "Corr", "CorrCon", "CorrDiscon", "CorrWrite",
                      "CONNECT", "ITimer", "IDelete", "cdSensor", "corrSensor", "irSensor",
                      "tSensorCorrection", "tooldata", "wobjdata", "speeddata", "zonedata",
                      "robtarget", "jointtarget", "corrdescr", "pos", "intnum",
                      "ArcLStart", "ArcL", "ArcC", "ArcLEnd", "ArcCEnd", "Weave", "Track",
                      "seamdata", "welddata", "weavedata", "trackdata", "arcdata",
                      "ActUnit", "DeactUnit"}
                     | {f"v{v}" for v in PREDEFINED_SPEEDS_MM_S}
                     | set(PREDEFINED_ZONES_MM.values())
                     | common.WINDOWS_DEVICE_NAMES)

_MOVE_INSTRUCTIONS = {ir.JOINT: "MoveJ", ir.LINEAR: "MoveL",
                      ir.CIRCULAR: "MoveC"}

#: Speed of the orientation, external linear and rotational axes in every
#: speeddata we declare (deg/s, mm/s, deg/s), as in ABB's predefined data.
_V_ORI_LEAX_REAX = "500,5000,1000"

_UNUSED_EXTERNAL_AXES = "[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]"

# Moves along the seam take the sensor's correction; approach, entry and retract do not.
_CORRECTED_ROLES = (ir.ROLE_PATH, ir.ROLE_RISK, ir.ROLE_REORIENT)

_CORRECTION_DATA = (
    "! Path correction (seam tracking): the sensor's offset in path",
    "! coordinates, mm (y to the left of the travel, z up).",
    "LOCAL VAR corrdescr cdSensor;",
    "LOCAL VAR pos corrSensor := [0,0,0];",
    "LOCAL VAR intnum irSensor;")

_CORRECTION_TRAP = (
    "TRAP tSensorCorrection",
    "  ! CorrWrite hook: read the seam offset from your sensor into",
    "  ! corrSensor here (serial channel, group inputs, ...), then:",
    "  CorrWrite cdSensor, corrSensor;",
    "ENDTRAP")

_CORRECTION_OFF = ("IDelete irSensor;", "CorrDiscon cdSensor;")


@dataclass
class _Settings:
    """The options, read and checked once (see :data:`OPTIONS`)."""

    correction: bool
    rate_hz: float
    joint_targets: bool
    max_lines: int
    part_folder: object
    arc_units: str = "SI_UNITS"
    arc_data: str = "voltage_wirefeed"
    positioner_unit: str = "STN1"   # UNIT_DEFAULTS
    track_unit: str = "TRACK_1"

    @classmethod
    def read(cls, options):
        common.check_option_names(options, OPTIONS, NAME)
        return cls(correction=common.bool_option(options, "path_correction", False),
                   rate_hz=common.number_option(options, "correction_rate_hz", 5.0,
                                                *CORRECTION_RATE_RANGE_HZ),
                   joint_targets=common.joint_targets_option(options),
                   max_lines=common.whole_option(options, "max_lines", DEFAULT_MAX_LINES,
                                                 *MAX_LINES_RANGE),
                   part_folder=_part_folder(options.get("part_folder")),
                   arc_units=common.choice_option(options, "arc_units", "SI_UNITS",
                                                  tuple(ARC_UNITS)),
                   arc_data=common.choice_option(options, "arc_data", "voltage_wirefeed",
                                                 ARC_DATA),
                   positioner_unit=_unit_option(options, "positioner_unit"),
                   track_unit=_unit_option(options, "track_unit"))


def _part_folder(folder):
    """The ``part_folder`` option: None, or a controller path a RAPID string can hold."""
    if folder is None:
        return None
    if (not isinstance(folder, str) or not folder.strip() or len(folder) > MAX_STRING
            or not folder.isascii() or any(c in folder for c in '"\\') or not folder.isprintable()):
        raise PostError(f"part_folder must be a controller folder such as HOME:/CadRobot: 1 to "
                        f"{MAX_STRING} printable ASCII characters without '\"' or '\\', "
                        f"got {folder!r}.")
    return folder


@dataclass
class _Data:
    """What modules declare.

    ``pers`` are the tooldata and wobjdata lines every module declares;
    ``values`` maps a key ``(kind, key)`` (kind ``arc``, ``speed``, ``zone``,
    ``rob`` or ``joint``) to ``(identifier, declaration)``, the declaration ``""``
    for ABB's predefined data, in declaration order; ``runs`` the arc data
    keys of each weld run (:class:`_ArcKeys`).
    """

    tool: str
    wobjs: dict
    pers: list
    values: dict = field(default_factory=dict)
    runs: dict = field(default_factory=dict)   # run name -> _ArcKeys
    slow_welds: dict = field(default_factory=dict)   # id(move) -> welddata key
    units: tuple = ()   # mechanical units main activates (ActUnit), track first
    _order: dict = field(default_factory=dict)

    @property
    def order(self):
        """``{key: position}`` in declaration order."""
        if len(self._order) != len(self.values):
            self._order = {key: i for i, key in enumerate(self.values)}
        return self._order

    def name(self, kind, key):
        return self.values[(kind, key)][0]

    def has_joint_targets(self):
        return any(kind == "joint" for kind, _ in self.values)


@dataclass
class _Entry:
    """The instruction lines of one move (or of a whole weld run, which no
    module split may cut: ``moves`` > 1, ``weld`` names it) and the keys of the
    data they name."""

    lines: list
    keys: tuple
    moves: int = 1
    weld: str = ""


def export(program, options=None):
    """Write a program as RAPID modules: one, or a main module and its parts.

    Parameters
    ----------
    program : CadRobotWB.core.program.Program
        Targets in their work frames {B}, mm.
    options : dict, optional
        See :data:`OPTIONS`; any other name is refused.
        ``"module_name"`` : str — module name instead of ``program.name``
        (a valid RAPID identifier); the file is named after the module.
        ``"path_correction"`` : bool — seam tracking on the controller: the
        moves along each path carry ``\\Corr`` under a correction generator
        (``CorrCon``), and a timed interrupt calls the TRAP
        ``tSensorCorrection`` where the user's sensor writes its offset with
        ``CorrWrite`` (paper 4.1: 5 Hz).
        ``"correction_rate_hz"`` : float — that interrupt's rate, Hz (default 5).
        ``"joint_targets"`` : bool — joint moves to targets with solved joints
        are ``MoveAbsJ`` to jointtargets (default True).
        ``"max_lines"`` : int — most lines in one module (default
        :data:`DEFAULT_MAX_LINES`).

    Returns
    -------
    list of (str, str)
        ``[(f"{module}.mod", text)]``; for a program longer than
        ``max_lines``, the main module first, then its parts
        ``{module}_1.mod``, ``{module}_2.mod``, ... in the order main calls them.

    Raises
    ------
    PostError
        A bad option, or a move, speed, tool or frame RAPID cannot express.
    """
    options = {} if options is None else options
    settings = _Settings.read(options)
    # RAPID is case-insensitive; predefined names the module uses are taken too.
    names = common.Namer(RESERVED_WORDS | _PREDEFINED_NAMES, MAX_IDENTIFIER)
    module_name = _module_name(program, options.get("module_name"), names)
    moves = program.moves()
    for move in moves:
        common.check_move(move, program, _MOVE_INSTRUCTIONS, "ABB RAPID", speed_decimals=4)
    _check_transforms(program)
    _check_welds(program, settings)
    data = _data(program, moves, names, settings)
    monitored = common.opw_robot_spec(program) is not None and all(
        target.joints_deg is not None for target in program.targets())
    procs = [names.add(path.name, "path") for path in program.paths]
    bodies = [_path_entries(path, data, settings) for path in program.paths]
    lines = _single_module(program, module_name, data, procs, bodies, monitored, settings)
    if len(lines) <= settings.max_lines:
        return [(common.file_name(module_name, ".mod"), _text(lines))]
    if settings.correction:
        raise PostError(f"Program '{program.name}' needs {len(lines)} lines, more than "
                        f"max_lines={settings.max_lines}, and path correction cannot span "
                        "several modules; raise max_lines or set path_correction=false.")
    return _split_modules(program, module_name, data, bodies, monitored, settings, names)


def _check_transforms(program, tol=1e-6):
    """Refuse a tool, work frame or target whose pose is not a rigid transform.

    A quaternion of a sheared, scaled or mirrored matrix is some rotation the
    user never asked for, so nothing is written.

    Raises
    ------
    PostError
        Names the first tool, frame or target at fault.
    """
    tool = program.tool
    if not frames.is_rigid_transform(tool.T_f_t, tol):
        raise PostError(f"Tool '{tool.name}' has a TCP pose that is not a rigid transform "
                        "(rotation, then translation); check the tool.")
    if not np.all(np.isfinite(np.asarray(tool.cog_mm, dtype=float))):
        raise PostError(f"Tool '{tool.name}' has a centre of gravity that is not a finite "
                        "number; check the tool's load.")
    for key, frame in program.frames.items():
        if not frames.is_rigid_transform(frame.T_r_b, tol):
            raise PostError(f"Work frame '{key}' is not a rigid transform in the robot base "
                            "frame; check its calibration frame.")
    targets = program.targets()
    if targets:
        T = np.array([target.T_b_t for target in targets], dtype=float)
        R = T[:, :3, :3]
        error = np.abs(np.einsum("nji,njk->nik", R, R) - np.eye(3)).max(axis=(1, 2))
        error = np.maximum(error, np.abs(np.linalg.det(R) - 1.0))
        error = np.maximum(error, np.abs(T[:, 3] - [0.0, 0.0, 0.0, 1.0]).max(axis=1))
        bad = np.flatnonzero(~(error <= tol))
        if bad.size:
            raise PostError(f"Target '{targets[bad[0]].name}' has a pose that is not a rigid "
                            "transform; regenerate the program.")


def _text(lines):
    return "\n".join(lines) + "\n"


def _data(program, moves, names, settings):
    """Name and write every declaration of the program (:class:`_Data`)."""
    units, extax = _external(program, settings, names)
    tool = names.add(program.tool.name, "tool")
    wobjs = {key: names.add(key, "wobj") for key in program.frames}
    pers = [f"LOCAL PERS tooldata {tool} := {_tooldata(program.tool)};"]
    pers += [f"LOCAL PERS wobjdata {wobjs[key]} := "
             f"{_wobjdata(program, key, settings.positioner_unit)};" for key in program.frames]
    data = _Data(tool, wobjs, pers, units=units)
    _arc_declarations(program, data, names, settings)
    data.values.update(_speed_declarations(moves, names))
    data.values.update(_zone_declarations(moves, names))
    data.values.update(_target_declarations(program, moves, names, settings.joint_targets,
                                            extax))
    return data


# --- one module -------------------------------------------------------------------

def _single_module(program, module_name, data, procs, bodies, monitored, settings):
    """The lines of the whole program as one module: main and one PROC per path."""
    lines = [f"MODULE {module_name}"]
    lines += _header(program, monitored, data.has_joint_targets(), settings)
    lines += _declaration_lines(data, data.values)
    if settings.correction:
        lines.append("")
        lines += [INDENT + text for text in _CORRECTION_DATA]
    lines.append("")
    lines += _main_proc(procs, monitored, data.units)
    for path, proc, body in zip(program.paths, procs, bodies):
        lines.append("")
        lines.append(INDENT + f"PROC {proc}()")
        lines.append(2 * INDENT + f"! Path: {common.path_label(path)}")
        lines += [2 * INDENT + line for entry in body for line in entry.lines]
        lines.append(INDENT + "ENDPROC")
    if settings.correction:
        lines.append("")
        lines += [INDENT + text for text in _CORRECTION_TRAP]
    lines.append("ENDMODULE")
    return lines


def _declaration_lines(data, keys):
    """Tool and work objects; speeds and zones; targets: each group after a blank line."""
    lines = [""] + [INDENT + text for text in data.pers]
    keys = sorted(keys, key=data.order.__getitem__)
    for kinds in (("arc",), ("speed", "zone"), ("rob", "joint")):
        texts = [data.values[key][1] for key in keys
                 if key[0] in kinds and data.values[key][1]]
        if texts:
            lines.append("")
            lines += [INDENT + text for text in texts]
    return lines


def _main_proc(calls, monitored, units=()):
    """``PROC main()``: configuration monitoring, the mechanical units activated
    (``ActUnit``), one call per name, the units deactivated (``DeactUnit``)."""
    state = "On" if monitored else "Off"
    return ([INDENT + "PROC main()", 2 * INDENT + f"ConfJ \\{state};",
             2 * INDENT + f"ConfL \\{state};"]
            + [2 * INDENT + f"ActUnit {unit};" for unit in units]
            + [2 * INDENT + f"{call};" for call in calls]
            + [2 * INDENT + f"DeactUnit {unit};" for unit in units] + [INDENT + "ENDPROC"])


# --- a main module and its parts ---------------------------------------------------

def _split_modules(program, module_name, data, bodies, monitored, settings, names):
    """A main module calling part modules of at most ``max_lines`` lines each.

    Every part declares its own ``LOCAL`` copy of the tool, the work objects
    and the speeds, zones and targets its moves use, so each part loads and
    checks on its own and no other module can shadow its data; its one
    global PROC is named after the part module.
    """
    parts = _pack(program, data, bodies, settings.max_lines)
    part_names = [_part_name(module_name, k + 1, names) for k in range(len(parts))]
    procs = [_part_name(name, "run", names) for name in part_names]
    first = 1
    files = []
    for k, (part, name, proc) in enumerate(zip(parts, part_names, procs)):
        lines = [f"MODULE {name}"]
        lines += [INDENT + "! " + text for text in (
            f"Part {k + 1} of {len(parts)} of program module {module_name}: moves {first} to "
            f"{first + part.moves - 1}.",
            f"Generated by CadRobot (post-processor {NAME}); {module_name}.mod calls it.")]
        lines += _declaration_lines(data, part.keys)
        lines += ["", INDENT + f"PROC {proc}()"]
        lines += [2 * INDENT + line for text, entry in part.body
                  for line in ([text] if entry is None else entry.lines)]
        lines += [INDENT + "ENDPROC", "ENDMODULE"]
        files.append((common.file_name(name, ".mod"), _text(lines)))
        first += part.moves
    main = [f"MODULE {module_name}"] + _header(program, monitored, data.has_joint_targets(),
                                               settings)
    held = (f"part module {part_names[0]}" if len(parts) == 1 else
            f"{len(parts)} part modules, {part_names[0]} to {part_names[-1]}")
    how = ("load them into this task together with this module." if settings.part_folder is None
           else f"copy them to {settings.part_folder}; main loads and unloads each in turn.")
    main += [INDENT + "! " + text for text in (
        f"The moves are in {held} (at most {settings.max_lines} lines each):", how)]
    if settings.part_folder is None:
        main += [""] + _main_proc(procs, monitored, data.units) + ["ENDMODULE"]
    else:
        main += _loading_main(part_names, procs, monitored, settings.part_folder, names,
                              data.units)
    if len(main) > settings.max_lines:
        raise PostError(f"max_lines={settings.max_lines} splits program '{program.name}' into "
                        f"{len(parts)} parts, too many for one main module; raise max_lines.")
    return [(common.file_name(module_name, ".mod"), _text(main))] + files


def _loading_main(part_names, procs, monitored, folder, names, units=()):
    """The rest of a main module that loads each part from `folder`, runs it and unloads it.

    ``Load \\Dynamic`` puts the part in program memory, the late-bound call
    ``%"<proc>"%`` runs it (main has no static reference to a module that is
    not loaded yet), ``UnLoad`` frees the memory for the next part.
    """
    folder_name = names.add("partFolder", "s")
    lines = ["", INDENT + f'LOCAL CONST string {folder_name} := "{folder}";', ""]
    main = _main_proc([], monitored, units)
    end = len(main) - 1 - len(units)   # the calls go before DeactUnit and ENDPROC
    for name, proc in zip(part_names, procs):
        main[end:end] = [2 * INDENT + text for text in (
            f'Load \\Dynamic, {folder_name} \\File:="{name}.mod";', f'%"{proc}"%;',
            f'UnLoad {folder_name} \\File:="{name}.mod";')]
        end += 3
    return lines + main + ["ENDMODULE"]


#: Lines of a part module around its declarations and instructions: MODULE,
#: two header comments, blank, PROC, ENDPROC, ENDMODULE.
_PART_FRAME_LINES = 7


class _Part:
    """A part being filled: its body and its line count, kept as it grows."""

    def __init__(self, data):
        self.data = data
        self.body = []          # (path comment, None) or (None, move entry)
        self.keys = set()
        self.moves = 0
        self.groups = {("arc",): 0, ("speed", "zone"): 0, ("rob", "joint"): 0}
        self.lines = _PART_FRAME_LINES + 1 + len(data.pers)

    def lines_with(self, entry):
        """The part's line count if `entry` were added (declarations included)."""
        return self.lines + len(entry.lines) + sum(self._new_lines(entry).values())

    def _new_lines(self, entry):
        new = {group: 0 for group in self.groups}
        for key in set(entry.keys) - self.keys:
            if self.data.values[key][1]:
                group = next(g for g in self.groups if key[0] in g)
                # a group's first declaration brings its blank line
                new[group] += 1 + (self.groups[group] + new[group] == 0)
        return new

    def add(self, comment=None, entry=None):
        if entry is None:
            self.body.append((comment, None))
            self.lines += 1
            return
        for group, count in self._new_lines(entry).items():
            self.lines += count
            self.groups[group] += count
        self.keys.update(entry.keys)
        self.body.append((None, entry))
        self.lines += len(entry.lines)
        self.moves += entry.moves


def _pack(program, data, bodies, max_lines):
    """Cut the program's moves into parts of at most ``max_lines`` lines.

    Returns
    -------
    list of _Part
        In order; each with at least one move.
    """
    parts = []
    part = _Part(data)
    for path, body in zip(program.paths, bodies):
        comment = f"! Path: {common.path_label(path)}"
        if body and part.body:
            part.add(comment)
        for entry in body:
            if not part.body:
                part.add(comment if entry is body[0] else comment + " (continued)")
            if part.lines_with(entry) > max_lines and part.moves:
                parts.append(part)
                part = _Part(data)
                part.add(comment + " (continued)")
            if part.lines_with(entry) > max_lines and entry.weld:
                raise PostError(f"{entry.weld} needs {part.lines_with(entry)} lines with its "
                                "declarations, and a weld is never split across modules: "
                                f"raise max_lines above {max_lines}.")
            if part.lines_with(entry) > max_lines:
                raise PostError(f"max_lines={max_lines} is too small for one move of program "
                                f"'{program.name}' and its declarations "
                                f"({part.lines_with(entry)} lines); raise max_lines.")
            part.add(entry=entry)
    if part.moves:
        parts.append(part)
    return parts


def _part_name(base, suffix, names):
    """``{base}_{suffix}``, cut to 32 characters, unique in the program."""
    tail = f"_{suffix}"
    return names.add(base[:MAX_IDENTIFIER - len(tail)] + tail, "M")


# --- instructions ----------------------------------------------------------------

def _path_entries(path, data, settings):
    """One :class:`_Entry` per move of a path, with comments and correction lines."""
    entries = []
    previous_comment = None
    corrected = False
    for move, (step, restarts) in zip(path.moves, common.weld_steps(path)):
        lines = []
        on_seam = settings.correction and move.role in _CORRECTED_ROLES
        if on_seam and not corrected:
            lines += ["CorrCon cdSensor;", "CONNECT irSensor WITH tSensorCorrection;",
                      f"ITimer {compact(1.0 / settings.rate_hz)}, irSensor;"]
        elif corrected and not on_seam:
            lines += list(_CORRECTION_OFF)
        corrected = on_seam
        comment = comment_text(move.comment)
        if comment and comment != previous_comment:
            lines.append(f"! {comment}")
        previous_comment = comment
        keys = _move_keys(move, settings.joint_targets)
        if step is None:
            lines.append(_move_instruction(move, keys, data, on_seam))
        for role, run in ([step] if step else []) + [(common.WELD_START, r) for r in restarts]:
            # a restart ignites where the move ended: ArcLStart to the same point
            arc_move = move if role != common.WELD_START else dataclasses.replace(
                move, kind=ir.LINEAR, via=None)
            arc_keys = _move_keys(arc_move, settings.joint_targets)
            arc = data.runs[run.name]
            if role != common.WELD_START and id(move) in data.slow_welds:
                arc = dataclasses.replace(arc, weld=data.slow_welds[id(move)])
            lines.append(_arc_instruction(arc_move, role, arc, arc_keys, data))
            keys += tuple(key for key in arc_keys + tuple(arc)
                          if key is not None and key not in keys)
        entries.append(_Entry(lines, keys))
    if corrected:
        entries[-1].lines += list(_CORRECTION_OFF)
    return _whole_runs(path, entries)


def _move_keys(move, joint_targets):
    """The data keys a move names: its targets, speed and zone."""
    if common.is_joint_target_move(move, joint_targets):
        points = (("joint", move.target.name),)
    else:
        points = (("rob", move.target.name),)
        if move.kind == ir.CIRCULAR:
            points = (("rob", move.via.name),) + points
    return points + (("speed", compact(move.speed_mm_s)), ("zone", zone_text(move.zone_mm)))


def _move_instruction(move, keys, data, corrected=False):
    """One MoveAbsJ/MoveJ/MoveL/MoveC instruction (without indentation); with
    ``\\Corr`` when the move takes the sensor's path correction."""
    instruction = "MoveAbsJ" if keys[0][0] == "joint" else _MOVE_INSTRUCTIONS[move.kind]
    arguments = ", ".join(data.name(*key) for key in keys)
    corr = " \\Corr" if corrected else ""
    return (f"{instruction} {arguments}, {data.tool} \\WObj:={data.wobjs[move.frame]}{corr};")


# --- data declarations ---------------------------------------------------------------

def _speed_declarations(moves, names):
    """``{("speed", text): (name, declaration or "")}`` of each distinct speed (mm/s):
    ABB's predefined ``vN`` where it is exactly N mm/s, else a speeddata constant."""
    predefined = {compact(v): f"v{v}" for v in PREDEFINED_SPEEDS_MM_S}
    return _named_values("speed", [compact(m.speed_mm_s) for m in moves], predefined,
                         ("v", "speeddata"), lambda text: f"[{text},{_V_ORI_LEAX_REAX}]", names)


def _named_values(kind, texts, predefined, prefix_type, value, names):
    """``{(kind, text): (name, declaration or "")}`` of each distinct text.

    Parameters
    ----------
    kind : str
    texts : list of str
        Values as written (:func:`compact`).
    predefined : dict of str to str
        ABB's name of a value, for those it predefines (nothing is declared).
    prefix_type : (str, str)
        The name prefix and the RAPID data type of a declared value.
    value : callable
        The declared value's text, from the value's text.
    names : common.Namer
    """
    prefix, data_type = prefix_type
    out = {}
    for text in texts:
        if (kind, text) in out:
            continue
        if text in predefined:
            out[(kind, text)] = (predefined[text], "")
        else:
            name = names.add(prefix + text.replace(".", "_"), prefix)
            out[(kind, text)] = (name, f"LOCAL CONST {data_type} {name} := {value(text)};")
    return out


def zone_text(zone_mm):
    """The zone radius we write: 4 decimals, rounded down, never more than asked.

    Parameters
    ----------
    zone_mm : float
        At least 0.

    Returns
    -------
    str
        ``"0.2999"`` for 0.29996 (never ``"0.3"``, ABB's ``z0``).
    """
    return compact(common.floor_decimals(zone_mm, 4))


def _zone_declarations(moves, names):
    """``{("zone", text): (name, declaration or "")}`` of each distinct zone (mm).

    ``fine`` for 0, ABB's predefined ``zN`` for its exact radius, else a
    zonedata constant of exactly that radius (:func:`zone_text`).
    """
    predefined = {compact(r): name for r, name in PREDEFINED_ZONES_MM.items()}
    predefined["0"] = "fine"
    return _named_values("zone", [zone_text(m.zone_mm) for m in moves], predefined,
                         ("z", "zonedata"), lambda text: _zonedata(float(text)), names)


def _target_declarations(program, moves, names, joint_targets, extax):
    """``{("rob" or "joint", target name): (identifier, declaration)}``, in target order.

    A target is a robtarget where a Cartesian move or a circle goes through
    it, a jointtarget where a joint move goes to its solved joints
    (:func:`common.is_joint_target_move`); a target used both ways gets both.
    `extax` gives the extjoint text of each target with external axes (by name).
    """
    joint = {m.target.name for m in moves if common.is_joint_target_move(m, joint_targets)}
    cartesian = {m.target.name for m in moves if not common.is_joint_target_move(m, joint_targets)}
    cartesian |= {m.via.name for m in moves if m.via is not None}
    named = common.target_names(program, names, "p")
    robtargets = [(target, name) for key, (target, name) in named.items() if key in cartesian]
    # Each robtarget's quaternion sign continues from the one declared before.
    quaternions = iter(rotations.quaternion_sequence_from_matrices(
        [target.T_b_t[:3, :3] for target, _ in robtargets]))
    spec = common.opw_robot_spec(program)
    out = {}
    for key, (target, name) in named.items():
        if key in cartesian:
            robtarget = _robtarget(target, next(quaternions), spec,
                                   extax.get(target.name, _UNUSED_EXTERNAL_AXES))
            out[("rob", key)] = (name, f"LOCAL CONST robtarget {name} := {robtarget};")
        if key in joint:
            jname = names.add(name + "_j", "j") if key in cartesian else name
            joints = common.controller_joints_deg(program, target)
            if not np.all(np.isfinite(joints)):
                raise PostError(f"Target '{target.name}' has solved joints that are not "
                                "finite numbers; check the program with the robot again.")
            jointtarget = _jointtarget(joints, extax.get(target.name, _UNUSED_EXTERNAL_AXES))
            out[("joint", key)] = (jname, f"LOCAL CONST jointtarget {jname} := {jointtarget};")
    return out


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
    common.check_file_stem(requested, "module_name")
    if names.is_taken(requested):
        raise PostError(f"Module name {requested!r} is a predefined RAPID "
                        "name; choose another module_name.")
    return names.add(requested, "M")


# --- data values -------------------------------------------------------------

def _tooldata(tool):
    """tooldata value: robot-held tool, TCP pose in the flange frame."""
    common.check_tool_mass(tool)
    pose = _pose(tool.T_f_t)
    cog = ",".join(compact(c) for c in np.asarray(tool.cog_mm, float))
    return (f"[TRUE,{pose},[{compact(tool.mass_kg)},[{cog}],"
            "[1,0,0,0],0,0,0]]")


def _wobjdata(program, key, positioner_unit):
    """wobjdata value of work frame `key`: a fixed user frame = {B} in {R} (in the
    world with a track) and identity object frame; on the positioner, coordinated
    with its unit: ufprog FALSE, ufmec the unit, the uframe the controller's (the
    unit's moving frame, identity here), the oframe {B} in the positioner's flange."""
    pose = _pose(common.frame_for_controller(program, key))
    if common.is_moving_frame(program, key):
        return f'[FALSE,FALSE,"{positioner_unit}",[[0,0,0],[1,0,0,0]],{pose}]'
    return f'[FALSE,TRUE,"",{pose},[[0,0,0],[1,0,0,0]]]'


def _zonedata(radius_mm):
    """zonedata value built like ABB's predefined zones.

    ABB's zN uses pzone_ori = pzone_eax = zone_leax = 1.5 N (mm) and
    zone_ori = zone_reax = 0.15 N (degrees).
    """
    big = compact(1.5 * radius_mm)
    angle = compact(0.15 * radius_mm)
    return (f"[FALSE,{compact(radius_mm)},{big},{big},{angle},{big},"
            f"{angle}]")


def _robtarget(target, q, spec, extax=_UNUSED_EXTERNAL_AXES):
    """robtarget value: position, orientation q (w, x, y, z), confdata, the
    external axes `extax` (none by default).

    confdata comes from the target's joints when it has them (and the robot
    is known), else ``[0,0,0,0]``.
    """
    q = _unit(q)
    conf = "0,0,0,0"
    if spec is not None and target.joints_deg is not None:
        conf = ",".join(str(v) for v in
                        configuration.abb_confdata(target.joints_deg, spec))
    return (f"[{_position(target.position_mm)},{_quaternion(q)},"
            f"[{conf}],{extax}]")


def _jointtarget(joints_deg, extax=_UNUSED_EXTERNAL_AXES):
    """jointtarget value: six robot joints (deg, the controller's convention),
    the external axes `extax` (none by default)."""
    return f"[[{','.join(fixed(v, 4) for v in joints_deg)}],{extax}]"


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


def _header(program, monitored=False, joint_targets=False, settings=None):
    """The ``!`` comment lines at the top of the module (``joint_targets``:
    some move goes to a jointtarget; `settings` for the arc welding lines)."""
    source, robot = common.source_and_robot(program)
    lines = [
        f"Generated by CadRobot (post-processor {NAME}) from {source}.",
        f"Robot: {robot}.",
        *textwrap.wrap(common.other_maker_note(program.robot, NAME, "ABB IRC5"), 70),
        "Units: mm; orientations are unit quaternions [q1,q2,q3,q4], q1 = w.",
        *(("Each wobjdata uframe is the calibration frame {B} in the robot base",
           "frame; this assumes the robot's world frame is its base frame.")
          if program.external is None else
          ("A fixed wobjdata's uframe is its calibration frame {B} in the world",
           "frame; a coordinated one's is set by the controller (External axes).")),
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
    if joint_targets:
        lines += [
            "Jointtargets are the joints CadRobot solved (deg, J3 as the",
            "controller counts it): air moves go there with MoveAbsJ.",
        ]
    if program.weld_runs():
        lines += _arc_header(program, settings)
    if program.external is not None:
        lines += _external_header(program, settings)
    return [INDENT + "! " + line for line in lines]


# --- arc welding (RobotWare Arc, option 633-4) ------------------------------------
# Syntax and record layouts: docs/controllers.md, ABB, "Welding" (plan issue22 b.1).

#: ``arc_units`` option: the controller's ARC_UNITS configuration instance decides the
#: units of the arc data (RobotWare 6.15 ``pARC_UNITS.cfg`` as read by a third party,
#: plan S4). Per quantity: (factor from our unit, decimals): length from mm, speed from
#: mm/s, wire feed from m/min.
ARC_UNITS = {
    "SI_UNITS": {"length": (1.0, 2), "speed": (1.0, 2), "wirefeed": (1000.0 / 60.0, 1),
                 "text": "length mm, speed mm/s, wire feed mm/s"},
    "WELD_UNITS": {"length": (1.0, 2), "speed": (1.0, 2), "wirefeed": (1.0, 2),
                   "text": "length mm, speed mm/s, wire feed m/min"},
    "US_UNITS": {"length": (1.0 / 25.4, 3), "speed": (60.0 / 25.4, 2),
                 "wirefeed": (1000.0 / 25.4, 1),
                 "text": "length inch, speed inch/min, wire feed inch/min"},
}
ARC_DATA = ("voltage_wirefeed", "job")

#: weavedata weave_shape of each pattern (batpartners DataType-WeaveData, plan S7):
#: 1 zigzag, 3 triangular, 4 circular (circular needs RobotWare 6: unverified). ABB has
#: no L weave.
WEAVE_SHAPES = {"zigzag": 1, "triangle": 3, "circle": 4}
#: Unverified: which weavedata component turns the weave plane about the travel
#: (weave_dir, weave_tilt or weave_ori, 0-based 8, 9, 10). The plan's reading: weave_ori.
WEAVE_ANGLE_FIELD = 10
#: Unverified: trackdata gains as percent (the public literal of plan S6 writes 50).
TRACK_GAIN_SCALE = 100.0

_ARC_INSTRUCTIONS = {
    (common.WELD_START, ir.LINEAR): "ArcLStart",
    (common.WELD_ON, ir.LINEAR): "ArcL", (common.WELD_ON, ir.CIRCULAR): "ArcC",
    (common.WELD_END, ir.LINEAR): "ArcLEnd", (common.WELD_END, ir.CIRCULAR): "ArcCEnd"}


@dataclass(frozen=True)
class _ArcKeys:
    """Keys in :attr:`_Data.values` of a run's seamdata, welddata, weavedata and
    trackdata (None: not written)."""

    seam: tuple
    weld: tuple
    weave: tuple = None
    track: tuple = None

    def __iter__(self):
        return iter((self.seam, self.weld, self.weave, self.track))


def _check_welds(program, settings):
    """Refuse weld runs and options RobotWare Arc instructions cannot carry.

    Raises
    ------
    PostError
        One line naming the weld (or the option) and the fix.
    """
    for path, run, what in common.checked_weld_runs(program):
        if settings.correction:
            raise PostError(f"{what}: path_correction (\\Corr) on RobotWare Arc instructions is "
                            "not verified: set path_correction=false for a program with welds.")
        common.check_weld_basics(path, run, "ABB RobotWare Arc", WEAVE_SHAPES, {
            "start": "ArcLStart", "arc": "\\Track", "laser": "\\Corr"})
        if settings.arc_data == "job" and not run.schedule.job_number:
            raise PostError(f"{what}: arc_data=job writes the power source's job, and its "
                            "schedule has none: give the schedule a job_number or use "
                            "arc_data=voltage_wirefeed.")


def _arc_value(value, quantity, settings):
    """A value in the controller's arc units (:data:`ARC_UNITS`), as text."""
    factor, decimals = ARC_UNITS[settings.arc_units][quantity]
    return compact(value * factor, decimals)


def _arcdata(voltage_v, wire_feed_m_min, job, settings):
    """arcdata ``[sched, mode, voltage, wirefeed, control, current, voltage2,
    wirefeed2, control2]``: voltage and wire feed, or only the job (``arc_data``)."""
    values = ["0"] * 9
    if settings.arc_data == "job":
        values[0] = str(job)
    else:
        values[2] = compact(voltage_v, 2)
        values[3] = _arc_value(wire_feed_m_min, "wirefeed", settings)
    return "[" + ",".join(values) + "]"


def _seamdata(schedule, settings):
    """seamdata: pre-flow, crater fill (time, arc), burn-back and post-flow; the
    ignition and heat phases 0 (their arc data all 0)."""
    zero_arc = "[" + ",".join(["0"] * 9) + "]"
    fill_arc = _arcdata(schedule.crater_voltage_v, schedule.crater_wire_feed_m_min,
                        schedule.job_number, settings)
    fields = ["0", compact(schedule.gas_preflow_s, 3), zero_arc, "0", "0", "0", "0", "0",
              zero_arc, "0", compact(schedule.crater_fill_s, 3), fill_arc,
              compact(schedule.burnback_s, 3), "0", zero_arc, compact(schedule.gas_postflow_s, 3)]
    return "[" + ",".join(fields) + "]"


def _welddata(schedule, settings, speed_mm_s=None):
    """welddata ``[weld_speed, org_weld_speed, main_arc, org_arc]``; the weld speed is
    the travel speed, or `speed_mm_s` (mm/s)."""
    main_arc = _arcdata(schedule.voltage_v, schedule.wire_feed_m_min, schedule.job_number,
                        settings)
    speed = _arc_value(schedule.travel_speed_mm_s if speed_mm_s is None else speed_mm_s,
                       "speed", settings)
    return f"[{speed},0,{main_arc},[{','.join(['0'] * 9)}]]"


def _weavedata(run, settings):
    """weavedata: shape, type 0 (geometric), cycle length, width (the circle's
    radius), height, dwells as travel along the seam, the weave angle."""
    weave, speed = run.weave, run.schedule.travel_speed_mm_s
    width = weave.width_mm / 2 if weave.pattern == "circle" else weave.width_mm
    height = weave.height if weave.pattern == "triangle" else 0.0
    fields = [str(WEAVE_SHAPES[weave.pattern]), "0"]
    fields += [_arc_value(v, "length", settings)
               for v in (weave.cycle_length_mm(speed), width, height,
                         *common.dwell_lengths_mm(run))]
    fields += ["0"] * 7
    fields[WEAVE_ANGLE_FIELD] = compact(weave.angle_deg, 2)
    return "[" + ",".join(fields) + "]"


def _trackdata(tracking, settings):
    """trackdata ``[track_system, store_path, max_corr, arctrack[9], reserved[7]]``:
    through-arc tracking (WeldGuide/arc sensing) with the lateral and height gains."""
    arctrack = ["0", compact(tracking.lateral_gain * TRACK_GAIN_SCALE, 1),
                compact(tracking.height_gain * TRACK_GAIN_SCALE, 1)] + ["0"] * 6
    return (f"[0,FALSE,{_arc_value(tracking.max_correction_mm, 'length', settings)},"
            f"[{','.join(arctrack)}],[{','.join(['0'] * 7)}]]")


def _arc_declarations(program, data, names, settings):
    """Declare each distinct arc datum once (LOCAL PERS: RobotWare Arc wants
    persistent references); record each run's keys in ``data.runs`` and, for a
    welded move slower than the travel speed (a corner slow-down), the key of a
    welddata at its speed in ``data.slow_welds``."""
    for path, run in program.weld_runs():
        keys = []
        for kind, prefix, literal in (
                ("seamdata", "sm", _seamdata(run.schedule, settings)),
                ("welddata", "wd", _welddata(run.schedule, settings)),
                ("weavedata", "wv", run.weave and _weavedata(run, settings)),
                ("trackdata", "tr", run.tracking.sensor == "arc"
                 and _trackdata(run.tracking, settings))):
            keys.append(_declare_arc(data, names, kind, prefix + run.name, literal)
                        if literal else None)
        data.runs[run.name] = _ArcKeys(*keys)
        for move in path.moves[run.start + 1:run.end + 1]:
            if move.speed_mm_s != run.schedule.travel_speed_mm_s:
                data.slow_welds[id(move)] = _declare_arc(
                    data, names, "welddata", "wd" + run.name,
                    _welddata(run.schedule, settings, move.speed_mm_s))


def _declare_arc(data, names, kind, name, literal):
    """The key of an arc datum, declared under a name made from `name` unless the
    same value is declared already."""
    key = ("arc", f"{kind} {literal}")
    if key not in data.values:
        name = names.add(name, name[:2])
        data.values[key] = (name, f"LOCAL PERS {kind} {name} := {literal};")
    return key


def _arc_instruction(move, role, arc, keys, data):
    """One ArcLStart/ArcL/ArcC/ArcLEnd/ArcCEnd instruction (without indentation).

    Parameters
    ----------
    move : Move
    role : str
        The move's weld role (:func:`common.weld_steps`).
    arc : _ArcKeys
    keys : tuple
        The move's point, speed and zone keys (:func:`_move_keys`).
    data : _Data
    """
    instruction = _ARC_INSTRUCTIONS[(role, move.kind)]
    points = ", ".join(data.name(*key) for key in keys[:-2])
    speed, zone = (data.name(*key) for key in keys[-2:])
    weave = f" \\Weave:={data.name(*arc.weave)}" if arc.weave else ""
    track = f" \\Track:={data.name(*arc.track)}" if arc.track else ""
    return (f"{instruction} {points}, {speed}, {data.name(*arc.seam)}, "
            f"{data.name(*arc.weld)}{weave}, {zone}, {data.tool} "
            f"\\WObj:={data.wobjs[move.frame]}{track};")


def _whole_runs(path, entries):
    """The entries of a path with each weld run's moves merged into one entry
    (runs that meet at a move, into one), so that splitting a long program never
    cuts a weld."""
    for run, start, end in reversed(common.weld_spans(path)):
        merged = entries[start:end + 1]
        entries[start:end + 1] = [_Entry(
            [line for entry in merged for line in entry.lines],
            tuple(dict.fromkeys(key for entry in merged for key in entry.keys)),
            moves=len(merged), weld=common.weld_what(path, run))]
    return entries


def _arc_header(program, settings):
    """Header lines of a program with welds: the system, the units, the arcdata
    components written, and each run's schedule."""
    components = ("voltage and wirefeed (sched, mode, control, current and the second set 0)"
                  if settings.arc_data == "voltage_wirefeed" else
                  "sched = the schedule's job number (the other components 0)")
    lines = [
        "Arc welding: RobotWare 6 (IRC5) with option 633-4 Arc; ArcLStart ignites",
        "at the seam start (fine), ArcL/ArcC weld, ArcLEnd/ArcCEnd fill the crater.",
        f"Arc data units {settings.arc_units} ({ARC_UNITS[settings.arc_units]['text']}):",
        "they must match the ARC_UNITS of the controller's arc configuration.",
        *textwrap.wrap(f"arcdata components written (option arc_data={settings.arc_data}): "
                       f"{components}.", 70),
    ]
    for _, run in program.weld_runs():
        lines += common.run_comment_lines(run)
    return lines


# --- external axes (issue 23) -------------------------------------------------------
# Syntax and sources: docs/controllers.md, "External axes: ABB and KUKA".

#: Logical external axes of a robtarget / jointtarget extjoint, in program order.
#: Unverified: that the controller's system parameters give the track and the
#: positioner these logical axes in this order (track first).
EXTAX_NAMES = tuple("eax_" + letter for letter in "abcdef")
#: Unverified: the mechanical unit names of the options' defaults; the controller's
#: system parameters name the units (public programs use STN1 for a positioner).
UNIT_DEFAULTS = {"positioner_unit": "STN1", "track_unit": "TRACK_1"}


def _unit_option(options, key):
    """A mechanical unit's name option: a RAPID identifier (``ActUnit`` takes it)."""
    value = options.get(key, UNIT_DEFAULTS[key])
    if not isinstance(value, str) or not is_identifier(value):
        raise PostError(f"{key} must be the mechanical unit's name in the controller's system "
                        f"parameters, a RAPID identifier such as {UNIT_DEFAULTS[key]}, got "
                        f"{value!r}.")
    return value


def _external(program, settings, names):
    """The mechanical units main activates and each target's extjoint text.

    Returns
    -------
    (tuple of str, dict of str to str)
        Units, track first (none without external axes); ``{target name:
        "[v1,...,9E+09]"}`` (linear axes mm, 3 decimals; rotary deg, 4).

    Raises
    ------
    PostError
        A unit name RAPID or the module already uses, or bad axis values.
    """
    external = program.external
    if external is None:
        return (), {}
    values = common.external_values(program, len(EXTAX_NAMES), "ABB RAPID")
    units = []
    for mechanism, key in ((external.track, "track_unit"), (external.positioner,
                                                            "positioner_unit")):
        if mechanism is None:
            continue
        unit = getattr(settings, key)
        if names.is_taken(unit):
            raise PostError(f"{key} {unit} is a name RAPID or this module uses already: give "
                            f"{mechanism.label}'s mechanical unit name as the controller has it.")
        units.append(names.add(unit, "M"))
    unused = ["9E+09"] * (len(EXTAX_NAMES) - len(external.axes()))
    extax = {name: "[" + ",".join(common.external_texts(program, v, 3, 4) + unused) + "]"
             for name, v in values.items()}
    return tuple(units), extax


def _external_header(program, settings):
    """Header lines of a program with external axes: the axes, the units, the
    coordinated work objects and the calibration the controller must hold."""
    external = program.external
    lines = ["External axes: robtarget and jointtarget extax, 9E+09 where unused:"]
    lines += ["  " + line for line in common.external_axis_lines(program, EXTAX_NAMES)]
    text = []
    if external.track is not None:
        text.append(f"The track {external.track.label} is mechanical unit {settings.track_unit} "
                    "(option track_unit). The world frame is the robot base with the track at "
                    "0: fixed work objects are in it.")
    if external.positioner is not None:
        positioner = external.positioner
        T_w_base = common.in_world(external, positioner.T_u_base)
        text.append(
            f"The positioner {positioner.label} is mechanical unit {settings.positioner_unit} "
            "(option positioner_unit). The work objects it carries are coordinated with it "
            f'(robhold FALSE, ufprog FALSE, ufmec "{settings.positioner_unit}"): the '
            "controller moves their user frame with the unit, and their object frame is the "
            "work frame in the positioner's flange. The controller's calibration of the unit "
            f"(system parameters, which a program cannot set) must match CadRobot's: its base "
            f"frame in the world {_pose(T_w_base)}, its flange at axis values 0 in that base "
            f"{_pose(positioner.fk(np.zeros(len(positioner.axes))))}.")
    text.append("main activates the units (ActUnit) before the first move and deactivates "
                "them (DeactUnit) after the last.")
    return lines + [line for paragraph in text for line in textwrap.wrap(paragraph, 70)]
