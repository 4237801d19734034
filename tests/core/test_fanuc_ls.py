"""Tests of the Fanuc LS post-processor (posts/fanuc_ls.py).

Programs are compared with golden files, parsed back (numbered ``/MN`` lines
against ``LINE_COUNT``, every ``P[n]`` used once and defined once, its UF
the active ``UFRAME_NUM``, its CONFIG) and their poses compared with the
program's, rebuilt here with scipy; the W, P, R convention is checked
against robodk's ``robomath`` (``Pose_2_Fanuc`` / ``Fanuc_2_Pose``).

The hand-made programs are those of test_motoman_inform.py.

To rewrite the golden files after a reviewed change of the output:
``CADROBOT_UPDATE_GOLDEN=1 python3 -m pytest tests/core/test_fanuc_ls.py``.
Golden files are stored with LF line ends; the programs end their lines
with CR LF (checked apart).
"""

import dataclasses
import datetime
import os
import re
from pathlib import Path

import numpy as np
import pytest

from CadRobotWB.core import program as ir
from CadRobotWB.errors import PostError
from CadRobotWB.posts import fanuc_ls
from CadRobotWB.robots.kinematics import models
from CadRobotWB.robots.motion import configuration

from test_motoman_inform import (ANGLE_TOL_DEG, DOWN, POSE_ANGLE_TOL_DEG, POSITION_TOL_MM,
                                 ROBODK_MISSING, ROBOT, configured_program, flipped_contour_program,
                                 matrix_from_values,
                                 minimal_program, near_gimbal_lock, needs_robodk, pose,
                                 robomath, rotation_error_deg, two_frame_program, wrap180)

GOLDEN_DIR = Path(__file__).parent / "golden"


def export_text(program, options=None):
    files = fanuc_ls.export(program, options or {})
    assert len(files) == 1
    return files[0][1]


# --- parsing our own output ---------------------------------------------------

NUMBERED = re.compile(r"^ *(\d+):(.*)$")
CONTINUATION = re.compile(r"^    :  (.*)$")
P_RECORD = re.compile(
    r"^P\[(\d+)\]\{\n   GP1:\n"
    r"\tUF : (\d+), UT : (\d+),\t\tCONFIG : '([^']*)',\n"
    r"\tX = *(-?[\d.]+)  mm,\tY = *(-?[\d.]+)  mm,\tZ = *(-?[\d.]+)  mm,\n"
    r"\tW = *(-?[\d.]+) deg,\tP = *(-?[\d.]+) deg,\tR = *(-?[\d.]+) deg\n"
    r"\};$", re.MULTILINE)
MOTION = re.compile(r"^(J|L) P\[(\d+)\] (\S+) (FINE|CNT\d+)    $")
J_RECORD = re.compile(
    r"^P\[(\d+)\]\{\n   GP1:\n"
    r"\tUF : (\d+), UT : (\d+),\t\n"
    r"\tJ1= *(-?[\d.]+) deg,\tJ2= *(-?[\d.]+) deg,\tJ3= *(-?[\d.]+) deg,\n"
    r"\tJ4= *(-?[\d.]+) deg,\tJ5= *(-?[\d.]+) deg,\tJ6= *(-?[\d.]+) deg\n"
    r"\};$", re.MULTILINE)


@dataclasses.dataclass
class LsProgram:
    name: str
    attr: dict
    lines: list          # (number, text of the instruction, continuation or None)
    positions: dict      # n -> (uf, ut, config, values (6,)); config None: J1..J6 in values
    position_order: list


def parse_ls(text):
    """Parse an LS program: /PROG, /ATTR, numbered /MN lines, /POS records."""
    assert text.endswith("\r\n") and "\n" not in text.replace("\r\n", "")
    lines = text.split("\r\n")[:-1]
    assert lines[0].startswith("/PROG  ") and lines[1] == "/ATTR" and lines[-1] == "/END"
    mn, pos = lines.index("/MN"), lines.index("/POS")
    attr = {}
    for line in lines[2:mn]:
        m = re.match(r"^\s*(\w+)(?::\s+(\w+))?\s*=\s*(.*?)[;,]$", line)
        assert m, line
        attr[m.group(2) or m.group(1)] = m.group(3)
    numbered = []
    for line in lines[mn + 1:pos]:
        m = CONTINUATION.match(line)
        if m:
            number, body, _ = numbered[-1]
            assert body.startswith("C P[")
            numbered[-1] = (number, body, m.group(1))
            continue
        m = NUMBERED.match(line)
        assert m, line
        numbered.append((int(m.group(1)), m.group(2), None))
    block = "\n".join(lines[pos + 1:-1])
    records = [(m.start(), m.groups()) for m in P_RECORD.finditer(block)]
    records += [(m.start(), m.groups()[:3] + (None,) + m.groups()[3:])
                for m in J_RECORD.finditer(block)]
    records = [r for _, r in sorted(records)]
    assert len(records) == block.count("P["), "every record must match the format"
    positions = {int(r[0]): (int(r[1]), int(r[2]), r[3], np.array(r[4:10], dtype=float))
                 for r in records}
    return LsProgram(lines[0][len("/PROG  "):], attr, numbered, positions,
                     [int(r[0]) for r in records])


def motions(ls):
    """[(kind, [P numbers], speed, termination, active UF, active UT)] of the /MN lines."""
    out, uf, ut = [], None, None
    for _, body, continuation in ls.lines:
        if body.startswith("  UFRAME_NUM="):
            uf = int(body.split("=")[1].rstrip(" ;"))
        elif body.startswith("  UTOOL_NUM="):
            ut = int(body.split("=")[1].rstrip(" ;"))
        elif body.startswith("C P["):
            via = int(re.match(r"C P\[(\d+)\]    $", body).group(1))
            m = re.match(r"P\[(\d+)\] (\S+) (FINE|CNT\d+)    ;$", continuation)
            out.append(("C", [via, int(m.group(1))], m.group(2), m.group(3), uf, ut))
        elif not body.startswith("  "):
            m = MOTION.match(body[:-1])
            assert m, body
            out.append((m.group(1), [int(m.group(2))], m.group(3), m.group(4), uf, ut))
        else:
            assert re.fullmatch(r"  (!.*|CALL [A-Z][A-Z0-9_]*|PAYLOAD\[\d+\]) ;", body), body
    return out


def comments(ls):
    return [body[3:-2] for _, body, _ in ls.lines if body.startswith("  !")]


def expected_positions(program):
    """[(T_b_t, frame, joints)] in P order: a circular move's via, then its end."""
    out = []
    for move in program.moves():
        if move.kind == ir.CIRCULAR:
            out.append((move.via.T_b_t, move.frame, move.via.joints_deg))
        out.append((move.target.T_b_t, move.frame, move.target.joints_deg))
    return out


# --- golden files -------------------------------------------------------------

GOLDEN = [
    ("fanuc_ls_two_frames.LS", two_frame_program, {}),
    ("fanuc_ls_configured.LS", configured_program, {}),
    ("fanuc_ls_minimal.LS", minimal_program,
     {"user_frame": 3, "tool": 2, "date": datetime.datetime(2024, 5, 6, 7, 8, 9)}),
]


@pytest.mark.parametrize("name, build, options", GOLDEN, ids=[g[0] for g in GOLDEN])
def test_golden_output(name, build, options):
    plain = export_text(build(), options).replace("\r\n", "\n")
    golden = GOLDEN_DIR / name
    if os.environ.get("CADROBOT_UPDATE_GOLDEN"):
        golden.write_text(plain, newline="\n")
    assert golden.exists(), f"missing {golden}; see this file's docstring"
    assert plain == golden.read_text()


def test_export_is_deterministic_named_after_program_and_crlf():
    program = two_frame_program()
    first = fanuc_ls.export(program, {})
    assert first == fanuc_ls.export(program, None)
    assert [f for f, _ in first] == ["CELL.LS"]
    text = first[0][1]
    assert text.count("\r\n") == text.count("\n") and text.endswith("/END\r\n")
    assert text.isascii()


# --- structure ----------------------------------------------------------------

@pytest.mark.parametrize("build", [two_frame_program, configured_program, minimal_program])
def test_line_count_and_numbering(build):
    ls = parse_ls(export_text(build()))
    assert int(ls.attr["LINE_COUNT"]) == len(ls.lines)
    assert [n for n, _, _ in ls.lines] == list(range(1, len(ls.lines) + 1))


@pytest.mark.parametrize("build", [two_frame_program, configured_program, minimal_program])
def test_every_position_is_used_once_and_defined_in_order(build):
    program = build()
    ls = parse_ls(export_text(program))
    used = [n for m in motions(ls) for n in m[1]]
    assert used == list(range(1, len(expected_positions(program)) + 1))
    assert ls.position_order == used


def test_attributes_and_header():
    text = export_text(two_frame_program(), {"date": datetime.datetime(2023, 7, 9, 16, 0, 48)})
    lines = text.split("\r\n")
    assert lines[0] == "/PROG  CELL"
    ls = parse_ls(text)
    assert ls.attr["OWNER"] == "MNEDITOR" and ls.attr["COMMENT"] == '"CadRobot"'
    assert ls.attr["CREATE"] == ls.attr["MODIFIED"] == "DATE 23-07-09  TIME 16:00:48"
    assert ls.attr["PROTECT"] == "READ_WRITE" and ls.attr["DEFAULT_GROUP"] == "1,*,*,*,*"
    assert ls.attr["STACK_SIZE"] == "0" and ls.attr["PAUSE_REQUEST"] == "0"
    for key in ("PROG_SIZE", "FILE_NAME", "VERSION", "MEMORY_SIZE", "CONTROL_CODE"):
        assert key in ls.attr
    default = parse_ls(export_text(two_frame_program()))
    assert default.attr["CREATE"] == "DATE 00-01-01  TIME 00:00:00"


# --- poses, frames, configurations ----------------------------------------------

def test_positions_recover_every_pose_frame_and_tool():
    program = two_frame_program()
    ls = parse_ls(export_text(program, {"user_frame": 4, "tool": 7}))
    users = {"Table": 4, "Fixture": 5}
    expected = expected_positions(program)
    assert len(ls.positions) == len(expected) == 11
    for n, (T, frame, _) in enumerate(expected, start=1):
        uf, ut, config, values = ls.positions[n]
        recovered = matrix_from_values(values)
        assert np.abs(recovered[:3, 3] - T[:3, 3]).max() <= POSITION_TOL_MM
        assert rotation_error_deg(recovered[:3, :3], T[:3, :3]) <= POSE_ANGLE_TOL_DEG
        assert (uf, ut, config) == (users[frame], 7, "N U T, 0, 0, 0")


def test_each_position_is_in_the_active_user_frame_and_tool():
    ls = parse_ls(export_text(two_frame_program(), {"user_frame": {"Table": 9, "Fixture": 0}}))
    seen = []
    for _, numbers, _, _, uf, ut in motions(ls):
        for n in numbers:
            assert (ls.positions[n][0], ls.positions[n][1]) == (uf, ut)
            seen.append(uf)
    assert seen == [9] * 7 + [0] * 4


def test_random_orientations_round_trip():
    """Positions within 5e-4 mm, each W, P, R within 5e-5 degree of the exact
    angle, the orientation within 1.5e-4 degree."""
    from scipy.spatial.transform import Rotation
    rng = np.random.default_rng(11)
    rotations_ = list(Rotation.random(150, random_state=5))
    rotations_ += [Rotation.from_euler("xyz", e, degrees=True)
                   for e in [(0, 90, 30), (20, -90, 0), (180, 0, 180), (-180, 45, -180)]]
    tool = ir.ToolData("Tool", np.eye(4))
    frames = {"B": ir.WorkFrame("B", np.eye(4), np.eye(4))}
    moves = []
    for k, R in enumerate(rotations_):
        T = np.eye(4)
        T[:3, :3] = R.as_matrix()
        T[:3, 3] = rng.uniform(-2000, 2000, 3)
        moves.append(ir.Move(ir.LINEAR, ir.Target(f"t{k}", T), 10, 0, "B"))
    program = ir.Program("Random", ROBOT, tool, frames, [ir.ProgramPath("P", "P", moves)])
    ls = parse_ls(export_text(program))
    for n, move in enumerate(moves, start=1):
        T, values = move.target.T_b_t, ls.positions[n][3]
        recovered = matrix_from_values(values)
        assert np.abs(recovered[:3, 3] - T[:3, 3]).max() <= 5e-4 + 1e-9
        assert rotation_error_deg(recovered[:3, :3], T[:3, :3]) <= POSE_ANGLE_TOL_DEG
        if not near_gimbal_lock(T):
            exact = np.degrees(Rotation.from_matrix(T[:3, :3]).as_euler("xyz"))
            assert np.abs(wrap180(values[3:] - exact)).max() <= ANGLE_TOL_DEG


def test_angle_decimals_option():
    ls = parse_ls(export_text(two_frame_program(), {"angle_decimals": 3}))
    text = export_text(two_frame_program(), {"angle_decimals": 3})
    assert "W =   180.000 deg," in text and "X =     0.000  mm," in text
    assert len(ls.positions) == 11
    with pytest.raises(PostError, match="angle_decimals"):
        fanuc_ls.export(two_frame_program(), {"angle_decimals": 5})


def test_number_format():
    text = export_text(two_frame_program())
    assert "-0.000" not in text
    for record in P_RECORD.findall(text.replace("\r\n", "\n")):
        assert all(re.fullmatch(r"-?\d+\.\d{3}", v) for v in record[4:7])
        assert all(re.fullmatch(r"-?\d+\.\d{4}", v) for v in record[7:10])


@needs_robodk
def test_w_p_r_agree_with_robodk_pose_2_fanuc():
    """Our W, P, R are robodk's Pose_2_Fanuc angles (away from gimbal lock),
    and robodk's Fanuc_2_Pose rebuilds our printed values into the pose."""
    assert not ROBODK_MISSING, ROBODK_MISSING
    rng = np.random.default_rng(5)
    eulers = [tuple(v) for v in rng.uniform([-180, -90, -180], [180, 90, 180], (100, 3))]
    eulers += [(0, 90, 30), (0, -90, -120), (180, 0, 0), (0, 0, 180), (-170, 60, 170)]
    for e in eulers:
        T = pose(e, rng.uniform(-1000, 1000, 3))
        ours = np.array(fanuc_ls.pose_values(T), dtype=float)
        ref = np.array(robomath.Pose_2_Fanuc(robomath.Mat(T.tolist())), dtype=float)
        np.testing.assert_allclose(ours[:3], ref[:3], atol=5e-4)
        if not near_gimbal_lock(T):
            assert np.abs(wrap180(ours[3:] - ref[3:])).max() <= ANGLE_TOL_DEG, (e, ours, ref)
        rebuilt = np.array(robomath.Fanuc_2_Pose(ours.tolist()).rows)
        assert np.abs(rebuilt[:3, 3] - T[:3, 3]).max() <= POSITION_TOL_MM
        assert rotation_error_deg(rebuilt[:3, :3], T[:3, :3]) <= POSE_ANGLE_TOL_DEG


@needs_robodk
def test_program_positions_decode_with_robodk():
    assert not ROBODK_MISSING, ROBODK_MISSING
    program = configured_program()
    ls = parse_ls(export_text(program, {"joint_targets": False}))
    for n, (T, _, _) in enumerate(expected_positions(program), start=1):
        rebuilt = np.array(robomath.Fanuc_2_Pose(ls.positions[n][3].tolist()).rows)
        assert np.abs(rebuilt[:3, 3] - T[:3, 3]).max() <= POSITION_TOL_MM
        assert rotation_error_deg(rebuilt[:3, :3], T[:3, :3]) <= POSE_ANGLE_TOL_DEG


def test_config_comes_from_the_joints():
    program = flipped_contour_program()
    text = export_text(program, {"joint_targets": False})
    ls = parse_ls(text)
    robot = models.model(ROBOT)
    for n, (_, _, joints) in enumerate(expected_positions(program), start=1):
        assert ls.positions[n][2] == configuration.fanuc_config(joints, robot)
    with_joints = parse_ls(export_text(program))
    joint = [flag for move in program.moves()
             for flag in ([False, False] if move.kind == ir.CIRCULAR else [move.kind == ir.JOINT])]
    assert sum(joint) == 2
    for n, is_joint in enumerate(joint, start=1):
        assert (with_joints.positions[n][2] is None) == is_joint
        if not is_joint:
            assert with_joints.positions[n][:3] == ls.positions[n][:3]
    assert ls.positions[1][2] == "N U T, 0, 0, 0"      # the seam
    assert ls.positions[11][2] == "F U T, 0, 0, 0"     # the contour: wrist flipped
    assert "CONFIG: the checked arm config" in comments(ls)


def test_targets_without_joints_get_the_default_config_and_say_so():
    program = flipped_contour_program()
    program.paths[1].moves[2].target.joints_deg = None        # q3 = P[10]
    ls = parse_ls(export_text(program))
    assert ls.positions[10][2] == "N U T, 0, 0, 0"
    assert ls.positions[9][2] == "F U T, 0, 0, 0"
    assert "CONFIG 'N U T, 0, 0, 0' where" in comments(ls)
    program.robot = "SOME_OTHER_ROBOT"
    with pytest.raises(PostError, match="joint_targets=false"):
        export_text(program)            # the joints' convention is unknown
    ls = parse_ls(export_text(program, {"joint_targets": False}))
    assert {p[2] for p in ls.positions.values()} == {"N U T, 0, 0, 0"}


# --- instructions -------------------------------------------------------------

def test_instructions():
    text = export_text(two_frame_program())
    # Line 50: the header has 6 lines saying the program is for another maker's robot.
    assert "  50:C P[5]    \r\n    :  P[6] 75cm/min FINE    ;\r\n" in text
    ls = parse_ls(text)
    assert [(kind, numbers, speed, term) for kind, numbers, speed, term, _, _ in motions(ls)] == [
        ("J", [1], "10%", "CNT100"),             # zone 10 mm: 1 mm or more is CNT100
        ("L", [2], "75cm/min", "CNT30"),         # 12.5 mm/s, zone 0.3 mm / 0.01 mm per step
        ("L", [3], "75cm/min", "CNT30"),
        ("L", [4], "75cm/min", "CNT30"),
        ("C", [5, 6], "75cm/min", "FINE"),
        ("L", [7], "100mm/sec", "FINE"),
        ("J", [8], "10%", "CNT100"),
        ("L", [9], "75cm/min", "CNT100"),        # zone 2.5 mm
        ("L", [10], "75cm/min", "FINE"),
        ("L", [11], "100mm/sec", "FINE"),
    ]
    bodies = [body for _, body, _ in ls.lines]
    assert bodies.index("  UFRAME_NUM=1 ;") < bodies.index("  UTOOL_NUM=1 ;") < \
        bodies.index("J P[1] 10% CNT100    ;")


@pytest.mark.parametrize("zone, cnt_mm, text", [
    (0, 1, "FINE"), (0.3, 1, "FINE"), (0.999, 1, "FINE"), (1, 1, "CNT1"), (2.5, 1, "CNT2"),
    (10, 1, "CNT10"), (99.4, 1, "CNT99"), (250, 1, "CNT100"),
    (0.3, 0.1, "CNT3"), (0.35, 0.1, "CNT3"), (4.9, 2.5, "CNT1"), (5, 2.5, "CNT2")])
def test_termination_rule(zone, cnt_mm, text):
    assert fanuc_ls.termination(zone, cnt_mm) == text


def test_termination_never_rounds_more_than_asked():
    """Under the rule CNTn = n * cnt_mm, no zone is written larger than asked, and
    no smaller by a whole step (or more) unless capped at CNT100."""
    rng = np.random.default_rng(3)
    for zone, cnt_mm in zip(rng.uniform(0, 150, 2000), rng.choice([0.1, 0.5, 1, 2.5], 2000)):
        text = fanuc_ls.termination(zone, cnt_mm)
        written = 0.0 if text == "FINE" else int(text[3:]) * cnt_mm
        assert written <= zone + 1e-9
        assert zone - written < cnt_mm or text == "CNT100"


def test_cnt_mm_option():
    ls = parse_ls(export_text(two_frame_program(), {"cnt_mm": 0.1}))
    assert [m[3] for m in motions(ls)][:3] == ["CNT100", "CNT3", "CNT3"]
    assert "CNTn: n = zone / 0.1 mm" in comments(ls)


@pytest.mark.parametrize("speed, text", [(100, "100mm/sec"), (12.5, "75cm/min"),
                                         (10.3, "62cm/min"), (0.5, "3cm/min"),
                                         (1, "1mm/sec"), (2000, "2000mm/sec")])
def test_linear_speed_rule(speed, text):
    assert fanuc_ls.linear_speed(speed) == text


def test_joint_speed_options():
    ls = parse_ls(export_text(two_frame_program(), {"joint_speed_percent": 30}))
    assert motions(ls)[0][2] == "30%"
    ls = parse_ls(export_text(two_frame_program(), {"joint_speed_reference_mm_s": 400}))
    assert motions(ls)[0][2] == "25%"
    assert fanuc_ls.joint_speed_percent(1) == 1 and fanuc_ls.joint_speed_percent(5000) == 100


def test_comments_name_paths_and_segments():
    ls = parse_ls(export_text(two_frame_program()))
    found = comments(ls)
    for expected in ("Path: Weld seam", "segment 1: line Sketch.Edge1",
                     "segment 2: arc Sketch.Edge2", "Path: Edge contour", "Units: mm, deg",
                     "Source: demo.FCStd / Cell", "Robot: MOTOMAN_HP6"):
        assert expected in found
    assert max(len(c) for c in found) <= 32
    program = two_frame_program()
    program.paths[0].moves[0].comment = 'approach; "quoted"'
    found = comments(parse_ls(export_text(program)))
    assert "approach quoted" in found


def test_frame_and_tool_values_in_the_comments():
    program = two_frame_program()
    found = comments(parse_ls(export_text(program, {"user_frame": 2, "tool": 5})))

    def values_after(title):
        i = found.index(title)
        pairs = re.findall(r"\b(X|Y|Z|W|P|R)=(-?[\d.]+)", " ".join(found[i + 1:i + 4]))
        d = {k: float(v) for k, v in pairs}
        return matrix_from_values([d[k] for k in "XYZWPR"])

    assert np.abs(values_after("UFRAME 2 = Table") - program.frames["Table"].T_r_b).max() < 1e-3
    assert np.abs(values_after("UFRAME 3 = Fixture")
                  - program.frames["Fixture"].T_r_b).max() < 1e-3
    assert np.abs(values_after("UTOOL 5 = Torch (faceplate)") - program.tool.T_f_t).max() < 1e-3
    assert "Payload 1.5 kg" in found and "CoG Z=120.000" in found


# --- names --------------------------------------------------------------------

def test_program_names():
    assert fanuc_ls.program_name("Cell") == "CELL"
    resume = fanuc_ls.program_name("Cell_resume")
    corrected = fanuc_ls.program_name("Cell_corrected")
    assert resume != corrected and len(resume) == len(corrected) == 8
    assert fanuc_ls.program_name("3D cell") == "P3D_CELL"
    assert fanuc_ls.program_name("Cell_corrected", 36) == "CELL_CORRECTED"
    files = fanuc_ls.export(two_frame_program(), {"program_name": "weld_1"})
    assert files[0][0] == "WELD_1.LS" and files[0][1].startswith("/PROG  WELD_1\r\n")
    program = two_frame_program()
    program.name = "Seam_with_a_long_name"
    assert fanuc_ls.export(program, {})[0][0] == fanuc_ls.program_name(program.name) + ".LS"
    assert fanuc_ls.export(program, {"max_name_length": 36})[0][0] == "SEAM_WITH_A_LONG_NAME.LS"
    for bad in ("1ABC", "A B", "TOOLONGNAME", ""):
        with pytest.raises(PostError, match="Program name"):
            fanuc_ls.export(two_frame_program(), {"program_name": bad})


# --- what LS cannot express -----------------------------------------------------

def test_speed_below_one_cm_per_min_is_a_post_error():
    # What every post refuses is in test_posts_refuse.py.
    program = minimal_program()
    program.paths[0].moves[0].speed_mm_s = 0.05
    with pytest.raises(PostError, match="1 cm/min"):
        fanuc_ls.export(program, {})


def test_circular_move_without_via_is_a_post_error():
    with pytest.raises(PostError, match="via"):
        fanuc_ls.export(minimal_program(move_kind=ir.CIRCULAR), {})
    via = ir.Target("v", pose(DOWN, (5, 5, 0)))
    text = export_text(minimal_program(move_kind=ir.CIRCULAR, via=via))
    assert "C P[1]    \r\n    :  P[2] 10mm/sec FINE    ;" in text


@pytest.mark.parametrize("options, match", [
    ({"user_frame": 10}, "user_frame"),
    ({"user_frame": 9}, "beyond UF 9"),
    ({"user_frame": {"Table": 1}}, "Fixture"),
    ({"user_frame": {"Table": 1, "Fixture": 1}}, "same number"),
    ({"tool": 0}, "tool"),
    ({"tool": 11}, "tool"),
    ({"joint_speed_percent": 0}, "joint_speed_percent"),
    ({"joint_speed_reference_mm_s": 0}, "joint_speed_reference_mm_s"),
    ({"max_name_length": 37}, "max_name_length"),
    ({"date": "2024"}, "date"),
    ({"joint_targets": "maybe"}, "joint_targets must be true or false"),
    ({"joint_targets": 1}, "joint_targets"),
    ({"max_lines": 3}, "max_lines must be a whole number from 4 to 9999"),
    ({"max_lines": 10000}, "max_lines"),
    ({"max_lines": 100.0}, "max_lines"),
    ({"max_positions": 1}, "max_positions"),
    ({"max_positions": 10000}, "max_positions"),
    ({"cnt_mm": 0}, "cnt_mm"),
    ({"cnt_mm": float("nan")}, "cnt_mm"),
    ({"cnt_mm": float("inf")}, "cnt_mm"),
    ({"cnt_mm": "1"}, "cnt_mm"),
    ({"payload_schedule": 0}, "payload_schedule"),
    ({"payload_schedule": 11}, "payload_schedule"),
    ({"payload_schedule": True}, "payload_schedule"),
    ({"joint_speed_percent": None}, "joint_speed_percent"),
    ({"joint_speed_reference_mm_s": float("nan")}, "joint_speed_reference_mm_s"),
    ({"angle_decimals": "4"}, "angle_decimals"),
])
def test_bad_options_are_post_errors(options, match):
    with pytest.raises(PostError, match=match):
        fanuc_ls.export(two_frame_program(), options)


# --- joint targets ----------------------------------------------------------------

FANUC = "FANUC_M20IA"


def fanuc_program(n_moves=40):
    from post_programs import long_program
    return long_program(FANUC, n_moves)


def test_joint_positions_give_the_target_pose_through_the_model():
    """J1..J6 of each joint position, taken back to model joints with the model's
    model_joints and put through fk, give the move's flange pose T_r_b T_b_t inv(T_f_t);
    on this FANUC arm the written J3 is not the model's q3 (J2/J3 interaction)."""
    program = fanuc_program()
    files = fanuc_ls.export(program, {})
    ls = parse_ls(files[0][1])
    robot = models.model(FANUC)
    joint_moves = [(n, move) for n, move in enumerate(program.moves(), start=1)
                   if move.kind == ir.JOINT]
    assert [n for n, _ in joint_moves] == [1]
    n, move = joint_moves[0]
    uf, ut, config, written = ls.positions[n]
    assert config is None and (uf, ut) == (1, 1)
    frame = program.frames[move.frame]
    expected = frame.T_r_b @ move.target.T_b_t @ np.linalg.inv(program.tool.T_f_t)
    flange = robot.fk(robot.model_joints(written))
    assert np.abs(flange[:3, 3] - expected[:3, 3]).max() < 0.05
    assert rotation_error_deg(flange[:3, :3], expected[:3, :3]) < 1e-3
    q = move.target.joints_deg
    assert abs(written[2] - (q[2] - q[1])) < 1e-4 and abs(q[1]) > 1   # J3 = q3 - q2 here
    wrong = robot.fk(written)                                         # J3 taken as q3
    assert np.abs(wrong[:3, 3] - expected[:3, 3]).max() > 1.0


def test_joint_targets_off_writes_the_cartesian_position():
    program = fanuc_program()
    ls = parse_ls(export_text(program, {"joint_targets": False}))
    uf, ut, config, values = ls.positions[1]
    assert config == configuration.fanuc_config(program.moves()[0].target.joints_deg,
                                                models.model(FANUC))
    T = program.moves()[0].target.T_b_t
    assert np.abs(matrix_from_values(values) - T).max() < 1e-3
    assert all(p[2] is not None for p in ls.positions.values())


def test_joint_move_without_joints_stays_cartesian():
    program = fanuc_program()
    program.moves()[0].target.joints_deg = None
    ls = parse_ls(export_text(program))
    assert ls.positions[1][2] == "N U T, 0, 0, 0"


# --- long programs ------------------------------------------------------------------

def split_export(program, options):
    """{name: LsProgram} of every file, and the names in file order."""
    files = fanuc_ls.export(program, options)
    parsed = {}
    for file_name, text in files:
        ls = parse_ls(text)
        assert file_name == ls.name + ".LS"
        parsed[ls.name] = ls
    assert len(parsed) == len(files), "program names must be unique"
    return parsed, [f[:-3] for f, _ in files]


def check_program_limits(ls, max_lines, max_positions, name_length=8):
    """LINE_COUNT = the /MN lines, numbered 1..n <= max_lines; every P[n] used is
    declared once in this file's /POS, at most max_positions of them."""
    assert int(ls.attr["LINE_COUNT"]) == len(ls.lines) <= max_lines
    assert [n for n, _, _ in ls.lines] == list(range(1, len(ls.lines) + 1))
    used = [n for m in motions(ls) for n in m[1]]
    assert used == list(range(1, len(used) + 1)) == ls.position_order
    assert len(used) <= max_positions
    assert fanuc_ls.is_program_name(ls.name, name_length)


def check_split(program, options, max_lines, max_positions):
    """Every part within the limits; the main calls every part once, in file order,
    and the parts' moves in that order are the program's moves, in the active frame."""
    parsed, names = split_export(program, options)
    main, parts = parsed[names[0]], names[1:]
    assert len(parts) >= 2
    for name in names:
        check_program_limits(parsed[name], max_lines, max_positions)
    calls = [body.strip()[5:-2] for _, body, _ in main.lines if body.strip().startswith("CALL ")]
    assert calls == parts
    assert not motions(main) and not main.positions
    written = []
    for name in parts:
        ls = parsed[name]
        for kind, numbers, speed, term, uf, ut in motions(ls):
            for n in numbers:
                assert ls.positions[n][:2] == (uf, ut)
            written.append((kind, [ls.positions[n] for n in numbers]))
    moves = program.moves()
    assert len(written) == len(moves)
    for (kind, records), move in zip(written, moves):
        assert kind == fanuc_ls._MOTION[move.kind]
        targets = [move.via, move.target] if move.kind == ir.CIRCULAR else [move.target]
        for (_, _, config, values), target in zip(records, targets):
            if config is None:
                assert np.abs(values - models.model(program.robot).controller_joints(
                    target.joints_deg)).max() < 1e-3
            else:
                assert np.abs(matrix_from_values(values)[:3, 3] - target.T_b_t[:3, 3]).max() \
                    < 1e-3
    return parsed, names


def test_a_long_program_is_split_at_max_lines():
    program = fanuc_program(300)
    parsed, names = check_split(program, {"max_lines": 60}, 60, 9999)
    assert names == ["LONG"] + [f"LONG_{k}" for k in range(1, 7)]     # 304 entries, 57 a part
    first = parsed[names[1]]
    assert [body for _, body, _ in first.lines[:3]] == [
        "  !Part 1 of %d of LONG ;" % (len(names) - 1), "  UFRAME_NUM=1 ;", "  UTOOL_NUM=1 ;"]
    assert max(len(parsed[n].lines) for n in names[1:]) == 60


def test_a_long_program_is_split_at_max_positions():
    program = fanuc_program(300)
    parsed, names = check_split(program, {"max_positions": 50}, 9999, 50)
    counts = [len(parsed[n].positions) for n in names[1:]]
    assert max(counts) in (49, 50) and sum(counts) == sum(
        2 if m.kind == ir.CIRCULAR else 1 for m in program.moves())


def test_each_part_starts_in_the_frame_active_where_it_starts():
    program = two_frame_program()
    parsed, names = check_split(program, {"max_positions": 3}, 9999, 3)
    frames = [parsed[name].lines[1][1] for name in names[1:]]
    assert frames == sorted(frames) and frames[0] != frames[-1]   # table, then fixture


def test_a_program_that_fits_is_one_file_at_the_limit():
    program = two_frame_program()
    lines = len(parse_ls(export_text(program)).lines)
    assert len(fanuc_ls.export(program, {"max_lines": lines})) == 1
    assert len(fanuc_ls.export(program, {"max_lines": lines - 1, "max_name_length": 12})) > 1
    assert len(fanuc_ls.export(program, {"max_positions": 11})) == 1
    assert len(fanuc_ls.export(program, {"max_positions": 10})) > 1


@pytest.mark.parametrize("main, count, length, expected", [
    ("LONG", 6, 8, ["LONG_1", "LONG_6"]),
    ("SEAMWELD", 12, 8, ["SEAMW_01", "SEAMW_12"]),
    ("ABCDEF_1", 3, 8, ["ABCDEFP1", "ABCDEFP3"]),    # '_' would give the main's own name
    ("A", 1000, 8, ["A_0001", "A_1000"]),
])
def test_part_names(main, count, length, expected):
    names = fanuc_ls.part_names(main, count, length)
    assert [names[0], names[-1]] == expected
    assert len(set(names + [main])) == count + 1
    assert all(fanuc_ls.is_program_name(n, length) for n in names)


def test_part_names_need_room():
    with pytest.raises(PostError, match="max_name_length"):
        fanuc_ls.part_names("LONG", 100, 3)


def test_main_too_long_for_max_lines_is_a_post_error():
    with pytest.raises(PostError, match="raise max_lines"):
        fanuc_ls.export(fanuc_program(300), {"max_lines": 20})


@pytest.fixture(scope="module")
def fifty_thousand_moves():
    return fanuc_program(50000)


def test_fifty_thousand_moves_export_within_the_controller_limits(fifty_thousand_moves):
    import time
    start = time.perf_counter()
    parsed, names = check_split(fifty_thousand_moves, {}, 9999, 9999)
    elapsed = time.perf_counter() - start
    # 50,000 moves, 12,499 of them arcs: 62,499 positions need 7 parts of <= 9,999
    # (the 50,004 lines alone would fit in 6 parts of 9,996)
    assert len(names) - 1 == 7
    print(f"50,000 moves: {len(names)} files, export and check {elapsed:.1f} s")


# --- options ------------------------------------------------------------------------

def test_payload_schedule_option():
    ls = parse_ls(export_text(two_frame_program(), {"payload_schedule": 3}))
    bodies = [body for _, body, _ in ls.lines]
    assert bodies.index("  UTOOL_NUM=1 ;") + 1 == bodies.index("  PAYLOAD[3] ;")
    assert bodies.index("  PAYLOAD[3] ;") < bodies.index("J P[1] 10% CNT100    ;")
    assert "PAYLOAD[3]: Payload 1.5 kg" in comments(ls)
    assert "PAYLOAD[" not in export_text(two_frame_program())


def test_every_declared_option_is_taken_and_others_are_refused():
    from CadRobotWB import posts
    good = {"program_name": "W1", "max_name_length": 10, "user_frame": 2, "tool": 3,
            "joint_speed_percent": 20, "joint_speed_reference_mm_s": 500.0,
            "angle_decimals": 3, "joint_targets": False, "max_lines": 500,
            "max_positions": 400, "cnt_mm": 0.5, "payload_schedule": 2,
            "weld_schedule": 3, "weld_speed": "explicit",
            "date": datetime.datetime(2024, 1, 1)}
    assert set(good) == set(fanuc_ls.OPTIONS) | {"date"}
    assert posts.run(fanuc_ls, two_frame_program(), good)[0][0] == "W1.LS"
    with pytest.raises(PostError, match="no option joint_target\\b"):
        posts.run(fanuc_ls, two_frame_program(), {"joint_target": True})
