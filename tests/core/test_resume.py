"""Resuming a path where a run stopped: the torch goes back to the stop point."""

import numpy as np
import pytest

from CadRobotWB.core import program as ir
from CadRobotWB.core import trajectory
from CadRobotWB.core.resume import resume_program
from CadRobotWB.errors import InputError

DOWN = np.diag([1.0, -1.0, -1.0])


def pose(p):
    T = np.eye(4)
    T[:3, :3] = DOWN
    T[:3, 3] = p
    return T


def seam_program():
    """Approach, entry at (0,0,0), a line to (100,0,0), a half circle to (100,100,0), retract.
    {B} sits at (500, 0, 200) in {U}."""
    T_u_b = np.eye(4)
    T_u_b[:3, 3] = (500, 0, 200)
    frame = ir.WorkFrame("B", T_u_b, T_u_b)
    m = [ir.Move(ir.JOINT, ir.Target("a", pose((0, 0, 50))), 100, 0, "B", role=ir.ROLE_APPROACH),
         ir.Move(ir.LINEAR, ir.Target("s", pose((0, 0, 0))), 50, 0, "B", role=ir.ROLE_ENTRY),
         ir.Move(ir.LINEAR, ir.Target("l", pose((100, 0, 0))), 10, 1, "B", segment=1),
         ir.Move(ir.CIRCULAR, ir.Target("c", pose((100, 100, 0))), 10, 0, "B",
                 via=ir.Target("v", pose((150, 50, 0))), segment=2),
         ir.Move(ir.LINEAR, ir.Target("r", pose((100, 100, 50))), 100, 0, "B", role=ir.ROLE_RETRACT)]
    return ir.Program("Weld", "ABB_IRB2400", ir.ToolData("t", np.eye(4)), {"B": frame},
                      [ir.ProgramPath("Seam", "Seam", m)])


def test_stop_on_a_line_resumes_from_the_stop_point():
    stop_u = pose((500 + 40, 0, 200))           # 40 mm along the line, in {U}
    resumed = resume_program(seam_program(), 2, stop_u, approach_mm=30)
    moves = resumed.moves()
    assert resumed.name == "Weld_resume"
    assert [(m.kind, m.role) for m in moves] == [
        (ir.JOINT, ir.ROLE_APPROACH), (ir.LINEAR, ir.ROLE_ENTRY), (ir.LINEAR, ir.ROLE_PATH),
        (ir.CIRCULAR, ir.ROLE_PATH), (ir.LINEAR, ir.ROLE_RETRACT)]
    np.testing.assert_allclose(moves[0].target.position_mm, (40, 0, 30))   # above it, tool -Z is up
    np.testing.assert_allclose(moves[1].target.position_mm, (40, 0, 0))
    np.testing.assert_allclose(moves[2].target.position_mm, (100, 0, 0))
    assert moves[1].speed_mm_s == 50 and moves[2].speed_mm_s == 10
    assert len({t.name for t in resumed.targets()}) == len(resumed.targets())


def test_stop_on_an_arc_resumes_on_what_is_left_of_it():
    # Stopped a quarter of the way round the half circle centred at (100, 50), radius 50.
    angle = -np.pi / 2 + np.pi / 4
    stop_b = (100 + 50 * np.cos(angle), 50 + 50 * np.sin(angle), 0)
    resumed = resume_program(seam_program(), 3, pose(np.add(stop_b, (500, 0, 200))))
    arc = resumed.moves()[2]
    assert arc.kind == ir.CIRCULAR
    middle = -np.pi / 2 + 0.625 * np.pi          # halfway between the stop and the end
    np.testing.assert_allclose(arc.via.position_mm, (100 + 50 * np.cos(middle), 50 + 50 * np.sin(middle), 0),
                               atol=1e-9)
    np.testing.assert_allclose(arc.target.position_mm, (100, 100, 0))


def test_bad_move_index():
    with pytest.raises(InputError, match="move 9"):
        resume_program(seam_program(), 9, np.eye(4))


def test_a_weld_stopped_inside_strikes_again_at_the_stop_point():
    import weld_fixtures
    from CadRobotWB.core.weld_runs import check_runs
    program = weld_fixtures.woven_fillet_program()
    moves = program.moves()
    T_u_stop = trajectory.target_in_u(program, moves[3], moves[2].target)   # at t3, welding
    resumed = resume_program(program, 3, T_u_stop)
    (run,) = resumed.paths[0].welds
    assert (run.name, run.start, run.end) == ("Weld", 1, 2)
    assert [m.weld for m in resumed.moves()] == [None, None, "Weld", None]
    check_runs(resumed)


def test_a_weld_not_yet_reached_is_kept_whole():
    import weld_fixtures
    program = weld_fixtures.woven_fillet_program()
    T_u_stop = trajectory.target_in_u(program, program.moves()[0], program.moves()[0].target)
    (run,) = resume_program(program, 0, T_u_stop).paths[0].welds
    assert (run.start, run.end) == (3, 5)
