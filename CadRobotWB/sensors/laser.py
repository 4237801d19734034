"""The virtual laser-line sensor of seam tracking (paper 4.1).

A laser-triangulation camera (the paper's Servo Robot DIGI-I/S) rides on the
torch and projects a line of light across the joint, `look_ahead_mm` ahead of
the TCP; its camera returns the line's profile: the (y, z) coordinates of
each lit point in the sensor frame.

Sensor frame {S}: origin at the look-ahead point on the path, +X along the
travel, +Z along the tool axis (into the work), +Y = Z x X (the lateral
direction). The laser plane is the frame's Y-Z plane (normal to the travel).
The emitter sits ``emitter_mm`` behind the origin on -Z and fans
``n_points`` rays in that plane, evenly spread in angle, so that the line is
``line_width_mm`` wide at the origin's depth.

Ray casting. All rays lie in the laser plane, so a ray meets the mesh
exactly where it meets the mesh's *cross-section* by that plane. Each scan
therefore (1) cuts every triangle with the plane (vectorised: signed vertex
distances, the two crossing edges of each straddling triangle) into 2-D
segments, then (2) intersects the M rays with those S segments in 2-D
(an (M, S) solve) and keeps the nearest hit of each ray. This is exact,
needs no spatial index (trimesh's own ray queries need rtree or embree,
which we do not ship) and costs O(triangles + M·S) per scan: about 0.1 ms
for a few hundred triangles. Anything in the mesh occludes: foreign
objects are just more triangles.

Noise: each hit moves along its ray by a normal draw of RMS ``noise_mm``
(triangulation noise is a range error). Hits outside the depth range
``depth_range_mm`` (z in {S}) are out of the camera's view: NaN.

Pure numpy / trimesh: never imports FreeCAD.
"""

import numpy as np

from ..errors import InputError


class LaserScene:
    """The triangles the laser can see, in {U}.

    Parameters
    ----------
    meshes : trimesh.Trimesh or sequence of trimesh.Trimesh
        The real workpiece and every foreign object, in {U}, mm.
    """

    def __init__(self, meshes):
        if not isinstance(meshes, (list, tuple)):
            meshes = [meshes]
        triangles = [np.asarray(m.triangles, dtype=float).reshape(-1, 3, 3) for m in meshes
                     if m is not None and len(m.faces)]
        if not triangles:
            raise InputError("The laser has nothing to see: the real workpiece mesh is empty.")
        self.triangles = np.concatenate(triangles)          # (T, 3, 3)

    def section(self, T_u_s):
        """The scene cut by the laser plane (the Y-Z plane of {S}).

        Parameters
        ----------
        T_u_s : ndarray, shape (4, 4)
            Sensor frame in {U}, mm.

        Returns
        -------
        ndarray, shape (S, 2, 2)
            Segments, each two (y, z) end points in {S}, mm.
        """
        R, o = T_u_s[:3, :3], T_u_s[:3, 3]
        local = (self.triangles - o) @ R                      # (T, 3, 3) vertices in {S}
        x = local[..., 0]
        above = x >= 0.0
        count = above.sum(axis=1)
        cut = local[(count == 1) | (count == 2)]             # straddling triangles
        if len(cut) == 0:
            return np.zeros((0, 2, 2))
        xa = cut[..., 0] >= 0.0
        # The lone vertex (alone on its side) and its two neighbours: both
        # crossing edges start at it.
        lone = np.where(xa.sum(axis=1) == 1, np.argmax(xa, axis=1), np.argmin(xa, axis=1))
        rows = np.arange(len(cut))
        a = cut[rows, lone]
        b = cut[rows, (lone + 1) % 3]
        c = cut[rows, (lone + 2) % 3]
        p = a + (a[:, :1] / (a[:, :1] - b[:, :1])) * (b - a)
        q = a + (a[:, :1] / (a[:, :1] - c[:, :1])) * (c - a)
        return np.stack([p[:, 1:], q[:, 1:]], axis=1)


def laser_frame(origin_u, travel_u, tool_z_u):
    """Sensor frame {S} from a point, the travel direction and the tool axis.

    Parameters
    ----------
    origin_u : ndarray, shape (3,)
        Where the laser line crosses the path, {U}, mm.
    travel_u : ndarray, shape (3,)
        Travel direction (becomes +X; need not be unit).
    tool_z_u : ndarray, shape (3,)
        Tool axis (+Z after removing its part along the travel).

    Returns
    -------
    ndarray, shape (4, 4)
        T_u_s.
    """
    x = np.asarray(travel_u, dtype=float)
    x = x / np.linalg.norm(x)
    z = np.asarray(tool_z_u, dtype=float)
    z = z - (z @ x) * x
    norm = np.linalg.norm(z)
    if norm < 1e-9:
        raise InputError("The tool axis runs along the travel: the laser plane is undefined.")
    z = z / norm
    T = np.eye(4)
    T[:3, 0], T[:3, 1], T[:3, 2], T[:3, 3] = x, np.cross(z, x), z, origin_u
    return T


class LaserLineSensor:
    """A laser line camera on the torch.

    Parameters
    ----------
    look_ahead_mm : float
        Distance from the TCP to the laser line along the path, mm.
    line_width_mm : float
        Width of the projected line at the origin's depth, mm.
    n_points : int
        Points per profile (rays in the fan).
    emitter_mm : float
        Distance from the emitter to the sensor origin along -Z, mm.
    depth_range_mm : (float, float)
        Measuring range: z (in {S}) of the nearest and farthest point the
        camera sees, mm.
    noise_mm : float
        RMS range noise of each point, mm (``Reality.laser_noise_mm``).
    """

    def __init__(self, look_ahead_mm=30.0, line_width_mm=30.0, n_points=200, emitter_mm=100.0,
                 depth_range_mm=(-20.0, 20.0), noise_mm=0.02):
        if not look_ahead_mm >= 0:
            raise InputError("The laser's look-ahead must be >= 0 mm, got %r." % look_ahead_mm)
        if not line_width_mm > 0 or int(n_points) < 2:
            raise InputError("The laser line needs a width > 0 mm and >= 2 points, got %r mm, %r."
                             % (line_width_mm, n_points))
        if not emitter_mm > -depth_range_mm[0] or not depth_range_mm[1] > depth_range_mm[0]:
            raise InputError("The laser's depth range %r mm must lie beyond its emitter (%r mm)."
                             % (tuple(depth_range_mm), emitter_mm))
        if not noise_mm >= 0:
            raise InputError("The laser noise must be >= 0 mm, got %r." % noise_mm)
        self.look_ahead_mm = float(look_ahead_mm)
        self.line_width_mm = float(line_width_mm)
        self.n_points = int(n_points)
        self.emitter_mm = float(emitter_mm)
        self.depth_range_mm = (float(depth_range_mm[0]), float(depth_range_mm[1]))
        self.noise_mm = float(noise_mm)
        half = np.arctan2(self.line_width_mm / 2.0, self.emitter_mm)
        angles = np.linspace(-half, half, self.n_points)
        self.ray_directions = np.stack([np.sin(angles), np.cos(angles)], axis=1)   # (M, 2) y, z
        self.emitter_yz = np.array([0.0, -self.emitter_mm])

    @classmethod
    def from_reality(cls, reality, **options):
        """A sensor with the noise of `reality` (``laser_noise_mm``)."""
        options.setdefault("noise_mm", reality.laser_noise_mm)
        return cls(**options)

    def profile(self, T_u_s, scene, rng=None):
        """Scan the scene once.

        Parameters
        ----------
        T_u_s : ndarray, shape (4, 4)
            Sensor frame in {U} (see :func:`laser_frame`), mm.
        scene : LaserScene or trimesh.Trimesh
            What the laser sees, {U}.
        rng : numpy.random.Generator, optional
            Source of the noise; None = no noise.

        Returns
        -------
        ndarray, shape (n_points, 2)
            (y, z) of each lit point in {S}, mm, ordered by y; NaN where the
            ray hits nothing within the depth range.
        """
        if not isinstance(scene, LaserScene):
            scene = LaserScene(scene)
        t = self.ray_distances(scene.section(T_u_s))
        if rng is not None and self.noise_mm > 0:
            t = t + rng.normal(0.0, self.noise_mm, t.shape)
        points = self.emitter_yz + t[:, None] * self.ray_directions
        z = points[:, 1]
        with np.errstate(invalid="ignore"):
            outside = (z < self.depth_range_mm[0]) | (z > self.depth_range_mm[1])
        points[outside | np.isnan(t)] = np.nan
        return points

    def ray_distances(self, segments):
        """Distance from the emitter to the first hit of each ray, mm.

        Parameters
        ----------
        segments : ndarray, shape (S, 2, 2)
            The scene's cross-section, (y, z) in {S}.

        Returns
        -------
        ndarray, shape (n_points,)
            NaN where a ray meets no segment.
        """
        if len(segments) == 0:
            return np.full(self.n_points, np.nan)
        a = segments[:, 0] - self.emitter_yz                      # (S, 2)
        d = segments[:, 1] - segments[:, 0]                       # (S, 2)
        u = self.ray_directions                                   # (M, 2)
        denom = u[:, :1] * d[None, :, 1] - u[:, 1:] * d[None, :, 0]           # u x d, (M, S)
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (a[None, :, 0] * d[None, :, 1] - a[None, :, 1] * d[None, :, 0]) / denom
            w = (a[None, :, 0] * u[:, 1:] - a[None, :, 1] * u[:, :1]) / denom
            valid = (t > 0) & (w >= 0) & (w <= 1)
        t = np.where(valid, t, np.inf).min(axis=1)
        t[np.isinf(t)] = np.nan
        return t
