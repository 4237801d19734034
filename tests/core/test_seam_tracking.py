"""Seam tracking (paper 4.1): the paper's numbers, an L seam, and every failure of 4.3.

The cell: two 8 mm plates with a 1.5 mm root gap on a table, the seam on their
top (z = 8) along +X; the torch points straight down (tool Z = -Z) and
travels at 10 mm/s; the laser runs at 5 Hz, 30 mm ahead.
"""

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation

from CadRobotWB.core import program as ir
from CadRobotWB.core.trajectory import tcp_trajectory
from CadRobotWB.errors import InputError
from CadRobotWB.sensors.reality import Reality
from CadRobotWB.sensors.seam_features import JointTemplate
from CadRobotWB.sensors.seam_tracking import (LookAheadBuffer, PathFrames, resample, seam_error_mm,
                                              simulate_seam_tracking)

SPEED_MM_S = 10.0
TOP_MM = 8.0
GAP_MM = 1.5
TORCH_DOWN = np.array([[1.0, 0, 0], [0, -1, 0], [0, 0, -1]])     # tool X = +X, Z = -Z
BUTT = JointTemplate("butt", gap_mm=GAP_MM)


def box(low, high):
    low, high = np.asarray(low, float), np.asarray(high, float)
    return trimesh.creation.box(high - low, trimesh.transformations.translation_matrix((low + high) / 2))


def straight_butt(length_mm, plates_end_mm=None):
    """Plates from x = -50 to `plates_end_mm` (default length + 50), gap centred on y = 0."""
    end = length_mm + 50.0 if plates_end_mm is None else plates_end_mm
    g = GAP_MM / 2
    return trimesh.util.concatenate([box((-50, -100, 0), (end, -g, TOP_MM)),
                                     box((-50, g, 0), (end, 100, TOP_MM)),
                                     box((-50, -100, -20), (length_mm + 50, 100, 0))])


def l_butt():
    """Like examples/seam_tracking_cell.py: seam (0,0) -> (100,0) -> (100,100); plate A inside
    the corner, the L-shaped plate B around it."""
    g = GAP_MM / 2
    return trimesh.util.concatenate([box((-50, g, 0), (100 - g, 150, TOP_MM)),           # A
                                     box((-50, -100, 0), (200, -g, TOP_MM)),            # B, along leg 1
                                     box((100 + g, -100, 0), (200, 150, TOP_MM)),       # B, along leg 2
                                     box((-50, -100, -20), (200, 150, 0))])             # table


def pose(p, R=TORCH_DOWN):
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p
    return T


def trajectory(points, R=TORCH_DOWN, dt_s=0.01):
    """Linear moves through `points` at 10 mm/s (a hand-made core Program, work frame = {U});
    `R` is the tool rotation (3, 3) of every point or one per point (N, 3, 3)."""
    rotations = R if np.ndim(R) == 3 else [R] * len(points)
    moves = [ir.Move(ir.JOINT, ir.Target("p0", pose(points[0], rotations[0])), 100.0, 0.0, "B")]
    moves += [ir.Move(ir.LINEAR, ir.Target("p%d" % k, pose(p, r)), SPEED_MM_S, 0.0, "B")
              for k, (p, r) in enumerate(zip(points[1:], rotations[1:]), 1)]
    program = ir.Program("P", "ABB_IRB2400", ir.ToolData("t", np.eye(4)),
                         {"B": ir.WorkFrame("B", np.eye(4), np.eye(4))}, [ir.ProgramPath("p", "p", moves)])
    return tcp_trajectory(program, dt_s, first_move=1)


def paper_deviation(about=(0.0, 0.0, TOP_MM)):
    """The workpiece 5 mm sideways (+Y), 2 mm up and turned 1° about Z at `about` (the seam start)."""
    T = np.eye(4)
    T[:3, :3] = Rotation.from_euler("z", 1.0, degrees=True).as_matrix()
    T[:3, 3] = np.asarray(about) - T[:3, :3] @ np.asarray(about) + [0.0, 5.0, 2.0]
    return T


def real(mesh, reality, extra=()):
    moved = mesh.copy()
    moved.apply_transform(reality.T_u_dev)
    return trimesh.util.concatenate([moved] + [m for _, m in extra])


LENGTH_MM = 200.0
NOMINAL = trajectory([(0, 0, TOP_MM), (LENGTH_MM, 0, TOP_MM)])


def paper_run(**options):
    reality = Reality(T_u_dev=paper_deviation(), laser_noise_mm=0.02, seed=3)
    seam = reality.rigid_points([(-50, 0, TOP_MM), (LENGTH_MM + 50, 0, TOP_MM)])
    return simulate_seam_tracking(NOMINAL, real(straight_butt(LENGTH_MM), reality), seam, reality,
                                  BUTT, **options)


def hand_error_mm(s_mm):
    """Open-loop error by hand: the real seam crosses the plane x = s at y = 5 + s tan 1°, z = 8 + 2."""
    return np.hypot(5.0 + s_mm * np.tan(np.radians(1.0)), 2.0)


# ------------------------------------------------------------- the paper's numbers


def test_open_loop_error_is_the_displacement_geometry():
    run = paper_run(controller="none")
    s = run.nominal_mm[:, 0]
    np.testing.assert_allclose(run.error_mm, hand_error_mm(s), atol=1e-9)
    assert abs(run.error_mm[0] - np.hypot(5.0, 2.0)) < 1e-9          # "about 5 mm"
    np.testing.assert_array_equal(run.correction_mm, 0.0)
    assert not run.aborted and run.metrics["n_corrections"] == 0
    assert abs(run.metrics["open_loop_max_error_mm"] - hand_error_mm(LENGTH_MM)) < 1e-9


def test_closed_loop_meets_the_paper_numbers():
    run = paper_run(controller="pi")
    m = run.metrics
    assert not run.aborted
    assert m["rms_error_after_20mm_mm"] <= 0.2
    assert m["max_step_mm"] <= 0.5 + 1e-12
    assert m["open_loop_rms_error_mm"] > 5.0
    # the same numbers recomputed from the samples
    after = run.error_mm[run.nominal_mm[:, 0] >= 20.0]
    assert abs(np.sqrt(np.mean(after ** 2)) - m["rms_error_after_20mm_mm"]) < 1e-12
    # the correction at the end is the displacement there: +Y 5 + s tan 1°, +Z 2
    np.testing.assert_allclose(run.correction_mm[-1], [0.0, 5.0 + LENGTH_MM * np.tan(np.radians(1)), 2.0],
                               atol=0.1)
    # 5 Hz: one measurement per 2 mm of the 170 mm the laser sees before the path end
    assert m["n_measurements"] == 86 and m["seam_lost_count"] == 0


def test_steps_are_quantised_to_the_resolution_and_limited():
    run = paper_run(controller="pi", robot_lag_s=0.0)           # the robot takes each command at once
    # path frame: Y = -Y_U, Z = -Z_U, so the correction's U components are the commands
    lateral, standoff = -run.correction_mm[:, 1], -run.correction_mm[:, 2]
    for c in (lateral, standoff):
        np.testing.assert_allclose(c / 0.01, np.round(c / 0.01), atol=1e-6)
        assert np.abs(np.diff(c)).max() <= 0.5 + 1e-9
    changes = np.flatnonzero(np.abs(np.diff(lateral)) > 1e-9) + 1
    assert np.all(changes % 20 == 0)                             # only every 20 samples: 5 Hz at 10 ms
    # the first 0.5 mm steps: 5.5 mm to go with 0.5 mm per period
    np.testing.assert_allclose(-lateral[[0, 20, 40, 60]], [0.5, 1.0, 1.5, 2.0], atol=1e-9)


def test_fuzzy_pi_tracks_too():
    run = paper_run(controller="fuzzy_pi")
    assert run.metrics["rms_error_after_20mm_mm"] <= 0.2
    assert run.metrics["max_step_mm"] <= 0.5 + 1e-12


def test_a_coarser_trajectory_is_resampled():
    coarse = trajectory([(0, 0, TOP_MM), (LENGTH_MM, 0, TOP_MM)], dt_s=0.05)
    fine = resample(coarse, 0.01)
    np.testing.assert_allclose(np.diff(fine.time_s), 0.01, atol=1e-9)
    np.testing.assert_allclose(fine.position_mm[:, 0], SPEED_MM_S * fine.time_s, atol=1e-9)
    reality = Reality(T_u_dev=paper_deviation(), seed=3)
    seam = reality.rigid_points([(-50, 0, TOP_MM), (LENGTH_MM + 50, 0, TOP_MM)])
    run = simulate_seam_tracking(coarse, real(straight_butt(LENGTH_MM), reality), seam, reality, BUTT)
    assert len(run.time_s) == len(fine.time_s)
    assert run.metrics["rms_error_after_20mm_mm"] <= 0.2


def test_an_l_shaped_seam_is_tracked_round_the_corner():
    nominal = trajectory([(0, 0, TOP_MM), (100, 0, TOP_MM), (100, 100, TOP_MM)])
    T = np.eye(4)
    T[:3, 3] = [1.5, -2.0, 1.0]
    reality = Reality(T_u_dev=T, seed=5)
    seam = reality.rigid_points([(-50, 0, TOP_MM), (100, 0, TOP_MM), (100, 150, TOP_MM)])
    run = simulate_seam_tracking(nominal, real(l_butt(), reality), seam, reality, BUTT)
    assert not run.aborted, run.reason
    # open loop: leg 1 is 2 mm off sideways, leg 2 1.5 mm; 1 mm high on both (the corner
    # sample already travels along leg 2)
    open_loop = simulate_seam_tracking(nominal, real(l_butt(), reality), seam, reality, BUTT,
                                       controller="none").error_mm
    on_leg1 = run.nominal_mm[:, 0] < 100.0 - 1e-9
    np.testing.assert_allclose(open_loop[on_leg1], np.hypot(2.0, 1.0), atol=1e-9)
    np.testing.assert_allclose(open_loop[~on_leg1], np.hypot(1.5, 1.0), atol=1e-9)
    assert run.metrics["rms_error_after_20mm_mm"] <= 0.2
    # the correction is the translation itself, on both legs: the torch turns at the real corner
    # and ends where the real seam ends
    x = run.nominal_mm[:, 0]
    leg1 = run.correction_mm[(x > 40) & (x < 60), 1:]
    np.testing.assert_allclose(leg1, np.tile([-2.0, 1.0], (len(leg1), 1)), atol=0.1)
    np.testing.assert_allclose(run.correction_mm[-1], [1.5, -2.0, 1.0], atol=0.1)
    corner = np.argmin(np.linalg.norm(run.nominal_mm - [100, 0, TOP_MM], axis=1))
    np.testing.assert_allclose(run.actual_mm[corner], [101.5, -2.0, TOP_MM + 1.0], atol=0.1)


def test_a_fillet_joint_with_a_tilted_torch():
    z = np.array([0, 1, -1]) / np.sqrt(2)                              # into the corner at 45°
    R = np.column_stack([[1, 0, 0], np.cross(z, [1, 0, 0]), z])
    nominal = trajectory([(0, 0, TOP_MM), (150, 0, TOP_MM)], R=R)
    mesh = trimesh.util.concatenate([box((-50, -100, 0), (200, 100, TOP_MM)),
                                     box((-50, 0, TOP_MM), (200, 8, 108))])       # web face at y = 0
    T = np.eye(4)
    T[:3, 3] = [0.0, -3.0, 1.0]
    reality = Reality(T_u_dev=T, seed=2)
    seam = reality.rigid_points([(-50, 0, TOP_MM), (200, 0, TOP_MM)])
    run = simulate_seam_tracking(nominal, real(mesh, reality), seam, reality, JointTemplate("fillet"))
    assert not run.aborted, run.reason
    assert abs(run.metrics["open_loop_max_error_mm"] - np.hypot(3.0, 1.0)) < 1e-9
    assert run.metrics["rms_error_after_20mm_mm"] <= 0.2


# ------------------------------------------------------------------ failures


def flat_run(mesh=None, extra=(), seam_end=LENGTH_MM + 50, **options):
    reality = Reality(foreign_objects=list(extra), seed=1)
    mesh = straight_butt(LENGTH_MM) if mesh is None else mesh
    seam = np.array([(-50, 0, TOP_MM), (seam_end, 0, TOP_MM)], float)
    return simulate_seam_tracking(NOMINAL, real(mesh, reality, extra), seam, reality, BUTT, **options)


def test_a_seam_that_ends_is_lost_and_the_robot_stops_and_retracts():
    run = flat_run(straight_butt(LENGTH_MM, plates_end_mm=119.0), seam_end=119.0)
    assert run.aborted and run.reason.startswith("seam lost")
    # The laser looks 30 mm ahead every 2 mm (s = 0, 2, ...): stations 30, 32, ..., 118 are on
    # the plates, 120, 122 and 124 miss; the third miss comes with the TCP at 124 - 30 = 94 mm.
    assert run.metrics["stop_s_mm"] == pytest.approx(94.0)
    assert "laser at s = 124.0 mm" in run.reason
    k = run.stop_index
    np.testing.assert_allclose(run.stop_T_u_t[:3, 3], run.actual_mm[k])
    np.testing.assert_allclose(run.stop_T_u_t[:3, :3], TORCH_DOWN, atol=1e-12)
    # retract: straight up the tool axis (-Z tool = +Z) by 50 mm at 50 mm/s
    back = run.actual_mm[k + 1:] - run.actual_mm[k]
    np.testing.assert_allclose(back[:, :2], 0.0, atol=1e-12)
    assert abs(back[-1, 2] - 50.0) < 1e-9 and np.all(np.diff(back[:, 2]) > 0)
    assert len(back) == 100 and np.isnan(run.error_mm[k + 1:]).all()
    assert run.metrics["seam_lost_count"] == 3


def test_an_unreachable_correction_stops_the_robot():
    reality = Reality(T_u_dev=paper_deviation(), seed=3)
    seam = reality.rigid_points([(-50, 0, TOP_MM), (LENGTH_MM + 50, 0, TOP_MM)])
    mesh = real(straight_butt(LENGTH_MM), reality)

    def reach_check(T_u_t, _time_s=None):  # the work area ends 3 mm to the side of the seam
        return "outside the work area" if T_u_t[1, 3] > 3.0 + 1e-9 else None

    run = simulate_seam_tracking(NOMINAL, mesh, seam, reality, BUTT, reach_check=reach_check)
    assert run.aborted and "unreachable" in run.reason and "outside the work area" in run.reason
    # commands go 0.5, 1.0, ... mm: the 7th (3.5 mm, period 6 = 1.2 s = 12 mm) is refused
    assert run.stop_index == 120 and run.metrics["stop_s_mm"] == pytest.approx(12.0)
    # it stops where it is: the 3.0 mm correction applied (after the robot's lag), 12 mm along
    np.testing.assert_allclose(run.stop_T_u_t[:2, 3], [12.0, 3.0], atol=0.02)

    run = simulate_seam_tracking(NOMINAL, mesh, seam, reality, BUTT, reach_check=reach_check,
                                 on_failure="reactive")
    assert not run.aborted
    assert run.time_s[-1] == pytest.approx(LENGTH_MM / SPEED_MM_S)
    assert run.correction_mm[:, 1].max() <= 3.0 + 1e-9          # held at the last reachable one
    kinds = [e["kind"] for e in run.metrics["events"]]
    assert kinds[0] == "unreachable" and run.metrics["events"][0]["s_mm"] == pytest.approx(12.0)


def test_a_correction_beyond_its_limit_stops_the_robot():
    # 5 + s tan 1° sideways and 2 up pass 7 mm at s = (sqrt(7² - 2²) - 5) / tan 1° = 97.8 mm
    run = paper_run(max_correction_mm=7.0)
    assert run.aborted and run.reason.startswith("correction beyond its limit")
    s_limit = (np.sqrt(7.0 ** 2 - 2.0 ** 2) - 5.0) / np.tan(np.radians(1.0))
    assert abs(run.metrics["stop_s_mm"] + 1.0 - s_limit) <= 3.0     # read 1 mm ahead, 2 mm periods


CLAMP = ("clamp", box((100, -10, TOP_MM), (110, 10, TOP_MM + 15)))


def test_a_foreign_object_on_the_seam_is_seen_by_the_laser_first():
    run = flat_run(extra=[CLAMP])
    assert run.aborted and run.reason.startswith("seam lost")
    assert 100.0 - 30.0 <= run.metrics["stop_s_mm"] < 100.0          # stopped before reaching it


def test_a_foreign_object_hit_by_the_tool_is_a_collision():
    run = flat_run(extra=[CLAMP], lost_limit=1000)                    # the lost seam is tolerated
    assert run.aborted and run.reason.startswith("collision") and "clamp" in run.reason
    # the tool (TCP up 150 mm) first crosses the clamp just past its face at x = 100
    assert 100.0 <= run.metrics["stop_s_mm"] <= 100.1 + 1e-9


def test_reactive_mode_keeps_going_past_the_failures():
    run = flat_run(extra=[CLAMP], on_failure="reactive")
    assert not run.aborted and run.reason == "" and run.stop_index is None
    assert run.time_s[-1] == pytest.approx(LENGTH_MM / SPEED_MM_S)
    kinds = [e["kind"] for e in run.metrics["events"]]
    assert kinds == ["seam_lost", "collision"]
    lost, hit = run.metrics["events"]
    assert lost["s_mm"] < hit["s_mm"]
    assert run.metrics["seam_lost_count"] >= 5                        # 10 mm of clamp, 2 mm a profile


# --------------------------------------------------------------- pieces


def test_seam_error_is_measured_in_the_plane_normal_to_the_travel():
    points = np.array([[10.0, 0, 0], [20.0, 0, 0], [300.0, 0, 0]])
    normals = np.tile([1.0, 0, 0], (3, 1))
    seam = np.array([[0.0, 3.0, 4.0], [100.0, 3.0 + 100 * np.tan(0.1), 4.0]])   # turned 0.1 rad
    error = seam_error_mm(points, normals, seam)
    np.testing.assert_allclose(error[:2], np.hypot(3.0 + points[:2, 0] * np.tan(0.1), 4.0))
    assert np.isnan(error[2])                                          # past the seam's end


def test_the_buffer_takes_the_unseen_along_travel_part_from_the_newest_measurement():
    buffer = LookAheadBuffer(10)
    for s_mm in (10.0, 20.0, 30.0):                                   # leg 1, along +X
        buffer.store(s_mm, np.array([0.0, -2.0, 1.0]), np.array([1.0, 0, 0]), s_tcp_mm=0.0)
    buffer.store(40.0, np.array([1.5, -2.0, 1.0]), np.array([0, 1.0, 0]), s_tcp_mm=15.0)   # leg 2
    np.testing.assert_allclose(buffer.reference(10.0), [0.0, -2.0, 1.0])    # behind the TCP: kept
    np.testing.assert_allclose(buffer.reference(20.0), [1.5, -2.0, 1.0])    # ahead: X from leg 2
    np.testing.assert_allclose(buffer.reference(25.0), [1.5, -2.0, 1.0])
    np.testing.assert_allclose(buffer.reference(0.0), [0.0, -2.0, 1.0])     # flat before the first
    np.testing.assert_allclose(buffer.reference(99.0), [1.5, -2.0, 1.0])    # and after the last


def test_path_frames_continue_straight_past_the_end():
    frames = PathFrames(NOMINAL)
    p, X, Y, Z = frames.at(LENGTH_MM + 30.0)
    np.testing.assert_allclose(p, [LENGTH_MM + 30.0, 0, TOP_MM], atol=1e-9)
    np.testing.assert_allclose(np.array([X, Y, Z]).T, TORCH_DOWN, atol=1e-12)


def test_bad_options_are_refused():
    with pytest.raises(InputError):
        paper_run(on_failure="ignore")
    with pytest.raises(InputError):
        paper_run(controller="pid")
    with pytest.raises(InputError):
        paper_run(max_step_mm=0.001)
    with pytest.raises(InputError):
        paper_run(gains={"kd": 1.0})
    with pytest.raises(InputError, match="corner_hold_mm"):
        paper_run(corner_hold_mm=-1.0)
    with pytest.raises(InputError, match="capture_mm"):
        paper_run(capture_mm=0.0)
