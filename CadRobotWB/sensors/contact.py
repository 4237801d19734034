"""The ball tool touching the real workpiece: the virtual F/T sensor (paper 4.2).

::

    surface = MeshSurface(real_mesh)                       # the part as built, {U}
    rough = RoughnessProfile.from_reality(reality)         # heights along the path
    ball = BallContact(radius_mm=5.0, stiffness_n_mm=20.0)
    gap_mm, normal_u = ball.gap_mm(surface, T_u_t, rough.height_mm(s_mm))
    force_n = ball.normal_force_n(gap_mm)
    reading = ForceTorqueSensor(reality.force_noise_n, reality.seed).read(
        ball.wrench(T_u_t, normal_u, force_n))

Geometry. The tool is a ball of radius r on the flange; the TCP is the ball's
contact point on the surface, tool +Z points into the surface, so the ball's
centre is ``TCP - r * z``. The gap is the signed distance from the ball's
surface to the real surface, measured along the surface normal through the
centre: negative when the ball is pressed in.

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

import numpy as np
from scipy.spatial import cKDTree

from .. import dependencies
from ..errors import InputError

dependencies.require("trimesh")
from trimesh.triangles import closest_point as closest_point_on_triangles  # noqa: E402

#: Independent random streams drawn from one Reality seed.
ROUGHNESS_STREAM = 1
NOISE_STREAM = 2


class MeshSurface:
    """Nearest point on a triangle mesh, for one point at a time.

    A k-d tree over the triangle centroids gives the candidate triangles
    (every triangle whose centroid lies within the distance to the nearest
    centroid plus the largest centroid-to-vertex distance), then the exact
    closest point is taken among those. It needs no rtree (which trimesh's
    own proximity queries do).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The surface in {U}, mm. For a closed solid (``mesh.is_volume``) the
        face normals say which side is outside; an open sheet is taken to be
        outside on the side the tool comes from, and everywhere beyond its
        border.
    """

    def __init__(self, mesh):
        if mesh is None or len(mesh.faces) == 0:
            raise InputError("The real workpiece mesh is empty: give the part as a triangle mesh.")
        self.triangles = np.asarray(mesh.triangles, dtype=float)        # (M, 3, 3)
        self.face_normals = np.asarray(mesh.face_normals, dtype=float)  # (M, 3)
        self.is_volume = bool(mesh.is_volume)
        self.bounds = np.asarray(mesh.bounds, dtype=float)              # (2, 3)
        # border[f, j]: edge j of face f (vertex j to j + 1) belongs to no other face
        edges = np.sort(np.asarray(mesh.faces)[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
        _, inverse, counts = np.unique(edges, axis=0, return_inverse=True, return_counts=True)
        self.border = (counts[inverse.ravel()] == 1).reshape(-1, 3)
        centroids = self.triangles.mean(axis=1)
        self._tree = cKDTree(centroids)
        self._reach_mm = float(np.linalg.norm(self.triangles - centroids[:, None], axis=2).max())

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
        point = np.asarray(point_mm, dtype=float)
        centroid_distance, _ = self._tree.query(point)
        candidates = self._tree.query_ball_point(point, centroid_distance + self._reach_mm + 1e-9)
        candidates = np.asarray(candidates, dtype=int)
        closest = closest_point_on_triangles(self.triangles[candidates],
                                             np.broadcast_to(point, (len(candidates), 3)))
        distances = np.linalg.norm(closest - point, axis=1)
        best = int(np.argmin(distances))
        return closest[best], int(candidates[best]), float(distances[best])

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
        """Whether a ball touches the mesh (or lies inside it, for a solid).

        A bounding-box test first, so far-away objects cost nothing.
        """
        centre = np.asarray(centre_mm, dtype=float)
        lo, hi = self.bounds
        if np.any(centre < lo - radius_mm) or np.any(centre > hi + radius_mm):
            return False
        closest, face, distance = self.nearest(centre)
        if distance <= radius_mm:
            return True
        return self.is_volume and np.dot(centre - closest, self.face_normals[face]) < 0


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
        centre = self.centre_mm(T_u_t)
        closest, face, distance = surface.nearest(centre)
        face_normal = surface.face_normals[face]
        if not surface.is_volume and np.dot(face_normal, T_u_t[:3, 2]) > 0:
            face_normal = -face_normal                  # a sheet: outside faces the tool
        offset = centre - closest
        side = 1.0 if np.dot(offset, face_normal) >= 0 else -1.0
        if side < 0 and not surface.is_volume and surface.on_border(face, closest):
            side = 1.0                                  # beside a sheet, not under it
        normal = side * offset / distance if distance > 1e-9 else face_normal
        return side * distance - self.radius_mm - roughness_mm, normal

    def normal_force_n(self, gap_mm, gap_rate_mm_s=0.0):
        """Contact force along the normal, N (>= 0): ``k p + c dp/dt`` for ``p = -gap > 0``."""
        if gap_mm >= 0.0:
            return 0.0
        return max(0.0, -self.stiffness_n_mm * gap_mm - self.damping_n_s_mm * gap_rate_mm_s)

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
        R_u_t = T_u_t[:3, :3]
        force_t = R_u_t.T @ (-force_n * np.asarray(normal_u, dtype=float))
        contact_u = self.centre_mm(T_u_t) - self.radius_mm * np.asarray(normal_u, dtype=float)
        arm_t_mm = R_u_t.T @ (contact_u - T_u_t[:3, 3])
        return np.concatenate([force_t, _cross(arm_t_mm, force_t) / 1000.0])


def _cross(a, b):
    """Cross product of two (3,) vectors (np.cross is slow for one pair)."""
    return np.array([a[1] * b[2] - a[2] * b[1],
                     a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])


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
        if self.noise_n > 0:
            reading[:3] += self._rng.normal(0.0, self.noise_n, 3)
        return reading
