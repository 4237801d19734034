"""The virtual laser line: exact profiles of known geometry, occlusion, range, noise, real joints."""

import numpy as np
import pytest
import trimesh

from CadRobotWB.errors import InputError
from CadRobotWB.sensors.laser import LaserLineSensor, LaserScene, laser_frame
from CadRobotWB.sensors.seam_features import JointTemplate, extract_seam

DOWN = np.array([0.0, 0.0, -1.0])
ALONG_X = np.array([1.0, 0.0, 0.0])


def box(low, high):
    low, high = np.asarray(low, float), np.asarray(high, float)
    return trimesh.creation.box(high - low, trimesh.transformations.translation_matrix((low + high) / 2))


def prism(section_yz, x0=-50.0, x1=250.0):
    """A convex prism along X from a convex (y, z) cross-section."""
    section = np.asarray(section_yz, float)
    points = np.vstack([np.column_stack([np.full(len(section), x), section]) for x in (x0, x1)])
    return trimesh.convex.convex_hull(points)


def fan_y(sensor, depth_mm):
    """Where the fan's rays cross the plane z = depth in {S}: (E + z) tan(theta), by hand."""
    half = np.arctan(sensor.line_width_mm / 2 / sensor.emitter_mm)
    return (sensor.emitter_mm + depth_mm) * np.tan(np.linspace(-half, half, sensor.n_points))


def test_the_sensor_frame_is_right_handed_and_the_laser_plane_normal_to_the_travel():
    T = laser_frame([1, 2, 3], [2, 0, 0], [0, 0.2, -1])            # tool axis tilted along Y
    np.testing.assert_allclose(T[:3, :3].T @ T[:3, :3], np.eye(3), atol=1e-12)
    assert np.isclose(np.linalg.det(T[:3, :3]), 1.0)
    np.testing.assert_allclose(T[:3, 0], ALONG_X)
    np.testing.assert_allclose(T[:3, 3], [1, 2, 3])
    tool = np.array([0, 0.2, -1]) / np.linalg.norm([0, 0.2, -1])
    np.testing.assert_allclose(T[:3, 2], tool, atol=1e-12)          # already normal to X: kept


def test_a_flat_plate_gives_the_fan_geometry_exactly():
    plate = box((-50, -100, 0), (50, 100, 8))
    sensor = LaserLineSensor(noise_mm=0.0)
    T_u_s = laser_frame([0, 0, 11.0], ALONG_X, DOWN)                # origin 3 mm above the plate
    profile = sensor.profile(T_u_s, plate)
    assert profile.shape == (200, 2)
    np.testing.assert_allclose(profile[:, 1], 3.0, atol=1e-9)
    np.testing.assert_allclose(profile[:, 0], fan_y(sensor, 3.0), atol=1e-9)
    # 30 mm wide at the origin's depth
    at_origin = fan_y(sensor, 0.0)
    assert np.isclose(at_origin[-1] - at_origin[0], 30.0)


def test_misses_and_points_outside_the_depth_range_are_nan():
    sensor = LaserLineSensor(noise_mm=0.0, depth_range_mm=(-20.0, 20.0))
    narrow = box((-50, -2, 0), (50, 2, 8))                          # only the middle rays hit it
    profile = sensor.profile(laser_frame([0, 0, 8.0], ALONG_X, DOWN), narrow)
    hit = ~np.isnan(profile[:, 0])
    assert 0 < hit.sum() < 40
    assert np.all(np.abs(profile[hit, 0]) <= 2.0 + 1e-9)
    far = box((-50, -100, -30), (50, 100, -22))                     # top 30 mm below the origin
    assert np.isnan(sensor.profile(laser_frame([0, 0, 8.0], ALONG_X, DOWN), far)).all()


def test_a_foreign_object_occludes_the_line():
    plate = box((-50, -100, 0), (50, 100, 8))
    clamp = box((-5, -3, 8), (5, 3, 20))                            # 12 mm block on the plate
    sensor = LaserLineSensor(noise_mm=0.0)
    profile = sensor.profile(laser_frame([0, 0, 8.0], ALONG_X, DOWN), LaserScene([plate, clamp]))
    on_clamp = np.abs(profile[:, 1] + 12.0) < 1e-9
    assert on_clamp.any()
    np.testing.assert_allclose(profile[on_clamp, 0], fan_y(sensor, -12.0)[on_clamp], atol=1e-9)
    assert np.all(np.abs(profile[on_clamp, 0]) <= 3.0 + 1e-9)


def _ray_cast_brute_force(T_u_s, sensor, mesh):
    """Moller-Trumbore on every triangle: the first hit distance of each ray (independent check)."""
    R, o = T_u_s[:3, :3], T_u_s[:3, 3]
    origin = o + R @ np.array([0.0, 0.0, -sensor.emitter_mm])
    out = []
    for dy, dz in sensor.ray_directions:
        d = R @ np.array([0.0, dy, dz])
        best = np.inf
        for v0, v1, v2 in mesh.triangles:
            e1, e2 = v1 - v0, v2 - v0
            p = np.cross(d, e2)
            det = e1 @ p
            if abs(det) < 1e-12:
                continue
            s = origin - v0
            u = (s @ p) / det
            q = np.cross(s, e1)
            v = (d @ q) / det
            t = (e2 @ q) / det
            if u >= 0 and v >= 0 and u + v <= 1 and t > 0:
                best = min(best, t)
        out.append(best)
    return np.array(out)


def test_the_plane_section_caster_agrees_with_brute_force_ray_casting():
    sphere = trimesh.creation.icosphere(subdivisions=2, radius=12.0)
    sphere.apply_translation([3.0, 1.0, 5.0])
    T_u_s = laser_frame([0.0, 0.0, 20.0], [1.0, 0.3, 0.1], [0.1, -0.2, -1.0])    # oblique
    sensor = LaserLineSensor(n_points=60, noise_mm=0.0, depth_range_mm=(-90, 90))
    ours = sensor.ray_distances(LaserScene(sphere).section(T_u_s))
    theirs = _ray_cast_brute_force(T_u_s, sensor, sphere)
    assert np.isfinite(theirs).sum() > 20 and np.isinf(theirs).sum() > 5
    np.testing.assert_array_equal(np.isnan(ours), np.isinf(theirs))
    np.testing.assert_allclose(ours[np.isfinite(theirs)], theirs[np.isfinite(theirs)], atol=1e-9)


def test_noise_is_along_the_ray_with_the_reality_rms():
    plate = box((-50, -100, 0), (50, 100, 8))
    sensor = LaserLineSensor(n_points=2000, noise_mm=0.05)
    profile = sensor.profile(laser_frame([0, 0, 8.0], ALONG_X, DOWN), plate, np.random.default_rng(1))
    along_ray = profile[:, 1] / sensor.ray_directions[:, 1]          # the plate is at depth 0
    assert abs(np.std(along_ray) - 0.05) < 0.005
    assert abs(np.mean(along_ray)) < 0.005


def test_bad_sensor_settings_are_refused():
    with pytest.raises(InputError):
        LaserLineSensor(n_points=1)
    with pytest.raises(InputError):
        LaserLineSensor(emitter_mm=10.0, depth_range_mm=(-20.0, 20.0))
    with pytest.raises(InputError):
        LaserScene([])


# Real joints seen by the laser: the seam point comes out where the geometry puts it.

def butt_mesh(gap=1.5, thickness=8.0):
    g = gap / 2
    return trimesh.util.concatenate([box((-50, -100, 0), (250, -g, thickness)),
                                     box((-50, g, 0), (250, 100, thickness)),
                                     box((-50, -100, -20), (250, 100, 0))])          # the table


def fillet_mesh():
    """Base plate (top z = 8) and a web standing on it with its face at y = 0: root at (y 0, z 8)."""
    return trimesh.util.concatenate([box((-50, -100, 0), (250, 100, 8)), box((-50, 0, 8), (250, 8, 108))])


def lap_mesh(step=3.0):
    """Upper plate (step thick) on the lower one, its edge at y = 0: root at (y 0, z 8)."""
    return trimesh.util.concatenate([box((-50, -100, 0), (250, 100, 8)),
                                     box((-50, 0, 8), (250, 100, 8 + step))])


def v_groove_mesh(thickness=10.0, included_deg=60.0):
    """Two bevelled plates meeting at the root (y 0, z 0), no root face, no gap."""
    w = thickness * np.tan(np.radians(included_deg / 2))
    left = prism([(-100, 0), (0, 0), (-w, thickness), (-100, thickness)])
    right = prism([(0, 0), (100, 0), (100, thickness), (w, thickness)])
    return trimesh.util.concatenate([left, right])


TORCH_AT_45 = np.array([0, 1, -1]) / np.sqrt(2)       # into the corner of the T joint


@pytest.mark.parametrize("mesh, template, root_u, tool_z", [
    (butt_mesh(), JointTemplate("butt", gap_mm=1.5), (0.0, 8.0), DOWN),
    (fillet_mesh(), JointTemplate("fillet", angle_deg=90.0), (0.0, 8.0), TORCH_AT_45),
    (lap_mesh(), JointTemplate("lap", step_mm=3.0), (0.0, 8.0), DOWN),
    (v_groove_mesh(), JointTemplate("v_groove", angle_deg=60.0, angle_tol_deg=8.0), (0.0, 0.0), DOWN),
], ids=["butt", "fillet", "lap", "v_groove"])
@pytest.mark.parametrize("shift_u", [-4.0, 0.0, 2.5])
def test_each_joint_is_found_where_it_is(mesh, template, root_u, tool_z, shift_u):
    """The sensor is shifted sideways (U y) by `shift_u` from the root: the seam point in
    {S} is the root expressed there, by hand: y_S = (root - origin) . Y_S."""
    origin = np.array([100.0, root_u[0] + shift_u, root_u[1]])
    T_u_s = laser_frame(origin, ALONG_X, tool_z)
    expected = (np.array([100.0, root_u[0], root_u[1]]) - origin) @ T_u_s[:3, :3]
    rng = np.random.default_rng(7)
    feature = extract_seam(LaserLineSensor(noise_mm=0.02).profile(T_u_s, mesh, rng), template)
    assert feature is not None
    assert abs(feature.y_mm - expected[1]) < 0.1
    assert abs(feature.z_mm - expected[2]) < 0.1
    assert 0.0 <= feature.score <= 1.0
