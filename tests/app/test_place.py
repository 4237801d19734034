"""Place robot in real documents: ``api.place_robot`` and ``cadrobot place``.

The example seam cell with its robot moved 1.5 m away, where it reaches
nothing: ``cadrobot place`` finds placements, and ``cadrobot check`` of the
document with the robot moved to each of them passes (both through the real
launcher).  On a small grid, the search's verdict at every base is the one
``api.check`` gives with the cell moved there.
"""

import json

import numpy as np
import pytest

import FreeCAD
import Part
from conftest import run_cadrobot, sha256
from CadRobotWB import api
from CadRobotWB.errors import FrameError, InputError

V = FreeCAD.Vector
FAR = FreeCAD.Placement(V(-1500, 0, 0), FreeCAD.Rotation())
REGION = "-1500,-1000,1500,1000"


@pytest.fixture(scope="module")
def far_file(tmp_path_factory):
    """The seam cell with its robot where it cannot reach the seam, saved."""
    import seam_tracking_cell
    doc = FreeCAD.newDocument("FarSeam")
    try:
        cell = seam_tracking_cell.build(doc)
        cell.Placement = FAR
        doc.recompute()
        path = str(tmp_path_factory.mktemp("far") / "far.FCStd")
        doc.saveAs(path)
    finally:
        FreeCAD.closeDocument(doc.Name)
    return path


def moved_copy(source, placement, path):
    """`source` saved again as `path` with its cell at `placement` (through the API)."""
    doc = FreeCAD.openDocument(source)
    try:
        api.set_robot_placement(api.find_cells(doc)[0], placement)
        doc.saveAs(str(path))
    finally:
        FreeCAD.closeDocument(doc.Name)
    return str(path)


def test_cadrobot_place_finds_placements_where_cadrobot_check_passes(far_file, tmp_path):
    before = sha256(far_file)
    assert run_cadrobot("check", far_file).returncode == 1          # out of reach where it is
    run = run_cadrobot("place", far_file, "--region", REGION, "--step", "250", "--count", "3", "--json")
    assert run.returncode == 0, run.stderr
    found = json.loads(run.stdout)
    assert found["ok"] and found["cell"] == "SeamCell" and len(found["candidates"]) == 3
    assert found["counts"]["passed"] == 3 and found["counts"]["unreachable"] > 0
    scores = [c["score"] for c in found["candidates"]]
    assert scores == sorted(scores, reverse=True)
    for k, candidate in enumerate(found["candidates"]):
        T = np.array(candidate["T_u_r"])
        assert T[:3, 3].tolist() == [candidate["x_mm"], candidate["y_mm"], candidate["z_mm"]]
        assert -1500 <= T[0, 3] <= 1500 and -1000 <= T[1, 3] <= 1000
        moved = moved_copy(far_file, api.placement_from_matrix(T), tmp_path / ("moved%d.FCStd" % k))
        check = run_cadrobot("check", moved, "--json")
        assert check.returncode == 0, check.stdout
        report = json.loads(check.stdout)["cells"][0]
        assert report["ok"] and report["errors"] == 0
        assert report["cycle_time_s"] == pytest.approx(candidate["parts"]["cycle_time_s"])
    assert sha256(far_file) == before                                 # never modified


def test_text_output_names_the_score_and_the_closest_failures(far_file):
    run = run_cadrobot("place", far_file, "--region", REGION, "--step", "500", "--count", "2")
    assert run.returncode == 0, run.stderr
    lines = run.stdout.splitlines()
    assert lines[0].startswith("SeamCell: 35 candidate bases, ")
    assert lines[1] == ("SeamCell: score = 0.40 x fastest cycle time / cycle time + 0.30 x min(1, "
                        "joint-limit margin / 45 deg) + 0.30 x manipulability")
    assert lines[2].startswith("SeamCell:  1. score ") and "cycle time" in lines[2]
    assert any("FAILS at x " in line and "unreachable: " in line and "of 13 targets of path 'Seam'"
               in line for line in lines)


def test_nowhere_in_reach_exits_1_and_says_why(far_file):
    run = run_cadrobot("place", far_file, "--region", "4000,4000,5000,5000", "--step", "500")
    assert run.returncode == 1, run.stderr
    lines = run.stdout.splitlines()
    assert "0 pass" in lines[0]
    assert "SeamCell: FAILS at x 4000, y 4000, z 0 mm" in run.stdout
    assert "unreachable: 13 of 13 targets of path 'Seam' are out of reach" in run.stdout
    assert lines[-1].startswith("SeamCell: no placement in the region works")


def test_every_base_of_the_grid_agrees_with_api_check(seam_cell):
    """Brute force: the cell moved to every base of the grid (the turn the search gives it),
    api.check there, against the search's pass or fail."""
    cell = seam_cell
    region = (-1200.0, -800.0, 1200.0, 800.0)
    found = api.place_robot(cell, region=region, step_mm=600.0, margin_deg=0.0, singularities=False,
                            count=100, turn_deg=(0.0, 180.0), turn_step_deg=90.0)
    verdicts = {}
    for x in np.linspace(region[0], region[2], 5):
        for y in np.linspace(region[1], region[3], 4):
            for turn in (0.0, 90.0, 180.0):
                api.set_robot_placement(cell, FreeCAD.Placement(V(x, y, 0), FreeCAD.Rotation(V(0, 0, 1), turn)))
                verdicts[(round(x), round(y), round(turn) % 360)] = api.check(cell).ok
    passed = {(round(c.x_mm), round(c.y_mm), round(c.turn_deg) % 360) for c in found}
    assert passed == {k for k, ok in verdicts.items() if ok}
    assert found.counts["candidates"] == 60 and 0 < len(passed) < 60


def test_found_placements_pass_api_check_with_margins(seam_cell):
    cell = seam_cell
    cell.Placement = FAR
    found = api.place_robot(cell, region=(-1500, -1000, 1500, 1000), step_mm=300, count=3)
    assert len(found) == 3
    for candidate in found:
        assert isinstance(candidate.placement, FreeCAD.Placement)
        api.set_robot_placement(cell, candidate.placement)
        result = api.check(cell)
        assert result.ok and not result.report.warnings, result.lines()
        assert result.cycle_time["total_s"] == pytest.approx(candidate.parts["cycle_time_s"])
        q = api.robot(cell.Robot).controller_joints(result.solution.joints())
        model = api.robot(cell.Robot)
        margin = np.min(np.minimum(q - model.joint_min_deg, model.joint_max_deg - q))
        assert margin >= 5.0 and margin == pytest.approx(candidate.parts["limit_margin_deg"])


def test_a_floor_face_limits_the_positions(seam_cell):
    doc = seam_cell.Document
    floor = doc.addObject("Part::Feature", "Pedestal")
    # An L-shaped plate, top at z = 100 mm: no position in the missing quarter.
    outline = [V(x, y, 0) for x, y in ((-1200, -800), (0, -800), (0, 0), (-600, 0), (-600, 800),
                                       (-1200, 800), (-1200, -800))]
    floor.Shape = Part.Face(Part.makePolygon(outline)).extrude(V(0, 0, 100))
    doc.recompute()
    top = next("Face%d" % (i + 1) for i, f in enumerate(floor.Shape.Faces)
               if abs(f.normalAt(0, 0).z - 1) < 1e-9)
    found = api.place_robot(seam_cell, face=(floor, top), step_mm=300, count=2, collisions=False)
    heat = found.heat
    assert heat.z_mm == pytest.approx(100.0)
    for cand in list(found) + found.failures:
        assert cand.z_mm == pytest.approx(100.0)
        assert not (cand.x_mm > -600 + 1e-6 and cand.y_mm > 1e-6)          # not in the notch
    assert ((heat.state >= 0) == np.array([[not (x > -600 + 1e-6 and y > 1e-6) for x in heat.x_mm]
                                           for y in heat.y_mm])).all()
    side = next("Face%d" % (i + 1) for i, f in enumerate(floor.Shape.Faces)
                if abs(f.normalAt(0, 0).z) < 1e-9)
    with pytest.raises(InputError, match="tilted 90 deg from horizontal"):
        api.place_robot(seam_cell, face=(floor, side))


def test_bad_api_input(seam_cell):
    with pytest.raises(InputError, match="give the region to search"):
        api.place_robot(seam_cell)
    with pytest.raises(InputError, match="'SeamCell'.*xmin \\(5\\) is greater"):
        api.place_robot(seam_cell, region=(5, 0, 0, 10))
    with pytest.raises(InputError, match="cell must be a CadRobot Cell, got 'Table'"):
        api.place_robot(seam_cell.Document.getObject("Table"), region=(0, 0, 10, 10))


def test_set_robot_placement_moves_the_cell(seam_cell):
    wanted = FreeCAD.Placement(V(1, 2, 3), FreeCAD.Rotation(V(0, 0, 1), 30))
    pl = api.set_robot_placement(seam_cell, api.matrix_from_placement(wanted))
    assert np.allclose(api.matrix_from_placement(seam_cell.Placement), api.matrix_from_placement(wanted))
    assert np.allclose(api.matrix_from_placement(pl), api.matrix_from_placement(wanted))


@pytest.fixture(scope="module")
def bad_files(tmp_path_factory):
    """Documents `cadrobot place` must refuse: a cell without paths, a taught frame."""
    import seam_tracking_cell
    folder = tmp_path_factory.mktemp("bad")
    files = {}
    doc = FreeCAD.newDocument("NoPaths")
    api.make_cell(doc, name="Empty")
    files["nopaths"] = str(folder / "nopaths.FCStd")
    doc.saveAs(files["nopaths"])
    FreeCAD.closeDocument(doc.Name)
    doc = FreeCAD.newDocument("Taught")
    cell = seam_tracking_cell.build(doc)
    api.teach_calibration_frame(cell.CalibrationFrame, [(0, 0, 0), (100, 0, 0), (0, 100, 0)],
                                [(10, 0, 0), (110, 0, 0), (10, 100, 0)])
    files["taught"] = str(folder / "taught.FCStd")
    doc.saveAs(files["taught"])
    FreeCAD.closeDocument(doc.Name)
    return files


@pytest.mark.parametrize("args, words", [
    (["--region", "0,0,100,0"], ["'SeamCell'", "is empty (no area)", "xmax > xmin"]),
    (["--region", "100,0,0,500"], ["xmin (100) is greater than its xmax (0)"]),
    (["--region", "0,0,100,100", "--z", "300,0"], ["height range z 300..0 mm runs backwards"]),
    (["--region", "0,0,100,100", "--turn", "90,-90"], ["turn range 90..-90 deg runs backwards"]),
    (["--region", "0,0,100"], ["argument --region: give 4 finite numbers xmin,ymin,xmax,ymax"]),
    (["--region", "0,0,100,100", "--step", "0"], ["argument --step: give a number > 0, not '0'"]),
    (["--region", "0,0,100,100", "--count", "0"], ["argument --count: give a whole number >= 1"]),
    (["--region", "0,0,100,100", "--cell", "Nope"], ["no cell 'Nope'", "SeamCell"]),
    ([], ["the following arguments are required: --region"]),
])
def test_bad_input_is_one_line_and_exit_2(far_file, args, words):
    run = run_cadrobot("place", far_file, *args)
    assert run.returncode == 2, (run.stdout, run.stderr)
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("cadrobot: error: "), run.stderr
    for word in words:
        assert word in lines[0], lines[0]
    assert run.stdout == ""


def test_a_cell_without_paths_or_with_a_taught_frame_exits_2(bad_files):
    run = run_cadrobot("place", bad_files["nopaths"], "--region", "0,0,100,100")
    assert run.returncode == 2 and len(run.stderr.strip().splitlines()) == 1
    assert "Cell 'Empty' has no paths. Add one" in run.stderr
    run = run_cadrobot("place", bad_files["taught"], "--region", "0,0,100,100", "--json")
    assert run.returncode == 2 and len(run.stderr.strip().splitlines()) == 1
    assert "'TableFrame' is taught (UseTaught)" in run.stderr and "turn UseTaught off on 'TableFrame', place the robot" in run.stderr
    assert json.loads(run.stdout) == {"ok": False, "error": run.stderr.strip()[len("cadrobot: error: "):],
                                      "object": "TableFrame", "kind": FrameError.__name__}


def test_a_robot_not_in_the_catalog_exits_2(tmp_path, monkeypatch):
    """A cell made with an imported robot, opened where that robot was never imported."""
    import os
    import shutil
    import seam_tracking_cell
    from CadRobotWB.robots.catalog import catalog
    from required import ROBOT_DATA
    folder = str(tmp_path / "robots")
    monkeypatch.setenv("CADROBOT_ROBOT_FOLDER", folder)
    shutil.copytree(os.path.join(ROBOT_DATA, "abb_irb1600_6_12"), str(tmp_path / "urdf"))
    try:
        name = api.import_robot(str(tmp_path / "urdf" / "robot.urdf"), name="SHOP_1600")
        doc = FreeCAD.newDocument("Shop")
        seam_tracking_cell.build(doc, robot=name)
        path = str(tmp_path / "shop.FCStd")
        doc.saveAs(path)
        FreeCAD.closeDocument(doc.Name)
    finally:
        monkeypatch.delenv("CADROBOT_ROBOT_FOLDER")
        catalog.forget_user_robots()
    run = run_cadrobot("place", path, "--region", "0,0,100,100",
                       env={"CADROBOT_ROBOT_FOLDER": str(tmp_path / "elsewhere")})
    assert run.returncode == 2, (run.stdout, run.stderr)
    assert len(run.stderr.strip().splitlines()) == 1
    assert "SeamCell" in run.stderr and "SHOP_1600" in run.stderr
