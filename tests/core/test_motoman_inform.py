"""Tests of the Yaskawa Motoman INFORM post-processor (posts/motoman_inform.py).

Jobs are compared with golden files, parsed back (every C position, its
user frame and RCONF, NPOS against the C lines and the move instructions)
and their poses compared with the program's, rebuilt here with scipy; the
Rx, Ry, Rz convention is checked against robodk's ``robomath``
(``Pose_2_Motoman`` / ``Motoman_2_Pose``, PyPI ``robodk``, installed for the
tests by tools/setup.sh).

To rewrite the golden files after a reviewed change of the output:
``CADROBOT_UPDATE_GOLDEN=1 python3 -m pytest tests/core/test_motoman_inform.py``.
Golden files are stored with LF line ends; the jobs end their lines with
CR LF (checked apart).
"""

import dataclasses
import datetime
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
from CadRobotWB.posts import motoman_inform
from CadRobotWB.robots.kinematics import models
from CadRobotWB.robots.motion import configuration

from robodk_check import ROBODK_MISSING, needs_robodk, robomath  # noqa: E402,F401

GOLDEN_DIR = Path(__file__).parent / "golden"
ROBOT = "MOTOMAN_HP6"

#: Rx, Ry, Rz are written with 4 decimals (the controller's 0.0001 degree):
#: each angle is within 5e-5 degree of the exact one, so the orientation is
#: within 1.5e-4 degree (three half steps) in the worst case, and the
#: position within 5e-4 mm.
ANGLE_TOL_DEG = 5e-5 + 1e-9
POSE_ANGLE_TOL_DEG = 1.5e-4
POSITION_TOL_MM = 1e-3


# --- programs built by hand ---------------------------------------------------



def two_frame_program(robot=ROBOT):
    return post_programs.two_frame_program(robot)


def configured_program():
    """two_frame_program with every target's joints solved for the HP6 (all
    reachable, both paths in the natural arm configuration: wrist not flipped,
    upper arm, front)."""
    program = two_frame_program()
    solution = configuration.solve_program(program, models.model(ROBOT))
    assert solution.ok
    return program


def flipped_contour_program():
    """configured_program with the contour's joints turned to the other wrist
    solution (R + 180, B mirrored about the straight wrist at B = 90, T + 180):
    the same flange poses, within the limits, in another arm configuration."""
    program = configured_program()
    robot = models.model(ROBOT)
    for move in program.paths[1].moves:
        q = np.asarray(move.target.joints_deg, dtype=float)
        flipped = q + np.array([0, 0, 0, 180, 180 - 2 * q[4], 180])
        flipped[[3, 5]] = wrap180(flipped[[3, 5]])
        np.testing.assert_allclose(robot.fk(flipped), robot.fk(q), atol=1e-9)
        assert robot.within_limits(flipped)
        move.target.joints_deg = flipped
    return program


def minimal_program(move_kind=ir.LINEAR, via=None, frame="B", name="P"):
    return post_programs.minimal_program(ROBOT, move_kind, via, frame, name)


def arcs_program(n_lines=10, n_arc_pairs=3, name="Arcs"):
    """Linear moves then pairs of consecutive arcs (a full circle as two
    half circles), repeated: for splitting and arc separation."""
    tool = ir.ToolData("Tool", pose(position=(0, 0, 100)))
    frames = {"B": ir.WorkFrame("B", pose((0, 0, 30), (700, 0, 300)), np.eye(4))}
    moves = [ir.Move(ir.JOINT, ir.Target("a0", pose(DOWN, (0, 0, 50))), 100, 5, "B")]
    k = 0
    for block in range(n_arc_pairs):
        for i in range(n_lines):
            k += 1
            target = ir.Target(f"l{k}", pose(DOWN, (i * 5.0, block * 10.0, 0)))
            moves.append(ir.Move(ir.LINEAR, target, 20, 1, "B", segment=block + 1,
                                 comment=f"segment {block + 1}: line"))
        start = moves[-1].target.T_b_t[:3, 3]
        center = start + np.array([20.0, 0, 0])
        half_1 = ir.Target(f"h{block}a", pose(DOWN, center + [20, 0, 0]))
        via_1 = ir.Target(f"v{block}a", pose(DOWN, center + [0, 20, 0]))
        half_2 = ir.Target(f"h{block}b", pose(DOWN, start))
        via_2 = ir.Target(f"v{block}b", pose(DOWN, center + [0, -20, 0]))
        moves.append(ir.Move(ir.CIRCULAR, half_1, 20, 1, "B", via=via_1, segment=block + 1,
                             comment=f"segment {block + 1}: arc"))
        moves.append(ir.Move(ir.CIRCULAR, half_2, 20, 1, "B", via=via_2, segment=block + 1,
                             comment=f"segment {block + 1}: arc"))
    return ir.Program(name, ROBOT, tool, frames, [ir.ProgramPath("Path", "Path", moves)])


def export_texts(program, options=None):
    return [text for _, text in motoman_inform.export(program, options or {})]


def export_text(program, options=None):
    files = motoman_inform.export(program, options or {})
    assert len(files) == 1
    return files[0][1]


# --- parsing our own output ---------------------------------------------------

C_LINE = re.compile(r"^C(\d{5})=(.*)$")
MOVE_LINE = re.compile(r"^(MOVJ|MOVL|MOVC) C(\d{5}) (VJ|V)=([0-9.]+)(?: PL=(\d))?$")


@dataclasses.dataclass
class Job:
    name: str
    npos: list
    positions: list          # (values (6,), user, tool, rconf tuple)
    instructions: list       # lines between NOP and END
    attr: str
    inst_header: list        # ///DATE ... lines before NOP


def parse_job(text):
    """Parse a job: header, C positions with the pseudo instructions in force,
    instructions."""
    assert text.endswith("\r\n") and "\n" not in text.replace("\r\n", "")
    lines = text.split("\r\n")[:-1]
    assert lines[:3] == ["/JOB", lines[1], "//POS"] and lines[1].startswith("//NAME ")
    name = lines[1][len("//NAME "):]
    assert lines[3].startswith("///NPOS ")
    npos = [int(v) for v in lines[3][len("///NPOS "):].split(",")]
    inst = lines.index("//INST")
    user = tool = rconf = postype = None
    positions = []
    for line in lines[4:inst]:
        m = C_LINE.match(line)
        if m:
            assert int(m.group(1)) == len(positions), line
            values = np.array(m.group(2).split(","), dtype=float)
            if postype == "PULSE":
                assert re.fullmatch(r"-?\d+(,-?\d+){5}", m.group(2)), line
                positions.append((values, "PULSE", tool, None))
            else:
                assert postype == "USER"
                positions.append((values, user, tool, rconf))
        elif line.startswith("///USER "):
            user = int(line.split()[1])
        elif line.startswith("///TOOL "):
            tool = int(line.split()[1])
        elif line.startswith("///POSTYPE "):
            postype = line.split()[1]
        elif line.startswith("///RCONF "):
            rconf = tuple(int(v) for v in line.split()[1].split(","))
        else:
            assert line == ("///PULSE" if postype == "PULSE" else "///RECTAN"), line
    nop = lines.index("NOP")
    assert lines[-1] == "END"
    header = lines[inst + 1:nop]
    attr = [line for line in header if line.startswith("///ATTR ")][0]
    return Job(name, npos, positions, lines[nop + 1:-1], attr, header)


def move_lines(job):
    return [line for line in job.instructions if line.startswith("MOV")]


def matrix_from_values(values):
    """Independent decoding (scipy): R = Rz(Rz) Ry(Ry) Rx(Rx) = extrinsic xyz."""
    T = np.eye(4)
    T[:3, :3] = Rotation.from_euler("xyz", values[3:6], degrees=True).as_matrix()
    T[:3, 3] = values[:3]
    return T


def rotation_error_deg(R1, R2):
    return np.degrees(Rotation.from_matrix(np.asarray(R1).T @ np.asarray(R2)).magnitude())


def expected_steps(program):
    """What INFORM must receive, written from the rules (module docstring):
    [(instruction, T_b_t, frame, joints)]; an arc is MOVC start (the previous
    target), via, end, with a MOVL at the start when the previous move is an
    arc too."""
    out, previous = [], None
    for move in program.moves():
        if move.kind == ir.CIRCULAR:
            T_r_prev = program.frames[previous.frame].T_r_b @ previous.target.T_b_t
            T_start = np.linalg.inv(program.frames[move.frame].T_r_b) @ T_r_prev
            if previous.kind == ir.CIRCULAR:
                out.append(("MOVL", T_start, move.frame, previous.target.joints_deg))
            out.append(("MOVC", T_start, move.frame, previous.target.joints_deg))
            out.append(("MOVC", move.via.T_b_t, move.frame, move.via.joints_deg))
        instruction = {ir.JOINT: "MOVJ", ir.LINEAR: "MOVL", ir.CIRCULAR: "MOVC"}[move.kind]
        out.append((instruction, move.target.T_b_t, move.frame, move.target.joints_deg))
        previous = move
    return out


def assert_job_consistent(job):
    """NPOS counts = C lines = move instructions, each C used once, in order."""
    moves = move_lines(job)
    assert job.npos == [len(job.positions), 0, 0, 0, 0, 0]
    assert len(moves) == len(job.positions)
    used = [int(MOVE_LINE.match(line).group(2)) for line in moves]
    assert used == list(range(len(job.positions)))


# --- golden files -------------------------------------------------------------

def split_options():
    return {"max_positions": 12}


GOLDEN = [
    ("motoman_inform_two_frames", two_frame_program, {}),
    ("motoman_inform_configured", configured_program, {}),
    ("motoman_inform_dx100_relative", lambda: minimal_program(name="Relative seam job"),
     {"controller": "dx100", "relative_job": True, "user_frame": 3, "tool": 2,
      "date": datetime.datetime(2024, 5, 6, 7, 8)}),
    ("motoman_inform_split", lambda: arcs_program(n_lines=4, n_arc_pairs=2),
     split_options()),
]


@pytest.mark.parametrize("stem, build, options", GOLDEN, ids=[g[0] for g in GOLDEN])
def test_golden_output(stem, build, options):
    files = motoman_inform.export(build(), options)
    for k, (filename, text) in enumerate(files):
        golden = GOLDEN_DIR / f"{stem}_{k}.JBI" if len(files) > 1 else GOLDEN_DIR / f"{stem}.JBI"
        plain = text.replace("\r\n", "\n")
        if os.environ.get("CADROBOT_UPDATE_GOLDEN"):
            golden.write_text(plain, newline="\n")
        assert golden.exists(), f"missing {golden}; see this file's docstring"
        assert plain == golden.read_text(), filename


def test_export_is_deterministic_named_after_program_and_crlf():
    program = two_frame_program()
    first = motoman_inform.export(program, {})
    assert first == motoman_inform.export(program, None)
    assert [f for f, _ in first] == ["CELL.JBI"]
    text = first[0][1]
    assert text.count("\r\n") == text.count("\n") and text.endswith("END\r\n")
    assert text.isascii()


# --- structure and NPOS -------------------------------------------------------

@pytest.mark.parametrize("build", [two_frame_program, configured_program, minimal_program,
                                   arcs_program])
def test_npos_matches_positions_and_instructions(build):
    for text in export_texts(build()):
        assert_job_consistent(parse_job(text))


def test_job_header_and_instruction_header():
    text = export_text(two_frame_program(), {"date": datetime.datetime(2012, 4, 25, 14, 11)})
    lines = text.split("\r\n")
    assert lines[:9] == ["/JOB", "//NAME CELL", "//POS", "///NPOS 12,0,0,0,0,0", "///USER 1",
                         "///TOOL 0", "///POSTYPE USER", "///RECTAN", "///RCONF 0,0,0,0,0,0"]
    job = parse_job(text)
    assert job.inst_header == ["///DATE 2012/04/25 14:11", "///COMM CadRobot Cell",
                               "///ATTR SC,RW", "///GROUP1 RB1"]
    default = parse_job(export_text(two_frame_program()))
    assert default.inst_header[0] == "///DATE 2000/01/01 00:00"


def test_positions_recover_every_pose_user_frame_and_tool():
    program = two_frame_program()
    job = parse_job(export_text(program, {"user_frame": 4, "tool": 7}))
    steps = expected_steps(program)
    assert len(job.positions) == len(steps) == 12
    users = {"Table": 4, "Fixture": 5}
    for (values, user, tool, rconf), (instruction, T, frame, _) in zip(job.positions, steps):
        recovered = matrix_from_values(values)
        assert np.abs(recovered[:3, 3] - T[:3, 3]).max() <= 1e-3
        assert rotation_error_deg(recovered[:3, :3], T[:3, :3]) <= POSE_ANGLE_TOL_DEG
        assert (user, tool) == (users[frame], 7)
        assert rconf == (0, 0, 0, 0, 0, 0)
    assert [MOVE_LINE.match(line).group(1) for line in move_lines(job)] == [s[0] for s in steps]


def test_random_orientations_round_trip_to_1e_4_degree():
    """Every pose of a program with random orientations (and gimbal lock,
    +-180 degrees) comes back within 5e-4 mm, each angle within 5e-5 degree
    of the exact one (4 decimals), the orientation within 1.5e-4 degree."""
    rng = np.random.default_rng(6)
    rotations_ = list(Rotation.random(200, random_state=7))
    rotations_ += [Rotation.from_euler("xyz", e, degrees=True) for e in
                   [(0, 90, 30), (20, -90, 0), (180, 0, 180), (-180, 45, -180),
                    (179.99996, 0, -179.99996), (0, 89.99999, 0)]]
    tool = ir.ToolData("Tool", np.eye(4))
    frames = {"B": ir.WorkFrame("B", np.eye(4), np.eye(4))}
    moves = []
    for k, R in enumerate(rotations_):
        T = np.eye(4)
        T[:3, :3] = R.as_matrix()
        T[:3, 3] = rng.uniform(-1500, 1500, 3)
        moves.append(ir.Move(ir.LINEAR, ir.Target(f"t{k}", T), 10, 0, "B"))
    program = ir.Program("Random", ROBOT, tool, frames, [ir.ProgramPath("P", "P", moves)])
    job = parse_job(export_text(program))
    worst = 0.0
    for (values, *_), move in zip(job.positions, moves):
        T = move.target.T_b_t
        recovered = matrix_from_values(values)
        assert np.abs(recovered[:3, 3] - T[:3, 3]).max() <= 5e-4 + 1e-9
        worst = max(worst, rotation_error_deg(recovered[:3, :3], T[:3, :3]))
        if not near_gimbal_lock(T):
            exact = np.degrees(Rotation.from_matrix(T[:3, :3]).as_euler("xyz"))
            assert np.abs(wrap180(values[3:] - exact)).max() <= ANGLE_TOL_DEG
    assert worst <= POSE_ANGLE_TOL_DEG


def near_gimbal_lock(T):
    """Ry within 0.01 degree of +-90: only Rx -+ Rz is defined there, and
    implementations split it differently (the pose is compared instead)."""
    return np.hypot(T[0, 0], T[1, 0]) < np.sin(np.radians(0.01))


def wrap180(angles_deg):
    return (np.asarray(angles_deg) + 180.0) % 360.0 - 180.0


def test_number_format():
    text = export_text(two_frame_program())
    assert "-0.000" not in text
    for line in text.split("\r\n"):
        m = C_LINE.match(line)
        if m:
            values = m.group(2).split(",")
            assert len(values) == 6
            assert all(re.fullmatch(r"-?\d+\.\d{3}", v) for v in values[:3])
            assert all(re.fullmatch(r"-?\d+\.\d{4}", v) for v in values[3:])


# --- conventions against robodk ----------------------------------------------

@needs_robodk
def test_rx_ry_rz_agree_with_robodk_pose_2_motoman():
    """Our Rx, Ry, Rz are robodk's Pose_2_Motoman angles (away from gimbal
    lock, where only Rx -+ Rz is defined), and robodk's Motoman_2_Pose
    rebuilds our printed values into the original pose, gimbal lock included."""
    rng = np.random.default_rng(3)
    eulers = [tuple(v) for v in rng.uniform([-180, -90, -180], [180, 90, 180], (100, 3))]
    eulers += [(0, 90, 30), (0, -90, -120), (180, 0, 0), (0, 0, 180), (45, 89.5, -10)]
    for e in eulers:
        T = pose(e, rng.uniform(-1000, 1000, 3))
        ours = np.array(motoman_inform.pose_values(T), dtype=float)
        ref = np.array(robomath.Pose_2_Motoman(robomath.Mat(T.tolist())), dtype=float)
        np.testing.assert_allclose(ours[:3], ref[:3], atol=5e-4)
        if not near_gimbal_lock(T):
            assert np.abs(wrap180(ours[3:] - ref[3:])).max() <= ANGLE_TOL_DEG, (e, ours, ref)
        rebuilt = np.array(robomath.Motoman_2_Pose(ours.tolist()).rows)
        assert np.abs(rebuilt[:3, 3] - T[:3, 3]).max() <= 1e-3
        assert rotation_error_deg(rebuilt[:3, :3], T[:3, :3]) <= POSE_ANGLE_TOL_DEG


@needs_robodk
def test_job_positions_decode_with_robodk():
    assert not ROBODK_MISSING, ROBODK_MISSING
    program = configured_program()
    job = parse_job(export_text(program))
    for (values, *_), (_, T, _, _) in zip(job.positions, expected_steps(program)):
        rebuilt = np.array(robomath.Motoman_2_Pose(values.tolist()).rows)
        assert np.abs(rebuilt[:3, 3] - T[:3, 3]).max() <= 1e-3
        assert rotation_error_deg(rebuilt[:3, :3], T[:3, :3]) <= POSE_ANGLE_TOL_DEG


# --- RCONF ----------------------------------------------------------------------

def test_rconf_comes_from_the_joints_and_changes_with_them():
    for program, changes in ((configured_program(), 0), (flipped_contour_program(), 1)):
        text = export_text(program)
        job = parse_job(text)
        robot = models.model(ROBOT)
        steps = expected_steps(program)
        for (_, _, _, rconf), (_, _, _, joints) in zip(job.positions, steps):
            assert rconf == configuration.motoman_rconf(joints, robot)
        # The seam in the natural configuration (R within +-90: flip), the flipped
        # contour with R beyond 90 (no flip).
        assert job.positions[0][3] == (0, 0, 0, 0, 0, 0)
        assert job.positions[-1][3] == ((1, 0, 0, 0, 0, 0) if changes else (0,) * 6)
        pos = text.split("//INST")[0]
        assert pos.count("///RCONF ") == 1 + changes      # written again only on a change
        assert "'RCONF: the checked arm config" in text


def test_targets_without_joints_get_the_default_rconf_and_say_so():
    program = flipped_contour_program()
    program.paths[1].moves[2].target.joints_deg = None       # q3
    job = parse_job(export_text(program))
    assert job.positions[10][3] == (0, 0, 0, 0, 0, 0)
    assert job.positions[9][3] == (1, 0, 0, 0, 0, 0)
    text = export_text(two_frame_program())
    assert "'RCONF 0,0,0,0,0,0 (flip, upper" in text


def test_unknown_robot_writes_default_rconf():
    program = configured_program()
    program.robot = "SOME_OTHER_ROBOT"
    job = parse_job(export_text(program))
    assert {p[3] for p in job.positions} == {(0, 0, 0, 0, 0, 0)}


# --- instructions, speeds, levels ------------------------------------------------

def test_instructions():
    job = parse_job(export_text(two_frame_program()))
    assert move_lines(job) == [
        "MOVJ C00000 VJ=10.00 PL=1",   # no pl_radii_mm: a zone > 0 is PL=1, zone 0 PL=0
        "MOVL C00001 V=12.5 PL=1",
        "MOVL C00002 V=12.5 PL=1",
        "MOVL C00003 V=12.5 PL=1",
        "MOVC C00004 V=12.5",          # arc start = p4, where the robot is
        "MOVC C00005 V=12.5",          # via
        "MOVC C00006 V=12.5 PL=0",     # end
        "MOVL C00007 V=100.0 PL=0",
        "MOVJ C00008 VJ=10.00 PL=1",
        "MOVL C00009 V=12.5 PL=1",
        "MOVL C00010 V=12.5 PL=0",
        "MOVL C00011 V=100.0 PL=0",
    ]
    np.testing.assert_array_equal(job.positions[4][0], job.positions[3][0])


def test_comments_name_paths_and_segments_and_fit_32_characters():
    text = export_text(two_frame_program())
    job = parse_job(text)
    comments = [line[1:] for line in job.instructions if line.startswith("'")]
    for expected in ("Path: Weld seam", "segment 1: line Sketch.Edge1",
                     "segment 2: arc Sketch.Edge2", "Path: Edge contour",
                     "Source: demo.FCStd / Cell", "Robot: MOTOMAN_HP6", "Units: mm, deg",
                     "V in mm/s (0.1 mm/s steps)"):
        assert expected in comments
    assert max(len(c) for c in comments) <= 32
    # The comment of a move comes right before it.
    i = job.instructions.index("'segment 2: arc Sketch.Edge2")
    assert job.instructions[i + 1].startswith("MOVC")


def test_user_frame_and_tool_values_in_the_comments():
    program = two_frame_program()
    text = export_text(program, {"user_frame": 2, "tool": 5})
    comments = [line[1:] for line in parse_job(text).instructions if line.startswith("'")]
    i = comments.index("USER 2 = Table (robot coords)")
    block = " ".join(comments[i + 1:i + 4])
    found = dict((k, float(v)) for k, v in re.findall(r"(X|Y|Z|Rx|Ry|Rz)=(-?[\d.]+)", block))
    T = matrix_from_values([found[k] for k in ("X", "Y", "Z", "Rx", "Ry", "Rz")])
    assert np.abs(T - program.frames["Table"].T_r_b).max() < 1e-3
    assert "USER 3 = Fixture (robot coords)" in comments
    # ORG, XX, XY: origin, +100 mm along x and y of the frame, in robot coordinates.
    T_f = program.frames["Fixture"].T_r_b
    j = comments.index("USER 3 = Fixture (robot coords)")
    xy = [c for c in comments[j:] if c.startswith("XY ")][:2]
    point = [float(v) for v in re.findall(r"=(-?[\d.]+)", " ".join(xy))]
    np.testing.assert_allclose(point, T_f[:3, 3] + 100 * T_f[:3, 1], atol=1e-3)
    k = comments.index("TOOL 5 = Torch (flange coords)")
    block = " ".join(comments[k + 1:k + 4])
    found = dict((key, float(v)) for key, v in re.findall(r"(X|Y|Z|Rx|Ry|Rz)=(-?[\d.]+)", block))
    T = matrix_from_values([found[key] for key in ("X", "Y", "Z", "Rx", "Ry", "Rz")])
    assert np.abs(T - program.tool.T_f_t).max() < 1e-3
    assert "W=1.5 kg" in comments and "Zg=120.000" in comments


def test_frame_change_writes_user_before_its_positions():
    job = parse_job(export_text(two_frame_program(), {"user_frame": {"Table": 7, "Fixture": 2}}))
    assert [p[1] for p in job.positions] == [7] * 8 + [2] * 4


def test_arc_after_a_move_in_another_frame_starts_at_that_point():
    program = two_frame_program()
    contour = program.paths[1].moves
    # An arc in the table frame right after the contour's retract (fixture frame).
    arc = ir.Move(ir.CIRCULAR, ir.Target("e", pose(DOWN, (10, 10, 0))), 12.5, 0, "Table",
                  via=ir.Target("v", pose(DOWN, (0, 20, 0))))
    contour.append(arc)
    job = parse_job(export_text(program))
    start_values, user, _, _ = job.positions[-3]
    assert user == 1
    T_r_start = program.frames["Table"].T_r_b @ matrix_from_values(start_values)
    T_r_prev = program.frames["Fixture"].T_r_b @ contour[-2].target.T_b_t
    assert np.abs(T_r_start[:3, 3] - T_r_prev[:3, 3]).max() <= 2e-3
    assert rotation_error_deg(T_r_start[:3, :3], T_r_prev[:3, :3]) <= 2e-4


def test_consecutive_arcs_are_separated_by_a_linear_step():
    program = arcs_program(n_lines=2, n_arc_pairs=1)
    job = parse_job(export_text(program))
    kinds = [MOVE_LINE.match(line).group(1) for line in move_lines(job)]
    assert kinds == ["MOVJ", "MOVL", "MOVL", "MOVC", "MOVC", "MOVC", "MOVL", "MOVC", "MOVC",
                     "MOVC"]
    # The separator, the second arc's start and the first arc's end are one point.
    np.testing.assert_array_equal(job.positions[5][0], job.positions[6][0])
    np.testing.assert_array_equal(job.positions[6][0], job.positions[7][0])
    for (values, *_), (_, T, _, _) in zip(job.positions, expected_steps(program)):
        assert np.abs(matrix_from_values(values) - T).max() < 1e-3


RADII = (1, 2.5, 5, 10, 25, 50, 100, 200)


@pytest.mark.parametrize("zone, level", [(0, 0), (0.3, 0), (0.999, 0), (1, 1), (2.4, 1),
                                         (2.5, 2), (5, 3), (10, 4), (24, 4), (25, 5),
                                         (50, 6), (100, 7), (200, 8), (5000, 8)])
def test_position_level_never_rounds_more_than_the_zone(zone, level):
    assert motoman_inform.position_level(zone, RADII) == level
    assert level == 0 or RADII[level - 1] <= zone          # the level's radius fits
    # No radii given: the least rounding short of a stop for any zone, the point at zone 0.
    assert motoman_inform.position_level(zone) == (1 if zone > 0 else 0)


def test_pl_radii_option_sets_the_levels_and_is_stated():
    text = export_text(two_frame_program(), {"pl_radii_mm": "0.2,2,8"})
    levels = [MOVE_LINE.match(line).group(5) for line in move_lines(parse_job(text))]
    # zones 10, 0.3, 0.3, 0.3, (arc start, via), 0, 0 | 10, 2.5, 0, 0
    assert levels == ["3", "1", "1", "1", None, None, "0", "0", "3", "2", "0", "0"]
    assert "PL1.. radii mm: 0.2,2,8" in text.replace("\r\n'", " ")
    assert "'PL=1 where the zone is > 0," in export_text(two_frame_program())
    # One number (as the CLI passes pl_radii_mm=2): PL=1 from 2 mm on.
    levels = [MOVE_LINE.match(line).group(5) for line in
              move_lines(parse_job(export_text(two_frame_program(), {"pl_radii_mm": 2})))]
    assert levels == ["1", "0", "0", "0", None, None, "0", "0", "1", "1", "0", "0"]


def test_speed_units_and_joint_speed_options():
    program = two_frame_program()
    job = parse_job(export_text(program, {"linear_speed_unit": "cm/min",
                                          "joint_speed_percent": 25}))
    lines = move_lines(job)
    assert lines[0] == "MOVJ C00000 VJ=25.00 PL=1"
    assert lines[1] == "MOVL C00001 V=75 PL=1"             # 12.5 mm/s = 75 cm/min
    assert lines[7] == "MOVL C00007 V=600 PL=0"            # 100 mm/s
    text = export_text(program, {"linear_speed_unit": "cm/min"})
    assert "'V in cm/min (1 cm/min steps)" in text
    job = parse_job(export_text(program, {"joint_speed_reference_mm_s": 400}))
    assert move_lines(job)[0] == "MOVJ C00000 VJ=25.00 PL=1"
    assert motoman_inform.joint_speed_percent(5000) == 100.0
    assert motoman_inform.joint_speed_percent(0.01) == 0.01


def test_speed_resolution():
    program = minimal_program()
    program.paths[0].moves[0].speed_mm_s = 0.25
    assert "V=0.2" in export_text(program) or "V=0.3" in export_text(program)
    program.paths[0].moves[0].speed_mm_s = 0.04
    with pytest.raises(PostError, match="0.1 to 9999.9 mm/s"):
        motoman_inform.export(program, {})


# --- long programs ------------------------------------------------------------------

def test_long_program_is_split_into_called_sub_jobs():
    program = arcs_program(n_lines=400, n_arc_pairs=3)          # 1 + 1200 + 3*7 steps
    files = motoman_inform.export(program, {})
    names = [f for f, _ in files]
    assert names == ["ARCS.JBI", "ARCS_1.JBI", "ARCS_2.JBI"]
    jobs = [parse_job(text) for _, text in files]
    main = jobs[0]
    assert main.npos == [0, 0, 0, 0, 0, 0] and not main.positions
    calls = [line for line in main.instructions if not line.startswith("'")]
    assert calls == ["CALL JOB:ARCS_1", "CALL JOB:ARCS_2"]
    for job in jobs[1:]:
        assert_job_consistent(job)
        assert 0 < job.npos[0] <= 999
        assert len(job.name) <= 8
    positions = [p for job in jobs[1:] for p in job.positions]
    steps = expected_steps(program)
    assert len(positions) == len(steps) == 1 + 1200 + 21
    for (values, *_), (_, T, _, _) in zip(positions, steps):
        assert np.abs(matrix_from_values(values)[:3, 3] - T[:3, 3]).max() <= 1e-3


@pytest.mark.parametrize("max_positions", [4, 5, 6, 7, 12])
def test_arcs_are_never_split_between_jobs(max_positions):
    program = arcs_program(n_lines=3, n_arc_pairs=3)
    files = motoman_inform.export(program, {"max_positions": max_positions})
    assert len(files) > 1
    jobs = [parse_job(text) for _, text in files[1:]]
    total = []
    for job in jobs:
        assert_job_consistent(job)
        assert job.npos[0] <= max_positions
        kinds = [MOVE_LINE.match(line).group(1) for line in move_lines(job)]
        total += kinds
        # Every run of MOVC in a job is whole arcs (3 steps), after a MOVL/MOVJ or at
        # the start of the job (then the MOVL separator went with it).
        runs = re.findall(r"C+", "".join("C" if k == "MOVC" else "x" for k in kinds))
        assert all(len(run) == 3 for run in runs)
    assert total == [s[0] for s in expected_steps(program)]


def test_max_positions_too_small_is_a_post_error():
    with pytest.raises(PostError, match="max_positions"):
        motoman_inform.export(two_frame_program(), {"max_positions": 3})


# --- names --------------------------------------------------------------------------

def test_job_names_fit_the_controller_and_stay_distinct():
    assert motoman_inform.job_name("Cell") == "CELL"
    resume = motoman_inform.job_name("Cell_resume")
    corrected = motoman_inform.job_name("Cell_corrected")
    assert resume != corrected
    for name in (resume, corrected):
        assert len(name) == 8 and name.startswith("CELL_") and motoman_inform.is_job_name(name)
    assert motoman_inform.job_name("3D cell") == "J3D_CELL"
    assert motoman_inform.job_name("Soudé") == "SOUDE"
    long = "Force following of the fixture edge"
    assert motoman_inform.job_name(long, 32) == motoman_inform.job_name(long, 32)
    assert len(motoman_inform.job_name(long, 32)) == 32
    assert motoman_inform.job_name("Cell_resume", 32) == "CELL_RESUME"


def test_controller_name_length_and_rconf_fields():
    program = configured_program()
    program.name = "Seam_with_a_long_name"
    nx = parse_job(export_text(program))
    dx = parse_job(export_text(program, {"controller": "dx100"}))
    yrc = parse_job(export_text(program, {"controller": "YRC1000"}))
    assert len(nx.name) == 8 and dx.name == yrc.name == "SEAM_WITH_A_LONG_NAME"
    assert len(nx.positions[0][3]) == 6
    assert len(dx.positions[0][3]) == 24 and dx.positions[0][3][6:] == (0,) * 18
    assert dx.positions[0][3][:6] == nx.positions[0][3]
    assert "'Controller: YRC1000" in yrc.instructions


def test_job_name_option():
    files = motoman_inform.export(two_frame_program(), {"job_name": "weld1"})
    assert files[0][0] == "WELD1.JBI" and "//NAME WELD1\r\n" in files[0][1]
    for bad in ("1ABC", "A B", "TOOLONGNAME", "", 3):
        with pytest.raises(PostError, match="Job name"):
            motoman_inform.export(two_frame_program(), {"job_name": bad})
    files = motoman_inform.export(two_frame_program(), {"job_name": "TOOLONGNAME",
                                                        "controller": "dx200"})
    assert files[0][0] == "TOOLONGNAME.JBI"


# --- relative jobs --------------------------------------------------------------------

def test_relative_job_on_dx100_names_its_user_frame():
    text = export_text(minimal_program(), {"controller": "dx100", "relative_job": True,
                                           "user_frame": 3})
    job = parse_job(text)
    assert job.attr == "///ATTR SC,RW,RJ"
    assert "////FRAME USER 3" in job.inst_header
    with pytest.raises(PostError, match="one"):
        motoman_inform.export(two_frame_program(), {"controller": "dx100",
                                                    "relative_job": True})
    with pytest.raises(PostError, match="DX100 and later"):
        motoman_inform.export(minimal_program(), {"relative_job": True})


# --- what INFORM cannot express ----------------------------------------------------------

def test_circular_move_without_via_or_start_is_a_post_error():
    with pytest.raises(PostError, match="via"):
        motoman_inform.export(minimal_program(move_kind=ir.CIRCULAR), {})
    via = ir.Target("v", pose(DOWN, (5, 5, 0)))
    with pytest.raises(PostError, match="first move"):
        motoman_inform.export(minimal_program(move_kind=ir.CIRCULAR, via=via), {})


@pytest.mark.parametrize("options, match", [
    ({"controller": "xrc"}, "Unknown controller"),
    ({"user_frame": 24}, "user_frame"),
    ({"user_frame": 23}, "beyond 23"),                 # two frames: 23 and 24
    ({"user_frame": {"Table": 1}}, "Fixture"),
    ({"user_frame": {"Table": 1, "Fixture": 1}}, "same number"),
    ({"tool": 24}, "tool"),
    ({"tool": 1.5}, "tool"),
    ({"linear_speed_unit": "in/min"}, "linear_speed_unit"),
    ({"joint_speed_percent": 0}, "joint_speed_percent"),
    ({"joint_speed_reference_mm_s": -1}, "joint_speed_reference_mm_s"),
    ({"date": "2024-01-01"}, "date"),
    ({"controller": 3}, "Unknown controller"),
    ({"max_positions": 100000}, "max_positions"),
    ({"max_lines": 10}, "max_lines"),
    ({"max_lines": "many"}, "max_lines"),
    ({"relative_job": "maybe"}, "relative_job"),
    ({"joint_targets": 1}, "joint_targets"),
    ({"joint_speed_percent": float("nan")}, "joint_speed_percent"),
    ({"joint_speed_reference_mm_s": float("inf")}, "joint_speed_reference_mm_s"),
    ({"pulses_per_degree": "1,2,3,4,5"}, "pulses_per_degree"),
    ({"pulses_per_degree": "1,2,3,4,5,x"}, "pulses_per_degree"),
    ({"pulses_per_degree": [1, 2, 3, 4, 5, float("nan")]}, "pulses_per_degree"),
    ({"pulses_per_degree": [1, 2, 3, 4, 5, 0]}, "non-zero"),
    ({"pulses_per_degree": [1, 2, 3, 4, 5, True]}, "pulses_per_degree"),
    ({"pulses_per_degree": 7}, "pulses_per_degree"),
    ({"pulse_zero_deg": "0,0,0,0,0,0"}, "give both"),
    ({"pl_radii_mm": "2,1"}, "increasing"),
    ({"pl_radii_mm": "0,1"}, "increasing"),
    ({"pl_radii_mm": "1,2,3,4,5,6,7,8,9"}, "pl_radii_mm"),
    ({"pl_radii_mm": ""}, "pl_radii_mm"),
])
def test_bad_options_are_post_errors(options, match):
    with pytest.raises(PostError, match=match):
        motoman_inform.export(two_frame_program(), options)


def test_dx_controllers_take_more_frames_and_tools():
    text = export_text(two_frame_program(), {"controller": "dx100", "user_frame": 40,
                                             "tool": 63})
    job = parse_job(text)
    assert {p[1] for p in job.positions} == {40, 41} and job.positions[0][2] == 63


# --- joint targets: PULSE positions ------------------------------------------------------

#: Test values only (not any robot's): pulses per degree and zero-pulse angles.
PPD = (1341.38, -1907.67, 1592.89, 1022.86, -980.24, 454.75)
ZERO = (1.0, -2.0, 3.0, 0.0, 0.5, 5.0)


def pulse_options(**more):
    return dict({"pulses_per_degree": ",".join(map(str, PPD)),
                 "pulse_zero_deg": list(ZERO)}, **more)


def test_joint_moves_go_to_pulse_positions_that_reach_the_pose():
    program = configured_program()
    job = parse_job(export_text(program, pulse_options()))
    assert_job_consistent(job)
    robot = models.model(ROBOT)
    steps = expected_steps(program)
    assert len(job.positions) == len(steps)
    for (values, user, _, _), (instruction, T_b_t, frame, joints) in zip(job.positions, steps):
        if instruction != "MOVJ":
            assert user != "PULSE"
            continue
        assert user == "PULSE"
        expected = np.floor(np.asarray(PPD) * (np.asarray(joints) - ZERO) + 0.5)
        np.testing.assert_array_equal(values, expected)
        # Decoded back to joints, the pulses put the TCP on the program's pose.
        q = values / np.asarray(PPD) + ZERO
        T_r_t = robot.fk(q) @ program.tool.T_f_t
        T_ref = program.frames[frame].T_r_b @ T_b_t
        assert np.abs(T_r_t[:3, 3] - T_ref[:3, 3]).max() < 0.02
        assert rotation_error_deg(T_r_t[:3, :3], T_ref[:3, :3]) < 0.01
    assert sum(p[1] == "PULSE" for p in job.positions) == 2
    assert "MOVJ with solved joints to" in export_text(program, pulse_options())


def test_pulse_section_restates_the_cartesian_pseudo_instructions():
    text = export_text(configured_program(), pulse_options())
    pos = text.split("//INST")[0].split("\r\n")
    assert pos[4:7] == ["///TOOL 0", "///POSTYPE PULSE", "///PULSE"]
    assert pos[8:13] == ["///USER 1", "///TOOL 0", "///POSTYPE USER", "///RECTAN",
                         pos[12]] and pos[12].startswith("///RCONF ")


def test_without_pulses_or_with_joint_targets_off_joint_moves_stay_cartesian():
    program = configured_program()
    for options, why in (({}, "no pulses_per_degree given"),
                         (pulse_options(joint_targets=False), "joint_targets off")):
        text = export_text(program, options)
        assert "PULSE" not in text.split("//INST")[0]
        assert why.split()[0] in text
    # Targets without joints stay Cartesian even with pulses per degree.
    job = parse_job(export_text(two_frame_program(), pulse_options()))
    assert all(p[1] != "PULSE" for p in job.positions)


def test_pulses_for_a_robot_outside_the_catalog_are_refused():
    program = configured_program()
    program.robot = "SOME_OTHER_ROBOT"
    with pytest.raises(PostError, match="joint_targets=false"):
        motoman_inform.export(program, pulse_options())


# --- long programs: limits ------------------------------------------------------------

def test_sub_job_names_fit_and_never_collide():
    assert motoman_inform.sub_job_names("LONG", 3, 8) == ["LONG_1", "LONG_2", "LONG_3"]
    for main, count, length in (("SEAMWELD", 88, 8), ("ABCDEFG", 10, 8), ("A" * 32, 500, 32)):
        names = motoman_inform.sub_job_names(main, count, length)
        assert len(set(names)) == count and main not in names
        assert all(motoman_inform.is_job_name(n, length) for n in names)


def assert_within_limits(files, max_name, max_positions=999, max_lines=2000):
    jobs = [parse_job(text) for _, text in files]
    names = [job.name for job in jobs]
    assert len(set(names)) == len(names)
    assert [f for f, _ in files] == [n + ".JBI" for n in names]
    for job in jobs:
        assert len(job.name) <= max_name
        assert len(job.positions) <= max_positions
        assert len(job.instructions) <= max_lines
        assert_job_consistent(job)
    calls = [line for line in jobs[0].instructions if not line.startswith("'")]
    assert calls == [f"CALL JOB:{n}" for n in names[1:]]
    return jobs


def test_max_lines_splits_a_job_with_many_comments():
    program = arcs_program(n_lines=30, n_arc_pairs=4)      # a comment before every move
    for move in program.moves():
        move.comment = f"move to {move.target.name}"
    files = motoman_inform.export(program, {"max_lines": 60})
    jobs = assert_within_limits(files, 8, max_lines=60)
    assert len(jobs) > 3
    positions = [p for job in jobs[1:] for p in job.positions]
    assert len(positions) == len(expected_steps(program))


def test_main_job_too_long_for_max_lines_is_a_post_error():
    with pytest.raises(PostError, match="CALL lines"):
        motoman_inform.export(arcs_program(n_lines=200, n_arc_pairs=1),
                              {"max_positions": 4, "max_lines": 60})


@pytest.fixture(scope="module")
def program_50000():
    return post_programs.long_program(ROBOT, 50000)


@pytest.mark.parametrize("controller, max_name", [("nx100", 8), ("yrc1000", 32)])
def test_a_50000_move_program_exports_within_the_limits(program_50000, controller, max_name):
    import time
    start = time.perf_counter()
    files = motoman_inform.export(program_50000, {"controller": controller})
    seconds = time.perf_counter() - start
    jobs = assert_within_limits(files, max_name)
    positions = [p for job in jobs[1:] for p in job.positions]
    steps = expected_steps(program_50000)
    assert len(positions) == len(steps)
    for k in range(0, len(steps), 997):
        assert np.abs(matrix_from_values(positions[k][0])[:3, 3] - steps[k][1][:3, 3]).max() \
            <= 1e-3
    assert seconds < 30, seconds


def test_every_option_read_is_declared():
    import inspect
    source = inspect.getsource(motoman_inform)
    read = set(re.findall(r'options(?:\.get\(|, )"(\w+)"', source))
    read |= set(re.findall(r'_option\(options, "(\w+)"', source))
    assert read - {"date"} <= set(motoman_inform.OPTIONS)
    from CadRobotWB import posts
    with pytest.raises(PostError, match="no option max_position"):
        posts.run(motoman_inform, two_frame_program(), {"max_position": 10})
