"""CadRobot_SensorRun in the real FreeCAD window: set up a deviation, run the laser or the
force sensor, read the results and plots, play nominal and corrected paths in the 3D view."""

import os

import numpy as np
import pytest

import FreeCADGui
from PySide import QtGui

from conftest import process_events, render

from CadRobotWB.gui import sensor_run_panel, simulation_player

NAME = "CadRobot_SensorRun"


@pytest.fixture
def cleanup():
    yield
    sensor_run_panel.close_panel()
    simulation_player.close_player()
    process_events()


@pytest.fixture
def seam_cell(gui_doc, cleanup):
    import seam_tracking_cell
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    cell = seam_tracking_cell.build(gui_doc)
    gui_doc.recompute()
    FreeCADGui.Selection.clearSelection()
    process_events()
    return cell


@pytest.fixture
def profile_cell(gui_doc, cleanup):
    import profile_following_cell
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    cell = profile_following_cell.build(gui_doc)
    gui_doc.recompute()
    FreeCADGui.Selection.clearSelection()
    process_events()
    return cell


def set_deviation(panel, values):
    for box, value in zip(panel.deviation_boxes, values):
        box.setValue(value)


def png_size(png):
    image = QtGui.QImage()
    assert image.loadFromData(png, "PNG")
    return image.width(), image.height()


def assert_plot_shown(panel, index):
    """The plot fills the label's width, in the PNG's proportions."""
    process_events()
    label = panel.plot_label
    pixmap = label.pixmap()
    assert pixmap is not None and not pixmap.isNull() and label.isVisible()
    width, height = png_size(panel.plots[index][1])
    assert 200 < label.width() < width and pixmap.width() == label.width()
    assert abs(pixmap.height() - pixmap.width() * height / width) <= 1
    assert label.height() == pixmap.height()
    assert (label.full.width(), label.full.height()) == (width, height)
    assert label.toolTip() == panel.plots[index][0]


def save_screenshot(panel, path):
    """The panel as the user sees it (shown in the task view), saved as a PNG."""
    process_events()
    assert panel.form.grab().save(str(path))
    shots = os.environ.get("CADROBOT_SCREENSHOTS")
    if shots:
        panel.form.grab().save(os.path.join(shots, os.path.basename(str(path))))


def test_the_command_is_in_the_toolbar_and_active_only_with_a_cell(gui_doc):
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    process_events()
    assert NAME in FreeCADGui.listCommands()
    command = FreeCADGui.Command.get(NAME)
    assert not command.isActive(), "no cell in the document yet"
    info = command.getInfo()
    assert info["pixmap"].endswith(NAME + ".svg") and os.path.isfile(info["pixmap"])
    assert info["menuText"] == "Sensor run" and info["toolTip"]
    toolbar = FreeCADGui.getMainWindow().findChild(QtGui.QToolBar, "CadRobot")
    assert "Sensor run" in [a.text() for a in toolbar.actions()]
    import seam_tracking_cell
    seam_tracking_cell.build(gui_doc)
    gui_doc.recompute()
    process_events()
    assert command.isActive()


def test_a_laser_run_tracks_the_deviated_seam_and_plays_both_paths(seam_cell, tmp_path):
    objects_before = len(seam_cell.Document.Objects)
    FreeCADGui.runCommand(NAME)
    process_events()
    panel = sensor_run_panel.active_panel()
    assert panel is not None and FreeCADGui.Control.activeDialog()
    assert panel.settings() == {"sensor": "laser", "controller": "pi", "rate_hz": 5.0,
                                "deviation": (0.0,) * 6, "seed": 0}
    assert not panel.plot_label.isVisible() and not panel.play_button.isVisible()
    save_screenshot(panel, tmp_path / "sensor_run_setup.png")

    set_deviation(panel, (0, 5, 2, 0, 0, 1))
    panel.run_button.click()
    process_events()
    assert [r.controller for r in panel.runs] == ["pi", "none"]
    run = panel.runs[0]
    rms = run.metrics["rms_error_after_20mm_mm"]
    assert not run.aborted and rms < 0.2
    text = panel.results_label.text()
    assert "completed" in text and "%.3f" % rms in text and "aborted" not in text
    assert "Corrected program: %d moves from %d samples" % (
        run.metrics["corrected_moves"], len(run.time_s)) in text
    open_loop = panel.runs[1].metrics["rms_error_after_20mm_mm"]
    assert open_loop > 2.0 and "<b>Open loop</b>: completed. RMS error after 20 mm %.3f mm" % open_loop in text
    assert "red" not in panel.results_label.styleSheet()

    assert [title for title, _ in panel.plots] == ["Seam corrections", "Paths"]
    assert panel.plot_box.currentIndex() == 0 and panel.plot_label.isVisible()
    assert_plot_shown(panel, 0)
    save_screenshot(panel, tmp_path / "sensor_run_laser.png")
    panel.plot_box.setCurrentIndex(1)                   # as the user picks it
    process_events()
    assert_plot_shown(panel, 1)
    save_screenshot(panel, tmp_path / "sensor_run_paths.png")
    # The plot follows the panel's width and does not widen it.
    wide = panel.plot_label.width()
    panel.plot_label.resize(wide - 60, panel.plot_label.height())
    assert panel.plot_label.pixmap().width() == wide - 60
    window = panel.full_size_button.click() or panel.full_size_window
    process_events()
    shown = window.findChild(QtGui.QLabel).pixmap()
    assert window.isVisible() and (shown.width(), shown.height()) == png_size(panel.plots[1][1])
    window.close()

    panel.play_button.click()
    for _ in range(50):
        process_events()
        if simulation_player.active_player() is not None:
            break
    player = simulation_player.active_player()
    assert player is not None and sensor_run_panel.active_panel() is None
    assert len(player.robot.polylines) == 2 and all(p.visible for p in player.robot.polylines)
    legend = [label.text() for label in player.form.findChildren(QtGui.QLabel)
              if label.text().startswith("\u25a0")]
    assert legend == ["\u25a0 nominal", "\u25a0 corrected"]
    timeline = player.timeline
    assert timeline.failure is None and len(timeline) == len(run.time_s)
    # The robot follows the corrected path: its TCP ends where the run's TCP ended.
    player.show_frame(len(timeline) - 1)
    np.testing.assert_allclose(timeline.tcp_u[-1], run.actual_mm[-1], atol=1e-3)
    view = FreeCADGui.getDocument(seam_cell.Document.Name).activeView()
    view.viewIsometric()
    view.fitAll()
    render(view, tmp_path / "sensor_run_played.png")
    shots = os.environ.get("CADROBOT_SCREENSHOTS")
    if shots:
        render(view, os.path.join(shots, "sensor_run_played.png"))
        save_screenshot(player, tmp_path / "sensor_run_player.png")
    assert len(seam_cell.Document.Objects) == objects_before, "the panel added document objects"


def test_corrected_poses_keep_the_nominal_orientation_at_the_runs_times(seam_cell):
    panel = sensor_run_panel.open_panel(seam_cell, {"deviation": (0, 3, 0, 0, 0, 0)})
    assert panel.run()
    (_, T_nominal, t_nominal), (_, T_corrected, t_corrected) = sensor_run_panel.player_trajectories(
        panel.scene, panel.runs[0])
    run = panel.runs[0]
    assert T_corrected.shape == (len(run.time_s), 4, 4)
    np.testing.assert_allclose(t_corrected, run.time_s)
    np.testing.assert_allclose(T_corrected[:, :3, 3], run.actual_mm)
    nearest = np.abs(t_nominal[None, :] - run.time_s[:, None]).argmin(axis=1)
    np.testing.assert_allclose(T_corrected[:, :3, :3], T_nominal[nearest, :3, :3], atol=1e-12)


def test_the_profile_cell_runs_the_force_sensor_with_pi_and_fuzzy_pi(profile_cell, tmp_path):
    panel = sensor_run_panel.open_panel(profile_cell)
    settings = panel.settings()
    assert settings["sensor"] == "force" and settings["rate_hz"] == 20.0
    set_deviation(panel, (0, 0, -3, 0, 0, 0))
    assert panel.run()
    assert [r.controller for r in panel.runs] == ["pi", "fuzzy_pi", "none"]
    text = panel.results_label.text()
    for run in panel.runs[:2]:
        error = run.metrics["rms_force_error_pct"]
        assert not run.aborted and error < 10.0
        assert "%.1f %%" % error in text
    assert "<b>PI</b>: completed" in text and "<b>Fuzzy-PI</b>: completed" in text
    # The part lies 3 mm low: without correction the ball never reaches it.
    assert "<b>Open loop</b>: completed. The tool never touched the part" in text
    assert panel.plots[0][0] == "Contact force"
    assert_plot_shown(panel, 0)
    save_screenshot(panel, tmp_path / "sensor_run_force.png")

    # Choosing the sensor sets its rate; choosing "none" runs the open loop alone.
    panel.sensor_box.setCurrentIndex(panel.sensor_box.findData("laser"))
    assert panel.settings()["rate_hz"] == 5.0
    assert sensor_run_panel.controllers_to_run("force", "fuzzy_pi") == ["fuzzy_pi", "pi", "none"]
    assert sensor_run_panel.controllers_to_run("laser", "none") == ["none"]


def test_a_bad_cell_shows_the_error_in_red_and_selects_the_object_at_fault(seam_cell, tmp_path):
    doc = seam_cell.Document
    doc.removeObject(seam_cell.CalibrationFrame.Name)
    doc.recompute()
    panel = sensor_run_panel.open_panel(seam_cell)
    assert not panel.run()
    text = panel.results_label.text()
    assert "was deleted" in text and "TableFrame" in text
    assert "red" in panel.results_label.styleSheet()
    assert not panel.plot_label.isVisible() and not panel.play_button.isVisible()
    assert [o.Name for o in FreeCADGui.Selection.getSelection()] == [seam_cell.Name]
    assert sensor_run_panel.active_panel() is panel and FreeCADGui.Control.activeDialog()
    save_screenshot(panel, tmp_path / "sensor_run_error.png")
