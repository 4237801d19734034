"""The ball tool against the real surface (sensors/contact.py): gap, force, wrench, noise."""

import numpy as np
import pytest
import trimesh
from trimesh.triangles import closest_point as closest_point_on_triangles

from CadRobotWB.errors import InputError
from CadRobotWB.sensors.contact import (BallContact, ForceTorqueSensor, MeshSurface,
                                        RoughnessProfile)
from CadRobotWB.sensors.reality import Reality

RADIUS = 5.0
K = 20.0


def plate(size=200.0, tilt_deg=0.0):
    """A square sheet in z = 0 (two triangles), tilted about Y by `tilt_deg`."""
    h = size / 2
    mesh = trimesh.Trimesh([[-h, -h, 0], [h, -h, 0], [h, h, 0], [-h, h, 0]], [[0, 1, 2], [0, 2, 3]])
    mesh.apply_transform(trimesh.transformations.rotation_matrix(np.radians(tilt_deg), [0, 1, 0]))
    return mesh


def tool_down(x=0.0, y=0.0, z=0.0):
    """TCP at (x, y, z) with tool +Z pointing down (-Z of {U}), into a plate below."""
    T = np.diag([1.0, -1.0, -1.0, 1.0])
    T[:3, 3] = (x, y, z)
    return T


@pytest.mark.parametrize("height", [3.0, 0.0, -0.5, -2.0])
def test_gap_on_a_plate_is_the_tcp_height(height):
    ball = BallContact(RADIUS, K)
    gap, normal = ball.gap_mm(MeshSurface(plate()), tool_down(10, 5, height))
    assert gap == pytest.approx(height, abs=1e-12)
    np.testing.assert_allclose(normal, [0, 0, 1], atol=1e-12)
    assert ball.normal_force_n(gap) == pytest.approx(max(0.0, -K * height))


def test_roughness_raises_the_surface():
    ball = BallContact(RADIUS, K)
    gap, _ = ball.gap_mm(MeshSurface(plate()), tool_down(z=0.0), roughness_mm=0.1)
    assert gap == pytest.approx(-0.1)


def test_sheet_normals_either_way_give_the_same_gap():
    flipped = plate()
    flipped.invert()
    ball = BallContact(RADIUS, K)
    for mesh in (plate(), flipped):
        gap, normal = ball.gap_mm(MeshSurface(mesh), tool_down(z=-1.0))
        assert gap == pytest.approx(-1.0) and normal[2] == pytest.approx(1.0)


def test_a_solid_uses_its_own_outside():
    box = trimesh.creation.box([100, 100, 20])          # top face at z = 10
    ball = BallContact(RADIUS, K)
    assert ball.gap_mm(MeshSurface(box), tool_down(z=12.0))[0] == pytest.approx(2.0)
    assert ball.gap_mm(MeshSurface(box), tool_down(z=8.0))[0] == pytest.approx(-2.0)
    # the centre itself inside the solid (pressed in deeper than the radius)
    assert ball.gap_mm(MeshSurface(box), tool_down(z=3.0))[0] == pytest.approx(-7.0)


def test_gap_on_a_cylinder_matches_the_circle():
    R = 100.0
    cylinder = trimesh.creation.cylinder(radius=R, height=50.0, sections=720)   # axis Z
    ball = BallContact(RADIUS, K)
    surface = MeshSurface(cylinder)
    for angle in np.radians([0.3, 17.0, 123.4]):
        radial = np.array([np.cos(angle), np.sin(angle), 0.0])
        for depth in (1.0, -0.5):
            T = np.eye(4)
            T[:3, 2] = -radial                                       # tool +Z towards the axis
            T[:3, 0] = [0, 0, 1]
            T[:3, 1] = np.cross(T[:3, 2], T[:3, 0])
            T[:3, 3] = (R + depth) * radial                          # TCP `depth` outside
            gap, normal = ball.gap_mm(surface, T)
            sag = R * (1 - np.cos(np.pi / 720))                      # facets lie inside the circle
            assert gap == pytest.approx(depth, abs=sag + 1e-9)
            np.testing.assert_allclose(normal, radial, atol=0.01)


def test_nearest_is_exact_against_all_triangles():
    mesh = trimesh.creation.icosphere(subdivisions=3, radius=40.0)
    mesh.vertices *= [1.0, 0.6, 1.4]                                 # uneven triangles
    surface = MeshSurface(mesh)
    points = np.random.default_rng(3).uniform(-80, 80, (50, 3))
    for p in points:
        every = closest_point_on_triangles(mesh.triangles, np.tile(p, (len(mesh.faces), 1)))
        expected = np.linalg.norm(every - p, axis=1).min()
        assert surface.nearest(p)[2] == pytest.approx(expected, abs=1e-9)


def test_force_is_a_spring_with_damping_and_never_pulls():
    ball = BallContact(RADIUS, K, damping_n_s_mm=0.5)
    assert ball.normal_force_n(-1.0, gap_rate_mm_s=0.0) == pytest.approx(20.0)
    assert ball.normal_force_n(-1.0, gap_rate_mm_s=-4.0) == pytest.approx(22.0)   # pressing in
    assert ball.normal_force_n(-1.0, gap_rate_mm_s=100.0) == 0.0                 # leaving fast
    assert ball.normal_force_n(0.5) == 0.0


def test_wrench_pressing_along_the_tool_axis_is_plus_fz():
    ball = BallContact(RADIUS, K)
    T = tool_down(z=-1.0)
    gap, normal = ball.gap_mm(MeshSurface(plate()), T)
    wrench = ball.wrench(T, normal, ball.normal_force_n(gap))
    np.testing.assert_allclose(wrench, [0, 0, 20.0, 0, 0, 0], atol=1e-12)


def test_wrench_on_a_tilted_surface_acts_through_the_ball_centre():
    ball = BallContact(RADIUS, K)
    T = tool_down(z=0.0)
    gap, normal = ball.gap_mm(MeshSurface(plate(tilt_deg=20.0)), T)
    force = ball.normal_force_n(gap)
    assert force > 0
    wrench = ball.wrench(T, normal, force)
    expected_force_t = T[:3, :3].T @ (-force * normal)
    np.testing.assert_allclose(wrench[:3], expected_force_t, atol=1e-12)
    assert abs(wrench[0]) > 0.1 * force                                   # tilted: an Fx too
    centre_t = np.array([0.0, 0.0, -RADIUS])                  # the ball centre in the tool frame
    np.testing.assert_allclose(wrench[3:], np.cross(centre_t, wrench[:3]) / 1000.0, atol=1e-12)


def test_roughness_has_its_rms_and_repeats_with_its_seed():
    s = np.linspace(0.0, 20000.0, 200001)
    rough = RoughnessProfile(0.05, 2.0, seed=4)
    heights = rough.height_mm(s)
    assert np.sqrt(np.mean(heights ** 2)) == pytest.approx(0.05, rel=0.1)
    np.testing.assert_array_equal(heights, RoughnessProfile(0.05, 2.0, seed=4).height_mm(s))
    assert not np.allclose(heights, RoughnessProfile(0.05, 2.0, seed=5).height_mm(s))
    assert RoughnessProfile(0.0, 2.0).height_mm(3.0) == 0.0
    reality = Reality(roughness_mm=0.05, roughness_wavelength_mm=2.0, seed=4)
    from_reality = RoughnessProfile.from_reality(reality)
    np.testing.assert_array_equal(from_reality.height_mm(s[:100]), heights[:100])


def test_roughness_peaks_are_about_a_wavelength_apart():
    s = np.linspace(0.0, 2000.0, 200001)
    heights = RoughnessProfile(0.05, 4.0, seed=1).height_mm(s)
    crossings = np.count_nonzero(np.diff(np.sign(heights)) > 0)      # one per period
    assert 2000.0 / 8.0 < crossings < 2000.0 / 2.0


def test_sensor_noise_has_its_rms_on_forces_only_and_repeats():
    wrench = np.array([0.0, 0.0, 20.0, 0.1, 0.2, 0.3])
    readings = np.array([ForceTorqueSensor(0.5, seed=2).read(wrench) for _ in range(1)])
    sensor = ForceTorqueSensor(0.5, seed=2)
    many = np.array([sensor.read(wrench) for _ in range(20000)])
    np.testing.assert_allclose(many[:, :3].std(axis=0), 0.5, rtol=0.05)
    np.testing.assert_allclose(many[:, :3].mean(axis=0), wrench[:3], atol=0.02)
    np.testing.assert_array_equal(many[:, 3:], np.tile(wrench[3:], (20000, 1)))
    np.testing.assert_array_equal(readings[0], many[0])
    np.testing.assert_array_equal(ForceTorqueSensor(0.0).read(wrench), wrench)


def test_bad_parameters_are_refused():
    with pytest.raises(InputError):
        BallContact(0.0, K)
    with pytest.raises(InputError):
        BallContact(RADIUS, -1.0)
    with pytest.raises(InputError):
        RoughnessProfile(0.1, 0.0)
    with pytest.raises(InputError):
        ForceTorqueSensor(-0.1)
