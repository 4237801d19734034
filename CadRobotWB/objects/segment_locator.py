"""Which segment of a long path a point lies on, without testing every segment.

:func:`core.geometry.assign_point` tests the segments one by one in Python,
which is fine for a sketch of ten edges and far too slow for a polyline of
20,000 edges with a marker on many of them.  A :class:`SegmentLocator`
first keeps the segments whose bounding box (grown by the tolerance) holds
the point, found through a k-d tree of the boxes' centres, and hands only
those to ``assign_point``, in path order, so the answer is the same.
"""

import numpy as np
from scipy.spatial import cKDTree

from ..core import geometry

# Boxes grow by this beyond the tolerance, so rounding never drops a segment
# assign_point would keep (it makes the exact test), mm.
SLACK_MM = 1e-6


def bounding_boxes(segments):
    """Axis-aligned boxes holding every point of each segment.

    Parameters
    ----------
    segments : sequence of core segments (Line, Arc, Polyline)
        {U}, mm.

    Returns
    -------
    lo, hi : ndarray, shape (N, 3)
        Corners, mm; an arc's box is its whole circle's (a little larger than
        the arc, never smaller).
    """
    starts = np.array([seg.start for seg in segments], dtype=float).reshape(-1, 3)
    ends = np.array([seg.end for seg in segments], dtype=float).reshape(-1, 3)
    lo, hi = np.minimum(starts, ends), np.maximum(starts, ends)     # right for lines
    for k, seg in enumerate(segments):
        if isinstance(seg, geometry.Arc):
            lo[k], hi[k] = seg.center - seg.radius, seg.center + seg.radius
        elif isinstance(seg, geometry.Polyline):
            lo[k], hi[k] = seg.points.min(axis=0), seg.points.max(axis=0)
    return lo, hi


class SegmentLocator:
    """Finds the segment a point lies on, as :func:`core.geometry.assign_point` does.

    Parameters
    ----------
    segments : sequence of core segments
        A chained path in travel order, {U}, mm.
    tol_mm : float
        Largest distance from a segment that still counts as on it, mm.
    """

    def __init__(self, segments, tol_mm):
        self.segments = list(segments)
        self.tol_mm = float(tol_mm)
        self.lo, self.hi = bounding_boxes(self.segments)
        grow = self.tol_mm + SLACK_MM
        self.lo -= grow
        self.hi += grow
        centers = (self.lo + self.hi) / 2.0
        self.radius = float(np.linalg.norm(self.hi - centers, axis=1).max()) if self.segments else 0.0
        self.tree = cKDTree(centers) if self.segments else None
        self._found = {}        # point (x, y, z) -> segment index or None

    def candidates(self, point):
        """Indices (ascending) of the segments whose grown box holds `point` ((3,), mm)."""
        if self.tree is None:
            return []
        point = np.asarray(point, dtype=float).reshape(3)
        near = np.array(sorted(self.tree.query_ball_point(point, self.radius * (1.0 + 1e-9))), dtype=int)
        if not len(near):
            return []
        inside = np.all((self.lo[near] <= point) & (point <= self.hi[near]), axis=1)
        return near[inside].tolist()

    def segment_of(self, point):
        """0-based index of the segment `point` lies on, or None (rules of ``assign_point``).

        Answers are remembered per point: markers that did not move cost a
        look-up when the cell is read again."""
        key = tuple(float(c) for c in point)
        if key not in self._found:
            near = self.candidates(key)
            found = geometry.assign_point([self.segments[k] for k in near], key, self.tol_mm)
            self._found[key] = None if found is None else near[found]
        return self._found[key]
