"""The contact computed for many steps at once (sensors/contact.py) is the contact of each.

Force following computes a control period's contacts together: the nearest
points of a cluster of ball centres, their gaps and forces, the wrenches
and the sensor noise. Each is checked here against an independent answer:
trimesh's closest point on every triangle, the wrench's definition, the
sensor's readings one after another.
"""

import numpy as np
import pytest
import trimesh
from trimesh.triangles import closest_point as closest_point_on_triangles

from CadRobotWB.sensors import contact
from CadRobotWB.sensors.contact import BallContact, ForceTorqueSensor, MeshSurface


def brute_force_nearest(mesh, points):
    """Distances (N,) from each point to the closest of all the mesh's triangles."""
    every = [closest_point_on_triangles(mesh.triangles, np.tile(p, (len(mesh.faces), 1)))
             for p in points]
    return np.array([np.linalg.norm(c - p, axis=1).min() for c, p in zip(every, points)])


def uneven_sphere():
    mesh = trimesh.creation.icosphere(subdivisions=3, radius=40.0)
    mesh.vertices *= [1.0, 0.6, 1.4]
    return mesh


def clustered_points(rng, n_clusters=4, per_cluster=25, spread_mm=1.5):
    """Points in tight groups (as a control period's ball centres are) and a few stray ones."""
    centres = rng.uniform(-70, 70, (n_clusters, 3))
    groups = [c + rng.uniform(-spread_mm, spread_mm, (per_cluster, 3)) for c in centres]
    return np.concatenate(groups + [rng.uniform(-90, 90, (7, 3))])


def test_nearest_points_of_clusters_match_every_triangle():
    mesh = uneven_sphere()
    surface = MeshSurface(mesh)
    points = clustered_points(np.random.default_rng(5))
    closest, faces, distances = surface.nearest_points(points)
    np.testing.assert_allclose(distances, brute_force_nearest(mesh, points), rtol=0, atol=1e-9)
    np.testing.assert_allclose(np.linalg.norm(closest - points, axis=1), distances, atol=1e-12)
    # the closest point lies on the face given
    on_face = closest_point_on_triangles(mesh.triangles[faces], closest)
    np.testing.assert_allclose(on_face, closest, atol=1e-9)


def test_nearest_points_one_by_one_are_the_same():
    surface = MeshSurface(uneven_sphere())
    points = clustered_points(np.random.default_rng(6), n_clusters=2, per_cluster=12)
    closest, _, distances = surface.nearest_points(points)
    for k, p in enumerate(points):
        one_closest, _, one_distance = surface.nearest(p)
        assert one_distance == pytest.approx(distances[k], abs=1e-12)
        np.testing.assert_allclose(one_closest, closest[k], atol=1e-9)


def test_points_far_apart_and_far_away_are_split_but_still_exact(monkeypatch):
    monkeypatch.setattr(contact, "MAX_PAIRS", 2000)         # 16 points x 1280 triangles: split
    mesh = uneven_sphere()
    surface = MeshSurface(mesh)
    points = np.random.default_rng(7).uniform(-400, 400, (16, 3))       # one cluster, spread out
    np.testing.assert_allclose(surface.nearest_points(points)[2],
                               brute_force_nearest(mesh, points), atol=1e-9)
    assert [len(a) for a in surface.nearest_points(np.zeros((0, 3)))] == [0, 0, 0]


def test_a_triangle_with_two_equal_corners_is_its_segment():
    # a sliver a = b on the segment (0, 0, 0) - (10, 0, 0), and a triangle far from it
    vertices = [[0, 0, 0], [0, 0, 0], [10, 0, 0], [0, 100, 0], [10, 100, 0], [0, 110, 0]]
    mesh = trimesh.Trimesh(vertices, [[0, 1, 2], [3, 4, 5]], process=False)
    surface = MeshSurface(mesh)
    points = np.array([[3.0, -2.0, 1.0], [-4.0, -1.0, 0.0], [12.0, -3.0, 0.5], [5.0, 5.0, 9.0]])
    closest, faces, distances = surface.nearest_points(points)
    assert faces.tolist() == [0, 0, 0, 0]
    np.testing.assert_allclose(closest, [[3, 0, 0], [0, 0, 0], [10, 0, 0], [5, 0, 0]], atol=1e-12)
    np.testing.assert_allclose(distances, brute_force_nearest(mesh, points), atol=1e-9)


def test_touching_balls_one_at_a_time_and_together():
    box = trimesh.creation.box([20, 20, 20])
    surface = MeshSurface(box)
    centres = np.array([[0, 0, 16.0], [0, 0, 14.0], [0, 0, 0.0], [40, 0, 0], [13, 13, 13]])
    expected = [surface.touches_ball(c, 5.0) for c in centres]
    assert expected == [False, True, True, False, False]
    assert surface.touches_balls(centres, 5.0).tolist() == expected


def random_rotations(rng, n):
    q = rng.normal(size=(n, 4))
    w, x, y, z = (q / np.linalg.norm(q, axis=1)[:, None]).T
    return np.stack([np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
                     np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
                     np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)],
                    axis=1)


def test_wrenches_are_the_force_at_the_contact_point_about_the_tcp():
    rng = np.random.default_rng(8)
    ball = BallContact(5.0, 20.0)
    R = random_rotations(rng, 20)
    normals = rng.normal(size=(20, 3))
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    forces = rng.uniform(0.0, 40.0, 20)
    tcp = rng.uniform(-500, 500, (20, 3))
    wrenches = ball.wrenches(R, normals, forces)
    for k in range(20):
        force_u = -forces[k] * normals[k]
        contact_u = tcp[k] - 5.0 * R[k][:, 2] - 5.0 * normals[k]        # ball centre, then r
        torque_u = np.cross(contact_u - tcp[k], force_u) / 1000.0       # N·m about the TCP
        np.testing.assert_allclose(wrenches[k, :3], R[k].T @ force_u, atol=1e-12)
        np.testing.assert_allclose(wrenches[k, 3:], R[k].T @ torque_u, atol=1e-12)


def test_gaps_and_forces_together_are_each_steps():
    mesh = trimesh.creation.cylinder(radius=100.0, height=50.0, sections=180)
    surface = MeshSurface(mesh)
    ball = BallContact(5.0, 20.0, damping_n_s_mm=0.5)
    angles = np.linspace(0.1, 0.4, 12)
    radial = np.stack([np.cos(angles), np.sin(angles), np.zeros(12)], axis=1)
    tcp = (100.0 + np.linspace(-1.0, 1.0, 12))[:, None] * radial
    rough = np.linspace(0.0, 0.05, 12)
    gaps, normals = ball.gaps_mm(surface, tcp, -radial, rough)
    rates = np.linspace(-3.0, 3.0, 12)
    forces = ball.normal_forces_n(gaps, rates)
    for k in range(12):
        T = np.eye(4)
        T[:3, 2], T[:3, 0] = -radial[k], [0, 0, 1]
        T[:3, 1] = np.cross(T[:3, 2], T[:3, 0])
        T[:3, 3] = tcp[k]
        gap, normal = ball.gap_mm(surface, T, rough[k])
        assert gap == pytest.approx(gaps[k], abs=1e-12)
        np.testing.assert_allclose(normal, normals[k], atol=1e-12)
        assert ball.normal_force_n(gap, rates[k]) == pytest.approx(forces[k], abs=1e-12)
    assert (forces[gaps >= 0] == 0).all() and (forces[gaps < -0.5] > 0).all()


def test_the_noise_of_many_readings_drawn_at_once_is_that_of_one_after_another():
    wrench = np.array([0.0, 0.0, 20.0, 0.1, 0.2, 0.3])
    one_by_one = ForceTorqueSensor(0.5, seed=2)
    readings = np.array([one_by_one.read(wrench) for _ in range(500)])
    noise = ForceTorqueSensor(0.5, seed=2).next_noise(500)
    np.testing.assert_array_equal(readings[:, :3], wrench[:3] + noise)
    np.testing.assert_array_equal(ForceTorqueSensor(0.0).next_noise(3), np.zeros((3, 3)))
