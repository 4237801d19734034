"""The track rides abreast of the torch (issue 23): one offset per run from abreast of each
seam target, or the lazy travel where that ranks worse.

The fixture (``external_fixtures.track_program``): the ABB IRB 2400 at the origin on a track
along +X (travel 0..4000 mm), seams at z = 400 mm. Along a straight seam parallel to the
track, travel = x - c with one c puts every target at the same pose relative to the robot
base, so every joint is the same number along the weld.
"""

import numpy as np
import pytest

from CadRobotWB.robots.checks import checks
from CadRobotWB.robots.kinematics import models
from CadRobotWB.robots.mechanisms import arm_fit, choose
from CadRobotWB.robots.mechanisms.choose import choose_external
from CadRobotWB.robots.motion import configuration

from external_fixtures import track_program

S = 1.0 / np.sqrt(2.0)
#: The torch 45 degrees into a fillet's corner, away from the robot (which stands at -y
#: of the seam): tool Z (0, 1, -1)/sqrt 2, X along the seam.
INTO_CORNER = np.array([[1.0, 0.0, 0.0], [0.0, -S, S], [0.0, -S, -S]])


@pytest.fixture(scope="module")
def arm():
    return models.model("ABB_IRB2400")


def seam_travel(program, n):
    names = {t.name: t for t in program.targets()}
    return np.array([names["s%d" % k].external[0] for k in range(n)])


def test_a_long_fillet_parallel_to_the_track_rides_abreast(arm):
    """2.5 m fillet 886 mm beside the track: travel - x is one number along the run, within
    the travel; the solved joints are the same at every seam target (within 1e-6 deg: each
    is the same pose in the robot base, so the closed-form IK gives the same numbers, and
    one branch is kept), J1 and J4 included; Check finds no joint limit, reach or
    singularity error."""
    x = np.arange(500.0, 3001.0, 250.0)
    program = track_program(x, y_mm=886.0, travel_mm=4000.0, R_tcp=INTO_CORNER)
    choice = choose_external(program, arm)
    travel = seam_travel(program, len(x))
    assert choice.unhelped == []
    assert np.ptp(travel - x) < 1e-6 and np.all((travel > 0.0) & (travel < 4000.0))
    solution = configuration.solve_program(program, arm, assign=False)
    q = np.array([e.joints_deg for e in solution.entries])[1:-1]      # the seam targets
    assert np.ptp(q, axis=0).max() < 1e-6
    report = checks.check_program(program, arm, solution)
    assert report.ok and {f.kind for f in report.findings} <= {"weld_position"}


def test_the_offset_is_the_best_ranked_and_abreast_is_a_candidate(arm):
    """The offsets tried include 0 (the run's middle, and every target, abreast), and the
    one taken is the best ranked of them by the arm along the run (fewest missed, then best
    worst point, then best sum)."""
    x = np.arange(500.0, 3001.0, 250.0)
    program = track_program(x, y_mm=886.0, travel_mm=4000.0, R_tcp=INTO_CORNER)
    assert np.any(np.abs(choose.ABREAST_OFFSETS) < 1e-12)
    choose_external(program, arm)
    c = float(np.mean(x - seam_travel(program, len(x))))
    far = arm_fit.reach_band(arm)[1]
    assert np.min(np.abs(choose.ABREAST_OFFSETS * far - c)) < 1e-6


def test_a_seam_across_the_track_keeps_the_lazy_travel(arm):
    """A seam across the track (x = 1500, y 600 -> 1100): abreast of every target is the
    same travel, so each offset is one constant travel; every one of them has a worse worst
    point than the lazy travel (which keeps each target within the reach band from the
    robot's side, moving as the band asks: by hand 1500 - sqrt(r^2 - y^2) at each y, r the
    band's outer radius, clipped to 0..4000), so the lazy travel stays."""
    y = np.arange(600.0, 1101.0, 100.0)
    program = track_program(np.full(len(y), 1500.0), y_mm=y, travel_mm=4000.0)
    choice = choose_external(program, arm)
    far = arm_fit.reach_band(arm)[1]
    lazy = np.maximum.accumulate(1500.0 - np.sqrt(far ** 2 - y ** 2))
    np.testing.assert_allclose(seam_travel(program, len(y)), lazy, atol=1e-6)
    assert choice.unhelped == []


def test_a_seam_at_30_degrees_to_the_track_rides_with_one_offset(arm):
    """A 1 m seam at 30 degrees to the track, from (500, 500) away from it: abreast of each
    target is its x, so travel - x is one number; every target reached, Check passes."""
    t = np.arange(0.0, 1001.0, 125.0)
    x, y = 500.0 + t * np.cos(np.radians(30.0)), 500.0 + t * np.sin(np.radians(30.0))
    program = track_program(x, y_mm=y, travel_mm=4000.0)
    choice = choose_external(program, arm)
    travel = seam_travel(program, len(x))
    assert choice.unhelped == [] and np.ptp(travel - x) < 1e-6
    report = checks.check_program(program, arm)
    assert report.ok, [f.kind for f in report.findings]


def test_a_track_slower_than_the_weld_keeps_the_lazy_travel_for_the_speed_pass(arm):
    """A seam 500 mm beside the track (inside the reach band's inner radius, 0.35 x 1572 =
    550 mm, so the speed pass may move the travel only behind the robot's side) welded at
    7.5 mm/s on a 5 mm/s track: abreast, the carriage would move as the torch does (250 mm
    per 33.3 s move = 7.5 mm/s) with no room to slow it; the lazy travel stays and the
    speed pass moves it within the band: every move's track speed (by hand: travel step
    over 250 mm / 7.5 mm/s) within 5 mm/s, and Check passes."""
    x = np.arange(500.0, 3001.0, 250.0)
    program = track_program(x, y_mm=500.0, travel_mm=4000.0, track_limits=(5.0, 2000.0))
    choice = choose_external(program, arm)
    travel = seam_travel(program, len(x))
    assert choice.limited == {"W": ["E1"]} and np.ptp(travel - x) > 100.0
    assert np.abs(np.diff(travel)).max() / (250.0 / 7.5) <= 5.0 + 1e-9
    assert checks.check_program(program, arm).ok


def test_a_pose_near_a_singularity_counts_as_missed(arm):
    """The fillet 600 mm beside the track: riding exactly abreast the torch lies in the
    arm's plane and the wrist bends 4.7 deg (J5), inside Check's 5 deg margin; the offset
    taken keeps every seam target's J5 outside that margin, and Check passes."""
    x = np.arange(500.0, 3001.0, 250.0)
    program = track_program(x, y_mm=600.0, travel_mm=4000.0, R_tcp=INTO_CORNER)
    choose_external(program, arm)
    travel = seam_travel(program, len(x))
    assert np.ptp(travel - x) < 1e-6 and abs(np.mean(travel - x)) > 100.0
    solution = configuration.solve_program(program, arm, assign=False)
    j5 = np.array([e.joints_deg[4] for e in solution.entries])[1:-1]
    assert np.all(np.abs(j5) > 5.0)
    assert checks.check_program(program, arm, solution).ok
