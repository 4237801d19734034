"""Joint detection: hand-built face sets classified, and the laser model agreeing with it."""

import numpy as np
import pytest
import trimesh

from CadRobotWB.core.geometry import Arc
from CadRobotWB.core.segment_orientation import CONSTANT, TURNS_WITH_ARC, segment_orientations
from CadRobotWB.sensors.joint_detection import (FaceSide, PathSample, approaches_at, classify_sample,
                                                 detect_joint, sensor_of)
from CadRobotWB.sensors.laser import LaserLineSensor, laser_frame
from CadRobotWB.sensors.seam_features import JOINT_KINDS, JointTemplate, extract_seam

X, Y, Z = np.eye(3)
S30, C30 = np.sin(np.radians(30)), np.cos(np.radians(30))
DOWN = -Z
TORCH_AT_45 = np.array([0, -1, -1]) / np.sqrt(2)      # into the corner of a T joint (web at y <= 0)
EDGE_BISECTOR = -np.array([0, 1, 1]) / np.sqrt(2)     # onto the outside edge of a block


def face(solid, name, normal, into, gap=0.0, extent=float("inf")):
    return FaceSide(solid, name, np.asarray(normal, float), np.asarray(into, float), gap, extent)


def sample(faces, approach, s=0.0, segment=1):
    return PathSample(s, segment, np.zeros(3), X, None if approach is None else np.asarray(approach, float),
                      faces)


# The face sets of the meshes below, as the App layer reads them (path along +X through the root).
FILLET_FACES = [face("Base", "Face6", Z, Y), face("Web", "Face3", Y, Z, extent=100.0)]
BUTT_FACES = [face("PlateA", "Face6", Z, -Y, gap=0.75), face("PlateB", "Face6", Z, Y, gap=0.75)]
LAP_FACES = [face("Lower", "Face6", Z, -Y), face("Upper", "Face1", -Y, Z, extent=3.0)]
V_FACES = [face("Left", "Face2", (0, C30, S30), (0, -S30, C30), extent=11.5),
           face("Right", "Face4", (0, -C30, S30), (0, S30, C30), extent=11.5)]
PLANE_FACES = [face("Block", "Face5", Z, Y), face("Block", "Face5", Z, -Y)]
CONVEX_FACES = [face("Pocket011", "Face5", Z, -Y), face("Pocket011", "Face8", Y, -Z)]


@pytest.mark.parametrize("faces, approach, kind, measure", [
    (FILLET_FACES, TORCH_AT_45, "fillet", ("angle_deg", 90.0)),
    (BUTT_FACES, DOWN, "butt", ("gap_mm", 1.5)),
    (LAP_FACES, DOWN, "lap", ("step_mm", 3.0)),
    (V_FACES, DOWN, "v_groove", ("angle_deg", 60.0)),
    (PLANE_FACES, DOWN, "surface", None),
    (CONVEX_FACES, EDGE_BISECTOR, "convex_edge", ("angle_deg", 90.0)),
    (CONVEX_FACES, DOWN, "convex_edge", ("angle_deg", 90.0)),
    (CONVEX_FACES, None, "convex_edge", ("angle_deg", 90.0)),      # no marker: the faces' bisector
    ([], DOWN, "none", None),
], ids=["fillet", "butt", "lap", "v_groove", "plane", "convex_bisector", "convex_down", "convex_nomarker",
        "nothing"])
def test_each_face_set_is_its_kind(faces, approach, kind, measure):
    result = classify_sample(sample(faces, approach))
    assert result.kind == kind
    if measure:
        assert getattr(result, measure[0]) == pytest.approx(measure[1], abs=1e-6)


def test_one_solid_with_a_gap_is_a_butt_joint_and_without_one_a_surface():
    slot = [face("Block", "Face5", Z, Y, gap=0.5), face("Block", "Face9", Z, -Y, gap=0.5)]
    assert classify_sample(sample(slot, DOWN)).kind == "butt"
    assert classify_sample(sample(PLANE_FACES, DOWN)).kind == "surface"


def test_a_concave_corner_of_one_solid_is_a_fillet_and_a_tall_web_is_no_lap():
    inside = [face("Pocket", "Face2", Z, Y), face("Pocket", "Face7", Y, Z, extent=3.0)]
    assert classify_sample(sample(inside, TORCH_AT_45)).kind == "fillet"      # one solid: no lap
    tall = [face("Lower", "Face6", Z, -Y), face("Upper", "Face1", -Y, Z, extent=40.0)]
    assert classify_sample(sample(tall, DOWN)).kind == "fillet"


def test_a_corner_too_flat_or_too_sharp_for_the_laser_is_no_joint():
    # 164 degrees of free space: two faces tilted 8 degrees into a shallow valley
    c, s = np.cos(np.radians(8)), np.sin(np.radians(8))
    flat = [face("A", "Face1", (0, s, c), (0, -c, s)), face("B", "Face1", (0, -s, c), (0, c, s))]
    assert flat[0].into @ flat[1].normal > 0 and flat[1].into @ flat[0].normal > 0   # concave
    assert classify_sample(sample(flat, DOWN)).kind == "surface"
    # 20 degrees: a slit narrower than the laser can look into
    c, s = np.cos(np.radians(80)), np.sin(np.radians(80))
    slit = [face("A", "Face1", (0, s, c), (0, -c, s)), face("B", "Face1", (0, -s, c), (0, c, s))]
    assert classify_sample(sample(slit, DOWN)).kind == "surface"


def test_faces_facing_away_from_the_tool_are_left_out():
    underside = face("Block", "Face4", -Z, Y)
    assert classify_sample(sample([underside], DOWN)).kind == "none"
    assert classify_sample(sample(CONVEX_FACES + [underside], DOWN)).kind == "convex_edge"


def test_the_side_of_a_face_is_left_or_right_of_the_travel_seen_from_the_tool():
    a, b = BUTT_FACES
    assert a.side(X, Z) == "right" and b.side(X, Z) == "left"


def test_the_convex_edge_reason_names_the_faces_the_angle_and_force():
    samples = [sample(CONVEX_FACES, EDGE_BISECTOR, s=20.0 * k) for k in range(6)]
    result = detect_joint(samples, "Path")
    assert (result.kind, result.sensor, result.fraction) == ("convex_edge", "force", 1.0)
    assert result.reason == ("Path Path runs along a convex edge between Face5 and Face8 of Pocket011 "
                             "(outside corner, 90\u00b0): no joint for a laser to find; follow the "
                             "surface with force.")
    assert result.fits("force") and not result.fits("laser")
    assert result.why_not("force") == ""
    assert result.why_not("laser") == ("the path has no joint: it runs along a convex edge between "
                                       "Face5 and Face8 of Pocket011 (outside corner, 90\u00b0)")
    assert result.template() is None
    assert result.to_dict()["faces"] == ["Pocket011.Face5", "Pocket011.Face8"]


def test_a_mixed_path_takes_the_majority_by_length_and_says_where_it_differs():
    # samples every 20 mm from 0 to 200: 0..140 fillet (segment 1), 160..200 convex (segment 2)
    samples = [sample(FILLET_FACES, TORCH_AT_45, s=s, segment=1) for s in range(0, 141, 20)]
    samples += [sample(CONVEX_FACES, EDGE_BISECTOR, s=s, segment=2) for s in range(160, 201, 20)]
    result = detect_joint(samples, "Seam")
    # weights: half-way to each neighbour: fillet 0..150 mm, convex 150..200 mm of 200 mm
    assert result.kind == "fillet" and result.sensor == "laser"
    assert result.fraction == pytest.approx(150.0 / 200.0)
    assert result.elsewhere == [("convex_edge", 160.0, 200.0, [2])]
    assert "(75% of its length; elsewhere convex edge at s = 160-200 mm (segment 2))" in result.reason
    assert "Base.Face6 and Web.Face3" in result.reason
    assert "laser" in result.why_not("force") and result.why_not("laser") == ""


def test_a_path_touching_nothing_fits_no_sensor():
    result = detect_joint([sample([], DOWN)], "Air")
    assert result.sensor is None and sensor_of("none") is None
    assert "no face" in result.why_not("laser") and "no surface" in result.why_not("force")


# --- agreement with the laser model: a path detected as a joint is tracked, an edge is not ---

def box(low, high):
    low, high = np.asarray(low, float), np.asarray(high, float)
    return trimesh.creation.box(high - low, trimesh.transformations.translation_matrix((low + high) / 2))


def prism(section_yz, x0=-50.0, x1=250.0):
    section = np.asarray(section_yz, float)
    points = np.vstack([np.column_stack([np.full(len(section), x), section]) for x in (x0, x1)])
    return trimesh.convex.convex_hull(points)


W = 10.0 * np.tan(np.radians(30))
MESHES = {   # root of each joint at (y 0, z 0), path along X
    "fillet": (trimesh.util.concatenate([box((-50, -100, -8), (250, 100, 0)), box((-50, -8, 0), (250, 0, 100))]),
               [face("Base", "Face6", Z, Y), face("Web", "Face3", Y, Z, extent=100.0)], TORCH_AT_45),
    "butt": (trimesh.util.concatenate([box((-50, -100, -8), (250, -0.75, 0)), box((-50, 0.75, -8), (250, 100, 0)),
                                       box((-50, -100, -28), (250, 100, -8))]), BUTT_FACES, DOWN),
    "lap": (trimesh.util.concatenate([box((-50, -100, -8), (250, 100, 0)), box((-50, -100, 0), (250, 0, 3))]),
            [face("Lower", "Face6", Z, Y), face("Upper", "Face2", Y, Z, extent=3.0)], DOWN),
    "v_groove": (trimesh.util.concatenate([prism([(-100, 0), (0, 0), (-W, 10), (-100, 10)]),
                                           prism([(0, 0), (100, 0), (100, 10), (W, 10)])]), V_FACES, DOWN),
}


@pytest.mark.parametrize("kind", sorted(MESHES))
def test_the_laser_finds_the_joint_the_detection_names_with_its_template(kind):
    mesh, faces, approach = MESHES[kind]
    detection = detect_joint([sample(faces, approach)])
    assert detection.kind == kind
    template = detection.template()
    assert template.kind == kind
    T_u_s = laser_frame(np.array([100.0, 1.5, 0.0]), X, approach)     # 1.5 mm off the root
    expected = (np.zeros(3) + [100.0, 0, 0] - T_u_s[:3, 3]) @ T_u_s[:3, :3]
    profile = LaserLineSensor(noise_mm=0.02).profile(T_u_s, mesh, np.random.default_rng(3))
    feature = extract_seam(profile, template)
    assert feature is not None
    assert abs(feature.y_mm - expected[1]) < 0.2 and abs(feature.z_mm - expected[2]) < 0.2


def test_the_laser_finds_no_joint_on_a_convex_edge_the_detection_gives_to_force():
    block = box((-50, -100, -60), (250, 0, 0))          # its top outer edge along X at y 0, z 0
    detection = detect_joint([sample(CONVEX_FACES, EDGE_BISECTOR)])
    assert detection.sensor == "force"
    T_u_s = laser_frame(np.array([100.0, 0.0, 0.0]), X, EDGE_BISECTOR)
    profile = LaserLineSensor(noise_mm=0.02).profile(T_u_s, block, np.random.default_rng(3))
    assert np.isfinite(profile).all(axis=1).sum() > 50            # it sees the block
    for kind in JOINT_KINDS:
        assert extract_seam(profile, JointTemplate(kind)) is None, kind


# --- a fillet all round a pipe: the tool turning with the circle sees the joint everywhere ---

PIPE_R = 60.0
#: A pipe of radius 60 mm standing on a plate (its top at z 0), the fillet round its foot.
PIPE_ON_PLATE = trimesh.util.concatenate([
    box((-150, -150, -10), (150, 150, 0)),
    trimesh.creation.cylinder(radius=PIPE_R, height=100.0, sections=180,
                              transform=trimesh.transformations.translation_matrix((0, 0, 50)))])
#: Stations every 20 mm round the 377 mm foot, the first 10 mm in (as the App samples).
PIPE_STATIONS = [(s, 0, s) for s in np.arange(10.0, 2 * np.pi * PIPE_R, 20.0)]


def pipe_foot_samples(tool_on_arcs):
    """The PathSamples round the pipe's foot, their approach from the tool's law along the
    circle (one marker at the start: 45 deg into the corner, square to the travel)."""
    foot = Arc((0, 0, 0), Z, (PIPE_R, 0, 0), 2 * np.pi)
    approach = np.array([-1.0, 0.0, -1.0]) / np.sqrt(2)
    R_marker = np.column_stack([Y, np.cross(approach, Y), approach])      # X along the travel
    laws = segment_orientations([foot], [R_marker], [0.0], tool_on_arcs)
    out = []
    for (s, _, _), approach in zip(PIPE_STATIONS, approaches_at(laws, PIPE_STATIONS)):
        radial = foot.point_at(s) / PIPE_R
        faces = [face("Plate", "Face6", Z, radial), face("Pipe", "Face1", radial, Z, extent=100.0)]
        out.append(PathSample(s, 1, foot.point_at(s), foot.tangent_at(s), approach, faces))
    return out


def laser_finds_root(samples):
    """Per sample, whether the laser (its stripe at the sample, across the travel, its
    axis the sample's approach) finds the 90-degree fillet in the pipe-on-plate mesh
    within 0.2 mm of the root (the sample's point, the stripe's origin)."""
    sensor, rng, fillet = LaserLineSensor(noise_mm=0.02), np.random.default_rng(5), JointTemplate("fillet")
    found = [extract_seam(sensor.profile(laser_frame(x.point, x.tangent, x.approach), PIPE_ON_PLATE, rng),
                          fillet) for x in samples]
    return np.array([f is not None and np.hypot(f.y_mm, f.z_mm) < 0.2 for f in found])


def test_a_tool_turning_round_a_pipe_sees_the_fillet_all_round_as_the_laser_does():
    """By hand: a tool turning with the circle keeps the marker's view (m + z) / sqrt 2 of the
    corner at every angle (m the outward radial), so both faces face it (n . view = 0.707)
    at a free-space angle of 90 deg: a fillet over the whole length, and the laser finds its
    root at every station. (The demo's pipe read 59% when each sample took its marker's
    approach unturned.)"""
    samples = pipe_foot_samples(TURNS_WITH_ARC)
    detection = detect_joint(samples)
    assert (detection.kind, detection.fraction) == ("fillet", 1.0)
    assert laser_finds_root(samples).all()


def test_a_tool_kept_constant_round_a_pipe_sees_the_fillet_only_on_its_near_side():
    """By hand: a constant view (1, 0, 1) / sqrt 2 meets the pipe's face at angle phi with
    n . view = cos(phi) / sqrt 2, below the facing-away limit -0.1 beyond |phi| = 98.1 deg
    (there the tool would stand inside the pipe): of the stations at phi = 9.5, 28.6, ...,
    353.3 deg, the 10 within 98.1 deg of 0 are fillets, 180 of the 360 mm they stand for."""
    detection = detect_joint(pipe_foot_samples(CONSTANT))
    assert (detection.kind, detection.fraction) == ("fillet", pytest.approx(0.5, abs=1e-9))
