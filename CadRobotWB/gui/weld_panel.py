"""The weld panel: where a weld goes, its schedule, its weave and its tracking.

``open_panel(cell, path=None, first_segment=None, last_segment=None)`` shows
the path and its segment range; the schedule combo lists "From the joint"
(the library's row for the joint the faces show, with the sentence why),
the library's rows, the user's own ("yours") and Custom; the schedule's
values below it (changing one makes the schedule Custom); the weave group
(unchecked: no weave) and the tracking. The woven path is drawn in the 3D
view while the panel is open. "Save as my schedule" keeps the values in the
user's schedule folder. OK journals ``api.make_weld(...)`` (one undo step,
see :func:`CadRobotWB.commands.base.journal`).
"""

import FreeCAD
import FreeCADGui
from PySide import QtGui

from .. import api
from ..commands import base as command_base
from ..core.welding import (POSITIONS, SCHEDULE_FIELDS, TRACKING_SENSORS, WEAVE_FIELDS,
                            WEAVE_PATTERNS, Weave)
from ..errors import CadRobotError
from ..objects import reader
from ..objects import weld as weld_object
from ..workflow import welds as weld_workflow
from . import triad_display
from .task_panels import PanelSlot, TaskPanel
from .view_providers import STYLES

translate = FreeCAD.Qt.translate

_slot = PanelSlot(before_close=lambda panel: panel.remove_preview())

FROM_JOINT, CUSTOM = "", weld_object.CUSTOM
#: Schedule fields the panel shows: (key, label, decimals).
SCHEDULE_ROWS = (("voltage_v", "Voltage", 1), ("current_a", "Current", 0),
                 ("wire_feed_m_min", "Wire feed", 1), ("travel_speed_mm_s", "Travel speed", 1),
                 ("wire_mm", "Wire diameter", 1), ("ctwd_mm", "CTWD", 1),
                 ("gas_preflow_s", "Gas pre-flow", 2), ("gas_postflow_s", "Gas post-flow", 2),
                 ("crater_fill_s", "Crater fill", 2), ("burnback_s", "Burn-back", 2))
#: Weave fields the panel shows: (key, label, decimals).
WEAVE_ROWS = (("width_mm", "Width", 1), ("frequency_hz", "Frequency", 2),
              ("length_mm", "Length per cycle", 1), ("dwell_left_s", "Dwell left", 2),
              ("dwell_center_s", "Dwell centre", 2), ("dwell_right_s", "Dwell right", 2),
              ("angle_deg", "Angle", 1))
PREVIEW_WIDTH_PX = 3.0


def _spin(spec, decimals):
    """A spin box over the field's range; 0 reads "-" (not given) for fields without a default."""
    default, low, high, unit, what = spec
    box = QtGui.QDoubleSpinBox()
    box.setDecimals(decimals)
    box.setRange(0.0 if default is None else low, high)
    if default is None:
        box.setSpecialValueText("-")
        what += translate("CadRobot_Weld", "; - : not given")
    if unit:
        box.setSuffix(" " + unit)
    box.setToolTip(what)
    box.setValue(default or 0.0)
    return box


def _form(rows, table, parent_layout):
    """{key: spin box} of `rows`, in a form whose labels go above their boxes when the
    panel is narrow (FreeCAD's default panel width)."""
    form = QtGui.QFormLayout()
    form.setRowWrapPolicy(QtGui.QFormLayout.WrapLongRows)
    boxes = {}
    for key, label, decimals in rows:
        boxes[key] = _spin(table[key], decimals)
        form.addRow(translate("CadRobot_Weld", label), boxes[key])
    parent_layout.addLayout(form)
    return boxes


class WeldPanel(TaskPanel):
    """Task panel: make one weld on a path of `cell`.

    Attributes
    ----------
    schedules : dict of str to dict
        The library's and the user's (``api.weld_schedules()``), as the combo lists them.
    picked : tuple or None
        ``(WeldSchedule, note)`` of "From the joint" for the path and segments
        shown, or the CadRobotError why there is none.
    preview : coin.SoSeparator or None
        The woven path drawn in the 3D view.
    """

    ACTION_BUTTONS = ("save_button",)

    def __init__(self, cell, path=None, first_segment=None, last_segment=None):
        self.cell, self.doc = cell, cell.Document
        self.paths = reader.cell_paths(cell)
        self.picked, self.preview, self._filling = None, None, False
        self.form = QtGui.QWidget()
        self.form.setWindowTitle(translate("CadRobot_Weld", "Weld"))
        layout = QtGui.QVBoxLayout(self.form)
        self._where(layout, path, first_segment, last_segment)
        self._schedule_group(layout)
        self._weave_group(layout)
        self._tracking(layout)
        self.message = QtGui.QLabel()
        self.message.setWordWrap(True)
        layout.addWidget(self.message)
        self.load_schedules()
        self.schedule_combo.setCurrentIndex(0)
        self.schedule_chosen()

    # --- building the form -------------------------------------------------------------------
    def _where(self, layout, path, first, last):
        grid = QtGui.QGridLayout()
        grid.addWidget(QtGui.QLabel(translate("CadRobot_Weld", "Path")), 0, 0)
        self.path_combo = QtGui.QComboBox()
        self.path_combo.addItems([p.Label for p in self.paths])
        if path is not None and path in self.paths:
            self.path_combo.setCurrentIndex(self.paths.index(path))
        grid.addWidget(self.path_combo, 0, 1)
        self.first_spin, self.last_spin = QtGui.QSpinBox(), QtGui.QSpinBox()
        for row, (box, label, special, value) in enumerate((
                (self.first_spin, "First segment", "first", first),
                (self.last_spin, "Last segment", "last", last)), start=1):
            box.setRange(0, 100000)
            box.setSpecialValueText(translate("CadRobot_Weld", special))
            box.setValue(value or 0)
            grid.addWidget(QtGui.QLabel(translate("CadRobot_Weld", label)), row, 0)
            grid.addWidget(box, row, 1)
        layout.addLayout(grid)
        self.path_combo.currentIndexChanged.connect(lambda _i: self.where_changed())
        self.first_spin.valueChanged.connect(lambda _v: self.where_changed())
        self.last_spin.valueChanged.connect(lambda _v: self.where_changed())

    def _schedule_group(self, layout):
        group = QtGui.QGroupBox(translate("CadRobot_Weld", "Schedule"))
        inner = QtGui.QVBoxLayout(group)
        self.schedule_combo = QtGui.QComboBox()
        self.schedule_combo.currentIndexChanged.connect(lambda _i: self.schedule_chosen())
        inner.addWidget(self.schedule_combo)
        # above the (long) note: in view without scrolling in FreeCAD 1.1's task overlay
        self.save_name = QtGui.QLineEdit()      # one per row: fits FreeCAD's default panel width
        self.save_name.setPlaceholderText(translate("CadRobot_Weld", "my schedule's name"))
        inner.addWidget(self.save_name)
        self.save_button = QtGui.QPushButton(translate("CadRobot_Weld", "Save as my schedule"))
        self.save_button.clicked.connect(self.save_schedule)
        inner.addWidget(self.save_button)
        self.note = QtGui.QLabel()
        self.note.setWordWrap(True)
        inner.addWidget(self.note)
        self.schedule_boxes = _form(SCHEDULE_ROWS, SCHEDULE_FIELDS, inner)
        for box in self.schedule_boxes.values():
            box.valueChanged.connect(lambda _v: self.schedule_edited())
        layout.addWidget(group)

    def _weave_group(self, layout):
        self.weave_group = QtGui.QGroupBox(translate("CadRobot_Weld", "Weave"))
        self.weave_group.setCheckable(True)
        self.weave_group.setChecked(False)
        inner = QtGui.QVBoxLayout(self.weave_group)
        self.pattern_combo = QtGui.QComboBox()
        self.pattern_combo.addItems(list(WEAVE_PATTERNS))
        inner.addWidget(self.pattern_combo)
        self.weave_boxes = _form(WEAVE_ROWS, WEAVE_FIELDS, inner)
        self.weave_group.toggled.connect(lambda _on: self.update_preview())
        self.pattern_combo.currentIndexChanged.connect(lambda _i: self.update_preview())
        for box in self.weave_boxes.values():
            box.valueChanged.connect(lambda _v: self.update_preview())
        layout.addWidget(self.weave_group)

    def _tracking(self, layout):
        row = QtGui.QHBoxLayout()
        row.addWidget(QtGui.QLabel(translate("CadRobot_Weld", "Tracking")))
        self.tracking_combo = QtGui.QComboBox()
        self.tracking_combo.addItems(list(TRACKING_SENSORS))
        self.tracking_combo.setToolTip(translate(
            "CadRobot_Weld", "arc: through-arc seam tracking (needs a weave); laser: the laser seam tracker"))
        row.addWidget(self.tracking_combo)
        layout.addLayout(row)
        row = QtGui.QHBoxLayout()
        row.addWidget(QtGui.QLabel(translate("CadRobot_Weld", "Position")))
        self.position_combo = QtGui.QComboBox()
        self.position_combo.addItems(list(POSITIONS))
        self.position_combo.setToolTip(translate(
            "CadRobot_Weld", "The position a positioner keeps the seam in: PA flat, PB "
            "horizontal-vertical fillet (ISO 6947)"))
        row.addWidget(self.position_combo)
        layout.addLayout(row)

    # --- the schedule ------------------------------------------------------------------------
    def load_schedules(self, select=None):
        """Fill the combo: From the joint, the library's rows, the user's own, Custom."""
        from ..core import schedule_library
        self.schedules = api.weld_schedules()
        library = schedule_library.library_rows()
        self.schedule_combo.blockSignals(True)
        self.schedule_combo.clear()
        self.schedule_combo.addItem(translate("CadRobot_Weld", "From the joint"), FROM_JOINT)
        for name, schedule in self.schedules.items():
            yours = name not in library or schedule["source"] != library[name].get("source")
            shown = name + (translate("CadRobot_Weld", " (yours)") if yours else "")
            self.schedule_combo.addItem(shown, name)
        self.schedule_combo.addItem(translate("CadRobot_Weld", "Custom"), CUSTOM)
        if select is not None:
            self.schedule_combo.setCurrentIndex(self.schedule_combo.findData(select))
        self.schedule_combo.blockSignals(False)

    def chosen(self):
        """The combo's choice: FROM_JOINT, a schedule name or CUSTOM."""
        return self.schedule_combo.itemData(self.schedule_combo.currentIndex())

    def schedule_chosen(self):
        """Show the chosen schedule's values and where they come from."""
        choice = self.chosen()
        schedule, note = None, ""
        if choice == FROM_JOINT:
            picked = self.joint_pick()
            if isinstance(picked, CadRobotError):
                note = str(picked)
            else:
                schedule, note = picked[0].as_dict(), picked[1]
        elif choice != CUSTOM:
            schedule = self.schedules[choice]
            note = schedule["source"] or translate("CadRobot_Weld", "Your own schedule.")
        if schedule is not None:
            self._filling = True
            for key, box in self.schedule_boxes.items():
                box.setValue(schedule[key] or 0.0)
            self._filling = False
        self.note.setText(note)
        self.update_preview()

    def joint_pick(self):
        """(WeldSchedule, note) of "From the joint" for the path and segments shown, or the
        CadRobotError why there is none (computed once per path and segments)."""
        key = (self.path().Name, self.segments_given())
        if self.picked is None or self.picked[0] != key:
            try:
                result = weld_workflow.library_pick(self.cell, self.path(), self.segments(),
                                                    translate("CadRobot_Weld", "The weld"))
            except CadRobotError as err:
                result = err
            self.picked = (key, result)
        return self.picked[1]

    def schedule_edited(self):
        """A value changed by hand: the schedule is the user's (Custom)."""
        if self._filling:
            return
        self.schedule_combo.blockSignals(True)
        self.schedule_combo.setCurrentIndex(self.schedule_combo.findData(CUSTOM))
        self.schedule_combo.blockSignals(False)
        self.note.setText(translate("CadRobot_Weld", "Your values (Custom)."))
        self.update_preview()

    def schedule_values(self):
        """The schedule fields shown, as the API dict (0 in a field without a default left out)."""
        values = {}
        for key, box in self.schedule_boxes.items():
            if box.value() or SCHEDULE_FIELDS[key][0] is not None:
                values[key] = round(box.value(), box.decimals())
        return values

    def save_schedule(self):
        """Keep the values shown as the user's schedule named in the box."""
        name = self.save_name.text().strip()
        try:
            written = api.save_weld_schedule(name, self.schedule_values())
        except CadRobotError as err:
            self.show_message(str(err), error=True)
            return None
        self.load_schedules(select=name)
        self.schedule_chosen()
        self.show_message(translate("CadRobot_Weld", "Saved as '{0}' in {1}.").format(name, written))
        return written

    # --- where --------------------------------------------------------------------------------
    def path(self):
        return self.paths[self.path_combo.currentIndex()]

    def segments_given(self):
        """(first, last) as typed; 0 = the path's end."""
        return self.first_spin.value(), self.last_spin.value()

    def segments(self):
        """(first, last), 1-based, of the path shown (raises InputError off the path)."""
        first, last = self.segments_given()
        return weld_workflow.segment_range(self.path(), first or None, last or None,
                                           translate("CadRobot_Weld", "The weld"))

    def where_changed(self):
        if self.chosen() == FROM_JOINT:
            self.schedule_chosen()
        else:
            self.update_preview()

    # --- the call -----------------------------------------------------------------------------
    def weave_values(self):
        """The weave dict of the API, or None when the weave group is unchecked."""
        if not self.weave_group.isChecked():
            return None
        values = {"pattern": self.pattern_combo.currentText()}
        for key, box in self.weave_boxes.items():
            if box.value() or WEAVE_FIELDS[key][0] is not None:
                values[key] = round(box.value(), box.decimals())
        return values

    def arguments(self):
        """The keyword arguments of api.make_weld besides doc, cell and path."""
        choice = self.chosen()
        out = {}
        if choice == CUSTOM:
            out["schedule"] = self.schedule_values()
        elif choice != FROM_JOINT:
            out["schedule"] = choice
        weave = self.weave_values()
        if weave is not None:
            out["weave"] = weave
        first, last = self.segments_given()
        if first:
            out["first_segment"] = first
        if last:
            out["last_segment"] = last
        if self.tracking_combo.currentText() != TRACKING_SENSORS[0]:
            out["tracking"] = self.tracking_combo.currentText()
        if self.position_combo.currentText() != POSITIONS[0]:
            out["position"] = self.position_combo.currentText()
        return out

    def journal_line(self):
        return "weld = " + command_base.call("api.make_weld", self.doc, self.cell, self.path(),
                                             **self.arguments())

    # --- the preview -------------------------------------------------------------------------
    def update_preview(self):
        """Draw the woven path of the values shown (nothing, and why, when they are wrong)."""
        self.remove_preview()
        try:
            weave = self.weave_values()
            if weave is not None:
                weave = Weave.from_dict(weave, what=translate("CadRobot_Weld", "The weave"))
            speed = self.schedule_boxes["travel_speed_mm_s"].value()
            points = weld_object.woven_path(self.cell, self.path(), self.segments(), speed, weave)
        except CadRobotError as err:
            self.show_message(str(err), error=True)
            return None
        self.show_message("")
        color = STYLES["Weld"][0]
        self.preview = triad_display.segments_node(points[:-1], points[1:], color, PREVIEW_WIDTH_PX)
        graph = _scene_graph(self.doc)
        if graph is not None:
            graph.addChild(self.preview)
        return points

    def remove_preview(self):
        graph = _scene_graph(self.doc)
        if self.preview is not None and graph is not None:
            graph.removeChild(self.preview)
        self.preview = None

    def show_message(self, text, error=False):
        self.message.setStyleSheet("color: red;" if error else "")
        self.message.setText(text)

    # -- task dialog --
    def ok(self):
        """Journal api.make_weld (one undo step). True when done."""
        try:
            done = command_base.journal(self.doc, translate("CadRobot_Weld", "Weld"),
                                        [self.journal_line()], results=["weld"])
        except CadRobotError as err:
            command_base.report_error(self.doc, "", err, show=False)
            self.show_message(str(err), error=True)
            return False
        command_base.select_in_tree(self.doc, done[0].Name)
        return True

    def close_panel(self):
        close_panel()


def _scene_graph(doc):
    """The scene graph of `doc`'s active 3D view, or None."""
    try:
        view = FreeCADGui.getDocument(doc.Name).activeView()
        return view.getSceneGraph()
    except (AttributeError, RuntimeError, ReferenceError):
        return None


def open_panel(cell, path=None, first_segment=None, last_segment=None):
    """Open the weld panel on `cell` (on `path` and its segments when given).

    Raises
    ------
    CadRobotError
        When another task panel is open, or the cell has no path.
    """
    if not reader.cell_paths(cell):
        from ..errors import InputError
        raise InputError(translate("CadRobot_Weld", "Cell {0} has no paths: mark one first (Mark path).")
                         .format(cell.Label), cell.Name)
    return _slot.open(lambda: WeldPanel(cell, path, first_segment, last_segment), translate(
        "CadRobot_Weld", "Another task panel is open; close it first."))


def active_panel():
    """The open WeldPanel, or None."""
    return _slot.panel


def close_panel():
    """Close the panel, if open."""
    _slot.close()
