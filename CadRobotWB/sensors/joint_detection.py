"""Which sensor fits a path: a joint a laser can track, or a surface to follow with force.

The App layer samples the path (every ``SAMPLE_STEP_MM`` and at each
segment's middle) and, at each sample, describes the faces of the solids
that touch the path there as :class:`FaceSide` (one per side of the path a
face reaches: a face the path runs across the middle of gives two). This
module classifies each sample and then the whole path.

Kinds (the laser's kinds are those of :mod:`sensors.seam_features`)
-----------------------------------------------------------------
butt (laser)
    Two coplanar faces on either side of the path, of different solids, or
    of one solid with a gap between them (the path in the gap).
fillet (laser)
    Two faces meeting at a concave corner (each reaches into the free side
    of the other), the angle of free space between them
    ``CORNER_MIN_DEG``..``CORNER_MAX_DEG`` (90 for a T joint).
v_groove (laser)
    A concave corner narrower than ``V_GROOVE_MAX_DEG`` between faces of two
    different solids: two bevels sloping into a groove.
lap (laser)
    A concave corner where one face is the edge of a plate (it reaches no
    more than ``LAP_MAX_STEP_MM`` from the path) of another solid lying on
    the other face: the step the laser's lap template looks for.
convex_edge (force)
    Two faces meeting at a convex edge (an outside corner such as the top
    outer loop of a block): the laser sees a single bend, no joint.
surface (force)
    The path lies on one face (or on coplanar faces of one solid with no gap).
none (neither)
    No face of a solid touches the path.

The concave/convex test: a face's direction ``into`` (in the face, normal to
the travel, from the path into the face) points to the free side of the
other face (``into_a . normal_b > 0``) at a concave corner, into its material
at a convex one. Faces facing away from the tool (``normal . view < -0.1``,
``view`` = minus the approach direction) are left out: the underside of a
plate is not what the tool works on.

Pure numpy: never imports FreeCAD.
"""

from dataclasses import dataclass, field
from typing import List, Optional, Tuple

import numpy as np

from .seam_features import JointTemplate

#: Kinds a laser tracks (the seam template kinds) and kinds force follows.
LASER_KINDS = ("butt", "fillet", "lap", "v_groove")
FORCE_KINDS = ("surface", "convex_edge")
#: Kinds through-arc tracking can sense: sidewalls that slope toward the torch, so the
#: current changes across the weave (a square butt joint has none).
ARC_KINDS = ("fillet", "v_groove", "lap")
KINDS = LASER_KINDS + FORCE_KINDS + ("none",)
#: Path distance between samples, mm (plus each segment's middle).
SAMPLE_STEP_MM = 20.0
#: Angle of free space between the faces of a concave corner that a laser
#: recognises as a fillet, degrees.
CORNER_MIN_DEG = 30.0
CORNER_MAX_DEG = 150.0
#: A concave corner narrower than this between two solids is a V-groove, degrees.
V_GROOVE_MAX_DEG = 80.0
#: The plate edge of a lap joint reaches at most this far from the path, mm.
LAP_MAX_STEP_MM = 12.0
#: Two faces are coplanar when their normals are within this angle, degrees.
COPLANAR_DEG = 10.0
#: Faces at most this far (sum of both sides) from the path count as touching it
#: with no gap, mm.
NO_GAP_MM = 0.05
#: A face whose normal makes ``normal . view`` below this faces away from the tool.
FACING_AWAY = -0.1
#: Concave/convex threshold of ``into_a . normal_b``.
BEND_DOT = 0.05

#: How each sensor is named to the user.
SENSOR_NAMES = {"laser": "Laser seam tracking", "force": "Force profile following",
                "arc": "Through-arc seam tracking"}
#: Why a weld without a weave cannot be tracked by its arc.
NO_WEAVE = "through-arc tracking needs a weave: give the weld a weave"
#: Why through-arc tracking cannot track a square butt joint.
ARC_NO_SIDEWALLS = ("a square butt joint has no sidewalls: the current does not change across "
                    "the weave; use the laser")

_KIND_NAMES = {"butt": "butt joint", "fillet": "fillet (T) joint", "lap": "lap joint",
               "v_groove": "V-groove", "surface": "surface", "convex_edge": "convex edge",
               "none": "nothing"}


def not_offered_note(sensor, why):
    """``"Laser seam tracking: not offered, <why>."``, or "" when `why` is empty."""
    return "%s: not offered, %s." % (SENSOR_NAMES[sensor], why) if why else ""


def kind_name(kind):
    """How a kind is written in sentences ("fillet (T) joint", "convex edge", ...)."""
    return _KIND_NAMES[kind]


def sensor_of(kind):
    """``"laser"``, ``"force"`` or None (no sensor fits) for a detection kind."""
    if kind in LASER_KINDS:
        return "laser"
    if kind in FORCE_KINDS:
        return "force"
    return None


@dataclass
class FaceSide:
    """A face touching the path at one sample, on one side of the path.

    Attributes
    ----------
    solid : str
        Label of the solid the face belongs to.
    face : str
        The face's name in that solid (``"Face3"``).
    normal : ndarray, shape (3,)
        Outward unit normal of the face at the path, {U}.
    into : ndarray, shape (3,)
        Unit vector in the face, normal to the travel, from the path into
        the face, {U}.
    gap_mm : float
        Distance from the path to the face (0 when the path lies on it), mm.
    extent_mm : float
        How far the face reaches from the path along `into` (``inf``: farther
        than the App layer looked), mm.
    """

    solid: str
    face: str
    normal: np.ndarray
    into: np.ndarray
    gap_mm: float = 0.0
    extent_mm: float = float("inf")

    @property
    def label(self):
        """``"Solid.FaceN"``."""
        return "%s.%s" % (self.solid, self.face)

    def side(self, tangent, view):
        """``"left"`` or ``"right"`` of the travel `tangent` seen from `view` (3,)
        (the side toward the tool), or ``"ahead"`` for a face along the view."""
        left = np.cross(view, tangent)
        dot = float(np.dot(self.into, left))
        return "ahead" if abs(dot) < 1e-6 else ("left" if dot > 0 else "right")


@dataclass
class PathSample:
    """The path at one sample point.

    Attributes
    ----------
    s_mm : float
        Path distance from the start, mm.
    segment : int
        1-based segment number.
    point, tangent : ndarray, shape (3,)
        Position (mm) and unit travel direction, {U}.
    approach : ndarray, shape (3,) or None
        The tool's approach direction at the sample (its +Z, into the work,
        as the program turns it: :func:`approaches_at`); None when the path
        has no marker there (the faces' bisector is used).
    faces : list of FaceSide
    """

    s_mm: float
    segment: int
    point: np.ndarray
    tangent: np.ndarray
    approach: Optional[np.ndarray]
    faces: List[FaceSide] = field(default_factory=list)


@dataclass
class SampleKind:
    """What one sample is.

    Attributes
    ----------
    kind : str
        One of :data:`KINDS`.
    faces : tuple of FaceSide
        The faces that make it (two for joints and edges, one for a surface).
    angle_deg : float or None
        Corner and edge kinds: the angle of free space between the faces
        (concave) or of material (convex edge), degrees.
    gap_mm : float or None
        Butt: the gap between the faces, mm.
    step_mm : float or None
        Lap: height of the plate edge, mm.
    """

    kind: str
    faces: Tuple[FaceSide, ...] = ()
    angle_deg: Optional[float] = None
    gap_mm: Optional[float] = None
    step_mm: Optional[float] = None

    def what(self):
        """The sample described in words (the middle of the reason sentence)."""
        names = _face_names(self.faces)
        if self.kind == "surface":
            return "lies on %s" % names
        if self.kind == "none":
            return "touches no face of a solid"
        if self.kind == "convex_edge":
            return "runs along a convex edge between %s (outside corner, %.0f\u00b0)" % (
                names, self.angle_deg)
        if self.kind == "butt":
            gap = ("%.1f mm gap" % self.gap_mm) if self.gap_mm > NO_GAP_MM else "no gap"
            return "runs along a butt joint between %s (coplanar, %s)" % (names, gap)
        if self.kind == "lap":
            return "runs along a lap joint: the %.1f mm edge %s on %s" % (
                self.step_mm, self.faces[1].label, self.faces[0].label)
        return "runs along a %s between %s (concave corner, %.0f\u00b0)" % (
            kind_name(self.kind), names, self.angle_deg)


def _face_names(faces):
    """"Face3 and Face7 of Pocket011", or "PlateA.Face6 and PlateB.Face2"."""
    if not faces:
        return "no face"
    solids = {f.solid for f in faces}
    distinct = []
    for f in faces:
        if f.label not in [d.label for d in distinct]:
            distinct.append(f)
    if len(solids) == 1:
        names = [f.face for f in distinct]
        joined = names[0] if len(names) == 1 else " and ".join(names)
        return "%s of %s" % (joined, faces[0].solid)
    return " and ".join(f.label for f in distinct)


def _unit(v):
    v = np.asarray(v, dtype=float)
    n = np.linalg.norm(v)
    return v / n if n > 0 else v


def approaches_at(laws, stations):
    """The tool's approach direction at each sample station, as the program turns the tool.

    A tool that turns with an arc (``ToolOnArcs``) looks at the joint from the same
    side all round it: round a pipe's foot its approach turns with the circle, while
    the marker's own approach, kept, would look at the far side's wall from behind.

    Parameters
    ----------
    laws : sequence of core.segment_orientation.SegmentOrientation
        The tool's orientation along each segment of the path (``.at(s)`` ->
        R_u_t (3, 3) at arc length s mm from the segment's start).
    stations : sequence of (float, int, float)
        (path distance mm, 0-based segment index, arc length within that segment mm).

    Returns
    -------
    ndarray, shape (N, 3)
        Unit approach direction (the tool's +Z) per station, {U}.
    """
    return np.array([np.asarray(laws[index].at(s), float)[:, 2] for _, index, s in stations]
                    ).reshape(-1, 3)


def _view(sample):
    """Unit direction from the work toward the tool at `sample`."""
    if sample.approach is not None and np.linalg.norm(sample.approach) > 0:
        return -_unit(sample.approach)
    if sample.faces:
        total = np.sum([_unit(f.normal) for f in sample.faces], axis=0)
        if np.linalg.norm(total) > 1e-9:
            return _unit(total)
    return np.array([0.0, 0.0, 1.0])


def _angle_deg(u, v):
    return float(np.degrees(np.arccos(np.clip(np.dot(_unit(u), _unit(v)), -1.0, 1.0))))


def classify_sample(sample):
    """Classify the path at one sample.

    Parameters
    ----------
    sample : PathSample

    Returns
    -------
    SampleKind
        Concave corners (fillet, V-groove, lap) win over butt joints, butt
        joints over convex edges, and those over a single surface.
    """
    view = _view(sample)
    faces = [f for f in sample.faces if np.dot(_unit(f.normal), view) >= FACING_AWAY]
    if not faces:
        return SampleKind("none")
    corners, butts, edges = [], [], []
    for i in range(len(faces)):
        for j in range(i + 1, len(faces)):
            a, b = faces[i], faces[j]
            na, nb = _unit(a.normal), _unit(b.normal)
            between = _angle_deg(na, nb)
            if between <= COPLANAR_DEG:
                if np.dot(_unit(a.into), _unit(b.into)) < -0.5:
                    gap = a.gap_mm + b.gap_mm
                    if a.solid != b.solid or gap > NO_GAP_MM:
                        butts.append(SampleKind("butt", (a, b), gap_mm=gap))
                continue
            ab, ba = float(np.dot(_unit(a.into), nb)), float(np.dot(_unit(b.into), na))
            if ab > BEND_DOT and ba > BEND_DOT:
                corners.append(_corner(a, b, 180.0 - between, view))
            elif ab < -BEND_DOT and ba < -BEND_DOT:
                edges.append(SampleKind("convex_edge", (a, b), angle_deg=180.0 - between))
    corners = [c for c in corners if c is not None]
    if corners:
        # the corner the tool looks into most squarely
        return max(corners, key=lambda c: min(np.dot(_unit(f.normal), view) for f in c.faces))
    if butts:
        return min(butts, key=lambda c: c.gap_mm)
    if edges:
        return edges[0]
    return SampleKind("surface", (max(faces, key=lambda f: np.dot(_unit(f.normal), view)),))


def _corner(a, b, angle_deg, view):
    """SampleKind of the concave corner between faces a and b (free-space angle
    `angle_deg`), or None when the laser cannot recognise it."""
    if not CORNER_MIN_DEG <= angle_deg <= CORNER_MAX_DEG:
        return None
    if a.solid != b.solid:
        for lower, edge in ((a, b), (b, a)):
            if edge.extent_mm <= LAP_MAX_STEP_MM and lower.extent_mm > edge.extent_mm \
                    and abs(angle_deg - 90.0) <= 20.0:
                return SampleKind("lap", (lower, edge), angle_deg=angle_deg, step_mm=edge.extent_mm)
        if angle_deg < V_GROOVE_MAX_DEG:
            return SampleKind("v_groove", (a, b), angle_deg=angle_deg)
    return SampleKind("fillet", (a, b), angle_deg=angle_deg)


@dataclass
class JointDetection:
    """What the path is, for choosing its sensor.

    Attributes
    ----------
    kind : str
        The majority kind along the path (one of :data:`KINDS`).
    sensor : str or None
        ``"laser"``, ``"force"``, or None when neither fits.
    fraction : float
        Share of the path's length where `kind` holds, 0..1.
    reason : str
        One sentence: what the path is, along which faces, and which sensor.
    example : SampleKind
        A sample of the majority kind (its faces and measures).
    elsewhere : list of (str, float, float, list of int)
        The stretches of other kinds: kind, from and to path distance (mm),
        segment numbers.
    path : str
        The path's label.
    """

    kind: str
    sensor: Optional[str]
    fraction: float
    reason: str
    example: SampleKind
    elsewhere: list = field(default_factory=list)
    path: str = ""

    def fits(self, sensor):
        """True when `sensor` suits the path (the detected sensor; ``"arc"`` on
        the joints of :data:`ARC_KINDS`, whether the weld weaves is the weld's
        matter)."""
        if sensor == "arc":
            return self.kind in ARC_KINDS
        return sensor == self.sensor

    def why_not(self, sensor):
        """One sentence: why `sensor` does not suit the path ("" when it does)."""
        if self.fits(sensor):
            return ""
        what = self.example.what()
        if sensor == "arc":
            if self.kind == "butt":
                return ARC_NO_SIDEWALLS
            if self.kind == "none":
                return "the path %s: the arc has no joint to burn on" % what
            return ("the path has no joint: it %s; through-arc tracking senses the sidewalls "
                    "of a fillet, V-groove or lap joint" % what)
        if sensor == "laser":
            if self.kind == "none":
                return "the path %s: the laser has no joint to find" % what
            return "the path has no joint: it %s" % what
        if self.kind == "none":
            return "the path %s: the ball tool has no surface to press on" % what
        return ("the path is a seam: it %s; force following presses a ball tool on a "
                "surface and would not find the joint; track it with the laser" % what)

    def not_offered(self, sensor):
        """The one-line note of a sensor that does not suit the path ("" when it does):
        ``"Laser seam tracking: not offered, the path has no joint: it runs ..."``."""
        return not_offered_note(sensor, self.why_not(sensor))

    def reason_for(self, sensor):
        """:attr:`reason` with its advice said for `sensor`: through-arc tracking on
        a joint with walls gets its own (the reason's is the laser's)."""
        if sensor != "arc" or self.kind not in ARC_KINDS:
            return self.reason
        return self.reason.replace(_advice(self.kind), "a joint through-arc tracking can "
                                   "follow: its walls change the current across the weave")

    def run_anyway_note(self, sensor):
        """What a run's summary says once when the user asked for a sensor that
        does not suit the path ("" when it does)."""
        why = self.why_not(sensor)
        if not why:
            return ""
        return "%s was asked for although %s; it ran as asked." % (SENSOR_NAMES[sensor], why)

    def wall_angle_deg(self):
        """Angle of the joint's walls from the torch axis on the bisector, degrees, for
        through-arc tracking: half the corner's opening (45 for a T joint); 45 for a lap.
        None for the kinds the arc cannot sense."""
        if self.kind in ("fillet", "v_groove"):
            return round(self.example.angle_deg / 2.0, 1)
        return 45.0 if self.kind == "lap" else None

    def template(self):
        """The :class:`JointTemplate` the laser should look for, or None (not a joint).

        Fillet and V-groove take the measured corner angle, lap the measured
        step, butt the measured gap (at least the template's tolerance away
        from zero is kept as is)."""
        if self.kind not in LASER_KINDS:
            return None
        ex = self.example
        if self.kind in ("fillet", "v_groove"):
            return JointTemplate(self.kind, angle_deg=round(ex.angle_deg, 1))
        if self.kind == "lap":
            return JointTemplate("lap", step_mm=round(ex.step_mm, 2))
        return JointTemplate("butt", gap_mm=round(ex.gap_mm, 2))

    def to_dict(self):
        """Plain values for report.json."""
        return {"kind": self.kind, "sensor": self.sensor, "fraction": round(self.fraction, 4),
                "reason": self.reason, "path": self.path,
                "faces": [f.label for f in self.example.faces],
                "elsewhere": [{"kind": k, "from_mm": round(a, 1), "to_mm": round(b, 1),
                               "segments": list(segs)} for k, a, b, segs in self.elsewhere]}


def _advice(kind):
    if kind in LASER_KINDS:
        return "a joint the laser seam tracker can follow"
    if kind in FORCE_KINDS:
        return "no joint for a laser to find; follow the surface with force"
    return "neither sensor has anything to follow"


def _weights(samples):
    """Path length each sample stands for (half the distance to each neighbour), mm."""
    s = np.array([x.s_mm for x in samples], dtype=float)
    if len(s) == 1:
        return np.ones(1)
    edges = np.concatenate([[s[0]], (s[1:] + s[:-1]) / 2.0, [s[-1]]])
    w = np.diff(edges)
    return w if w.sum() > 0 else np.ones(len(s))


def detect_joint(samples, path_label=""):
    """Classify a path from its samples.

    Parameters
    ----------
    samples : list of PathSample
        In path order.
    path_label : str

    Returns
    -------
    JointDetection
        The majority kind (by path length), the share where it holds, the
        reason sentence, and where the path differs.
    """
    if not samples:
        empty = SampleKind("none")
        return JointDetection("none", None, 0.0, "The path has no samples: %s." % _advice("none"),
                              empty, [], path_label)
    samples = sorted(samples, key=lambda x: x.s_mm)
    kinds = [classify_sample(x) for x in samples]
    weights = _weights(samples)
    totals = {}
    for k, w in zip(kinds, weights):
        totals[k.kind] = totals.get(k.kind, 0.0) + w
    # ties go to the laser kinds first, then force (KINDS order)
    kind = max(totals, key=lambda k: (totals[k], -KINDS.index(k)))
    fraction = totals[kind] / float(sum(weights))
    example = _typical(kind, kinds)
    elsewhere = _stretches(samples, kinds, kind)
    name = ("path %s" % path_label) if path_label else "the path"
    sentence = "%s %s: %s" % (name[0].upper() + name[1:], example.what(), _advice(kind))
    if elsewhere:
        sentence += " (%.0f%% of its length; elsewhere %s)" % (100.0 * fraction, "; ".join(
            "%s at s = %.0f-%.0f mm (segment %s)" % (kind_name(k), a, b, ", ".join(map(str, segs)))
            for k, a, b, segs in elsewhere[:3]) + ("; ..." if len(elsewhere) > 3 else ""))
    return JointDetection(kind, sensor_of(kind), fraction, sentence + ".", example, elsewhere,
                          path_label)


def _typical(kind, kinds):
    """The sample of `kind` whose faces occur most often (named in the reason)."""
    of_kind = [k for k in kinds if k.kind == kind]
    counts = {}
    for k in of_kind:
        key = tuple(sorted(f.label for f in k.faces))
        counts[key] = counts.get(key, 0) + 1
    best = max(counts, key=counts.get)
    chosen = [k for k in of_kind if tuple(sorted(f.label for f in k.faces)) == best]
    if kind in ("fillet", "v_groove", "convex_edge"):
        angle = float(np.median([k.angle_deg for k in chosen]))
        return min(chosen, key=lambda k: abs(k.angle_deg - angle))
    return chosen[len(chosen) // 2]


def _stretches(samples, kinds, majority):
    """[(kind, s from, s to, segments)] of the runs of samples not of `majority`."""
    out = []
    for index, (x, k) in enumerate(zip(samples, kinds)):
        if k.kind == majority:
            continue
        if out and out[-1][0] == k.kind and out[-1][4] == index - 1:
            kind, a, _, segs, _ = out[-1]
            out[-1] = (kind, a, x.s_mm, segs | {x.segment}, index)
        else:
            out.append((k.kind, x.s_mm, x.s_mm, {x.segment}, index))
    return [(k, a, b, sorted(segs)) for k, a, b, segs, _ in out]
