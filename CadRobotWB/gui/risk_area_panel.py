"""The risk area panel: the places where a cell's tool turns sharply, as a checklist.

``open_panel(cell, path=None)`` lists :func:`api.suggest_risk_areas` for the
cell (or one of its paths) at the ``RiskThreshold`` preference: one per
corner, with the path, its segments, the corner span, the turn the area
really makes (summed through the markers in it), the interpolation step it
gets and the moves it adds; below, the program's size now and with the
checked suggestions. "At the corners" chooses between welding through them
and stopping to reorient. OK creates the checked ones as one undo step
(journaled, see :func:`CadRobotWB.commands.base.journal`), each with its
suggested step, corner span and corner choice.

When the suggestions cannot be computed (two markers on one segment, a
path that cannot be read, ...) the list stays empty and the panel shows why.
"""

import FreeCAD
from PySide import QtCore, QtGui

from .. import api, preferences
from ..commands import base as command_base
from ..core.generate import AT_CORNER
from ..errors import CadRobotError, InputError
from .task_panels import PanelSlot, TaskPanel

translate = FreeCAD.Qt.translate

_slot = PanelSlot()


def suggestion_text(suggestion):
    """How one suggestion reads in the list: segments, corner span, turn, step, moves added."""
    turn = suggestion.jump_deg if suggestion.turn_deg is None else suggestion.turn_deg
    first, last = suggestion.first_segment, suggestion.last_segment
    if first > last and suggestion.corner_span_mm:
        text = translate("CadRobot_RiskArea", "{0}: segments {1} to {2} (where the loop closes), {3:g} mm "
                         "each side of the corner, welding on over the start, tool turns {4:.1f}\u00b0"
                         ).format(suggestion.path.Label, first, last, suggestion.corner_span_mm, turn)
    elif first > last:
        text = translate("CadRobot_RiskArea", "{0}: segments {1} to {2} (where the loop closes), tool "
                         "turns {3:.1f}\u00b0 round the end point").format(suggestion.path.Label, first, last, turn)
    elif suggestion.corner_span_mm:
        text = translate("CadRobot_RiskArea", "{0}: segments {1} to {2}, {3:g} mm each side of the corner, "
                         "tool turns {4:.1f}\u00b0").format(suggestion.path.Label, first, last,
                                                            suggestion.corner_span_mm, turn)
    else:
        text = translate("CadRobot_RiskArea", "{0}: segments {1} to {2}, tool turns {3:.1f}\u00b0").format(
            suggestion.path.Label, first, last, turn)
    if suggestion.step_mm is None:
        return text
    added = int(suggestion.moves_added)
    if added < 0:     # the area's few long moves replace more of the segments' own
        return text + translate("CadRobot_RiskArea", ", step {0:g} mm, {1:d} fewer moves").format(
            suggestion.step_mm, -added)
    return text + translate("CadRobot_RiskArea", ", step {0:g} mm, {1:+d} moves").format(
        suggestion.step_mm, added)


def suggestion_tooltip(suggestion):
    """Why the suggestion has its step."""
    return translate("CadRobot_RiskArea", "Step {0:g} mm: {1}").format(suggestion.step_mm, suggestion.step_rule)


def step_rule_text():
    """The default step rule, as the panel states it."""
    from ..core import risk_suggestions
    return translate(
        "CadRobot_RiskArea", "Step: the path's speed \u00d7 sample time (the paper's rule), made coarser "
        "where that only lengthens the program: the tool turns at most {0:g}\u00b0 per move, and moves "
        "on arcs and splines stay within the path's chord tolerance.").format(
            risk_suggestions.MAX_TURN_PER_MOVE_DEG)


def journal_line(cell, suggestion):
    """The API call that makes the risk area of `suggestion` (with its suggested step,
    corner span and corner choice)."""
    extra = {} if suggestion.step_mm is None else {"step_mm": float(suggestion.step_mm)}
    if suggestion.corner_span_mm:
        extra["corner_span_mm"] = float(suggestion.corner_span_mm)
    if suggestion.at_corner:
        extra["at_corner"] = suggestion.at_corner
    return "risk = " + command_base.call("api.make_risk_area", cell.Document, cell, suggestion.path,
                                         int(suggestion.first_segment), int(suggestion.last_segment),
                                         **extra)


class RiskAreaPanel(TaskPanel):
    """Task panel: choose among the suggested risk areas of a cell or one path.

    Attributes
    ----------
    suggestions : list of RiskSuggestion
        What the list shows, in its order.
    """

    ACTION_BUTTONS = ('find_button',)

    def __init__(self, cell, path=None):
        self.cell, self.path = cell, path
        self.suggestions = []
        self.form = QtGui.QWidget()
        self.form.setWindowTitle(translate("CadRobot_RiskArea", "Risk areas"))
        layout = QtGui.QVBoxLayout(self.form)
        intro = QtGui.QLabel(translate(
            "CadRobot_RiskArea", "Corners where the tool turns more than the threshold between "
            "consecutive segments. The checked ones become risk areas: there the orientation turns "
            "smoothly through every tool marker, over a few mm each side of the corner."))
        intro.setWordWrap(True)
        layout.addWidget(intro)
        row = QtGui.QGridLayout()          # one field per row: fits FreeCAD's default panel width
        row.addWidget(QtGui.QLabel(translate("CadRobot_RiskArea", "Threshold")), 0, 0)
        self.threshold = QtGui.QDoubleSpinBox()
        self.threshold.setRange(0.0, 180.0)
        self.threshold.setDecimals(1)
        self.threshold.setSuffix(" \u00b0")
        self.threshold.setValue(preferences.get("RiskThreshold"))
        self.threshold.setToolTip(translate(
            "CadRobot_RiskArea", "Smallest turn of the tool between two segments that needs a risk area"))
        row.addWidget(self.threshold, 0, 1)
        row.addWidget(QtGui.QLabel(translate("CadRobot_RiskArea", "At the corners")), 1, 0, 1, 2)
        self.at_corner = QtGui.QComboBox()
        self.at_corner.addItems(list(AT_CORNER))
        self.at_corner.setToolTip(translate(
            "CadRobot_RiskArea", "Weld through: the torch turns while it welds on round the corner. "
            "Stop and reorient: it stops exactly at the corner, turns in place and goes on (where "
            "the arc goes off and on)"))
        self.at_corner.currentIndexChanged.connect(lambda _index: self.find())
        row.addWidget(self.at_corner, 2, 0, 1, 2)
        self.find_button = QtGui.QPushButton(translate("CadRobot_RiskArea", "Find"))
        self.find_button.clicked.connect(self.find)
        row.addWidget(self.find_button, 3, 0, 1, 2)
        layout.addLayout(row)
        # What was found (or why nothing) and the program's size above the list: in view.
        self.message = QtGui.QLabel()
        self.message.setWordWrap(True)
        layout.addWidget(self.message)
        self.size = QtGui.QLabel()
        self.size.setWordWrap(True)
        layout.addWidget(self.size)
        self.list = QtGui.QListWidget()
        self.list.setWordWrap(True)
        self.list.itemChanged.connect(self.show_size)
        layout.addWidget(self.list)
        self.rule = QtGui.QLabel(step_rule_text())
        self.rule.setWordWrap(True)
        layout.addWidget(self.rule)
        self.moves_now = None           # moves of the program now, or the reason it is unknown (str)
        self.find()

    def show_message(self, text, error=False):
        self.message.setStyleSheet("color: red;" if error else "")
        self.message.setText(text)

    def find(self):
        """List the suggestions at the current threshold, all checked."""
        self.list.blockSignals(True)
        self.list.clear()
        self.list.blockSignals(False)
        self.suggestions = []
        self.size.setText("")
        try:
            found = api.suggest_risk_areas(self.cell, self.threshold.value(), self.at_corner.currentText())
        except Exception as err:        # noqa: BLE001 -- whatever stops the list is shown, not hidden
            self.show_error(command_base.as_cadrobot_error(err))
            return []
        self.suggestions = [s for s in found if self.path is None or s.path == self.path]
        self.list.blockSignals(True)
        for suggestion in self.suggestions:
            item = QtGui.QListWidgetItem(suggestion_text(suggestion))
            item.setToolTip(suggestion_tooltip(suggestion))
            item.setFlags(item.flags() | QtCore.Qt.ItemIsUserCheckable)
            item.setCheckState(QtCore.Qt.Checked)
            self.list.addItem(item)
        self.list.blockSignals(False)
        try:
            self.moves_now = api.program_move_count(self.cell)
        except Exception as err:        # noqa: BLE001 -- the size is then unknown, and why
            self.moves_now = str(command_base.as_cadrobot_error(err))
        self.show_size()
        if self.suggestions:
            self.show_message(translate("CadRobot_RiskArea", "{0} suggested risk areas.").format(
                len(self.suggestions)))
        else:
            self.show_message(translate(
                "CadRobot_RiskArea", "The tool turns by at most {0:.1f}\u00b0 between segments outside "
                "the existing risk areas: none needed.").format(self.threshold.value()))
        return self.suggestions

    def program_size(self):
        """(moves now, moves with the checked suggestions); None for both when the
        program cannot be generated yet."""
        if not isinstance(self.moves_now, int):
            return None, None
        return self.moves_now, self.moves_now + sum(int(s.moves_added) for s in self.checked())

    def show_size(self, *_changed):
        """The program's size now and with the checked suggestions."""
        if not self.suggestions:
            self.size.setText("")
            return
        now, with_checked = self.program_size()
        added = sum(int(s.moves_added) for s in self.checked())
        if now is None:
            self.size.setText(translate(
                "CadRobot_RiskArea", "The checked risk areas add {0:+d} moves. Program size unknown "
                "until it generates: {1}").format(added, self.moves_now))
        else:
            self.size.setText(translate(
                "CadRobot_RiskArea", "Program: {0} moves now, {1} with the checked risk areas "
                "({2:+d}).").format(now, with_checked, added))

    def set_checked(self, index, checked):
        """Check or uncheck suggestion `index`."""
        self.list.item(index).setCheckState(QtCore.Qt.Checked if checked else QtCore.Qt.Unchecked)

    def checked(self):
        """The checked suggestions."""
        return [s for i, s in enumerate(self.suggestions)
                if self.list.item(i).checkState() == QtCore.Qt.Checked]

    def show_error(self, err):
        """`err` in red in the panel, the object at fault selected."""
        command_base.report_error(self.cell.Document, "", err, show=False)
        self.show_message(str(err), error=True)

    def create(self):
        """Make the checked risk areas (one undo step). True when done."""
        chosen = self.checked()
        if not chosen:
            self.show_error(InputError(translate(
                "CadRobot_RiskArea", "Check at least one suggested risk area, or Cancel.")))
            return False
        try:
            command_base.journal(self.cell.Document, translate("CadRobot_RiskArea", "Risk areas"),
                                 [journal_line(self.cell, s) for s in chosen])
        except CadRobotError as err:
            self.show_error(err)
            return False
        return True

    # -- task dialog --
    def ok(self):
        return self.create()

    def close_panel(self):
        close_panel()


def open_panel(cell, path=None):
    """Open the risk area panel on `cell` (only `path`'s suggestions when given).

    Raises
    ------
    CadRobotError
        When another task panel is open.
    """
    return _slot.open(lambda: RiskAreaPanel(cell, path), translate(
        "CadRobot_RiskArea", "Another task panel is open; close it first."))


def active_panel():
    """The open RiskAreaPanel, or None."""
    return _slot.panel


def close_panel():
    """Close the panel, if open."""
    _slot.close()
