"""The new cell panel: choose a robot from the catalog and place its base.

``open_panel(doc)`` shows the catalog (each robot's maker, controller,
payload, reach and the catalog's notes), the cell's name and the robot base
{R} in {U}: X, Y, Z and a rotation about Z, or the selected vertex / point.
While the panel is open the chosen robot stands in the 3D view at the base
typed (:func:`.robot_display.robot_at`; nothing added to the document), and
goes when the panel closes.  OK adds the cell as one journaled undo step
(``api.make_cell``).
"""

import functools

import FreeCAD
import FreeCADGui
import numpy as np
from PySide import QtGui

from .. import api, preferences
from ..commands import base as command_base
from ..commands import selection
from ..errors import CadRobotError, InputError
from ..objects.convert import matrix_from_placement
from ..robots import catalog, models
from . import robot_display
from .task_panels import PanelSlot, TaskPanel

translate = FreeCAD.Qt.translate

_slot = PanelSlot(before_close=lambda panel: panel.remove_preview())

#: Spin box range for the base position, mm.
POSITION_RANGE_MM = 1.0e6


@functools.lru_cache(maxsize=None)
def reach_mm(robot, samples=20000):
    """How far the flange gets from axis 1 (horizontally), mm: the largest of
    `samples` random joint vectors within the catalog's limits (seeded, so
    always the same number)."""
    model = models.model(robot)
    spec = model.spec
    q_ctrl = np.random.default_rng(0).uniform(spec.joint_min_deg, spec.joint_max_deg, (samples, 6))
    T_r_f = model.fk(model.model_joints(q_ctrl))
    return float(np.hypot(T_r_f[:, 0, 3], T_r_f[:, 1, 3]).max())


def robot_description(robot):
    """Rich text describing catalog robot `robot`."""
    spec = catalog.get(robot)
    text = translate("CadRobot_NewCell", "<b>{0} {1}</b><br>Controller {2}, payload {3:g} kg, "
                     "reach about {4:.0f} mm, programs in {5}.").format(
        spec.manufacturer, spec.model, spec.controller, spec.payload_kg,
        round(reach_mm(robot), -1), spec.default_post)
    if spec.notes:
        text += "<br><i>%s</i>" % spec.notes.replace("&", "&amp;").replace("<", "&lt;")
    return text


def _spin(suffix, limit, decimals=3):
    box = QtGui.QDoubleSpinBox()
    box.setRange(-limit, limit)
    box.setDecimals(decimals)
    box.setSuffix(suffix)
    return box


class NewCellPanel(TaskPanel):
    """Task panel: the robot and where its base stands.

    Attributes
    ----------
    preview : robot_view.RobotView or None
        The chosen robot drawn at the base typed (None without a 3D view).
    """

    def __init__(self, doc):
        self.doc = doc
        self.preview = None
        self.form = QtGui.QWidget()
        self.form.setWindowTitle(translate("CadRobot_NewCell", "New robot cell"))
        layout = QtGui.QVBoxLayout(self.form)

        robot_box = QtGui.QGroupBox(translate("CadRobot_NewCell", "Robot"))
        robot_layout = QtGui.QFormLayout(robot_box)
        self.robot = QtGui.QComboBox()
        self.robot.addItems(api.robot_names())
        robot_layout.addRow(translate("CadRobot_NewCell", "Model"), self.robot)
        self.description = QtGui.QLabel()
        self.description.setWordWrap(True)
        robot_layout.addRow(self.description)
        self.name = QtGui.QLineEdit("Cell")
        robot_layout.addRow(translate("CadRobot_NewCell", "Name"), self.name)
        layout.addWidget(robot_box)

        base_box = QtGui.QGroupBox(translate("CadRobot_NewCell", "Robot base {R} in the drawing"))
        base_layout = QtGui.QFormLayout(base_box)
        self.x, self.y, self.z = (_spin(" mm", POSITION_RANGE_MM) for _ in range(3))
        self.rotation = _spin(" \u00b0", 360.0, decimals=2)
        for label, box in (("X", self.x), ("Y", self.y), ("Z", self.z)):
            base_layout.addRow(label, box)
        base_layout.addRow(translate("CadRobot_NewCell", "Rotation about Z"), self.rotation)
        self.use_selection = QtGui.QPushButton(translate("CadRobot_NewCell", "Use selected point"))
        self.use_selection.setToolTip(translate(
            "CadRobot_NewCell", "Put the base on the selected vertex or point (select it in the 3D view)"))
        self.use_selection.clicked.connect(self.take_selected_point)
        base_layout.addRow(self.use_selection)
        layout.addWidget(base_box)

        self.message = QtGui.QLabel()
        self.message.setWordWrap(True)
        layout.addWidget(self.message)

        self.robot.currentIndexChanged.connect(self._robot_changed)
        for box in (self.x, self.y, self.z, self.rotation):
            box.valueChanged.connect(self.update_preview)
        default = preferences.get("DefaultRobot")
        names = api.robot_names()
        self.robot.setCurrentIndex(names.index(default) if default in names else 0)
        self._robot_changed()
        self.take_selected_point(quiet=True)

    def _robot_changed(self, _index=None):
        self.description.setText(robot_description(self.robot.currentText()))
        self.update_preview()

    def base_placement(self):
        """FreeCAD.Placement: the robot base {R} in {U} as typed."""
        return FreeCAD.Placement(FreeCAD.Vector(self.x.value(), self.y.value(), self.z.value()),
                                 FreeCAD.Rotation(FreeCAD.Vector(0, 0, 1), self.rotation.value()))

    def update_preview(self, *_args):
        """Draw the chosen robot at the base typed (new solids only for another robot)."""
        robot, T_u_r = self.robot.currentText(), matrix_from_placement(self.base_placement())
        if self.preview is not None and self.preview.model.spec.name != robot:
            self.remove_preview()
        if self.preview is None:
            gui_doc = FreeCADGui.getDocument(self.doc.Name)
            view = gui_doc.activeView() if gui_doc is not None else None
            if hasattr(view, "getSceneGraph"):      # not in a spreadsheet or drawing view
                self.preview = robot_display.robot_at(robot, T_u_r, view=view)
        if self.preview is not None:
            self.preview.set_base(T_u_r)

    def remove_preview(self):
        """Take the preview robot out of the view."""
        if self.preview is not None:
            self.preview.remove()
            self.preview = None

    def take_selected_point(self, quiet=False):
        """Put the base on the selected vertex / point. True when there was one."""
        point = selection.picked_point(selection.selected(self.doc))
        if point is None:
            if not quiet:
                self.show_message(translate("CadRobot_NewCell", "Select a vertex or a point in the "
                                            "3D view first."), error=True)
            return False
        self.x.setValue(point.x)
        self.y.setValue(point.y)
        self.z.setValue(point.z)
        self.show_message("")
        return True

    def show_message(self, text, error=False):
        self.message.setStyleSheet("color: red;" if error else "")
        self.message.setText(text)

    def placement_code(self):
        """Source of the base placement as the user typed it."""
        return command_base.Code("FreeCAD.Placement(FreeCAD.Vector(%r, %r, %r), FreeCAD.Rotation("
                                 "FreeCAD.Vector(0, 0, 1), %r))" % (
                                     self.x.value(), self.y.value(), self.z.value(),
                                     self.rotation.value()))

    def journal_line(self):
        """The API call that makes the cell."""
        name = self.name.text().strip() or "Cell"
        return "cell = " + command_base.call("api.make_cell", self.doc, robot=self.robot.currentText(),
                                             name=name, placement=self.placement_code())

    def create(self):
        """Add the cell (one undo step). The new cell, or None (error shown)."""
        try:
            if not self.name.text().strip():
                raise InputError(translate("CadRobot_NewCell", "Give the cell a name."))
            cell, = command_base.journal(self.doc, translate("CadRobot_NewCell", "New robot cell"),
                                         [self.journal_line()], results=["cell"])
        except CadRobotError as err:
            command_base.report_error(self.doc, "", err, show=False)
            self.show_message(str(err), error=True)
            return None
        command_base.select_in_tree(self.doc, cell.Name)
        return cell

    # -- task dialog --
    def ok(self):
        return self.create() is not None

    def close_panel(self):
        close_panel()


def open_panel(doc):
    """Open the new cell panel for `doc` (InputError when another task panel is open)."""
    return _slot.open(lambda: NewCellPanel(doc), translate(
        "CadRobot_NewCell", "Another task panel is open; close it first."))


def active_panel():
    """The open NewCellPanel, or None."""
    return _slot.panel


def close_panel():
    """Close the panel, if open."""
    _slot.close()
