"""The placement search (robots/placement/placement.py, robots/placement/placement_search.py).

The cell: two weld paths on a 600 x 500 mm table top (z = 700 mm), the torch
pointing down and tilted 20 degrees, an ABB IRB 2400 on the floor.  The
search's verdict on every base of a small grid is compared with brute force:
the cell generated again with the robot at that base (``core.generate`` from
the cell description, not the search's own shortcut), its joints solved, the
program checked and its collisions with the table found, exactly as
``api.check`` does; the numbers the search reports (counts of unreachable
targets, joint-limit margins) are computed again from the IK.
"""

import numpy as np
import pytest
import trimesh

from CadRobotWB.core.generate import CellSpec, FrameSpec, PathSpec, generate
from CadRobotWB.core.geometry import Line
from CadRobotWB.core.program import ToolData
from CadRobotWB.errors import InputError
from CadRobotWB.robots.checks import checks, collision
from CadRobotWB.robots.kinematics import models
from CadRobotWB.robots.motion import configuration as cfg
from CadRobotWB.robots.placement import placement, placement_search

ROBOT = models.model("ABB_IRB2400")
DOWN = np.diag([1.0, -1.0, -1.0])
TILT = np.array([[1.0, 0.0, 0.0], [0.0, np.cos(0.35), -np.sin(0.35)], [0.0, np.sin(0.35), np.cos(0.35)]])
TABLE_TOP_MM = 690.0


def rz(deg):
    return placement.rotation_z(np.radians(deg))


def pose(x, y, z, turn_deg=0.0):
    T = np.eye(4)
    T[:3, :3] = rz(turn_deg)
    T[:3, 3] = (x, y, z)
    return T


def weld_path(name, points, turn_deg=0.0):
    points = [np.array(p, dtype=float) for p in points]
    segments = [Line(a, b) for a, b in zip(points[:-1], points[1:])]
    R = rz(turn_deg) @ DOWN @ TILT
    return PathSpec(name=name, label=name, segments=segments, R_u_t=[R] * len(segments), frame="F",
                    speed_mm_s=20.0, zone_mm=1.0, approach_mm=60.0, retract_mm=60.0,
                    approach_speed_mm_s=200.0, sample_time_s=0.3, step_mm=None)


def cell_spec(T_u_r=np.eye(4)):
    """Two paths: an L on the table's near half, a line on its far edge."""
    tool = np.eye(4)
    tool[:3, 3] = (0.0, 0.0, 250.0)
    paths = [weld_path("Seam", [(-150, -100, 700), (150, -100, 700), (150, 50, 700)]),
             weld_path("Edge", [(-200, 150, 700), (200, 150, 700)], turn_deg=90.0)]
    return CellSpec(name="Cell", label="Cell", robot="ABB_IRB2400", T_u_r=T_u_r,
                    tool=ToolData("torch", tool),
                    frames={"F": FrameSpec(name="F", label="Table frame", T_u_b=np.eye(4))},
                    paths=paths, source="test")


def table_u():
    mesh = trimesh.creation.box(extents=(600.0, 500.0, TABLE_TOP_MM))
    mesh.apply_translation((0.0, 25.0, TABLE_TOP_MM / 2.0))
    return [("Table", mesh)]


@pytest.fixture(scope="module")
def program():
    return generate(cell_spec())


def brute_force(T_u_r, criteria):
    """What `api.check` says of the cell with the robot moved to `T_u_r`, plus the margin and
    singularity rules, every step done again from the cell description."""
    moved = generate(cell_spec(T_u_r))
    solution = cfg.solve_program(moved, ROBOT, assign=False)
    report = checks.check_program(moved, ROBOT, solution)
    T_r_u = np.linalg.inv(T_u_r)
    solids = [(name, mesh.copy().apply_transform(T_r_u)) for name, mesh in table_u()]
    if collision.is_available():
        checker = collision.RobotCollisionChecker(ROBOT, solids, tool_T_f_t=moved.tool.T_f_t)
        report.findings += collision.program_collision_findings(moved, solution, checker)
    if not report.ok:
        return False
    q = ROBOT.controller_joints(solution.joints())
    margin = np.min(np.minimum(q - ROBOT.joint_min_deg, ROBOT.joint_max_deg - q))
    if margin < criteria.margin_deg:
        return False
    singular = [f for f in report.warnings if f.kind == checks.SINGULARITY]
    return not (criteria.singularities and singular)


def grid():
    return placement.make_space((-1600.0, -1200.0, 1600.0, 1200.0), np.eye(4), turn_deg=(0.0, 180.0),
                                step_mm=800.0, turn_step_deg=180.0)


@pytest.mark.parametrize("criteria", [placement.Criteria(margin_deg=0.0, shoulder_mm=None),
                                      placement.Criteria()], ids=["check-only", "margins"])
def test_the_search_passes_exactly_the_bases_brute_force_passes(program, criteria):
    space = grid()
    found = placement_search.search(program, ROBOT, space, table_u(), criteria=criteria, count=None)
    T_u_r, _, _ = space.bases(np.zeros(3))
    expected = [brute_force(T, criteria) for T in T_u_r]
    key = lambda T: tuple(np.round(T[:3, 3]).astype(int)) + (int(round(np.degrees(np.arctan2(T[1, 0], T[0, 0])))),)
    passed = sorted(key(c.T_u_r) for c in found)
    assert passed == sorted(key(T) for T, ok in zip(T_u_r, expected) if ok)
    # The grid holds every case: passes, bases out of reach, bases in the table.
    assert 0 < len(passed) < len(T_u_r) - 10
    assert found.counts["unreachable"] > 0
    if collision.is_available():
        assert found.counts.get("collision", 0) > 0
    assert found.counts["candidates"] == len(T_u_r) == 5 * 4 * 2
    scores = [c.score for c in found]
    assert scores == sorted(scores, reverse=True)


def test_the_screen_never_refuses_a_base_the_check_accepts(program):
    criteria = placement.Criteria(margin_deg=0.0, shoulder_mm=None)
    space = placement.make_space((-1400.0, -1300.0, 1400.0, 1300.0), np.eye(4), step_mm=350.0)
    solution = cfg.solve_program(program, ROBOT, assign=False)
    targets = placement.target_set(program, solution)
    T_u_r, _, _ = space.bases(targets.centre_mm)
    screened = placement.screen(ROBOT, targets, T_u_r, criteria)
    for T, passed in zip(T_u_r, screened.passed):
        moved = generate(cell_spec(T))
        if cfg.solve_program(moved, ROBOT, assign=False).ok:
            assert passed, T[:3, 3]
    assert 0 < screened.passed.sum() < len(T_u_r)


def test_a_base_too_far_away_says_how_many_targets_are_out_of_reach(program):
    solution = cfg.solve_program(program, ROBOT, assign=False)
    targets = placement.target_set(program, solution)
    T = pose(-1400.0, -100.0, 0.0)
    # Independently: the targets of each path no IK row reaches.
    Q = ROBOT.ik(np.linalg.inv(T) @ targets.T_u_f)
    out = np.isnan(Q).all(axis=(1, 2))
    seam = targets.run == 0
    assert 0 < out[seam].sum() < seam.sum()        # a part of the seam is within reach
    kind, text = placement.explain(ROBOT, targets, T)
    assert kind == placement.UNREACHABLE
    first = targets.names[int(np.flatnonzero(out & seam)[0])]
    assert text == "unreachable: %d of %d targets of path 'Seam' are out of reach (first '%s')" % (
        out[seam].sum(), seam.sum(), first)
    assert placement.explain(ROBOT, targets, pose(-900.0, 0.0, 0.0)) is None


def test_limit_margin_is_the_best_shift_by_360_degrees():
    rng = np.random.default_rng(3)
    q = rng.uniform(-180.0, 180.0, (500, 6))
    margin = placement.limit_margin_deg(ROBOT, q)
    qc = ROBOT.controller_joints(q)
    shifted = qc[:, None, :] + 360.0 * np.arange(-2, 3)[None, :, None]          # (N, 5, 6)
    inside = np.minimum(shifted - ROBOT.joint_min_deg, ROBOT.joint_max_deg - shifted)
    expected = np.min(np.max(inside, axis=1), axis=1)
    assert np.allclose(margin, expected, atol=1e-9)
    assert np.array_equal(margin >= 0.0, cfg.fits_limits(q, ROBOT))


def test_manipulability_vanishes_at_the_wrist_singularity():
    q = np.array([[0.0, 10.0, 20.0, 30.0, 40.0, 0.0], [0.0, 10.0, 20.0, 30.0, 0.0, 0.0]])
    shoulder, elbow, wrist = cfg.arm_geometry(q, ROBOT).singularity_distances()
    m = placement.manipulability((shoulder, elbow, wrist), 1500.0)
    assert m[1] == pytest.approx(0.0, abs=1e-12)
    assert m[0] == pytest.approx(np.sin(np.radians(elbow[0])) * np.sin(np.radians(40.0))
                                 * min(1.0, shoulder[0] / 750.0))


def test_score_formula():
    total, parts = placement.score([10.0, 20.0], [45.0, 9.0], [0.5, 2.0])
    assert parts["time"].tolist() == [1.0, 0.5]
    assert parts["margin"].tolist() == [1.0, 0.2]
    assert parts["manipulability"].tolist() == [0.5, 1.0]
    assert total.tolist() == pytest.approx([0.4 + 0.3 + 0.15, 0.2 + 0.06 + 0.3])
    total, _ = placement.score([10.0], [45.0], [0.5], placement.Weights(1.0, 0.0, 0.0))
    assert total.tolist() == [1.0]


def test_grid_of_the_space():
    space = placement.make_space((0, 0, 1000, 500), pose(0, 0, 120, 30), step_mm=250,
                                 turn_deg=(-180, 180), turn_step_deg=90)
    assert space.x_mm.tolist() == [0, 250, 500, 750, 1000]
    assert space.y_mm.tolist() == [0, 250, 500]
    assert space.z_mm.tolist() == [120.0]                 # the present height
    assert space.turn_deg.tolist() == [-180, -90, 0, 90]  # +180 is -180
    assert np.allclose(space.R_mount, np.eye(3))
    T, index, turns = space.bases(np.zeros(3))
    assert len(T) == 5 * 3 * 4
    assert np.allclose(T[7], pose(space.x_mm[index[7, 1]], space.y_mm[index[7, 0]], 120, turns[7]))
    facing = placement.make_space((0, 0, 1000, 500), np.eye(4), step_mm=500)
    T, _, turns = facing.bases(np.array([500.0, 1000.0, 0.0]))
    for Ti in T:                                          # X of the base points at the centre
        to_centre = np.array([500.0, 1000.0]) - Ti[:2, 3]
        assert np.allclose(Ti[:2, 0], to_centre / np.linalg.norm(to_centre))


def test_a_hanging_robot_keeps_its_mounting():
    hanging = np.eye(4)
    hanging[:3, :3] = rz(40) @ np.diag([1.0, -1.0, -1.0])
    turn, M = placement.mounting(hanging[:3, :3])
    assert turn == pytest.approx(40.0)
    assert np.allclose(M, np.diag([1.0, -1.0, -1.0]))


@pytest.mark.parametrize("kwargs, words", [
    (dict(region=(100, 0, 0, 500)), "xmin (100) is greater than its xmax (0)"),
    (dict(region=(0, 0, 100, 0)), "is empty (no area)"),
    (dict(region=(0, 0, 100)), "must be 4 numbers"),
    (dict(region=(0, 0, 100, float("nan"))), "must be 4 numbers"),
    (dict(z_mm=(300, 0)), "height range z 300..0 mm runs backwards"),
    (dict(turn_deg=(90, -90)), "turn range 90..-90 deg runs backwards"),
    (dict(step_mm=0), "grid step must be a number > 0"),
    (dict(step_mm=0.01), "more than"),
    (dict(step_mm=1e-9), "raise the step"),
])
def test_bad_search_spaces_say_what_to_fix(kwargs, words):
    args = dict(region=(0, 0, 1000, 500))
    args.update(kwargs)
    region = args.pop("region")
    with pytest.raises(InputError) as err:
        placement.make_space(region, np.eye(4), name="Cell SeamCell", **args)
    assert words in str(err.value) and str(err.value).startswith("Cell SeamCell: ")


def test_a_taught_frame_cannot_be_searched(program):
    import dataclasses
    frame = program.frames[next(iter(program.frames))]
    taught = dataclasses.replace(program, frames={
        "F": frame, "G": dataclasses.replace(frame, name="G", source="Taught frame",
                                             T_r_b=pose(10, 0, 0) @ frame.T_r_b)})
    with pytest.raises(InputError, match="Taught frame' is taught"):
        placement.base_of(taught)


def test_the_search_can_be_cancelled(program):
    calls = []

    def progress(fraction, text):
        calls.append(fraction)
        return len(calls) < 3

    with pytest.raises(placement.SearchCancelled):
        placement_search.search(program, ROBOT, grid(), progress=progress)
    assert len(calls) == 3


def test_results_read_and_serialise(program):
    found = placement_search.search(program, ROBOT, grid(), table_u(), count=2)
    assert len(found) == 2 and found.ok
    lines = found.lines()
    assert lines[0].startswith("40 candidate bases, ")
    assert lines[1].startswith("score = 0.40 x fastest cycle time / cycle time")
    assert lines[2].startswith(" 1. score %.3f at x " % found[0].score)
    assert any(line.startswith("FAILS at ") for line in lines)
    data = found.to_dict()
    assert data["ok"] and len(data["candidates"]) == 2 and data["failures"]
    assert set(data["candidates"][0]["parts"]) == {"cycle_time_s", "limit_margin_deg", "manipulability",
                                                   "time_part", "margin_part", "manipulability_part"}
    best = found[0]
    total = (0.4 * best.parts["time_part"] + 0.3 * best.parts["margin_part"]
             + 0.3 * best.parts["manipulability_part"])
    assert best.score == pytest.approx(total)
    assert best.parts["margin_part"] == pytest.approx(min(1.0, best.parts["limit_margin_deg"] / 45.0))
    assert best.parts["cycle_time_s"] == pytest.approx(best.cycle_time["total_s"])
    heat = found.heat
    assert heat.state.shape == (4, 5)
    assert (heat.state == placement_search.PASSES).sum() >= 1
    assert (heat.state == placement_search.FAILS_SCREEN).sum() >= 1
