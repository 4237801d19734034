"""CadRobot_Check: check that the robot can run the cell's program, colour the targets."""

import FreeCAD

from .. import api
from ..gui import progress as gui_progress
from ..gui import status_overlay
from .base import QT_TRANSLATE_NOOP, CellCommand, show_message, translate

NAME = "CadRobot_Check"


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
        show_message(translate("CadRobot_Check", "Check cell"), summary(result),
                     "\n".join(result.lines()), error=not result.ok)
