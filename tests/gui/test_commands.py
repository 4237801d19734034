"""The toolbar commands that build a cell, in the real FreeCAD window.

Every command runs on a prepared selection of a 100 x 60 x 20 mm box at the
origin; the objects it makes are checked against numbers derived by hand
from the box (frames from its vertices, tool axes from the bisector of the
two faces at an edge), then undone and redone. The lines each command hands
to FreeCADGui.doCommand are replayed in FreeCADCmd on the document saved
before, and must give the same objects.
"""

import json
import math
import os
import re
import subprocess

import numpy as np
import pytest

import FreeCAD
import FreeCADGui
from PySide import QtGui

from conftest import REPO, close_panels, process_events

from CadRobotWB import api, preferences
from CadRobotWB.commands import base as command_base
from CadRobotWB.commands import TOOLBARS
from CadRobotWB.gui import calibration_panel, new_cell_panel, risk_area_panel
from CadRobotWB.objects import base as objects_base
from CadRobotWB.objects import reader

V = FreeCAD.Vector
S2 = math.sqrt(0.5)
BOX_MM = (100.0, 60.0, 20.0)
# Top edges of the box, as (start, end) corners: front (y = 0), right (x = 100), back (y = 60).
FRONT = (V(0, 0, 20), V(100, 0, 20))
RIGHT = (V(100, 0, 20), V(100, 60, 20))
BACK = (V(100, 60, 20), V(0, 60, 20))
# Tool +Z (into the work) at those edges, work angle 90: minus the bisector of the two faces.
Z_FRONT = V(0, S2, -S2)
Z_RIGHT = V(-S2, 0, -S2)
Z_BACK = V(0, -S2, -S2)

MY_COMMANDS = ("CadRobot_NewCell", "CadRobot_CalibrationFrame", "CadRobot_MarkPath",
               "CadRobot_ToolMarker", "CadRobot_AutoToolMarkers", "CadRobot_RiskArea", "CadRobot_Weld")


# --- fixtures and helpers --------------------------------------------------------------------


@pytest.fixture
def box_doc(gui_doc):
    """The box, no cell yet; the CadRobot workbench active, nothing selected."""
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    box = gui_doc.addObject("Part::Box", "Box")
    box.Length, box.Width, box.Height = BOX_MM
    gui_doc.recompute()
    FreeCADGui.Selection.clearSelection()
    close_panels()
    yield gui_doc
    FreeCADGui.Selection.clearSelection()
    close_panels()


@pytest.fixture
def cell_doc(box_doc):
    """The box and a cell (robot base 1 m in front of the box), its torch square to the
    travel (TravelAngle 0, not the 10 deg push of a new cell): the marker tests measure
    the edges' geometry."""
    cell = api.make_cell(box_doc, placement=FreeCAD.Placement(V(0, -1000, 0), FreeCAD.Rotation(V(0, 0, 1), 90)))
    cell.TravelAngle = 0.0
    box_doc.recompute()
    FreeCADGui.Selection.clearSelection()
    process_events()
    return box_doc


@pytest.fixture
def prefs():
    """Set preferences for one test, restored afterwards."""
    saved = {}

    def set_pref(name, value):
        saved.setdefault(name, preferences.get(name))
        preferences.set(name, value)
    yield set_pref
    for name, value in saved.items():
        preferences.set(name, value)


@pytest.fixture
def journal(monkeypatch):
    """Every line handed to FreeCADGui.doCommand, in order."""
    lines = []
    original = FreeCADGui.doCommand

    def recording(line):
        lines.append(line)
        return original(line)
    monkeypatch.setattr(FreeCADGui, "doCommand", recording)
    return lines


def cell_of(doc):
    return objects_base.objects_of_type(doc, "Cell")[0]


def element_name(obj, kind, *points):
    """Name of the vertex at a point / edge between two points / face through three points."""
    elements = {"Vertex": obj.Shape.Vertexes, "Edge": obj.Shape.Edges, "Face": obj.Shape.Faces}[kind]
    for k, element in enumerate(elements, 1):
        corners = [v.Point for v in element.Vertexes]
        if all(any((c - p).Length < 1e-7 for c in corners) for p in points):
            return "%s%d" % (kind, k)
    raise AssertionError("no %s through %s" % (kind, points))


def select(obj, sub="", point=None):
    if point is None:
        FreeCADGui.Selection.addSelection(obj.Document.Name, obj.Name, sub)
    else:
        FreeCADGui.Selection.addSelection(obj.Document.Name, obj.Name, sub, point.x, point.y, point.z)


def active(name):
    process_events()
    return FreeCADGui.Command.get(name).isActive()


def run(name):
    FreeCADGui.runCommand(name)
    process_events()


def names(doc):
    return [o.Name for o in doc.Objects]


def assert_vec(actual, expected, tol=1e-9):
    assert (V(actual) - V(expected)).Length < tol, "%s != %s" % (actual, expected)


def assert_axes(placement, x=None, y=None, z=None, tol=1e-9):
    rotation = placement.Rotation
    for axis, expected in ((V(1, 0, 0), x), (V(0, 1, 0), y), (V(0, 0, 1), z)):
        if expected is not None:
            assert_vec(rotation.multVec(axis), expected, tol)


def undo_redo(doc, made):
    """One undo removes exactly `made` (names); one redo brings them back."""
    after = names(doc)
    before = [n for n in after if n not in made]
    doc.undo()
    doc.recompute()
    assert names(doc) == before
    doc.redo()
    doc.recompute()
    assert names(doc) == after


def same_placement(a, b, tol):
    return np.allclose(np.array(a.toMatrix().A), np.array(b.toMatrix().A), atol=tol)


def new_objects(doc, before):
    return [n for n in names(doc) if n not in before]


def error_text():
    box = command_base._message_box
    assert box is not None and box.isVisible(), "no message shown"
    return box.text()


def selected_names():
    return [o.Name for o in FreeCADGui.Selection.getSelection()]


# --- the toolbar ------------------------------------------------------------------------------

def test_commands_are_in_the_toolbar_in_order_with_icons_and_tips(box_doc):
    process_events()
    toolbar_names = TOOLBARS[0][1]
    assert toolbar_names[:7] == list(MY_COMMANDS)
    assert toolbar_names.index("CadRobot_RiskArea") < toolbar_names.index("CadRobot_Check")
    for name in MY_COMMANDS:
        assert name in FreeCADGui.listCommands()
        info = FreeCADGui.Command.get(name).getInfo()
        assert info["pixmap"].endswith(name + ".svg") and os.path.isfile(info["pixmap"])
        assert info["menuText"] and len(info["toolTip"]) > 40 and info["statusTip"]
    toolbar = FreeCADGui.getMainWindow().findChild(QtGui.QToolBar, "CadRobot")
    texts = [a.text() for a in toolbar.actions() if a.text()]
    wanted = ["New cell", "Calibration frame", "Mark path", "Tool marker",
              "Tool markers on every segment", "Risk area", "Weld"]
    assert [t for t in texts if t in wanted] == wanted


def test_icons_are_drawn(tmp_path):
    """Each icon renders to a 64x64 image with dark outlines and some colour."""
    from PySide import QtSvg
    for name in MY_COMMANDS:
        path = os.path.join(command_base.ICONS, name + ".svg")
        renderer = QtSvg.QSvgRenderer(path)
        assert renderer.isValid(), path
        image = QtGui.QImage(64, 64, QtGui.QImage.Format_ARGB32)
        image.fill(0)
        painter = QtGui.QPainter(image)
        renderer.render(painter)
        painter.end()
        drawn = [QtGui.QColor.fromRgba(image.pixel(x, y)) for y in range(64) for x in range(64)]
        opaque = [c for c in drawn if c.alpha() > 200]
        assert len(opaque) > 600, name
        assert sum(c.value() < 60 for c in opaque) > 100, name + ": no outline"
        assert sum(c.saturation() > 120 for c in opaque) > 100, name + ": no colour"


# --- New cell ---------------------------------------------------------------------------------

def test_new_cell_from_the_catalog_on_a_selected_vertex(box_doc, prefs):
    prefs("DefaultRobot", "KUKA_KR16")
    box = box_doc.getObject("Box")
    assert active("CadRobot_NewCell")
    corner = V(100, 60, 0)
    select(box, element_name(box, "Vertex", corner))
    run("CadRobot_NewCell")
    panel = new_cell_panel.active_panel()
    assert panel is not None and FreeCADGui.Control.activeDialog()
    assert panel.robot_name() == "KUKA_KR16"
    assert sorted(panel.visible_robots()) == sorted(api.robot_names())
    assert "KR 16" in panel.description.text() and "reach" in panel.description.text()
    assert (panel.x.value(), panel.y.value(), panel.z.value()) == (100.0, 60.0, 0.0)
    panel.select_robot("MOTOMAN_HP6")
    assert "HP6" in panel.description.text()
    panel.rotation.setValue(30.0)
    before = names(box_doc)
    assert panel.accept()
    process_events()
    assert new_cell_panel.active_panel() is None and not FreeCADGui.Control.activeDialog()
    made = new_objects(box_doc, before)
    assert len(made) == 1
    cell = box_doc.getObject(made[0])
    assert objects_base.type_of(cell) == "Cell" and cell.Robot == "MOTOMAN_HP6"
    assert cell.PostProcessor == "motoman_inform"
    assert_vec(cell.Placement.Base, corner)
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    assert_axes(cell.Placement, x=V(c, s, 0), y=V(-s, c, 0), z=V(0, 0, 1))
    undo_redo(box_doc, made)


def test_new_cell_reach_is_the_arm_stretched_out():
    # ABB IRB 2400 (OPW): wrist centre at a1 + sqrt(c3^2 + a2^2) + c2 = 100 + 767 + 705 mm
    # stretched out flat, the flange c4 = 85 mm beyond: about 1657 mm at most.
    reach = new_cell_panel.reach_mm("ABB_IRB2400")
    assert 1500 < reach <= 100 + math.hypot(755, 135) + 705 + 85 + 1e-6


def test_new_cell_is_greyed_out_without_a_document(box_doc):
    assert active("CadRobot_NewCell")
    others = [d for d in FreeCAD.listDocuments() if d != box_doc.Name]
    FreeCAD.closeDocument(box_doc.Name)
    process_events()
    if not others:
        assert not active("CadRobot_NewCell")


def test_new_cell_error_stays_in_the_panel(box_doc):
    run("CadRobot_NewCell")
    panel = new_cell_panel.active_panel()
    panel.name.setText("  ")
    before = names(box_doc)
    assert not panel.accept()
    assert "name" in panel.message.text() and names(box_doc) == before
    assert new_cell_panel.active_panel() is panel


# --- Calibration frame ------------------------------------------------------------------------

def test_calibration_frame_from_three_vertices(cell_doc):
    box, cell = cell_doc.getObject("Box"), cell_of(cell_doc)
    origin, on_x, in_xy = V(0, 0, 20), V(0, 60, 20), V(0, 0, 0)
    select(box, element_name(box, "Vertex", origin))
    select(box, element_name(box, "Vertex", on_x))
    assert not active("CadRobot_CalibrationFrame"), "two vertices do not make a frame"
    select(box, element_name(box, "Vertex", in_xy))
    assert active("CadRobot_CalibrationFrame")
    before = names(cell_doc)
    run("CadRobot_CalibrationFrame")
    made = new_objects(cell_doc, before)
    assert len(made) == 1
    frame = cell_doc.getObject(made[0])
    assert frame in cell.Group and cell.CalibrationFrame == frame
    # X towards on_x = +Y; in_xy lies at -Z from the origin, so Y = -Z and Z = X x Y = -X.
    assert_vec(frame.Placement.Base, origin)
    assert_axes(frame.Placement, x=V(0, 1, 0), y=V(0, 0, -1), z=V(-1, 0, 0))
    panel = calibration_panel.active_panel()
    assert panel is not None and panel.frame == frame, "the teaching panel opens on the new frame"
    close_panels()
    undo_redo(cell_doc, made)
    # The frame selected alone: the command opens its teaching panel, adds nothing.
    FreeCADGui.Selection.clearSelection()
    select(frame)
    assert active("CadRobot_CalibrationFrame")
    before = names(cell_doc)
    run("CadRobot_CalibrationFrame")
    assert names(cell_doc) == before and calibration_panel.active_panel().frame == frame


def test_calibration_frame_from_a_face_and_an_edge(cell_doc):
    box = cell_doc.getObject("Box")
    top = element_name(box, "Face", V(0, 0, 20), V(100, 0, 20), V(0, 60, 20))
    select(box, top, V(50, 30, 20))
    assert not active("CadRobot_CalibrationFrame"), "a face alone does not make a frame"
    select(box, element_name(box, "Edge", *FRONT), V(90, 0, 20))      # picked near the x = 100 end
    assert active("CadRobot_CalibrationFrame")
    before = names(cell_doc)
    run("CadRobot_CalibrationFrame")
    frame = cell_doc.getObject(new_objects(cell_doc, before)[0])
    assert_vec(frame.Placement.Base, V(100, 0, 20))
    assert_axes(frame.Placement, x=V(-1, 0, 0), y=V(0, -1, 0), z=V(0, 0, 1))


def test_calibration_frame_on_the_working_plane(cell_doc, monkeypatch):
    assert active("CadRobot_CalibrationFrame"), "nothing selected: the working plane"
    plane = FreeCAD.Placement(V(10, 20, 30), FreeCAD.Rotation(V(1, 0, 0), 90))

    class Plane:                              # FreeCAD 0.20's Draft working plane
        def getPlacement(self):
            return plane
    monkeypatch.setattr(FreeCAD, "DraftWorkingPlane", Plane(), raising=False)
    import WorkingPlane
    monkeypatch.delattr(WorkingPlane, "get_working_plane", raising=False)
    before = names(cell_doc)
    run("CadRobot_CalibrationFrame")
    frame = cell_doc.getObject(new_objects(cell_doc, before)[0])
    assert_vec(frame.Placement.Base, V(10, 20, 30))
    assert_axes(frame.Placement, x=V(1, 0, 0), y=V(0, 0, 1), z=V(0, -1, 0))
    close_panels()
    monkeypatch.setattr(FreeCAD, "DraftWorkingPlane", None, raising=False)
    FreeCADGui.Selection.clearSelection()          # (the new frame is selected)
    before = names(cell_doc)
    run("CadRobot_CalibrationFrame")
    frame = cell_doc.getObject(new_objects(cell_doc, before)[0])
    assert same_placement(frame.Placement, FreeCAD.Placement(), 1e-12), "no Draft plane: the XY plane"


def test_calibration_frame_error_is_one_message_with_the_object_selected(cell_doc):
    box = cell_doc.getObject("Box")
    select(box, element_name(box, "Face", V(0, 0, 20), V(100, 0, 20), V(0, 60, 20)), V(50, 30, 20))
    select(box, element_name(box, "Edge", V(0, 0, 0), V(0, 0, 20)), V(0, 0, 10))   # not in the face
    assert active("CadRobot_CalibrationFrame")
    before, undo_count = names(cell_doc), cell_doc.UndoCount
    run("CadRobot_CalibrationFrame")
    assert names(cell_doc) == before and cell_doc.UndoCount == undo_count
    text = error_text()
    assert "off the plane" in text and "Traceback" not in text
    assert selected_names() == ["Box"]
    assert calibration_panel.active_panel() is None


# --- Teaching ---------------------------------------------------------------------------------

def _teaching_data(cell, frame):
    """CAD points (box corners) and where a robot measures them when the real part sits
    2, -1, 0.5 mm off and turned 1 degree about Z from the drawing."""
    cad = [V(0, 0, 20), V(100, 0, 20), V(100, 60, 20), V(0, 60, 0)]
    deviation = FreeCAD.Placement(V(2, -1, 0.5), FreeCAD.Rotation(V(0, 0, 1), 1.0))
    T_r_u = cell.Placement.inverse()
    measured = [T_r_u.multVec(deviation.multVec(p)) for p in cad]
    T_r_b = T_r_u.multiply(deviation).multiply(frame.Placement)
    return cad, measured, T_r_b


def test_teaching_panel_fits_applies_and_undoes(cell_doc):
    cell = cell_of(cell_doc)
    frame = api.make_calibration_frame(cell_doc, cell, FreeCAD.Placement(V(0, 0, 20), FreeCAD.Rotation()))
    cad, measured, T_r_b = _teaching_data(cell, frame)
    panel = calibration_panel.edit(frame)
    assert panel is calibration_panel.active_panel() and panel.point_count() == 3
    # CAD points: two typed, two picked in the 3D view.
    box = cell_doc.getObject("Box")
    for row in (0, 1):
        panel.set_cad_point(row, tuple(cad[row]))
    panel.set_picking(True)
    panel.table.setCurrentCell(calibration_panel.table_row(2, False), 0)
    select(box, element_name(box, "Vertex", cad[2]))
    select(box, element_name(box, "Vertex", cad[3]))
    panel.set_picking(False)
    assert panel.point_count() == 4
    # Measured points pasted, one "x y z" line and three "x, y, z" lines.
    text = ["%r %r %r" % tuple(measured[0])] + ["%r, %r, %r" % tuple(m) for m in measured[1:]]
    panel.paste_text.setPlainText("\n".join(text) + "\n\n")
    assert panel.fill_measured_from_text() == 4
    got_cad, got_measured = panel.points()
    assert np.allclose(got_cad, [tuple(p) for p in cad], atol=1e-4)
    assert np.allclose(got_measured, [tuple(p) for p in measured], atol=1e-4)
    undo_count = cell_doc.UndoCount
    residuals = panel.fit()
    assert residuals is not None and len(residuals) == 4 and max(residuals) < 1e-3
    assert "RMS" in panel.result.text()
    # The frame's origin (0, 0, 20) lies on the deviation's Z axis: it moves by |(2, -1, 0.5)|.
    assert "2.29 mm and 1.00\u00b0" in panel.result.text()
    assert cell_doc.UndoCount == undo_count and not frame.UseTaught, "Fit changes nothing"
    assert panel.apply()
    assert frame.UseTaught and len(frame.CadPoints) == 4
    assert same_placement(frame.TaughtPlacement, T_r_b, 1e-6)
    assert cell_doc.UndoCount == undo_count + 1
    close_panels()
    cell_doc.undo()
    cell_doc.recompute()
    assert not frame.UseTaught and len(frame.CadPoints) == 0
    cell_doc.redo()
    cell_doc.recompute()
    assert frame.UseTaught and same_placement(frame.TaughtPlacement, T_r_b, 1e-6)
    # Reopened (a double-click), the panel shows what was taught.
    panel = calibration_panel.edit(frame)
    assert panel.point_count() == 4 and panel.use_taught.isChecked()
    assert panel.residuals is not None and panel.residuals[3] < 1e-3 and "4: 0.000" in panel.result.text()


def test_teaching_residuals_and_the_use_taught_box(cell_doc):
    cell = cell_of(cell_doc)
    frame = api.make_calibration_frame(cell_doc, cell, FreeCAD.Placement())
    cad = [V(0, 0, 0), V(100, 0, 0), V(0, 100, 0), V(100, 100, 0)]
    measured = [V(p.x, p.y, p.z) for p in cad]
    measured[3] = V(100, 100, 0.4)
    panel = calibration_panel.edit(frame)
    for row, (c, m) in enumerate(zip(cad, measured)):
        panel.set_cad_point(row, tuple(c))
        panel.set_measured_point(row, tuple(m))
    residuals = panel.fit()
    # One corner of a square 0.4 mm high: the best rigid fit tilts the square and spreads it,
    # a quarter of 0.4 mm at each corner (the four residuals are equal by symmetry).
    assert np.allclose(residuals, 0.1, atol=1e-3)
    assert "RMS 0.100 mm" in panel.result.text()
    panel.use_taught.setChecked(False)
    assert panel.accept()
    assert len(frame.MeasuredPoints) == 4 and not frame.UseTaught


def test_teaching_errors_stay_in_the_panel(cell_doc):
    cell = cell_of(cell_doc)
    frame = api.make_calibration_frame(cell_doc, cell, FreeCAD.Placement())
    panel = calibration_panel.edit(frame)
    panel.set_cad_point(0, (0, 0, 0))
    panel.set_measured_point(0, (0, 0, 0))
    panel.set_cad_point(1, (10, 0, 0))
    panel.set_measured_point(1, (10, 0, 0))
    undo_count = cell_doc.UndoCount
    FreeCADGui.Selection.clearSelection()
    assert not panel.accept()
    assert "three points" in panel.result.text() and calibration_panel.active_panel() is panel
    assert selected_names() == [frame.Name] and cell_doc.UndoCount == undo_count
    panel.set_cad_point(2, (20, 0, 0))           # collinear
    panel.set_measured_point(2, (20, 0, 0))
    assert not panel.apply() and "collinear" in panel.result.text().lower()
    panel.table.item(calibration_panel.table_row(2, True), 1).setText("abc")
    assert not panel.apply() and "Point 3" in panel.result.text()
    panel.paste_text.setPlainText("1 2 3\n4 5\n")
    assert panel.fill_measured_from_text() == 0 and "Line 2" in panel.result.text()
    assert cell_doc.UndoCount == undo_count and not frame.CadPoints


# --- Mark path --------------------------------------------------------------------------------

def test_mark_path_from_selected_edges_with_the_preferences(cell_doc, prefs):
    prefs("ApproachDistance", 33.0)
    prefs("InterpolationStep", 2.5)
    box = cell_doc.getObject("Box")
    top = element_name(box, "Face", V(0, 0, 20), V(100, 0, 20), V(0, 60, 20))
    select(box, top)
    assert active("CadRobot_MarkPath"), "a face gives its outer loop"
    FreeCADGui.Selection.clearSelection()
    front, right = element_name(box, "Edge", *FRONT), element_name(box, "Edge", *RIGHT)
    select(box, front)
    select(box, right)
    assert active("CadRobot_MarkPath")
    before = names(cell_doc)
    run("CadRobot_MarkPath")
    made = new_objects(cell_doc, before)
    assert len(made) == 1
    path = cell_doc.getObject(made[0])
    assert objects_base.type_of(path) == "RobotPath" and path in cell_of(cell_doc).Group
    assert [(o.Name, list(subs)) for o, subs in path.Source] == [("Box", [front, right])]
    assert path.SegmentCount == 2 and abs(float(path.PathLength) - 160.0) < 1e-9
    assert path.ApproachDistance == 33.0 and path.InterpolationStep == 2.5
    assert selected_names() == [path.Name]
    undo_redo(cell_doc, made)


def test_mark_path_round_a_selected_face(cell_doc):
    """A face's outer boundary, in the order its edges join: the box top is 100 x 60 mm."""
    box = cell_doc.getObject("Box")
    top = element_name(box, "Face", V(0, 0, 20), V(100, 0, 20), V(0, 60, 20))
    select(box, top)
    before = names(cell_doc)
    run("CadRobot_MarkPath")
    path = cell_doc.getObject(new_objects(cell_doc, before)[0])
    [(source, subs)] = path.Source
    assert source == box and len(subs) == 4 and len(set(subs)) == 4
    top_edges = [e for e in box.Shape.getElement(top).Edges]
    assert all(any(box.Shape.getElement(sub).isSame(e) for e in top_edges) for sub in subs)
    assert path.SegmentCount == 4 and abs(float(path.PathLength) - 320.0) < 1e-9


def test_mark_path_from_a_whole_sketch(cell_doc):
    import Part
    import Sketcher
    sketch = cell_doc.addObject("Sketcher::SketchObject", "Sketch")
    sketch.addGeometry(Part.LineSegment(V(0, 0, 0), V(50, 0, 0)))
    sketch.addGeometry(Part.LineSegment(V(50, 0, 0), V(50, 40, 0)))
    sketch.addConstraint(Sketcher.Constraint("Coincident", 0, 2, 1, 1))
    cell_doc.recompute()
    select(sketch)
    assert active("CadRobot_MarkPath")
    before = names(cell_doc)
    run("CadRobot_MarkPath")
    path = cell_doc.getObject(new_objects(cell_doc, before)[0])
    assert path.Source[0][0] == sketch and path.SegmentCount == 2
    assert abs(float(path.PathLength) - 90.0) < 1e-9


def test_mark_path_error_shows_one_message(cell_doc):
    box = cell_doc.getObject("Box")
    select(box, element_name(box, "Edge", *FRONT))
    select(box, element_name(box, "Edge", *BACK))          # not joined to the front edge
    before, undo_count = names(cell_doc), cell_doc.UndoCount
    run("CadRobot_MarkPath")
    assert names(cell_doc) == before and cell_doc.UndoCount == undo_count
    text = error_text()
    assert "Traceback" not in text and "mm" in text, text


# --- Tool marker ------------------------------------------------------------------------------

def test_tool_marker_on_a_box_edge_is_the_bisector(cell_doc):
    box, cell = cell_doc.getObject("Box"), cell_of(cell_doc)
    front = element_name(box, "Edge", *FRONT)
    select(box, front, V(30, 0, 20))
    select(box, element_name(box, "Edge", *RIGHT), V(100, 30, 20))
    assert not active("CadRobot_ToolMarker"), "two edges"
    FreeCADGui.Selection.clearSelection()
    select(box, front, V(30, 0, 20))
    assert active("CadRobot_ToolMarker")
    before = names(cell_doc)
    run("CadRobot_ToolMarker")
    made = new_objects(cell_doc, before)
    assert len(made) == 1
    marker = cell_doc.getObject(made[0])
    assert objects_base.type_of(marker) == "ToolMarker" and marker in cell.Group
    assert_vec(marker.Placement.Base, V(30, 0, 20))
    x = marker.Placement.Rotation.multVec(V(1, 0, 0))
    assert abs(abs(x.x) - 1) < 1e-9, "X along the edge"
    assert_axes(marker.Placement, z=Z_FRONT)
    assert_axes(marker.Placement, y=Z_FRONT.cross(x))
    assert selected_names() == [marker.Name], "selected, ready for Transform"
    undo_redo(cell_doc, made)


def test_tool_marker_with_a_face_and_the_cell_angles(cell_doc):
    box, cell = cell_doc.getObject("Box"), cell_of(cell_doc)
    cell.WorkAngle = 60.0
    select(box, element_name(box, "Edge", *RIGHT), V(100, 45, 20))
    select(box, element_name(box, "Face", V(0, 0, 20), V(100, 0, 20), V(0, 60, 20)), V(50, 30, 20))
    assert active("CadRobot_ToolMarker")
    before = names(cell_doc)
    run("CadRobot_ToolMarker")
    marker = cell_doc.getObject(new_objects(cell_doc, before)[0])
    assert_vec(marker.Placement.Base, V(100, 45, 20))
    # Normal +Z from the face; 60 degrees from the surface, leaning to -(d x n) for travel d.
    d = marker.Placement.Rotation.multVec(V(1, 0, 0))
    assert abs(abs(d.y) - 1) < 1e-9
    side = d.cross(V(0, 0, 1))
    expected_z = V(0, 0, -math.sin(math.radians(60))) + side * math.cos(math.radians(60))
    assert_axes(marker.Placement, z=expected_z)


def test_tool_marker_on_an_edge_of_a_path_follows_its_travel(cell_doc):
    box, cell = cell_doc.getObject("Box"), cell_of(cell_doc)
    path = api.make_path(cell_doc, cell, [(box, [element_name(box, "Edge", *e) for e in (FRONT, RIGHT)])])
    path.Reversed = True
    cell_doc.recompute()
    k = element_name(path, "Edge", *RIGHT)
    select(path, k, V(100, 20, 20))
    assert active("CadRobot_ToolMarker")
    before = names(cell_doc)
    run("CadRobot_ToolMarker")
    marker = cell_doc.getObject(new_objects(cell_doc, before)[0])
    assert_vec(marker.Placement.Base, V(100, 20, 20))
    assert_axes(marker.Placement, z=Z_RIGHT)
    # +X is the travel direction along the right edge, as the path's own (reversed) geometry runs.
    segments = reader.path_geometry(path)[0]
    k_right = [k for k, seg in enumerate(segments, 1) if abs(seg.start[0] - 100) + abs(seg.end[0] - 100) < 1e-9]
    assert len(k_right) == 1
    seg = segments[k_right[0] - 1]
    assert_vec(marker.Placement.Rotation.multVec(V(1, 0, 0)), V(*((seg.end - seg.start) / seg.length)))
    assert api.marker_segment(cell, marker) == (path, k_right[0])


def test_tool_marker_without_a_face_names_the_edge(cell_doc):
    import Part
    line = cell_doc.addObject("Part::Feature", "Wire")
    line.Shape = Part.makeLine(V(0, 200, 0), V(50, 200, 0))
    cell_doc.recompute()
    select(line, "Edge1", V(10, 200, 0))
    before, undo_count = names(cell_doc), cell_doc.UndoCount
    run("CadRobot_ToolMarker")
    assert names(cell_doc) == before and cell_doc.UndoCount == undo_count
    text = error_text()
    assert "select a face too" in text and "Traceback" not in text
    assert selected_names() == ["Wire"]


# --- Auto tool markers ------------------------------------------------------------------------

def test_auto_tool_markers_one_per_segment(cell_doc):
    box, cell = cell_doc.getObject("Box"), cell_of(cell_doc)
    path = api.make_path(cell_doc, cell, [(box, [element_name(box, "Edge", *e) for e in (FRONT, RIGHT, BACK)])])
    select(box)
    assert not active("CadRobot_AutoToolMarkers"), "a box is no path"
    FreeCADGui.Selection.clearSelection()
    select(path)
    assert active("CadRobot_AutoToolMarkers")
    before = names(cell_doc)
    run("CadRobot_AutoToolMarkers")
    made = new_objects(cell_doc, before)
    markers = [cell_doc.getObject(n) for n in made]
    assert len(markers) == 3 and all(objects_base.type_of(m) == "ToolMarker" for m in markers)
    by_segment = {m.Segment: m for m in markers}
    assert sorted(by_segment) == [1, 2, 3] and all(m.Path == path for m in markers)
    expected = [(V(50, 0, 20), Z_FRONT), (V(100, 30, 20), Z_RIGHT), (V(50, 60, 20), Z_BACK)]
    for marker in markers:
        z_expected = [z for p, z in expected if (p - marker.Placement.Base).Length < 1e-9]
        assert len(z_expected) == 1, marker.Placement.Base
        assert_axes(marker.Placement, z=z_expected[0])
    assert {m.Label for m in markers} == {"%s_Tool%d" % (path.Label, k) for k in (1, 2, 3)}
    undo_redo(cell_doc, made)


# --- Risk area --------------------------------------------------------------------------------

@pytest.fixture
def three_segment_path(cell_doc):
    box, cell = cell_doc.getObject("Box"), cell_of(cell_doc)
    path = api.make_path(cell_doc, cell, [(box, [element_name(box, "Edge", *e) for e in (FRONT, RIGHT, BACK)])])
    markers = api.make_tool_markers_auto(cell_doc, cell, path)
    cell_doc.recompute()
    FreeCADGui.Selection.clearSelection()
    return path, markers


def segment_edge(path, k):
    """The RobotPath's edge for segment k: EdgeK (the path's shape lists the segments in order)."""
    segment = reader.path_geometry(path)[0][k - 1]
    edge = path.Shape.Edges[k - 1]
    ends = [tuple(v.Point) for v in edge.Vertexes]
    assert all(min(np.linalg.norm(np.subtract(e, p)) for e in ends) < 1e-9
               for p in (segment.start, segment.end))
    return "Edge%d" % k


def middle(path, k):
    """The middle of segment k (a point picked on it)."""
    return V(*reader.path_geometry(path)[0][k - 1].point_at(reader.path_geometry(path)[0][k - 1].length / 2))


def test_risk_area_over_selected_segments(cell_doc, three_segment_path):
    path, _markers = three_segment_path
    select(path, segment_edge(path, 2), middle(path, 2))
    select(path, segment_edge(path, 3), middle(path, 3))
    assert active("CadRobot_RiskArea")
    before = names(cell_doc)
    run("CadRobot_RiskArea")
    made = new_objects(cell_doc, before)
    assert len(made) == 1
    risk = cell_doc.getObject(made[0])
    assert objects_base.type_of(risk) == "RiskArea" and risk.Path == path
    assert (risk.FirstSegment, risk.LastSegment) == (2, 3)
    # The risk area's shape is those two edges: the right and the back edge.
    assert abs(float(risk.Shape.Length) - 160.0) < 1e-9
    undo_redo(cell_doc, made)


def test_risk_area_between_two_markers(cell_doc, three_segment_path):
    path, markers = three_segment_path
    by_segment = {m.Segment: m for m in markers}
    select(by_segment[3])
    assert not active("CadRobot_RiskArea"), "one marker"
    select(by_segment[1])
    assert active("CadRobot_RiskArea")
    before = names(cell_doc)
    run("CadRobot_RiskArea")
    risk = cell_doc.getObject(new_objects(cell_doc, before)[0])
    assert (risk.Path, risk.FirstSegment, risk.LastSegment) == (path, 1, 3)


def test_risk_area_segments_must_follow_each_other(cell_doc, three_segment_path):
    path, _markers = three_segment_path
    select(path, segment_edge(path, 1), middle(path, 1))
    select(path, segment_edge(path, 3), middle(path, 3))
    assert active("CadRobot_RiskArea")
    before, undo_count = names(cell_doc), cell_doc.UndoCount
    run("CadRobot_RiskArea")
    assert names(cell_doc) == before and cell_doc.UndoCount == undo_count
    assert "do not follow each other" in error_text()
    assert selected_names() == [path.Name]


def test_risk_area_suggestions_as_a_checklist(cell_doc, three_segment_path, prefs):
    path, _markers = three_segment_path
    prefs("RiskThreshold", 30.0)
    select(path)
    assert active("CadRobot_RiskArea")
    run("CadRobot_RiskArea")
    panel = risk_area_panel.active_panel()
    assert panel is not None and panel.threshold.value() == 30.0
    # At each corner the tool turns 90 degrees: travelling F -> R, X (1,0,0) -> (0,1,0),
    # Z (0,1,-1)/sqrt2 -> (-1,0,-1)/sqrt2, Y = Z x X (0,-1,-1)/sqrt2 -> (1,0,-1)/sqrt2;
    # trace(R1' R2) = 0 + 1/2 + 1/2 = 1, angle = acos((1 - 1) / 2) = 90. Both corners are sharp:
    # one area per corner (issue 20), each a few mm either side of it.
    assert [(s.path, s.first_segment, s.last_segment) for s in panel.suggestions] == [(path, 1, 2), (path, 2, 3)]
    assert all(abs(s.jump_deg - 90.0) < 1e-6 and abs(s.turn_deg - 90.0) < 1e-6 for s in panel.suggestions)
    assert panel.list.count() == 2 and "1 to 2" in panel.list.item(0).text()
    assert "mm each side of the corner" in panel.list.item(0).text()
    panel.threshold.setValue(120.0)
    assert panel.find() == [] and panel.list.count() == 0
    panel.threshold.setValue(30.0)
    panel.find()
    panel.set_checked(0, False)
    panel.set_checked(1, False)
    assert not panel.accept() and "Check at least one" in panel.message.text()
    panel.set_checked(0, True)
    panel.set_checked(1, True)
    before = names(cell_doc)
    assert panel.accept()
    made = new_objects(cell_doc, before)
    risks = [cell_doc.getObject(name) for name in made]
    assert sorted((r.FirstSegment, r.LastSegment) for r in risks) == [(1, 2), (2, 3)]
    assert all(float(r.CornerSpan) > 0 and r.AtCorner == "Weld through" for r in risks)
    assert risk_area_panel.active_panel() is None
    undo_redo(cell_doc, made)


# --- journal: the recorded lines replay in FreeCADCmd ----------------------------------------

DUMP_SOURCE = '''
def dump(doc):
    """The CadRobot objects of doc: name, type, placement, key properties."""
    from CadRobotWB.objects import base
    out = {}
    for obj in doc.Objects:
        kind = base.type_of(obj)
        if not kind:
            continue
        entry = {"type": kind, "label": obj.Label,
                 "placement": [list(r) for r in __import__("numpy").array(obj.Placement.toMatrix().A).reshape(4, 4)]}
        for prop in ("Robot", "SegmentCount", "PathLength", "FirstSegment", "LastSegment", "Segment",
                     "ApproachDistance", "InterpolationStep", "UseTaught"):
            if prop in obj.PropertiesList:
                value = getattr(obj, prop)
                entry[prop] = float(value) if not isinstance(value, (str, bool)) else value
        for prop in ("Path", "CalibrationFrame"):
            if prop in obj.PropertiesList:
                entry[prop] = getattr(obj, prop).Name if getattr(obj, prop) is not None else None
        if "CadPoints" in obj.PropertiesList:
            entry["CadPoints"] = [list(v) for v in obj.CadPoints]
            entry["TaughtPlacement"] = list(obj.TaughtPlacement.toMatrix().A)
        if "Group" in obj.PropertiesList:
            entry["Group"] = [o.Name for o in obj.Group]
        out[obj.Name] = entry
    return out
'''

REPLAY_SOURCE = '''
import json, sys
import FreeCAD
doc = FreeCAD.openDocument(sys.argv[1])
lines = json.load(open(sys.argv[2]))
namespace = {"__name__": "__main__"}
for line in lines:
    exec(line, namespace)
doc.recompute()
''' + DUMP_SOURCE + '''
json.dump(dump(doc), open(sys.argv[3], "w"))
'''


def _dump(doc):
    namespace = {}
    exec(DUMP_SOURCE, namespace)
    return namespace["dump"](doc)


def _same(a, b, path=""):
    if isinstance(a, dict):
        assert isinstance(b, dict) and sorted(a) == sorted(b), path
        for k in a:
            _same(a[k], b[k], path + "/" + k)
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            _same(x, y, "%s[%d]" % (path, i))
    elif isinstance(a, float):
        assert abs(a - b) < 1e-9, "%s: %r != %r" % (path, a, b)
    else:
        assert a == b, "%s: %r != %r" % (path, a, b)


def test_journaled_lines_replay_in_freecadcmd(box_doc, journal, tmp_path):
    doc = box_doc
    box = doc.getObject("Box")
    saved = tmp_path / (doc.Name + ".FCStd")
    doc.saveAs(str(saved))
    # New cell on a vertex.
    select(box, element_name(box, "Vertex", V(0, 0, 0)))
    run("CadRobot_NewCell")
    panel = new_cell_panel.active_panel()
    panel.rotation.setValue(-45.0)
    panel.y.setValue(-900.0)
    assert panel.accept()
    FreeCADGui.Selection.clearSelection()
    # Calibration frame from three vertices, then taught.
    for p in (V(0, 0, 20), V(100, 0, 20), V(0, 60, 20)):
        select(box, element_name(box, "Vertex", p))
    run("CadRobot_CalibrationFrame")
    teaching = calibration_panel.active_panel()
    cell = cell_of(doc)
    cad, measured, _T = _teaching_data(cell, teaching.frame)
    for row, (c, m) in enumerate(zip(cad, measured)):
        teaching.set_cad_point(row, tuple(c))
        teaching.set_measured_point(row, tuple(m))
    assert teaching.accept()
    FreeCADGui.Selection.clearSelection()
    # A path, a marker picked on it, markers on every segment, a risk area.
    for edge in (FRONT, RIGHT, BACK):
        select(box, element_name(box, "Edge", *edge))
    run("CadRobot_MarkPath")
    path = objects_base.objects_of_type(doc, "RobotPath")[0]
    FreeCADGui.Selection.clearSelection()
    select(box, element_name(box, "Edge", *RIGHT), V(100, 12.5, 20))
    run("CadRobot_ToolMarker")
    FreeCADGui.Selection.clearSelection()
    select(path)
    run("CadRobot_AutoToolMarkers")
    FreeCADGui.Selection.clearSelection()
    select(path, "Edge1", middle(path, 1))
    select(path, "Edge2", middle(path, 2))
    run("CadRobot_RiskArea")
    marker_line = [line for line in journal if "edge_tool_placement" in line]
    assert len(marker_line) == 1 and "path=FreeCAD.getDocument(%r).getObject(%r)" % (doc.Name, path.Name) \
        in marker_line[0], "the marker on an edge of a path follows the path's travel"
    gui_result = _dump(doc)
    types = sorted(e["type"] for e in gui_result.values())
    assert types == ["CalibrationFrame", "Cell", "RiskArea", "RobotPath"] + ["ToolMarker"] * 4
    assert all(re.match(r"(import |from |\w+ = api\.|FreeCAD\.getDocument\()", line)
               for line in journal), journal
    # Replay in FreeCADCmd on the document as it was before the first command.
    (tmp_path / "lines.json").write_text(json.dumps(journal))
    (tmp_path / "replay.py").write_text(REPLAY_SOURCE)
    done = subprocess.run(["/usr/bin/python3", "tools/freecad_run.py", str(tmp_path / "replay.py"),
                           str(saved), str(tmp_path / "lines.json"), str(tmp_path / "replayed.json")],
                          cwd=REPO, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
    replayed = json.loads((tmp_path / "replayed.json").read_text())
    _same(gui_result, replayed)


# --- the journal helper ------------------------------------------------------------------------

def test_journal_aborts_and_keeps_the_error_and_its_object(box_doc):
    box = box_doc.getObject("Box")
    before, undo_count = names(box_doc), box_doc.UndoCount
    import __main__
    __main__.CadRobotTestError = __import__("CadRobotWB.errors", fromlist=["x"]).MarkerError
    lines = ["cell = api.make_cell(FreeCAD.getDocument(%r), name='Cell')" % box_doc.Name,
             "raise CadRobotTestError('Marker M is off the path; move it.', 'Box')"]
    result = command_base.run_journaled(box_doc, "Test", lines)
    assert result is None
    assert names(box_doc) == before and box_doc.UndoCount == undo_count and box_doc.RedoCount == 0
    assert error_text() == "Marker M is off the path; move it."
    assert selected_names() == [box.Name]
    # A failure that is not a CadRobotError: its text, no traceback.
    result = command_base.run_journaled(box_doc, "Test", ["1 / 0"])
    assert result is None and error_text() == "division by zero (ZeroDivisionError)"


def test_literal_rebuilds_values_exactly(box_doc):
    box = box_doc.getObject("Box")
    placement = FreeCAD.Placement(V(0.1, 1 / 3, -2e-7), FreeCAD.Rotation(V(1, 2, 3), 37.123456789))
    values = [placement, V(1 / 7, 2, 3), (box, ["Edge1", "Edge2"]), [box], None, 2.5, "a'b", True,
              command_base.Code("placement")]
    namespace = {"FreeCAD": FreeCAD, "placement": 42}
    rebuilt = eval(command_base.literal(values), namespace)
    assert rebuilt[0].Base == placement.Base and rebuilt[0].Rotation.Q == placement.Rotation.Q
    assert rebuilt[1] == values[1]
    assert rebuilt[2] == (box, ["Edge1", "Edge2"]) and rebuilt[3] == [box]
    assert rebuilt[4:] == [None, 2.5, "a'b", True, 42]


def test_double_click_on_a_frame_opens_and_closes_its_teaching_panel(cell_doc):
    frame = api.make_calibration_frame(cell_doc, cell_of(cell_doc), FreeCAD.Placement())
    gui_document = FreeCADGui.getDocument(cell_doc.Name)
    gui_document.setEdit(frame.Name, 0)              # what a double-click does
    process_events()
    panel = calibration_panel.active_panel()
    assert panel is not None and panel.frame == frame and FreeCADGui.Control.activeDialog()
    assert panel.reject()
    process_events()
    assert calibration_panel.active_panel() is None and not FreeCADGui.Control.activeDialog()
    assert gui_document.getInEdit() is None
