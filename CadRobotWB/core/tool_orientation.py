"""Tool orientation from process angles (welding conventions).

The tool frame {T} has its origin on the path, +Z along the tool axis
pointing into the work, +X along the travel direction (made perpendicular
to Z) and Y = Z × X.
"""

import numpy as np

from ..errors import InputError


def _unit(v, what):
    v = np.asarray(v, dtype=float)
    norm = np.linalg.norm(v)
    if norm < 1e-12:
        raise InputError("The %s is a zero vector." % what)
    return v / norm


def tool_rotation(travel_dir, surface_normal, work_angle_deg=90.0, travel_angle_deg=0.0):
    """Rotation R_u_t of a tool held at a work angle and a travel angle.

    Parameters
    ----------
    travel_dir : array_like, shape (3,)
        Direction of travel along the seam.
    surface_normal : array_like, shape (3,)
        Normal of the work surface, pointing out of the material (towards
        the tool). Its component along `travel_dir` is ignored.
    work_angle_deg : float
        Angle between the tool axis and the surface, in the plane normal to
        the travel direction (90° = square to the surface; 45° for a fillet
        weld). Below 90° the tool leans to the side of -(travel × normal).
    travel_angle_deg : float
        Tilt of the tool axis towards the travel direction (positive =
        pushing, negative = dragging).

    Returns
    -------
    ndarray, shape (3, 3)
        Columns are the tool's X, Y, Z axes in the frame of the inputs.
    """
    d = _unit(travel_dir, "travel direction")
    n = np.asarray(surface_normal, dtype=float)
    n = _unit(n - np.dot(n, d) * d, "surface normal (parallel to the travel direction?)")
    side = np.cross(d, n)
    work = np.radians(work_angle_deg)
    travel = np.radians(travel_angle_deg)
    z0 = -np.sin(work) * n + np.cos(work) * side
    z = np.cos(travel) * z0 + np.sin(travel) * d
    x = _unit(d - np.dot(d, z) * z, "travel direction (along the tool axis?)")
    return np.column_stack([x, np.cross(z, x), z])
