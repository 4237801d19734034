"""Long API calls in the GUI with a progress bar and Cancel, without freezing the window.

Cooperative, in the GUI thread: the engine reports ``progress(fraction, text)``
often (``core.progress``: every few items of its long loops, at least every
~0.2 s of work), and the callback here moves the bar and lets Qt handle its
events (``QApplication.processEvents``), so the window repaints, the 3D view
turns and the Cancel button can be pressed.  Cancel makes the next report
return False and the engine raises ``Cancelled``.

Why not a worker thread: the engine reads FreeCAD document objects (paths,
shapes, solids) at several points of a call, and FreeCAD objects must only be
touched from the GUI thread; reading everything first would mean a second
copy of each command's reading.  Cooperative progress needs no locking, and
the work cannot race with the user's edits because both run in one thread.

While one work runs (:func:`busy`), a command or button that starts work
must not start another (``processEvents`` lets the user click it again):
:class:`ProgressRunner` refuses, and commands check :func:`busy` first.
Nothing here writes into the document: callers apply results only after the
call has returned.
"""

import contextlib
import time

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from ..core.progress import Cancelled, ambient

translate = FreeCAD.Qt.translate
CONTEXT = "CadRobot_Progress"

#: Least seconds between two event-loop turns (reports in between only store the fraction).
EVENTS_EVERY_S = 0.03

_under_way = []          # names of the works running now (nested only through processEvents)


def busy():
    """bool: a CadRobot work is running (a second one must not start)."""
    return bool(_under_way)


def running_work():
    """The name of the work running now, or None."""
    return _under_way[-1] if _under_way else None


class Busy(Exception):
    """Another work is running; this one was not started."""


@contextlib.contextmanager
def under_way(name):
    """Mark the block as the work `name` running (:func:`busy` is True meanwhile).

    For a panel with its own bar (Place robot); :class:`ProgressRunner` does it itself.
    Raises :class:`Busy` when another work is running.
    """
    if busy():
        raise Busy(running_work())
    _under_way.append(name)
    try:
        yield name
    finally:
        _under_way.remove(name)


class ProgressRunner:
    """Runs API calls that take ``progress=``, one at a time, on a bar with a Cancel button.

    Parameters
    ----------
    bar : QtGui.QProgressBar
        Shows the fraction (range set to 0..1000) and the text.
    cancel_button : QtGui.QAbstractButton, optional
        Enabled while a call runs; clicking it cancels.
    name : str
        Names the work (for :func:`running_work`).

    Attributes
    ----------
    reports : int
        Progress reports of the last call (for tests and diagnostics).
    """

    def __init__(self, bar, cancel_button=None, name="work"):
        self.bar, self.cancel_button, self.name = bar, cancel_button, name
        self.bar.setRange(0, 1000)
        self.bar.setTextVisible(True)
        self.running = False
        self.cancelled = False
        self.reports = 0
        self._events_at = 0.0
        if cancel_button is not None:
            cancel_button.setEnabled(False)
            cancel_button.clicked.connect(self.cancel)
        self._show(False)        # shown while a work runs: an idle panel keeps its room

    def _show(self, on):
        for widget in (self.bar, self.cancel_button):
            if widget is not None:
                widget.setVisible(on)

    def cancel(self):
        """Stop the running call at its next report (it raises ``Cancelled``)."""
        if self.running:
            self.cancelled = True

    def progress(self, fraction, text=""):
        """The engine's callback: move the bar, let Qt run, False once cancelled."""
        if self.cancelled:
            return False
        self.reports += 1
        self.bar.setValue(int(round(1000 * fraction)))
        self.bar.setFormat("%s: %%p%%" % text if text else "%p%")
        now = time.monotonic()
        if now - self._events_at >= EVENTS_EVERY_S:
            self._events_at = now
            QtGui.QApplication.processEvents()
        return not self.cancelled

    def run(self, function, *args, **kwargs):
        """``function(*args, progress=..., **kwargs)``, with the bar live and Cancel enabled.

        Returns
        -------
        What `function` returns.

        Raises
        ------
        Busy
            A work is already running (here or elsewhere): nothing was started.
        core.progress.Cancelled
            Cancel was pressed (or :meth:`cancel` called); the caller says so once.
        """
        with self._running():
            return function(*args, progress=self.progress, **kwargs)

    def run_ambient(self, function, *args, **kwargs):
        """``function(*args, **kwargs)`` with this runner as the ambient progress callback.

        For journaled calls (``FreeCADGui.doCommand`` lines a recorded macro
        replays as they are): the API calls they make report here
        (``core.progress.ambient``).  Raises as :meth:`run`.
        """
        with self._running(), ambient(self.progress):
            return function(*args, **kwargs)

    @contextlib.contextmanager
    def _running(self):
        if self.running or busy():
            raise Busy(running_work())
        self.running, self.cancelled, self.reports = True, False, 0
        self._events_at = 0.0
        _under_way.append(self.name)
        if self.cancel_button is not None:
            self.cancel_button.setEnabled(True)
        self._show(True)
        self.bar.setValue(0)
        self.bar.setFormat(translate(CONTEXT, "Starting...") + " %p%")
        try:
            yield self
        finally:
            _under_way.remove(self.name)
            self.running = False
            if self.cancel_button is not None:
                self.cancel_button.setEnabled(False)
            self._show(False)
        self.bar.setValue(1000)
        self.bar.setFormat(translate(CONTEXT, "Done") + " %p%")


class ProgressDialog(QtGui.QDialog):
    """A small non-modal window: what runs, a bar, Cancel; closing it cancels.

    For toolbar commands without a task panel (Check, Simulate).
    """

    def __init__(self, title, name, parent=None):
        super().__init__(parent if parent is not None else FreeCADGui.getMainWindow())
        self.setWindowTitle(title)
        self.setModal(False)
        layout = QtGui.QVBoxLayout(self)
        self.label = QtGui.QLabel(title)
        layout.addWidget(self.label)
        self.bar = QtGui.QProgressBar()
        self.bar.setMinimumWidth(320)
        layout.addWidget(self.bar)
        self.cancel_button = QtGui.QPushButton(translate(CONTEXT, "Cancel"))
        layout.addWidget(self.cancel_button, 0, QtCore.Qt.AlignRight)
        self.runner = ProgressRunner(self.bar, self.cancel_button, name)

    def reject(self):           # Esc and the window's close button
        self.runner.cancel()
        if not self.runner.running:
            super().reject()

    def closeEvent(self, event):
        self.runner.cancel()
        super().closeEvent(event)


#: The dialog of the work running now (tests reach its Cancel button here).
current_dialog = None


def run_with_dialog(title, name, function, *args, **kwargs):
    """Run ``function(*args, progress=..., **kwargs)`` showing a :class:`ProgressDialog`.

    Returns
    -------
    What `function` returns.

    Raises
    ------
    Busy
        Another work is running: nothing was started (no dialog shown).
    core.progress.Cancelled
        The user pressed Cancel or closed the dialog.
    """
    global current_dialog
    if busy():
        raise Busy(running_work())
    dialog = ProgressDialog(title, name)
    current_dialog = dialog
    dialog.show()
    try:
        return dialog.runner.run(function, *args, **kwargs)
    finally:
        current_dialog = None
        dialog.hide()
        dialog.deleteLater()


def say_busy(what):
    """One line in the status bar and the Report view: `what` was not started."""
    text = translate(CONTEXT, "{0}: another CadRobot work is still running ({1}); wait for it or "
                              "cancel it.").format(what, running_work() or "")
    FreeCAD.Console.PrintWarning(text + "\n")
    show_status(text)


def say_cancelled(what):
    """One line in the status bar and the Report view: `what` was cancelled, nothing changed."""
    text = translate(CONTEXT, "{0}: cancelled; nothing was changed.").format(what)
    FreeCAD.Console.PrintMessage(text + "\n")
    show_status(text)
    return text


def show_status(text, timeout_ms=8000):
    window = FreeCADGui.getMainWindow()
    if window is not None and window.statusBar() is not None:
        window.statusBar().showMessage(text, timeout_ms)


__all__ = ["Busy", "Cancelled", "ProgressDialog", "ProgressRunner", "busy", "run_with_dialog",
           "running_work", "say_busy", "say_cancelled"]
