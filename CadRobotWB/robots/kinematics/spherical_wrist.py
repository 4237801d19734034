"""PLACEHOLDER of part D (issue 24): the spherical-wrist solver's interface only.

The merge of branch ``ik-spherical`` replaces this whole file.  ``recognise``
checks the class (so the catalog and the URDF import can be built and
tested); ``inverse`` is not written here.

Pure numpy: never imports FreeCAD.
"""

import numpy as np

from .chain_geometry import axis_points, line_distance_mm

KIND = "spherical_wrist"
MAX_SOLUTIONS = 8

_DIRECTION_TOL = 1e-9
#: Placeholder: the KUKA files that round pi/2 miss a common wrist point by 2e-4 mm.
_WRIST_TOL_MM = 1e-3


def recognise(params):
    """The constants of an arm with axes 2 and 3 parallel and axes 4, 5, 6 meeting in one point.

    Raises
    ------
    ValueError
        Saying which condition fails.
    """
    points, H = axis_points(params), params.H
    if np.linalg.norm(np.cross(H[1], H[2])) > _DIRECTION_TOL:
        raise ValueError("axes 2 and 3 are not parallel")
    for i, j in ((3, 4), (4, 5), (3, 5)):
        if line_distance_mm(points[i], H[i], points[j], H[j]) > _WRIST_TOL_MM:
            raise ValueError("axes 4, 5 and 6 do not meet in a point")
    return params


def inverse(constants, T_0T):
    """Every solution, (N, 4, 4) mm -> (N, 8, 6) rad: written by part D."""
    raise NotImplementedError("spherical_wrist.inverse is part D of issue 24")
