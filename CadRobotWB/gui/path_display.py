"""What a robot path shows in the 3D view, besides its own edges.

Per segment, in travel order (segment k is Edge k of the path's shape and
segment k of ``reader.path_geometry``): a cone at mid-length pointing along
the travel tangent, and the segment's number (1-based, as FreeCAD users
count edges and as risk areas and tool markers name segments).  The
generated targets (:mod:`target_display`) hang here too, so hiding the path
hides its targets.  While tool markers are selected, the segments whose
orientation they set (their own and the following ones up to the next
marker, ``reader.governed_segments``) are drawn over the path, thick and in
the markers' orange (:class:`GovernedHighlighter`).

Scene graph (under the view provider's root)::

    SoSwitch  visibility (the object's Visibility)
    +-- SoSeparator
        +-- SoPickStyle UNPICKABLE   picking goes to the path's edges
        +-- SoResetTransform         everything below is in {U}
        +-- arrows (SoSwitch)        ShowArrows
        +-- numbers (SoSwitch)       ShowSegmentNumbers
        +-- targets (SoSwitch)       set by target_display
        +-- governed (SoSwitch)      on while a marker of this path is selected
"""

import FreeCAD
import numpy as np
from pivy import coin
from PySide import QtCore

from ..errors import CadRobotError
from ..objects.base import objects_of_type
from . import triad_display

#: Colour of the direction arrows (a darker blue than the path's line), RGB 0..1.
ARROW_COLOR = (0.0, 0.2, 0.75)
#: Colour of the segment numbers.
NUMBER_COLOR = (0.0, 0.08, 0.3)
#: Arrow length as a fraction of the path's extent (capped by half the segment length).
ARROW_FRACTION = 0.05
#: Target triad axis length as a fraction of the extent of the targets.
TARGET_FRACTION = 0.04
#: Colour and width (px) of the segments a selected tool marker governs (the markers' orange).
GOVERNED_COLOR = (1.0, 0.55, 0.0)
GOVERNED_WIDTH = 8.0
#: Largest angle between the chords drawn for an arc, degrees.
ARC_STEP_DEG = 5.0


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


def segment_points(segment):
    """Points along a core segment, enough to draw it as a polyline.

    Returns
    -------
    ndarray, shape (N, 3)
        From start to end, mm: a line's two ends, a sampled curve's samples,
        an arc every :data:`ARC_STEP_DEG` degrees at most.
    """
    points = getattr(segment, "points", None)
    if points is not None:
        return np.asarray(points, dtype=float)
    sweep = getattr(segment, "sweep_rad", None)
    if sweep is None:
        return np.array([segment.start, segment.end], dtype=float)
    count = int(np.ceil(np.degrees(sweep) / ARC_STEP_DEG)) + 1
    return segment.points_at(np.linspace(0.0, segment.length, max(count, 2)))


def governed_node(segments, ranges):
    """The segments in `ranges` as thick orange lines, drawn over everything.

    Parameters
    ----------
    segments : list of core segments
        The path's, in travel order, {U}.
    ranges : iterable of (int, int)
        (first, last) segment numbers, 1-based, inclusive.

    Returns
    -------
    coin.SoSeparator
    """
    chords = [segment_points(segments[k - 1]) for first, last in ranges for k in range(first, last + 1)]
    starts = np.concatenate([c[:-1] for c in chords]) if chords else np.zeros((0, 3))
    ends = np.concatenate([c[1:] for c in chords]) if chords else np.zeros((0, 3))
    sep = coin.SoSeparator()
    if hasattr(coin, "SoDepthBuffer"):     # on top of the path's own, equally deep, line
        depth = coin.SoDepthBuffer()
        depth.function = coin.SoDepthBuffer.ALWAYS
        sep.addChild(depth)
    sep.addChild(triad_display.unlit())
    sep.addChild(triad_display.segments_node(starts, ends, GOVERNED_COLOR, GOVERNED_WIDTH))
    return sep


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
    governed : coin.SoSwitch
        The highlighted segments (off when none).
    governed_ranges : tuple of (int, int)
        (first, last) segment numbers highlighted, 1-based, sorted; () for none.
    """

    def __init__(self, root):
        self.switch, sep = triad_display.overlay(root, "CadRobotPathDisplay")
        sep.addChild(coin.SoResetTransform())
        self.arrows, self.numbers, self.targets, self.governed = (
            triad_display.switch_node() for _ in range(4))
        for switch in (self.arrows, self.numbers, self.targets, self.governed):
            switch.addChild(coin.SoSeparator())
            sep.addChild(switch)
        triad_display.set_visible(self.governed, False)
        self.segment_count = 0
        self.target_count = 0
        self.governed_ranges = ()
        self._governed_segments = None
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

    def show_governed(self, segments, ranges):
        """Highlight segments `ranges` ((first, last), 1-based) of `segments`
        (the path's core segments); none when `ranges` is empty.
        Redrawn only when the segments or the ranges changed."""
        ranges = tuple(sorted(set(ranges)))
        same_segments = self._governed_segments is not None and len(segments) == len(
            self._governed_segments) and all(a is b for a, b in zip(segments, self._governed_segments))
        if ranges == self.governed_ranges and (same_segments or not ranges):
            return
        self.governed_ranges = ranges
        self._governed_segments = list(segments) if ranges else None
        self.governed.replaceChild(0, governed_node(segments, ranges) if ranges else coin.SoSeparator())
        triad_display.set_visible(self.governed, bool(ranges))


# --- what the selected tool markers govern ---------------------------------------------------

_highlighter = None


def selected_marker_names(doc):
    """Internal names of the tool markers selected in `doc`."""
    import FreeCADGui
    from ..objects.base import type_of
    return {o.Name for o in FreeCADGui.Selection.getSelection(doc.Name) if type_of(o) == "ToolMarker"}


def governed_ranges(doc, marker_names):
    """{path name: [(first, last), ...]} the markers `marker_names` of `doc` govern."""
    from ..objects import reader
    out = {}
    if not marker_names:
        return out
    for cell in objects_of_type(doc, "Cell"):
        for name, governed in reader.governed_segments(cell).items():
            if name in marker_names and isinstance(governed, reader.Governed):
                out.setdefault(governed.path.Name, []).append((governed.first, governed.last))
    return out


def highlight_governed(doc):
    """Highlight, on every path of `doc`, the segments its selected tool markers govern."""
    from ..objects import reader
    ranges = governed_ranges(doc, selected_marker_names(doc))
    for path in objects_of_type(doc, "RobotPath"):
        display = getattr(getattr(path.ViewObject, "Proxy", None), "path_display", None)
        if display is None:
            continue
        if path.Name not in ranges:
            display.show_governed([], ())
            continue
        display.show_governed(reader.path_geometry(path)[0], ranges[path.Name])


class GovernedHighlighter:
    """Selection and document observer: after the selection changes or a
    document recomputes, the governed segments are drawn again (once, from the
    event loop, however many notices came)."""

    def __init__(self):
        self.pending = set()

    def _soon(self, doc_name):
        if not self.pending:
            QtCore.QTimer.singleShot(0, self.refresh)
        self.pending.add(doc_name)

    def refresh(self):
        names, self.pending = self.pending, set()
        documents = FreeCAD.listDocuments()
        if "" in names:          # a notice for no document in particular (clearSelection())
            names = set(documents)
        for name in names:
            doc = documents.get(name)
            if doc is None:
                continue
            try:
                highlight_governed(doc)
            except Exception as err:     # never a traceback from an observer
                FreeCAD.Console.PrintWarning("CadRobot: governed segments not shown: %s\n" % err)

    # Selection observer (document names).
    def addSelection(self, doc, obj, sub, pnt):
        self._soon(doc)

    def removeSelection(self, doc, obj, sub):
        self._soon(doc)

    def setSelection(self, doc):
        self._soon(doc)

    def clearSelection(self, doc):
        self._soon(doc)

    # Document observer (documents).
    def slotRecomputedDocument(self, doc):
        self._soon(doc.Name)


def install():
    """Start highlighting (once per session); returns the observer."""
    global _highlighter
    if _highlighter is None:
        import FreeCADGui
        _highlighter = GovernedHighlighter()
        FreeCADGui.Selection.addObserver(_highlighter)
        FreeCAD.addDocumentObserver(_highlighter)
    return _highlighter
