"""Spherical wrist, axes 2 and 3 parallel (robots/kinematics/spherical_wrist.py, subproblems.py).

Checked against numbers computed independently of the solver:

1. the subproblems against angles drawn at random and turned by hand (Rodrigues);
2. on the five KUKA files that round pi/2 to 1.5708 (axes 1 and 2 at 89.99979 deg, wrist
   axes 0.15-0.42 um from one point) and on an oblique spherical wrist (the MPX3500
   file with its 114 mm wrist offset removed: wrist axes 60 deg apart): every solution
   reproduces its pose by :func:`poe.fk` (<= 1e-6 mm, <= 1e-9 rad), the joint set that
   made the pose is among them, and on 10 poses per arm the numerical IK finds no
   solution the closed form misses;
3. on exact OPW arms: the same solution sets as ``opw.inverse``;
4. refusals: offset wrists (FANUC CRX-10iA/L, Yaskawa MPX3500 as its file gives it);
5. the compiled kernel against the numpy code, and the output's form.
"""

import os

import numpy as np
import pytest

from CadRobotWB.robots.kinematics import poe, spherical_wrist as sw, spherical_wrist_kernel
from CadRobotWB.robots.kinematics.subproblems import rotate, sp1, sp3, sp4, sp4_unit
from CadRobotWB.robots.urdf import identify, numeric_ik, urdf
from required import ROBOT_DATA as DATA, skip_unless_required

KUKA = ["kuka_kr10_r1100_3", "kuka_kr120_r2700_2", "kuka_kr13_r900_3", "kuka_kr16_r1100_3",
        "kuka_kr20_r1820_2_e"]
OBLIQUE = "mpx3500_without_wrist_offset"
ARMS = KUKA + [OBLIQUE]
OPW_ARMS = ["abb_irb2400", "kuka_kr6_r700_sixx", "fanuc_m20ia", "staubli_tx2_90"]
POSITION_TOL_MM = 1e-6
ROTATION_TOL_RAD = 1e-9
JOINT_TOL_RAD = 1e-6

_chains = {}


def chain(name):
    """The URDF chain of an arm of the data folder, or the oblique spherical wrist."""
    if name not in _chains:
        if name == OBLIQUE:
            with open(os.path.join(DATA, "motoman_mpx3500", "robot.urdf")) as f:
                text = f.read()
            # joint_6_t sits 114 mm along axis 5 from joint 5: put it on joint 5.
            moved = '<origin rpy="0 -1.0471975511965976 0" xyz="0.114 0 0"/>'
            assert text.count(moved) == 1
            source = text.replace(moved, moved.replace("0.114 0 0", "0 0 0"))
        else:
            source = os.path.join(DATA, name, "robot.urdf")
        _chains[name] = urdf.serial_chain(urdf.read_urdf(source))
    return _chains[name]


def joint_distance(a, b):
    """Largest joint difference modulo 2 pi, (..., 6) and (..., 6) -> (...)."""
    return np.abs((a - b + np.pi) % (2 * np.pi) - np.pi).max(axis=-1)


def pose_errors(params, q, T):
    """Position (mm) and rotation (rad) errors of rows q (M, 6) against T (M, 4, 4)."""
    T_q = poe.fk(params, q)
    position = np.linalg.norm(T_q[:, :3, 3] - T[:, :3, 3], axis=1)
    rotation = np.linalg.norm(numeric_ik.rotation_error(T[:, :3, :3], T_q[:, :3, :3]), axis=1)
    return position, rotation


def solved(name, count, seed):
    """(params, joints (count, 6), poses, solutions (count, 8, 6)) of an arm."""
    params = poe.from_chain(chain(name))
    q = identify.random_joints(chain(name), count, seed)
    T = poe.fk(params, q)
    return params, q, T, sw.inverse(sw.recognise(params), T)


# ---- 1. subproblems ------------------------------------------------------------------

def _unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def test_subproblems_find_the_angle_that_made_the_problem():
    rng = np.random.default_rng(3)
    n = 200
    k, h, p = _unit(rng.normal(size=(n, 3))), rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
    p2 = 3 * rng.normal(size=(n, 3))
    theta = rng.uniform(-np.pi, np.pi, n)
    turned = rotate(k, theta, p)
    # Rodrigues by hand for one case: a quarter turn about z takes x to y.
    assert np.allclose(rotate(np.array([0, 0, 1.0]), np.pi / 2, np.array([1.0, 0, 0])), [0, 1, 0])

    found, valid = sp1(p, turned, k)
    assert valid.all() and np.abs(joint_distance(found[:, None], theta[:, None])).max() < 1e-9

    roots, valid = sp4(h, p, k, np.sum(h * turned, axis=1))
    assert valid.all()
    assert np.min(np.abs((roots - theta[:, None] + np.pi) % (2 * np.pi) - np.pi), axis=1).max() < 1e-7
    assert np.allclose(np.sum(h[:, None] * rotate(k[:, None], roots, p[:, None]), axis=2),
                       np.sum(h * turned, axis=1)[:, None])

    roots, valid = sp3(p, p2, k, np.linalg.norm(p2 - turned, axis=1))
    assert valid.all()
    assert np.min(np.abs((roots - theta[:, None] + np.pi) % (2 * np.pi) - np.pi), axis=1).max() < 1e-7


def test_sp4_unit_is_exact_at_its_double_root():
    """An oblique wrist (axes 60 deg apart) next to q5 = 0: the half-angle form finds q5 to
    rounding, the cosine form of SP4 only to sqrt(rounding) (1e-8 rad: q5 = 1e-8 reads 0)."""
    h4, h5 = np.array([-1.0, 0, 0]), np.array([-0.5, 0, np.sqrt(3) / 2])
    h6 = h4
    for q5 in (0.0, 1e-8, 1e-7):
        x = rotate(h5, q5, h6)
        roots, valid = sp4_unit(h4, h6, h5, x)
        assert valid and np.abs(roots - [q5, -q5]).max() < 1e-15
    roots, valid = sp4(h4, h6, h5, h4 @ rotate(h5, 1e-8, h6))
    assert np.abs(np.abs(roots) - 1e-8).max() > 5e-9
    rng = np.random.default_rng(4)
    k, p, h = (_unit(rng.normal(size=(100, 3))) for _ in range(3))
    theta = rng.uniform(-np.pi, np.pi, 100)
    roots, valid = sp4_unit(h, p, k, rotate(k, theta, p))
    assert valid.all()
    assert np.min(np.abs((roots - theta[:, None] + np.pi) % (2 * np.pi) - np.pi), axis=1).max() < 1e-9


def test_sp4_beyond_reach_is_invalid_and_gives_the_nearest_angle():
    k, p, h = np.array([0, 0, 1.0]), np.array([1.0, 0, 0]), np.array([1.0, 0, 0])
    # h . rot(z, theta) x = cos(theta): 2 is out of reach, cos = 1 (theta = 0) is nearest.
    roots, valid = sp4(h, p, k, np.array([2.0, 0.5]))
    assert valid.tolist() == [False, True]
    assert np.allclose(roots[0], 0.0)
    assert np.allclose(sorted(roots[1]), [-np.pi / 3, np.pi / 3])


# ---- 2. the arms -----------------------------------------------------------------------

@pytest.mark.parametrize("name", ARMS)
def test_every_solution_reproduces_the_pose_and_the_joints_that_made_it_are_found(name):
    params, q, T, Q = solved(name, 500, seed=11)
    valid = ~np.isnan(Q[..., 0])
    position, rotation = pose_errors(params, Q[valid], np.repeat(T, 8, axis=0)[valid.ravel()])
    assert position.max() <= POSITION_TOL_MM and rotation.max() <= ROTATION_TOL_RAD
    distance = np.where(valid, joint_distance(Q, q[:, None]), np.inf).min(axis=1)
    assert distance.max() <= JOINT_TOL_RAD
    assert 4 <= valid.sum(axis=1).min() and valid.sum(axis=1).max() == 8


@pytest.mark.parametrize("name", ARMS)
def test_the_numerical_ik_finds_no_solution_the_closed_form_misses(name):
    params, q, T, Q = solved(name, 10, seed=12)
    numeric = np.radians(numeric_ik.solve(chain(name), T, max_solutions=16))
    ours, theirs = ~np.isnan(Q[..., 0]), ~np.isnan(numeric[..., 0])
    gap = joint_distance(numeric[:, :, None], Q[:, None])                  # (10, 16, 8)
    nearest = np.where(ours[:, None], gap, np.inf).min(axis=2)
    # 1e-4 deg: the numerical IK stops within 1e-9 mm of the pose, not of the joints.
    assert nearest[theirs].max() <= np.radians(1e-4)
    assert (ours.sum(axis=1) == theirs.sum(axis=1)).all()


def test_the_kuka_files_need_the_correction_of_their_wrist():
    """Solved as exactly spherical, the KUKA KR 120's flange would miss by ~1e-3 mm."""
    params, q, T, _ = solved("kuka_kr120_r2700_2", 200, seed=13)
    k = sw.recognise(params)
    assert 1e-4 < k.wrist_gap_mm < sw.WRIST_GAP_TOL_MM and k.correction_steps > 0
    q_model, valid = sw.branches(k, T)
    position, _ = pose_errors(params, q_model.reshape(-1, 6)[valid.ravel()],
                              np.repeat(T, 8, axis=0)[valid.ravel()])
    assert position.max() > 1e-4


def test_next_to_a_wrist_singularity_the_correction_keeps_every_solution():
    """q5 = -1e-5 rad on the KR 16 file: q4 and q6 are ill-conditioned, two branches need
    ten corrections; the numerical IK's 8 solutions are all found, by both codes (to 1e-4
    rad: both stop within 1e-8 mm of the pose, which leaves q4 and q6 there ~1e-5 rad loose)."""
    c = chain("kuka_kr16_r1100_3")
    params = poe.from_chain(c)
    k = sw.recognise(params)
    T = poe.fk(params, np.array([[2.959832, -3.049113, 2.554297, 2.356685, -1e-5, 2.552571]]))
    numeric = np.radians(numeric_ik.solve(c, T, max_solutions=16))[0]
    numeric = numeric[~np.isnan(numeric[:, 0])]
    assert len(numeric) == 8
    for Q in (sw.inverse(k, T)[0], sw.inverse_numpy(k, T)[0]):
        Q = Q[~np.isnan(Q[:, 0])]
        assert len(Q) == 8
        assert joint_distance(numeric[:, None], Q[None]).min(axis=1).max() <= 1e-4


# ---- 3. exact OPW arms ----------------------------------------------------------------

@pytest.mark.parametrize("name", OPW_ARMS)
def test_an_exact_opw_arm_gives_the_solutions_of_opw_inverse(name):
    params, q, T, Q = solved(name, 200, seed=14)
    assert sw.recognise(params).correction_steps == 0
    opw = np.radians(identify.identify(chain(name), samples=100).ik(T))     # (200, 8, 6)
    ours, theirs = ~np.isnan(Q[..., 0]), ~np.isnan(opw[..., 0])
    gap = joint_distance(opw[:, :, None], Q[:, None])
    assert np.where(ours[:, None], gap, np.inf).min(axis=2)[theirs].max() < 1e-9
    assert (ours.sum(axis=1) == theirs.sum(axis=1)).all()


def test_at_a_wrist_singularity_an_exact_arm_keeps_it_once_with_q4_0():
    """IRB 2400 at q5 = 0: axes 4 and 6 in line, only q4 + q6 = 0.5 - 0.2 matters; the
    wrist's two roots are one solution, given as opw.inverse gives it (q4 = 0)."""
    params = poe.from_chain(chain("abb_irb2400"))
    T = poe.fk(params, np.array([[0.3, -1.0, 0.4, 0.5, 0.0, -0.2]]))
    for Q in (sw.inverse(sw.recognise(params), T)[0],
              sw.inverse_numpy(sw.recognise(params), T)[0]):
        Q = Q[~np.isnan(Q[:, 0])]
        assert len(Q) == 7
        singular = Q[joint_distance(Q[:, :3], np.array([0.3, -1.0, 0.4])) < 1e-9]
        assert len(singular) == 1
        assert np.abs(singular[0] - [0.3, -1.0, 0.4, 0.0, 0.0, 0.3]).max() < 1e-12


# ---- 4. refusals -----------------------------------------------------------------------

@pytest.mark.parametrize("name, gap", [("fanuc_crx10ial", "75 mm"), ("motoman_mpx3500", "49.3634 mm")])
def test_an_offset_wrist_is_refused(name, gap):
    with pytest.raises(ValueError, match="axes 4, 5 and 6 do not meet in one point: .*%s.*offset "
                                         "wrist" % gap):
        sw.recognise(poe.from_chain(chain(name)))


def test_axes_2_and_3_not_parallel_are_refused():
    params = poe.from_chain(chain("abb_irb2400"))
    H = params.H.copy()
    H[2] = [0.0, np.cos(1e-3), np.sin(1e-3)]
    with pytest.raises(ValueError, match="axes 2 and 3 are not parallel \\(0.0572958 deg"):
        sw.recognise(poe.ChainParameters(H=H, P=params.P, R_6T=params.R_6T))


# ---- 5. kernel and form ----------------------------------------------------------------

@pytest.mark.parametrize("name", ["kuka_kr16_r1100_3", OBLIQUE, "abb_irb2400"])
def test_the_compiled_kernel_gives_the_numpy_answers(name):
    if not spherical_wrist_kernel.available():
        skip_unless_required("numba is not available: %s" % spherical_wrist_kernel.why_not)
    params, q, T, Q = solved(name, 300, seed=15)
    reference = sw.inverse_numpy(sw.recognise(params), T)
    assert (np.isnan(Q) == np.isnan(reference)).all()
    assert np.nanmax(joint_distance(Q, np.nan_to_num(reference))) < 1e-9


@pytest.mark.parametrize("name", ["kuka_kr16_r1100_3", "abb_irb2400"])
@pytest.mark.parametrize("solve", [sw.inverse, sw.inverse_numpy])
def test_form_of_the_answer(name, solve):
    """Wrapped, distinct (q5 = 0 makes the wrist's two roots one), NaN rows last."""
    params = poe.from_chain(chain(name))
    k = sw.recognise(params)
    q = np.array([[0.3, -1.0, 0.4, 0.5, 0.0, -0.2],          # wrist singular: q5 = 0
                  [0.3, -1.0, 0.4, 3.0, 0.8, -3.1]])
    T = poe.fk(params, q)
    far = T[1].copy()
    far[:3, 3] *= 100.0                                      # 100 m away: unreachable
    Q = solve(k, np.concatenate([T, far[None]]))
    assert Q.shape == (3, sw.MAX_SOLUTIONS, 6) and np.isnan(Q[2]).all()
    valid = ~np.isnan(Q[..., 0])
    assert (np.sort(~valid, axis=1) == ~valid).all()                         # NaN rows last
    assert (Q[valid] > -np.pi).all() and (Q[valid] <= np.pi).all()
    assert valid[:2].sum(axis=1).min() >= 2
    for row in Q[:2]:
        found = row[~np.isnan(row[:, 0])]
        gap = joint_distance(found[:, None], found[None]) + 10 * np.eye(len(found))
        assert gap.min() > sw.DUPLICATE_TOL_RAD                              # distinct
    position, rotation = pose_errors(params, Q[:2][valid[:2]],
                                     np.repeat(T, valid[:2].sum(axis=1), axis=0))
    assert position.max() <= POSITION_TOL_MM and rotation.max() <= ROTATION_TOL_RAD
    assert solve(k, T[1]).shape == (sw.MAX_SOLUTIONS, 6)
