"""Every CadRobot task panel at FreeCAD's default panel width on a 1366x768 screen.

FreeCAD's combo view (0.20, 1.0) opens about 260 px wide in a 1366x768 main
window on a new user's first start (measured: 264 px on 0.20.2); FreeCAD 1.1
shows task panels in an overlay on the right, 388 x 429 px (measured with a new
user's settings). Each panel opened there must be usable without
dragging the panel wider:

* nothing is cut off on the right (no horizontal scrolling of the task view);
* every table shows all its columns (no horizontal scroll bar in the table);
* the panel's own action buttons (its ``ACTION_BUTTONS``: Search, Run, Write...)
  are in view without scrolling the task view (when the Report view is closed, as
  on a new user's first start; with it open the panel must still not be cut off
  on the right). FreeCAD 1.1 shows the task panel in an overlay on the right,
  about 375 x 350 px at 1366x768: the buttons sit near the top of each panel;
* long text (a program, a description) sits in an area the user can resize
  (a ``QSplitter``), so it does not push the buttons below the fold.

A screenshot of the main window is saved per panel (``tmp_path``, or the folder
named by ``CADROBOT_PANEL_SHOTS``): look at them.
"""

import os
import sys
import time

import FreeCADGui
import pytest
from PySide import QtCore, QtGui

from conftest import close_panels, process_events

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "examples"))

SCREEN_PX = (1366, 768)
#: FreeCAD's default width of the dock holding the task view, px (see the module docstring).
DEFAULT_DOCK_PX = 264


def _task_scroll_area(form):
    """The task view's scroll area holding `form`."""
    parent = form.parentWidget()
    while parent is not None:
        if isinstance(parent, QtGui.QScrollArea):
            return parent
        parent = parent.parentWidget()
    raise AssertionError("the panel is not inside the task view")


def _shot_folder(tmp_path):
    folder = os.environ.get("CADROBOT_PANEL_SHOTS") or str(tmp_path)
    os.makedirs(folder, exist_ok=True)
    return folder


@pytest.fixture(params=["report view hidden", "report view shown"])
def small_window(request):
    """The main window at 1366x768 with the task view's dock at FreeCAD's default width:
    a new user's window (the Report view hidden), and one where warnings opened the
    Report view (a shorter task view, so it scrolls: its scroll bar takes width)."""
    window = FreeCADGui.getMainWindow()
    saved = window.size()
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    close_panels()
    window.showNormal()
    window.resize(*SCREEN_PX)
    # A new user's window: the Report view (shown by earlier warnings) is hidden by default.
    reports = [d for d in window.findChildren(QtGui.QDockWidget) if d.objectName() == "Report view"]
    was_visible = [d.isVisible() for d in reports]
    for dock in reports:
        dock.setVisible(request.param == "report view shown")
    process_events()
    window.report_view_shown = request.param == "report view shown"
    yield window
    close_panels()
    for dock, visible in zip(reports, was_visible):
        dock.setVisible(visible)
    window.resize(saved)
    process_events()


def _fit_dock(window, form):
    docks = [d for d in window.findChildren(QtGui.QDockWidget)
             if d.isVisible() and form in d.findChildren(QtGui.QWidget)]
    if docks and hasattr(window, "resizeDocks"):
        window.resizeDocks(docks, [DEFAULT_DOCK_PX], QtCore.Qt.Horizontal)
    process_events()


def _in_splitter(widget, form):
    parent = widget.parentWidget()
    while parent is not None and parent is not form:
        if isinstance(parent, QtGui.QSplitter):
            return True
        parent = parent.parentWidget()
    return False


def _settled_right_edge(form, viewport, rounds=20):
    """The form's right edge in the task view's viewport once the layout has settled.

    When the vertical scroll bar appears, the viewport narrows (FreeCAD 1.1's task
    overlay: 379 -> 374 px) one event-loop pass before the scroll area narrows the form
    to it; measured in between, a fitting form looks 5 px too wide (seen in two 1.1 CI
    runs, on two panels). So the events are processed until the edge stops moving."""
    right = None
    for _ in range(rounds):
        process_events()
        now = form.mapTo(viewport, QtCore.QPoint(form.width(), 0)).x()
        if now == right:
            break
        right = now
        time.sleep(0.02)
    return right


def problems(panel, buttons_in_view=True):
    """What is not usable in `panel` as shown: a list of sentences (empty: it fits).
    With `buttons_in_view` False only the width is checked."""
    form = panel.form
    found = []
    area = _task_scroll_area(form)
    area.verticalScrollBar().setValue(0)
    viewport = area.viewport()
    right = _settled_right_edge(form, viewport)
    if right > viewport.width() + 1:
        found.append("cut off on the right: the form ends at %d px of the task view's %d"
                     % (right, viewport.width()))
    for table in form.findChildren(QtGui.QAbstractItemView):
        if not table.isVisible() or not isinstance(table, (QtGui.QTableView, QtGui.QTreeView)):
            continue
        bar = table.horizontalScrollBar()
        if bar.maximum() > 0:
            found.append("table '%s' scrolls sideways by %d px" % (
                table.objectName() or type(table).__name__, bar.maximum()))
    for button in [getattr(panel, name) for name in panel.ACTION_BUTTONS]:
        if not button.isVisible() or not buttons_in_view:
            continue
        bottom = button.mapTo(viewport, QtCore.QPoint(0, button.height())).y()
        right_edge = button.mapTo(viewport, QtCore.QPoint(button.width(), 0)).x()
        if bottom > viewport.height() or right_edge > viewport.width() + 1:
            found.append("button '%s' is out of view (bottom %d px of %d, right %d px of %d)" % (
                button.text(), bottom, viewport.height(), right_edge, viewport.width()))
    for text in form.findChildren(QtGui.QPlainTextEdit) + form.findChildren(QtGui.QTextEdit):
        if text.isVisible() and text.isReadOnly() and not _in_splitter(text, form):
            found.append("read-only text '%s' is not in a resizable area (QSplitter)"
                         % (text.objectName() or type(text).__name__))
    return found


def _check_panel(window, panel, name, tmp_path):
    process_events()
    _fit_dock(window, panel.form)
    shown = getattr(window, "report_view_shown", False)
    path = os.path.join(_shot_folder(tmp_path), "panel_%s_1366x768%s.png"
                        % (name, "_report_view" if shown else ""))
    assert window.grab().save(path)
    # With the Report view open the task view is about 370 px tall: buttons below the
    # fold are expected there, a panel wider than the view is not.
    found = problems(panel, buttons_in_view=not shown)
    print("%s: %s" % (name, "; ".join(found) or "fits"))
    assert not found, "%s panel at 1366x768: %s (screenshot %s)" % (name, "; ".join(found), path)


@pytest.fixture
def seam_cell(gui_doc):
    import seam_tracking_cell
    built = seam_tracking_cell.build(gui_doc)
    gui_doc.recompute()
    return built["cell"] if isinstance(built, dict) else built


def test_new_cell_panel_fits(small_window, gui_doc, tmp_path):
    from CadRobotWB.gui import new_cell_panel
    panel = new_cell_panel.open_panel(gui_doc)
    _check_panel(small_window, panel, "new_cell", tmp_path)


def test_generate_panel_fits(small_window, seam_cell, tmp_path):
    from CadRobotWB.gui import generate_panel
    panel = generate_panel.open_panel(seam_cell)
    _check_panel(small_window, panel, "generate", tmp_path)


def test_place_panel_fits(small_window, seam_cell, tmp_path):
    from CadRobotWB.gui import place_panel
    panel = place_panel.open_panel(seam_cell)
    _check_panel(small_window, panel, "place_robot", tmp_path)


def test_risk_area_panel_fits(small_window, seam_cell, tmp_path):
    from CadRobotWB.gui import risk_area_panel
    panel = risk_area_panel.open_panel(seam_cell)
    _check_panel(small_window, panel, "risk_area", tmp_path)


def test_weld_panel_fits(small_window, seam_cell, tmp_path):
    from CadRobotWB.gui import weld_panel
    panel = weld_panel.open_panel(seam_cell)
    panel.weave_group.setChecked(True)
    _check_panel(small_window, panel, "weld", tmp_path)


def test_sensor_run_panel_fits(small_window, seam_cell, tmp_path):
    from CadRobotWB.gui import sensor_run_panel
    panel = sensor_run_panel.open_panel(seam_cell)
    _check_panel(small_window, panel, "sensor_run", tmp_path)


def test_calibration_panel_fits(small_window, seam_cell, tmp_path):
    from CadRobotWB.gui import calibration_panel
    panel = calibration_panel.edit(seam_cell.CalibrationFrame)
    _check_panel(small_window, panel, "calibration", tmp_path)


def test_simulation_player_fits(small_window, seam_cell, tmp_path):
    from CadRobotWB.gui import simulation_player
    panel = simulation_player.open_player(seam_cell)
    _check_panel(small_window, panel, "simulation_player", tmp_path)


def test_edit_tool_panel_fits(small_window, seam_cell, tmp_path):
    from CadRobotWB.gui import tool_group
    panel = tool_group.open_edit_panel(seam_cell)
    _check_panel(small_window, panel, "edit_tool", tmp_path)
