"""Which sensor fits a path, read from the faces along it in real documents."""

import json
import re

import numpy as np
import pytest

import FreeCAD
from CadRobotWB import api
from CadRobotWB.sensors import run as sensor_run
from CadRobotWB.sensors.seam_features import JointTemplate
from conftest import run_cadrobot
from drilling_part import drilling_block, top_outer_loop
from helpers import sketch_of, polyline

V = FreeCAD.Vector
PLACEHOLDERS = re.compile(r"(^|[\s(=:])(-|nan|None)([\s),;.]|$)")


@pytest.fixture
def drilling_cell():
    doc, pocket = drilling_block()
    cell = api.make_cell(doc, robot="ABB_IRB2400", name="Cell",
                         placement=FreeCAD.Placement(V(-800, 0, -500), FreeCAD.Rotation()))
    api.make_calibration_frame(doc, cell, FreeCAD.Placement())
    cell.ToolTCP = FreeCAD.Placement(V(0, 0, 200), FreeCAD.Rotation())
    path = api.make_path(doc, cell, [(pocket, name) for name in top_outer_loop(pocket)])
    api.make_tool_markers_auto(doc, cell, path)
    doc.recompute()
    yield cell
    FreeCAD.closeDocument(doc.Name)


@pytest.fixture
def fillet_cell(doc):
    """A T joint: a web (y -8..0, 100 mm tall) standing on a base plate (top z = 8); the
    seam sketch runs along the root (y 0, z 8), the torch at 45° into the corner."""
    base = doc.addObject("Part::Box", "Base")
    base.Length, base.Width, base.Height = 300, 200, 8
    base.Placement.Base = V(0, -100, 0)
    web = doc.addObject("Part::Box", "Web")
    web.Length, web.Width, web.Height = 300, 8, 100
    web.Placement.Base = V(0, -8, 8)
    sketch = sketch_of(doc, polyline([(50, 0), (250, 0)]), FreeCAD.Placement(V(0, 0, 8), FreeCAD.Rotation()),
                       name="Root")
    cell = api.make_cell(doc, robot="ABB_IRB2400", name="FilletCell",
                         placement=FreeCAD.Placement(V(-700, 300, -400), FreeCAD.Rotation()))
    cell.ToolTCP = FreeCAD.Placement(V(0, 0, 300), FreeCAD.Rotation())
    api.make_calibration_frame(doc, cell, FreeCAD.Placement())
    api.make_path(doc, cell, sketch, speed_mm_s=10.0, name="Root")
    into_corner = V(0, 1, 1).normalize()
    api.make_tool_marker(doc, cell, api.tool_placement(V(150, 0, 8), V(1, 0, 0), into_corner, 90.0, 0.0))
    doc.recompute()
    return cell


def test_the_seam_example_is_a_butt_joint_for_the_laser(seam_cell):
    fit = api.sensor_fit(seam_cell)
    assert (fit.kind, fit.sensor, fit.fraction) == ("butt", "laser", 1.0)
    # PlateA and PlateB either side of the 1.5 mm root gap (the example's ROOT_GAP_MM)
    assert fit.example.gap_mm == pytest.approx(1.5, abs=1e-6)
    assert {f.solid for f in fit.example.faces} == {"PlateA", "PlateB"}
    assert "butt joint between PlateA.Face" in fit.reason and "1.5 mm gap" in fit.reason
    assert fit.template() == JointTemplate("butt", gap_mm=1.5)
    assert "has no joint" not in fit.why_not("force") and fit.why_not("laser") == ""


def test_the_force_example_is_a_surface_for_force(doc):
    import profile_following_cell
    cell = profile_following_cell.build(doc)
    fit = api.sensor_fit(cell)
    assert (fit.kind, fit.sensor, fit.fraction) == ("surface", "force", 1.0)
    assert "lies on Face3 of Profile" in fit.reason and "follow the surface with force" in fit.reason
    assert fit.why_not("laser").startswith("the path has no joint: it lies on Face3 of Profile")


def test_the_top_outer_loop_of_drillings_pocket011_is_a_convex_edge_for_force(drilling_cell):
    fit = api.sensor_fit(drilling_cell)
    assert (fit.kind, fit.sensor) == ("convex_edge", "force")
    assert fit.fraction >= 0.9
    assert fit.example.angle_deg == pytest.approx(90.0, abs=0.5)        # the block's sides are square
    assert fit.example.faces[0].solid == "Pocket011"
    assert re.search(r"runs along a convex edge between Face\d+ and Face\d+ of Pocket011 "
                     r"\(outside corner, 90\u00b0\): no joint for a laser to find; follow the surface "
                     r"with force", fit.reason)
    assert fit.not_offered("laser").startswith("Laser seam tracking: not offered, the path has no joint: "
                                               "it runs along a convex edge between Face")


def test_the_laser_asked_for_on_the_outside_edge_runs_and_says_why_once(drilling_cell):
    run = api.simulate(drilling_cell, sensor="laser")
    assert run.aborted and run.reason.startswith("seam lost")
    asked = [n for n in run.notes if "asked for" in n]
    assert len(asked) == 1 and "the path has no joint" in asked[0] and "Pocket011" in asked[0]
    phrases = sensor_run.metric_phrases(run)
    text = ". ".join(phrases)
    assert "RMS error after 20 mm: not measured, the run aborted after %.0f mm (seam lost)" % (
        run.travelled_mm()) in text
    assert not PLACEHOLDERS.search(text), text
    assert text.count("asked for") == 1


def test_a_fillet_is_detected_and_the_laser_tracks_it_with_the_detected_template(fillet_cell):
    fit = api.sensor_fit(fillet_cell)
    assert (fit.kind, fit.sensor, fit.fraction) == ("fillet", "laser", 1.0)
    assert fit.example.angle_deg == pytest.approx(90.0, abs=0.5)
    assert "Base.Face" in fit.reason and "Web.Face" in fit.reason
    deviation = (0, 1.5, 1.0, 0, 0, 0)             # the real part 1.5 mm aside, 1 mm up
    run = api.simulate(fillet_cell, sensor="laser", deviation=deviation)
    assert not run.aborted, run.reason
    assert run.metrics["rms_error_after_20mm_mm"] < 0.3
    assert run.notes == []
    # the butt template the laser used before this detection loses the seam
    blind = api.simulate(fillet_cell, sensor="laser", deviation=deviation, template=JointTemplate("butt"))
    assert blind.aborted and blind.reason.startswith("seam lost")


def test_force_on_a_cell_without_the_ball_tool_says_so(fillet_cell):
    from CadRobotWB.objects import joint_faces
    notes = joint_faces.sensor_notes(fillet_cell, "force", api.sensor_fit(fillet_cell))
    assert len(notes) == 2
    assert notes[0].startswith("Force profile following was asked for although the path is a seam")
    assert "needs the ball tool on the real robot" in notes[1] and "radius 5 mm" in notes[1]
    assert joint_faces.sensor_notes(fillet_cell, "laser", api.sensor_fit(fillet_cell)) == []
    assert fillet_cell.ToolType == "Straight torch"          # a new cell's default tool
    assert "the cell's tool is the 'Straight torch'" in joint_faces.tool_notes(fillet_cell, "force")[0]
    api.set_tool(fillet_cell, tool="Ball tool")
    assert joint_faces.tool_notes(fillet_cell, "force") == []
    api.set_tool(fillet_cell, tool="Straight torch")


@pytest.fixture(scope="module")
def profile_file(tmp_path_factory):
    import profile_following_cell
    folder = tmp_path_factory.mktemp("doc")
    doc = FreeCAD.newDocument("SavedProfile")
    try:
        profile_following_cell.build(doc)
        path = str(folder / "profile.FCStd")
        doc.saveAs(path)
    finally:
        FreeCAD.closeDocument(doc.Name)
    return path


def test_cli_simulate_without_sensor_uses_the_detected_one_and_says_why(profile_file, tmp_path):
    run = run_cadrobot("simulate", profile_file, "-o", str(tmp_path / "out"))
    assert run.returncode == 0, run.stderr
    first = run.stdout.splitlines()[0]
    assert first.startswith("Sensor: force (detected): Path Profile") and "lies on Face3 of Profile" in first
    assert [line.split(":")[0] for line in run.stdout.splitlines()[1:4]] == \
        ["force pi", "force fuzzy_pi", "force none"]
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    assert (report["sensor"], report["sensor_chosen"]) == ("force", "detected")
    assert report["sensor_fit"]["kind"] == "surface"


def test_cli_simulate_laser_asked_for_on_a_surface_runs_and_prints_no_placeholder(profile_file, tmp_path):
    run = run_cadrobot("simulate", profile_file, "--sensor", "laser", "-o", str(tmp_path / "out"))
    assert run.returncode == 1, run.stderr             # the laser finds no seam: aborted
    lines = run.stdout.splitlines()
    assert lines[0].startswith("Sensor: laser (asked for): Path Profile")
    assert lines[1].startswith("laser pi: ABORTED: seam lost")
    assert "rms_error_after_20mm_mm, max_error_mm: not measured, the run aborted after" in lines[1] \
        or "rms_error_after_20mm_mm: not measured, the run aborted after" in lines[1]
    notes = [line for line in lines if line.startswith("Note: ")]
    assert len(notes) == 1 and "Laser seam tracking was asked for although the path has no joint" in notes[0]
    for line in lines:
        if not line.startswith("wrote "):
            assert not PLACEHOLDERS.search(line), line
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    assert report["runs"][0]["notes"] == [notes[0][len("Note: "):]]
    assert report["runs"][0]["summary"][0].startswith("RMS error after 20 mm: not measured, the run aborted after")


def test_sampling_covers_every_segment_and_each_20_mm(seam_cell):
    from CadRobotWB.objects import joint_faces, reader
    path, samples = joint_faces.path_samples(seam_cell)
    lengths = [seg.length for seg in reader.path_geometry(path)[0]]
    assert sorted({x.segment for x in samples}) == [1, 2, 3, 4]
    s = np.array([x.s_mm for x in samples])
    assert np.all(np.diff(s) > 0) and np.diff(s).max() <= 20.0 + 1e-9
    assert s[-1] < sum(lengths) and s[0] > 0


def test_a_lap_joint_in_a_document_gives_the_plate_edge_as_the_step(doc):
    """A 7 mm plate lying on an 8 mm one, its edge at y = 0: the seam sketch runs along it."""
    lower = doc.addObject("Part::Box", "Lower")
    lower.Length, lower.Width, lower.Height = 300, 200, 8
    lower.Placement.Base = V(0, -100, 0)
    upper = doc.addObject("Part::Box", "Upper")
    upper.Length, upper.Width, upper.Height = 300, 100, 7
    upper.Placement.Base = V(0, -100, 8)
    sketch = sketch_of(doc, polyline([(50, 0), (250, 0)]), FreeCAD.Placement(V(0, 0, 8), FreeCAD.Rotation()))
    cell = api.make_cell(doc, robot="ABB_IRB2400", name="LapCell")
    api.make_calibration_frame(doc, cell, FreeCAD.Placement())
    api.make_path(doc, cell, sketch)
    api.make_tool_marker(doc, cell, api.tool_placement(V(150, 0, 8), V(1, 0, 0), V(0, 1, 1).normalize(), 90, 0))
    doc.recompute()
    fit = api.sensor_fit(cell)
    assert (fit.kind, fit.sensor, fit.fraction) == ("lap", "laser", 1.0)
    assert fit.example.step_mm == pytest.approx(7.0, abs=0.1)
    assert fit.template() == JointTemplate("lap", step_mm=fit.template().step_mm)
    assert "lap joint: the 7.0 mm edge Upper.Face" in fit.reason and "on Lower.Face" in fit.reason
