"""The Weld command and panel in the FreeCAD window: the selected segment opens the
panel, the library row for the joint is shown with why, the woven path is drawn in the
3D view, OK journals api.make_weld, "Save as my schedule" keeps the values."""

import os
import sys

import FreeCAD
import FreeCADGui
import pytest
from PySide import QtGui

from CadRobotWB import api, preferences
from CadRobotWB.gui import weld_panel
from CadRobotWB.objects import base as objects_base
from CadRobotWB.objects import weld as weld_object
import test_commands
from conftest import close_panels, process_events, render

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "app"))
from helpers import fillet_cell  # noqa: E402  (the App tier's builders)

AMBER = QtGui.QColor.fromRgbF(1.0, 0.75, 0.0)


# The fixture of test_commands: the journaled lines.
journal = test_commands.journal


def amber_pixels(image):
    """Pixels drawn in the weld colour (within a few levels: antialiasing)."""
    return sum(1 for y in range(0, image.height()) for x in range(0, image.width())
               if all(abs(a - b) <= 8 for a, b in zip(QtGui.QColor.fromRgb(image.pixel(x, y)).getRgb()[:3],
                                                         AMBER.getRgb()[:3])))


def _seam_only(doc, cell, *shown):
    """The 3D view looking down on the `shown` objects alone (the plates, markers and robot
    hidden)."""
    FreeCADGui.Selection.clearSelection()
    cell.ViewObject.ShowRobot = False
    for obj in doc.Objects:
        if obj not in (cell,) + shown and hasattr(obj, "ViewObject") and obj.ViewObject is not None:
            obj.ViewObject.Visibility = False
    view = FreeCADGui.getDocument(doc.Name).activeView()
    view.viewTop()
    view.fitAll()
    return view


def test_the_weld_panel_previews_the_woven_path_and_journals_make_weld(gui_doc, journal, monkeypatch,
                                                                       tmp_path):
    monkeypatch.setattr(preferences, "weld_schedule_folder", lambda: str(tmp_path / "mine"))
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    close_panels()
    cell, path, _ = fillet_cell(gui_doc)
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(gui_doc.Name, path.Name, "Edge2")
    process_events()
    assert FreeCADGui.Command.get("CadRobot_Weld").isActive()
    FreeCADGui.runCommand("CadRobot_Weld")
    process_events()
    panel = weld_panel.active_panel()
    try:
        assert panel is not None and panel.segments_given() == (2, 2) and panel.path() == path
        # From the joint: the 6 mm web's row, and why (plan table c: 265 A, 27.5 V, 7.5 mm/s)
        assert panel.chosen() == weld_panel.FROM_JOINT
        assert "Picked fillet_t6" in panel.note.text() and "6.0 mm thick" in panel.note.text()
        boxes = panel.schedule_boxes
        assert (boxes["current_a"].value(), boxes["voltage_v"].value(), boxes["travel_speed_mm_s"].value()) \
            == (265.0, 27.5, 7.5)
        plain = panel.preview
        panel.weave_group.setChecked(True)
        panel.weave_boxes["width_mm"].setValue(6.0)
        panel.weave_boxes["frequency_hz"].setValue(1.0)
        assert panel.preview is not None and panel.preview is not plain
        view = _seam_only(gui_doc, cell, path)
        image = render(view, tmp_path / "weld_panel_preview.png")
        assert amber_pixels(image) > 200, "no woven preview in %s" % (tmp_path / "weld_panel_preview.png")
        # a value changed by hand makes the schedule the user's, and it can be kept
        boxes["voltage_v"].setValue(28.0)
        assert panel.chosen() == weld_panel.CUSTOM
        panel.save_name.setText("my_fillet")
        written = panel.save_schedule()
        assert written and os.path.isfile(written) and panel.chosen() == "my_fillet"
        assert panel.schedule_combo.currentText() == "my_fillet (yours)"
        assert panel.position_combo.currentText() == "PA"
        panel.position_combo.setCurrentIndex(panel.position_combo.findText("PB"))
        assert panel.accept()
    finally:
        close_panels()
    lines = [line for line in journal if "make_weld" in line]
    assert lines == ["weld = api.make_weld(FreeCAD.getDocument(%r), FreeCAD.getDocument(%r).getObject(%r), "
                     "FreeCAD.getDocument(%r).getObject(%r), schedule='my_fillet', weave={'pattern': "
                     "'zigzag', 'width_mm': 6.0, 'frequency_hz': 1.0, 'dwell_left_s': 0.0, "
                     "'dwell_center_s': 0.0, 'dwell_right_s': 0.0, 'angle_deg': 0.0}, first_segment=2, "
                     "last_segment=2, position='PB')" % (gui_doc.Name, gui_doc.Name, cell.Name, gui_doc.Name, path.Name)]
    [weld] = objects_base.objects_of_type(gui_doc, "Weld")
    assert weld in cell.Group and weld.Schedule == "my_fillet" and weld.Voltage == 28.0
    assert weld.Position == "PB"
    assert (weld.WeavePattern, float(weld.WeaveWidth)) == ("zigzag", 6.0)
    assert (weld.FirstSegment, weld.LastSegment) == (2, 2) and weld.ViewObject.Visibility
    assert tuple(weld.ViewObject.LineColor)[:3] == pytest.approx((1.0, 0.75, 0.0), abs=0.01)
    # the journaled line, run as a macro runs it, makes the same weld again
    namespace = {"FreeCAD": FreeCAD, "api": api}
    exec(lines[0], namespace)
    again = namespace["weld"]
    assert (weld_object.spec_of(again, 2).schedule, weld_object.spec_of(again, 2).weave) == \
        (weld_object.spec_of(weld, 2).schedule, weld_object.spec_of(weld, 2).weave)
    assert again.Shape.Length == pytest.approx(weld.Shape.Length) and again.Schedule == "my_fillet"
    gui_doc.removeObject(again.Name)
    # the panel's preview is gone; the weld's own woven line is drawn
    image = render(_seam_only(gui_doc, cell, path, weld), tmp_path / "weld.png")
    assert amber_pixels(image) > 200
