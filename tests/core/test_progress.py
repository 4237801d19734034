"""The progress protocol (core/progress.py) and its use by the engine's long loops.

Every long function takes ``progress(fraction, text)``: it must be told often
(more than a handful of times over a long path), with fractions that never
decrease and stay in [0, 1]; its result must not depend on being watched; and
a callback returning False must stop it with ``Cancelled`` before it changes
what it was given.
"""

import numpy as np
import pytest
import trimesh

from CadRobotWB.core import progress as pg
from CadRobotWB.core.generate import CellSpec, FrameSpec, PathSpec, generate
from CadRobotWB.core.geometry import Line
from CadRobotWB.core.program import ToolData
from CadRobotWB.errors import CadRobotError
from CadRobotWB.robots.checks import checks, collision
from CadRobotWB.robots.kinematics import models
from CadRobotWB.robots.motion import configuration as cfg, move_sampling, timing
from CadRobotWB.robots.placement import placement

ROBOT = models.model("ABB_IRB2400")
DOWN = np.diag([1.0, -1.0, -1.0])
SEGMENTS = 400          # a 400 mm seam in 1 mm lines


class Recorder:
    """A progress callback that keeps every report; returns False at report `stop_at`."""

    def __init__(self, stop_at=None):
        self.reports, self.stop_at = [], stop_at

    def __call__(self, fraction, text):
        self.reports.append((fraction, text))
        if self.stop_at is not None and len(self.reports) >= self.stop_at:
            return False
        return None

    @property
    def fractions(self):
        return [f for f, _ in self.reports]


def assert_told_often(recorder, at_least):
    fractions = recorder.fractions
    assert len(fractions) >= at_least, recorder.reports
    assert all(0.0 <= f <= 1.0 for f in fractions)
    assert all(a <= b + 1e-12 for a, b in zip(fractions, fractions[1:])), fractions
    assert all(isinstance(t, str) and t for _, t in recorder.reports)


def cell_spec():
    """One straight seam of 1 mm lines in front of an IRB 2400 (every target reachable)."""
    xs = np.linspace(-200.0, 200.0, SEGMENTS + 1)
    points = [np.array((x, 0.0, 500.0)) for x in xs]
    path = PathSpec(name="Seam", label="Seam", segments=[Line(a, b) for a, b in zip(points[:-1], points[1:])],
                    R_u_t=[DOWN] * SEGMENTS, frame="F", speed_mm_s=20.0, zone_mm=1.0,
                    approach_mm=50.0, retract_mm=50.0, approach_speed_mm_s=200.0,
                    sample_time_s=0.3, step_mm=None)
    T_u_r = np.eye(4)
    T_u_r[:3, 3] = (-900.0, 0.0, -300.0)
    return CellSpec(name="Cell", label="Cell", robot="ABB_IRB2400", T_u_r=T_u_r,
                    tool=ToolData("torch", np.eye(4)),
                    frames={"F": FrameSpec(name="F", label="Frame", T_u_b=np.eye(4))},
                    paths=[path], source="test")


@pytest.fixture(scope="module")
def solved():
    program = generate(cell_spec())
    solution = cfg.solve_program(program, ROBOT, assign=False)
    assert not np.isnan(solution.joints()).any()      # every target reachable: the loops run fully
    return program, solution


# --- the protocol ---------------------------------------------------------------------------

def test_cancelled_is_the_one_error_every_caller_catches():
    assert issubclass(pg.Cancelled, CadRobotError)
    assert pg.Cancelled().exit_code == 130
    assert "Cancelled" in str(pg.Cancelled())
    assert placement.SearchCancelled is pg.Cancelled       # api.SearchCancelled is this class too


@pytest.mark.parametrize("answer", [None, True, 0, 1, ""])
def test_only_false_stops(answer):
    pg.report_now(lambda f, t: answer, 0.5, "x")


def test_false_raises_and_fractions_are_clipped():
    seen = []
    pg.report_now(lambda f, t: seen.append((f, t)), 1.7, "over")
    pg.report_now(lambda f, t: seen.append((f, t)), -0.2, "under")
    pg.report_now(None, 0.5, "nobody listens")
    assert seen == [(1.0, "over"), (0.0, "under")]
    with pytest.raises(pg.Cancelled):
        pg.report_now(lambda f, t: False, 0.5, "stop")


def test_stage_maps_into_its_sub_range_and_passes_the_answer_back():
    outer = Recorder(stop_at=3)
    sub = pg.stage(outer, 0.2, 0.6)
    assert sub(0.0, "a") is None and sub(0.5, "b") is None
    assert sub(1.0, "c") is False
    assert outer.reports == [(0.2, "a"), (pytest.approx(0.4), "b"), (pytest.approx(0.6), "c")]
    nested = pg.stage(pg.stage(outer, 0.5, 1.0), 0.5, 1.0)
    nested(0.5, "d")
    assert outer.fractions[-1] == pytest.approx(0.875)
    assert pg.stage(None, 0.0, 1.0) is None


def test_steps_reports_every_share_of_the_loop():
    recorder = Recorder()
    steps = pg.Steps(recorder, 1000, "looping", reports=10)
    for i in range(1000):
        steps(i)
    assert recorder.fractions == [k / 10 for k in range(10)]
    assert {t for _, t in recorder.reports} == {"looping"}
    few = Recorder()
    steps = pg.Steps(few, 3, "short", reports=10)
    for i in range(3):
        steps(i)
    assert few.fractions == pytest.approx([0.0, 1 / 3, 2 / 3])
    pg.Steps(None, 10, "nobody")(0)


# --- the engine --------------------------------------------------------------------------------

def test_generate_reports_segments_and_gives_the_same_program():
    recorder = Recorder()
    watched = generate(cell_spec(), progress=recorder)
    assert_told_often(recorder, 20)
    plain = generate(cell_spec())
    assert [m.target.position_mm.tolist() for m in watched.moves()] == \
        [m.target.position_mm.tolist() for m in plain.moves()]
    with pytest.raises(pg.Cancelled):
        generate(cell_spec(), progress=Recorder(stop_at=5))


def test_solve_program_reports_and_a_cancel_assigns_no_joints():
    program = generate(cell_spec())
    recorder = Recorder()
    solution = cfg.solve_program(program, ROBOT, assign=False, progress=recorder)
    assert_told_often(recorder, 20)
    np.testing.assert_array_equal(solution.joints(),
                                  cfg.solve_program(program, ROBOT, assign=False).joints())
    fresh = generate(cell_spec())
    with pytest.raises(pg.Cancelled):
        cfg.solve_program(fresh, ROBOT, assign=True, progress=Recorder(stop_at=10))
    assert all(m.target.joints_deg is None for m in fresh.moves())


def test_sampling_checks_and_timing_report(solved):
    program, solution = solved
    margins = checks.Margins()
    recorder = Recorder()
    sampled = move_sampling.sample_program(program, ROBOT, solution, margins, progress=recorder)
    assert_told_often(recorder, 3)
    assert recorder.fractions[-1] == 1.0

    recorder = Recorder()
    report = checks.check_program(program, ROBOT, solution, sampled=sampled, progress=recorder)
    assert_told_often(recorder, 20)
    assert report.to_dict() == checks.check_program(program, ROBOT, solution, sampled=sampled).to_dict()
    with pytest.raises(pg.Cancelled):
        checks.check_program(program, ROBOT, solution, sampled=sampled, progress=Recorder(stop_at=4))

    recorder = Recorder()
    times = timing.cycle_time(program, ROBOT, solution, sampled=sampled, progress=recorder)
    assert_told_often(recorder, 20)
    assert times["total_s"] == timing.cycle_time(program, ROBOT, solution, sampled=sampled)["total_s"]


@pytest.mark.skipif(not collision.is_available(), reason="python-fcl is not installed")
def test_collision_check_reports_between_chunks(solved):
    program, solution = solved
    table = trimesh.creation.box(extents=(600.0, 400.0, 20.0))
    table.apply_translation((900.0, 0.0, 780.0))           # {R}: just below the seam
    checker = collision.RobotCollisionChecker(ROBOT, [("Table", table)], tool_T_f_t=program.tool.T_f_t)
    recorder = Recorder()
    found = collision.program_collision_findings(program, solution, checker, progress=recorder)
    poses = len(solution.entries)                          # at least one pose per target
    assert len(recorder.reports) >= poses // collision.CHUNK_POSES
    assert_told_often(recorder, 4)
    assert [f.to_dict() for f in found] == \
        [f.to_dict() for f in collision.program_collision_findings(program, solution, checker)]
    with pytest.raises(pg.Cancelled):
        collision.program_collision_findings(program, solution, checker, progress=Recorder(stop_at=2))
