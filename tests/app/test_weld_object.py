"""The Weld document object: api.make_weld on real cells, the library pick from the
faces, the woven preview, save and reopen, and every refusal naming the weld.

Library values checked here are those of the plan's table (issue 22, section (c)):
fillet_t6 = Daihen OTC CPTX-i 400-2W, plate 6 mm: 250-280 A -> 265 A, 26-29 V -> 27.5 V,
40-50 cm/min -> 45 cm/min = 7.5 mm/s; fillet_t4.5: 190-230 A -> 210 A, 22-24 V -> 23 V;
butt_t9 = Panasonic YD-400VP1YHD, 9 mm: 320-340 A -> 330 A, 32-34 V -> 33 V, 0.40-0.50
m/min -> 7.5 mm/s, welded from both sides.
"""

import numpy as np
import pytest

import FreeCAD
import Part
from CadRobotWB import api
from CadRobotWB.core.welding import Tracking, Weave, WeldSchedule, WeldSpec
from CadRobotWB.errors import CadRobotError
from CadRobotWB.objects import reader
from CadRobotWB.objects import weld as weld_object
from helpers import ROOT_Z_MM, WEB_MM, fillet_cell, polyline, sketch_of

V = FreeCAD.Vector
ZIGZAG = {"pattern": "zigzag", "width_mm": 4.0, "frequency_hz": 1.0}


@pytest.fixture(scope="module")
def fillet():
    doc = FreeCAD.newDocument("WeldObject")
    cell, path, web = fillet_cell(doc)
    yield doc, cell, path, web
    if doc.Name in FreeCAD.listDocuments():
        FreeCAD.closeDocument(doc.Name)


@pytest.fixture
def fresh(fillet):
    """The fillet document with the welds of each test removed after it."""
    doc = fillet[0]
    before = {o.Name for o in doc.Objects}
    yield fillet
    for obj in list(doc.Objects):
        if obj.Name not in before:
            doc.removeObject(obj.Name)
    doc.recompute()


def test_the_default_schedule_is_the_librarys_for_the_fillet_and_the_thinner_plate(fresh):
    doc, cell, path, web = fresh
    weld = api.make_weld(doc, cell, path)
    assert weld in cell.Group and weld.Path == path and (weld.FirstSegment, weld.LastSegment) == (0, 0)
    assert weld.Schedule == "fillet_t6"
    assert (weld.Current, weld.Voltage, float(weld.TravelSpeed)) == (265.0, 27.5, 7.5)
    assert "Daihen" in weld.ScheduleSource and "6 mm" in weld.ScheduleSource
    note = weld.ScheduleNote
    assert "fillet (T) joint between Base.Face" in note and "Web.Face" in note, note
    assert "The thinner plate is 6.0 mm thick. Picked fillet_t6" in note, note
    assert (weld.WeavePattern, weld.Tracking) == ("None", "None")
    # a 4.5 mm web: the thinner plate is the web, and the row follows it
    web.Width = 4.5
    web.Placement.Base = V(0, -4.5, ROOT_Z_MM)
    doc.recompute()
    try:
        thinner = api.make_weld(doc, cell, path, name="Thin")
    finally:
        web.Width = WEB_MM
        web.Placement.Base = V(0, -WEB_MM, ROOT_Z_MM)
        doc.recompute()
    assert (thinner.Schedule, thinner.Current, thinner.Voltage) == ("fillet_t4.5", 210.0, 23.0)
    assert "4.5 mm thick" in thinner.ScheduleNote


def test_a_tube_on_a_plate_is_as_thick_as_its_wall_not_both_walls():
    """A tube of 100 mm outside diameter and 5 mm wall standing on a 10 mm plate, welded
    all round its foot: the thinner plate is the 5 mm wall (the probe across the wall
    leaves the solid after 5 mm; across the bore it would add the far wall: 10 mm), so
    the library's row is fillet_t4.5 (210 A), not fillet_t9 (290 A)."""
    doc = FreeCAD.newDocument("TubeOnPlate")
    try:
        plate = doc.addObject("Part::Feature", "Plate")
        plate.Shape = Part.makeBox(200, 200, 10, V(-100, -100, 0))
        tube = doc.addObject("Part::Feature", "Tube")
        tube.Shape = Part.makeCylinder(50, 100, V(0, 0, 10)).cut(Part.makeCylinder(45, 100, V(0, 0, 10)))
        doc.recompute()
        foot = next("Edge%d" % k for k, e in enumerate(tube.Shape.Edges, 1)
                    if abs(e.BoundBox.ZMax - 10) < 1e-6 and abs(e.BoundBox.XLength - 100) < 1e-6)
        cell = api.make_cell(doc, robot="ABB_IRB2400", name="TubeCell")
        api.make_calibration_frame(doc, cell, FreeCAD.Placement())
        path = api.make_path(doc, cell, (tube, foot), name="Foot")
        api.make_tool_markers_auto(doc, cell, path)
        weld = api.make_weld(doc, cell, path)
        assert "The thinner plate is 5.0 mm thick" in weld.ScheduleNote, weld.ScheduleNote
        assert (weld.Schedule, weld.Current) == ("fillet_t4.5", 210.0)
    finally:
        FreeCAD.closeDocument(doc.Name)


def test_the_paper_seam_cell_is_a_butt_joint_and_the_note_says_it_is_welded_from_both_sides(seam_cell):
    path = reader.cell_paths(seam_cell)[0]
    weld = api.make_weld(seam_cell.Document, seam_cell, path)
    assert (weld.Schedule, weld.Current, weld.Voltage, float(weld.TravelSpeed)) == ("butt_t9", 330.0, 33.0,
                                                                                     7.5)
    assert "butt joint between Plate" in weld.ScheduleNote and "8.0 mm thick" in weld.ScheduleNote
    assert "both sides" in weld.ScheduleNote, weld.ScheduleNote


def _lateral(points):
    """Signed distance of woven points from the root line (x axis at z 8) across the
    seam, along the weave's lateral axis Y = Z x X, with the tool Z = -(0, 1, 1)/sqrt 2
    (into the corner) and X = +x: Y = (0, -1, 1)/sqrt 2 (right of the travel)."""
    return (-points[:, 1] + (points[:, 2] - ROOT_Z_MM)) / np.sqrt(2.0)


def test_the_preview_is_the_woven_centre_line_with_the_weaves_width_and_period(fresh):
    doc, cell, path, _ = fresh
    weld = api.make_weld(doc, cell, path, weave=ZIGZAG)
    points = np.array([[v.X, v.Y, v.Z] for v in weld.Shape.Vertexes])
    assert points[0] == pytest.approx([50, 0, ROOT_Z_MM]) and points[-1] == pytest.approx([250, 0, ROOT_Z_MM])
    lateral = _lateral(points)
    # the weave is across the seam only: no part along the tool axis (x-free, lateral plane)
    assert np.allclose(points[:, 1] + points[:, 2] - ROOT_Z_MM, 0.0, atol=1e-9)
    inside = (points[:, 0] > 60) & (points[:, 0] < 240)          # past the half-cycle ramps
    assert lateral[inside].max() == pytest.approx(2.0, abs=1e-9)   # width 4 mm peak to peak
    assert lateral[inside].min() == pytest.approx(-2.0, abs=1e-9)
    # one cycle per second at 7.5 mm/s: the right ends 7.5 mm apart along the seam
    right_ends = points[inside][np.isclose(lateral[inside], 2.0, atol=1e-9), 0]
    assert np.diff(right_ends) == pytest.approx(7.5, abs=1e-6)
    plain = api.make_weld(doc, cell, path, first_segment=2, name="Plain")
    assert plain.Shape.Length == pytest.approx(100.0) and plain.Shape.BoundBox.XMin == pytest.approx(150.0)


def test_a_schedule_dict_and_a_weave_dict_round_trip_through_the_object_and_the_reader(fresh):
    doc, cell, path, _ = fresh
    schedule = {"voltage_v": 24.0, "current_a": 200.0, "wire_mm": 1.2, "travel_speed_mm_s": 6.0,
                "gas_postflow_s": 1.0, "job_number": 7, "gas": "M21"}
    weave = {"pattern": "triangle", "width_mm": 5.0, "length_mm": 3.0, "dwell_left_s": 0.1,
             "dwell_right_s": 0.1, "angle_deg": 10.0, "height_mm": 2.0}
    weld = api.make_weld(doc, cell, path, schedule=schedule, weave=weave, first_segment=1,
                         last_segment=2, tracking="arc", name="Dict")
    assert weld.Schedule == "Custom" and weld.ScheduleNote == ""
    expected = WeldSpec("Dict", "Dict", WeldSchedule.from_dict(schedule), Weave.from_dict(weave),
                        Tracking("arc"), 1, 2)
    # 200 A of 1.2 mm wire: 200 x 1 in/min per A = 5.08 m/min, shown as 5.1 (Miller's rule)
    assert expected.schedule.wire_feed_m_min == 5.1 and expected.schedule.wire_feed_estimated
    [read] = reader.read_cell(cell).paths[0].welds
    assert read == expected
    [row] = api.list_welds(doc)
    assert row["schedule"] == expected.schedule.as_dict() and row["weave"] == expected.weave.as_dict()
    # 200 mm at 6 mm/s plus 0.3 s of crater fill
    assert (row["length_mm"], row["tracking"]) == (200.0, "arc")
    assert row["arc_time_s"] == pytest.approx(200 / 6 + 0.3, abs=1e-3)
    # a dict without travel speed welds at the path's speed
    assert float(api.make_weld(doc, cell, path, schedule={"voltage_v": 20, "wire_feed_m_min": 4},
                               name="PathSpeed").TravelSpeed) == 10.0


def test_a_saved_weld_reopens_with_its_values_and_gains_properties_it_lacked(doc, tmp_path):
    cell, path, _ = fillet_cell(doc)
    weld = api.make_weld(doc, cell, path, weave=ZIGZAG, name="Saved")
    before = reader.read_cell(cell).paths[0].welds
    shape_length = weld.Shape.Length
    weld.removeProperty("WeaveHeight")          # as saved by a version without it
    file_name, cell_name = str(tmp_path / "weld.FCStd"), cell.Name
    doc.saveAs(file_name)
    FreeCAD.closeDocument(doc.Name)
    reopened = FreeCAD.openDocument(file_name)
    try:
        saved = reopened.getObject("Saved")
        assert type(saved.Proxy) is weld_object.Weld and saved.Proxy.Type == "CadRobot::Weld"
        assert "WeaveHeight" in saved.PropertiesList and float(saved.WeaveHeight) == 0.0
        reopened.recompute()
        cell_again = reopened.getObject(cell_name)
        assert reader.read_cell(cell_again).paths[0].welds == before
        assert saved.Shape.Length == pytest.approx(shape_length)
    finally:
        FreeCAD.closeDocument(reopened.Name)


REFUSALS = [
    (dict(schedule={"volts": 20}), "Weld 'Bad': unknown key 'volts'"),
    (dict(schedule={"current_a": 200}), "Weld 'Bad': voltage_v is missing"),
    (dict(schedule="fillet_t99"), "Weld 'Bad': schedule 'fillet_t99' is not in the library: use one of"),
    (dict(weave={"pattern": "sine"}), "Weld 'Bad': pattern 'sine' is unknown"),
    (dict(weave={"width_mm": 4, "frequency_hz": 2, "dwell_left_s": 0.3, "dwell_right_s": 0.3}),
     "Weld 'Bad': its dwells (0.6 s) fill the whole weave cycle (0.5 s): lower the frequency"),
    (dict(first_segment=2, last_segment=3), "Weld 'Bad': segments 2-3 are not on path 'Root"),
    (dict(first_segment=2, last_segment=1), "Weld 'Bad': segments 2-1 are not on path"),
    (dict(tracking="arc"), "Weld 'Bad': through-arc tracking needs a weave"),
]


def test_every_refusal_is_one_line_naming_the_weld_and_leaves_the_document_as_it_was(fresh):
    doc, cell, path, _ = fresh
    names = [o.Name for o in doc.Objects]
    for keywords, start in REFUSALS:
        with pytest.raises(CadRobotError) as caught:
            api.make_weld(doc, cell, path, name="Bad", **keywords)
        message = str(caught.value)
        assert message.startswith(start) and "\n" not in message, (keywords, message)
        assert [o.Name for o in doc.Objects] == names
    # a path on the base plate's top, away from the web: a surface, no library row
    top = sketch_of(doc, polyline([(50, -50), (250, -50)]), FreeCAD.Placement(V(0, 0, ROOT_Z_MM),
                                                                              FreeCAD.Rotation()))
    on_top = api.make_path(doc, cell, top, name="OnTop")
    api.make_tool_marker(doc, cell, api.tool_placement(V(100, -50, ROOT_Z_MM), V(1, 0, 0), V(0, 0, 1),
                                                       90.0, 0.0), path=on_top)
    with pytest.raises(CadRobotError, match=r"^Weld 'Top': the library has no schedule for it: Path "
                                            r"OnTop lies on Face6 of Base.* Give schedule= a library"):
        api.make_weld(doc, cell, on_top, name="Top")


def test_values_changed_in_the_property_editor_are_checked_when_the_cell_is_read(fresh):
    doc, cell, path, _ = fresh
    weld = api.make_weld(doc, cell, path, schedule="fillet_t6", name="Edited")
    for prop, value, start in (("Voltage", 0.0, "Weld 'Edited': voltage_v is missing"),
                               ("Current", 900.0, "Weld 'Edited': current_a 900 A is outside"),
                               ("LastSegment", 3, "Weld 'Edited' welds segments 1-3, but path 'Root"),
                               ("Tracking", "Arc", "Weld 'Edited': through-arc tracking needs a weave"),
                               ("WeavePattern", "circle", None)):
        old = getattr(weld, prop)
        setattr(weld, prop, value)
        try:
            if start is None:
                assert reader.read_cell(cell).paths[0].welds[0].weave.pattern == "circle"
                continue
            with pytest.raises(CadRobotError) as caught:
                reader.read_cell(cell)
            assert str(caught.value).startswith(start), str(caught.value)
            assert caught.value.obj_name == weld.Name     # the GUI selects it
        finally:
            setattr(weld, prop, old)
    weld.Path = None
    with pytest.raises(CadRobotError, match=r"^Weld 'Edited' refers to a path 'Root\w*' that was deleted"):
        reader.read_cell(cell)


def test_a_library_schedule_changed_in_the_property_editor_is_named_changed(fresh):
    doc, cell, path, _ = fresh
    weld = api.make_weld(doc, cell, path, schedule="fillet_t6", name="Edited")
    assert weld.Schedule == "fillet_t6"
    weld.Voltage = 26.0
    weld.Current = 250.0
    assert weld.Schedule == "fillet_t6 (changed)"
    assert reader.read_cell(cell).paths[0].welds[0].schedule.name == "fillet_t6 (changed)"
