"""How many moves a suggested risk area adds, and its default step (issue 14, item 8).

Hand counts follow generate's rules: outside an area a line is 1 move, an arc
1 circular move per half turn begun, a spline 1 move per sample, and a
junction where the orientation changes 1 reorientation move; inside an area
each segment of length L at step s is ceil(L / s) linear moves (eqs 8-13:
stations 0, s, 2s, ..., L) and nothing reorients. Every hand count is then
checked against generate itself: moves with the area minus moves without.
"""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from CadRobotWB.core import risk_suggestions as rs
from CadRobotWB.core.generate import RiskAreaSpec, generate
from CadRobotWB.core.geometry import Arc, Line, Polyline
from test_generate import DOWN, make_cell, make_path


def turned(deg):
    """DOWN turned `deg` degrees about Z of {U}: `deg` from DOWN."""
    return Rotation.from_euler("z", deg, degrees=True).as_matrix() @ DOWN


def two_lines():
    """An L of two 50 mm lines: 100 mm."""
    return [Line((0, 0, 0), (50, 0, 0), "E1"), Line((50, 0, 0), (50, 50, 0), "E2")]


def generated_moves(segments, R_u_t, areas=()):
    path = make_path(segments, R_u_t, risk_areas=list(areas))
    return len(generate(make_cell([path], T_u_b=np.eye(4))).moves())


def assert_generate_agrees(segments, R_u_t, first, last, step):
    without = generated_moves(segments, R_u_t)
    with_area = generated_moves(segments, R_u_t, [RiskAreaSpec("R", "Risk", first, last, step_mm=step)])
    assert with_area - without == rs.moves_added(segments, R_u_t, first, last, step)


def test_100_mm_area_at_1_mm_adds_97_moves():
    # With the area: 50 + 50 = 100 linear moves. Without: 2 lines + 1 reorientation = 3.
    segments, R = two_lines(), [DOWN, turned(45)]
    assert rs.moves_added(segments, R, 1, 2, 1.0) == 97
    assert_generate_agrees(segments, R, 1, 2, 1.0)


def test_one_marker_orientation_has_no_reorientation_to_save():
    segments, R = two_lines(), [DOWN, DOWN]          # one marker: one array, no reorientation
    assert rs.moves_added(segments, R, 1, 2, 1.0) == 98
    assert_generate_agrees(segments, R, 1, 2, 1.0)


def test_uneven_lengths_round_up_per_segment():
    # 30 mm and 20 mm at 7 mm: ceil(30/7) + ceil(20/7) = 5 + 3 = 8; minus 2 lines and 1 turn.
    segments = [Line((0, 0, 0), (30, 0, 0)), Line((30, 0, 0), (30, 20, 0))]
    R = [DOWN, turned(30)]
    assert rs.moves_added(segments, R, 1, 2, 7.0) == 5
    assert_generate_agrees(segments, R, 1, 2, 7.0)


def test_arc_and_spline_areas():
    # Line 10 mm, quarter arc r = 10 (15.708 mm, 1 circular move), spline of 3 samples (3 moves).
    arc = Arc([10, 10, 0], [0, 0, 1], (10, 0, 0), math.pi / 2, "E2")
    spline = Polyline([(20, 10, 0), (20, 14, 0), (21, 17, 0), (23, 19, 0)], "E3")
    segments = [Line((0, 0, 0), (10, 0, 0)), arc, spline]
    L3 = 4 + math.sqrt(10) + math.sqrt(8)
    R = [DOWN, turned(40), turned(80)]
    # At 2 mm: 5 + ceil(15.708/2) = 8 + ceil(9.99/2) = 5 -> 18; without 1 + 1 + 3 + 2 turns = 7.
    assert math.ceil(L3 / 2.0) == 5
    assert rs.moves_added(segments, R, 1, 3, 2.0) == 11
    assert_generate_agrees(segments, R, 1, 3, 2.0)
    assert_generate_agrees(segments, R, 2, 3, 0.7)


def test_a_full_circle_counts_two_circular_moves():
    circle = Arc([0, 10, 0], [0, 0, 1], (0, 0, 0), 2 * math.pi, "C")
    segments = [Line((-20, 0, 0), (0, 0, 0)), circle]
    R = [DOWN, turned(20)]
    assert rs.segment_moves(circle) == 2
    assert_generate_agrees(segments, R, 1, 2, 3.0)


def test_step_coarsens_speed_times_sample_time_to_2_degrees_per_move():
    # 45 deg over 100 mm at 1 mm: 0.45 deg per move <= 2: but 1 mm is far finer than needed,
    # so the rule coarsens: L * 2 / 45 = 4.444 -> 4.4 mm.
    segments, R = two_lines(), [DOWN, turned(45)]
    step, rule = rs.area_step_mm(segments, R, 1, 2, 1.0, 0.1)
    assert step == pytest.approx(4.4) and "2° turn per move" in rule
    # 24 moves (ceil(50/4.4) = 12 twice) minus 3: each turns the tool by 45 * 4.4 / 100 = 1.98 deg.
    assert rs.moves_added(segments, R, 1, 2, step) == 21
    assert_generate_agrees(segments, R, 1, 2, step)
    path = make_path(segments, R, risk_areas=[RiskAreaSpec("R", "Risk", 1, 2, step_mm=step)])
    risk = [m.target.T_b_t[:3, :3] for m in generate(make_cell([path], T_u_b=np.eye(4))).moves()
            if m.role == "risk"]
    turns = [np.degrees(np.arccos(np.clip((np.trace(a.T @ b) - 1) / 2, -1, 1)))
             for a, b in zip([DOWN] + risk[:-1], risk)]
    assert len(risk) == 24 and max(turns) == pytest.approx(1.98) and max(turns) <= 2.0
    # 90 deg over 100 mm needs 2.2 mm; a path stepping 3 mm (speed x time) keeps its 3 mm.
    assert rs.area_step_mm(segments, [DOWN, turned(90)], 1, 2, 1.0, 0.1)[0] == pytest.approx(2.2)
    assert rs.area_step_mm(segments, [DOWN, turned(90)], 1, 2, 3.0, 0.1) == (3.0, "speed × sample time")


def test_step_on_an_arc_stays_within_the_chord_tolerance():
    # Arc r = 100, tol 0.1: arc length 2 r acos(1 - 0.001) = 8.9453 mm -> 8.9 mm,
    # finer than the turn's 157.08 * 2 / 10 = 31.4 mm.
    arc = Arc([0, 100, 0], [0, 0, 1], (0, 0, 0), math.pi / 2, "A")
    segments, R = [Line((-10, 0, 0), (0, 0, 0)), arc], [DOWN, turned(10)]
    assert rs.chord_step_mm([arc], 0.1) == pytest.approx(200 * math.acos(0.999))
    step, rule = rs.area_step_mm(segments, R, 1, 2, 1.0, 0.1)
    assert step == pytest.approx(8.9) and rule.startswith("chord tolerance")
    chord_error = 100 * (1 - math.cos(step / 200))          # sagitta of one move's chord
    assert chord_error <= 0.1
    assert_generate_agrees(segments, R, 1, 2, step)


def test_spline_step_is_at_most_its_sample_spacing():
    spline = Polyline([(0, 0, 0), (3, 0, 0), (6, 1, 0), (9, 3, 0)], "S")
    assert rs.chord_step_mm([spline], 0.1) == pytest.approx(3.0)
