"""objects/segment_locator.py (numpy and scipy only): the segment a tool marker lies on,
found without testing every segment, with the answers of core.geometry.assign_point."""

import time

import numpy as np
import pytest

from CadRobotWB.core.geometry import Arc, Line, Polyline, assign_point
from CadRobotWB.objects.segment_locator import SegmentLocator, bounding_boxes


def zigzag(count, step=1.0):
    """`count` lines of length `step` (mm) along a zig-zag in the XY plane."""
    points = [np.array([step * k, 0.3 * step * (k % 2), 0.0]) for k in range(count + 1)]
    return [Line(a, b) for a, b in zip(points[:-1], points[1:])]


def mixed_path():
    """A line, a half circle (radius 10 about (20, 0, 0)), a sampled curve, a line."""
    line = Line((0, 0, 0), (10, 0, 0))
    arc = Arc((20, 0, 0), (0, 0, -1), (10, 0, 0), np.pi)          # over the top to (30, 0, 0)
    curve = Polyline([(30, 0, 0), (35, -3, 1), (40, -4, 0), (45, 0, 0)])
    return [line, arc, curve, Line((45, 0, 0), (60, 0, 0))]


def test_boxes_hold_every_point_of_each_segment():
    segments = mixed_path()
    lo, hi = bounding_boxes(segments)
    for seg, a, b in zip(segments, lo, hi):
        points = seg.points_at(np.linspace(0.0, seg.length, 200))
        assert np.all(points >= a - 1e-12) and np.all(points <= b + 1e-12)
    np.testing.assert_allclose(lo[1], [10, -10, -10])            # the arc's whole circle
    np.testing.assert_allclose(hi[1], [30, 10, 10])
    np.testing.assert_allclose(lo[2], [30, -4, 0])
    np.testing.assert_allclose(hi[2], [45, 0, 1])


@pytest.mark.parametrize("tol", [0.01, 0.1, 0.6, 3.0])
def test_same_answers_as_assign_point(tol):
    rng = np.random.default_rng(7)
    after = np.array([60.0, 0.0, 0.0])                            # the zig-zag goes on from there
    segments = mixed_path() + [Line(s.start + after, s.end + after) for s in zigzag(40, 1.5)]
    locator = SegmentLocator(segments, tol)
    on_path = [s.point_at(u * s.length) for s in segments for u in (0.0, 0.3, 1.0)]
    near = [p + rng.normal(0.0, tol, 3) for p in on_path]
    anywhere = list(rng.uniform((-5, -15, -5), (125, 15, 5), size=(300, 3)))
    for point in on_path + near + anywhere:
        assert locator.segment_of(point) == assign_point(segments, point, tol), point


def test_a_junction_belongs_to_the_segment_starting_there():
    segments = zigzag(5)
    locator = SegmentLocator(segments, 0.1)
    assert locator.segment_of(segments[2].start) == 2
    assert locator.segment_of(segments[-1].end) == 4              # the end of an open path
    assert locator.segment_of((2.5, 5.0, 0.0)) is None


def test_an_empty_path_holds_no_point():
    assert SegmentLocator([], 0.1).segment_of((0, 0, 0)) is None


def test_finding_many_points_on_a_long_path_is_not_quadratic():
    segments = zigzag(20000)
    rng = np.random.default_rng(3)
    picks = rng.integers(0, 20000, size=2000)
    began = time.perf_counter()
    locator = SegmentLocator(segments, 0.1)
    found = [locator.segment_of(segments[k].point_at(0.5)) for k in picks]
    seconds = time.perf_counter() - began
    assert found == picks.tolist()
    # assign_point alone tests every segment: about 0.1-0.5 s per point here, minutes for 2,000.
    assert seconds < 5.0, "%.1f s" % seconds
