"""Tests of core/zones.py: the zones of a path's interior targets.

Expected zones are derived by hand from the rule in the module's docstring:
half the shorter neighbouring move, the corner cut r tan(theta / 4) within
the tolerance, rounded down to 0.1 mm.
"""

import math

import numpy as np

from CadRobotWB.core import zones
from CadRobotWB.core.generate import CellSpec, FrameSpec, PathSpec, RiskAreaSpec, generate
from CadRobotWB.core.geometry import Arc, Line
from CadRobotWB.core.program import (CIRCULAR, JOINT, LINEAR, ROLE_APPROACH, ROLE_PATH,
                                     ROLE_REORIENT, ROLE_RISK, Move, Target, ToolData)

DOWN = np.diag([1.0, -1.0, -1.0])


def move(p, kind=LINEAR, role=ROLE_PATH, zone=zones.AUTOMATIC, via=None):
    T = np.eye(4)
    T[:3, 3] = p
    via_target = None
    if via is not None:
        T_via = np.eye(4)
        T_via[:3, 3] = via
        via_target = Target("v", T_via)
    return Move(kind=kind, target=Target("t", T), speed_mm_s=10.0, zone_mm=zone, frame="F",
                via=via_target, role=role)


def zones_of(moves, tolerance_mm=0.1):
    return [m.zone_mm for m in zones.limit_zones(moves, tolerance_mm)]


def test_collinear_points_blend_by_half_their_spacing():
    # 2.1 mm spacing: half is 1.05 mm, rounded down to 1.0; the cut is 0 on a line.
    moves = [move((0, 0, 0), JOINT, ROLE_APPROACH, zone=0.0)]
    moves += [move((2.1 * k, 0, 0)) for k in range(1, 6)]
    assert zones_of(moves) == [0.0, 1.0, 1.0, 1.0, 1.0, 0.0]


def test_a_right_angle_is_cut_by_at_most_the_tolerance():
    # theta = 90 deg: r tan(22.5 deg) <= 0.1 mm gives r <= 0.2414, i.e. 0.2 mm.
    moves = [move((0, 0, 0), JOINT, ROLE_APPROACH, zone=0.0), move((10, 0, 0)), move((10, 10, 0))]
    assert zones_of(moves) == [0.0, 0.2, 0.0]
    moves = [move((0, 0, 0), JOINT, ROLE_APPROACH, zone=0.0), move((10, 0, 0)), move((10, 10, 0))]
    assert zones_of(moves, tolerance_mm=1.0) == [0.0, 2.4, 0.0]      # 1 / tan(22.5 deg) = 2.414


def test_a_line_into_a_tangent_arc_counts_the_arc_turning_inside_the_zone():
    # Line to (0, 0), then a quarter arc of R = 12 mm tangent to it. theta(r) = r / 12:
    # 2.1 tan(2.1 / 48) = 0.092 <= 0.1 < 2.2 tan(2.2 / 48) = 0.101, so 2.1 mm.
    c = 12 * math.sqrt(0.5)
    arc_end, arc_via = (12.0, 12.0, 0.0), (c, 12.0 - c, 0.0)        # centre (0, 12)
    moves = [move((-30, 0, 0), JOINT, ROLE_APPROACH, zone=0.0), move((0, 0, 0)),
             move(arc_end, CIRCULAR, via=arc_via), move((12, 40, 0))]
    result = zones_of(moves)
    assert result[1] == 2.1 and result[-1] == 0.0
    assert 2.1 * math.tan(2.1 / 48) <= 0.1 < 2.2 * math.tan(2.2 / 48)


def test_exact_stops_and_given_zones_are_kept_within_half_the_moves():
    moves = [move((0, 0, 0), JOINT, ROLE_APPROACH, zone=0.0), move((4, 0, 0), zone=5.0),
             move((8, 0, 0), zone=0.0), move((8, 0, 0), role=ROLE_REORIENT, zone=0.0),
             move((20, 0, 0), zone=5.0), move((40, 0, 0), zone=5.0), move((41, 0, 0), zone=5.0)]
    # 5 mm asked: 2.0 (half of 4), the writer's stop, the reorientation, 5 (12 | 20 mm
    # moves: cap 6), 0.5 (half of 1), the path's end.
    assert zones_of(moves) == [0.0, 2.0, 0.0, 0.0, 5.0, 0.5, 0.0]


def test_generate_blends_a_risk_area_and_stops_at_its_ends():
    R2 = np.array([[0, 1, 0], [1, 0, 0], [0, 0, -1]], float)
    path = PathSpec(name="Weld", label="Weld", segments=[Line((0, 0, 0), (21, 0, 0)),
                    Line((21, 0, 0), (42, 0, 0))], R_u_t=[DOWN, R2], frame="F",
                    speed_mm_s=10.0, sample_time_s=0.21,
                    risk_areas=[RiskAreaSpec("Risk", "Risk", 1, 2)])
    assert path.zone_mm is None                                        # automatic by default
    cell = CellSpec(name="C", label="C", robot="ABB_IRB2400", T_u_r=np.eye(4),
                    tool=ToolData(name="torch", T_f_t=np.eye(4)),
                    frames={"F": FrameSpec(name="F", label="F", T_u_b=np.eye(4))}, paths=[path])
    moves = generate(cell).paths[0].moves
    risk = [m for m in moves if m.role == ROLE_RISK]
    assert len(risk) == 20                                             # 42 mm at 2.1 mm
    assert [m.zone_mm for m in risk] == [1.0] * 19 + [0.0]
    assert all(m.zone_mm == 0.0 for m in moves if m.role != ROLE_RISK)


def test_round_down_zone_never_rounds_up():
    assert zones.round_down_zone(0.09999) == 0.09        # below 0.1 mm: to 0.01 mm
    assert zones.round_down_zone(0.0099) == 0.0          # below 0.01 mm: an exact stop
    assert zones.round_down_zone(0.022) == 0.02          # a corner area's moves 0.044 mm apart
    assert zones.round_down_zone(0.3) == 0.3
    assert zones.round_down_zone(1.05) == 1.0


def test_a_given_zone_that_fits_is_kept_as_it_is():
    moves = [move((0, 0, 0), JOINT, ROLE_APPROACH, zone=0.0), move((10, 0, 0), zone=0.25),
             move((10, 10, 0), zone=0.25), move((10, 11.05, 0), zone=0.25)]
    # Not rounded to 0.2: 0.25 is below both caps (5 mm, then half of 1.05 mm = 0.525);
    # a given zone is not bounded by the tolerance (the automatic one here would be 0.2).
    assert zones_of(moves) == [0.0, 0.25, 0.25, 0.0]
