"""Deterministic output (issue 10, item 3): rounding noise never changes a program.

FreeCAD 0.20.2, 1.0 and 1.1 (different numpy and OCCT), and a document saved
and reopened, give the same rotation matrices up to the last bits (~1e-16).
A tool turned 180 degrees about an axis in the XY plane has w = ±1e-17: with
a ``w < 0`` sign rule the quaternion flipped with that noise, and so did
KUKA's C (180 / -180) and UR's rotation vector (±axis·π).  Here the same
targets, perturbed in several ways, must give byte-identical programs.
"""

import datetime
import itertools

import numpy as np
import pytest

from CadRobotWB.core import rotations
from CadRobotWB.core.generate import CellSpec, FrameSpec, PathSpec, RiskAreaSpec, generate
from CadRobotWB.core.geometry import Line
from CadRobotWB.core.program import ToolData
from CadRobotWB.posts import abb_rapid, fanuc_ls, kuka_krl, motoman_inform, ur_script

POSTS = (abb_rapid, kuka_krl, ur_script, fanuc_ls, motoman_inform)
OPTIONS = {"date": datetime.datetime(2024, 1, 2, 3, 4, 5)}


def half_turn_axes():
    """Unit axes (N, 3) in the XY plane, and the one of the bug report."""
    degrees = np.radians([0.0, 10.0, 45.0, 90.0, 150.0, -30.0])
    axes = [(np.cos(a), np.sin(a), 0.0) for a in degrees]
    axes.append((0.996195, 0.0, 0.087156))
    return np.array(axes) / np.linalg.norm(axes, axis=1, keepdims=True)


def half_turn_exact(axis):
    """Rotation by π about a unit axis: 2 n nᵀ - I (exactly symmetric)."""
    n = np.asarray(axis, dtype=float)
    return 2.0 * np.outer(n, n) - np.eye(3)


def noisy_versions(R):
    """The same rotation as different versions / a reopened file give it.

    Returns
    -------
    list of ndarray, shape (3, 3)
        Rounding-level variants of R; their antisymmetric parts (the w of a
        half turn) have both signs.
    """
    axis = rotations.rotvec_from_matrix(R)
    antisym = np.array([[0.0, -1.0, 1.0], [1.0, 0.0, -1.0], [-1.0, 1.0, 0.0]])
    out = [R,
           rotations.matrix_from_axis_angle(axis, np.pi),     # w = cos(π/2) = 6e-17
           rotations.matrix_from_axis_angle(-axis, np.pi),
           rotations.matrix_from_axis_angle(axis, -np.pi),
           R + 1e-16 * antisym,                              # w = +5e-17
           R - 1e-16 * antisym,                              # w = -5e-17
           R + 3e-16 * antisym.T + 2e-16 * np.eye(3)]
    rng = np.random.default_rng(7)
    out += [R + rng.uniform(-2e-16, 2e-16, (3, 3)) for _ in range(6)]
    return out


def cell_with(R_u_t):
    """One path of three lines, the tool turned R_u_t on the first two
    segments and a further half turn about Z on the third, with a risk area
    over segments 2-3 (a slerp between orientations 180 degrees apart)."""
    Rz_half = np.diag([-1.0, -1.0, 1.0])
    points = [(0, 0, 0), (100, 0, 0), (100, 80, 0), (20, 80, 0)]
    segments = [Line(a, b, "Sketch.Edge%d" % i) for i, (a, b) in
                enumerate(zip(points[:-1], points[1:]), start=1)]
    T_u_b = np.eye(4)
    T_u_b[:3, 3] = (400.0, -100.0, 300.0)
    path = PathSpec(name="Weld", label="Weld", segments=segments,
                    R_u_t=[R_u_t, R_u_t, Rz_half @ R_u_t], frame="Frame",
                    speed_mm_s=20.0, zone_mm=1.0, sample_time_s=1.0,
                    risk_areas=[RiskAreaSpec("Risk", "Risk", 2, 3, step_mm=20.0)])
    T_u_r = np.eye(4)
    T_u_r[:3, 3] = (-500.0, 0.0, 0.0)
    return CellSpec(name="Cell", label="Cell", robot="ABB_IRB2400", T_u_r=T_u_r,
                    tool=ToolData("Torch", np.eye(4)),
                    frames={"Frame": FrameSpec("Frame", "Frame", T_u_b)},
                    paths=[path], source="doc.FCStd / Cell")


def texts(R_u_t):
    """{post name: program text} of the cell with tool orientation R_u_t."""
    program = generate(cell_with(R_u_t))
    return {post.NAME: "".join(text for _, text in post.export(program, dict(OPTIONS)))
            for post in POSTS}


@pytest.mark.parametrize("axis", half_turn_axes(), ids=lambda a: "axis(%.3f,%.3f,%.3f)" % tuple(a))
def test_half_turn_gives_the_same_program_whatever_the_noise(axis):
    versions = noisy_versions(half_turn_exact(axis))
    signs = {np.sign(R[2, 1] - R[1, 2]) for R in versions}
    assert len(signs) > 1        # the noise really reaches both signs of w
    expected = texts(versions[0])
    for i, R in enumerate(versions[1:], start=1):
        got = texts(R)
        for name in expected:
            assert got[name] == expected[name], f"{name}: variant {i} differs"


def test_half_turn_quaternion_is_canonical():
    """The bug report's target: w = ±1e-17 gives one text, first non-zero positive."""
    R = half_turn_exact((0.996195, 0.0, 0.087156))
    quats = [rotations.quaternion_from_matrix(Rn) for Rn in noisy_versions(R)]
    for q in quats:
        assert abs(q[0]) < 1e-15 and q[1] > 0.99 and q[3] > 0.08
    assert len({abb_rapid._quaternion(q) for q in quats}) == 1


def test_euler_and_rotation_vector_at_pi_are_canonical():
    R = half_turn_exact((np.cos(0.3), np.sin(0.3), 0.0))
    for Rn in noisy_versions(R):
        a, b, c = np.degrees(rotations.euler_zyx_from_matrix(Rn))
        assert c == pytest.approx(180.0) and abs(b) < 1e-12
        v = rotations.rotvec_from_matrix(Rn)
        assert v[0] > 0 and np.linalg.norm(v) == pytest.approx(np.pi)
    # Gimbal lock (B = -90): a fixed rule, C = 0, and A = 180 not -180.
    locked = half_turn_exact(np.array([1.0, 0.0, 1.0]) / np.sqrt(2.0))
    for Rn in noisy_versions(locked):
        a, b, c = np.degrees(rotations.euler_zyx_from_matrix(Rn))
        assert (a, b, c) == pytest.approx((180.0, -90.0, 0.0))


# --- the rule ------------------------------------------------------------------

@pytest.mark.parametrize("q, expected", [
    ((-0.5, 0.5, -0.5, 0.5), (0.5, -0.5, 0.5, -0.5)),       # w decides
    ((0.0, -1.0, 0.0, 0.0), (0.0, 1.0, 0.0, 0.0)),          # w = 0: x decides
    ((0.0, 0.0, -0.6, 0.8), (0.0, 0.0, 0.6, -0.8)),         # w = x = 0: y decides
    ((0.0, 0.0, 0.0, -1.0), (0.0, 0.0, 0.0, 1.0)),          # only z
    ((-0.0, 0.0, 0.0, 1.0), (-0.0, 0.0, 0.0, 1.0)),         # -0 decides nothing
    ((-1e-17, 0.6, -0.8, 0.0), (-1e-17, 0.6, -0.8, 0.0)),   # noise in w decides nothing
    ((1e-17, -0.6, 0.8, 0.0), (-1e-17, 0.6, -0.8, 0.0)),
    ((2e-13, -1e-12, 0.0, -1.0), (-2e-13, 1e-12, 0.0, 1.0)),
])
def test_canonical_sign(q, expected):
    got = rotations.choose_quaternion_sign(q)
    np.testing.assert_array_equal(got, expected)
    np.testing.assert_array_equal(rotations.choose_quaternion_sign(-np.asarray(q)), expected)


def test_canonical_sign_of_a_stack():
    q = np.array([[-1.0, 0, 0, 0], [0, -1.0, 0, 0], [1e-18, 0, -1.0, 0]])
    np.testing.assert_array_equal(rotations.choose_quaternion_sign(q),
                                  [[1.0, 0, 0, 0], [0, 1.0, 0, 0], [-1e-18, 0, 1.0, 0]])


def test_previous_quaternion_decides_unless_half_a_turn_away():
    q = np.array([0.0, 0.0, 0.0, -1.0])
    # Near the previous one: continuous, even though w < 0 afterwards.
    np.testing.assert_array_equal(rotations.choose_quaternion_sign(q, (-0.1, 0, 0, -0.995)), q)
    np.testing.assert_array_equal(rotations.choose_quaternion_sign(-q, (-0.1, 0, 0, -0.995)), q)
    # 180 degrees from the previous one (q · prev = ±noise): canonical.
    for prev in [(0.0, 1.0, 0.0, 0.0), (1e-17, 1.0, 0.0, 0.0), (-1e-17, -1.0, 0.0, 0.0)]:
        for sign in (1.0, -1.0):
            np.testing.assert_array_equal(
                rotations.choose_quaternion_sign(sign * (q + [1e-17, 0, 0, 0]), prev),
                (-1e-17, 0.0, 0.0, 1.0))


def test_sequence_is_sign_continuous():
    """A tool turning 720 degrees about a tilted axis: no jump between neighbours,
    even where w passes 0 (a ``w >= 0`` rule would jump there)."""
    axis = np.array([0.3, -0.4, 0.866])
    angles = np.radians(np.arange(0.0, 721.0, 7.5))
    q = rotations.quaternion_sequence_from_matrices(rotations.matrix_from_axis_angle(
        np.broadcast_to(axis, (len(angles), 3)), angles))
    assert np.all(np.sum(q[1:] * q[:-1], axis=1) > 0.99)
    assert q[0, 0] == pytest.approx(1.0)
    assert np.any(q[:, 0] < -0.5)            # it does go past w = 0
    # Each still stands for its rotation.
    R = rotations.matrix_from_axis_angle(np.broadcast_to(axis, (len(angles), 3)), angles)
    np.testing.assert_allclose(rotations.matrix_from_quaternion(q), R, atol=1e-12)


def test_robtargets_are_sign_continuous():
    """ABB robtargets keep one hemisphere while the risk area turns the tool
    from Rz(90) Ry(150) (w = 0.18) to Rz(270) Ry(150) (w = -0.18)."""
    R = (rotations.matrix_from_axis_angle((0, 0, 1), np.pi / 2)
         @ rotations.matrix_from_axis_angle((0, 1, 0), np.radians(150.0)))
    program = generate(cell_with(R))
    text = abb_rapid.export(program, {})[0][1]
    quats = [np.array(line.split("],[")[1].split(","), dtype=float)
             for line in text.splitlines() if "CONST robtarget" in line]
    assert len(quats) > 5
    dots = [float(np.dot(a, b)) for a, b in itertools.pairwise(quats)]
    assert min(dots) > 0.0


def test_slerp_between_opposite_orientations_does_not_depend_on_noise():
    """A half turn about Z between two half turns about X and Y: both ways
    are equally short; the canonical sign picks one, not the noise."""
    R0 = half_turn_exact((1.0, 0.0, 0.0))
    R1 = half_turn_exact((0.0, 1.0, 0.0))
    mids = set()
    for A, B in itertools.product(noisy_versions(R0), noisy_versions(R1)):
        q = rotations.quaternion_slerp(rotations.quaternion_from_matrix(A),
                                       rotations.quaternion_from_matrix(B), 0.5)
        mids.add(tuple(np.round(rotations.matrix_from_quaternion(q), 9).ravel() + 0.0))
    assert len(mids) == 1


@pytest.mark.parametrize("robot", ["ABB_IRB2400", "KUKA_KR16", "MOTOMAN_HP6"])
def test_configuration_data_ignores_joint_noise(robot):
    """A joint at 0 (or 90) up to noise is read as exactly there: the ABB quadrant,
    KUKA turn bits, Fanuc flip and Motoman RCONF do not depend on the noise's sign."""
    from CadRobotWB.robots.kinematics import models
    from CadRobotWB.robots.motion import configuration
    model = models.model(robot)
    readers = (configuration.abb_confdata, configuration.kuka_status_turn,
               configuration.fanuc_config, configuration.motoman_rconf)
    for base in ([0.0, 10.0, 20.0, 0.0, 30.0, 0.0], [0.0, 10.0, 20.0, 90.0, 0.0, -90.0]):
        q = np.array(base)
        for reader in readers:
            values = {reader(q + noise, model) for noise in
                      (np.zeros(6), np.full(6, 1e-13), np.full(6, -1e-13), -q * 1e-16)}
            assert len(values) == 1, (reader.__name__, base, values)


def test_joints_on_the_180_degree_seam_and_on_a_limit_ignore_noise():
    """A wrist at ±180 (HP6 J4 on a half-turned tool) reads +180 and is within J4's ±180."""
    from CadRobotWB.robots.kinematics import models, opw
    noise = np.array([-1e-13, -1e-15, 0.0, 1e-15, 1e-13])
    for seam in (-180.0, 180.0):
        np.testing.assert_allclose(opw.wrap_deg(seam + noise), 180.0, atol=1e-12)
    assert opw.wrap_deg(-180.0 + 1e-6) == pytest.approx(-180.0 + 1e-6)   # not noise: kept
    hp6 = models.model("MOTOMAN_HP6")
    q = np.zeros((len(noise), 6))
    q[:, 1], q[:, 3] = 10.0, 180.0 + noise                               # J4 on its limit
    assert hp6.within_limits(q).all()
    q[:, 3] = 180.0 + 1e-6                                                # past it: refused
    assert not hp6.within_limits(q).any()


@pytest.mark.parametrize("robot", ["ABB_IRB2400", "KUKA_KR16", "MOTOMAN_HP6"])
def test_solved_half_turns_give_the_same_program_whatever_the_noise(robot):
    """With the joints solved, as an export does: the HP6 meets a half-turned tool with
    J4 and J6 at ±180 from a start of 0, where noise once chose the turn (and J4 = -180
    - 1e-14 fell outside its ±180 limit)."""
    from CadRobotWB.robots.kinematics import models
    from CadRobotWB.robots.motion import configuration
    model = models.model(robot)

    def solved_texts(R_u_t):
        cell = cell_with(R_u_t)
        cell.robot = robot
        program = generate(cell)
        configuration.solve_program(program, model)
        return {post.NAME: "".join(text for _, text in post.export(program, dict(OPTIONS)))
                for post in POSTS if post is not ur_script}      # UR posts need a UR arm

    for axis in half_turn_axes():
        versions = noisy_versions(half_turn_exact(axis))
        expected = solved_texts(versions[0])
        for i, R in enumerate(versions[1:], start=1):
            got = solved_texts(R)
            for name in expected:
                assert got[name] == expected[name], f"{name}, axis {axis}: variant {i} differs"
