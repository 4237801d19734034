"""Link solids of a robot read from a URDF: the convex hulls of its collision meshes.

A robot of the catalog table or imported from a URDF is drawn and
collision-checked with one convex hull per body (base and links 1-6, the
bodies of :func:`link_frames`), made from the URDF's collision shapes
(meshes, boxes, cylinders, spheres) of every link rigidly attached to that
body.  Hulls keep FCL exact and fast (:mod:`.collision` takes convex pieces)
and the file small: a body with no collision shape keeps its simple solid.

The hulls are kept in a compressed ``.npz`` file as their vertices only
(``vertices_<i>``, (V, 3) float32, mm, in body i's frame of
:func:`link_frames`, for the bodies that have one); the faces are the
convex hull of the vertices, made again when read.  A hull keeps at most
:data:`MAX_VERTICES` vertices, picked farthest-first from its own, so a
robot's file stays near 15 kB.

Pure numpy + trimesh: never imports FreeCAD.
"""

import io
import os

import numpy as np
from scipy.spatial import ConvexHull
from scipy.spatial import QhullError

from ... import dependencies
from ...errors import InputError
from ...core.frames import invert_transform
from ..kinematics.link_frames import link_frames
from . import package_files, urdf

trimesh = dependencies.require("trimesh")

#: Bodies in a meshes file (the order of :func:`link_frames`).
BODIES = 7
#: Most vertices kept of a hull.
MAX_VERTICES = 160
#: Triangles of a binary STL read at a time; each part is reduced to its convex hull's
#: points before the next is read (the link solid is the hull: nothing is lost), so a
#: 4-million-triangle (200 MB) STL takes tens of MB, not GBs.
TRIANGLES_PER_READ = 200000
#: Most triangles of a binary STL read (500 MB); past it the import is refused.
MAX_STL_TRIANGLES = 10 * 10 ** 6
#: Most bytes of mesh files read for one robot (the distinct files of all its links).
MAX_TOTAL_MESH_BYTES = 2 * 10 ** 9
#: Largest mesh file of another format (ASCII STL, OBJ, PLY, DAE, ...) read, bytes: trimesh
#: loads it whole; past it the import is refused.
MAX_OTHER_MESH_BYTES = 20 * 10 ** 6


def farthest_points(points, count):
    """`count` of `points` picked farthest-first (the first is the one farthest from their mean).

    Parameters
    ----------
    points : ndarray, shape (N, 3)
    count : int

    Returns
    -------
    ndarray, shape (min(N, count), 3)
    """
    if len(points) <= count:
        return points
    chosen = [int(np.argmax(np.linalg.norm(points - points.mean(axis=0), axis=1)))]
    distance = np.linalg.norm(points - points[chosen[0]], axis=1)
    for _ in range(count - 1):
        chosen.append(int(np.argmax(distance)))
        distance = np.minimum(distance, np.linalg.norm(points - points[chosen[-1]], axis=1))
    return points[chosen]


def shape_mesh(geometry, urdf_path, link="", cache=None):
    """One collision shape as a trimesh in its link's frame (mm), or None.

    A mesh file gives its convex hull only (all a link solid keeps): a binary STL is read :data:`TRIANGLES_PER_READ`
    triangles at a time, so memory stays bounded whatever its size.

    Parameters
    ----------
    geometry : urdf.Geometry
    urdf_path : str
    link : str
        The link, for messages.
    cache : dict, optional
        Hull points by mesh file, so a file named by many shapes is read once
        (and at most :data:`MAX_TOTAL_MESH_BYTES` are read in all).

    Returns
    -------
    trimesh.Trimesh or None
        None for a mesh that is missing or cannot be read.

    Raises
    ------
    package_files.MeshPathError
        A mesh outside the URDF's folder and package.
    InputError
        A mesh past its size bound (:data:`MAX_STL_TRIANGLES`,
        :data:`MAX_OTHER_MESH_BYTES`, :data:`MAX_TOTAL_MESH_BYTES` with `cache`), a binary STL whose header does not
        match its size, or a mesh with points that are not finite.
    """
    if geometry.kind == "box":
        mesh = trimesh.creation.box(geometry.size_mm)
    elif geometry.kind == "cylinder":
        radius, length = geometry.size_mm
        mesh = trimesh.creation.cylinder(radius, length, sections=24)
    elif geometry.kind == "sphere":
        mesh = trimesh.creation.icosphere(subdivisions=2, radius=geometry.size_mm[0])
    else:
        path = package_files.mesh_path(geometry.filename, urdf_path, link)
        if path is None:
            return None
        cache = {} if cache is None else cache
        if path not in cache:
            what = "URDF link '%s': mesh '%s'" % (link, geometry.filename)
            if sum(os.path.getsize(p) for p in list(cache) + [path]) > MAX_TOTAL_MESH_BYTES:
                raise InputError("%s: the robot's mesh files together are more than %d MB, the "
                                 "most CadRobot reads for one robot: reduce them (a link solid is "
                                 "their convex hull) and import again."
                                 % (what, MAX_TOTAL_MESH_BYTES // 10 ** 6))
            cache[path] = mesh_points(path, what)
        if cache[path] is None:
            return None
        mesh = _hull_mesh(cache[path])
        mesh.apply_scale(np.asarray(geometry.scale) * urdf.MM_PER_M)
    return mesh.apply_transform(geometry.T_link_geom)


def mesh_points(path, what):
    """The convex hull's points of a mesh file (its own unit), or None when it cannot be read.

    Parameters
    ----------
    path : str
    what : str
        The link and mesh, for messages.

    Returns
    -------
    ndarray, shape (V, 3) or None
    """
    count = binary_stl_triangles(path, what)
    if count is not None:
        if count > MAX_STL_TRIANGLES:
            raise InputError("%s has %d triangles, more than the %d CadRobot reads: reduce it (a "
                             "link solid is its convex hull) and import again."
                             % (what, count, MAX_STL_TRIANGLES))
        points = _binary_stl_hull_points(path, count)
    else:
        size = os.path.getsize(path)
        if size > MAX_OTHER_MESH_BYTES:
            raise InputError("%s is %d MB, more than the %d MB CadRobot reads of a mesh that is "
                             "not a binary STL: save it as binary STL or reduce it, and import "
                             "again." % (what, size // 10 ** 6, MAX_OTHER_MESH_BYTES // 10 ** 6))
        try:
            mesh = trimesh.load(path, force="mesh")
        except Exception:   # an unreadable or unsupported file (e.g. .dae without pycollada)
            return None
        if not isinstance(mesh, trimesh.Trimesh) or len(mesh.vertices) == 0:
            return None
        points = np.asarray(mesh.vertices, dtype=float)
    if not np.isfinite(points).all():
        raise InputError("%s has points that are not finite numbers (NaN or inf): repair the "
                         "mesh and import again." % what)
    return _hull_points(points)


def binary_stl_triangles(path, what):
    """The triangle count of a binary STL from its header, or None for another file.

    A file named ``.stl`` that does not start with ``solid`` (an ASCII STL)
    must be exactly 84 + 50 x count bytes; read before anything else.

    Raises
    ------
    InputError
        A binary STL whose header count does not match its size.
    """
    with open(path, "rb") as stream:
        header = stream.read(84)
    size = os.path.getsize(path)
    if len(header) == 84:
        count = int(np.frombuffer(header[80:], dtype="<u4")[0])
        if size == 84 + 50 * count:
            return count
    if not path.lower().endswith(".stl") or header.lstrip().lower().startswith(b"solid"):
        return None
    raise InputError("%s is not a valid binary STL: its header says %s triangles (%s bytes) but "
                     "the file has %d bytes; export the mesh again."
                     % (what, count if len(header) == 84 else "no",
                        84 + 50 * count if len(header) == 84 else "84", size))


_STL_TRIANGLE = np.dtype([("normal", "<f4", (3,)), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])


def _binary_stl_hull_points(path, count):
    """Hull points of a binary STL, read TRIANGLES_PER_READ triangles at a time."""
    kept = np.empty((0, 3))
    with open(path, "rb") as stream:
        stream.seek(84)
        for start in range(0, count, TRIANGLES_PER_READ):
            block = np.fromfile(stream, dtype=_STL_TRIANGLE, count=min(TRIANGLES_PER_READ,
                                                                      count - start))
            kept = _hull_points(np.vstack([kept, block["corners"].reshape(-1, 3)]))
    return kept


def _hull_mesh(points):
    """The convex hull of `points` (N, 3) as a trimesh; just the points when they span no volume."""
    try:
        return trimesh.convex.convex_hull(points, qhull_options="QbB Pp QJ")
    except (QhullError, ValueError, IndexError):
        return trimesh.Trimesh(vertices=points, process=False)


def _hull_points(points):
    """The points of `points` (N, 3) on their convex hull (all of them when fewer than 5
    or not finite; joggled for flat sets)."""
    if len(points) < 5 or not np.isfinite(points).all():
        return points
    try:
        return points[ConvexHull(points, qhull_options="QJ").vertices]
    except QhullError:   # all on one line or point
        return np.unique(points, axis=0)


def body_hulls(robot, chain, T_link_chain):
    """The convex hull of each body's collision shapes.

    Parameters
    ----------
    robot : urdf.UrdfRobot
        Its ``path`` locates the mesh files (:func:`.package_files.mesh_path`).
    chain : urdf.Chain
    T_link_chain : ndarray, shape (7, 4, 4)
        The chain's body frame i in the catalog model's link frame i (both
        move with the same body, so it is constant), mm.

    Returns
    -------
    hulls : list of 7 (trimesh.Trimesh or None)
        In the catalog model's link frames; None for a body without shapes.
    missing : list of str
        Mesh files that could not be found or read.
    """
    hulls, missing, cache = [], [], {}
    for i, body in enumerate(chain.body_links):
        points = []
        for link, T_body_link in body:
            for geometry in robot.collisions.get(link, ()):
                mesh = shape_mesh(geometry, robot.path, link, cache)
                if mesh is None:
                    missing.append(geometry.filename)
                    continue
                points.append(trimesh.transform_points(mesh.vertices, T_link_chain[i] @ T_body_link))
        if not points:
            hulls.append(None)
            continue
        hull = trimesh.Trimesh(np.vstack(points)).convex_hull
        hull = trimesh.Trimesh(farthest_points(hull.vertices, MAX_VERTICES)).convex_hull
        hulls.append(hull if hull.volume > 0 else None)
    return hulls, missing


def save(path, hulls):
    """Write hulls to a compressed ``.npz`` file atomically.

    Parameters
    ----------
    path : str
    hulls : list of 7 (trimesh.Trimesh or None)
    """
    arrays = {}
    for i, hull in enumerate(hulls):
        if hull is not None:
            arrays["vertices_%d" % i] = np.asarray(hull.vertices, dtype=np.float32)
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **arrays)
    temporary = path + ".tmp"
    try:
        with open(temporary, "wb") as stream:
            stream.write(buffer.getvalue())
        os.replace(temporary, path)
    except OSError:
        if os.path.exists(temporary):
            os.remove(temporary)
        raise


def load(path):
    """Read the hulls of a meshes file.

    Returns
    -------
    list of 7 (trimesh.Trimesh or None)
    """
    with np.load(path) as data:
        return [trimesh.Trimesh(data["vertices_%d" % i].astype(float)).convex_hull
                if "vertices_%d" % i in data else None for i in range(BODIES)]


def replace_parts(parts, path):
    """Simple-solid pieces per body with each body's hull put in their place where there is one.

    Parameters
    ----------
    parts : list of 7 lists of trimesh.Trimesh
    path : str
        A meshes file; when it cannot be read the simple solids stay.

    Returns
    -------
    list of 7 lists of trimesh.Trimesh
    """
    try:
        hulls = load(path)
    except (OSError, KeyError, ValueError):
        return parts
    return [[hull] if hull is not None else pieces for hull, pieces in zip(hulls, parts)]


def chain_in_link_frames(model, chain):
    """``T_link_chain`` for :func:`body_hulls`: each chain body frame in the model's link frame.

    Parameters
    ----------
    model : RobotModel
        Built from `chain` (its base is the chain's root link).
    chain : urdf.Chain

    Returns
    -------
    ndarray, shape (7, 4, 4)
    """
    T_r_link = link_frames(model, np.zeros(6))
    T_r_chain = urdf.chain_frames(chain, np.zeros((1, 6)))[0][0]
    return np.array([invert_transform(T_r_link[i]) @ T_r_chain[i] for i in range(BODIES)])
