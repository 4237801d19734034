"""PLACEHOLDER of part C (issue 24): the offset-wrist solver's interface only.

The merge of branch ``ik-offset`` replaces this whole file.  ``recognise``
checks the class (so the catalog and the URDF import can be built and
tested); ``inverse`` is not written here.

Pure numpy: never imports FreeCAD.
"""

import numpy as np

from .chain_geometry import axis_points, line_distance_mm

KIND = "offset_wrist"
MAX_SOLUTIONS = 16

_DIRECTION_TOL = 1e-9
#: Placeholder: the KUKA files that round pi/2 miss a common wrist point by 2e-4 mm.
_WRIST_TOL_MM = 1e-3


def recognise(params):
    """The constants of an offset-wrist arm: axes 2 and 3 parallel, axis 4 perpendicular
    to them, axes 4, 5 and 6 not meeting in one point (placeholder test: part C's
    ``recognise`` decides).

    Raises
    ------
    ValueError
        Saying which condition fails.
    """
    points, H = axis_points(params), params.H
    if np.linalg.norm(np.cross(H[1], H[2])) > _DIRECTION_TOL:
        raise ValueError("axes 2 and 3 are not parallel")
    if abs(H[1] @ H[3]) > _DIRECTION_TOL:
        raise ValueError("axis 4 is not perpendicular to axes 2 and 3")
    if max(line_distance_mm(points[i], H[i], points[j], H[j])
           for i, j in ((3, 4), (4, 5), (3, 5))) <= _WRIST_TOL_MM:
        raise ValueError("axes 4, 5 and 6 meet in a point: a spherical wrist")
    return params


def inverse(constants, T_0T):
    """Every solution, (N, 4, 4) mm -> (N, 16, 6) rad: written by part C."""
    raise NotImplementedError("offset_wrist.inverse is part C of issue 24")
