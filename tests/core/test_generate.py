"""Tests of core/generate.py: CellSpec -> Program.

Expected targets are computed by hand: {B} is {U} turned 90 deg about Z and
moved to (100, 200, 0), so a point (x, y, z) of {U} is (y - 200, 100 - x, z)
in {B} and a rotation R of {U} is Rz(-90) R in {B}. Risk-area orientations
are checked against scipy's Slerp (scipy is used in tests only).
"""

import math
import re

import numpy as np
import pytest
from scipy.spatial.transform import Rotation, Slerp

from CadRobotWB.core.generate import (CellSpec, FrameSpec, PathSpec, RiskAreaSpec, generate,
                                      sanitize_identifier)
from CadRobotWB.core.geometry import Arc, Line, Polyline
from CadRobotWB.core.program import ToolData
from CadRobotWB.errors import FrameError, InputError, MarkerError, RiskAreaError

T_U_B = np.array([[0, -1, 0, 100], [1, 0, 0, 200], [0, 0, 1, 0], [0, 0, 0, 1]], float)
T_U_R = np.array([[1, 0, 0, -500], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], float)
RZ_MINUS_90 = np.array([[0, 1, 0], [-1, 0, 0], [0, 0, 1]], float)
DOWN = np.diag([1.0, -1.0, -1.0])                       # tool +Z pointing down
DOWN_TURNED = np.array([[0, 1, 0], [1, 0, 0], [0, 0, -1]], float)   # Rz(90) @ DOWN


def to_b(p):
    x, y, z = p
    return np.array([y - 200.0, 100.0 - x, z])


def close(a, b, atol=1e-9):
    return np.allclose(np.asarray(a, float), np.asarray(b, float), rtol=0.0, atol=atol)


def make_cell(paths, T_u_b=T_U_B, name="Cell"):
    return CellSpec(name=name, label="My cell", robot="ABB_IRB2400", T_u_r=T_U_R,
                    tool=ToolData(name="torch", T_f_t=np.eye(4)),
                    frames={"Frame": FrameSpec(name="Frame", label="Table frame", T_u_b=T_u_b)},
                    paths=paths, source="doc.FCStd / My cell")


def make_path(segments, R_u_t, **kw):
    args = dict(name="Weld", label="Weld seam", segments=segments, R_u_t=R_u_t, frame="Frame",
                speed_mm_s=10.0, zone_mm=2.0, approach_mm=50.0, retract_mm=30.0,
                approach_speed_mm_s=100.0, sample_time_s=0.3)
    args.update(kw)
    return PathSpec(**args)


def summary(moves):
    return [(m.kind, m.role, m.segment, m.speed_mm_s, m.zone_mm) for m in moves]


# --- identifiers ------------------------------------------------------------

def test_sanitize_identifier():
    assert sanitize_identifier("Weld seam #2") == "Weld_seam_2"
    assert sanitize_identifier("2nd pass", "path") == "path_2nd_pass"
    assert sanitize_identifier("éé", "path") == "path"
    assert len(sanitize_identifier("a" * 40)) == 24


# --- a two-line path with two orientations ----------------------------------

def test_two_lines_exact_move_list():
    A, B, C = (110.0, 220.0, 5.0), (160.0, 220.0, 5.0), (160.0, 260.0, 5.0)
    path = make_path([Line(A, B, "Sketch.Edge1"), Line(B, C, "Sketch.Edge2")],
                     [DOWN, DOWN_TURNED])
    prog = generate(make_cell([path]))

    assert prog.name == "Cell" and prog.robot == "ABB_IRB2400"
    assert prog.source == "doc.FCStd / My cell" and prog.tool.name == "torch"
    assert list(prog.frames) == ["Frame"]
    wobj = prog.frames["Frame"]
    assert wobj.source == "Table frame"
    assert close(wobj.T_r_b, [[0, -1, 0, 600], [1, 0, 0, 200], [0, 0, 1, 0], [0, 0, 0, 1]])

    assert len(prog.paths) == 1
    assert prog.paths[0].name == "Weld" and prog.paths[0].label == "Weld seam"
    moves = prog.paths[0].moves
    assert summary(moves) == [
        ("joint", "approach", None, 100.0, 0.0),
        ("linear", "entry", None, 100.0, 0.0),
        ("linear", "path", 1, 10.0, 0.0),       # stops: the tool turns at B
        ("linear", "reorient", 2, 10.0, 0.0),
        ("linear", "path", 2, 10.0, 0.0),       # last path move stops exactly
        ("linear", "retract", None, 100.0, 0.0),
    ]
    # Approach point 50 mm back along tool -Z, i.e. 50 mm above A.
    positions = [[20, -10, 55], [20, -10, 5], [20, -60, 5], [20, -60, 5], [60, -60, 5],
                 [60, -60, 35]]
    R_b_1 = np.array([[0, -1, 0], [-1, 0, 0], [0, 0, -1]], float)    # Rz(-90) @ DOWN
    R_b_2 = np.array([[1, 0, 0], [0, -1, 0], [0, 0, -1]], float)     # Rz(-90) @ DOWN_TURNED
    rots = [R_b_1, R_b_1, R_b_1, R_b_2, R_b_2, R_b_2]
    for m, p, R in zip(moves, positions, rots):
        assert close(m.target.position_mm, p)
        assert close(m.target.T_b_t[:3, :3], R)
        assert close(m.target.T_b_t[3], [0, 0, 0, 1])
        assert m.frame == "Frame" and m.via is None
    assert moves[2].comment == "segment 1: line Sketch.Edge1"
    assert "reorient" in moves[3].comment and "90.0 deg" in moves[3].comment

    names = [t.name for t in prog.targets()]
    assert len(set(names)) == len(names)
    assert all(re.fullmatch(r"[A-Za-z][A-Za-z0-9_]{0,23}", n) for n in names)


def test_intermediate_moves_use_the_path_zone():
    pts = [(110, 220, 5), (160, 220, 5), (160, 260, 5), (120, 260, 5)]
    segs = [Line(pts[i], pts[i + 1]) for i in range(3)]
    moves = generate(make_cell([make_path(segs, [DOWN] * 3)])).paths[0].moves
    assert [m.role for m in moves] == ["approach", "entry", "path", "path", "path", "retract"]
    assert [m.zone_mm for m in moves] == [0.0, 0.0, 2.0, 2.0, 0.0, 0.0]


def test_no_approach_and_no_retract():
    A, B = (110.0, 220.0, 5.0), (160.0, 220.0, 5.0)
    moves = generate(make_cell([make_path([Line(A, B)], [DOWN], approach_mm=0.0,
                                          retract_mm=0.0)])).paths[0].moves
    assert summary(moves) == [("joint", "approach", None, 100.0, 0.0),
                              ("linear", "path", 1, 10.0, 0.0)]
    assert close(moves[0].target.position_mm, to_b(A))
    assert close(moves[1].target.position_mm, to_b(B))


# --- risk areas ---------------------------------------------------------------

def slerp_in_b(R0, R1, fractions):
    """Expected orientations in {B} by scipy's Slerp."""
    slerp = Slerp([0.0, 1.0], Rotation.from_matrix(np.array([R0, R1])))
    return RZ_MINUS_90 @ slerp(fractions).as_matrix()


def test_risk_area_over_two_lines():
    A, B, C, D = (110.0, 220.0, 5.0), (120.0, 220.0, 5.0), (120.0, 227.0, 5.0), (150.0, 227.0, 5.0)
    R2 = Rotation.from_euler("xyz", [180, 30, 60], degrees=True).as_matrix()
    path = make_path([Line(A, B, "E1"), Line(B, C, "E2"), Line(C, D, "E3")],
                     [DOWN, R2, R2],
                     risk_areas=[RiskAreaSpec("Risk", "Corner", 1, 2)])
    moves = generate(make_cell([path])).paths[0].moves
    # step = |v| dt = 10 mm/s * 0.3 s = 3 mm: stations 3, 6, 9, 10 on E1 and 3, 6, 7 on E2.
    assert [(m.role, m.segment) for m in moves] == (
        [("approach", None), ("entry", None)] + [("risk", 1)] * 4 + [("risk", 2)] * 3
        + [("path", 3), ("retract", None)])
    risk = moves[2:9]
    assert all(m.kind == "linear" and m.speed_mm_s == 10.0 for m in risk)
    # Zone 2 mm, at most half the shorter neighbouring move (3, 3, 3, 1 | 3, 3, 1 | 30 mm).
    assert [m.zone_mm for m in risk] == [1.5, 1.5, 0.5, 0.5, 1.5, 0.5, 0.5]
    assert moves[9].zone_mm == 0.0
    assert risk[0].comment.startswith("risk area 'Corner' segments 1-2")

    # Eqs 8-13: r(k) = P_j + v k dt, v = |v| W/|W|, last point P_j+1.
    v1 = 10.0 * (np.subtract(B, A) / 10.0)
    v2 = 10.0 * (np.subtract(C, B) / 7.0)
    expected = [np.add(A, v1 * k * 0.3) for k in (1, 2, 3)] + [B] + \
               [np.add(B, v2 * k * 0.3) for k in (1, 2)] + [C]
    for m, p in zip(risk, expected):
        assert close(m.target.position_mm, to_b(p))
    # Eqs 14-15 by arc-length fraction of the 17 mm area.
    fractions = np.array([3, 6, 9, 10, 13, 16, 17]) / 17.0
    for m, R in zip(risk, slerp_in_b(DOWN, R2, fractions)):
        assert close(m.target.T_b_t[:3, :3], R)
    # The entry keeps segment 1's orientation; the last risk point has segment 2's.
    assert close(moves[1].target.T_b_t[:3, :3], RZ_MINUS_90 @ DOWN)
    assert close(risk[-1].target.T_b_t[:3, :3], RZ_MINUS_90 @ R2)


def test_risk_area_with_an_arc_and_its_own_step():
    # Line 0 -> 10 along X, then a quarter circle radius 10 about (10, 10, 0).
    A, B = (0.0, 0.0, 0.0), (10.0, 0.0, 0.0)
    arc = Arc([10, 10, 0], [0, 0, 1], B, math.pi / 2, "E2")     # ends at (20, 10, 0)
    R2 = Rotation.from_euler("z", 90, degrees=True).as_matrix() @ DOWN
    path = make_path([Line(A, B, "E1"), arc], [DOWN, R2],
                     risk_areas=[RiskAreaSpec("Risk", "Corner", 1, 2, step_mm=4.0)])
    prog = generate(make_cell([path], T_u_b=np.eye(4)))
    risk = [m for m in prog.paths[0].moves if m.role == "risk"]
    arc_len = 10 * math.pi / 2
    s_line = [4.0, 8.0, 10.0]
    s_arc = [4.0, 8.0, 12.0, arc_len]
    expected = [(s, 0.0, 0.0) for s in s_line] + \
               [(10 + 10 * math.sin(s / 10), 10 - 10 * math.cos(s / 10), 0.0) for s in s_arc]
    assert len(risk) == len(expected)
    for m, p in zip(risk, expected):
        assert close(m.target.position_mm, p)
    fractions = np.array(s_line + [10 + s for s in s_arc]) / (10 + arc_len)
    slerp = Slerp([0.0, 1.0], Rotation.from_matrix(np.array([DOWN, R2])))
    for m, R in zip(risk, slerp(fractions).as_matrix()):
        assert close(m.target.T_b_t[:3, :3], R)


def test_reorient_on_entering_and_leaving_a_risk_area():
    pts = [(0, 0, 0), (10, 0, 0), (10, 10, 0), (20, 10, 0), (20, 20, 0)]
    segs = [Line(pts[i], pts[i + 1]) for i in range(4)]
    Rz = lambda deg: Rotation.from_euler("z", deg, degrees=True).as_matrix() @ DOWN
    path = make_path(segs, [Rz(0), Rz(30), Rz(60), Rz(90)], step_mm=5.0,
                     risk_areas=[RiskAreaSpec("Risk", "Corner", 2, 3)])
    moves = generate(make_cell([path], T_u_b=np.eye(4))).paths[0].moves
    assert [(m.role, m.segment) for m in moves] == [
        ("approach", None), ("entry", None), ("path", 1),
        ("reorient", 2), ("risk", 2), ("risk", 2), ("risk", 3), ("risk", 3),
        ("reorient", 4), ("path", 4), ("retract", None)]
    assert [m.zone_mm for m in moves] == [0, 0, 0, 0, 2, 2, 2, 0, 0, 0, 0]
    assert close(moves[3].target.position_mm, [10, 0, 0])
    assert close(moves[3].target.T_b_t[:3, :3], Rz(30))
    assert close(moves[8].target.position_mm, [20, 10, 0])
    assert close(moves[8].target.T_b_t[:3, :3], Rz(90))
    # Halfway through the area (10 of 20 mm) the slerp is at 45 deg.
    assert close(moves[5].target.T_b_t[:3, :3], Rz(45))


@pytest.mark.parametrize("first, last", [(0, 1), (2, 4), (3, 2)])
def test_risk_area_out_of_range(first, last):
    segs = [Line((0, 0, 0), (10, 0, 0)), Line((10, 0, 0), (10, 10, 0)),
            Line((10, 10, 0), (0, 10, 0))]
    path = make_path(segs, [DOWN] * 3, risk_areas=[RiskAreaSpec("Risk", "Corner", first, last)])
    with pytest.raises(RiskAreaError, match=r"Risk area 'Corner'.*segments 1-3"):
        generate(make_cell([path]))


def test_overlapping_risk_areas():
    segs = [Line((0, 0, 0), (10, 0, 0)), Line((10, 0, 0), (10, 10, 0)),
            Line((10, 10, 0), (0, 10, 0))]
    path = make_path(segs, [DOWN] * 3, risk_areas=[RiskAreaSpec("R2", "Second", 2, 3),
                                                   RiskAreaSpec("R1", "First", 1, 2)])
    with pytest.raises(RiskAreaError, match=r"'First' \(segments 1-2\) and 'Second'"):
        generate(make_cell([path]))


def test_risk_area_bad_step():
    path = make_path([Line((0, 0, 0), (10, 0, 0))], [DOWN],
                     risk_areas=[RiskAreaSpec("Risk", "Corner", 1, 1, step_mm=0.0)])
    with pytest.raises(RiskAreaError, match="Corner"):
        generate(make_cell([path]))


# --- arcs and splines -----------------------------------------------------------

def test_full_circle_gives_two_circular_moves():
    circle = Arc([0, 0, 0], [0, 0, 1], [50, 0, 0], 2 * math.pi, "Sketch.Edge1")
    path = make_path([circle], [DOWN], closed=True)
    moves = generate(make_cell([path], T_u_b=np.eye(4))).paths[0].moves
    assert summary(moves) == [
        ("joint", "approach", None, 100.0, 0.0), ("linear", "entry", None, 100.0, 0.0),
        ("circular", "path", 1, 10.0, 2.0), ("circular", "path", 1, 10.0, 0.0),
        ("linear", "retract", None, 100.0, 0.0)]
    assert close(moves[2].via.position_mm, [0, 50, 0])
    assert close(moves[2].target.position_mm, [-50, 0, 0])
    assert close(moves[3].via.position_mm, [0, -50, 0])
    assert close(moves[3].target.position_mm, [50, 0, 0])
    for m in moves[2:4]:
        assert close(m.via.T_b_t[:3, :3], DOWN) and close(m.target.T_b_t[:3, :3], DOWN)
    assert moves[2].comment == "segment 1: arc Sketch.Edge1 (part 1 of 2)"


@pytest.mark.parametrize("sweep_deg, vias_deg, ends_deg", [
    (90, [45], [90]), (180, [90], [180]), (270, [67.5, 202.5], [135, 270])])
def test_arc_pieces_at_most_180_degrees(sweep_deg, vias_deg, ends_deg):
    arc = Arc([0, 0, 0], [0, 0, 1], [20, 0, 0], math.radians(sweep_deg))
    moves = generate(make_cell([make_path([arc], [DOWN])], T_u_b=np.eye(4))).paths[0].moves
    circ = [m for m in moves if m.kind == "circular"]
    assert len(circ) == len(ends_deg)
    on_circle = lambda deg: [20 * math.cos(math.radians(deg)), 20 * math.sin(math.radians(deg)), 0]
    for m, via, end in zip(circ, vias_deg, ends_deg):
        assert close(m.via.position_mm, on_circle(via))
        assert close(m.target.position_mm, on_circle(end))


def test_spline_linear_moves_through_samples():
    pts = [(0, 0, 0), (5, 1, 0), (10, 3, 0), (15, 6, 0)]
    path = make_path([Polyline(pts, source="Sketch.Edge4")], [DOWN])
    moves = generate(make_cell([path], T_u_b=np.eye(4))).paths[0].moves
    body = [m for m in moves if m.role == "path"]
    assert [m.kind for m in body] == ["linear"] * 3
    for m, p in zip(body, pts[1:]):
        assert close(m.target.position_mm, p)
    assert body[0].comment == "segment 1: spline Sketch.Edge4"


# --- names and errors ---------------------------------------------------------

def test_names_are_sanitised_and_unique():
    seg = [Line((0, 0, 0), (10, 0, 0))]
    paths = [make_path(seg, [DOWN], name="Weld seam #1", label="Weld seam #1"),
             make_path(seg, [DOWN], name="Weld seam #1", label="copy")]
    prog = generate(make_cell(paths, name="2 cells"))
    assert prog.name == "Cell_2_cells"
    assert [p.name for p in prog.paths] == ["Weld_seam_1", "Weld_seam_1_2"]
    assert [p.label for p in prog.paths] == ["Weld seam #1", "copy"]
    names = [t.name for t in prog.targets()]
    assert len(set(n.lower() for n in names)) == len(names)
    assert all(re.fullmatch(r"[A-Za-z][A-Za-z0-9_]{0,23}", n) for n in names)


def test_unknown_frame():
    path = make_path([Line((0, 0, 0), (10, 0, 0))], [DOWN], frame="Nope")
    with pytest.raises(FrameError, match="Path 'Weld seam' uses calibration frame 'Nope'"):
        generate(make_cell([path]))


def test_orientation_count_and_validity():
    segs = [Line((0, 0, 0), (10, 0, 0)), Line((10, 0, 0), (10, 10, 0))]
    with pytest.raises(MarkerError, match="2 segments but 1 tool orientations"):
        generate(make_cell([make_path(segs, [DOWN])]))
    with pytest.raises(MarkerError, match="segment 2"):
        generate(make_cell([make_path(segs, [DOWN, 2 * DOWN])]))


def test_segments_sharing_one_orientation_read_like_copies_of_it():
    # A tool marker's orientation inherited by the following segments is one array shared
    # by them; the program is the one of separate equal copies, without a reorientation.
    segs = [Line((0, 0, 0), (10, 0, 0)), Line((10, 0, 0), (10, 10, 0)), Line((10, 10, 0), (20, 10, 0)),
            Line((20, 10, 0), (20, 0, 0))]
    shared = [DOWN, DOWN, DOWN_TURNED, DOWN_TURNED]
    copies = [DOWN.copy(), DOWN.copy(), DOWN_TURNED.copy(), DOWN_TURNED.copy()]
    programs = [generate(make_cell([make_path(segs, R_u_t)])) for R_u_t in (shared, copies)]
    summaries = [summary(p.paths[0].moves) for p in programs]
    assert summaries[0] == summaries[1]
    assert [m[2] for m in summaries[0] if m[1] == "reorient"] == [3]
    for a, b in zip(programs[0].paths[0].moves, programs[1].paths[0].moves):
        assert np.array_equal(a.target.T_b_t, b.target.T_b_t)


def test_a_shared_orientation_that_is_no_rotation_names_its_first_segment():
    segs = [Line((0, 0, 0), (10, 0, 0)), Line((10, 0, 0), (10, 10, 0)), Line((10, 10, 0), (20, 10, 0))]
    squashed = 2 * DOWN
    with pytest.raises(MarkerError, match=r"orientation of segment 2 is not a rotation"):
        generate(make_cell([make_path(segs, [DOWN, squashed, squashed])]))


def test_bad_speed():
    path = make_path([Line((0, 0, 0), (10, 0, 0))], [DOWN], speed_mm_s=0.0)
    with pytest.raises(InputError, match="Speed"):
        generate(make_cell([path]))
