"""The paper's seam-tracking cell built with the toolbar, as a user does it.

Starts from the drawing only (table, plates, seam sketch) and uses the
CadRobot commands and their task panels in the real FreeCAD window:

1. New cell: the IRB 2400 at the origin.
2. Calibration frame: three vertices of the table top (corner, along X,
   along Y); then its teaching panel, with four table corners "measured"
   on a real table that sits 2 mm off and turned 0.5° (0.03 mm noise).
3. Mark path: the seam sketch.
4. Tool markers on every segment: the cell's work angle 90°, push 10°.
5. Risk area: the paper's, over the two segments round the corner.
6. Generate: the RAPID module.

Run in the GUI (``tools/freecad_run.py --gui examples/gui_walkthrough.py OUT``,
``make demo`` does): each step's window is saved as ``OUT/walkthrough/NN_*.png``
and the module as ``OUT/walkthrough/SeamWeld.mod``. The GUI test tier runs
:func:`run` and compares its program with the scripted example's.
"""

import os
import sys

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import seam_tracking_cell  # noqa: E402  (examples/)
from CadRobotWB import compat  # noqa: E402

V = FreeCAD.Vector
#: The real table: 2 mm along X, -1.5 mm along Y, 0.8 mm up and 0.5° about Z from the drawing.
REAL_TABLE_SHIFT = FreeCAD.Placement(V(2.0, -1.5, 0.8), FreeCAD.Rotation(V(0, 0, 1), 0.5))
#: Measurement noise added to each measured coordinate, mm (fixed, so runs repeat).
NOISE_MM = ((0.03, -0.02, 0.01), (-0.01, 0.03, -0.02), (0.02, 0.01, 0.03), (-0.03, -0.02, -0.01))
WINDOW_SIZE = (1400, 950)


def _events():
    QtGui.QApplication.processEvents()


class Walkthrough:
    """Runs the steps; ``snap`` saves the main window when a folder is given."""

    def __init__(self, out_dir=None):
        self.out_dir = out_dir
        self.snaps = []
        if out_dir:
            os.makedirs(out_dir, exist_ok=True)

    def snap(self, name):
        if not self.out_dir:
            return
        _events()
        path = os.path.join(self.out_dir, name + ".png")
        window_with_3d_view().save(path)
        self.snaps.append(path)

    @staticmethod
    def select(obj, subs=()):
        FreeCADGui.Selection.clearSelection()
        for sub in subs or [""]:
            FreeCADGui.Selection.addSelection(obj.Document.Name, obj.Name, sub)
        _events()

    @staticmethod
    def run_command(name):
        assert FreeCADGui.Command.get(name).isActive(), "%s is greyed out" % name
        FreeCADGui.runCommand(name)
        _events()


def window_with_3d_view():
    """The main window as a QImage, with the 3D view rendered into it.

    ``QWidget.grab`` leaves OpenGL widgets blank under Xvfb, so the view is
    drawn with ``saveImage`` at its own size and painted over its place.
    """
    import tempfile
    window = FreeCADGui.getMainWindow()
    image = window.grab().toImage()
    gl_widgets = [w for w in window.findChildren(QtGui.QWidget)
                  if w.isVisible() and (w.inherits("QOpenGLWidget") or w.inherits("QGLWidget"))]
    gui_doc = FreeCADGui.activeDocument()
    if gl_widgets and gui_doc is not None:
        widget = gl_widgets[0]
        with tempfile.TemporaryDirectory() as folder:
            rendered = os.path.join(folder, "view.png")
            compat.draw_now(gui_doc.activeView())
            gui_doc.activeView().saveImage(rendered, widget.width(), widget.height(), "Current")
            painter = QtGui.QPainter(image)
            painter.drawImage(widget.mapTo(window, QtCore.QPoint(0, 0)), QtGui.QImage(rendered))
            painter.end()
    return image


def _widen_task_panel(width_px=430):
    window = FreeCADGui.getMainWindow()
    docks = [d for d in window.findChildren(QtGui.QDockWidget) if d.objectName() == "Combo View"]
    if docks and hasattr(window, "resizeDocks"):
        window.resizeDocks(docks, [width_px], QtCore.Qt.Horizontal)


def show_the_plates(doc):
    """Isometric view fitted to the plates (the seam is small next to the table)."""
    FreeCADGui.activeDocument().activeView().viewIsometric()
    FreeCADGui.Selection.clearSelection()
    for name in ("PlateA", "PlateB"):
        FreeCADGui.Selection.addSelection(doc.Name, name)
    FreeCADGui.runCommand("Std_ViewFitSelection")
    FreeCADGui.Selection.clearSelection()
    _events()


def _vertex(obj, local_point):
    for k, vertex in enumerate(obj.Shape.Vertexes, 1):
        if (vertex.Point - local_point).Length < 1e-6:
            return "Vertex%d" % k
    raise ValueError("%s has no vertex at %s" % (obj.Label, local_point))


def table_corners(doc):
    """(vertex names, points in {U}) of the table top's corners: origin, +X, +Y, far corner."""
    table = doc.getObject("Table")
    length, width, height = seam_tracking_cell.TABLE_SIZE_MM
    local = [V(0, 0, height), V(length, 0, height), V(0, width, height), V(length, width, height)]
    to_u = doc.getObject("Fixture").Placement
    return [_vertex(table, p) for p in local], [to_u.multVec(p) for p in local]


def measured_on_the_real_table(cad_points):
    """The corners as the robot measures them (robot base {R} = {U} here), mm."""
    return [REAL_TABLE_SHIFT.multVec(p) + V(*n) for p, n in zip(cad_points, NOISE_MM)]


def run(out_dir=None, doc_name="SeamByClicks", robot_file=None, robot_name=None):
    """Build the seam cell with the toolbar; returns a dict of what it made.

    With `robot_file`, the robot is the arm of that URDF file, imported in
    the New cell panel (**Import URDF…**) as `robot_name`, and the program is
    written in its maker's language.

    Returns
    -------
    dict
        ``doc``, ``cell``, ``frame``, ``path``, ``markers``, ``risk_areas``,
        ``residuals_mm`` (teaching), ``files`` (written), ``snaps`` (PNG paths).
    """
    compat.no_camera_animation()  # FreeCAD 1.x animates camera moves; a screenshot shows the end
    window = FreeCADGui.getMainWindow()
    geometry, state = window.saveGeometry(), window.saveState()
    window.resize(*WINDOW_SIZE)
    _widen_task_panel()
    try:
        return _steps(Walkthrough(out_dir), out_dir, doc_name, robot_file, robot_name)
    finally:   # leave the window as it was (later renders depend on the view's size)
        window.restoreGeometry(geometry)
        window.restoreState(state)
        _events()


def _steps(steps, out_dir, doc_name, robot_file=None, robot_name=None):
    from CadRobotWB import api
    from CadRobotWB.gui import calibration_panel, generate_panel, new_cell_panel
    from CadRobotWB.objects.base import objects_of_type

    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    doc = FreeCAD.newDocument(doc_name)
    FreeCADGui.setActiveDocument(doc.Name)
    _fixture, sketch = seam_tracking_cell.build_drawing(doc)
    show_the_plates(doc)
    steps.snap("01_drawing")

    # 1. New cell: robot from the catalog, base at the origin.
    FreeCADGui.Selection.clearSelection()
    steps.run_command("CadRobot_NewCell")
    panel = new_cell_panel.active_panel()
    if robot_file:
        assert panel.import_file(robot_file, name=robot_name), panel.message.text()
    else:
        panel.select_robot("ABB_IRB2400")
    # The paper's robot stands at the origin (its table was drawn for it): typed over the
    # panel's default base beside the table.
    for box in (panel.x, panel.y, panel.z, panel.rotation):
        box.setValue(0.0)
    FreeCADGui.activeDocument().activeView().fitAll()    # the robot's preview and the table
    steps.snap("02_new_cell")
    assert panel.accept(), "the new cell panel refused"
    show_the_plates(doc)
    cell = objects_of_type(doc, "Cell")[0]
    # The property editor: tool, program name, sample time, the push angle.
    seam_tracking_cell.setup_tool(cell)
    cell.TravelAngle = seam_tracking_cell.TRAVEL_ANGLE_DEG
    doc.recompute()

    # 2. Calibration frame on the table corner, then taught on the real table.
    names, cad_points = table_corners(doc)
    steps.select(doc.getObject("Table"), names[:3])
    steps.run_command("CadRobot_CalibrationFrame")
    frame = objects_of_type(doc, "CalibrationFrame")[0]
    panel = calibration_panel.active_panel()
    panel.table.setRowCount(0)
    for cad, measured in zip(cad_points, measured_on_the_real_table(cad_points)):
        panel.add_row(cad=cad, measured=measured)
    residuals = panel.fit()
    steps.snap("03_teach_frame")
    assert panel.accept(), "the teaching panel refused: %s" % panel.result.text()

    # 3. The seam sketch becomes the path.
    steps.select(sketch)
    steps.run_command("CadRobot_MarkPath")
    path = objects_of_type(doc, "RobotPath")[0]

    # 4. A torch on every segment, from the plates' faces and the cell's angles.
    steps.select(path)
    steps.run_command("CadRobot_AutoToolMarkers")
    doc.recompute()
    steps.snap("04_tool_markers")

    # 5. The paper's risk area: the two segments round the corner, whole (the suggestion
    # would turn the torch over a few mm each side of the corner instead).
    steps.select(path, ["Edge2", "Edge3"])
    steps.run_command("CadRobot_RiskArea")
    steps.snap("05_risk_areas")

    # 6. Generate the RAPID module.
    steps.select(cell)
    steps.run_command("CadRobot_Generate")
    panel = generate_panel.active_panel()
    panel.set_post(cell.PostProcessor)
    panel.folder_edit.setText(out_dir or os.path.join(FreeCAD.getUserAppDataDir(), "CadRobotWalkthrough"))
    panel.refresh()
    steps.snap("06_generate")
    files = panel.write()
    assert files, "nothing written: %s" % panel.message_label.text()
    panel.reject()
    show_the_plates(doc)
    steps.snap("07_cell")
    FreeCADGui.activeDocument().activeView().fitAll()
    steps.snap("08_robot_and_cell")
    return dict(doc=doc, cell=cell, frame=frame, path=path,
                markers=objects_of_type(doc, "ToolMarker"),
                risk_areas=objects_of_type(doc, "RiskArea"),
                residuals_mm=residuals, files=files, snaps=steps.snaps)


def main(argv):
    out = os.path.join(argv[0] if argv else "out", "walkthrough")
    result = run(out)
    path = os.path.join(out, "seam_by_clicks.FCStd")
    if os.path.exists(path):          # a fresh file, not FreeCAD's .FCStd1 backup of the last run
        os.remove(path)
    result["doc"].saveAs(path)
    print("walkthrough: %d screenshots and %s in %s"
          % (len(result["snaps"]), ", ".join(os.path.basename(f) for f in result["files"]), out))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
