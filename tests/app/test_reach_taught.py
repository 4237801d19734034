"""Reach findings that point the way, and taught frames every command agrees on (issue 14).

A hand-built IRB 2400 cell with a path beyond reach: the check groups its
findings, says how far to move the robot, and moving the robot that far makes
the targets reachable.  A taught frame: check, the sensor simulation (and so
the sweep) and api.robot_base put the robot at the same base, which the cell's
Placement does not change.
"""

import json
import os

import numpy as np
import pytest

import FreeCAD
from CadRobotWB import api, simulation
from CadRobotWB.errors import FrameError
from CadRobotWB.objects import cell as cell_module
from CadRobotWB.objects.convert import matrix_from_placement
from CadRobotWB.robots.checks import checks
from conftest import REPO, run_cadrobot
from helpers import polyline, simple_cell, sketch_of

V = FreeCAD.Vector
REACH_KINDS = (checks.UNREACHABLE, checks.JOINT_LIMIT)


def far_cell(doc):
    """A 100 mm line in 20 segments, 1800 mm ahead of the robot's axis 1: out of reach."""
    sketch = sketch_of(doc, polyline([(900 + 5 * i, 0) for i in range(21)]))
    cell, path = simple_cell(doc, sketch, markers=[(900, 0, 0)])
    doc.recompute()
    return cell


@pytest.fixture
def far_doc():
    doc = FreeCAD.newDocument("FarCell")
    yield doc
    FreeCAD.closeDocument(doc.Name)


def reach_errors(result):
    return [f for f in result.report.errors if f.kind in REACH_KINDS]


def test_far_targets_are_one_group_whose_advice_brings_them_in(far_doc):
    cell = far_cell(far_doc)
    result = api.check(cell, collisions=False)
    failing = reach_errors(result)
    assert len(failing) >= 20                                  # every target kept
    groups = [g for g in result.report.groups() if g.kind in REACH_KINDS]
    assert len(groups) == 1 and len(groups[0].findings) == len(failing)
    advice = groups[0].advice
    assert advice is not None and advice.verified
    # The part lies straight ahead along +X of {U}: toward the robot is -X.
    assert advice.move_u_mm[0] <= -200.0 and advice.move_u_mm[1] == 0.0
    assert "toward the robot" in advice.text
    lines = result.lines()
    assert sum(": ERROR: " in line for line in lines) == 1
    assert not any("Cycle time" in line for line in lines)
    assert result.cycle_time_s is None and result.to_dict()["cycle_time_s"] is None
    # Stand the robot where the advice says (the robot moves by minus the part's move).
    cell.Placement = FreeCAD.Placement(cell.Placement.Base - V(*advice.move_u_mm),
                                       cell.Placement.Rotation)
    far_doc.recompute()
    after = api.check(cell, collisions=False)
    assert reach_errors(after) == [], after.lines()
    # Half of it is not enough: the advice is not far too generous.
    cell.Placement = FreeCAD.Placement(cell.Placement.Base + V(*advice.move_u_mm) * 0.5,
                                       cell.Placement.Rotation)
    far_doc.recompute()
    assert reach_errors(api.check(cell, collisions=False))


def test_cli_check_prints_groups_no_cycle_time_and_the_place_hint_once(far_doc, tmp_path):
    far_cell(far_doc)
    path = str(tmp_path / "my part.FCStd")
    far_doc.saveAs(path)
    launcher = tmp_path / "bin"                # `cadrobot` on the PATH: the hint names it
    launcher.mkdir()
    os.symlink(os.path.join(REPO, "cadrobot"), str(launcher / "cadrobot"))
    run = run_cadrobot("check", path, "--no-collisions",
                       env={"PATH": str(launcher) + os.pathsep + os.environ["PATH"]})
    assert run.returncode == 1, run.stderr
    lines = run.stdout.strip().splitlines()
    assert sum(": ERROR: unreachable: " in line for line in lines) == 1, run.stdout
    assert "Cycle time" not in run.stdout
    assert sum("cadrobot place" in line for line in lines) == 1
    assert lines[-1] == ('(`cadrobot place "%s" --region xmin,ymin,xmax,ymax` searches bases where '
                         'the robot reaches every target.)' % path)
    run = run_cadrobot("check", path, "--no-collisions", "--json")
    data = json.loads(run.stdout)["cells"][0]
    assert data["cycle_time_s"] is None and not data["ok"]
    assert len(data["findings"]) > len(data["groups"])
    assert any(g["advice"] and g["advice"]["verified"] for g in data["groups"])


# --- taught frames -----------------------------------------------------------------------

@pytest.fixture
def taught_doc():
    import seam_tracking_cell
    doc = FreeCAD.newDocument("TaughtCell")
    cell = seam_tracking_cell.build(doc)
    # The real part lies 10 mm along X and turned 2 deg from where the drawing puts it.
    cad = [(0, 0, 0), (100, 0, 0), (0, 100, 0)]
    turn = FreeCAD.Rotation(V(0, 0, 1), 2.0)
    measured = [tuple(turn.multVec(V(*p)) + V(10, 0, 0)) for p in cad]
    api.teach_calibration_frame(cell.CalibrationFrame, cad, measured)
    doc.recompute()
    name = doc.Name
    yield doc, cell
    if name in FreeCAD.listDocuments():
        FreeCAD.closeDocument(name)


def expected_base(cell):
    """T_u_b @ inv(T_r_b) of the cell's taught frame, worked out here."""
    frame = cell.CalibrationFrame
    T_u_b = matrix_from_placement(frame.getGlobalPlacement())
    T_r_b = matrix_from_placement(api.taught_frame(frame)[0])
    return T_u_b @ np.linalg.inv(T_r_b)


def simulation_base(cell):
    scene = simulation.read_scene(cell, "laser")
    return np.linalg.inv(scene.robot.T_r_u)


def test_check_and_sensor_run_stand_the_robot_at_the_taught_base_wherever_the_cell_is(taught_doc):
    doc, cell = taught_doc
    want = expected_base(cell)
    drawn = matrix_from_placement(cell.Placement)
    assert np.linalg.norm(want[:3, 3] - drawn[:3, 3]) > 5.0       # the teaching moved it
    checked = api.check(cell, collisions=False)
    assert checked.base.taught_frame == cell.CalibrationFrame.Label
    assert checked.base.T_u_r == pytest.approx(want, abs=1e-6)
    assert simulation_base(cell) == pytest.approx(want, abs=1e-6)
    assert matrix_from_placement(api.robot_base(cell)) == pytest.approx(want, abs=1e-6)
    lines_before = checked.lines()

    cell_module._told.discard((doc.Name, cell.Name))
    with cell_module.own_write(cell):                            # no warning for this write
        cell.Placement = FreeCAD.Placement(V(-300, 250, -100), FreeCAD.Rotation(V(0, 0, 1), 30))
        doc.recompute()
    assert (doc.Name, cell.Name) not in cell_module._told
    assert api.check(cell, collisions=False).base.T_u_r == pytest.approx(want, abs=1e-6)
    assert simulation_base(cell) == pytest.approx(want, abs=1e-6)
    assert api.check(cell, collisions=False).lines() == lines_before


def test_place_robot_with_a_taught_frame_says_what_it_fixes(taught_doc):
    doc, cell = taught_doc
    with pytest.raises(FrameError) as err:
        api.place_robot(cell, region=(-1500, -500, 0, 500))
    text = str(err.value)
    label = cell.CalibrationFrame.Label
    assert "fixes the part relative to the robot" in text
    assert "turn UseTaught off on '%s', place the robot (Place robot), then teach the frame again" \
        % label in text
    assert err.value.obj_name == cell.CalibrationFrame.Name
    assert api.taught_frame_labels(cell) == [label]


def test_moving_the_robot_with_a_taught_frame_warns_once_per_cell(taught_doc, tmp_path):
    doc, cell = taught_doc
    key = (doc.Name, cell.Name)
    cell_module._told.discard(key)
    cell.Placement = FreeCAD.Placement(V(-950, 0, -600), FreeCAD.Rotation())
    assert key in cell_module._told
    # Once: a second move says nothing.
    assert cell_module.warn_taught_move(cell) is None
    # Not while restoring: reopening the saved document tells nothing.
    path, name = str(tmp_path / "taught.FCStd"), cell.Name
    doc.saveAs(path)
    FreeCAD.closeDocument(doc.Name)
    cell_module._told.clear()
    reopened = FreeCAD.openDocument(path)
    try:
        assert not cell_module._told
        moved = reopened.getObject(name)
        text = cell_module.warn_taught_move(moved)
        assert "moving the robot of cell '%s' changes nothing" % moved.Label in text
    finally:
        FreeCAD.closeDocument(reopened.Name)


def test_without_a_taught_frame_moving_the_robot_says_nothing(far_doc):
    cell = far_cell(far_doc)
    cell_module._told.clear()
    cell.Placement = FreeCAD.Placement(V(-700, 0, -600), FreeCAD.Rotation())
    assert not cell_module._told
    assert matrix_from_placement(api.robot_base(cell)) == pytest.approx(
        matrix_from_placement(cell.Placement))
