"""CadRobot_Check: check that the robot can run the cell's program, colour the targets."""

import os

import FreeCAD
import FreeCADGui
from PySide import QtGui

from .. import api
from ..errors import CadRobotError
from ..gui import status_overlay
from .selection import find_cell

translate = FreeCAD.Qt.translate
QT_TRANSLATE_NOOP = FreeCAD.Qt.QT_TRANSLATE_NOOP

NAME = "CadRobot_Check"
ICON = os.path.join(os.path.dirname(os.path.dirname(__file__)), "resources", "icons",
                    NAME + ".svg")

_message_box = None     # the last result box (non-modal, so kept alive here)


def report(result):
    """Print a check's lines in the Report view: errors red, warnings orange."""
    console = FreeCAD.Console
    for line in result.lines():
        text = line + "\n"
        if ": ERROR: " in line:
            console.PrintError(text)
        elif ": WARNING: " in line:
            console.PrintWarning(text)
        else:
            console.PrintMessage(text)


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


def summary(result):
    """One paragraph: how many errors and warnings, and the cycle time."""
    findings = result.report
    cycle = result.cycle_time
    text = translate("CadRobot_Check", "{0}: {1} errors, {2} warnings. Cycle time {3:.1f} s.").format(
        result.cell, len(findings.errors), len(findings.warnings), cycle["total_s"])
    if findings.errors:
        text += "\n\n" + translate("CadRobot_Check", "First error: {0}").format(
            findings.errors[0].message)
    return text


class CheckCommand:
    """Check reach, joint limits, singularities, speeds and collisions of the cell's program."""

    def GetResources(self):
        return {
            "Pixmap": ICON,
            "CmdType": "ForEdit",      # only views: usable while a task panel is open
            "MenuText": QT_TRANSLATE_NOOP(NAME, "Check cell"),
            "ToolTip": QT_TRANSLATE_NOOP(
                NAME, "Check that the robot can run the selected cell's program: reach, joint "
                "limits, singularities, joint speeds, collisions and cycle time. The targets "
                "turn green, orange (warning) or red (error) in the 3D view."),
            "StatusTip": QT_TRANSLATE_NOOP(
                NAME, "Check the selected cell's program and colour its targets by status"),
        }

    def IsActive(self):
        return find_cell() is not None

    def Activated(self):
        cell = find_cell()
        if cell is None:
            return
        try:
            result = api.check(cell)
        except CadRobotError as exc:
            FreeCAD.Console.PrintError("%s\n" % exc)
            show_message(translate("CadRobot_Check", "Check cell"), str(exc), error=True)
            return
        status_overlay.show_check(cell, result)
        report(result)
        show_message(translate("CadRobot_Check", "Check cell"), summary(result),
                     "\n".join(result.lines()), error=not result.ok)
