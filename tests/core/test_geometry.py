"""Tests of core/geometry.py: segments, chaining, marker assignment.

Expected numbers are derived by hand (circle parametrisation, elementary
trigonometry), not from the code under test.
"""

import math

import numpy as np
import pytest

from CadRobotWB.core.geometry import Arc, Line, Polyline, assign_point, chain_segments
from CadRobotWB.errors import GeometryError

S45 = math.sqrt(0.5)


def close(a, b, atol=1e-9):
    return np.allclose(np.asarray(a, float), np.asarray(b, float), rtol=0.0, atol=atol)


# --- Line -------------------------------------------------------------------

def test_line_basics():
    line = Line([0, 0, 0], [30, 40, 0], source="Sketch.Edge1")
    assert line.kind == "line"
    assert line.length == pytest.approx(50.0)
    assert close(line.point_at(25.0), [15, 20, 0])
    assert close(line.points_at([0.0, 10.0, 50.0]), [[0, 0, 0], [6, 8, 0], [30, 40, 0]])
    assert close(line.tangent_at(3.0), [0.6, 0.8, 0.0])
    rev = line.reversed()
    assert close(rev.start, [30, 40, 0]) and close(rev.end, [0, 0, 0])
    assert rev.source == "Sketch.Edge1"


def test_line_closest_clamps_to_ends():
    line = Line([0, 0, 0], [10, 0, 0])
    assert close(line.closest([4, 3, 0]), [3.0, 4.0])
    assert close(line.closest([-3, 4, 0]), [5.0, 0.0])      # before the start
    assert close(line.closest([13, 0, 4]), [5.0, 10.0])     # past the end


def test_line_transformed():
    # Rotation 90 deg about Z, then translation (1, 2, 3).
    T = np.array([[0, -1, 0, 1], [1, 0, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]], float)
    moved = Line([1, 0, 0], [2, 0, 0]).transformed(T)
    assert close(moved.start, [1, 3, 3]) and close(moved.end, [1, 4, 3])


# --- Arc --------------------------------------------------------------------

def test_quarter_circle_about_z():
    arc = Arc([0, 0, 0], [0, 0, 1], [50, 0, 0], math.pi / 2, source="Sketch.Edge3")
    assert arc.kind == "arc"
    assert arc.radius == pytest.approx(50.0)
    assert arc.length == pytest.approx(25.0 * math.pi)
    assert close(arc.point_at(math.pi * 50 / 4), [50 * S45, 50 * S45, 0])
    assert close(arc.end, [0, 50, 0])
    assert close(arc.mid, [50 * S45, 50 * S45, 0])
    assert close(arc.tangent_at(0.0), [0, 1, 0])
    assert close(arc.tangent_at(arc.length), [-1, 0, 0])
    # 30 degrees: (50 cos 30, 50 sin 30, 0)
    assert close(arc.points_at([50 * math.pi / 6]), [[25 * math.sqrt(3), 25, 0]])


def test_arc_in_tilted_plane():
    # Circle of radius 20 about c = (10, 20, 30), axis n = (1, 0, 1)/sqrt2,
    # starting at c + 20 (0, 1, 0).  u = (0, 1, 0), v = n x u = (-1, 0, 1)/sqrt2.
    c = np.array([10.0, 20.0, 30.0])
    n = np.array([1.0, 0.0, 1.0]) / math.sqrt(2)
    arc = Arc(c, [2, 0, 2], c + [0, 20, 0], math.radians(120))   # normal is normalised
    assert close(arc.normal, n)
    assert arc.length == pytest.approx(20 * 2 * math.pi / 3)
    h = 20 * S45
    # phi = 90 deg: c + 20 v
    assert close(arc.point_at(20 * math.pi / 2), [10 - h, 20, 30 + h])
    # phi = 60 deg: c + 20 (cos60 u + sin60 v)
    s60 = math.sin(math.radians(60))
    assert close(arc.point_at(20 * math.pi / 3), [10 - h * s60, 20 + 10, 30 + h * s60])
    # phi = 120 deg (end)
    assert close(arc.end, [10 - h * s60, 20 - 10, 30 + h * s60])
    pts = arc.points_at(np.linspace(0, arc.length, 17))
    assert close(np.linalg.norm(pts - c, axis=1), np.full(17, 20.0))
    assert close((pts - c) @ n, np.zeros(17))


def test_arc_center_off_plane_is_slid_along_axis():
    arc = Arc([0, 0, 7], [0, 0, 1], [50, 0, 0], math.pi)
    assert close(arc.center, [0, 0, 0])
    assert arc.radius == pytest.approx(50.0)


def test_arc_bad_input():
    with pytest.raises(GeometryError):
        Arc([0, 0, 0], [0, 0, 1], [0, 0, 0], 1.0)          # zero radius
    with pytest.raises(GeometryError):
        Arc([0, 0, 0], [0, 0, 0], [1, 0, 0], 1.0)          # zero normal
    for sweep in (0.0, -1.0, 7.0):
        with pytest.raises(GeometryError):
            Arc([0, 0, 0], [0, 0, 1], [1, 0, 0], sweep)


def test_arc_from_three_points_both_senses():
    ccw = Arc.from_three_points([50, 0, 0], [0, 50, 0], [-50, 0, 0])
    assert close(ccw.center, [0, 0, 0]) and close(ccw.normal, [0, 0, 1])
    assert ccw.sweep_rad == pytest.approx(math.pi)
    cw = Arc.from_three_points([50, 0, 0], [0, -50, 0], [-50, 0, 0])
    assert close(cw.normal, [0, 0, -1])
    assert close(cw.mid, [0, -50, 0])


def test_arc_from_three_points_270_degrees():
    a135 = math.radians(135)
    arc = Arc.from_three_points([50, 0, 0], [50 * math.cos(a135), 50 * math.sin(a135), 0],
                                [0, -50, 0], source="Sketch.Edge9")
    assert arc.source == "Sketch.Edge9"
    assert close(arc.center, [0, 0, 0]) and close(arc.normal, [0, 0, 1])
    assert arc.sweep_rad == pytest.approx(1.5 * math.pi)


def test_arc_from_three_points_tilted_matches_definition():
    c = np.array([10.0, 20.0, 30.0])
    ref = Arc(c, [1, 0, 1], c + [0, 20, 0], math.radians(200))
    arc = Arc.from_three_points(ref.start, ref.point_at(5.0), ref.end)
    assert close(arc.center, c) and close(arc.normal, ref.normal)
    assert arc.sweep_rad == pytest.approx(math.radians(200))
    assert close(arc.mid, ref.mid)


def test_arc_from_three_points_collinear():
    with pytest.raises(GeometryError, match="collinear"):
        Arc.from_three_points([0, 0, 0], [1, 1, 1], [2, 2, 2])
    with pytest.raises(GeometryError):
        Arc.from_three_points([0, 0, 0], [0, 0, 0], [2, 0, 0])


def test_arc_reversed():
    arc = Arc([0, 0, 0], [0, 0, 1], [50, 0, 0], math.pi / 2, source="E")
    rev = arc.reversed()
    assert close(rev.start, [0, 50, 0]) and close(rev.end, [50, 0, 0])
    assert close(rev.normal, [0, 0, -1])
    assert rev.sweep_rad == pytest.approx(arc.sweep_rad)
    assert rev.source == "E"
    for s in np.linspace(0, arc.length, 7):
        assert close(rev.point_at(s), arc.point_at(arc.length - s))


def test_arc_closest():
    arc = Arc([0, 0, 0], [0, 0, 1], [50, 0, 0], math.pi / 2)
    # At 30 deg, radius 80, 7 above the plane: 30 mm out and 7 mm up.
    a = math.radians(30)
    d, s = arc.closest([80 * math.cos(a), 80 * math.sin(a), 7])
    assert d == pytest.approx(math.hypot(30, 7)) and s == pytest.approx(50 * a)
    # At 135 deg: outside the sweep, nearer the end (0, 50, 0).
    b = math.radians(135)
    p = [50 * math.cos(b), 50 * math.sin(b), 0]
    d, s = arc.closest(p)
    assert s == pytest.approx(arc.length)
    assert d == pytest.approx(np.linalg.norm(np.subtract(p, [0, 50, 0])))
    # At -20 deg: nearer the start.
    d, s = arc.closest([50 * math.cos(-0.35), 50 * math.sin(-0.35), 0])
    assert s == 0.0 and d == pytest.approx(2 * 50 * math.sin(0.175))


def test_full_circle_closest():
    circle = Arc([0, 0, 0], [0, 0, 1], [50, 0, 0], 2 * math.pi)
    assert close(circle.end, circle.start, atol=1e-9)
    assert close(circle.closest([50, 0, 0]), [0.0, 0.0])
    d, s = circle.closest([50, -1e-13, 0])             # just before the start
    assert d == pytest.approx(0.0, abs=1e-9)
    assert close(circle.point_at(s), [50, 0, 0], atol=1e-9)
    a = math.radians(350)
    d, s = circle.closest([60 * math.cos(a), 60 * math.sin(a), 0])
    assert d == pytest.approx(10.0) and s == pytest.approx(50 * a)


def test_arc_transformed():
    T = np.array([[0, -1, 0, 1], [1, 0, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]], float)
    arc = Arc([0, 0, 0], [1, 0, 0], [0, 10, 0], math.pi / 2).transformed(T)
    assert close(arc.center, [1, 2, 3]) and close(arc.normal, [0, 1, 0])
    assert close(arc.start, [-9, 2, 3])
    # Original end: about +X from +Y, a quarter turn -> (0, 0, 10) -> moved (1, 2, 13).
    assert close(arc.end, [1, 2, 13])


# --- Polyline ---------------------------------------------------------------

def test_polyline():
    poly = Polyline([[0, 0, 0], [3, 4, 0], [3, 4, 0], [3, 4, 12]], source="Sketch.Edge7")
    assert poly.kind == "spline"
    assert len(poly.points) == 3                        # duplicate dropped
    assert poly.length == pytest.approx(17.0)
    assert close(poly.point_at(2.5), [1.5, 2.0, 0])
    assert close(poly.point_at(11.0), [3, 4, 6])
    assert close(poly.tangent_at(1.0), [0.6, 0.8, 0]) and close(poly.tangent_at(6.0), [0, 0, 1])
    assert close(poly.closest([3, 10, 6]), [6.0, 11.0])
    rev = poly.reversed()
    assert close(rev.start, [3, 4, 12]) and close(rev.point_at(6.0), [3, 4, 6])
    assert close(poly.transformed(np.eye(4)).points, poly.points)
    with pytest.raises(GeometryError):
        Polyline([[0, 0, 0]])


# --- chain_segments ---------------------------------------------------------

def square_edges():
    A, B, C, D = [0, 0, 0], [10, 0, 0], [10, 10, 0], [0, 10, 0]
    return A, B, C, D


def test_chain_square_shuffled_and_reversed():
    A, B, C, D = square_edges()
    segs = [Line(A, B, "E1"), Line(D, C, "E3"), Line(D, A, "E4"), Line(C, B, "E2")]
    ordered, closed = chain_segments(segs, 0.01, "Square")
    assert closed
    assert [s.source for s in ordered] == ["E1", "E2", "E3", "E4"]
    expected = [(A, B), (B, C), (C, D), (D, A)]
    for seg, (p, q) in zip(ordered, expected):
        assert close(seg.start, p) and close(seg.end, q)


def test_chain_l_shape_first_segment_in_middle():
    P0, P1, P2, P3 = [0, 0, 0], [10, 0, 0], [10, 20, 0], [25, 20, 0]
    segs = [Line(P1, P2, "mid"), Line(P3, P2, "last"), Line(P0, P1, "first")]
    ordered, closed = chain_segments(segs, 0.01, "L")
    assert not closed
    assert [s.source for s in ordered] == ["first", "mid", "last"]
    for seg, (p, q) in zip(ordered, [(P0, P1), (P1, P2), (P2, P3)]):
        assert close(seg.start, p) and close(seg.end, q)
    # segments[0] drawn the other way round sets the direction of travel.
    segs = [Line(P2, P1, "mid"), Line(P3, P2, "last"), Line(P0, P1, "first")]
    ordered, closed = chain_segments(segs, 0.01, "L")
    assert [s.source for s in ordered] == ["last", "mid", "first"]
    assert close(ordered[0].start, P3) and close(ordered[-1].end, P0)


def test_chain_small_gap_within_tolerance():
    segs = [Line([0, 0, 0], [10, 0, 0], "a"), Line([10.004, 0, 0], [10, 5, 0], "b")]
    ordered, closed = chain_segments(segs, 0.01)
    assert [s.source for s in ordered] == ["a", "b"] and not closed


def test_chain_circle_of_two_arcs():
    upper = Arc([0, 0, 0], [0, 0, 1], [50, 0, 0], math.pi, "E1")          # via (0, 50)
    lower_cw = Arc([0, 0, 0], [0, 0, -1], [50, 0, 0], math.pi, "E2")       # via (0, -50)
    ordered, closed = chain_segments([upper, lower_cw], 0.01, "Circle")
    assert closed
    assert ordered[0] is upper
    second = ordered[1]
    assert close(second.start, [-50, 0, 0]) and close(second.end, [50, 0, 0])
    assert close(second.normal, [0, 0, 1]) and close(second.mid, [0, -50, 0])


def test_chain_single_full_circle_is_closed():
    ordered, closed = chain_segments([Arc([0, 0, 0], [0, 0, 1], [5, 0, 0], 2 * math.pi)], 0.01)
    assert closed and len(ordered) == 1


def test_chain_is_deterministic():
    A, B, C, D = square_edges()
    segs = [Line(C, B, "E2"), Line(A, B, "E1"), Line(D, A, "E4"), Line(D, C, "E3")]
    first = [(s.source, tuple(s.start)) for s in chain_segments(segs, 0.01)[0]]
    second = [(s.source, tuple(s.start)) for s in chain_segments(segs, 0.01)[0]]
    assert first == second
    assert first[0] == ("E2", (10, 10, 0))


def test_chain_empty():
    with pytest.raises(GeometryError, match="Path 'Weld' has no segments"):
        chain_segments([], 0.01, "Weld")


def test_chain_zero_length_segment():
    segs = [Line([0, 0, 0], [10, 0, 0], "Sketch.Edge1"),
            Line([10, 0, 0], [10.005, 0, 0], "Sketch.Edge2")]
    with pytest.raises(GeometryError, match=r"Path 'Weld': Sketch\.Edge2 has zero length"):
        chain_segments(segs, 0.01, "Weld")


def test_chain_gap_message():
    segs = [Line([0, 0, 0], [10, 0, 0], "Sketch.Edge2"),
            Line([11.5, 0, 0], [20, 0, 0], "Sketch.Edge5")]
    with pytest.raises(GeometryError) as err:
        chain_segments(segs, 0.01, "Weld")
    assert str(err.value) == (
        "Path 'Weld': Sketch.Edge2 and Sketch.Edge5 do not connect (gap 1.500 mm > "
        "tolerance 0.010 mm). Close the gap in the drawing or raise the path's "
        "ConnectTolerance.")


def test_chain_gap_names_unnamed_segments_by_number():
    segs = [Line([0, 0, 0], [10, 0, 0]), Line([10, 0, 0], [10, 10, 0]),
            Line([10, 12, 0], [0, 12, 0])]
    with pytest.raises(GeometryError, match=r"segment 2 and segment 3 .*gap 2\.000 mm"):
        chain_segments(segs, 0.01, "P")


def test_chain_stray_segment_next_to_closed_loop():
    A, B, C, D = square_edges()
    segs = [Line(A, B, "E1"), Line(B, C, "E2"), Line(C, D, "E3"), Line(D, A, "E4"),
            Line([13, 10, 0], [20, 10, 0], "Stray")]
    with pytest.raises(GeometryError, match=r"E2 and Stray do not connect \(gap 3\.000 mm"):
        chain_segments(segs, 0.01, "Square")


def test_chain_branch():
    segs = [Line([0, 0, 0], [10, 0, 0], "a"), Line([10, 0, 0], [20, 0, 0], "b"),
            Line([10, 0, 0], [10, 10, 0], "c")]
    with pytest.raises(GeometryError, match=r"Path 'T' branches .*a, b, c"):
        chain_segments(segs, 0.01, "T")


def test_chain_thousands_of_shuffled_reversed_edges():
    # A zig-zag of 3000 edges, shuffled, every second one drawn backwards; the chain
    # starts from the first edge given (edge 1234) and extends both ways.
    n = 3000
    points = [np.array([10.0 * k, 15.0 * math.sin(0.7 * k), 0.0]) for k in range(n + 1)]
    segs = [Line(points[k], points[k + 1], "E%d" % k) if k % 2 else
            Line(points[k + 1], points[k], "E%d" % k) for k in range(n)]
    order = list(range(n))
    np.random.default_rng(3).shuffle(order)
    order.remove(1234)
    ordered, closed = chain_segments([segs[1234]] + [segs[k] for k in order], 0.01)
    assert not closed and len(ordered) == n
    sources = [s.source for s in ordered]
    assert sources in (["E%d" % k for k in range(n)], ["E%d" % k for k in reversed(range(n))])
    for a, b in zip(ordered[:-1], ordered[1:]):
        assert close(a.end, b.start)


def test_chain_branch_among_thousands_of_edges():
    segs = [Line([10.0 * k, 0, 0], [10.0 * (k + 1), 0, 0], "E%d" % k) for k in range(2000)]
    segs.append(Line([10000.0, 0, 0], [10000.0, 5.0, 0], "spur"))
    with pytest.raises(GeometryError, match=r"branches at \(10000.000, 0.000, 0.000\).*E999, E1000, spur"):
        chain_segments(segs, 0.01, "Long")


# --- assign_point -----------------------------------------------------------

def test_assign_point_open_path():
    P0, P1, P2 = [0, 0, 0], [10, 0, 0], [10, 10, 0]
    arc = Arc([10, 15, 0], [0, 0, 1], P2, math.pi)        # (10,10) -> (15,15) -> (10,20)
    path = [Line(P0, P1), Line(P1, P2), arc]
    assert assign_point(path, [5, 0.001, 0], 0.01) == 0
    assert assign_point(path, P0, 0.01) == 0
    assert assign_point(path, P1, 0.01) == 1              # junction: segment starting there
    assert assign_point(path, P2, 0.01) == 2
    assert assign_point(path, [15, 15, 0], 0.01) == 2
    assert assign_point(path, [10, 20, 0], 0.01) == 2     # end of an open path: last segment
    assert assign_point(path, [5, 5, 0], 0.01) is None


def test_assign_point_closed_path_start():
    A, B, C, D = square_edges()
    path = [Line(A, B), Line(B, C), Line(C, D), Line(D, A)]
    assert assign_point(path, A, 0.01) == 0
    assert assign_point(path, [0, 5, 0], 0.01) == 3
