"""Seam tracking round a corner: the programmed corners, the tracking hold, the hand-over.

The cell: a 40 mm high block (x -50..60, y 0..100) standing on a plate (top z = 0);
the fillet runs along its foot, leg 1 from (-20, 0) to the convex corner (60, 0)
travelling +X, leg 2 up its end face to (60, 60) travelling +Y. The torch turns in
place at the corner and points into each fillet at 45°. 10 mm/s, laser 30 mm ahead
at 5 Hz: a profile every 2 mm, the corner at s = 80 mm.
"""

import numpy as np
import trimesh

from CadRobotWB.sensors.corners import CornerZone, corner_zones, in_hold
from CadRobotWB.sensors.reality import Reality
from CadRobotWB.sensors.seam_features import JointTemplate
from CadRobotWB.sensors.seam_tracking import simulate_seam_tracking
from test_seam_tracking import box, real, trajectory

FILLET = JointTemplate("fillet")
BLOCK = trimesh.util.concatenate([box((-60, -60, -10), (140, 140, 0)), box((-50, 0, 0), (60, 100, 40))])
CORNER_S_MM = 80.0


def torch(travel, into):
    """Tool rotation: X along `travel`, Z (approach) along `into`."""
    z = np.asarray(into, float) / np.linalg.norm(into)
    x = np.asarray(travel, float)
    return np.column_stack([x, np.cross(z, x), z])


ALONG_X = torch((1, 0, 0), (0, 1, -1))           # leg 1: the wall on +Y
ALONG_Y = torch((0, 1, 0), (-1, 0, -1))          # leg 2: the end face on -X


ROUND_THE_BLOCK = trajectory([(-20, 0, 0), (60, 0, 0), (60, 0, 0), (60, 60, 0)],
                             [ALONG_X, ALONG_X, ALONG_Y, ALONG_Y])


def shifted(dx, dy, dz):
    T = np.eye(4)
    T[:3, 3] = dx, dy, dz
    return Reality(T_u_dev=T, seed=4)


# ------------------------------------------------------------------ corners of a path


def chords(points):
    points = np.asarray(points, float)
    d = np.diff(points, axis=0)
    length = np.linalg.norm(d, axis=1)
    return np.r_[0.0, np.cumsum(length)], d / length[:, None]


def arc(centre, radius_mm, start_deg, end_deg, n=30):
    a = np.radians(np.linspace(start_deg, end_deg, n))
    return np.column_stack([centre[0] + radius_mm * np.cos(a), centre[1] + radius_mm * np.sin(a), 0 * a])


def test_a_sharp_corner_and_a_small_toe_arc_are_one_corner_a_wide_arc_none():
    # the end of a cleat's leg: 100 mm, a sharp 90° turn, 4 mm, an R6 toe turning 90° more
    leg_end = np.vstack([[(0, 0, 0)], [(100, 0, 0)], [(100, 4, 0)], arc((94, 4), 6.0, 0, 90)[1:],
                         [(50, 10, 0)]])
    (zone,) = corner_zones(*chords(leg_end))
    assert zone.s_in_mm == 100.0                                       # the sharp corner
    toe_mm = 29 * 2 * 6.0 * np.sin(np.radians(90.0 / 29) / 2)           # its 29 chords
    assert abs(zone.s_out_mm - (104 + toe_mm)) < 1e-9                   # the toe's end
    assert abs(zone.turn_deg - 180.0) < 1e-9
    # an R50 bend of 90° (radius above 30 mm) is followed like a straight seam ...
    bend = np.vstack([[(-100, -50, 0)], arc((0, 0), 50.0, 270, 360), [(50, 100, 0)]])
    assert corner_zones(*chords(bend)) == []
    # ... an R12 root is a corner (turn 90° over 18.8 mm)
    (root,) = corner_zones(*chords(np.vstack([[(-100, -12, 0)], arc((0, 0), 12.0, 270, 360),
                                              [(12, 100, 0)]])))
    root_mm = 29 * 2 * 12.0 * np.sin(np.radians(90.0 / 29) / 2)
    assert abs(root.turn_deg - 90.0) < 1e-9 and abs(root.s_out_mm - root.s_in_mm - root_mm) < 1e-9


# ------------------------------------------------------------------ the hand-over


def test_the_laser_holds_round_a_convex_corner_and_hands_over_to_the_next_leg():
    # The block 7 mm back along leg 1 (-X), 7 mm aside (+Y), 1 mm up: the real leg 1 ends at
    # x = 53, 7 mm before the programmed corner. The stripe (x = s - 20, moved by the 7 mm
    # lateral correction) misses at x = 54, 56, 58: three profiles in a row.
    reality = shifted(-7.0, 7.0, 1.0)
    seam = reality.rigid_points([(-50, 0, 0), (60, 0, 0), (60, 100, 0)])
    mesh = real(BLOCK, reality)
    without = simulate_seam_tracking(ROUND_THE_BLOCK, mesh, seam, reality, FILLET, corner_hold_mm=0.0)
    assert without.aborted and "laser at s = 78.0 mm" in without.reason
    run = simulate_seam_tracking(ROUND_THE_BLOCK, mesh, seam, reality, FILLET)
    assert not run.aborted, run.reason
    m = run.metrics
    assert (m["corners"], m["corner_holds"], m["seam_lost_count"]) == (1, 3, 3)
    assert m["rms_error_after_20mm_mm"] <= 0.1
    # Leg 1 measures the lateral 7 and the height 1; leg 2, re-acquired, the -7 along X;
    # the held correction is the translation itself, so the torch turns at the real corner
    # (within 0.1 mm: the 7 mm along X, seen 28 mm ahead, is taken at 0.5 mm a period).
    s = np.interp(run.time_s, ROUND_THE_BLOCK.time_s, ROUND_THE_BLOCK.s_mm)
    leg1 = run.correction_mm[(s > 30) & (s < 50)]
    np.testing.assert_allclose(leg1[:, 1:], np.tile([7.0, 1.0], (len(leg1), 1)), atol=0.05)
    leg2 = run.correction_mm[s > CORNER_S_MM + 10]
    np.testing.assert_allclose(leg2, np.tile([-7.0, 7.0, 1.0], (len(leg2), 1)), atol=0.05)
    corner = np.argmin(np.abs(s - CORNER_S_MM))
    np.testing.assert_allclose(run.actual_mm[corner], [53.0, 7.0, 1.0], atol=0.1)


def test_a_seam_that_ends_at_a_corner_is_still_lost_after_the_hold():
    # The path turns at the block's corner onto the bare plate (-Y): no wall on leg 2. The
    # profiles at s = 80 ... 90 (the corner and 10 mm of hold) are held, 92, 94, 96 lost.
    away = torch((0, -1, 0), (-1, 0, -1))
    off_the_end = trajectory([(-20, 0, 0), (60, 0, 0), (60, 0, 0), (60, -50, 0)],
                             [ALONG_X, ALONG_X, away, away])
    reality = Reality(seed=4)
    seam = np.array([(-50, 0, 0), (60, 0, 0)], float)
    run = simulate_seam_tracking(off_the_end, real(BLOCK, reality), seam, reality, FILLET)
    assert run.aborted and "laser at s = 96.0 mm" in run.reason
    assert abs(run.metrics["stop_s_mm"] - 66.0) < 1e-9                   # the TCP 30 mm behind
    assert (run.metrics["corner_holds"], run.metrics["seam_lost_count"]) == (6, 9)


def test_a_seam_that_ends_beside_another_joint_is_lost_not_swapped_for_it():
    # The wall ends at x = 101; another one, 8 mm further aside, starts there. The stripe
    # (x = s - 20) finds that one's fillet at x = 102, 104, 106: 8 mm from the seam, beyond
    # the 5 mm capture, so three profiles without the seam.
    walls = trimesh.util.concatenate([box((-60, -60, -10), (200, 60, 0)), box((-50, 0, 0), (101, 40, 40)),
                                      box((101, 8, 0), (200, 48, 40))])
    straight = trajectory([(-20, 0, 0), (150, 0, 0)], ALONG_X)
    reality = Reality(seed=4)
    seam = np.array([(-50, 0, 0), (101, 0, 0)], float)
    run = simulate_seam_tracking(straight, real(walls, reality), seam, reality, FILLET)
    assert run.aborted and "laser at s = 126.0 mm" in run.reason
    assert run.metrics["other_joints"] == 3
    swapped = simulate_seam_tracking(straight, real(walls, reality), seam, reality, FILLET, capture_mm=1e6)
    assert not swapped.aborted and abs(swapped.correction_mm[-1, 1] - 8.0) < 0.05   # the other wall's


def test_a_hold_covers_a_short_corner_but_only_the_ends_of_a_long_one():
    toe = CornerZone(100.0, 113.4, 180.0)                 # a leg's end: held from 90 to 123.4
    assert [in_hold([toe], s, 10.0) for s in (89.9, 90.0, 106.7, 123.4, 123.5)] == \
        [False, True, True, True, False]
    ring = CornerZone(0.0, 2 * np.pi * 20.0, 360.0)       # an R20 boss welded all round
    assert [in_hold([ring], s, 10.0) for s in (10.0, 11.0, 62.8, 115.0, 116.0)] == \
        [True, False, False, False, True]
