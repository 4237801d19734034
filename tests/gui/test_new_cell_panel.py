"""The New cell panel with the full catalog: maker filter, search, the table, the
description of robots without a post, URDF import from the panel, the preview of a
table robot and the panel's size in FreeCAD's narrow task panel.

Screenshots of the panel (``form.grab()``) and of the 3D view go to pytest's tmp_path.
"""

import os
import shutil

import pytest

import FreeCADGui
from PySide import QtCore, QtGui

from conftest import REPO, close_panels, process_events
from test_robot_display import floor, robots_drawn, top_pixels

from CadRobotWB import api, preferences
from CadRobotWB.gui import new_cell_panel
from CadRobotWB.robots.catalog import catalog
from CadRobotWB.objects import base as objects_base
from required import ROBOT_DATA as DATA

#: What a FreeCAD task panel gets on a 1366x768 screen: the combo view is about 300-400
#: px wide; below the menu, toolbars, the panel's own title and OK/Cancel buttons and
#: above the status bar and a desktop task bar, about 500 px of height are left.
#: FreeCAD 0.20's default combo view leaves a task panel about 225 px: the panel must
#: shrink to that without clipping.
MAX_WIDTH_PX, MAX_HEIGHT_PX, MIN_WIDTH_PX = 400, 500, 225


@pytest.fixture
def panel(gui_doc):
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    close_panels()
    FreeCADGui.Selection.clearSelection()
    opened = new_cell_panel.open_panel(gui_doc)
    process_events()
    yield opened
    close_panels()


@pytest.fixture
def robot_folder(tmp_path, monkeypatch):
    """The user robot folder is a fresh tmp folder for the test, restored afterwards.

    Set before the panel opens (tests name it before ``panel``), so the panel's robot list
    is read from the same folder as after an import, whatever the user has imported."""
    saved = preferences.get("UserRobotFolder")
    folder = tmp_path / "user_robots"
    folder.mkdir()
    monkeypatch.delenv(preferences.ROBOT_FOLDER_VARIABLE, raising=False)
    preferences.set("UserRobotFolder", str(folder))
    preferences.use_user_robot_folder()
    try:
        yield folder
    finally:
        preferences.set("UserRobotFolder", saved)
        monkeypatch.undo()
        preferences.use_user_robot_folder()
        catalog.forget_user_robots()


def copy_robot(folder, tmp_path):
    """A copy of the data folder's `folder` (URDF and its collision meshes) under tmp_path."""
    target = tmp_path / folder
    shutil.copytree(os.path.join(DATA, folder), str(target))
    return str(target / "robot.urdf")


def save_panel(panel, path):
    process_events()
    assert panel.form.grab().save(str(path)), path


def test_the_table_lists_every_robot_with_maker_model_payload_and_reach(panel, tmp_path):
    assert sorted(panel.visible_robots()) == sorted(api.robot_names())
    assert len(panel.visible_robots()) >= 150
    header = panel.robots.headerItem()
    assert [header.text(c) for c in range(panel.robots.columnCount())] == [
        "Name", "kg", "Reach", "Maker", "Model"]
    assert panel.robot_name() == preferences.get("DefaultRobot")
    rows = {panel.robots.topLevelItem(i).text(0): panel.robots.topLevelItem(i)
            for i in range(panel.robots.topLevelItemCount())}
    gp25 = rows["MOTOMAN_GP25"]
    assert [gp25.text(c) for c in range(5)] == [
        "MOTOMAN_GP25", "25", "%.0f" % catalog.get("MOTOMAN_GP25").reach_mm, "Yaskawa Motoman",
        "GP25"]
    assert rows["STAUBLI_TX2_60"].text(1) == "\u2014"                 # payload unknown
    assert rows["KUKA_KR16"].text(2) == "%.0f" % new_cell_panel.reach_mm("KUKA_KR16")
    # Sorting by payload (a number, the unknown ones first), by reach, and back by name.
    panel.robots.sortByColumn(1, QtCore.Qt.AscendingOrder)
    payloads = [panel.robots.topLevelItem(i).text(1) for i in range(panel.robots.topLevelItemCount())]
    unknown = payloads.count("\u2014")
    assert unknown > 0 and set(payloads[:unknown]) == {"\u2014"}
    known = [float(p.split()[0]) for p in payloads[unknown:]]
    assert known == sorted(known) and known[0] < known[-1]
    panel.robots.sortByColumn(2, QtCore.Qt.DescendingOrder)
    reaches = [float(panel.robots.topLevelItem(i).text(2).split()[0])
               for i in range(panel.robots.topLevelItemCount())]
    assert reaches == sorted(reaches, reverse=True)
    panel.robots.sortByColumn(0, QtCore.Qt.AscendingOrder)
    assert panel.visible_robots() == sorted(panel.visible_robots(), key=str.lower)
    save_panel(panel, tmp_path / "panel_all.png")


def test_filter_by_maker_and_search(panel, tmp_path):
    assert panel.maker.itemText(0) == "All makers"
    assert {"ABB", "KUKA", "FANUC", "Yaskawa Motoman", "Staubli", "Universal Robots",
            "Kawasaki", "DENSO"} <= set(panel.makers())
    assert panel.set_maker_filter("KUKA")
    kuka = panel.visible_robots()
    assert len(kuka) > 10
    assert all(catalog.get(name).manufacturer == "KUKA" for name in kuka)
    assert sorted(kuka) == sorted(n for n in api.robot_names()
                                  if catalog.get(n).manufacturer == "KUKA")
    assert catalog.get(panel.robot_name()).manufacturer == "KUKA"     # the choice follows
    save_panel(panel, tmp_path / "panel_kuka.png")
    panel.set_maker_filter("")
    # Typing filters at once; any case; name, maker or model.
    panel.search.setFocus()
    type_keys(panel.search, "gp25")
    assert panel.visible_robots() == ["MOTOMAN_GP25"]
    assert panel.robot_name() == "MOTOMAN_GP25"
    panel.set_search("Universal")                                     # a maker
    assert panel.visible_robots() and all(n.startswith("UR") for n in panel.visible_robots())
    panel.set_search("kr 16")                                         # a model, not a name
    assert "KUKA_KR16" in panel.visible_robots()
    panel.set_maker_filter("ABB")
    panel.set_search("kr 16")
    assert panel.visible_robots() == []                               # both filters apply
    panel.set_search("")
    assert all(catalog.get(n).manufacturer == "ABB" for n in panel.visible_robots())


def type_keys(widget, text):
    """Type `text` into `widget` key by key, as a user does."""
    for char in text:
        event = QtGui.QKeyEvent(QtCore.QEvent.KeyPress, 0, QtCore.Qt.NoModifier, char)
        QtGui.QApplication.sendEvent(widget, event)
    process_events()


def test_a_searched_robot_makes_the_cell_with_its_makers_post(panel, gui_doc):
    panel.set_search("gp25")
    assert panel.visible_robots() == ["MOTOMAN_GP25"]
    panel.select_robot("MOTOMAN_GP25")
    text = panel.description.text()
    assert "Yaskawa Motoman GP25" in text and "payload 25 kg" in text.lower()
    assert "programs in motoman_inform" in text and "Source:" in text
    before = {o.Name for o in gui_doc.Objects}
    assert panel.accept()
    process_events()
    assert new_cell_panel.active_panel() is None
    cell, = [o for o in gui_doc.Objects if o.Name not in before
             and objects_base.type_of(o) == "Cell"]
    assert cell.Robot == "MOTOMAN_GP25" and cell.PostProcessor == "motoman_inform"


def test_a_staubli_arm_says_cadrobot_has_no_post_for_it(panel, tmp_path):
    panel.select_robot("STAUBLI_TX2_60")
    text = panel.description.text()
    print(text)
    assert "CadRobot has no post-processor for Staubli's VAL3 yet" in text
    assert "Generate panel" in text and "PostProcessor" in text
    assert "payload not given by the maker's designation" in text.lower()
    assert "reach about" in text
    save_panel(panel, tmp_path / "panel_staubli.png")
    panel.select_robot("KAWASAKI_RS013N")
    assert "no post-processor for Kawasaki's AS" in panel.description.text()
    panel.select_robot("ABB_IRB2400")                                 # a hand-written robot
    assert "Controller S4C+ / IRC5, payload 10 kg" in panel.description.text()
    assert "no post-processor" not in panel.description.text()


def test_importing_a_urdf_adds_it_to_the_table_and_chooses_it(robot_folder, panel, tmp_path,
                                                              monkeypatch):
    urdf = copy_robot("staubli_tx2_60", tmp_path)
    lines = []
    original = FreeCADGui.doCommand
    monkeypatch.setattr(FreeCADGui, "doCommand", lambda line: (lines.append(line), original(line))[1])
    before = panel.visible_robots()
    # Its own name ships with CadRobot: a clear red line, nothing added.
    assert panel.import_file(urdf) is None
    assert "ships with CadRobot" in panel.message.text() and "red" in panel.message.styleSheet()
    assert "Traceback" not in panel.message.text() and "\n" not in panel.message.text()
    assert panel.visible_robots() == before and panel.suggested_name() == "MY_STAUBLI_TX2_60"
    # Under another name.
    panel.set_maker_filter("KUKA")                                    # hides a Staubli arm
    assert panel.import_file(urdf, name="MY_TX60") == "MY_TX60"
    assert panel.robot_name() == "MY_TX60" and "MY_TX60" in panel.visible_robots()
    assert sorted(panel.visible_robots()) == sorted(before + ["MY_TX60"])
    assert "Staubli" in panel.makers()
    assert "Imported MY_TX60" in panel.message.text() and "red" not in panel.message.styleSheet()
    assert "MY_TX60" in api.robot_names() and any(robot_folder.iterdir())
    assert "robot = api.import_robot(%r, name='MY_TX60')" % urdf in lines
    assert panel.preview is not None and panel.preview.model.spec.name == "MY_TX60"
    save_panel(panel, tmp_path / "panel_imported.png")
    print(panel.message.text())


def test_the_import_button_asks_for_another_name_when_the_name_is_taken(
        robot_folder, panel, tmp_path, monkeypatch):
    urdf = copy_robot("staubli_tx2_60", tmp_path)
    asked = []
    monkeypatch.setattr(QtGui.QFileDialog, "getOpenFileName",
                        staticmethod(lambda *args, **kw: (urdf, "")))
    monkeypatch.setattr(QtGui.QInputDialog, "getText", staticmethod(
        lambda parent, title, label, mode, text: (asked.append(text), ("MY_TX60", True))[1]))
    panel.import_button.click()
    process_events()
    assert asked == ["MY_STAUBLI_TX2_60"]
    assert panel.robot_name() == "MY_TX60"


def test_importing_an_arm_of_no_class_shows_why_and_adds_nothing(robot_folder, panel, tmp_path):
    urdf = copy_robot("fanuc_crx10ial", tmp_path)
    with open(urdf, encoding="utf-8") as stream:      # axis 3 tilted 0.1 rad against axis 2
        text = stream.read().replace('<origin rpy="0 0 0" xyz="0 0 0.710"/>',
                                     '<origin rpy="0.1 0 0" xyz="0 0 0.710"/>', 1)
    with open(urdf, "w", encoding="utf-8") as stream:
        stream.write(text)
    before, chosen = panel.visible_robots(), panel.robot_name()
    assert panel.import_file(urdf, name="MY_CRX") is None
    text = panel.message.text()
    assert "not an offset-wrist arm (" in text and "red" in panel.message.styleSheet()
    assert "Traceback" not in text
    assert panel.visible_robots() == before and panel.robot_name() == chosen
    assert "MY_CRX" not in api.robot_names() and list(robot_folder.iterdir()) == []


def test_the_preview_of_a_table_robot_draws_its_meshes(panel, gui_doc, tmp_path):
    floor(gui_doc, -2000.0, 2000.0, -2000.0, 2000.0)
    assert catalog.get("MOTOMAN_GP25").meshes
    panel.select_robot("MOTOMAN_GP25")
    process_events()
    assert robots_drawn(gui_doc) == 1 and panel.preview.model.spec.name == "MOTOMAN_GP25"
    pixels = top_pixels(gui_doc, tmp_path, "preview_gp25")
    print("GP25 preview pixels:", int(pixels.sum()))
    assert pixels.sum() > 300


def test_the_list_has_the_offset_wrist_cobots_and_draws_one(panel, gui_doc, tmp_path):
    """Issue 24: the CRX-10iA/L (kind 'chain', simple solids: no meshes in its data) is listed
    and previewed like any arm."""
    floor(gui_doc, -2000.0, 2000.0, -2000.0, 2000.0)
    assert {"FANUC_CRX10IAL", "MOTOMAN_HC10", "ABB_CRB15000_5_95"} <= set(panel.visible_robots())
    panel.select_robot("FANUC_CRX10IAL")
    process_events()
    assert robots_drawn(gui_doc) == 1 and panel.preview.model.kind == "chain"
    pixels = top_pixels(gui_doc, tmp_path, "preview_crx")
    print("CRX preview pixels:", int(pixels.sum()))
    assert pixels.sum() > 300


def test_the_panel_fits_a_1366x768_screen(panel, tmp_path):
    sizes = {}
    for robot in ("KUKA_KR16", "ABB_IRB2400", "STAUBLI_TX2_60", "MOTOMAN_GP25", "UR5E"):
        panel.select_robot(robot)
        process_events()
        hint, least = panel.form.sizeHint(), panel.form.minimumSizeHint()
        sizes[robot] = (hint.width(), hint.height(), least.width(), least.height())
    print("sizeHint, minimumSizeHint:", sizes)
    for robot, (width, height, least_width, _least_height) in sizes.items():
        assert width <= MAX_WIDTH_PX and height <= MAX_HEIGHT_PX, (robot, width, height)
        assert least_width <= MIN_WIDTH_PX, (robot, least_width)
    # Laid out 350 px wide (FreeCAD's combo view) with the longest description, it
    # needs no more height.
    panel.select_robot("KUKA_KR16")
    layout = panel.form.layout()
    height = layout.totalHeightForWidth(350) if layout.hasHeightForWidth() else \
        panel.form.sizeHint().height()
    print("height for 350 px width:", height)
    assert height <= MAX_HEIGHT_PX
    save_panel(panel, tmp_path / "panel_350.png")


def test_the_panel_in_a_1366x768_main_window(gui_doc, tmp_path):
    """The panel in FreeCAD's combo view of a 1366x768 main window: screenshot, and how
    much of it the task view has to scroll (printed)."""
    import time
    window = FreeCADGui.getMainWindow()
    saved = window.size()
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    close_panels()
    try:
        window.showNormal()
        window.resize(1366, 768)
        start = time.perf_counter()
        panel = new_cell_panel.open_panel(gui_doc)
        process_events()
        print("panel opened in %.2f s" % (time.perf_counter() - start))
        panel.select_robot("STAUBLI_TX2_60")
        process_events()
        parent, scrolled = panel.form.parentWidget(), None
        while parent is not None:
            if isinstance(parent, QtGui.QScrollArea) and scrolled is None:
                scrolled = parent
            parent = parent.parentWidget()
        print("form %dx%d in a task view of %dx%d; it scrolls %d px" % (
            panel.form.width(), panel.form.height(), scrolled.viewport().width(),
            scrolled.viewport().height(), scrolled.verticalScrollBar().maximum()))
        assert panel.form.width() >= 200
        right = panel.form.mapTo(scrolled.viewport(), QtCore.QPoint(panel.form.width(), 0)).x()
        print("the panel's right edge at %d px of the task view's %d" % (
            right, scrolled.viewport().width()))
        assert right <= scrolled.viewport().width(), "clipped on the right"
        # The combo view dragged to 400 px: name, payload and reach in view.
        dock = [d for d in window.findChildren(QtGui.QDockWidget) if scrolled in
                d.findChildren(QtGui.QScrollArea)]
        if dock:
            window.resizeDocks(dock, [400], QtCore.Qt.Horizontal)
            process_events()
            tree = panel.robots
            shown = tree.header().sectionViewportPosition(2) + tree.columnWidth(2)
            print("at 400 px: form %d px wide, Reach ends at %d of %d px" % (
                panel.form.width(), shown, tree.viewport().width()))
            assert shown <= tree.viewport().width()
            assert window.grab().save(str(tmp_path / "main_window_wider_dock.png"))
        assert window.grab().save(str(tmp_path / "main_window_1366x768.png"))
    finally:
        close_panels()
        window.resize(saved)


def test_the_base_starts_beside_the_part_and_keeps_what_the_user_types(gui_doc):
    """Hand-derived (tests/app/test_default_base.py): the angle cleat's solids centre
    (150, 125) mm, top 60 mm; IRB 2400 a1 + far / 2 = 100 + (705 + hypot(135, 755)) / 2 =
    835.99 mm in front (-Y), shoulder (615 mm) level with the top; KR 16: 260 + (680 +
    hypot(35, 670)) / 2 = 935.46 mm, shoulder 675 mm."""
    from angle_cleat import cleat_on_plate
    cleat_on_plate(gui_doc)
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    close_panels()
    FreeCADGui.Selection.clearSelection()
    panel = new_cell_panel.open_panel(gui_doc)
    try:
        panel.select_robot("ABB_IRB2400")

        def boxes():
            return [b.value() for b in (panel.x, panel.y, panel.z, panel.rotation)]
        assert boxes() == pytest.approx([150.0, -710.987, -555.0, 90.0], abs=1e-3)
        assert panel.base_is_default() and "beside the part" in panel.message.text()
        panel.select_robot("KUKA_KR16")             # the default follows the robot's reach
        assert boxes() == pytest.approx([150.0, -810.458, -615.0, 90.0], abs=1e-3)
        panel.x.setValue(-400.0)                     # typed: kept when the robot changes
        panel.select_robot("ABB_IRB2400")
        assert not panel.base_is_default()
        assert boxes() == pytest.approx([-400.0, -810.458, -615.0, 90.0], abs=1e-3)
        assert panel.accept()
        process_events()
        cell, = objects_base.objects_of_type(gui_doc, "Cell")
        base = cell.Placement.Base
        assert (base.x, base.y, base.z) == pytest.approx((-400.0, -810.458, -615.0), abs=1e-3)
    finally:
        close_panels()
