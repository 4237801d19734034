"""A horizontal planar face of the document as the floor a robot may stand on (Place robot)."""

import numpy as np

import FreeCAD

from ..errors import InputError
from .base import describe
from .picking import element, global_shape, plane_of

#: A face counts as horizontal when its normal is within this angle of Z, degrees.
HORIZONTAL_TOL_DEG = 1.0
#: A grid position counts as on the face within this distance of it, mm.
ON_FACE_TOL_MM = 1e-3


def floor_face(item):
    """The face, its rectangle and its height.

    Parameters
    ----------
    item : (App.DocumentObject, str)
        An object and one of its faces, ``"FaceN"``.

    Returns
    -------
    face : Part.Face
        In {U}.
    region : tuple of 4 float
        ``(xmin, ymin, xmax, ymax)`` of the face's bounding box, mm.
    z_mm : float
        The face's height.

    Raises
    ------
    InputError
        Not an (object, "FaceN") pair, not a planar face, or not horizontal.
    """
    try:
        obj, name = item
    except (TypeError, ValueError):
        obj, name = None, ""
    if obj is None or not str(name).startswith("Face"):
        raise InputError("Give the face the robot may stand on as (object, 'FaceN'), not %r." % (item,))
    face = element(global_shape(obj), obj, name)
    plane = plane_of(face)
    if plane is None:
        raise InputError("%s %s is not planar: select a flat, horizontal face for the robot to stand "
                         "on." % (describe(obj), name), obj.Name)
    centre, normal = plane
    tilt = np.degrees(np.arccos(min(1.0, abs(float(normal[2])))))
    if tilt > HORIZONTAL_TOL_DEG:
        raise InputError("%s %s is tilted %.0f deg from horizontal: select a horizontal face (floor, "
                         "pedestal or table top) for the robot to stand on." % (describe(obj), name, tilt),
                         obj.Name)
    box = face.BoundBox
    return face, (box.XMin, box.YMin, box.XMax, box.YMax), float(centre[2])


def positions_on(face, x_mm, y_mm, z_mm):
    """Which grid positions lie on `face`.

    Parameters
    ----------
    face : Part.Face
    x_mm : ndarray, shape (nx,)
    y_mm : ndarray, shape (ny,)
    z_mm : float

    Returns
    -------
    ndarray of bool, shape (ny, nx)
    """
    return np.array([[face.isInside(FreeCAD.Vector(float(x), float(y), z_mm), ON_FACE_TOL_MM, True)
                      for x in x_mm] for y in y_mm], dtype=bool)
