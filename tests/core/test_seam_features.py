"""Joint templates: each joint found on synthetic noisy profiles, the wrong ones rejected."""

import numpy as np
import pytest

from CadRobotWB.errors import InputError
from CadRobotWB.sensors.seam_features import JointTemplate, extract_seam, find_faces

Y = np.linspace(-15.0, 15.0, 200)          # the laser line: 30 mm, 200 points
NOISE_MM = 0.02


def noisy(z, seed=0):
    """Profile (200, 2) with range noise on z; NaN where z is NaN."""
    z = np.asarray(z, dtype=float) + np.random.default_rng(seed).normal(0.0, NOISE_MM, len(Y))
    return np.column_stack([np.where(np.isnan(z), np.nan, Y), z])


def butt(y0=0.0, z0=0.0, gap=1.5, mismatch=0.0, table_mm=8.0):
    z = np.where(Y < y0, z0, z0 + mismatch)
    return np.where(np.abs(Y - y0) < gap / 2, z0 + table_mm if table_mm else np.nan, z)


def corner(y0=0.0, z0=0.0, angle_deg=90.0, depth=None):
    """A symmetric concave corner (fillet seen at 45°, or a V): faces rising from (y0, z0)."""
    z = z0 - np.abs(Y - y0) / np.tan(np.radians(angle_deg / 2))
    return z if depth is None else np.maximum(z, z0 - depth)        # flat plate tops beside a V


def lap(y0=0.0, z0=0.0, step=3.0):
    return np.where(Y < y0, z0 - step, z0)                           # upper plate on the left


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("y0, z0", [(0.0, 0.0), (4.3, -1.7), (-6.1, 2.2)])
def test_each_joint_gives_its_seam_point(seed, y0, z0):
    cases = [
        (butt(y0, z0), JointTemplate("butt", gap_mm=1.5), 0.08),           # ray spacing 0.15 mm
        (butt(y0, z0, table_mm=0), JointTemplate("butt", gap_mm=1.5), 0.08),   # nothing under the gap
        (corner(y0, z0, 90.0), JointTemplate("fillet", angle_deg=90.0, gap_mm=0.0), 0.03),
        (lap(y0, z0, 3.0), JointTemplate("lap", step_mm=3.0, gap_mm=0.0), 0.08),
        (corner(y0, z0, 60.0, depth=10.0), JointTemplate("v_groove", angle_deg=60.0, gap_mm=0.0), 0.05),
    ]
    for z, template, tol in cases:
        feature = extract_seam(noisy(z, seed), template)
        assert feature is not None, template.kind
        assert abs(feature.y_mm - y0) < tol, template.kind
        assert abs(feature.z_mm - z0) < 0.05, template.kind
        assert 0.7 < feature.score <= 1.0, template.kind


def test_the_measures_are_the_joint_geometry():
    f = extract_seam(noisy(butt(gap=2.0, mismatch=0.4)), JointTemplate("butt", gap_mm=1.5))
    assert abs(f.measures["gap_mm"] - 2.0) < 0.16 and abs(f.measures["mismatch_mm"] - 0.4) < 0.02
    # score = 1 - largest deviation / tolerance: the gap is 0.5 off of a 1.0 tolerance
    assert abs(f.score - 0.5) < 0.16
    f = extract_seam(noisy(corner(angle_deg=80.0)), JointTemplate("fillet", angle_deg=90.0))
    assert abs(f.measures["angle_deg"] - 80.0) < 0.5
    f = extract_seam(noisy(lap(step=3.6)), JointTemplate("lap", step_mm=3.0))
    assert abs(f.measures["step_mm"] - 3.6) < 0.02
    f = extract_seam(noisy(corner(angle_deg=64.0, depth=10)), JointTemplate("v_groove", angle_deg=60.0))
    assert abs(f.measures["angle_deg"] - 64.0) < 0.5


def test_a_lap_with_the_upper_plate_on_the_right():
    z = np.where(Y > 2.0, -3.0, 0.0)
    f = extract_seam(noisy(z), JointTemplate("lap", step_mm=3.0, gap_mm=0.0))
    assert abs(f.y_mm - 2.0) < 0.08 and abs(f.z_mm) < 0.02


ALL = [JointTemplate("butt"), JointTemplate("fillet"), JointTemplate("lap"), JointTemplate("v_groove")]


@pytest.mark.parametrize("template", ALL, ids=lambda t: t.kind)
def test_a_flat_plate_has_no_joint(template):
    assert extract_seam(noisy(np.zeros_like(Y)), template) is None
    assert extract_seam(noisy(0.1 * Y), template) is None                  # tilted plate


@pytest.mark.parametrize("template", ALL, ids=lambda t: t.kind)
def test_an_empty_profile_has_no_joint(template):
    assert extract_seam(np.full((200, 2), np.nan), template) is None


@pytest.mark.parametrize("z, template", [
    (butt(gap=4.0), JointTemplate("butt", gap_mm=1.5, gap_tol_mm=1.0)),          # gap too wide
    (butt(mismatch=2.0), JointTemplate("butt", gap_mm=1.5, mismatch_tol_mm=1.0)),  # plates misaligned
    (corner(angle_deg=120.0), JointTemplate("fillet", angle_deg=90.0, angle_tol_deg=15.0)),
    (lap(step=6.0), JointTemplate("lap", step_mm=3.0, step_tol_mm=1.0)),
    (corner(angle_deg=90.0, depth=10), JointTemplate("v_groove", angle_deg=60.0, angle_tol_deg=10.0)),
    (corner(angle_deg=60.0, depth=10), JointTemplate("fillet", angle_deg=90.0, angle_tol_deg=15.0)),
    (corner(angle_deg=90.0), JointTemplate("butt")),                               # another kind
    (butt(), JointTemplate("lap", step_mm=3.0)),
], ids=["wide gap", "mismatch", "fillet angle", "lap step", "v angle", "v as fillet", "fillet as butt",
        "butt as lap"])
def test_a_joint_outside_the_tolerance_is_rejected(z, template):
    assert extract_seam(noisy(z), template) is None


def test_a_convex_edge_is_not_a_fillet():
    ridge = np.abs(Y)                     # a roof seen from above: faces falling away from the middle
    assert extract_seam(noisy(ridge), JointTemplate("fillet", angle_deg=90.0)) is None


def test_faces_of_a_v_groove():
    faces, spacing = find_faces(noisy(corner(angle_deg=60.0, depth=10.0)))
    assert len(faces) == 4                # top, bevel, bevel, top
    assert abs(spacing - 30.0 / 199) < 1e-9
    slopes = [np.degrees(np.arctan2(f.direction[1], f.direction[0])) for f in faces]
    np.testing.assert_allclose(slopes, [0.0, 60.0, -60.0, 0.0], atol=0.5)


def test_bad_templates_are_refused():
    with pytest.raises(InputError):
        JointTemplate("corner")
    with pytest.raises(InputError):
        JointTemplate("butt", gap_tol_mm=0.0)
