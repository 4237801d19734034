"""The program sampled in time: positions at the programmed speed, arcs on their circle."""

import numpy as np
from scipy.spatial.transform import Rotation

from CadRobotWB.core import program as ir
from CadRobotWB.core.trajectory import REORIENT_SPEED_DEG_S, tcp_trajectory


def pose(p, rotvec=(0, 0, 0)):
    T = np.eye(4)
    T[:3, :3] = Rotation.from_rotvec(rotvec).as_matrix()
    T[:3, 3] = p
    return T


def program_of(moves, T_u_b=np.eye(4)):
    frame = ir.WorkFrame("B", T_r_b=np.eye(4), T_u_b=T_u_b)
    return ir.Program("P", "ABB_IRB2400", ir.ToolData("t", np.eye(4)), {"B": frame},
                      [ir.ProgramPath("p", "p", moves)])


def move(kind, p, speed, via=None, rotvec=(0, 0, 0)):
    return ir.Move(kind, ir.Target("t", pose(p, rotvec)), speed, 0.0, "B",
                   via=ir.Target("v", pose(via)) if via is not None else None)


def test_a_line_is_travelled_at_its_speed():
    T_u_b = pose((100, 0, 0))
    program = program_of([move(ir.JOINT, (0, 0, 0), 100), move(ir.LINEAR, (0, 100, 0), 10)], T_u_b)
    traj = tcp_trajectory(program, 0.2, first_move=1)
    assert len(traj.time_s) == 51 and traj.time_s[-1] == 10.0
    np.testing.assert_allclose(traj.position_mm[:, 1], 2.0 * np.arange(51), atol=1e-9)
    np.testing.assert_allclose(traj.position_mm[:, 0], 100.0)     # {B} sits at x = 100 in {U}
    np.testing.assert_allclose(traj.s_mm, 2.0 * np.arange(51), atol=1e-9)


def test_an_arc_stays_on_its_circle_at_constant_speed():
    program = program_of([move(ir.JOINT, (50, 0, 0), 100),
                          move(ir.CIRCULAR, (-50, 0, 0), 10, via=(0, 50, 0))])
    traj = tcp_trajectory(program, 0.1, first_move=1)
    np.testing.assert_allclose(np.linalg.norm(traj.position_mm[:, :2], axis=1), 50.0, atol=1e-9)
    assert abs(traj.time_s[-1] - np.pi * 50 / 10) < 1e-12
    steps = np.linalg.norm(np.diff(traj.position_mm, axis=0), axis=1)[:-1]
    np.testing.assert_allclose(steps, 2 * 50 * np.sin(0.1 * 10 / 50 / 2), rtol=1e-9)  # chord of 1 mm arc


def test_turning_in_place_takes_the_reorientation_speed():
    program = program_of([move(ir.JOINT, (0, 0, 0), 100),
                          move(ir.LINEAR, (0, 0, 0), 10, rotvec=(0, 0, np.pi / 2))])
    traj = tcp_trajectory(program, 0.05, first_move=1)
    assert abs(traj.time_s[-1] - 90.0 / REORIENT_SPEED_DEG_S) < 1e-12
    angles = Rotation.from_matrix(traj.T_u_t[:, :3, :3]).magnitude()
    np.testing.assert_allclose(angles, np.radians(90) * traj.time_s / traj.time_s[-1], atol=1e-9)
