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

Concave arcs (``TURNS_WITH_ARC`` only). An arc is concave when its centre lies
on the side the tool's body leans to (the body, along -Z from the TCP, has a
component towards the centre): the walls wrap round the torch, and the wall
of the segment before the arc stands behind the torch at the arc's end (at
the tangent length r tan(theta / 2) for a tangent line). A torch that turns
with the arc keeps its travel angle, so at the arc's end its body leans back
towards that wall (and, dragging, towards the next wall at the arc's start).
On a run of consecutive concave arcs about one axis (swept angle Theta) the
tool's lean in the arc's plane, gamma = atan2(z.d, z.m) (z the tool axis, d
the tangent, m the outward radial direction; the travel angle's sign), goes
linearly with arc length from +g at the run's start (pushing: the body leans
away from the wall ahead) through 0 at its middle to -g at its end (dragging:
away from the wall behind), with g = min(|gamma|, Theta / 2): the path's own
travel angle, mirrored, so the work angle at both ends is the marker's and
the lean stays within the path's travel angle. Along the run the tool turns
about the arc's axis by Theta - 2 g instead of Theta (never against the arc):
a rotation about one axis in proportion to the swept angle, which every
controller's circular move reproduces exactly. The neighbouring segments
take the difference back over a lead (:func:`lead_length_mm`): the tool
turns about the arc's axis, in proportion to arc length, from the run's end
orientation to its own law, so the orientation is continuous at every
junction (no reorientation is written there) and the neighbour keeps its
marker's angles beyond the lead. A whole closed loop of concave arcs has
nothing to ease into and is left as it is.

Pure numpy; never imports FreeCAD.
"""

from collections import namedtuple

import numpy as np

from .rotations import matrix_from_axis_angle

#: The tool turns about the arc's axis with the swept angle (new paths).
TURNS_WITH_ARC = "Turns with the arc"
#: The marker's orientation, unchanged along the whole arc (the paper's rule).
CONSTANT = "Constant"
#: The choices of RobotPath.ToolOnArcs, the default for new paths first.
TOOL_ON_ARCS = (TURNS_WITH_ARC, CONSTANT)


#: A lean (radians) this small is none: a tool square to the travel is left as it is.
NO_LEAN_RAD = 1e-9

#: An extra turn about `axis` by `angle_rad` times a weight going linearly from 1 at arc
#: length `s_full` to 0 at `s_zero` (mm), 0 beyond: a neighbour's lead into a concave arc.
Lead = namedtuple("Lead", "axis angle_rad s_full s_zero")


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
    rate : float
        On a turning arc, the tool's turn per swept angle (1: with the arc; below 1 on a
        concave arc, see the module's docstring).
    leads : sequence of Lead
        Extra turns near the ends (leads into a concave arc), applied on the left.
    """

    def __init__(self, R_ref, length, s_ref=0.0, arc=None, rate=1.0, leads=()):
        self.R_ref = R_ref
        self.s_ref = float(s_ref)
        self.arc = arc
        self.length = float(length)
        self.rate = float(rate)
        self.leads = tuple(leads)

    @property
    def turns(self):
        """True when the orientation changes along the segment."""
        return self.arc is not None or bool(self.leads)

    @property
    def breaks(self):
        """Arc lengths strictly inside the segment where a lead ends (mm, increasing): the
        orientation's rate changes there, so a target is written there."""
        return sorted({lead.s_zero for lead in self.leads if 0.0 < lead.s_zero < self.length})

    def at(self, s):
        """R_u_t (3, 3) at arc length `s` (mm); the very `R_ref` object when constant."""
        R = self.R_ref
        if self.arc is not None:
            R = matrix_from_axis_angle(self.arc.normal, self.rate * (float(s) - self.s_ref) / self.arc.radius) @ R
        for lead in self.leads:
            weight = float(_lead_weights(lead, np.array([float(s)]))[0])
            if weight > 0.0:
                R = matrix_from_axis_angle(lead.axis, weight * lead.angle_rad) @ R
        return R

    def at_many(self, s):
        """R_u_t (N, 3, 3) at arc lengths `s` (N,), mm."""
        s = np.atleast_1d(np.asarray(s, dtype=float))
        R = np.repeat(np.asarray(self.R_ref, dtype=float)[None], len(s), axis=0)
        if self.arc is not None:
            R = matrix_from_axis_angle(np.repeat(self.arc.normal[None], len(s), axis=0),
                                       self.rate * (s - self.s_ref) / self.arc.radius) @ R
        for lead in self.leads:
            R = matrix_from_axis_angle(np.repeat(np.asarray(lead.axis, dtype=float)[None], len(s), axis=0),
                                       _lead_weights(lead, s) * lead.angle_rad) @ R
        return R

    @property
    def start(self):
        return self.at(0.0)

    @property
    def end(self):
        return self.at(self.length)


def _lead_weights(lead, s):
    """The weight (N,) of `lead` at arc lengths `s` (N,): 1 at s_full, 0 at s_zero and beyond."""
    return np.clip((s - lead.s_zero) / (lead.s_full - lead.s_zero), 0.0, 1.0)


def segment_orientations(segments, R_u_t, marker_s_mm=None, tool_on_arcs=CONSTANT, closed=False):
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
    closed : bool
        The path ends where it starts: the last and the first segment are
        neighbours (a concave arc at one end leads into the other).

    Returns
    -------
    list of SegmentOrientation
        With ``CONSTANT`` each is exactly ``R_u_t[i]`` (the same arrays). With
        ``TURNS_WITH_ARC`` concave arcs lean as the module's docstring says.
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
    if tool_on_arcs == TURNS_WITH_ARC:
        for run in _concave_runs(laws, closed):
            _lean_through(laws, run, closed)
    return laws


def lead_length_mm(run_length_mm, neighbour_length_mm):
    """How far into a neighbouring segment the tool takes back a concave run's lean, mm.

    ``min(2 x run length, half the neighbour)``: the tool turns back at half
    the rate (or less) it turned round the corner, so the torch's body
    regains its travel angle only as the wall the run left falls behind. On
    the L100x100x10 cleat's R12 root (18.8 mm) with a 28 mm torch at 45 deg
    and 10 deg push, a lead of one run length left the tube 4.3 mm clear
    of the leg behind, 12 mm left it 7.7 mm deep, and at 15 deg push one run
    length was 8.4 mm deep where 1.5 were 4.4 mm clear. Half the neighbour
    leaves its other half to a lead or a corner at its other end.
    """
    return min(2.0 * float(run_length_mm), 0.5 * float(neighbour_length_mm))


def _concave(law):
    """True when `law` turns with a concave arc: its centre on the side the tool's body
    (-Z) leans to, at the arc's middle."""
    arc = law.arc
    if arc is None:
        return False
    middle = 0.5 * law.length
    body = -law.at(middle)[:, 2]
    return float(np.dot(arc.center - arc.point_at(middle), body)) > 1e-9 * arc.radius


def _concave_runs(laws, closed):
    """[[index, ...]] of the runs of consecutive concave arcs about one axis, in path order
    (on a closed path a run may wrap past the last segment); a whole closed loop is left out."""
    n = len(laws)
    concave = [_concave(law) for law in laws]

    def joined(i, j):
        return concave[i] and concave[j] and np.allclose(laws[i].arc.normal, laws[j].arc.normal, atol=1e-9)

    # A run starts where the segment before is not joined to it (a closed loop of joined
    # concave arcs has no start: nothing to lean into).
    starts = [i for i in range(n) if concave[i] and not ((i > 0 or closed) and joined((i - 1) % n, i))]
    runs = []
    for i in starts:
        run = [i]
        while (run[-1] + 1 < n or closed) and joined(run[-1], (run[-1] + 1) % n) and len(run) < n:
            run.append((run[-1] + 1) % n)
        runs.append(run)
    return runs


def _lean_through(laws, run, closed):
    """Lean the tool on the concave `run` (indices into `laws`) and lead the neighbours in."""
    n = len(laws)
    axis = laws[run[0]].arc.normal
    run_length = sum(laws[i].length for i in run)
    sweep = sum(laws[i].arc.sweep_rad for i in run)
    gamma = _lean_rad(_without_leads(laws[run[0]]))
    if abs(gamma) <= NO_LEAN_RAD:
        return
    g = min(abs(gamma), 0.5 * sweep)
    done = 0.0
    for i in run:
        law = _without_leads(laws[i])
        # Turn (about the axis) added to the arc's own law at its start and its end.
        lean0 = g * (1.0 - 2.0 * done / run_length) - gamma
        done += law.length
        lean1 = g * (1.0 - 2.0 * done / run_length) - gamma
        R_start = matrix_from_axis_angle(axis, lean0) @ law.at(0.0)
        laws[i] = SegmentOrientation(R_start, law.length, 0.0, law.arc,
                                     law.rate + (lean1 - lean0) / law.arc.sweep_rad, laws[i].leads)
    lean_in, lean_out = g - gamma, -g - gamma
    before = run[0] - 1 if run[0] > 0 else (n - 1 if closed else None)
    after = run[-1] + 1 if run[-1] + 1 < n else (0 if closed else None)
    if before is not None and before not in run and abs(lean_in) > 0.0:
        law = laws[before]
        lead = Lead(axis, lean_in, law.length, law.length - lead_length_mm(run_length, law.length))
        laws[before] = _with_lead(law, lead)
    if after is not None and after not in run and abs(lean_out) > 0.0:
        law = laws[after]
        laws[after] = _with_lead(law, Lead(axis, lean_out, 0.0, lead_length_mm(run_length, law.length)))


def _with_lead(law, lead):
    return SegmentOrientation(law.R_ref, law.length, law.s_ref, law.arc, law.rate, law.leads + (lead,))


def _without_leads(law):
    return SegmentOrientation(law.R_ref, law.length, law.s_ref, law.arc, law.rate)


def _lean_rad(law):
    """The tool's lean on a turning arc at its start, radians: the angle of the tool axis's
    component in the arc's plane from the outward radial direction, towards the travel
    (positive: pushing). It is the same all along the arc for ``rate = 1``."""
    arc = law.arc
    z = law.at(0.0)[:, 2]
    outward = (arc.start - arc.center) / arc.radius
    return float(np.arctan2(np.dot(z, arc.tangent_at(0.0)), np.dot(z, outward)))


def _along_axis(R, arc, tol=1e-9):
    """True when the tool axis (R's Z) is parallel to the arc's axis: turning with the arc
    would only spin the tool about its own axis (wrist travel for nothing, 360 degrees on
    a full circle), so the tool keeps its orientation there."""
    return abs(float(np.dot(np.asarray(R)[:, 2], arc.normal))) >= 1.0 - tol
