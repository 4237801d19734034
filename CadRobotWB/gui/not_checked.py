"""Checks left out, said first and in orange, with the button that installs what they need.

Wherever a result says a check was left out (``not_checked``: collisions without
python-fcl), the GUI shows :func:`headline_html` as its first line and offers
"Install python-fcl" (:func:`add_install_button` on a message box,
:class:`NotCheckedBar` in a panel).  The button opens :class:`InstallDialog`:
pip runs in a worker thread (``package_install.run_pip``: it touches no
document), its output scrolls in the dialog, and at the end the package is
made importable in the GUI thread (``package_install.finish``) and the result
is shown, with "Check again" after a success.
"""

import html
import threading
import time

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from .. import dependencies, package_install

translate = FreeCAD.Qt.translate
CONTEXT = "CadRobot_NotChecked"

#: The headline's colour (orange: a warning, not an error).
ORANGE = "#d35400"
#: Milliseconds between two looks at the worker's output.
POLL_MS = 100

_dialog = None        # the install dialog open now (one install at a time)


def left_out_now():
    """The checks a check would leave out now, judged by the packages alone (dict like a
    report's ``not_checked``): for panels that check without showing the report (Generate)."""
    from ..robots.checks import collision
    if collision.is_available():
        return {}
    return {"collisions": dependencies.reason(collision.FCL_PACKAGE)}


def packages_to_install(not_checked):
    """The packages the checks of `not_checked` need (list of str, no repeats)."""
    names = [dependencies.CHECK_PACKAGES.get(check) for check in not_checked]
    return sorted({name for name in names if name})


def headline_html(not_checked):
    """The orange first line for `not_checked` (rich text), or "" when nothing was left out."""
    text = dependencies.headline(not_checked)
    if not text:
        return ""
    return '<p style="color:%s"><b>%s</b></p>' % (ORANGE, html.escape(text, quote=False))


def show_status(not_checked, timeout_ms=60000):
    """Put the headline in the main window's status bar (nothing when nothing was left out).

    Now and once more from the event loop: FreeCAD shows each Report view warning in the
    status bar through a queued event, which would otherwise replace it.

    Returns
    -------
    str or None
        The headline.
    """
    text = dependencies.headline(not_checked)
    window = FreeCADGui.getMainWindow()
    if text and window is not None and window.statusBar() is not None:
        show = lambda: window.statusBar().showMessage(text, timeout_ms)  # noqa: E731
        show()
        QtCore.QTimer.singleShot(0, show)
    return text


def install_button_text(name):
    return translate(CONTEXT, "Install {0}").format(name)


def add_install_button(box, not_checked, on_installed=None):
    """Add "Install python-fcl" to message `box` when `not_checked` needs it.

    Parameters
    ----------
    box : QtGui.QMessageBox
    not_checked : dict of str to str
    on_installed : callable, optional
        Called with no argument by the dialog's "Check again" after a success.

    Returns
    -------
    QtGui.QPushButton or None
    """
    names = packages_to_install(not_checked)
    if not names:
        return None
    button = box.addButton(install_button_text(names[0]), QtGui.QMessageBox.ActionRole)
    button.clicked.connect(lambda: start_install(names[0], on_installed))
    return button


class NotCheckedBar(QtGui.QWidget):
    """A panel's orange line "Collisions NOT checked: ..." with the Install button (hidden when
    nothing was left out).

    Parameters
    ----------
    on_installed : callable, optional
        Called by the install dialog's "Check again" (e.g. search again).
    """

    def __init__(self, on_installed=None, parent=None):
        super().__init__(parent)
        self.on_installed = on_installed
        self.package = None
        layout = QtGui.QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        self.label = QtGui.QLabel()
        self.label.setWordWrap(True)
        self.label.setTextFormat(QtCore.Qt.RichText)
        layout.addWidget(self.label)
        self.button = QtGui.QPushButton()
        self.button.clicked.connect(lambda: start_install(self.package, self.on_installed))
        layout.addWidget(self.button)
        self.setVisible(False)

    def show_for(self, not_checked):
        """Show the headline and button for `not_checked`, or hide when it is empty."""
        names = packages_to_install(not_checked)
        self.package = names[0] if names else None
        self.label.setText(headline_html(not_checked))
        self.button.setText(install_button_text(self.package or ""))
        self.button.setVisible(self.package is not None)
        self.setVisible(bool(not_checked))


def start_install(name, on_installed=None):
    """What the Install button does: open :class:`InstallDialog` and start pip for `name`.

    Returns
    -------
    InstallDialog
        The dialog (the one already running, when an install is under way).
    """
    global _dialog
    if _dialog is not None and _dialog.running():
        _dialog.raise_()
        return _dialog
    _dialog = InstallDialog(name, on_installed, FreeCADGui.getMainWindow())
    _dialog.show()
    _dialog.start()
    return _dialog


def active_dialog():
    """The install dialog, or None."""
    return _dialog


class InstallDialog(QtGui.QDialog):
    """pip installing one package: its output, a busy bar, then the result.

    Attributes
    ----------
    result : package_install.InstallResult or None
        Once pip has ended.
    """

    def __init__(self, name, on_installed=None, parent=None):
        super().__init__(parent)
        self.name, self.on_installed, self.result = name, on_installed, None
        self._lines, self._worker, self._finished = [], None, None
        self.setWindowTitle(install_button_text(name))
        self.setModal(False)
        layout = QtGui.QVBoxLayout(self)
        self.message = QtGui.QLabel(translate(
            CONTEXT, "Installing {0} with FreeCAD's Python into the folder FreeCAD reads. This "
            "takes up to a minute; FreeCAD stays usable.").format(name))
        self.message.setWordWrap(True)
        self.message.setTextInteractionFlags(QtCore.Qt.TextSelectableByMouse)
        layout.addWidget(self.message)
        self.bar = QtGui.QProgressBar()
        self.bar.setRange(0, 0)             # busy: pip tells no fraction
        layout.addWidget(self.bar)
        self.output = QtGui.QPlainTextEdit()
        self.output.setReadOnly(True)
        self.output.setMinimumSize(560, 160)
        layout.addWidget(self.output)
        buttons = QtGui.QHBoxLayout()
        self.check_again = QtGui.QPushButton(translate(CONTEXT, "Check again"))
        self.check_again.clicked.connect(self._check_again)
        self.check_again.setVisible(False)
        self.close_button = QtGui.QPushButton(translate(CONTEXT, "Close"))
        self.close_button.clicked.connect(self.close)
        buttons.addStretch(1)
        buttons.addWidget(self.check_again)
        buttons.addWidget(self.close_button)
        layout.addLayout(buttons)
        self.timer = QtCore.QTimer(self)
        self.timer.setInterval(POLL_MS)
        self.timer.timeout.connect(self._poll)

    def start(self):
        """Run pip in a worker thread; the timer shows its lines and its end."""
        self._worker = threading.Thread(target=self._run, name="CadRobot pip", daemon=True)
        self._worker.start()
        self.timer.start()

    def running(self):
        """bool: pip has not ended yet."""
        return self._worker is not None and self.result is None

    def _run(self):
        try:
            self._finished = package_install.run_pip(self.name, on_line=self._lines.append)
        except Exception as error:  # noqa: BLE001 -- shown in the dialog, never lost in a thread
            self._finished = package_install.InstallResult(
                self.name, message="%s: %s" % (type(error).__name__, error))

    def _poll(self):
        while self._lines:
            self.output.appendPlainText(self._lines.pop(0))
        if self._worker.is_alive():
            return
        self.timer.stop()
        self._done(package_install.finish(self._finished))

    def _done(self, result):
        self.result = result
        self.bar.setRange(0, 1)
        self.bar.setValue(1)
        self.bar.setVisible(False)
        colour = "green" if result.importable else (ORANGE if result.ok else "red")
        self.message.setStyleSheet("color: %s;" % colour)
        self.message.setText(result.message)
        self.check_again.setVisible(result.importable and self.on_installed is not None)
        log = FreeCAD.Console.PrintMessage if result.ok else FreeCAD.Console.PrintError
        log("CadRobot: %s\n" % result.message)
        window = FreeCADGui.getMainWindow()
        if window is not None and window.statusBar() is not None:
            window.statusBar().showMessage(result.message.splitlines()[0], 60000)

    def wait(self, timeout_s=None):
        """Run the event loop until pip has ended (tests, scripts); returns the result or None."""
        end = None if timeout_s is None else time.monotonic() + timeout_s
        while self.result is None and (end is None or time.monotonic() < end):
            QtGui.QApplication.processEvents()
            time.sleep(0.02)
        return self.result

    def _check_again(self):
        self.close()
        if self.on_installed is not None:
            self.on_installed()
