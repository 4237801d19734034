"""The teaching panel of a calibration frame {B}.

``edit(frame)`` opens it (CadRobot_CalibrationFrame after adding a frame, and
a double-click on a frame). For each point of the part: the point as
drawn, in the document frame {U} (typed, or filled by clicking a vertex in
the 3D view while "Pick CAD points" is on), and the same point measured
with the real robot, in its base frame {R} (typed, or pasted as lines
``x y z`` / ``x,y,z``). Fit shows each point's residual and the RMS without
changing anything; Apply (and OK) stores the points with
``api.teach_calibration_frame`` as one journaled undo step, and the "Use the
taught frame" box says whether the programs use the taught frame or the
drawn one. Errors are shown in the panel, the object at fault selected.

Each point takes two rows of the table, X, Y and Z across: "1 CAD" (the
point as drawn) above "1 robot" (as measured). Three columns fit FreeCAD's
default panel width (about 260 px); seven did not.
"""

import re

import FreeCAD
import FreeCADGui
import numpy as np
from PySide import QtCore, QtGui

from ..commands import base as command_base
from ..commands import selection
from ..core import frames
from ..core.rotations import rotation_angle_between
from ..errors import CadRobotError, FrameError, InputError
from ..objects import base, calibration_frame
from ..objects.convert import array_from_vector, matrix_from_placement
from .task_panels import PanelSlot, TaskPanel

translate = FreeCAD.Qt.translate
CONTEXT = "CadRobot_CalibrationFrame"

#: Table columns: X, Y, Z, of the CAD row ({U}) and of the robot row ({R}) of each point.
CAD_COLUMNS = MEASURED_COLUMNS = (0, 1, 2)
#: Points shown for a frame not taught yet.
EMPTY_ROWS = 3


def table_row(point, measured):
    """The table row of point `point` (0-based): its CAD row, or its robot row when `measured`."""
    return 2 * point + (1 if measured else 0)

#: The open panel; closing it stops picking CAD points.
_slot = PanelSlot(before_close=lambda panel: panel.set_picking(False))


def parse_points(text):
    """Points from text, one per line: ``x y z``, ``x,y,z``, ``x;y;z`` or tab separated.

    Returns
    -------
    ndarray, shape (N, 3)
        Blank lines are skipped. InputError naming the first bad line.
    """
    points = []
    for number, line in enumerate(text.splitlines(), 1):
        if not line.strip():
            continue
        fields = [f for f in re.split(r"[\s,;]+", line.strip()) if f]
        try:
            values = [float(f) for f in fields]
        except ValueError:
            values = []
        if len(values) != 3:
            raise InputError(translate(CONTEXT, "Line {0} '{1}' is not a point: give three numbers "
                                                "'x y z' or 'x, y, z' per line.").format(number, line.strip()))
        points.append(values)
    return np.array(points, dtype=float).reshape(-1, 3)


def _number(text):
    """A typed number (a decimal comma allowed), or None when empty; ValueError if not a number."""
    text = text.strip().replace(",", ".")
    return float(text) if text else None


def _format(value):
    """A coordinate as typed: mm to a micrometre's thousandth, no trailing zeros."""
    text = ("%.6f" % value).rstrip("0").rstrip(".")
    return "0" if text in ("", "-0") else text


def cell_of(frame):
    """The cell holding `frame`, or None."""
    for parent in frame.InList:
        if base.type_of(parent) == "Cell":
            return parent
    return None


class CalibrationPanel(TaskPanel):
    """Task panel teaching one calibration frame.

    Attributes
    ----------
    frame : App.DocumentObject
    residuals : ndarray or None
        Residual per complete row of the last fit, mm.
    """

    ACTION_BUTTONS = ('fit_button', 'apply_button')

    def __init__(self, frame):
        self.frame = frame
        self.residuals = None
        self.picking = False
        self.form = QtGui.QWidget()
        self.form.setWindowTitle(translate(CONTEXT, "Teach calibration frame"))
        layout = QtGui.QVBoxLayout(self.form)
        intro = QtGui.QLabel(translate(
            CONTEXT, "Teach {0}: three or more points of the part as drawn (CAD rows) and as "
            "the robot measured them (robot rows), mm.").format(frame.Label))
        intro.setWordWrap(True)
        layout.addWidget(intro)
        # Fit and Apply, and what they found, above the table: in view in FreeCAD 1.1's
        # task overlay (about 350 px tall at 1366x768).
        fit_row = QtGui.QHBoxLayout()
        self.fit_button = QtGui.QPushButton(translate(CONTEXT, "Fit"))
        self.fit_button.setToolTip(translate(CONTEXT, "Fit the frame to the points and show the "
                                                      "residuals; nothing is changed"))
        self.fit_button.clicked.connect(self.fit)
        fit_row.addWidget(self.fit_button)
        self.apply_button = QtGui.QPushButton(translate(CONTEXT, "Apply"))
        self.apply_button.setToolTip(translate(CONTEXT, "Store the points on the frame (one undo step)"))
        self.apply_button.clicked.connect(self.apply)
        fit_row.addWidget(self.apply_button)
        layout.addLayout(fit_row)
        self.result = QtGui.QLabel()
        self.result.setWordWrap(True)
        layout.addWidget(self.result)

        self.table = QtGui.QTableWidget(0, 3)
        self.table.setHorizontalHeaderLabels(["X", "Y", "Z"])
        self.table.horizontalHeader().setSectionResizeMode(QtGui.QHeaderView.Stretch)
        self.table.horizontalHeader().setMinimumSectionSize(20)
        self.table.setHorizontalScrollBarPolicy(QtCore.Qt.ScrollBarAlwaysOff)
        row_px = self.table.fontMetrics().height() + 8
        self.table.verticalHeader().setDefaultSectionSize(row_px)
        self.table.setMinimumHeight(7 * row_px + 4)         # the header and three points
        layout.addWidget(self.table)

        rows = QtGui.QGridLayout()
        self.add_button = QtGui.QPushButton(translate(CONTEXT, "Add point"))
        self.add_button.clicked.connect(lambda: self.add_row())
        self.remove_button = QtGui.QPushButton(translate(CONTEXT, "Remove point"))
        self.remove_button.clicked.connect(self.remove_row)
        self.pick_button = QtGui.QPushButton(translate(CONTEXT, "Pick CAD points"))
        self.pick_button.setCheckable(True)
        self.pick_button.setToolTip(translate(
            CONTEXT, "While on, a vertex clicked in the 3D view fills the CAD row of the current point"))
        self.pick_button.toggled.connect(self.set_picking)
        rows.addWidget(self.add_button, 0, 0)
        rows.addWidget(self.remove_button, 0, 1)
        rows.addWidget(self.pick_button, 1, 0, 1, 2)
        layout.addLayout(rows)

        self.paste_text = QtGui.QPlainTextEdit()
        self.paste_text.setPlaceholderText(translate(
            CONTEXT, "Paste the robot's points, one per line: x y z  or  x, y, z"))
        self.paste_text.setMaximumHeight(80)
        layout.addWidget(self.paste_text)
        self.paste_button = QtGui.QPushButton(translate(CONTEXT, "Fill the robot rows"))
        self.paste_button.setToolTip(translate(CONTEXT, "Put the pasted points into the robot rows, "
                                                        "first point first"))
        self.paste_button.clicked.connect(self.fill_measured_from_text)
        layout.addWidget(self.paste_button)

        self.use_taught = QtGui.QCheckBox(translate(CONTEXT, "Programs use the taught frame"))
        self.use_taught.setToolTip(translate(
            CONTEXT, "On: programs use the frame fitted to the measured points; off: the frame as "
                     "drawn. The drawing does not change either way."))
        layout.addWidget(self.use_taught)
        self.load()

    # -- table --
    def load(self):
        """Fill the table and the check box from the frame's properties."""
        cad = [array_from_vector(v) for v in self.frame.CadPoints]
        measured = [array_from_vector(v) for v in self.frame.MeasuredPoints]
        self.table.setRowCount(0)
        for k in range(max(len(cad), len(measured), EMPTY_ROWS)):
            self.add_row(cad[k] if k < len(cad) else None, measured[k] if k < len(measured) else None)
        taught = len(cad) >= 3
        self.use_taught.setChecked(bool(self.frame.UseTaught) or not taught)
        residuals = list(self.frame.Residuals or [])
        if taught and len(residuals) == len(cad):
            self.show_residuals(np.array(residuals))
        elif taught:        # the residual column would be empty: say why
            self.show_result(translate(
                CONTEXT, "{0} has {1} points but {2} stored residuals (points edited outside this "
                "panel): press Fit to compute them.").format(self.frame.Label, len(cad), len(residuals)))
        else:
            self.show_result("")

    def point_count(self):
        """int: points in the table (two rows each)."""
        return self.table.rowCount() // 2

    def _label_rows(self):
        self.table.setVerticalHeaderLabels([
            translate(CONTEXT, "{0} robot").format(k // 2 + 1) if k % 2 else
            translate(CONTEXT, "{0} CAD").format(k // 2 + 1) for k in range(self.table.rowCount())])

    def add_row(self, cad=None, measured=None):
        """Append a point (its CAD and robot rows; points as (3,) arrays, or None for empty
        cells); returns its index."""
        point_index = self.point_count()
        for is_measured, point in ((False, cad), (True, measured)):
            row = table_row(point_index, is_measured)
            self.table.insertRow(row)
            for c in range(3):
                self.table.setItem(row, c, QtGui.QTableWidgetItem(
                    "" if point is None else _format(point[c])))
        self._label_rows()
        return point_index

    def remove_row(self):
        """Remove the current point (the last when none is current)."""
        point_index = self.table.currentRow() // 2 if self.table.currentRow() >= 0 \
            else self.point_count() - 1
        if point_index >= 0:
            self.table.removeRow(table_row(point_index, True))
            self.table.removeRow(table_row(point_index, False))
            self._label_rows()

    def _cell_text(self, row, column):
        item = self.table.item(row, column)
        return item.text() if item is not None else ""

    def set_point(self, point_index, measured, point):
        """Write point (3,) into the CAD or robot row of point `point_index`, adding points
        as needed."""
        while self.point_count() <= point_index:
            self.add_row()
        for c in range(3):
            self.table.item(table_row(point_index, measured), c).setText(_format(float(point[c])))

    def set_cad_point(self, point_index, point):
        self.set_point(point_index, False, point)

    def set_measured_point(self, point_index, point):
        self.set_point(point_index, True, point)

    def _row_values(self, point_index):
        return [_number(self._cell_text(table_row(point_index, measured), c))
                for measured in (False, True) for c in range(3)]

    def points(self):
        """(cad (N, 3) in {U}, measured (N, 3) in {R}) of the filled rows.

        Empty points are skipped; InputError for a point filled in part or a
        cell that is not a number (naming the point).
        """
        cad, measured = [], []
        for point_index in range(self.point_count()):
            try:
                values = self._row_values(point_index)
            except ValueError:
                raise InputError(translate(CONTEXT, "Point {0}: every cell must be a number (mm).")
                                 .format(point_index + 1), self.frame.Name) from None
            if all(v is None for v in values):
                continue
            if any(v is None for v in values):
                raise InputError(translate(CONTEXT, "Point {0}: give both its CAD row and its robot "
                                                    "row (x, y, z each), or clear it.")
                                 .format(point_index + 1), self.frame.Name)
            cad.append(values[:3])
            measured.append(values[3:])
        return np.array(cad, dtype=float).reshape(-1, 3), np.array(measured, dtype=float).reshape(-1, 3)

    def _filled_points(self):
        return [k for k in range(self.point_count())
                if any(self._cell_text(table_row(k, m), c).strip() for m in (False, True)
                       for c in range(3))]

    def fill_measured_from_text(self):
        """Put the pasted points into the robot rows, first point first."""
        try:
            pasted = parse_points(self.paste_text.toPlainText())
        except CadRobotError as err:
            self.show_error(err)
            return 0
        for row, point in enumerate(pasted):
            self.set_measured_point(row, point)
        self.show_result(translate(CONTEXT, "{0} measured points filled in.").format(len(pasted)))
        return len(pasted)

    # -- picking CAD points in the 3D view --
    def set_picking(self, on):
        """Start or stop filling CAD points from vertices clicked in the 3D view."""
        if on and not self.picking:
            FreeCADGui.Selection.addObserver(self)
        elif not on and self.picking:
            FreeCADGui.Selection.removeObserver(self)
        self.picking = bool(on)
        if self.pick_button.isChecked() != self.picking:
            self.pick_button.setChecked(self.picking)

    def addSelection(self, doc_name, obj_name, sub, pnt):
        """Selection observer: a clicked vertex (or point) fills the CAD row of
        the current point, or of the first point without one, and moves on."""
        if not self.picking:
            return
        doc = FreeCAD.getDocument(doc_name)
        obj = doc.getObject(obj_name) if doc else None
        if obj is None:
            return
        if sub.split(".")[-1].startswith("Vertex"):       # "Box.Vertex3" inside an App::Part
            try:
                point = selection.global_element(obj, sub).Point
            except Exception:  # noqa: BLE001 -- an observer must not raise into the selection
                return
        elif pnt is not None and sub:
            point = FreeCAD.Vector(*pnt)
        else:
            return
        def has_cad(k):
            return any(self._cell_text(table_row(k, False), c).strip() for c in range(3))
        current = self.table.currentRow() // 2 if self.table.currentRow() >= 0 else -1
        if current < 0 or has_cad(current):
            current = next((k for k in range(self.point_count()) if not has_cad(k)),
                           self.point_count())
        self.set_cad_point(current, (point.x, point.y, point.z))
        self.table.setCurrentCell(table_row(min(current + 1, self.point_count() - 1), False), 0)

    # -- fitting and applying --
    def show_result(self, text, error=False):
        self.result.setStyleSheet("color: red;" if error else "")
        self.result.setText(text)

    def show_error(self, err):
        """`err` in red in the panel, the object at fault selected."""
        command_base.report_error(self.frame.Document, "", err, show=False)
        self.show_result(str(err), error=True)

    def show_residuals(self, residuals, T_r_b=None):
        """Residual per filled point and their RMS (and, given the fitted T_r_b,
        how far the taught frame is from the drawn one)."""
        residuals = np.asarray(residuals, dtype=float)
        self.residuals = residuals
        rms = float(np.sqrt(np.mean(residuals ** 2))) if len(residuals) else 0.0
        text = translate(CONTEXT, "Residuals (mm): {0}. RMS {1:.3f} mm, largest {2:.3f} mm.").format(
            ", ".join("%d: %.3f" % (k + 1, value) for k, value in zip(self._filled_points(), residuals)),
            rms, float(residuals.max()) if len(residuals) else 0.0)
        offset = self.offset_from_drawing(T_r_b)
        if offset is not None:
            text += " " + translate(CONTEXT, "The taught frame lies {0:.2f} mm and {1:.2f}\u00b0 from "
                                             "where the drawing puts it for the robot.").format(*offset)
        self.show_result(text)

    def offset_from_drawing(self, T_r_b):
        """(distance mm, angle deg) between the taught {B} and the drawn {B}, both in {R}."""
        cell = cell_of(self.frame)
        if T_r_b is None or cell is None:
            return None
        T_r_b_drawn = frames.invert_transform(matrix_from_placement(base.global_placement(cell))) @ \
            matrix_from_placement(base.global_placement(self.frame))
        distance = float(np.linalg.norm(T_r_b[:3, 3] - T_r_b_drawn[:3, 3]))
        angle = float(np.degrees(rotation_angle_between(T_r_b[:3, :3], T_r_b_drawn[:3, :3])))
        return distance, angle

    def fit(self):
        """Fit the frame to the points and show the residuals; nothing changes.

        Returns
        -------
        ndarray or None
            Residual per filled point, mm; None on an error (shown).
        """
        try:
            cad, measured = self.points()
            if len(cad) < 3:
                raise FrameError(translate(CONTEXT, "Give at least three points (CAD and robot rows "
                                                    "filled) to teach the frame."), self.frame.Name)
            T_r_b, residuals = calibration_frame.fit_points(self.frame, cad, measured)
        except Exception as err:        # noqa: BLE001 -- why no residuals, never an empty column alone
            self.show_error(command_base.as_cadrobot_error(err))
            return None
        self.show_residuals(residuals, T_r_b)
        return np.asarray(residuals)

    def journal_lines(self):
        """The API calls Apply makes (InputError for unusable rows)."""
        cad, measured = self.points()
        frame = command_base.literal(self.frame)
        lines = []
        if len(cad) or not self.frame.CadPoints:
            lines.append("residuals = " + command_base.call(
                "api.teach_calibration_frame", self.frame,
                [FreeCAD.Vector(*p) for p in cad], [FreeCAD.Vector(*p) for p in measured]))
        use = self.use_taught.isChecked()
        if not lines or not use:
            lines += ["%s.UseTaught = %r" % (frame, use), "%s.Document.recompute()" % frame]
        return lines

    def apply(self):
        """Store the points (and the check box) on the frame as one undo step. True when done."""
        try:
            lines = self.journal_lines()
            if self.fit() is None and any(line.startswith("residuals") for line in lines):
                return False
            command_base.journal(self.frame.Document, translate(CONTEXT, "Teach calibration frame"),
                                 lines)
        except CadRobotError as err:
            self.show_error(err)
            return False
        self.fit()
        return True

    # -- task dialog --
    def ok(self):
        return self.apply()

    def close_panel(self):
        close_panel()


def edit(frame):
    """Open the teaching panel of calibration frame `frame`.

    Returns
    -------
    CalibrationPanel or None
        None when another task panel is open (the user is told so in a
        message box, nothing is raised).
    """
    # An open teaching panel is closed without leaving edit mode (close_panel's
    # reset_edit=False): edit() runs from the view provider's setEdit.
    return _slot.open(lambda: CalibrationPanel(frame),
                      translate(CONTEXT, "Another task panel is open; close it first."),
                      on_busy=lambda message: command_base.show_message(
                          translate(CONTEXT, "Teach calibration frame"), message, error=True))


def active_panel():
    """The open CalibrationPanel, or None."""
    return _slot.panel


def close_panel(reset_edit=True):
    """Close the panel, if open, and leave the frame's edit mode (double-click)."""
    panel = _slot.close()
    if panel is None or not reset_edit:
        return
    gui_doc = FreeCADGui.getDocument(panel.frame.Document.Name)
    in_edit = gui_doc.getInEdit() if gui_doc is not None else None
    if in_edit is not None and getattr(in_edit, "Object", None) == panel.frame:
        gui_doc.resetEdit()
