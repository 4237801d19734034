"""The document's solids as collision obstacles for a cell's robot."""

import numpy as np

from .base import global_placement, type_of


def _is_final_solid(obj):
    """A solid nobody consumes: a Box used by a Cut is represented by the Cut."""
    shape = getattr(obj, "Shape", None)
    if shape is None or shape.isNull() or not shape.Solids or type_of(obj):
        return False
    if obj.TypeId in ("App::Part", "PartDesign::Body", "App::Link"):
        return False
    for user in obj.InList:
        user_shape = getattr(user, "Shape", None)
        is_container = user.TypeId in ("App::Part", "App::DocumentObjectGroup", "PartDesign::Body")
        if not is_container and user_shape is not None and not user_shape.isNull() and user_shape.Solids:
            return False
    return True


def cell_obstacles(cell, T_r_u, tolerance_mm=1.0):
    """Meshes of every final solid in the cell's document, in the robot base {R}.

    Parameters
    ----------
    cell : App.DocumentObject
        The cell; CadRobot's own objects (tool markers, ...) are never obstacles.
    T_r_u : ndarray, shape (4, 4)
        The assembly frame {U} in the robot base {R}, mm.
    tolerance_mm : float
        Tessellation tolerance.

    Returns
    -------
    list of (str, trimesh.Trimesh)
        Label and mesh, mm.
    """
    import trimesh
    out = []
    for obj in cell.Document.Objects:
        if not _is_final_solid(obj):
            continue
        shape = obj.Shape.copy()
        shape.Placement = global_placement(obj)
        points, faces = shape.tessellate(tolerance_mm)
        if not faces:
            continue
        vertices = np.array([(p.x, p.y, p.z) for p in points], dtype=float)
        vertices = vertices @ T_r_u[:3, :3].T + T_r_u[:3, 3]
        out.append((obj.Label, trimesh.Trimesh(vertices, np.array(faces, dtype=int), process=True)))
    return out

