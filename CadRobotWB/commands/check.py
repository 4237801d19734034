"""CadRobot_Check: check that the robot can run the cell's program, colour the targets."""

import html

import FreeCAD
from PySide import QtCore

from .. import api, dependencies
from ..gui import not_checked
from ..gui import progress as gui_progress
from ..gui import status_overlay
from .base import QT_TRANSLATE_NOOP, CellCommand, show_message, translate

NAME = "CadRobot_Check"


def report(result):
    """Print a check's lines in the Report view: errors red, warnings and checks left out orange."""
    console = FreeCAD.Console
    for line in result.lines():
        text = line + "\n"
        if ": ERROR: " in line:
            console.PrintError(text)
        elif ": WARNING: " in line or ": NOT CHECKED: " in line:
            console.PrintWarning(text)
        else:
            console.PrintMessage(text)


def summary(result):
    """What the check found, in plain text; its first line says which checks were left out
    (collisions without python-fcl), so "0 errors, 0 warnings" is never all it says."""
    headline = dependencies.headline(result.report.not_checked)
    return (headline + "\n\n" if headline else "") + findings_summary(result)


def summary_html(result):
    """:func:`summary` as the message box's rich text: the left-out checks in orange."""
    body = html.escape(findings_summary(result), quote=False)
    return not_checked.headline_html(result.report.not_checked) + body.replace("\n", "<br>")


def findings_summary(result):
    """One paragraph: how many errors and warnings, the cycle time when the check passed,
    and the first error group (with its advice)."""
    findings = result.report
    text = translate("CadRobot_Check", "{0}: {1} errors, {2} warnings.").format(
        result.cell, len(findings.errors), len(findings.warnings))
    if result.cycle_time_s is not None:
        text += " " + translate("CadRobot_Check", "Cycle time {0:.1f} s.").format(result.cycle_time_s)
    groups = [g for g in findings.groups() if g.severity == "error"]
    if groups:
        text += "\n\n" + translate("CadRobot_Check", "First error: {0}").format(
            groups[0].line().split(": ", 2)[-1])
    if not result.ok and findings.placement_helps:
        text += "\n\n" + translate("CadRobot_Check", "Place robot searches bases where the robot "
                                     "reaches every target.")
    return text


def add_place_robot_button(box, cell):
    """Add "Place robot..." to the check's message `box`: it opens the Place robot panel on `cell`.

    Returns
    -------
    QtGui.QPushButton
    """
    from PySide import QtGui
    button = box.addButton(translate("CadRobot_Check", "Place robot..."), QtGui.QMessageBox.ActionRole)

    def open_place_robot():
        from ..gui import place_panel
        from .base import report_error
        from ..errors import CadRobotError
        try:
            place_panel.open_panel(cell)
        except CadRobotError as err:
            report_error(cell.Document, "", err)

    button.clicked.connect(open_place_robot)
    return button


class CheckCommand(CellCommand):
    """Check reach, joint limits, singularities, speeds and collisions of the cell's program."""

    NAME = NAME
    MENU_TEXT = QT_TRANSLATE_NOOP("CadRobot_Check", "Check cell")
    TOOLTIP = QT_TRANSLATE_NOOP(
        "CadRobot_Check", "Check that the robot can run the selected cell's program: reach, joint "
        "limits, singularities, joint speeds, collisions and cycle time. The targets turn green, "
        "orange (warning) or red (error) in the 3D view.")
    STATUS_TIP = QT_TRANSLATE_NOOP(
        "CadRobot_Check", "Check the selected cell's program and colour its targets by status")

    def run(self, cell):
        # A progress window with Cancel; the window stays live. The targets are coloured
        # only once the check has finished: a cancelled check changes nothing.
        if gui_progress.busy():
            gui_progress.say_busy(self.title())
            return
        try:
            result = gui_progress.run_with_dialog(self.title(), NAME, api.check, cell)
        except gui_progress.Cancelled:
            gui_progress.say_cancelled(self.title())
            return
        status_overlay.show_check(cell, result)
        report(result)
        box = show_message(translate("CadRobot_Check", "Check cell"), summary_html(result),
                           "\n".join(result.lines()),
                           error=not result.ok or bool(result.report.not_checked))
        box.setTextFormat(QtCore.Qt.RichText)
        if not not_checked.show_status(result.report.not_checked):
            gui_progress.show_status(findings_summary(result).split("\n")[0])
        not_checked.add_install_button(box, result.report.not_checked,
                                       on_installed=lambda: self.run(cell))
        if not result.ok and result.report.placement_helps:
            add_place_robot_button(box, cell)
        return box
