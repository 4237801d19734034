"""What every CadRobot command shares: its icon, being active when a cell is
found, showing a CadRobotError instead of a traceback, and running the API
calls that change the document as one journaled undo step
(:func:`run_journaled`)."""

import os
import sys
import traceback

import FreeCAD
import FreeCADGui
from PySide import QtGui

from ..errors import CadRobotError
from .selection import find_cell

translate = FreeCAD.Qt.translate
QT_TRANSLATE_NOOP = FreeCAD.Qt.QT_TRANSLATE_NOOP
ICONS = os.path.join(os.path.dirname(os.path.dirname(__file__)), "resources", "icons")

_message_box = None     # the last message box (non-modal, so kept alive here)

#: The lines every journal starts with (a recorded macro must stand on its own).
IMPORT_LINES = ("import FreeCAD", "from CadRobotWB import api")


def show_message(title, text, details="", error=False):
    """A non-modal message box over the main window (does not stop the GUI)."""
    global _message_box
    if _message_box is not None:
        _message_box.close()
    icon = QtGui.QMessageBox.Warning if error else QtGui.QMessageBox.Information
    box = QtGui.QMessageBox(icon, title, text, QtGui.QMessageBox.Ok, FreeCADGui.getMainWindow())
    if details:
        box.setDetailedText(details)
    box.setModal(False)
    box.show()
    _message_box = box
    return box


class Command:
    """What a CadRobot command tells FreeCAD about itself.

    Subclasses set NAME, MENU_TEXT, TOOLTIP, STATUS_TIP (wrapped in
    QT_TRANSLATE_NOOP); the icon is ``resources/icons/<NAME>.svg``.

    Attributes
    ----------
    CMD_TYPE : str
        FreeCAD's ``CmdType`` of the command.
    """

    NAME = ""
    MENU_TEXT = ""
    TOOLTIP = ""
    STATUS_TIP = ""
    CMD_TYPE = ""

    def GetResources(self):
        return {
            "Pixmap": os.path.join(ICONS, self.NAME + ".svg"),
            "CmdType": self.CMD_TYPE,
            "MenuText": self.MENU_TEXT,
            "ToolTip": self.TOOLTIP,
            "StatusTip": self.STATUS_TIP,
        }

    def title(self):
        """The translated menu text (message box titles, undo step names)."""
        return translate(self.NAME, self.MENU_TEXT)


class CellCommand(Command):
    """A command acting on the selected (or only) cell; subclasses implement :meth:`run`."""

    CMD_TYPE = "ForEdit"      # these only view: usable while a task panel is open

    def IsActive(self):
        return find_cell() is not None

    def Activated(self):
        cell = find_cell()
        if cell is None:
            return
        try:
            self.run(cell)
        except CadRobotError as exc:
            FreeCAD.Console.PrintError("%s\n" % exc)
            show_message(self.title(), str(exc), error=True)

    def run(self, cell):
        raise NotImplementedError


# --- journaled document changes ------------------------------------------------------------

class Code(str):
    """Source text put into a journal line as it is (e.g. a variable an earlier line set)."""


def literal(value):
    """Python source that rebuilds `value` in a journal line.

    Handles None, bool, int, float (exact ``repr``), str, FreeCAD.Vector,
    FreeCAD.Rotation, FreeCAD.Placement, document objects (by document and
    internal name) and lists/tuples of these, and dicts of str to these.
    """
    if isinstance(value, Code):
        return str(value)
    if value is None or isinstance(value, (bool, int, str)):
        return repr(value)
    if isinstance(value, float):
        return repr(float(value))
    if isinstance(value, (list, tuple)) and hasattr(value, "_fields"):
        raise TypeError("cannot journal a %s" % type(value).__name__)
    if isinstance(value, FreeCAD.Vector):
        return "FreeCAD.Vector(%r, %r, %r)" % (float(value.x), float(value.y), float(value.z))
    if isinstance(value, FreeCAD.Rotation):
        return "FreeCAD.Rotation(%r, %r, %r, %r)" % tuple(float(q) for q in value.Q)
    if isinstance(value, FreeCAD.Placement):
        return "FreeCAD.Placement(%s, %s)" % (literal(value.Base), literal(value.Rotation))
    if hasattr(value, "Objects") and hasattr(value, "FileName") and hasattr(value, "Name"):
        return "FreeCAD.getDocument(%r)" % value.Name
    if hasattr(value, "Document") and hasattr(value, "Name") and hasattr(value, "TypeId"):
        return "FreeCAD.getDocument(%r).getObject(%r)" % (value.Document.Name, value.Name)
    if isinstance(value, tuple):
        items = [literal(v) for v in value]
        return "(%s,)" % items[0] if len(items) == 1 else "(%s)" % ", ".join(items)
    if isinstance(value, list):
        return "[%s]" % ", ".join(literal(v) for v in value)
    if isinstance(value, dict) and all(isinstance(k, str) for k in value):
        return "{%s}" % ", ".join("%r: %s" % (k, literal(v)) for k, v in value.items())
    try:                                    # numpy scalars
        return repr(float(value))
    except (TypeError, ValueError):
        raise TypeError("cannot journal a %s" % type(value).__name__) from None


def call(function, *args, **kwargs):
    """``"function(arg, ..., name=value)"`` with every argument as a :func:`literal`."""
    parts = [literal(a) for a in args] + ["%s=%s" % (k, literal(v)) for k, v in kwargs.items()]
    return "%s(%s)" % (function, ", ".join(parts))


def as_cadrobot_error(exc):
    """`exc` as a CadRobotError whose text the user can act on.

    FreeCADGui.doCommand (0.20 and 1.x) runs its line with ``PyRun_String`` in
    ``__main__`` and hands back the line's own exception object, type and
    attributes (``obj_name``) intact: a CadRobotError stays itself. Anything
    else is a bug or a FreeCAD failure: its one-line text is kept (without a
    ``"Type: "`` prefix FreeCAD's C++ errors carry) and the traceback goes to
    the Report view's log only.
    """
    if isinstance(exc, CadRobotError):
        return exc
    FreeCAD.Console.PrintLog("".join(traceback.format_exception(type(exc), exc, exc.__traceback__)))
    text = str(exc).strip() or type(exc).__name__
    prefix = type(exc).__name__ + ": "
    if text.startswith(prefix):
        text = text[len(prefix):]
    return CadRobotError("%s (%s)" % (text, type(exc).__name__), getattr(exc, "obj_name", None))


def journal(doc, title, lines, results=()):
    """Run `lines` through ``FreeCADGui.doCommand`` as ONE undo step of `doc`.

    Each line is recorded by the macro recorder and shown in the Python
    console, so a recorded macro replays the same API calls in FreeCADCmd.
    On an exception the transaction is aborted (the document is as before)
    and a CadRobotError is raised (see :func:`as_cadrobot_error`).

    Parameters
    ----------
    doc : App.Document
    title : str
        The undo step's name (translated).
    lines : sequence of str
        Python statements; :data:`IMPORT_LINES` are run first.
    results : sequence of str
        Names of variables the lines assign (in ``__main__``) to hand back.

    Returns
    -------
    list
        The values of `results`, in order.
    """
    doc.openTransaction(title)
    try:
        for line in list(IMPORT_LINES) + list(lines):
            FreeCADGui.doCommand(line)
        namespace = vars(sys.modules["__main__"])
        values = [namespace.get(name) for name in results]
    except Exception as exc:  # noqa: BLE001 -- every failure must leave the document unchanged
        doc.abortTransaction()
        doc.recompute()
        raise as_cadrobot_error(exc) from exc
    doc.commitTransaction()
    return values


def select_in_tree(doc, obj_name):
    """Select object `obj_name` of `doc` alone (tree and 3D view); nothing if it does not exist."""
    if not obj_name or doc is None or doc.getObject(obj_name) is None:
        return False
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, obj_name)
    return True


def report_error(doc, title, err, show=True):
    """Tell the user about CadRobotError `err`: one line in the Report view, one
    non-modal message (unless `show` is False, e.g. a task panel shows it itself),
    and the object at fault (``err.obj_name``) selected in the tree."""
    FreeCAD.Console.PrintError("CadRobot: %s\n" % err)
    select_in_tree(doc, getattr(err, "obj_name", None))
    if show:
        show_message(title, str(err), error=True)


def run_journaled(doc, title, lines, results=(), show=True):
    """:func:`journal`, reporting a failure with :func:`report_error` instead of raising.

    Returns
    -------
    list or None
        The values of `results`; None when the change failed (the document is unchanged).
    """
    try:
        return journal(doc, title, lines, results)
    except CadRobotError as err:
        report_error(doc, title, err, show)
        return None


class DocumentCommand(Command):
    """A command that changes the document from the selection.

    Subclasses implement :meth:`fits` (cheap: it runs with every selection
    change) and :meth:`run`; a CadRobotError raised by :meth:`run` is shown,
    never a traceback. The command manages its own undo step
    (:func:`journal`), so FreeCAD's automatic per-command transaction is
    switched off.
    """

    CMD_TYPE = "NoTransaction"

    def IsActive(self):
        doc = FreeCAD.ActiveDocument
        if doc is None:
            return False
        try:
            return bool(self.fits(doc))
        except Exception:  # noqa: BLE001 -- a greyed button, never a traceback per redraw
            return False

    def Activated(self):
        doc = FreeCAD.ActiveDocument
        if doc is None:
            return
        try:
            self.run(doc)
        except CadRobotError as err:
            report_error(doc, self.title(), err)

    def fits(self, doc):
        """True when the selection in `doc` is something this command acts on."""
        raise NotImplementedError

    def run(self, doc):
        raise NotImplementedError
