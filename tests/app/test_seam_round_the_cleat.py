"""Issue 20: the laser follows the fillet all round the angle cleat, corners included.

The cleat of ``examples/angle_cleat.py`` (an L100x100x10 standing on a plate) welded all
round its foot: 9 edges, 389.7 mm, with the tool markers the workbench puts on it. Going
round from the heel, the path turns at the end of the x leg (a sharp 90° and the R6 toe:
180° within s = 100 ... 113.4 mm), at the R12 root (90°, s = 185.4 ... 204.3 mm) and at
the end of the y leg (s = 276.3 ... 289.7 mm). The real part stands 2 mm off along X and
along Y (2 mm across every straight leg, as in ``examples/fillet_cell.py``) and 1 mm high.

Cost: each run reads the cell and tracks the whole 390 mm loop (185 profiles), about 1.2 s of
CPU; only the whole loop goes round all three corners with the markers the workbench sets.
"""

import numpy as np
import pytest

import FreeCAD
from CadRobotWB import api
from angle_cleat import LEG_MM, ROOT_RADIUS_MM, THICKNESS_MM, TOE_RADIUS_MM, cleat_on_plate, foot_loop_edges

DEVIATION = (2.0, 2.0, 1.0, 0.0, 0.0, 0.0)              # mm and degrees: 2 mm lateral, 1 mm high
END_MM = THICKNESS_MM - TOE_RADIUS_MM                  # the straight end of a leg, 4 mm
INNER_MM = LEG_MM - THICKNESS_MM - ROOT_RADIUS_MM - TOE_RADIUS_MM
TOE_ARC_MM, ROOT_ARC_MM = np.pi / 2 * TOE_RADIUS_MM, np.pi / 2 * ROOT_RADIUS_MM
X_END = (LEG_MM, LEG_MM + END_MM + TOE_ARC_MM)         # s of the three corners, mm
ROOT = (X_END[1] + INNER_MM, X_END[1] + INNER_MM + ROOT_ARC_MM)
Y_END = (ROOT[1] + INNER_MM, ROOT[1] + INNER_MM + TOE_ARC_MM + END_MM)
NEAR_MM = 10.0                                         # a corner's neighbourhood, each side


@pytest.fixture(scope="module")
def cleat_cell():
    doc = FreeCAD.newDocument("CleatSeam")
    cleat, _ = cleat_on_plate(doc)
    cell = api.make_cell(doc)
    # beside the plate and below it, where the IRB 2400 reaches the whole loop
    api.set_robot_placement(cell, FreeCAD.Placement(FreeCAD.Vector(-600, 125, -400), FreeCAD.Rotation()))
    api.make_calibration_frame(doc, cell, FreeCAD.Placement(FreeCAD.Vector(0, 0, 10), FreeCAD.Rotation()))
    path = api.make_path(doc, cell, [(cleat, e) for e in foot_loop_edges(cleat)])
    api.make_tool_markers_auto(doc, cell, path)
    yield cell
    FreeCAD.closeDocument(doc.Name)


def path_distance(run):
    """s (N,) of each sample of a completed run, along its nominal path, mm."""
    return np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(run.nominal_mm, axis=0), axis=1))]


def corner_errors(run):
    """Largest error (mm) within NEAR_MM of each corner."""
    s = path_distance(run)
    return [np.nanmax(run.error_mm[(s >= a - NEAR_MM) & (s <= b + NEAR_MM)]) for a, b in (X_END, ROOT, Y_END)]


def test_the_laser_follows_the_fillet_round_every_corner_of_the_loop(cleat_cell):
    run = api.simulate(cleat_cell, sensor="laser", deviation=DEVIATION)
    assert not run.aborted, run.reason
    m = run.metrics
    assert abs(path_distance(run)[-1] - 389.7) < 0.1                     # all the way round
    assert m["corners"] == 3
    # open loop: hypot(2, 1) on every straight leg; the most, hypot(2 sqrt 2, 1) = 3 mm, half-way
    # round an arc, where (2, 2) points along the radius
    assert m["open_loop_max_error_mm"] == pytest.approx(3.0, abs=0.01)
    assert m["rms_error_after_20mm_mm"] <= 0.3
    assert max(corner_errors(run)) <= 0.3


def test_the_part_where_it_was_drawn_is_followed_without_a_correction(cleat_cell):
    run = api.simulate(cleat_cell, sensor="laser")
    assert not run.aborted, run.reason
    assert run.metrics["rms_error_after_20mm_mm"] <= 0.05
    assert np.abs(run.correction_mm).max() <= 0.1
