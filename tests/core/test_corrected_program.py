"""The corrected path as a program: lines and arcs within tolerance, in the work object."""

import numpy as np
import pytest

from CadRobotWB import posts
from CadRobotWB.core import program as ir
from CadRobotWB.core.trajectory import tcp_trajectory
from CadRobotWB.robots.kinematics import models
from CadRobotWB.robots.motion import configuration
from CadRobotWB.sensors.corrected_program import corrected_program, fit_corrected_path
from CadRobotWB.sensors.run import SensorRun
from CadRobotWB.sensors.scene import RobotSetup, SensorScene

from rapid_check import assert_rapid_ok, needs_rapidchecker

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


def test_each_corrected_move_keeps_the_zone_and_speed_of_the_move_it_corrects():
    """An L seam: 100 mm along X at 10 mm/s blending through a 2 mm zone into 100 mm along
    Y at 20 mm/s, stopping there. Shifted 3 mm, it becomes two lines; the first keeps
    the corner's zone and speed (not the entry's fine point), the last stops exactly."""
    frame = ir.WorkFrame("B", np.eye(4), np.eye(4))
    moves = [ir.Move(ir.JOINT, ir.Target("a", pose((900, 0, 650))), 100, 0, "B",
                     role=ir.ROLE_APPROACH),
             ir.Move(ir.LINEAR, ir.Target("s", pose((900, 0, 600))), 50, 0, "B",
                     role=ir.ROLE_ENTRY),
             ir.Move(ir.LINEAR, ir.Target("c", pose((1000, 0, 600))), 10, 2.0, "B", segment=1),
             ir.Move(ir.LINEAR, ir.Target("e", pose((1000, 100, 600))), 20, 0, "B", segment=2),
             ir.Move(ir.LINEAR, ir.Target("r", pose((1000, 100, 650))), 100, 0, "B",
                     role=ir.ROLE_RETRACT)]
    program = ir.Program("L", "ABB_IRB2400", ir.ToolData("t", np.eye(4)), {"B": frame},
                         [ir.ProgramPath("p", "Seam", moves)])
    traj = tcp_trajectory(program, 0.05, 2, 3)
    scene = SensorScene("laser", "Seam", traj, [], RobotSetup("ABB_IRB2400", np.eye(4), np.eye(4)),
                        program=program)
    actual = traj.position_mm + (3, 3, 0)
    run = SensorRun("laser", "pi", traj.time_s, traj.position_mm, actual,
                    actual - traj.position_mm, np.zeros(len(actual)))
    got = [(m.role, tuple(np.round(m.target.position_mm, 6)), m.speed_mm_s, m.zone_mm)
           for m in corrected_program(scene, run).moves()]
    assert got[2:4] == [(ir.ROLE_PATH, (1003, 3, 600), 10, 2.0),
                        (ir.ROLE_PATH, (1003, 103, 600), 20, 0.0)]


def arc_program():
    """An entry, a 90° arc of radius 50 mm about (0, 50, 0) in {B} and a retract; {B} at
    (900, 0, 600) in the IRB 2400's base frame (= {U}), within its reach."""
    T_u_b = np.eye(4)
    T_u_b[:3, 3] = (900, 0, 600)
    frame = ir.WorkFrame("B", T_u_b, T_u_b)
    via = (50 * np.sin(np.pi / 4), 50 - 50 * np.cos(np.pi / 4), 0)
    moves = [ir.Move(ir.JOINT, ir.Target("a", pose((0, 0, 50))), 100, 0, "B", role=ir.ROLE_APPROACH),
             ir.Move(ir.LINEAR, ir.Target("s", pose((0, 0, 0))), 50, 0, "B", role=ir.ROLE_ENTRY),
             ir.Move(ir.CIRCULAR, ir.Target("e", pose((50, 50, 0))), 10, 0, "B", via=ir.Target("v", pose(via)),
                     segment=1),
             ir.Move(ir.LINEAR, ir.Target("r", pose((50, 50, 30))), 100, 0, "B", role=ir.ROLE_RETRACT)]
    tool = ir.ToolData("Torch", pose((0, 0, 150)))
    tool.T_f_t[:3, :3] = np.eye(3)
    return ir.Program("Arc", "ABB_IRB2400", tool, {"B": frame}, [ir.ProgramPath("p", "Seam", moves)])


def shifted_run(program, shift_mm):
    traj = tcp_trajectory(program, 0.01, 2, 2)
    scene = SensorScene("laser", "Seam", traj, [], RobotSetup("ABB_IRB2400", np.eye(4), np.eye(4)),
                        program=program)
    actual = traj.position_mm + shift_mm
    run = SensorRun("laser", "pi", traj.time_s, traj.position_mm, actual, actual - traj.position_mm,
                    np.zeros(len(actual)))
    return scene, run


def test_an_arc_run_becomes_one_circular_move_on_the_shifted_arc():
    program = arc_program()
    scene, run = shifted_run(program, (0, 0, 2))       # the part is 2 mm higher
    fitted = fit_corrected_path(scene, run)
    assert fitted.counts() == {"samples": len(run.time_s), "moves": 1, "lines": 0, "arcs": 1}
    assert len(run.time_s) > 700                        # 78.5 mm at 10 mm/s, 10 ms steps
    corrected = corrected_program(scene, run, fitted=fitted)
    kinds = [m.kind for m in corrected.moves()]
    assert kinds == [ir.JOINT, ir.LINEAR, ir.CIRCULAR, ir.LINEAR]
    arc = corrected.moves()[2]
    # in {B}: the via point on the circle of radius 50 about (0, 50, 2), the end at (50, 50, 2)
    assert np.linalg.norm(arc.via.position_mm - (0, 50, 2)) == pytest.approx(50, abs=1e-6)
    assert arc.via.position_mm[2] == pytest.approx(2, abs=1e-9)
    np.testing.assert_allclose(arc.target.position_mm, (50, 50, 2), atol=1e-9)


@needs_rapidchecker
def test_the_corrected_arc_program_exports_in_every_language_and_passes_rapidchecker():
    program = arc_program()
    scene, run = shifted_run(program, (0, 0, 2))
    corrected = corrected_program(scene, run)
    configuration.solve_program(corrected, models.model(corrected.robot))
    assert all(t.joints_deg is not None for t in corrected.targets())
    for name in ("abb_rapid", "kuka_krl", "ur_script", "fanuc_ls", "motoman_inform"):
        files = posts.run(posts.get(name), corrected, {})
        assert files and all(text for _, text in files)
    (name, text), = posts.run(posts.get("abb_rapid"), corrected, {})
    assert text.count("MoveC ") == 1
    assert_rapid_ok(text)


def test_a_welded_path_stays_welded_after_correction():
    import weld_fixtures
    from CadRobotWB.core.weld_runs import check_runs
    program = weld_fixtures.woven_fillet_program()
    traj = tcp_trajectory(program, 0.1, 2, 3)
    scene = SensorScene("laser", "Seam", traj, [], RobotSetup("ABB_IRB2400", np.eye(4), np.eye(4)),
                        program=program)
    actual = traj.position_mm + (0, 3, 0)
    run = SensorRun("laser", "pi", traj.time_s, traj.position_mm, actual, actual - traj.position_mm,
                    np.zeros(len(actual)))
    corrected = corrected_program(scene, run)
    (weld,) = corrected.paths[0].welds
    moves = corrected.moves()
    assert (weld.name, weld.start, weld.end) == ("Weld", 1, len(moves) - 2)
    assert {m.speed_mm_s for m in moves if m.weld} == {7.5}
    check_runs(corrected)
