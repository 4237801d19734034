"""Coordinated motion with external axes (issue 23): sampling, cycle time, playback, placement.

The cell of ``external_fixtures``: the pipe-to-flange fillet (radius 60 mm about
B's Z) welded all round on the generic tilt-and-turn positioner, flat by hand
(tilt -45 deg, turn -90 - phi deg at the seam point at angle phi), optionally
with the robot on a generic track (E1 0 -> 300 mm along the weld).

Hand numbers: the work frame B is at (1200, 0, 800) in {U} at tilt = turn = 0,
the tilt axis is X_U through that point. At turn = -90 - phi every seam point
turns to angle -90 deg about Z_B, i.e. (0, -60, 0) from B's origin; tilting
that by -45 deg about X gives (0, -60 cos 45, 60 sin 45): the TCP stands still
at (1200, -42.426, 842.426) in {U} while the seam runs under it, and the
bisector torch axis points straight down.
"""

import math

import numpy as np
import pytest

from CadRobotWB.core import frames as tf
from CadRobotWB.robots.kinematics import models
from CadRobotWB.robots.motion import configuration as cfg
from CadRobotWB.robots.motion import move_sampling as ms
from CadRobotWB.robots.motion import playback, timing
from CadRobotWB.robots.placement import placement, placement_search

import external_fixtures as ef

MODEL = models.model("ABB_IRB2400")
FLAT_TCP_U = np.array([1200.0, -60.0 / math.sqrt(2.0), 800.0 + 60.0 / math.sqrt(2.0)])
ARC_MM = 60.0 * math.pi / 2.0                 # one circular move: a quarter of the seam


def solved(track=False, **speeds):
    """The fixture program and its solution; `speeds` {move index as 'm2': mm/s}."""
    program = ef.positioner_weld_program(track=track)
    for key, speed in speeds.items():
        program.paths[0].moves[int(key[1:])].speed_mm_s = speed
    return program, cfg.solve_program(program, MODEL)


@pytest.fixture(scope="module", params=[False, True], ids=["positioner", "track"])
def sampled_program(request):
    program, solution = solved(track=request.param)
    return program, ms.sample_program(program, MODEL, solution, ms.Margins())


def tcp_of_samples(program, sampled):
    """TCP poses of the sampled joints, in {R} and in {U} (the base at each sample's travel)."""
    T_r_t = MODEL.fk(sampled.q_deg) @ program.tool.T_f_t
    return T_r_t, program.external.T_u_r_at(sampled.external) @ T_r_t


def test_coordinated_circle_stays_on_the_circle_in_b_and_flat_in_u(sampled_program):
    program, sampled = sampled_program
    assert (sampled.status == ms.OK).all()
    T_r_t, T_u_t = tcp_of_samples(program, sampled)
    frame = program.frames["B"]
    T_b_t = tf.invert_transform(program.external.T_r_b(frame, sampled.external)) @ T_r_t
    circular = np.concatenate([np.arange(sampled.offsets[k], sampled.offsets[k + 1])
                               for k in range(len(sampled))
                               if sampled.groups[k][-1].move.kind == "circular"])
    assert len(circular) > 4 * 45                     # 90 deg of turn at <= 2 deg a step
    p_b = T_b_t[circular, :3, 3]
    np.testing.assert_allclose(np.hypot(p_b[:, 0], p_b[:, 1]), 60.0, atol=1e-6)
    np.testing.assert_allclose(p_b[:, 2], 0.0, atol=1e-6)
    # The positioner turns in step: turn = -90 - phi at every sample (phi unwrapped).
    phi = np.degrees(np.unwrap(np.arctan2(p_b[:, 1], p_b[:, 0])))
    turn = sampled.external[circular, -1]
    np.testing.assert_allclose(turn, -90.0 - phi, atol=1e-6)
    # ... so the TCP stands still in {U}, the torch pointing straight down.
    np.testing.assert_allclose(T_u_t[circular, :3, 3], np.tile(FLAT_TCP_U, (len(circular), 1)),
                               atol=1e-6)
    np.testing.assert_allclose(T_u_t[circular, :3, 2], np.tile([0, 0, -1], (len(circular), 1)),
                               atol=1e-9)
    steps = np.abs(np.diff(sampled.external, axis=0))
    inside = np.ones(len(steps), dtype=bool)
    inside[sampled.offsets[1:-1] - 1] = False         # not across two moves
    assert steps[inside, -1].max() <= 2.0 + 1e-9


def test_track_travel_is_linear_along_each_move():
    program, solution = solved(track=True)
    sampled = ms.sample_program(program, MODEL, solution, ms.Margins())
    k = next(k for k in range(len(sampled)) if sampled.groups[k][-1].target.name == "t3")
    rows = slice(sampled.offsets[k], sampled.offsets[k + 1])
    # From t2 (phi 0, travel 0) to t3 (phi 90, travel 75 mm): travel = 75 f.
    np.testing.assert_allclose(sampled.external[rows, 0], 75.0 * sampled.fractions[rows],
                               atol=1e-9)
    np.testing.assert_allclose(sampled.external_delta[k], [75.0, 0.0, -90.0], atol=1e-9)


def test_without_external_axes_the_samples_carry_none():
    program, solution = solved()
    program.external = None
    sampled = ms.sample_program(program, MODEL, cfg.solve_program(program, MODEL),
                                ms.Margins())
    assert sampled.external is None and sampled.external_delta is None


def test_a_coordinated_move_takes_the_time_its_positioner_needs():
    """Move 2 (t2 -> t3) at 200 mm/s: the TCP needs 94.2 mm / 200 mm/s = 0.47 s, but the turn
    axis (90 deg/s, 180 deg/s^2) turns 90 deg from rest at t2 (zone 0) and blends into the
    next move at t3: 0.5 s to reach 90 deg/s over 22.5 deg, then 67.5 deg at 90 deg/s = 0.75 s."""
    program, solution = solved(m2=200.0)
    times = timing.cycle_time(program, MODEL, solution)["moves"]
    assert times[2]["target"] == "t3"
    assert times[2]["limited_by"] == "E2 speed"
    assert times[2]["time_s"] == pytest.approx(0.5 + 67.5 / 90.0, abs=1e-9)
    # Stopping at t3 too (zone 0): the full trapezoid, 0.5 + 0.5 + 45 / 90 = 1.5 s.
    program.paths[0].moves[2].zone_mm = 0.0
    times = timing.cycle_time(program, MODEL, cfg.solve_program(program, MODEL))["moves"]
    assert times[2]["time_s"] == pytest.approx(1.5, abs=1e-9)
    # At the fillet's travel speed the TCP is slower than the axis: the move is the arc's time.
    program, solution = solved()
    move = timing.cycle_time(program, MODEL, solution)["moves"][3]
    assert not move["limited_by"].startswith("E")


def test_a_joint_move_waits_for_its_external_axes():
    """The retract as a joint move that also turns the part back 180 deg: the turn axis needs
    0.5 + 0.5 + 135 / 90 = 2.5 s (a trapezoid from rest to rest), longer than the arm."""
    program = ef.positioner_weld_program()
    retract = program.paths[0].moves[-1]
    retract.kind = "joint"
    retract.target.external = retract.target.external + [0.0, 180.0]
    solution = cfg.solve_program(program, MODEL)
    move = timing.cycle_time(program, MODEL, solution)["moves"][-1]
    assert move["limited_by"] == "E2"
    assert move["time_s"] == pytest.approx(2.5, abs=1e-9)


@pytest.mark.parametrize("track", [False, True], ids=["positioner", "track"])
def test_timeline_carries_the_external_values(track):
    program, solution = solved(track=track)
    timeline = playback.joint_timeline(program, MODEL, solution, dt_s=0.5)
    assert timeline.failure is None
    assert timeline.external.shape == (len(timeline), 3 if track else 2)
    moves = program.moves()
    # At the end of every move the axes are at its target's values.
    for index in range(len(moves)):
        last = np.flatnonzero(timeline.move_index == index)[-1]
        np.testing.assert_allclose(timeline.external[last], moves[index].target.external,
                                   atol=1e-9)
    # Inside move 2 (t2 -> t3): linear in time, turn = -90 - 90 f.
    rows = np.flatnonzero(timeline.move_index == 2)
    start = timeline.time_s[rows[0] - 1]
    f = (timeline.time_s[rows] - start) / (timeline.time_s[rows[-1]] - start)
    np.testing.assert_allclose(timeline.external[rows, -1], -90.0 - 90.0 * f, atol=1e-9)
    t = float(timeline.time_s[rows[3]])
    np.testing.assert_allclose(timeline.external_at(t), timeline.external[rows[3]])
    # The TCP stands still in {U} while the seam is welded; on a track the base rides along.
    welded = np.isin(timeline.move_index, [2, 3, 4, 5])
    np.testing.assert_allclose(timeline.tcp_u[welded], np.tile(FLAT_TCP_U, (welded.sum(), 1)),
                               atol=1e-6)
    if track:
        np.testing.assert_allclose(timeline.base_u[:, :3, 3],
                                   np.column_stack([timeline.external[:, 0],
                                                    np.zeros((len(timeline), 2))]), atol=1e-9)
    else:
        assert timeline.base_u is None


def test_the_player_slows_a_move_its_positioner_cannot_follow():
    """Move 2 (t2 -> t3) at 200 mm/s: the TCP would take 94.25 mm / 200 mm/s = 0.47 s, but the
    turn axis (90 deg/s) needs 90 deg / 90 deg/s = 1.0 s, so the controller (and the player)
    slows the TCP to 1.0 s; the turn then runs at 90 deg/s and the TCP still stands flat. At
    the fillet's travel speed the arc is slower than the axis: move 3 keeps its own time."""
    program, solution = solved(m2=200.0)
    timeline = playback.joint_timeline(program, MODEL, solution, dt_s=0.05)
    assert timeline.failure is None

    def span(index):
        rows = np.flatnonzero(timeline.move_index == index)
        return rows, float(timeline.time_s[rows[-1]] - timeline.time_s[rows[0] - 1])

    rows, duration = span(2)
    assert duration == pytest.approx(90.0 / 90.0, abs=1e-9)
    turn_rate = np.diff(timeline.external[rows[0] - 1:rows[-1] + 1, -1]) / np.diff(
        timeline.time_s[rows[0] - 1:rows[-1] + 1])
    np.testing.assert_allclose(turn_rate, -90.0, atol=1e-6)
    assert np.max(np.diff(timeline.time_s[rows[0] - 1:rows[-1] + 1])) <= 0.05 + 1e-9
    np.testing.assert_allclose(timeline.tcp_u[rows], np.tile(FLAT_TCP_U, (len(rows), 1)),
                               atol=1e-6)
    speed = program.paths[0].moves[3].speed_mm_s
    assert span(3)[1] == pytest.approx(ARC_MM / speed, rel=1e-9)


def test_timeline_without_external_axes_has_none():
    program, solution = solved()
    program.external = None
    timeline = playback.joint_timeline(program, MODEL, cfg.solve_program(program, MODEL),
                                       dt_s=1.0)
    assert timeline.external is None and timeline.base_u is None
    assert timeline.external_at(0.0) is None


def test_placement_rides_the_track_to_each_target():
    """The robot 1000 mm behind its drawn base along the track (-X): out of reach standing
    still, in reach riding. At t1 (flange (1200, -42.4, 1242.4) in {U}) the flange is 2200 mm
    ahead and 42.4 mm aside: the robot rides 2200 - sqrt(d^2 - 42.4^2) to keep it at its
    preferred distance d."""
    base = np.eye(4)
    base[0, 3] = -1000.0
    fixed = ef.positioner_weld_program()
    fixed_targets = placement.target_set(fixed, cfg.solve_program(fixed, MODEL, assign=False))
    assert placement.KIND_NAMES[placement.screen(MODEL, fixed_targets, base[None]).status[0]] \
        == "unreachable"
    program = ef.positioner_weld_program(track=True)
    targets = placement.target_set(program, cfg.solve_program(program, MODEL, assign=False))
    assert placement.screen(MODEL, targets, base[None]).status[0] == placement.OK
    travel = targets.travel
    np.testing.assert_allclose(travel.direction_r, [1.0, 0.0, 0.0], atol=1e-12)
    assert (travel.lower_mm, travel.upper_mm) == (0.0, 3000.0)
    moved = placement.program_at(program, base)
    aside = 60.0 / math.sqrt(2.0)
    expected = 2200.0 - math.sqrt(travel.preferred_mm ** 2 - aside ** 2)
    assert moved.paths[0].moves[0].target.external[0] == pytest.approx(expected, abs=1e-6)
    assert program.paths[0].moves[0].target.external[0] == 0.0       # the input unchanged
    assert placement_search.check_at(program, MODEL, base).kind == "ok"
    # The track is clipped to its travel: a base 3500 mm behind cannot ride far enough.
    base[0, 3] = -3500.0
    assert placement.screen(MODEL, targets, base[None]).status[0] == placement.UNREACHABLE
