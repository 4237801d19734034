"""The mechanism panel: a positioner holding the part, or a track under the robot.

``open_panel(cell, "positioner")`` shows the kind (turntable or tilt-and-turn),
the catalog model (``robots.mechanisms.catalog.names(kind)``, or the generic
one), the base in the drawing (X, Y, Z and a rotation about Z: by default the
positioner's table under the parts, the track's carriage under the robot),
the parts riding on it (the objects selected when the panel opened, or "Use
selection") and the name. ``open_panel(cell, "track")`` shows the model, the
travel length, the base and the name. OK journals ONE API call,
``api.add_positioner(...)`` or ``api.add_track(...)`` (one undo step, see
:func:`CadRobotWB.commands.base.journal`). While the panel is open, the
mechanism chosen is drawn at the base typed (:mod:`.mechanism_preview`, outside
the document); OK, Cancel and closing take it away.

:func:`default_base`, :func:`riding_objects` and :func:`journal_line` are what
the New cell panel shares.
"""

import FreeCAD
import FreeCADGui
import numpy as np
from PySide import QtGui

from ..commands import base as command_base
from ..commands import selection
from ..core import frames as tf
from ..core import mechanisms as mech
from ..errors import CadRobotError
from ..objects.convert import matrix_from_placement, placement_from_matrix
from ..robots.mechanisms import catalog
from .mechanism_preview import MechanismPreview
from .task_panels import PanelSlot, TaskPanel

translate = FreeCAD.Qt.translate
CONTEXT = "CadRobot_Mechanism"

_slot = PanelSlot(before_close=lambda panel: panel.remove_preview())

POSITIONER, TRACK = "positioner", "track"
#: What each panel offers: kinds (the combo's items, with their labels), default name.
PANELS = {
    POSITIONER: ((mech.TILT_TURN, "Tilt-and-turn positioner (2 axes)"),
                 (mech.TURNTABLE, "Turntable (1 axis)")),
    TRACK: ((mech.TRACK, "Linear track under the robot (1 axis)"),),
}
DEFAULT_NAMES = {POSITIONER: "Positioner", TRACK: "Track"}
#: A new track's travel, mm (the generic track's).
DEFAULT_TRACK_MM = 3000.0
#: Shown in the model combo for the generic mechanism of a kind (``model=None``).
GENERIC = "Generic"
#: Spin box range for the base position, mm.
POSITION_RANGE_MM = 1.0e6
#: Narrowest a base coordinate box gets, pixels (two side by side in a 220 px panel).
MIN_SPIN_WIDTH_PX = 76
#: CadRobot objects that never ride on a positioner themselves (their sources do).
NOT_RIDING = ("Cell", "RobotPath", "Weld", "RiskArea", "Positioner", "Track")


# --- what the panels share ---------------------------------------------------------------------

def riding_objects(items):
    """The whole objects among the selected `items` a positioner can carry (solids,
    calibration frames, tool markers...), each once, in the order selected."""
    out = []
    for item in items:
        if item.cad_type in NOT_RIDING or item.obj in out:
            continue
        out.append(item.obj)
    return out


def _parts_bottom_centre(parts):
    """(x, y, z_min) of the parts' bounding box in {U}, mm, or None without shapes."""
    boxes = [p.Shape.BoundBox for p in parts
             if hasattr(p, "Shape") and not p.Shape.isNull() and p.Shape.BoundBox.isValid()]
    if not boxes:
        return None
    box = boxes[0]
    for other in boxes[1:]:
        box.add(other)
    return np.array([box.Center.x, box.Center.y, box.ZMin])


def default_base(kind, model=None, parts=(), robot_base=None, length_mm=None):
    """Where a new mechanism's base goes by default, in {U}.

    A positioner: its flange (table) at the bottom centre of the parts' bounding
    box (the parts stand on it as drawn; at the origin without parts); a
    tilt-and-turn positioner turned so that its tilt axis runs across the line
    from the table to the robot (its base's +Y toward the robot), so that its
    pillars stand at the table's sides, not between it and the robot (the
    MOTOPOS D500's reach 770 mm along the tilt axis from the table's centre;
    unverified: that robots usually stand so, no maker's cell layout was
    read). A track: its carriage under the
    robot base at the values the document shows (the robot rides on it as
    placed).

    Parameters
    ----------
    kind : str
        One of ``core.mechanisms.KINDS``.
    model : str or None
        Catalog name; None: the generic mechanism.
    parts : sequence of App.DocumentObject
    robot_base : FreeCAD.Placement, optional
        The robot base {R} in {U}; the origin if None.
    length_mm : float, optional
        A track's travel.

    Returns
    -------
    FreeCAD.Placement
        ``T_u_flange @ inv(fk(drawn_at))``: the base that puts the flange there.
    """
    mechanism = catalog.build(kind, model, length_mm=length_mm)
    if kind == mech.TRACK:
        T_u_flange = np.eye(4) if robot_base is None else matrix_from_placement(robot_base)
    else:
        T_u_flange = np.eye(4)
        centre = _parts_bottom_centre(parts)
        if centre is not None:
            T_u_flange[:3, 3] = centre
        if kind == mech.TILT_TURN:
            robot = np.zeros(3) if robot_base is None else np.array(tuple(robot_base.Base))
            T_u_flange[:3, :3] = _facing_robot(robot - T_u_flange[:3, 3])
    T_base_flange = mechanism.fk(mechanism.drawn_at)
    return placement_from_matrix(T_u_flange @ tf.invert_transform(T_base_flange))


def _facing_robot(to_robot):
    """Rotation (3, 3) about Z turning +Y along the horizontal part of `to_robot` (3,)
    (the identity when the robot stands right above or below)."""
    dx, dy = float(to_robot[0]), float(to_robot[1])
    if np.hypot(dx, dy) < 1e-6:
        return np.eye(3)
    angle = np.arctan2(dy, dx) - np.pi / 2.0
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def placement_code(x, y, z, rz_deg):
    """Source of a placement at (x, y, z) mm turned `rz_deg` about Z, as a journal keeps it."""
    return command_base.Code(
        "FreeCAD.Placement(FreeCAD.Vector(%r, %r, %r), FreeCAD.Rotation(FreeCAD.Vector(0, 0, 1), %r))"
        % (float(x), float(y), float(z), float(rz_deg)))


def journal_line(cell, kind, placement, model=None, parts=(), name=None, length_mm=None):
    """The one API call that adds the mechanism: ``api.add_positioner`` or ``api.add_track``.

    Parameters
    ----------
    cell : App.DocumentObject or Code
        The cell (or the journal's variable holding it).
    kind : str
        ``"turntable"``, ``"tilt_turn"`` or ``"track"``.
    placement : FreeCAD.Placement or Code
        Its base in {U}.
    model : str or None
    parts : sequence of App.DocumentObject
        What a positioner carries (ignored for a track).
    name : str, optional
    length_mm : float, optional
        A track's travel (DEFAULT_TRACK_MM if None).

    Returns
    -------
    str
        ``"positioner = api.add_positioner(...)"`` or ``"track = api.add_track(...)"``.
    """
    if kind == mech.TRACK:
        length = DEFAULT_TRACK_MM if length_mm is None else float(length_mm)
        return "track = " + command_base.call("api.add_track", cell, length, placement=placement,
                                              model=model, name=name or DEFAULT_NAMES[TRACK])
    return "positioner = " + command_base.call(
        "api.add_positioner", cell, kind=kind, placement=placement, parts=list(parts),
        model=model, name=name or DEFAULT_NAMES[POSITIONER])


def model_names(kind):
    """[GENERIC] and the catalog's names of `kind`."""
    return [GENERIC] + list(catalog.names(kind))


def _spin(suffix, limit, decimals):
    box = QtGui.QDoubleSpinBox()
    box.setRange(-limit, limit)
    box.setDecimals(decimals)
    box.setSuffix(suffix)
    box.setMinimumWidth(MIN_SPIN_WIDTH_PX)     # its hint fits "-1000000.000 mm": too wide
    return box


def base_boxes(grid, decimals=1):
    """X, Y, Z (mm, `decimals`) and Rz (deg) spin boxes of a base placement, two per row
    in the first two rows of `grid`, each after its label.

    Returns
    -------
    tuple of 4 QtGui.QDoubleSpinBox
        x, y, z, rotation about Z.
    """
    x, y, z = (_spin(" mm", POSITION_RANGE_MM, decimals) for _ in range(3))
    rotation = _spin(" \u00b0", 360.0, 2)
    rotation.setToolTip(translate(CONTEXT, "Rotation of the base about Z"))
    for k, (label, box) in enumerate((("X", x), ("Y", y), ("Z", z), ("Rz", rotation))):
        text = QtGui.QLabel(label)
        text.setToolTip(box.toolTip())
        grid.addWidget(text, k // 2, 2 * (k % 2))
        grid.addWidget(box, k // 2, 2 * (k % 2) + 1)
    return x, y, z, rotation


# --- the panel ---------------------------------------------------------------------------------

class MechanismPanel(TaskPanel):
    """Task panel: add a positioner or a track to `cell`.

    Parameters
    ----------
    cell : App.DocumentObject
    what : {"positioner", "track"}
    parts : sequence of App.DocumentObject
        What a positioner carries, to start with (the selection).

    Attributes
    ----------
    parts : list of App.DocumentObject
        The objects shown in the parts list (a positioner's).
    preview : MechanismPreview or None
        The mechanism drawn at the base typed, while the panel is open.
    """

    def __init__(self, cell, what, parts=()):
        self.cell, self.doc, self.what = cell, cell.Document, what
        self.parts = list(parts)
        self.preview = None
        self._base_is_default = True
        self.form = QtGui.QWidget()
        self.form.setWindowTitle(translate(CONTEXT, "Add positioner" if what == POSITIONER
                                           else "Add track"))
        layout = QtGui.QVBoxLayout(self.form)
        self._mechanism_rows(layout)
        self._base_rows(layout)
        if what == POSITIONER:
            self._parts_rows(layout)
        self.message = QtGui.QLabel()
        self.message.setWordWrap(True)
        layout.addWidget(self.message)
        layout.addStretch(1)
        self.kind_changed()

    # -- building the form --
    def _mechanism_rows(self, layout):
        form = QtGui.QFormLayout()
        form.setRowWrapPolicy(QtGui.QFormLayout.WrapLongRows)
        self.kind_combo = QtGui.QComboBox()
        for kind, label in PANELS[self.what]:
            self.kind_combo.addItem(translate(CONTEXT, label), kind)
        self.kind_combo.currentIndexChanged.connect(lambda _i: self.kind_changed())
        form.addRow(translate(CONTEXT, "Kind"), self.kind_combo)
        self.model_combo = QtGui.QComboBox()
        self.model_combo.setToolTip(translate(
            CONTEXT, "A real mechanism from the catalog (cadrobot mechanisms), or the generic one"))
        self.model_combo.currentIndexChanged.connect(lambda _i: self.refresh_default_base())
        form.addRow(translate(CONTEXT, "Model"), self.model_combo)
        self.length = _spin(" mm", POSITION_RANGE_MM, 1)
        self.length.setRange(1.0, POSITION_RANGE_MM)
        self.length.setValue(DEFAULT_TRACK_MM)
        self.length.setToolTip(translate(CONTEXT, "How far the carriage travels, mm"))
        self.length.valueChanged.connect(lambda _v: self.refresh_default_base())
        if self.what == TRACK:
            form.addRow(translate(CONTEXT, "Travel"), self.length)
        self.name = QtGui.QLineEdit(DEFAULT_NAMES[self.what])
        form.addRow(translate(CONTEXT, "Name"), self.name)
        layout.addLayout(form)

    def _base_rows(self, layout):
        box = QtGui.QGroupBox(translate(CONTEXT, "Base in the drawing"))
        grid = QtGui.QGridLayout(box)
        self.x, self.y, self.z, self.rotation = base_boxes(grid)
        for spin in (self.x, self.y, self.z, self.rotation):
            spin.valueChanged.connect(self._base_edited)
        layout.addWidget(box)

    def _parts_rows(self, layout):
        box = QtGui.QGroupBox(translate(CONTEXT, "Parts on its table"))
        inner = QtGui.QVBoxLayout(box)
        self.parts_list = QtGui.QListWidget()
        self.parts_list.setMaximumHeight(90)
        self.parts_list.setToolTip(translate(
            CONTEXT, "The solids, calibration frames and tool markers that ride on the "
                     "positioner's table"))
        inner.addWidget(self.parts_list)
        self.use_selection = QtGui.QPushButton(translate(CONTEXT, "Use selection"))
        self.use_selection.setToolTip(translate(
            CONTEXT, "The objects selected in the tree or the 3D view become the parts"))
        self.use_selection.clicked.connect(self.take_selection)
        inner.addWidget(self.use_selection)
        layout.addWidget(box)
        self._show_parts()

    # -- values --
    def kind(self):
        return self.kind_combo.itemData(self.kind_combo.currentIndex())

    def model(self):
        """The catalog name chosen, None for the generic mechanism."""
        text = self.model_combo.currentText()
        return None if text in ("", GENERIC) else text

    def set_model(self, name):
        """Choose catalog model `name` (None: generic); False when the kind has no such model."""
        index = self.model_combo.findText(name or GENERIC)
        if index < 0:
            return False
        self.model_combo.setCurrentIndex(index)
        return True

    def set_kind(self, kind):
        self.kind_combo.setCurrentIndex(self.kind_combo.findData(kind))

    def kind_changed(self):
        self.model_combo.blockSignals(True)
        self.model_combo.clear()
        self.model_combo.addItems(model_names(self.kind()))
        self.model_combo.blockSignals(False)
        self.refresh_default_base()

    def _base_edited(self, *_args):
        self._base_is_default = False
        self.update_preview()

    def refresh_default_base(self):
        """Fill the base with :func:`default_base`, unless the user typed one; redraw the
        preview (the kind, the model or the travel may have changed)."""
        if self._base_is_default:
            self._fill_default_base()
        self.update_preview()

    def _fill_default_base(self):
        try:
            placement = default_base(self.kind(), self.model(), self.parts,
                                     self.cell.Placement, self.length.value())
        except CadRobotError as err:
            self.show_message(str(err), error=True)
            return
        values = tuple(placement.Base) + (placement.Rotation.toEuler()[0],)
        for spin, value in zip((self.x, self.y, self.z, self.rotation), values):
            spin.blockSignals(True)
            spin.setValue(value)
            spin.blockSignals(False)
        self.show_message(translate(CONTEXT, "The base puts the table under the parts.")
                          if self.what == POSITIONER else
                          translate(CONTEXT, "The base puts the carriage under the robot."))

    def base_placement(self):
        """FreeCAD.Placement: the base typed (X, Y, Z, turned Rz about Z)."""
        return FreeCAD.Placement(FreeCAD.Vector(self.x.value(), self.y.value(), self.z.value()),
                                 FreeCAD.Rotation(FreeCAD.Vector(0, 0, 1), self.rotation.value()))

    def update_preview(self):
        """Draw the chosen mechanism at the base typed (new solids only for another kind,
        model or travel; none while the choice is refused, e.g. a travel too long)."""
        key = (self.kind(), self.model(), self.length.value() if self.what == TRACK else None)
        if self.preview is not None and self.preview.key != key:
            self.remove_preview()
        if self.preview is None:
            gui_doc = FreeCADGui.getDocument(self.doc.Name)
            view = gui_doc.activeView() if gui_doc is not None else None
            if not hasattr(view, "getSceneGraph"):      # not in a spreadsheet or drawing view
                return
            try:
                self.preview = MechanismPreview(view, *key)
            except CadRobotError as err:
                self.show_message(str(err), error=True)
                return
        self.preview.set_base(matrix_from_placement(self.base_placement()))

    def remove_preview(self):
        """Take the preview out of the view."""
        if self.preview is not None:
            self.preview.remove()
            self.preview = None

    def take_selection(self):
        """The selected objects become the parts (a positioner's)."""
        self.parts = riding_objects(selection.selected(self.doc))
        self._show_parts()
        self.refresh_default_base()
        return self.parts

    def _show_parts(self):
        self.parts_list.clear()
        self.parts_list.addItems([p.Label for p in self.parts])

    def placement_code(self):
        return placement_code(self.x.value(), self.y.value(), self.z.value(),
                              self.rotation.value())

    def journal_line(self):
        return journal_line(self.cell, self.kind(), self.placement_code(), self.model(),
                            self.parts, self.name.text().strip() or None,
                            self.length.value() if self.what == TRACK else None)

    def show_message(self, text, error=False):
        self.message.setStyleSheet("color: red;" if error else "")
        self.message.setText(text)

    # -- task dialog --
    def ok(self):
        """Journal the API call (one undo step). True when done."""
        result = "track" if self.what == TRACK else "positioner"
        title = self.form.windowTitle()
        try:
            added, = command_base.journal(self.doc, title, [self.journal_line()], results=[result])
        except CadRobotError as err:
            command_base.report_error(self.doc, "", err, show=False)
            self.show_message(str(err), error=True)
            return False
        command_base.select_in_tree(self.doc, getattr(added, "Name", None))
        return True

    def close_panel(self):
        close_panel()


def open_panel(cell, what=POSITIONER):
    """Open the panel adding a positioner (the selected objects as its parts) or a track.

    Raises
    ------
    CadRobotError
        When another task panel is open.
    """
    parts = riding_objects(selection.selected(cell.Document)) if what == POSITIONER else ()
    return _slot.open(lambda: MechanismPanel(cell, what, parts), translate(
        CONTEXT, "Another task panel is open; close it first."))


def active_panel():
    """The open MechanismPanel, or None."""
    return _slot.panel


def close_panel():
    """Close the panel, if open."""
    _slot.close()

