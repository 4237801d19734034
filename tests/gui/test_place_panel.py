"""The Place robot command and panel in the real FreeCAD window: search with a progress bar
(and Stop), the heat map on the floor, the robot previewed at a picked placement, Apply as
one undo step journaled as an API call, and the face of a solid as the floor."""

import FreeCAD
import FreeCADGui
import numpy as np
import pytest
from PySide import QtCore

from conftest import close_panels, process_events, render
from CadRobotWB import api
from CadRobotWB.gui import heat_map, place_panel, robot_display
from CadRobotWB.gui.robot_view import matrix_from_transform
from CadRobotWB.robots.placement import placement_search as ps

V = FreeCAD.Vector
FAR = FreeCAD.Placement(V(-1500, 0, 0), FreeCAD.Rotation())


@pytest.fixture
def far_cell(gui_doc):
    import seam_tracking_cell
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    close_panels()
    cell = seam_tracking_cell.build(gui_doc)
    cell.Placement = FAR
    gui_doc.recompute()
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(gui_doc.Name, cell.Name)
    process_events()
    yield cell
    place_panel.close_panel()
    close_panels()


def open_from_toolbar():
    FreeCADGui.runCommand("CadRobot_PlaceRobot")
    process_events()
    panel = place_panel.active_panel()
    assert panel is not None and FreeCADGui.Control.activeDialog()
    return panel


def small_search(panel, count=2):
    for box, value in ((panel.xmin, -1500), (panel.ymin, -1000), (panel.xmax, 1500), (panel.ymax, 1000),
                       (panel.step, 500), (panel.zmin, 0), (panel.zmax, 0)):
        box.setValue(value)
    panel.count.setValue(count)
    return panel.search()


def in_scene(view, node):
    return view.getSceneGraph().findChild(node) >= 0


def matrix(placement):
    return api.matrix_from_placement(placement)


def test_search_pick_preview_apply_and_undo(far_cell, tmp_path):
    doc = far_cell.Document
    view = FreeCADGui.getDocument(doc.Name).activeView()
    panel = open_from_toolbar()
    reports = []
    panel_progress = panel._progress
    panel._progress = lambda f, text: reports.append(f) or panel_progress(f, text)
    result = small_search(panel)
    assert result is not None and len(result) == 2
    assert reports and reports[-1] == 1.0 and panel.progress.value() == 1000
    assert panel.list.count() == 2 and panel.list.item(0).text().startswith("1. score ")
    assert "35 candidate bases" in panel.message.text()
    # The heat map: 7 x 5 squares, grey where out of reach, score colours where a base works.
    assert panel.heat is not None and in_scene(view, panel.heat.root)
    assert len(panel.heat.colors) == 35
    grey = np.all(np.isclose(panel.heat.colors, heat_map.FAIL_SCREEN_COLOR), axis=1)
    assert grey.sum() == (result.heat.state == ps.FAILS_SCREEN).sum() > 0
    assert (result.heat.state == ps.PASSES).sum() >= 1
    # Picking a placement draws the robot there, the cell's own robot hidden meanwhile.
    panel.list.setCurrentRow(1)
    process_events()
    picked = result[1]
    assert np.allclose(matrix_from_transform(panel.preview.base), picked.T_u_r, atol=1e-6)
    assert not robot_display.display_of(far_cell).shown
    view.viewTop()
    view.fitAll()
    image = render(view, tmp_path / "heat_map.png")
    assert image.width() == 640
    # Apply: one undo step, journaled as an API call that replays.
    undo_before = doc.UndoCount
    lines = panel.journal_lines(picked)
    assert lines[0].startswith("# x ") and "api.place_robot(FreeCAD.getDocument(" in lines[0]
    assert lines[1].startswith("api.set_robot_placement(FreeCAD.getDocument(%r).getObject(%r), "
                               "FreeCAD.Placement(" % (doc.Name, far_cell.Name))
    assert panel.apply()
    assert np.allclose(matrix(far_cell.Placement), picked.T_u_r, atol=1e-9)
    assert doc.UndoCount == undo_before + 1
    assert api.check(far_cell).ok
    doc.undo()
    process_events()
    assert np.allclose(matrix(far_cell.Placement), matrix(FAR), atol=1e-9)
    namespace = {"FreeCAD": FreeCAD, "api": api}
    exec(lines[1], namespace)                            # what a recorded macro runs
    assert np.allclose(matrix(far_cell.Placement), picked.T_u_r, atol=1e-9)
    # Closing the panel takes the heat map and the preview away.
    heat_root = panel.heat.root
    place_panel.close_panel()
    assert not in_scene(view, heat_root)
    assert robot_display.display_of(far_cell).shown


def test_stop_ends_a_running_search(far_cell):
    panel = open_from_toolbar()
    QtCore.QTimer.singleShot(0, panel.stop)
    assert small_search(panel) is None
    assert panel.message.text() == "Stopped."
    assert panel.search_button.isEnabled() and not panel.stop_button.isEnabled()
    assert panel.heat is None and panel.list.count() == 0


def test_nowhere_says_why_in_red(far_cell):
    panel = open_from_toolbar()
    for box, value in ((panel.xmin, 4000), (panel.ymin, 4000), (panel.xmax, 5000), (panel.ymax, 5000),
                       (panel.step, 500), (panel.zmin, 0), (panel.zmax, 0)):
        box.setValue(value)
    result = panel.search()
    assert result is not None and len(result) == 0
    assert "No placement works here" in panel.message.text()
    assert "unreachable: 13 of 13 targets of path 'Seam'" in panel.message.text()
    assert "red" in panel.message.styleSheet() and not panel.apply_button.isEnabled()
    assert not panel.apply()


def test_a_selected_face_is_the_floor(far_cell):
    doc = far_cell.Document
    plate = doc.addObject("Part::Box", "Pedestal")
    plate.Length, plate.Width, plate.Height = 1000, 800, 50
    plate.Placement.Base = V(-1600, -400, 0)
    doc.recompute()
    top = next("Face%d" % (i + 1) for i, f in enumerate(plate.Shape.Faces)
               if abs(f.normalAt(0, 0).z - 1) < 1e-9)
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, plate.Name, top)
    FreeCADGui.Selection.addSelection(doc.Name, far_cell.Name)
    process_events()
    panel = open_from_toolbar()
    assert panel.face == (plate, top)
    assert [b.value() for b in (panel.xmin, panel.ymin, panel.xmax, panel.ymax, panel.zmin)] == \
        [-1600, -400, -600, 400, 50]
    assert panel.arguments()["face"] == (plate, top)
    side = next("Face%d" % (i + 1) for i, f in enumerate(plate.Shape.Faces)
                if abs(f.normalAt(0, 0).z) < 1e-9)
    assert not panel.use_face((plate, side))
    assert "tilted 90 deg" in panel.message.text()


def test_default_heights_reach_down_to_a_table(far_cell):
    """The heights searched by default: from half the robot's reach below the lowest target
    (rounded down to 100 mm) up to the robot's present height."""
    import numpy as np
    from CadRobotWB import api
    from CadRobotWB.robots.catalog import catalog
    program = api.generate(far_cell)
    T_u_b = np.asarray(next(iter(program.frames.values())).T_u_b)
    lowest = min((T_u_b @ np.r_[m.target.position_mm, 1.0])[2] for m in program.moves())
    reach = catalog.reach_mm(catalog.get(far_cell.Robot))
    z_now = far_cell.Placement.Base.z
    *_, (z_low, z_high) = place_panel.default_region(far_cell)
    assert z_high == z_now
    assert z_low == min(z_now, 100.0 * np.floor((lowest - reach / 2) / 100.0))
    assert z_low < lowest - 0.4 * reach
