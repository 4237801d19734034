"""Joint values in time for the 3D-view player (robots/motion/playback.py).

Programs are built from joint vectors through the forward kinematics, so
every target is reachable by construction; expected TCP poses come from
core.trajectory (the program sampled in time), never from playback itself.
"""

import numpy as np
import pytest

from CadRobotWB.core import program as ir
from CadRobotWB.core.trajectory import tcp_trajectory
from CadRobotWB.robots.checks import checks
from CadRobotWB.robots.motion import configuration as cf, playback

from test_configuration import IRB2400, TOOL, program_from_joints

JOINTS = [(0, 10, 10, 0, 40, 0), (5, 15, 5, 10, 45, -10), (10, 20, 0, 20, 50, -20),
          (20, 15, 5, 10, 45, -30)]
KINDS = [ir.JOINT, ir.LINEAR, ir.LINEAR, ir.JOINT]
DT = 0.05


def solved(program, q_start=(0, 0, 0, 0, 30, 0)):
    return cf.solve_program(program, IRB2400, q_start_deg=q_start)


def tcp_poses(timeline, program):
    T_u_r = playback.base_in_assembly(program)
    return T_u_r @ IRB2400.fk(timeline.q_deg) @ program.tool.T_f_t


def test_path_moves_follow_the_programmed_tcp_poses():
    program = program_from_joints(IRB2400, JOINTS, KINDS)
    timeline = playback.joint_timeline(program, IRB2400, solved(program), DT)
    assert timeline.failure is None
    poses = tcp_poses(timeline, program)
    for k in (1, 2):                                   # the two linear moves
        expected = tcp_trajectory(program, DT, first_move=k, last_move=k)
        on_move = timeline.move_index == k
        assert on_move.sum() == len(expected.time_s) - 1
        np.testing.assert_allclose(poses[on_move], expected.T_u_t[1:], atol=1e-6)
        start = timeline.time_s[np.flatnonzero(on_move)[0] - 1]
        np.testing.assert_allclose(timeline.time_s[on_move] - start, expected.time_s[1:], atol=1e-9)
    np.testing.assert_allclose(timeline.tcp_u, poses[:, :3, 3], atol=1e-9)


def test_joint_moves_end_on_their_targets_and_start_from_the_start_joints():
    program = program_from_joints(IRB2400, JOINTS, KINDS)
    solution = solved(program)
    timeline = playback.joint_timeline(program, IRB2400, solution, DT)
    np.testing.assert_allclose(timeline.q_deg[0], solution.q_start_deg)
    assert timeline.time_s[0] == 0.0 and np.all(np.diff(timeline.time_s) > 0)
    for k in (0, 3):
        last = np.flatnonzero(timeline.move_index == k)[-1]
        np.testing.assert_allclose(timeline.q_deg[last], JOINTS[k], atol=1e-6)
    # In between, a joint move is a straight line in joint space.
    on_move = timeline.q_deg[timeline.move_index == 3]
    step = np.diff(on_move, axis=0)
    direction = np.subtract(JOINTS[3], JOINTS[2])
    np.testing.assert_allclose(np.cross(step[:, :3], direction[:3]), 0.0, atol=1e-9)


def test_the_wrist_stays_in_its_configuration_along_a_path():
    program = program_from_joints(IRB2400, JOINTS, KINDS)
    timeline = playback.joint_timeline(program, IRB2400, solved(program), DT)
    families = cf.family(timeline.q_deg, IRB2400)
    assert len(set(families[timeline.move_index > 0])) == 1
    assert np.abs(np.diff(timeline.q_deg, axis=0)).max() < 10.0     # no jumps


def far_away(program, move_index, offset=(3000.0, 0.0, 0.0)):
    target = program.moves()[move_index].target
    target.T_b_t = target.T_b_t.copy()
    target.T_b_t[:3, 3] += offset


def test_an_unreachable_target_stops_the_robot_at_the_edge_of_its_reach():
    program = program_from_joints(IRB2400, JOINTS, KINDS)
    far_away(program, 2)
    timeline = playback.joint_timeline(program, IRB2400, solved(program), DT)
    failure = timeline.failure
    assert (failure.move_index, failure.target, failure.kind) == (2, "t3", cf.UNREACHABLE)
    assert failure.sample == len(timeline) - 1 and failure.time_s == timeline.time_s[-1]
    assert "t3" in failure.reason and "out of reach" in failure.reason
    assert timeline.move_index.max() == 2
    # The robot went part of the way along the line towards the far target, on the line.
    start = tcp_trajectory(program, DT, first_move=2, last_move=2).T_u_t
    a, b = start[0, :3, 3], start[-1, :3, 3]
    travelled = timeline.tcp_u[timeline.move_index == 2]
    assert len(travelled) > 0
    along = (travelled - a) @ (b - a) / np.dot(b - a, b - a)
    assert 0.0 < along[-1] < 1.0
    np.testing.assert_allclose(travelled, a + along[:, None] * (b - a), atol=1e-6)


def test_an_unreachable_first_target_leaves_the_robot_where_it_starts():
    program = program_from_joints(IRB2400, JOINTS, KINDS)
    far_away(program, 0)
    solution = solved(program)
    timeline = playback.joint_timeline(program, IRB2400, solution, DT)
    assert len(timeline) == 1 and timeline.failure.sample == 0
    assert timeline.failure.move_index == 0
    np.testing.assert_allclose(timeline.q_deg[0], solution.q_start_deg)


def test_the_reports_first_error_stops_the_robot_at_its_target_with_its_message():
    program = program_from_joints(IRB2400, JOINTS, KINDS)
    solution = solved(program)
    report = checks.Report(robot="ABB_IRB2400", findings=[
        checks.Finding("singularity", checks.WARNING, "t2", 1, "Path 0", "just a warning"),
        checks.Finding("collision", checks.ERROR, "t3", 2, "Path 0", "link5 hits the table")])
    timeline = playback.joint_timeline(program, IRB2400, solution, DT, report=report)
    failure = timeline.failure
    assert (failure.move_index, failure.kind, failure.reason) == (2, "collision",
                                                                  "link5 hits the table")
    np.testing.assert_allclose(timeline.q_deg[-1], JOINTS[2], atol=1e-6)
    # The report's message also names an unreachable target.
    far_away(program, 2)
    report = checks.check_program(program, IRB2400, solved(program))
    timeline = playback.joint_timeline(program, IRB2400, solved(program), DT, report=report)
    assert timeline.failure.reason == report.errors[0].message


def test_sampling_time_must_be_positive():
    program = program_from_joints(IRB2400, JOINTS, KINDS)
    with pytest.raises(ValueError):
        playback.joint_timeline(program, IRB2400, solved(program), 0.0)


# --- a TCP path handed in ------------------------------------------------------------------

T_U_R = np.array([[0.0, -1.0, 0.0, 200.0], [1.0, 0.0, 0.0, -50.0], [0.0, 0.0, 1.0, 100.0],
                  [0.0, 0.0, 0.0, 1.0]])


def sensor_path(n=60):
    """A wavy TCP path in {U} made from joint vectors (reachable by construction)."""
    s = np.linspace(0.0, 1.0, n)
    q = np.column_stack([-10 + 30 * s, 10 + 5 * np.sin(6 * s), 10 - 5 * s, 5 + 40 * s,
                         45 + 3 * np.cos(5 * s), -20 + 60 * s])
    return T_U_R @ IRB2400.fk(q) @ TOOL.T_f_t, 0.1 * np.arange(n), q


def test_a_tcp_path_is_followed_pose_by_pose():
    T_u_t, times, q_made = sensor_path()
    timeline = playback.timeline_from_tcp(T_u_t, times, IRB2400, T_U_R, TOOL.T_f_t,
                                          q_start=q_made[0])
    assert timeline.failure is None and len(timeline) == len(times)
    np.testing.assert_allclose(T_U_R @ IRB2400.fk(timeline.q_deg) @ TOOL.T_f_t, T_u_t, atol=1e-6)
    np.testing.assert_allclose(timeline.q_deg, q_made, atol=1e-6)   # the same, continuous branch
    np.testing.assert_array_equal(timeline.time_s, times)
    assert np.all(timeline.move_index == -1)


def test_a_tcp_path_without_start_joints_picks_a_solution_within_the_limits():
    T_u_t, times, _ = sensor_path()
    timeline = playback.timeline_from_tcp(T_u_t, times, IRB2400, T_U_R, TOOL.T_f_t)
    assert timeline.failure is None
    assert IRB2400.within_limits(timeline.q_deg).all()
    assert np.abs(np.diff(timeline.q_deg, axis=0)).max() < 10.0
    np.testing.assert_allclose(timeline.tcp_u, T_u_t[:, :3, 3], atol=1e-6)


def test_a_tcp_path_leaving_the_reach_stops_before_it():
    T_u_t, times, q_made = sensor_path()
    T_u_t[40:, :3, 3] += [5000.0, 0.0, 0.0]
    timeline = playback.timeline_from_tcp(T_u_t, times, IRB2400, T_U_R, TOOL.T_f_t,
                                          q_start=q_made[0])
    assert len(timeline) == 40
    failure = timeline.failure
    assert (failure.sample, failure.kind, failure.move_index) == (39, cf.UNREACHABLE, -1)
    assert failure.time_s == times[39] and "t = 4.00 s" in failure.reason
