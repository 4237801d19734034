"""The "CadRobot" page of Edit -> Preferences.

FreeCAD (0.20 and 1.x) takes a Python class for a preferences page: it
makes one object of it, shows its ``form`` widget, calls ``loadSettings()``
when the dialog opens and ``saveSettings()`` on OK / Apply.  A class (not
a ``.ui`` file of ``Gui::Pref*`` widgets) because the robot and
post-processor lists are read from the catalog and the post folders.

Every setting is a parameter of :data:`~CadRobotWB.preferences.PATH`,
named as in :data:`~CadRobotWB.preferences.DEFAULTS`, read and written
only through :mod:`CadRobotWB.preferences`.

Registered at GUI start-up by ``InitGui.py`` (:func:`register`), so the
page is there before the workbench is first activated.  Importing this
module stays cheap: the catalog and post lists are read when the page opens.
"""

import FreeCAD
from PySide import QtGui

from .. import preferences

translate = FreeCAD.Qt.translate
QT_TRANSLATE_NOOP = FreeCAD.Qt.QT_TRANSLATE_NOOP
CONTEXT = "CadRobot_Preferences"
#: The group (page title) in the preferences dialog; its icon is ``preferences-cadrobot.svg``.
GROUP = "CadRobot"

#: Numeric settings: (name, label, unit suffix, minimum, maximum, decimals, text shown at 0, tip).
NUMBERS = (
    ("ApproachDistance", QT_TRANSLATE_NOOP(CONTEXT, "Approach distance"), " mm", 0.0, 10000.0, 1,
     None, QT_TRANSLATE_NOOP(CONTEXT, "How far above the first target the robot arrives (and "
                                      "leaves after the last), along the tool axis, for new paths")),
    ("InterpolationStep", QT_TRANSLATE_NOOP(CONTEXT, "Interpolation step"), " mm", 0.0, 1000.0, 3,
     QT_TRANSLATE_NOOP(CONTEXT, "speed \u00d7 sample time"),
     QT_TRANSLATE_NOOP(CONTEXT, "Distance between the interpolated points in a risk area; 0 = "
                                "the path speed times the cell's sample time")),
    ("RiskThreshold", QT_TRANSLATE_NOOP(CONTEXT, "Risk threshold"), " \u00b0", 0.0, 180.0, 1, None,
     QT_TRANSLATE_NOOP(CONTEXT, "Segments where the tool turns by more than this angle are "
                                "suggested as risk areas")),
)


def _add_item_once(box, text, data):
    """Add `data` to the combo box unless it is there; return its index."""
    index = box.findData(data)
    if index < 0:
        box.addItem(text, data)
        index = box.count() - 1
    return index


class CadRobotPreferencesPage:
    """Edit -> Preferences -> CadRobot.

    Parameters
    ----------
    parent : QtGui.QWidget, optional
        Given by FreeCAD's preferences dialog (it re-parents ``form`` itself).

    Attributes
    ----------
    form : QtGui.QWidget
        The page.
    robot_box, post_box : QtGui.QComboBox
        Names as item data (``""`` in ``post_box`` = the robot's own language).
    output_edit, post_folder_edit : QtGui.QLineEdit
    number_boxes : dict of str to QtGui.QDoubleSpinBox
        One per entry of :data:`NUMBERS`.
    """

    def __init__(self, parent=None):
        self.form = QtGui.QWidget(parent)
        self.form.setObjectName("CadRobotPreferences")
        self.form.setWindowTitle(translate(CONTEXT, "CadRobot"))
        layout = QtGui.QVBoxLayout(self.form)

        program = QtGui.QGroupBox(translate(CONTEXT, "Programs"))
        grid = QtGui.QFormLayout(program)
        self.robot_box = QtGui.QComboBox()
        self.robot_box.setToolTip(translate(CONTEXT, "Robot of new cells"))
        grid.addRow(translate(CONTEXT, "Default robot"), self.robot_box)
        self.post_box = QtGui.QComboBox()
        self.post_box.setToolTip(translate(
            CONTEXT, "Post-processor the Generate panel starts with, for cells that use their "
            "robot's own language"))
        grid.addRow(translate(CONTEXT, "Default post-processor"), self.post_box)
        self.output_edit = self._folder_row(
            grid, translate(CONTEXT, "Output folder"), translate(CONTEXT, "the document's folder"),
            translate(CONTEXT, "Where programs are written; empty = the document's folder"))
        self.post_folder_edit = self._folder_row(
            grid, translate(CONTEXT, "User post folder"),
            translate(CONTEXT, "only FreeCAD's macro folder"),
            translate(CONTEXT, "A folder searched for your own post-processors (<name>_post.py), "
                               "besides FreeCAD's macro folder"))
        self.post_folder_edit.editingFinished.connect(self._post_folder_edited)
        self.robot_folder_edit = self._folder_row(
            grid, translate(CONTEXT, "Imported robots folder"),
            translate(CONTEXT, "CadRobot/robots in FreeCAD's user data"),
            translate(CONTEXT, "Where robots imported from URDF files are kept (a team can share "
                               "one folder); empty = CadRobot/robots in FreeCAD's user data folder"))
        layout.addWidget(program)

        motion = QtGui.QGroupBox(translate(CONTEXT, "Paths"))
        grid = QtGui.QFormLayout(motion)
        self.number_boxes = {}
        for name, label, suffix, low, high, decimals, special, tip in NUMBERS:
            box = QtGui.QDoubleSpinBox()
            box.setRange(low, high)
            box.setDecimals(decimals)
            box.setSuffix(suffix)
            box.setToolTip(translate(CONTEXT, tip))
            if special:
                box.setSpecialValueText(translate(CONTEXT, special))
            grid.addRow(translate(CONTEXT, label), box)
            self.number_boxes[name] = box
        layout.addWidget(motion)
        layout.addStretch(1)

    def _folder_row(self, grid, label, placeholder, tip):
        row = QtGui.QHBoxLayout()
        edit = QtGui.QLineEdit()
        edit.setPlaceholderText(placeholder)
        edit.setToolTip(tip)
        row.addWidget(edit, 1)
        button = QtGui.QPushButton(translate(CONTEXT, "Browse..."))
        button.clicked.connect(lambda: self._browse(edit, label))
        row.addWidget(button)
        grid.addRow(label, row)
        return edit

    def _browse(self, edit, title):
        folder = QtGui.QFileDialog.getExistingDirectory(self.form, title, edit.text())
        if folder:
            edit.setText(folder)
            edit.editingFinished.emit()

    # -- lists --
    def _fill_robots(self, chosen):
        from ..robots.catalog import catalog
        self.robot_box.clear()
        preferences.use_user_robot_folder()
        for name in catalog.names():
            spec = catalog.get(name)
            self.robot_box.addItem("%s (%s %s)" % (name, spec.manufacturer, spec.model), name)
        self.robot_box.setCurrentIndex(_add_item_once(self.robot_box, chosen, chosen))

    def _fill_posts(self, chosen, post_folder):
        from .. import posts
        self.post_box.clear()
        self.post_box.addItem(translate(CONTEXT, "The robot's own language"), "")
        for name in posts.names(extra_dirs=[FreeCAD.getUserMacroDir(True), post_folder]):
            label = name if name in posts.BUILTIN else translate(CONTEXT, "{0} (user post)").format(name)
            self.post_box.addItem(label, name)
        missing = translate(CONTEXT, "{0} (not found)").format(chosen)
        self.post_box.setCurrentIndex(_add_item_once(self.post_box, missing, chosen))

    def _post_folder_edited(self):
        """List the posts of the folder just typed, keeping the choice."""
        self._fill_posts(self.post_box.itemData(self.post_box.currentIndex()) or "",
                         self.post_folder_edit.text().strip())

    # -- FreeCAD's calls --
    def loadSettings(self):
        """Show the stored preferences."""
        self.output_edit.setText(preferences.get("OutputFolder"))
        self.post_folder_edit.setText(preferences.get("PostFolder"))
        self.robot_folder_edit.setText(preferences.get("UserRobotFolder"))
        self._fill_robots(preferences.get("DefaultRobot"))
        self._fill_posts(preferences.get("DefaultPost"), preferences.get("PostFolder"))
        for name, box in self.number_boxes.items():
            box.setValue(preferences.get(name))

    def saveSettings(self):
        """Store what the page shows."""
        preferences.set("DefaultRobot", self.robot_box.itemData(self.robot_box.currentIndex()))
        preferences.set("DefaultPost", self.post_box.itemData(self.post_box.currentIndex()) or "")
        preferences.set("OutputFolder", self.output_edit.text().strip())
        preferences.set("PostFolder", self.post_folder_edit.text().strip())
        preferences.set("UserRobotFolder", self.robot_folder_edit.text().strip())
        for name, box in self.number_boxes.items():
            preferences.set(name, box.value())


def register():
    """Add the page to Edit -> Preferences (FreeCAD keeps the class and makes the page on demand)."""
    import FreeCADGui
    FreeCADGui.addPreferencePage(CadRobotPreferencesPage, GROUP)
