"""What the CadRobot task panels share: one open panel per kind, and the OK / Cancel buttons.

Each panel module keeps its own :class:`PanelSlot` (its ``open_panel`` /
``active_panel`` / ``close_panel`` use it) and its panel class derives from
:class:`TaskPanel`, which answers FreeCAD's task dialog calls
(``getStandardButtons``, ``accept``, ``reject``).
"""

import FreeCAD
import FreeCADGui
from PySide import QtGui

from ..errors import InputError


def button_flags(*names):
    """Standard buttons of the task dialog as the int FreeCAD wants.

    Parameters
    ----------
    *names : str
        Names of ``QDialogButtonBox`` standard buttons, e.g. ``"Ok"``, ``"Cancel"``.

    Returns
    -------
    int
        The buttons or-ed together (PySide6 enums are not ints).
    """
    flags = 0
    for name in names:
        button = getattr(QtGui.QDialogButtonBox, name)
        flags |= int(getattr(button, "value", button))
    return flags


#: Every PanelSlot made, so a panel is closed with its document (:class:`_DocumentWatcher`).
_slots = []
_watcher = None


def document_name(panel):
    """Name of the document `panel` works on (its ``doc``, or its ``cell``'s or
    ``frame``'s document), or None."""
    for attr in ("doc", "cell", "frame"):
        value = getattr(panel, attr, None)
        doc = value if attr == "doc" else getattr(value, "Document", None)
        name = getattr(doc, "Name", None)
        if isinstance(name, str):
            return name
    return None


class _DocumentWatcher:
    """Closes the open panels of a document that is being closed (FreeCAD leaves a
    Python task dialog open on a closed document: OK would then raise on its
    deleted objects and a picking observer would stay installed)."""

    def slotDeletedDocument(self, doc):
        for slot in list(_slots):
            if slot.panel is not None and slot.document_name == doc.Name:
                try:
                    slot.close()
                except Exception as exc:  # noqa: BLE001 -- never a traceback from an observer
                    FreeCAD.Console.PrintLog("CadRobot: closing a panel: %s\n" % exc)
                    slot.panel = None


class PanelSlot:
    """The one open task panel of a kind, or None.

    Parameters
    ----------
    before_close : callable, optional
        Called with the panel when it is closed, before the task dialog goes
        (e.g. to stop a selection observer).

    Attributes
    ----------
    panel : object or None
        The panel shown, None when closed.
    """

    def __init__(self, before_close=None):
        self.panel = None
        self.before_close = before_close
        self.document_name = None
        _slots.append(self)

    def open(self, make_panel, busy_message, on_busy=None):
        """Close the panel of this slot, then make a new one and show it in the task view.

        Parameters
        ----------
        make_panel : callable
            Makes the panel (no arguments); not called when another task
            dialog is open.
        busy_message : str
            What the user is told when another task dialog is open.
        on_busy : callable, optional
            Called with `busy_message` instead of raising when another task
            dialog is open; ``open`` then returns None.

        Returns
        -------
        object or None
            The panel shown; None when `on_busy` was called.

        Raises
        ------
        InputError
            `busy_message`, when another task dialog is open and `on_busy` is None.
        """
        self.close()
        if FreeCADGui.Control.activeDialog():
            if on_busy is None:
                raise InputError(busy_message)
            on_busy(busy_message)
            return None
        global _watcher
        if _watcher is None:
            _watcher = _DocumentWatcher()
            FreeCAD.addDocumentObserver(_watcher)
        self.panel = make_panel()
        self.document_name = document_name(self.panel)
        FreeCADGui.Control.showDialog(self.panel)
        return self.panel

    def close(self):
        """Forget the panel and close the task dialog, if a panel is open.

        Returns
        -------
        object or None
            The panel that was open.
        """
        panel, self.panel = self.panel, None
        if panel is None:
            return None
        if self.before_close is not None:
            self.before_close(panel)
        try:
            FreeCADGui.Control.closeDialog()
        except RuntimeError:
            pass
        return panel


class TaskPanel:
    """Base of a task panel: OK does the panel's work and closes it, Cancel closes it.

    Subclasses implement :meth:`ok` and :meth:`close_panel` (their module's
    ``close_panel``), and may set :attr:`BUTTONS`.

    Attributes
    ----------
    BUTTONS : tuple of str
        The ``QDialogButtonBox`` standard buttons shown (see :func:`button_flags`).
    ACTION_BUTTONS : tuple of str
        Attribute names of the panel's own action buttons.
    """

    BUTTONS = ("Ok", "Cancel")
    #: Attributes naming the panel's own action buttons (Run, Search, Write...): laid out
    #: where they show without scrolling at 1366x768 (tests/gui/test_panels_fit.py).
    ACTION_BUTTONS = ()

    def ok(self):
        """Do what OK does; True when done (the panel then closes), False to stay open."""
        raise NotImplementedError

    def close_panel(self):
        """Close this panel (through its module's slot)."""
        raise NotImplementedError

    # -- the task dialog's calls --
    def getStandardButtons(self):
        return button_flags(*self.BUTTONS)

    def accept(self):
        if not self.ok():
            return False
        self.close_panel()
        return True

    def reject(self):
        self.close_panel()
        return True
