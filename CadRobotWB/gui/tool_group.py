"""The "Tool" group of the New cell panel, and the Edit tool panel that shows it for a cell.

The group offers the tool library (``robots/catalog/tools.py``) and "Solid from the
document…" (the selected solid, picked when chosen or with "Use selected
solid"), the TCP {T} in the flange frame {F} (x, y, z in mm; rx, ry, rz in
degrees, turned about X, then Y, then Z of {F}), the mass and the centre of
gravity in {F}, and a short description of the chosen tool.  A library
choice fills the numbers from the library; numbers changed after that are
passed to ``api.set_tool`` as overrides.  For a document solid the flange is
the solid's own origin and the TCP is given in its own coordinates ("TCP at
selected point" takes a vertex of it).

``open_edit_panel(cell)`` opens the group for an existing cell; OK journals
``api.set_tool`` as one undo step.
"""

import FreeCAD
from PySide import QtCore, QtGui

from ..commands import base as command_base
from ..commands import selection
from ..errors import CadRobotError, InputError
from ..objects import base as objects_base
from ..robots.catalog import tools
from .task_panels import PanelSlot, TaskPanel

translate = FreeCAD.Qt.translate
CONTEXT = "CadRobot_EditTool"

#: The combo entry for a tool body taken from the document.
SOLID_ITEM = "Solid from the document\u2026"

#: Narrowest a number box gets, pixels (three in a row in a 225 px panel).
MIN_SPIN_WIDTH_PX = 46

#: Decimals of the boxes: mm and degrees, kg.
DECIMALS = 3

_slot = PanelSlot()


def _spin(suffix, low, high, tip=""):
    box = QtGui.QDoubleSpinBox()
    box.setRange(low, high)
    box.setDecimals(DECIMALS)
    box.setSuffix(suffix)
    box.setMinimumWidth(MIN_SPIN_WIDTH_PX)
    box.setSizePolicy(QtGui.QSizePolicy.Ignored, QtGui.QSizePolicy.Fixed)
    box.setButtonSymbols(QtGui.QAbstractSpinBox.NoButtons)    # three numbers across ~250 px
    box.setToolTip(tip)
    return box


def _row(boxes):
    widget = QtGui.QWidget()
    layout = QtGui.QHBoxLayout(widget)
    layout.setContentsMargins(0, 0, 0, 0)
    layout.setSpacing(2)
    for box in boxes:
        layout.addWidget(box, 1)
    return widget


def solid_of(items):
    """The first selected object with a solid shape (not a CadRobot object), or None."""
    for item in items:
        shape = getattr(item.obj, "Shape", None)
        if (shape is not None and not shape.isNull() and shape.Solids
                and not objects_base.type_of(item.obj)):
            return item.obj
    return None


class ToolGroup:
    """The "Tool" group box (:attr:`box`) and what it says.

    Parameters
    ----------
    doc : App.Document
    cell : Cell, optional
        Fill from this cell's tool (else the straight torch).
    details : bool
        Show the TCP, mass and CoG boxes at first (else folded away).
    framed : bool
        :attr:`box` is a group box titled "Tool" (else a plain widget whose
        first row is labelled "Tool", to sit in another group).
    """

    def __init__(self, doc, cell=None, details=False, framed=True):
        self.doc = doc
        self.body = None
        self._filled = None
        self.box = QtGui.QGroupBox(translate(CONTEXT, "Tool")) if framed else QtGui.QWidget()
        form = QtGui.QFormLayout(self.box)
        if not framed:
            form.setContentsMargins(0, 0, 0, 0)
        form.setFieldGrowthPolicy(QtGui.QFormLayout.AllNonFixedFieldsGrow)
        self.choice = QtGui.QComboBox()
        self.choice.addItems(tools.names() + [translate(CONTEXT, SOLID_ITEM)])
        self.choice.setSizePolicy(QtGui.QSizePolicy.Ignored, QtGui.QSizePolicy.Fixed)
        self.choice.setToolTip(translate(CONTEXT, "A tool of CadRobot's library, or a solid of "
                                         "the document drawn with the flange at its origin"))
        # The numbers fold away (the New cell panel must fit a 1366x768 screen).
        self.details_button = QtGui.QToolButton()
        self.details_button.setText(translate(CONTEXT, "TCP…"))
        self.details_button.setToolTip(translate(CONTEXT, "Show the TCP, mass and centre of "
                                                 "gravity"))
        self.details_button.setToolButtonStyle(QtCore.Qt.ToolButtonTextBesideIcon)
        self.details_button.setCheckable(True)
        self.details_button.setAutoRaise(True)
        self.details_button.toggled.connect(self.show_details)
        choice_row = QtGui.QHBoxLayout()
        choice_row.setContentsMargins(0, 0, 0, 0)
        choice_row.addWidget(self.choice, 1)
        choice_row.addWidget(self.details_button)
        if framed:
            form.addRow(choice_row)
        else:
            form.addRow(translate(CONTEXT, "Tool"), choice_row)
        self.description = QtGui.QLabel()
        self.description.setWordWrap(True)
        form.addRow(self.description)

        self.body_row = QtGui.QWidget()
        body_layout = QtGui.QHBoxLayout(self.body_row)
        body_layout.setContentsMargins(0, 0, 0, 0)
        self.use_solid = QtGui.QPushButton(translate(CONTEXT, "Use selected solid"))
        self.use_solid.setToolTip(translate(CONTEXT, "Take the solid selected in the 3D view or "
                                            "the tree as the tool body"))
        self.use_solid.clicked.connect(lambda: self.take_selected_solid())
        self.use_point = QtGui.QPushButton(translate(CONTEXT, "TCP at selected point"))
        self.use_point.setToolTip(translate(CONTEXT, "Put the TCP on the selected vertex of the "
                                            "tool body (in the body's own coordinates)"))
        self.use_point.clicked.connect(lambda: self.take_selected_point())
        for button in (self.use_solid, self.use_point):
            button.setSizePolicy(QtGui.QSizePolicy.Ignored, QtGui.QSizePolicy.Fixed)
            body_layout.addWidget(button, 1)
        form.addRow(self.body_row)

        self.details = QtGui.QWidget()
        outer_form, form = form, QtGui.QFormLayout(self.details)
        form.setContentsMargins(0, 0, 0, 0)
        form.setFieldGrowthPolicy(QtGui.QFormLayout.AllNonFixedFieldsGrow)
        outer_form.addRow(self.details)

        tip = translate(CONTEXT, "TCP {T} in the flange frame {F}: position, mm")
        self.tcp_xyz = [_spin("", -5000.0, 5000.0, tip) for _ in range(3)]
        form.addRow(translate(CONTEXT, "TCP x y z"), _row(self.tcp_xyz))
        tip = translate(CONTEXT, "TCP orientation: turned about X, then Y, then Z of the flange, "
                        "degrees (+Z of the TCP points out of the tool, into the work)")
        self.tcp_rxyz = [_spin("\u00b0", -360.0, 360.0, tip) for _ in range(3)]
        form.addRow(translate(CONTEXT, "rx ry rz"), _row(self.tcp_rxyz))
        self.mass = _spin(" kg", 0.0, 1000.0, translate(CONTEXT, "Tool mass, kg"))
        form.addRow(translate(CONTEXT, "Mass"), self.mass)
        tip = translate(CONTEXT, "Centre of gravity in the flange frame {F}, mm")
        self.cog = [_spin("", -5000.0, 5000.0, tip) for _ in range(3)]
        form.addRow(translate(CONTEXT, "CoG x y z"), _row(self.cog))

        self.show_details(details)
        self.choice.currentIndexChanged.connect(self._choice_changed)
        if cell is not None and getattr(cell, "ToolType", tools.CUSTOM) == tools.CUSTOM:
            self.choice.blockSignals(True)
            self.choice.setCurrentIndex(len(tools.names()))
            self.choice.blockSignals(False)
            self.body = cell.ToolBody
            self._show_custom()
            self.set_numbers(cell.ToolTCP, cell.ToolMass, tuple(cell.ToolCenterOfGravity))
        elif cell is not None:
            self.set_tool(cell.ToolType)
            self.set_numbers(cell.ToolTCP, cell.ToolMass, tuple(cell.ToolCenterOfGravity))
        else:
            self.set_tool(tools.DEFAULT)

    def show_details(self, shown=True):
        """Unfold (or fold) the TCP, mass and CoG boxes."""
        shown = bool(shown)
        if self.details_button.isChecked() != shown:
            self.details_button.setChecked(shown)      # calls back here
            return
        self.details.setVisible(shown)
        self.details_button.setArrowType(QtCore.Qt.DownArrow if shown else QtCore.Qt.RightArrow)

    # -- what is chosen --
    def tool_name(self):
        """str: the library name chosen, or :data:`tools.CUSTOM` for a document solid."""
        index = self.choice.currentIndex()
        return tools.names()[index] if index < len(tools.names()) else tools.CUSTOM

    def set_tool(self, name):
        """Choose library tool `name` (its numbers fill the boxes) or :data:`tools.CUSTOM`."""
        index = tools.tool_types().index(name) if name in tools.tool_types() else -1
        if index < 0:
            raise InputError(translate(CONTEXT, "Unknown tool '{0}'.").format(name))
        if self.choice.currentIndex() == index:
            self._choice_changed(index)
        else:
            self.choice.setCurrentIndex(index)

    def _choice_changed(self, _index=None):
        name = self.tool_name()
        if name == tools.CUSTOM:
            if self.body is None:
                self.take_selected_solid(quiet=True)
            self._show_custom()
            return
        tool = tools.get(name)
        self.body_row.setVisible(False)
        self.description.setText(tool.description)
        from ..objects.convert import placement_from_matrix
        self.set_numbers(placement_from_matrix(tool.T_f_t), tool.mass_kg, tuple(tool.cog_mm))
        self._filled = self.numbers()

    def _show_custom(self):
        self.body_row.setVisible(True)
        self._filled = None
        if self.body is None:
            self.description.setText(translate(
                CONTEXT, "Select a solid drawn with the robot's flange at its origin (tool axis "
                         "+Z), then press 'Use selected solid'; put the TCP on its tip."))
        else:
            self.description.setText(translate(
                CONTEXT, "Tool body: {0}. The flange is its own origin; the TCP is given in its "
                         "own coordinates.").format(self.body.Label))

    def take_selected_solid(self, quiet=False):
        """Take the selected solid as the tool body. True when there was one."""
        solid = solid_of(selection.selected(self.doc))
        if solid is None:
            if not quiet:
                self.description.setText(translate(CONTEXT, "Select a solid in the 3D view or "
                                                   "the tree first."))
            return False
        self.body = solid
        if self.tool_name() != tools.CUSTOM:
            self.choice.setCurrentIndex(len(tools.names()))
        self._show_custom()
        return True

    def take_selected_point(self):
        """Put the TCP position on the selected vertex, in the tool body's own coordinates."""
        point = selection.picked_point(selection.selected(self.doc))
        if point is None or self.body is None:
            self.description.setText(translate(CONTEXT, "Choose the tool body, then select a "
                                               "vertex of it."))
            return False
        local = objects_base.global_placement(self.body).inverse().multVec(point)
        for box, value in zip(self.tcp_xyz, (local.x, local.y, local.z)):
            box.setValue(value)
        return True

    # -- the numbers --
    def set_numbers(self, tcp, mass_kg, cog_mm):
        """Show TCP placement `tcp`, mass and CoG (3 mm)."""
        yaw, pitch, roll = tcp.Rotation.toEuler()
        for box, value in zip(self.tcp_xyz + self.tcp_rxyz + [self.mass] + self.cog,
                              (tcp.Base.x, tcp.Base.y, tcp.Base.z, roll, pitch, yaw, mass_kg)
                              + tuple(cog_mm)):
            box.setValue(float(value))

    def numbers(self):
        """tuple of 10 float: TCP x y z, rx ry rz, mass, CoG x y z as shown."""
        return tuple(box.value() for box in self.tcp_xyz + self.tcp_rxyz + [self.mass] + self.cog)

    def tcp_placement(self):
        """FreeCAD.Placement: the TCP in {F} as shown (rotation about X, then Y, then Z)."""
        x, y, z, rx, ry, rz = self.numbers()[:6]
        return FreeCAD.Placement(FreeCAD.Vector(x, y, z), FreeCAD.Rotation(rz, ry, rx))

    def overridden(self):
        """bool: numbers differ from the library tool's (False for a document solid)."""
        return self._filled is not None and self.numbers() != self._filled

    def set_tool_arguments(self):
        """Keyword arguments of ``api.set_tool`` for what is shown, or None when the
        library tool is taken as it is.

        Raises
        ------
        InputError
            "Solid from the document…" without a solid.
        """
        numbers = self.numbers()
        extra = {"tcp": self.tcp_placement(), "mass_kg": numbers[6], "cog_mm": numbers[7:]}
        if self.tool_name() == tools.CUSTOM:
            if self.body is None:
                raise InputError(translate(CONTEXT, "Choose the tool body: select a solid and "
                                           "press 'Use selected solid'."))
            return dict(body=self.body, **extra)
        if not self.overridden():
            return None
        return dict(tool=self.tool_name(), **extra)

    def journal_line(self, cell_code):
        """``api.set_tool(...)`` for the cell the code `cell_code` names, or None."""
        arguments = self.set_tool_arguments()
        if arguments is None:
            return None
        return command_base.call("api.set_tool", command_base.Code(cell_code), **arguments)


class EditToolPanel(TaskPanel):
    """Task panel: the tool of an existing cell (OK journals ``api.set_tool``)."""

    def __init__(self, cell):
        self.cell = cell
        self.form = QtGui.QWidget()
        self.form.setWindowTitle(translate(CONTEXT, "Tool of {0}").format(cell.Label))
        layout = QtGui.QVBoxLayout(self.form)
        layout.setContentsMargins(0, 0, 0, 0)
        self.group = ToolGroup(cell.Document, cell, details=True)
        layout.addWidget(self.group.box)
        self.message = QtGui.QLabel()
        self.message.setWordWrap(True)
        layout.addWidget(self.message)
        layout.addStretch(1)

    def journal_lines(self):
        """The journaled lines OK runs."""
        cell_code = command_base.literal(self.cell)
        line = self.group.journal_line(cell_code)
        if line is None:        # the library tool as it is
            line = command_base.call("api.set_tool", command_base.Code(cell_code),
                                     tool=self.group.tool_name())
        return [line]

    def apply(self):
        """Set the cell's tool (one undo step). True when done (else the error is shown)."""
        try:
            command_base.journal(self.cell.Document, translate(CONTEXT, "Edit tool"),
                                 self.journal_lines())
        except CadRobotError as err:
            command_base.report_error(self.cell.Document, "", err, show=False)
            self.message.setStyleSheet("color: red;")
            self.message.setText(str(err))
            return False
        return True

    def ok(self):
        return self.apply()

    def close_panel(self):
        close_panel()


def open_edit_panel(cell):
    """Open the Edit tool panel for `cell` (InputError when another task panel is open)."""
    return _slot.open(lambda: EditToolPanel(cell), translate(
        CONTEXT, "Another task panel is open; close it first."))


def active_panel():
    """The open EditToolPanel, or None."""
    return _slot.panel


def close_panel():
    """Close the Edit tool panel, if open."""
    _slot.close()
