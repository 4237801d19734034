"""The optimised :func:`CadRobotWB.robots.kinematics.opw.inverse` gives the same answers as
the straightforward implementation it replaced (issue #4, IK throughput), both
through the compiled kernel (:mod:`~CadRobotWB.robots.kinematics.opw_kernel`, numba; issue #12)
and through the numpy code that is its fallback (``opw.inverse_numpy``).

``_reference_inverse`` below is that implementation, copied verbatim (with its
helpers) before the rewrite; it is frozen here as the specification.  For
every OPW robot of the catalog, on random joints, random poses (many
branches and whole poses out of reach), singular poses (wrist theta5 = 0 and
180 deg, wrist centre on axis 1, arm stretched and folded, joint values on
multiples of 90 deg), inputs with NaN and inf entries, and batch sizes on both
sides of the block size the new code works in, the two agree:

* the same NaN pattern (a branch missing in one is missing in the other, a
  whole row NaN);
* every other joint value within 1e-9 deg, compared modulo 360 (a value at
  exactly +-180 deg may come out as 180 on one side and -180 on the other
  only through rounding; both lie in (-180, 180] up to one ulp).
"""

import collections
import dataclasses

import numpy as np
import pytest

from CadRobotWB.robots.catalog import catalog
from CadRobotWB.robots.kinematics import models, opw, opw_kernel
from required import skip_unless_required
from robot_sample import sample_names

TOL_DEG = 1e-9
OPW_ROBOTS = [name for name in sample_names() if catalog.get(name).opw is not None]


#: The compiled kernel computes the elbow's sine from its cosine and every angle
#: through its own atan2, so its rounding differs from numpy's.  Where the equations
#: are well conditioned its joint values agree to this; at an elbow or wrist
#: singularity (and next to one) rounding decides the split between joints, so
#: there rows are compared by the pose they give.  Both reproduce the pose equally
#: well: 2e-12 mm and 3e-15 in the rotation matrix (measured on 50,000 poses of
#: three arms).
TOL_COMPILED_DEG = 1e-7

#: sin(theta5) or sin(elbow) below this: a singular row (compared by pose only).
SINGULAR_SIN = 1e-5

Solver = collections.namedtuple("Solver", "solve check")


@pytest.fixture(params=["compiled", "numpy"])
def inverse(request):
    """opw.inverse as it runs with numba (compiled) and without it (numpy), with the
    comparison each must pass against the reference."""
    if request.param == "numpy":
        return Solver(opw.inverse_numpy, assert_same_solutions)
    if not opw_kernel.available():
        skip_unless_required("the compiled IK is not available: %s" % opw_kernel.why_not)
    return Solver(opw.inverse, assert_same_poses)


# --- the reference: opw.inverse as it was before the optimisation (verbatim) -------------------

_REF_ACOS_TOLERANCE = 1e-12
_REF_WRIST_SINGULAR_SIN = 1e-12


def _ref_params_arrays(params):
    offsets_rad = np.radians(np.asarray(params.offsets_deg, dtype=float))
    signs = np.asarray(params.signs, dtype=float)
    return offsets_rad, signs


def _ref_safe_arccos(x):
    x = np.asarray(x, dtype=float)
    with np.errstate(invalid="ignore"):
        x = np.where(np.abs(x) <= 1.0 + _REF_ACOS_TOLERANCE, np.clip(x, -1.0, 1.0), np.nan)
    return np.arccos(x)


def _ref_wrap_deg(q_deg):
    q_deg = np.asarray(q_deg, dtype=float)
    return q_deg - 360.0 * np.ceil((q_deg - 180.0) / 360.0)


def _reference_inverse(params, T_r_f):
    T = np.asarray(T_r_f, dtype=float)
    single = T.ndim == 2
    T = T.reshape((-1, 4, 4))
    p = params
    offsets_rad, signs = _ref_params_arrays(params)
    R = T[:, :3, :3]

    # Wrist centre, the shoulder angle and the arm's planar distances.
    centre = T[:, :3, 3] - p.c4 * R[:, :, 2]
    cx, cy, cz = centre[:, 0], centre[:, 1], centre[:, 2]
    with np.errstate(invalid="ignore"):
        nx1 = np.sqrt(cx * cx + cy * cy - p.b * p.b) - p.a1
    phi = np.arctan2(cy, cx)
    beta = np.arctan2(p.b, nx1 + p.a1)
    theta1_i = phi - beta
    theta1_ii = phi + beta - np.pi

    dz = cz - p.c1
    s1_sq = nx1 * nx1 + dz * dz
    nx2 = nx1 + 2.0 * p.a1
    s2_sq = nx2 * nx2 + dz * dz
    kappa_sq = p.a2 * p.a2 + p.c3 * p.c3
    c2_sq = p.c2 * p.c2
    kappa = np.sqrt(kappa_sq)
    with np.errstate(invalid="ignore"):
        elbow_front = _ref_safe_arccos((s1_sq - c2_sq - kappa_sq) / (2.0 * p.c2 * kappa))
        elbow_back = _ref_safe_arccos((s2_sq - c2_sq - kappa_sq) / (2.0 * p.c2 * kappa))
    psi3 = np.arctan2(p.a2, p.c3)

    theta1 = np.stack([theta1_i, theta1_i, theta1_ii, theta1_ii], axis=1)
    elbow = np.stack([elbow_front, -elbow_front, elbow_back, -elbow_back], axis=1)
    theta3 = elbow - psi3
    reach = np.stack([nx1, nx1, -nx2, -nx2], axis=1)
    theta2 = (np.arctan2(reach, dz[:, None])
              - np.arctan2(kappa * np.sin(elbow), p.c2 + kappa * np.cos(elbow)))

    sin1 = np.sin(theta1[:, ::2])[..., None]  # (N, 2, 1)
    cos1 = np.cos(theta1[:, ::2])[..., None]
    u = np.repeat(cos1 * R[:, None, 0, :] + sin1 * R[:, None, 1, :], 2, axis=1)   # (N, 4, 3)
    v = np.repeat(-sin1 * R[:, None, 0, :] + cos1 * R[:, None, 1, :], 2, axis=1)
    s23, c23 = np.sin(theta2 + theta3), np.cos(theta2 + theta3)  # (N, 4)
    ce0 = c23[..., None] * u - s23[..., None] * R[:, None, 2, :]  # row 0 of R_ce
    ce1 = v                                                        # row 1
    ce22 = s23 * u[..., 2] + c23 * R[:, None, 2, 2]               # R_ce[2, 2] = cos(theta5)

    sin5 = np.hypot(ce0[..., 2], ce1[..., 2])
    theta4 = np.where(sin5 < _REF_WRIST_SINGULAR_SIN, 0.0, np.arctan2(ce1[..., 2], ce0[..., 2]))
    sin4, cos4 = np.sin(theta4), np.cos(theta4)
    theta5 = np.arctan2(cos4 * ce0[..., 2] + sin4 * ce1[..., 2], ce22)
    theta6 = np.arctan2(-sin4 * ce0[..., 0] + cos4 * ce1[..., 0],
                        -sin4 * ce0[..., 1] + cos4 * ce1[..., 1])

    model = np.empty((T.shape[0], 8, 6))
    for wrist, (t4, t5, t6) in enumerate(((theta4, theta5, theta6),
                                          (theta4 + np.pi, -theta5, theta6 - np.pi))):
        rows = slice(4 * wrist, 4 * wrist + 4)
        model[:, rows, 0] = theta1
        model[:, rows, 1] = theta2
        model[:, rows, 2] = theta3
        model[:, rows, 3] = t4
        model[:, rows, 4] = t5
        model[:, rows, 5] = t6
    q_deg = _ref_wrap_deg(np.degrees((model + offsets_rad) * signs))
    q_deg[np.isnan(q_deg).any(axis=-1)] = np.nan
    return q_deg[0] if single else q_deg


# --- pose sets ---------------------------------------------------------------------------------

def _reach(p):
    return p.c2 + np.hypot(p.a2, p.c3)


def _controller(p, theta_model_deg):
    """Controller joints of model angles (the inverse of ``q * sign - offset``)."""
    return (np.asarray(theta_model_deg, dtype=float) + np.asarray(p.offsets_deg)) * np.asarray(p.signs)


def _random_rotations(rng, n):
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
    ], axis=1)


def _poses(R, p):
    T = np.zeros((len(R), 4, 4))
    T[:, :3, :3] = R
    T[:, :3, 3] = p
    T[:, 3, 3] = 1.0
    return T


def random_joint_poses(robot, n, seed):
    """FK of joints anywhere in (-180, 180]^6 (not only within the limits)."""
    q = np.random.default_rng(seed).uniform(-180.0, 180.0, (n, 6))
    return robot.fk(q)


def random_box_poses(robot, n, seed):
    """Random rotations at random points of a box 1.3 times the reach: many branches and
    whole poses out of reach, wrist centres close to axis 1."""
    rng = np.random.default_rng(seed)
    p = robot.spec.opw
    half = 1.3 * (_reach(p) + abs(p.a1) + p.c4)
    centre = np.array([0.0, 0.0, p.c1])
    return _poses(_random_rotations(rng, n), centre + rng.uniform(-half, half, (n, 3)))


def singular_poses(robot):
    """Poses at or on the edge of every singularity, and on multiples of 90 deg."""
    p = robot.spec.opw
    rng = np.random.default_rng(7)
    poses = []
    # Joint grid on multiples of 45 deg (model angles): theta5 = 0 and 180 among them.
    grid = np.radians(np.arange(-180.0, 181.0, 45.0))
    g = np.array(np.meshgrid(grid[::2], grid[::2], grid, grid[::2], grid, grid[::4],
                             indexing="ij")).reshape(6, -1).T
    poses.append(robot.fk(_controller(p, np.degrees(g))))
    # Wrist singular: model theta5 = 0 / 180 deg with random other joints.
    q = rng.uniform(-180.0, 180.0, (400, 6))
    q[:200, 4], q[200:, 4] = 0.0, 180.0
    poses.append(robot.fk(_controller(p, q)))
    # Arm stretched (elbow angle 0: c2 and the forearm in one line) and folded (elbow 180).
    psi3 = np.degrees(np.arctan2(p.a2, p.c3))
    q = rng.uniform(-180.0, 180.0, (400, 6))
    q[:200, 2], q[200:, 2] = -psi3, 180.0 - psi3
    poses.append(robot.fk(_controller(p, q)))
    # Wrist centre exactly on axis 1 (x = y = 0), tool axis along +-z, at several heights.
    R = _random_rotations(rng, 60)
    heights = p.c1 + np.linspace(-1.2, 1.2, 60) * _reach(p)
    R_axial = np.zeros((60, 3, 3))
    angle = rng.uniform(-np.pi, np.pi, 60)
    flip = np.where(np.arange(60) % 2 == 0, 1.0, -1.0)
    R_axial[:, 0, 0], R_axial[:, 0, 1] = np.cos(angle), -np.sin(angle) * flip
    R_axial[:, 1, 0], R_axial[:, 1, 1] = np.sin(angle), np.cos(angle) * flip
    R_axial[:, 2, 2] = flip
    poses.append(_poses(R_axial, np.stack([np.zeros(60), np.zeros(60), heights + p.c4 * flip], -1)))
    # Wrist centre on the shoulder circle / exactly at full reach along each axis.
    reach = _reach(p) + p.a1
    for centre in ([reach, 0, p.c1], [0, -reach, p.c1], [p.a1, 0, p.c1 + _reach(p)],
                   [0, 0, p.c1], [p.a1, 0, p.c1], [-p.a1, 0, p.c1]):
        T = np.eye(4)
        T[:3, 3] = np.asarray(centre, dtype=float) + p.c4 * T[:3, 2]
        poses.append(T[None])
    poses.append(_poses(R[:10], np.zeros((10, 3))))  # flange at the base origin
    return np.concatenate(poses)


def garbage_poses(robot):
    """Finite poses with a NaN or an inf in one entry, and all-zero matrices."""
    base = random_joint_poses(robot, 24, seed=11)
    out = []
    for value in (np.nan, np.inf, -np.inf):
        for k, (i, j) in enumerate([(r, c) for r in range(3) for c in range(4)]):
            T = base[k % len(base)].copy()
            T[i, j] = value
            out.append(T)
    out.append(np.zeros((4, 4)))
    Z = np.zeros((4, 4))
    Z[3, 3] = 1.0
    out.append(Z)
    return np.array(out)


# --- comparison --------------------------------------------------------------------------------

def assert_wrapped(q_deg):
    """In (-180 + tol, 180 + tol] as opw.wrap_deg wraps (tol = ANGLE_TOLERANCE_DEG: rounding
    never decides between -180 and +180), up to rounding of the wrap's own subtraction."""
    tol = opw.ANGLE_TOLERANCE_DEG
    assert (q_deg > -180.0 + tol - 1e-12).all() and (q_deg <= 180.0 + tol + 1e-12).all()


def assert_same_solutions(new, ref, params=None):
    """Same NaN pattern and the same angles to TOL_DEG.

    With `params`, rows at a wrist singularity (sin theta5 within 1e-7 of 0)
    are compared by what is defined there: joints 1, 2, 3, 5 and the pose the
    row gives. Only theta4 + theta6 is fixed at the singularity; how it splits
    between them depends on rounding, even between two runs of one solver.
    """
    assert new.shape == ref.shape and new.dtype == np.float64
    nan_new, nan_ref = np.isnan(new), np.isnan(ref)
    assert np.array_equal(nan_new, nan_ref), "NaN patterns differ at %s" % (
        np.argwhere(nan_new != nan_ref)[:5].tolist(),)
    ok = ~nan_ref
    assert_wrapped(new[ok])
    compared = ok.copy()
    if params is not None:
        rows_new, rows_ref = new.reshape(-1, 6), ref.reshape(-1, 6)
        theta5 = rows_ref[:, 4] * params.signs[4] - params.offsets_deg[4]
        singular = ~np.isnan(theta5) & (np.abs(np.sin(np.radians(theta5))) < 1e-7)
        if singular.any():
            T_new = opw.forward(params, rows_new[singular])
            T_ref = opw.forward(params, rows_ref[singular])
            np.testing.assert_allclose(T_new[:, :3, 3], T_ref[:, :3, 3], atol=1e-6)
            np.testing.assert_allclose(T_new[:, :3, :3], T_ref[:, :3, :3], atol=1e-9)
            compared = compared.reshape(-1, 6)
            compared[np.ix_(singular, [3, 5])] = False
            compared = compared.reshape(ok.shape)
    diff = np.abs(opw.wrap_deg(new[compared] - ref[compared]))
    assert diff.max(initial=0.0) <= TOL_DEG, "max difference %.3g deg" % diff.max()


def assert_same_poses(new, ref, params):
    """Same NaN pattern, every row the pose of the reference's row (1e-6 mm, 1e-9),
    and the same joints to TOL_COMPILED_DEG on rows away from a singularity."""
    assert new.shape == ref.shape and new.dtype == np.float64
    nan_new, nan_ref = np.isnan(new), np.isnan(ref)
    assert np.array_equal(nan_new, nan_ref), "NaN patterns differ at %s" % (
        np.argwhere(nan_new != nan_ref)[:5].tolist(),)
    rows_new, rows_ref = new.reshape(-1, 6), ref.reshape(-1, 6)
    ok = ~np.isnan(rows_ref).any(axis=1)
    assert_wrapped(rows_new[ok])
    T_new, T_ref = opw.forward(params, rows_new[ok]), opw.forward(params, rows_ref[ok])
    np.testing.assert_allclose(T_new[:, :3, 3], T_ref[:, :3, 3], atol=1e-6)
    np.testing.assert_allclose(T_new[:, :3, :3], T_ref[:, :3, :3], atol=1e-9)
    model = np.radians(rows_ref[ok] * np.asarray(params.signs) - np.asarray(params.offsets_deg))
    elbow = model[:, 2] + np.arctan2(params.a2, params.c3)
    regular = (np.abs(np.sin(model[:, 4])) > SINGULAR_SIN) & (np.abs(np.sin(elbow)) > SINGULAR_SIN)
    diff = np.abs(opw.wrap_deg(rows_new[ok][regular] - rows_ref[ok][regular]))
    assert diff.max(initial=0.0) <= TOL_COMPILED_DEG, "max difference %.3g deg" % diff.max()


@pytest.mark.parametrize("name", OPW_ROBOTS)
def test_random_joint_poses(inverse, name):
    robot = models.model(name)
    T = random_joint_poses(robot, 20000, seed=1)
    inverse.check(inverse.solve(robot.spec.opw, T), _reference_inverse(robot.spec.opw, T),
                          robot.spec.opw)


@pytest.mark.parametrize("name", OPW_ROBOTS)
def test_random_box_poses(inverse, name):
    robot = models.model(name)
    T = random_box_poses(robot, 20000, seed=2)
    S_ref = _reference_inverse(robot.spec.opw, T)
    assert np.isnan(S_ref).all(axis=(1, 2)).any() and (~np.isnan(S_ref)).all(axis=2).any()
    inverse.check(inverse.solve(robot.spec.opw, T), S_ref, robot.spec.opw)


@pytest.mark.parametrize("name", OPW_ROBOTS)
def test_singular_poses(inverse, name):
    robot = models.model(name)
    T = singular_poses(robot)
    inverse.check(inverse.solve(robot.spec.opw, T), _reference_inverse(robot.spec.opw, T),
                          robot.spec.opw)


@pytest.mark.parametrize("name", OPW_ROBOTS)
def test_nan_and_inf_entries(inverse, name):
    robot = models.model(name)
    T = garbage_poses(robot)
    with np.errstate(all="ignore"):
        S_ref = _reference_inverse(robot.spec.opw, T)
        S_new = inverse.solve(robot.spec.opw, T)
    inverse.check(S_new, S_ref, robot.spec.opw)


#: Not in the catalog: a lateral offset b (every catalog robot has b = 0, which
#: the new code treats as a special case), negative a1, an offset on every
#: joint and mixed signs.
OTHER_PARAMETERS = [
    catalog.OPWParameters(150, -115, 60, 445, 700, 795, 85, (10, -90, 30, -45, 90, 180),
                          (1, -1, 1, -1, -1, 1)),
    catalog.OPWParameters(-40, 35, -120, 675, 680, 670, 158, (180, 0, -90, 0, -180, 45),
                          (-1, 1, -1, 1, 1, -1)),
]


@pytest.mark.parametrize("params", OTHER_PARAMETERS, ids=["b60", "b-120"])
def test_other_parameters(inverse, params):
    robot = models.as_model(dataclasses.replace(catalog.get("KUKA_KR16"), name="TEST",
                                                opw=params, dh=None))
    T = np.concatenate([random_joint_poses(robot, 5000, seed=4),
                        random_box_poses(robot, 5000, seed=5), singular_poses(robot)])
    S_ref = _reference_inverse(params, T)
    assert np.isnan(S_ref).all(axis=2).any() and (~np.isnan(S_ref)).all(axis=2).any()
    inverse.check(inverse.solve(params, T), S_ref, params)


@pytest.mark.parametrize("n", [0, 1, 2, 7, 1023, 1024, 1025,
                               opw_kernel.BLOCK_POSES - 1, opw_kernel.BLOCK_POSES,
                               opw_kernel.BLOCK_POSES + 1,
                               opw.BLOCK_POSES - 1, opw.BLOCK_POSES, opw.BLOCK_POSES + 1,
                               3 * opw.BLOCK_POSES + 17])
def test_batch_sizes(inverse, n):
    robot = models.model("KUKA_KR16")
    T = random_box_poses(robot, n, seed=n)
    inverse.check(inverse.solve(robot.spec.opw, T), _reference_inverse(robot.spec.opw, T),
                          robot.spec.opw)


def test_input_forms(inverse):
    """One pose (4, 4), lists, float32, non-contiguous and Fortran-ordered batches; the
    input is never modified and the result is a fresh C-contiguous float64 array."""
    # (robot.ik is opw.inverse: tests/core/test_kinematics_reference.py checks it.)
    robot = models.model("ABB_IRB2400")
    params = robot.spec.opw
    T = random_joint_poses(robot, 301, seed=3)
    keep = T.copy()
    for form in (T, T[::3], np.asfortranarray(T), T.astype(np.float32), T.tolist(),
                 np.ascontiguousarray(T.transpose(0, 2, 1)).transpose(0, 2, 1)):
        new = inverse.solve(params, form)
        assert new.flags.c_contiguous
        inverse.check(new, _reference_inverse(params, form), params)
    np.testing.assert_array_equal(T, keep)
    one = inverse.solve(params, T[5])
    assert one.shape == (8, 6)
    inverse.check(one[None], _reference_inverse(params, T[5])[None], params)
