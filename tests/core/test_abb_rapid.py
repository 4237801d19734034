"""Tests of the ABB RAPID post-processor (posts/abb_rapid.py).

The generated module is compared with golden files, checked by the
independent ``rapidchecker`` grammar and format checker, and its robtargets
are parsed back and compared with poses computed here with scipy.

To rewrite the golden files after a reviewed change of the output:
``CADROBOT_UPDATE_GOLDEN=1 python3 -m pytest tests/core/test_abb_rapid.py``.
"""

import dataclasses
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from CadRobotWB.core import program as ir
import post_programs  # noqa: E402
from CadRobotWB.errors import PostError
from CadRobotWB.posts import abb_rapid
from CadRobotWB.robots.kinematics import models
from CadRobotWB.robots.motion import configuration

from rapid_check import assert_rapid_ok, needs_rapidchecker

GOLDEN_DIR = Path(__file__).parent / "golden"

ROBTARGET_RE = re.compile(
    r"^\s*LOCAL CONST robtarget (\w+) := "
    r"\[\[([^\]]*)\],\[([^\]]*)\],\[([^\]]*)\],\[([^\]]*)\]\];$",
    re.MULTILINE)


# --- programs built by hand ---------------------------------------------------

def pose(rotvec_deg=(0, 0, 0), position=(0, 0, 0), euler_xyz_deg=None):
    """4x4 transform from a rotation vector (deg) or extrinsic xyz angles."""
    T = np.eye(4)
    if euler_xyz_deg is not None:
        T[:3, :3] = Rotation.from_euler("xyz", euler_xyz_deg,
                                        degrees=True).as_matrix()
    else:
        T[:3, :3] = Rotation.from_rotvec(rotvec_deg, degrees=True).as_matrix()
    T[:3, 3] = position
    return T


# Torch pointing down (+Z of the tool into the table), as a rotation vector in degrees.
DOWN = (180, 0, 0)


def two_frame_program():
    """The shared two-frame program (a custom speed of 12.5 mm/s, zones 0.3 = ABB z0,
    10 = z10, 2.5 custom and 0 = fine)."""
    return post_programs.two_frame_program("ABB_IRB2400")


def minimal_program(move_kind=ir.LINEAR, via=None, frame="B", name="P"):
    return post_programs.minimal_program("ABB_IRB2400", move_kind, via, frame, name)


def export_text(program, options=None):
    files = abb_rapid.export(program, options or {})
    assert len(files) == 1
    return files[0][1]


# --- rapidchecker -------------------------------------------------------------

def configured_program():
    """two_frame_program with the table 100 mm higher (the IRB 2400 reaches its tilted
    targets there within its J3 limit, J3 = q2 + q3 <= 65 deg) and every target's joints
    solved."""
    program = two_frame_program()
    table = program.frames["Table"]
    T_r_b = np.array(table.T_r_b, dtype=float)
    T_r_b[2, 3] += 100.0
    program.frames["Table"] = dataclasses.replace(table, T_r_b=T_r_b)
    configuration.solve_program(program, models.model(program.robot))
    return program


@needs_rapidchecker
@pytest.mark.parametrize("build", [two_frame_program, minimal_program, configured_program])
def test_every_module_passes_rapidchecker(build):
    assert_rapid_ok(export_text(build()))


@needs_rapidchecker
def test_module_with_renamed_identifiers_passes_rapidchecker():
    assert_rapid_ok(export_text(awkward_names_program()))


@needs_rapidchecker
@pytest.mark.parametrize("old, new", [
    ("MODULE Cell", "module Cell"),                       # lowercase keyword
    ("ConfL \\Off;", "ConfL \\Off"),                      # missing ';'
    ("    ConfJ \\Off;", "   ConfJ \\Off;"),              # bad indentation
    ("ENDPROC", "ENDPROC "),                              # trailing space
    ("ENDMODULE", "ENDMODUL"),                            # broken grammar
    ("PROC main()", "\n\n\n  PROC main()"),               # too many blank lines
])
def test_rapidchecker_rejects_broken_module(old, new):
    text = export_text(two_frame_program())
    assert old in text
    broken = text.replace(old, new, 1)
    with pytest.raises(AssertionError, match="rapidchecker"):
        assert_rapid_ok(broken)


@needs_rapidchecker
def test_rapidchecker_command_line(tmp_path):
    """``python -m rapidchecker`` agrees: exit 0 for ours, 1 when broken."""
    good = tmp_path / "Cell.mod"
    bad = tmp_path / "Broken.mod"
    text = export_text(two_frame_program())
    good.write_text(text)
    bad.write_text(text.replace("MoveL", "movel;", 1))
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    for path, expected in ((good, 0), (bad, 1)):
        run = subprocess.run([sys.executable, "-m", "rapidchecker", str(path)],
                             capture_output=True, text=True, env=env,
                             cwd=tmp_path)
        assert run.returncode == expected, run.stdout + run.stderr


# --- golden files -------------------------------------------------------------

@pytest.mark.parametrize("name, build", [
    ("abb_rapid_two_frames.mod", two_frame_program),
    ("abb_rapid_minimal.mod", minimal_program),
    ("abb_rapid_configured.mod", configured_program),
])
def test_golden_output(name, build):
    text = export_text(build())
    golden = GOLDEN_DIR / name
    if os.environ.get("CADROBOT_UPDATE_GOLDEN"):
        golden.parent.mkdir(exist_ok=True)
        golden.write_text(text, newline="\n")
    assert golden.exists(), f"missing {golden}; see this file's docstring"
    assert text == golden.read_text()


def test_export_is_deterministic_and_named_after_program():
    program = two_frame_program()
    first = abb_rapid.export(program, {})
    assert first == abb_rapid.export(program, {})
    assert [f for f, _ in first] == ["Cell.mod"]
    assert abb_rapid.export(program, None) == first


# --- robtargets parsed back ---------------------------------------------------

def quaternion_wxyz(R):
    """Independent reference: scipy gives (x, y, z, w)."""
    x, y, z, w = Rotation.from_matrix(R).as_quat()
    return np.array([w, x, y, z])


def parse_robtargets(text):
    out = {}
    for name, pos, quat, conf, axes in ROBTARGET_RE.findall(text):
        out[name] = (np.array(pos.split(","), float),
                     np.array(quat.split(","), float), conf, axes)
    return out


def test_robtargets_recover_positions_and_quaternions():
    program = two_frame_program()
    text = export_text(program)
    parsed = parse_robtargets(text)
    targets = {t.name: t for t in program.targets()}
    assert sorted(parsed) == sorted(targets)
    for name, (position, q, conf, axes) in parsed.items():
        T = targets[name].T_b_t
        np.testing.assert_allclose(position, T[:3, 3], atol=1e-3)
        q_ref = quaternion_wxyz(T[:3, :3])
        error = min(np.abs(q - q_ref).max(), np.abs(q + q_ref).max())
        assert error <= 1e-6, (name, q, q_ref)
        assert abs(np.linalg.norm(q) - 1.0) < 2e-6
        assert conf == "0,0,0,0"
        assert axes == ",".join(["9E+09"] * 6)


def test_number_format():
    text = export_text(two_frame_program())
    assert "-0.000" not in text
    for line in text.splitlines():
        m = ROBTARGET_RE.match(line)
        if m:
            assert all(re.fullmatch(r"-?\d+\.\d{3}", v)
                       for v in m.group(2).split(","))
            assert all(re.fullmatch(r"-?\d\.\d{6}", v)
                       for v in m.group(3).split(","))


# --- data declarations and instructions ---------------------------------------

def test_tool_and_work_objects():
    text = export_text(two_frame_program())
    q_tool = quaternion_wxyz(pose((0, 30, 0))[:3, :3])
    m = re.search(r"LOCAL PERS tooldata Torch := \[TRUE,\[\[([^\]]*)\],\[([^\]]*)\]\],"
                  r"\[1\.5,\[0,0,120\],\[1,0,0,0\],0,0,0\]\];", text)
    assert m, text
    np.testing.assert_allclose(np.array(m.group(1).split(","), float),
                               [10, 0, 250], atol=1e-3)
    np.testing.assert_allclose(np.array(m.group(2).split(","), float),
                               q_tool, atol=1e-6)

    program = two_frame_program()
    for name in ("Table", "Fixture"):
        m = re.search(rf'LOCAL PERS wobjdata {name} := \[FALSE,TRUE,"",'
                      r"\[\[([^\]]*)\],\[([^\]]*)\]\],"
                      r"\[\[0,0,0\],\[1,0,0,0\]\]\];", text)
        assert m, name
        T_r_b = program.frames[name].T_r_b
        np.testing.assert_allclose(np.array(m.group(1).split(","), float),
                                   T_r_b[:3, 3], atol=1e-3)
        q = np.array(m.group(2).split(","), float)
        q_ref = quaternion_wxyz(T_r_b[:3, :3])
        assert min(np.abs(q - q_ref).max(), np.abs(q + q_ref).max()) <= 1e-6


def test_speeds_and_zones():
    text = export_text(two_frame_program())
    # 12.5 mm/s is not predefined: declared like ABB's vN.
    assert "LOCAL CONST speeddata v12_5 := [12.5,500,5000,1000];" in text
    # 100 mm/s, z10 and z0 (0.3 mm) are ABB predefined: used, not declared.
    assert "speeddata v100" not in text
    assert "zonedata z10 " not in text and "zonedata z0 " not in text
    # 2.5 mm is not predefined: [FALSE, r, 1.5r, 1.5r, 0.15r, 1.5r, 0.15r].
    assert ("LOCAL CONST zonedata z2_5 := [FALSE,2.5,3.75,3.75,0.375,3.75,0.375];"
            in text)
    assert text.count("speeddata") == 1 and text.count("zonedata") == 1


def test_instructions():
    text = export_text(two_frame_program())
    lines = [line.strip() for line in text.splitlines()]
    assert lines[0] == "MODULE Cell" and lines[-1] == "ENDMODULE"
    main = lines[lines.index("PROC main()"):]
    assert main[1:5] == ["ConfJ \\Off;", "ConfL \\Off;", "Seam;", "Contour;"]
    expected = [
        "MoveJ p1, v100, z10, Torch \\WObj:=Table;",
        "MoveL p2, v12_5, z0, Torch \\WObj:=Table;",
        "MoveL p3, v12_5, z0, Torch \\WObj:=Table;",
        "MoveL p4, v12_5, z0, Torch \\WObj:=Table;",
        "MoveC p5, p6, v12_5, fine, Torch \\WObj:=Table;",
        "MoveL p7, v100, fine, Torch \\WObj:=Table;",
        "MoveJ q1, v100, z10, Torch \\WObj:=Fixture;",
        "MoveL q2, v12_5, z2_5, Torch \\WObj:=Fixture;",
        "MoveL q3, v12_5, fine, Torch \\WObj:=Fixture;",
        "MoveL q4, v100, fine, Torch \\WObj:=Fixture;",
    ]
    assert [line for line in lines if line.startswith("Move")] == expected
    for comment in ("! segment 1: line Sketch.Edge1", "! segment 2: reorient",
                    "! segment 2: arc Sketch.Edge2", "! Path: Weld seam",
                    "! Robot: ABB_IRB2400.", "! Generated by CadRobot "
                    "(post-processor abb_rapid) from demo.FCStd / Cell."):
        assert comment in lines


def test_header_states_units_and_frames():
    text = export_text(two_frame_program())
    header = text.split("PERS")[0]
    assert "Units: mm" in header and "q1 = w" in header
    assert "{B} in the robot base" in header and "world frame" in header


def test_module_name_option_names_the_file_too():
    program = two_frame_program()
    files = abb_rapid.export(program, {"module_name": "Weld1"})
    assert files[0][0] == "Weld1.mod"
    assert files[0][1].startswith("MODULE Weld1\n")
    for bad in ("1abc", "MODULE", "a b", "x" * 33, "tool0", "CON", "lpt1", 3):
        with pytest.raises(PostError, match="module_name"):
            abb_rapid.export(program, {"module_name": bad})


# --- identifiers ----------------------------------------------------------------

def awkward_names_program():
    """Names RAPID cannot take as they are."""
    program = minimal_program(name="3D_Cell")
    program.tool.name = "tool0"                       # predefined
    program.frames = {"wobj0": ir.WorkFrame("wobj0", np.eye(4), np.eye(4))}
    long_a = "A_very_long_target_name_made_by_a_generator_1"
    long_b = "A_very_long_target_name_made_by_a_generator_2"
    moves = [
        ir.Move(ir.LINEAR, ir.Target(long_a, pose(DOWN, (0, 0, 0))), 10, 0,
                "wobj0"),
        ir.Move(ir.LINEAR, ir.Target(long_b, pose(DOWN, (1, 0, 0))), 10, 0,
                "wobj0"),
        ir.Move(ir.LINEAR, ir.Target("v12_5", pose(DOWN, (2, 0, 0))), 12.5,
                0, "wobj0"),
        ir.Move(ir.LINEAR, ir.Target("P1", pose(DOWN, (3, 0, 0))), 10, 0,
                "wobj0"),
        ir.Move(ir.LINEAR, ir.Target("p1", pose(DOWN, (4, 0, 0))), 10, 0,
                "wobj0"),
    ]
    program.paths = [ir.ProgramPath("PROC", "Proc", moves),
                     ir.ProgramPath("main", "Main", [])]
    return program


def declared_identifiers(text):
    names = re.findall(r"^\s*LOCAL (?:PERS|CONST) \w+ (\w+) :=", text, re.MULTILINE)
    names += re.findall(r"^\s*PROC (\w+)\(\)", text, re.MULTILINE)
    names += re.findall(r"^MODULE (\w+)", text, re.MULTILINE)
    return names


def test_identifiers_are_valid_unique_and_short():
    text = export_text(awkward_names_program())
    names = declared_identifiers(text)
    assert len(names) == 12
    assert len({n.upper() for n in names}) == len(names)  # case-insensitive
    for name in names:
        assert abb_rapid.is_identifier(name), name
    for predefined in ("tool0", "wobj0"):
        assert predefined not in names
    assert "MODULE M3D_Cell" in text
    assert "PROC main()" in text and "PROC main_2()" in text


def test_same_target_used_twice_is_declared_once():
    program = minimal_program()
    move = program.paths[0].moves[0]
    program.paths[0].moves.append(ir.Move(ir.LINEAR, move.target, 10, 0, "B"))
    text = export_text(program)
    assert text.count("LOCAL CONST robtarget t1 :=") == 1
    assert text.count("MoveL t1,") == 2


# --- robot configurations -------------------------------------------------------

def test_confdata_comes_from_the_joints_and_is_monitored():
    program = configured_program()
    text = export_text(program, {"joint_targets": False})
    targets = {t.name: t for t in program.targets()}
    parsed = parse_robtargets(text)
    robot = models.model(program.robot)
    for name, (_, _, conf, _) in parsed.items():
        expected = configuration.abb_confdata(targets[name].joints_deg, robot)
        assert tuple(int(v) for v in conf.split(",")) == expected
    # The seam's J4 is near -50 (quadrant -1), the contour's J6 beyond 180 (quadrant 2).
    assert parsed["p1"][2] == "-1,-1,1,0" and parsed["q1"][2] == "0,0,2,0"
    lines = [line.strip() for line in text.splitlines()]
    main = lines[lines.index("PROC main()"):]
    assert main[1:3] == ["ConfJ \\On;", "ConfL \\On;"]
    assert "\\Off" not in text
    assert "configurations are monitored (ConfJ \\On, ConfL \\On)." in text


def test_one_target_without_joints_turns_monitoring_off():
    program = configured_program()
    program.paths[1].moves[2].target.joints_deg = None          # q3
    text = export_text(program)
    parsed = parse_robtargets(text)
    assert parsed["q3"][2] == "0,0,0,0" and parsed["q2"][2] == "0,0,2,0"
    lines = [line.strip() for line in text.splitlines()]
    main = lines[lines.index("PROC main()"):]
    assert main[1:3] == ["ConfJ \\Off;", "ConfL \\Off;"]
    assert "not monitored (ConfJ \\Off, ConfL \\Off)." in text


def test_unknown_robot_writes_no_confdata():
    program = configured_program()
    program.robot = "SOME_OTHER_ROBOT"
    with pytest.raises(PostError, match="joint_targets=false"):
        export_text(program)        # its joint convention is unknown
    text = export_text(program, {"joint_targets": False})
    assert {conf for _, _, conf, _ in parse_robtargets(text).values()} == {"0,0,0,0"}
    assert "ConfL \\Off;" in text


@needs_rapidchecker
def test_rapidchecker_rejects_a_broken_configured_module():
    text = export_text(configured_program())
    assert_rapid_ok(text)
    with pytest.raises(AssertionError, match="rapidchecker"):
        assert_rapid_ok(text.replace("ConfL \\On;", "ConfL \\On", 1))


# --- live path correction (seam tracking on the controller) -------------------

@needs_rapidchecker
def test_path_correction_corrects_only_the_moves_along_the_seam():
    text = export_text(two_frame_program(), {"path_correction": True, "correction_rate_hz": 4})
    assert_rapid_ok(text)
    lines = [line.strip() for line in text.splitlines()]
    corrected = [line.split()[1].rstrip(",") for line in lines if line.endswith("\\Corr;")]
    # Segment moves, the reorientation and the arc; not approach, entry or retract.
    assert corrected == ["p3", "p4", "p5", "q3"]
    seam = lines[lines.index("PROC Seam()"):lines.index("PROC Contour()")]
    order = [line for line in seam if line.startswith(("CorrCon", "ITimer", "IDelete", "CorrDiscon",
                                                       "MoveL p2", "MoveL p3", "MoveC", "MoveL p7"))]
    assert order == ["MoveL p2, v12_5, z0, Torch \\WObj:=Table;", "CorrCon cdSensor;",
                     "ITimer 0.25, irSensor;", "MoveL p3, v12_5, z0, Torch \\WObj:=Table \\Corr;",
                     "MoveC p5, p6, v12_5, fine, Torch \\WObj:=Table \\Corr;",
                     "IDelete irSensor;", "CorrDiscon cdSensor;",
                     "MoveL p7, v100, fine, Torch \\WObj:=Table;"]
    assert "CorrWrite cdSensor, corrSensor;" in lines and "TRAP tSensorCorrection" in lines


def test_without_the_option_nothing_is_corrected():
    assert "Corr" not in export_text(two_frame_program())


# --- options --------------------------------------------------------------------

@pytest.mark.parametrize("options, word", [
    ({"path_correction": "maybe"}, "path_correction"),      # a typo must not switch it on
    ({"path_correction": 1}, "path_correction"),
    ({"correction_rate_hz": float("nan")}, "correction_rate_hz"),
    ({"correction_rate_hz": 0}, "correction_rate_hz"),
    ({"correction_rate_hz": 1000}, "correction_rate_hz"),
    ({"correction_rate_hz": "5"}, "correction_rate_hz"),
    ({"joint_targets": "yes"}, "joint_targets"),
    ({"max_lines": 10}, "max_lines"),
    ({"max_lines": 2.5}, "max_lines"),
    ({"max_lines": True}, "max_lines"),
    ({"no_such_option": 3}, "no_such_option"),
    ({"part_folder": ""}, "part_folder"),
    ({"part_folder": 'HOME:/a"b'}, "part_folder"),
    ({"part_folder": "HOME:\\parts"}, "part_folder"),
    ({"part_folder": "HOME:/" + "x" * 80}, "part_folder"),
    ({"part_folder": 5}, "part_folder"),
])
def test_bad_options_are_refused_by_name(options, word):
    with pytest.raises(PostError, match=word):
        abb_rapid.export(two_frame_program(), options)


def test_every_option_is_declared():
    assert set(abb_rapid.OPTIONS) == {"module_name", "path_correction", "correction_rate_hz",
                                      "joint_targets", "max_lines", "part_folder",
                                      "arc_units", "arc_data", "positioner_unit", "track_unit"}
    assert all(isinstance(text, str) and text for text in abb_rapid.OPTIONS.values())


# --- module and file names --------------------------------------------------------

@pytest.mark.parametrize("label", ["PROC", "MODULE", "main", "Main", "CON", "3D cell", "Cell"])
def test_module_name_equals_file_name(label):
    program = minimal_program(name=label)
    (name, text), = abb_rapid.export(program, {})
    module = re.match(r"MODULE (\w+)\n", text).group(1)
    assert name == module + ".mod"
    assert abb_rapid.is_identifier(module) and module.upper() not in ("PROC", "MODULE", "MAIN",
                                                                       "CON")


def test_no_data_is_global():
    """Every data declaration is LOCAL: another loaded module cannot shadow it (a global
    PERS of the same name elsewhere would give this module that module's value)."""
    for text in (export_text(configured_program()),
                 export_text(two_frame_program(), {"path_correction": True})):
        declarations = [line.strip() for line in text.splitlines()
                        if re.match(r"\s*(LOCAL )?(PERS|CONST|VAR) ", line)]
        assert declarations and all(line.startswith("LOCAL ") for line in declarations)


# --- zones ------------------------------------------------------------------------

#: ABB's predefined zonedata, TCP zone radius (pzone_tcp, mm), from the RAPID reference
#: (zonedata, "Predefined data"): z0 is 0.3 mm.
ABB_ZONES_MM = {"z0": 0.3, "z1": 1, "z5": 5, "z10": 10, "z15": 15, "z20": 20, "z30": 30,
                "z40": 40, "z50": 50, "z60": 60, "z80": 80, "z100": 100, "z150": 150,
                "z200": 200, "fine": 0}


@pytest.mark.parametrize("asked", [0.3, 0.29996, 0.30004, 0.2, 0.31, 1.0, 1.5, 0.00004, 7.0,
                                   10.0, 199.99999, 250.0, 0.0])
def test_zones_are_never_bigger_than_asked(asked):
    program = minimal_program()
    program.paths[0].moves[0].zone_mm = asked
    text = export_text(program)
    zone = re.search(r"MoveL t1, v10, (\w+), ", text).group(1)
    declared = re.search(rf"LOCAL CONST zonedata {zone} := \[FALSE,([\d.]+),", text)
    radius = float(declared.group(1)) if declared else ABB_ZONES_MM[zone]
    assert radius <= asked and asked - radius < 1e-4, (zone, radius)


# --- joint targets ----------------------------------------------------------------

JOINTTARGET_RE = re.compile(r"^\s*LOCAL CONST jointtarget (\w+) := \[\[([^\]]*)\],\[([^\]]*)\]\];$",
                            re.MULTILINE)


def parse_jointtargets(text):
    return {name: (np.array(joints.split(","), float), axes)
            for name, joints, axes in JOINTTARGET_RE.findall(text)}


def test_air_moves_go_to_jointtargets_that_reach_the_robtarget_pose():
    """jointtarget -> model joints -> fk -> TCP in {B} is the robtarget written without
    joint targets (two independent routes to one pose)."""
    program = configured_program()
    text = export_text(program)
    cartesian = parse_robtargets(export_text(program, {"joint_targets": False}))
    jointtargets = parse_jointtargets(text)
    assert sorted(jointtargets) == ["p1", "q1"]
    moves = [line.strip() for line in text.splitlines() if line.strip().startswith("Move")]
    assert [m.split(",")[0] for m in moves if m.startswith("MoveAbsJ")] == ["MoveAbsJ p1",
                                                                          "MoveAbsJ q1"]
    assert not any(m.startswith("MoveJ ") for m in moves)
    robot = models.model(program.robot)
    frames = {"p1": program.frames["Table"], "q1": program.frames["Fixture"]}
    for name, (joints, axes) in jointtargets.items():
        assert axes == ",".join(["9E+09"] * 6)
        T_r_f = robot.fk(robot.model_joints(joints)[None])[0]
        T_b_t = np.linalg.inv(frames[name].T_r_b) @ T_r_f @ program.tool.T_f_t
        position, q, _, _ = cartesian[name]
        np.testing.assert_allclose(T_b_t[:3, 3], position, atol=0.01)
        q_fk = quaternion_wxyz(T_b_t[:3, :3])
        assert min(np.abs(q_fk - q).max(), np.abs(q_fk + q).max()) < 1e-5
    # IRB 2400 J3 is counted against the base: J3 = q2 + q3 of the model.
    target = {t.name: t for t in program.targets()}["p1"]
    q = target.joints_deg
    np.testing.assert_allclose(jointtargets["p1"][0], [q[0], q[1], q[1] + q[2], *q[3:]],
                               atol=1e-4)


def test_joint_targets_off_writes_movej_to_robtargets():
    text = export_text(configured_program(), {"joint_targets": False})
    assert "MoveAbsJ" not in text and "jointtarget" not in text
    assert "MoveJ p1, v100, z10, Torch \\WObj:=Table;" in text


def test_a_target_without_joints_stays_a_movej():
    program = configured_program()
    program.paths[0].moves[0].target.joints_deg = None
    text = export_text(program)
    assert "MoveJ p1, v100" in text and "MoveAbsJ q1, v100" in text


# --- long programs ----------------------------------------------------------------

def statements(files):
    """Every move of a set of modules, in execution order from main, with each target
    argument replaced by its declared value: ``[(instruction, values...), ...]``."""
    texts = dict(files)
    main = texts[files[0][0]]
    declared = {}
    order = []
    for name, text in files:
        module = re.match(r"MODULE (\w+)\n", text).group(1)
        assert name == module + ".mod"
        values = dict(re.findall(r"^\s*LOCAL CONST \w+ (\w+) := (.*);$", text, re.MULTILINE))
        procs = re.findall(r"^  PROC (\w+)\(\)\n(.*?)^  ENDPROC", text, re.MULTILINE | re.DOTALL)
        for proc, body in procs:
            declared[proc] = [tuple(values.get(a.strip(), a.strip()) for a in
                                    re.split(r"[ ,]+", line.strip().rstrip(";"), maxsplit=0)[:4])
                              for line in body.splitlines() if line.strip().startswith("Move")]
    calls = re.search(r"PROC main\(\)\n(.*?)ENDPROC", main, re.DOTALL).group(1).split()
    for call in calls[2:]:                       # after ConfJ, ConfL
        order += declared[call.rstrip(";")] if call.rstrip(";") in declared else []
    return order


def test_a_program_longer_than_max_lines_is_split_in_order():
    program = post_programs.long_program("ABB_IRB2400", 300)
    whole = abb_rapid.export(program, {})
    assert len(whole) == 1
    limit = 200
    files = abb_rapid.export(program, {"max_lines": limit})
    assert [name for name, _ in files] == ["Long.mod"] + [f"Long_{k}.mod"
                                                          for k in range(1, len(files))]
    assert len(files) >= 4
    for name, text in files:
        assert len(text.splitlines()) <= limit, name
    main = files[0][1]
    calls = re.search(r"PROC main\(\)\n(.*?)  ENDPROC", main, re.DOTALL).group(1).split()
    assert calls == ["ConfJ", "\\On;", "ConfL", "\\On;"] + [f"Long_{k}_run;"
                                                           for k in range(1, len(files))]
    # the same moves to the same values, in the same order
    split_moves, whole_moves = statements(files), statements(whole)
    assert len(whole_moves) == 300 and split_moves == whole_moves


def test_a_program_that_fits_is_not_split():
    program = post_programs.long_program("ABB_IRB2400", 60)
    (_, text), = abb_rapid.export(program, {})
    lines = len(text.splitlines())
    assert len(abb_rapid.export(program, {"max_lines": lines})) == 1
    assert len(abb_rapid.export(program, {"max_lines": lines - 1})) > 1


def test_a_split_refuses_what_it_cannot_do():
    program = post_programs.long_program("ABB_IRB2400", 60)
    with pytest.raises(PostError, match="path correction.*max_lines"):
        abb_rapid.export(program, {"max_lines": 60, "path_correction": True})
    program.frames.update({f"F{i}": program.frames["B"] for i in range(60)})
    with pytest.raises(PostError, match="max_lines=60 is too small"):
        abb_rapid.export(program, {"max_lines": 60})


@needs_rapidchecker
def test_every_part_passes_rapidchecker():
    program = post_programs.long_program("ABB_IRB2400", 120)
    files = abb_rapid.export(program, {"max_lines": 100})
    assert len(files) >= 4
    for name, text in files:
        assert_rapid_ok(text)


def test_fifty_thousand_moves_export_in_seconds():
    import time
    program = post_programs.long_program("ABB_IRB2400", 50000)
    start = time.perf_counter()
    files = abb_rapid.export(program, {})
    seconds = time.perf_counter() - start
    assert seconds < 60, seconds
    assert [name for name, _ in files] == ["Long.mod"] + [f"Long_{k}.mod"
                                                          for k in range(1, len(files))]
    for name, text in files:
        assert len(text.splitlines()) <= abb_rapid.DEFAULT_MAX_LINES, name
    moves = statements(files)
    assert len(moves) == 50000
    assert moves[0][0] == "MoveAbsJ" and moves[-1][0] == "MoveL"


@needs_rapidchecker
@pytest.mark.skipif(not os.environ.get("CADROBOT_SLOW"),
                    reason="rapidchecker reads about 40 lines/s: the 50,000-move program's "
                           "100,000 lines took 47 min here; set CADROBOT_SLOW=1 to run it")
def test_every_file_of_fifty_thousand_moves_passes_rapidchecker():
    files = abb_rapid.export(post_programs.long_program("ABB_IRB2400", 50000), {})
    for name, text in files:
        assert_rapid_ok(text)


def test_a_target_used_by_a_joint_and_a_linear_move_gets_both_data():
    program = configured_program()
    seam = program.paths[0].moves
    seam.append(ir.Move(ir.LINEAR, seam[0].target, 100.0, 0.0, "Table"))   # back to p1
    text = export_text(program)
    assert "MoveAbsJ p1_j, v100, z10" in text and "MoveL p1, v100, fine" in text
    assert set(parse_jointtargets(text)) == {"p1_j", "q1"} and "p1" in parse_robtargets(text)


def _mirrored(T):
    T = np.array(T, dtype=float)
    T[:3, 0] *= -1.0
    return T


@pytest.mark.parametrize("spoil, word", [
    (lambda p: setattr(p.tool, "T_f_t", np.diag([2.0, 2.0, 2.0, 1.0])), "Tool 'Torch'"),
    (lambda p: setattr(p.tool, "T_f_t", _mirrored(p.tool.T_f_t)), "Tool 'Torch'"),
    (lambda p: setattr(p.tool, "cog_mm", np.array([0.0, np.nan, 1.0])), "centre of gravity"),
    (lambda p: p.frames.__setitem__("Table", dataclasses.replace(
        p.frames["Table"], T_r_b=p.frames["Table"].T_r_b @ np.array(
            [[1, 0.2, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]]))), "Work frame 'Table'"),
    (lambda p: setattr(p.paths[1].moves[2].target, "T_b_t",
                       _mirrored(p.paths[1].moves[2].target.T_b_t)), "Target 'q3'"),
    (lambda p: setattr(p.paths[1].moves[0].target, "joints_deg", np.full(6, np.nan)),
     "Target 'q1'"),
])
def test_poses_that_are_not_rigid_are_refused(spoil, word):
    program = configured_program()
    spoil(program)
    with pytest.raises(PostError, match=word):
        export_text(program)


@needs_rapidchecker
def test_parts_loaded_from_a_folder_are_loaded_run_and_unloaded_in_order():
    program = post_programs.long_program("ABB_IRB2400", 120)
    together = abb_rapid.export(program, {"max_lines": 100})
    files = abb_rapid.export(program, {"max_lines": 100, "part_folder": "HOME:/CadRobot"})
    assert files[1:] == together[1:]                      # the same parts
    main = files[0][1]
    assert_rapid_ok(main)
    assert 'LOCAL CONST string partFolder := "HOME:/CadRobot";' in main
    body = re.search(r"PROC main\(\)\n(.*?)  ENDPROC", main, re.DOTALL).group(1).split("\n")
    expected = ["ConfJ \\On;", "ConfL \\On;"]
    for name, _ in files[1:]:
        module = name[:-len(".mod")]
        expected += [f'Load \\Dynamic, partFolder \\File:="{name}";', f'%"{module}_run"%;',
                     f'UnLoad partFolder \\File:="{name}";']
    assert [line.strip() for line in body if line.strip()] == expected
    for name, text in files[1:]:
        assert f"PROC {name[:-len('.mod')]}_run()" in text
