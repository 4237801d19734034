"""A torch round a concave arc leans away from the walls (issue 20, item 5).

The corner is an inside fillet like the angle cleat's root: walls y <= 0 and
x <= 0 on a floor z = 0, a line along -x at y = 0, an R10 quarter arc about
(10, 10) (clockwise seen from +z: axis -z) and a line along +y at x = 0. Every
marker is a fillet torch built here by hand: its axis on the bisector of the
floor and the wall (45 deg work angle), tilted by the travel angle tau towards
the travel direction. Expected numbers come from that construction:

* the lean gamma: the tool axis in the floor plane is sin(tau) along the travel
  and cos(tau) / sqrt(2) towards the wall, so tan(gamma) = sqrt(2) tan(tau)
  (14.002 deg at tau = 10 deg);
* over the arc the tool turns about its axis by 90 - 2 gamma deg (61.996 deg),
  its travel angle going +tau, 0, -tau at the start, middle and end;
* at the middle the axis lies in the plane normal to the travel, elevated
  atan(cos(tau) / sqrt(2) / sqrt(sin^2 tau + cos^2 tau / 2)) = 44.136 deg,
  0.864 deg above the bisector.
"""

import math

import numpy as np
import pytest

from CadRobotWB.core import program as ir
from CadRobotWB.core import risk_suggestions as rs
from CadRobotWB.core.generate import RiskAreaSpec, generate
from CadRobotWB.core.geometry import Arc, Line
from CadRobotWB.core.interpolation import interpolate_orientations
from CadRobotWB.core.rotations import matrix_from_quaternion, quaternion_from_matrix, rotation_angle_between
from CadRobotWB.core.segment_orientation import CONSTANT, TURNS_WITH_ARC, lead_length_mm, segment_orientations
from test_generate import make_cell, make_path

UP = np.array([0.0, 0.0, 1.0])
ROOT_CENTRE = np.array([10.0, 10.0, 0.0])
ARC_LENGTH = 10.0 * math.pi / 2


def torch(travel, wall_normal, tau_deg):
    """R_u_t of a fillet torch: Z on the bisector of the floor and the wall, into the joint,
    tilted by `tau_deg` towards `travel`; X along the travel (as tilted), Y = Z x X."""
    d, n = np.asarray(travel, float), np.asarray(wall_normal, float)
    z0 = -(n + UP) / np.linalg.norm(n + UP)
    tau = math.radians(tau_deg)
    z = math.cos(tau) * z0 + math.sin(tau) * d
    x = math.cos(tau) * d - math.sin(tau) * z0
    return np.column_stack([x, np.cross(z, x), z])


def inside_corner(tau_deg, outside=False):
    """(segments, R_u_t, marker_s_mm): line, concave R10 quarter arc, 80 mm line, one marker
    at each segment's middle. `outside`: the torch on the other side of the same seam (walls
    y >= 0 and x >= 0): the arc is then convex."""
    sign = -1.0 if outside else 1.0
    arc = Arc(ROOT_CENTRE, (0, 0, -1), (10, 0, 0), math.pi / 2, "Root")
    segments = [Line((50, 0, 0), (10, 0, 0), "Leg x"), arc, Line((0, 10, 0), (0, 90, 0), "Leg y")]
    diagonal = np.array([1.0, 1.0, 0.0]) / math.sqrt(2)
    R_u_t = [torch((-1, 0, 0), sign * np.array([0.0, 1.0, 0.0]), tau_deg),
             torch(np.array([-1.0, 1.0, 0.0]) / math.sqrt(2), sign * diagonal, tau_deg),
             torch((0, 1, 0), sign * np.array([1.0, 0.0, 0.0]), tau_deg)]
    return segments, R_u_t, [20.0, ARC_LENGTH / 2, 40.0]


def laws_of(tau_deg, **kw):
    segments, R_u_t, marker_s = inside_corner(tau_deg, **kw)
    return segments, segment_orientations(segments, R_u_t, marker_s, TURNS_WITH_ARC)


def travel_deg(R, tangent):
    return math.degrees(math.asin(np.clip(R[:, 2] @ tangent, -1.0, 1.0)))


def deg(R1, R2):
    return math.degrees(rotation_angle_between(R1, R2))


def test_on_a_concave_arc_the_push_becomes_a_drag_and_the_tool_turns_less():
    segments, laws = laws_of(10.0)
    arc, law = segments[1], laws[1]
    gamma = math.degrees(math.atan(math.sqrt(2) * math.tan(math.radians(10.0))))
    assert gamma == pytest.approx(14.002, abs=1e-3)
    assert deg(law.start, law.end) == pytest.approx(90.0 - 2 * gamma, abs=1e-9)
    assert [travel_deg(law.at(s), arc.tangent_at(s)) for s in (0.0, ARC_LENGTH / 2, ARC_LENGTH)] == \
        pytest.approx([10.0, 0.0, -10.0], abs=1e-9)
    # Work angle: exact at the ends (the lean mirrored), 0.864 deg more upright at the middle.
    z_mid = law.at(ARC_LENGTH / 2)[:, 2]
    assert math.degrees(math.asin(-z_mid[2])) == pytest.approx(44.136, abs=1e-3)
    assert deg(law.start, laws[0].R_ref) < 1e-9       # the leg's own push: no lead before
    assert laws[0].leads == () and laws[0].at(40.0) is laws[0].R_ref


def test_the_lean_is_one_turn_about_the_arc_axis_so_a_circular_move_reproduces_it():
    _segments, laws = laws_of(10.0)
    law = laws[1]
    q = interpolate_orientations(quaternion_from_matrix(law.start), quaternion_from_matrix(law.end),
                                 np.array([1 / 3, 0.5, 0.8]))
    expected = law.at_many(np.array([1 / 3, 0.5, 0.8]) * ARC_LENGTH)
    assert max(deg(a, b) for a, b in zip(matrix_from_quaternion(q), expected)) < 1e-9


def test_the_next_leg_takes_its_push_back_over_the_lead_continuously():
    segments, laws = laws_of(10.0)
    leg, law = segments[2], laws[2]
    lead = lead_length_mm(ARC_LENGTH, leg.length)
    assert lead == pytest.approx(2 * ARC_LENGTH) and law.breaks == [pytest.approx(2 * ARC_LENGTH)]
    assert deg(laws[1].end, law.start) < 1e-9
    assert [travel_deg(law.at(s), leg.tangent_at(s)) for s in (0.0, lead / 2, lead)] == \
        pytest.approx([-10.0, 0.0, 10.0], abs=1e-9)
    assert law.at(lead + 1.0) is law.R_ref
    # One turn about the arc's axis over the lead: a linear move's slerp is the law.
    q = interpolate_orientations(quaternion_from_matrix(law.start), quaternion_from_matrix(law.at(lead)),
                                 np.array([0.25]))
    assert deg(matrix_from_quaternion(q)[0], law.at(lead / 4)) < 1e-9


def test_generate_writes_the_lean_without_stopping_to_reorient():
    segments, R_u_t, marker_s = inside_corner(10.0)
    path = make_path(segments, R_u_t, marker_s_mm=marker_s, tool_on_arcs=TURNS_WITH_ARC)
    moves = [m for m in generate(make_cell([path], T_u_b=np.eye(4))).paths[0].moves
             if m.role in (ir.ROLE_PATH, ir.ROLE_REORIENT)]
    assert [(m.kind, m.segment) for m in moves] == [(ir.LINEAR, 1), (ir.CIRCULAR, 2), (ir.LINEAR, 3),
                                                    (ir.LINEAR, 3)]
    root, lead_end = moves[1], moves[2]
    assert travel_deg(root.via.T_b_t[:3, :3], np.array([-1.0, 1.0, 0.0]) / math.sqrt(2)) == pytest.approx(0.0, abs=1e-9)
    assert travel_deg(root.target.T_b_t[:3, :3], np.array([0.0, 1.0, 0.0])) == pytest.approx(-10.0, abs=1e-9)
    assert np.allclose(lead_end.target.T_b_t[:3, 3], (0.0, 10.0 + 2 * ARC_LENGTH, 0.0), atol=1e-9)
    assert deg(lead_end.target.T_b_t[:3, :3], R_u_t[2]) < 1e-9
    assert rs.suggest(rs.junction_turns_deg(segment_orientations(segments, R_u_t, marker_s, TURNS_WITH_ARC)),
                      1.0) == []


def test_a_dragging_torch_pushes_at_the_arcs_start_after_a_lead_on_the_leg_before():
    segments, laws = laws_of(-10.0)
    arc = segments[1]
    assert [travel_deg(laws[1].at(s), arc.tangent_at(s)) for s in (0.0, ARC_LENGTH)] == \
        pytest.approx([10.0, -10.0], abs=1e-9)
    # The leg before is 40 mm: its lead is its last half, from its drag to the arc's push.
    assert laws[0].breaks == [pytest.approx(20.0)] and laws[0].at(19.0) is laws[0].R_ref
    assert travel_deg(laws[0].end, np.array([-1.0, 0.0, 0.0])) == pytest.approx(10.0, abs=1e-9)
    assert deg(laws[0].end, laws[1].start) < 1e-9 and laws[2].leads == ()


def test_convex_arcs_constant_tools_and_no_travel_angle_are_left_as_they_were():
    segments, laws = laws_of(10.0, outside=True)
    assert laws[1].rate == 1.0 and deg(laws[1].start, laws[1].end) == pytest.approx(90.0, abs=1e-9)
    assert all(law.leads == () for law in laws)
    segments, R_u_t, marker_s = inside_corner(10.0)
    constant = segment_orientations(segments, R_u_t, marker_s, CONSTANT)
    assert all(law.R_ref is R and law.arc is None and law.leads == () for law, R in zip(constant, R_u_t))
    _segments, upright = laws_of(0.0)
    assert upright[1].rate == 1.0 and all(law.leads == () for law in upright)


def test_a_short_concave_arc_holds_the_tool_and_splits_the_lean():
    """A 20 deg concave arc at a 10 deg push (lean 14.0 deg): the lean is capped at half the
    sweep, so the tool holds its orientation over the arc (it never turns against it)."""
    sweep = math.radians(20.0)
    arc = Arc(ROOT_CENTRE, (0, 0, -1), (10, 0, 0), sweep, "Short")
    after = arc.tangent_at(arc.length)
    end = arc.end
    segments = [Line((50, 0, 0), (10, 0, 0), "Before"), arc, Line(end, end + 40.0 * after, "After")]
    wall_end = (ROOT_CENTRE - end) / 10.0
    R_u_t = [torch((-1, 0, 0), (0, 1, 0), 10.0), None, torch(after, wall_end, 10.0)]
    R_u_t[1] = R_u_t[0]                                 # the arc inherits the leg's marker
    laws = segment_orientations(segments, R_u_t, [20.0, None, 20.0], TURNS_WITH_ARC)
    assert laws[1].rate == pytest.approx(0.0, abs=1e-12) and deg(laws[1].start, laws[1].end) < 1e-9
    assert deg(laws[0].end, laws[1].start) < 1e-9 and deg(laws[1].end, laws[2].start) < 1e-9
    assert travel_deg(laws[1].start, np.array([-1.0, 0.0, 0.0])) < 10.0


def test_a_closed_loop_of_one_concave_circle_keeps_turning_with_it():
    circle = Arc(ROOT_CENTRE, (0, 0, -1), (10, 0, 0), 2 * math.pi, "Bore")
    R = torch((-1, 0, 0), (0, 1, 0), 10.0)
    law, = segment_orientations([circle], [R], [0.0], TURNS_WITH_ARC, closed=True)
    assert law.rate == 1.0 and law.leads == () and deg(law.start, law.end) < 1e-9


def test_a_corner_area_at_the_roots_end_reads_the_whole_paths_laws():
    """Dragging at 10 deg: the leg after the root keeps its drag (no lead), so an area over the
    root's last 3 mm and the leg's first 3 mm turns only as the root's law does there: 0.3 rad
    of sweep at (90 - 2 gamma) / 90 deg per deg, 11.841 deg (the segments 2-3 read alone
    start pushing at the root, so the leg would get a lead: 13.489 deg)."""
    segments, R_u_t, marker_s = inside_corner(-10.0)
    gamma = math.degrees(math.atan(math.sqrt(2) * math.tan(math.radians(10.0))))
    turn = rs.area_turn_deg(segments, R_u_t, 2, 3, 3.0, marker_s, TURNS_WITH_ARC)
    assert turn == pytest.approx(math.degrees(0.3) * (90.0 - 2 * gamma) / 90.0, abs=1e-9)
    assert turn == pytest.approx(11.841, abs=1e-3)

    def count(areas):
        path = make_path(segments, R_u_t, marker_s_mm=marker_s, tool_on_arcs=TURNS_WITH_ARC, risk_areas=areas)
        return len(generate(make_cell([path], T_u_b=np.eye(4))).paths[0].moves)

    area = RiskAreaSpec("R", "Root end", 2, 3, step_mm=0.5, corner_span_mm=3.0)
    added = rs.moves_added(segments, R_u_t, 2, 3, 0.5, 3.0, marker_s_mm=marker_s, tool_on_arcs=TURNS_WITH_ARC)
    # 6 + 6 risk moves at 0.5 mm; the root (one circular move) and the leg (one linear move)
    # are only shortened.
    assert added == count([area]) - count([]) == 12
