"""Normals and frames from picked CAD geometry (pure numpy, no FreeCAD).

The App layer finds the faces and edges; this module does the vector math:
the normal a tool must face on an edge between several faces, and a frame
from a face normal and an edge lying in that face.
"""

import numpy as np

from ..errors import FrameError, InputError
from .frames import make_transform

# Normals closer than this (radians) to cancelling out give no bisector.
MIN_BISECTOR_NORM = 1e-6


def bisector(normals):
    """The unit bisector of unit surface normals: their normalised sum.

    Parameters
    ----------
    normals : array_like, shape (N, 3)
        Outward normals of the faces meeting at an edge (N >= 1); repeated
        normals (coplanar faces, e.g. two plates either side of a gap)
        count once.

    Returns
    -------
    ndarray, shape (3,)
        Unit vector; for one normal that normal, for two the bisector of
        the angle between them (e.g. (0, -1, 1)/sqrt(2) for the -Y and +Z
        faces of a box edge).

    Raises
    ------
    InputError
        No normals, or normals that cancel out (faces back to back).
    """
    N = np.asarray(normals, dtype=float).reshape(-1, 3)
    if len(N) == 0:
        raise InputError("No face normal to orient the tool from.")
    units = N / np.linalg.norm(N, axis=1)[:, None]
    distinct = []
    for n in units:
        if not any(np.dot(n, m) > 1.0 - 1e-9 for m in distinct):
            distinct.append(n)
    total = np.sum(distinct, axis=0)
    norm = np.linalg.norm(total)
    if norm < MIN_BISECTOR_NORM:
        raise InputError("The faces at the edge face opposite ways, so they give no tool "
                         "direction; select the face the tool works on.")
    return total / norm


def frame_from_normal_and_edge(normal, edge_start, edge_end, tol_mm=1e-6, tol_rad=1e-6):
    """Frame with Z along a face normal and X along an edge lying in that face.

    Parameters
    ----------
    normal : array_like, shape (3,)
        Outward normal of the face (need not be unit).
    edge_start, edge_end : array_like, shape (3,)
        Ends of a straight edge in the face's plane, mm; the origin is
        `edge_start` and X points towards `edge_end`.
    tol_mm, tol_rad : float
        Shortest accepted edge, mm; largest accepted angle between the edge
        and the face's plane, radians.

    Returns
    -------
    ndarray, shape (4, 4)
        The frame in the points' frame, mm.

    Raises
    ------
    FrameError
        Zero-length edge, zero normal, or an edge not parallel to the face.
    """
    p0, p1 = (np.asarray(p, dtype=float) for p in (edge_start, edge_end))
    z = np.asarray(normal, dtype=float)
    if np.linalg.norm(z) < 1e-12:
        raise FrameError("The face has no normal; select a planar face.")
    z = z / np.linalg.norm(z)
    x = p1 - p0
    length = np.linalg.norm(x)
    if length < tol_mm:
        raise FrameError("The edge has no length; select a straight edge of the face.")
    x = x / length
    if abs(np.dot(x, z)) > np.sin(tol_rad):
        raise FrameError("The edge is not parallel to the face (%.3g° out of its plane); select "
                         "an edge lying in the face." % np.degrees(np.arcsin(min(1.0, abs(np.dot(x, z))))))
    x = x - np.dot(x, z) * z
    x = x / np.linalg.norm(x)
    return make_transform(np.column_stack([x, np.cross(z, x), z]), p0)
