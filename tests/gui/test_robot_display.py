"""The cell's robot in the 3D view: at its base, in its start pose, hidden with the
cell or ShowRobot, drawn again when a saved file is opened, previewed by the New
cell panel, and never twice while the player runs.

Poses are read back from the Coin nodes and compared with robots.checks.links; pixels
are counted in renders on white (robot_view.ROBOT_COLOR is yellow).
"""

import subprocess
import textwrap

import numpy as np
import Part
import pytest
from pivy import coin

import FreeCAD
import FreeCADGui

from conftest import REPO, process_events, render
from test_view_display import rgb

from CadRobotWB import api
from CadRobotWB.gui import new_cell_panel, robot_display, simulation_player
from CadRobotWB.robots.checks import links
from CadRobotWB.robots.motion import configuration

V = FreeCAD.Vector
#: A start pose away from the reference pose: the arm points elsewhere.
START_JOINTS = [60.0, -30.0, 20.0, 45.0, -60.0, 90.0]


# --- helpers -------------------------------------------------------------------------------

def yellow(pixels):
    """Mask (H, W) of robot-yellow pixels: hue 40-55 degrees, saturated, not dark
    (ROBOT_COLOR lit by the view's light)."""
    r, g, b = pixels[..., 0], pixels[..., 1], pixels[..., 2]
    high, low = pixels.max(axis=-1), pixels.min(axis=-1)
    span = np.maximum(high - low, 1)
    hue = 60.0 * (g - b) / span
    return (r == high) & (hue >= 40) & (hue <= 55) & (span * 255 > 150 * high) & (high > 60)


def centroid(mask):
    ys, xs = np.nonzero(mask)
    assert len(xs), "no robot pixels"
    return np.array([xs.mean(), ys.mean()])


def view_of(doc):
    return FreeCADGui.getDocument(doc.Name).activeView()


def top_pixels(doc, tmp_path, name, fit=True):
    """Robot-yellow mask of a top view render (480 x 360), fitted to the scene when `fit`."""
    view = view_of(doc)
    view.viewTop()
    if fit:
        view.fitAll()
    return yellow(rgb(render(view, tmp_path / ("%s.png" % name), 480, 360)))


def floor(doc, x0, x1, y0, y1):
    """A thin grey plate below the robots: fixes the fitted view and gives its scale."""
    plate = doc.addObject("Part::Feature", "Floor")
    plate.Shape = Part.makeBox(x1 - x0, y1 - y0, 5.0, V(x0, y0, -20.0))
    doc.recompute()
    return plate


def expected_links(cell, q_deg):
    """(7, 4, 4) link frames in {U}: cell Placement @ links.link_frames(model, q)."""
    model = api.robot(cell.Robot)
    return api.matrix_from_placement(cell.Placement) @ links.link_frames(model, np.asarray(q_deg))


def display(cell):
    return cell.ViewObject.Proxy.robot_display


def robots_drawn(doc):
    """How many robots the view draws (RobotView roots reachable through switches that are on)."""
    search = coin.SoSearchAction()
    search.setName("CadRobotRobotView")
    search.setInterest(coin.SoSearchAction.ALL)
    search.setSearchingAll(False)
    search.apply(view_of(doc).getSceneGraph())
    return search.getPaths().getLength()


# --- the cell's robot ----------------------------------------------------------------------

def test_a_cell_shows_its_robot_yellow_at_its_base_and_hides_it(gui_doc, tmp_path):
    cell = api.make_cell(gui_doc)
    shown = top_pixels(gui_doc, tmp_path, "shown")
    count = int(shown.sum())
    print("robot pixels, top view fitted:", count)
    assert count > 2000
    # Fitted to the robot alone: its base (the image centre's neighbourhood) is covered.
    h, w = shown.shape
    assert shown[h // 2 - 40:h // 2 + 40, w // 2 - 40:w // 2 + 40].any()

    cell.ViewObject.ShowRobot = False
    assert top_pixels(gui_doc, tmp_path, "show_robot_off", fit=False).sum() == 0
    cell.ViewObject.ShowRobot = True
    cell.ViewObject.Visibility = False
    assert top_pixels(gui_doc, tmp_path, "cell_hidden", fit=False).sum() == 0
    cell.ViewObject.Visibility = True
    assert top_pixels(gui_doc, tmp_path, "shown_again", fit=False).sum() == count


def test_moving_the_placement_moves_the_robot_pixels(gui_doc, tmp_path):
    cell = api.make_cell(gui_doc)
    plate = floor(gui_doc, -700.0, 1900.0, -500.0, 800.0)
    before = top_pixels(gui_doc, tmp_path, "before")
    grey = rgb(render(view_of(gui_doc), tmp_path / "scale.png", 480, 360)).min(axis=-1) < 245
    xs = np.nonzero(grey.any(axis=0))[0]
    px_per_mm = (xs.max() - xs.min() + 1) / plate.Shape.BoundBox.XLength
    cell.Placement = FreeCAD.Placement(V(800, 300, 0), FreeCAD.Rotation())
    gui_doc.recompute()
    after = top_pixels(gui_doc, tmp_path, "after", fit=False)
    shift = centroid(after) - centroid(before)
    expected = np.array([800.0, -300.0]) * px_per_mm       # image y grows downwards
    print("robot pixels %d -> %d; centroid shift %s px, expected %s px (%.4f px/mm)"
          % (before.sum(), after.sum(), shift.round(2), expected.round(2), px_per_mm))
    assert abs(int(after.sum()) - int(before.sum())) < 0.05 * before.sum()
    np.testing.assert_allclose(shift, expected, atol=2.0)


def test_the_robot_stands_in_the_start_pose(gui_doc):
    import seam_tracking_cell
    cell = seam_tracking_cell.build(gui_doc)
    gui_doc.recompute()
    drawn = display(cell).robot
    solver_start = api.check(cell, collisions=False).solution.reference_deg
    np.testing.assert_allclose(drawn.link_matrices(), expected_links(cell, solver_start), atol=1e-3)

    cell.StartJoints = START_JOINTS
    gui_doc.recompute()
    np.testing.assert_allclose(drawn.link_matrices(), expected_links(cell, START_JOINTS), atol=1e-3)
    assert np.abs(drawn.link_matrices()[6, :3, 3] - expected_links(cell, solver_start)[6, :3, 3]).max() > 100

    cell.ToolTCP = FreeCAD.Placement(V(0, 0, 250), FreeCAD.Rotation())
    cell.Robot = "KUKA_KR16"
    gui_doc.recompute()
    drawn = display(cell).robot
    assert drawn.model.spec.name == "KUKA_KR16"
    np.testing.assert_allclose(drawn.link_matrices(), expected_links(cell, START_JOINTS), atol=1e-3)


def reopened_matches(path, name, q_deg):
    """Open `path`; its cell `name` draws its robot at its Placement in pose `q_deg`, and it
    is the only robot drawn."""
    doc = FreeCAD.openDocument(path)
    try:
        for _ in range(5):
            process_events()
        cell = doc.getObject(name)
        assert display(cell).shown and robots_drawn(doc) == 1
        np.testing.assert_allclose(display(cell).robot.link_matrices(), expected_links(cell, q_deg),
                                   atol=1e-3)
    finally:
        FreeCAD.closeDocument(doc.Name)


def test_a_reopened_document_shows_the_robot_again(gui_doc, tmp_path):
    cell = api.make_cell(gui_doc, placement=FreeCAD.Placement(V(100, 200, 0), FreeCAD.Rotation(30, 0, 0)))
    cell.StartJoints = START_JOINTS
    api.make_cell(gui_doc, name="NoRobotShown").ViewObject.ShowRobot = False
    gui_doc.recompute()
    path, name = str(tmp_path / "cell.FCStd"), cell.Name
    gui_doc.saveAs(path)
    FreeCAD.closeDocument(gui_doc.Name)
    reopened_matches(path, name, START_JOINTS)


def test_a_document_saved_headless_shows_the_robot(gui_doc, tmp_path):
    path = tmp_path / "headless.FCStd"
    script = tmp_path / "make_cell.py"
    script.write_text(textwrap.dedent("""
        import sys
        import FreeCAD
        from CadRobotWB import api
        doc = FreeCAD.newDocument("Headless")
        cell = api.make_cell(doc, placement=FreeCAD.Placement(FreeCAD.Vector(500, 0, 0),
                                                                FreeCAD.Rotation()))
        cell.StartJoints = %r
        doc.saveAs(sys.argv[1])
    """ % START_JOINTS))
    done = subprocess.run(["/usr/bin/python3", "tools/freecad_run.py", str(script), str(path)],
                          cwd=REPO, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0 and path.is_file(), done.stderr[-3000:]
    reopened_matches(str(path), "Cell", START_JOINTS)


# --- the New cell panel's preview ----------------------------------------------------------

def test_the_new_cell_panel_previews_the_robot_until_cancel(gui_doc, tmp_path):
    FreeCADGui.Selection.clearSelection()
    floor(gui_doc, -2000.0, 2000.0, -2000.0, 2000.0)
    objects, undo = len(gui_doc.Objects), gui_doc.UndoCount
    before = top_pixels(gui_doc, tmp_path, "no_panel")
    panel = new_cell_panel.open_panel(gui_doc)
    try:
        process_events()
        first = top_pixels(gui_doc, tmp_path, "preview", fit=False)
        panel.x.setValue(600.0)                                   # as the user types
        moved = top_pixels(gui_doc, tmp_path, "preview_moved", fit=False)
        panel.select_robot("MOTOMAN_HP6")
        other = top_pixels(gui_doc, tmp_path, "preview_hp6", fit=False)
        print("preview pixels %d, moved %d (centroid dx %.1f px), HP6 %d"
              % (first.sum(), moved.sum(), centroid(moved)[0] - centroid(first)[0], other.sum()))
        assert before.sum() == 0 and first.sum() > 300
        assert centroid(moved)[0] - centroid(first)[0] > 20
        assert other.sum() > 300 and (other != moved).sum() > 100     # another robot, same base
        assert robots_drawn(gui_doc) == 1
        T_u_r = api.matrix_from_placement(FreeCAD.Placement(V(600, 0, 0), FreeCAD.Rotation()))
        model = api.robot("MOTOMAN_HP6")
        np.testing.assert_allclose(panel.preview.link_matrices(),
                                   T_u_r @ links.link_frames(model, configuration.reference_joints(model)),
                                   atol=1e-3)
        assert len(gui_doc.Objects) == objects and gui_doc.UndoCount == undo
    finally:
        panel.reject()                                            # Cancel
    process_events()
    assert new_cell_panel.active_panel() is None and robots_drawn(gui_doc) == 0
    assert top_pixels(gui_doc, tmp_path, "cancelled", fit=False).sum() == 0
    assert len(gui_doc.Objects) == objects and gui_doc.UndoCount == undo


def test_ok_leaves_one_robot_the_cells(gui_doc):
    FreeCADGui.Selection.clearSelection()
    panel = new_cell_panel.open_panel(gui_doc)
    panel.y.setValue(250.0)
    assert robots_drawn(gui_doc) == 1
    assert panel.accept()
    process_events()
    cell, = api.find_cells(gui_doc)
    assert panel.preview is None and robots_drawn(gui_doc) == 1 and display(cell).shown


# --- the player ----------------------------------------------------------------------------

@pytest.fixture
def seam_cell(gui_doc):
    import seam_tracking_cell
    cell = seam_tracking_cell.build(gui_doc)
    gui_doc.recompute()
    yield cell
    simulation_player.close_player()
    process_events()


def test_no_second_robot_while_the_player_runs(seam_cell, tmp_path):
    doc = seam_cell.Document
    assert robots_drawn(doc) == 1 and display(seam_cell).shown
    player = simulation_player.open_player(seam_cell)
    process_events()
    assert robots_drawn(doc) == 1 and not display(seam_cell).shown
    player.slider.setValue(len(player.timeline) // 2)
    process_events()
    assert robots_drawn(doc) == 1
    simulation_player.close_player()
    process_events()
    assert robots_drawn(doc) == 1 and display(seam_cell).shown


def test_held_robot_of_a_deleted_cell_is_no_error(seam_cell):
    doc = seam_cell.Document
    simulation_player.open_player(seam_cell)
    doc.removeObject(seam_cell.Name)
    simulation_player.close_player()            # must not raise
    assert robot_display.display_of(seam_cell) is None and robots_drawn(doc) == 0
