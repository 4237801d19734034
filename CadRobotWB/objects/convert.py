"""Conversions between FreeCAD values and the core's numpy arrays.

The only place where FreeCAD placements become 4x4 matrices and back, so the
core never sees a FreeCAD type and quaternion orderings never mix.
"""

import FreeCAD
import numpy as np


def matrix_from_placement(placement):
    """ndarray, shape (4, 4): the homogeneous transform of a FreeCAD Placement (mm).
    ArgumentError for anything else (api.matrix_from_placement)."""
    if not isinstance(placement, FreeCAD.Placement):
        _refuse("matrix_from_placement", "placement", "a FreeCAD.Placement", placement)
    return np.array(placement.toMatrix().A, dtype=float).reshape(4, 4)


def placement_from_matrix(T):
    """FreeCAD.Placement of a rigid 4x4 transform `T` (mm). ArgumentError for anything but
    4x4 numbers (api.placement_from_matrix)."""
    try:
        matrix = np.asarray(T, dtype=float)
    except (TypeError, ValueError):
        matrix = None
    if matrix is None or matrix.shape != (4, 4):
        _refuse("placement_from_matrix", "T", "a 4x4 matrix of numbers (mm)", T)
    return FreeCAD.Placement(FreeCAD.Matrix(*matrix.ravel()))


def _refuse(function, argument, expected, value):
    """The API's one-line ArgumentError (these two are re-exported by api.py)."""
    from ..workflow.arguments import Arguments     # not at the top: workflow imports this module
    Arguments(function).refuse(argument, expected, value)


def array_from_vector(v):
    """ndarray, shape (3,): a FreeCAD.Vector as floats (mm)."""
    return np.array([v.x, v.y, v.z], dtype=float)


def vector_from_array(a):
    """FreeCAD.Vector from a length-3 sequence (mm)."""
    return FreeCAD.Vector(float(a[0]), float(a[1]), float(a[2]))
