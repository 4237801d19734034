"""What a robot path shows in the 3D view, besides its own edges.

Per segment, in travel order (segment k is Edge k of the path's shape and
segment k of ``reader.path_geometry``): a cone at mid-length pointing along
the travel tangent, and the segment's number (1-based, as FreeCAD users
count edges and as risk areas and tool markers name segments).  The
generated targets (:mod:`target_display`) hang here too, so hiding the path
hides its targets.

Scene graph (under the view provider's root)::

    SoSwitch  visibility (the object's Visibility)
    +-- SoSeparator
        +-- SoPickStyle UNPICKABLE   picking goes to the path's edges
        +-- SoResetTransform         everything below is in {U}
        +-- arrows (SoSwitch)        ShowArrows
        +-- numbers (SoSwitch)       ShowSegmentNumbers
        +-- targets (SoSwitch)       set by target_display
"""

import numpy as np
from pivy import coin

from ..errors import CadRobotError
from . import triad_display

#: Colour of the direction arrows (a darker blue than the path's line), RGB 0..1.
ARROW_COLOR = (0.0, 0.2, 0.75)
#: Colour of the segment numbers.
NUMBER_COLOR = (0.0, 0.08, 0.3)
#: Arrow length as a fraction of the path's extent (capped by half the segment length).
ARROW_FRACTION = 0.05
#: Target triad axis length as a fraction of the extent of the targets.
TARGET_FRACTION = 0.04


def extent_mm(points):
    """Diagonal of the bounding box of `points` ((N, 3), mm); 0 for none."""
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    return float(np.linalg.norm(points.max(axis=0) - points.min(axis=0))) if len(points) else 0.0


def side_direction(tangent):
    """A unit vector across `tangent`, in the XY plane when it can be (where numbers go)."""
    for axis in (np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])):
        side = np.cross(axis, tangent)
        norm = np.linalg.norm(side)
        if norm > 1e-6:
            return side / norm
    return np.zeros(3)


def segment_marks(segments):
    """Where each segment's arrow and number go.

    Parameters
    ----------
    segments : list of core geometry segments
        In travel order, {U}.

    Returns
    -------
    list of (midpoint (3,), tangent (3,), arrow_length_mm)
        The point at half the segment's length, the unit travel tangent there,
        and the arrow length.
    """
    points = [p for s in segments for p in (s.start, s.end, s.point_at(s.length / 2.0))]
    reference = max(extent_mm(points), 1e-3)
    out = []
    for seg in segments:
        s_mid = seg.length / 2.0
        arrow = max(min(ARROW_FRACTION * reference, 0.5 * seg.length), 1e-3)
        out.append((np.asarray(seg.point_at(s_mid), dtype=float),
                    np.asarray(seg.tangent_at(s_mid), dtype=float), arrow))
    return out


class PathDisplay:
    """Direction arrows, segment numbers and target triads of one path.

    Parameters
    ----------
    root : coin.SoGroup
        The view provider's root node; the display adds its switch to it.

    Attributes
    ----------
    switch : coin.SoSwitch
        On while the path is visible.
    arrows, numbers, targets : coin.SoSwitch
        Each holds one ``SoSeparator`` with that part's nodes.
    segment_count : int
        Segments drawn (0 when the path's geometry cannot be read).
    target_count : int
        Target triads drawn.
    """

    def __init__(self, root):
        self.switch, sep = triad_display.overlay(root, "CadRobotPathDisplay")
        sep.addChild(coin.SoResetTransform())
        self.arrows, self.numbers, self.targets = (triad_display.switch_node() for _ in range(3))
        for switch in (self.arrows, self.numbers, self.targets):
            switch.addChild(coin.SoSeparator())
            sep.addChild(switch)
        self.segment_count = 0
        self.target_count = 0
        self._target_poses = np.zeros((0, 4, 4))

    def set_visible(self, visible):
        triad_display.set_visible(self.switch, visible)

    def show_arrows(self, visible):
        triad_display.set_visible(self.arrows, visible)

    def show_numbers(self, visible):
        triad_display.set_visible(self.numbers, visible)

    def update(self, path):
        """Redraw the arrows and numbers from `path`'s geometry (nothing when it cannot be read)."""
        from ..objects import reader
        try:
            segments = reader.path_geometry(path)[0]
        except (CadRobotError, AttributeError, TypeError, ValueError):
            segments = []      # half-built or restoring path: generating reports the problem
        self.draw_segments(segments)

    def draw_segments(self, segments):
        """Redraw the arrows and numbers of `segments` (core segments in travel order, {U})."""
        arrows = coin.SoSeparator()
        arrows.addChild(triad_display.unlit())
        arrows.addChild(triad_display.base_color(ARROW_COLOR))
        numbers = coin.SoSeparator()
        for number, (mid, tangent, length) in enumerate(segment_marks(segments), start=1):
            arrows.addChild(triad_display.cone_node(mid + tangent * length / 2.0, tangent, length,
                                                    length / 3.0))
            numbers.addChild(triad_display.text_node(str(number), mid + side_direction(tangent) * length,
                                                     NUMBER_COLOR, size_px=13))
        self.arrows.replaceChild(0, arrows)
        self.numbers.replaceChild(0, numbers)
        self.segment_count = len(segments)

    def set_targets(self, poses):
        """Draw a small triad at every pose (nothing when `poses` is empty).

        Parameters
        ----------
        poses : array_like, shape (N, 4, 4)
            Targets in {U}, mm. Redrawn only when they differ from the last call.
        """
        poses = np.asarray(poses, dtype=float).reshape(-1, 4, 4)
        if poses.shape == self._target_poses.shape and np.array_equal(poses, self._target_poses):
            return
        self._target_poses = poses
        length = max(TARGET_FRACTION * extent_mm(poses[:, :3, 3]), 1.0)
        self.targets.replaceChild(0, triad_display.triads_node(poses, length))
        self.target_count = len(poses)
