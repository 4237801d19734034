"""Geometry of a 6R arm given as :class:`.poe.ChainParameters`: its axis lines, its
wrist point, its reach and the frames of its links.

Used by the catalog entries of kind ``chain`` (:class:`.models.ChainModel`), their
link solids and the class checks.  Lengths in mm, angles in radians.

Pure numpy: never imports FreeCAD.
"""

import numpy as np

from ...core.rotations import matrix_from_axis_angle
from . import poe

#: Grid points per joint of the first search for the reach (a full turn), the factor by
#: which each next grid is finer, and how many grids in all.
REACH_GRID = 37
REACH_ZOOM = 5
REACH_LEVELS = 16


def axis_points(params):
    """The point of each axis at zero joint values.

    Parameters
    ----------
    params : poe.ChainParameters

    Returns
    -------
    ndarray, shape (6, 3)
        mm, base frame: ``P[0] + ... + P[i]`` for axis ``i + 1``.
    """
    return np.cumsum(params.P[:6], axis=0)


def line_distance_mm(p1, u1, p2, u2):
    """Distance between two lines (point, unit direction), parallel ones too, mm."""
    normal = np.cross(u1, u2)
    w = np.asarray(p2, dtype=float) - p1
    if np.linalg.norm(normal) < 1e-12:
        return float(np.linalg.norm(w - (w @ u1) * u1))
    return abs(float(w @ normal)) / float(np.linalg.norm(normal))


def nearest_on_line(point, origin, direction):
    """The point of the line (origin, unit direction) nearest `point`, mm (3,)."""
    return origin + ((point - origin) @ direction) * direction


def nearest_between_lines(p1, u1, p2, u2):
    """The point of line 1 (p1, unit u1) nearest line 2, mm (3,); `p1` for parallel lines."""
    if np.linalg.norm(np.cross(u1, u2)) < 1e-9:
        return np.asarray(p1, dtype=float)
    w = p1 - p2
    b = u1 @ u2
    return p1 + (b * (u2 @ w) - u1 @ w) / (1.0 - b * b) * u1


def wrist_point(params):
    """The point of axis 4 nearest axis 5 (where they meet) at zero joint values, mm (3,).

    It moves with joints 1-3 only (it lies on axis 4); for a spherical wrist it
    is the wrist centre.
    """
    points = axis_points(params)
    return nearest_between_lines(points[3], params.H[3], points[4], params.H[4])


def link_frames(params, q_rad):
    """The pose of each body: frame i turns with joint i about its axis point.

    Parameters
    ----------
    params : poe.ChainParameters
    q_rad : array_like, shape (N, 6)

    Returns
    -------
    ndarray, shape (N, 7, 4, 4)
        Frame 0 the identity; frame i (1..5) has the rotation ``R_0i`` and its origin
        on axis i (:func:`axis_points`, moved); frame 6 is ``poe.fk`` without ``R_6T``
        (its origin the flange, its rotation ``R_06``), mm.
    """
    R = poe.rotations(params, q_rad)
    n = R.shape[0]
    steps = np.einsum("nkij,kj->nki", R, params.P[1:])          # R_0k P[k], k = 1..6
    origins = params.P[0] + np.concatenate([np.zeros((n, 1, 3)), np.cumsum(steps, axis=1)], axis=1)
    frames = np.zeros((n, 7, 4, 4))
    frames[:, :, 3, 3] = 1.0
    frames[:, 0, :3, :3] = np.eye(3)
    frames[:, 1:, :3, :3] = R
    frames[:, 1:6, :3, 3] = origins[:, :5]
    frames[:, 6, :3, 3] = origins[:, 6]
    return frames


def _wrist_distances(params, q23):
    """Distances of the wrist point from axis 1 at joints (0, q2, q3, 0, 0, 0), mm (M,)."""
    R_02 = matrix_from_axis_angle(params.H[1], q23[:, 0])
    R_03 = R_02 @ matrix_from_axis_angle(params.H[2], q23[:, 1])
    to_wrist = params.P[3] + wrist_point(params) - axis_points(params)[3]   # axis 3 -> wrist
    w = params.P[1] + R_02 @ params.P[2] + R_03 @ to_wrist                  # from axis 1's point
    radial = w - np.outer(w @ params.H[0], params.H[0])
    return np.linalg.norm(radial, axis=1)


def reach_mm(params):
    """Largest distance of the wrist point (:func:`wrist_point`) from axis 1, mm.

    As data sheets give reach for a spherical wrist (to its centre).  Found on a
    grid of joints 2 and 3 over a full turn each, then on finer grids round the
    best point (each :data:`REACH_ZOOM` times finer, :data:`REACH_LEVELS` of them:
    the last step is below 1e-10 rad).

    Parameters
    ----------
    params : poe.ChainParameters

    Returns
    -------
    float
    """
    steps = np.linspace(-np.pi, np.pi, REACH_GRID)
    step = steps[1] - steps[0]
    best = np.zeros(2)
    for _level in range(REACH_LEVELS):
        q2, q3 = np.meshgrid(best[0] + steps, best[1] + steps)
        q23 = np.column_stack([q2.ravel(), q3.ravel()])
        distances = _wrist_distances(params, q23)
        best = q23[np.argmax(distances)]
        step /= REACH_ZOOM
        steps = step * np.arange(-REACH_ZOOM, REACH_ZOOM + 1)
    return float(distances.max())
