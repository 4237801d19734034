"""Picking inside a moved App::Part gives global coordinates ({U}) to every command and
panel, and closing a document closes its task panels."""

import FreeCAD
import FreeCADGui
import pytest

from conftest import close_panels, process_events

from CadRobotWB import api
from CadRobotWB.commands import selection
from CadRobotWB.gui import calibration_panel, new_cell_panel
from CadRobotWB.objects import base as objects_base

V = FreeCAD.Vector
OFFSET = V(500.0, 200.0, 0.0)



@pytest.fixture
def part_doc(gui_doc):
    """A 100 x 60 x 20 box inside an App::Part moved by OFFSET; the workbench active."""
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    part = gui_doc.addObject("App::Part", "Part")
    box = gui_doc.addObject("Part::Box", "Box")
    box.Length, box.Width, box.Height = 100.0, 60.0, 20.0
    part.addObject(box)
    part.Placement = FreeCAD.Placement(OFFSET, FreeCAD.Rotation())
    gui_doc.recompute()
    FreeCADGui.Selection.clearSelection()
    close_panels()
    yield gui_doc
    FreeCADGui.Selection.clearSelection()
    close_panels()


def element_name(obj, kind, *points):
    """Name of the element of `obj` through `points` given in the object's own frame."""
    elements = {"Vertex": obj.Shape.Vertexes, "Edge": obj.Shape.Edges}[kind]
    for k, element in enumerate(elements, 1):
        corners = [v.Point for v in element.Vertexes]
        if all(any((c - p).Length < 1e-7 for c in corners) for p in points):
            return "%s%d" % (kind, k)
    raise AssertionError("no %s through %s" % (kind, points))


def select_in_part(doc, sub, point=None):
    """Select Box.<sub> through its Part, as a click in the 3D view does (point in {U})."""
    if point is None:
        FreeCADGui.Selection.addSelection(doc.Name, "Part", "Box." + sub)
    else:
        FreeCADGui.Selection.addSelection(doc.Name, "Part", "Box." + sub, point.x, point.y, point.z)
    process_events()


def test_selected_vertex_in_a_moved_part_is_in_global_coordinates(part_doc):
    box = part_doc.getObject("Box")
    select_in_part(part_doc, element_name(box, "Vertex", V(100, 60, 0)))
    items = selection.selected(part_doc)
    print(items)
    point = selection.picked_point(items)
    assert (point - (V(100, 60, 0) + OFFSET)).Length < 1e-9


def test_picked_point_on_an_edge_in_a_moved_part_is_kept(part_doc):
    box = part_doc.getObject("Box")
    edge = element_name(box, "Edge", V(0, 0, 20), V(100, 0, 20))
    picked = V(20, 0, 20) + OFFSET
    select_in_part(part_doc, edge, picked)
    item, = selection.selected(part_doc)
    print(item)
    assert selection.point_on(item.obj, item.sub, item.point) is not None


def test_picking_a_cad_point_in_a_moved_part_gives_global_coordinates(part_doc):
    cell = api.make_cell(part_doc)
    frame = api.make_calibration_frame(part_doc, cell, FreeCAD.Placement())
    part_doc.recompute()
    panel = calibration_panel.edit(frame)
    assert panel is not None
    panel.set_picking(True)
    box = part_doc.getObject("Box")
    select_in_part(part_doc, element_name(box, "Vertex", V(100, 60, 0)))
    expected = V(100, 60, 0) + OFFSET
    assert [panel._cell_text(0, c) for c in calibration_panel.CAD_COLUMNS] == \
        [calibration_panel._format(v) for v in (expected.x, expected.y, expected.z)]
    panel.set_picking(False)


def test_new_cell_on_a_vertex_of_a_moved_part(part_doc):
    box = part_doc.getObject("Box")
    select_in_part(part_doc, element_name(box, "Vertex", V(100, 60, 0)))
    panel = new_cell_panel.open_panel(part_doc)
    assert (panel.x.value(), panel.y.value(), panel.z.value()) == (600.0, 260.0, 0.0)


def test_tool_marker_at_the_picked_point_of_an_edge_in_a_moved_part(part_doc):
    api.make_cell(part_doc)
    part_doc.recompute()
    box = part_doc.getObject("Box")
    edge = element_name(box, "Edge", V(0, 0, 20), V(100, 0, 20))
    select_in_part(part_doc, edge, V(20, 0, 20) + OFFSET)
    before = [o.Name for o in part_doc.Objects]
    FreeCADGui.runCommand("CadRobot_ToolMarker")
    process_events()
    made = [o for o in part_doc.Objects if o.Name not in before]
    marker, = [o for o in made if objects_base.type_of(o) == "ToolMarker"]
    assert (marker.Placement.Base - (V(20, 0, 20) + OFFSET)).Length < 1e-6


def test_closing_the_document_closes_its_teaching_panel_and_stops_picking():
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    close_panels()
    doc = FreeCAD.newDocument("ReviewClosed")
    cell = api.make_cell(doc)
    frame = api.make_calibration_frame(doc, cell, FreeCAD.Placement())
    doc.recompute()
    FreeCADGui.Selection.clearSelection()
    panel = calibration_panel.edit(frame)       # as CadRobot_CalibrationFrame opens it
    assert panel is not None
    panel.set_picking(True)
    process_events()
    FreeCAD.closeDocument(doc.Name)
    process_events()
    assert calibration_panel.active_panel() is None
    assert not FreeCADGui.Control.activeDialog(), "the panel stayed open on a closed document"
    assert not panel.picking, "the selection observer stayed installed"
    other = FreeCAD.newDocument("ReviewOther")
    try:
        new_cell_panel.open_panel(other)        # a new panel can open at once
        assert new_cell_panel.active_panel() is not None
    finally:
        close_panels()
        FreeCAD.closeDocument(other.Name)
        process_events()
