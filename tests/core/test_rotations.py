"""Tests of core/rotations.py against scipy.spatial.transform and hand-derived values."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation, Slerp

from CadRobotWB.core import rotations as rot
from CadRobotWB.errors import InputError

REPO = Path(__file__).resolve().parents[2]
RNG_SEED = 20120101


def wxyz(r):
    """scipy Rotation -> (w, x, y, z) with w >= 0."""
    q = np.roll(r.as_quat(), 1, axis=-1)
    return q * np.where(q[..., :1] < 0, -1.0, 1.0)


def same_rotation(q_a, q_b, atol=1e-12):
    """q and -q are the same rotation: |q_a . q_b| == 1."""
    np.testing.assert_allclose(np.abs(np.sum(q_a * q_b, axis=-1)), 1.0, rtol=0, atol=atol)


@pytest.fixture
def rng():
    return np.random.default_rng(RNG_SEED)


def random_rotations(n, seed=RNG_SEED):
    return Rotation.random(n, random_state=seed)


RZ90 = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])


def test_module_imports_neither_scipy_nor_freecad():
    code = ("import sys, CadRobotWB.core.rotations; "
            "bad = [m for m in ('scipy', 'FreeCAD') if m in sys.modules]; "
            "sys.exit(1 if bad else 0)")
    result = subprocess.run([sys.executable, "-c", code], cwd=REPO)
    assert result.returncode == 0


# --- quaternion_from_matrix -------------------------------------------------

def test_quaternion_from_matrix_matches_scipy_for_random_rotations():
    r = random_rotations(500)
    q = rot.quaternion_from_matrix(r.as_matrix())
    assert q.shape == (500, 4)
    np.testing.assert_allclose(q, wxyz(r), atol=1e-12)


def test_quaternion_from_matrix_hand_derived_rz90():
    s = np.sqrt(0.5)
    np.testing.assert_allclose(rot.quaternion_from_matrix(RZ90), [s, 0, 0, s], atol=1e-15)
    np.testing.assert_allclose(rot.quaternion_from_matrix(np.eye(3)), [1, 0, 0, 0])


@pytest.mark.parametrize("axis, angle", [
    ([1, 0, 0], np.pi),                 # R00 largest branch
    ([0, 1, 0], np.pi),                 # R11 largest
    ([0, 0, 1], np.pi),                 # R22 largest
    ([1, 1, 0], np.pi),
    ([1, 1, 1], np.pi - 1e-7),
    ([0.3, -0.2, 0.9], np.pi - 1e-12),
    ([0.3, -0.2, 0.9], 1e-12),          # trace largest
    ([-0.7, 0.1, 0.2], 2.0),
])
def test_quaternion_from_matrix_every_branch_matches_scipy(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    r = Rotation.from_rotvec(axis * angle)
    q = rot.quaternion_from_matrix(r.as_matrix())
    assert q.shape == (4,)
    assert q[0] >= 0
    np.testing.assert_allclose(np.linalg.norm(q), 1.0, atol=1e-15)
    same_rotation(q, wxyz(r))
    # The axis is recovered to full precision even at 180 degrees.
    xyz = q[1:] * np.sign(q[1:] @ axis)
    np.testing.assert_allclose(xyz / np.linalg.norm(xyz), axis, atol=1e-12)


def test_quaternion_from_matrix_normalises_slightly_non_orthogonal_input():
    R = random_rotations(1).as_matrix()[0] * (1 + 1e-7)
    q = rot.quaternion_from_matrix(R)
    np.testing.assert_allclose(np.linalg.norm(q), 1.0, atol=1e-15)


def test_quaternion_from_matrix_batch_equals_single():
    R = random_rotations(7).as_matrix()
    batch = rot.quaternion_from_matrix(R)
    for i in range(7):
        np.testing.assert_array_equal(batch[i], rot.quaternion_from_matrix(R[i]))


# --- matrix_from_quaternion, multiply, conjugate ----------------------------

def test_matrix_from_quaternion_matches_scipy_and_normalises():
    r = random_rotations(100)
    q = wxyz(r) * np.linspace(0.2, 5.0, 100)[:, None]     # not unit on purpose
    R = rot.matrix_from_quaternion(q)
    assert R.shape == (100, 3, 3)
    np.testing.assert_allclose(R, r.as_matrix(), atol=1e-14)
    np.testing.assert_allclose(rot.matrix_from_quaternion([np.sqrt(0.5), 0, 0, np.sqrt(0.5)]),
                               RZ90, atol=1e-15)


def test_quaternion_multiply_composes_like_matrices_and_scipy():
    r1, r2 = random_rotations(50, 1), random_rotations(50, 2)
    q = rot.quaternion_multiply(wxyz(r1), wxyz(r2))
    np.testing.assert_allclose(rot.matrix_from_quaternion(q),
                               r1.as_matrix() @ r2.as_matrix(), atol=1e-14)
    same_rotation(q, wxyz(r1 * r2))


def test_quaternion_conjugate_is_inverse():
    r = random_rotations(20)
    q = wxyz(r)
    qc = rot.quaternion_conjugate(q)
    np.testing.assert_allclose(rot.matrix_from_quaternion(qc), r.inv().as_matrix(), atol=1e-14)
    np.testing.assert_allclose(rot.quaternion_multiply(q, qc),
                               np.tile([1.0, 0, 0, 0], (20, 1)), atol=1e-15)


# --- quaternion_slerp (eqs 14-15) -------------------------------------------

def scipy_slerp(q0, q1, t):
    key = Rotation.from_quat(np.roll(np.stack([q0, q1]), -1, axis=-1))
    return wxyz(Slerp([0.0, 1.0], key)(t))


def test_slerp_matches_scipy_for_random_pairs():
    t = np.linspace(0.0, 1.0, 11)
    for q0, q1 in zip(wxyz(random_rotations(30, 3)), wxyz(random_rotations(30, 4))):
        q = rot.quaternion_slerp(q0, q1, t)
        assert q.shape == (11, 4)
        same_rotation(q, scipy_slerp(q0, q1, t))


@pytest.mark.parametrize("angle", [1e-9, 1e-6, 1.0, np.pi - 1e-6])
def test_slerp_from_identity_is_exact_fraction_of_the_rotation(angle):
    # Hand-derived: from the identity, slerp(t) is the rotation by t*angle
    # about the same axis, i.e. (cos(t angle/2), sin(t angle/2) n).
    n = np.array([0.48, -0.6, 0.64])
    q1 = np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * n])
    t = np.array([0.0, 0.1, 0.25, 0.5, 0.9, 1.0])
    q = rot.quaternion_slerp([1.0, 0, 0, 0], q1, t)
    expected = np.column_stack([np.cos(t * angle / 2), np.outer(np.sin(t * angle / 2), n)])
    assert np.all(np.isfinite(q))
    np.testing.assert_allclose(q[:, 0], expected[:, 0], rtol=1e-12)
    np.testing.assert_allclose(q[1:, 1:], expected[1:, 1:], rtol=1e-9)
    np.testing.assert_array_equal(q[0], [1.0, 0, 0, 0])


@pytest.mark.parametrize("angle", [1e-9, 1e-6, np.pi - 1e-6])
def test_slerp_small_and_near_pi_angles_match_scipy(angle, rng):
    q0 = wxyz(random_rotations(1, 5))[0]
    axis = rng.normal(size=3)
    step = Rotation.from_rotvec(axis / np.linalg.norm(axis) * angle)
    q1 = wxyz(step * Rotation.from_quat(np.roll(q0, -1)))
    t = np.linspace(0.0, 1.0, 9)
    q = rot.quaternion_slerp(q0, q1, t)
    same_rotation(q, scipy_slerp(q0, q1, t), atol=1e-14)
    # Each step covers the same fraction of the angle.
    steps = rot.rotation_angle_between(rot.matrix_from_quaternion(q[:-1]),
                                       rot.matrix_from_quaternion(q[1:]))
    np.testing.assert_allclose(steps, angle / 8, rtol=1e-6 if angle > 1e-6 else 1e-3)


def test_slerp_takes_the_short_way():
    # 270 deg about z is the same rotation as -90 deg; halfway must be -45 deg.
    q_long = np.array([np.cos(3 * np.pi / 4), 0, 0, np.sin(3 * np.pi / 4)])
    assert q_long[0] < 0                      # q0 . q1 < 0 with q0 = identity
    q_half = rot.quaternion_slerp([1.0, 0, 0, 0], q_long, 0.5)
    c = np.sqrt(0.5)
    np.testing.assert_allclose(rot.matrix_from_quaternion(q_half),
                               [[c, c, 0], [-c, c, 0], [0, 0, 1]], atol=1e-15)
    t = np.linspace(0, 1, 5)
    q0, q1 = wxyz(random_rotations(2, 6))
    np.testing.assert_allclose(rot.quaternion_slerp(q0, -q1, t),
                               rot.quaternion_slerp(q0, q1, t), atol=1e-15)


def test_slerp_hand_derived_halfway_and_endpoints():
    s = np.sqrt(0.5)
    q_rz90 = np.array([s, 0, 0, s])
    q = rot.quaternion_slerp([1.0, 0, 0, 0], q_rz90, [0.0, 0.5, 1.0])
    np.testing.assert_allclose(q[1], [np.cos(np.pi / 8), 0, 0, np.sin(np.pi / 8)], atol=1e-15)
    np.testing.assert_allclose(q[0], [1, 0, 0, 0], atol=1e-15)
    np.testing.assert_allclose(q[2], q_rz90, atol=1e-15)
    assert rot.quaternion_slerp([1.0, 0, 0, 0], q_rz90, 0.5).shape == (4,)


def test_slerp_identical_quaternions_gives_that_quaternion():
    q0 = wxyz(random_rotations(1, 7))[0]
    q = rot.quaternion_slerp(q0, q0, np.linspace(0, 1, 4))
    np.testing.assert_allclose(q, np.tile(q0, (4, 1)), atol=1e-15)


# --- angles, axis-angle, rotation vectors -----------------------------------

def test_rotation_angle_between_matches_scipy():
    r1, r2 = random_rotations(100, 8), random_rotations(100, 9)
    angles = rot.rotation_angle_between(r1.as_matrix(), r2.as_matrix())
    assert angles.shape == (100,)
    np.testing.assert_allclose(angles, (r1.inv() * r2).magnitude(), atol=1e-12)


@pytest.mark.parametrize("angle", [0.0, 1e-8, 0.3, np.pi - 1e-7, np.pi])
def test_rotation_angle_between_small_and_large(angle):
    R1 = random_rotations(1, 10).as_matrix()[0]
    R2 = R1 @ Rotation.from_rotvec([0, angle, 0]).as_matrix()
    result = rot.rotation_angle_between(R1, R2)
    assert 0.0 <= result <= np.pi
    np.testing.assert_allclose(result, angle, rtol=1e-6, atol=1e-14)


def test_rotation_angle_between_is_pi_for_half_turn():
    half_turn_x = np.diag([1.0, -1.0, -1.0])
    assert rot.rotation_angle_between(np.eye(3), half_turn_x) == pytest.approx(np.pi)


def test_matrix_from_axis_angle_matches_scipy(rng):
    axes = rng.normal(size=(50, 3)) * 7.0                   # not unit on purpose
    angles = rng.uniform(-2 * np.pi, 2 * np.pi, 50)
    R = rot.matrix_from_axis_angle(axes, angles)
    unit = axes / np.linalg.norm(axes, axis=1, keepdims=True)
    np.testing.assert_allclose(R, Rotation.from_rotvec(unit * angles[:, None]).as_matrix(),
                               atol=1e-14)
    np.testing.assert_allclose(rot.matrix_from_axis_angle([0, 0, 2], np.pi / 2), RZ90, atol=1e-15)


def test_matrix_from_axis_angle_broadcasts_one_axis_over_angles():
    R = rot.matrix_from_axis_angle([0, 0, 1], [0.0, np.pi / 2])
    assert R.shape == (2, 3, 3)
    np.testing.assert_allclose(R[1], RZ90, atol=1e-15)
    R = rot.matrix_from_axis_angle([[0, 0, 1], [1, 0, 0]], np.pi / 2)
    assert R.shape == (2, 3, 3)
    np.testing.assert_allclose(R[0], RZ90, atol=1e-15)


def test_matrix_from_axis_angle_rejects_zero_axis():
    with pytest.raises(InputError, match="zero length"):
        rot.matrix_from_axis_angle([0, 0, 0], 1.0)


def test_rotvec_from_matrix_matches_scipy():
    r = random_rotations(200, 11)
    rv = rot.rotvec_from_matrix(r.as_matrix())
    assert rv.shape == (200, 3)
    np.testing.assert_allclose(rv, r.as_rotvec(), atol=1e-12)


@pytest.mark.parametrize("angle", [0.0, 1e-10, 1e-5, np.pi - 1e-6])
def test_rotvec_from_matrix_small_and_near_pi(angle):
    rv_true = np.array([0.36, 0.48, -0.8]) * angle
    rv = rot.rotvec_from_matrix(Rotation.from_rotvec(rv_true).as_matrix())
    np.testing.assert_allclose(rv, rv_true, rtol=1e-6, atol=1e-15)


def test_rotvec_from_matrix_half_turn_reproduces_the_matrix():
    R = np.diag([-1.0, 1.0, -1.0])                           # 180 deg about y
    rv = rot.rotvec_from_matrix(R)
    np.testing.assert_allclose(np.abs(rv), [0, np.pi, 0], atol=1e-15)


# --- Euler conventions ------------------------------------------------------

def random_angles(rng, n):
    return (rng.uniform(-np.pi, np.pi, n), rng.uniform(-np.pi / 2, np.pi / 2, n),
            rng.uniform(-np.pi, np.pi, n))


def test_matrix_from_euler_zyx_is_kuka_abc_intrinsic_zyx(rng):
    a, b, c = random_angles(rng, 100)
    R = rot.matrix_from_euler_zyx(a, b, c)
    assert R.shape == (100, 3, 3)
    expected = Rotation.from_euler("ZYX", np.column_stack([a, b, c])).as_matrix()
    np.testing.assert_allclose(R, expected, atol=1e-14)


def test_matrix_from_euler_zyx_hand_derived():
    np.testing.assert_allclose(rot.matrix_from_euler_zyx(np.pi / 2, 0, 0), RZ90, atol=1e-15)
    # B = 90 deg about y turns the z axis onto x; C = 90 deg about x turns y onto z.
    np.testing.assert_allclose(rot.matrix_from_euler_zyx(0, np.pi / 2, 0) @ [0, 0, 1],
                               [1, 0, 0], atol=1e-15)
    np.testing.assert_allclose(rot.matrix_from_euler_zyx(0, 0, np.pi / 2) @ [0, 1, 0],
                               [0, 0, 1], atol=1e-15)


def test_euler_zyx_from_matrix_matches_scipy(rng):
    a, b, c = random_angles(rng, 100)
    R = Rotation.from_euler("ZYX", np.column_stack([a, b, c]))
    abc = rot.euler_zyx_from_matrix(R.as_matrix())
    assert abc.shape == (100, 3)
    np.testing.assert_allclose(abc, R.as_euler("ZYX"), atol=1e-12)
    np.testing.assert_allclose(abc, np.column_stack([a, b, c]), atol=1e-12)
    assert rot.euler_zyx_from_matrix(R.as_matrix()[0]).shape == (3,)


@pytest.mark.parametrize("b", [np.pi / 2, -np.pi / 2])
def test_euler_zyx_at_gimbal_lock_reproduces_the_matrix(b):
    R = rot.matrix_from_euler_zyx(0.7, b, -0.4)
    a2, b2, c2 = rot.euler_zyx_from_matrix(R)
    assert b2 == pytest.approx(b)
    assert c2 == 0.0
    np.testing.assert_allclose(rot.matrix_from_euler_zyx(a2, b2, c2), R, atol=1e-12)


def test_matrix_from_euler_xyz_fixed_is_extrinsic_xyz(rng):
    rx, ry, rz = random_angles(rng, 100)
    R = rot.matrix_from_euler_xyz_fixed(rx, ry, rz)
    expected = Rotation.from_euler("xyz", np.column_stack([rx, ry, rz])).as_matrix()
    np.testing.assert_allclose(R, expected, atol=1e-14)


def test_euler_xyz_fixed_from_matrix_matches_scipy(rng):
    rx, ry, rz = random_angles(rng, 100)
    R = Rotation.from_euler("xyz", np.column_stack([rx, ry, rz]))
    angles = rot.euler_xyz_fixed_from_matrix(R.as_matrix())
    np.testing.assert_allclose(angles, R.as_euler("xyz"), atol=1e-12)
    np.testing.assert_allclose(angles, np.column_stack([rx, ry, rz]), atol=1e-12)


def test_fixed_xyz_and_kuka_abc_are_the_same_angles_reversed():
    # Fanuc (W, P, R) = (C, B, A) of KUKA.
    R = rot.matrix_from_euler_zyx(0.1, 0.2, 0.3)
    np.testing.assert_allclose(rot.euler_xyz_fixed_from_matrix(R), [0.3, 0.2, 0.1], atol=1e-14)
