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

from ... import dependencies
from ...core.frames import invert_transform
from ..kinematics.link_frames import link_frames
from . import package_files, urdf

trimesh = dependencies.require("trimesh")

#: Bodies in a meshes file (the order of :func:`link_frames`).
BODIES = 7
#: Most vertices kept of a hull.
MAX_VERTICES = 160


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


def shape_mesh(geometry, urdf_path, link=""):
    """One collision shape as a trimesh in its link's frame (mm), or None.

    Raises :class:`.package_files.MeshPathError` for a mesh outside the
    URDF's folder and package (``link`` names it in the message)."""
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
        try:
            mesh = trimesh.load(path, force="mesh")
        except Exception:   # an unreadable or unsupported file (e.g. .dae without pycollada)
            return None
        if not isinstance(mesh, trimesh.Trimesh) or len(mesh.vertices) == 0:
            return None
        mesh.apply_scale(np.asarray(geometry.scale) * urdf.MM_PER_M)
    return mesh.apply_transform(geometry.T_link_geom)


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
    hulls, missing = [], []
    for i, body in enumerate(chain.body_links):
        points = []
        for link, T_body_link in body:
            for geometry in robot.collisions.get(link, ()):
                mesh = shape_mesh(geometry, robot.path, link)
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
