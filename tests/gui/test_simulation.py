"""Check and Simulate in the real FreeCAD window: the robot in the 3D view, the player, the
status overlay.

Expected robot poses come from robots.checks.links / the kinematic model and the
program's own targets, read back from the Coin nodes the view draws; pixel
colours from the saved images.
"""

import time

import numpy as np
import pytest

import FreeCAD
import FreeCADGui
from PySide import QtGui

from conftest import process_events, render

from CadRobotWB import api
from CadRobotWB.core.trajectory import target_in_u, tcp_trajectory
from CadRobotWB.gui import robot_view, simulation_player, status_overlay
from CadRobotWB.robots.checks import links

COMMANDS = ("CadRobot_Check", "CadRobot_Simulate")


@pytest.fixture
def seam_cell(gui_doc):
    import seam_tracking_cell
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    cell = seam_tracking_cell.build(gui_doc)
    gui_doc.recompute()
    FreeCADGui.Selection.clearSelection()
    process_events()
    yield cell
    simulation_player.close_player()
    status_overlay.remove()
    from CadRobotWB.commands import base
    if base._message_box is not None:
        base._message_box.close()
    process_events()


def out_of_reach(cell, x_mm):
    """Move the robot base along x (the part stays): part or all of the seam out of reach."""
    cell.Placement = FreeCAD.Placement(FreeCAD.Vector(x_mm, 0, 0), FreeCAD.Rotation())
    cell.Document.recompute()


def view_of(cell):
    return FreeCADGui.getDocument(cell.Document.Name).activeView()


def fitted(view, isometric=True):
    if isometric:
        view.viewIsometric()
    else:
        view.viewFront()
    view.fitAll()
    return view


def base_of(cell):
    return api.matrix_from_placement(cell.Placement)


def hue_counts(image, step=1):
    """Pixel counts: robot yellow (lit), overlay green/red and trace colours (unlit)."""
    counts = dict(yellow=0, green=0, red=0, cyan=0, violet=0, magenta=0)
    for y in range(0, image.height(), step):
        for x in range(0, image.width(), step):
            c = QtGui.QColor(image.pixel(x, y))
            r, g, b = c.red(), c.green(), c.blue()
            h, s, v = c.hsvHue(), c.hsvSaturation(), c.value()
            counts["yellow"] += 40 <= h <= 55 and s > 150 and v > 60
            counts["green"] += g > 150 and r < 60 and b < 60
            counts["red"] += r > 200 and g < 50 and b < 50
            counts["cyan"] += r < 40 and 150 < g < 220 and 150 < b < 220 and abs(g - b) < 20
            counts["violet"] += 70 < r < 110 and 35 < g < 70 and b > 230
            counts["magenta"] += r > 230 and g < 40 and b > 230
    return counts


def hide_document(doc):
    for obj in doc.Objects:
        if obj.ViewObject is not None:
            obj.ViewObject.Visibility = False


# --- commands --------------------------------------------------------------------------------

def test_commands_are_in_the_toolbar_and_active_only_with_a_cell(gui_doc):
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    process_events()
    for name in COMMANDS:
        assert name in FreeCADGui.listCommands()
        assert not FreeCADGui.Command.get(name).isActive(), "no cell in the document yet"
        info = FreeCADGui.Command.get(name).getInfo()
        assert info["pixmap"].endswith(name + ".svg") and info["menuText"] and info["toolTip"]
    toolbar = FreeCADGui.getMainWindow().findChild(QtGui.QToolBar, "CadRobot")
    texts = [a.text() for a in toolbar.actions()]
    assert {"Check cell", "Simulate"} <= set(texts)

    import seam_tracking_cell
    seam_tracking_cell.build(gui_doc)
    gui_doc.recompute()
    process_events()
    for name in COMMANDS:
        assert FreeCADGui.Command.get(name).isActive()


# --- the player ------------------------------------------------------------------------------

def test_the_player_poses_the_robot_by_its_kinematics_and_shows_the_joints(seam_cell, tmp_path):
    objects_before = len(seam_cell.Document.Objects)
    FreeCADGui.runCommand("CadRobot_Simulate")
    process_events()
    player = simulation_player.active_player()
    assert player is not None and FreeCADGui.Control.activeDialog()
    # Both commands only view the cell, so they stay usable while the panel is open.
    toolbar = FreeCADGui.getMainWindow().findChild(QtGui.QToolBar, "CadRobot")
    end = time.time() + 2.0
    while time.time() < end:          # FreeCAD refreshes the actions' state on a timer
        process_events()
        time.sleep(0.02)
    assert all(a.isEnabled() for a in toolbar.actions() if a.text() in ("Check cell", "Simulate"))
    model = api.robot(seam_cell.Robot)
    program = api.generate(seam_cell)
    timeline = player.timeline
    assert timeline.failure is None and "Finished" not in player.status_label.text()
    assert player.robot.polylines == []            # no weld weaves: no woven path drawn

    player.step(1)
    player.step(1)
    player.step(-1)
    assert player.frame == 1 and player.slider.value() == 1
    frames = [1, 37, len(timeline) // 2, len(timeline) - 1]
    for frame in frames:
        player.slider.setValue(frame)                      # as the user drags it
        process_events()
        assert player.frame == frame
        q = timeline.q_deg[frame]
        expected = base_of(seam_cell) @ links.link_frames(model, q)
        read_back = np.array([robot_view.matrix_from_transform(player.robot.base)
                              @ robot_view.matrix_from_transform(t)
                              for t in player.robot.link_transforms])
        np.testing.assert_allclose(read_back, expected, atol=1e-3)
        shown = [float(label.text().rstrip("\u00b0")) for label in player.joint_labels]
        np.testing.assert_allclose(shown, model.controller_joints(q), atol=0.051)

    # At the end of each move the TCP is on that move's target, with the target's joints.
    moves = program.moves()
    for k in (0, 2, 7, len(moves) - 1):
        frame = int(np.flatnonzero(timeline.move_index == k)[-1])
        player.show_frame(frame)
        T_u_t = player.robot.link_matrices()[6] @ program.tool.T_f_t
        np.testing.assert_allclose(T_u_t, target_in_u(program, moves[k], moves[k].target), atol=1e-3)
        shown = [float(label.text().rstrip("\u00b0")) for label in player.joint_labels]
        np.testing.assert_allclose(shown, model.controller_joints(moves[k].target.joints_deg),
                                   atol=0.051)
        assert moves[k].target.name in player.move_label.text()
    assert "Finished" in player.status_label.text()

    # The robot stands in the view: a render shows its yellow, none without it.
    view = fitted(view_of(seam_cell))
    player.show_frame(int(np.flatnonzero(timeline.move_index == 2)[-1]))
    with_robot = hue_counts(render(view, tmp_path / "robot_at_seam.png"))
    fitted(view_of(seam_cell), isometric=False)
    render(view, tmp_path / "robot_front.png")
    assert with_robot["yellow"] > 3000 and with_robot["magenta"] > 50     # robot and TCP trace
    assert len(seam_cell.Document.Objects) == objects_before, "the player added document objects"

    simulation_player.close_player()
    process_events()
    assert not player.robot.shown and not FreeCADGui.Control.activeDialog()
    seam_cell.ViewObject.ShowRobot = False      # the cell's own robot is back (test_robot_display)
    without = hue_counts(render(fitted(view), tmp_path / "no_robot.png"))
    assert without["yellow"] < 50 and without["magenta"] == 0


def play_to_end(player, timeout_s=30.0):
    player.set_speed(10.0)
    player.play()
    end = time.time() + timeout_s
    while player.playing and time.time() < end:
        process_events()
        time.sleep(0.01)
    assert not player.playing, "playback did not stop"


def test_playback_stops_at_the_first_unreachable_target_with_the_reason_in_red(seam_cell, tmp_path):
    out_of_reach(seam_cell, -800.0)          # the seam's start is reachable, its middle is not
    player = simulation_player.open_player(seam_cell)
    failure = player.timeline.failure
    assert failure is not None and failure.target == "Seam_30" and failure.sample > 10
    assert "Stopped" not in player.status_label.text()
    play_to_end(player)
    assert player.frame == failure.sample == len(player.timeline) - 1
    text = player.status_label.text()
    assert "Seam_30" in text and "out of reach" in text
    assert "red" in player.status_label.styleSheet()
    # Where it stopped the robot really stands, on the line towards the target.
    model = api.robot(seam_cell.Robot)
    expected = base_of(seam_cell) @ links.link_frames(model, player.timeline.q_deg[-1])
    np.testing.assert_allclose(player.robot.link_matrices(), expected, atol=1e-3)
    render(fitted(view_of(seam_cell)), tmp_path / "stopped.png")


def test_a_cell_far_out_of_reach_stops_before_the_first_move(seam_cell):
    out_of_reach(seam_cell, -3000.0)
    player = simulation_player.open_player(seam_cell)
    assert len(player.timeline) == 1
    text = player.status_label.text()
    assert "Seam_10" in text and "out of reach" in text and "red" in player.status_label.styleSheet()


def zoom_front_on(view, points):
    """Centre the front view's (orthographic) camera on points (M, 3) and zoom to them."""
    camera = view.getCameraNode()
    low, high = points.min(axis=0), points.max(axis=0)
    centre = 0.5 * (low + high)
    x, y, z = camera.position.getValue().getValue()
    camera.position.setValue(centre[0], y, centre[2])
    camera.height.setValue(1.5 * max(high[0] - low[0], high[2] - low[2]))


def test_a_pair_of_sensor_paths_is_drawn_as_two_traces_and_followed(seam_cell, tmp_path):
    program = api.generate(seam_cell)
    path = [k for k, m in enumerate(program.moves()) if m.role in ("path", "risk")]
    nominal = tcp_trajectory(program, 0.2, first_move=path[0], last_move=path[-1])
    corrected = nominal.T_u_t.copy()
    corrected[:, :3, 3] += [0.0, 0.0, 25.0] * np.sin(np.linspace(0, np.pi, len(corrected)))[:, None]
    hide_document(seam_cell.Document)
    player = simulation_player.open_player(
        seam_cell, [("nominal", nominal.T_u_t, nominal.time_s), ("corrected", corrected, nominal.time_s)])
    robot = player.robot
    assert len(robot.polylines) == 2 and all(p.visible for p in robot.polylines)
    assert player.timeline.failure is None and len(player.timeline) == len(nominal.time_s)
    player.show_frame(len(player.timeline) - 1)
    T_u_t = robot.link_matrices()[6] @ program.tool.T_f_t
    np.testing.assert_allclose(T_u_t, corrected[-1], atol=1e-3)           # follows the last one
    view = view_of(seam_cell)
    view.viewFront()
    view.fitAll()
    zoom_front_on(view, np.vstack([nominal.position_mm, corrected[:, :3, 3]]))
    player.robot.set_trace([])
    counts = hue_counts(render(view, tmp_path / "two_traces.png"))
    assert counts["cyan"] > 30 and counts["violet"] > 30, counts


# --- the check overlay -------------------------------------------------------------------------

def overlay_counts(cell, tmp_path, name):
    hide_document(cell.Document)
    view = view_of(cell)
    view.viewTop()
    view.fitAll()         # the overlay's dots are all that is shown
    return hue_counts(render(view, tmp_path / name))


def test_check_colours_the_seam_cells_targets_green(seam_cell, tmp_path):
    FreeCADGui.runCommand("CadRobot_Check")
    process_events()
    overlay = status_overlay.current(seam_cell.Document.Name)
    assert overlay is not None and overlay.counts() == {"ok": 13, "warning": 0, "error": 0}
    assert overlay.failures == []
    counts = overlay_counts(seam_cell, tmp_path, "check_ok.png")
    assert counts["green"] > 40 and counts["red"] == 0, counts


def test_check_colours_an_unreachable_cells_targets_red_and_keeps_the_reasons(seam_cell, tmp_path):
    out_of_reach(seam_cell, -3000.0)
    FreeCADGui.runCommand("CadRobot_Check")
    process_events()
    overlay = status_overlay.current(seam_cell.Document.Name)
    assert overlay.counts()["error"] == 13
    first = overlay.failures[0]
    assert first.name == "Seam_10" and "out of reach" in first.messages[0]
    counts = overlay_counts(seam_cell, tmp_path, "check_failed.png")
    assert counts["red"] > 40 and counts["green"] == 0, counts
    status_overlay.remove()
    process_events()
    assert overlay_counts(seam_cell, tmp_path, "check_removed.png")["red"] == 0
