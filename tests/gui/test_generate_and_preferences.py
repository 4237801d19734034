"""CadRobot_Generate and the CadRobot preferences page in the real FreeCAD window.

The Generate panel shows what ``api.program_files`` makes, for built-in and user
posts; Write writes the bytes ``api.export`` writes (and journals the call, so the
macro replays it); errors stay in the panel, in red, with the object at fault
selected and nothing written. The preferences page round-trips every setting
through FreeCAD's parameter group.
"""

import os
import re

import pytest

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from conftest import REPO, process_events

from CadRobotWB import api, preferences
from CadRobotWB.gui import generate_panel, preferences_page

NAME = "CadRobot_Generate"
MACRO_PARAMS = "User parameter:BaseApp/Preferences/Macro"


def readme_user_post():
    """The example user post of the README (the tests load what users are shown)."""
    with open(os.path.join(REPO, "README.md"), encoding="utf-8") as handle:
        text = handle.read()
    match = re.search(r"```python\n(NAME = \"mybrand\".*?)```", text, re.S)
    assert match, "README.md lost its mybrand_post.py example"
    return match.group(1)


# --- fixtures --------------------------------------------------------------------------------

@pytest.fixture
def saved_preferences():
    """Restore every CadRobot preference (and the macro folder) after the test."""
    group = FreeCAD.ParamGet(preferences.PATH)
    macro = FreeCAD.ParamGet(MACRO_PARAMS)
    before = {name: (name in _names(group, value), preferences.get(name))
              for name, value in preferences.DEFAULTS.items()}
    macro_before = macro.GetString("MacroPath", "")
    yield
    for name, (stored, value) in before.items():
        if stored:
            preferences.set(name, value)
        elif isinstance(preferences.DEFAULTS[name], float):
            group.RemFloat(name)
        else:
            group.RemString(name)
    if macro_before:
        macro.SetString("MacroPath", macro_before)
    else:
        macro.RemString("MacroPath")


def _names(group, default):
    return group.GetFloats() if isinstance(default, float) else group.GetStrings()


@pytest.fixture
def clean_preferences(saved_preferences):
    """Every CadRobot preference at its default for the test (restored afterwards)."""
    for name, value in preferences.DEFAULTS.items():
        preferences.set(name, value)
    yield


@pytest.fixture
def seam_cell(gui_doc, clean_preferences, monkeypatch):
    import seam_tracking_cell
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1325376000")       # 2012-01-01, the paper's year
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    cell = seam_tracking_cell.build(gui_doc)
    gui_doc.recompute()
    FreeCADGui.Selection.clearSelection()
    process_events()
    yield cell
    generate_panel.close_panel()
    process_events()


def open_generate():
    FreeCADGui.runCommand(NAME)
    process_events()
    panel = generate_panel.active_panel()
    assert panel is not None and FreeCADGui.Control.activeDialog()
    return panel


def files_in(folder):
    """{file name: bytes} of a folder (empty when it does not exist), but the list of
    a program's files (``.cadrobot-files-*``, fileio)."""
    if not os.path.isdir(folder):
        return {}
    result = {}
    for name in sorted(os.listdir(folder)):
        if name.startswith(".cadrobot-files-"):
            continue
        with open(os.path.join(folder, name), "rb") as handle:
            result[name] = handle.read()
    return result


def as_shown(files):
    """Files as a text view shows them (Qt shows CRLF line ends as new lines)."""
    return [(name, text.replace("\r\n", "\n")) for name, text in files]


def is_red(label):
    return "red" in label.styleSheet()


# --- the command -----------------------------------------------------------------------------

def test_generate_is_greyed_out_without_a_cell_and_sits_before_check(gui_doc):
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    process_events()
    command = FreeCADGui.Command.get(NAME)
    assert not command.isActive(), "no cell in the document yet"
    info = command.getInfo()
    assert info["pixmap"].endswith(NAME + ".svg") and os.path.isfile(info["pixmap"])
    assert info["menuText"] == "Generate program" and info["toolTip"] and info["statusTip"]
    toolbar = FreeCADGui.getMainWindow().findChild(QtGui.QToolBar, "CadRobot")
    texts = [a.text() for a in toolbar.actions()]
    assert texts.index("Generate program") < texts.index("Check cell")

    import seam_tracking_cell
    seam_tracking_cell.build(gui_doc)
    gui_doc.recompute()
    process_events()
    assert command.isActive()


# --- showing the program ---------------------------------------------------------------------

def test_panel_shows_the_cells_program_and_follows_the_chosen_post(seam_cell):
    panel = open_generate()
    assert panel.cell is seam_cell and panel.check_box.isChecked()
    assert panel.post() == "abb_rapid" == seam_cell.PostProcessor
    names = [panel.post_box.itemData(i) for i in range(panel.post_box.count())]
    assert names == api.post_names()
    # The document is unsaved and OutputFolder is empty: the home folder.
    assert panel.folder_edit.text() == os.path.expanduser("~")

    rapid = api.program_files(seam_cell)
    assert [name for name, _ in rapid] == ["SeamWeld.mod"]
    assert panel.files == rapid and panel.tab_texts() == as_shown(rapid)
    assert "MODULE SeamWeld" in rapid[0][1]
    view = panel.tabs.widget(0)
    assert view.isReadOnly() and QtGui.QFontInfo(view.font()).fixedPitch()
    assert not is_red(panel.message_label)

    panel.set_post("kuka_krl")
    process_events()
    krl = api.program_files(seam_cell, post="kuka_krl")
    assert [name for name, _ in krl] == [name for name, _ in panel.tab_texts()]
    assert {os.path.splitext(name)[1] for name, _ in krl} == {".src", ".dat"}
    assert "\r\n" in krl[0][1]                       # KRL files end lines with CRLF
    assert panel.files == krl and panel.tab_texts() == as_shown(krl)

    panel.set_post("abb_rapid")
    panel.options_edit.setText("path_correction=true")
    panel.options_edit.editingFinished.emit()
    process_events()
    corrected = api.program_files(seam_cell, options={"path_correction": True})
    assert panel.files == corrected and panel.tab_texts() == as_shown(corrected)
    assert corrected != rapid


def test_refresh_shows_the_program_after_the_document_changed(seam_cell):
    panel = open_generate()
    seam_cell.ProgramName = "SeamWeld2"           # edited in the property editor
    seam_cell.Document.recompute()
    assert [name for name, _ in panel.files] == ["SeamWeld.mod"]
    panel.refresh_button.click()
    process_events()
    assert [name for name, _ in panel.files] == ["SeamWeld2.mod"]
    assert panel.files == api.program_files(seam_cell)


def test_default_post_preference_applies_to_cells_in_their_robots_language(seam_cell):
    preferences.set("DefaultPost", "fanuc_ls")
    panel = open_generate()
    assert panel.post() == "fanuc_ls"
    fanuc = api.program_files(seam_cell, post="fanuc_ls")
    assert panel.files == fanuc and panel.tab_texts() == as_shown(fanuc)
    generate_panel.close_panel()
    seam_cell.PostProcessor = "ur_script"        # chosen for this cell: it wins
    assert open_generate().post() == "ur_script"


def test_bad_options_are_shown_in_red(seam_cell):
    panel = open_generate()
    panel.options_edit.setText("path_correction")
    panel.options_edit.editingFinished.emit()
    process_events()
    assert is_red(panel.message_label) and "key=value" in panel.message_label.text()
    assert panel.tabs.count() == 0


# --- writing ---------------------------------------------------------------------------------

def answer_question(monkeypatch, button):
    """Answer QMessageBox.question with `button`; returns the texts it was asked."""
    asked = []

    def question(parent, title, text, buttons, default):
        asked.append((title, text, default))
        return button
    monkeypatch.setattr(generate_panel.QtGui.QMessageBox, "question", staticmethod(question))
    return asked


def test_write_writes_what_api_export_writes_and_the_journal_replays_it(seam_cell, tmp_path,
                                                                        monkeypatch):
    answer_question(monkeypatch, QtGui.QMessageBox.Yes)    # KRL for the seam cell's ABB arm
    panel = open_generate()
    panel.set_post("kuka_krl")
    panel.folder_edit.setText(str(tmp_path / "panel"))
    written = panel.write()
    assert written == panel.written and not is_red(panel.message_label)
    expected = api.export(seam_cell, post="kuka_krl", output_dir=str(tmp_path / "api"))
    assert [os.path.basename(p) for p in written] == [os.path.basename(p) for p in expected]
    assert all(os.path.dirname(p) == str(tmp_path / "panel") for p in written)
    assert files_in(tmp_path / "panel") == files_in(tmp_path / "api")
    assert {name: data.decode() for name, data in files_in(tmp_path / "panel").items()} == dict(
        panel.files)
    for path in written:
        assert path in panel.message_label.text()

    # What the Write button journals, run as a macro would: the same files again.
    lines = generate_panel.export_lines(seam_cell, "kuka_krl", str(tmp_path / "macro"), {}, True)
    assert any("api.export(" in line for line in lines)
    namespace = {}
    exec("\n".join(lines), namespace)
    assert files_in(tmp_path / "macro") == files_in(tmp_path / "api")


def test_another_makers_post_is_written_only_after_a_yes(seam_cell, tmp_path, monkeypatch):
    """KRL for the seam cell's ABB IRB 2400: the question names both; No writes nothing,
    Yes writes the program, whose header says it too. (The robot's own post asks nothing:
    the other Write tests would wait on the question otherwise.)"""
    asked = answer_question(monkeypatch, QtGui.QMessageBox.No)
    panel = open_generate()
    panel.check_box.setChecked(False)                     # the question, not the check
    panel.set_post("kuka_krl")
    panel.folder_edit.setText(str(tmp_path))
    assert panel.write() is None and files_in(tmp_path) == {}
    assert "Nothing written" in panel.message_label.text()
    title, text, default = asked[0]
    assert text.startswith("Written for a KUKA controller, but the cell's robot is an "
                           "ABB IRB 2400/10 (ABB_IRB2400).")
    assert default == QtGui.QMessageBox.No
    answer_question(monkeypatch, QtGui.QMessageBox.Yes)
    assert [os.path.basename(p) for p in panel.write()] == ["SeamWeld.src", "SeamWeld.dat"]
    assert b"; Written for a KUKA KR C4 controller" in files_in(tmp_path)["SeamWeld.src"]


def test_ok_writes_and_closes(seam_cell, tmp_path):
    panel = open_generate()
    panel.folder_edit.setText(str(tmp_path))
    assert panel.accept() is True
    process_events()
    assert generate_panel.active_panel() is None and not FreeCADGui.Control.activeDialog()
    assert list(files_in(tmp_path)) == ["SeamWeld.mod"]


@pytest.mark.parametrize("where", ["PostFolder", "macro folder"])
def test_a_user_post_appears_and_writes_its_file(seam_cell, tmp_path, where):
    folder = tmp_path / "posts"
    folder.mkdir()
    (folder / "mybrand_post.py").write_text(readme_user_post())
    if where == "PostFolder":
        preferences.set("PostFolder", str(folder))
    else:
        FreeCAD.ParamGet(MACRO_PARAMS).SetString("MacroPath", str(folder))
        assert os.path.samefile(FreeCAD.getUserMacroDir(True), folder)
    assert "mybrand" in api.post_names()

    panel = open_generate()
    index = panel.post_box.findData("mybrand")
    assert index >= 0 and "user post" in panel.post_box.itemText(index)
    panel.set_post("mybrand")
    process_events()
    expected = api.program_files(seam_cell, post="mybrand")
    assert panel.files == expected and panel.tab_texts() == as_shown(expected)
    assert expected[0][0] == "SeamWeld.prg"
    # Independently: one line per move, each naming its motion type and speed.
    program = api.check(seam_cell).program
    lines = expected[0][1].splitlines()
    assert len(lines) == len(program.moves())
    assert [line.split()[0] for line in lines] == [m.kind.upper() for m in program.moves()]

    panel.folder_edit.setText(str(tmp_path / "out"))
    assert panel.write() == [str(tmp_path / "out" / "SeamWeld.prg")]
    assert files_in(tmp_path / "out") == {"SeamWeld.prg": expected[0][1].encode()}


# --- errors ----------------------------------------------------------------------------------

def test_a_path_that_lost_its_frame_is_shown_in_red_selected_and_nothing_written(seam_cell,
                                                                                   tmp_path):
    doc = seam_cell.Document
    path = doc.getObject("Seam")
    own = api.make_calibration_frame(doc, seam_cell, doc.getObject("TableFrame").Placement,
                                     name="SeamFrame")
    path.CalibrationFrame = own
    doc.recompute()
    assert api.program_files(seam_cell)         # the path's own frame works
    doc.removeObject("SeamFrame")
    doc.recompute()
    process_events()
    panel = open_generate()
    assert is_red(panel.message_label)
    assert "SeamFrame" in panel.message_label.text() and "deleted" in panel.message_label.text()
    assert panel.error.obj_name == path.Name and panel.tabs.count() == 0
    assert [o.Name for o in FreeCADGui.Selection.getSelection()] == [path.Name]
    assert "Traceback" not in panel.message_label.text()

    FreeCADGui.Selection.clearSelection()
    out = tmp_path / "out"
    panel.folder_edit.setText(str(out))
    assert panel.write() is None and panel.written == []
    assert not out.exists()
    assert is_red(panel.message_label)
    assert [o.Name for o in FreeCADGui.Selection.getSelection()] == [path.Name]
    assert panel.accept() is False and generate_panel.active_panel() is panel


def test_a_check_finding_blocks_writing_until_check_first_is_off(seam_cell, tmp_path):
    seam_cell.Placement.Base = FreeCAD.Vector(-5000, 0, 0)      # the robot cannot reach the part
    seam_cell.Document.recompute()
    process_events()
    panel = open_generate()
    assert is_red(panel.message_label) and "cannot run" in panel.message_label.text()
    # No command line to run (none exists for an Addon Manager user): every problem is listed here.
    text = panel.message_label.text()
    assert "cadrobot" not in text and "FreeCADCmd" not in text, text
    assert "Check cell lists all of them and colours the targets" in text
    details = panel.error.details        # the check's lines, the summary last
    assert len(details) >= 2 and details[0].startswith("SeamCell: ERROR: unreachable: ")
    assert details[-1].startswith("SeamCell: FAILED: ") and text.count("<br>SeamCell: ") == len(details)
    assert panel.tabs.count() == 0 and panel.error.obj_name == seam_cell.Name
    assert [o.Name for o in FreeCADGui.Selection.getSelection()] == [seam_cell.Name]
    panel.folder_edit.setText(str(tmp_path))
    assert panel.write() is None and files_in(tmp_path) == {}

    panel.check_box.setChecked(False)
    process_events()
    assert not is_red(panel.message_label)
    unchecked = api.program_files(seam_cell, check_first=False)
    assert panel.files == unchecked and panel.tab_texts() == as_shown(unchecked)
    assert [os.path.basename(p) for p in panel.write()] == ["SeamWeld.mod"]


# --- preferences -----------------------------------------------------------------------------

SETTINGS = {"DefaultRobot": "MOTOMAN_HP6", "DefaultPost": "ur_script", "OutputFolder": "/tmp/cr-out",
            "ApproachDistance": 75.5, "InterpolationStep": 2.25, "RiskThreshold": 12.5}


def test_preferences_page_loads_and_saves_every_setting(saved_preferences, tmp_path):
    group = FreeCAD.ParamGet(preferences.PATH)
    for name, value in SETTINGS.items():
        preferences.set(name, value)
    preferences.set("PostFolder", str(tmp_path))
    page = preferences_page.CadRobotPreferencesPage()
    page.loadSettings()
    assert page.robot_box.itemData(page.robot_box.currentIndex()) == "MOTOMAN_HP6"
    assert page.post_box.itemData(page.post_box.currentIndex()) == "ur_script"
    assert page.post_box.itemData(0) == ""          # the robot's own language
    assert [page.robot_box.itemData(i) for i in range(page.robot_box.count())] == api.robot_names()
    assert page.output_edit.text() == "/tmp/cr-out" and page.post_folder_edit.text() == str(tmp_path)
    for name in ("ApproachDistance", "InterpolationStep", "RiskThreshold"):
        assert page.number_boxes[name].value() == pytest.approx(SETTINGS[name])

    # A user post in the folder typed is offered at once.
    (tmp_path / "mybrand_post.py").write_text(readme_user_post())
    page.post_folder_edit.editingFinished.emit()
    assert page.post_box.findData("mybrand") > 0
    assert page.post_box.itemData(page.post_box.currentIndex()) == "ur_script"

    page.robot_box.setCurrentIndex(page.robot_box.findData("KUKA_KR16"))
    page.post_box.setCurrentIndex(page.post_box.findData("mybrand"))
    page.output_edit.setText("/tmp/cr-programs")
    assert page.robot_folder_edit.text() == ""       # the default folder
    page.robot_folder_edit.setText(str(tmp_path / "team robots"))
    page.number_boxes["ApproachDistance"].setValue(20.0)
    page.number_boxes["InterpolationStep"].setValue(0.0)
    page.number_boxes["RiskThreshold"].setValue(45.0)
    page.saveSettings()
    assert group.GetString("DefaultRobot") == "KUKA_KR16"
    assert group.GetString("DefaultPost") == "mybrand"
    assert group.GetString("OutputFolder") == "/tmp/cr-programs"
    assert group.GetString("PostFolder") == str(tmp_path)
    assert preferences.user_robot_folder() == str(tmp_path / "team robots")
    assert group.GetFloat("ApproachDistance") == 20.0
    assert group.GetFloat("InterpolationStep") == 0.0
    assert group.GetFloat("RiskThreshold") == 45.0
    assert page.number_boxes["InterpolationStep"].text() == "speed \u00d7 sample time"

    page.post_box.setCurrentIndex(0)
    page.saveSettings()
    assert group.GetString("DefaultPost") == ""


def test_output_folder_is_the_documents_folder_unless_the_preference_is_set(seam_cell, tmp_path):
    (tmp_path / "doc").mkdir()
    seam_cell.Document.saveAs(str(tmp_path / "doc" / "cell.FCStd"))
    assert open_generate().folder_edit.text() == str(tmp_path / "doc")
    generate_panel.close_panel()
    preferences.set("OutputFolder", str(tmp_path / "programs"))
    assert open_generate().folder_edit.text() == str(tmp_path / "programs")


def test_preferences_page_is_in_the_preferences_dialog(saved_preferences):
    """Edit -> Preferences has the CadRobot page (registered at start-up)."""
    found = {}

    def inspect_and_close():
        dialog = QtGui.QApplication.activeModalWidget()
        if dialog is None:
            QtCore.QTimer.singleShot(100, inspect_and_close)
            return
        page = dialog.findChild(QtGui.QWidget, "CadRobotPreferences")
        found["page"] = page is not None
        if page is not None:
            found["robot"] = page.findChild(QtGui.QComboBox) is not None
        dialog.reject()

    QtCore.QTimer.singleShot(200, inspect_and_close)
    FreeCADGui.runCommand("Std_DlgPreferences")
    process_events()
    assert found.get("page"), "no CadRobot page in Edit -> Preferences"
    assert found.get("robot")
