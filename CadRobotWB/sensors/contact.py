"""The ball tool touching the real workpiece: the virtual F/T sensor (paper 4.2).

::

    surface = MeshSurface(real_mesh)                       # the part as built, {U}
    rough = RoughnessProfile.from_reality(reality)         # heights along the path
    ball = BallContact(radius_mm=5.0, stiffness_n_mm=20.0)
    gap_mm, normal_u = ball.gap_mm(surface, T_u_t, rough.height_mm(s_mm))
    force_n = ball.normal_force_n(gap_mm)
    reading = ForceTorqueSensor(reality.force_noise_n, reality.seed).read(
        ball.wrench(T_u_t, normal_u, force_n))

Each has a form for many poses at once (``gaps_mm``, ``normal_forces_n``,
``wrenches``, ``MeshSurface.nearest_points``, ``ForceTorqueSensor.next_noise``):
force following computes a control period's steps together.

Geometry. The tool is a ball of radius r on the flange; the TCP is the ball's
contact point on the surface, tool +Z points into the surface, so the ball's
centre is ``TCP - r * z``. The gap is the signed distance from the ball's
surface to the real surface, measured along the surface normal through the
centre: negative when the ball is pressed in. Inside or outside a solid is
read from the angle-weighted pseudo-normal of the feature (face, edge,
corner) the closest point lies on, which is exact for a closed mesh; a ball
on an edge has its closest point on the edge, and one face's own normal
gets the side wrong where the faces meet at less than 90 degrees.

Contact law: a linear spring, plus an optional damper on the penetration rate,
``F = k * p + c * dp/dt`` while ``p > 0`` (never pulling). Why linear and not
Hertz: the force a position-controlled robot feels when its ball presses a part
is set by the softest element of the chain tool holder - F/T sensor - ball -
part clamping, and over the indentations of force following (tenths of a mm
to a few mm) that chain is close to a linear spring. The local Hertz
deformation of a steel ball on steel (``F ~ p**1.5``, about 2e4 N/mm at 20 N
for r = 5 mm) is in series with it and orders of magnitude stiffer, so it does
not change the force. A linear law also makes the controllers' tuning (gains
``~ 1/k``) exact. The contact is friction-free: the force lies along the
surface normal, no tangential force.

Roughness is a height field along the path distance (a sum of sinusoids drawn
from the reality's seed) added to the smooth mesh along its normal; the ball's
own filtering of wavelengths shorter than its radius is not modelled.

Pure numpy / scipy / trimesh: never imports FreeCAD.
"""

import math

import numpy as np
from scipy.spatial import cKDTree

from .. import dependencies
from ..errors import InputError

dependencies.require("trimesh")
from trimesh.constants import tol as tolerance  # noqa: E402

#: Independent random streams drawn from one Reality seed.
ROUGHNESS_STREAM = 1
NOISE_STREAM = 2
#: Points whose nearest points are looked up with one candidate set.
CLUSTER_SIZE = 16
#: Most point-triangle pairs computed at once (points far apart or far from the
#: mesh have many candidates: they are then split).
MAX_PAIRS = 100000


class MeshSurface:
    """Nearest point on a triangle mesh, for many points at once.

    A k-d tree over points sampled on the triangles (the centroids of a
    triangle's subdivision, so that long slivers of a CAD tessellation do not
    widen every query) gives the candidate triangles (for one point, every
    triangle with a sample within the distance to the nearest sample plus the
    largest sample-to-vertex distance; for a few points close together, one
    set holding each one's), then the exact closest point is taken among
    those. It needs no rtree (which trimesh's own proximity queries do).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The surface in {U}, mm. For a closed solid (``mesh.is_volume``) the
        angle-weighted pseudo-normal of the face, edge or corner a closest
        point lies on says which side is outside (:meth:`outward`); an open
        sheet is taken to be outside on the side the tool comes from, and
        everywhere beyond its border.
    """

    def __init__(self, mesh):
        if mesh is None or len(mesh.faces) == 0:
            raise InputError("The real workpiece mesh is empty: give the part as a triangle mesh.")
        self.triangles = np.asarray(mesh.triangles, dtype=float)        # (M, 3, 3)
        self.face_normals = np.asarray(mesh.face_normals, dtype=float)  # (M, 3)
        self.is_volume = bool(mesh.is_volume)
        self.bounds = np.asarray(mesh.bounds, dtype=float)              # (2, 3)
        self.border = _border_edges(np.asarray(mesh.faces))
        self.pseudo_normals = _pseudo_normals(np.asarray(mesh.faces), np.asarray(mesh.vertices),
                                              self.face_normals)        # (M, 7, 3)
        samples, self._sample_faces, self._reach_mm = _triangle_samples(self.triangles)
        self._tree = cKDTree(samples)
        self._edges = _TriangleEdges(self.triangles)

    def nearest(self, point_mm):
        """Closest point of the mesh to one point.

        Parameters
        ----------
        point_mm : array_like, shape (3,)

        Returns
        -------
        closest_mm : ndarray, shape (3,)
        face : int
            Index of the triangle the closest point lies on.
        distance_mm : float
            Unsigned distance from `point_mm` to `closest_mm`.
        """
        closest, faces, distances = self.nearest_points(np.reshape(point_mm, (1, 3)))
        return closest[0], int(faces[0]), float(distances[0])

    def nearest_points(self, points_mm):
        """Closest points of the mesh to many points.

        The points are taken :data:`CLUSTER_SIZE` at a time, each group with
        one set of candidate triangles (see :meth:`_candidates`): fast for
        points close together, such as the ball's centres over a control
        period.

        Parameters
        ----------
        points_mm : array_like, shape (N, 3)

        Returns
        -------
        closest_mm : ndarray, shape (N, 3)
        faces : ndarray of int, shape (N,)
            Index of the triangle each closest point lies on (the first
            candidate in the k-d tree's order when several are as close).
        distances_mm : ndarray, shape (N,)
            Unsigned distance from each point to its closest point.
        """
        return self.nearest_features(points_mm)[:3]

    def nearest_features(self, points_mm):
        """:meth:`nearest_points`, and on which feature of its triangle each
        closest point lies.

        Returns
        -------
        closest_mm, faces, distances_mm
            As :meth:`nearest_points`.
        features : ndarray of int, shape (N,)
            :data:`FEATURE_FACE` (inside the triangle), ``FEATURE_EDGE + j``
            (on its edge from corner j to corner j + 1) or ``FEATURE_CORNER + j``
            (on its corner j), j = 0, 1, 2: the row of :attr:`pseudo_normals`
            that says which side of the surface a point is on.
        """
        points = np.asarray(points_mm, dtype=float)
        if len(points) == 0:
            return (np.zeros((0, 3)), np.zeros(0, dtype=np.intp), np.zeros(0),
                    np.zeros(0, dtype=np.intp))
        return _joined([self._nearest_in_cluster(points[start:start + CLUSTER_SIZE])
                        for start in range(0, len(points), CLUSTER_SIZE)])

    def outward(self, points_mm, closest_mm, faces, features):
        """Whether each point lies outside a solid, from its closest point.

        The sign of ``(point - closest) . pseudo-normal`` of the feature the
        closest point lies on (Baerentzen and Aanaes, "Signed distance
        computation using the angle weighted pseudonormal", IEEE TVCG 11(3),
        2005): exact for a closed mesh, whatever the feature. A triangle's
        own normal is not: where the closest point lies on an edge, it is
        the same point for both triangles of the edge, and at an acute edge
        (the faces meeting at less than 90 degrees, material side) a point
        outside lies behind one of the two planes. On FreeCAD's
        Drilling_1 (Pocket011's top face meets an overhanging wall at 73
        degrees) that one plane put a ball 2.9 mm above the edge 2.9 mm
        inside the part: a gap of -7.9 mm and 160 N instead of -1.9 mm.

        Parameters
        ----------
        points_mm, closest_mm : ndarray, shape (N, 3)
        faces, features : ndarray of int, shape (N,)
            From :meth:`nearest_features`.

        Returns
        -------
        ndarray of bool, shape (N,)
            True outside (or on the surface).
        """
        normals = self.pseudo_normals[faces, features]
        return _row_dot(np.asarray(points_mm, dtype=float) - closest_mm, normals) >= 0

    def _nearest_in_cluster(self, points):
        """:meth:`nearest_points` of a few points (B, 3) against one candidate set."""
        lo, hi = points.min(axis=0), points.max(axis=0)
        half_diagonal = 0.5 * (hi - lo)                 # every point lies within its length of
        candidates = self._candidates(lo + half_diagonal, math.sqrt(half_diagonal @ half_diagonal))
        if len(points) > 1 and len(points) * len(candidates) > MAX_PAIRS:
            half = len(points) // 2                     # far apart, or far from the mesh
            return _joined([self._nearest_in_cluster(points[:half]),
                            self._nearest_in_cluster(points[half:])])
        closest, s, t = self._edges.closest_points(candidates, points, coordinates=True)
        offsets = closest - points[:, None]                                  # (B, K, 3)
        distances = np.sqrt(np.einsum("bki,bki->bk", offsets, offsets))      # (B, K)
        best = np.argmin(distances, axis=1)
        rows = np.arange(len(points))
        return (closest[rows, best], candidates[best], distances[rows, best],
                _feature(s[rows, best], t[rows, best]))

    def _candidates(self, centre_mm, spread_mm):
        """Triangles (K,) that may hold the closest point of any point within
        `spread_mm` of `centre_mm` (3,), in increasing order.

        Every point of a triangle lies within ``reach`` of one of its samples
        (:func:`_triangle_samples`). A point p's closest point then lies on a
        triangle with a sample within ``d0(p) + reach`` of p, d0 being the
        distance to the nearest sample (a sample is a point of the mesh: no
        triangle is further than ``d0(p)``). As ``d0(p) <= d0(c) + |p - c|``,
        every such sample lies within ``d0(c) + 2 |p - c| + reach`` of the
        centre c.
        """
        sample_distance, _ = self._tree.query(centre_mm)
        radius = sample_distance + 2.0 * spread_mm + self._reach_mm + 1e-9
        near = np.asarray(self._tree.query_ball_point(centre_mm, radius), dtype=np.intp)
        return np.unique(self._sample_faces[near])

    def on_border(self, face, point_mm, tol_mm=1e-9):
        """Whether `point_mm`, on triangle `face`, lies on an edge of the mesh's border."""
        a, b, c = self.triangles[face]
        # distance to edge j (vertex j to j + 1), j = 0, 1, 2
        for j, (p, q) in enumerate(((a, b), (b, c), (c, a))):
            if self.border[face, j]:
                t = np.clip(np.dot(point_mm - p, q - p) / np.dot(q - p, q - p), 0.0, 1.0)
                miss = np.linalg.norm(p + t * (q - p) - point_mm)
                if miss <= tol_mm * max(1.0, np.linalg.norm(q - p)):
                    return True
        return False

    def touches_ball(self, centre_mm, radius_mm):
        """Whether a ball touches the mesh (or lies inside it, for a solid)."""
        return bool(self.touches_balls(np.reshape(centre_mm, (1, 3)), radius_mm)[0])

    def touches_balls(self, centres_mm, radius_mm):
        """Which of many balls touch the mesh (or lie inside it, for a solid).

        A bounding-box test first, so far-away balls cost nothing.

        Parameters
        ----------
        centres_mm : array_like, shape (N, 3)
        radius_mm : float

        Returns
        -------
        ndarray of bool, shape (N,)
        """
        centres = np.asarray(centres_mm, dtype=float)
        lo, hi = self.bounds
        near = np.flatnonzero(np.all((centres >= lo - radius_mm) & (centres <= hi + radius_mm),
                                     axis=1))
        touching = np.zeros(len(centres), dtype=bool)
        if len(near) == 0:
            return touching
        closest, faces, distances, features = self.nearest_features(centres[near])
        touching[near] = distances <= radius_mm
        if self.is_volume:
            touching[near] |= ~self.outward(centres[near], closest, faces, features)
        return touching


def _border_edges(faces):
    """border[f, j] (M, 3): edge j of face f (vertex j to j + 1) belongs to no other face."""
    edges = np.sort(faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2).astype(np.int64), axis=1)
    keys = edges[:, 0] * (int(edges.max()) + 1) + edges[:, 1]          # one number per edge
    _, inverse, counts = np.unique(keys, return_inverse=True, return_counts=True)
    return (counts[inverse.ravel()] == 1).reshape(-1, 3)


#: Rows of :attr:`MeshSurface.pseudo_normals`: the face, its edges j (corner j to
#: j + 1), its corners j.
FEATURE_FACE, FEATURE_EDGE, FEATURE_CORNER = 0, 1, 4
#: Barycentric coordinates this close to 0 or 1 put a closest point on an edge or corner.
FEATURE_TOL = 1e-9


def _feature(s, t):
    """Feature (N,) of closest points ``a + s ab + t ac`` (s, t: (N,)), see FEATURE_*."""
    on_ab, on_ac, on_bc = t <= FEATURE_TOL, s <= FEATURE_TOL, s + t >= 1.0 - FEATURE_TOL
    feature = np.full(len(s), FEATURE_FACE, dtype=np.intp)
    feature[on_bc] = FEATURE_EDGE + 1
    feature[on_ac] = FEATURE_EDGE + 2
    feature[on_ab] = FEATURE_EDGE + 0
    feature[on_ab & on_ac] = FEATURE_CORNER + 0
    feature[on_ab & on_bc] = FEATURE_CORNER + 1
    feature[on_ac & on_bc] = FEATURE_CORNER + 2
    return feature


def _pseudo_normals(faces, vertices, face_normals):
    """Angle-weighted pseudo-normals (M, 7, 3) of every triangle's features.

    Row 0 the face's normal; rows 1-3 its edges j (corner j to j + 1): the
    sum of the normals of the triangles sharing the edge; rows 4-6 its
    corners j: the normals of the triangles around the vertex, each weighted
    by its angle there. Unit length (the face normal where a sum vanishes).
    Triangles share an edge or a corner only through shared vertex indices.
    """
    m = len(faces)
    pseudo = np.empty((m, 7, 3))
    pseudo[:, FEATURE_FACE] = face_normals
    edges = np.sort(faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2).astype(np.int64), axis=1)
    keys = edges[:, 0] * (int(faces.max()) + 1) + edges[:, 1]
    _, edge_ids = np.unique(keys, return_inverse=True)
    edge_ids = edge_ids.ravel()
    edge_sums = np.zeros((edge_ids.max() + 1, 3))
    np.add.at(edge_sums, edge_ids, np.repeat(face_normals, 3, axis=0))
    pseudo[:, FEATURE_EDGE:FEATURE_EDGE + 3] = edge_sums[edge_ids].reshape(m, 3, 3)
    corners = vertices[faces]                                           # (M, 3, 3)
    angles = np.empty((m, 3))
    for j in range(3):
        u = corners[:, (j + 1) % 3] - corners[:, j]
        w = corners[:, (j + 2) % 3] - corners[:, j]
        angles[:, j] = np.arctan2(np.linalg.norm(np.cross(u, w), axis=1), _row_dot(u, w))
    vertex_sums = np.zeros((len(vertices), 3))
    np.add.at(vertex_sums, faces.ravel(), (angles[:, :, None] * face_normals[:, None]).reshape(-1, 3))
    pseudo[:, FEATURE_CORNER:FEATURE_CORNER + 3] = vertex_sums[faces]
    lengths = np.linalg.norm(pseudo, axis=2)
    vanished = lengths < 1e-12
    pseudo = np.where(vanished[:, :, None], face_normals[:, None], pseudo)
    return pseudo / np.where(vanished, 1.0, lengths)[:, :, None]


#: Most k-d tree samples per triangle of the mesh, on average (bounds the memory
#: :func:`_triangle_samples` takes on a mesh of few, very unequal triangles).
MAX_SAMPLES_PER_TRIANGLE = 64


def _subdivision_centroids(n):
    """Barycentric weights (S, 2) of the centroids of a triangle cut into n x n
    similar triangles: point = a + u (b - a) + v (c - a); S = n * n."""
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    up = (i + j <= n - 1)
    down = (i + j <= n - 2)
    weights = [np.c_[i[up] + 1.0 / 3.0, j[up] + 1.0 / 3.0], np.c_[i[down] + 2.0 / 3.0, j[down] + 2.0 / 3.0]]
    return np.vstack(weights) / n


def _triangle_samples(triangles):
    """Points on each triangle such that every point of it is within `reach` of one.

    A triangle whose centroid-to-vertex distance is more than the median one is cut
    into n x n similar triangles, n the ratio rounded up; the samples are their
    centroids, and each of them lies within 1/n of that distance of its points.

    Parameters
    ----------
    triangles : ndarray, shape (M, 3, 3)

    Returns
    -------
    samples : ndarray, shape (S, 3)
    faces : ndarray of int, shape (S,)
        The triangle each sample lies on.
    reach_mm : float
        The largest distance from a point of a triangle to its nearest sample
        on that triangle (the largest sub-triangle centroid-to-vertex distance).
    """
    centroids = triangles.mean(axis=1)
    reach = np.linalg.norm(triangles - centroids[:, None], axis=2).max(axis=1)      # (M,)
    target = float(np.median(reach)) if len(reach) else 0.0
    cuts = np.ones(len(reach), dtype=int)
    if target > 0.0:
        cuts = np.maximum(1, np.ceil(reach / target - 1e-9).astype(int))
        while (cuts.astype(float) ** 2).sum() > MAX_SAMPLES_PER_TRIANGLE * len(reach):
            target *= 1.5
            cuts = np.maximum(1, np.ceil(reach / target - 1e-9).astype(int))
    samples, faces = [centroids[cuts == 1]], [np.flatnonzero(cuts == 1)]
    for n in np.unique(cuts[cuts > 1]):
        rows = np.flatnonzero(cuts == n)
        uv = _subdivision_centroids(int(n))                                           # (S, 2)
        a, b, c = triangles[rows, 0], triangles[rows, 1], triangles[rows, 2]
        points = (a[:, None] + uv[None, :, :1] * (b - a)[:, None]
                  + uv[None, :, 1:] * (c - a)[:, None])                               # (R, S, 3)
        samples.append(points.reshape(-1, 3))
        faces.append(np.repeat(rows, len(uv)))
    return (np.vstack(samples), np.concatenate(faces).astype(np.intp),
            float((reach / cuts).max()) if len(reach) else 0.0)


class _TriangleEdges:
    """Each triangle as a corner and two edges, for closest-point queries.

    The closest point on a triangle is found as in trimesh's
    ``triangles.closest_point`` (Ericson, Real-Time Collision Detection,
    5.1.5, with trimesh's zero tolerance and its handling of a triangle
    whose first two corners coincide), for every pair of a few points and a
    few triangles at once. What depends on the triangle alone is computed
    once: the edges' dot products and the denominators of the projections
    (``|ab|^2``, ``|ac|^2``, ``|bc|^2`` and the Gram determinant ``|ab x
    ac|^2``, which Ericson sums from the pair's terms), as reciprocals, 0
    for a degenerate triangle instead of a division by zero.

    Parameters
    ----------
    triangles : ndarray, shape (M, 3, 3)
        Corners a, b, c of each triangle, mm.
    """

    def __init__(self, triangles):
        ab = triangles[:, 1] - triangles[:, 0]
        ac = triangles[:, 2] - triangles[:, 0]
        ab_ab, ab_ac, ac_ac = _row_dot(ab, ab), _row_dot(ab, ac), _row_dot(ac, ac)
        denominators = np.stack([ab_ab, ac_ac, ab_ab - 2.0 * ab_ac + ac_ac,
                                 ab_ab * ac_ac - ab_ac * ab_ac], axis=1)
        reciprocals = np.divide(1.0, denominators, out=np.zeros_like(denominators),
                                where=denominators != 0)
        # one row per triangle: a, ab, ac (mm), ab.ab, ab.ac, ac.ac (mm^2), then
        # 1 / |ab|^2, 1 / |ac|^2, 1 / |bc|^2, 1 / |ab x ac|^2
        self.table = np.concatenate([triangles[:, 0], ab, ac, ab_ab[:, None], ab_ac[:, None],
                                     ac_ac[:, None], reciprocals], axis=1)
        self.collapsed_ab = np.all(ab == 0.0, axis=1)
        self.any_collapsed = bool(self.collapsed_ab.any())

    def closest_points(self, faces, points, coordinates=False):
        """Closest point on each triangle ``faces`` (K,) to each point (B, 3) -> (B, K, 3), mm.

        With `coordinates`, also s and t (B, K): the point is ``a + s ab + t ac``.
        """
        rows = self.table[faces]
        a, ab, ac = rows[:, 0:3], rows[:, 3:6], rows[:, 6:9]
        # ap . ab = p . ab - a . ab, with coordinates taken from the first point: small
        # numbers, so the difference keeps its digits.
        origin = points[0]
        local, a_local = points - origin, a - origin
        d1 = local @ ab.T - _row_dot(a_local, ab)                        # ab . ap, (B, K)
        d2 = local @ ac.T - _row_dot(a_local, ac)                        # ac . ap
        s, t = self._coordinates(d1, d2, rows[:, 9:].T)
        if self.any_collapsed:
            collapsed = self.collapsed_ab[faces]        # a = b: the segment ac (trimesh's case)
            along = np.minimum(np.maximum(d2 * rows[:, 13], 0.0), 1.0)
            s, t = np.where(collapsed, 0.0, s), np.where(collapsed, along, t)
        closest = a + s[:, :, None] * ab + t[:, :, None] * ac
        return (closest, s, t) if coordinates else closest

    @staticmethod
    def _coordinates(d1, d2, per_triangle):
        """Where each closest point lies: ``a + s ab + t ac``; returns s, t (B, K).

        `per_triangle` (7, K): ab.ab, ab.ac, ac.ac and the reciprocals of
        |ab|^2, |ac|^2, |bc|^2, |ab x ac|^2. The regions are tried in
        trimesh's order (corner a, corner b, edge ab, corner c, edge ac,
        edge bc, inside): the first that holds wins, so each is written
        over the later ones here.
        """
        ab_ab, ab_ac, ac_ac, per_ab, per_ac, per_bc, per_gram = per_triangle
        zero = tolerance.zero
        d3, d4 = d1 - ab_ab, d2 - ab_ac                 # ab . bp, ac . bp
        d5, d6 = d1 - ab_ac, d2 - ac_ac                 # ab . cp, ac . cp
        va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
        d43, d56 = d4 - d3, d5 - d6
        s, t = vb * per_gram, vc * per_gram
        region = (va < zero) & (d43 > -zero) & (d56 > -zero)
        on_bc = d43 * per_bc
        s, t = np.where(region, 1.0 - on_bc, s), np.where(region, on_bc, t)
        region = (vb < zero) & (d2 > -zero) & (d6 < zero)
        s, t = np.where(region, 0.0, s), np.where(region, d2 * per_ac, t)
        region = (d6 > -zero) & (d5 <= d6)
        s, t = np.where(region, 0.0, s), np.where(region, 1.0, t)
        region = (vc < zero) & (d1 > -zero) & (d3 < zero)
        s, t = np.where(region, d1 * per_ab, s), np.where(region, 0.0, t)
        region = (d3 > -zero) & (d4 <= d3)
        s, t = np.where(region, 1.0, s), np.where(region, 0.0, t)
        region = (d1 < zero) & (d2 < zero)
        return np.where(region, 0.0, s), np.where(region, 0.0, t)


def _joined(parts):
    """(closest, faces, distances) of consecutive groups of points, joined."""
    if len(parts) == 1:
        return parts[0]
    return tuple(np.concatenate(column) for column in zip(*parts))


def _row_dot(a, b):
    """Dot product of each row of `a` (N, 3) with the same row of `b` (N, 3) -> (N,)."""
    return np.einsum("ij,ij->i", a, b)


class RoughnessProfile:
    """Height of the real surface above its smooth shape along the path, mm.

    ``h(s) = sum_k a * sin(2 pi s / lambda_k + phi_k)`` with `n_waves` waves,
    wavelengths ``lambda_k`` log-uniform in [wavelength/2, 2 wavelength],
    phases uniform, and ``a = rms * sqrt(2 / n_waves)`` so the RMS height over
    a long path is `rms_mm`. Positive heights stick out of the part.

    Parameters
    ----------
    rms_mm : float
        RMS roughness height, mm (0 = smooth).
    wavelength_mm : float
        Typical distance between peaks, mm (> 0).
    seed : int
        Same seed, same surface.
    n_waves : int
    """

    def __init__(self, rms_mm, wavelength_mm, seed=0, n_waves=8):
        if rms_mm < 0 or not wavelength_mm > 0:
            raise InputError("Roughness needs an RMS height >= 0 and a wavelength > 0 mm, "
                             "got %r and %r." % (rms_mm, wavelength_mm))
        rng = np.random.default_rng([int(seed), ROUGHNESS_STREAM])
        self.rms_mm = float(rms_mm)
        self.wavelengths_mm = wavelength_mm * np.exp(rng.uniform(np.log(0.5), np.log(2.0), n_waves))
        self.phases_rad = rng.uniform(0.0, 2.0 * np.pi, n_waves)
        self.amplitude_mm = self.rms_mm * np.sqrt(2.0 / n_waves)

    @classmethod
    def from_reality(cls, reality):
        """The roughness a :class:`~.reality.Reality` describes."""
        return cls(reality.roughness_mm, reality.roughness_wavelength_mm, reality.seed)

    def height_mm(self, s_mm):
        """Heights at path distances `s_mm` (scalar or (N,)) -> same shape, mm."""
        s = np.asarray(s_mm, dtype=float)
        if self.rms_mm == 0.0:
            return np.zeros_like(s)
        angles = 2.0 * np.pi * s[..., None] / self.wavelengths_mm + self.phases_rad
        return self.amplitude_mm * np.sin(angles).sum(axis=-1)


class BallContact:
    """A ball tool pressed against the real surface: gap, force, wrench.

    Parameters
    ----------
    radius_mm : float
        Ball radius r, mm.
    stiffness_n_mm : float
        Contact stiffness k (tool, sensor, ball and part in series), N/mm.
    damping_n_s_mm : float
        Contact damping c on the penetration rate, N·s/mm (0 = none).
    """

    def __init__(self, radius_mm, stiffness_n_mm, damping_n_s_mm=0.0):
        if not radius_mm > 0 or not stiffness_n_mm > 0 or damping_n_s_mm < 0:
            raise InputError("The ball tool needs a radius > 0 mm and a contact stiffness > 0 N/mm "
                             "(damping >= 0), got %r, %r, %r."
                             % (radius_mm, stiffness_n_mm, damping_n_s_mm))
        self.radius_mm = float(radius_mm)
        self.stiffness_n_mm = float(stiffness_n_mm)
        self.damping_n_s_mm = float(damping_n_s_mm)

    def centre_mm(self, T_u_t):
        """Ball centre (3,) in {U}: the TCP moved back r along tool Z."""
        return T_u_t[:3, 3] - self.radius_mm * T_u_t[:3, 2]

    def gap_mm(self, surface, T_u_t, roughness_mm=0.0):
        """Signed distance of the ball to the real surface, and its normal.

        Parameters
        ----------
        surface : MeshSurface
            The real workpiece, {U}.
        T_u_t : ndarray, shape (4, 4)
            Where the TCP really is, {U}, mm.
        roughness_mm : float
            Roughness height of the surface here (raises it along its normal).

        Returns
        -------
        gap_mm : float
            From the ball's surface to the real surface along the normal
            through the ball's centre; negative = pressed in by ``-gap_mm``.
        normal_u : ndarray, shape (3,)
            Unit outward normal of the real surface at the contact (pointing
            from the part to the ball centre), {U}.
        """
        gaps, normals = self.gaps_mm(surface, T_u_t[None, :3, 3], T_u_t[None, :3, 2],
                                     roughness_mm)
        return float(gaps[0]), normals[0]

    def gaps_mm(self, surface, tcp_mm, tool_z, roughness_mm=0.0):
        """:meth:`gap_mm` for many TCP poses at once.

        Parameters
        ----------
        surface : MeshSurface
        tcp_mm : ndarray, shape (N, 3)
            Where the TCPs really are, {U}, mm.
        tool_z : ndarray, shape (N, 3)
            Their tool +Z axes (unit, into the surface), {U}.
        roughness_mm : float or ndarray, shape (N,)

        Returns
        -------
        gaps_mm : ndarray, shape (N,)
        normals_u : ndarray, shape (N, 3)
        """
        centres = tcp_mm - self.radius_mm * tool_z
        closest, faces, distances, features = surface.nearest_features(centres)
        face_normals = surface.face_normals[faces]
        offsets = centres - closest
        if surface.is_volume:                           # inside or out: the pseudo-normals
            sides = np.where(surface.outward(centres, closest, faces, features), 1.0, -1.0)
        else:                                           # a sheet: outside faces the tool
            face_normals = np.where((_row_dot(face_normals, tool_z) > 0)[:, None],
                                    -face_normals, face_normals)
            sides = np.where(_row_dot(offsets, face_normals) >= 0, 1.0, -1.0)
        if not surface.is_volume:
            for row in np.flatnonzero(sides < 0):
                if surface.on_border(faces[row], closest[row]):
                    sides[row] = 1.0                    # beside a sheet, not under it
        apart = distances > 1e-9
        if apart.all():
            normals = sides[:, None] * offsets / distances[:, None]
        else:                                           # the centre on the surface
            normals = np.where(apart[:, None], sides[:, None] * offsets
                               / np.where(apart, distances, 1.0)[:, None], face_normals)
        return sides * distances - self.radius_mm - roughness_mm, normals

    def normal_force_n(self, gap_mm, gap_rate_mm_s=0.0):
        """Contact force along the normal, N (>= 0): ``k p + c dp/dt`` for ``p = -gap > 0``."""
        return float(self.normal_forces_n(np.array([gap_mm], dtype=float), gap_rate_mm_s)[0])

    def normal_forces_n(self, gaps_mm, gap_rates_mm_s=0.0):
        """:meth:`normal_force_n` of gaps (N,) and their rates (N,) or scalar, mm/s -> (N,) N."""
        pressed = -self.stiffness_n_mm * gaps_mm - self.damping_n_s_mm * gap_rates_mm_s
        return np.where(gaps_mm >= 0.0, 0.0, np.maximum(0.0, pressed))

    def wrench(self, T_u_t, normal_u, force_n):
        """The wrench the tool applies to the part, in the tool frame.

        Parameters
        ----------
        T_u_t : ndarray, shape (4, 4)
            Actual TCP pose, {U}, mm.
        normal_u : ndarray, shape (3,)
            Outward unit normal of the part at the contact, {U}.
        force_n : float
            Normal contact force, N.

        Returns
        -------
        ndarray, shape (6,)
            Fx, Fy, Fz (N) and Tx, Ty, Tz (N·m) about the TCP, tool axes:
            pressing along the tool axis reads ``Fz = +force_n``. The force
            acts at the ball's contact point, so a surface tilted away from
            the tool axis also gives Fx, Fy and a torque.
        """
        return self.wrenches(T_u_t[None, :3, :3], np.reshape(normal_u, (1, 3)),
                             np.array([force_n], dtype=float))[0]

    def wrenches(self, R_u_t, normals_u, forces_n):
        """:meth:`wrench` for many contacts at once.

        The force ``-f n`` acts at the contact ``TCP - r z - r n``: its arm
        about the TCP is ``-r (z + n)``, in tool axes ``-r (e_z + n_t)``, so
        the torque is ``r f (e_z x n_t) = r f (-n_ty, n_tx, 0)``.

        Parameters
        ----------
        R_u_t : ndarray, shape (N, 3, 3)
            Tool orientations (rotation matrices), {U}.
        normals_u : ndarray, shape (N, 3)
            Outward unit normals of the part at the contacts, {U}.
        forces_n : ndarray, shape (N,)
            Normal contact forces, N.

        Returns
        -------
        ndarray, shape (N, 6)
        """
        normals_t = np.einsum("nji,nj->ni", R_u_t, normals_u)
        moment_n_m = self.radius_mm / 1000.0 * forces_n
        wrenches = np.empty((len(forces_n), 6))
        wrenches[:, :3] = -forces_n[:, None] * normals_t
        wrenches[:, 3] = -moment_n_m * normals_t[:, 1]
        wrenches[:, 4] = moment_n_m * normals_t[:, 0]
        wrenches[:, 5] = 0.0
        return wrenches


class ForceTorqueSensor:
    """Readings of the 6-axis F/T sensor: the true wrench plus white noise.

    Parameters
    ----------
    noise_n : float
        RMS noise of each force component, N (torques are read noise-free).
    seed : int
        Same seed, same noise.
    """

    def __init__(self, noise_n, seed=0):
        if noise_n < 0:
            raise InputError("The force noise must be >= 0 N, got %r." % noise_n)
        self.noise_n = float(noise_n)
        self._rng = np.random.default_rng([int(seed), NOISE_STREAM])

    def read(self, wrench):
        """One reading (6,) of the true wrench (6,): forces get the noise."""
        reading = np.array(wrench, dtype=float)
        reading[:3] += self.next_noise(1)[0]
        return reading

    def next_noise(self, count):
        """The force noise of the next `count` readings, (count, 3), N.

        The same numbers as `count` calls of :meth:`read` would add, in
        order (zeros when the sensor has no noise).
        """
        if self.noise_n > 0:
            return self._rng.normal(0.0, self.noise_n, (count, 3))
        return np.zeros((count, 3))
