"""Reading paths from the document: every line type, every placement."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import FreeCAD
import Part
from CadRobotWB import api, compat
from CadRobotWB.core import program as ir
from CadRobotWB.objects import reader
from helpers import V, down_placement, polyline, simple_cell, sketch_of


def test_shuffled_and_reversed_edges_form_one_path(doc):
    # A U shape drawn out of order, the middle edge backwards.
    edges = [Part.LineSegment(V(100, 0, 0), V(100, 50, 0)),
             Part.LineSegment(V(100, 0, 0), V(0, 0, 0)),      # reversed
             Part.LineSegment(V(0, 50, 0), V(0, 0, 0))]
    sketch = sketch_of(doc, edges)
    # Markers away from the junctions so each lies on exactly one segment.
    cell, path = simple_cell(doc, sketch, markers=[(100, 25, 0), (50, 0, 0), (0, 25, 0)])
    segments, closed, _ = reader.path_geometry(path)
    assert not closed
    # Travel keeps the direction of the first edge drawn, (100,0) -> (100,50).
    np.testing.assert_allclose([s.start for s in segments] + [segments[-1].end],
                               [(0, 50, 0), (0, 0, 0), (100, 0, 0), (100, 50, 0)], atol=1e-9)
    path.Reversed = True
    segments, _, _ = reader.path_geometry(path)
    np.testing.assert_allclose(segments[0].start, (100, 50, 0), atol=1e-9)
    assert path.SegmentCount == 3 and float(path.PathLength) == pytest.approx(200.0)


def test_arc_in_a_tilted_sketch_becomes_a_circular_move_through_its_middle(doc):
    tilt = FreeCAD.Placement(V(10, 20, 30), FreeCAD.Rotation(V(1, 0, 0), 30))
    arc = Part.ArcOfCircle(Part.Circle(V(0, 0, 0), V(0, 0, 1), 40), 0.0, np.pi / 2)
    line = Part.LineSegment(V(40, 0, 0), V(40, -60, 0))
    sketch = sketch_of(doc, [arc, line], placement=tilt)
    R = Rotation.from_euler("x", 30, degrees=True).as_matrix()
    to_u = lambda p: R @ np.asarray(p, float) + (10, 20, 30)  # noqa: E731  sketch -> {U}
    on_arc = to_u((40 * np.cos(np.pi / 4), 40 * np.sin(np.pi / 4), 0))
    on_line = to_u((40, -30, 0))
    cell, path = simple_cell(doc, sketch, markers=[on_arc, on_line])
    program = api.generate(cell)
    circular = [m for m in program.moves() if m.kind == ir.CIRCULAR]
    assert len(circular) == 1
    # {B} = {U} here. Travel starts at either free end (a sketch's edge order is its own).
    np.testing.assert_allclose(circular[0].via.position_mm, on_arc, atol=1e-6)
    start = program.moves()[1].target.position_mm
    if np.allclose(start, to_u((0, 40, 0))):
        np.testing.assert_allclose(circular[0].target.position_mm, to_u((40, 0, 0)), atol=1e-6)
    else:
        np.testing.assert_allclose(start, to_u((40, -60, 0)), atol=1e-6)
        np.testing.assert_allclose(circular[0].target.position_mm, to_u((0, 40, 0)), atol=1e-6)


def test_full_circle_is_two_half_circles(doc):
    sketch = sketch_of(doc, [Part.Circle(V(0, 0, 0), V(0, 0, 1), 25)],
                       placement=FreeCAD.Placement(V(0, 0, 5), FreeCAD.Rotation()))
    cell, path = simple_cell(doc, sketch, markers=[(0, 25, 5)])
    program = api.generate(cell)
    circular = [m for m in program.moves() if m.kind == ir.CIRCULAR]
    assert len(circular) == 2
    start = program.moves()[1].target.position_mm
    assert np.linalg.norm(start[:2]) == pytest.approx(25.0)
    # Each half ends opposite where it started and passes through the quarter point.
    np.testing.assert_allclose(circular[0].target.position_mm[:2], -start[:2], atol=1e-6)
    np.testing.assert_allclose(circular[1].target.position_mm, start, atol=1e-6)
    for move in circular:
        assert np.linalg.norm(move.via.position_mm[:2]) == pytest.approx(25.0)
        assert move.via.position_mm[2] == pytest.approx(5.0)


@pytest.mark.parametrize("make_curve", [
    lambda: _bspline(),
    lambda: Part.ArcOfEllipse(Part.Ellipse(V(0, 0, 0), 60, 30), 0.0, np.pi),
], ids=["bspline", "ellipse-arc"])
def test_splines_and_ellipses_become_linear_moves_within_the_chord_tolerance(doc, make_curve):
    curve = make_curve()
    sketch = sketch_of(doc, [curve])
    edge = sketch.Shape.Edges[0]
    middle = edge.valueAt((edge.FirstParameter + edge.LastParameter) / 2)
    cell, path = simple_cell(doc, sketch, markers=[tuple(middle)])
    path.ChordTolerance = 0.05
    program = api.generate(cell)
    points = [m.target.position_mm for m in program.moves() if m.role == ir.ROLE_PATH]
    assert len(points) > 10
    for a, b in zip(points[:-1], points[1:]):   # the chord's middle stays near the curve
        mid = Part.Vertex(V(*((a + b) / 2)))
        assert mid.distToShape(edge)[0] <= 0.05 + 1e-6


def _bspline():
    spline = Part.BSplineCurve()
    spline.interpolate([V(0, 0, 0), V(40, 30, 0), V(80, -10, 0), V(120, 20, 0)])
    return spline


def test_edges_of_a_solid_and_a_nested_part(doc):
    container = doc.addObject("App::Part", "Holder")
    container.Placement = FreeCAD.Placement(V(500, 0, 0), FreeCAD.Rotation(V(0, 0, 1), 90))
    box = doc.addObject("Part::Box", "Block")
    box.Length, box.Width, box.Height = 100, 60, 20
    container.addObject(box)
    doc.recompute()
    top = ["Edge%d" % (i + 1) for i, e in enumerate(box.Shape.Edges)
           if all(abs(v.Point.z - 20) < 1e-9 for v in e.Vertexes)]
    assert len(top) == 4
    cell = api.make_cell(doc)
    api.make_calibration_frame(doc, cell, FreeCAD.Placement())
    path = api.make_path(doc, cell, [(box, top)])
    segments, closed, _ = reader.path_geometry(path)
    assert closed and len(segments) == 4
    # The block's top corners, turned 90° about Z and moved to x = 500.
    corners = {tuple(np.round(s.start, 6)) for s in segments}
    assert corners == {(500.0, 0.0, 20.0), (500.0, 100.0, 20.0), (440.0, 100.0, 20.0), (440.0, 0.0, 20.0)}


def test_sketch_attached_to_a_face_follows_the_face(doc):
    box = doc.addObject("Part::Box", "Base")
    box.Placement = FreeCAD.Placement(V(0, 0, 100), FreeCAD.Rotation())
    doc.recompute()
    sketch = sketch_of(doc, polyline([(0, 0), (10, 0)]))
    compat.set_attachment_support(sketch, [(box, "Face6")])   # the top face, z = 110
    sketch.MapMode = "FlatFace"
    doc.recompute()
    cell, path = simple_cell(doc, sketch, markers=[(5, 0, 110)])
    positions = [m.target.position_mm for m in api.generate(cell).moves()]
    np.testing.assert_allclose(positions[1], (0, 0, 110), atol=1e-6)
    np.testing.assert_allclose(positions[2], (10, 0, 110), atol=1e-6)


def test_path_with_its_own_calibration_frame(doc):
    sketch = sketch_of(doc, polyline([(0, 0), (100, 0)]))
    cell, path = simple_cell(doc, sketch, markers=[(50, 0, 0)])
    other = api.make_calibration_frame(doc, cell, FreeCAD.Placement(V(0, 100, 0), FreeCAD.Rotation()),
                                       name="Fixture2")
    path.CalibrationFrame = other
    program = api.generate(cell)
    assert set(program.frames) == {"Fixture2"}
    np.testing.assert_allclose(program.moves()[1].target.position_mm, (0, -100, 0), atol=1e-9)


def test_marker_at_a_junction_sets_the_segment_that_starts_there(doc):
    sketch = sketch_of(doc, polyline([(0, 0), (50, 0), (50, 50)]))
    cell = api.make_cell(doc)
    api.make_calibration_frame(doc, cell, FreeCAD.Placement())
    api.make_path(doc, cell, sketch)
    api.make_tool_marker(doc, cell, down_placement((0, 0, 0)))
    api.make_tool_marker(doc, cell, down_placement((50, 0, 0), travel=(0, 1, 0)))
    moves = api.generate(cell).moves()
    along = [m for m in moves if m.role in (ir.ROLE_PATH, ir.ROLE_REORIENT)]
    assert [m.role for m in along] == [ir.ROLE_PATH, ir.ROLE_REORIENT, ir.ROLE_PATH]
    np.testing.assert_allclose(along[1].target.T_b_t[:3, 0], (0, 1, 0), atol=1e-9)


def test_marker_linked_explicitly_may_stand_off_the_path(doc):
    sketch = sketch_of(doc, polyline([(0, 0), (50, 0), (50, 50)]))
    cell, path = simple_cell(doc, sketch, markers=[(25, 0, 0)])
    # A marker drawn 200 mm away, beside the part, linked to segment 2: only its orientation counts.
    api.make_tool_marker(doc, cell, down_placement((300, 300, 200), travel=(0, 1, 0)),
                         path=path, segment=2)
    moves = api.generate(cell).moves()
    last = [m for m in moves if m.role == ir.ROLE_PATH][-1]
    np.testing.assert_allclose(last.target.position_mm, (50, 50, 0), atol=1e-9)
    np.testing.assert_allclose(last.target.T_b_t[:3, 0], (0, 1, 0), atol=1e-9)
