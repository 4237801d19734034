"""A new cell's default robot base (robots/placement/default_base.py): the side, the distance,
the floor and the height, against hand-derived numbers for the ABB IRB 2400.

IRB 2400 (catalog OPW lengths a1 = 100, c1 = 615, c2 = 705, a2 = -135, c3 = 755 mm): the
wrist centre reaches far = c2 + hypot(a2, c3) = 1471.97 mm from axis 2, so the work's
centre lies a1 + far / 2 = 835.99 mm from axis 1; the base solid's radius is
0.085 * far = 125.12 mm (links.RADIUS_FRACTIONS).
"""

import math

import numpy as np
import pytest

from CadRobotWB.robots.placement import default_base

ROBOT = "ABB_IRB2400"
FAR_MM = 705.0 + math.hypot(135.0, 755.0)
DISTANCE_MM = 100.0 + FAR_MM / 2.0
FOOTPRINT_MM = 0.085 * FAR_MM
SHOULDER_MM = 615.0
TURNED_90 = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])


def box(lo, hi):
    return [lo, hi]


def test_the_rules_numbers():
    assert default_base.reach_distance_mm(ROBOT) == pytest.approx(DISTANCE_MM, abs=1e-6)
    assert default_base.footprint_radius_mm(ROBOT) == pytest.approx(FOOTPRINT_MM, abs=1e-6)
    assert default_base.shoulder_height_mm(ROBOT) == SHOULDER_MM


def test_a_part_longer_in_y_has_the_robot_on_its_minus_x_side_facing_it():
    T = default_base.default_base(ROBOT, [box((0, 0, 0), (100, 400, 50))])
    np.testing.assert_allclose(T[:3, 3], (50 - DISTANCE_MM, 200, 50 - SHOULDER_MM), atol=1e-6)
    np.testing.assert_allclose(T[:3, :3], np.eye(3), atol=1e-12)


def test_a_floor_slab_under_everything_is_stood_on_and_is_not_the_work():
    slab, part = box((-2000, -2000, -20), (2000, 2000, 0)), box((0, 0, 0), (300, 250, 60))
    T = default_base.default_base(ROBOT, [slab, part])
    np.testing.assert_allclose(T[:3, 3], (150, 125 - DISTANCE_MM, 0), atol=1e-6)
    np.testing.assert_allclose(T[:3, :3], TURNED_90, atol=1e-12)
    assert default_base.default_base(ROBOT, [slab]) is None       # a floor only: no work


def test_a_table_within_the_distance_is_stood_beside_on_the_floor():
    table, part = box((-750, -500, 0), (750, 500, 800)), box((-100, -100, 800), (100, 100, 850))
    T = default_base.default_base(ROBOT, [table, part])
    # The top, 850 mm, is above the shoulder from the floor: the robot stays on the floor.
    np.testing.assert_allclose(T[:3, 3], (0, -DISTANCE_MM, 0), atol=1e-6)


def test_a_wide_work_pushes_the_robot_out_until_its_footprint_clears_the_box():
    a, b = box((0, 0, 0), (2000, 1000, 100)), box((0, 1000, 0), (2000, 3000, 100))
    T = default_base.default_base(ROBOT, [a, b])
    # -X side (3000 mm in Y); 1000 mm to the edge + footprint + 100 mm > 835.99 mm.
    x = 1000 - (1000 + FOOTPRINT_MM + default_base.CLEARANCE_MM)
    np.testing.assert_allclose(T[:3, 3], (x, 1500, 100 - SHOULDER_MM), atol=1e-6)


def test_paths_without_solids_and_no_work_at_all():
    T = default_base.default_base(ROBOT, np.zeros((0, 2, 3)), box((100, 75, 10), (200, 175, 10)))
    np.testing.assert_allclose(T[:3, 3], (150, 125 - DISTANCE_MM, 10 - SHOULDER_MM), atol=1e-6)
    assert default_base.default_base(ROBOT, np.zeros((0, 2, 3))) is None
