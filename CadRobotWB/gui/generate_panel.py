"""The Generate panel: choose a post-processor and an output folder, see the program, write it.

``open_panel(cell)`` shows, for one cell:

- the post-processor (every name of :func:`~CadRobotWB.api.post_names`:
  built-in posts and the user's ``<name>_post.py`` files), its options as
  ``key=value`` text (what ``cadrobot export --option`` takes), "check
  first", and the output folder;
- the program, one read-only tab per file, as
  :func:`~CadRobotWB.api.program_files` makes it (nothing written);
- a Write button (and OK = write and close) that journals one
  ``api.export(...)`` call with ``FreeCADGui.doCommand``, so a recorded
  macro replays it in FreeCADCmd, and lists the files written.

A CadRobotError (a broken document, a check finding, a bad option) is shown
in red in the panel, never as a traceback; the object at fault is selected
in the tree and nothing is written.  The document is never changed.
"""

import argparse
import os
import traceback

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from .. import api, posts, preferences
from ..cli import parse_post_option
from ..errors import CadRobotError, InputError
from ..robots.catalog import catalog
from . import not_checked
from . import progress as gui_progress
from .task_panels import PanelSlot, TaskPanel

translate = FreeCAD.Qt.translate
CONTEXT = "CadRobot_Generate"
#: Name of the variable the journaled export leaves in the console's namespace.
RESULT_VARIABLE = "cadrobot_files"

_slot = PanelSlot(before_close=lambda panel: panel.stop())


def _escaped(text):
    return str(text).replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


# --- what the panel starts with --------------------------------------------------------------

def default_post(cell, available):
    """The post-processor the panel starts with.

    The cell's ``PostProcessor`` when it was chosen for this cell (it is not
    its robot's own language); else the ``DefaultPost`` preference when set
    and available; else the cell's ``PostProcessor`` (its robot's language).

    Parameters
    ----------
    cell : App.DocumentObject
    available : list of str
        Post names offered (``api.post_names()``).

    Returns
    -------
    str
    """
    own = cell.PostProcessor
    try:
        robot_language = catalog.get(cell.Robot).default_post
    except CadRobotError:
        robot_language = own
    preferred = preferences.get("DefaultPost")
    if own == robot_language and preferred and preferred in available:
        return preferred
    return own


def default_output_folder(doc):
    """The ``OutputFolder`` preference, else the document's folder, else the home folder."""
    folder = preferences.get("OutputFolder")
    if folder:
        return folder
    if doc.FileName:
        return os.path.dirname(doc.FileName)
    return os.path.expanduser("~")


def parse_options(text):
    """Post options from ``key=value`` words (spaces, commas or new lines between them).

    Values read as in ``cadrobot export --option``: true/false, integers and
    decimals become bool, int and float, anything else stays a string.

    Returns
    -------
    dict

    Raises
    ------
    InputError
        A word is not ``key=value``.
    """
    options = {}
    for word in text.replace(",", " ").split():
        try:
            key, value = parse_post_option(word)
        except argparse.ArgumentTypeError:
            raise InputError(translate(
                CONTEXT, "Post option '{0}' is not key=value (e.g. path_correction=true).").format(
                    word)) from None
        options[key] = value
    return options


def export_lines(cell, post, output_dir, options, check_first):
    """The Python lines the Write button journals (a recorded macro replays them).

    Returns
    -------
    list of str
        The last line leaves the written paths in :data:`RESULT_VARIABLE`.
    """
    return ["import FreeCAD",
            "from CadRobotWB import api",
            "%s = api.export(FreeCAD.getDocument(%r).getObject(%r), post=%r, output_dir=%r, "
            "options=%r, check_first=%r)" % (RESULT_VARIABLE, cell.Document.Name, cell.Name, post,
                                             output_dir, options, bool(check_first))]


def ask_other_maker(note):
    """Ask before writing another maker's language than the cell's robot's.

    Parameters
    ----------
    note : str
        :func:`api.other_maker_note`: whose controller the program is for.

    Returns
    -------
    bool
        True: write it (the program's header says so too); False: write nothing.
    """
    answer = QtGui.QMessageBox.question(
        FreeCADGui.getMainWindow(), translate(CONTEXT, "Another maker's robot language"),
        note + "\n\n" + translate(CONTEXT, "Write this program anyway?"),
        QtGui.QMessageBox.Yes | QtGui.QMessageBox.No, QtGui.QMessageBox.No)
    return answer == QtGui.QMessageBox.Yes


def post_label(name):
    """How a post is listed: its name, and "(user post)" for one found in a folder."""
    if name in posts.BUILTIN:
        return name
    return translate(CONTEXT, "{0} (user post)").format(name)


# --- the panel -------------------------------------------------------------------------------

class GeneratePanel(TaskPanel):
    """Task panel: the program of one cell, and writing it.

    Parameters
    ----------
    cell : App.DocumentObject
        A CadRobot cell.

    Attributes
    ----------
    form : QtGui.QWidget
        What FreeCAD shows in the task view.
    post_box : QtGui.QComboBox
        Post names as item data.
    options_edit : QtGui.QLineEdit
    check_box : QtGui.QCheckBox
    folder_edit : QtGui.QLineEdit
    message_label : QtGui.QLabel
        What happened last; red for an error.
    tabs : QtGui.QTabWidget
        One read-only :class:`QtGui.QPlainTextEdit` per program file.
    files : list of (str, str)
        The program shown (file name, text); empty after an error.
    written : list of str
        Paths written by the last Write (empty before, or after an error).
    error : CadRobotError or None
        The last error shown.
    """

    ACTION_BUTTONS = ('refresh_button', 'write_button')

    def __init__(self, cell):
        self.cell = cell
        self.files = []
        self.written = []
        self.error = None
        self.closed = False
        self.form = self._build_form()
        names = api.post_names()
        for name in names:
            self.post_box.addItem(post_label(name), name)
        chosen = default_post(cell, names)
        if self.post_box.findData(chosen) < 0:      # e.g. a user post that was removed
            self.post_box.addItem(chosen, chosen)
        self.post_box.setCurrentIndex(self.post_box.findData(chosen))
        self.folder_edit.setText(default_output_folder(cell.Document))
        self.post_box.currentIndexChanged.connect(self._changed)
        self.check_box.toggled.connect(self._changed)
        self.options_edit.editingFinished.connect(self._options_edited)
        self._shown_options = ""
        self.refresh()

    # -- widgets --
    def _build_form(self):
        form = QtGui.QWidget()
        form.setObjectName("CadRobotGeneratePanel")
        form.setWindowTitle(translate(CONTEXT, "Generate program"))
        layout = QtGui.QVBoxLayout(form)
        layout.addWidget(QtGui.QLabel("<b>%s</b>" % _escaped(self.cell.Label)))

        group = QtGui.QGroupBox(translate(CONTEXT, "Program"))
        grid = QtGui.QFormLayout(group)
        grid.setRowWrapPolicy(QtGui.QFormLayout.WrapLongRows)     # fits a narrow task view
        grid.setFieldGrowthPolicy(QtGui.QFormLayout.AllNonFixedFieldsGrow)
        self.post_box = QtGui.QComboBox()
        self.post_box.setSizeAdjustPolicy(QtGui.QComboBox.AdjustToMinimumContentsLengthWithIcon)
        self.post_box.setMinimumContentsLength(10)
        self.post_box.setToolTip(translate(
            CONTEXT, "Post-processor: the robot language written. User posts are the "
            "<name>_post.py files in FreeCAD's macro folder and in the post folder set in the "
            "CadRobot preferences."))
        grid.addRow(translate(CONTEXT, "Post-processor"), self.post_box)
        self.options_edit = QtGui.QLineEdit()
        self.options_edit.setPlaceholderText("key=value ...")
        self.options_edit.setToolTip(translate(
            CONTEXT, "Options of the post-processor, key=value separated by spaces, e.g. "
            "path_correction=true"))
        grid.addRow(translate(CONTEXT, "Options"), self.options_edit)
        self.check_box = QtGui.QCheckBox(translate(CONTEXT, "Check first"))
        self.check_box.setChecked(True)
        self.check_box.setToolTip(translate(
            CONTEXT, "Check reach, joint limits and speeds first, and write nothing when the "
            "robot cannot run the program"))
        grid.addRow("", self.check_box)
        folder_row = QtGui.QHBoxLayout()
        self.folder_edit = QtGui.QLineEdit()
        self.folder_edit.setToolTip(translate(CONTEXT, "Folder the program files are written to"))
        folder_row.addWidget(self.folder_edit, 1)
        self.browse_button = QtGui.QPushButton(translate(CONTEXT, "Browse..."))
        self.browse_button.clicked.connect(self.browse)
        folder_row.addWidget(self.browse_button)
        grid.addRow(translate(CONTEXT, "Output folder"), folder_row)
        # The program text shares a splitter with the settings and buttons: drag it to read
        # more program; the buttons stay in view above the text (a 768 px screen).
        top = QtGui.QWidget()
        top_layout = QtGui.QVBoxLayout(top)
        top_layout.setContentsMargins(0, 0, 0, 0)
        top_layout.addWidget(group)
        layout = top_layout

        self.write_button = QtGui.QPushButton(translate(CONTEXT, "Write"))
        self.write_button.setToolTip(translate(
            CONTEXT, "Write the program files into the output folder (all or nothing)"))
        self.write_button.clicked.connect(self.write)
        self.refresh_button = QtGui.QPushButton(translate(CONTEXT, "Refresh"))
        self.refresh_button.setToolTip(translate(
            CONTEXT, "Generate the program text again (after changes to the document)"))
        self.refresh_button.clicked.connect(lambda: self.refresh())
        buttons = QtGui.QHBoxLayout()
        buttons.addWidget(self.refresh_button)
        buttons.addWidget(self.write_button)
        layout.addLayout(buttons)

        # Making the program (and writing it) reports here; the window stays live.
        progress_row = QtGui.QHBoxLayout()
        self.progress_bar = QtGui.QProgressBar()
        progress_row.addWidget(self.progress_bar, 1)
        self.cancel_button = QtGui.QPushButton(translate(CONTEXT, "Cancel"))
        self.cancel_button.setToolTip(translate(
            CONTEXT, "Stop making the program; nothing is written"))
        progress_row.addWidget(self.cancel_button)
        layout.addLayout(progress_row)

        self.not_checked_bar = not_checked.NotCheckedBar(on_installed=self.refresh)
        layout.addWidget(self.not_checked_bar)   # "Collisions NOT checked", with Install
        self.message_label = QtGui.QLabel()
        self.message_label.setWordWrap(True)
        self.message_label.setTextFormat(QtCore.Qt.RichText)
        self.message_label.setTextInteractionFlags(QtCore.Qt.TextSelectableByMouse)
        layout.addWidget(self.message_label)

        self.tabs = QtGui.QTabWidget()
        self.tabs.setMinimumHeight(120)
        splitter = QtGui.QSplitter(QtCore.Qt.Vertical)
        splitter.setChildrenCollapsible(False)
        splitter.addWidget(top)
        splitter.addWidget(self.tabs)
        splitter.setStretchFactor(1, 1)
        form.layout().addWidget(splitter, 1)
        self.runner = gui_progress.ProgressRunner(self.progress_bar, self.cancel_button,
                                                  "CadRobot_Generate")
        return form

    def stop(self):
        """The panel closes: cancel a running call (it stops at its next report)."""
        self.closed = True
        self.runner.cancel()

    def _run(self, function, ambient=False):
        """`function` on the panel's progress bar, the buttons off meanwhile.

        Returns
        -------
        What `function` returns.

        Raises
        ------
        gui.progress.Busy, core.progress.Cancelled
        """
        buttons = (self.refresh_button, self.write_button, self.post_box, self.check_box)
        for widget in buttons:
            widget.setEnabled(False)
        try:
            if ambient:
                return self.runner.run_ambient(function)
            return self.runner.run(function)
        finally:
            if not self.closed:
                for widget in buttons:
                    widget.setEnabled(True)

    def browse(self):
        """Choose the output folder in a folder dialog."""
        folder = QtGui.QFileDialog.getExistingDirectory(
            self.form, translate(CONTEXT, "Output folder"), self.folder_edit.text())
        if folder:
            self.folder_edit.setText(folder)

    # -- settings --
    def post(self):
        """str: the chosen post-processor's name."""
        return self.post_box.itemData(self.post_box.currentIndex())

    def set_post(self, name):
        """Choose post `name` (shows its program)."""
        index = self.post_box.findData(name)
        if index < 0:
            raise InputError("No post-processor '%s' in the list." % name)
        self.post_box.setCurrentIndex(index)

    def options(self):
        """dict: the post options typed (InputError when malformed)."""
        return parse_options(self.options_edit.text())

    def output_dir(self):
        """str: the output folder, ``~`` expanded."""
        return os.path.expanduser(self.folder_edit.text().strip())

    def _changed(self, *_args):
        self.refresh()

    def _options_edited(self):
        if self.options_edit.text() != self._shown_options:
            self.refresh()

    # -- showing the program --
    def refresh(self):
        """Make the program with the panel's settings and show it, one tab per file.

        Returns
        -------
        bool
            False when an error was shown instead.
        """
        self._shown_options = self.options_edit.text()
        self.written = []
        if self.runner.running or gui_progress.busy():
            return False        # a click while the program is being made (through processEvents)
        try:
            post, options, check_first = self.post(), self.options(), self.check_box.isChecked()
            files = self._run(lambda progress: api.program_files(
                self.cell, post=post, options=options, check_first=check_first, progress=progress))
        except gui_progress.Cancelled:
            if not self.closed:
                self._show_files([])
                self._show_message(translate(CONTEXT, "Cancelled: no program made. Press Refresh "
                                                      "to make it."))
            return False
        except Exception as exc:  # noqa: BLE001 -- shown in the panel, never a traceback
            if self.closed:
                return False
            self._show_files([])
            self.show_error(exc)
            return False
        if self.closed:
            return False
        self._show_files(files)
        self.not_checked_bar.show_for(not_checked.left_out_now() if check_first else {})
        self._show_message(translate(CONTEXT, "{0} file(s) to write: {1}").format(
            len(files), ", ".join(name for name, _ in files)))
        return True

    def _show_files(self, files):
        self.files = list(files)
        self.tabs.clear()
        font = QtGui.QFontDatabase.systemFont(QtGui.QFontDatabase.FixedFont)
        for name, text in self.files:
            view = QtGui.QPlainTextEdit()
            view.setReadOnly(True)
            view.setLineWrapMode(QtGui.QPlainTextEdit.NoWrap)
            view.setFont(font)
            view.setPlainText(text)
            self.tabs.addTab(view, name)

    def tab_texts(self):
        """list of (str, str): the tab titles and the text each shows."""
        return [(self.tabs.tabText(i), self.tabs.widget(i).toPlainText())
                for i in range(self.tabs.count())]

    # -- writing --
    def write(self):
        """Journal and run ``api.export`` with the panel's settings.

        Returns
        -------
        list of str or None
            The written paths, or None when an error was shown (nothing written).
        """
        self.written = []
        if self.runner.running or gui_progress.busy():
            return None
        try:
            note = api.other_maker_note(self.cell, self.post())
            if note and not ask_other_maker(note):
                self._show_message(translate(CONTEXT, "Nothing written: choose the robot's own "
                                             "post-processor, or answer Yes to write this one."))
                return None
            lines = export_lines(self.cell, self.post(), self.output_dir(), self.options(),
                                 self.check_box.isChecked())
            # The journaled line reports to the panel's bar (core.progress.ambient); files
            # are written all-or-nothing after the last report, so Cancel writes nothing.
            self._run(lambda: [FreeCADGui.doCommand(line) for line in lines], ambient=True)
            import __main__
            written = list(vars(__main__).get(RESULT_VARIABLE) or [])
        except gui_progress.Cancelled:
            if not self.closed:
                self._show_message(translate(CONTEXT, "Cancelled: nothing was written."))
            return None
        except Exception as exc:  # noqa: BLE001 -- shown in the panel, never a traceback
            if not self.closed:
                self.show_error(exc)
            return None
        self.written = written
        self._show_message(translate(CONTEXT, "Wrote {0} file(s):").format(len(written)) + "<br>"
                           + "<br>".join(_escaped(path) for path in written))
        FreeCAD.Console.PrintMessage("CadRobot: wrote %s\n" % ", ".join(written))
        return written

    # -- messages --
    def _show_message(self, html):
        self.error = None
        self.message_label.setStyleSheet("")
        self.message_label.setText(html)

    def show_error(self, exc):
        """Show an error in red in the panel and select the object at fault.

        A CadRobotError is shown as it is; anything else is a bug (of CadRobot
        or of a user post): its type and message are shown, the traceback
        goes to the Report view.
        """
        if not isinstance(exc, CadRobotError):
            FreeCAD.Console.PrintError(traceback.format_exc())
            exc = InputError(translate(
                CONTEXT, "The program could not be made: {0}: {1} (details in the Report "
                "view).").format(type(exc).__name__, exc))
        else:
            FreeCAD.Console.PrintError("%s\n" % exc)
        self.error = exc
        self.message_label.setStyleSheet("color: red;")
        details = getattr(exc, "details", None) or []    # e.g. every finding of a failed check
        self.message_label.setText("<br>".join(_escaped(line) for line in [exc] + list(details)))
        obj_name = getattr(exc, "obj_name", None)
        obj = self.cell.Document.getObject(obj_name) if obj_name else None
        if obj is not None:
            FreeCADGui.Selection.clearSelection()
            FreeCADGui.Selection.addSelection(obj)

    # -- task dialog --
    BUTTONS = ("Ok", "Close")

    def ok(self):
        """OK: write, and close unless an error was shown."""
        return self.write() is not None

    def close_panel(self):
        close_panel()


# --- opening and closing ---------------------------------------------------------------------

def open_panel(cell):
    """Open the Generate panel on `cell` in the task view.

    Returns
    -------
    GeneratePanel

    Raises
    ------
    CadRobotError
        When another task panel is open.
    """
    return _slot.open(lambda: GeneratePanel(cell),
                      "Another task panel is open; close it before generating a program.")


def active_panel():
    """The open GeneratePanel, or None."""
    return _slot.panel


def close_panel():
    """Close the panel, if open."""
    _slot.close()
