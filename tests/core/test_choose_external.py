"""The external-axis chooser (issue 23, robots/mechanisms/choose.py).

Expectations are derived by hand from the cell of tests/core/external_fixtures.py
(the pipe-to-flange seam on a tilt-and-turn positioner: flat at tilt -45,
turn -90 - phi) and from small cells built here; gravity angles are measured
with the mechanisms' forward kinematics (core.mechanisms), not with the chooser.
"""

import numpy as np
import pytest

from CadRobotWB.core import mechanisms as mech
from CadRobotWB.core import program as ir
from CadRobotWB.robots.catalog import catalog
from CadRobotWB.robots.kinematics import models
from CadRobotWB.robots.mechanisms import arm_fit, axis_motion, choose
from CadRobotWB.robots.mechanisms.choose import (TOLERANCE_DEG, choose_external, gravity_angles,
                                                 weld_positions)
from CadRobotWB.robots.motion import configuration

from external_fixtures import T_U_B, positioner_weld_program, track_program
from post_programs import pose
from weld_fixtures import FILLET_T6

# Targets of positioner_weld_program (vias first): approach, entry (arc on at phi 0),
# v3 t3 ... v6 t6 every 45 degrees, retract. The seam targets and their angles:
SEAM = ["t2", "v3", "t3", "v4", "t4", "v5", "t5", "v6", "t6"]
PHI = {name: 45.0 * k for k, name in enumerate(SEAM)}


@pytest.fixture(scope="module")
def arm():
    return models.model("ABB_IRB2400")


def cleared(program):
    for target in program.targets():
        target.external = None
    return program


def by_name(program):
    return {t.name: t for t in program.targets()}


def seam_direction_u(program, target, vector_b):
    """A vector of the part (frame B) in {U} at the target's external values."""
    positioner = program.external.positioner
    _, values = program.external.split(target.external)
    return (positioner.motion(values) @ T_U_B)[:3, :3] @ vector_b


def angle_to_gravity(vector_u):
    return np.degrees(np.arccos(np.clip(-vector_u[2] / np.linalg.norm(vector_u), -1, 1)))


def seam_gravity(program, target):
    """Gravity angle measured by hand: on this seam the torch axis is already
    perpendicular to the travel, so the weld frame's Z is the tool's Z."""
    return angle_to_gravity(seam_direction_u(program, target, target.T_b_t[:3, 2]))


def wrapped(angle_deg):
    return (np.asarray(angle_deg) + 180.0) % 360.0 - 180.0


def test_flat_all_round_as_by_hand(arm):
    """Cleared values: every seam target flat (< 0.1 deg), on one of the two branches
    of the closed form: the fixture's (tilt -45, turn -90 - phi) or its mirror
    through the tilt axis's vertical plane (tilt +45, turn 90 - phi); the turn
    continuous (45-degree steps), approach / retract on the seam start / end."""
    program = cleared(positioner_weld_program())
    choice = choose_external(program, arm)
    targets = by_name(program)
    tilt = targets["t2"].external[0]
    assert abs(abs(tilt) - 45.0) < 1e-6
    turn_zero = -90.0 if tilt < 0 else 90.0
    for name in SEAM:
        target = targets[name]
        assert seam_gravity(program, target) < 0.1
        assert target.external[0] == pytest.approx(tilt, abs=1e-6)
        assert wrapped(target.external[1] - (turn_zero - PHI[name])) == pytest.approx(0, abs=1e-6)
    turns = np.array([targets[n].external[1] for n in SEAM])
    assert np.allclose(np.diff(turns), -45.0)
    np.testing.assert_allclose(targets["t1"].external, targets["t2"].external)
    np.testing.assert_allclose(targets["t7"].external, targets["t6"].external)
    assert choice.values.shape == (11, 2)
    assert choice.worst_gravity_deg["Weld"] < 0.1 and choice.unhelped == []
    np.testing.assert_allclose(gravity_angles(program)[1:10], 0.0, atol=0.1)


def test_fixture_hand_values_measure_flat():
    """gravity_angles reads the values already set: the fixture's hand values are flat,
    the drawn pose (tilt 0) leaves the bisector 45 degrees from gravity."""
    program = positioner_weld_program()
    np.testing.assert_allclose(gravity_angles(program)[1:10], 0.0, atol=1e-6)
    assert np.isnan(gravity_angles(program)[[0, 10]]).all()
    np.testing.assert_allclose(gravity_angles(cleared(program))[1:10], 45.0, atol=1e-6)


def test_horizontal_vertical_PB(arm):
    """PB: the bisector 45 degrees from gravity and the seam (the circle's tangent)
    horizontal at every seam target."""
    program = cleared(positioner_weld_program())
    program.paths[0].welds[0].position = "PB"
    choose_external(program, arm)
    for name in SEAM:
        target = by_name(program)[name]
        phi = np.radians(PHI[name])
        travel_u = seam_direction_u(program, target, np.array([-np.sin(phi), np.cos(phi), 0.0]))
        assert seam_gravity(program, target) == pytest.approx(45.0, abs=0.1)
        assert abs(travel_u[2]) < np.sin(np.radians(0.1))


def test_fixed_tilt(arm):
    """Tilt fixed at -30: the bisector (45 degrees off the table's normal) comes no
    nearer gravity than 45 - 30 = 15 degrees, at the flat turn -90 - phi."""
    program = cleared(positioner_weld_program())
    program.external.positioner.axes[0].fixed = -30.0
    choose_external(program, arm)
    for name in SEAM:
        target = by_name(program)[name]
        assert target.external[0] == -30.0
        assert seam_gravity(program, target) == pytest.approx(15.0, abs=0.1)
        assert wrapped(target.external[1] + 90.0 + PHI[name]) == pytest.approx(0, abs=1e-6)


def test_turn_limits_narrower_than_the_seam(arm):
    """Turn limited to +-200 (as the MOTOPOS D500), tilt fixed at -45: flat asks for
    turn -90 - phi, 360 degrees of turn; continued, the least outside +-200 is
    the run shifted by +360 (270 - phi: 70 and 25 degrees over at phi 0 and 45)
    rather than as found (-90 - phi: 25 + 70 + 115 + ... + 250 under)."""
    program = cleared(positioner_weld_program())
    turn = program.external.positioner.axes[1]
    turn.lower, turn.upper = -200.0, 200.0
    program.external.positioner.axes[0].fixed = -45.0
    choose_external(program, arm)
    turns = np.array([by_name(program)[n].external[1] for n in SEAM])
    np.testing.assert_allclose(turns, [270.0 - PHI[n] for n in SEAM], atol=1e-6)


def test_values_given_at_targets_are_kept(arm):
    """t4 gives its turn (0; NaN tilt), t5 both values: the numbers stay, t4's tilt
    is the best for that turn (a 0.05-degree scan), the rest of the seam flat."""
    program = cleared(positioner_weld_program())
    targets = by_name(program)
    targets["t4"].external = np.array([np.nan, 0.0])
    targets["t5"].external = np.array([-10.0, 33.0])
    choose_external(program, arm)
    assert targets["t4"].external[1] == 0.0
    np.testing.assert_array_equal(targets["t5"].external, [-10.0, 33.0])
    z_b = targets["t4"].T_b_t[:3, 2]
    positioner = program.external.positioner
    scan = np.arange(-135.0, 135.0, 0.05)
    R = (positioner.motion(np.column_stack([scan, np.zeros_like(scan)])) @ T_U_B)[:, :3, :3]
    best = np.min(np.degrees(np.arccos(np.clip(-(R @ z_b)[:, 2], -1, 1))))
    assert seam_gravity(program, targets["t4"]) <= best + 1e-3
    assert best > 10.0          # the given turn is far from flat: the scan is a real test
    for name in set(SEAM) - {"t4", "t5"}:
        assert seam_gravity(program, targets[name]) < 0.1


def turntable_program(centre_x_mm=1000.0, radius_mm=60.0, arcs=4):
    """The fixture's seam (scaled to `radius_mm`) on a vertical turntable
    (hand-built: base at (centre_x_mm, 0, 0), table 750 mm up), robot at the origin."""
    program = cleared(positioner_weld_program(arcs=arcs))
    for target in program.targets():
        target.T_b_t[:3, 3] *= radius_mm / 60.0
    axis = mech.Axis("turn", mech.ROTARY, pose((0, 0, 0), (0.0, 0.0, 750.0)), -720.0, 720.0,
                     90.0, 180.0)
    table = mech.Mechanism("Table", "Table", mech.TURNTABLE, "", [axis],
                           T_u_base=pose((0, 0, 0), (centre_x_mm, 0.0, 0.0)))
    program.external = mech.ExternalAxes(T_u_r=np.eye(4), positioner=table, moving_frames=("B",))
    T_u_b = pose((0, 0, 0), (centre_x_mm, 0.0, 750.0))
    program.frames["B"] = ir.WorkFrame("B", T_u_b, T_u_b.copy(), "CalibrationFrame")
    return program, T_u_b


def test_turntable_faces_the_robot(arm):
    """A vertical turntable cannot change the gravity angle (the torch stays 45
    degrees off the vertical): it turns each seam point to face the robot, the
    point at angle phi on the pipe to azimuth 180 in {U}: turn = 180 - phi."""
    program, T_u_b = turntable_program()
    choice = choose_external(program, arm)
    targets = by_name(program)
    turns = np.array([targets[n].external[0] for n in SEAM])
    np.testing.assert_allclose(wrapped(turns + [PHI[n] for n in SEAM] - 180.0), 0.0, atol=1e-6)
    assert np.all(np.abs(np.diff(turns)) < 180.0)
    np.testing.assert_allclose(choice.gravity_deg[1:10], 45.0, atol=1e-6)
    for name in SEAM:
        motion = program.external.positioner.motion(targets[name].external)
        p_u = (motion @ T_u_b @ targets[name].T_b_t)[:3, 3]
        assert p_u[0] == pytest.approx(1000.0 - 60.0, abs=1e-6) and abs(p_u[1]) < 1e-6


@pytest.mark.parametrize("arcs", [4, 100])
def test_turntable_turns_the_run_when_facing_misses(arm, arcs):
    """Table 300 mm from the robot, seam radius 200: facing the robot (turn 180 - phi)
    puts the seam 100 mm from axis 1, which the arm's own solver cannot take; the
    chooser turns the whole run by one offset (a multiple of 15 degrees) and
    every target is reached, the gravity angle unchanged (45). With 100 arcs (203
    targets) the offsets are ranked on 64 targets first."""
    naive, _ = turntable_program(300.0, 200.0, arcs)
    for target in naive.targets():
        phi = np.degrees(np.arctan2(target.T_b_t[1, 3], target.T_b_t[0, 3]))
        target.external = np.array([180.0 - phi])
    assert statuses(naive, arm) != {"ok"}
    program, _ = turntable_program(300.0, 200.0, arcs)
    choice = choose_external(program, arm)
    assert statuses(program, arm) == {"ok"} and choice.unhelped == []
    offsets = wrapped([t.external[0] - n.external[0]
                       for t, n in zip(program.targets(), naive.targets())])
    assert np.ptp(offsets) < 1e-6 and abs(offsets[0]) >= 15.0 and offsets[0] % 15.0 < 1e-6
    np.testing.assert_allclose(choice.gravity_deg[1:-1], 45.0, atol=1e-6)


def test_track_moves_only_as_much_as_needed(arm):
    """Seam 800 mm beside the track, out to x = 4000 and back to 2500: the robot
    keeps each target within 0.75 x reach horizontally, i.e. within
    f = sqrt(r^2 - 800^2) along X. Out: the travel stays at 0 until the seam
    leaves that, then follows x - f, clamped at the 3000 mm end of the travel.
    Back: every target is within f of 3000 (x >= 3000 - f), so it stays there."""
    out, back = np.arange(0.0, 4001.0, 250.0), np.arange(3750.0, 2499.0, -250.0)
    x = np.concatenate([out, back])
    program = track_program(x)
    choice = choose_external(program, arm)
    reach = arm_fit.GOOD_REACH[1] * catalog.reach_mm(arm.spec)
    f = np.sqrt(reach ** 2 - 800.0 ** 2)
    expected = np.concatenate([np.clip(out - f, 0.0, 3000.0), np.full(len(back), 3000.0)])
    names = by_name(program)
    travel = np.array([names["s%d" % k].external[0] for k in range(len(x))])
    assert choice.unhelped == []
    np.testing.assert_allclose(travel, expected, atol=1e-6)
    assert names["a"].external[0] == travel[0] and names["r"].external[0] == travel[-1]
    assert expected[0] == 0.0 and 0.0 < expected[8] < 3000.0 and back[-1] < 3000.0 - f + 500.0


def test_track_stays_behind_a_near_seam(arm):
    """Seam 400 mm beside the track, nearer than the band's inner edge (0.35 x reach):
    the robot keeps behind each target (travel below it, drawn at 0 < the first x)
    by at least sqrt(r_in^2 - 400^2) and at most f = sqrt(r^2 - 400^2): lazily,
    travel = max(0, x - f)."""
    x = np.arange(1000.0, 3001.0, 250.0)
    program = track_program(x, y_mm=400.0)
    choice = choose_external(program, arm)
    spec_reach = catalog.reach_mm(arm.spec)
    f = np.sqrt((arm_fit.GOOD_REACH[1] * spec_reach) ** 2 - 400.0 ** 2)
    names = by_name(program)
    travel = np.array([names["s%d" % k].external[0] for k in range(len(x))])
    assert choice.unhelped == []
    np.testing.assert_allclose(travel, np.maximum(0.0, x - f), atol=1e-6)
    assert np.all(x - travel >= np.sqrt((arm_fit.GOOD_REACH[0] * spec_reach) ** 2 - 400.0 ** 2))


def test_positioner_and_track(arm):
    """The fixture on the track: the positioner brings every seam point to the same
    place, (1200, +-42.4, 842.4) in {U} (TCP, tilt +-45), so the travel is one value
    for the whole weld: the robot (drawn at travel 0, behind it) moves just enough
    to have it at the band's outer edge: 1200 - sqrt(r^2 - 42.43^2)."""
    program = cleared(positioner_weld_program(track=True))
    choice = choose_external(program, arm)
    reach = arm_fit.GOOD_REACH[1] * catalog.reach_mm(arm.spec)
    travel = 1200.0 - np.sqrt(reach ** 2 - (60.0 / np.sqrt(2.0)) ** 2)
    np.testing.assert_allclose(choice.values[:, 0], travel, atol=1e-6)
    np.testing.assert_allclose(choice.gravity_deg[1:10], 0.0, atol=0.1)
    assert choice.unhelped == [] and abs(abs(choice.values[1, 1]) - 45.0) < 1e-6


def far_robot_program(distance_mm):
    """The fixture with the robot moved to (1200, d, 0), facing -Y: the fixture's
    branch brings the seam point to y = -42 mm (the far side), the mirror to +42."""
    program = cleared(positioner_weld_program())
    program.external.T_u_r = pose((0, 0, -90), (1200.0, distance_mm, 0.0))
    return program


def statuses(program, arm):
    return {e.status for e in configuration.solve_program(program, arm, assign=False).entries}


def test_unreachable_branch_is_avoided(arm):
    """Robot 1380 mm off: the fixture's hand values are out of reach (the arm's own
    solver says so); the chooser takes the mirror branch, still flat, all reached."""
    naive = far_robot_program(1380.0)
    for target in naive.targets():
        target.external = None
    hand = positioner_weld_program()
    for target, hand_target in zip(naive.targets(), hand.targets()):
        target.external = hand_target.external.copy()
    assert "unreachable" in statuses(naive, arm)
    program = far_robot_program(1380.0)
    choice = choose_external(program, arm)
    assert statuses(program, arm) == {"ok"} and choice.unhelped == []
    assert by_name(program)["t2"].external[0] == pytest.approx(45.0)
    assert max(seam_gravity(program, by_name(program)[n]) for n in SEAM) < 0.1


def test_tolerance_helps_the_arm(arm):
    """Robot 1460 mm off: neither exact branch is reached; within the 10-degree
    tolerance the chooser finds values the arm takes, the seam within 10 degrees."""
    exact = far_robot_program(1460.0)
    for target in exact.targets():
        target.external = np.array([45.0, 0.0])     # any turn: the seam point stays put
    assert statuses(exact, arm) == {"unreachable"}
    program = far_robot_program(1460.0)
    choice = choose_external(program, arm)
    assert statuses(program, arm) == {"ok"} and choice.unhelped == []
    worst = max(seam_gravity(program, by_name(program)[n]) for n in SEAM)
    assert 0.1 < worst <= choice.tolerance_deg + 1e-6
    assert choice.worst_gravity_deg["Weld"] == pytest.approx(worst, abs=1e-6)


def tool_down_at(arm, speed_mm_s, tolerance_deg=TOLERANCE_DEG, tilt_deg=None):
    """The fixture, cleared, without its weld (a path whose tool axis is kept down), its
    four arcs at `speed_mm_s`, the tilt fixed at `tilt_deg` if given, chosen."""
    program = cleared(positioner_weld_program())
    program.paths[0].welds = []
    for move in program.moves():
        move.weld = None
    for move in program.paths[0].moves[2:6]:
        move.speed_mm_s = speed_mm_s
    program.external.positioner.axes[0].fixed = tilt_deg
    return program, choose_external(program, arm, tolerance_deg=tolerance_deg)


def tool_axis_tilts(program):
    """(N,) each target's tool axis from straight down, deg, by hand with the FK."""
    return np.array([angle_to_gravity(seam_direction_u(program, t, t.T_b_t[:3, 2]))
                     for t in program.targets()])


def test_without_welds_tool_down(arm):
    """A path without welds: every target's tool axis turned straight down."""
    program, choice = tool_down_at(arm, FILLET_T6.travel_speed_mm_s)
    assert tool_axis_tilts(program).max() < 0.1
    assert np.isnan(choice.gravity_deg).all()


def test_no_external_axes(arm):
    program = cleared(positioner_weld_program())
    program.external = None
    assert choose_external(program, arm).values.shape == (0, 0)
    assert all(t.external is None for t in program.targets())


@pytest.mark.parametrize("change, words", [
    (lambda p: setattr(by_name(p)["t4"], "external", np.array([1.0, 2.0, 3.0])),
     ["Target 't4'", "3 external axis values", "has 2 (E1, E2)"]),
    (lambda p: setattr(p.paths[0].welds[0], "position", "PC"),
     ["Weld 'Pipe to flange'", "'PC'", "PA or PB"]),
])
def test_refusals_name_the_object_and_change_nothing(arm, change, words):
    from CadRobotWB.errors import InputError
    program = cleared(positioner_weld_program())
    change(program)
    before = [None if t.external is None else t.external.copy() for t in program.targets()]
    with pytest.raises(InputError) as error:
        choose_external(program, arm)
    message = str(error.value)
    assert "\n" not in message and all(w in message for w in words), message
    after = [t.external for t in program.targets()]
    assert all((a is None and b is None) or np.array_equal(a, b) for a, b in zip(before, after))


# --- speeds and accelerations of the axes (the speed pass, robots/mechanisms/axis_motion.py) ---

ARC_MM = 60.0 * np.pi / 2.0          # each of the fixture's four welded arcs, 94.25 mm
TURN_LIMITS = (90.0, 180.0)          # the generic positioner's turn: deg/s, deg/s^2
KNOTS = ["t2", "t3", "t4", "t5", "t6"]


def at_speeds(speeds, tolerance_deg=TOLERANCE_DEG, arm=None):
    """The fixture, cleared, its four welded arcs at `speeds` (mm/s), chosen."""
    program = cleared(positioner_weld_program())
    for move, speed in zip(program.paths[0].moves[2:6], speeds):
        move.speed_mm_s = speed
    return program, choose_external(program, arm, tolerance_deg=tolerance_deg)


def turn_motion(turns, speeds):
    """By hand from the knots' turns (5,): each arc's turn speed (4,) (the arc lasts
    ARC_MM / speed) and at t3, t4, t5 (zone 1 mm, the TCP 1 mm each side at each arc's
    speed: 1 / v_in + 1 / v_out s) the acceleration (3,)."""
    speeds = np.asarray(speeds, dtype=float)
    rate = np.diff(turns) / (ARC_MM / speeds)
    return np.abs(rate), np.abs(np.diff(rate)) / (1.0 / speeds[:-1] + 1.0 / speeds[1:])


@pytest.mark.parametrize("speeds, over", [
    ([98.0] * 4, "speed"),               # 90 deg in 0.9617 s: 93.58 deg/s > 90
    ([40.0, 60.0, 60.0, 40.0], "accel"),  # at t3: 38.20 -> 57.30 deg/s in 0.04167 s: 458.4 > 180
], ids=["speed", "accel"])
def test_a_seam_too_fast_for_the_turn_is_moved_within_the_tolerance(arm, speeds, over):
    """The exact flat values (turn -45 deg per arc) need the turn beyond its limits at these
    speeds; the chooser moves the turn (only) so that every arc's turn speed and every
    blended corner's acceleration are within 90 deg/s and 180 deg/s^2, every welded target
    within 10 deg of flat (measured by hand with the positioner's FK, and by
    gravity_angles / weld_positions), each via on the line between its arc's ends."""
    exact_speed, exact_accel = turn_motion(-90.0 * np.arange(5), speeds)
    assert (exact_speed.max() > TURN_LIMITS[0]) == (over == "speed")
    assert (exact_accel.max() > TURN_LIMITS[1]) == (over == "accel")
    program, choice = at_speeds(speeds, arm=arm)
    targets = by_name(program)
    assert choice.limited == {"Weld": ["E2"]}
    turns = np.array([targets[n].external[1] for n in KNOTS])
    speed, accel = turn_motion(turns, speeds)
    assert speed.max() <= TURN_LIMITS[0] + 1e-9 and accel.max() <= TURN_LIMITS[1] + 1e-9
    for k, via in enumerate(["v3", "v4", "v5", "v6"]):
        assert targets[via].external[1] == pytest.approx(0.5 * (turns[k] + turns[k + 1]))
    gravity = [seam_gravity(program, targets[n]) for n in SEAM]
    assert 0.1 < max(gravity) <= TOLERANCE_DEG + 1e-6
    np.testing.assert_allclose(gravity_angles(program)[1:10], gravity, atol=1e-6)
    assert weld_positions(program)[0].worst_deg == pytest.approx(max(gravity), abs=1e-6)
    np.testing.assert_allclose([abs(targets[n].external[0]) for n in SEAM], 45.0, atol=1e-9)
    np.testing.assert_array_equal(targets["t1"].external, targets["t2"].external)
    np.testing.assert_array_equal(targets["t7"].external, targets["t6"].external)


@pytest.mark.parametrize("speeds, tolerance", [
    ([98.0] * 4, 0.0), ([40.0, 60.0, 60.0, 40.0], 0.0), ([200.0] * 4, TOLERANCE_DEG),
], ids=["speed", "accel", "beyond the tolerance"])
def test_where_nothing_fits_the_exact_values_stay(arm, speeds, tolerance):
    """Tolerance 0: no slack. At 200 mm/s the whole circle lasts 4 x 0.4712 s = 1.885 s;
    the ends may move by at most 14.2 deg of turn each (10 deg of gravity angle, the turn
    axis 45 deg from the bisector: 2 asin(sin 5 / sin 45)), so the turn still needs
    (360 - 2 x 14.2) / 1.885 = 176 deg/s > 90. Either way the values stay the exact flat
    ones, too fast as they are (Check reports them: test_external_checks)."""
    program, choice = at_speeds(speeds, tolerance_deg=tolerance, arm=arm)
    reference, _ = at_speeds([FILLET_T6.travel_speed_mm_s] * 4, arm=arm)
    assert choice.limited == {}
    np.testing.assert_array_equal(choice.values, np.array(
        [t.external for t in reference.targets()]))


def test_a_smooth_seam_is_left_as_it_was(arm, monkeypatch):
    """At the fixture's welding speed (7.5 mm/s: the turn at 7.2 deg/s, the same on every
    arc) the values are exactly those chosen without the speed pass."""
    program, choice = at_speeds([FILLET_T6.travel_speed_mm_s] * 4, arm=arm)
    monkeypatch.setattr(choose, "_limit_speeds", lambda *args: {})
    _, without = at_speeds([FILLET_T6.travel_speed_mm_s] * 4, arm=arm)
    assert choice.limited == {}
    np.testing.assert_array_equal(choice.values, without.values)


def test_band_from_the_tolerance():
    """2 asin(sin(alpha) sin(band / 2)) = slack: an axis perpendicular to the vector
    turns it by the band itself; at alpha = 30 deg a 10 deg slack allows
    2 asin(sin 5 / 0.5) = 20.07 deg; no slack, none; an axis along it, any turn."""
    np.testing.assert_allclose(axis_motion.band_deg([1.0, 0.5, 0.5, 0.0], [10.0, 10.0, 0.0, 5.0]),
                               [10.0, np.degrees(2 * np.arcsin(np.sin(np.radians(5)) / 0.5)),
                                0.0, 180.0])
    assert axis_motion.band_deg([0.5], [10.0])[0] == pytest.approx(20.07, abs=0.01)


def test_path_lengths_and_via_fractions():
    """A quarter circle of radius 60 through its 45-degree point: 30 pi mm, the via
    halfway; through its 30-degree point: a third of the way; a line: its length."""
    def point(deg):
        return 60.0 * np.array([np.cos(np.radians(deg)), np.sin(np.radians(deg)), 0.0])
    start = np.array([point(0), point(0), [0.0, 0.0, 0.0]])
    via = np.array([point(45), point(30), [np.nan] * 3])
    end = np.array([point(90), point(90), [3.0, 4.0, 0.0]])
    length, fraction = axis_motion._path_lengths(start, via, end)
    np.testing.assert_allclose(length, [30 * np.pi, 30 * np.pi, 5.0])
    np.testing.assert_allclose(fraction[:2], [0.5, 1.0 / 3.0])
    assert np.isnan(fraction[2])


def test_a_path_without_welds_too_fast_for_the_turn_is_moved_within_the_tolerance(arm):
    """The fixture without its weld, its four arcs at 98 mm/s: kept with the tool axis
    straight down (turn -90 deg per arc) the turn needs 93.58 deg/s > 90 (so before the
    speed pass covered paths without welds, these values stayed and Check reported them).
    Now the turn moves so that every move's turn speed (entry 50 mm in 1 s, arcs
    ARC_MM / 98 s, retract 50 mm in 0.25 s) and every blended corner's acceleration are
    within the limits, every tool axis within 10 deg of straight down (measured by hand
    with the positioner's FK), every target reached (the arm's own solver)."""
    speeds = [98.0] * 4
    assert turn_motion(-90.0 * np.arange(5), speeds)[0].max() > TURN_LIMITS[0]
    program, choice = tool_down_at(arm, 98.0)
    targets = by_name(program)
    assert choice.limited == {"path:Seam": ["E2"]}
    turns = np.array([targets[n].external[1] for n in KNOTS])
    speed, accel = turn_motion(turns, speeds)
    assert speed.max() <= TURN_LIMITS[0] + 1e-9 and accel.max() <= TURN_LIMITS[1] + 1e-9
    entry = abs(targets["t2"].external[1] - targets["t1"].external[1]) / (50.0 / 50.0)
    retract = abs(targets["t7"].external[1] - targets["t6"].external[1]) / (50.0 / 200.0)
    assert max(entry, retract) <= TURN_LIMITS[0]
    assert 0.1 < tool_axis_tilts(program).max() <= TOLERANCE_DEG + 1e-6
    assert statuses(program, arm) == {"ok"} and choice.unhelped == []


def test_a_path_without_welds_may_leave_as_near_down_as_it_goes_by_the_tolerance(arm):
    """The tilt fixed at -30 (15 deg from the -45 that turns the tool axis down): the turn
    alone leaves every tool axis 15 deg from straight down at best (by hand with the FK,
    at the fixture's 7.5 mm/s, where nothing is moved). At 98 mm/s the turn is moved within
    10 deg beyond those 15 (a weld's tolerance, counted from straight down, would leave it
    no slack). With a 1 deg tolerance nothing fits: the ends would have to give up
    360 - 90 x 4 x ARC_MM / 98 = 13.8 deg of turn, each end's band being
    2 asin(sin 0.5 / sin 45) = 1.41 deg; the exact values stay."""
    exact_program, exact = tool_down_at(arm, 7.5, tilt_deg=-30.0)
    np.testing.assert_allclose(tool_axis_tilts(exact_program), 15.0, atol=1e-6)
    program, choice = tool_down_at(arm, 98.0, tilt_deg=-30.0)
    assert choice.limited == {"path:Seam": ["E2"]}
    turns = np.array([by_name(program)[n].external[1] for n in KNOTS])
    speed, accel = turn_motion(turns, [98.0] * 4)
    assert speed.max() <= TURN_LIMITS[0] + 1e-9 and accel.max() <= TURN_LIMITS[1] + 1e-9
    assert 15.1 < tool_axis_tilts(program).max() <= 25.0 + 1e-6
    assert statuses(program, arm) == {"ok"}
    _, strict = tool_down_at(arm, 98.0, tolerance_deg=1.0, tilt_deg=-30.0)
    assert strict.limited == {}
    np.testing.assert_array_equal(strict.values, exact.values)


def travel_motion(travel, step_mm, speed_mm_s):
    """By hand: each welded move (step_mm at speed_mm_s) gives the track's speed (K,); each
    blended target between two (zone 1 mm: 1 mm each side at speed_mm_s) its acceleration."""
    rate = np.diff(travel) / (step_mm / speed_mm_s)
    return np.abs(rate), np.abs(np.diff(rate)) / (2.0 / speed_mm_s)


@pytest.mark.parametrize("track_limits, over", [
    ((1000.0, 2000.0), "accel"),     # the travel starts at s4: 0 -> 53.6 -> 100 mm/s in 0.02 s
    ((80.0, 5000.0), "speed"),       # a slow track: following the TCP at 100 mm/s
], ids=["accel", "speed"])
def test_a_track_too_slow_for_the_seam_starts_earlier_within_the_reach_band(arm, track_limits,
                                                                             over):
    """The seam of test_track_moves_only_as_much_as_needed out to x = 4000, at 100 mm/s. The
    travel keeping each target just within the reach band (by hand: clip(x - f, 0, 3000),
    f = sqrt(r^2 - 800^2), the travel the chooser gave before this pass moved tracks)
    breaks the track's limit; now the track moves earlier and smoother: every move's speed
    and every corner's acceleration within the limits (by hand from the travel), every
    target still within the reach band horizontally (but the last, whose band lies beyond
    the track's end: it stays there) and reached (the arm's own solver)."""
    x = np.arange(0.0, 4001.0, 250.0)
    reach = catalog.reach_mm(arm.spec)
    far, near = arm_fit.GOOD_REACH[1] * reach, arm_fit.GOOD_REACH[0] * reach
    lazy_speed, lazy_accel = travel_motion(np.clip(x - np.sqrt(far ** 2 - 800.0 ** 2), 0.0,
                                                   3000.0), 250.0, 100.0)
    assert (lazy_speed.max() > track_limits[0]) == (over == "speed")
    assert (lazy_accel.max() > track_limits[1]) == (over == "accel")
    program = track_program(x, speed_mm_s=100.0, track_limits=track_limits)
    choice = choose_external(program, arm)
    names = by_name(program)
    travel = np.array([names["s%d" % k].external[0] for k in range(len(x))])
    assert choice.limited == {"W": ["E1"]} and choice.unhelped == []
    speed, accel = travel_motion(travel, 250.0, 100.0)
    assert speed.max() <= track_limits[0] + 1e-9 and accel.max() <= track_limits[1] + 1e-9
    horizontal = np.hypot(x - travel, 800.0)[:-1]     # x = 4000: beyond the band at 3000
    assert np.all((horizontal >= near - 1e-6) & (horizontal <= far + 1e-6))
    assert np.all((travel >= 0.0) & (travel <= 3000.0)) and travel[-1] == 3000.0
    assert statuses(program, arm) == {"ok"}
    assert names["a"].external[0] == travel[0] and names["r"].external[0] == travel[-1]


def test_stretches_of_a_path_without_welds():
    """Check times linear and circular moves only, each in its work frame: a joint move
    ends a stretch, and so does a move into another frame (its duration would depend on
    the axes); the next stretch leaves from its target."""
    from types import SimpleNamespace as Move
    kinds_frames = [(ir.JOINT, "B"), (ir.LINEAR, "B"), (ir.LINEAR, "B"), (ir.JOINT, "B"),
                    (ir.LINEAR, "B"), (ir.CIRCULAR, "B"), (ir.LINEAR, "C"), (ir.LINEAR, "C")]
    moves = [Move(kind=kind, frame=frame) for kind, frame in kinds_frames]
    assert axis_motion._coordinated_stretches(moves) == [(0, 3), (3, 6), (6, 8)]
