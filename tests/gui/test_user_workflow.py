"""The seam cell built with the toolbar only gives the scripted example's program.

examples/gui_walkthrough.py clicks through New cell, Calibration frame (and its
teaching panel), Mark path, Tool markers on every segment, Risk area
(suggestion) and Generate. Its robtargets and moves must be those of the
hand-checked golden module of examples/seam_tracking_cell.py (targets are in
{B}, so teaching does not move them); its work object must be the drawn
frame moved as the "real" table was.
"""

import os
import re

import numpy as np

import FreeCAD
from conftest import REPO
from rapid_check import assert_rapid_ok
from required import ROBOT_DATA as DATA

import gui_walkthrough

GOLDEN = os.path.join(REPO, "tests", "app", "golden", "SeamWeld.mod")
ROBTARGET = re.compile(r"CONST robtarget \w+ := \[\[([^\]]*)\],\[([^\]]*)\],\[([^\]]*)\]")
MOVE = re.compile(r"^\s*(Move[JLC])\s+\w+,\s*(\w+),\s*(\w+),", re.M)
MOVE_ABSJ = re.compile(r"^\s*(MoveAbsJ)\s+\w+,\s*(\w+),\s*(\w+),", re.M)
WOBJ = re.compile(r"PERS wobjdata \w+ := \[FALSE,TRUE,\"\",\[\[([^\]]*)\],\[([^\]]*)\]\]")


def numbers(text):
    return [float(v) for v in text.split(",")]


def robtargets(module):
    return [tuple(numbers(g) for g in m.groups()) for m in ROBTARGET.finditer(module)]


def quaternion_wxyz(rotation):
    x, y, z, w = rotation.Q
    return np.array([w, x, y, z])


def test_the_toolbar_builds_the_papers_seam_cell(tmp_path, monkeypatch):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "0")
    made = gui_walkthrough.run(str(tmp_path), doc_name="SeamByClicksTest")
    doc = made["doc"]
    try:
        # The frame from three table vertices is the example's {B}: the table top corner.
        fixture = doc.getObject("Fixture").Placement
        corner = fixture.multiply(FreeCAD.Placement(FreeCAD.Vector(0, 0, 600), FreeCAD.Rotation()))
        assert np.allclose(made["frame"].Placement.toMatrix().A, corner.toMatrix().A, atol=1e-9)
        # Four markers, one per segment, and the corner's risk area over segments 2-3.
        assert len(made["markers"]) == 4
        assert [(r.FirstSegment, r.LastSegment) for r in made["risk_areas"]] == [(2, 3)]
        # Teaching on a table 2 mm off: residuals at the noise's scale (0.03 mm per coordinate).
        assert len(made["residuals_mm"]) == 4 and max(made["residuals_mm"]) < 0.06

        module_path, = made["files"]
        assert os.path.basename(module_path) == "SeamWeld.mod"
        with open(module_path) as handle:
            module = handle.read()
        assert_rapid_ok(module)
        with open(GOLDEN) as handle:
            golden = handle.read()

        ours, expected = robtargets(module), robtargets(golden)
        assert len(ours) == len(expected) == 12   # the approach is a jointtarget
        for (pos, quat, conf), (pos0, quat0, conf0) in zip(ours, expected):
            assert np.allclose(pos, pos0, atol=1e-3) and np.allclose(quat, quat0, atol=1e-6)
            assert conf == conf0
        assert MOVE.findall(module) == MOVE.findall(golden)
        assert MOVE_ABSJ.findall(module) == MOVE_ABSJ.findall(golden) != []

        # The work object is the drawn frame where the real table put it (within the noise).
        T_expected = gui_walkthrough.REAL_TABLE_SHIFT.multiply(corner)
        (position, quaternion), = [tuple(numbers(g) for g in m.groups()) for m in WOBJ.finditer(module)]
        assert np.allclose(position, tuple(T_expected.Base), atol=0.05)
        q_expected = quaternion_wxyz(T_expected.Rotation)
        assert min(np.abs(np.array(quaternion) - s * q_expected).max() for s in (1, -1)) < 2e-4
        drawn = [numbers(g) for g in WOBJ.search(golden).groups()]
        assert not np.allclose(position, drawn[0], atol=1.0), "the taught frame was not used"

        # Every step left a screenshot of the window.
        assert [os.path.basename(p) for p in made["snaps"]] == [
            "01_drawing.png", "02_new_cell.png", "03_teach_frame.png", "04_tool_markers.png",
            "05_risk_areas.png", "06_generate.png", "07_cell.png", "08_robot_and_cell.png"]
        assert all(os.path.getsize(p) > 10000 for p in made["snaps"])
    finally:
        FreeCAD.closeDocument(doc.Name)


def test_a_new_user_imports_a_urdf_and_writes_its_program(tmp_path, monkeypatch):
    """The same clicks with the user's own arm: an ABB IRB 1600-6/1.2 URDF (with its collision
    meshes beside it) imported in the New cell panel; the program is RAPID for that robot and
    its robtargets are the paper robot's (the targets are in {B}, whatever the robot)."""
    import shutil
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "0")
    monkeypatch.setenv("CADROBOT_ROBOT_FOLDER", str(tmp_path / "robots"))
    shutil.copytree(os.path.join(DATA, "abb_irb1600_6_12"), tmp_path / "downloads")
    made = gui_walkthrough.run(str(tmp_path), doc_name="ImportedByClicksTest",
                               robot_file=str(tmp_path / "downloads" / "robot.urdf"),
                               robot_name="SHOP_IRB1600")
    try:
        assert made["cell"].Robot == "SHOP_IRB1600" and made["cell"].PostProcessor == "abb_rapid"
        assert sorted(os.listdir(tmp_path / "robots")) == ["SHOP_IRB1600.csv", "SHOP_IRB1600.npz"]
        module_path, = made["files"]
        with open(module_path) as handle:
            module = handle.read()
        assert_rapid_ok(module)
        assert "! Robot: SHOP_IRB1600." in module
        with open(GOLDEN) as handle:
            golden = handle.read()
        ours, expected = robtargets(module), robtargets(golden)
        assert len(ours) == len(expected) == 12   # the approach is a jointtarget
        for (pos, quat, _conf), (pos0, quat0, _conf0) in zip(ours, expected):
            assert np.allclose(pos, pos0, atol=1e-3) and np.allclose(quat, quat0, atol=1e-6)
    finally:
        FreeCAD.closeDocument(made["doc"].Name)
        monkeypatch.delenv("CADROBOT_ROBOT_FOLDER")
        from CadRobotWB import preferences
        preferences.use_user_robot_folder()
