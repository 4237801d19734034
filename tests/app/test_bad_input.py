"""Every bad input gets one typed error naming the object and the fix, and
nothing is written."""

import os

import numpy as np
import pytest

import FreeCAD
import Part
from CadRobotWB import api
from CadRobotWB.errors import (FrameError, GeometryError, InputError, MarkerError, RiskAreaError,
                               UnknownNameError)
from helpers import V, down_placement, polyline, simple_cell, sketch_of


def export_fails(cell, tmp_path, error, *words, post="abb_rapid"):
    """Export must raise `error` whose message holds every word, and write nothing."""
    out = tmp_path / "out"
    with pytest.raises(error) as caught:
        api.export(cell, post=post, output_dir=str(out))
    message = str(caught.value)
    for word in words:
        assert word in message, message
    assert not out.exists() or not os.listdir(out)
    return caught.value


def test_empty_sketch(doc):
    sketch = sketch_of(doc, [], name="Empty")
    cell = api.make_cell(doc)
    count = len(doc.Objects)
    with pytest.raises(GeometryError, match="'Empty' has no edges"):
        api.make_path(doc, cell, sketch)
    assert len(doc.Objects) == count   # the half-made path was removed


def test_edges_that_do_not_connect(doc):
    sketch = sketch_of(doc, [Part.LineSegment(V(0, 0, 0), V(10, 0, 0)),
                             Part.LineSegment(V(11, 0, 0), V(20, 0, 0))], name="Gappy")
    with pytest.raises(GeometryError) as caught:
        api.make_path(doc, api.make_cell(doc), sketch)
    message = str(caught.value)
    assert "Gappy.Edge1" in message and "Gappy.Edge2" in message and "1.000 mm" in message


def test_zero_length_segment(doc):
    wire = doc.addObject("Part::Feature", "Wire")
    wire.Shape = Part.Compound([Part.makeLine(V(0, 0, 0), V(10, 0, 0)),
                                Part.makeLine(V(10, 0, 0), V(10, 0.001, 0)),
                                Part.makeLine(V(10, 0.001, 0), V(20, 0.001, 0))])
    with pytest.raises(GeometryError, match="Wire.Edge2"):
        api.make_path(doc, api.make_cell(doc), wire)


def test_segments_before_the_first_tool_marker(doc, tmp_path):
    sketch = sketch_of(doc, polyline([(0, 0), (50, 0), (50, 50), (100, 50)]))
    cell, path = simple_cell(doc, sketch, markers=[(100, 50, 0), (75, 50, 0)])   # both on segment 3
    error = export_fails(cell, tmp_path, MarkerError, "Path 'Path': segments 1-2 (Sketch.Edge1 to "
                         "Sketch.Edge2) come before its first tool marker 'ToolMarker' (on segment 3)",
                         "Place a tool marker on segment 1", "or move 'ToolMarker' onto segment 1")
    assert error.obj_name == path.Name and "\n" not in str(error)


def test_path_without_a_tool_marker(doc, tmp_path):
    sketch = sketch_of(doc, polyline([(0, 0), (50, 0), (50, 50)]))
    cell, path = simple_cell(doc, sketch, markers=[])
    export_fails(cell, tmp_path, MarkerError, "Path 'Path' has no tool marker, so segments 1-2 "
                 "(Sketch.Edge1 to Sketch.Edge2) have no tool orientation. Place one on segment 1")


def test_marker_far_from_every_path(doc, tmp_path):
    sketch = sketch_of(doc, polyline([(0, 0), (50, 0)]))
    cell, path = simple_cell(doc, sketch, markers=[(25, 0, 0)])
    api.make_tool_marker(doc, cell, down_placement((25, 3, 0)), name="Stray")
    export_fails(cell, tmp_path, MarkerError, "'Stray'", "3.000 mm", "tolerance 0.100 mm")


def test_two_markers_disagreeing_on_one_segment(doc, tmp_path):
    sketch = sketch_of(doc, polyline([(0, 0), (50, 0)]))
    cell, path = simple_cell(doc, sketch, markers=[(10, 0, 0)])
    tilted = api.tool_placement(V(40, 0, 0), V(1, 0, 0), V(0, 0, 1), 90.0, 15.0)
    # Kept on purpose (make_tool_marker refuses it by default), as an old document may hold it.
    api.make_tool_marker(doc, cell, tilted, name="Tilted", on_conflict="keep")
    export_fails(cell, tmp_path, MarkerError, "'ToolMarker'", "'Tilted'", "15.00°")


@pytest.mark.parametrize("first, last, words", [
    (2, 5, ("segments 2-5", "segments 1-2")),
    (0, 1, ("segments 0-1", "segments 1-2")),
    (2, 1, ("FirstSegment 2 comes after LastSegment 1",)),
])
def test_risk_area_outside_the_path_or_not_consecutive(doc, tmp_path, first, last, words):
    sketch = sketch_of(doc, polyline([(0, 0), (50, 0), (50, 50)]))
    cell, path = simple_cell(doc, sketch, markers=[(25, 0, 0), (50, 25, 0)])
    api.make_risk_area(doc, cell, path, first, last, name="Bend")
    export_fails(cell, tmp_path, RiskAreaError, "'Bend'", *words)


def test_missing_calibration_frame(doc, tmp_path):
    sketch = sketch_of(doc, polyline([(0, 0), (50, 0)]))
    cell = api.make_cell(doc, name="Lonely")
    api.make_path(doc, cell, sketch)
    api.make_tool_marker(doc, cell, down_placement((25, 0, 0)))
    export_fails(cell, tmp_path, FrameError, "'Lonely'", "no calibration frame")


def test_deleted_calibration_frame(doc, tmp_path):
    sketch = sketch_of(doc, polyline([(0, 0), (50, 0)]))
    cell, path = simple_cell(doc, sketch, markers=[(25, 0, 0)])
    doc.removeObject(cell.CalibrationFrame.Name)
    doc.recompute()
    export_fails(cell, tmp_path, FrameError, "'CalibrationFrame'", "was deleted")


def test_deleted_path_of_a_risk_area(doc, tmp_path):
    sketch = sketch_of(doc, polyline([(0, 0), (50, 0), (50, 50)]))
    cell, path = simple_cell(doc, sketch, markers=[(25, 0, 0), (50, 25, 0)])
    api.make_risk_area(doc, cell, path, 1, 2, name="Orphan")
    other = api.make_path(doc, cell, sketch, name="Again")
    doc.removeObject(path.Name)
    doc.recompute()
    assert other.Name in [o.Name for o in cell.Group]
    export_fails(cell, tmp_path, RiskAreaError, "'Orphan'", "deleted")


def test_unknown_post_and_robot(doc, tmp_path):
    sketch = sketch_of(doc, polyline([(0, 0), (50, 0)]))
    cell, path = simple_cell(doc, sketch, markers=[(25, 0, 0)])
    export_fails(cell, tmp_path, UnknownNameError, "'brand_x'", "abb_rapid", post="brand_x")
    count = len(doc.Objects)
    with pytest.raises(UnknownNameError, match="Unknown robot 'IRB9999'.*robots.* to list them, or import its URDF with `"):
        api.make_cell(doc, robot="IRB9999")
    assert len(doc.Objects) == count


def test_failed_export_keeps_existing_files(doc, tmp_path):
    sketch = sketch_of(doc, polyline([(0, 0), (50, 0), (50, 50)]))
    cell, path = simple_cell(doc, sketch, markers=[(25, 0, 0), (50, 25, 0)])
    written = api.export(cell, output_dir=str(tmp_path))
    before = open(written[0]).read()
    doc.removeObject(cell.CalibrationFrame.Name)
    with pytest.raises(FrameError):
        api.export(cell, output_dir=str(tmp_path))
    assert open(written[0]).read() == before
    assert sorted(os.listdir(tmp_path)) == [os.path.basename(written[0])]


def test_frame_placement_must_be_a_placement_or_matrix(doc):
    cell = api.make_cell(doc)
    with pytest.raises(Exception, match="FreeCAD.Placement or a 4x4 matrix"):
        api.make_calibration_frame(doc, cell, (1, 2, 3))
    assert cell.CalibrationFrame is None and FreeCAD.ActiveDocument is not None


def test_marker_segment_out_of_range_or_without_its_path(doc, tmp_path):
    sketch = sketch_of(doc, polyline([(0, 0), (50, 0)]))
    cell, path = simple_cell(doc, sketch, markers=[(25, 0, 0)])
    wrong = api.make_tool_marker(doc, cell, down_placement((25, 0, 0)), name="Far", path=path, segment=4)
    export_fails(cell, tmp_path, MarkerError, "'Far'", "segment 4", "has 1 segments")
    wrong.Segment = 1
    wrong.Path = None
    api.make_path(doc, cell, sketch_of(doc, polyline([(0, 100), (50, 100)]), name="Other"))
    export_fails(cell, tmp_path, MarkerError, "'Far'", "names no path", "has 2 paths")


def _matrix(rotation_block):
    T = np.eye(4)
    T[:3, :3] = rotation_block
    T[:3, 3] = (10.0, 20.0, 30.0)
    return T


#: 4x4 matrices that are no rigid transform, and the word that says why.
NOT_RIGID = [
    ("zero rotation", _matrix(np.zeros((3, 3))), "zero column"),
    ("scale", _matrix(2.0 * np.eye(3)), "column lengths 2, 2, 2"),
    ("shear", _matrix([[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]), "column lengths"),
    ("shear, unit columns", _matrix([[1, np.sqrt(0.5), 0], [0, np.sqrt(0.5), 0], [0, 0, 1]]), "shears"),
    ("mirror", _matrix(np.diag([1.0, 1.0, -1.0])), "mirror (determinant -1)"),
    ("nan", _matrix(np.diag([1.0, np.nan, 1.0])), "NaN or infinite"),
    ("projection", np.vstack([np.eye(4)[:3], [0, 0, 1, 1]]), "last row"),
]


def _makers(doc):
    cell = api.make_cell(doc, name="Host")
    return cell, {
        "make_cell": (lambda T: api.make_cell(doc, name="Robot", placement=T), "Cell 'Robot'"),
        "make_calibration_frame": (lambda T: api.make_calibration_frame(doc, cell, T, name="Datum"),
                                   "Calibration frame 'Datum'"),
        "make_tool_marker": (lambda T: api.make_tool_marker(doc, cell, T, name="Torch1"),
                             "Tool marker 'Torch1'"),
        "set_robot_placement": (lambda T: api.set_robot_placement(cell, T), "Cell 'Host'"),
    }


@pytest.mark.parametrize("maker", ["make_cell", "make_calibration_frame", "make_tool_marker",
                                   "set_robot_placement"])
@pytest.mark.parametrize("case, T, word", NOT_RIGID, ids=[c[0] for c in NOT_RIGID])
def test_a_placement_that_is_not_rigid_is_refused_naming_the_object(doc, maker, case, T, word):
    cell, makers = _makers(doc)
    make, name = makers[maker]
    count, host = len(doc.Objects), FreeCAD.Placement(cell.Placement)
    with pytest.raises(InputError) as caught:
        make(T)
    message = str(caught.value)
    kind = "robot base placement" if name.startswith("Cell") else "placement"
    assert message.startswith("%s: the %s is not a rigid transform: " % (name, kind)) and word in message
    assert "array(" not in message
    assert len(doc.Objects) == count and cell.Placement == host
    for matrix in (FreeCAD.Matrix(*np.asarray(T, dtype=float).ravel()), np.asarray(T).tolist()):
        with pytest.raises(InputError, match="not a rigid transform"):
            make(matrix)                      # as a FreeCAD.Matrix and as nested lists too


def test_a_rigid_matrix_is_taken_as_given(doc):
    R = FreeCAD.Rotation(FreeCAD.Vector(1, 2, 3), 40.0)
    T = np.array(FreeCAD.Placement(V(10, 20, 30), R).toMatrix().A).reshape(4, 4)
    frame = api.make_calibration_frame(doc, api.make_cell(doc), T)
    assert np.allclose(np.array(frame.Placement.toMatrix().A).reshape(4, 4), T, atol=1e-12)


def test_a_marker_with_a_nan_coordinate_is_named_in_the_export_error(doc, tmp_path):
    sketch = sketch_of(doc, polyline([(0, 0), (50, 0)]))
    cell, path = simple_cell(doc, sketch, markers=[(25, 0, 0)])
    marker = cell.Group[-1]
    marker.Label = "NanTorch"
    marker.Placement = FreeCAD.Placement(V(25, float("nan"), 0), marker.Placement.Rotation)
    error = export_fails(cell, tmp_path, MarkerError, "Tool marker 'NanTorch' (ToolMarker)",
                         "NaN or infinite")
    assert error.obj_name == marker.Name


@pytest.mark.parametrize("deviation, words", [
    ((0, 0, float("nan"), 0, 0, 0), ["deviation", "not finite", "value 3 of 6"]),
    (_matrix(2.0 * np.eye(3)), ["deviation", "scales"]),
    ((1, 2, 3), ["deviation", "(x, y, z, rx, ry, rz)"]),
])
def test_a_bad_deviation_is_refused_before_the_run(seam_cell, deviation, words):
    with pytest.raises(InputError) as caught:
        api.simulate(seam_cell, "laser", deviation=deviation)
    for word in words:
        assert word in str(caught.value)


@pytest.mark.parametrize("rate, words", [(0.0, ">= 0.1"), (float("nan"), "finite"), (1000.0, "<= 100")])
def test_a_rate_outside_what_the_simulation_can_run_is_refused(seam_cell, rate, words):
    with pytest.raises(InputError, match=words):
        api.simulate(seam_cell, "laser", rate_hz=rate)


def test_an_empty_post_name_is_not_the_default(doc, tmp_path):
    sketch = sketch_of(doc, polyline([(0, 0), (50, 0)]))
    cell, _ = simple_cell(doc, sketch, markers=[(25, 0, 0)])
    export_fails(cell, tmp_path, UnknownNameError, "Unknown post-processor ''", post="")


@pytest.mark.parametrize("call, words", [
    (lambda doc, cell, sketch: api.make_path(doc, cell, sketch, speed_mm_s=float("nan"), name="Fast"),
     "Path 'Fast': speed_mm_s must be a finite number > 0"),
    (lambda doc, cell, sketch: api.make_path(doc, cell, sketch, speed_mm_s=0.0), "> 0, not 0.0"),
    (lambda doc, cell, sketch: api.make_tool_marker(doc, cell, down_placement((25, 0, 0)), segment=1.5),
     "Tool marker 'ToolMarker': segment must be a whole number >= 0, not 1.5"),
    (lambda doc, cell, sketch: api.make_risk_area(doc, cell, cell.Group[1], 1, float("inf")),
     "Risk area 'RiskArea': last_segment must be a whole number"),
    (lambda doc, cell, sketch: api.make_risk_area(doc, cell, cell.Group[1], 1, 1, step_mm=-2.0),
     "step_mm must be a finite number >= 0"),
])
def test_api_numbers_are_checked_before_an_object_is_added(doc, call, words):
    sketch = sketch_of(doc, polyline([(0, 0), (50, 0)]))
    cell, _ = simple_cell(doc, sketch, markers=[(25, 0, 0)])
    count = len(doc.Objects)
    with pytest.raises(InputError) as caught:
        call(doc, cell, sketch)
    assert words in str(caught.value)
    assert len(doc.Objects) == count


def test_place_robot_refuses_a_margin_that_is_not_a_finite_angle(doc):
    sketch = sketch_of(doc, polyline([(0, 0), (50, 0)]))
    cell, _ = simple_cell(doc, sketch, markers=[(25, 0, 0)])
    with pytest.raises(InputError, match="margin_deg must be a finite number >= 0 and <= 180, not nan"):
        api.place_robot(cell, region=(-1000, -100, -800, 100), margin_deg=float("nan"))
