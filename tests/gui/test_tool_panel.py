"""The Tool group of the New cell panel, the Edit tool panel and command, and tool
markers drawing the cell's tool in the GUI."""

import numpy as np
import pytest

import FreeCAD
import FreeCADGui

from conftest import close_panels, process_events

from CadRobotWB import api
from CadRobotWB.commands import TOOLBARS
from CadRobotWB.gui import new_cell_panel, tool_group
from CadRobotWB.objects.convert import matrix_from_placement
from CadRobotWB.robots.catalog import tools

V = FreeCAD.Vector

#: The New cell panel's height must fit a 1366x768 screen (test_new_cell_panel.py).
MAX_HEIGHT_PX = 500


@pytest.fixture
def panel(gui_doc):
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    close_panels()
    FreeCADGui.Selection.clearSelection()
    opened = new_cell_panel.open_panel(gui_doc)
    process_events()
    yield opened
    close_panels()
    FreeCADGui.Selection.clearSelection()


def test_the_panel_offers_the_library_with_the_straight_torch_first(panel, gui_doc):
    group = panel.tool
    items = [group.choice.itemText(i) for i in range(group.choice.count())]
    assert items == tools.names() + ["Solid from the document\u2026"]
    assert group.tool_name() == "Straight torch"
    assert group.description.text() == tools.get("Straight torch").description
    assert group.numbers()[:3] == (0.0, 0.0, 385.0) and group.numbers()[6] == pytest.approx(1.851)
    assert group.details.isHidden()                 # folded: the panel stays short
    # The default journals a plain make_cell; the cell carries the torch.
    assert panel.journal_lines() == [panel.journal_line()] and "tool=" not in panel.journal_line()
    cell = panel.create()
    assert cell.ToolType == "Straight torch" and cell.ToolTCP.Base == V(0, 0, 385)


def test_the_panel_creates_a_cell_with_the_chosen_library_tool(panel, gui_doc):
    panel.tool.set_tool("Deburring spindle")
    assert "spindle" in panel.tool.description.text().lower()
    assert panel.tool.numbers()[:3] == (50.0, 0.0, 270.0)
    assert "tool='Deburring spindle'" in panel.journal_line() and len(panel.journal_lines()) == 1
    cell = panel.create()
    assert cell.ToolType == "Deburring spindle"
    assert cell.ToolMass == pytest.approx(tools.get("Deburring spindle").mass_kg)


def test_changed_numbers_are_journaled_as_set_tool(panel, gui_doc):
    panel.tool.set_tool("Bent torch")
    panel.tool.show_details()
    assert not panel.tool.details.isHidden()
    panel.tool.mass.setValue(2.4)
    panel.tool.cog[2].setValue(150.0)
    lines = panel.journal_lines()
    assert len(lines) == 2 and lines[1].startswith("api.set_tool(cell, tool='Bent torch'")
    cell = panel.create()
    assert cell.ToolType == "Bent torch" and cell.ToolMass == 2.4
    assert tuple(cell.ToolCenterOfGravity)[2] == pytest.approx(150.0)
    # The TCP kept the library's (22 degrees about Y) through the boxes.
    np.testing.assert_allclose(matrix_from_placement(cell.ToolTCP), tools.get("Bent torch").T_f_t,
                               atol=1e-3)


def test_a_solid_of_the_document_as_the_tool(panel, gui_doc):
    block = gui_doc.addObject("Part::Box", "Gripper")
    block.Length, block.Width, block.Height = 40, 40, 150
    block.Placement = FreeCAD.Placement(V(300, 0, 0), FreeCAD.Rotation())
    gui_doc.recompute()
    # Chosen with nothing selected: it says what to do, and OK refuses with that.
    panel.tool.set_tool(tools.CUSTOM)
    assert panel.tool.body is None and "Select a solid" in panel.tool.description.text()
    assert panel.create() is None and "tool body" in panel.message.text()
    top = max(range(len(block.Shape.Vertexes)),                  # the corner (340, 40, 150)
              key=lambda k: tuple(block.Shape.Vertexes[k].Point)[::-1])
    FreeCADGui.Selection.addSelection(gui_doc.Name, block.Name, "Vertex%d" % (top + 1))
    assert panel.tool.take_selected_solid() and panel.tool.body == block
    assert panel.tool.take_selected_point()
    assert panel.tool.numbers()[:3] == pytest.approx((40.0, 40.0, 150.0))
    panel.tool.tcp_xyz[0].setValue(20.0)
    panel.tool.tcp_xyz[1].setValue(20.0)
    panel.tool.mass.setValue(1.5)
    line = panel.journal_lines()[1]
    assert "body=FreeCAD.getDocument(%r).getObject('Gripper')" % gui_doc.Name in line
    cell = panel.create()
    assert cell.ToolType == "Custom body" and cell.ToolBody == block and cell.ToolMass == 1.5
    assert cell.ToolTCP.Base == V(20, 20, 150)


def test_the_panel_with_the_tool_group_fits_a_1366x768_screen(panel, tmp_path):
    height = panel.form.layout().totalHeightForWidth(350) \
        if panel.form.layout().hasHeightForWidth() else panel.form.sizeHint().height()
    print("New cell panel height at 350 px with the tool group folded:", height)
    assert height <= MAX_HEIGHT_PX
    assert panel.form.minimumSizeHint().width() <= 225
    assert panel.form.grab().save(str(tmp_path / "new_cell_with_tool.png"))


def test_edit_tool_command_and_markers_follow_the_tool(gui_doc, tmp_path):
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    close_panels()
    assert "CadRobot_EditTool" in TOOLBARS[0][1]
    assert "CadRobot_EditTool" in FreeCADGui.listCommands()
    cell = api.make_cell(gui_doc)
    marker = api.make_tool_marker(gui_doc, cell, FreeCAD.Placement(
        V(0, 0, 0), FreeCAD.Rotation(V(1, 0, 0), 180)))          # pointing down at the origin
    box = marker.Shape.BoundBox
    assert (box.ZMin, box.ZMax) == pytest.approx((0.0, 385.0), abs=1e-6)
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(gui_doc.Name, cell.Name)
    FreeCADGui.runCommand("CadRobot_EditTool")
    process_events()
    edit = tool_group.active_panel()
    try:
        assert edit is not None and edit.cell == cell
        assert edit.group.tool_name() == "Straight torch" and not edit.group.details.isHidden()
        edit.group.set_tool("Ball tool")
        assert edit.journal_lines() == ["api.set_tool(FreeCAD.getDocument(%r).getObject(%r), "
                                        "tool='Ball tool')" % (gui_doc.Name, cell.Name)]
        assert edit.form.grab().save(str(tmp_path / "edit_tool.png"))
        assert edit.accept()
    finally:
        close_panels()
    assert cell.ToolType == "Ball tool"
    box = marker.Shape.BoundBox
    assert (box.ZMin, box.ZMax, box.XLength) == pytest.approx((0.0, 210.0, 80.0), abs=1e-6)
    # One undo step brings the torch back.
    gui_doc.undo()
    gui_doc.recompute()
    assert cell.ToolType == "Straight torch"
    assert marker.Shape.BoundBox.ZMax == pytest.approx(385.0, abs=1e-6)
