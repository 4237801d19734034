"""Offset-wrist solutions where axis 5 is parallel to axis 2 (robots/kinematics/offset_wrist_polish.py).

The one-dimensional search cannot build axis 4 there; the torch straight down puts every
solution of a CRX or HC10 there. The numerical IK of the URDF chain is the reference.
"""

import os

import numpy as np
import pytest

from CadRobotWB.core.rotations import matrix_from_axis_angle
from CadRobotWB.robots.kinematics import models, offset_wrist_polish, poe
from CadRobotWB.robots.urdf import numeric_ik, urdf

ROBOTS = os.path.join(os.path.dirname(__file__), os.pardir, "data", "robots")
DOWN = np.diag([1.0, -1.0, -1.0])


def _chain(folder):
    return urdf.serial_chain(urdf.read_urdf(os.path.join(ROBOTS, folder, "robot.urdf")))


def _missed(q_closed, q_numeric):
    """Numerical solutions (deg) that no closed-form row matches within 1e-3 deg."""
    missed = 0
    for closed, numeric in zip(q_closed, q_numeric):
        rows = closed[~np.isnan(closed[:, 0])]
        for q in numeric[~np.isnan(numeric[:, 0])]:
            if len(rows) == 0 or np.abs((rows - q + 180.0) % 360.0 - 180.0).max(axis=1).min() > 1e-3:
                missed += 1
    return missed


@pytest.mark.parametrize("name, folder", [("FANUC_CRX10IAL", "fanuc_crx10ial"),
                                          ("MOTOMAN_HC10", "motoman_hc10")])
@pytest.mark.parametrize("tilt_deg", [0.0, 1e-6])
def test_torch_down_poses_get_every_solution(name, folder, tilt_deg):
    """Flange Z straight down (and a hair off it): the rows the numerical IK finds, no fewer."""
    model = models.model(name)
    points = [(x, y, z) for x in (350.0, 450.0, 550.0, 650.0) for y in (-150.0, 0.0, 150.0)
              for z in (200.0, 400.0)]
    T = np.tile(np.eye(4), (len(points), 1, 1))
    T[:, :3, :3] = DOWN @ matrix_from_axis_angle([1.0, 0.3, 0.0], np.radians(tilt_deg))
    T[:, :3, 3] = points
    q_closed = model.ik(T)
    q_numeric = numeric_ik.solve(_chain(folder), T, max_solutions=16)
    assert (~np.isnan(q_numeric[..., 0])).sum() >= 150          # the poses are reachable
    assert _missed(q_closed, q_numeric) == 0
    good = ~np.isnan(q_closed[..., 0])
    F = model.fk(q_closed[good])
    assert np.abs(F[:, :3, 3] - np.repeat(T, 16, axis=0)[good.ravel()][:, :3, 3]).max() < 1e-6


def test_a_solution_with_joint_4_at_180_is_found():
    q = np.array([-18.9, 30.7, 36.5, 180.0, 95.8, -161.1])
    model = models.model("FANUC_CRX10IAL")
    rows = model.ik(model.fk(q))
    rows = rows[~np.isnan(rows[:, 0])]
    assert np.abs((rows - q + 180.0) % 360.0 - 180.0).max(axis=1).min() < 1e-6


def test_the_aligned_joint_4_by_hand():
    """CRX: axis 5 is parallel to axis 2 at J4 = 0 and 180 deg (its zero pose has the
    wrist in the arm's plane); the MPX3500's axes 4 and 5 are 60 deg apart: never."""
    params = poe.from_chain(_chain("fanuc_crx10ial"))
    aligned = offset_wrist_polish.aligned_q4_rad(params)
    assert len(aligned) == 2 and np.abs(np.sin(aligned)).max() < 1e-12     # 0 and 180 deg
    assert abs(np.cos(aligned[1] - aligned[0]) + 1.0) < 1e-12
    for a in aligned:
        h5 = matrix_from_axis_angle(params.H[3], a) @ params.H[4]
        assert np.linalg.norm(np.cross(h5, params.H[1])) < 1e-12
    assert len(offset_wrist_polish.aligned_q4_rad(poe.from_chain(_chain("motoman_mpx3500")))) == 0


def test_torch_down_out_of_reach_gives_no_row():
    """Beyond the reach the shoulder's subproblem has roots but the elbow's has none:
    those half-solved rows are dropped, not polished (a NaN row once stopped the SVD)."""
    model = models.model("FANUC_CRX10IAL")
    T = np.tile(np.eye(4), (4, 1, 1))
    T[:, :3, :3] = DOWN
    T[:, :3, 3] = [(x, 0.0, 500.0) for x in (1500.0, 2000.0, 3000.0, 0.0)]
    assert np.isnan(model.ik(T)).all()


def test_the_compiled_loops_give_the_numpy_answers():
    """offset_wrist_polish_kernel against the numpy reference: rows polished onto poses
    1e-3 rad away (and rows too far to reach them, dropped) to 1e-9 rad, the same merged
    rows (a repeat 1e-8 rad off dropped, one 1e-3 rad off kept)."""
    kernel = offset_wrist_polish.kernel
    if not kernel.available():
        pytest.skip("numba: %s" % kernel.why_not)
    params = models.model("MOTOMAN_HC10").params
    rng = np.random.default_rng(7)
    q = rng.uniform(-np.pi, np.pi, (50, 4, 6))
    q[:, 3] = np.nan
    T = poe.fk(params, q[:, 0] + rng.normal(0.0, 1e-3, (50, 6)))
    compiled = _compiled_polish(params, q, T)
    reference = offset_wrist_polish._polished_onto_numpy(params, q, T)
    assert np.array_equal(np.isnan(compiled), np.isnan(reference))
    assert np.nanmax(np.abs(compiled - reference)) < 1e-9
    assert (~np.isnan(compiled[:, 0, 0])).all() and np.isnan(compiled[:, 1:, 0]).all()
    rows = np.full((50, 16, 6), np.nan)
    rows[:, :3] = rng.uniform(-np.pi, np.pi, (50, 3, 6))
    extra = np.concatenate([rows[:, 1:2] + 1e-8, np.full((50, 1, 6), np.nan),
                            rows[:, 2:3] + 1e-3, rows[:, 2:3] + 1e-3], axis=1)
    merged = kernel.merged(rows, extra, offset_wrist_polish.SAME_RAD)
    assert np.array_equal(merged, offset_wrist_polish._merged_numpy(rows, extra), equal_nan=True)
    assert (~np.isnan(merged[..., 0])).sum(axis=1).tolist() == [4] * 50


def test_a_pose_next_to_upright_and_the_wrist_singularity_keeps_its_search():
    """HC10, 0.0005 deg off straight down, next to its wrist singularity (J5 near 180, J4
    near 0): two pairs of solutions 0.25 deg apart in J4 where the upright pose has one
    of each. The search (poses off upright by more than rounding) finds both of each pair,
    the closed forms polished alone one (the numerical IK: 8 solutions)."""
    model = models.model("MOTOMAN_HC10")
    T = np.eye(4)
    T[:3, :3] = (matrix_from_axis_angle([0.3405705337781045, -0.4861719071399926,
                                         -0.6409975166442754], np.radians(5e-4))
                 @ matrix_from_axis_angle([0.0, 0.0, 1.0], -0.6319297187214739) @ DOWN)
    T[:3, 3] = (9.036731629390232, 406.1558695185629, 52.42813904155895)
    q_numeric = numeric_ik.solve(_chain("motoman_hc10"), T[None], max_solutions=16)
    assert (~np.isnan(q_numeric[..., 0])).sum() == 8
    assert _missed(model.ik(T[None]), q_numeric) == 0


def test_upright_poses_skip_the_search():
    """Straight down to rounding on an arm whose upright solutions are all in the closed
    forms (CRX: axes 1-2, 4-5, 5-6 perpendicular): the search is not called for them."""
    solver = models.model("FANUC_CRX10IAL").solver
    T = np.tile(np.eye(4), (3, 1, 1))
    T[:, :3, :3] = matrix_from_axis_angle([0.0, 1.0, 0.0], np.pi / 2)    # axis 6 along +-z
    T[:, :3, 3] = [(500.0, 0.0, 300.0), (400.0, 200.0, 300.0), (500.0, 0.0, 800.0)]
    T[2, :3, :3] = matrix_from_axis_angle([1.0, 0.0, 0.0], 0.3) @ T[2, :3, :3]   # tilted
    searched = []

    def search(T_0T):
        searched.append(len(T_0T))
        return solver.module.inverse(solver.constants, T_0T)

    assert offset_wrist_polish.upright_closed(solver.params)
    q = offset_wrist_polish.solve(solver.params, search, T, 16)
    assert searched == [1]                                   # the tilted pose only
    good = ~np.isnan(q[:2, :, 0])
    assert good.sum(axis=1).min() >= 8
    F = poe.fk(solver.params, q[:2][good])
    assert np.abs(F - np.repeat(T[:2], 16, axis=0)[good.ravel()]).max() < 1e-6


def test_beyond_reach_never_flags_a_reachable_pose():
    """The bound (axis 6's point farther from axis 1's than |P1| + ... + |P5|) holds for
    any joint values, so no pose of the forward kinematics is beyond it; one 1 mm past it
    along a straight arm is."""
    params = models.model("FANUC_CRX10IAL").params
    q = np.random.default_rng(3).uniform(-np.pi, np.pi, (2000, 6))
    assert not offset_wrist_polish.beyond_reach(params, poe.fk(params, q)).any()
    links = np.linalg.norm(params.P[1:6], axis=1).sum()
    T = np.eye(4)[None].copy()
    T[0, :3, 3] = params.P[0] + params.R_6T.T @ params.P[6] + (links + 1.0) * np.array([0.6, 0.0, 0.8])
    assert offset_wrist_polish.beyond_reach(params, T).all()
    T[0, :3, 3] -= 2.0 * np.array([0.6, 0.0, 0.8])
    assert not offset_wrist_polish.beyond_reach(params, T).any()


def test_the_compiled_screening_flags_the_poses_numpy_flags():
    """offset_wrist.inverse_screened (search and screening in one compiled pass) against
    offset_wrist_polish.screened on the CRX: random poses, upright ones (to rounding, 5e-4
    and 0.01 deg off), ones with joint 4 within SUSPECT_DEG of its aligned 0 (suspect) and
    one beyond reach (not suspect though it has no solution)."""
    from CadRobotWB.robots.kinematics import offset_wrist
    solver = models.model("FANUC_CRX10IAL").solver
    if not offset_wrist.offset_wrist_kernel.available():
        pytest.skip("numba: %s" % offset_wrist.offset_wrist_kernel.why_not)
    params, k = solver.params, solver.constants
    rng = np.random.default_rng(11)
    q = rng.uniform(-np.pi, np.pi, (60, 6))
    q[:20, 3] = rng.uniform(-1e-3, 1e-3, 20)            # J4 within 0.06 deg of aligned
    T = poe.fk(params, q)
    upright = matrix_from_axis_angle([0.0, 1.0, 0.0], np.pi / 2)      # axis 6 along -z
    T[20:30, :3, :3] = upright
    for poses, tilt_deg in ((slice(25, 28), 0.01), (slice(28, 30), 5e-4)):
        T[poses, :3, :3] = matrix_from_axis_angle([1.0, 0.3, 0.0], np.radians(tilt_deg)) @ upright
    T[30, :3, 3] = (3000.0, 0.0, 0.0)
    reference = offset_wrist_polish.screened(
        params, lambda T: offset_wrist.inverse(k, T), T, 16, offset_wrist_polish.aligned_q4_rad(params))
    compiled = offset_wrist.inverse_screened(k, T, offset_wrist_polish.screen_vector(params))
    assert np.array_equal(compiled[0], reference[0], equal_nan=True)
    assert np.array_equal(compiled[1], reference[1])
    assert np.array_equal(compiled[2], reference[2])
    assert reference[1].sum() == 10 and 30 not in reference[2] and len(reference[2]) >= 10


def _compiled_polish(params, q, T):
    """kernel.polished_onto with offset_wrist_polish's settings."""
    p = offset_wrist_polish
    return p.kernel.polished_onto(params.H, params.P, params.R_6T, q, T, p.STEPS, p.GIVE_UP_STEP,
                                  p.GIVE_UP_TOL, p.POSITION_TOL_MM, p.ROTATION_TOL_RAD,
                                  p.PINV_RCOND)


def _singular_q5(params, q):
    """q (M, 6) with joint 5 moved to a root of det J (bisection to rounding), and the
    Jacobians' smallest over largest singular values there (M,)."""
    def jacobian(q5):
        q_ = np.repeat(q, q5.size // len(q), axis=0)
        q_[:, 4] = q5.ravel()
        _, _, p_flange = offset_wrist_polish._errors(params, q_, poe.fk(params, q_))
        return offset_wrist_polish._jacobian(params, q_, p_flange)

    def sign(q5):
        return np.sign(np.linalg.det(jacobian(q5))).reshape(q5.shape)
    grid = q[:, 4, None] + np.linspace(-np.pi, np.pi, 73)                   # (M, 73)
    signs = sign(grid)
    first = np.argmax(signs[:, :-1] != signs[:, 1:], axis=1)
    lo, hi = grid[np.arange(len(q)), first], grid[np.arange(len(q)), first + 1]
    sign_lo = sign(lo)
    for _ in range(55):                          # 2 pi / 72 / 2^55: under rounding
        mid = 0.5 * (lo + hi)
        sign_mid = sign(mid)
        lower = sign_mid != sign_lo
        lo, hi, sign_lo = (np.where(lower, lo, mid), np.where(lower, mid, hi),
                           np.where(lower, sign_lo, sign_mid))
    q5 = 0.5 * (lo + hi)
    s = np.linalg.svd(jacobian(q5), compute_uv=False)
    singular = q.copy()
    singular[:, 4] = q5
    return singular, s[:, -1] / s[:, 0]


def test_the_compiled_polish_steps_as_numpy_at_a_singular_jacobian():
    """HC10 rows started exactly at singular joint values (det J = 0, joint 5 by bisection:
    the smallest singular value 1e-16 of the largest, far under pinv's rcond 1e-10) towards
    poses 1e-4 and 1e-2 rad away: the compiled polish (pivoted QR where that shows J
    regular, a Jacobi SVD where it does not) keeps and drops the rows numpy's pinv steps
    keep and drop, and moves them to the same joint values to 1e-9 rad."""
    kernel = offset_wrist_polish.kernel
    if not kernel.available():
        pytest.skip("numba: %s" % kernel.why_not)
    params = models.model("MOTOMAN_HC10").params
    rng = np.random.default_rng(5)
    singular, ratio = _singular_q5(params, rng.uniform(-2.0, 2.0, (8, 6)))
    assert ratio.max() < 1e-14
    away = np.concatenate([rng.normal(0.0, size, (8, 6)) for size in (1e-4, 1e-2, 0.3)])
    q = np.tile(singular, (3, 1))[:, None]                          # (24, 1, 6)
    T = poe.fk(params, q[:, 0] + away)
    compiled = _compiled_polish(params, q, T)
    reference = offset_wrist_polish._polished_onto_numpy(params, q, T)
    assert np.array_equal(np.isnan(compiled), np.isnan(reference))
    assert np.nanmax(np.abs(compiled - reference)) < 1e-9
    kept = ~np.isnan(reference[:, 0, 0])
    assert kept[:16].all() and not kept[16:].all()


def test_the_compiled_step_is_numpys_pinv_at_rank_deficient_jacobians():
    """The compiled step against ``np.linalg.pinv(J, rcond=1e-10) @ e`` (the numpy polish's):
    two leading columns parallel (rank 5; a QR without pivoting would divide by zero), two
    dependencies (rank 4), and singular values 1e-12 (dropped), 1e-9 (kept: a Jacobi SVD,
    not the QR), 1e-3 (the QR) of the largest, to the rounding such a ratio allows."""
    kernel = offset_wrist_polish.kernel
    if not kernel.available():
        pytest.skip("numba: %s" % kernel.why_not)
    rng = np.random.default_rng(3)
    U, _ = np.linalg.qr(rng.normal(size=(6, 6)))
    V, _ = np.linalg.qr(rng.normal(size=(6, 6)))
    jacobians = [U @ np.diag([800.0, 300.0, 20.0, 1.0, 0.5, 800.0 * ratio]) @ V.T
                 for ratio in (1e-12, 1e-9, 1e-3)]
    rank_5 = rng.normal(size=(6, 6)) * np.array([300.0, 300.0, 300.0, 1.0, 1.0, 1.0])[:, None]
    rank_5[:, 1] = 2.0 * rank_5[:, 0]
    rank_4 = rank_5.copy()
    rank_4[:, 3] = rank_4[:, 2] - rank_4[:, 4]
    scratch = (np.empty((6, 6)), np.empty((6, 6)), np.empty(6), np.empty(6, dtype=np.int64))
    for J, tol in zip(jacobians + [rank_5, rank_4], (1e-9, 1e-5, 1e-9, 1e-9, 1e-9)):
        e = rng.normal(size=6)
        step = np.empty(6)
        kernel._pinv_step(J, e, offset_wrist_polish.PINV_RCOND, step, *scratch)
        reference = np.linalg.pinv(J, rcond=offset_wrist_polish.PINV_RCOND) @ e
        assert np.abs(step - reference).max() <= tol * np.abs(reference).max()
