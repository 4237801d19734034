"""Cycle-time estimate (robots/motion/timing.py), against trapezoids worked by hand.

Trapezoid from rest to rest over d with top speed v and acceleration a:
t = 2 v / a + (d - v^2 / a) / v when d >= v^2 / a, else 2 sqrt(d / a).
"""

import json
import math

import numpy as np
import pytest

from CadRobotWB.core import program as ir
from CadRobotWB.robots.motion import configuration as cf, timing

from test_configuration import IRB2400, T_R_B, TOOL

Q0 = np.array([0, 10, 10, 0, 45, 0.0])


def tcp_in_b(q, shift_mm=(0, 0, 0)):
    """TCP pose in {B} of joints q, moved by shift_mm in {R}."""
    T_r_t = IRB2400.fk(np.asarray(q, float)) @ TOOL.T_f_t
    T_r_t[:3, 3] += shift_mm
    return np.linalg.inv(T_R_B) @ T_r_t


def program_of(moves):
    return ir.Program("P", "ABB_IRB2400", TOOL, {"B": ir.WorkFrame("B", T_R_B, np.eye(4))},
                      [ir.ProgramPath("A", "Path A", moves)])


def line_program(zone_mid_mm, length_mm=100.0, speed=50.0):
    """Joint move turning J1 by 90 deg from Q0, then two linear moves straight down."""
    q1 = Q0 + [90, 0, 0, 0, 0, 0]
    moves = [
        ir.Move(ir.JOINT, ir.Target("t1", tcp_in_b(q1)), 100, 0, "B", role=ir.ROLE_APPROACH),
        ir.Move(ir.LINEAR, ir.Target("t2", tcp_in_b(q1, (0, 0, -length_mm))), speed,
                zone_mid_mm, "B"),
        ir.Move(ir.LINEAR, ir.Target("t3", tcp_in_b(q1, (0, 0, -2 * length_mm))), speed, 0.0,
                "B"),
    ]
    return program_of(moves)


def test_trapezoids_by_hand():
    # 100 mm at 50 mm/s, 2000 mm/s^2: 0.025 s up, 0.625 mm; cruise 98.75 mm = 1.975 s.
    assert timing.trapezoid_time(100, 50, 2000) == pytest.approx(2.025)
    # 1 mm at 100 mm/s: triangular, peak sqrt(2000 * 1) = 44.72 mm/s, t = 2 * 44.72 / 2000.
    assert timing.trapezoid_time(1, 100, 2000) == pytest.approx(2 * math.sqrt(2000) / 2000)
    # Arriving at full speed, stopping at the end: 1.9875 s cruise + 0.025 s down.
    assert timing.trapezoid_time(100, 50, 2000, v_start=50) == pytest.approx(2.0125)
    assert timing.trapezoid_time(100, 50, 2000, v_start=50, v_end=50) == pytest.approx(2.0)
    # Peak sqrt(a d + (v0^2 + v1^2) / 2) = sqrt(2000 + 2000) with v0 = sqrt(4000), v1 = 0.
    v0 = math.sqrt(4000)
    assert timing.trapezoid_time(1, 100, 2000, v_start=v0) == pytest.approx(v0 / 2000)
    assert timing.trapezoid_time(0, 50, 2000) == 0.0


def test_trapezoid_agrees_with_a_simulation():
    """Step the motion with a small dt: accelerate while the stopping distance allows."""
    d, v, a, dt = 37.0, 80.0, 900.0, 1e-5
    x, s, t = 0.0, 0.0, 0.0
    while x < d:
        stopping = s * s / (2 * a)
        s = max(min(s + a * dt, v) if d - x > stopping else s - a * dt, a * dt)
        x += s * dt
        t += dt
    assert timing.trapezoid_time(d, v, a) == pytest.approx(t, rel=1e-3)


def test_joint_move_is_the_slowest_joint():
    speeds = np.array(IRB2400.spec.joint_speed_deg_s, float)        # 150 x3, 360, 360, 450
    accels = speeds / 0.25
    # J1 90 deg at 150 deg/s, 600 deg/s^2: 0.25 s up (18.75 deg) and down, 52.5 deg cruise.
    assert timing.joint_move_time(np.zeros(6), [90, 0, 0, 0, 0, 0], speeds, accels) == \
        (pytest.approx(0.85), 1)
    # J1 10 deg: triangular 2 sqrt(10 / 600) = 0.258 s; J4 180 deg: 0.5 + 90 / 360 = 0.75 s.
    t, joint = timing.joint_move_time(np.zeros(6), [10, 0, 0, 180, 0, 0], speeds, accels)
    assert (t, joint) == (pytest.approx(0.75), 4)


def test_blended_line_is_one_trapezoid():
    """Zone 10 at t2: the two 100 mm moves make one 200 mm trapezoid at 50 mm/s:
    0.025 + 0.625 mm ... split at the middle: 2.0125 s each; plus the 0.85 s joint move."""
    program = line_program(zone_mid_mm=10.0)
    solution = cf.solve_program(program, IRB2400, q_start_deg=Q0)
    np.testing.assert_allclose(solution.entries[0].joints_deg, Q0 + [90, 0, 0, 0, 0, 0],
                               atol=1e-6)
    result = timing.cycle_time(program, IRB2400, solution)
    times = [m["time_s"] for m in result["moves"]]
    assert times == [pytest.approx(0.85), pytest.approx(2.0125), pytest.approx(2.0125)]
    assert [m["limited_by"] for m in result["moves"]] == ["J1", "TCP speed", "TCP speed"]
    assert [(m["v_start_mm_s"], m["v_end_mm_s"]) for m in result["moves"][1:]] == [(0, 50),
                                                                                 (50, 0)]
    assert result["moves"][1]["length_mm"] == pytest.approx(100.0)
    assert result["total_s"] == pytest.approx(0.85 + 4.025)
    assert result["complete"]
    assert result["paths"] == [{"path": "Path A", "time_s": pytest.approx(4.875)}]
    assert result["assumptions"]["accel_mm_s2"] == 2000.0
    assert result["assumptions"]["joint_accel_deg_s2"] == [600, 600, 600, 1440, 1440, 1800]
    assert json.loads(json.dumps(result))["total_s"] == pytest.approx(4.875)


def test_fine_point_stops():
    program = line_program(zone_mid_mm=0.0)
    solution = cf.solve_program(program, IRB2400, q_start_deg=Q0)
    result = timing.cycle_time(program, IRB2400, solution)
    assert [m["time_s"] for m in result["moves"][1:]] == [pytest.approx(2.025)] * 2
    assert result["total_s"] == pytest.approx(0.85 + 4.05)


def test_short_blended_moves_never_reach_their_speed():
    """Two 1 mm moves at 100 mm/s blended: 2 mm triangular, peak sqrt(2000 * 2) = 63.2 mm/s
    at the junction (lowered from 100 by the look-ahead), total 2 * 63.2 / 2000 s."""
    program = line_program(zone_mid_mm=5.0, length_mm=1.0, speed=100.0)
    solution = cf.solve_program(program, IRB2400, q_start_deg=Q0)
    result = timing.cycle_time(program, IRB2400, solution)
    peak = math.sqrt(2000 * 2)
    assert result["moves"][1]["v_end_mm_s"] == pytest.approx(peak)
    assert [m["time_s"] for m in result["moves"][1:]] == [pytest.approx(peak / 2000)] * 2


def test_joint_speed_slows_a_fast_reorientation():
    """Turning the tool 170 deg about its axis (= axis 6) at 5000 deg/s would take
    2 sqrt(170 / 20000) = 0.184 s; J6 (450 deg/s) needs 170 / 450 = 0.378 s."""
    q1 = Q0 + [0, 0, 0, 0, 0, 170]
    moves = [ir.Move(ir.JOINT, ir.Target("a", tcp_in_b(Q0)), 100, 0, "B"),
             ir.Move(ir.LINEAR, ir.Target("b", tcp_in_b(q1)), 10, 0, "B",
                     role=ir.ROLE_REORIENT)]
    program = program_of(moves)
    solution = cf.solve_program(program, IRB2400, q_start_deg=Q0)
    fast = timing.cycle_time(program, IRB2400, solution, orientation_speed_deg_s=5000.0)
    move = fast["moves"][1]
    assert move["angle_deg"] == pytest.approx(170.0)
    assert move["length_mm"] == pytest.approx(0.0, abs=1e-9)
    assert (move["time_s"], move["limited_by"]) == (pytest.approx(170 / 450), "J6 speed")
    # At 500 deg/s the orientation is slower than J6: trapezoid 0.25 + 0.25 + 45 / 500 s.
    slow = timing.cycle_time(program, IRB2400, solution)
    assert (slow["moves"][1]["time_s"], slow["moves"][1]["limited_by"]) == \
        (pytest.approx(0.59), "orientation speed")
    # The start joints are the target's: the joint move takes no time.
    assert fast["moves"][0]["time_s"] == pytest.approx(0.0, abs=1e-6)


def test_unknown_start_and_unreachable_targets_leave_gaps():
    program = line_program(zone_mid_mm=0.0)
    solution = cf.solve_program(program, IRB2400)            # no start joints
    result = timing.cycle_time(program, IRB2400, solution)
    assert result["moves"][0]["time_s"] is None
    assert result["moves"][0]["limited_by"] == "unknown start joints"
    assert not result["complete"]
    assert result["total_s"] == pytest.approx(4.05)


def test_joint_acceleration_can_be_given():
    program = line_program(zone_mid_mm=0.0)
    solution = cf.solve_program(program, IRB2400, q_start_deg=Q0)
    # J1 90 deg at 150 deg/s with 300 deg/s^2: 0.5 s up (37.5 deg) and down, 15 deg cruise.
    result = timing.cycle_time(program, IRB2400, solution, joint_accel_deg_s2=300.0)
    assert result["moves"][0]["time_s"] == pytest.approx(1.1)


def collinear_program(zone_mm, count=50, step_mm=2.0, speed=50.0):
    """A joint move, then `count` linear moves of `step_mm` straight down, all with
    `zone_mm` but the last (the end of the path stops)."""
    q1 = Q0 + [90, 0, 0, 0, 0, 0]
    moves = [ir.Move(ir.JOINT, ir.Target("t0", tcp_in_b(q1)), 100, 0, "B",
                     role=ir.ROLE_APPROACH)]
    for k in range(1, count + 1):
        moves.append(ir.Move(ir.LINEAR, ir.Target("t%d" % k, tcp_in_b(q1, (0, 0, -step_mm * k))),
                             speed, zone_mm if k < count else 0.0, "B"))
    return program_of(moves)


def path_time(zone_mm, **kw):
    program = collinear_program(zone_mm, **kw)
    solution = cf.solve_program(program, IRB2400, q_start_deg=Q0)
    return sum(m["time_s"] for m in timing.cycle_time(program, IRB2400, solution)["moves"][1:])


def test_blended_short_moves_take_length_over_speed_and_fine_ones_stop_at_each():
    """50 moves of 2 mm at 50 mm/s. Blended: one 100 mm trapezoid, 100 / 50 + 50 / 2000
    = 2.025 s. Fine: 50 trapezoids of 2 mm, each 0.025 s up and down (0.625 mm each)
    and 0.75 mm at 50 mm/s: 50 * 0.065 = 3.25 s."""
    assert path_time(1.0) == pytest.approx(2.025)
    assert path_time(0.0) == pytest.approx(3.25)


def test_a_blended_right_angle_is_passed_at_the_speed_its_blend_arc_allows():
    """A 90 deg corner in a 0.2 mm zone: blend radius 0.2 / tan(45 deg) = 0.2 mm, so
    sqrt(2000 * 0.2) = 20 mm/s at the corner, not the programmed 50."""
    q1 = Q0 + [90, 0, 0, 0, 0, 0]
    moves = [ir.Move(ir.JOINT, ir.Target("t0", tcp_in_b(q1)), 100, 0, "B", role=ir.ROLE_APPROACH),
             ir.Move(ir.LINEAR, ir.Target("t1", tcp_in_b(q1, (0, 0, -50))), 50, 0.2, "B"),
             ir.Move(ir.LINEAR, ir.Target("t2", tcp_in_b(q1, (0, 50, -50))), 50, 0.0, "B")]
    program = program_of(moves)
    result = timing.cycle_time(program, IRB2400, cf.solve_program(program, IRB2400, q_start_deg=Q0))
    assert result["moves"][1]["v_end_mm_s"] == pytest.approx(20.0)
    assert result["moves"][2]["v_start_mm_s"] == pytest.approx(20.0)
