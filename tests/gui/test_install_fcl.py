"""Without python-fcl (every Addon Manager user), Check and Place robot say first, in orange,
that collisions were not checked, and offer "Install python-fcl"; the button's install runs
without freezing the window and ends with "Check again", whose check then has no such line.

pip is replaced here (no network in the GUI tier): the real pip call is the install tier's
(tests/install/test_install_fcl.py)."""

import FreeCAD
import FreeCADGui
import pytest
from PySide import QtGui

from conftest import close_panels, process_events
from test_place_panel import small_search
from CadRobotWB import package_install
from CadRobotWB.commands import base as command_base
from CadRobotWB.commands import check as check_command
from CadRobotWB.gui import generate_panel, not_checked, place_panel
from CadRobotWB.robots.checks import collision

HEADLINE = "Collisions NOT checked: python-fcl is not installed."


@pytest.fixture
def without_fcl(gui_doc, monkeypatch):
    import seam_tracking_cell
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    close_panels()
    monkeypatch.setattr(collision, "is_available", lambda: False)
    cell = seam_tracking_cell.build(gui_doc)
    gui_doc.recompute()
    yield cell
    if not_checked.active_dialog() is not None:
        not_checked.active_dialog().close()
    place_panel.close_panel()
    generate_panel.close_panel()
    close_panels()


def status_bar_text():
    return FreeCADGui.getMainWindow().statusBar().currentMessage()


def fake_pip(monkeypatch):
    """pip as a worker thread sees it: lines, then success; python-fcl is 'there' afterwards."""
    threads = []

    def run_pip(name, on_line=None):
        import threading
        threads.append(threading.current_thread().name)
        for line in ("Collecting python-fcl", "Successfully installed python-fcl-0.7.0.11"):
            on_line(line)
        monkeypatch.setattr(collision, "is_available", lambda: True)
        return package_install.InstallResult(name, ok=True, command=["python3", "-m", "pip"])
    monkeypatch.setattr(package_install, "run_pip", run_pip)
    monkeypatch.setattr(package_install, "activate", lambda name: True)
    return threads


def test_check_says_first_that_collisions_were_not_checked_and_installs_fcl(without_fcl, monkeypatch):
    box = check_command.CheckCommand().run(without_fcl)
    process_events()
    text = box.text()
    assert text.startswith('<p style="color:%s"><b>%s</b></p>' % (not_checked.ORANGE, HEADLINE)), text
    assert "SeamCell: 0 errors" in text and text.index(HEADLINE) < text.index("0 errors")
    assert status_bar_text() == HEADLINE
    assert box.icon() == QtGui.QMessageBox.Warning          # not the "all is well" icon
    buttons = {b.text(): b for b in box.buttons()}
    assert "Install python-fcl" in buttons, list(buttons)

    threads = fake_pip(monkeypatch)
    buttons["Install python-fcl"].click()
    dialog = not_checked.active_dialog()
    result = dialog.wait(timeout_s=30)
    assert threads == ["CadRobot pip"]                  # pip ran in the worker, not the GUI thread
    assert result.ok and result.importable
    assert dialog.output.toPlainText().splitlines() == [
        "Collecting python-fcl", "Successfully installed python-fcl-0.7.0.11"]
    assert dialog.message.text() == ("python-fcl is installed and loaded in this FreeCAD (no restart "
                                     "needed): collisions are checked from now on. Run the check again.")
    assert dialog.check_again.isVisibleTo(dialog)
    dialog.check_again.click()                          # the check runs again, with collisions
    process_events()
    again = command_base._message_box
    assert again is not box and "NOT checked" not in again.text()
    assert again.text().startswith("SeamCell: 0 errors"), again.text()
    assert again.icon() == QtGui.QMessageBox.Information
    assert "Install python-fcl" not in [b.text() for b in again.buttons()]


def test_a_failed_install_shows_pips_last_lines_in_red(without_fcl, monkeypatch):
    def run_pip(name, on_line=None):
        return package_install.InstallResult(name, message="python-fcl was not installed: PyPI has "
                                             "no python-fcl for Python 3.14 on this system ...")
    monkeypatch.setattr(package_install, "run_pip", run_pip)
    dialog = not_checked.start_install("python-fcl", on_installed=lambda: None)
    result = dialog.wait(timeout_s=30)
    assert not result.ok and dialog.message.text().startswith("python-fcl was not installed: PyPI")
    assert "red" in dialog.message.styleSheet() and not dialog.check_again.isVisibleTo(dialog)


def test_place_robot_says_first_that_collisions_were_not_checked(without_fcl):
    without_fcl.Placement = FreeCAD.Placement(FreeCAD.Vector(-1500, 0, 0), FreeCAD.Rotation())
    panel = place_panel.open_panel(without_fcl)
    assert not panel.not_checked_bar.isVisibleTo(panel.form)
    small_search(panel, count=1)
    bar = panel.not_checked_bar
    assert bar.isVisibleTo(panel.form) and HEADLINE in bar.label.text()
    assert bar.button.text() == "Install python-fcl" and bar.button.isVisibleTo(panel.form)
    assert status_bar_text() == HEADLINE
    assert panel.message.text().startswith("35 candidate bases")   # the counts, not the NOT CHECKED line


def test_generate_says_collisions_were_not_checked_above_the_program(without_fcl):
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(without_fcl.Document.Name, without_fcl.Name)
    FreeCADGui.runCommand("CadRobot_Generate")
    process_events()
    panel = generate_panel.active_panel()
    bar = panel.not_checked_bar
    assert panel.files and bar.isVisibleTo(panel.form) and HEADLINE in bar.label.text()
    assert bar.button.text() == "Install python-fcl"
    panel.check_box.setChecked(False)      # written without any check: nothing to say about one
    process_events()
    assert panel.files and not bar.isVisibleTo(panel.form)
