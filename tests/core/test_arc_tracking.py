"""Through-arc seam tracking (issue 22): the hand-computed step response of the per-cycle law
(plan d.2), the issue's acceptance case, and every refusal and failure.

The part: a T-joint, the floor plate's top in z = 0 (y < 10), the wall's face in y = 0
(z > 0); the seam (the root) runs along +X at the origin. The torch points into the corner on
the bisector, tool Z = (0, 1, -1)/sqrt(2), so the walls are 45 degrees from its axis; the
weave frame's lateral Y = Z x X = (0, -1, -1)/sqrt(2).
"""


import numpy as np
import pytest
import trimesh

from CadRobotWB.core import program as ir
from CadRobotWB.core.trajectory import tcp_trajectory
from CadRobotWB.core.welding import Tracking, Weave
from CadRobotWB.errors import InputError
from CadRobotWB.sensors.arc_tracking import NO_WEAVE, simulate_arc_tracking
from CadRobotWB.sensors.joint_detection import FaceSide, PathSample, detect_joint
from CadRobotWB.sensors.reality import Reality
from CadRobotWB.sensors.run import metric_phrases

from weld_fixtures import FILLET_T6, ZIGZAG_4MM

TOOL_Z = np.array([0.0, 1.0, -1.0]) / np.sqrt(2)
TRAVEL = np.array([1.0, 0.0, 0.0])
LATERAL = np.cross(TOOL_Z, TRAVEL)
TORCH = np.column_stack([TRAVEL, LATERAL, TOOL_Z])
SPEED = FILLET_T6.travel_speed_mm_s             # 7.5 mm/s
#: The step-response weave: 10 mm wide (half width 5 mm > 3 mm / 0.75: the linear range),
#: 2 Hz (3.75 mm per cycle), 0.1 s dwell at each end.
WIDE = Weave("zigzag", width_mm=10.0, frequency_hz=2.0, dwell_left_s=0.1,
             dwell_right_s=0.1).validated()


def box(low, high):
    low, high = np.asarray(low, float), np.asarray(high, float)
    return trimesh.creation.box(high - low,
                                trimesh.transformations.translation_matrix((low + high) / 2))

def fillet(length_mm, part_end_mm=None):
    end = length_mm + 50.0 if part_end_mm is None else part_end_mm
    return trimesh.util.concatenate([box((-50, -60, -10), (end, 10, 0)),
                                     box((-50, 0, 0), (end, 10, 60))])


def seam_trajectory(length_mm, dt_s=0.002):
    """The weave-centre path along the root, at the schedule's travel speed."""
    def pose(x):
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = TORCH, (x, 0.0, 0.0)
        return T
    moves = [ir.Move(ir.JOINT, ir.Target("p0", pose(0.0)), 100.0, 0.0, "B"),
             ir.Move(ir.LINEAR, ir.Target("p1", pose(length_mm)), SPEED, 0.0, "B")]
    program = ir.Program("P", "ABB_IRB2400", ir.ToolData("t", np.eye(4)),
                         {"B": ir.WorkFrame("B", np.eye(4), np.eye(4))},
                         [ir.ProgramPath("p", "p", moves)])
    return tcp_trajectory(program, dt_s, first_move=1)

def run(shift_mm, weave=ZIGZAG_4MM, length_mm=100.0, part_end_mm=None, noise_a=5.0, **options):
    """The tracker on the fillet moved by `shift_mm` (3,) in {U}."""
    T = np.eye(4)
    T[:3, 3] = shift_mm
    mesh = fillet(length_mm, part_end_mm)
    mesh.apply_transform(T)
    seam = np.array([[-50.0, 0, 0], [length_mm + 50.0, 0, 0]]) + shift_mm
    reality = Reality(T_u_dev=T, arc_current_noise_a=noise_a, seed=7)
    return simulate_arc_tracking(seam_trajectory(length_mm), mesh, seam, reality, weave, FILLET_T6,
                                 **options)


def per_cycle_error(result, weave=WIDE):
    """The error at the middle of each weave cycle k = 0, 1, ... (mm)."""
    cycle = weave.cycle_time_s(SPEED)
    t = result.time_s - result.time_s[0]
    middles = np.arange(0.5 * cycle, t[-1] - 0.5 * cycle, cycle)
    return result.error_mm[np.searchsorted(t, middles)]

def test_lateral_step_follows_the_hand_computed_recurrence():
    # 3 mm step to the left of the root; lags and noise off, height correction off, a fine
    # resolution. Cycle 0 ramps the weave in (not measured); cycle 1 measures e = 3 mm exactly
    # (linear range: S_y = |dI/dLt| / tan 45 at the end zones' CTWD); its correction applies
    # from cycle 2: e_k = 3 (1 - g)^(k - 1) for k >= 1.
    g = 0.3
    result = run(3.0 * LATERAL, weave=WIDE, noise_a=0.0, current_lag_s=0.0, robot_lag_s=0.0,
                 resolution_mm=1e-4, tracking=Tracking("arc", lateral_gain=g, height_gain=0.0))
    assert not result.aborted
    errors = per_cycle_error(result)[:10]
    expected = np.r_[3.0, 3.0 * (1 - g) ** np.arange(9)]
    np.testing.assert_allclose(errors, expected, rtol=0.01)
    # the torch is to the left (-Y): the first estimate is -3 mm (to the model's third order)
    assert result.metrics["cycle_estimates_mm"][0][1] == pytest.approx(-3.0, rel=0.02)


def test_height_step_is_corrected_from_the_mean_current():
    # 1 mm closer to the torch along its axis, lateral correction off: the cycle-mean current
    # against the schedule's reference. Each cycle removes g of the error, to the model's
    # curvature: I'' is about 0.4 A/mm^2 at 12 mm CTWD against |I'| of 6 A/mm, so the linear
    # estimate of a 1 mm error is about 3 % high.
    g = 0.5
    result = run(-1.0 * TOOL_Z, weave=WIDE, noise_a=0.0, current_lag_s=0.0, robot_lag_s=0.0,
                 resolution_mm=1e-4, tracking=Tracking("arc", lateral_gain=0.0, height_gain=g))
    errors = per_cycle_error(result)[:6]
    assert errors[:2] == pytest.approx([1.0, 1.0], abs=1e-6)
    np.testing.assert_allclose(errors[2:] / errors[1:-1], 1 - g, atol=0.02)


def test_the_issues_fillet_3mm_lateral_2mm_height_is_five_times_better_than_open_loop():
    shift = 3.0 * LATERAL - 2.0 * TOOL_Z
    closed = run(shift)                                  # 5 A RMS current noise, seeded
    open_loop = run(shift, controller="none")
    assert not closed.aborted and not open_loop.aborted
    assert open_loop.metrics["rms_error_after_20mm_mm"] == pytest.approx(np.sqrt(13.0), abs=1e-6)
    assert closed.metrics["rms_error_after_20mm_mm"] * 5 <= \
        open_loop.metrics["rms_error_after_20mm_mm"]
    assert closed.metrics["max_step_mm"] <= 1.0
    assert closed.sensor == "arc" and closed.metrics["n_measurements"] >= 20
    assert metric_phrases(closed)[0].startswith("RMS error after 20 mm 0.")


def test_a_turned_weave_is_measured_against_the_difference_it_expects():
    # turned 20 degrees toward the tool axis, one end of the weave is 1.4 mm nearer the work
    # than the other: the tracker subtracts that expected current difference
    turned = Weave("zigzag", width_mm=4.0, frequency_hz=2.0, angle_deg=20.0).validated()
    result = run(3.0 * LATERAL - 2.0 * TOOL_Z, weave=turned)
    assert result.metrics["rms_error_after_20mm_mm"] < 0.2       # 0.6 mm without it


def test_learned_reference_keeps_a_height_error_present_at_the_start():
    result = run(-1.0 * TOOL_Z, weave=WIDE, noise_a=0.0,
                 tracking=Tracking("arc", reference="learned"))
    assert result.metrics["rms_error_after_20mm_mm"] == pytest.approx(1.0, abs=0.02)

def test_no_weave_is_refused_with_the_sentence():
    with pytest.raises(InputError) as refused:
        run(np.zeros(3), weave=None, weld_label="Weld")
    assert str(refused.value) == "Weld 'Weld': " + NO_WEAVE + "."
    assert NO_WEAVE == "through-arc tracking needs a weave: give the weld a weave"

def test_a_square_butt_joint_is_not_offered_with_its_reason():
    butt = [FaceSide("PlateA", "Face6", np.array([0, 0, 1.0]), np.array([0, -1.0, 0]), 0.75),
            FaceSide("PlateB", "Face6", np.array([0, 0, 1.0]), np.array([0, 1.0, 0]), 0.75)]
    detection = detect_joint([PathSample(0.0, 1, np.zeros(3), TRAVEL, np.array([0, 0, -1.0]),
                                         butt)])
    assert detection.kind == "butt" and not detection.fits("arc")
    assert detection.why_not("arc") == ("a square butt joint has no sidewalls: the current "
                                         "does not change across the weave; use the laser")
    assert detection.not_offered("arc").startswith("Through-arc seam tracking: not offered, ")
    # test_joint_detection's T joint (web at y <= 0), the torch into its corner
    fillet_faces = [FaceSide("Base", "Face6", np.array([0, 0, 1.0]), np.array([0, 1.0, 0])),
                    FaceSide("Web", "Face3", np.array([0, 1.0, 0]), np.array([0, 0, 1.0]),
                             extent_mm=100.0)]
    fillet_detection = detect_joint([PathSample(0.0, 1, np.zeros(3), TRAVEL,
                                                np.array([0, -1.0, -1.0]) / np.sqrt(2),
                                                fillet_faces)])
    assert fillet_detection.fits("arc") and fillet_detection.why_not("arc") == ""
    assert fillet_detection.wall_angle_deg() == pytest.approx(45.0)


def test_no_surface_under_the_torch_is_arc_lost():
    # the part ends at x = 60 mm, the weld goes on to 100 mm
    aborted = run(np.zeros(3), part_end_mm=60.0)
    assert aborted.aborted and aborted.failure() == "arc lost"
    assert 59.0 < aborted.metrics["stop_s_mm"] < 62.0
    assert "no surface within 35 mm of the contact tip" in aborted.reason
    reactive = run(np.zeros(3), part_end_mm=60.0, on_failure="reactive")
    assert not reactive.aborted
    assert [e["kind"] for e in reactive.metrics["events"]] == ["arc_lost"]


def test_options_that_do_not_apply_are_refused():
    with pytest.raises(InputError, match="controller 'fuzzy_pi' is not offered"):
        run(np.zeros(3), controller="fuzzy_pi")
    with pytest.raises(InputError, match="once per weave cycle: leave rate_hz out"):
        run(np.zeros(3), rate_hz=5.0)


def test_the_weld_to_track_and_its_moves_come_from_the_program():
    from CadRobotWB.sensors.arc_tracking import weld_to_track
    from weld_fixtures import woven_fillet_program
    program = woven_fillet_program()
    program.paths.insert(0, ir.ProgramPath("Other", "Other", program.paths[0].moves[:2]))
    run, first, last = weld_to_track(program, program.paths[1])
    assert run.name == "Weld" and (first, last) == (2 + 2, 3 + 2)   # after the other path's 2
    with pytest.raises(InputError, match="^Path 'Other' has no weld: through-arc tracking"):
        weld_to_track(program, program.paths[0])
    with pytest.raises(InputError, match="^Path 'Fillet seam' has no weld 'Nope': "):
        weld_to_track(program, program.paths[1], "Nope")
    plain = woven_fillet_program(weave=None)
    with pytest.raises(InputError) as refused:
        weld_to_track(plain, plain.paths[0], "Fillet weld")
    assert str(refused.value) == "Weld 'Fillet weld': " + NO_WEAVE + "."

