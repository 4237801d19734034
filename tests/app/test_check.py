"""Can the robot run the program? Reach, limits, collisions, cycle time, and
what export and the CLI do about it."""

import json

import numpy as np
import pytest

import FreeCAD
from CadRobotWB import api
from CadRobotWB.errors import FindingError
from conftest import run_cadrobot
from rapid_check import assert_rapid_ok, needs_rapidchecker

V = FreeCAD.Vector


def test_seam_cell_passes_and_its_cycle_time_is_the_weld_time_plus_the_moves(seam_cell):
    result = api.check(seam_cell)
    assert result.ok, result.lines()
    assert result.report.findings == []
    # 420 mm of seam at 10 mm/s is 42 s; approach, entry, retract and stops add a little.
    assert 42.0 < result.cycle_time["total_s"] < 46.0
    joints = [t.joints_deg for t in result.program.targets()]
    assert all(q is not None and q.shape == (6,) for q in joints)


def test_solved_joints_put_the_tcp_on_the_targets(seam_cell):
    program = api.generate(seam_cell)
    robot = api.robot("ABB_IRB2400")
    frame = program.frames["TableFrame"]
    T_f_t = program.tool.T_f_t
    for target in program.targets():
        T_r_t = robot.fk(target.joints_deg[None, :])[0] @ T_f_t
        np.testing.assert_allclose(T_r_t, frame.T_r_b @ target.T_b_t, atol=1e-6)


def test_unreachable_cell_is_reported_and_not_exported(seam_cell, tmp_path):
    seam_cell.Placement = FreeCAD.Placement(V(-3000, 0, 0), FreeCAD.Rotation())
    result = api.check(seam_cell)
    assert not result.ok
    assert {f.kind for f in result.report.errors} == {"unreachable"}
    assert len(result.report.errors) == len(result.program.targets())
    with pytest.raises(FindingError, match="'SeamCell'.*cannot run"):
        api.export(seam_cell, output_dir=str(tmp_path / "out"))
    assert not (tmp_path / "out").exists()
    assert api.export(seam_cell, output_dir=str(tmp_path / "forced"), check_first=False)


def test_a_wall_between_robot_and_table_is_a_collision(seam_cell):
    wall = seam_cell.Document.addObject("Part::Box", "Wall")
    wall.Length, wall.Width, wall.Height = 40, 1200, 2500
    wall.Placement.Base = V(420, -600, 0)   # the arm reaches over x = 420..460 to the seam
    seam_cell.Document.recompute()
    result = api.check(seam_cell)
    collisions = [f for f in result.report.errors if f.kind == "collision"]
    assert collisions and all("Wall" in f.message for f in collisions)
    assert api.check(seam_cell, collisions=False).ok


@needs_rapidchecker
def test_rapid_carries_the_checked_configurations(seam_cell, tmp_path):
    text = open(api.export(seam_cell, output_dir=str(tmp_path))[0]).read()
    assert "ConfL \\On;" in text and "ConfL \\Off" not in text
    assert_rapid_ok(text)


def test_cli_check_exit_codes_and_json(seam_cell, tmp_path):
    good = str(tmp_path / "good.FCStd")
    seam_cell.Document.saveAs(good)
    run = run_cadrobot("check", good)
    assert run.returncode == 0, run.stderr
    assert "SeamCell: OK: 13 targets" in run.stdout and "Cycle time" in run.stdout
    seam_cell.Placement = FreeCAD.Placement(V(-3000, 0, 0), FreeCAD.Rotation())
    bad = str(tmp_path / "bad.FCStd")
    seam_cell.Document.saveAs(bad)
    run = run_cadrobot("check", bad, "--json")
    assert run.returncode == 1, run.stderr
    report = json.loads(run.stdout)
    assert report["ok"] is False and report["cells"][0]["errors"] == 13
    assert report["cells"][0]["findings"][0]["kind"] == "unreachable"
    run = run_cadrobot("export", bad, "-o", str(tmp_path / "out"))
    assert run.returncode == 1 and "cannot run" in run.stderr
    assert not (tmp_path / "out").exists()
    run = run_cadrobot("export", bad, "-o", str(tmp_path / "out"), "--no-check")
    assert run.returncode == 0, run.stderr


def test_a_calibration_frame_no_path_uses_is_a_warning_naming_it(seam_cell):
    """A second frame added to the cell (as a new user does for a second part) is used by
    no path: the path takes the cell's frame. Check says so once; linked to the path, the
    frame is used and the warning goes (the cell's own frame, the paths' default, never
    gets one)."""
    from CadRobotWB.objects import reader
    doc = seam_cell.Document
    first = seam_cell.CalibrationFrame
    second = api.make_calibration_frame(doc, seam_cell, first.Placement, name="SecondPart")
    result = api.check(seam_cell, collisions=False)
    [warning] = [f for f in result.report.findings if f.kind == "unused_frame"]
    assert warning.severity == "warning" and result.ok
    assert warning.message == (
        "calibration frame 'SecondPart' is used by no path of cell %s (a path without its own "
        "CalibrationFrame uses the cell's, %s): set the CalibrationFrame property of the path "
        "on that part to 'SecondPart', or delete the frame." % (label(seam_cell), label(first)))
    [path] = reader.cell_paths(seam_cell)
    path.CalibrationFrame = second
    doc.recompute()
    result = api.check(seam_cell, collisions=False)
    assert not [f for f in result.report.findings if f.kind == "unused_frame"]


def label(obj):
    return "'%s'" % obj.Label if obj.Label == obj.Name else "'%s' (%s)" % (obj.Label, obj.Name)
