"""Tests of the KUKA KRL post-processor (posts/kuka_krl.py).

The .src/.dat pair is compared with golden files; its FRAME and E6POS data
are parsed back here and turned into poses with an independent
implementation of KUKA's A, B, C convention (``robodk.robomath``, from PyPI)
and with scipy, and compared with the program's poses in the robot base
frame.

To rewrite the golden files after a reviewed change of the output:
``CADROBOT_UPDATE_GOLDEN=1 python3 -m pytest tests/core/test_kuka_krl.py``.
"""

import os
import re
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from CadRobotWB.core import program as ir
import post_programs  # noqa: E402
from post_programs import DOWN, pose  # noqa: E402
from CadRobotWB.errors import PostError
from CadRobotWB.posts import kuka_krl
from CadRobotWB.robots.catalog import catalog
from CadRobotWB.robots.kinematics import models
from CadRobotWB.robots.motion import configuration

from robodk_check import ROBODK_MISSING, needs_robodk, robomath  # noqa: E402,F401

GOLDEN_DIR = Path(__file__).parent / "golden"


# --- programs built by hand ---------------------------------------------------



def two_frame_program():
    return post_programs.two_frame_program("KUKA_KR16")


def configured_program():
    """two_frame_program with every target's joints solved for the KR 16."""
    program = two_frame_program()
    solution = configuration.solve_program(program, models.model(program.robot))
    assert solution.ok
    return program


def minimal_program(move_kind=ir.LINEAR, via=None, frame="B", name="P"):
    return post_programs.minimal_program("KUKA_KR16", move_kind, via, frame, name)


def random_program(seed=7, count=40):
    """Random orientations (gimbal lock B = +-90 deg and 180 deg turns
    included) and positions, in a frame turned every way."""
    rng = np.random.default_rng(seed)
    rotations = list(Rotation.random(count, random_state=seed).as_matrix())
    rotations += [Rotation.from_euler("ZYX", [30, 90, 0], degrees=True).as_matrix(),
                  Rotation.from_euler("ZYX", [-120, -90, 0], degrees=True).as_matrix(),
                  Rotation.from_euler("ZYX", [10, 90, 40], degrees=True).as_matrix(),
                  Rotation.from_rotvec([np.pi, 0, 0]).as_matrix(),
                  Rotation.from_rotvec([0, 0, np.pi]).as_matrix(), np.eye(3)]
    moves = []
    for i, R in enumerate(rotations):
        T = np.eye(4)
        T[:3, :3] = R
        T[:3, 3] = rng.uniform(-400, 400, 3)
        moves.append(ir.Move(ir.LINEAR, ir.Target(f"r{i}", T), 50.0, 0.0, "W"))
    frame = np.eye(4)
    frame[:3, :3] = Rotation.from_euler("zyx", [123.4, -56.7, 89.1], degrees=True).as_matrix()
    frame[:3, 3] = [912.3456, -345.6789, 678.9012]
    tool = ir.ToolData("Tool", pose((12.5, -33.3, 170), (1.2345, -6.789, 234.5678)))
    return ir.Program("Random", "KUKA_KR16", tool,
                      {"W": ir.WorkFrame("W", frame, np.eye(4))},
                      [ir.ProgramPath("Path", "Path", moves)])


def export_files(program, options=None):
    files = kuka_krl.export(program, options or {})
    assert [name.rsplit(".", 1)[1] for name, _ in files] == ["src", "dat"]
    return files[0][1], files[1][1]


# --- a small KRL reader ----------------------------------------------------------

AGGREGATE_RE = re.compile(r"^\s*DECL (FRAME|E6POS|E6AXIS) (\w+)=\{([^}]*)\}\s*$", re.MULTILINE)


def parse_aggregate(text):
    """``X 1.0,Y 2.0,...,S 6,T 27`` -> {"X": 1.0, ..., "S": 6.0, "T": 27.0}."""
    out = {}
    for item in text.split(","):
        key, value = item.split()
        out[key] = float(value)
    return out


def parse_dat(dat):
    """{name: (type, components)} of every FRAME, E6POS and E6AXIS declaration."""
    return {name: (kind, parse_aggregate(body)) for kind, name, body in AGGREGATE_RE.findall(dat)}


def parse_motions(src):
    """Every motion of every subprogram, in order:
    [(instruction, [points], $BASE, approximation words, $VEL.CP, $APO.CDIS)]."""
    motions, base, vel, cdis = [], None, None, None
    for line in src.splitlines():
        line = line.split(";")[0].strip()
        if line.startswith("DEF "):
            base = vel = cdis = None
        elif line.startswith("$BASE = "):
            base = line.split("=", 1)[1].strip()
        elif line.startswith("$VEL.CP = "):
            vel = float(line.split("=", 1)[1])
        elif line.startswith("$APO.CDIS = "):
            cdis = float(line.split("=", 1)[1])
        m = re.fullmatch(r"(PTP|LIN|CIRC) (\w+)(?:, (\w+))?((?: C_\w+)*)", line)
        if m and m.group(2) != "$AXIS_ACT":
            points = [p for p in (m.group(2), m.group(3)) if p]
            motions.append((m.group(1), points, base, m.group(4).split(), vel, cdis))
    return motions


def matrix_scipy(c):
    """Independent pose of X, Y, Z, A, B, C: intrinsic z-y'-x'' rotations."""
    T = np.eye(4)
    T[:3, :3] = Rotation.from_euler("ZYX", [c["A"], c["B"], c["C"]], degrees=True).as_matrix()
    T[:3, 3] = [c["X"], c["Y"], c["Z"]]
    return T


def flange_pose(robot, c):
    """Flange in the robot base frame of an E6AXIS's A1..A6 through the robot model
    (KUKA's A1..A6 are the model joints: robots/catalog/makers.py)."""
    q = [c[f"A{i}"] for i in range(1, 7)]
    return models.model(robot).fk(np.array([q]))[0]


def angle_deg(R1, R2):
    return np.degrees(Rotation.from_matrix(R1.T @ R2).magnitude())


def assert_same_pose(T, T_ref, what):
    np.testing.assert_allclose(T[:3, 3], T_ref[:3, 3], atol=1e-3, err_msg=what)
    assert angle_deg(T[:3, :3], T_ref[:3, :3]) <= 1e-4, what


# --- golden files ---------------------------------------------------------------

@pytest.mark.parametrize("name, build, options", [
    ("kuka_krl_two_frames", two_frame_program, {}),
    ("kuka_krl_configured", configured_program, {}),
    ("kuka_krl_krc2_numbered", configured_program,
     {"controller": "krc2", "base_number": {"Table": 1, "Fixture": 2}, "tool_number": 3}),
])
def test_golden_output(name, build, options):
    src, dat = export_files(build(), options)
    for extension, text in ((".src", src), (".dat", dat)):
        golden = GOLDEN_DIR / (name + extension)
        if os.environ.get("CADROBOT_UPDATE_GOLDEN"):
            golden.parent.mkdir(exist_ok=True)
            golden.write_bytes(text.encode("ascii"))
        assert golden.exists(), f"missing {golden}; see this file's docstring"
        assert text == golden.read_bytes().decode("ascii"), golden.name


def test_export_is_deterministic_and_files_are_named_after_the_program():
    program = two_frame_program()
    files = kuka_krl.export(program, {})
    assert files == kuka_krl.export(program, None)
    assert [f for f, _ in files] == ["Cell.src", "Cell.dat"]
    src, dat = (text for _, text in files)
    assert src.startswith("&ACCESS RVP\r\n&REL 1\r\nDEF Cell( )\r\n")
    assert dat.startswith("&ACCESS RVP\r\n&REL 1\r\nDEFDAT Cell\r\n")
    assert dat.endswith("\r\nENDDAT\r\n")


def test_line_ends_and_characters():
    program = two_frame_program()
    program.source = "Fräse Ölwanne.FCStd / Zelle"
    program.paths[0].moves[2].comment = "segment 1: ligne côté \u2192 bord"
    for text in export_files(program):
        assert "\n" not in text.replace("\r\n", "")    # CR LF only
        text.encode("ascii")                            # plain ASCII
    src, _ = export_files(program)
    assert "from Frase Olwanne.FCStd / Zelle." in src
    assert "; segment 1: ligne cote ? bord" in src
    assert "-0.0000" not in src + export_files(program)[1]


# --- orientation convention against robodk --------------------------------------------

@needs_robodk
@pytest.mark.parametrize("build", [two_frame_program, random_program])
def test_abc_convention_matches_robodk(build):
    """Every FRAME and E6POS written gives the program's rotation through
    robodk's KUKA_2_Pose, and robodk's Pose_2_KUKA gives the angles written
    (away from gimbal lock, where only A - C or A + C is defined)."""
    assert not ROBODK_MISSING, ROBODK_MISSING
    program = build()
    _, dat = export_files(program)
    data = parse_dat(dat)
    expected = {t.name: t.T_b_t for t in program.targets()}
    expected[program.tool.name] = program.tool.T_f_t
    expected.update({key: f.T_r_b for key, f in program.frames.items()})
    assert sorted(data) == sorted(expected)
    for name, (_, c) in data.items():
        xyzabc = [c[k] for k in "XYZABC"]
        T_ref = np.asarray(expected[name], float)
        T_rdk = np.array(robomath.KUKA_2_Pose(xyzabc).rows, float)
        assert_same_pose(T_rdk, T_ref, name)
        a, b, cc = robomath.Pose_2_KUKA(robomath.Mat(T_ref.tolist()))[3:]
        if abs(abs(b) - 90) > 1e-3:
            wrapped = (np.array([a, b, cc]) - np.array(xyzabc[3:]) + 180) % 360 - 180
            np.testing.assert_allclose(wrapped, 0, atol=1e-4, err_msg=name)


def test_abc_convention_matches_scipy_intrinsic_zyx():
    _, dat = export_files(random_program())
    data = parse_dat(dat)
    for target in random_program().targets():
        assert_same_pose(matrix_scipy(data[target.name][1]), target.T_b_t, target.name)


# --- round trip: every pose in the robot base frame -----------------------------------

@pytest.mark.parametrize("build, options", [
    (two_frame_program, {}),
    (configured_program, {"controller": "krc2"}),
    (random_program, {}),
])
def test_every_pose_is_recovered_in_the_robot_base_frame(build, options):
    program = build()
    src, dat = export_files(program, options)
    data = parse_dat(dat)
    motions = parse_motions(src)
    moves = program.moves()
    assert len(motions) == len(moves)
    for move, (instruction, points, base, _, _, _) in zip(moves, motions):
        T_r_b = program.frames[move.frame].T_r_b
        assert data[base][0] == "FRAME"
        targets = [move.via, move.target] if move.via is not None else [move.target]
        assert len(points) == len(targets)
        for point, target in zip(points, targets):
            if data[point][0] == "E6AXIS":      # joint target: through the model's fk
                assert instruction == "PTP" and target.joints_deg is not None
                T_r_t = flange_pose(program.robot, data[point][1]) @ program.tool.T_f_t
            else:
                assert data[point][0] == "E6POS"
                T_r_t = matrix_scipy(data[base][1]) @ matrix_scipy(data[point][1])
            assert_same_pose(T_r_t, T_r_b @ target.T_b_t, point)
    tool = parse_dat(dat)[program.tool.name][1]
    assert_same_pose(matrix_scipy(tool), program.tool.T_f_t, "tool")


# --- instructions, speeds and zones -----------------------------------------------------

def test_instructions_speeds_and_zones():
    src, _ = export_files(two_frame_program())
    got = [(i, p, b, a, v, z) for i, p, b, a, v, z in parse_motions(src)]
    assert got == [
        ("PTP", ["p1"], "Table", ["C_DIS"], None, 10.0),
        ("LIN", ["p2"], "Table", ["C_DIS"], 0.0125, 0.3),
        ("LIN", ["p3"], "Table", ["C_DIS"], 0.0125, 0.3),
        ("LIN", ["p4"], "Table", ["C_DIS"], 0.0125, 0.3),
        ("CIRC", ["p5", "p6"], "Table", [], 0.0125, 0.3),
        ("LIN", ["p7"], "Table", [], 0.1, 0.3),
        ("PTP", ["q1"], "Fixture", ["C_DIS"], None, 10.0),
        ("LIN", ["q2"], "Fixture", ["C_DIS"], 0.0125, 2.5),
        ("LIN", ["q3"], "Fixture", [], 0.0125, 2.5),
        ("LIN", ["q4"], "Fixture", [], 0.1, 2.5),
    ]
    lines = [line.strip() for line in src.splitlines()]
    # $VEL.CP (m/s) only where the speed changes, $APO.CDIS where the zone does.
    assert lines.count("$VEL.CP = 0.0125") == 2 and lines.count("$VEL.CP = 0.1") == 2
    assert [line for line in lines if line.startswith("$APO.CDIS")] == [
        "$APO.CDIS = 10", "$APO.CDIS = 0.3", "$APO.CDIS = 10", "$APO.CDIS = 2.5"]
    main = lines[lines.index("DEF Cell( )"):lines.index("END")]
    assert main[-3:] == ["", "Seam( )", "Contour( )"]
    assert "PTP $AXIS_ACT ; BCO run where the robot stands" in main
    for comment in ("; Path: Weld seam", "; segment 1: line Sketch.Edge1",
                    "; segment 2: arc Sketch.Edge2",
                    "; Robot: KUKA_KR16. Controller: KR C4 (KSS 8.x).",
                    "; Generated by CadRobot (post-processor kuka_krl) from demo.FCStd / Cell."):
        assert comment in lines


def test_setup_tool_load_and_frames():
    src, dat = export_files(two_frame_program())
    lines = [line.strip() for line in src.splitlines()]
    for line in ("$TOOL = Torch", "$IPO_MODE = #BASE", "$VEL_AXIS[6] = 20", "$VEL.ORI1 = 200",
                 "$ACC.CP = 2", "$LOAD = {M 1.5,CM {X 0,Y 0,Z 120,A 0,B 0,C 0},J {X 0,Y 0,Z 0}}"):
        assert line in lines
    assert "$BASE = Table" in lines and "$BASE = Fixture" in lines
    assert "$APO.CPTP" not in src and "C_PTP" not in src
    data = parse_dat(dat)
    assert data["Torch"][0] == data["Table"][0] == data["Fixture"][0] == "FRAME"
    np.testing.assert_allclose([data["Table"][1][k] for k in "XYZABC"],
                               [800, -200, 400, 90, 0, 0], atol=1e-9)


def test_options_change_setup_values():
    src, _ = export_files(two_frame_program(), {
        "ptp_speed_percent": 35, "ori_speed_deg_s": 90, "cp_accel_m_s2": 1.5,
        "ori_accel_deg_s2": 50, "no_such_option": 1})
    lines = [line.strip() for line in src.splitlines()]
    for line in ("$VEL_AXIS[1] = 35", "$VEL.ORI2 = 90", "$ACC.CP = 1.5", "$ACC.ORI1 = 50"):
        assert line in lines


def test_base_and_tool_numbers():
    program = two_frame_program()
    src, dat = export_files(program, {"base_number": {"Table": 4, "Fixture": 5},
                                      "tool_number": 2})
    lines = [line.strip() for line in src.splitlines()]
    assert "$TOOL = TOOL_DATA[2]" in lines and "$LOAD = LOAD_DATA[2]" in lines
    assert [b for _, _, b, _, _, _ in parse_motions(src)] == ["BASE_DATA[4]"] * 6 + \
        ["BASE_DATA[5]"] * 4
    assert "DECL FRAME" not in dat
    # The comments give the values to teach.
    m = re.search(r"BASE_DATA\[5\] must hold \{([^}]*)\}", src)
    assert_same_pose(matrix_scipy(parse_aggregate(m.group(1))),
                     program.frames["Fixture"].T_r_b, "Fixture")
    m = re.search(r"TOOL_DATA\[2\] must hold \{([^}]*)\}", src)
    assert_same_pose(matrix_scipy(parse_aggregate(m.group(1))), program.tool.T_f_t, "tool")
    assert "LOAD_DATA[2] must hold {M 1.5,CM {X 0,Y 0,Z 120" in src

    one = minimal_program()
    src, _ = export_files(one, {"base_number": 7})
    assert "$BASE = BASE_DATA[7]" in src


@pytest.mark.parametrize("options, match", [
    ({"controller": "krc5"}, "controller"),
    ({"base_number": 1}, "base_number as"),
    ({"base_number": {"Table": 1}}, "Fixture"),
    ({"base_number": {"Table": 1, "Fixture": 33}}, "1 to 32"),
    ({"base_number": {"Table": 1, "Fixture": 2.0}}, "1 to 32"),
    ({"tool_number": 0}, "1 to 16"),
    ({"tool_number": True}, "1 to 16"),
    ({"ptp_speed_percent": 0}, "ptp_speed_percent"),
    ({"ptp_speed_percent": 12.5}, "ptp_speed_percent"),
    ({"ptp_approx_percent": 101}, "ptp_approx_percent"),
    ({"cp_accel_m_s2": -1}, "cp_accel_m_s2"),
    ({"ori_speed_deg_s": "fast"}, "ori_speed_deg_s"),
    ({"program_name": "1abc"}, "program_name"),
    ({"program_name": "LIN"}, "program_name"),
    ({"program_name": "x" * 25}, "program_name"),
])
def test_bad_options_are_post_errors(options, match):
    with pytest.raises(PostError, match=match):
        kuka_krl.export(two_frame_program(), options)


def test_program_name_option():
    files = kuka_krl.export(two_frame_program(), {"program_name": "Weld_1"})
    assert [f for f, _ in files] == ["Weld_1.src", "Weld_1.dat"]
    assert "\r\nDEF Weld_1( )\r\n" in files[0][1] and "\r\nDEFDAT Weld_1\r\n" in files[1][1]


# --- KR C2 -------------------------------------------------------------------------

def test_krc2_approximates_ptp_with_c_ptp():
    program = two_frame_program()
    # A second PTP after the first: PTP-to-PTP needs C_PTP alone.
    seam = program.paths[0]
    seam.moves.insert(0, ir.Move(ir.JOINT, ir.Target("p0", pose(DOWN, (0, 0, 80))), 100.0,
                                 10.0, "Table", role=ir.ROLE_APPROACH, comment="approach"))
    src, _ = export_files(program, {"controller": "krc2", "ptp_approx_percent": 30})
    motions = parse_motions(src)
    assert motions[0][:4] == ("PTP", ["p0"], "Table", ["C_PTP"])
    assert motions[1][:4] == ("PTP", ["p1"], "Table", ["C_PTP", "C_DIS"])
    assert motions[2][:4] == ("LIN", ["p2"], "Table", ["C_DIS"])
    lines = [line.strip() for line in src.splitlines()]
    assert "$APO.CPTP = 30" in lines
    assert not any(line.startswith("$LOAD") for line in lines)
    assert "; Robot: KUKA_KR16. Controller: KR C2 (KSS 5.x)." in lines
    assert "; Load of the tool, to set on the pendant: {M 1.5,CM {X 0,Y 0,Z 120,A 0,B 0,C 0}," \
           "J {X 0,Y 0,Z 0}}" in lines


# --- Status and Turn ------------------------------------------------------------------

def test_status_and_turn_come_from_the_joints():
    program = configured_program()
    src, dat = export_files(program, {"joint_targets": False})
    data = parse_dat(dat)
    spec = catalog.get(program.robot)
    for target in program.targets():
        c = data[target.name][1]
        assert (int(c["S"]), int(c["T"])) == configuration.kuka_status_turn(target.joints_deg,
                                                                             spec)
    # Basic area, elbow up, A5 > 0 (S = 2); A2 and A6 < 0 (T = 34), A1 < 0 too (T = 35).
    assert (data["p1"][1]["S"], data["p1"][1]["T"]) == (2, 34)
    assert (data["p3"][1]["S"], data["p3"][1]["T"]) == (2, 35)
    assert "S and T of every point are the arm configuration CadRobot checked." in src
    assert "no S and T" not in dat


def test_points_without_joints_have_no_status_and_turn():
    program = configured_program()
    program.paths[1].moves[2].target.joints_deg = None            # q3
    src, dat = export_files(program, {"joint_targets": False})
    data = parse_dat(dat)
    assert "S" not in data["q3"][1] and "T" not in data["q3"][1]
    assert data["q2"][1]["S"] == 2
    assert "; q3: no S and T (no joint values for this target)" in dat
    assert "1 of 11 points have no S and T" in src

    src, dat = export_files(two_frame_program())
    assert not any("S" in c for _, c in parse_dat(dat).values())
    assert "11 of 11 points have no S and T" in src

    program = configured_program()
    program.robot = "UR5E"            # not an OPW robot: no S and T at all
    src, dat = export_files(program, {"joint_targets": False})
    assert not any("S" in c for _, c in parse_dat(dat).values())
    assert "not an OPW robot" in src


# --- names ----------------------------------------------------------------------------

def awkward_names_program():
    """Names KRL cannot take as they are."""
    program = minimal_program(name="3D_Cell")
    program.tool.name = "TOOL_DATA"
    program.frames = {"$BASE": ir.WorkFrame("$BASE", np.eye(4), np.eye(4))}
    names = ["A_very_long_target_name_made_by_a_generator_1",
             "A_very_long_target_name_made_by_a_generator_2",
             "LIN", "P1", "p1", "Cell"]
    moves = [ir.Move(ir.LINEAR, ir.Target(n, pose(DOWN, (i, 0, 0))), 10, 0, "$BASE")
             for i, n in enumerate(names)]
    program.paths = [ir.ProgramPath("END", "End", moves), ir.ProgramPath("Path", "Main", [])]
    return program


def declared_names(src, dat):
    names = re.findall(r"^\s*DECL \w+ (\w+)=", dat, re.MULTILINE)
    names += re.findall(r"^DEF (\w+)\( \)", src, re.MULTILINE)
    return names


def test_names_are_valid_unique_and_short():
    src, dat = export_files(awkward_names_program())
    names = declared_names(src, dat)
    assert len(names) == 2 + 6 + 3          # frames, points, DEFs
    assert len({n.upper() for n in names}) == len(names)
    for name in names:
        assert kuka_krl.is_name(name) and len(name) <= 24, name
    assert "DEF P3D_Cell( )" in src
    assert "$TOOL = TOOL_DATA_2" in src and "$BASE = B_BASE" in src
    assert "DEF END_2( )" in src and "  END_2( )" in src
    assert "LIN LIN_2" in src and "LIN p1_2" in src


def test_long_program_name_is_cut_to_24_characters():
    program = minimal_program(name="A_program_name_far_longer_than_KRL_allows")
    files = kuka_krl.export(program, {})
    assert files[0][0] == "A_program_name_far_longe.src"
    assert "\r\nDEF A_program_name_far_longe( )\r\n" in files[0][1]


def test_same_target_used_twice_is_declared_once():
    program = minimal_program()
    move = program.paths[0].moves[0]
    program.paths[0].moves.append(ir.Move(ir.LINEAR, move.target, 10, 0, "B"))
    src, dat = export_files(program)
    assert dat.count("DECL E6POS t1=") == 1
    assert src.count("LIN t1") == 2


# --- options ------------------------------------------------------------------------

def test_every_option_read_is_declared_and_others_are_refused():
    from CadRobotWB import posts
    assert set(kuka_krl.OPTIONS) == {
        "controller", "program_name", "base_number", "tool_number", "ptp_speed_percent",
        "ptp_approx_percent", "ori_speed_deg_s", "cp_accel_m_s2", "ori_accel_deg_s2",
        "joint_targets", "max_lines", "arctech_version", "channels", "positioner_machine"}
    with pytest.raises(PostError, match="no option max_line"):
        posts.run(kuka_krl, two_frame_program(), {"max_line": 100})
    files = posts.run(kuka_krl, two_frame_program(), {"max_lines": 2500, "joint_targets": True})
    assert [f for f, _ in files] == ["Cell.src", "Cell.dat"]


@pytest.mark.parametrize("options, match", [
    ({"joint_targets": "maybe"}, "joint_targets must be true or false"),
    ({"joint_targets": 1}, "joint_targets must be true or false"),
    ({"max_lines": 99}, "max_lines must be a whole number from 100"),
    ({"max_lines": 2500.0}, "max_lines must be a whole number"),
    ({"max_lines": True}, "max_lines must be a whole number"),
    ({"ori_speed_deg_s": float("nan")}, "ori_speed_deg_s must be a number"),
    ({"cp_accel_m_s2": float("inf")}, "cp_accel_m_s2 must be a number"),
    ({"ori_accel_deg_s2": 0}, "ori_accel_deg_s2 must be a number of at least 0.001"),
    ({"controller": None}, "controller must be one of krc4, krc2"),
    ({"base_number": {"Table": 1, "Fixture": "2"}}, "base_number of work frame 'Fixture'"),
])
def test_bad_option_values_name_the_option(options, match):
    with pytest.raises(PostError, match=match):
        kuka_krl.export(two_frame_program(), options)


# --- zones --------------------------------------------------------------------------

@pytest.mark.parametrize("zone, text", [
    (10.0, "10"), (2.5, "2.5"), (0.3, "0.3"), (0.29, "0.29"), (0.12345, "0.1234"),
    (2.99999, "2.9999"), (0.0001, "0.0001"), (0.00009, None), (1e-12, None)])
def test_zone_is_rounded_down_never_up(zone, text):
    assert kuka_krl.zone_text(zone) == text
    if text is not None:
        assert float(text) <= zone


def test_a_zone_below_the_resolution_is_an_exact_stop():
    program = minimal_program()
    move = program.paths[0].moves[0]
    program.paths[0].moves += [
        ir.Move(ir.LINEAR, ir.Target("t2", pose(DOWN, (5, 2, 3))), 10.0, 0.12345, "B"),
        ir.Move(ir.LINEAR, ir.Target("t3", pose(DOWN, (9, 2, 3))), 10.0, 0.00004, "B"),
        ir.Move(ir.LINEAR, move.target, 10.0, 0.0, "B")]
    src, _ = export_files(program)
    assert [(m[0], m[1], m[3], m[5]) for m in parse_motions(src)] == [
        ("LIN", ["t1"], [], None), ("LIN", ["t2"], ["C_DIS"], 0.1234),
        ("LIN", ["t3"], [], 0.1234), ("LIN", ["t1"], [], 0.1234)]


# --- joint targets --------------------------------------------------------------------

def test_kuka_axes_are_the_model_joints():
    """KUKA's A1..A6 are the model's joints (robots/catalog/makers.py): KUKA's HOME
    {A1 0,A2 -90,A3 90,A4 0,A5 0,A6 0} has the lower arm up and the upper arm
    level, so the flange is at x = 260 + 670 + 158, z = 675 + 680 - 35 (kr_16.csv
    lengths) facing +X; A1 > 0 turns the arm clockwise seen from above (joint_a1
    about -Z in ROS-Industrial's KUKA URDFs, sign -1 in opw_kinematics' KR 6 R700)."""
    model = models.model("KUKA_KR16")
    np.testing.assert_allclose(model.controller_joints([10, -20, 30, -40, 50, -60]),
                               [10, -20, 30, -40, 50, -60])
    home, turned = model.fk(np.array([[0, -90, 90, 0, 0, 0], [30, -90, 90, 0, 0, 0]]))
    np.testing.assert_allclose(home[:3, 3], [1088, 0, 1320], atol=1e-9)
    np.testing.assert_allclose(home[:3, 2], [1, 0, 0], atol=1e-12)
    np.testing.assert_allclose(turned[:3, 3], [1088 * np.cos(np.radians(30)),
                                               -1088 * np.sin(np.radians(30)), 1320], atol=1e-9)


def test_joint_moves_go_to_e6axis_points_of_the_solved_joints():
    program = configured_program()
    src, dat = export_files(program)
    data = parse_dat(dat)
    motions = parse_motions(src)
    joint_moves = [m for m in program.moves() if m.kind == ir.JOINT]
    assert [m[1] for m in motions if m[0] == "PTP"] == [[m.target.name] for m in joint_moves]
    _, cartesian_dat = export_files(program, {"joint_targets": False})
    cartesian = parse_dat(cartesian_dat)
    for move in joint_moves:
        kind, axes = data[move.target.name]
        assert kind == "E6AXIS" and cartesian[move.target.name][0] == "E6POS"
        assert list(axes) == [f"A{i}" for i in range(1, 7)] + [f"E{i}" for i in range(1, 7)]
        assert all(axes[f"E{i}"] == 0 for i in range(1, 7))
        np.testing.assert_allclose([axes[f"A{i}"] for i in range(1, 7)],
                                   move.target.joints_deg, atol=5e-6)
        # The axis values through the model give the pose of the E6POS written
        # without joint targets (in the robot base frame).
        T_base = matrix_scipy(cartesian[move.frame][1])
        assert_same_pose(flange_pose(program.robot, axes) @ program.tool.T_f_t,
                         T_base @ matrix_scipy(cartesian[move.target.name][1]), move.target.name)
    assert sum(kind == "E6AXIS" for kind, _ in data.values()) == len(joint_moves)
    assert "E6AXIS" not in cartesian_dat


def test_target_of_a_ptp_and_a_lin_is_declared_both_ways():
    program = configured_program()
    seam = program.paths[0].moves
    seam.append(ir.Move(ir.LINEAR, seam[0].target, 100.0, 0.0, "Table"))   # back to p1
    src, dat = export_files(program)
    data = parse_dat(dat)
    assert data["p1"][0] == "E6POS" and data["p1_J"][0] == "E6AXIS"
    assert [m[1] for m in parse_motions(src)][:1] == [["p1_J"]]
    assert ("LIN", ["p1"]) in [m[:2] for m in parse_motions(src)]


def test_joint_move_without_joints_stays_cartesian():
    program = configured_program()
    program.paths[0].moves[0].target.joints_deg = None
    _, dat = export_files(program)
    data = parse_dat(dat)
    assert data["p1"][0] == "E6POS" and "S" not in data["p1"][1]
    assert data["q1"][0] == "E6AXIS"


def test_joint_targets_need_a_robot_of_the_catalog():
    program = configured_program()
    program.robot = "NoSuchRobot"
    with pytest.raises(PostError, match="joint_targets=false"):
        kuka_krl.export(program, {})
    src, dat = export_files(program, {"joint_targets": False})
    assert "E6AXIS" not in dat


def test_batch_status_and_turn_agree_with_configuration():
    program = post_programs.long_program("KUKA_KR16", 600)
    program.paths[0].moves += configured_program().paths[1].moves
    targets = program.targets()
    targets[5].joints_deg = None
    spec = catalog.get("KUKA_KR16")
    got = kuka_krl.status_turn_of(targets, spec)
    expected = [None if t.joints_deg is None else configuration.kuka_status_turn(t.joints_deg, spec)
                for t in targets]
    assert got == expected
    assert len(set(got)) > 2
    assert kuka_krl.status_turn_of(targets, None) == [None] * len(targets)


# --- long programs ------------------------------------------------------------------

def modules(files):
    """{module name: (src, dat)} of exported files, checking they come in pairs."""
    names = [f for f, _ in files]
    assert [n.rsplit(".", 1)[1] for n in names] == ["src", "dat"] * (len(files) // 2)
    pairs = {}
    for (src_name, src), (dat_name, dat) in zip(files[::2], files[1::2]):
        stem = src_name[:-4]
        assert dat_name == stem + ".dat"
        pairs[stem] = (src, dat)
    return pairs


def check_module(stem, src, dat, max_lines):
    """One module is a valid KRL pair within the limit; returns its motions."""
    for text in (src, dat):
        assert "\n" not in text.replace("\r\n", "")
        assert len(text.split("\r\n")) - 1 <= max_lines, stem
    src_lines, dat_lines = src.split("\r\n")[:-1], dat.split("\r\n")[:-1]
    assert src_lines[:3] == ["&ACCESS RVP", "&REL 1", f"DEF {stem}( )"] and src_lines[-1] == "END"
    assert dat_lines[:3] == ["&ACCESS RVP", "&REL 1", f"DEFDAT {stem}"]
    assert dat_lines[-1] == "ENDDAT"
    assert [line for line in src_lines if line.startswith("DEF")] == [f"DEF {stem}( )"]
    assert kuka_krl.is_name(stem) and len(stem) <= 24
    declared = parse_dat(dat)
    motions = parse_motions(src)
    for instruction, points, base, _, _, _ in motions:
        assert base.startswith("BASE_DATA[") or declared[base][0] == "FRAME", (stem, base)
        for point in points:                 # every point is in the module's own .dat
            assert declared[point][0] in ("E6POS", "E6AXIS"), (stem, point)
    return motions, declared


@pytest.fixture(scope="module")
def long_50000():
    return post_programs.long_program("KUKA_KR16", 50000)


def test_a_50000_move_program_is_split_within_the_limits(long_50000):
    import time
    program = long_50000
    start = time.perf_counter()
    files = kuka_krl.export(program, {})
    seconds = time.perf_counter() - start
    print(f"KRL export of 50,000 moves: {seconds:.2f} s, {len(files)} files, "
          f"{sum(len(t) for _, t in files)} bytes")
    assert seconds < 60
    pairs = modules(files)
    main_src, main_dat = pairs.pop("Long")
    parts = list(pairs)
    assert len(parts) >= 50000 // kuka_krl.MAX_LINES
    assert len({p.upper() for p in parts} | {"LONG"}) == len(parts) + 1
    # The main program calls every part once, in order, and declares them EXT.
    main_lines = [line.strip() for line in main_src.split("\r\n")]
    assert [line for line in main_lines if line.endswith("( )") and not line.startswith(
        ("DEF", ";"))] == [f"{p}( )" for p in parts]
    assert [line.strip() for line in main_dat.split("\r\n") if "EXT" in line] == \
        [f"EXT {p}( )" for p in parts]
    assert "$TOOL = Torch" in main_lines and parse_dat(main_dat)["Torch"][0] == "FRAME"
    check_module("Long", main_src, main_dat, kuka_krl.MAX_LINES)
    # The parts' motions, in order, are the program's moves, to the same points.
    moves = program.moves()
    done = 0
    for part in parts:
        motions, declared = check_module(part, *pairs[part], kuka_krl.MAX_LINES)
        for instruction, points, base, _, _, _ in motions:
            move = moves[done]
            expected = [move.via.name, move.target.name] if move.via else [move.target.name]
            assert instruction == {"joint": "PTP", "linear": "LIN", "circular": "CIRC"}.get(
                move.kind, instruction) and points == expected, (part, done)
            done += 1
    assert done == len(moves) == 50000


@pytest.mark.parametrize("options", [
    {"max_lines": 150},
    {"max_lines": 150, "controller": "krc2", "joint_targets": False, "base_number": 3,
     "tool_number": 2}])
def test_every_pose_of_a_split_program_is_recovered(options):
    program = post_programs.long_program("KUKA_KR16", 700)
    files = kuka_krl.export(program, options)
    pairs = modules(files)
    pairs.pop("Long")
    assert len(pairs) >= 875 // 150     # 700 points and 175 via points, one line each
    moves = iter(program.moves())
    for stem, (src, dat) in pairs.items():
        motions, declared = check_module(stem, src, dat, 150)
        for instruction, points, base, _, _, _ in motions:
            move = next(moves)
            targets = [move.via, move.target] if move.via is not None else [move.target]
            for point, target in zip(points, targets):
                T_r_b = program.frames[move.frame].T_r_b
                if declared[point][0] == "E6AXIS":
                    T_r_t = flange_pose(program.robot, declared[point][1]) @ program.tool.T_f_t
                elif base == "BASE_DATA[3]":
                    T_r_t = T_r_b @ matrix_scipy(declared[point][1])
                else:
                    T_r_t = matrix_scipy(declared[base][1]) @ matrix_scipy(declared[point][1])
                assert_same_pose(T_r_t, T_r_b @ target.T_b_t, point)
    assert next(moves, None) is None


def test_each_part_sets_base_speed_and_zone_itself():
    program = post_programs.long_program("KUKA_KR16", 400, solve=False)
    pairs = modules(kuka_krl.export(program, {"max_lines": 120}))
    pairs.pop("Long")
    for stem, (src, _) in pairs.items():
        motions = parse_motions(src)
        first_cp = next(m for m in motions if m[0] != "PTP")
        assert motions[0][2] == "B" and first_cp[4] is not None, stem
        assert all(m[5] is not None for m in motions if "C_DIS" in m[3]), stem
        assert "; Path: Long seam" in src.split("\r\n")[4]


def test_a_program_within_the_limit_is_one_pair_of_files():
    program = post_programs.long_program("KUKA_KR16", 1000, solve=False)
    single = kuka_krl.export(program, {})
    assert [f for f, _ in single] == ["Long.src", "Long.dat"]
    assert max(t.count("\r\n") for _, t in single) <= kuka_krl.MAX_LINES
    lines = max(t.count("\r\n") for _, t in single)
    assert [f for f, _ in kuka_krl.export(program, {"max_lines": lines})] == \
        ["Long.src", "Long.dat"]
    assert len(kuka_krl.export(program, {"max_lines": lines - 1})) > 2


def test_part_names_avoid_taken_names_and_stay_short():
    program = post_programs.long_program("KUKA_KR16", 300, solve=False)
    program.paths[0].moves[3].target.name = "Long_2"
    names = list(modules(kuka_krl.export(program, {"max_lines": 100})))
    assert names[0] == "Long" and names[1] == "Long_P1" and "Long_2" not in names
    long_name = "W" * 24
    names = list(modules(kuka_krl.export(program, {"max_lines": 100,
                                                   "program_name": long_name})))
    assert names[0] == long_name and names[1] == "W" * 22 + "_1"
    assert all(len(n) <= 24 and kuka_krl.is_name(n) for n in names)
    assert len({n.upper() for n in names}) == len(names)


def test_too_many_parts_for_the_main_program_is_refused():
    program = post_programs.long_program("KUKA_KR16", 5000, solve=False)
    with pytest.raises(PostError, match="more than max_lines 100; raise max_lines"):
        kuka_krl.export(program, {"max_lines": 100})


@pytest.mark.parametrize("joints", [[0, float("nan"), 0, 0, 0, 0], [0, 0, float("inf"), 0, 0, 0]])
def test_joint_values_that_are_not_finite_are_refused(joints):
    program = configured_program()
    program.paths[0].moves[0].target.joints_deg = np.array(joints)
    with pytest.raises(PostError, match="Target 'p1' has joint values"):
        kuka_krl.export(program, {})
    program.paths[0].moves[0].target.joints_deg = np.array(joints)
    with pytest.raises(PostError, match="Target 'p1' has joint values that are not finite"):
        kuka_krl.export(program, {"joint_targets": False})
