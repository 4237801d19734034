"""What every CadRobot command shares: its icon, being active when a cell is
found, and showing a CadRobotError instead of a traceback."""

import os

import FreeCAD
import FreeCADGui
from PySide import QtGui

from ..errors import CadRobotError
from .selection import find_cell

translate = FreeCAD.Qt.translate
QT_TRANSLATE_NOOP = FreeCAD.Qt.QT_TRANSLATE_NOOP
ICONS = os.path.join(os.path.dirname(os.path.dirname(__file__)), "resources", "icons")

_message_box = None     # the last message box (non-modal, so kept alive here)


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


class CellCommand:
    """A command acting on the selected (or only) cell.

    Subclasses set NAME, MENU_TEXT, TOOLTIP, STATUS_TIP (wrapped in
    QT_TRANSLATE_NOOP) and implement :meth:`run`.
    """

    NAME = ""
    MENU_TEXT = ""
    TOOLTIP = ""
    STATUS_TIP = ""

    def GetResources(self):
        return {
            "Pixmap": os.path.join(ICONS, self.NAME + ".svg"),
            "CmdType": "ForEdit",      # these only view: usable while a task panel is open
            "MenuText": self.MENU_TEXT,
            "ToolTip": self.TOOLTIP,
            "StatusTip": self.STATUS_TIP,
        }

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
            show_message(translate(self.NAME, self.MENU_TEXT), str(exc), error=True)

    def run(self, cell):
        raise NotImplementedError
