"""Issue 14 in the window: the robot drawn where a taught frame puts it, Place robot
saying what a taught frame fixes, and a failed check offering Place robot."""

import numpy as np
import pytest

import FreeCAD
import FreeCADGui

from conftest import close_panels, process_events
from test_robot_display import centroid, display, floor, top_pixels
from CadRobotWB import api
from CadRobotWB.commands import check as check_command
from CadRobotWB.gui import place_panel, triad_display
from CadRobotWB.gui.robot_view import matrix_from_transform

V = FreeCAD.Vector
#: The real part lies this far along +X of the robot from where it is drawn, mm.
SHIFT_MM = 400.0


@pytest.fixture
def clean(gui_doc):
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    close_panels()
    yield gui_doc
    place_panel.close_panel()
    close_panels()


def taught_cell(doc):
    """A robot at {U}'s origin, its frame drawn 1000 mm ahead and taught SHIFT_MM further."""
    cell = api.make_cell(doc)
    frame = api.make_calibration_frame(doc, cell, FreeCAD.Placement(V(1000, 0, 0), FreeCAD.Rotation()),
                                       name="Corner")
    doc.recompute()
    return cell, frame


def teach(frame):
    cad = [(1000, 0, 0), (1100, 0, 0), (1000, 100, 0), (1000, 0, 50)]
    measured = [(x + SHIFT_MM, y, z) for x, y, z in cad]
    api.teach_calibration_frame(frame, [V(*p) for p in cad], [V(*p) for p in measured])
    frame.Document.recompute()
    process_events()


def test_a_taught_frame_draws_the_robot_at_its_effective_base(clean, tmp_path):
    doc = clean
    cell, frame = taught_cell(doc)
    floor(doc, -1500, 1800, -900, 900)
    shown = display(cell)
    assert shown.base_switch.whichChild.getValue() != 0             # no drawn-base triad yet
    drawn = centroid(top_pixels(doc, tmp_path, "drawn"))

    teach(frame)
    # The part is SHIFT_MM further from the robot than drawn: relative to the drawn part,
    # the robot stands SHIFT_MM further back (-X).
    np.testing.assert_allclose(shown.T_u_r[:3, 3], [-SHIFT_MM, 0, 0], atol=1e-6)
    np.testing.assert_allclose(matrix_from_transform(shown.robot.base)[:3, 3], [-SHIFT_MM, 0, 0],
                               atol=1e-3)
    assert shown.base_switch.whichChild.getValue() == 0            # the dashed drawn base
    assert "drawn base (taught frame in use)" in triad_display.texts_in(shown.base_switch)
    moved = centroid(top_pixels(doc, tmp_path, "taught", fit=False))
    # 3300 mm of floor over 480 px: 400 mm is about 58 px to the left.
    assert moved[0] < drawn[0] - 35, (drawn, moved)
    assert abs(moved[1] - drawn[1]) < 8, (drawn, moved)

    # Moving the robot while the taught frame holds: said once, in the status bar too.
    from CadRobotWB.objects import cell as cell_module
    cell_module._told.discard((doc.Name, cell.Name))
    cell.Placement = FreeCAD.Placement(V(0, 300, 0), FreeCAD.Rotation())
    # read at once: FreeCAD 1.1's recompute writes its own status line over it
    status = FreeCADGui.getMainWindow().statusBar().currentMessage()
    doc.recompute()
    process_events()
    # (the status bar may elide the middle of the long line; the Report view has all of it)
    assert "Calibration frame 'Corner' is taught (UseTaught)" in status, status
    assert status.endswith("then teach the frame again."), status
    np.testing.assert_allclose(shown.T_u_r[:3, 3], [-SHIFT_MM, 0, 0], atol=1e-6)   # unmoved
    cell.Placement = FreeCAD.Placement()
    doc.recompute()

    frame.UseTaught = False
    doc.recompute()
    process_events()
    np.testing.assert_allclose(shown.T_u_r, np.eye(4), atol=1e-9)
    assert shown.base_switch.whichChild.getValue() != 0
    back = centroid(top_pixels(doc, tmp_path, "untaught", fit=False))
    assert abs(back[0] - drawn[0]) < 3


def test_place_robot_panel_says_what_a_taught_frame_fixes(clean):
    cell, frame = taught_cell(clean)
    teach(frame)
    panel = place_panel.open_panel(cell)
    process_events()
    text = panel.message.text()
    assert "'Corner' is taught (UseTaught): it fixes the part relative to the robot" in text
    assert "turn UseTaught off on 'Corner'" in text
    assert not panel.search_button.isEnabled()


def test_a_failed_check_offers_place_robot(clean):
    import seam_tracking_cell
    cell = seam_tracking_cell.build(clean)
    cell.Placement = FreeCAD.Placement(V(-1500, 0, 0), FreeCAD.Rotation())
    clean.recompute()
    box = check_command.CheckCommand().run(cell)
    process_events()
    assert "Cycle time" not in box.text()
    buttons = {b.text(): b for b in box.buttons()}
    assert "Place robot..." in buttons, list(buttons)
    buttons["Place robot..."].click()
    process_events()
    panel = place_panel.active_panel()
    assert panel is not None and panel.cell is cell
    assert panel.search_button.isEnabled()
