"""The new cell panel: choose a robot from the catalog and place its base.

``open_panel(doc)`` shows the catalog as a sortable table (name, maker,
model, payload, reach) with a filter by maker and a search box, the chosen
robot's description (controller, payload, reach, post-processor or that
CadRobot has none for its maker, the catalog's notes and source), an
"Import URDF…" button (``api.import_robot``, journaled), the cell's name and
the robot base {R} in {U}: X, Y, Z and a rotation about Z, or the selected
vertex / point (it starts at ``api.make_cell``'s default for the chosen robot:
beside the part, facing it, :func:`..workflow.base_site.default_placement`;
the message line says so), and the tool (:class:`.tool_group.ToolGroup`: the tool
library or a document solid, TCP, mass, centre of gravity; the straight
torch by default), and optional external axes: a track under the robot, or a
positioner (turntable or tilt-and-turn) holding the selected objects (every
solid of the document when none is selected), each at its default base
(:func:`.mechanism_panel.default_base`).  While the panel is open the chosen robot stands in the 3D
view at the base typed (:func:`.robot_display.robot_at`; nothing added to
the document), and goes when the panel closes.  OK adds the cell as one
journaled undo step (``api.make_cell``, ``api.set_tool`` for a
document solid or changed tool numbers, and ``api.add_track`` or
``api.add_positioner`` for the external axes chosen).

Scripts and tests drive it with :meth:`NewCellPanel.select_robot`,
:meth:`NewCellPanel.robot_name`, :meth:`NewCellPanel.visible_robots`,
:meth:`NewCellPanel.set_maker_filter`, :meth:`NewCellPanel.set_search` and
:meth:`NewCellPanel.import_file`.
"""

import functools
import html
import os
import sys

import FreeCAD
import FreeCADGui
import numpy as np
from PySide import QtCore, QtGui

from .. import api, preferences
from ..commands import base as command_base
from ..commands import selection
from ..errors import CadRobotError, InputError, NameTakenError, UnknownNameError
from ..objects.convert import matrix_from_placement
from ..robots.catalog import catalog, makers, tools
from ..robots.kinematics import models
from ..workflow import base_site
from . import mechanism_panel, robot_display, tool_group
from .task_panels import PanelSlot, TaskPanel

translate = FreeCAD.Qt.translate
CONTEXT = "CadRobot_NewCell"

_slot = PanelSlot(before_close=lambda panel: panel.remove_preview())

#: Columns of the robot table: the numbers come right after the name, so they show in
#: FreeCAD's narrow task panel (maker and model are in most names; scroll to see them).
COLUMNS = ("Name", "Payload", "Reach", "Maker", "Model")
NAME, PAYLOAD, REACH, MAKER, MODEL = range(len(COLUMNS))

#: Height of the robot table, pixels: about six rows, so the panel fits a 1366x768 screen.
LIST_HEIGHT_PX = 132

#: Narrowest the Name column gets when the table is resized, pixels (longer names are
#: elided in the middle; the column can be dragged wider).
MIN_NAME_WIDTH_PX = 72

#: Lines of text the description shows before it scrolls.
DESCRIPTION_LINES = 4

#: Shown for a payload the maker's designation does not give.
UNKNOWN = "\u2014"

#: The external axes the panel offers besides none: (kind, label).
EXTERNAL_CHOICES = (("track", "Track"),
                    ("tilt_turn", "Tilt-and-turn positioner"),
                    ("turntable", "Turntable"))

#: Qt's role holding a cell's sort key.
SORT_ROLE = QtCore.Qt.UserRole


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


def robot_reach_mm(spec):
    """Reach of catalog robot `spec`, mm: the catalog's when it gives one, else :func:`reach_mm`."""
    return float(spec.reach_mm) if getattr(spec, "reach_mm", None) else reach_mm(spec.name)


def _escape(text):
    return html.escape(text, quote=False)


def _breakable(text):
    """`text` with a line-break chance after each ``/`` (long paths wrap in a narrow panel)."""
    return text.replace("/", "/\u200b")


def no_post_sentence(spec):
    """The plain sentence for a robot whose maker has no post-processor (translated)."""
    try:
        language = makers.convention(spec.manufacturer).language
    except UnknownNameError:
        language = ""
    maker = "%s's %s" % (spec.manufacturer, language.split(" (")[0]) if language else spec.manufacturer
    return translate(CONTEXT, "CadRobot has no post-processor for {0} yet: pick any post in "
                     "the Generate panel or the cell's PostProcessor property.").format(maker)


def robot_description(robot):
    """Rich text describing catalog robot `robot`."""
    spec = catalog.get(robot)
    reach = round(robot_reach_mm(spec), -1)
    if spec.controller and spec.payload_kg is not None and spec.default_post:
        # The hand-written robots: every field known.
        text = translate(CONTEXT, "<b>{0} {1}</b><br>Controller {2}, payload {3:g} kg, "
                         "reach about {4:.0f} mm, programs in {5}.").format(
            _escape(spec.manufacturer), _escape(spec.model), _escape(spec.controller),
            spec.payload_kg, reach, spec.default_post)
    else:
        parts = []
        if spec.controller:
            parts.append(translate(CONTEXT, "Controller {0}").format(_escape(spec.controller)))
        if spec.payload_kg is None:
            parts.append(translate(CONTEXT, "payload not given by the maker's designation"))
        else:
            parts.append(translate(CONTEXT, "payload {0:g} kg").format(spec.payload_kg))
        parts.append(translate(CONTEXT, "reach about {0:.0f} mm").format(reach))
        if spec.default_post:
            parts.append(translate(CONTEXT, "programs in {0}").format(spec.default_post))
        sentence = ", ".join(parts)
        text = "<b>%s %s</b><br>%s." % (_escape(spec.manufacturer), _escape(spec.model),
                                        sentence[:1].upper() + sentence[1:])
    if not spec.default_post:
        text += "<br>" + _escape(no_post_sentence(spec))
    if spec.notes:
        text += "<br><i>%s</i>" % _escape(spec.notes)
    if getattr(spec, "source", ""):
        text += "<br><small>%s</small>" % _escape(_breakable(
            translate(CONTEXT, "Source: {0}").format(spec.source)))
    return text


class _RobotRow(QtGui.QTreeWidgetItem):
    """A row of the robot table, sorted by each cell's :data:`SORT_ROLE` key."""

    def __lt__(self, other):
        tree = self.treeWidget()
        column = tree.sortColumn() if tree is not None else NAME
        a, b = self.data(column, SORT_ROLE), other.data(column, SORT_ROLE)
        if a is None or b is None or type(a) is not type(b):
            return self.text(column).lower() < other.text(column).lower()
        return a < b


def _row(spec):
    """The table row of `spec`."""
    payload = spec.payload_kg
    reach = robot_reach_mm(spec)
    texts = {NAME: spec.name, MAKER: spec.manufacturer, MODEL: spec.model,
             PAYLOAD: UNKNOWN if payload is None else "%g" % payload, REACH: "%.0f" % reach}
    row = _RobotRow([texts[column] for column in range(len(COLUMNS))])
    for column, key in ((NAME, spec.name.lower()), (MAKER, spec.manufacturer.lower()),
                        (MODEL, spec.model.lower()),
                        (PAYLOAD, -1.0 if payload is None else float(payload)),
                        (REACH, float(reach))):
        row.setData(column, SORT_ROLE, key)
    for column in (PAYLOAD, REACH):
        # setData, not setTextAlignment: PySide6 deprecates its int overload, PySide2 has no other.
        row.setData(column, QtCore.Qt.TextAlignmentRole,
                    int(QtCore.Qt.AlignRight | QtCore.Qt.AlignVCenter))
    if payload is None:
        row.setToolTip(PAYLOAD, translate(CONTEXT, "Payload not given by the maker's designation"))
    row.setToolTip(NAME, spec.name if spec.default_post else
                   "%s: %s" % (spec.name, no_post_sentence(spec)))
    return row


class _RobotTable(QtGui.QTreeWidget):
    """The robot table: whenever it is resized, the Name column takes the room Payload and
    Reach leave (no more than its names need), so the numbers stay in view; Maker and
    Model are shown only when every column fits (the maker filter and the description
    below the table say them in a narrow panel)."""

    def resizeEvent(self, event):
        super().resizeEvent(event)
        self.fit_name_column()

    def fit_name_column(self):
        """Size the Name column to the viewport's room left of the other shown columns."""
        width_px = self.viewport().width()
        all_px = sum(max(self.sizeHintForColumn(c), self.header().sectionSizeHint(c))
                     for c in range(len(COLUMNS)))
        for column in (MAKER, MODEL):
            self.setColumnHidden(column, width_px < all_px)
        room_px = (width_px - self.columnWidth(PAYLOAD) - self.columnWidth(REACH)
                   - sum(self.columnWidth(c) for c in (MAKER, MODEL) if not self.isColumnHidden(c)))
        needed_px = max(self.sizeHintForColumn(NAME),
                        self.header().sectionSizeHint(NAME))
        self.setColumnWidth(NAME, max(MIN_NAME_WIDTH_PX, min(needed_px, room_px)))


class NewCellPanel(TaskPanel):
    """Task panel: the robot and where its base stands.

    Attributes
    ----------
    preview : robot_view.RobotView or None
        The chosen robot drawn at the base typed (None without a 3D view).
    robots : QtGui.QTreeWidget
        The robot table (columns :data:`COLUMNS`).
    maker : QtGui.QComboBox
        The maker filter ("All makers" first).
    search : QtGui.QLineEdit
        Case-insensitive substring of a robot's name, maker or model.
    """

    def __init__(self, doc):
        self.doc = doc
        self.preview = None
        self._robot = None
        self._base_is_default = True     # until the user types a base or takes a point
        self.form = QtGui.QWidget()
        self.form.setWindowTitle(translate(CONTEXT, "New robot cell"))
        layout = QtGui.QVBoxLayout(self.form)
        layout.setContentsMargins(0, 0, 0, 0)     # the task box has its own

        robot_box = QtGui.QGroupBox(translate(CONTEXT, "Robot"))
        robot_layout = QtGui.QVBoxLayout(robot_box)
        robot_layout.setContentsMargins(4, 4, 4, 4)      # the table's columns need the room
        filters = QtGui.QHBoxLayout()
        self.maker = QtGui.QComboBox()
        self.maker.setToolTip(translate(CONTEXT, "Show the robots of one maker"))
        self.maker.setMinimumWidth(90)
        filters.addWidget(self.maker)
        self.search = QtGui.QLineEdit()
        self.search.setPlaceholderText(translate(CONTEXT, "Search\u2026"))
        self.search.setToolTip(translate(CONTEXT, "Show the robots whose name, maker or model "
                                         "contains this text (any case)"))
        self.search.setClearButtonEnabled(True)
        self.search.setMinimumWidth(70)
        filters.addWidget(self.search, 1)
        robot_layout.addLayout(filters)

        self.robots = _RobotTable()
        self.robots.setColumnCount(len(COLUMNS))
        headers = {NAME: translate(CONTEXT, "Name"), MAKER: translate(CONTEXT, "Maker"),
                   MODEL: translate(CONTEXT, "Model"), PAYLOAD: translate(CONTEXT, "kg"),
                   REACH: translate(CONTEXT, "Reach")}
        self.robots.setHeaderLabels([headers[column] for column in range(len(COLUMNS))])
        self.robots.headerItem().setToolTip(PAYLOAD, translate(
            CONTEXT, "Rated payload, kg (\u2014: not given by the maker's designation)"))
        self.robots.headerItem().setToolTip(REACH, translate(
            CONTEXT, "How far the arm reaches from axis 1, mm"))
        # Units in the tooltips, numbers bare: name, payload and reach fit FreeCAD's
        # default panel width (about 260 px).
        self.robots.setRootIsDecorated(False)
        self.robots.setUniformRowHeights(True)
        self.robots.setAlternatingRowColors(True)
        self.robots.setAllColumnsShowFocus(True)
        self.robots.setTextElideMode(QtCore.Qt.ElideLeft)   # "...IRB2400": the maker filter says the rest
        self.robots.setSelectionMode(QtGui.QAbstractItemView.SingleSelection)
        self.robots.setFixedHeight(LIST_HEIGHT_PX)
        self.robots.setMinimumWidth(120)
        self.robots.setSortingEnabled(True)
        robot_layout.addWidget(self.robots)

        self.description = QtGui.QLabel()
        self.description.setWordWrap(True)
        self.description.setTextFormat(QtCore.Qt.RichText)
        self.description.setAlignment(QtCore.Qt.AlignTop | QtCore.Qt.AlignLeft)
        self.description_area = QtGui.QScrollArea()
        self.description_area.setWidget(self.description)
        self.description_area.setWidgetResizable(True)
        self.description_area.setFrameShape(QtGui.QFrame.NoFrame)
        self.description_area.setHorizontalScrollBarPolicy(QtCore.Qt.ScrollBarAlwaysOff)
        self.description_area.setFixedHeight(
            self.description.fontMetrics().lineSpacing() * DESCRIPTION_LINES + 4)
        robot_layout.addWidget(self.description_area)

        import_row = QtGui.QHBoxLayout()
        self.import_button = QtGui.QPushButton(translate(CONTEXT, "Import URDF\u2026"))
        self.import_button.setToolTip(translate(
            CONTEXT, "Add a six-axis arm from its URDF (or xacro) file to the catalog; it "
                     "stays there in later sessions"))
        self.import_button.clicked.connect(self._import_clicked)
        import_row.addWidget(self.import_button)
        self.import_button.setMinimumWidth(self.import_button.sizeHint().width())   # never clipped
        # The cell's name shares the row (the panel must fit a 1366x768 screen).
        name_label = QtGui.QLabel(translate(CONTEXT, "Name"))
        name_label.setToolTip(translate(CONTEXT, "Name of the new cell"))
        import_row.addWidget(name_label)
        self.name = QtGui.QLineEdit("Cell")
        self.name.setToolTip(name_label.toolTip())
        self.name.setMinimumWidth(40)
        import_row.addWidget(self.name, 1)
        robot_layout.addLayout(import_row)
        # The robot's tool: the library or a document solid (TCP, mass, CoG folded away).
        self.tool = tool_group.ToolGroup(doc, framed=False)
        robot_layout.addWidget(self.tool.box)
        layout.addWidget(robot_box)

        base_box = QtGui.QGroupBox(translate(CONTEXT, "Robot base {R} in the drawing"))
        base_layout = QtGui.QGridLayout(base_box)
        self.x, self.y, self.z, self.rotation = mechanism_panel.base_boxes(base_layout, decimals=3)
        base_layout.setColumnStretch(1, 1)
        base_layout.setColumnStretch(3, 1)
        self.use_selection = QtGui.QPushButton(translate(CONTEXT, "Selected point"))
        self.use_selection.setToolTip(translate(
            CONTEXT, "Put the base on the selected vertex or point (select it in the 3D view)"))
        self.use_selection.clicked.connect(self.take_selected_point)
        base_layout.addWidget(self.use_selection, 2, 0, 1, 2)
        self._external_axes_box(base_layout, 2)
        layout.addWidget(base_box)

        self.message = QtGui.QLabel()
        self.message.setWordWrap(True)
        layout.addWidget(self.message)

        self.robots.sortByColumn(NAME, QtCore.Qt.AscendingOrder)
        self.fill_robots()
        self.robots.currentItemChanged.connect(self._row_changed)
        self.maker.currentIndexChanged.connect(self.apply_filter)
        self.search.textChanged.connect(self.apply_filter)
        for box in (self.x, self.y, self.z, self.rotation):
            box.valueChanged.connect(self._base_edited)
        default = preferences.get("DefaultRobot")
        names = api.robot_names()
        self.select_robot(default if default in names else names[0])
        self.take_selected_point(quiet=True)

    def _external_axes_box(self, grid, row):
        """The optional track or positioner: a combo beside "Selected point" (the
        panel must fit a 1366x768 screen)."""
        self.external = QtGui.QComboBox()
        self.external.setSizeAdjustPolicy(QtGui.QComboBox.AdjustToMinimumContentsLengthWithIcon)
        self.external.setMinimumContentsLength(2)
        self.external.addItem(translate(CONTEXT, "No external axes"), "")
        for kind, text in EXTERNAL_CHOICES:
            self.external.addItem(translate(CONTEXT, text), kind)
        self.external.setToolTip(translate(
            CONTEXT, "External axes: a linear track under the robot (the carriage under the base "
                     "typed), or a positioner holding the selected objects (every solid when "
                     "none is selected) on its table. Change them later with Add track / Add "
                     "positioner."))
        grid.addWidget(self.external, row, 2, 1, 2)

    def set_external_axes(self, kind):
        """Choose the external axes: "" (none), "track", "turntable" or "tilt_turn"."""
        self.external.setCurrentIndex(self.external.findData(kind))

    def external_axes(self):
        """The kind of external axes chosen, "" for none."""
        return self.external.itemData(self.external.currentIndex())

    def external_axes_line(self):
        """The API call adding the external axes chosen to ``cell``, or None."""
        kind = self.external_axes()
        if not kind:
            return None
        parts = () if kind == "track" else self.positioner_parts()
        placement = mechanism_panel.default_base(kind, parts=parts,
                                                 robot_base=self.base_placement())
        return mechanism_panel.journal_line(command_base.Code("cell"), kind, placement,
                                            parts=parts)

    def positioner_parts(self):
        """The selected objects a positioner carries, or every solid of the document."""
        parts = mechanism_panel.riding_objects(selection.selected(self.doc))
        if parts:
            return parts
        return [o for o in self.doc.Objects if o.isDerivedFrom("Part::Feature")
                and not o.isDerivedFrom("Part::FeaturePython") and o.Shape.Solids
                and getattr(o, "InList", None) == []]

    # -- the robot table --
    def fill_robots(self):
        """(Re)fill the table and the maker filter from the catalog (imported robots too)."""
        names = api.robot_names()
        specs = [catalog.get(name) for name in names]
        self.robots.blockSignals(True)
        self.maker.blockSignals(True)
        try:
            self.robots.clear()
            self.robots.addTopLevelItems([_row(spec) for spec in specs])
            for column in (PAYLOAD, REACH, MAKER, NAME, MODEL):
                self.robots.resizeColumnToContents(column)
            self.robots.fit_name_column()
            chosen = self.maker_filter()
            self.maker.clear()
            self.maker.addItem(translate(CONTEXT, "All makers"), "")
            for maker in sorted({spec.manufacturer for spec in specs}, key=str.lower):
                self.maker.addItem(maker, maker)
            index = self.maker.findData(chosen) if chosen else 0
            self.maker.setCurrentIndex(max(index, 0))
            if self._item(self._robot) is not None:
                self.robots.setCurrentItem(self._item(self._robot))
        finally:
            self.maker.blockSignals(False)
            self.robots.blockSignals(False)
        self.apply_filter()

    def _items(self):
        return [self.robots.topLevelItem(i) for i in range(self.robots.topLevelItemCount())]

    def _item(self, name):
        for item in self._items():
            if item.text(NAME) == name:
                return item
        return None

    def maker_filter(self):
        """str: the maker shown ("" for all makers)."""
        return self.maker.currentData() or "" if self.maker.count() else ""

    def set_maker_filter(self, maker):
        """Show the robots of `maker` only ("" or None: every maker); False for an unknown maker."""
        index = self.maker.findData(maker) if maker else 0
        if index < 0:
            return False
        self.maker.setCurrentIndex(index)
        return True

    def set_search(self, text):
        """Type `text` into the search box (the table filters at once)."""
        self.search.setText(text)

    def makers(self):
        """list of str: the makers the filter offers (after "All makers")."""
        return [self.maker.itemData(i) for i in range(1, self.maker.count())]

    def apply_filter(self, *_args):
        """Hide the rows the maker filter and the search box leave out; when the
        chosen robot's row goes, the first row shown is chosen."""
        maker, needle = self.maker_filter(), self.search.text().strip().lower()
        for item in self._items():
            shown = (not maker or item.text(MAKER) == maker) and (
                not needle or any(needle in item.text(c).lower() for c in (NAME, MAKER, MODEL)))
            item.setHidden(not shown)
        current = self.robots.currentItem()
        if self._robot is not None and (current is None or current.isHidden()):
            visible = self.visible_robots()
            if visible:
                self._set_current(visible[0])

    def visible_robots(self):
        """list of str: names of the robots the table shows, top to bottom."""
        return [item.text(NAME) for item in self._items() if not item.isHidden()]

    def robot_name(self):
        """str: the chosen robot (the one described, previewed and put in the cell)."""
        return self._robot

    def select_robot(self, name):
        """Choose robot `name`; the filters are cleared when they hide it.

        Raises
        ------
        InputError
            When the catalog has no robot `name`.
        """
        item = self._item(name)
        if item is None:
            raise InputError(translate(CONTEXT, "The catalog has no robot '{0}'.").format(name))
        if item.isHidden():
            self.maker.blockSignals(True)
            self.search.blockSignals(True)
            self.maker.setCurrentIndex(0)
            self.search.clear()
            self.maker.blockSignals(False)
            self.search.blockSignals(False)
            self.apply_filter()
        self._set_current(name)

    def _set_current(self, name):
        item = self._item(name)
        self.robots.setCurrentItem(item)
        self.robots.scrollToItem(item)
        if name != self._robot:      # setCurrentItem of the current row sends no signal
            self._robot_changed(name)

    def _row_changed(self, current, _previous=None):
        if current is not None and current.text(NAME) != self._robot:
            self._robot_changed(current.text(NAME))

    def _robot_changed(self, name):
        self._robot = name
        self.description.setText(robot_description(name))
        if self._base_is_default:
            self.use_default_base()
        else:
            self.update_preview()

    # -- importing a URDF --
    def _import_clicked(self):
        path, _filter = QtGui.QFileDialog.getOpenFileName(
            self.form, translate(CONTEXT, "Import a robot from its URDF file"), "",
            translate(CONTEXT, "Robot descriptions (*.urdf *.xacro);;All files (*)"))
        if not path:
            return
        if self.import_file(path) is None:
            suggested = self.suggested_name()
            if suggested:          # the file's robot name is a shipped robot's: ask for another
                name, ok = QtGui.QInputDialog.getText(
                    self.form, translate(CONTEXT, "Import URDF"),
                    translate(CONTEXT, "A robot of that name ships with CadRobot. "
                                       "Import it as:"), QtGui.QLineEdit.Normal, suggested)
                if ok and name.strip():
                    self.import_file(path, name=name.strip())

    def suggested_name(self):
        """The name the last failed import suggests (its name was a shipped robot's), or ""."""
        return self._suggested

    _suggested = ""

    def import_file(self, path, name=None):
        """Import the URDF/xacro file `path` as robot `name` (default: the file's).

        Runs ``api.import_robot`` through ``FreeCADGui.doCommand`` (a recorded
        macro replays it).  On success the table and the maker filter are
        refilled, the new robot is chosen and the message line says what was
        imported; on an error the message line shows it in red and nothing
        changes.

        Returns
        -------
        str or None
            The name the robot was registered under; None on an error.
        """
        self._suggested = ""
        line = "robot = " + command_base.call("api.import_robot", path,
                                              **({"name": name} if name else {}))
        try:
            for command in list(command_base.IMPORT_LINES) + [line]:
                FreeCADGui.doCommand(command)
            registered = vars(sys.modules["__main__"]).get("robot")
        except Exception as exc:  # noqa: BLE001 -- shown in the panel, never raised into Qt
            err = command_base.as_cadrobot_error(exc)
            FreeCAD.Console.PrintError("CadRobot: %s\n" % err)
            if isinstance(err, NameTakenError):
                self._suggested = err.suggested_name
            self.show_message(str(err), error=True)
            return None
        self.fill_robots()
        self.select_robot(registered)
        spec = catalog.get(registered)
        text = translate(CONTEXT, "Imported {0}: {1} {2} from {3}.").format(
            registered, spec.manufacturer, spec.model, os.path.basename(path))
        if spec.notes:
            text += " " + spec.notes
        self.show_message(text)
        FreeCAD.Console.PrintMessage("CadRobot: %s\n" % text)
        return registered

    # -- the base --
    def base_placement(self):
        """FreeCAD.Placement: the robot base {R} in {U} as typed."""
        return FreeCAD.Placement(FreeCAD.Vector(self.x.value(), self.y.value(), self.z.value()),
                                 FreeCAD.Rotation(FreeCAD.Vector(0, 0, 1), self.rotation.value()))

    def base_is_default(self):
        """bool: the base boxes hold the default for the chosen robot (nothing typed or picked)."""
        return self._base_is_default

    def use_default_base(self):
        """Fill the base boxes with where ``api.make_cell`` stands the chosen robot by
        default (beside the part, facing it; the origin in a document without solids),
        and say so on the message line."""
        placement = base_site.default_placement(self.doc, self.robot_name())
        yaw_deg = placement.Rotation.toEuler()[0]
        boxes = (self.x, self.y, self.z, self.rotation)
        for box, value in zip(boxes, tuple(placement.Base) + (yaw_deg,)):
            box.blockSignals(True)
            box.setValue(value)
            box.blockSignals(False)
        self._base_is_default = True
        self.update_preview()
        if placement.isIdentity():
            self.show_message(translate(CONTEXT, "The base is at the origin: the document has "
                                        "no solids yet."))
        else:
            self.show_message(translate(CONTEXT, "The base is beside the part, facing it: the "
                                        "default for this robot's reach. Type another or use "
                                        "a selected point."))

    def _base_edited(self, *_args):
        self._base_is_default = False
        self.update_preview()

    def update_preview(self, *_args):
        """Draw the chosen robot at the base typed (new solids only for another robot)."""
        robot, T_u_r = self.robot_name(), matrix_from_placement(self.base_placement())
        if robot is None:
            return
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
        """Put the base on the selected vertex / point (turned 0 degrees when it replaces
        the default base). True when there was one."""
        point = selection.picked_point(selection.selected(self.doc))
        if point is None:
            if not quiet:
                self.show_message(translate(CONTEXT, "Select a vertex or a point in the "
                                            "3D view first."), error=True)
            return False
        if self._base_is_default:
            self.rotation.setValue(0.0)
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
        """The API call that makes the cell (with the library tool chosen)."""
        name = self.name.text().strip() or "Cell"
        tool = self.tool.tool_name()
        extra = {"tool": tool} if tool not in (tools.DEFAULT, tools.CUSTOM) else {}
        return "cell = " + command_base.call("api.make_cell", self.doc, robot=self.robot_name(),
                                             name=name, placement=self.placement_code(), **extra)

    def journal_lines(self):
        """The API calls that make the cell and give it its tool (``api.set_tool`` when
        the tool is a document solid or its numbers were changed)."""
        tool_line = self.tool.journal_line("cell")
        external_line = self.external_axes_line()
        return [self.journal_line()] + [line for line in (tool_line, external_line) if line]

    def create(self):
        """Add the cell (one undo step). The new cell, or None (error shown)."""
        try:
            if not self.name.text().strip():
                raise InputError(translate(CONTEXT, "Give the cell a name."))
            cell, = command_base.journal(self.doc, translate(CONTEXT, "New robot cell"),
                                         self.journal_lines(), results=["cell"])
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
        CONTEXT, "Another task panel is open; close it first."))


def active_panel():
    """The open NewCellPanel, or None."""
    return _slot.panel


def close_panel():
    """Close the panel, if open."""
    _slot.close()
