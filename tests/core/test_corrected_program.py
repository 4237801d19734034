"""The corrected path as a program: lines and arcs within tolerance, in the work object."""

import numpy as np

from CadRobotWB.core import program as ir
from CadRobotWB.core.trajectory import tcp_trajectory
from CadRobotWB.sensors.corrected_program import corrected_program
from CadRobotWB.sensors.run import SensorRun
from CadRobotWB.sensors.scene import RobotSetup, SensorScene

DOWN = np.diag([1.0, -1.0, -1.0])


def pose(p):
    T = np.eye(4)
    T[:3, :3] = DOWN
    T[:3, 3] = p
    return T


def test_a_run_shifted_sideways_becomes_moves_along_the_shifted_line():
    T_u_b = pose((0, 0, 0))
    T_u_b[:3, :3] = np.eye(3)
    T_u_b[:3, 3] = (500, 0, 0)
    frame = ir.WorkFrame("B", T_u_b, T_u_b)
    moves = [ir.Move(ir.JOINT, ir.Target("a", pose((0, 0, 50))), 100, 0, "B", role=ir.ROLE_APPROACH),
             ir.Move(ir.LINEAR, ir.Target("s", pose((0, 0, 0))), 50, 0, "B", role=ir.ROLE_ENTRY),
             ir.Move(ir.LINEAR, ir.Target("e", pose((100, 0, 0))), 10, 0, "B", segment=1),
             ir.Move(ir.LINEAR, ir.Target("r", pose((100, 0, 30))), 100, 0, "B", role=ir.ROLE_RETRACT)]
    program = ir.Program("W", "ABB_IRB2400", ir.ToolData("t", np.eye(4)), {"B": frame},
                         [ir.ProgramPath("p", "Seam", moves)])
    traj = tcp_trajectory(program, 0.1, 2, 2)
    scene = SensorScene("laser", "Seam", traj, [], RobotSetup("ABB_IRB2400", np.eye(4), np.eye(4)),
                        program=program)
    actual = traj.position_mm + (0, 3, 0)      # the sensor moved the whole seam 3 mm sideways
    run = SensorRun("laser", "pi", traj.time_s, traj.position_mm, actual, actual - traj.position_mm,
                    np.zeros(len(actual)))
    corrected = corrected_program(scene, run)
    got = [(m.kind, m.role, tuple(np.round(m.target.position_mm, 6))) for m in corrected.moves()]
    assert got == [(ir.JOINT, ir.ROLE_APPROACH, (0, 3, 50)), (ir.LINEAR, ir.ROLE_ENTRY, (0, 3, 0)),
                   (ir.LINEAR, ir.ROLE_PATH, (100, 3, 0)), (ir.LINEAR, ir.ROLE_RETRACT, (100, 3, 30))]
    assert corrected.name == "W_corrected"
