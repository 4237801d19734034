"""Tests of the Universal Robots URScript post-processor (posts/ur_script.py).

The script is compared with golden files; its ``p[...]`` poses are parsed
back here and turned into transforms with an independent implementation of
UR's rotation vector (``robodk.robomath``, from PyPI) and with scipy, and the
poses each move reaches through ``pose_trans(frame, target)`` are compared
with the program's poses in the robot base frame.

To rewrite the golden files after a reviewed change of the output:
``CADROBOT_UPDATE_GOLDEN=1 python3 -m pytest tests/core/test_ur_script.py``.
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
from CadRobotWB.posts import ur_script

from robodk_check import ROBODK_MISSING, needs_robodk, robomath  # noqa: E402,F401

GOLDEN_DIR = Path(__file__).parent / "golden"


# --- programs built by hand ---------------------------------------------------



def two_frame_program():
    # The UR5e reaches less far: both frames closer to its base.
    return post_programs.two_frame_program("UR5E", table_mm=(400.0, -200.0, 100.0),
                                           fixture_mm=(300.0, 300.0, 50.0))


def minimal_program(move_kind=ir.LINEAR, via=None, frame="B", name="Job"):
    return post_programs.minimal_program("UR5E", move_kind, via, frame, name)


def random_program(seed=11, count=40):
    """Random orientations (180 degree turns and the identity included) and
    positions, in a frame turned every way."""
    rng = np.random.default_rng(seed)
    rotations = list(Rotation.random(count, random_state=seed).as_matrix())
    rotations += [Rotation.from_rotvec(v).as_matrix() for v in
                  ([np.pi, 0, 0], [0, 0, -np.pi], [np.pi / np.sqrt(2), -np.pi / np.sqrt(2), 0],
                   [0, 3.1415, 0], [1e-9, 0, 0], [0, 0, 0])]
    moves = []
    for i, R in enumerate(rotations):
        T = np.eye(4)
        T[:3, :3] = R
        T[:3, 3] = rng.uniform(-300, 300, 3)
        moves.append(ir.Move(ir.LINEAR, ir.Target(f"r{i}", T), 50.0, 0.0, "W"))
    frame = np.eye(4)
    frame[:3, :3] = Rotation.from_euler("zyx", [123.4, -56.7, 89.1], degrees=True).as_matrix()
    frame[:3, 3] = [412.3456, -345.6789, 78.9012]
    tool = ir.ToolData("Tool", pose((12.5, -33.3, 170), (1.2345, -6.789, 234.5678)))
    return ir.Program("Random", "UR5E", tool, {"W": ir.WorkFrame("W", frame, np.eye(4))},
                      [ir.ProgramPath("Path", "Path", moves)])


def export_text(program, options=None):
    files = ur_script.export(program, options or {})
    assert len(files) == 1 and files[0][0].endswith(".script")
    return files[0][1]


# --- a small URScript reader -----------------------------------------------------

NUMBER = r"-?\d+(?:\.\d+)?"
POSE_RE = re.compile(r"^\s*(\w+) = p\[([^\]]*)\]$", re.MULTILINE)
MOVE_RE = re.compile(r"^\s*(movej|movel|movec)\((.*)\)$", re.MULTILINE)
TRANS_RE = re.compile(r"pose_trans\((\w+), (\w+)\)")


def parse_poses(text):
    """{variable: (6,) array} of every ``name = p[...]`` assignment."""
    return {name: np.array(values.split(","), float) for name, values in POSE_RE.findall(text)}


def parse_moves(text):
    """[(function, [(frame, target), ...], {keyword: value})] in order."""
    out = []
    for function, args in MOVE_RE.findall(text):
        points = TRANS_RE.findall(args)
        keywords = {k: float(v) for k, v in re.findall(rf"(\w+)=({NUMBER})", args)}
        out.append((function, points, keywords))
    return out


def matrix_scipy(values):
    """Independent transform (mm) of p[x, y, z, rx, ry, rz] (m, rad)."""
    T = np.eye(4)
    T[:3, :3] = Rotation.from_rotvec(values[3:]).as_matrix()
    T[:3, 3] = 1000.0 * np.asarray(values[:3])
    return T


def angle_deg(R1, R2):
    return np.degrees(Rotation.from_matrix(R1.T @ R2).magnitude())


def assert_same_pose(T, T_ref, what):
    np.testing.assert_allclose(T[:3, 3], T_ref[:3, 3], atol=1e-3, err_msg=what)
    assert angle_deg(T[:3, :3], T_ref[:3, :3]) <= 1e-4, what


# --- golden files ---------------------------------------------------------------

@pytest.mark.parametrize("name, build, options", [
    ("ur_script_two_frames.script", two_frame_program, {}),
    ("ur_script_minimal_call.script", minimal_program, {"call": True}),
])
def test_golden_output(name, build, options):
    text = export_text(build(), options)
    golden = GOLDEN_DIR / name
    if os.environ.get("CADROBOT_UPDATE_GOLDEN"):
        golden.parent.mkdir(exist_ok=True)
        golden.write_text(text, newline="\n")
    assert golden.exists(), f"missing {golden}; see this file's docstring"
    assert text == golden.read_text()


def test_export_is_deterministic_and_named_after_program():
    program = two_frame_program()
    files = ur_script.export(program, {})
    assert files == ur_script.export(program, None)
    assert [f for f, _ in files] == ["Cell.script"]


def test_layout_runs_when_loaded_and_fits_port_30002_without_the_call():
    """By default the function is called after ``end``: a file loaded as a
    script (PolyScope) runs.  With ``call=false``: URControl's rule for a
    script sent to port 30002, ``def`` in the first column, every other line
    indented, ``end`` in the first column last."""
    lines = export_text(two_frame_program()).splitlines()
    assert lines[0] == "def Cell():" and lines[-2:] == ["end", "Cell()"]
    lines = export_text(two_frame_program(), {"call": False}).splitlines()
    assert lines[0] == "def Cell():" and lines[-1] == "end"
    assert all(line.startswith(" ") for line in lines[1:-1])
    assert all(line.strip() for line in lines)          # no empty lines
    export_text(two_frame_program()).encode("ascii")
    with pytest.raises(PostError, match="call must be true or false"):
        ur_script.export(two_frame_program(), {"call": "maybe"})


def test_comments_are_plain_ascii():
    program = two_frame_program()
    program.source = "Fräse Ölwanne.FCStd / Zelle"
    program.paths[0].moves[2].comment = "segment 1: ligne côté \u2192 bord"
    text = export_text(program)
    text.encode("ascii")
    assert ("  # Generated by CadRobot (post-processor ur_script) from "
            "Frase Olwanne.FCStd / Zelle.") in text.splitlines()
    assert "  # segment 1: ligne cote ? bord" in text.splitlines()


# --- rotation vector against robodk -------------------------------------------------

@needs_robodk
@pytest.mark.parametrize("build", [two_frame_program, random_program])
def test_rotation_vectors_match_robodk(build):
    """Every p[...] written gives the program's pose through robodk's
    UR_2_Pose, and robodk's Pose_2_UR gives the rotation vector written (up
    to the sign of the axis at exactly 180 degrees)."""
    assert not ROBODK_MISSING, ROBODK_MISSING
    program = build()
    text = export_text(program)
    poses = parse_poses(text)
    expected = {t.name: t.T_b_t for t in program.targets()}
    expected.update({key: f.T_r_b for key, f in program.frames.items()})
    assert sorted(poses) == sorted(expected)
    for name, values in poses.items():
        T_ref = np.asarray(expected[name], float)
        mm = list(1000.0 * values[:3]) + list(values[3:])
        assert_same_pose(np.array(robomath.UR_2_Pose(mm).rows, float), T_ref, name)
        rotvec = np.array(robomath.Pose_2_UR(robomath.Mat(T_ref.tolist()))[3:])
        error = np.abs(rotvec - values[3:]).max()
        if abs(np.linalg.norm(rotvec) - np.pi) < 1e-6:
            error = min(error, np.abs(rotvec + values[3:]).max())
        assert error <= 1e-7, (name, rotvec, values[3:])


@needs_robodk
def test_tcp_matches_robodk():
    assert not ROBODK_MISSING, ROBODK_MISSING
    program = two_frame_program()
    text = export_text(program)
    m = re.search(r"set_tcp\(p\[([^\]]*)\]\)", text)
    values = np.array(m.group(1).split(","), float)
    mm = list(1000.0 * values[:3]) + list(values[3:])
    assert_same_pose(np.array(robomath.UR_2_Pose(mm).rows, float), program.tool.T_f_t, "tcp")


# --- round trip: every pose in the robot base frame -----------------------------------

@pytest.mark.parametrize("build", [two_frame_program, random_program])
def test_every_pose_is_recovered_in_the_robot_base_frame(build):
    program = build()
    text = export_text(program)
    poses = parse_poses(text)
    parsed = parse_moves(text)
    moves = program.moves()
    assert len(parsed) == len(moves)
    for move, (_, points, _) in zip(moves, parsed):
        T_r_b = program.frames[move.frame].T_r_b
        targets = [move.via, move.target] if move.via is not None else [move.target]
        assert len(points) == len(targets)
        for (frame, point), target in zip(points, targets):
            # pose_trans(frame, point) = frame composed with point.
            T_r_t = matrix_scipy(poses[frame]) @ matrix_scipy(poses[point])
            assert_same_pose(T_r_t, T_r_b @ target.T_b_t, point)


def test_number_format():
    """Metres and radians with 7 decimals, never -0."""
    text = export_text(random_program())
    written = re.findall(r"^\s*(?:\w+ = |set_tcp\()p\[([^\]]*)\]", text, re.MULTILINE)
    assert len(written) == 1 + 1 + 46
    for values in written:
        assert all(re.fullmatch(r"-?\d+\.\d{7}", v) for v in values.split(", ")), values
    assert "-0.0000000," not in text and "-0.0000000]" not in text


# --- instructions, speeds and zones -----------------------------------------------------

def test_instructions_speeds_accelerations_and_blends():
    parsed = parse_moves(export_text(two_frame_program()))
    got = [(f, [p for _, p in points], k) for f, points, k in parsed]
    joint = {"a": 1.4, "v": 1.05}
    linear = {"a": 1.2}
    assert got == [
        ("movej", ["p1"], {**joint, "r": 0.01}),
        ("movel", ["p2"], {**linear, "v": 0.0125, "r": 0.0003}),
        ("movel", ["p3"], {**linear, "v": 0.0125, "r": 0.0003}),
        ("movel", ["p4"], {**linear, "v": 0.0125, "r": 0.0003}),
        ("movec", ["p5", "p6"], {**linear, "v": 0.0125, "r": 0.0, "mode": 0}),
        ("movel", ["p7"], {**linear, "v": 0.1, "r": 0.0}),
        ("movej", ["q1"], {**joint, "r": 0.01}),
        ("movel", ["q2"], {**linear, "v": 0.0125, "r": 0.0025}),
        ("movel", ["q3"], {**linear, "v": 0.0125, "r": 0.0}),
        ("movel", ["q4"], {**linear, "v": 0.1, "r": 0.0}),
    ]
    assert [f for _, points, _ in parsed for f, _ in points] == ["Table"] * 7 + ["Fixture"] * 4


def test_acceleration_and_joint_speed_options():
    parsed = parse_moves(export_text(two_frame_program(), {
        "linear_accel_m_s2": 0.5, "joint_accel_rad_s2": 0.8, "joint_speed_rad_s": 0.3,
        "no_such_option": 1}))
    assert parsed[0][2] == {"a": 0.8, "v": 0.3, "r": 0.01}
    assert parsed[1][2] == {"a": 0.5, "v": 0.0125, "r": 0.0003}


@pytest.mark.parametrize("options, match", [
    ({"linear_accel_m_s2": 0}, "linear_accel_m_s2"),
    ({"joint_accel_rad_s2": -1}, "joint_accel_rad_s2"),
    ({"joint_speed_rad_s": "fast"}, "joint_speed_rad_s"),
    ({"joint_speed_rad_s": float("nan")}, "joint_speed_rad_s"),
    ({"program_name": "1abc"}, "program_name"),
    ({"program_name": "movel"}, "program_name"),
    ({"program_name": "a b"}, "program_name"),
    ({"program_name": "x" * 33}, "program_name"),
    ({"linear_accel_m_s2": 1e-9}, "linear_accel_m_s2"),
    ({"joint_targets": "yes"}, "joint_targets"),
    ({"payload_function": "set_payload_mass"}, "payload_function"),
    ({"max_moves": -1}, "max_moves"),
    ({"max_moves": 2.5}, "max_moves"),
])
def test_bad_options_are_post_errors(options, match):
    with pytest.raises(PostError, match=match):
        ur_script.export(two_frame_program(), options)


def test_program_name_option():
    files = ur_script.export(two_frame_program(), {"program_name": "weld_1", "call": True})
    assert files[0][0] == "weld_1.script"
    lines = files[0][1].splitlines()
    assert lines[0] == "def weld_1():" and lines[-1] == "weld_1()"


def test_tool_payload_and_frames():
    program = two_frame_program()
    text = export_text(program)
    lines = [line.strip() for line in text.splitlines()]
    assert "set_payload(1.5, [0, 0, 0.12])" in lines
    m = re.search(r"set_tcp\(p\[([^\]]*)\]\)", text)
    assert_same_pose(matrix_scipy(np.array(m.group(1).split(","), float)),
                     program.tool.T_f_t, "tcp")
    poses = parse_poses(text)
    np.testing.assert_allclose(poses["Table"], [0.4, -0.2, 0.1, 0, 0, np.pi / 2], atol=1e-7)
    for comment in ("# Path: Weld seam", "# segment 2: arc Sketch.Edge2", "# Robot: UR5E.",
                    "# Table (CalibrationFrame)", "# Fixture (CalibrationFrame001)"):
        assert comment in lines


# --- names ----------------------------------------------------------------------------

def awkward_names_program():
    """Names URScript cannot take as they are."""
    program = minimal_program(name="3D Cell")
    program.frames = {"def": ir.WorkFrame("def", np.eye(4), np.eye(4))}
    names = ["A_very_long_target_name_made_by_a_generator_1",
             "A_very_long_target_name_made_by_a_generator_2",
             "p", "movel", "P1", "p1", "end", "3rd"]
    moves = [ir.Move(ir.LINEAR, ir.Target(n, pose(DOWN, (i, 0, 0))), 10, 0, "def")
             for i, n in enumerate(names)]
    program.paths = [ir.ProgramPath("Path", "Path", moves)]
    return program


def test_names_are_valid_unique_and_short():
    text = export_text(awkward_names_program())
    names = list(parse_poses(text))
    names.append(re.match(r"def (\w+)\(\):", text).group(1))
    assert len(names) == 1 + 8 + 1
    assert len({n.lower() for n in names}) == len(names)
    for name in names:
        assert ur_script.is_name(name), name
    assert text.startswith("def prog_3D_Cell():\n")
    assert "def_2 = p[" in text and "p_2 = p[" in text and "movel_2 = p[" in text
    assert "p1_2 = p[" in text and "t_3rd = p[" in text and "end_2 = p[" in text


def test_same_target_used_twice_is_declared_once():
    program = minimal_program()
    move = program.paths[0].moves[0]
    program.paths[0].moves.append(ir.Move(ir.LINEAR, move.target, 10, 0, "B"))
    text = export_text(program)
    assert text.count("t1 = p[") == 1
    assert text.count("pose_trans(B, t1)") == 2


# --- joint targets, blends, payload ---------------------------------------------------

JOINTS_RE = re.compile(r"^\s*movej\(\[([^\]]*)\]", re.MULTILINE)


def solved_program():
    from CadRobotWB.robots.kinematics import models
    from CadRobotWB.robots.motion import configuration
    program = two_frame_program()
    assert configuration.solve_program(program, models.model("UR5E")).ok
    return program


def test_joint_moves_go_to_the_solved_joints_which_reach_the_pose():
    from CadRobotWB.robots.kinematics import models
    program = solved_program()
    text = export_text(program)
    written = [np.array(m.split(","), float) for m in JOINTS_RE.findall(text)]
    joint_moves = [m for m in program.moves() if m.kind == ir.JOINT]
    assert len(written) == len(joint_moves) == 2
    robot = models.model("UR5E")
    for q_rad, move in zip(written, joint_moves):
        np.testing.assert_allclose(np.degrees(q_rad), move.target.joints_deg, atol=1e-5)
        T_r_t = robot.fk(np.degrees(q_rad)) @ program.tool.T_f_t
        T_ref = program.frames[move.frame].T_r_b @ move.target.T_b_t
        assert_same_pose(T_r_t, T_ref, move.target.name)
    # Targets reached only by joints are not declared as poses.
    assert "p1 = p[" not in text and "q1 = p[" not in text and "p2 = p[" in text
    cartesian = export_text(program, {"joint_targets": False})
    assert not JOINTS_RE.findall(cartesian) and "movej(pose_trans(Table, p1)" in cartesian


@pytest.mark.parametrize("zone_mm, text", [(0, "0"), (0.3, "0.0003"), (0.0004, "0"),
                                           (1.0000009, "0.001"), (2.5, "0.0025"),
                                           (4.35, "0.00435"), (10, "0.01")])
def test_blend_radius_is_never_larger_than_the_zone(zone_mm, text):
    assert ur_script.blend_text(zone_mm) == text


def test_blend_radius_rounding_on_random_zones():
    for zone in np.random.default_rng(3).uniform(0, 50, 2000):
        r_mm = 1000.0 * float(ur_script.blend_text(zone))
        assert zone - 1e-3 - 1e-9 <= r_mm <= zone + 1e-9


def test_payload_function_option():
    lines = [line.strip() for line in export_text(
        two_frame_program(), {"payload_function": "set_target_payload"}).splitlines()]
    assert "set_target_payload(1.5, [0, 0, 0.12])" in lines
    assert not any(line.startswith("set_payload(") for line in lines)


# --- long programs -----------------------------------------------------------------------

def test_a_program_longer_than_max_moves_is_split_into_runnable_parts():
    program = two_frame_program()                      # 10 moves
    files = ur_script.export(program, {"max_moves": 3})
    assert [f for f, _ in files] == [f"Cell_{k}.script" for k in (1, 2, 3, 4)]
    parsed = []
    for k, (filename, text) in enumerate(files, start=1):
        lines = text.splitlines()
        assert lines[0] == f"def Cell_{k}():" and lines[-2:] == ["end", f"Cell_{k}()"]
        moves = parse_moves(text)
        assert len(moves) == (3 if k < 4 else 1)
        if k < 4:
            assert moves[-1][2]["r"] == 0.0            # a part ends stopped
        # Each part declares what it uses and reaches the program's poses.
        poses = parse_poses(text)
        for _, points, _ in moves:
            for frame, point in points:
                assert frame in poses and point in poses
        parsed += moves
        assert f"# Part {k} of 4" in text
    whole = parse_moves(export_text(program))
    assert [(f, p) for f, p, _ in parsed] == [(f, p) for f, p, _ in whole]
    assert "# Path: Weld seam (continued)" in files[1][1]


def test_max_moves_zero_never_splits():
    assert len(ur_script.export(two_frame_program(), {"max_moves": 0})) == 1


def test_a_50000_move_program_exports_in_parts_of_5000_moves():
    import time
    program = post_programs.long_program("UR5E", 50000)
    start = time.perf_counter()
    files = ur_script.export(program, {})
    seconds = time.perf_counter() - start
    assert len(files) == 10
    counts = [len(parse_moves(text)) for _, text in files]
    assert counts == [5000] * 10
    first = files[0][1]
    assert JOINTS_RE.search(first)                     # the approach goes to joints
    assert seconds < 30, seconds


def test_every_option_read_is_declared():
    import inspect
    source = inspect.getsource(ur_script)
    read = set(re.findall(r'options(?:\.get\(|, )"(\w+)"', source))
    read |= set(re.findall(r'_option\(options, "(\w+)"', source))
    assert read and read <= set(ur_script.OPTIONS)
    from CadRobotWB import posts
    with pytest.raises(PostError, match="no option no_such_option"):
        posts.run(ur_script, two_frame_program(), {"no_such_option": 1})
