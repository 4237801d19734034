"""Checks of external axes (issue 23): limits, speeds, collisions with what they carry.

The program is ``external_fixtures.positioner_weld_program``: the fillet all round a
pipe of radius 60 mm on the generic tilt-and-turn positioner (tilt -135..135 deg at
70 deg/s, turn -3600..3600 deg at 90 deg/s), flat by hand; the torch welds it from
above while the part turns under it (see test_external_motion for the numbers).
"""

import math

import numpy as np
import pytest
import trimesh

from CadRobotWB.core import frames as tf
from CadRobotWB.robots.checks import checks, collision, mechanism_solids
from CadRobotWB.robots.kinematics import models
from CadRobotWB.robots.mechanisms import catalog, choose
from CadRobotWB.robots.motion import configuration as cfg

import external_fixtures as ef

MODEL = models.model("ABB_IRB2400")
ARC_MM = 60.0 * math.pi / 2.0          # each of the fixture's four welded arcs

needs_fcl = pytest.mark.skipif(not collision.is_available(), reason="python-fcl not installed")


def checked(program):
    return checks.check_program(program, MODEL, cfg.solve_program(program, MODEL))


def of_kind(report, kind):
    return [f for f in report.findings if f.kind == kind]


def no_mechanism_solids(monkeypatch):
    """Leave the mechanisms' own solids out: the test is about the obstacles it gives."""
    monkeypatch.setattr(catalog, "solids", lambda mechanism, values=None: [])


def test_the_hand_flat_program_passes_with_nothing_left_unchecked():
    """Limits, speeds, accelerations, collisions with the mechanism's solids: all checked."""
    report = checked(ef.positioner_weld_program())
    assert report.ok and not report.warnings, report.lines()
    assert report.not_checked == {} and report.lines()[0].startswith("OK: 11 targets"), \
        report.lines()


def test_an_axis_beyond_its_limit_is_an_error_naming_mechanism_axis_and_target():
    program = ef.positioner_weld_program()
    program.paths[0].moves[3].target.external[1] = -3700.0       # t4: turn, limit -3600
    findings = of_kind(checked(program), checks.EXTERNAL_LIMIT)
    assert len(findings) == 1
    finding = findings[0]
    assert (finding.severity, finding.target, finding.value, finding.limit) == \
        ("error", "t4", -3700.0, -3600.0)
    assert finding.message.startswith(
        "Target 't4' (path 'Pipe seam', move 4) needs Positioner's E2 (turn) at -3700.0 deg, "
        "100.0 deg beyond its limit of -3600 deg: give it a value from -3600 to 3600 deg")


def _with_turn_limits(program, lower_deg, upper_deg):
    turn = program.external.positioner.axes[1]
    turn.lower, turn.upper = lower_deg, upper_deg
    return program


def test_a_weld_round_that_fits_the_turn_range_is_told_how_far_to_turn_the_part():
    """The seam turns the table 360 deg (-90 - phi for phi 0..360, by hand), more than
    -200..200 allows from there. Turning the part on the table by delta moves the seam
    point at phi to phi + delta, so the weld then needs the fixture's flat_values(phi +
    delta): the suggested delta must bring all of them within the limits (at some whole
    turn), with the margin split evenly."""
    program = _with_turn_limits(ef.positioner_weld_program(), -200.0, 200.0)
    findings = of_kind(checked(program), checks.EXTERNAL_LIMIT)
    assert findings and all(f.message.endswith(
        "or turn the part on the positioner's table by +90 deg (counter-clockwise seen from "
        "above the table): path 'Pipe seam' (360.0 deg of turn) then fits between -200 and "
        "200 deg (+70.0 and +110.0 deg reach the limits).") for f in findings), findings[0].message
    turn_after = np.array([ef.flat_values(phi + 90.0)[1] for phi in np.linspace(0, 360, 73)])
    shift = 360.0 * np.round(-turn_after.mean() / 360.0)
    assert turn_after.min() + shift == pytest.approx(-180.0)
    assert turn_after.max() + shift == pytest.approx(180.0)


def test_the_part_turn_is_told_the_same_way_on_an_axis_counted_clockwise():
    """The MOTOPOS D500 counts its turn clockwise seen from above the table ("reversed"):
    the same motion has the turn values negated, and the advice is the same physical turn
    of the part, +90 deg counter-clockwise seen from above."""
    program = ef.positioner_weld_program()
    program.external.positioner = catalog.build("tilt_turn", "YASKAWA_MOTOPOS_D500",
                                                T_u_base=ef.T_U_POSITIONER)
    for target in {id(t): t for p in program.paths for m in p.moves
                   for t in (m.target, m.via) if t is not None}.values():
        target.external = np.array([target.external[0], -target.external[1]])
    findings = of_kind(checked(program), checks.EXTERNAL_LIMIT)
    assert findings and all(
        "turn the part on the positioner's table by +90 deg (counter-clockwise seen from above "
        "the table): path 'Pipe seam' (360.0 deg of turn) then fits between -200 and 200 deg "
        "(+70.0 and +110.0 deg reach the limits)." in f.message for f in findings), \
        findings[0].message


def test_a_weld_round_needing_more_turn_than_the_axis_has_is_told_to_split():
    program = _with_turn_limits(ef.positioner_weld_program(), -150.0, 150.0)
    findings = of_kind(checked(program), checks.EXTERNAL_LIMIT)
    assert findings and all(f.message.endswith(
        "or turn the part on the positioner. Path 'Pipe seam' needs 360.0 deg of turn, more "
        "than its 300 deg from -150 to 150: split it into welds of at most 300 deg of turn "
        "each.") for f in findings), findings[0].message


def test_an_axis_too_fast_for_the_programmed_speed_is_an_error_with_the_speed_that_fits():
    """t2 -> t3 at 200 mm/s: the arc (60 pi / 2 = 94.25 mm) takes 0.4712 s, in which the turn
    axis turns 90 deg: 191.0 deg/s against 90; 200 * 90 / 191.0 = 94.2 mm/s fits."""
    program = ef.positioner_weld_program()
    program.paths[0].moves[2].speed_mm_s = 200.0
    findings = of_kind(checked(program), checks.EXTERNAL_SPEED)
    assert [f.target for f in findings] == ["t3"]
    needed = 90.0 / (60.0 * math.pi / 2.0 / 200.0)
    assert findings[0].value == pytest.approx(needed, rel=1e-9)
    assert findings[0].limit == 90.0
    assert findings[0].severity == "error"
    assert "Positioner's E2 (turn) would have to move 90.0 deg in that time, at 191.0 deg/s; " \
           "its limit is 90 deg/s" in findings[0].message
    assert "program the move at %.3g mm/s or slower" % (200.0 * 90.0 / needed) \
        in findings[0].message
    assert "94.2 mm/s" in findings[0].message
    program.paths[0].moves[2].speed_mm_s = 94.0                 # slower than that: fine
    assert not of_kind(checked(program), checks.EXTERNAL_SPEED)


def at_speeds(speeds, tolerance_deg=None):
    """The fixture's four welded arcs at `speeds` (mm/s); with `tolerance_deg`, the values
    chosen by the chooser with that tolerance instead of the hand values."""
    program = ef.positioner_weld_program()
    for move, speed in zip(program.paths[0].moves[2:6], speeds):
        move.speed_mm_s = speed
    if tolerance_deg is not None:
        for target in program.targets():
            target.external = None
        choose.choose_external(program, MODEL, tolerance_deg=tolerance_deg)
    return program


def test_a_corner_too_quick_for_the_axis_is_a_warning_with_the_speed_and_zone_that_fit():
    """Arcs at 40, 60, 60, 40 mm/s (94.25 mm, 90 deg of turn each: -38.20, -57.30, -57.30,
    -38.20 deg/s), 1 mm zones: at t3 the TCP is in the zone 1/40 + 1/60 = 0.04167 s, in
    which the turn changes speed by 19.10 deg/s: 458.4 deg/s^2 against 180; t5 the same,
    t4 none. The fixes: both moves slower by sqrt(180 / 458.4) = 0.6267 (62 %: 25 and
    37.5 mm/s, then 458.4 x 0.625^2 = 179.1), or a zone of 2.6 mm (458.4 / 2.6 = 176.3);
    each makes the warning go. The chooser with tolerance 0 keeps these values (it has
    no slack), so Check reports the same."""
    needed = (90.0 / (ARC_MM / 60.0) - 90.0 / (ARC_MM / 40.0)) / (1.0 / 40.0 + 1.0 / 60.0)
    assert needed == pytest.approx(458.37, abs=0.01)
    for tolerance in (None, 0.0):
        findings = of_kind(checked(at_speeds([40.0, 60.0, 60.0, 40.0], tolerance)),
                           checks.EXTERNAL_ACCEL)
        assert [(f.target, f.severity) for f in findings] == [("t3", "warning"), ("t5", "warning")]
        assert findings[0].value == pytest.approx(needed, rel=1e-9) and findings[0].limit == 180.0
    message = findings[0].message
    assert message.startswith(
        "At target 't3' (path 'Pipe seam', move 3), Positioner's E2 (turn) changes speed from "
        "-38.2 to -57.3 deg/s within the 1 mm zone (0.042 s): 458.4 deg/s^2, its limit is "
        "180 deg/s^2"), message
    assert "program both moves at 62% of their speed or slower (25 and 37.5 mm/s), give the " \
           "target a zone of 2.6 mm or more, or fix the axis." in message, message
    assert not of_kind(checked(at_speeds([25.0, 37.5, 37.5, 25.0])), checks.EXTERNAL_ACCEL)
    program = at_speeds([40.0, 60.0, 60.0, 40.0])
    for move in program.paths[0].moves[2:5]:
        move.zone_mm = 2.6
    assert not of_kind(checked(program), checks.EXTERNAL_ACCEL)


def test_the_chooser_without_tolerance_leaves_a_too_fast_turn_to_check():
    """At 98 mm/s the flat values turn the table 90 deg in 0.9617 s: 93.6 deg/s against 90.
    With tolerance 0 the chooser keeps them and Check names the axis on every arc; with
    the default 10 deg it moves them and Check finds neither speed nor acceleration."""
    speed = of_kind(checked(at_speeds([98.0] * 4, 0.0)), checks.EXTERNAL_SPEED)
    assert [f.target for f in speed] == ["t3", "t4", "t5", "t6"]
    assert speed[0].value == pytest.approx(90.0 / (ARC_MM / 98.0), rel=1e-9)
    assert "Positioner's E2 (turn) would have to move 90.0 deg" in speed[0].message
    report = checked(at_speeds([98.0] * 4, choose.TOLERANCE_DEG))
    assert not of_kind(report, checks.EXTERNAL_SPEED) and not of_kind(report,
                                                                      checks.EXTERNAL_ACCEL)


def test_a_mechanism_without_solids_is_reported_not_checked(monkeypatch):
    no_mechanism_solids(monkeypatch)
    report = checked(ef.positioner_weld_program())
    assert report.not_checked["mechanism collisions"] == "tilt_turn 'Positioner' has no solids"


# --- collisions -------------------------------------------------------------------------------

def cube(centre_u, T_u_r, size_mm=20.0):
    """A cube mesh centred at `centre_u` ({U}), given in {R} (the robot base T_u_r)."""
    mesh = trimesh.creation.box(extents=(size_mm,) * 3)
    mesh.apply_translation(tf.transform_points(tf.invert_transform(T_u_r), centre_u))
    return mesh


def behind_the_torch_at(phi_deg, back_mm=100.0):
    """A point on the torch's axis `back_mm` behind the TCP at the seam point `phi_deg`, in
    {U} as drawn (positioner at 0, 0)."""
    T = ef.T_U_B @ ef.seam_pose(phi_deg)
    return T[:3, 3] - back_mm * T[:3, 2]


def collisions(program, obstacles):
    solution = cfg.solve_program(program, MODEL)
    checker = collision.RobotCollisionChecker(MODEL, obstacles,
                                              **collision.tool_arguments(program.tool))
    return collision.program_collision_findings(program, solution, checker)


@needs_fcl
@pytest.mark.parametrize("track", [False, True], ids=["positioner", "track"])
def test_a_solid_riding_on_the_positioner_turns_with_it(track, monkeypatch):
    """A 20 mm cube drawn on the torch's axis 100 mm behind the seam point at phi = 90 deg:
    riding on the positioner it meets the torch (radius 20 mm) at t3, 10 + 20 = 30 mm deep;
    standing still it stays where the torch never goes."""
    no_mechanism_solids(monkeypatch)
    program = ef.positioner_weld_program(track=track)
    block = [("Block", cube(behind_the_torch_at(90.0), program.external.T_u_r))]
    assert collisions(program, block) == []
    program.external.riding_solids = ("Block",)
    hits = collisions(program, block)
    at_t3 = [f for f in hits if f.target == "t3"]
    assert at_t3 and at_t3[0].value == pytest.approx(30.0, abs=1e-6)
    assert "hits Block (30.0 mm deep) at target t3" in at_t3[0].message


@needs_fcl
def test_a_still_solid_moves_in_the_robot_base_as_the_track_carries_the_robot(monkeypatch):
    """A cube on the torch axis 100 mm above the flat TCP stands still in {U}; the TCP does
    too, so the torch meets it at every seam target although the robot rides 300 mm."""
    no_mechanism_solids(monkeypatch)
    program = ef.positioner_weld_program(track=True)
    tcp = np.array([1200.0, -60.0 / math.sqrt(2.0), 800.0 + 60.0 / math.sqrt(2.0)])
    post = [("Post", cube(tcp + [0.0, 0.0, 100.0], program.external.T_u_r))]
    hit = {f.target for f in collisions(program, post)}
    assert {"t2", "t3", "t4", "t5", "t6"} <= hit


def box_solid(lo, hi):
    mesh = trimesh.creation.box(np.subtract(hi, lo))
    mesh.apply_translation(0.5 * np.add(lo, hi))
    return np.asarray(mesh.vertices), np.asarray(mesh.faces)


def fake_solids(mechanism, values=None):
    """One box per body, base first, each carried by its axis (:func:`body_motions`)."""
    values = mechanism.drawn_at if values is None else np.asarray(values, dtype=float)
    motions = mechanism_solids.body_motions(mechanism, values)[0]
    base = mechanism.T_u_base[:3, 3]
    boxes = [box_solid(base + [-200, -200, 0], base + [200, 200, 700]),      # pedestal
             box_solid(base + [-150, -250, 700], base + [150, 250, 760]),    # yoke
             box_solid(base + [-250, -250, 760], base + [250, 250, 790])]    # table
    return [(tf.transform_points(T, v), f)
            for T, (v, f) in zip(motions, boxes[:len(mechanism.axes) + 1])]


def test_the_positioners_bodies_move_with_their_axes(monkeypatch):
    """Table corner (1450, 250, 790) at tilt -45, turn -90: the turn about Z_B takes
    (250, 250, -10) from B's origin to (250, -250, -10); the tilt by -45 deg about X
    (through (1200, 0, 800); y' = c y + c z, z' = -c y + c z, c = cos 45) to
    (250, -260 c, 240 c), back in {U}: (1450, -183.85, 969.71). The yoke only tilts, the
    pedestal stays; with the robot 120 mm along the track {R} sees all of it 120 mm back,
    but the carriage still."""
    monkeypatch.setattr(catalog, "solids", fake_solids)
    program = ef.positioner_weld_program(track=True)
    external = program.external
    solids, problems = mechanism_solids.mechanism_solids(external)
    names = [name for name, _, _ in solids]
    assert problems == []
    assert names == ["Track base", "Track travel", "Positioner base", "Positioner tilt",
                     "Positioner turn"]
    scene = mechanism_solids.SceneMotion(external, names + ["Floor"])
    values = np.array([[120.0, -45.0, -90.0]])
    poses = scene.poses(values)
    corner_r0 = [1450.0, 250.0, 790.0]            # T_u_r is the identity at travel 0
    c = math.sqrt(0.5)
    moved_u = [1450.0, -260.0 * c, 240.0 * c + 800.0]
    # The robot rode 120 mm along +X: {R} sees everything 120 mm back.
    expected_r = np.subtract(moved_u, [120.0, 0.0, 0.0])
    np.testing.assert_allclose(tf.transform_points(poses["Positioner turn"][0], corner_r0),
                               expected_r, atol=1e-9)
    np.testing.assert_allclose(tf.transform_points(poses["Positioner base"][0], corner_r0),
                               np.subtract(corner_r0, [120.0, 0.0, 0.0]), atol=1e-9)
    np.testing.assert_allclose(tf.transform_points(poses["Floor"][0], corner_r0),
                               np.subtract(corner_r0, [120.0, 0.0, 0.0]), atol=1e-9)
    # The track's carriage carries the robot: it stands still in {R}.
    np.testing.assert_allclose(poses["Track travel"][0], np.eye(4), atol=1e-9)
    # The yoke tilts but does not turn: (250, 250, -10) -> (250, 240 c, -260 c).
    np.testing.assert_allclose(
        tf.transform_points(poses["Positioner tilt"][0], corner_r0),
        [1450.0 - 120.0, 240.0 * c, -260.0 * c + 800.0], atol=1e-9)


@needs_fcl
def test_the_mechanisms_solids_join_the_collision_check(monkeypatch):
    """With the fake positioner's solids the flat weld is clear of them (its table turns
    under the torch, 60 mm and more from the seam); a torch pushed 80 mm deeper into the
    work reaches the table."""
    monkeypatch.setattr(catalog, "solids", fake_solids)
    program = ef.positioner_weld_program()
    assert collisions(program, []) == []
    for move in program.paths[0].moves[2:6]:
        for target in (move.target, move.via):
            target.T_b_t[:3, 3] += 80.0 * target.T_b_t[:3, 2]
    hits = collisions(program, [])
    assert hits and all("Positioner turn" in f.message for f in hits)


def test_each_weld_says_how_far_it_is_from_its_position_and_warns_beyond_the_tolerance():
    """The hand values weld flat (0 deg); the tilt held at -30 instead of -45 leaves the
    bisector 15 deg from straight down at every target (the turn still brings the seam
    point to the bottom), beyond the 10 deg tolerance: one warning, numbers in it."""
    report = checked(ef.positioner_weld_program())
    assert not of_kind(report, checks.WELD_POSITION)
    assert "Weld 'Pipe to flange': at most 0.00 deg from flat (PA) over its 9 welded targets" \
        in report.lines()[-1]
    program = ef.positioner_weld_program()
    for target in program.targets():
        target.external = target.external + np.array([15.0, 0.0])
    report = checked(program)
    [warning] = of_kind(report, checks.WELD_POSITION)
    assert warning.severity == checks.WARNING and warning.target == "t2"
    assert warning.value == pytest.approx(15.0) and warning.limit == 10.0
    assert "15.0 deg from flat (PA)" in warning.message and "Tolerance" in warning.message
    assert report.to_dict()["weld_positions"][0]["worst_deg"] == pytest.approx(15.0)
    program.paths[0].welds[0].position = "PB"          # 15 deg is 30 deg from PB's 45
    [warning] = of_kind(checked(program), checks.WELD_POSITION)
    assert warning.value == pytest.approx(30.0) and "horizontal-vertical (PB)" in warning.message


def test_an_unreachable_target_with_the_track_at_its_end_says_the_track_is_too_short():
    """The robot 3000 mm back from the pipe along the track (the carriage at travel 0, the
    lower end of the generic 0..3000 mm): every seam target is out of reach, and each says
    the track is at its end there; at travel 1 mm (not an end) none says so."""
    program = ef.positioner_weld_program(track=True)
    back = tf.make_transform(np.eye(3), [-3000.0, 0.0, 0.0])
    program.external.T_u_r = back @ program.external.T_u_r
    program.external.track.T_u_base = back @ program.external.track.T_u_base
    for travel, says in ((0.0, True), (1.0, False)):
        for target in program.targets():
            target.external[0] = travel
        unreachable = of_kind(checked(program), checks.UNREACHABLE)
        assert unreachable and all(("Track 'Track' is at the end of its travel (0..3000 mm) there"
                                    in f.message) is says for f in unreachable)


def test_an_unreachable_target_on_the_positioner_says_to_move_the_positioner():
    """The positioner (and the part on it, frame B) 3000 mm farther along X: every seam
    target is out of reach, and each says the part rides on the positioner."""
    program = ef.positioner_weld_program()
    away = tf.make_transform(np.eye(3), [3000.0, 0.0, 0.0])
    program.external.positioner.T_u_base = away @ program.external.positioner.T_u_base
    unreachable = of_kind(checked(program), checks.UNREACHABLE)
    assert unreachable and all("The part rides on positioner 'Positioner': move the positioner"
                               in f.message for f in unreachable)


def test_a_tolerance_of_zero_asks_for_exactly_flat():
    """Tolerance 0 is read as 0 (as the chooser reads it), not as the 10 deg default."""
    program = ef.positioner_weld_program()
    for target in program.targets():
        target.external = target.external + np.array([1.0, 0.0])
    assert not of_kind(checked(program), checks.WELD_POSITION)        # 1 deg < 10 deg
    program.external.tolerance_deg = 0.0
    [warning] = of_kind(checked(program), checks.WELD_POSITION)
    assert warning.value == pytest.approx(1.0) and warning.limit == 0.0


def test_a_track_alone_cannot_turn_the_seam_and_the_warning_says_so():
    """A straight seam on a track-only cell, torch straight down (flat, 0 deg), asked for
    horizontal-vertical (PB, 45 deg): 45 deg off at every welded target, beyond the 10 deg
    tolerance; nothing turns the part, so the fix is not about a positioner."""
    program = ef.track_program(np.arange(0.0, 1001.0, 250.0))
    program.paths[0].welds[0].position = "PB"
    [warning] = of_kind(checked(program), checks.WELD_POSITION)
    assert warning.value == pytest.approx(45.0)
    assert "nothing in this cell turns the part" in warning.message
    assert "positioner's" not in warning.message
