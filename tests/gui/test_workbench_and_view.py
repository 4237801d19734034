"""The workbench in the real FreeCAD window, and a cell built by script drawn in the 3D view."""

import FreeCADGui
from PySide import QtGui

from conftest import non_white_pixels, process_events, render


def test_workbench_activates_with_its_icon():
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    process_events()
    workbench = FreeCADGui.activeWorkbench()
    assert workbench.name() == "CadRobotWorkbench"
    assert workbench.Icon.endswith("CadRobot.svg")
    assert "CadRobotWorkbench" in FreeCADGui.listWorkbenches()


def colour_counts(image):
    """Pixels that are the path's blue and the markers' (shaded) orange."""
    blue = orange = 0
    for y in range(image.height()):
        for x in range(image.width()):
            c = QtGui.QColor(image.pixel(x, y))
            r, g, b = c.red(), c.green(), c.blue()
            blue += b > 180 and r < 60 and 40 < g < 130
            orange += r > 120 and 0.35 * r < g < 0.75 * r and b < 0.25 * r
    return blue, orange


def test_seam_cell_is_drawn_in_the_3d_view(gui_doc, tmp_path):
    import seam_tracking_cell
    cell = seam_tracking_cell.build(gui_doc)
    gui_doc.recompute()
    ours = list(cell.Group)
    assert {o.Label for o in ours} >= {"TableFrame", "Seam", "Torch1", "Torch4", "Corner"}
    gui_doc.getObject("Fixture").ViewObject.Visibility = False   # the table and plates
    cell.ViewObject.ShowRobot = False           # the robot would dwarf the markers (test_robot_display)
    view = FreeCADGui.activeDocument().activeView()
    view.viewIsometric()
    view.fitAll()
    blue, orange = colour_counts(render(view, tmp_path / "cell.png"))
    assert blue > 100, "the path is not drawn in its colour"
    assert orange > 1000, "the tool markers are not drawn"
    for obj in ours:
        obj.ViewObject.Visibility = False
    assert non_white_pixels(render(view, tmp_path / "nothing.png")) == 0


def test_document_saved_without_the_gui_is_drawn_when_opened(tmp_path):
    import subprocess
    import FreeCAD
    from conftest import REPO
    from CadRobotWB.gui.view_providers import ViewProvider
    run = subprocess.run(["/usr/bin/python3", "tools/freecad_run.py", "examples/make_demo.py", str(tmp_path)],
                         cwd=REPO, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    doc = FreeCAD.openDocument(str(tmp_path / "seam_tracking.FCStd"))
    process_events()   # FreeCAD's GUI restore, then our repair (FreeCAD < 1.1 hides everything)
    try:
        assert doc.getObject("Table").ViewObject.Visibility
        assert not doc.getObject("Origin").ViewObject.Visibility
        cell = doc.getObject("SeamCell")
        assert all(isinstance(o.ViewObject.Proxy, ViewProvider) for o in [cell] + cell.Group)
        assert cell.ViewObject.Proxy.robot_display.shown
        doc.getObject("Fixture").ViewObject.Visibility = False
        cell.ViewObject.ShowRobot = False
        view = FreeCADGui.getDocument(doc.Name).activeView()
        view.viewIsometric()
        view.fitAll()
        blue, orange = colour_counts(render(view, tmp_path / "reopened.png"))
        assert blue > 100 and orange > 1000
    finally:
        FreeCAD.closeDocument(doc.Name)
