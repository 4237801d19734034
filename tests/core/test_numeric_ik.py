"""Numerical IK (:mod:`CadRobotWB.robots.urdf.numeric_ik`) on the arms of the shared data folder.

1. On every arm without a closed form: for 50 random poses (FK of random
   joint sets within the limits), every returned solution reproduces the pose
   (<= 1e-6 mm, <= 1e-9 rad) and the joint set that made it is among them.
2. On OPW arms and a UR arm: the same solutions as the closed form
   (``identify.identify(chain).ik``) on 50 poses away from singularities,
   as sets modulo 360 degrees (<= 1e-6 deg), none missing and none extra.
3. An unreachable pose gives only NaN rows; so does a NaN pose; a singular pose (a
   continuum of solutions) gives some of them.
4. Shapes, wrapping, sort order, determinism, and the model interface.
"""

import os

import numpy as np
import pytest

from CadRobotWB.robots.urdf import identify, numeric_ik, urdf
from required import ROBOT_DATA as DATA


#: Neither OPW nor UR (offset or oblique wrists, and KUKA files that round pi/2 to 1.5708).
NUMERIC_ARMS = [
    "abb_crb15000_5_95", "fanuc_crx10ial", "fanuc_m430ia2p", "motoman_hc10", "motoman_hc10dt",
    "motoman_hc10dt_b10", "motoman_hc10dtp_b00", "motoman_mpx3500", "kuka_kr10_r1100_3",
    "kuka_kr120_r2700_2", "kuka_kr13_r900_3", "kuka_kr16_r1100_3", "kuka_kr20_r1820_2_e"]
CLOSED_FORM_ARMS = ["abb_irb2400", "kuka_kr6_r700_sixx", "fanuc_m20ia", "staubli_tx2_90", "ur5e"]
POSES = 50
POSITION_TOL_MM = 1e-6
ROTATION_TOL_RAD = 1e-9
JOINT_TOL_DEG = 1e-6

_chains = {}


def chain(folder):
    if folder not in _chains:
        path = os.path.join(DATA, folder, "robot.urdf")
        _chains[folder] = urdf.serial_chain(urdf.read_urdf(path))
    return _chains[folder]


def random_joints_rad(c, count, seed):
    """(count, 6) joint sets within the limits (and within +-180 deg)."""
    rng = np.random.default_rng(seed)
    return rng.uniform(np.maximum(c.lower_rad, -np.pi), np.minimum(c.upper_rad, np.pi), (count, 6))


def joint_distance_deg(a, b):
    """Largest joint difference modulo 360, (..., 6) and (..., 6) -> (...)."""
    return np.abs((a - b + 180.0) % 360.0 - 180.0).max(axis=-1)


def pose_errors(c, q_deg, T):
    """Position (mm) and rotation (rad) errors (M,) of rows q_deg (M, 6) against T (M, 4, 4)."""
    T_found = urdf.chain_fk(c, np.radians(q_deg))
    position = np.linalg.norm(T_found[:, :3, 3] - T[:, :3, 3], axis=1)
    rotation = np.linalg.norm(numeric_ik.rotation_error(T[:, :3, :3], T_found[:, :3, :3]), axis=1)
    return position, rotation


def rows_of(solutions):
    """The non-NaN rows of one pose's (K, 6)."""
    return solutions[~np.isnan(solutions[:, 0])]


# ------------------------------------------------------------------ 1. arms without a closed form

@pytest.mark.parametrize("folder", NUMERIC_ARMS)
def test_numeric_arm_solutions_reproduce_the_pose_and_include_the_joints(folder):
    c = chain(folder)
    with pytest.raises(identify.KinematicsError):      # no OPW or UR closed form
        identify.opw_from_chain(c)
    with pytest.raises(identify.KinematicsError):
        identify.ur_from_chain(c)
    q = random_joints_rad(c, POSES, seed=1)
    T = urdf.chain_fk(c, q)
    # 16: a 6R arm has at most 16 solutions, and the cobots here have up to 16.
    solutions = numeric_ik.solve(c, T, max_solutions=16)
    assert solutions.shape == (POSES, 16, 6)
    found = ~np.isnan(solutions[:, :, 0])
    assert np.all(np.isnan(solutions[~found]))
    pose_index = np.nonzero(found)[0]
    position, rotation = pose_errors(c, solutions[found], T[pose_index])
    assert position.max() <= POSITION_TOL_MM, position.max()
    assert rotation.max() <= ROTATION_TOL_RAD, rotation.max()
    distance = np.where(found, joint_distance_deg(solutions, np.degrees(q)[:, None, :]), np.inf)
    missing = np.flatnonzero(distance.min(axis=1) > JOINT_TOL_DEG)
    assert missing.size == 0, "joints not found for poses %s" % missing


# ------------------------------------------------------------------ 2. arms with a closed form

#: Poses whose closed-form solutions all have a scaled Jacobian (position rows divided by the
#: arm's length scale) with a smallest singular value above this are away from singularities.
REGULAR_SIGMA = 0.05


def regular_poses(c, closed_form, count):
    """`count` poses away from singularities: T (count, 4, 4) and the closed form's (count, 8, 6).

    Near a singularity the closed form's own error is magnified in the joints: the UR5e's
    closed form reproduces its URDF only to ~2e-7 mm and ~7e-10 rad (the file's angles are
    rounded), which at q5 = 1.4 degrees is 4e-6 degrees of joint error.
    """
    q = random_joints_rad(c, 10 * count, seed=2)
    T = urdf.chain_fk(c, q)
    Q = closed_form.ik(T)
    valid = ~np.isnan(Q[:, :, 0])
    J = numeric_ik.jacobian(c, np.radians(np.nan_to_num(Q.reshape(-1, 6))))
    J[:, :3] /= numeric_ik.length_scale_mm(c)
    sigma = np.linalg.svd(J, compute_uv=False)[:, -1].reshape(valid.shape)
    regular = np.flatnonzero(np.all(~valid | (sigma > REGULAR_SIGMA), axis=1) & valid.any(axis=1))
    assert len(regular) >= count
    keep = regular[:count]
    return T[keep], Q[keep]


@pytest.mark.parametrize("folder", CLOSED_FORM_ARMS)
def test_numeric_ik_finds_exactly_the_closed_form_solutions(folder):
    c = chain(folder)
    closed_form = identify.identify(c, samples=20)
    T, Q = regular_poses(c, closed_form, POSES)
    solutions = numeric_ik.solve(c, T)
    assert solutions.shape == (POSES, 8, 6)
    for i in range(POSES):
        ours, theirs = rows_of(solutions[i]), rows_of(Q[i])
        distance = joint_distance_deg(ours[:, None], theirs[None])              # (ours, theirs)
        assert np.all(distance.min(axis=0) <= JOINT_TOL_DEG), "pose %d: closed-form one missed" % i
        assert np.all(distance.min(axis=1) <= JOINT_TOL_DEG), "pose %d: one not closed-form" % i
        assert len(ours) == len(theirs)


# ------------------------------------------------------------------ 3. out of reach

def test_unreachable_pose_gives_only_nan():
    c = chain("fanuc_crx10ial")
    T = urdf.chain_fk(c, np.zeros((1, 6)))
    T[0, :3, 3] += (10000.0, 0.0, 0.0)            # 10 m away from a 1.4 m arm
    solutions = numeric_ik.solve(c, T)
    assert solutions.shape == (1, 8, 6)
    assert np.all(np.isnan(solutions))


# ------------------------------------------------------------------ 4. shapes, order, determinism

def test_shapes_wrapping_order_and_determinism():
    c = chain("motoman_hc10")
    q = random_joints_rad(c, 5, seed=3)
    T = urdf.chain_fk(c, q)
    first = numeric_ik.solve(c, T)
    assert first.shape == (5, 8, 6)
    assert numeric_ik.solve(c, T[0]).shape == (1, 8, 6)
    assert numeric_ik.solve(c, T, max_solutions=16).shape == (5, 16, 6)
    again = numeric_ik.solve(c, T)
    assert np.array_equal(first, again, equal_nan=True)
    # Each pose alone gives what it gives in the batch (to rounding).
    alone = numeric_ik.solve(c, T[2:3])
    assert np.array_equal(np.isnan(alone), np.isnan(first[2:3]))
    assert np.nanmax(np.abs(alone - first[2:3])) <= 1e-9
    for rows in first:
        valid = ~np.isnan(rows[:, 0])
        assert np.all(np.isnan(rows[~valid]))
        assert np.array_equal(valid, np.sort(valid)[::-1])            # NaN rows last
        found = rows[valid]
        assert np.all((found > -180.0) & (found <= 180.0 + 1e-9))
        keys = [tuple(np.round(r, numeric_ik.SORT_DECIMALS)) for r in found]
        assert keys == sorted(keys)
        apart = joint_distance_deg(found[:, None], found[None]) + 1e9 * np.eye(len(found))
        assert apart.min() > numeric_ik.DEDUP_TOL_DEG


def test_numeric_model_interface():
    c = chain("fanuc_crx10ial")
    model = numeric_ik.NumericModel(c)
    q_deg = np.degrees(random_joints_rad(c, 3, seed=4))
    T = model.fk(q_deg)
    assert T.shape == (3, 4, 4)
    assert np.allclose(T, urdf.chain_fk(c, np.radians(q_deg)), rtol=0, atol=1e-12)
    assert model.fk(q_deg[0]).shape == (1, 4, 4)
    Q = model.ik(T)
    assert Q.shape == (3, 8, 6)
    assert np.array_equal(Q, numeric_ik.solve(c, T), equal_nan=True)


def test_singular_pose_and_nan_input():
    # OPW arm at zero: wrist singular (q5 = 0), q4 + q6 fixed but each free: a continuum.
    c = chain("abb_irb2400")
    T = urdf.chain_fk(c, np.zeros((1, 6)))
    solutions = numeric_ik.solve(c, T, max_solutions=16)
    rows = rows_of(solutions[0])
    assert len(rows) >= 2
    position, rotation = pose_errors(c, rows, np.repeat(T, len(rows), axis=0))
    assert position.max() <= POSITION_TOL_MM and rotation.max() <= ROTATION_TOL_RAD
    assert np.all(np.isnan(numeric_ik.solve(c, np.full((2, 4, 4), np.nan))))
