"""Tests of core/interpolation.py (eqs 8-15) against hand-worked examples and scipy."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation, Slerp

from CadRobotWB.core import interpolation as interp
from CadRobotWB.errors import InputError

REPO = Path(__file__).resolve().parents[2]


def test_module_imports_neither_scipy_nor_freecad():
    code = ("import sys, CadRobotWB.core.interpolation; "
            "bad = [m for m in ('scipy', 'FreeCAD') if m in sys.modules]; "
            "sys.exit(1 if bad else 0)")
    assert subprocess.run([sys.executable, "-c", code], cwd=REPO).returncode == 0


# --- stations -----------------------------------------------------------------

@pytest.mark.parametrize("length, step, expected", [
    (10.0, 2.5, [0, 2.5, 5, 7.5, 10]),               # even division
    (10.0, 4.0, [0, 4, 8, 10]),                      # last interval is the 2 mm remainder
    (3.0, 5.0, [0, 3]),                              # step longer than the section
    (10.0, 10.0, [0, 10]),
    (0.0, 1.0, [0]),
])
def test_stations_hand_worked(length, step, expected):
    s = interp.stations(length, step)
    np.testing.assert_allclose(s, expected, rtol=0, atol=1e-12)
    assert s[-1] == length


def test_stations_no_sliver_interval_from_rounding():
    # 30.1 / 4.3 evaluates to 7.000000000000001: still 7 intervals, not 8.
    assert 30.1 / 4.3 > 7
    s = interp.stations(30.1, 4.3)
    assert len(s) == 8
    np.testing.assert_allclose(np.diff(s), 4.3, rtol=1e-12)


def test_stations_intervals_equal_step_but_last():
    s = interp.stations(123.4, 1.7)
    d = np.diff(s)
    assert len(s) == int(np.ceil(123.4 / 1.7)) + 1
    np.testing.assert_allclose(d[:-1], 1.7, rtol=1e-12)
    assert 0 < d[-1] <= 1.7
    assert s[-1] == 123.4


@pytest.mark.parametrize("length, step", [(10, 0), (10, -1), (10, np.nan), (-1, 1), (np.inf, 1)])
def test_stations_rejects_bad_input(length, step):
    with pytest.raises(InputError):
        interp.stations(length, step)


# --- interpolate_positions (eqs 8-13) ---------------------------------------

def test_positions_paper_style_example():
    # |v| = 10 mm/s, Δt = 0.25 s -> 2.5 mm apart along x.
    r = interp.interpolate_positions([0, 0, 0], [10, 0, 0], 10.0, 0.25)
    np.testing.assert_allclose(r, [[0, 0, 0], [2.5, 0, 0], [5, 0, 0], [7.5, 0, 0], [10, 0, 0]],
                               rtol=0, atol=1e-12)


def test_positions_uneven_last_interval():
    # |v| = 4 mm/s, Δt = 1 s -> 0, 4, 8 and then the end point at 10.
    r = interp.interpolate_positions([0, 0, 0], [10, 0, 0], 4.0, 1.0)
    np.testing.assert_allclose(r[:, 0], [0, 4, 8, 10], rtol=0, atol=1e-12)
    np.testing.assert_array_equal(r[:, 1:], 0.0)


def test_positions_oblique_hand_worked():
    # W = (6, 8, 0), |W| = 10, |v| = 2 mm/s, Δt = 1.5 s -> step 3 mm along (0.6, 0.8, 0):
    # eq 10: v = (1.2, 1.6, 0); eq 13: r(1) = (1, 2, 3) + v * 1.5 = (2.8, 4.4, 3).
    r = interp.interpolate_positions([1, 2, 3], [7, 10, 3], 2.0, 1.5)
    np.testing.assert_allclose(r, [[1, 2, 3], [2.8, 4.4, 3], [4.6, 6.8, 3], [6.4, 9.2, 3],
                                   [7, 10, 3]], rtol=0, atol=1e-12)


def test_positions_endpoints_exact_and_on_the_segment():
    p0 = np.array([12.3, -45.6, 78.9])
    p1 = np.array([-101.1, 202.2, 33.3])
    r = interp.interpolate_positions(p0, p1, 37.0, 0.012)
    np.testing.assert_array_equal(r[0], p0)                  # eq 11
    np.testing.assert_array_equal(r[-1], p1)                 # eq 12
    d = np.linalg.norm(np.diff(r, axis=0), axis=1)
    np.testing.assert_allclose(d[:-1], 37.0 * 0.012, rtol=1e-9)
    assert 0 < d[-1] <= 37.0 * 0.012 * (1 + 1e-9)
    # Every point lies on the segment: no component off the direction W.
    u = (p1 - p0) / np.linalg.norm(p1 - p0)
    off = (r - p0) - np.outer((r - p0) @ u, u)
    np.testing.assert_allclose(off, 0.0, atol=1e-9)
    assert len(r) == int(np.ceil(np.linalg.norm(p1 - p0) / (37.0 * 0.012))) + 1


@pytest.mark.parametrize("speed, dt, message", [
    (0.0, 0.1, "speed"), (-5.0, 0.1, "speed"), (10.0, 0.0, "Sampling time"),
    (10.0, -0.1, "Sampling time"),
])
def test_positions_rejects_non_positive_speed_or_dt(speed, dt, message):
    with pytest.raises(InputError, match=message):
        interp.interpolate_positions([0, 0, 0], [10, 0, 0], speed, dt)


def test_positions_rejects_coincident_points():
    with pytest.raises(InputError, match="coincident"):
        interp.interpolate_positions([1, 2, 3], [1, 2, 3], 10.0, 0.1)


# --- interpolate_orientations (eqs 14-15) -----------------------------------

def test_orientations_hand_derived_quarter_turn():
    s = np.sqrt(0.5)
    q = interp.interpolate_orientations([1, 0, 0, 0], [s, 0, 0, s], [0.0, 0.5, 1.0])
    expected = [[1, 0, 0, 0], [np.cos(np.pi / 8), 0, 0, np.sin(np.pi / 8)], [s, 0, 0, s]]
    np.testing.assert_allclose(q, expected, atol=1e-15)


def test_orientations_match_scipy_slerp():
    r = Rotation.random(2, random_state=12)
    q0, qn = np.roll(r.as_quat(), 1, axis=-1)
    fractions = np.array([0.0, 0.13, 0.4, 0.77, 1.0])
    q = interp.interpolate_orientations(q0, qn, fractions)
    assert q.shape == (5, 4)
    expected = np.roll(Slerp([0, 1], r)(fractions).as_quat(), 1, axis=-1)
    np.testing.assert_allclose(np.abs(np.sum(q * expected, axis=1)), 1.0, atol=1e-12)


def test_orientations_single_fraction_gives_one_row():
    assert interp.interpolate_orientations([1, 0, 0, 0], [0, 0, 0, 1], 0.5).shape == (1, 4)
