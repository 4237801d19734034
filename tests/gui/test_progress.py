"""Long work in the GUI: a progress bar, Cancel, a live window (gui/progress.py).

Check on a cell of several hundred 1 mm targets runs in a progress window:
while it works, the progress is reported many times with growing fractions
and Qt's event loop runs (a single-shot timer fires during the work); Cancel
pressed in that window stops it with one message, the document exactly as it
was (every property of every object compared) and no target coloured.  The
Generate and Sensor run panels cancel the same way, and closing a panel
cancels its work.  One work at a time: a second Check started meanwhile does
not run.
"""

import os

import pytest

import FreeCAD
import FreeCADGui
import Part
from PySide import QtCore, QtGui

from conftest import process_events

from CadRobotWB import api
from CadRobotWB.commands import base as command_base
from CadRobotWB.gui import generate_panel, progress as gui_progress, sensor_run_panel, status_overlay

V = FreeCAD.Vector
SEGMENTS = 300


@pytest.fixture
def long_cell(gui_doc):
    """A 300 mm seam of 1 mm lines over a block, one tool marker: 300 targets to check."""
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    sketch = gui_doc.addObject("Sketcher::SketchObject", "Seam")
    for k in range(SEGMENTS):
        sketch.addGeometry(Part.LineSegment(V(k, 0, 0), V(k + 1, 0, 0)), False)
    block = gui_doc.addObject("Part::Box", "Block")
    block.Length, block.Width, block.Height = SEGMENTS, 100, 20
    block.Placement.Base = V(0, -50, -25)
    gui_doc.recompute()
    cell = api.make_cell(gui_doc, robot="ABB_IRB2400")
    cell.Placement = FreeCAD.Placement(V(-700, 0, -800), FreeCAD.Rotation())    # all in reach
    api.make_calibration_frame(gui_doc, cell, FreeCAD.Placement())
    api.make_path(gui_doc, cell, sketch)
    api.make_tool_marker(gui_doc, cell, api.tool_placement(V(0, 0, 0), V(1, 0, 0), V(0, 0, 1)))
    gui_doc.recompute()
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(cell)
    process_events()
    yield cell
    generate_panel.close_panel()
    status_overlay.remove()
    if command_base._message_box is not None:
        command_base._message_box.close()
    process_events()


def fingerprint(doc):
    """Every property of every object, the undo stack and what is touched, comparable."""
    out = [("undo", doc.UndoCount), ("objects", tuple(o.Name for o in doc.Objects))]
    for obj in doc.Objects:
        out.append((obj.Name, "State", tuple(obj.State)))
        for prop in obj.PropertiesList:
            if prop.startswith("_"):     # FreeCAD 1.1's own caches (_Part_ShapeCache), not data
                continue
            try:
                value = getattr(obj, prop)
            except Exception:  # noqa: BLE001 -- a property that cannot be read is left out
                continue
            out.append((obj.Name, prop, _comparable(value)))
    return out


def _comparable(value):
    if hasattr(value, "exportBrepToString"):      # its geometry (a tessellation cache aside)
        if value.isNull():
            return "null shape"
        return (value.ShapeType, len(value.Faces), len(value.Edges), round(value.Volume, 6),
                round(value.Area, 6), round(value.Length, 6), tuple(value.Placement.toMatrix().A),
                tuple((round(v.X, 9), round(v.Y, 9), round(v.Z, 9)) for v in value.Vertexes))
    if isinstance(value, (list, tuple)):
        return tuple(_comparable(v) for v in value)
    if hasattr(value, "Name") and hasattr(value, "TypeId"):
        return ("object", value.Name)
    if isinstance(value, FreeCAD.Placement):
        return tuple(value.toMatrix().A)
    return repr(value)


class Watch:
    """Wraps ProgressRunner.progress: keeps the fractions, and runs `at(count)` after each."""

    def __init__(self, monkeypatch, at=None):
        self.fractions, self.at = [], at
        self.answers = []              # what the runner answered the engine
        original = gui_progress.ProgressRunner.progress
        watch = self

        def progress(runner, fraction, text=""):
            watch.fractions.append(fraction)
            if watch.at is not None:
                watch.at(len(watch.fractions), runner)
            watch.answers.append(original(runner, fraction, text))
            return watch.answers[-1]

        monkeypatch.setattr(gui_progress.ProgressRunner, "progress", progress)

    def stopped_at_once(self):
        """The engine stopped at the first False (Cancel handled), not later."""
        return self.answers[-1] is False and False not in self.answers[:-1]


def click_soon(button_of):
    """Click the button `button_of()` names from Qt's event loop (as a user would)."""
    QtCore.QTimer.singleShot(0, lambda: button_of().click())


def test_check_reports_often_and_the_window_stays_live(long_cell, monkeypatch):
    watch = Watch(monkeypatch)
    fired = []
    QtCore.QTimer.singleShot(0, lambda: fired.append(gui_progress.busy()))
    FreeCADGui.runCommand("CadRobot_Check")
    assert fired == [True], "the timer fired while the check was running"
    assert len(watch.fractions) > 50
    assert all(a <= b for a, b in zip(watch.fractions, watch.fractions[1:]))
    assert watch.fractions[-1] == 1.0
    assert not gui_progress.busy() and gui_progress.current_dialog is None
    overlay = status_overlay.current(long_cell.Document.Name)
    assert overlay is not None and sum(overlay.counts().values()) >= SEGMENTS


def test_cancel_in_the_progress_window_changes_nothing(long_cell, monkeypatch):
    doc = long_cell.Document
    before = fingerprint(doc)
    box_before = command_base._message_box
    statuses = []
    monkeypatch.setattr(gui_progress, "show_status", lambda text, timeout_ms=0: statuses.append(text))
    fired = []

    def cancel_at(count, runner):
        if count == 20:
            click_soon(lambda: gui_progress.current_dialog.cancel_button)
            QtCore.QTimer.singleShot(0, lambda: fired.append(gui_progress.busy()))

    watch = Watch(monkeypatch, cancel_at)
    FreeCADGui.runCommand("CadRobot_Check")
    assert fired == [True]
    assert len(watch.fractions) >= 20
    assert watch.stopped_at_once()
    assert len(statuses) == 1 and "cancelled" in statuses[0].lower(), statuses
    assert command_base._message_box is box_before, "no message box for a cancel"
    assert status_overlay.current(doc.Name) is None, "no target coloured"
    assert fingerprint(doc) == before
    assert not gui_progress.busy()


def test_a_second_check_does_not_start_while_one_runs(long_cell, monkeypatch):
    checks = []
    real_check = api.check
    monkeypatch.setattr(api, "check", lambda *a, **k: checks.append(1) or real_check(*a, **k))
    statuses = []
    monkeypatch.setattr(gui_progress, "show_status", lambda text, timeout_ms=0: statuses.append(text))
    again = []

    def start_again(count, runner):
        if count == 10:
            QtCore.QTimer.singleShot(0, lambda: again.append(FreeCADGui.runCommand("CadRobot_Check")))

    Watch(monkeypatch, start_again)
    FreeCADGui.runCommand("CadRobot_Check")
    assert again == [None] and checks == [1]
    # the second one says so once; the first one's result follows in the status bar
    assert len(statuses) == 2 and "still running" in statuses[0]
    assert statuses[1].startswith("Cell: 0 errors")
    assert status_overlay.current(long_cell.Document.Name) is not None


def test_generate_panel_cancel_and_close(long_cell, monkeypatch, tmp_path):
    panel = generate_panel.open_panel(long_cell)
    assert panel.files and panel.progress_bar.value() == 1000
    panel.folder_edit.setText(str(tmp_path / "out"))

    def cancel_at(count, runner):
        if count == 10:
            click_soon(lambda: panel.cancel_button)

    watch = Watch(monkeypatch, cancel_at)
    assert panel.refresh() is False
    assert watch.stopped_at_once()
    assert panel.files == [] and "Cancelled" in panel.message_label.text()
    assert panel.refresh_button.isEnabled() and not panel.cancel_button.isEnabled()

    watch.fractions.clear()
    assert panel.write() is None, "Write through the journaled api.export, cancelled"
    assert len(watch.fractions) >= 10, "the journaled call reported to the panel's bar"
    assert not (tmp_path / "out").exists() or not os.listdir(str(tmp_path / "out"))
    assert "nothing was written" in panel.message_label.text()

    closing = []

    def close_at(count, runner):
        if count == 10:
            QtCore.QTimer.singleShot(0, lambda: closing.append(generate_panel.close_panel()))

    watch.at = close_at
    watch.answers.clear()
    watch.fractions.clear()
    assert panel.refresh() is False, (closing, watch.answers[-3:])
    assert generate_panel.active_panel() is None and not gui_progress.busy()


def test_sensor_run_cancel_keeps_nothing(gui_doc, monkeypatch):
    import seam_tracking_cell
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    cell = seam_tracking_cell.build(gui_doc)
    gui_doc.recompute()
    process_events()
    before = fingerprint(gui_doc)
    panel = sensor_run_panel.open_panel(cell)
    try:
        def cancel_at(count, runner):
            if count == 5:
                click_soon(lambda: panel.cancel_button)

        watch = Watch(monkeypatch, cancel_at)
        assert panel.run() is False
        assert panel.runs is None and "Cancelled" in panel.results_label.text()
        assert 5 <= len(watch.fractions)
        assert panel.run_button.isEnabled()
        watch.at = None
        assert panel.run() is True and panel.runs
        assert len(watch.fractions) > 50
    finally:
        sensor_run_panel.close_panel()
        process_events()
    after = fingerprint(gui_doc)
    assert [a for a, b in zip(after, before) if a != b] == [] and after == before


def test_progress_dialog_close_cancels(gui_doc):
    def work(progress):
        for k in range(1000):
            if progress(k / 1000, "looping") is False:
                raise gui_progress.Cancelled()
        return "done"

    QtCore.QTimer.singleShot(0, lambda: gui_progress.current_dialog.close())
    with pytest.raises(gui_progress.Cancelled):
        gui_progress.run_with_dialog("Test", "test", work)
    assert not gui_progress.busy()
    assert gui_progress.run_with_dialog("Test", "test", work) == "done"
    with gui_progress.under_way("other"):
        with pytest.raises(gui_progress.Busy):
            gui_progress.run_with_dialog("Test", "test", work)
    assert isinstance(QtGui.QApplication.instance(), QtGui.QApplication)


def test_simulate_cancelled_opens_no_player(long_cell, monkeypatch):
    from CadRobotWB.gui import simulation_player
    before = fingerprint(long_cell.Document)

    def cancel_at(count, runner):
        if count == 10:
            click_soon(lambda: gui_progress.current_dialog.cancel_button)

    watch = Watch(monkeypatch, cancel_at)
    FreeCADGui.runCommand("CadRobot_Simulate")
    assert watch.stopped_at_once()
    assert simulation_player.active_player() is None and FreeCADGui.Control.activeDialog() is False
    assert fingerprint(long_cell.Document) == before
    watch.at = None
    FreeCADGui.runCommand("CadRobot_Simulate")
    try:
        assert simulation_player.active_player() is not None
        assert watch.fractions[-1] == 1.0
    finally:
        simulation_player.close_player()
        process_events()
