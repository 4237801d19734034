"""One tool marker for a long path (issue 12, part 5).

A marker sets the segment its origin lies on and every following segment up
to the next marker. Expected orientations are written down as quaternions
(w, x, y, z) computed by hand, not taken from the code under test:

- ``Q_DOWN``: the tool pointing down (-Z of {U}), X along +X: 180 deg about X,
  (cos 90, sin 90 (1, 0, 0)) = (0, 1, 0, 0).
- ``Q_TILTED``: that tool turned 30 deg about Y: (cos 15, 0, sin 15, 0) * (0, 1, 0, 0)
  = (0, cos 15, 0, -sin 15); its Z axis is (-sin 30, 0, -cos 30).

The calibration frame is {U} itself, so targets in {B} are the poses in {U}.
"""

import math
import time

import numpy as np
import pytest

import FreeCAD
import Part
from CadRobotWB import api
from CadRobotWB.core import generate as core_generate
from CadRobotWB.errors import MarkerError
from CadRobotWB.objects import path_cache, reader, tool_marker
from conftest import run_cadrobot
from helpers import V, polyline, simple_cell, sketch_of

C15, S15 = math.cos(math.radians(15.0)), math.sin(math.radians(15.0))
Q_DOWN = np.array([0.0, 1.0, 0.0, 0.0])
Q_TILTED = np.array([0.0, C15, 0.0, -S15])
# Five segments: 1 (0,0)-(50,0), 2 up to (50,50), 3 to (100,50), 4 down to (100,0), 5 to (150,0).
FIVE = [(0, 0), (50, 0), (50, 50), (100, 50), (100, 0), (150, 0)]


def placement(point, q_wxyz):
    """A FreeCAD placement at `point` turned by quaternion (w, x, y, z)."""
    w, x, y, z = q_wxyz
    return FreeCAD.Placement(V(*point), FreeCAD.Rotation(x, y, z, w))


def quaternion_of(T):
    """(w, x, y, z) of the rotation of a 4x4 pose (FreeCAD's own conversion), w >= 0 hemisphere
    left to the caller: compare with :func:`same_rotation`."""
    x, y, z, w = FreeCAD.Placement(FreeCAD.Matrix(*np.asarray(T, float).ravel())).Rotation.Q
    return np.array([w, x, y, z])


def same_rotation(q1, q2, atol=1e-9):
    """Quaternions q and -q are the same rotation."""
    return min(np.abs(q1 - q2).max(), np.abs(q1 + q2).max()) < atol


def five_segment_cell(doc, risk=None):
    """The five-segment path with a marker on segment 1 (down) and one on segment 4 (tilted)."""
    cell, path = simple_cell(doc, sketch_of(doc, polyline(FIVE)))
    first = api.make_tool_marker(doc, cell, placement((25, 0, 0), Q_DOWN), name="First")
    fourth = api.make_tool_marker(doc, cell, placement((100, 25, 0), Q_TILTED), name="Fourth")
    if risk is not None:
        api.make_risk_area(doc, cell, path, *risk)
    return cell, path, first, fourth


def path_moves(program):
    return [m for m in program.paths[0].moves if m.segment is not None]


def test_segments_take_the_orientation_of_the_marker_before_them(doc):
    cell, path, first, fourth = five_segment_cell(doc)
    (read_path, R_u_t, areas), = reader.path_orientations(cell)
    assert read_path == path and len(R_u_t) == 5 and areas == []
    expected = [Q_DOWN] * 3 + [Q_TILTED] * 2
    for k, (R, q) in enumerate(zip(R_u_t, expected), start=1):
        assert same_rotation(quaternion_of(np.block([[R, np.zeros((3, 1))], [0, 0, 0, 1]])), q), k

    program = api.generate(cell)
    moves = path_moves(program)
    assert sorted({m.segment for m in moves}) == [1, 2, 3, 4, 5]
    for move in moves:
        q = Q_DOWN if move.segment <= 3 else Q_TILTED
        assert same_rotation(quaternion_of(move.target.T_b_t), q), move.comment
    # The tool turns once, where the second marker's segments begin, and nowhere else.
    turns = [m for m in program.paths[0].moves if m.role == core_generate.ROLE_REORIENT]
    assert [(m.segment, tuple(np.round(m.target.position_mm, 9))) for m in turns] == [(4, (100.0, 50.0, 0.0))]
    assert "reorient tool 30.0 deg" in turns[0].comment


def test_governs_names_the_segments_and_follows_changes(doc, tmp_path):
    cell, path, first, fourth = five_segment_cell(doc)
    assert first.Governs == "segments 1-3 of Path" and fourth.Governs == "segments 4-5 of Path"
    assert first.getEditorMode("Governs") == ["ReadOnly"]
    fourth.Placement = placement((125, 0, 0), Q_TILTED)          # onto segment 5
    doc.recompute()
    assert first.Governs == "segments 1-4 of Path" and fourth.Governs == "segment 5 of Path"
    assert not [o.Name for o in doc.Objects if "Touched" in o.State]
    stray = api.make_tool_marker(doc, cell, placement((25, 3, 0), Q_DOWN), name="Stray")
    assert stray.Governs.startswith("nothing: Tool marker 'Stray' lies 3.000 mm from the nearest path")
    doc.removeObject(stray.Name)
    path.Reversed = True                                          # segment 1 is now (150,0)-(100,0)
    doc.recompute()
    assert fourth.Governs == "segments 1-4 of Path" and first.Governs == "segment 5 of Path"
    saved, name = str(tmp_path / "governs.FCStd"), fourth.Name
    doc.saveAs(saved)
    FreeCAD.closeDocument(doc.Name)
    again = FreeCAD.openDocument(saved)
    try:
        assert again.getObject(name).Governs == "segments 1-4 of Path"
    finally:
        FreeCAD.closeDocument(again.Name)


def test_risk_area_slerps_between_inherited_orientations(doc):
    # Risk area over segments 3-4: from segment 3's orientation (inherited from First)
    # to segment 4's (Fourth's), by the fraction of the area's length travelled.
    cell, path, first, fourth = five_segment_cell(doc, risk=(3, 4))
    moves = [m for m in path_moves(api.generate(cell)) if m.segment in (3, 4)]
    assert len(moves) > 10
    for move in moves:
        x, y, _ = move.target.position_mm
        travelled = (x - 50.0) if y >= 50.0 - 1e-9 else 50.0 + (50.0 - y)    # along (50,50)-(100,50)-(100,0)
        angle = math.radians(30.0) * travelled / 100.0                       # about Y, from Q_DOWN
        expected = np.array([0.0, math.cos(angle / 2), 0.0, -math.sin(angle / 2)])
        assert same_rotation(quaternion_of(move.target.T_b_t), expected, atol=1e-6), move.comment


def test_segments_before_the_first_marker_are_one_error(doc):
    cell, path = simple_cell(doc, sketch_of(doc, polyline(FIVE)))
    marker = api.make_tool_marker(doc, cell, placement((100, 25, 0), Q_TILTED), name="Fourth")
    assert marker.Governs == "segments 4-5 of Path"
    with pytest.raises(MarkerError) as caught:
        api.generate(cell)
    message = str(caught.value)
    assert message == (
        "Path 'Path': segments 1-3 (Sketch.Edge1 to Sketch.Edge3) come before its first tool "
        "marker 'Fourth' (on segment 4), so they have no tool orientation. Place a tool marker on "
        "segment 1 (api.make_tool_marker or the CadRobot_ToolMarker command), or move 'Fourth' onto "
        "segment 1; a marker sets its segment and every following one up to the next marker.")
    assert caught.value.obj_name == path.Name


def test_cli_check_reports_segments_before_the_first_marker_with_exit_2(doc, tmp_path):
    cell, path = simple_cell(doc, sketch_of(doc, polyline(FIVE), name="Seam"))
    api.make_tool_marker(doc, cell, placement((75, 50, 0), Q_DOWN), name="Third")
    saved = str(tmp_path / "late_marker.FCStd")
    doc.saveAs(saved)
    run = run_cadrobot("check", saved)
    assert run.returncode == 2, (run.stdout, run.stderr)
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("cadrobot: error: "), run.stderr
    assert "Path 'Path': segments 1-2 (Seam.Edge1 to Seam.Edge2) come before its first tool " \
           "marker 'Third' (on segment 3)" in lines[0]


def test_a_marker_per_segment_reads_as_before(doc):
    # Old documents: every segment has its own marker, and each keeps its own orientation.
    cell, path = simple_cell(doc, sketch_of(doc, polyline(FIVE)))
    turns = [Q_DOWN, Q_TILTED, Q_DOWN, Q_TILTED, Q_DOWN]
    mids = [(25, 0, 0), (50, 25, 0), (75, 50, 0), (100, 25, 0), (125, 0, 0)]
    markers = [api.make_tool_marker(doc, cell, placement(p, q)) for p, q in zip(mids, turns)]
    assert [m.Governs for m in markers] == ["segment %d of Path" % k for k in range(1, 6)]
    for move in path_moves(api.generate(cell)):
        assert same_rotation(quaternion_of(move.target.T_b_t), turns[move.segment - 1])


def long_polyline(doc, count):
    """A Part::Feature of `count` straight 0.02 mm-long edges along a gentle wave (a DXF polyline)."""
    t = np.linspace(0.0, 1.0, count + 1)
    points = [V(200.0 + 400.0 * x, 20.0 * math.sin(6.0 * x), 0.0) for x in t]
    feature = doc.addObject("Part::Feature", "Polyline")
    feature.Shape = Part.makePolygon(points)
    return feature, points


def test_one_marker_on_a_20000_edge_polyline_generates(doc):
    feature, points = long_polyline(doc, 20000)
    cell, path = simple_cell(doc, feature)
    start = np.array(points[0]) + (np.array(points[1]) - np.array(points[0])) / 2
    marker = api.make_tool_marker(doc, cell, placement(start, Q_DOWN))
    assert path.SegmentCount == 20000 and marker.Governs == "segments 1-20000 of Path"
    path_cache.forget()                            # as a fresh `cadrobot export` reads it
    began = time.perf_counter()
    program = core_generate.generate(reader.read_cell(cell))
    seconds = time.perf_counter() - began
    moves = path_moves(program)
    assert len(moves) == 20000 and [m.segment for m in moves] == list(range(1, 20001))
    assert all(same_rotation(quaternion_of(m.target.T_b_t), Q_DOWN) for m in moves[::997])
    assert not [m for m in program.paths[0].moves if m.role == core_generate.ROLE_REORIENT]
    np.testing.assert_allclose(moves[-1].target.position_mm, np.array(points[-1]), atol=1e-9)
    assert seconds < 20.0, "reading and generating took %.1f s" % seconds   # was quadratic-prone


def test_many_markers_on_a_long_path_are_found_quickly(doc):
    # 2,000 markers on a 20,000-edge path: each is found without testing every edge.
    feature, points = long_polyline(doc, 20000)
    cell, path = simple_cell(doc, feature)
    path.MarkerTolerance = 0.005       # the edges are 0.02 mm long: a mid-point is on one edge only
    marked = list(range(0, 20000, 10))
    for k in marked:
        mid = (np.array(points[k]) + np.array(points[k + 1])) / 2
        marker = doc.addObject("Part::FeaturePython", "Marker")
        tool_marker.ToolMarker(marker)
        marker.Placement = placement(mid, Q_DOWN if k % 20 else Q_TILTED)
        cell.addObject(marker)
    doc.recompute()
    began = time.perf_counter()
    governed = reader.governed_segments(cell)
    seconds = time.perf_counter() - began
    spans = sorted((g.first, g.last) for g in governed.values())
    assert spans == [(k + 1, k + 10) for k in marked]
    assert seconds < 10.0, "finding 2,000 markers took %.1f s" % seconds


def test_a_marker_outside_the_cell_counts_when_linked_to_its_path(doc):
    cell, path, first, fourth = five_segment_cell(doc)
    loose = doc.addObject("Part::FeaturePython", "Loose")         # in no group
    tool_marker.ToolMarker(loose)
    loose.Placement = placement((75, 50, 0), Q_TILTED)            # on segment 3
    doc.recompute()
    assert reader.cell_markers(cell) == [first, fourth]           # not linked: not the cell's
    loose.Path = path
    doc.recompute()
    assert reader.cell_markers(cell) == [first, fourth, loose]
    assert (first.Governs, loose.Governs) == ("segments 1-2 of Path", "segment 3 of Path")
    moves = path_moves(api.generate(cell))
    assert all(same_rotation(quaternion_of(m.target.T_b_t), Q_TILTED) for m in moves if m.segment == 3)
