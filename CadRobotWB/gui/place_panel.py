"""The Place robot panel: search where a cell's robot can stand, pick a place, apply it.

``open_panel(cell, face=None)`` shows the region to search (a rectangle of
the floor in {U}, or a selected horizontal face), the height and turn
ranges, the grid step and the joint margin.  Search runs
:func:`api.place_robot` with a progress bar; the window stays live (the
search hands control back to Qt between pieces of work) and Stop ends it.
The result is drawn as a heat map on the floor (:mod:`.heat_map`) and listed
best first; picking a placement in the list draws the robot there, at the
start of the first path (nothing is added to the document).  Apply (or OK)
stands the cell's robot at the picked placement as one undo step, journaled
as a call to :func:`api.set_robot_placement` after a comment recording the
search that found it, so a recorded macro replays it.
"""

import FreeCAD
import FreeCADGui
import numpy as np
from PySide import QtCore, QtGui

from .. import api, limits
from ..commands import base as command_base
from ..errors import CadRobotError, InputError
from ..objects import floor_face
from ..objects.convert import matrix_from_placement
from ..robots.catalog import catalog
from . import heat_map, not_checked, robot_display
from . import progress as gui_progress
from .task_panels import PanelSlot, TaskPanel

translate = FreeCAD.Qt.translate
CONTEXT = "CadRobot_PlaceRobot"

_slot = PanelSlot(before_close=lambda panel: panel.clean_up())


def _spin(low, high, value, suffix, decimals=0, step=None):
    box = QtGui.QDoubleSpinBox()
    box.setRange(low, high)
    box.setDecimals(decimals)
    box.setValue(value)
    box.setSuffix(suffix)
    if step is not None:
        box.setSingleStep(step)
    # Three across in FreeCAD's default panel width (about 260 px): no arrows, and the
    # width the layout gives rather than the width of the widest number of the range.
    box.setButtonSymbols(QtGui.QAbstractSpinBox.NoButtons)
    box.setSizePolicy(QtGui.QSizePolicy.Ignored, QtGui.QSizePolicy.Fixed)
    box.setMinimumWidth(45)
    return box


def candidate_text(rank, candidate):
    """How one placement reads in the list."""
    p = candidate.parts
    return translate(CONTEXT, "{0}. score {1:.3f}: x {2:.0f}, y {3:.0f}, z {4:.0f} mm, turn {5:.0f}\u00b0 "
                     "({6:.1f} s, margin {7:.0f}\u00b0, manipulability {8:.2f})").format(
        rank, candidate.score, candidate.x_mm, candidate.y_mm, candidate.z_mm, candidate.turn_deg,
        p["cycle_time_s"], p["limit_margin_deg"], p["manipulability"])


def default_region(cell):
    """(xmin, ymin, xmax, ymax, (zmin, zmax)): a square around the targets, the robot's reach
    on each side (hundreds of mm), and the heights of the base to try.

    The heights run from half the robot's reach below the targets' lowest point (or
    the robot's present height, when lower) up to the present height: a part
    drawn on the floor, like a robot standing on it, is rarely reached well from the
    floor (the arm folds down past its joint limits), and a table or pit is the usual
    answer. The search tries them all and ranks what passes.
    """
    T = matrix_from_placement(cell.Placement)
    try:
        program = api.generate(cell)
        T_u_b = [np.asarray(f.T_u_b) for f in program.frames.values()]
        points = np.array([T_u_b[0] @ np.r_[m.target.position_mm, 1.0] for m in program.moves()])[:, :3]
        centre = 0.5 * (points.min(axis=0) + points.max(axis=0))
        reach = catalog.reach_mm(catalog.get(cell.Robot)) or 1500.0
        lowest = float(points[:, 2].min())
    except (CadRobotError, IndexError, ValueError):
        centre, reach, lowest = T[:3, 3], 1500.0, float(T[2, 3])
    half = 100.0 * np.ceil(reach / 100.0)
    x, y = 100.0 * np.round(centre[:2] / 100.0)
    z_now = float(T[2, 3])
    z_low = min(z_now, 100.0 * np.floor((lowest - 0.5 * reach) / 100.0))
    return x - half, y - half, x + half, y + half, (z_low, z_now)


class PlacePanel(TaskPanel):
    """Task panel: search placements of a cell's robot, preview them, apply one.

    Attributes
    ----------
    result : robots.placement.placement_search.Placements or None
        The last search's result (best first).
    face : (App.DocumentObject, str) or None
        The face searched instead of the rectangle.
    heat : heat_map.HeatMapView or None
    preview : robot_view.RobotView or None
    """

    ACTION_BUTTONS = ('search_button', 'apply_button')

    def __init__(self, cell, face=None):
        self.cell, self.doc = cell, cell.Document
        self.result, self.face, self.heat, self.preview = None, None, None, None
        self.searching = self._stop = self.closed = False
        self.form = QtGui.QWidget()
        self.form.setWindowTitle(translate(CONTEXT, "Place robot"))
        layout = QtGui.QVBoxLayout(self.form)
        intro = QtGui.QLabel(translate(
            CONTEXT, "Where can the robot stand to reach every target? Search a rectangle of the "
            "floor (mm, document frame) or a selected horizontal face."))
        intro.setToolTip(translate(
            CONTEXT, "A placement passes when the robot reaches every target of every path in one "
            "arm configuration per path, within its joint limits, away from singularities and "
            "without collisions."))
        intro.setWordWrap(True)
        layout.addWidget(intro)

        # Search, Stop and Apply first, then what was found, then where to search: the
        # buttons show in FreeCAD 1.1's task overlay (about 350 px tall at 1366x768).
        buttons = QtGui.QGridLayout()
        self.search_button = QtGui.QPushButton(translate(CONTEXT, "Search"))
        self.search_button.clicked.connect(self.search)
        self.stop_button = QtGui.QPushButton(translate(CONTEXT, "Stop"))
        self.stop_button.clicked.connect(self.stop)
        self.stop_button.setEnabled(False)
        self.apply_button = QtGui.QPushButton(translate(CONTEXT, "Apply"))
        self.apply_button.setToolTip(translate(CONTEXT, "Stand the robot at the picked placement "
                                                         "(one undo step)"))
        self.apply_button.clicked.connect(self.apply)
        self.apply_button.setEnabled(False)
        for button in (self.search_button, self.stop_button, self.apply_button):
            button.setSizePolicy(QtGui.QSizePolicy.Ignored, QtGui.QSizePolicy.Fixed)
            button.setMinimumWidth(50)
        buttons.addWidget(self.search_button, 0, 0)
        buttons.addWidget(self.stop_button, 0, 1)
        buttons.addWidget(self.apply_button, 0, 2)
        layout.addLayout(buttons)
        self.progress = QtGui.QProgressBar()
        self.progress.setRange(0, 1000)
        self.progress.setTextVisible(True)
        self.progress.setVisible(False)          # shown while searching
        layout.addWidget(self.progress)
        self.not_checked_bar = not_checked.NotCheckedBar(on_installed=self.search)
        layout.addWidget(self.not_checked_bar)     # collisions NOT checked, first, with Install
        self.message = QtGui.QLabel()
        self.message.setWordWrap(True)
        self.message.setTextInteractionFlags(QtCore.Qt.TextSelectableByMouse)
        layout.addWidget(self.message)

        self.list = QtGui.QListWidget()
        self.list.setWordWrap(True)
        self.list.currentRowChanged.connect(self.pick)
        self.list.setMaximumHeight(140)          # five placements; the settings follow
        self.list.setVisible(False)              # until a search found some
        layout.addWidget(self.list)
        where_box = QtGui.QGroupBox(translate(CONTEXT, "Where to search"))
        where = QtGui.QVBoxLayout(where_box)
        where.setContentsMargins(4, 4, 4, 4)     # three numbers across ~250 px
        xmin, ymin, xmax, ymax, (zmin, zmax) = default_region(cell)
        grid = QtGui.QGridLayout()
        big = limits.MAX_COORDINATE_MM
        self.xmin, self.xmax = _spin(-big, big, xmin, " mm"), _spin(-big, big, xmax, " mm")
        self.ymin, self.ymax = _spin(-big, big, ymin, " mm"), _spin(-big, big, ymax, " mm")
        self.zmin, self.zmax = _spin(-big, big, zmin, " mm"), _spin(-big, big, zmax, " mm")
        self.z_step = _spin(1.0, big, 100.0 * max(1.0, round((zmax - zmin) / 400.0)), " mm")
        turn = limits.MAX_TURN_DEG
        self.turn_min, self.turn_max = _spin(-turn, turn, -180, "\u00b0"), _spin(-turn, turn, 150, "\u00b0")
        self.turn_step = _spin(1.0, turn, 30.0, "\u00b0")
        self.step = _spin(1.0, big, 100.0 * max(1.0, round((xmax - xmin) / 2000.0)), " mm")
        self.margin = _spin(0.0, 90.0, 5.0, "\u00b0", decimals=1)
        self.count = QtGui.QSpinBox()
        self.count.setRange(1, limits.MAX_PLACEMENTS)
        self.count.setValue(5)
        for c, title in enumerate((translate(CONTEXT, "from"), translate(CONTEXT, "to"),
                                   translate(CONTEXT, "step")), 1):
            grid.addWidget(QtGui.QLabel(title), 0, c)
        rows = [(translate(CONTEXT, "X"), self.xmin, self.xmax, self.step),
                (translate(CONTEXT, "Y"), self.ymin, self.ymax, None),
                (translate(CONTEXT, "Height"), self.zmin, self.zmax, self.z_step),
                (translate(CONTEXT, "Turn"), self.turn_min, self.turn_max, self.turn_step)]
        for r, (label, low, high, step) in enumerate(rows, 1):
            grid.addWidget(QtGui.QLabel(label), r, 0)
            grid.addWidget(low, r, 1)
            grid.addWidget(high, r, 2)
            if step is not None:
                grid.addWidget(step, r, 3)
        self.step.setToolTip(translate(CONTEXT, "Grid step along X and Y"))
        self.zmin.setToolTip(translate(
            CONTEXT, "Heights of the robot's base: below the part's height means the part stands "
            "on a table or the robot in a pit; above it, the robot on a pedestal"))
        where.addLayout(grid)
        self.face_the_part = QtGui.QCheckBox(translate(CONTEXT, "Turn it to face the part"))
        self.face_the_part.setToolTip(translate(
            CONTEXT, "At each position the robot is turned about Z to face the centre of the "
            "targets; off: the Turn range and step are searched"))
        self.face_the_part.setChecked(True)
        self.face_the_part.toggled.connect(self._turn_enabled)
        where.addWidget(self.face_the_part)
        self._turn_enabled(True)

        options = QtGui.QFormLayout()
        options.addRow(translate(CONTEXT, "Joint margin"), self.margin)
        options.addRow(translate(CONTEXT, "Placements to find"), self.count)
        where.addLayout(options)
        self.face_button = QtGui.QPushButton(translate(CONTEXT, "Use selected face"))
        self.face_button.setToolTip(translate(
            CONTEXT, "Search only positions on the selected horizontal face (floor, pedestal, table "
            "top), at its height"))
        self.face_button.clicked.connect(self.take_selected_face)
        self.face_label = QtGui.QLabel(translate(CONTEXT, "Rectangle"))
        self.face_label.setWordWrap(True)
        where.addWidget(self.face_button)
        where.addWidget(self.face_label)

        layout.addWidget(where_box)
        self.legend = QtGui.QLabel(translate(
            CONTEXT, "On the floor: blue to yellow = score (low to high); pale = reachable, not "
            "checked in full; red = fails the full check (collision...); grey = out of reach, "
            "joint limits or singularity."))
        self.legend.setWordWrap(True)
        layout.addWidget(self.legend)
        if face is not None:
            self.use_face(face)
        self.show_taught_note()

    def show_taught_note(self):
        """With a taught calibration frame the search has nothing to place: say why and how
        to plan with the drawn frame instead, and leave Search off.

        Returns
        -------
        str or None
            The note shown, or None (no taught frame, or the cell cannot be read yet:
            the search says why).
        """
        try:
            labels = api.taught_frame_labels(self.cell)
        except CadRobotError:
            return None
        if not labels:
            return None
        note = api.taught_frame_note(self.cell, labels[0])
        self.show_message(note)
        self.search_button.setEnabled(False)
        return note

    # -- inputs --
    def _turn_enabled(self, facing):
        for box in (self.turn_min, self.turn_max, self.turn_step):
            box.setEnabled(not facing)

    def show_message(self, text, error=False):
        self.message.setStyleSheet("color: red;" if error else "")
        self.message.setText(text)

    def show_error(self, err):
        """`err` in red in the panel, the object at fault selected."""
        command_base.report_error(self.doc, "", err, show=False)
        self.show_message(str(err), error=True)

    def use_face(self, face):
        """Search `face` ((obj, "FaceN"), horizontal): its rectangle and height fill the boxes."""
        try:
            _, (xmin, ymin, xmax, ymax), z = floor_face.floor_face(face)
        except CadRobotError as err:
            self.show_error(err)
            return False
        self.face = (face[0], face[1])
        for box, value in ((self.xmin, xmin), (self.ymin, ymin), (self.xmax, xmax), (self.ymax, ymax),
                           (self.zmin, z), (self.zmax, z)):
            box.setValue(value)
        self.face_label.setText(translate(CONTEXT, "Face: {0}.{1}").format(face[0].Label, face[1]))
        return True

    def take_selected_face(self):
        """Use the face selected in the 3D view, or go back to the rectangle when none is."""
        for sel in FreeCADGui.Selection.getSelectionEx(self.doc.Name):
            for name in sel.SubElementNames:
                if name.startswith("Face"):
                    return self.use_face((sel.Object, name))
        self.face = None
        self.face_label.setText(translate(CONTEXT, "Rectangle (select a face first to use one)"))
        return False

    def arguments(self):
        """The keyword arguments of :func:`api.place_robot` the boxes say (dict)."""
        args = {"region": (self.xmin.value(), self.ymin.value(), self.xmax.value(), self.ymax.value()),
                "z_mm": (self.zmin.value(), self.zmax.value()), "step_mm": self.step.value(),
                "z_step_mm": self.z_step.value(), "margin_deg": self.margin.value(),
                "count": self.count.value()}
        if not self.face_the_part.isChecked():
            args.update(turn_deg=(self.turn_min.value(), self.turn_max.value()),
                        turn_step_deg=self.turn_step.value())
        if self.face is not None:
            args["face"] = self.face
        return args

    # -- searching --
    def _progress(self, fraction, text):
        if self.closed:
            return False
        self.progress.setValue(int(round(1000 * fraction)))
        self.progress.setFormat("%s: %%p%%" % text)
        QtGui.QApplication.processEvents()
        return not self._stop

    def stop(self):
        """Stop the running search (it ends at its next progress report)."""
        self._stop = True

    def search(self):
        """Run the search; fill the list and draw the heat map.

        Returns
        -------
        robots.placement.placement_search.Placements or None
            None when it failed or was stopped.
        """
        if self.searching or gui_progress.busy():
            return None
        self.searching, self._stop = True, False
        self.search_button.setEnabled(False)
        self.stop_button.setEnabled(True)
        self.progress.setVisible(True)
        self.clear_result()
        self.show_message(translate(CONTEXT, "Searching..."))
        try:
            with gui_progress.under_way("CadRobot_PlaceRobot"):     # no other work meanwhile
                result = api.place_robot(self.cell, progress=self._progress, **self.arguments())
        except api.SearchCancelled:
            result = None
            if not self.closed:
                self.show_message(translate(CONTEXT, "Stopped."))
        except Exception as err:        # noqa: BLE001 -- why the list is empty, never a stuck panel
            result = None
            if not self.closed:
                self.show_error(command_base.as_cadrobot_error(err))
        finally:
            self.searching = False
        if self.closed:
            return None
        self.progress.setVisible(False)
        self.search_button.setEnabled(True)
        self.stop_button.setEnabled(False)
        if result is not None:
            self.show_result(result)
        return result

    def clear_result(self):
        self.result = None
        self.list.clear()
        self.list.setVisible(False)
        self.apply_button.setEnabled(False)
        self.remove_drawings()

    def show_result(self, result):
        self.result = result
        view = self._view()
        if view is not None:
            self.heat = heat_map.HeatMapView(view, result.heat)
        for rank, candidate in enumerate(result, 1):
            self.list.addItem(candidate_text(rank, candidate))
        self.list.setVisible(bool(result))
        lines = result.lines()
        self.not_checked_bar.show_for(result.not_checked)
        not_checked.show_status(result.not_checked)
        text = next(line for line in lines if not line.startswith("NOT CHECKED: "))
        if not result:
            text += "\n" + translate(CONTEXT, "No placement works here:") + "\n" + "\n".join(
                line for line in lines if line.startswith(("Failed", "FAILS")))
        self.show_message(text, error=not result)
        FreeCAD.Console.PrintMessage("".join("CadRobot: %s\n" % line for line in lines))
        if result:
            self.list.setCurrentRow(0)

    def _view(self):
        gui_doc = FreeCADGui.getDocument(self.doc.Name)
        view = gui_doc.activeView() if gui_doc is not None else None
        return view if hasattr(view, "getSceneGraph") else None

    # -- picking and applying --
    def picked(self):
        """The placement picked in the list, or None."""
        row = self.list.currentRow()
        if self.result is None or not 0 <= row < len(self.result):
            return None
        return self.result[row]

    def pick(self, row=None):
        """Draw the robot at the picked placement, at the start of the first path."""
        candidate = self.picked()
        self.apply_button.setEnabled(candidate is not None)
        if candidate is None:
            return
        view = self._view()
        if self.preview is None and view is not None:
            self.preview = robot_display.robot_at(self.cell.Robot, candidate.T_u_r,
                                                  matrix_from_placement(self.cell.ToolTCP), view=view)
            robot_display.hold(self.cell, True)
        if self.preview is not None:
            self.preview.set_base(candidate.T_u_r)
            if candidate.preview_joints_deg is not None:
                self.preview.set_joints(candidate.preview_joints_deg)

    def journal_lines(self, candidate):
        """The search as a comment, then the API call that stands the robot at `candidate`."""
        search = command_base.call("api.place_robot", self.cell, **self.arguments())
        return ["# %s found by %s" % (candidate.where(), search),
                command_base.call("api.set_robot_placement", self.cell, candidate.placement)]

    def apply(self):
        """Stand the cell's robot at the picked placement (one undo step). True when done."""
        candidate = self.picked()
        if candidate is None:
            self.show_error(InputError(translate(CONTEXT, "Search, then pick a placement in the list.")))
            return False
        try:
            command_base.journal(self.doc, translate(CONTEXT, "Place robot"),
                                 self.journal_lines(candidate))
        except CadRobotError as err:
            self.show_error(err)
            return False
        self.show_message(translate(CONTEXT, "The robot stands at {0}.").format(candidate.where()))
        return True

    def remove_drawings(self):
        """Take the heat map and the preview robot out of the view."""
        if self.heat is not None:
            self.heat.remove()
            self.heat = None
        if self.preview is not None:
            self.preview.remove()
            self.preview = None
            robot_display.hold(self.cell, False)

    def clean_up(self):
        """The panel closes: stop a search, remove the drawings."""
        self.closed = self._stop = True
        try:
            self.remove_drawings()
        except ReferenceError:       # the cell was deleted meanwhile
            pass

    # -- task dialog --
    def ok(self):
        if self.searching:
            self.stop()
            return False
        return self.picked() is None or self.apply()

    def close_panel(self):
        close_panel()


def open_panel(cell, face=None):
    """Open the Place robot panel on `cell` (searching `face`, ``(obj, "FaceN")``, when given).

    Raises
    ------
    CadRobotError
        When another task panel is open.
    """
    return _slot.open(lambda: PlacePanel(cell, face), translate(
        CONTEXT, "Another task panel is open; close it first."))


def active_panel():
    """The open PlacePanel, or None."""
    return _slot.panel


def close_panel():
    """Close the panel, if open."""
    _slot.close()
