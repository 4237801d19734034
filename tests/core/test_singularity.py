"""The singularity distance on the Jacobian (robots/kinematics/singularity.py).

Against what is known by hand on an OPW arm (the IRB 2400: det J is proportional to
sin(theta5) and to the elbow's sine, so the distance is tan of the angle), against a
finite-difference gradient, and on the CRX-10iA/L, whose singularities are not at J5 = 0.
"""

import os

import numpy as np
import pytest

from CadRobotWB.robots.kinematics import arm_families, models, poe, singularity
from CadRobotWB.robots.urdf import urdf

DATA = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "data", "robots")


def _params(folder):
    return poe.from_chain(urdf.serial_chain(urdf.read_urdf(os.path.join(DATA, folder,
                                                                          "robot.urdf"))))


IRB2400 = _params("abb_irb2400")
CRX = models.model("FANUC_CRX10IAL")


def _det(params, q_deg):
    v, w = singularity.spatial_twists(params, np.radians(np.atleast_2d(q_deg)))
    return np.linalg.det(np.concatenate([v, w], axis=2))


def _gradient_by_differences(params, q_deg, step_deg=1e-4):
    q = np.asarray(q_deg, dtype=float)
    return np.array([(_det(params, q + step_deg * e) - _det(params, q - step_deg * e))[0]
                     / np.radians(2 * step_deg) for e in np.eye(6)])


@pytest.mark.parametrize("theta5", [0.5, 2.0, -3.0])
def test_next_to_the_wrist_singularity_the_distance_is_tan_theta5(theta5):
    q = np.array([10.0, 20.0, -10.0, 30.0, theta5, 40.0])
    expected = np.degrees(np.tan(np.radians(abs(theta5))))
    assert singularity.distance_deg(IRB2400, q) == pytest.approx(expected, rel=0.02)


def _root(params, q, joint, lo, hi):
    """Joint `joint`'s value in (lo, hi) where det J changes sign, by bisection, deg."""
    def sign(value):
        row = np.array(q, dtype=float)
        row[joint] = value
        return np.sign(_det(params, row)[0])
    assert sign(lo) != sign(hi)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if sign(mid) == sign(lo) else (lo, mid)
    return 0.5 * (lo + hi)


def test_next_to_the_elbow_singularity_the_distance_is_the_elbow_angle():
    """On an OPW arm det J is proportional to the sine of the elbow's angle from stretched:
    the distance is its tangent, to first order (within 4 % at 1 deg, 8 % at 2 deg: the
    shoulder's factor turns with J2 and J3 too). The IRB 2400's URDF has it stretched or folded where axis
    3's forearm (135 mm up, 755 mm out) lines up with the upper arm: J3 = -90 + atan2(135,
    755) = -79.86 deg (and +100.14)."""
    q = np.array([0.0, 10.0, 0.0, 30.0, 60.0, 0.0])
    stretched = _root(IRB2400, q, 2, -95.0, -60.0)
    assert stretched == pytest.approx(-90.0 + np.degrees(np.arctan2(135.0, 755.0)), abs=1e-6)
    for off in (1.0, -2.0):
        q[2] = stretched + off
        expected = np.degrees(np.tan(np.radians(abs(off))))
        assert singularity.distance_deg(IRB2400, q) == pytest.approx(expected, rel=0.04 * abs(off))


def test_the_gradient_is_the_determinants_own():
    rng = np.random.default_rng(3)
    for q in rng.uniform(-150.0, 150.0, (5, 6)):
        det = _det(CRX.params, q)[0]
        expected = abs(det) / np.linalg.norm(_gradient_by_differences(CRX.params, q))
        assert singularity.distance_deg(CRX.params, q) == pytest.approx(
            np.degrees(expected), rel=1e-5)


def test_on_the_crx_a_distance_under_3_deg_has_a_singularity_within_twice_it():
    """Where the distance is under 3 deg, det J changes sign within two steps of it
    against the determinant's gradient (the gradient by differences here)."""
    rng = np.random.default_rng(4)
    q = rng.uniform(-170.0, 170.0, (4000, 6))
    d = singularity.distance_deg(CRX.params, q)
    near = np.flatnonzero(d < 3.0)[:20]
    assert len(near) == 20
    for row, distance in zip(q[near], d[near]):
        g = _gradient_by_differences(CRX.params, row)
        det = _det(CRX.params, row)[0]
        beyond = row - 2.0 * distance * np.sign(det) * g / np.linalg.norm(g)
        assert np.sign(_det(CRX.params, beyond)[0]) != np.sign(det)


def test_the_crx_is_singular_where_its_wrist_bit_says_nothing():
    """At J2 = 60, J3 = -120, J4 = 60 deg the CRX is not singular at J5 = 1 deg but at J5 =
    -59.5 deg (det J's root, by bisection): the distances Check uses say so, where J5's own
    angle would put the singularity at 1 deg. Off the root by a turn of J5 alone, the
    joint-space distance is at most that turn (the other joints may get there sooner)."""
    q = np.array([0.0, 60.0, -120.0, 60.0, 1.0, 0.0])
    assert arm_families.singular_on_jacobian(CRX)
    shoulder, elbow, wrist = arm_families.arm_geometry(q, CRX).singularity_distances()
    assert wrist > 20.0 and shoulder == np.inf and elbow == 90.0
    singular = _root(CRX.params, q, 4, -80.0, -40.0)
    assert singular == pytest.approx(-59.5, abs=0.5)
    for off in (0.5, -1.0):
        q[4] = singular + off
        distance = arm_families.arm_geometry(q, CRX).singularity_distances()[2]
        assert 0.2 * abs(off) < distance <= 1.02 * abs(off)


def test_a_spherical_wrist_keeps_its_three_singularities():
    assert not arm_families.singular_on_jacobian(models.model("KUKA_KR16_R1100_3"))
    assert not arm_families.singular_on_jacobian(models.model("ABB_IRB2400"))


def test_the_compiled_kernel_gives_the_numpy_distances():
    from CadRobotWB.robots.kinematics import singularity_kernel
    if not singularity_kernel.available():
        pytest.skip("numba: %s" % singularity_kernel.why_not)
    q = np.radians(np.random.default_rng(5).uniform(-170.0, 170.0, (500, 6)))
    q[0] = 0.0                                            # straight wrist: exactly singular?
    for params in (CRX.params, IRB2400):
        np.testing.assert_allclose(singularity_kernel.distances(params.H, params.P, q),
                                   singularity.distance_deg_numpy(params, q), rtol=1e-8)


def _crx_check(joints):
    """Check's singularity findings at the targets, each reached by a joint move (a linear
    move from J5 -20 to -58 deg crosses det J = 0, where the arm's path leaves its family's
    solution: the solver then takes another family, and Check has nothing to say here)."""
    from test_configuration import program_from_joints
    from CadRobotWB.core import program as ir
    from CadRobotWB.robots.checks import checks
    from CadRobotWB.robots.motion import configuration
    program = program_from_joints(CRX, joints, kinds=[ir.JOINT] * len(joints),
                                  robot="FANUC_CRX10IAL")
    solution = configuration.solve_program(program, CRX, q_start_deg=joints[0])
    report = checks.check_program(program, CRX, solution)
    return [f for f in report.findings if f.kind == checks.SINGULARITY]


def test_check_warns_next_to_the_crx_singularity_and_not_at_its_j5_zero():
    """Two CRX targets at J2 60, J3 -120, J4 60: J5 = 1 deg (40 deg from det J's root, no
    warning, where the wrist's angle alone would warn) and J5 = -58 deg (1.5 deg from
    it: a warning naming the arm's singularity, not the wrist's)."""
    far = _crx_check(np.array([[0.0, 60.0, -120.0, 60.0, 1.0, 0.0],
                               [2.0, 60.0, -120.0, 60.0, 1.0, 0.0]]))
    assert far == []
    near = _crx_check(np.array([[0.0, 60.0, -120.0, 60.0, -20.0, 0.0],
                                [0.0, 60.0, -120.0, 60.0, -58.0, 0.0]]))
    assert [f.target for f in near] == ["t2"]
    assert "deg (in joint space) from a singularity of the arm" in near[0].message
    assert near[0].value < 1.5
