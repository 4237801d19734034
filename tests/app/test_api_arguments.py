"""Wrong arguments to the scripting API: one CadRobotError naming the function and the
argument, and the documents left as they were.

Every public function of :mod:`CadRobotWB.api` that takes arguments is called with at
least three wrong ones: a wrong type, None, and where the argument is a document or one
of its objects a closed document, a deleted object, an object of another document or an
object of the wrong kind (issue 21, item 6). One FreeCAD process, one set of documents
for the whole file (module fixture); each refusal comes before any work, so each case
takes milliseconds.
"""

import os
import re
import types

import FreeCAD
import numpy as np
import pytest

from CadRobotWB import api
from CadRobotWB.errors import CadRobotError
from helpers import V, down_placement, polyline, sketch_of, simple_cell

PLACE = FreeCAD.Placement()


def _closed_document_and_cell():
    """A document with a cell, closed: both are stale Python objects now."""
    closed = FreeCAD.newDocument("ApiArgsClosed")
    cell = api.make_cell(closed, name="ClosedCell")
    FreeCAD.closeDocument(closed.Name)
    return closed, cell


def _deleted(doc, make):
    """An object made by `make(doc)` and then removed from `doc`."""
    obj = make(doc)
    doc.removeObject(obj.Name)
    return obj


@pytest.fixture(scope="module")
def w(tmp_path_factory):
    """The documents every case reads: a cell with a frame, a two-segment path and a
    marker; another document with a sketch, a cell and a box; stale objects."""
    doc = FreeCAD.newDocument("ApiArgs")
    other = FreeCAD.newDocument("ApiArgsOther")
    try:
        sketch = sketch_of(doc, polyline([(0, 0), (50, 0), (50, 30)]))
        cell, path = simple_cell(doc, sketch, markers=[(25, 0, 0)])
        box = doc.addObject("Part::Box", "Box")
        box.Placement = FreeCAD.Placement(V(-500, -500, -700), FreeCAD.Rotation())
        doc.recompute()
        closed_doc, closed_cell = _closed_document_and_cell()
        other_sketch = sketch_of(other, polyline([(0, 0), (10, 0)]), name="OtherSketch")
        other_cell = api.make_cell(other, name="OtherCell")
        other_box = other.addObject("Part::Box", "OtherBox")
        other.recompute()
        yield types.SimpleNamespace(
            doc=doc, other=other, cell=cell, path=path, sketch=sketch, box=box,
            frame=cell.CalibrationFrame, marker=[o for o in cell.Group if o.Label == "ToolMarker"][0],
            closed_doc=closed_doc, closed_cell=closed_cell, other_sketch=other_sketch,
            other_cell=other_cell, other_box=other_box,
            other_path=api.make_path(other, other_cell, other_sketch, name="OtherPath"),
            other_frame=api.make_calibration_frame(other, other_cell, PLACE, name="OtherFrame"),
            deleted_cell=_deleted(doc, lambda d: api.make_cell(d, name="Gone")),
            deleted_sketch=_deleted(doc, lambda d: sketch_of(d, polyline([(0, 0), (5, 0)]), name="Gone2")),
            out=str(tmp_path_factory.mktemp("out")))
    finally:
        for name in ("ApiArgs", "ApiArgsOther"):
            if name in FreeCAD.listDocuments():
                FreeCAD.closeDocument(name)


def _snapshot(document):
    """What a refused call must leave as it was, read without a recompute."""
    out = []
    for obj in document.Objects:
        props = [p for p in ("Placement", "Group", "ToolType", "ToolMass", "ToolTCP", "CadPoints",
                             "UseTaught", "Source", "Speed", "Path", "Segment", "PostProcessor")
                 if p in obj.PropertiesList]
        out.append((obj.Name, obj.Label) + tuple(repr(getattr(obj, p)) for p in props))
    return out


def _wrong_cells(function, keywords=lambda w: {}):
    """Calls of api.`function` whose cell is None, deleted, of a closed document or a sketch,
    with `keywords(w)` for its other arguments."""
    return [(function, "cell", lambda w, stale=stale: getattr(api, function)(
        getattr(w, stale) if stale else None, **keywords(w)))
        for stale in (None, "deleted_cell", "closed_cell", "sketch")]


#: (function, argument at fault, call). Each call is wrong in that one argument.
CASES = [
    ("make_cell", "doc", lambda w: api.make_cell(None)),
    ("make_cell", "doc", lambda w: api.make_cell(w.closed_doc)),
    ("make_cell", "doc", lambda w: api.make_cell("ApiArgs")),
    ("make_cell", "robot", lambda w: api.make_cell(w.doc, robot=None)),
    ("make_cell", "robot", lambda w: api.make_cell(w.doc, robot=2400)),
    ("make_cell", "name", lambda w: api.make_cell(w.doc, name=None)),
    ("make_cell", "name", lambda w: api.make_cell(w.doc, name=["Cell"])),
    ("make_cell", "placement", lambda w: api.make_cell(w.doc, placement="origin")),
    ("make_cell", "tool", lambda w: api.make_cell(w.doc, tool=3)),
    *_wrong_cells("set_tool", lambda w: dict(tool="Straight torch")),
    ("set_tool", "tool", lambda w: api.set_tool(w.cell, tool=7)),
    ("set_tool", "body", lambda w: api.set_tool(w.cell, body=w.other_box, tcp=PLACE)),
    ("set_tool", "body", lambda w: api.set_tool(w.cell, body="Box", tcp=PLACE)),
    ("set_tool", "mass_kg", lambda w: api.set_tool(w.cell, mass_kg="2")),
    ("set_tool", "mass_kg", lambda w: api.set_tool(w.cell, mass_kg=True)),
    ("set_tool", "cog_mm", lambda w: api.set_tool(w.cell, cog_mm="0,0,50")),
    ("set_tool", "tcp", lambda w: api.set_tool(w.cell, body=w.box, tcp="tip")),
    ("make_calibration_frame", "doc", lambda w: api.make_calibration_frame(None, w.cell, PLACE)),
    ("make_calibration_frame", "doc", lambda w: api.make_calibration_frame(w.closed_doc, w.cell, PLACE)),
    ("make_calibration_frame", "cell", lambda w: api.make_calibration_frame(w.doc, w.other_cell, PLACE)),
    ("make_calibration_frame", "cell", lambda w: api.make_calibration_frame(w.doc, w.deleted_cell, PLACE)),
    ("make_calibration_frame", "cell", lambda w: api.make_calibration_frame(w.doc, None, PLACE)),
    ("make_calibration_frame", "placement", lambda w: api.make_calibration_frame(w.doc, w.cell, None)),
    ("make_calibration_frame", "name", lambda w: api.make_calibration_frame(w.doc, w.cell, PLACE, name=5)),
    ("make_path", "doc", lambda w: api.make_path(None, w.cell, w.sketch)),
    ("make_path", "doc", lambda w: api.make_path(w.closed_doc, w.cell, w.sketch)),
    ("make_path", "cell", lambda w: api.make_path(w.doc, w.closed_cell, w.sketch)),
    ("make_path", "cell", lambda w: api.make_path(w.doc, w.sketch, w.sketch)),
    ("make_path", "source", lambda w: api.make_path(w.doc, w.cell, None)),
    ("make_path", "source", lambda w: api.make_path(w.doc, w.cell, w.other_sketch)),
    ("make_path", "source", lambda w: api.make_path(w.doc, w.cell, w.deleted_sketch)),
    ("make_path", "source", lambda w: api.make_path(w.doc, w.cell, [(w.sketch, 3)])),
    ("make_path", "speed_mm_s", lambda w: api.make_path(w.doc, w.cell, w.sketch, speed_mm_s="10")),
    ("make_path", "speed_mm_s", lambda w: api.make_path(w.doc, w.cell, w.sketch, speed_mm_s=None)),
    ("make_path", "name", lambda w: api.make_path(w.doc, w.cell, w.sketch, name=None)),
    ("make_path", "blend", lambda w: api.make_path(w.doc, w.cell, w.sketch, blend=True)),
    ("make_path", "ApproachDistance", lambda w: api.make_path(w.doc, w.cell, w.sketch, ApproachDistance="far")),
    ("make_path", "CalibrationFrame", lambda w: api.make_path(w.doc, w.cell, w.sketch,
                                                              CalibrationFrame=w.other_frame)),
    ("make_path", "CalibrationFrame", lambda w: api.make_path(w.doc, w.cell, w.sketch, CalibrationFrame=w.cell)),
    ("make_path", "Nope", lambda w: api.make_path(w.doc, w.cell, w.sketch, Nope=1)),
    ("make_path", "source", lambda w: api.make_path(w.doc, w.cell, [])),
    ("make_tool_marker", "doc", lambda w: api.make_tool_marker(None, w.cell, down_placement((25, 0, 0)))),
    ("make_tool_marker", "cell", lambda w: api.make_tool_marker(w.doc, w.deleted_cell, down_placement((25, 0, 0)))),
    ("make_tool_marker", "cell", lambda w: api.make_tool_marker(w.doc, w.other_cell, down_placement((25, 0, 0)))),
    ("make_tool_marker", "placement", lambda w: api.make_tool_marker(w.doc, w.cell, None)),
    ("make_tool_marker", "path", lambda w: api.make_tool_marker(w.doc, w.cell, down_placement((25, 0, 0)),
                                                                path=w.other_path, segment=1)),
    ("make_tool_marker", "path", lambda w: api.make_tool_marker(w.doc, w.cell, down_placement((25, 0, 0)),
                                                                path="Path", segment=1)),
    ("make_tool_marker", "segment", lambda w: api.make_tool_marker(w.doc, w.cell, down_placement((25, 0, 0)),
                                                                   segment="1")),
    ("make_tool_marker", "shape", lambda w: api.make_tool_marker(w.doc, w.cell, down_placement((25, 0, 0)),
                                                                 shape=None)),
    ("make_tool_marker", "on_conflict", lambda w: api.make_tool_marker(w.doc, w.cell, down_placement((25, 0, 0)),
                                                                       on_conflict=["keep"])),
    ("make_risk_area", "doc", lambda w: api.make_risk_area(w.closed_doc, w.cell, w.path, 1, 2)),
    ("make_risk_area", "cell", lambda w: api.make_risk_area(w.doc, None, w.path, 1, 2)),
    ("make_risk_area", "path", lambda w: api.make_risk_area(w.doc, w.cell, None, 1, 2)),
    ("make_risk_area", "path", lambda w: api.make_risk_area(w.doc, w.cell, w.other_path, 1, 2)),
    ("make_risk_area", "path", lambda w: api.make_risk_area(w.doc, w.cell, w.sketch, 1, 2)),
    ("make_risk_area", "first_segment", lambda w: api.make_risk_area(w.doc, w.cell, w.path, "1", 2)),
    ("make_risk_area", "last_segment", lambda w: api.make_risk_area(w.doc, w.cell, w.path, 1, None)),
    ("make_risk_area", "step_mm", lambda w: api.make_risk_area(w.doc, w.cell, w.path, 1, 2, step_mm="2")),
    ("make_risk_area", "at_corner", lambda w: api.make_risk_area(w.doc, w.cell, w.path, 1, 2, at_corner=1)),
    ("tool_placement", "point", lambda w: api.tool_placement(None, V(1, 0, 0), V(0, 0, 1))),
    ("tool_placement", "travel_dir", lambda w: api.tool_placement(V(), "x", V(0, 0, 1))),
    ("tool_placement", "surface_normal", lambda w: api.tool_placement(V(), V(1, 0, 0), 1.0)),
    ("tool_placement", "work_angle_deg", lambda w: api.tool_placement(V(), V(1, 0, 0), V(0, 0, 1), "90")),
    ("find_cells", "doc", lambda w: api.find_cells(None)),
    ("find_cells", "doc", lambda w: api.find_cells(w.closed_doc)),
    ("find_cells", "doc", lambda w: api.find_cells(w.cell)),
    *_wrong_cells("generate"),
    ("generate", "progress", lambda w: api.generate(w.cell, progress="yes")),
    *_wrong_cells("check"),
    ("check", "collisions", lambda w: api.check(w.cell, collisions="no")),
    ("check", "progress", lambda w: api.check(w.cell, progress=1)),
    *_wrong_cells("simulate"),
    ("simulate", "sensor", lambda w: api.simulate(w.cell, sensor=None)),
    ("simulate", "rate_hz", lambda w: api.simulate(w.cell, rate_hz="5")),
    ("simulate", "deviation", lambda w: api.simulate(w.cell, deviation="0,5,2,0,0,1")),
    ("simulate", "deviation", lambda w: api.simulate(w.cell, deviation=(0, 5, 2))),
    ("simulate", "controller", lambda w: api.simulate(w.cell, controller=None)),
    ("simulate", "weld", lambda w: api.simulate(w.cell, sensor="arc", weld=1)),
    ("simulate", "foreign_objects", lambda w: api.simulate(w.cell, foreign_objects=[w.deleted_sketch])),
    ("simulate", "foreign_objects", lambda w: api.simulate(w.cell, foreign_objects=[w.other_box])),
    *_wrong_cells("export", lambda w: dict(output_dir=w.out)),
    ("export", "output_dir", lambda w: api.export(w.cell, output_dir=None)),
    ("export", "output_dir", lambda w: api.export(w.cell, output_dir=3)),
    ("export", "output_dir", lambda w: api.export(w.cell, output_dir="")),
    ("export", "output_dir", lambda w: api.export(w.cell, output_dir=w.out + "\0x")),
    ("export", "post", lambda w: api.export(w.cell, post=5, output_dir=w.out)),
    ("export", "options", lambda w: api.export(w.cell, output_dir=w.out, options="date=now")),
    ("export", "check_first", lambda w: api.export(w.cell, output_dir=w.out, check_first="no")),
    *_wrong_cells("program_files"),
    ("program_files", "post", lambda w: api.program_files(w.cell, post=["abb_rapid"])),
    ("program_files", "options", lambda w: api.program_files(w.cell, options=[("date", 1)])),
    *_wrong_cells("default_post_name"),
    *_wrong_cells("other_maker_note", lambda w: dict(post="abb_rapid")),
    ("other_maker_note", "post", lambda w: api.other_maker_note(w.cell, None)),
    ("robot", "name", lambda w: api.robot(None)),
    ("robot", "name", lambda w: api.robot(2400)),
    ("robot", "name", lambda w: api.robot(["ABB_IRB2400"])),
    ("import_robot", "path", lambda w: api.import_robot(None)),
    ("import_robot", "path", lambda w: api.import_robot(3)),
    ("import_robot", "name", lambda w: api.import_robot(os.devnull, name=7)),
    ("import_robot", "j23_factor", lambda w: api.import_robot(os.devnull, j23_factor="1")),
    ("save_weld_schedule", "name", lambda w: api.save_weld_schedule(None, {"voltage_v": 20})),
    ("save_weld_schedule", "name", lambda w: api.save_weld_schedule(6, {"voltage_v": 20})),
    ("save_weld_schedule", "values", lambda w: api.save_weld_schedule("mine", None)),
    ("save_weld_schedule", "values", lambda w: api.save_weld_schedule("mine", "fillet_t6")),
    ("save_weld_schedule", "values", lambda w: api.save_weld_schedule("mine", {"name": "other"})),
    ("edit_robot", "name", lambda w: api.edit_robot(None)),
    ("edit_robot", "name", lambda w: api.edit_robot(5)),
    ("edit_robot", "joint_speed_deg_s", lambda w: api.edit_robot("ABB_IRB2400", joint_speed_deg_s=100)),
    *_wrong_cells("place_robot", lambda w: dict(region=(0, 0, 1, 1))),
    ("place_robot", "count", lambda w: api.place_robot(w.cell, region=(-1000, -100, -800, 100), count="3")),
    ("place_robot", "count", lambda w: api.place_robot(w.cell, region=(-1000, -100, -800, 100), count=None)),
    ("place_robot", "region", lambda w: api.place_robot(w.cell, region="everywhere")),
    ("place_robot", "region", lambda w: api.place_robot(w.cell, region=("0", "0", "1", "1"))),
    ("place_robot", "z_mm", lambda w: api.place_robot(w.cell, region=(-1000, -100, -800, 100), z_mm=5)),
    ("place_robot", "weights", lambda w: api.place_robot(w.cell, region=(-1000, -100, -800, 100),
                                                         weights="even")),
    ("place_robot", "collisions", lambda w: api.place_robot(w.cell, region=(-1000, -100, -800, 100),
                                                            collisions="no")),
    ("place_robot", "face", lambda w: api.place_robot(w.cell, face=(w.other_box, "Face6"))),
    ("place_robot", "progress", lambda w: api.place_robot(w.cell, region=(-1000, -100, -800, 100),
                                                          progress="yes")),
    *_wrong_cells("set_robot_placement", lambda w: dict(placement=PLACE)),
    ("set_robot_placement", "placement", lambda w: api.set_robot_placement(w.cell, None)),
    ("frame_placement_from_points", "origin", lambda w: api.frame_placement_from_points(None, V(1, 0, 0), V(0, 1, 0))),
    ("frame_placement_from_points", "on_x", lambda w: api.frame_placement_from_points(V(), "x", V(0, 1, 0))),
    ("frame_placement_from_points", "in_xy", lambda w: api.frame_placement_from_points(V(), V(1, 0, 0), 1)),
    ("frame_placement_from_selection", "items", lambda w: api.frame_placement_from_selection(None)),
    ("frame_placement_from_selection", "items", lambda w: api.frame_placement_from_selection(
        [(w.deleted_sketch, "Vertex1"), (w.box, "Vertex2"), (w.box, "Vertex3")])),
    ("frame_placement_from_selection", "items", lambda w: api.frame_placement_from_selection(
        [(w.box, 1), (w.box, "Vertex2"), (w.box, "Vertex3")])),
    ("frame_placement_from_selection", "near", lambda w: api.frame_placement_from_selection(
        [(w.box, "Face1"), (w.box, "Edge1")], near="here")),
    ("teach_calibration_frame", "frame", lambda w: api.teach_calibration_frame(None, [V()] * 3, [V()] * 3)),
    ("teach_calibration_frame", "frame", lambda w: api.teach_calibration_frame(w.cell, [V()] * 3, [V()] * 3)),
    ("teach_calibration_frame", "cad_points", lambda w: api.teach_calibration_frame(w.frame, None, [V()] * 3)),
    ("teach_calibration_frame", "measured_points", lambda w: api.teach_calibration_frame(w.frame, [V()] * 3, 5)),
    ("teach_calibration_frame", "measured_points", lambda w: api.teach_calibration_frame(w.frame, [V()] * 3,
                                                                                         [None] * 3)),
    ("taught_frame", "frame", lambda w: api.taught_frame(None)),
    ("taught_frame", "frame", lambda w: api.taught_frame(w.deleted_cell)),
    ("taught_frame", "frame", lambda w: api.taught_frame(w.marker)),
    ("edge_tool_placement", "obj", lambda w: api.edge_tool_placement(None, "Edge1")),
    ("edge_tool_placement", "obj", lambda w: api.edge_tool_placement(w.deleted_sketch, "Edge1")),
    ("edge_tool_placement", "edge_name", lambda w: api.edge_tool_placement(w.box, 1)),
    ("edge_tool_placement", "face", lambda w: api.edge_tool_placement(w.box, "Edge1", face="Face1")),
    ("edge_tool_placement", "work_angle_deg", lambda w: api.edge_tool_placement(w.box, "Edge1",
                                                                                work_angle_deg="90")),
    ("edge_tool_placement", "path", lambda w: api.edge_tool_placement(w.box, "Edge1", path=w.sketch)),
    ("make_tool_markers_auto", "doc", lambda w: api.make_tool_markers_auto(None, w.cell, w.path)),
    ("make_tool_markers_auto", "cell", lambda w: api.make_tool_markers_auto(w.doc, w.deleted_cell, w.path)),
    ("make_tool_markers_auto", "path", lambda w: api.make_tool_markers_auto(w.doc, w.cell, w.other_path)),
    ("make_tool_markers_auto", "work_angle_deg", lambda w: api.make_tool_markers_auto(w.doc, w.cell, w.path,
                                                                                      work_angle_deg="45")),
    ("make_tool_markers_auto", "shape", lambda w: api.make_tool_markers_auto(w.doc, w.cell, w.path, shape=3)),
    ("marker_segment", "cell", lambda w: api.marker_segment(None, w.marker)),
    ("marker_segment", "marker", lambda w: api.marker_segment(w.cell, None)),
    ("marker_segment", "marker", lambda w: api.marker_segment(w.cell, w.path)),
    *_wrong_cells("suggest_risk_areas"),
    ("suggest_risk_areas", "threshold_deg", lambda w: api.suggest_risk_areas(w.cell, threshold_deg="10")),
    ("suggest_risk_areas", "at_corner", lambda w: api.suggest_risk_areas(w.cell, at_corner=2)),
    *_wrong_cells("robot_base"),
    *_wrong_cells("taught_frame_labels"),
    *_wrong_cells("taught_frame_note", lambda w: dict(frame_label="Frame")),
    ("taught_frame_note", "frame_label", lambda w: api.taught_frame_note(w.cell, None)),
    ("tool_marker_conflict", "cell", lambda w: api.tool_marker_conflict(None, w.marker)),
    ("tool_marker_conflict", "marker", lambda w: api.tool_marker_conflict(w.cell, w.other_cell)),
    ("tool_marker_conflict", "path", lambda w: api.tool_marker_conflict(w.cell, placement=PLACE, path="Path")),
    ("tool_marker_conflict", "segment", lambda w: api.tool_marker_conflict(w.cell, placement=PLACE, path=w.path,
                                                                           segment="2")),
    ("resolve_marker_conflict", "cell", lambda w: api.resolve_marker_conflict(w.deleted_cell, w.marker, "next")),
    ("resolve_marker_conflict", "marker", lambda w: api.resolve_marker_conflict(w.cell, None, "next")),
    ("resolve_marker_conflict", "action", lambda w: api.resolve_marker_conflict(w.cell, w.marker, None)),
    ("auto_marker_conflicts", "cell", lambda w: api.auto_marker_conflicts(None, w.path)),
    ("auto_marker_conflicts", "path", lambda w: api.auto_marker_conflicts(w.cell, w.other_path)),
    ("auto_marker_conflicts", "placed", lambda w: api.auto_marker_conflicts(w.cell, w.path, placed=5)),
    ("risk_area_step", "cell", lambda w: api.risk_area_step(None, w.path, 1, 2)),
    ("risk_area_step", "path", lambda w: api.risk_area_step(w.cell, None, 1, 2)),
    ("risk_area_step", "first_segment", lambda w: api.risk_area_step(w.cell, w.path, None, 2)),
    ("risk_area_step", "last_segment", lambda w: api.risk_area_step(w.cell, w.path, 1, "2")),
    *_wrong_cells("program_move_count"),
    *_wrong_cells("sensor_fit"),
    ("sensor_fit", "path", lambda w: api.sensor_fit(w.cell, path=w.path)),
    ("make_weld", "doc", lambda w: api.make_weld(None, w.cell, w.path)),
    ("make_weld", "cell", lambda w: api.make_weld(w.doc, None, w.path)),
    ("make_weld", "cell", lambda w: api.make_weld(w.doc, w.deleted_cell, w.path)),
    ("make_weld", "cell", lambda w: api.make_weld(w.doc, w.other_cell, w.path)),
    ("make_weld", "path", lambda w: api.make_weld(w.doc, w.cell, w.other_path)),
    ("make_weld", "path", lambda w: api.make_weld(w.doc, w.cell, w.sketch)),
    ("make_weld", "schedule", lambda w: api.make_weld(w.doc, w.cell, w.path, schedule=5)),
    ("make_weld", "weave", lambda w: api.make_weld(w.doc, w.cell, w.path, weave="zigzag")),
    ("make_weld", "first_segment", lambda w: api.make_weld(w.doc, w.cell, w.path, first_segment="1")),
    ("make_weld", "last_segment", lambda w: api.make_weld(w.doc, w.cell, w.path, last_segment=1.5)),
    ("make_weld", "tracking", lambda w: api.make_weld(w.doc, w.cell, w.path, tracking="TAST")),
    ("make_weld", "name", lambda w: api.make_weld(w.doc, w.cell, w.path, name=None)),
    ("make_weld", "position", lambda w: api.make_weld(w.doc, w.cell, w.path, position="PF")),
    *_wrong_cells("add_positioner", lambda w: dict(kind="turntable", placement=PLACE, parts=[w.box])),
    ("add_positioner", "kind", lambda w: api.add_positioner(w.cell, "carousel", PLACE, [w.box])),
    ("add_positioner", "placement", lambda w: api.add_positioner(w.cell, "turntable", "0", [w.box])),
    ("add_positioner", "parts", lambda w: api.add_positioner(w.cell, "turntable", PLACE, w.box)),
    ("add_positioner", "parts", lambda w: api.add_positioner(w.cell, "turntable", PLACE, [w.other_box])),
    ("add_positioner", "model", lambda w: api.add_positioner(w.cell, "turntable", PLACE, [w.box], model=1)),
    ("add_positioner", "name", lambda w: api.add_positioner(w.cell, "turntable", PLACE, [w.box], name=None)),
    *_wrong_cells("add_track", lambda w: dict(length_mm=1000.0, placement=PLACE)),
    ("add_track", "length_mm", lambda w: api.add_track(w.cell, "1000", PLACE)),
    ("add_track", "placement", lambda w: api.add_track(w.cell, 1000.0, None)),
    ("add_track", "model", lambda w: api.add_track(w.cell, 1000.0, PLACE, model=3)),
    ("add_track", "name", lambda w: api.add_track(w.cell, 1000.0, PLACE, name=None)),
    ("list_welds", "doc", lambda w: api.list_welds(None)),
    ("list_welds", "doc", lambda w: api.list_welds(w.closed_doc)),
    ("list_welds", "doc", lambda w: api.list_welds(w.cell)),
    ("mechanism_names", "kind", lambda w: api.mechanism_names("crane")),
    ("mechanism_names", "kind", lambda w: api.mechanism_names(3)),
    ("matrix_from_placement", "placement", lambda w: api.matrix_from_placement(None)),
    ("matrix_from_placement", "placement", lambda w: api.matrix_from_placement(np.eye(4))),
    ("matrix_from_placement", "placement", lambda w: api.matrix_from_placement(w.cell)),
    ("placement_from_matrix", "T", lambda w: api.placement_from_matrix(None)),
    ("placement_from_matrix", "T", lambda w: api.placement_from_matrix("eye")),
    ("placement_from_matrix", "T", lambda w: api.placement_from_matrix(np.eye(3))),
]


def _ids():
    seen = {}
    out = []
    for function, argument, _ in CASES:
        key = "%s-%s" % (function, argument)
        seen[key] = seen.get(key, 0) + 1
        out.append("%s-%d" % (key, seen[key]))
    return out


@pytest.mark.parametrize("function, argument, call", CASES, ids=_ids())
def test_a_wrong_argument_is_one_line_naming_the_function_and_the_argument(w, function, argument, call):
    before = [_snapshot(w.doc), _snapshot(w.other)]
    with pytest.raises(CadRobotError) as caught:
        call(w)
    message = str(caught.value)
    assert re.match(r"%s( on '[^']+'(?: \(\w+\))?)?: " % function, message) and argument in message, message
    assert "\n" not in message and len(message) < 400, message
    assert [_snapshot(w.doc), _snapshot(w.other)] == before
    assert os.listdir(w.out) == []


def test_every_public_function_with_arguments_has_cases():
    """A function added to the API without cases here is a failure, not a gap."""
    import inspect
    covered = {function for function, _, _ in CASES}
    without_arguments = {"tool_names", "post_names", "robot_names", "user_post_dirs",
                         "weld_schedules"}
    public = {name for name in api.__all__ if inspect.isfunction(getattr(api, name))}
    assert public - without_arguments - covered == set()


def test_numpy_numbers_tuples_and_path_objects_are_still_taken(doc, tmp_path):
    """The checks refuse types, not the other spellings of a right value."""
    import pathlib
    sketch = sketch_of(doc, polyline([(0, 0), (50, 0), (50, 30)]))
    cell, _ = simple_cell(doc, sketch, markers=[(25, 0, 0)])
    path = api.make_path(doc, cell, [(sketch, ("Edge1", "Edge2"))], speed_mm_s=np.float64(12.5),
                         blend=np.float32(1.0), name="Numpy")
    assert float(path.Speed) == 12.5 and path.Blend == "Zone"
    T = np.asarray(down_placement((25, 0, 0)).toMatrix().A).reshape(4, 4).tolist()
    marker = api.make_tool_marker(doc, cell, T, path=path, segment=np.int64(1), on_conflict="keep")
    assert marker.Segment == 1
    area = api.make_risk_area(doc, cell, path, np.int64(1), 2.0, step_mm=np.float64(0.5))
    assert (area.FirstSegment, area.LastSegment) == (1, 2)
    pl = api.tool_placement((1, 2, 3), np.array([1.0, 0, 0]), V(0, 0, 1), np.float32(90), 0)
    assert tuple(pl.Base) == (1, 2, 3)
    doc.removeObject(path.Name)
    doc.removeObject(area.Name)
    doc.removeObject(marker.Name)
    written = api.export(cell, output_dir=pathlib.Path(tmp_path), check_first=np.bool_(False))
    assert written and all(os.path.dirname(f) == str(tmp_path) for f in written)
