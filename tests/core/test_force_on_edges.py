"""The ball tool on a convex edge (issue 14, FreeCAD's Drilling_1): the inside of a
solid at an acute edge, the normal force held off the tool axis, the drawn contact.

Every expected number is derived by hand in the test's docstring from the
geometry (a ball of radius r, a linear contact law F = k p for a pressing p).
"""

import math

import numpy as np
import pytest
import trimesh

from CadRobotWB.core import program as ir
from CadRobotWB.core.trajectory import tcp_trajectory
from CadRobotWB.sensors.contact import BallContact, FEATURE_EDGE, MeshSurface
from CadRobotWB.sensors.force_following import drawn_contact_mm, simulate_force_following
from CadRobotWB.sensors.reality import Reality

R = 5.0
K = 20.0
F_SET = 20.0
SPEED = 10.0
DT = 0.005


def wedge(angle_deg, length=200.0, size=30.0):
    """A prism along X whose edge at y = z = 0 has `angle_deg` of material: its top
    face z = 0 runs to +Y, its other face leaves the edge at `angle_deg` below it."""
    a = math.radians(angle_deg)
    section = [(0.0, 0.0), (size, 0.0), (size * math.cos(a), -size * math.sin(a))]
    points = [(x, y, z) for x in (-length / 2, length / 2) for y, z in section]
    return trimesh.convex.convex_hull(np.array(points))


def edge_box():
    """A block x -100..300, y 0..50, z -50..0: the edge along X at y = z = 0 is 90 degrees."""
    return trimesh.creation.box([400.0, 50.0, 50.0],
                                transform=trimesh.transformations.translation_matrix([100, 25, -25]))


def on_edge(x):
    """TCP on the edge y = z = 0 at `x`, tool +Z along the bisector into the block."""
    z_axis = np.array([0.0, 1.0, -1.0]) / math.sqrt(2.0)
    x_axis = np.array([1.0, 0.0, 0.0])
    T = np.eye(4)
    T[:3, 0], T[:3, 1], T[:3, 2], T[:3, 3] = x_axis, np.cross(z_axis, x_axis), z_axis, (x, 0, 0)
    return T


def edge_trajectory(x0=0.0, x1=200.0):
    frame = ir.WorkFrame("B", T_r_b=np.eye(4), T_u_b=np.eye(4))
    moves = [ir.Move(ir.JOINT, ir.Target("a", on_edge(x0)), 100.0, 0.0, "B"),
             ir.Move(ir.LINEAR, ir.Target("b", on_edge(x1)), SPEED, 0.0, "B")]
    program = ir.Program("Edge", "MOTOMAN_HP6", ir.ToolData("ball", np.eye(4)), {"B": frame},
                         [ir.ProgramPath("p", "p", moves)])
    return tcp_trajectory(program, DT, first_move=1)


def test_a_ball_pressed_into_a_square_edge_along_the_bisector_reads_k_times_the_depth():
    """The TCP on the edge, moved d along the bisector: the ball's centre is r - d
    from the edge line, so it is pressed d: F = k d, along the tool axis."""
    ball, surface = BallContact(R, K), MeshSurface(edge_box())
    for d in (0.0, 0.5, 1.0, 2.5):
        T = on_edge(50.0)
        T[:3, 3] += d * T[:3, 2]
        gap, normal = ball.gap_mm(surface, T)
        assert gap == pytest.approx(-d, abs=1e-9)
        np.testing.assert_allclose(normal, -T[:3, 2], atol=1e-9)        # from the edge to the centre
        wrench = ball.wrench(T, normal, ball.normal_force_n(gap))
        np.testing.assert_allclose(wrench[:3], [0.0, 0.0, K * d], atol=1e-9)


@pytest.mark.parametrize("phi_deg", [92.0, 100.0, 106.0, 120.0, 150.0, 180.0, 195.0])
def test_a_ball_above_an_acute_edge_is_outside(phi_deg):
    """Drilling_1's top face meets an overhanging wall at 73 degrees. A centre at
    angle phi (from the top face's direction +Y towards +Z, about the edge) has the
    edge as its closest point for 90 <= phi <= 197 degrees (it is behind neither
    face's edge-normal plane there) and lies outside, at its distance from the edge
    line: gap = |d| - r. The wall's own normal (-sin 73, -cos 73) does not say so:
    for phi < 107 degrees the centre lies behind the wall's plane (checked)."""
    mesh = wedge(73.0)
    surface = MeshSurface(mesh)
    distance = 3.0
    phi = math.radians(phi_deg)
    centre = np.array([10.0, distance * math.cos(phi), distance * math.sin(phi)])
    wall_normal = np.array([0.0, -math.sin(math.radians(73.0)), -math.cos(math.radians(73.0))])
    if phi_deg < 107.0:
        assert centre @ wall_normal < 0                                   # behind the wall's plane
    T = np.eye(4)
    T[:3, 2] = [0.0, 0.0, -1.0]
    T[:3, 3] = centre + R * T[:3, 2]
    gap, normal = BallContact(R, K).gap_mm(surface, T)
    assert gap == pytest.approx(distance - R, abs=1e-9)
    np.testing.assert_allclose(normal, (centre - [10.0, 0.0, 0.0]) / distance, atol=1e-9)
    closest, faces, _, features = surface.nearest_features(centre[None])
    assert FEATURE_EDGE <= features[0] < FEATURE_EDGE + 3
    assert surface.outward(centre[None], closest, faces, features)[0]
    # inside, just under the edge on the bisector: inside for every feature
    inside = np.array([10.0, 0.5, -0.3])
    closest, faces, _, features = surface.nearest_features(inside[None])
    assert not surface.outward(inside[None], closest, faces, features)[0]


def test_the_drawn_contact_of_a_tilted_ball_on_a_plane():
    """Tool axis 30 degrees off the plane's normal, TCP on the plane: the centre is
    r cos 30 above it, so the ball cuts in by r (1 - cos 30); backing off along
    the axis by r (1 - cos 30) / cos 30 = 0.7735 mm puts it just on the plane."""
    plane = trimesh.creation.box([200.0, 200.0, 20.0],
                                 transform=trimesh.transformations.translation_matrix([0, 0, -10]))
    tilt = math.radians(30.0)
    tool_z = np.array([[math.sin(tilt), 0.0, -math.cos(tilt)]])
    offsets = drawn_contact_mm(BallContact(R, K), MeshSurface(plane), np.zeros((1, 3)), tool_z, 15.0)
    expected = -R * (1.0 - math.cos(tilt)) / math.cos(tilt)
    assert expected == pytest.approx(-0.7735, abs=1e-4)
    assert offsets[0] == pytest.approx(expected, abs=1e-9)


def edge_run(shift_mm, follow):
    """A 200 mm pass along the block's edge, the real block moved `shift_mm` along +Y
    (away from the ball, across the edge), PI, no noise."""
    T = trimesh.transformations.translation_matrix([0.0, shift_mm, 0.0])
    real = edge_box()
    real.apply_transform(T)
    reality = Reality(T_u_dev=T, force_noise_n=0.0)
    return simulate_force_following(edge_trajectory(), real, reality, force_set_n=F_SET,
                                    stiffness_n_mm=K, radius_mm=R, controller="pi", follow=follow,
                                    drawn_mesh=edge_box())


def edge_contact(shift_mm, pressing_mm):
    """Where the ball sits when its centre, on the bisector, is r - p from the edge
    moved s across: with u = (r - delta) / sqrt 2 the centre is (-u - s, u) from the
    real edge (y, z), so 2 u^2 + 2 s u + s^2 = (r - p)^2. Returns cos(theta), theta
    between the contact normal (-(u + s), u) / (r - p) and the tool axis reversed."""
    s, q = shift_mm, R - pressing_mm
    u = (-2 * s + math.sqrt(4 * s * s - 8 * (s * s - q * q))) / 4
    normal = np.array([-(u + s), u]) / q
    return float(normal @ (np.array([-1.0, 1.0]) / math.sqrt(2.0)))


def test_following_the_normal_holds_the_normal_force_on_an_edge_off_the_axis():
    """Block moved 3 mm across the edge: holding |F| = 20 N presses p = 1 mm, the
    contact normal 32 degrees off the axis, so Fz = 20 cos(theta) = 16.96 N."""
    cos_theta = edge_contact(3.0, F_SET / K)
    assert cos_theta == pytest.approx(0.8478, abs=1e-4)
    run = edge_run(3.0, "normal")
    assert not run.aborted, run.reason
    late = run.time_s > run.time_s[-1] - 3.0
    force = np.linalg.norm(run.force_n[late, :3], axis=1)
    np.testing.assert_allclose(force, F_SET, atol=0.01)
    np.testing.assert_allclose(run.force_n[late, 2], F_SET * cos_theta, atol=0.01)
    assert run.metrics["follow"] == "normal" and run.metrics["drawn_contact_mm"] < 1e-9


def test_holding_fz_on_that_edge_presses_harder():
    """Holding Fz = 20 N instead: k p cos(theta(p)) = 20 with theta from the same
    geometry; solved by bisection on p, |F| = k p > 20 N (23.3 N)."""
    lo, hi = 0.5, 3.0
    for _ in range(60):
        p = (lo + hi) / 2
        lo, hi = (p, hi) if K * p * edge_contact(3.0, p) < F_SET else (lo, p)
    expected = K * (lo + hi) / 2
    run = edge_run(3.0, "tool_axis")
    late = run.time_s > run.time_s[-1] - 3.0
    np.testing.assert_allclose(run.force_n[late, 2], F_SET, atol=0.01)
    np.testing.assert_allclose(np.linalg.norm(run.force_n[late, :3], axis=1), expected, atol=0.02)
    assert expected > 23.0
