"""Reach advice (robots/checks/reach_advice.py), finding groups (robots/checks/checks.py) and the
one rule for where the robot stands (robots/playback.effective_base).

Hand-worked numbers on the IRB 2400 (OPW a1 = 100, a2 = -135, c1 = 615,
c2 = 705, c3 = 755, c4 = 85 mm): axis 2 at 100 mm from axis 1 and 615 mm
high; stretched, the wrist centre is c2 + hypot(a2, c3) = 705 + 766.97 =
1471.97 mm from axis 2 (joint 3 allows the stretched arm).
"""

import numpy as np
import pytest

from CadRobotWB.core import program as ir
from CadRobotWB.robots.checks import checks, reach_advice as ra
from CadRobotWB.robots.kinematics import models
from CadRobotWB.robots.motion import playback

from test_configuration import restricted

IRB2400 = models.model("ABB_IRB2400")
FAR_IRB2400 = 705.0 + np.hypot(135.0, 755.0)
# Flange Z along +x of the base (tool pointing straight ahead).
AHEAD = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])


def flange_at_wrist(centre, R=AHEAD, c4=85.0):
    """Flange pose whose wrist centre is `centre` (flange Z = R[:, 2])."""
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = np.asarray(centre, float) + c4 * R[:, 2]
    return T


def rz(deg, t=(0.0, 0.0, 0.0)):
    a = np.radians(deg)
    T = np.eye(4)
    T[:2, :2] = [[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]]
    T[:3, 3] = t
    return T


# --- the annulus ---------------------------------------------------------------------------

def test_annulus_of_the_irb2400_is_its_stretched_arm():
    ring = ra.annulus(IRB2400)
    assert ring["far_mm"] == pytest.approx(FAR_IRB2400, abs=0.5)
    assert (ring["shoulder_radial_mm"], ring["shoulder_z_mm"], ring["wrist_mm"]) == (100, 615, 85)


@pytest.mark.parametrize("q3", [-55.0, 0.0, 30.0, 60.0])
def test_wrist_distance_matches_the_forward_kinematics(q3):
    q = np.array([[20.0, 10.0, q3, 30.0, 40.0, 50.0]])
    T = IRB2400.fk(q)
    centre, distance, outside, ring = ra.wrist_geometry(IRB2400, T)
    shoulder = np.array([100.0 * np.cos(np.radians(20)), 100.0 * np.sin(np.radians(20)), 615.0])
    assert distance[0] == pytest.approx(np.linalg.norm(centre[0] - shoulder), abs=1e-6)
    assert ring["near_mm"] - 1e-6 <= distance[0] <= ring["far_mm"] + 1e-6
    assert outside[0] <= 1e-6


# --- translations --------------------------------------------------------------------------

def test_a_target_100_mm_beyond_reach_straight_ahead_moves_100_mm_toward():
    T = flange_at_wrist((100.0 + FAR_IRB2400 + 100.0, 0.0, 615.0))
    assert not ra.reachable(IRB2400, T[None])[0]
    advice = ra.translation_advice(IRB2400, T[None])
    assert advice.verified
    assert advice.move_u_mm == pytest.approx([-100.0, 0.0, 0.0])
    assert "at least 100 mm toward the robot (or the robot 100 mm toward it)" in advice.text
    moved = T.copy()
    moved[:3, 3] += advice.move_u_mm
    assert ra.reachable(IRB2400, moved[None])[0]


def test_a_high_far_target_moves_toward_and_down_in_the_assembly_frame():
    """Wrist centre 300 mm above axis 2 and 100 mm beyond reach along that line;
    the robot stands at (2000, 500, 0) turned 90 deg in {U}, so "toward the robot"
    is -Y of {U} for a part straight ahead of it."""
    direction = np.array([np.sqrt(FAR_IRB2400 ** 2 - 300.0 ** 2), 0.0, 300.0]) / FAR_IRB2400
    centre = np.array([100.0, 0.0, 615.0]) + (FAR_IRB2400 + 100.0) * direction
    T = flange_at_wrist(centre)
    T_u_r = rz(90.0, (2000.0, 500.0, 0.0))
    advice = ra.translation_advice(IRB2400, T[None], T_u_r)
    assert advice.verified
    # 100 mm along the line, rounded up per component: (97.9 -> 100 toward, 20.4 -> 30 down).
    assert advice.move_u_mm == pytest.approx([0.0, -100.0, -30.0], abs=1e-9)
    assert "100 mm toward the robot" in advice.text and "lower it by 30 mm" in advice.text
    T_r_shift = T.copy()
    T_r_shift[:3, 3] += T_u_r[:3, :3].T @ advice.move_u_mm
    assert ra.reachable(IRB2400, T_r_shift[None])[0]


def test_a_group_is_moved_until_its_farthest_target_is_in():
    targets = np.array([flange_at_wrist((100.0 + FAR_IRB2400 + extra, 0.0, 615.0))
                        for extra in (20.0, 180.0, 60.0)])
    advice = ra.translation_advice(IRB2400, targets)
    assert advice.move_u_mm == pytest.approx([-180.0, 0.0, 0.0])
    moved = targets.copy()
    moved[:, :3, 3] += advice.move_u_mm
    assert ra.reachable(IRB2400, moved).all()
    less = targets.copy()
    less[:, :3, 3] += advice.move_u_mm + [ra.STEP_MM, 0, 0]
    assert not ra.reachable(IRB2400, less).all()          # the least move, to 10 mm


def test_a_target_too_near_the_shoulder_moves_away():
    """KR 16 (a1 = 260, c1 = 675, c2 = 680, a2 = 35, c3 = 670, c4 = 158) with joint 3
    held within +-60 deg: the elbow angle q3 + atan2(35, 670) reaches 63.0 deg at most, so
    the wrist centre stays at least sqrt(680^2 + k^2 + 2 680 k cos 63.0) from axis 2."""
    model = restricted("KUKA_KR16", J3=(-60.0, 60.0))
    k = np.hypot(35.0, 670.0)
    folded = np.radians(60.0) + np.arctan2(35.0, 670.0)
    near = np.sqrt(680.0 ** 2 + k ** 2 + 2.0 * 680.0 * k * np.cos(folded))
    assert ra.annulus(model)["near_mm"] == pytest.approx(near)
    T = flange_at_wrist((260.0 + near - 150.0, 0.0, 675.0), c4=158.0)
    advice = ra.translation_advice(model, T[None])
    assert advice.verified and advice.move_u_mm[0] > 0.0
    assert "away from the robot" in advice.text


# --- turning about axis 1 --------------------------------------------------------------------

def test_joint_1_advice_turns_the_robot_and_the_turn_works():
    model = restricted(J1=(-90.0, 90.0))
    q = np.array([[120.0, 10.0, 10.0, 0.0, 30.0, 0.0]])
    T = IRB2400.fk(q)
    assert not ra.reachable(model, T)[0]
    advice = ra.advise(model, T, "joint_limit", joint=1)
    # The target sits at azimuth 120 deg; with the back branch excluded by J2, 30 deg turns it in.
    assert advice.verified and advice.turn_deg == pytest.approx(30.0)
    assert "30 deg counter-clockwise" in advice.text
    assert ra.reachable(model, ra._rz(-advice.turn_deg) @ T)[0]
    assert not ra.reachable(model, ra._rz(-(advice.turn_deg - ra.TURN_STEP_DEG)) @ T)[0]


def test_wrist_limits_get_no_move_advice():
    assert ra.advise(IRB2400, np.eye(4)[None], "joint_limit", joint=5) is None
    assert ra.advise(IRB2400, np.eye(4)[None], "singularity") is None


def test_ur_arms_get_an_estimated_annulus_and_verified_advice():
    ur = models.model("UR10")
    ring = ra.annulus(ur)
    assert ring["estimate"] and ring["far_mm"] > 1000.0
    T = ur.fk(np.array([[0.0, -90.0, 0.0, -90.0, 0.0, 0.0]]))    # stretched up
    far = T.copy()
    far[0, :3, 3] += [0.0, 0.0, 300.0]
    advice = ra.translation_advice(ur, far)
    assert advice.verified
    moved = far.copy()
    moved[0, :3, 3] += advice.move_u_mm
    assert ra.reachable(ur, moved)[0]
    assert advice.move_u_mm[2] < 0.0                      # lower it


# --- groups --------------------------------------------------------------------------------

def finding(kind, move_index, target, joint=None, path="P", severity=checks.ERROR):
    return checks.Finding(kind, severity, target, move_index, path, "%s at %s" % (kind, target),
                          joint=joint)


def test_runs_of_consecutive_targets_group_and_other_kinds_do_not_split_them():
    findings = ([finding(checks.UNREACHABLE, i, "p%d" % i) for i in range(3, 9)]
                + [finding("collision", 5, "p5")]
                + [finding(checks.UNREACHABLE, i, "p%d" % i) for i in (12, 13)]
                + [finding(checks.JOINT_LIMIT, 13, "p13", joint=2),
                   finding(checks.JOINT_LIMIT, 14, "p14", joint=3)])
    findings.sort(key=lambda f: f.move_index)
    groups = checks.group_findings(findings)
    summary = [(g.kind, g.joint, g.findings[0].target, len(g.findings)) for g in groups]
    assert summary == [(checks.UNREACHABLE, None, "p3", 6), ("collision", None, "p5", 1),
                       (checks.UNREACHABLE, None, "p12", 2), (checks.JOINT_LIMIT, 2, "p13", 1),
                       (checks.JOINT_LIMIT, 3, "p14", 1)]
    assert groups[0].line().startswith(
        "ERROR: unreachable: targets 'p3'..'p8' of path 'P' (6 targets, moves 4-9); the first: ")


def line_program(x_values, z=615.0 + 85.0):
    """Linear moves through flange targets straight ahead (frame {B} = {R})."""
    moves = [ir.Move(ir.JOINT if i == 0 else ir.LINEAR, ir.Target("p%d" % i, flange_at_wrist(
        (x, 0.0, 615.0))), 100.0, 0.0, "B") for i, x in enumerate(x_values)]
    return ir.Program("P", "ABB_IRB2400", ir.ToolData("Flange", np.eye(4)),
                      {"B": ir.WorkFrame("B", np.eye(4), np.eye(4))},
                      [ir.ProgramPath("A", "Path A", moves)])


def test_a_report_prints_one_line_per_group_with_advice_and_keeps_every_finding():
    x = [1200.0, 1300.0] + list(np.linspace(1700.0, 1720.0, 30)) + [1300.0]
    program = line_program(x)
    report = checks.check_program(program, IRB2400)
    unreachable = [f for f in report.findings if f.kind == checks.UNREACHABLE]
    assert len(unreachable) >= 30                          # kept per target
    groups = [g for g in report.groups() if g.kind == checks.UNREACHABLE]
    assert len(groups) == 1 and groups[0].findings[0].target == "p2"
    # Worst wrist centre at 1720 mm: 1720 - 100 - 1471.97 = 148.0 -> 150 mm toward.
    assert groups[0].advice.move_u_mm == pytest.approx([-150.0, 0.0, 0.0])
    lines = report.lines()
    assert sum("unreachable" in line for line in lines) == 1
    assert "Whole group: Move the part at least 150 mm toward the robot" in lines[0]
    data = report.to_dict()
    assert len(data["findings"]) == len(report.findings)
    group = [g for g in data["groups"] if g["kind"] == checks.UNREACHABLE][0]
    assert group["count"] == 30 and group["advice"]["move_mm"] == [-150.0, 0.0, 0.0]
    assert report.placement_helps


def test_moving_the_program_by_the_advice_makes_the_check_pass_its_reach():
    x = list(np.linspace(1650.0, 1700.0, 6))
    report = checks.check_program(line_program(x), IRB2400)
    advice = report.groups()[0].advice
    moved = line_program(list(np.array(x) + advice.move_u_mm[0]))
    after = checks.check_program(moved, IRB2400)
    assert not [f for f in after.findings if f.kind in (checks.UNREACHABLE, checks.JOINT_LIMIT)]


# --- where the robot stands ----------------------------------------------------------------

def test_the_drawn_base_holds_without_a_taught_frame():
    drawn = rz(30.0, (-800.0, 100.0, -200.0))
    T_u_b = rz(0.0, (500.0, 0.0, 0.0))
    T_r_b = np.linalg.inv(drawn) @ T_u_b
    base = playback.effective_base(drawn, [("F", T_u_b, None), ("G", T_u_b, T_r_b)])
    assert base.T_u_r == pytest.approx(drawn) and base.taught_frame is None and not base.moved


def test_a_taught_frame_puts_the_robot_where_the_teaching_says():
    drawn = rz(0.0, (-800.0, 0.0, 0.0))
    T_u_b = rz(0.0, (500.0, 0.0, 0.0))
    T_r_b = rz(90.0, (1000.0, 0.0, 0.0))        # the part was found 1000 mm ahead, turned 90 deg
    base = playback.effective_base(drawn, [("Drawn", T_u_b, None), ("Taught", T_u_b, T_r_b)])
    assert base.taught_frame == "Taught" and base.moved
    # The robot base R with T_u_r @ T_r_b = T_u_b: R at (500, 0) - Rz(-90) (1000, 0) = (500, 1000).
    assert base.T_u_r[:3, 3] == pytest.approx([500.0, 1000.0, 0.0])
    assert base.T_u_r @ T_r_b == pytest.approx(T_u_b)
    # The drawn placement does not matter.
    assert playback.effective_base(rz(45.0, (3, 4, 5)), [("Taught", T_u_b, T_r_b)]).T_u_r == \
        pytest.approx(base.T_u_r)


def test_two_taught_frames_that_disagree_the_first_decides_and_the_other_is_named():
    T_u_b = np.eye(4)
    first, second = rz(0.0, (1000.0, 0.0, 0.0)), rz(0.0, (1000.0, 50.0, 0.0))
    base = playback.effective_base(np.eye(4), [("A", T_u_b, first), ("B", T_u_b, second)])
    assert base.taught_frame == "A"
    assert base.T_u_r[:3, 3] == pytest.approx([-1000.0, 0.0, 0.0])
    assert [(c[0], round(c[1], 6)) for c in base.conflicts] == [("B", 50.0)]


def test_a_program_alone_takes_its_first_frame():
    frame = ir.WorkFrame("B", rz(0.0, (1000.0, 0.0, 0.0)), np.eye(4))
    program = ir.Program("P", "ABB_IRB2400", ir.ToolData("T", np.eye(4)), {"B": frame}, [])
    assert playback.base_in_assembly(program)[:3, 3] == pytest.approx([-1000.0, 0.0, 0.0])
    assert playback.robot_base(program, np.eye(4)).taught_frame == "B"
