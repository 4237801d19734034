"""``make demo``: a screenshot of each example cell, ``out/<document>.png``, of the
Place robot heat map, ``out/seam_tracking_place.png``, and of the woven fillet weld
close up, ``out/tee_joint_weave.png``.

Opens the documents ``make_demo.py`` saved (``out/seam_tracking.FCStd``,
``out/profile_following.FCStd``) in the real FreeCAD window, draws the robot
at the first target of its program (where the seam or profile starts; with
``gui/robot_view.py``, nothing added to the document) in place of the cell's
own robot at its start pose (``ShowRobot`` off), and saves the isometric
view, fitted, as a PNG.  For the heat map it opens the Place robot panel on the
seam cell, searches a 2.2 x 2.2 m square of floor around the table, and draws
the robot at the best placement found.

Runs in the FreeCAD GUI (under Xvfb when there is no display)::

    /usr/bin/python3 tools/freecad_run.py --gui examples/screenshots.py out
"""

import os
import sys

DOCUMENTS = ("seam_tracking.FCStd", "profile_following.FCStd", "seam_weld.FCStd",
             "tee_joint.FCStd")
#: The welded document whose woven path is shown close up, and the zoom on its weld.
WOVEN_DOCUMENT = "tee_joint.FCStd"
WOVEN_ZOOM = 4.0
WIDTH, HEIGHT = 1280, 960


def process_events(rounds=5):
    from PySide import QtGui
    for _ in range(rounds):
        QtGui.QApplication.processEvents()


def start_joints(result):
    """Model joints (deg, (6,)) at the program's first path target, or None.

    Parameters
    ----------
    result : api.CheckResult
        ``api.check(cell)``: its program and joint solution.
    """
    from CadRobotWB.core import program as ir
    moves = result.program.moves()
    entries = [e for e in result.solution.entries if e.joints_deg is not None]
    for role in (ir.ROLE_ENTRY, ir.ROLE_PATH):
        for entry in entries:
            if moves[entry.move_index].role == role:
                return entry.joints_deg
    return entries[0].joints_deg if entries else None


def show_robot(cell, view):
    """Draw the cell's robot at its first path target instead of its start pose; returns
    the RobotView (or None)."""
    import FreeCAD
    from CadRobotWB import api
    from CadRobotWB.errors import CadRobotError
    from CadRobotWB.gui.robot_view import RobotView
    try:
        result = api.check(cell, collisions=False)
    except CadRobotError as exc:
        FreeCAD.Console.PrintWarning("screenshots: %s: no robot drawn: %s\n" % (cell.Label, exc))
        return None
    cell.ViewObject.ShowRobot = False          # one robot: this one, on the seam
    model = api.robot(result.program.robot)
    robot = RobotView(view, model, api.matrix_from_placement(cell.Placement),
                      result.program.tool.T_f_t)
    q_deg = start_joints(result)
    if q_deg is not None:
        robot.set_joints(q_deg)
    return robot


def screenshot(doc_path, png_path):
    """Open `doc_path`, draw its cell and robot, save the isometric view to `png_path`."""
    import FreeCAD
    import FreeCADGui
    from CadRobotWB import api, compat
    compat.no_camera_animation()  # FreeCAD 1.x animates viewIsometric/fitAll by default
    doc = FreeCAD.openDocument(doc_path)
    process_events()            # files saved headless are repaired on a timer (gui/headless_files)
    gui_doc = FreeCADGui.getDocument(doc.Name)
    FreeCADGui.setActiveDocument(doc.Name)
    view = gui_doc.activeView()
    robots = [show_robot(cell, view) for cell in api.find_cells(doc)]
    view.viewIsometric()
    view.fitAll()
    process_events()
    compat.draw_now(view)
    view.saveImage(png_path, WIDTH, HEIGHT, "Current")
    for robot in robots:
        if robot is not None:
            robot.remove()
    FreeCAD.closeDocument(doc.Name)
    print("wrote %s" % png_path)


#: The floor searched for the heat map: mm in {U}, around the seam cell's table.
PLACE_REGION_MM = (-600.0, -1200.0, 1600.0, 1000.0)
PLACE_STEP_MM = 100.0


def place_screenshot(doc_path, png_path):
    """The Place robot panel's heat map on the seam cell, the robot at the best placement."""
    import FreeCAD
    import FreeCADGui
    from CadRobotWB import api, compat
    from CadRobotWB.gui import place_panel
    compat.no_camera_animation()
    doc = FreeCAD.openDocument(doc_path)
    process_events()
    FreeCADGui.setActiveDocument(doc.Name)
    view = FreeCADGui.getDocument(doc.Name).activeView()
    panel = place_panel.open_panel(api.find_cells(doc)[0])
    for box, value in zip((panel.xmin, panel.ymin, panel.xmax, panel.ymax), PLACE_REGION_MM):
        box.setValue(value)
    panel.step.setValue(PLACE_STEP_MM)
    result = panel.search()
    print("place: %s" % (result.lines()[0] if result is not None else panel.message.text()))
    view.viewIsometric()
    view.fitAll()
    process_events()
    compat.draw_now(view)
    view.saveImage(png_path, WIDTH, HEIGHT, "Current")
    place_panel.close_panel()
    FreeCAD.closeDocument(doc.Name)
    print("wrote %s" % png_path)
    return result is not None and len(result) > 0


def woven_screenshot(doc_path, png_path):
    """The weld of `doc_path` close up: its woven path (the Weld's preview) on the joint,
    seen from the isometric direction, the view fitted to the weld and zoomed in. The
    weave's ends dip into the plates (the wire tip crosses the joint at the root), so
    the plates are drawn see-through and the tool markers hidden."""
    import FreeCAD
    import FreeCADGui
    from CadRobotWB import compat
    from CadRobotWB.objects import base
    compat.no_camera_animation()
    doc = FreeCAD.openDocument(doc_path)
    process_events()
    FreeCADGui.setActiveDocument(doc.Name)
    view = FreeCADGui.getDocument(doc.Name).activeView()
    weld = base.objects_of_type(doc, "Weld")[0]
    for obj in doc.Objects:
        if obj.isDerivedFrom("Part::Box"):
            obj.ViewObject.Transparency = 70
    for marker in base.objects_of_type(doc, "ToolMarker"):
        marker.ViewObject.Visibility = False
    view.viewIsometric()
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(weld)
    FreeCADGui.SendMsgToActiveView("ViewSelection")
    FreeCADGui.Selection.clearSelection()
    camera = view.getCameraNode()
    camera.height.setValue(camera.height.getValue() / WOVEN_ZOOM)
    process_events()
    compat.draw_now(view)
    view.saveImage(png_path, WIDTH, HEIGHT, "Current")
    FreeCAD.closeDocument(doc.Name)
    print("wrote %s" % png_path)


def main(out_dir):
    import FreeCAD
    import FreeCADGui
    if not FreeCAD.GuiUp:
        print("screenshots.py needs the FreeCAD GUI: tools/freecad_run.py --gui ...", file=sys.stderr)
        return 2
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    FreeCADGui.getMainWindow().showMaximized()
    process_events()
    missing = [name for name in DOCUMENTS if not os.path.isfile(os.path.join(out_dir, name))]
    if missing:
        print("screenshots.py: run examples/make_demo.py first; missing %s" % ", ".join(missing),
              file=sys.stderr)
        return 1
    for name in DOCUMENTS:
        screenshot(os.path.join(out_dir, name),
                   os.path.join(out_dir, os.path.splitext(name)[0] + ".png"))
    woven_screenshot(os.path.join(out_dir, WOVEN_DOCUMENT),
                     os.path.join(out_dir, "tee_joint_weave.png"))
    found = place_screenshot(os.path.join(out_dir, DOCUMENTS[0]),
                             os.path.join(out_dir, "seam_tracking_place.png"))
    return 0 if found else 1


if __name__ in ("__main__", "screenshots"):
    sys.exit(main(os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else "out")))
