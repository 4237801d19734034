"""The risk-area panel states each suggestion's step and moves, and the program's size
(issue 14 item 8, issue 20 item 1).

Five 100 mm segments: 1 along +X, 2 up, 3 along +X, 4 down, 5 along +X. "First"
points down on segment 1; "Fourth" on segment 4 is tilted 30 deg (travel angle),
so the tool turns 30 deg at junction 3 only. Speed 10 mm/s x 0.1 s = 1 mm (the
paper's step). The suggested corner area covers min(5 mm, 100 mm / 4) = 5 mm each
side of junction 3: 10 mm turning 30 deg, step 10 * 2 / 30 = 0.667 -> 0.66 mm,
ceil(5 / 0.66) = 8 moves each side, 16 in all; segment 3 up to 5 mm before the
corner and segment 4 from 5 mm after it stay one line each: 18 moves for 2 lines
and 1 reorientation, +15. Stopping to reorient instead adds nothing: +0.
Selected segments 3-4 (whole, 200 mm): 200 * 2 deg / 30 deg = 13.33 -> 13.3 mm.
"""

import FreeCAD
import Part

from conftest import process_events

from CadRobotWB import api
from CadRobotWB.gui import risk_area_panel

V = FreeCAD.Vector
FIVE = [(0, 0, 0), (100, 0, 0), (100, 100, 0), (200, 100, 0), (200, 0, 0), (300, 0, 0)]


def turned_cell(doc):
    cell = api.make_cell(doc)
    cell.ViewObject.ShowRobot = False
    api.make_calibration_frame(doc, cell, FreeCAD.Placement())
    feature = doc.addObject("Part::Feature", "Polyline")
    feature.Shape = Part.makePolygon([V(*p) for p in FIVE])
    path = api.make_path(doc, cell, feature)
    api.make_tool_marker(doc, cell, api.tool_placement(V(50, 0, 0), V(1, 0, 0), V(0, 0, 1), 90.0, 0.0),
                         name="First")
    api.make_tool_marker(doc, cell, api.tool_placement(V(200, 50, 0), V(1, 0, 0), V(0, 0, 1), 90.0, 30.0),
                         name="Fourth")
    doc.recompute()
    process_events()
    return cell, path


def test_panel_states_step_moves_and_program_size(gui_doc):
    cell, path = turned_cell(gui_doc)
    now = api.program_move_count(cell)
    panel = risk_area_panel.RiskAreaPanel(cell)
    panel.threshold.setValue(10.0)
    (found,) = panel.find()
    assert (found.first_segment, found.last_segment) == (3, 4)
    assert abs(found.jump_deg - 30.0) < 1e-6
    text = panel.list.item(0).text()
    assert "segments 3 to 4, 5 mm each side of the corner" in text and "30.0\u00b0" in text
    assert "step 0.66 mm" in text and "+15 moves" in text
    assert "at most 2° turn per move" in panel.list.item(0).toolTip()
    assert "at most 2\u00b0 per move" in panel.rule.text() and "speed \u00d7 sample time" in panel.rule.text()
    assert panel.size.text() == "Program: %d moves now, %d with the checked risk areas (+15)." % (now, now + 15)
    panel.set_checked(0, False)
    process_events()
    assert panel.size.text() == "Program: %d moves now, %d with the checked risk areas (+0)." % (now, now)
    panel.at_corner.setCurrentIndex(panel.at_corner.findText("Stop and reorient"))
    process_events()
    assert "+0 moves" in panel.list.item(0).text() and panel.suggestions[0].at_corner == "Stop and reorient"
    panel.at_corner.setCurrentIndex(panel.at_corner.findText("Weld through"))
    process_events()
    assert panel.create()
    (risk,) = [o for o in gui_doc.Objects if o.TypeId == "Part::FeaturePython" and hasattr(o, "FirstSegment")]
    assert abs(float(risk.Step) - 0.66) < 1e-9 and float(risk.CornerSpan) == 5.0
    assert len(api.generate(cell).moves()) == now + 15 == panel.program_size()[1]


def test_size_unknown_says_why(gui_doc):
    cell, path = turned_cell(gui_doc)
    cell.CalibrationFrame = None
    for frame in [o for o in gui_doc.Objects if o.Name.startswith("CalibrationFrame")]:
        gui_doc.removeObject(frame.Name)
    gui_doc.recompute()
    panel = risk_area_panel.RiskAreaPanel(cell)
    panel.threshold.setValue(10.0)
    assert len(panel.find()) == 1
    assert "+15 moves" in panel.list.item(0).text()
    assert panel.program_size() == (None, None)
    assert "Program size unknown until it generates" in panel.size.text()
    assert "calibration frame 'CalibrationFrame', which was deleted" in panel.size.text()


def risk_area_from_selected(doc, path, subs):
    """Run CadRobot_RiskArea on edges `subs` of `path`; the one risk area it made."""
    import FreeCADGui
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    FreeCADGui.Selection.clearSelection()
    for sub in subs:
        FreeCADGui.Selection.addSelection(doc.Name, path.Name, sub)
    process_events()
    FreeCADGui.runCommand("CadRobot_RiskArea")
    process_events()
    (risk,) = [o for o in doc.Objects if hasattr(o, "FirstSegment")]
    return risk


def test_risk_area_command_on_selected_segments_gets_the_same_step(gui_doc):
    cell, path = turned_cell(gui_doc)
    risk = risk_area_from_selected(gui_doc, path, ("Edge3", "Edge4"))
    assert (risk.FirstSegment, risk.LastSegment) == (3, 4)
    assert abs(float(risk.Step) - 13.3) < 1e-9


def test_the_last_and_first_segment_of_a_loop_make_its_closing_corner(gui_doc):
    """Selecting segments 9 and 1 of the cleat's closed foot loop: the corner where the loop
    closes (9..1), not a complaint that they do not follow each other."""
    import angle_cleat
    cleat, _plate = angle_cleat.cleat_on_plate(gui_doc)
    cell = api.make_cell(gui_doc)
    cell.ViewObject.ShowRobot = False
    api.make_calibration_frame(gui_doc, cell, FreeCAD.Placement())
    path = api.make_path(gui_doc, cell, [(cleat, e) for e in angle_cleat.foot_loop_edges(cleat)])
    api.make_tool_markers_auto(gui_doc, cell, path)
    gui_doc.recompute()
    risk = risk_area_from_selected(gui_doc, path, ("Edge9", "Edge1"))
    assert (risk.FirstSegment, risk.LastSegment) == (9, 1)
    # Its shape is both edges: 100 mm of the y leg's outer face and 100 mm of the x leg's.
    assert abs(float(risk.Shape.Length) - 200.0) < 1e-6
