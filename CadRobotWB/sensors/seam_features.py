"""Joint templates and seam feature extraction from a laser profile (paper 4.1.3, steps 2-3).

The camera is configured with the joint it must find (a :class:`JointTemplate`:
kind, nominal geometry, tolerances); :func:`extract_seam` finds that joint in
one profile and returns the seam point, or None.

Method
------
1. Runs: the valid points, split wherever a ray missed (NaN) or two
   neighbours are more than ``jump`` apart (``max(1 mm, 5 x the ray
   spacing)``): an edge the laser jumps over.
2. Split and merge (iterative end-point fit): a run is split at its point
   farthest from the chord between its ends while that distance exceeds
   ``line_tol_mm``; then neighbours that one line fits within
   ``line_tol_mm`` are merged again. Each piece then takes in the
   neighbouring points of its run that lie within ``line_tol_mm`` of its
   line (a point split off at an edge comes back) and is refitted by total
   least squares (principal axis).
3. Faces: pieces at least ``min_face_mm`` long (and 5 points); shorter ones
   (the table seen through a root gap, a lap's edge) are ignored.
4. Candidates: each pair of faces (i, i+1) and (i, i+2) in order across the
   line is measured as the template's kind (below), every measure is turned
   into a ratio ``|measured - nominal| / tolerance``; a pair matches when
   every ratio is <= 1, its score is ``1 - max(ratios)`` (1 = exactly the
   nominal joint, 0 = at the edge of a tolerance). The best-scoring pair
   wins; no match -> None.

Kinds (left face A, right face B, across the line; z grows away from the camera)
----------------------------------------------------------------------------
butt
    A and B parallel (``parallel_tol_deg``), at one height (mismatch at the
    gap centre <= ``mismatch_tol_mm``), the gap between A's last point and B's
    first (less one ray spacing) = ``gap_mm +- gap_tol_mm``. Seam point: the
    centre of the gap on the surface (mean of the two face lines there).
fillet (T joint)
    A and B meet at a concave corner, the angle between the faces
    ``angle_deg +- angle_tol_deg`` (90 for a T joint), their inner ends
    ``gap_mm +- gap_tol_mm`` apart. Seam point: where the two face lines
    intersect (the root of the corner).
lap
    A and B parallel, one higher by ``step_mm +- step_tol_mm`` (the upper
    plate's thickness), the lower face starting within ``gap_mm + gap_tol_mm``
    of the upper plate's edge. Seam point: the upper plate's edge (half a ray
    spacing past its last lit point) on the lower face's line: the corner
    the fillet weld fills.
v_groove
    A and B are the bevels: a concave corner with the included angle
    ``angle_deg +- angle_tol_deg``, their lower ends ``gap_mm +- gap_tol_mm``
    apart (the root opening). Seam point: where the two bevel lines meet
    (the root for a groove without root face; deeper otherwise).

The template's ``tcp_offset_mm`` (y, z) is where the torch should be relative
to the seam point (paper step 2: "the desired vertical and/or horizontal
distances"); :func:`extract_seam` returns the seam point itself.

Pure numpy: never imports FreeCAD.
"""

from dataclasses import dataclass
from typing import Optional, Tuple

import numpy as np

from ..errors import InputError

JOINT_KINDS = ("butt", "fillet", "lap", "v_groove")
#: Nominal gap and angle of each kind when the template does not give them.
DEFAULT_GAP_MM = {"butt": 1.5, "fillet": 0.0, "lap": 0.0, "v_groove": 0.0}
DEFAULT_ANGLE_DEG = {"fillet": 90.0, "v_groove": 60.0}


@dataclass
class JointTemplate:
    """The joint the camera looks for: nominal geometry and tolerances.

    Attributes
    ----------
    kind : str
        ``"butt"``, ``"fillet"``, ``"lap"`` or ``"v_groove"``.
    gap_mm : float, optional
        Butt: root gap (default 1.5); fillet: opening between the faces
        (default 0); lap: largest distance from the edge to the lower face's
        first lit point (default 0); v_groove: root opening between the
        bevels' lower ends (default 0). mm.
    angle_deg : float, optional
        Fillet: angle between the two faces (default 90, a T joint);
        v_groove: included angle of the groove (default 60). Degrees.
    step_mm : float
        Lap: thickness of the upper plate (height of the step), mm.
    gap_tol_mm, angle_tol_deg, step_tol_mm : float
        Tolerances of the above.
    mismatch_tol_mm : float
        Butt: largest height difference of the two plates at the gap, mm.
    parallel_tol_deg : float
        Butt and lap: largest angle between the two faces, degrees.
    min_face_mm : float
        Shortest piece of line that counts as a face, mm.
    line_tol_mm : float
        Split-and-merge tolerance: a face's points lie within this of its
        line, mm (a few times the laser noise).
    tcp_offset_mm : (float, float)
        Where the TCP should be relative to the seam point, (y, z) in the
        sensor frame, mm (negative z = above the joint, along -tool Z).
    """

    kind: str = "butt"
    gap_mm: Optional[float] = None
    angle_deg: Optional[float] = None
    step_mm: float = 3.0
    gap_tol_mm: float = 1.0
    angle_tol_deg: float = 15.0
    step_tol_mm: float = 1.0
    mismatch_tol_mm: float = 1.0
    parallel_tol_deg: float = 10.0
    min_face_mm: float = 3.0
    line_tol_mm: float = 0.2
    tcp_offset_mm: Tuple[float, float] = (0.0, 0.0)

    def __post_init__(self):
        if self.kind not in JOINT_KINDS:
            raise InputError("Unknown joint kind %r: use one of %s." % (self.kind, ", ".join(JOINT_KINDS)))
        if self.gap_mm is None:
            self.gap_mm = DEFAULT_GAP_MM[self.kind]
        if self.angle_deg is None:
            self.angle_deg = DEFAULT_ANGLE_DEG.get(self.kind, 0.0)
        tolerances = (self.gap_tol_mm, self.angle_tol_deg, self.step_tol_mm, self.mismatch_tol_mm,
                      self.parallel_tol_deg, self.line_tol_mm)
        if not all(t > 0 for t in tolerances) or not self.min_face_mm > 0:
            raise InputError("Joint template %r: every tolerance and the shortest face must be > 0."
                             % self.kind)


@dataclass
class SeamFeature:
    """The seam found in one profile.

    Attributes
    ----------
    y_mm, z_mm : float
        Seam point in the sensor frame, mm.
    score : float
        Match quality in [0, 1]: 1 - the largest deviation from the
        template, as a fraction of its tolerance.
    measures : dict
        What was measured (gap_mm, angle_deg, step_mm, mismatch_mm, ...).
    """

    y_mm: float
    z_mm: float
    score: float
    measures: dict


@dataclass
class Face:
    """A straight piece of the profile (total least-squares line).

    Attributes
    ----------
    first, last : ndarray, shape (2,)
        The end points (first and last point projected on the line), (y, z).
    centre : ndarray, shape (2,)
    direction : ndarray, shape (2,)
        Unit, pointing from `first` to `last`.
    n_points : int
    """

    first: np.ndarray
    last: np.ndarray
    centre: np.ndarray
    direction: np.ndarray
    n_points: int

    @property
    def length(self):
        return float(np.linalg.norm(self.last - self.first))

    def z_at(self, y):
        """z of the face's line at lateral position y (the line must not be vertical)."""
        return float(self.centre[1] + (y - self.centre[0]) * self.direction[1] / self.direction[0])


def fit_line(points):
    """Total least-squares line through (N, 2) points -> (centre (2,), unit direction (2,), max residual)."""
    centre = points.mean(axis=0)
    _, _, vt = np.linalg.svd(points - centre, full_matrices=False)
    direction = vt[0]
    if direction[0] < 0 or (direction[0] == 0 and direction[1] < 0):
        direction = -direction
    normal = np.array([-direction[1], direction[0]])
    residual = float(np.abs((points - centre) @ normal).max()) if len(points) > 2 else 0.0
    return centre, direction, residual


def _runs(profile, jump_mm):
    """Index arrays of the stretches of consecutive valid points without a jump."""
    valid = ~np.isnan(profile).any(axis=1)
    index = np.flatnonzero(valid)
    if len(index) == 0:
        return []
    points = profile[index]
    breaks = (np.diff(index) > 1) | (np.linalg.norm(np.diff(points, axis=0), axis=1) > jump_mm)
    return np.split(index, np.flatnonzero(breaks) + 1)


def _split(points, tol):
    """Iterative end-point fit: [(i, j)] inclusive index ranges of straight pieces."""
    pieces, stack = [], [(0, len(points) - 1)]
    while stack:
        i, j = stack.pop()
        if j - i < 2:
            pieces.append((i, j))
            continue
        chord = points[j] - points[i]
        length = np.linalg.norm(chord)
        rel = points[i + 1:j] - points[i]
        if length < 1e-12:
            distance = np.linalg.norm(rel, axis=1)
        else:
            distance = np.abs(rel[:, 0] * chord[1] - rel[:, 1] * chord[0]) / length
        k = int(np.argmax(distance))
        if distance[k] > tol:
            stack += [(i + 1 + k, j), (i, i + 1 + k)]
        else:
            pieces.append((i, j))
    return sorted(pieces)


def _merge(points, pieces, tol):
    """Merge neighbouring pieces that one line fits within `tol`."""
    merged = True
    while merged and len(pieces) > 1:
        merged = False
        for n in range(len(pieces) - 1):
            i, j = pieces[n][0], pieces[n + 1][1]
            if fit_line(points[i:j + 1])[2] <= tol:
                pieces[n:n + 2] = [(i, j)]
                merged = True
                break
    return pieces


def _grow(points, i, j, tol):
    """Extend the piece i..j over neighbouring points within `tol` of its line."""
    centre, direction, _ = fit_line(points[i:j + 1])
    normal = np.array([-direction[1], direction[0]])

    def near(k):
        return abs((points[k] - centre) @ normal) <= tol

    while i > 0 and near(i - 1):
        i -= 1
    while j < len(points) - 1 and near(j + 1):
        j += 1
    return i, j


def find_faces(profile, line_tol_mm=0.2, min_face_mm=3.0, min_points=5):
    """The straight faces of a profile, in order across the line.

    Parameters
    ----------
    profile : ndarray, shape (M, 2)
        (y, z) points, mm, ordered by y; NaN rows = no return.
    line_tol_mm, min_face_mm : float
        See :class:`JointTemplate`.
    min_points : int
        Fewest points of a face.

    Returns
    -------
    faces : list of Face
    spacing_mm : float
        Median distance between neighbouring lit points (the ray spacing).
    """
    profile = np.asarray(profile, dtype=float)
    valid = profile[~np.isnan(profile).any(axis=1)]
    if len(valid) < 2:
        return [], np.nan
    spacing = float(np.median(np.abs(np.diff(valid[:, 0]))))
    faces = []
    for run in _runs(profile, max(1.0, 5.0 * spacing)):
        points = profile[run]
        for i, j in _merge(points, _split(points, line_tol_mm), line_tol_mm):
            if j - i + 1 < min_points:
                continue
            i, j = _grow(points, i, j, line_tol_mm)
            chunk = points[i:j + 1]
            centre, direction, _ = fit_line(chunk)
            first = centre + ((chunk[0] - centre) @ direction) * direction
            last = centre + ((chunk[-1] - centre) @ direction) * direction
            face = Face(first, last, centre, direction, len(chunk))
            if face.length >= min_face_mm:
                faces.append(face)
    return faces, spacing


def _intersection(a, b):
    """Where the lines of faces a and b meet, (2,), or None when parallel."""
    m = np.column_stack([a.direction, -b.direction])
    if abs(np.linalg.det(m)) < 1e-9:
        return None
    t = np.linalg.solve(m, b.centre - a.centre)
    return a.centre + t[0] * a.direction


def _angle_deg(u, v):
    return float(np.degrees(np.arccos(np.clip(abs(u @ v), -1.0, 1.0))))


def _cross(u, v):
    return float(u[0] * v[1] - u[1] * v[0])


def _measure_butt(a, b, template, spacing):
    gap = b.first[0] - a.last[0] - spacing
    y = 0.5 * (a.last[0] + b.first[0])
    za, zb = a.z_at(y), b.z_at(y)
    measures = {"gap_mm": gap, "mismatch_mm": zb - za, "parallel_deg": _angle_deg(a.direction, b.direction)}
    ratios = [abs(gap - template.gap_mm) / template.gap_tol_mm,
              abs(zb - za) / template.mismatch_tol_mm,
              measures["parallel_deg"] / template.parallel_tol_deg]
    return (y, 0.5 * (za + zb)), ratios, measures


def _measure_corner(a, b, template, spacing):
    """Fillet and V-groove: a concave corner between faces a (left) and b (right)."""
    corner = _intersection(a, b)
    # Concave: turning from a's direction to b's turns toward the camera (-z).
    if corner is None or _cross(a.direction, b.direction) >= 0:
        return None
    # The corner must lie between the faces (a before it, b after it across the line).
    if not (a.first[0] < corner[0] + template.gap_tol_mm and corner[0] - template.gap_tol_mm < b.last[0]):
        return None
    angle = 180.0 - float(np.degrees(np.arccos(np.clip(a.direction @ b.direction, -1.0, 1.0))))
    opening = float(np.linalg.norm(b.first - a.last))
    measures = {"angle_deg": angle, "gap_mm": opening}
    ratios = [abs(angle - template.angle_deg) / template.angle_tol_deg,
              abs(opening - template.gap_mm) / template.gap_tol_mm]
    return (float(corner[0]), float(corner[1])), ratios, measures


def _measure_lap(a, b, template, spacing):
    y_mid = 0.5 * (a.last[0] + b.first[0])
    za, zb = a.z_at(y_mid), b.z_at(y_mid)
    if za < zb:       # a is the upper plate (nearer the camera): its right end is the edge
        edge_y = a.last[0] + 0.5 * spacing
        lower = b
        opening = b.first[0] - edge_y
    else:             # b is the upper plate: its left end is the edge
        edge_y = b.first[0] - 0.5 * spacing
        lower = a
        opening = edge_y - a.last[0]
    step = abs(zb - za)
    measures = {"step_mm": step, "gap_mm": opening, "parallel_deg": _angle_deg(a.direction, b.direction)}
    ratios = [abs(step - template.step_mm) / template.step_tol_mm,
              max(0.0, opening - template.gap_mm) / template.gap_tol_mm,
              measures["parallel_deg"] / template.parallel_tol_deg]
    return (float(edge_y), lower.z_at(edge_y)), ratios, measures


_MEASURES = {"butt": _measure_butt, "fillet": _measure_corner, "lap": _measure_lap,
             "v_groove": _measure_corner}


def extract_seam(profile, template):
    """Find the template's joint in one laser profile.

    Parameters
    ----------
    profile : ndarray, shape (M, 2)
        (y, z) points in the sensor frame, mm, ordered by y; NaN = no return.
    template : JointTemplate

    Returns
    -------
    SeamFeature or None
        The seam point of the best-matching pair of faces, or None when no
        pair matches the template within its tolerances.
    """
    faces, spacing = find_faces(profile, template.line_tol_mm, template.min_face_mm)
    measure = _MEASURES[template.kind]
    best = None
    for i in range(len(faces)):
        for j in (i + 1, i + 2):
            if j >= len(faces):
                continue
            a, b = faces[i], faces[j]
            if not (a.first[0] < b.first[0] and a.last[0] < b.last[0]) \
                    or abs(a.direction[0]) < 0.1 or abs(b.direction[0]) < 0.1:
                continue      # out of order, or a face seen edge-on
            result = measure(a, b, template, spacing)
            if result is None:
                continue
            point, ratios, measures = result
            worst = max(ratios)
            if worst <= 1.0 and (best is None or 1.0 - worst > best.score):
                best = SeamFeature(float(point[0]), float(point[1]), 1.0 - worst, measures)
    return best
