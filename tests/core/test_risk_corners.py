"""Orientation on arcs, risk areas through their markers, corner spans, the corner where a
loop closes, and corner stops (issue 20, items 1 and 5).

Expected orientations are derived by hand: every marker here is DOWN turned about Z of
{U} (``rz(deg)``), so an orientation along an area is rz of an angle that grows linearly
with arc length between keyframes, and a tool turning with an arc about +Z is rz of the
swept angle. {B} = {U} (T_u_b = I), so targets read directly in {U}.
"""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from CadRobotWB.core import program as ir
from CadRobotWB.core import risk_suggestions as rs
from CadRobotWB.core.generate import CORNER_TURN_DEG_S, RiskAreaSpec, generate
from CadRobotWB.core.geometry import Arc, Line
from CadRobotWB.core.segment_orientation import CONSTANT, TURNS_WITH_ARC
from CadRobotWB.errors import RiskAreaError
from test_generate import DOWN, make_cell, make_path

TILTED = Rotation.from_euler("x", 135, degrees=True).as_matrix()   # Z leans 45 deg off vertical


def rz(deg, R=DOWN):
    return Rotation.from_euler("z", deg, degrees=True).as_matrix() @ R


def angle_deg(R1, R2):
    return math.degrees(Rotation.from_matrix(R1.T @ R2).magnitude())


def moves_of(path):
    return generate(make_cell([path], T_u_b=np.eye(4))).paths[0].moves


def body(moves):
    return [m for m in moves if m.role in (ir.ROLE_PATH, ir.ROLE_RISK, ir.ROLE_REORIENT)]


# --- the tool turns with an arc ------------------------------------------------------------

def line_and_quarter_arc():
    """Line (10, -20) -> (10, 0) along +y, then a quarter arc r = 10 about +Z to (0, 10): tangent."""
    arc = Arc((0, 0, 0), (0, 0, 1), (10, 0, 0), math.pi / 2, "Arc")
    return [Line((10, -20, 0), (10, 0, 0), "Line"), arc], arc


def test_a_marker_on_an_arc_sets_the_tool_relative_to_the_arc():
    segments, arc = line_and_quarter_arc()
    # The arc's marker at mid-arc (45 deg swept); the line's marker is the arc's start pose.
    R_mid = rz(0, TILTED)
    path = make_path(segments, [rz(-45, TILTED), R_mid], marker_s_mm=[10.0, arc.length / 2],
                     tool_on_arcs=TURNS_WITH_ARC)
    moves = body(moves_of(path))
    assert [m.kind for m in moves] == [ir.LINEAR, ir.CIRCULAR]      # tangent: nothing to reorient
    circular = moves[1]
    assert angle_deg(circular.via.T_b_t[:3, :3], R_mid) < 1e-9
    assert angle_deg(circular.target.T_b_t[:3, :3], rz(45, TILTED)) < 1e-9
    # Constant: the marker's orientation on the whole arc, and a reorientation at the junction.
    constant = body(moves_of(make_path(segments, [rz(-45, TILTED), R_mid], marker_s_mm=[10.0, 1.0],
                                       tool_on_arcs=CONSTANT)))
    assert [m.role for m in constant] == [ir.ROLE_PATH, ir.ROLE_REORIENT, ir.ROLE_PATH]
    assert angle_deg(constant[2].target.T_b_t[:3, :3], R_mid) < 1e-9


def test_an_inherited_arc_carries_on_from_the_segment_before():
    segments, arc = line_and_quarter_arc()
    R = rz(-45, TILTED)
    path = make_path(segments + [Line((0, 10, 0), (-20, 10, 0), "After")], [R, R, R],
                     marker_s_mm=[0.0, None, None], tool_on_arcs=TURNS_WITH_ARC)
    moves = body(moves_of(path))
    assert [m.kind for m in moves] == [ir.LINEAR, ir.CIRCULAR, ir.LINEAR]
    # Turned by the 90 deg swept; the line after keeps that.
    assert angle_deg(moves[1].target.T_b_t[:3, :3], rz(45, TILTED)) < 1e-9
    assert angle_deg(moves[2].target.T_b_t[:3, :3], rz(45, TILTED)) < 1e-9


def test_a_tool_along_the_arc_axis_does_not_spin():
    circle = Arc((0, 0, 0), (0, 0, 1), (25, 0, 0), 2 * math.pi, "Circle")
    moves = body(moves_of(make_path([circle], [DOWN], tool_on_arcs=TURNS_WITH_ARC)))
    assert [m.kind for m in moves] == [ir.CIRCULAR, ir.CIRCULAR]     # two half circles, as before
    assert all(angle_deg(m.target.T_b_t[:3, :3], DOWN) < 1e-12 for m in moves)


# --- risk areas through their markers -------------------------------------------------------

def three_lines():
    return [Line((0, 0, 0), (50, 0, 0), "A"), Line((50, 0, 0), (100, 0, 0), "B"),
            Line((100, 0, 0), (150, 0, 0), "C")]


def test_an_area_passes_every_marker_and_never_the_short_way_past_one():
    # Markers: 0 deg on A, 170 deg at B's middle (s = 75 mm), 340 deg on C. First against
    # last is 20 deg the short way (-20 deg); through the markers it is 170 + 170 = 340 deg.
    R = [rz(0), rz(170), rz(340)]
    area = RiskAreaSpec("R", "Risk", 1, 3, step_mm=5.0)
    path = make_path(three_lines(), R, marker_s_mm=[0.0, 25.0, 0.0], risk_areas=[area])
    moves = [m for m in moves_of(path) if m.role == ir.ROLE_RISK]
    assert len(moves) == 30
    for m in moves:
        s = m.target.T_b_t[0, 3]
        expected = 170.0 * s / 75.0 if s <= 75.0 else 170.0 + 170.0 * (s - 75.0) / 75.0
        assert angle_deg(m.target.T_b_t[:3, :3], rz(expected)) < 1e-9, s
    assert rs.area_turn_deg(three_lines(), R, 1, 3, marker_s_mm=[0.0, 25.0, 0.0]) == pytest.approx(340.0)


def test_an_area_between_two_markers_is_exactly_the_papers_slerp():
    """No marker strictly inside: the same targets, bit for bit, as without marker positions
    (eqs 14-15 from the first segment's orientation to the last's)."""
    segments = three_lines()[:2]
    area = RiskAreaSpec("R", "Risk", 1, 2, step_mm=3.0)
    known = moves_of(make_path(segments, [rz(0), rz(90)], marker_s_mm=[25.0, 25.0], risk_areas=[area]))
    unknown = moves_of(make_path(segments, [rz(0), rz(90)], risk_areas=[area]))
    assert len(known) == len(unknown)
    for a, b in zip(known, unknown):
        assert np.array_equal(a.target.T_b_t, b.target.T_b_t) and a.comment == b.comment


# --- corner spans ---------------------------------------------------------------------------

def test_a_corner_area_covers_only_its_span_on_each_side():
    segments = [Line((0, 0, 0), (50, 0, 0), "A"), Line((50, 0, 0), (50, 50, 0), "B")]
    area = RiskAreaSpec("R", "Corner", 1, 2, step_mm=1.0, corner_span_mm=5.0)
    moves = body(moves_of(make_path(segments, [rz(0), rz(90)], risk_areas=[area])))
    assert [m.role for m in moves] == [ir.ROLE_PATH] + [ir.ROLE_RISK] * 10 + [ir.ROLE_PATH]
    assert np.allclose(moves[0].target.T_b_t[:3, 3], (45, 0, 0))
    assert angle_deg(moves[0].target.T_b_t[:3, :3], rz(0)) < 1e-12     # the leg keeps its marker's
    corner = moves[5]                                                  # 5 mm on: the corner point
    assert np.allclose(corner.target.T_b_t[:3, 3], (50, 0, 0)) and angle_deg(corner.target.T_b_t[:3, :3], rz(45)) < 1e-9
    assert angle_deg(moves[10].target.T_b_t[:3, :3], rz(90)) < 1e-9 and np.allclose(moves[10].target.T_b_t[:3, 3], (50, 5, 0))
    assert angle_deg(moves[11].target.T_b_t[:3, :3], rz(90)) < 1e-12
    added = rs.moves_added(segments, [rz(0), rz(90)], 1, 2, 1.0, corner_span_mm=5.0)
    assert added == 12 - 3                                            # 2 lines + 1 reorientation before
    assert rs.corner_span_mm([100.0, 4.0]) == 1.0 and rs.corner_span_mm([50.0, 50.0]) == 5.0


def test_a_corner_is_driven_no_faster_than_the_tool_may_turn():
    segments = [Line((0, 0, 0), (50, 0, 0), "A"), Line((50, 0, 0), (50, 50, 0), "B")]
    area = RiskAreaSpec("R", "Corner", 1, 2, step_mm=1.0, corner_span_mm=5.0)
    moves = body(moves_of(make_path(segments, [rz(0), rz(90)], risk_areas=[area])))
    # 90 deg over 10 mm at 40 deg/s: 2.25 s, 4.44 mm/s, written in 0.1 mm/s steps (down)
    assert CORNER_TURN_DEG_S == 40.0
    assert [m.speed_mm_s for m in moves] == [10.0] + [4.4] * 10 + [10.0]
    wide = RiskAreaSpec("R", "Corner", 1, 2, step_mm=1.0, corner_span_mm=20.0)   # 40 mm: 17.7 mm/s
    moves = body(moves_of(make_path(segments, [rz(0), rz(90)], risk_areas=[wide])))
    assert {m.speed_mm_s for m in moves} == {10.0}                   # the path's speed is lower


def test_stop_and_reorient_marks_the_corner_stop():
    segments = [Line((0, 0, 0), (50, 0, 0), "A"), Line((50, 0, 0), (50, 50, 0), "B")]
    area = RiskAreaSpec("R", "Corner", 1, 2, corner_span_mm=5.0, at_corner="Stop and reorient")
    moves = body(moves_of(make_path(segments, [rz(0), rz(90)], risk_areas=[area])))
    assert [m.role for m in moves] == [ir.ROLE_PATH, ir.ROLE_REORIENT, ir.ROLE_PATH]
    assert moves[0].zone_mm == 0.0 and moves[1].zone_mm == 0.0
    assert moves[1].comment.startswith("corner stop") and np.allclose(moves[1].target.T_b_t[:3, 3], (50, 0, 0))


# --- the corner where a closed loop closes ---------------------------------------------------

def square_loop():
    corners = [(0, 0, 0), (40, 0, 0), (40, 40, 0), (0, 40, 0), (0, 0, 0)]
    return [Line(a, b, "E%d" % k) for k, (a, b) in enumerate(zip(corners, corners[1:]), 1)]


def test_the_loop_ends_as_it_started():
    R = [rz(0), rz(90), rz(180), rz(270)]
    area = RiskAreaSpec("R", "Heel", 4, 1)
    moves = moves_of(make_path(square_loop(), R, risk_areas=[area], closed=True))
    pivot = [m for m in moves if m.role == ir.ROLE_RISK]
    assert len(pivot) == 45                                          # 90 deg at 2 deg per move
    assert all(np.allclose(m.target.T_b_t[:3, 3], (0, 0, 0)) for m in pivot)
    assert angle_deg(pivot[0].target.T_b_t[:3, :3], rz(272)) < 1e-9
    entry = next(m for m in moves if m.role == ir.ROLE_ENTRY)
    assert angle_deg(pivot[-1].target.T_b_t[:3, :3], entry.target.T_b_t[:3, :3]) < 1e-9
    assert rs.moves_added(square_loop(), R, 4, 1, 1.0, closed=True, at_corner="Weld through") == 45
    stop = RiskAreaSpec("R", "Heel", 4, 1, at_corner="Stop and reorient")
    moves = body(moves_of(make_path(square_loop(), R, risk_areas=[stop], closed=True)))
    assert moves[-1].role == ir.ROLE_REORIENT and moves[-1].comment.startswith("corner stop")
    with pytest.raises(RiskAreaError, match="4-1: the corner where the loop closes"):
        generate(make_cell([make_path(square_loop(), R, risk_areas=[RiskAreaSpec("R", "Heel", 4, 2)],
                                      closed=True)], T_u_b=np.eye(4)))
    with pytest.raises(RiskAreaError, match="segments 1-4"):
        generate(make_cell([make_path(square_loop(), R, risk_areas=[area], closed=False)], T_u_b=np.eye(4)))


def test_a_loop_welded_through_its_closing_corner_overlaps_its_start():
    R = [rz(0), rz(90), rz(180), rz(270)]
    area = RiskAreaSpec("R", "Heel", 4, 1, step_mm=1.0, corner_span_mm=5.0)
    moves = moves_of(make_path(square_loop(), R, risk_areas=[area], closed=True))
    risk = [m for m in moves if m.role == ir.ROLE_RISK]
    points = [m.target.T_b_t[:3, 3] for m in risk]
    # the last 5 mm of the fourth leg (down x = 0 to the heel), then 5 mm over the first leg again
    assert np.allclose(points, [(0, 4 - k, 0) for k in range(5)] + [(k, 0, 0) for k in range(1, 6)])
    assert angle_deg(risk[4].target.T_b_t[:3, :3], rz(315)) < 1e-9        # half way round at the heel
    entry = next(m for m in moves if m.role == ir.ROLE_ENTRY)
    assert angle_deg(risk[-1].target.T_b_t[:3, :3], entry.target.T_b_t[:3, :3]) < 1e-9
    assert risk[-1].zone_mm == 0.0 and all(m.zone_mm > 0.0 for m in risk[:-1])
    last_leg = [m for m in moves if m.role == ir.ROLE_PATH][-1]
    assert np.allclose(last_leg.target.T_b_t[:3, 3], (0, 5, 0))          # the leg stops short by the span
    retract = moves[-1]
    assert retract.role == ir.ROLE_RETRACT and np.allclose(retract.target.T_b_t[:3, 3], (5, 0, 30))
    assert rs.moves_added(square_loop(), R, 4, 1, 1.0, 5.0, closed=True) == 10
    overlapping = RiskAreaSpec("S", "Start", 1, 2, step_mm=1.0, corner_span_mm=36.0)
    with pytest.raises(RiskAreaError, match="'Start' .*'Heel' .*overlap"):
        moves_of(make_path(square_loop(), R, risk_areas=[overlapping, area], closed=True))


def test_moves_added_is_what_generate_adds_on_a_turning_path():
    """Line, quarter arc (inherited: it turns from the line's orientation), line turned 30 deg
    at its junction: a corner area of 3 mm there counts exactly what generate writes."""
    segments, arc = line_and_quarter_arc()
    segments = segments + [Line((0, 10, 0), (-20, 10, 0), "After")]
    R = rz(-45, TILTED)
    R_u_t, marker_s = [R, R, rz(75, TILTED)], [0.0, None, 10.0]

    def count(areas):
        return len(moves_of(make_path(segments, R_u_t, marker_s_mm=marker_s, tool_on_arcs=TURNS_WITH_ARC,
                                      risk_areas=areas)))

    area = RiskAreaSpec("R", "Corner", 2, 3, step_mm=0.5, corner_span_mm=3.0)
    added = rs.moves_added(segments, R_u_t, 2, 3, 0.5, 3.0, marker_s_mm=marker_s, tool_on_arcs=TURNS_WITH_ARC)
    # The arc to 3 mm before its end and the line from 3 mm stay one move each, 6 + 6 risk moves
    # between: 14 moves for the arc, the reorientation and the line before.
    assert added == count([area]) - count([]) == 14 - 3
    assert rs.area_turn_deg(segments, R_u_t, 2, 3, 3.0, marker_s, TURNS_WITH_ARC) == pytest.approx(
        30.0 + math.degrees(3.0 / 10.0))    # 30 at the junction and the arc's last 3 mm (0.3 rad)
