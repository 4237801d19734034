"""The tool's orientation along each path segment: constant, or turning with an arc.

A tool marker sets the orientation of the segment its origin lies on and of
the following segments up to the next marker (DESIGN.md). On a line that
orientation is constant. On an arc the path turns, and a torch that must
keep its work angle to both faces of a fillet round the arc turns with it:
with ``tool_on_arcs = TURNS_WITH_ARC`` the marker sets the tool relative to
the arc's own frame, and along the arc

    R(s) = Rot(n, (s - s_m) / r) @ R_m

where n is the arc's axis (the arc runs counter-clockwise about it), r its
radius, s the arc length from the arc's start and (s_m, R_m) the marker's
arc-length position and orientation. A segment without a marker of its own
carries on from the orientation at the end of the segment before it (s_m = 0),
so a tangent line -> arc -> line junction has no orientation jump at all.
A tool whose axis is the arc's axis keeps its orientation (turning would only
spin it about its own axis).
``CONSTANT`` keeps the marker's orientation on the whole segment (documents
saved before this choice existed read as ``CONSTANT``).

Pure numpy; never imports FreeCAD.
"""

import numpy as np

from .rotations import matrix_from_axis_angle

#: The tool turns about the arc's axis with the swept angle (new paths).
TURNS_WITH_ARC = "Turns with the arc"
#: The marker's orientation, unchanged along the whole arc (the paper's rule).
CONSTANT = "Constant"
#: The choices of RobotPath.ToolOnArcs, the default for new paths first.
TOOL_ON_ARCS = (TURNS_WITH_ARC, CONSTANT)


class SegmentOrientation:
    """The tool orientation R_u_t(s) along one segment.

    Parameters
    ----------
    R_ref : ndarray, shape (3, 3)
        Orientation at arc length `s_ref`, {U}.
    s_ref : float
        Arc length from the segment's start where the orientation is `R_ref`, mm.
    arc : geometry.Arc, optional
        The tool turns about this arc's axis with the swept angle; None: constant.
    length : float
        The segment's length, mm.
    """

    def __init__(self, R_ref, length, s_ref=0.0, arc=None):
        self.R_ref = R_ref
        self.s_ref = float(s_ref)
        self.arc = arc
        self.length = float(length)

    @property
    def turns(self):
        """True when the orientation changes along the segment."""
        return self.arc is not None

    def at(self, s):
        """R_u_t (3, 3) at arc length `s` (mm); the very `R_ref` object when constant."""
        if self.arc is None:
            return self.R_ref
        return matrix_from_axis_angle(self.arc.normal, (float(s) - self.s_ref) / self.arc.radius) @ self.R_ref

    def at_many(self, s):
        """R_u_t (N, 3, 3) at arc lengths `s` (N,), mm."""
        s = np.atleast_1d(np.asarray(s, dtype=float))
        if self.arc is None:
            return np.repeat(np.asarray(self.R_ref, dtype=float)[None], len(s), axis=0)
        turn = matrix_from_axis_angle(np.repeat(self.arc.normal[None], len(s), axis=0),
                                      (s - self.s_ref) / self.arc.radius)
        return turn @ self.R_ref

    @property
    def start(self):
        return self.at(0.0)

    @property
    def end(self):
        return self.at(self.length)


def segment_orientations(segments, R_u_t, marker_s_mm=None, tool_on_arcs=CONSTANT):
    """The orientation law of every segment of a path.

    Parameters
    ----------
    segments : sequence of geometry segments
        In travel order, {U}, mm.
    R_u_t : sequence of ndarray, shape (3, 3)
        One orientation per segment: its marker's, or the inherited one
        (segments inheriting one marker's orientation share one array).
    marker_s_mm : sequence of (float or None), optional
        Per segment, the arc length (mm from its start) of the origin of the
        tool marker on it, or None when it inherits its orientation. Default:
        markers at their segments' starts, a segment sharing the array of the
        one before inherits.
    tool_on_arcs : {TURNS_WITH_ARC, CONSTANT}

    Returns
    -------
    list of SegmentOrientation
        With ``CONSTANT`` each is exactly ``R_u_t[i]`` (the same arrays).
    """
    if tool_on_arcs not in TOOL_ON_ARCS:
        raise ValueError("tool_on_arcs must be one of %s, got %r" % (TOOL_ON_ARCS, tool_on_arcs))
    laws = []
    for i, (seg, R) in enumerate(zip(segments, R_u_t)):
        if tool_on_arcs == CONSTANT:
            laws.append(SegmentOrientation(R, seg.length))
            continue
        own_s = None if marker_s_mm is None else marker_s_mm[i]
        inherited = i > 0 and own_s is None and (marker_s_mm is not None or R is R_u_t[i - 1])
        R_ref, s_ref = (laws[-1].end, 0.0) if inherited else (R, own_s or 0.0)
        turning = seg.kind == "arc" and not _along_axis(R_ref, seg)
        laws.append(SegmentOrientation(R_ref, seg.length, s_ref, seg if turning else None))
    return laws


def _along_axis(R, arc, tol=1e-9):
    """True when the tool axis (R's Z) is parallel to the arc's axis: turning with the arc
    would only spin the tool about its own axis (wrist travel for nothing, 360 degrees on
    a full circle), so the tool keeps its orientation there."""
    return abs(float(np.dot(np.asarray(R)[:, 2], arc.normal))) >= 1.0 - tol
