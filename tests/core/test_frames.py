"""Tests of core/frames.py (eqs 1-7, frame teaching) against hand-derived frames,
numpy.linalg.inv and known rigid transforms."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from CadRobotWB.core import frames
from CadRobotWB.errors import FrameError

REPO = Path(__file__).resolve().parents[2]

RZ90 = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])

# {B} rotated 90 deg about Z of {U}, origin at (100, 200, 0) in {U}:
# x_B = y_U, y_B = -x_U, z_B = z_U.
T_U_B = np.array([[0.0, -1.0, 0.0, 100.0],
                  [1.0, 0.0, 0.0, 200.0],
                  [0.0, 0.0, 1.0, 0.0],
                  [0.0, 0.0, 0.0, 1.0]])


def random_rigid(n, seed):
    rng = np.random.default_rng(seed)
    T = np.tile(np.eye(4), (n, 1, 1))
    T[:, :3, :3] = Rotation.random(n, random_state=seed).as_matrix()
    T[:, :3, 3] = rng.uniform(-2000, 2000, (n, 3))
    return T


def test_module_imports_neither_scipy_nor_freecad():
    code = ("import sys, CadRobotWB.core.frames; "
            "bad = [m for m in ('scipy', 'FreeCAD') if m in sys.modules]; "
            "sys.exit(1 if bad else 0)")
    assert subprocess.run([sys.executable, "-c", code], cwd=REPO).returncode == 0


def test_make_transform():
    np.testing.assert_array_equal(frames.make_transform(), np.eye(4))
    np.testing.assert_array_equal(frames.make_transform(RZ90, [100, 200, 0]), T_U_B)
    np.testing.assert_array_equal(frames.make_transform(p=[1, 2, 3])[:3, 3], [1, 2, 3])
    np.testing.assert_array_equal(frames.make_transform(R=RZ90)[:3, 3], [0, 0, 0])


# --- eqs 1-7 ----------------------------------------------------------------

def test_hand_derived_point_in_b():
    # U point (100, 210, 5) is 10 mm along y_U = x_B from B's origin, 5 mm up.
    T_b_u = frames.invert_transform(T_U_B)
    np.testing.assert_allclose(frames.transform_points(T_b_u, [100, 210, 5]), [10, 0, 5],
                               atol=1e-12)
    np.testing.assert_allclose(frames.transform_points(T_U_B, [10, 0, 5]), [100, 210, 5],
                               atol=1e-12)


def test_eq6_origin_of_u_in_b_hand_derived():
    # U's origin is at (-100, -200, 0) from B's origin in U axes:
    # along x_B = y_U: -200, along y_B = -x_U: +100.
    T_b_u = frames.invert_transform(T_U_B)
    np.testing.assert_allclose(T_b_u[:3, 3], [-200, 100, 0], atol=1e-12)
    np.testing.assert_allclose(T_b_u[:3, :3], RZ90.T, atol=0)


def test_eq7_matches_numpy_inverse():
    T = random_rigid(50, 1)
    T_inv = frames.invert_transform(T)
    assert T_inv.shape == (50, 4, 4)
    np.testing.assert_allclose(T_inv, np.linalg.inv(T), atol=1e-9)
    np.testing.assert_allclose(frames.invert_transform(T[0]), np.linalg.inv(T[0]), atol=1e-9)


def test_eq1_relative_transform_hand_derived():
    # Tool marker {C} at U (100, 210, 5), axes parallel to U.
    T_u_c = frames.make_transform(p=[100, 210, 5])
    T_b_c = frames.relative_transform(T_U_B, T_u_c)
    np.testing.assert_allclose(T_b_c[:3, 3], [10, 0, 5], atol=1e-12)
    np.testing.assert_allclose(T_b_c[:3, :3], RZ90.T, atol=1e-15)   # Rz(-90 deg)


def test_eq1_relative_transform_matches_numpy():
    T_u_b, T_u_c = random_rigid(20, 2), random_rigid(20, 3)
    np.testing.assert_allclose(frames.relative_transform(T_u_b, T_u_c),
                               np.linalg.inv(T_u_b) @ T_u_c, atol=1e-9)


def test_transform_points_shapes_and_batch():
    T = random_rigid(1, 4)[0]
    P = np.random.default_rng(4).uniform(-500, 500, (30, 3))
    out = frames.transform_points(T, P)
    assert out.shape == (30, 3)
    homogeneous = (T @ np.column_stack([P, np.ones(30)]).T).T[:, :3]
    np.testing.assert_allclose(out, homogeneous, atol=1e-9)
    assert frames.transform_points(T, P[0]).shape == (3,)
    np.testing.assert_allclose(frames.transform_points(T, P[0]), homogeneous[0], atol=1e-9)


def test_transform_vectors_ignores_translation():
    np.testing.assert_allclose(frames.transform_vectors(T_U_B, [1, 0, 0]), [0, 1, 0], atol=1e-15)
    V = np.eye(3)
    np.testing.assert_allclose(frames.transform_vectors(T_U_B, V), RZ90.T, atol=1e-15)


# --- frame_from_three_points -------------------------------------------------

@pytest.mark.parametrize("in_xy", [[50, 200, 0], [70, 260, 0], [0, 1e4, 0]])
def test_frame_from_three_points_hand_derived(in_xy):
    # X along +y_U; the third point lies on B's +y side (-x_U).
    T = frames.frame_from_three_points([100, 200, 0], [100, 250, 0], in_xy)
    np.testing.assert_allclose(T, T_U_B, atol=1e-12)


def test_frame_from_three_points_third_point_side_sets_z():
    T = frames.frame_from_three_points([100, 200, 0], [100, 250, 0], [150, 200, 0])
    np.testing.assert_allclose(T[:3, 2], [0, 0, -1], atol=1e-15)
    assert frames.is_rigid_transform(T)


def test_frame_from_three_points_recovers_random_frame():
    for T_true in random_rigid(10, 5):
        origin = T_true[:3, 3]
        on_x = frames.transform_points(T_true, [300, 0, 0])
        in_xy = frames.transform_points(T_true, [-40, 120, 0])
        np.testing.assert_allclose(frames.frame_from_three_points(origin, on_x, in_xy), T_true,
                                   atol=1e-9)


@pytest.mark.parametrize("origin, on_x, in_xy, message", [
    ([0, 0, 0], [10, 0, 0], [25, 0, 0], "collinear"),
    ([0, 0, 0], [10, 10, 10], [-3, -3, -3], "collinear"),
    ([0, 0, 0], [10, 0, 0], [5, 1e-9, 0], "collinear"),
    ([5, 5, 5], [5, 5, 5], [0, 1, 0], "X-axis point"),
])
def test_frame_from_three_points_degenerate_raises(origin, on_x, in_xy, message):
    with pytest.raises(FrameError, match=message):
        frames.frame_from_three_points(origin, on_x, in_xy)


# --- fit_frame ----------------------------------------------------------------

def test_fit_frame_exact_points_recover_transform():
    T_true = random_rigid(1, 6)[0]
    P = np.random.default_rng(6).uniform(-500, 500, (5, 3))
    T, residuals = frames.fit_frame(P, frames.transform_points(T_true, P))
    np.testing.assert_allclose(T, T_true, atol=1e-9)
    assert residuals.shape == (5,)
    assert np.all(residuals < 1e-9)


def test_fit_frame_three_points_is_enough():
    T_true = random_rigid(1, 7)[0]
    P = np.array([[0.0, 0, 0], [400, 0, 0], [0, 300, 0]])
    T, residuals = frames.fit_frame(P, frames.transform_points(T_true, P))
    np.testing.assert_allclose(T, T_true, atol=1e-9)


def test_fit_frame_noisy_points_residuals_match_noise():
    rng = np.random.default_rng(8)
    sigma = 0.05                                       # mm, per coordinate
    n = 200
    T_true = random_rigid(1, 8)[0]
    P = rng.uniform(-500, 500, (n, 3))
    noise = rng.normal(0, sigma, (n, 3))
    M = frames.transform_points(T_true, P) + noise
    T, residuals = frames.fit_frame(P, M)

    assert frames.is_rigid_transform(T)
    # With 6 fitted parameters, E[sum r^2] = (3n - 6) sigma^2.
    expected_rms = sigma * np.sqrt((3 * n - 6) / n)
    assert np.sqrt(np.mean(residuals ** 2)) == pytest.approx(expected_rms, rel=0.1)
    # The fit is at least as good as the truth, and close to it.
    truth = np.linalg.norm(noise, axis=1)
    assert np.sum(residuals ** 2) <= np.sum(truth ** 2)
    assert np.linalg.norm(T[:3, 3] - T_true[:3, 3]) < 0.05
    R_err = T[:3, :3].T @ T_true[:3, :3]
    assert np.degrees(np.arccos(np.clip((np.trace(R_err) - 1) / 2, -1, 1))) < 0.01
    # Residuals are the distances the returned transform leaves.
    np.testing.assert_allclose(
        residuals, np.linalg.norm((T @ np.column_stack([P, np.ones(n)]).T).T[:, :3] - M, axis=1),
        atol=1e-9)


def test_fit_frame_mirrored_points_still_give_a_proper_rotation():
    P = np.array([[0.0, 0, 0], [100, 0, 0], [0, 100, 0], [0, 0, 100], [50, 50, 50]])
    mirrored = P * [1, 1, -1]
    T, residuals = frames.fit_frame(P, mirrored)
    assert np.linalg.det(T[:3, :3]) == pytest.approx(1.0)
    assert frames.is_rigid_transform(T)
    assert residuals.max() > 10.0                      # a mirror cannot be fitted rigidly


def test_fit_frame_coplanar_points_give_a_proper_rotation():
    T_true = random_rigid(1, 9)[0]
    P = np.random.default_rng(9).uniform(-500, 500, (6, 3)) * [1, 1, 0]
    T, residuals = frames.fit_frame(P, frames.transform_points(T_true, P))
    np.testing.assert_allclose(T, T_true, atol=1e-9)


@pytest.mark.parametrize("P, M, message", [
    ([[0, 0, 0], [1, 0, 0]], [[0, 0, 0], [1, 0, 0]], "at least 3"),
    ([[0, 0, 0], [1, 0, 0], [2, 0, 0], [5, 0, 0]],
     [[0, 0, 0], [0, 1, 0], [0, 2, 0], [0, 5, 0]], "collinear"),
    ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 0, 0], [1, 0, 0]], "same size"),
    ([[0, 0], [1, 0], [0, 1]], [[0, 0], [1, 0], [0, 1]], "same size"),
])
def test_fit_frame_degenerate_raises(P, M, message):
    with pytest.raises(FrameError, match=message):
        frames.fit_frame(P, M)


def test_fit_frame_collinear_measured_points_raise():
    P = np.array([[0.0, 0, 0], [100, 0, 0], [0, 100, 0]])
    M = np.array([[0.0, 0, 0], [100, 0, 0], [200, 0, 0]])
    with pytest.raises(FrameError, match="measured points are collinear"):
        frames.fit_frame(P, M)


# --- is_rigid_transform -------------------------------------------------------

def test_is_rigid_transform():
    assert frames.is_rigid_transform(T_U_B)
    assert frames.is_rigid_transform(random_rigid(1, 10)[0])
    scaled = T_U_B.copy()
    scaled[:3, :3] *= 1.001
    mirrored = T_U_B @ np.diag([1.0, 1.0, -1.0, 1.0])
    bottom = T_U_B.copy()
    bottom[3, 0] = 0.5
    nan = T_U_B.copy()
    nan[0, 3] = np.nan
    for bad in (scaled, mirrored, bottom, nan, T_U_B[:3], np.eye(3)):
        assert not frames.is_rigid_transform(bad)
    near = T_U_B.copy()
    near[0, 0] += 1e-9
    assert frames.is_rigid_transform(near)
    assert not frames.is_rigid_transform(near, tol=1e-12)
