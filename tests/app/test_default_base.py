"""A new cell's robot stands beside the part, and the check says when it stands inside one
(issue 20 item 7), on the angle cleat standing on its plate (examples/angle_cleat.py).

Hand-derived numbers, ABB IRB 2400 (catalog OPW lengths: a1 = 100, c1 = 615, c2 = 705,
a2 = -135, c3 = 755 mm; base solid radius 0.085 * (c2 + hypot(a2, c3)) = 125.1 mm):
the wrist centre reaches far = c2 + hypot(a2, c3) = 1471.97 mm from axis 2, so the
rule's distance from the work's centre to axis 1 is a1 + far / 2 = 835.99 mm.
Solids: plate x 0..300, y 0..250, z 0..10; cleat z 10..60 -> box centre (150, 125), top
60, wider in X than in Y -> the robot on the -Y side, turned +90 deg about Z (+X toward
the part); on the floor (z = 0) the work's top would be less than c1 above the base, so
the base goes down until the shoulder is level with it: z = 60 - 615 = -555 mm.
"""

import math

import FreeCAD
import numpy as np
import Part
import pytest

from CadRobotWB import api
from CadRobotWB.objects.convert import matrix_from_placement
from CadRobotWB.workflow import base_site

from angle_cleat import cleat_on_plate, foot_loop_edges

V = FreeCAD.Vector
FAR_MM = 705.0 + math.hypot(135.0, 755.0)
DISTANCE_MM = 100.0 + FAR_MM / 2.0
FOOTPRINT_MM = 0.085 * FAR_MM


@pytest.fixture
def cleat_doc(doc):
    cleat, _plate = cleat_on_plate(doc)
    return doc, cleat


def add_loop(doc, cell, cleat):
    """The fillet all round the cleat's foot, its tool markers the automatic ones."""
    api.make_calibration_frame(doc, cell, FreeCAD.Placement(V(0, 0, 10), FreeCAD.Rotation()))
    path = api.make_path(doc, cell, [(cleat, e) for e in foot_loop_edges(cleat)])
    api.make_tool_markers_auto(doc, cell, path)
    return path


def test_a_new_cell_stands_beside_the_cleat_and_reaches_the_whole_loop(cleat_doc):
    doc, cleat = cleat_doc
    cell = api.make_cell(doc)
    base = cell.Placement.Base
    assert (base.x, base.y, base.z) == pytest.approx((150.0, 125.0 - DISTANCE_MM, 60.0 - 615.0),
                                                     abs=1e-6)
    # +X of the robot points at the part's centre (+Y of the drawing).
    assert tuple(cell.Placement.Rotation.multVec(V(1, 0, 0))) == pytest.approx((0, 1, 0), abs=1e-9)
    # Outside every solid's box: the footprint clears the plate's front edge (y = 0).
    for obj in (cleat, doc.getObject("BasePlate")):
        assert base.y + FOOTPRINT_MM < obj.Shape.BoundBox.YMin
    add_loop(doc, cell, cleat)
    result = api.check(cell, collisions=False)
    reach = [f for f in result.report.errors if f.kind in ("unreachable", "joint_limit")]
    # approach, entry, 6 lines and the lead's end on the y leg (the torch takes back its push
    # after the concave root, core.segment_orientation), 3 arcs (via and end: 2 targets each),
    # the reorientations at the leg ends' sharp corners (2; no risk areas here), retract:
    # 18 targets, all reached
    assert result.report.targets == 18 and reach == []
    assert not any(f.kind == "robot_inside" for f in result.report.findings)


def test_with_paths_the_default_faces_the_paths_and_not_the_solids(cleat_doc):
    doc, cleat = cleat_doc
    add_loop(doc, api.make_cell(doc, placement=FreeCAD.Placement()), cleat)
    # The loop's box: x 100..200, y 75..175 at z = 10 -> centre (150, 125), top 10.
    base = api.make_cell(doc, name="Second").Placement.Base
    assert (base.x, base.y, base.z) == pytest.approx((150.0, 125.0 - DISTANCE_MM, 10.0 - 615.0),
                                                     abs=1e-6)


def test_a_document_without_solids_keeps_the_origin_paths_or_not(doc):
    assert api.make_cell(doc).Placement.isIdentity()
    sketch = doc.addObject("Sketcher::SketchObject", "Seam")
    sketch.addGeometry(Part.LineSegment(V(500, 0, 0), V(800, 0, 0)), False)
    doc.recompute()
    api.make_path(doc, api.make_cell(doc, name="First"), sketch)
    assert api.make_cell(doc, name="Second").Placement.isIdentity()


def test_a_robot_at_the_origin_stands_in_the_plate_and_the_first_line_says_so(cleat_doc):
    doc, cleat = cleat_doc
    cell = api.make_cell(doc, placement=FreeCAD.Placement())
    add_loop(doc, cell, cleat)
    result = api.check(cell, collisions=False)      # python-fcl or not
    assert result.lines()[0] == (
        "Cell: ERROR: robot_inside: the robot ABB_IRB2400 stands inside BasePlate (its base at "
        "(0.0, 0.0, 0.0) mm is within the part): move the robot beside it (Place robot), or give "
        "the cell another Placement.")
    assert result.report.placement_helps            # the GUI's button, the CLI's place hint
    # A quarter of the base's footprint is in the 10 mm plate: pi r^2 / 4 * 10 mm^3.
    (label, volume), = base_site.parts_inside(doc, "ABB_IRB2400", _matrix(cell))
    assert label == "BasePlate"
    assert volume == pytest.approx(math.pi * FOOTPRINT_MM ** 2 / 4 * 10.0, rel=1e-3)


def test_standing_on_the_plate_or_under_both_parts(cleat_doc):
    doc, _cleat = cleat_doc
    on_plate = _translation(280, 230, 10)      # on its top face, 165 mm from the cleat's x leg
    assert base_site.parts_inside(doc, "ABB_IRB2400", on_plate) == []
    under = _translation(150, 125, -300)       # the column rises through the plate and the cleat
    assert [label for label, _ in base_site.parts_inside(doc, "ABB_IRB2400", under)] == [
        "BasePlate", "AngleCleat"]


def _translation(x, y, z):
    T = np.eye(4)
    T[:3, 3] = (x, y, z)
    return T


def _matrix(cell):
    return matrix_from_placement(cell.Placement)
