"""Link frames and link solids (robots/checks/links.py): frames consistent with the
forward kinematics of every catalog robot, each frame moved by its own joint
only, solids watertight and where the IRB 2400's numbers put them, the tool
solid's clearance rule."""

import numpy as np
import pytest

from CadRobotWB.robots.catalog import catalog
from CadRobotWB.robots.checks import links
from CadRobotWB.robots.kinematics import models
from robot_sample import hand_written_names, sample_names

ALL_ROBOTS = sample_names()
# The simple solids' geometry tests: robots without URDF meshes or frames.
SIMPLE = hand_written_names()
OPW_LIKE = [name for name in SIMPLE if catalog.get(name).opw is not None]


def random_joints(robot, n, seed):
    rng = np.random.default_rng(seed)
    low = np.maximum(robot.joint_min_deg, -180.0)
    high = np.minimum(robot.joint_max_deg, 180.0)
    return rng.uniform(low, high, (n, 6))


def invert(T):
    Ti = np.zeros_like(T)
    Rt = np.swapaxes(T[..., :3, :3], -1, -2)
    Ti[..., :3, :3] = Rt
    Ti[..., :3, 3] = -(Rt @ T[..., :3, 3:4])[..., 0]
    Ti[..., 3, 3] = 1.0
    return Ti


def inside_convex(mesh, points, tol=1e-6):
    """(M,) bool: points (M, 3) inside the convex `mesh` (all face planes)."""
    points = np.atleast_2d(points)
    offsets = np.einsum("fk,mfk->mf", mesh.face_normals,
                        points[:, None, :] - mesh.triangles[None, :, 0, :])
    return (offsets <= tol).all(axis=1)


def placed_parts(name, q_deg, body):
    """The convex pieces of `body` (index) placed in {R} at joint values q_deg (6,)."""
    T = links.link_frames(name, np.asarray(q_deg, dtype=float))[body]
    return [piece.copy().apply_transform(T) for piece in links.link_parts(name)[body]]


def inside_body(name, q_deg, body, points):
    pieces = placed_parts(name, q_deg, body)
    return np.any([inside_convex(piece, points) for piece in pieces], axis=0)


# --- frames ------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ALL_ROBOTS)
def test_last_frame_is_the_flange_of_fk(name):
    robot = models.model(name)
    q = random_joints(robot, 200, seed=3)
    q[0] = 0.0
    frames = links.link_frames(robot, q)
    assert frames.shape == (200, 7, 4, 4)
    np.testing.assert_allclose(frames[:, 0], np.broadcast_to(np.eye(4), (200, 4, 4)))
    np.testing.assert_allclose(frames[:, 6], robot.fk(q), rtol=0, atol=1e-9)
    # Every frame is a rigid transform.
    R = frames[..., :3, :3]
    np.testing.assert_allclose(R @ np.swapaxes(R, -1, -2),
                               np.broadcast_to(np.eye(3), R.shape), atol=1e-12)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=1e-12)
    np.testing.assert_allclose(frames[..., 3, :], np.broadcast_to([0, 0, 0, 1.0], (200, 7, 4)))
    # One pose in, one pose out; names and specs work as well as models.
    np.testing.assert_allclose(links.link_frames(name, q[5]), frames[5], atol=1e-12)
    np.testing.assert_allclose(links.link_frames(catalog.get(name), q[:3]), frames[:3], atol=1e-12)


@pytest.mark.parametrize("name", ALL_ROBOTS)
def test_each_frame_moves_with_its_own_joint_only(name):
    """inv(F[j-1]) F[j] depends on q_j alone: the link between joints is rigid."""
    robot = models.model(name)
    q = random_joints(robot, 50, seed=4)
    others = random_joints(robot, 50, seed=5)
    F = links.link_frames(robot, q)
    for j in range(1, 7):
        q_other = others.copy()
        q_other[:, j - 1] = q[:, j - 1]
        F_other = links.link_frames(robot, q_other)
        np.testing.assert_allclose(invert(F[:, j - 1]) @ F[:, j],
                                   invert(F_other[:, j - 1]) @ F_other[:, j], atol=1e-9)


@pytest.mark.parametrize("name", OPW_LIKE)
def test_opw_joint_geometry(name):
    """J1 vertical through the base origin, the wrist centre on frames 4 and 5,
    J2 at (a1, b, c1) turned by J1."""
    robot = models.model(name)
    p = robot.spec.opw
    q = random_joints(robot, 100, seed=6)
    F = links.link_frames(robot, q)
    T = robot.fk(q)
    centre = T[:, :3, 3] - p.c4 * T[:, :3, 2]
    np.testing.assert_allclose(F[:, 4, :3, 3], centre, atol=1e-9)
    np.testing.assert_allclose(F[:, 5, :3, 3], centre, atol=1e-9)
    F_opw = links.opw_link_frames(p, q)
    np.testing.assert_allclose(F_opw[:, 1, :3, 2], np.tile([0, 0, 1.0], (100, 1)), atol=1e-12)
    np.testing.assert_allclose(F_opw[:, 1, :3, 3], 0.0, atol=1e-12)
    theta1 = np.radians(q[:, 0]) * p.signs[0] - np.radians(p.offsets_deg[0])
    j2 = np.stack([p.a1 * np.cos(theta1) - p.b * np.sin(theta1),
                   p.a1 * np.sin(theta1) + p.b * np.cos(theta1), np.full(100, p.c1)], axis=1)
    np.testing.assert_allclose(F_opw[:, 2, :3, 3], j2, atol=1e-9)
    np.testing.assert_allclose(F_opw[:, 6], T, atol=1e-9)


def test_kr16_dh_frames_move_the_bodies_like_its_opw_chain():
    """The KR16's DH frames and its equivalent OPW chain describe the same bodies:
    each body's motion from q = 0 is the same in both."""
    robot = models.model("KUKA_KR16")
    q = random_joints(robot, 50, seed=7)
    F_dh, F_dh0 = links.link_frames(robot, q), links.link_frames(robot, np.zeros(6))
    F_opw = links.opw_link_frames(robot.spec.opw, q)
    F_opw0 = links.opw_link_frames(robot.spec.opw, np.zeros((1, 6)))[0]
    np.testing.assert_allclose(F_dh @ invert(F_dh0), F_opw @ invert(F_opw0), atol=1e-9)


def test_bad_input():
    with pytest.raises(ValueError):
        links.link_frames("ABB_IRB2400", np.zeros((3, 5)))
    with pytest.raises(TypeError):
        links.link_frames(42, np.zeros(6))


# --- solids ------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ALL_ROBOTS)
def test_solids_are_watertight_convex_pieces(name):
    solids = links.link_solids(name)
    parts = links.link_parts(name)
    assert len(solids) == len(parts) == 7 == len(links.LINK_NAMES)
    for solid, pieces in zip(solids, parts):
        assert solid.is_watertight and solid.is_volume
        assert all(piece.is_watertight and piece.is_convex for piece in pieces)
        assert len(solid.faces) == sum(len(piece.faces) for piece in pieces)


@pytest.mark.parametrize("name", SIMPLE)
def test_solids_stand_on_the_floor_at_zero(name):
    """At q = 0 nothing goes below the base plate, and the base starts on it."""
    frames = links.link_frames(name, np.zeros(6))
    lowest = [solid.copy().apply_transform(T).bounds[0, 2]
              for solid, T in zip(links.link_solids(name), frames)]
    assert lowest[0] == pytest.approx(0.0, abs=1e-9)
    assert min(lowest) >= -1e-9


@pytest.mark.parametrize("name", OPW_LIKE)
def test_solids_follow_the_joints(name):
    """At random poses, the joint points of the OPW chain lie inside the right bodies."""
    robot = models.model(name)
    p = robot.spec.opw
    for q in random_joints(robot, 5, seed=8):
        F = links.opw_link_frames(p, q[None])[0]
        shoulder, elbow, wrist = F[2, :3, 3], F[3, :3, 3], F[4, :3, 3]
        flange_inner = F[6, :3, 3] - 1.0 * F[6, :3, 2]       # 1 mm behind the flange face
        assert inside_body(name, q, 1, shoulder)[0]           # the J2 housing on the turret
        assert inside_body(name, q, 2, 0.5 * (shoulder + elbow))[0]
        assert inside_body(name, q, 3, elbow)[0]
        assert inside_body(name, q, 5, wrist)[0]
        assert inside_body(name, q, 6, flange_inner)[0]
        assert not inside_body(name, q, 6, F[6, :3, 3] + 1.0 * F[6, :3, 2])[0]


def test_ur5e_solids_follow_the_dh_frames():
    robot = models.model("UR5E")
    for q in random_joints(robot, 5, seed=9):
        F = links.link_frames(robot, q)
        for body in range(1, 6):
            assert inside_body("UR5E", q, body, F[body, :3, 3])[0], links.LINK_NAMES[body]
        assert inside_body("UR5E", q, 6, F[6, :3, 3] - F[6, :3, 2])[0]


def test_irb2400_solids_at_zero_where_the_reference_numbers_put_them():
    """ABB IRB 2400/10 (REFERENCE.md): a1 = 100, c1 = 615, c2 = 705, a2 = -135,
    c3 = 755, c4 = 85 mm; at q = 0 the upper arm is vertical, the forearm
    horizontal, the flange at (940, 0, 1455) facing +X.  Hand-derived points:
    J2 (100, 0, 615), elbow J3 (100, 0, 1320), forearm axis z = 1320 + 135 =
    1455 from x = 100 to the wrist centre (855, 0, 1455)."""
    name, q0 = "ABB_IRB2400", np.zeros(6)
    solids = [s.copy().apply_transform(T)
              for s, T in zip(links.link_solids(name), links.link_frames(name, q0))]

    flange = solids[6]
    centre = 0.5 * (flange.bounds[0] + flange.bounds[1])
    np.testing.assert_allclose(flange.bounds[1, 0], 940.0, atol=1e-9)   # the flange face
    np.testing.assert_allclose(centre[1:], [0.0, 1455.0], atol=1e-9)
    assert 5.0 <= 940.0 - flange.bounds[0, 0] <= 20.0                   # a disc
    assert 30.0 <= flange.bounds[1, 1] <= 60.0                          # radius
    assert inside_body(name, q0, 6, [935.0, 0.0, 1455.0])[0]

    assert inside_body(name, q0, 0, [0.0, 0.0, 100.0])[0]                # base
    assert inside_body(name, q0, 1, [100.0, 0.0, 615.0])[0]              # J2 on the turret
    assert inside_body(name, q0, 1, [0.0, 0.0, 400.0])[0]
    assert inside_body(name, q0, 2, [100.0, 0.0, 967.5])[0]              # upper arm middle
    assert inside_body(name, q0, 3, [100.0, 0.0, 1320.0])[0]             # elbow
    assert inside_body(name, q0, 3, [100.0, 0.0, 1455.0])[0]             # forearm start
    assert inside_body(name, q0, 5, [855.0, 0.0, 1455.0])[0]             # wrist centre

    # The forearm fills the axis from the elbow to the wrist centre (link 3 then the
    # link 4 tube), and is 50-100 mm thick, not more.
    axis = np.column_stack([np.linspace(110.0, 740.0, 40), np.zeros(40), np.full(40, 1455.0)])
    forearm = inside_body(name, q0, 3, axis) | inside_body(name, q0, 4, axis)
    assert forearm.all()
    for offset in (50.0, -50.0):
        beside = axis + [0.0, 0.0, offset]
        assert (inside_body(name, q0, 3, beside) | inside_body(name, q0, 4, beside)).all()
    far = axis + [0.0, 0.0, 100.0]
    assert not (inside_body(name, q0, 3, far) | inside_body(name, q0, 4, far)).any()
    # Link 4 is the wrist fork: the flange and tool swing between its prongs.
    assert not inside_body(name, q0, 4, [855.0 - 60.0, 0.0, 1455.0])[0]
    assert inside_body(name, q0, 4, [855.0, 65.0, 1455.0])[0]

    # Radii sized for a 1.5 m robot: 60-130 mm.
    radius = {i: 0.5 * (s.bounds[1, 1] - s.bounds[0, 1]) for i, s in enumerate(solids)}
    assert 100.0 <= radius[0] <= 130.0
    assert 60.0 <= radius[2] <= 120.0
    # The whole robot stays in the box the reference pose spans.
    every = np.vstack([s.vertices for s in solids])
    assert every[:, 0].max() == pytest.approx(940.0)
    assert every[:, 2].min() >= 0.0 and every[:, 2].max() < 1455.0 + 100.0


# --- tool ----------------------------------------------------------------------------------------

def transform(R=None, p=(0.0, 0.0, 0.0)):
    T = np.eye(4)
    if R is not None:
        T[:3, :3] = R
    T[:3, 3] = p
    return T


@pytest.mark.parametrize("tcp", [(0.0, 0.0, 250.0), (0.0, 80.0, 300.0), (40.0, -30.0, 60.0)])
def test_tool_solid_clearance_rule(tcp):
    tool = links.tool_solid(transform(p=tcp), radius_mm=20.0, clearance_mm=15.0)
    assert tool.is_watertight and tool.is_convex
    tcp = np.asarray(tcp)
    distances = np.linalg.norm(tool.vertices - tcp, axis=1)
    assert distances.min() == pytest.approx(15.0, abs=1e-9)     # the tip, 15 mm short of the TCP
    # It starts on the flange face and follows the flange-to-TCP line.
    u = tcp / np.linalg.norm(tcp)
    along = tool.vertices @ u
    assert along.min() == pytest.approx(0.0, abs=1e-9)
    assert along.max() == pytest.approx(np.linalg.norm(tcp) - 15.0)
    off_axis = np.linalg.norm(tool.vertices - np.outer(along, u), axis=1)
    assert off_axis.max() == pytest.approx(20.0)


def test_tool_solid_too_short_is_none():
    assert links.tool_solid(transform(p=(0.0, 0.0, 10.0)), clearance_mm=15.0) is None
    assert links.tool_solid(np.eye(4)) is None
