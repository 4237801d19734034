"""The document's solids as meshes: collision obstacles, workpieces for the sensors."""

import numpy as np

from .. import dependencies
from ..core.progress import report_now
from .base import global_placement, type_of


def is_final_solid(obj):
    """A solid nobody consumes: a Box used by a Cut is represented by the Cut."""
    shape = getattr(obj, "Shape", None)
    if shape is None or shape.isNull() or not shape.Solids or type_of(obj):
        return False
    if obj.TypeId in ("App::Part", "PartDesign::Body", "App::Link"):
        return False
    for user in obj.InList:
        if type_of(user):          # a CadRobot object links it (a positioner's Parts): not a use
            continue
        user_shape = getattr(user, "Shape", None)
        is_container = user.TypeId in ("App::Part", "App::DocumentObjectGroup", "PartDesign::Body")
        if not is_container and user_shape is not None and not user_shape.isNull() and user_shape.Solids:
            return False
    return True


def solid_meshes(doc, T_x_u, objects=None, tolerance_mm=1.0, progress=None):
    """Meshes of solids of `doc` in a frame {X}.

    Parameters
    ----------
    doc : App.Document
    T_x_u : ndarray, shape (4, 4)
        The assembly frame {U} in {X} (e.g. ``T_r_u`` for the robot base).
    objects : list of App.DocumentObject, optional
        Which solids; default every final solid of the document (CadRobot's
        own objects, such as tool markers, are never included).
    tolerance_mm : float
        Tessellation tolerance.
    progress : callable, optional
        ``progress(fraction, text)`` (``core.progress``), told solid by solid.

    Returns
    -------
    list of (str, trimesh.Trimesh)
        Label and mesh in {X}, mm.
    """
    trimesh = dependencies.require("trimesh")
    out = []
    solids = objects if objects is not None else [o for o in doc.Objects if is_final_solid(o)]
    for k, obj in enumerate(solids):
        report_now(progress, k / len(solids), "meshing %s" % obj.Label)
        shape = obj.Shape.copy()
        shape.Placement = global_placement(obj)
        points, faces = shape.tessellate(tolerance_mm)
        if not faces:
            continue
        vertices = np.array([(p.x, p.y, p.z) for p in points], dtype=float)
        vertices = vertices @ T_x_u[:3, :3].T + T_x_u[:3, 3]
        out.append((obj.Label, trimesh.Trimesh(vertices, np.array(faces, dtype=int), process=True)))
    return out
