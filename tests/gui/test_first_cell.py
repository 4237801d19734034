"""A new user's first cell on FreeCAD's own Drilling_1 part, with the defaults, through the GUI.

examples/first_cell.py (``make demo`` runs it) clicks through New cell, Calibration
frame, Mark path on the top face, Tool markers, Check, Place robot, Risk areas,
Check, Generate, Simulate and Sensor run in a 1366x768 window. This test runs it
and checks what a user would see at each step.
"""

import os

import pytest
from PySide import QtGui

from rapid_check import assert_rapid_ok

import first_cell


@pytest.fixture(scope="module")
def made(tmp_path_factory):
    try:
        first_cell.shipped_part()
    except FileNotFoundError as err:
        pytest.skip(str(err))
    return first_cell.run(str(tmp_path_factory.mktemp("first_cell")))


def test_the_new_cell_has_a_torch_and_the_path_is_the_top_face_outline(made):
    cell, path = made["cell"], made["path"]
    assert cell.ToolType == "Straight torch" and cell.ToolTCP.Base.Length > 300.0
    assert path.SegmentCount == 15 and abs(float(path.PathLength) - 803.7) < 0.5


def test_the_first_check_passes_where_the_new_cell_put_the_robot(made):
    """Beside the part by default (issue 20), the torch turning with the arcs: no advice needed."""
    first = made["first_check"]
    assert first.ok, "\n".join(first.lines())
    assert first.lines()[-1].startswith("Cell: Cycle time: ")


def test_place_robot_then_the_check_passes(made):
    checked = made["check"]
    assert checked.ok, "\n".join(checked.lines())
    assert checked.lines()[-1].startswith("Cell: Cycle time: ")
    base = made["cell"].Placement.Base
    assert (base.x, base.y, base.z) != (0.0, 0.0, 0.0), "the robot still stands at the origin"


def test_the_program_is_written_and_valid_rapid(made):
    [module] = made["files"]
    assert module.endswith(".mod") and os.path.getsize(module) > 0
    assert_rapid_ok(open(module).read())


def test_sensor_run_chose_force_for_an_outside_edge(made):
    assert made["sensor"] == "force"
    summary = made["sensor_summary"]
    assert summary and " - " not in summary and "nan" not in summary.lower()


def test_a_screenshot_per_step(made):
    names = [os.path.basename(p) for p in made["snaps"]]
    assert names == ["01_part.png", "02_new_cell.png", "03_calibration_frame.png",
                     "04_path_and_tool_markers.png", "05_first_check.png", "06_place_robot.png",
                     "07_risk_areas.png", "08_check.png", "09_generate.png", "10_simulate.png",
                     "11_sensor_run.png"]
    for path in made["snaps"]:
        image = QtGui.QImage(path)
        assert image.width() >= 1300 and image.height() >= 700, path
