"""Sensor run offers the sensor that fits the path: force on the outside edge of
FreeCAD's Drilling_1 block (the laser greyed out, its reason shown), the laser on the
seam example; an aborted run's summary prints no placeholder."""

import os
import re

import numpy as np
import pytest

import FreeCAD
import FreeCADGui
from PySide import QtCore

from conftest import process_events
from drilling_part import drilling_block, top_outer_loop

from CadRobotWB import api
from CadRobotWB.gui import sensor_run_panel
from CadRobotWB.sensors.run import SensorRun

V = FreeCAD.Vector
PLACEHOLDERS = re.compile(r"(^|[\s(=:>])(-|nan|None)([\s),;.<]|$)")


@pytest.fixture
def cleanup():
    yield
    sensor_run_panel.close_panel()
    process_events()


@pytest.fixture
def drilling_cell(cleanup):
    doc, pocket = drilling_block()
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    edges = top_outer_loop(pocket)
    cell = api.make_cell(doc, robot="ABB_IRB2400", name="Cell",
                         placement=FreeCAD.Placement(V(-800, 0, -500), FreeCAD.Rotation()))
    api.make_calibration_frame(doc, cell, FreeCAD.Placement())
    path = api.make_path(doc, cell, [(pocket, name) for name in edges])
    api.make_tool_markers_auto(doc, cell, path)
    doc.recompute()
    process_events()
    yield cell
    sensor_run_panel.close_panel()
    FreeCAD.closeDocument(doc.Name)
    process_events()


def sensor_index(panel, key):
    return panel.sensor_box.findData(key)


def test_the_outside_edge_of_pocket011_preselects_force_and_says_why_not_the_laser(drilling_cell, tmp_path):
    panel = sensor_run_panel.open_panel(drilling_cell)
    process_events()
    assert panel.settings()["sensor"] == "force" and panel.rate_box.value() == 20.0
    laser = sensor_index(panel, "laser")
    assert not sensor_run_panel.is_item_enabled(panel.sensor_box, laser)
    assert sensor_run_panel.is_item_enabled(panel.sensor_box, sensor_index(panel, "force"))
    tip = panel.sensor_box.itemData(laser, QtCore.Qt.ToolTipRole)
    assert tip.startswith("Not offered: the path has no joint: it runs along a convex edge between Face")
    note = panel.fit_label.text()
    assert panel.fit_label.isVisible()
    assert re.match(r"Laser seam tracking: not offered, the path has no joint: it runs along a convex edge "
                    r"between Face\d+ and Face\d+ of Pocket011 \(outside corner, 90\u00b0\)\.", note), note
    # the cell's tool is no ball tool: force following says so
    assert panel.tool_label.isVisible() and "needs the ball tool" in panel.tool_label.text()
    for label in (panel.fit_label, panel.tool_label):     # the whole note shows, not cut off
        assert label.height() >= label.heightForWidth(label.width()) > 0
    assert panel.form.grab().save(str(tmp_path / "sensor_fit_drilling.png"))
    shots = os.environ.get("CADROBOT_SCREENSHOTS")
    if shots:
        panel.form.grab().save(os.path.join(shots, "sensor_fit_drilling.png"))


def test_the_seam_example_preselects_the_laser_and_greys_out_force(gui_doc, cleanup):
    import seam_tracking_cell
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    cell = seam_tracking_cell.build(gui_doc)
    gui_doc.recompute()
    process_events()
    panel = sensor_run_panel.open_panel(cell)
    process_events()
    assert panel.settings()["sensor"] == "laser"
    assert not sensor_run_panel.is_item_enabled(panel.sensor_box, sensor_index(panel, "force"))
    assert panel.fit_label.text().startswith("Force profile following: not offered, the path is a seam: "
                                             "it runs along a butt joint between PlateA.Face")
    # no weld on the path: the arc tracker is not offered, and says why (issue 22)
    arc = sensor_index(panel, "arc")
    assert not sensor_run_panel.is_item_enabled(panel.sensor_box, arc)
    assert panel.sensor_box.itemData(arc, QtCore.Qt.ToolTipRole).startswith(
        "Not offered: the path has no weld: through-arc tracking senses the arc of a weld")
    assert "Through-arc seam tracking: not offered, the path has no weld" in panel.fit_label.text()
    assert not panel.tool_label.isVisible()


def test_an_aborted_runs_summary_has_no_placeholder():
    t = np.arange(0.0, 2.0, 0.01)
    nominal = np.column_stack([10.0 * t, np.zeros_like(t), np.zeros_like(t)])
    run = SensorRun("laser", "pi", t, nominal, nominal, 0 * nominal, np.full(len(t), np.nan),
                    metrics={"rms_error_after_20mm_mm": float("nan"), "max_error_mm": float("nan"),
                             "max_step_mm": 0.0},
                    aborted=True, reason="seam lost: no butt joint matched in 3 profiles in a row",
                    stop_index=120, notes=["Laser seam tracking was asked for although the path has no joint."])
    opened = SensorRun("laser", "none", t, nominal, nominal, 0 * nominal, np.full(len(t), np.nan),
                       metrics={"rms_error_after_20mm_mm": None, "max_error_mm": None},
                       notes=list(run.notes))
    html = sensor_run_panel.results_html([run, opened])
    assert "RMS error after 20 mm: not measured, the run aborted after 12 mm (seam lost)" in html
    assert "RMS error after 20 mm: not measured, the open loop never measured the seam" in html
    assert html.count("was asked for") == 1
    for line in html.split("<br>"):
        assert not PLACEHOLDERS.search(re.sub(r"<[^>]+>", " ", line)), line
