"""Checks of a program against a robot (robots/checks/checks.py).

Programs are built from joint vectors through the forward kinematics (so
what is reachable is known by construction) or from poses worked by hand on
the IRB 2400 (zero pose: flange at (940, 0, 1455), tool axis along base +x,
axis 2 at x = 100 mm, z = 615 mm; arm reach c2 + sqrt(a2^2 + c3^2) = 705 +
766.97 mm from axis 2).
"""

import json

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.spatial.transform import Rotation, Slerp

from CadRobotWB.core import program as ir
from CadRobotWB.robots.checks import checks
from CadRobotWB.robots.kinematics import models
from CadRobotWB.robots.motion import configuration as cf

from test_configuration import (IRB2400, JOINTS_A, T_R_B, TOOL, program_from_joints, restricted,
                                wrist_centre)

ZERO_R = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])  # flange at q = 0
NO_TOOL = ir.ToolData("Flange", np.eye(4))


def flange_target(name, position, R=ZERO_R):
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = position
    return ir.Target(name, T)


def base_program(moves, model_name="ABB_IRB2400", tool=NO_TOOL):
    """Targets given in the robot base frame ({B} = {R})."""
    return ir.Program("P", model_name, tool, {"B": ir.WorkFrame("B", np.eye(4), np.eye(4))},
                      [ir.ProgramPath("A", "Path A", moves)])


def kinds(report):
    return [(f.kind, f.severity, f.target) for f in report.findings]


def test_a_reachable_program_has_no_findings():
    program = program_from_joints(IRB2400, JOINTS_A)
    solution = cf.solve_program(program, IRB2400)
    report = checks.check_program(program, IRB2400, solution)
    assert report.ok and report.findings == []
    assert (report.targets, report.moves) == (4, 4)
    assert report.lines()[-1] == "OK: 4 targets, 4 moves: 0 errors, 0 warnings."


def test_check_solves_by_itself_without_touching_the_targets():
    program = program_from_joints(IRB2400, JOINTS_A)
    report = checks.check_program(program, IRB2400)
    assert report.ok
    assert all(t.joints_deg is None for t in program.targets())


def test_unreachable_target_says_how_far():
    """Flange at (3000, 0, 615) pointing along +x: wrist centre 85 mm back at x = 2915,
    2815 mm from axis 2 (x = 100, same height); the arm reaches 705 + 766.97 = 1472 mm,
    so 1343 mm too far."""
    moves = [ir.Move(ir.JOINT, flange_target("near", (940, 0, 1300)), 100, 0, "B"),
             ir.Move(ir.LINEAR, flange_target("far", (3000, 0, 615)), 100, 0, "B")]
    program = base_program(moves)
    report = checks.check_program(program, IRB2400)
    assert not report.ok
    unreachable = [f for f in report.findings if f.kind == checks.UNREACHABLE]
    assert len(unreachable) == 1
    f = unreachable[0]
    assert (f.severity, f.target, f.move_index, f.path) == ("error", "far", 1, "Path A")
    for number in ("2815 mm", "1472 mm", "1343 mm closer"):
        assert number in f.message


def test_joint_limit_names_the_joint_and_the_excess():
    model = restricted(J1=(-30, 30))
    program = program_from_joints(model, [[0, 10, 10, 0, 30, 0], [60, 10, 10, 0, 30, 0]])
    report = checks.check_program(program, model)
    limits = [f for f in report.findings if f.kind == checks.JOINT_LIMIT]
    assert len(limits) == 1
    f = limits[0]
    assert (f.joint, f.value, f.limit, f.severity) == (1, pytest.approx(60.0), 30.0, "error")
    assert "J1 at 60.0 deg, 30.0 deg beyond its limit of +30 deg" in f.message
    assert not report.ok


def test_config_change_on_a_linear_move_is_an_error():
    """J4 limited to +-90: the last target needs the flipped wrist (q5 < 0 with q4 = 0)."""
    model = restricted(J4=(-90, 90))
    program = program_from_joints(model, [[0, 10, 10, 0, q5, 0] for q5 in (30, 20, 10, -10)])
    report = checks.check_program(program, model)
    changes = [f for f in report.findings if f.kind == checks.CONFIG_CHANGE]
    assert [(f.target, f.severity) for f in changes] == [("t4", "error")]
    assert "'front, elbow up, wrist flipped'" in changes[0].message
    assert "keeps 'front, elbow up, wrist not flipped'" in changes[0].message


def lateral_move(half_width, role=ir.ROLE_PATH):
    """TCP = flange moving along y through the zero pose with the zero pose's orientation:
    at y = 0 the robot is at q = 0, where axis 5 is 0 (wrist singularity); on either side
    J1 turns and the wrist must turn back about the vertical, J4 = +-90: J4 flips 180 deg
    within the move."""
    moves = [ir.Move(ir.JOINT, flange_target("a", (940, -half_width, 1455)), 100, 0, "B",
                     role=ir.ROLE_APPROACH),
             ir.Move(ir.LINEAR, flange_target("b", (940, half_width, 1455)), 100, 0, "B",
                     role=role)]
    return base_program(moves)


def test_wrist_flip_in_mid_move_is_caught_by_sampling():
    program = lateral_move(200.0)
    solution = cf.solve_program(program, IRB2400)
    assert solution.ok
    q_a, q_b = solution.joints()
    assert abs(q_a[3]) == pytest.approx(90.0, abs=0.5) and q_a[3] == pytest.approx(-q_b[3])
    report = checks.check_program(program, IRB2400, solution)
    assert kinds(report) == [(checks.JOINT_SPEED, "error", "b"),
                             (checks.SINGULARITY, "warning", "b")]
    speed = report.findings[0]
    assert speed.joint == 4 and speed.value > 360.0 and speed.limit == 360.0
    assert "wrist flip" in speed.message
    assert report.findings[1].value == pytest.approx(0.0, abs=1e-6)
    # The same move as an approach-side move only warns.
    report = checks.check_program(lateral_move(200.0, role=ir.ROLE_ENTRY), IRB2400)
    assert report.findings[0].kind == checks.JOINT_SPEED and report.ok


def test_turning_the_tool_faster_than_j6_allows():
    """Pure rotation of 90 deg about the tool axis (= flange z, = axis 6): at the orientation
    speed 500 deg/s it takes 0.18 s, so J6 needs exactly 500 deg/s; its limit is 450."""
    q0 = np.array([0, 10, 10, 0, 45, 0.0])
    T0 = IRB2400.fk(q0)
    T1 = IRB2400.fk(q0 + [0, 0, 0, 0, 0, 90])
    moves = [ir.Move(ir.JOINT, ir.Target("a", T0), 100, 0, "B", role=ir.ROLE_APPROACH),
             ir.Move(ir.LINEAR, ir.Target("b", T1), 10, 0, "B", role=ir.ROLE_REORIENT)]
    program = base_program(moves)
    report = checks.check_program(program, IRB2400)
    assert kinds(report) == [(checks.JOINT_SPEED, "warning", "b")]
    f = report.findings[0]
    assert (f.joint, f.value, f.limit) == (6, pytest.approx(500.0, rel=1e-6), 450.0)
    assert "slows the tool's rotation to about 450 deg/s" in f.message
    # At 400 deg/s it fits.
    report = checks.check_program(program, IRB2400,
                                  margins=checks.Margins(orientation_speed_deg_s=400.0))
    assert report.findings == []


def test_joint_leaving_its_range_in_mid_move():
    """J1 limited to +-30: a circle through J1 = -20, 29 and 20 (same radius and height, so
    centred on axis 1) must go the long way round: from -20 down through -30."""
    model = restricted(J1=(-30, 30))
    joints = [[-20, 10, 10, 0, 45, 0], [29, 10, 10, 0, 45, 0], [20, 10, 10, 0, 45, 0]]
    T_b_r = np.linalg.inv(T_R_B)
    t = [ir.Target("t%d" % i, T_b_r @ model.fk(np.array(q, float)) @ TOOL.T_f_t)
         for i, q in enumerate(joints)]
    moves = [ir.Move(ir.JOINT, t[0], 50, 0, "B"),
             ir.Move(ir.CIRCULAR, t[2], 50, 0, "B", via=t[1])]
    program = ir.Program("P", "ABB_IRB2400", TOOL, {"B": ir.WorkFrame("B", T_R_B, np.eye(4))},
                         [ir.ProgramPath("A", "A", moves)])
    solution = cf.solve_program(program, model)
    assert solution.ok                                   # every target is fine on its own
    report = checks.check_program(program, model, solution)
    assert kinds(report) == [(checks.JOINT_LIMIT, "error", "t2")]
    f = report.findings[0]
    assert f.joint == 1 and f.limit == -30.0 and -32.0 < f.value < -30.0
    assert "circular move from 't0' to 't2'" in f.message


def test_singularity_warnings_at_targets():
    # Wrist: q5 = 3 deg.
    program = program_from_joints(IRB2400, [[0, 10, 10, 0, 30, 0], [0, 10, 10, 0, 3, 0]])
    report = checks.check_program(program, IRB2400)
    assert report.ok
    wrist = [f for f in report.findings if f.target == "t2" and f.kind == checks.SINGULARITY]
    assert len(wrist) == 1 and wrist[0].value == pytest.approx(3.0)
    assert "wrist singularity" in wrist[0].message
    # A smaller margin: no warning.
    report = checks.check_program(program, IRB2400, margins=checks.Margins(wrist_deg=2.0))
    assert not [f for f in report.findings if f.target == "t2"]


def test_shoulder_singularity_warning():
    """J2 leaning back until the wrist centre (from FK) is 30 mm in front of axis 1."""
    q2 = brentq(lambda a: wrist_centre(IRB2400, [0, a, 0, 0, 30, 0])[0] - 30.0, -90.0, 0.0)
    program = program_from_joints(IRB2400, [[0, 10, 10, 0, 30, 0], [0, q2, 0, 0, 30, 0]])
    report = checks.check_program(program, IRB2400)
    found = [f for f in report.findings if f.target == "t2" and f.kind == checks.SINGULARITY]
    assert len(found) == 1 and found[0].value == pytest.approx(30.0, abs=1e-6)
    assert "30 mm from axis 1" in found[0].message


def test_elbow_singularity_warning():
    """KR 6 R700 (the IRB 2400's J3 range does not reach its stretched elbow): stretched at
    A3 = atan2(35, 365) = 5.48 deg (a2 = -35, c3 = 365); 3 deg from it."""
    kr6 = models.model("KUKA_KR6_R700")
    a3 = np.degrees(np.arctan2(35.0, 365.0)) + 3.0
    program = program_from_joints(kr6, [[0, -90, 90, 0, 45, 0], [0, -30, a3, 0, 45, 0]],
                                  robot="KUKA_KR6_R700")
    report = checks.check_program(program, kr6)
    found = [f for f in report.findings if f.target == "t2" and f.kind == checks.SINGULARITY]
    assert len(found) == 1 and found[0].value == pytest.approx(3.0, abs=1e-9)
    assert "stretched or folded" in found[0].message


def test_report_json_and_lines():
    model = restricted(J1=(-30, 30))
    program = program_from_joints(model, [[0, 10, 10, 0, 30, 0], [60, 10, 10, 0, 3, 0]])
    report = checks.check_program(program, model)
    data = json.loads(json.dumps(report.to_dict()))
    assert data["ok"] is False and data["errors"] == len(report.errors) >= 1
    assert data["robot"] == "ABB_IRB2400_test" and data["targets"] == 2
    first = data["findings"][0]
    assert set(first) == {"kind", "severity", "target", "move_index", "path", "message",
                          "joint", "value", "limit"}
    assert report.lines()[-1].startswith("FAILED: 2 targets, 2 moves: ")
    assert report.lines()[0].startswith("ERROR: joint_limit: ")


def test_circular_via_is_checked_and_the_seam_example_is_clean():
    """A circular move in the path's family: its via and end are fine, so is the arc."""
    joints = [[0, 10, 10, 0, 45, 0], [5, 12, 9, 0, 44, 0], [10, 14, 8, 0, 43, 0]]
    T_b_r = np.linalg.inv(T_R_B)
    t = [ir.Target("t%d" % i, T_b_r @ IRB2400.fk(np.array(q, float)) @ TOOL.T_f_t)
         for i, q in enumerate(joints)]
    moves = [ir.Move(ir.JOINT, t[0], 50, 0, "B"),
             ir.Move(ir.CIRCULAR, t[2], 50, 0, "B", via=t[1])]
    program = ir.Program("P", "ABB_IRB2400", TOOL, {"B": ir.WorkFrame("B", T_R_B, np.eye(4))},
                         [ir.ProgramPath("A", "A", moves)])
    report = checks.check_program(program, IRB2400)
    assert report.ok and report.findings == [] and report.targets == 3 and report.moves == 2


def test_move_samples_follow_the_arc_and_the_slerp():
    """Samples of a circular move lie on the circle through start, via and end."""
    joints = [[0, 10, 10, 0, 45, 0], [5, 12, 9, 0, 44, 0], [10, 14, 8, 0, 43, 0]]
    program = program_from_joints(IRB2400, joints, kinds=[ir.JOINT, ir.LINEAR, ir.LINEAR])
    moves = program.paths[0].moves
    circular = ir.Move(ir.CIRCULAR, moves[2].target, 50, 0, "B", via=moves[1].target)
    program.paths[0].moves = [moves[0], circular]
    solution = cf.solve_program(program, IRB2400)
    start, via, end = solution.entries
    samples = checks.move_samples(program, IRB2400, start, [via, end], checks.Margins())
    assert samples["status"] == ["ok"] * len(samples["status"])
    T = IRB2400.fk(samples["q_deg"]) @ TOOL.T_f_t
    p = T[:, :3, 3]
    # Circle through the three TCP positions (in {R}): equal distance from its centre.
    a, b, c = (T_R_B @ e.target.T_b_t for e in (start, via, end))
    a, b, c = a[:3, 3], b[:3, 3], c[:3, 3]
    n = np.cross(b - a, c - a)
    A = np.array([b - a, c - a, n])
    rhs = np.array([np.dot(b - a, (a + b) / 2), np.dot(c - a, (a + c) / 2), np.dot(n, a)])
    centre = np.linalg.solve(A, rhs)
    radius = np.linalg.norm(a - centre)
    np.testing.assert_allclose(np.linalg.norm(p - centre, axis=1), radius, atol=1e-6)
    np.testing.assert_allclose(np.dot(p - a, n), 0.0, atol=1e-6)
    # Orientation: slerp of the end rotations (scipy), by fraction.
    Ra = Rotation.from_matrix((T_R_B @ start.target.T_b_t)[:3, :3])
    Rc = Rotation.from_matrix((T_R_B @ end.target.T_b_t)[:3, :3])
    expected = Slerp([0, 1], Rotation.concatenate([Ra, Rc]))(samples["fractions"]).as_matrix()
    np.testing.assert_allclose(T[:, :3, :3], expected, atol=1e-9)
