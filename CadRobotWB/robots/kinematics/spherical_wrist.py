"""Closed-form inverse kinematics of 6R arms with a spherical wrist and axes 2, 3 parallel.

The class: axes 4, 5 and 6 meet in one point (at any angles between them) and axes 2
and 3 are parallel; axes 1 and 2 may meet at any angle, or not meet at all.  OPW arms
are a special case; so are the KUKA arms whose URDF rounds pi/2 to 1.5708 (axes 1 and
2 at 89.99979 deg).  The arm is given as :class:`.poe.ChainParameters` (URDF joint
values, no offsets, no signs).

The method is IK-Geo's "spherical wrist, h2 parallel to h3" case (A. J. Elias,
J. T. Wen, arXiv:2211.05737, section 4; their ``IK_spherical_2_parallel.m``), on
the subproblems of :mod:`.subproblems`.  With ``p_w = p_0T - R_06 P_WT - P_01`` the
wrist centre seen from axis 1 and ``P_3W`` the vector from axis 3 to the centre:

1. rotations about h2 and h3 keep a vector's component along h2, so
   ``h2 . rot(-h1, q1) p_w = h2 . (P_12 + P_23 + P_3W)``: SP4, q1 (0-2 roots);
2. ``|rot(-h1, q1) p_w - P_12| = |P_23 + rot(h3, q3) P_3W|``: SP3, q3 (0-2);
3. ``rot(h2, q2) (P_23 + rot(h3, q3) P_3W) = rot(-h1, q1) p_w - P_12``: SP1, q2;
4. the wrist ``R_36 = rot(h4, q4) rot(h5, q5) rot(h6, q6)``: SP4 on
   ``h4 . rot(h5, q5) h6 = h4 . R_36 h6`` gives q5 (0-2; in the half-angle form of
   :func:`.subproblems.sp4_unit`, exact at a wrist singularity), SP1 then q4 (together
   SP2 solved as IK-Geo solves it), and SP1 q6 from a vector perpendicular to h6 (still
   defined at a wrist singularity, where q4 is set to 0 as ``opw.inverse`` sets it and
   q6 takes the rest).

That is up to 2 x 2 x 2 = :data:`MAX_SOLUTIONS` solutions.  A wrist spherical only to
:data:`WRIST_GAP_TOL_MM` (the KUKA files' rounding leaves their wrist axes 0.15-0.42 um
from one point) is solved exactly for the file, without snapping: the closed form solves
the *model* arm whose wrist axes are moved, parallel to themselves, through their nearest
common point.  Model and file have the same rotations at every q, and flanges a few
micrometres apart that change slowly with q (:func:`flanges`), so each branch is solved
again for the pose moved back by that offset at its previous answer (at most
:data:`CORRECTION_STEPS` times: a fixed point that typically contracts by ~1e-6 a step,
and keeps each branch apart from its neighbour next to a singularity, where a Newton step
would merge them).  Every solution is then checked against the forward kinematics of the
arm as given (:func:`.poe.fk`) and dropped if it misses by more than
:data:`POSITION_TOL_MM` or :data:`ROTATION_TOL_RAD`; a least-squares root (a pose a hair
beyond a fold) that passes the check is kept.

Where numba is installed, :func:`inverse` runs the same steps compiled
(:mod:`.spherical_wrist_kernel`); :func:`inverse_numpy` is the numpy code it falls back
to and the reference the tests compare it with.  Never imports FreeCAD.
"""

from dataclasses import dataclass

import numpy as np

from . import poe, spherical_wrist_kernel
from .chain_geometry import axis_points
from .subproblems import rotate, sp1, sp3, sp4, sp4_unit

KIND = "spherical_wrist"
#: Rows of :func:`inverse` per pose.
MAX_SOLUTIONS = 8

#: Axes this close to parallel (|sin| of their angle) count as parallel (as
#: ``identify.DIRECTION_TOL``).
DIRECTION_TOL = 1e-9
#: A wrist whose axes pass this close to one point is solved as spherical, then corrected
#: onto the arm as given.  The KUKA files (pi/2 written 1.5708) miss by 0.15-0.42 um;
#: offset wrists (FANUC CRX and M-430iA/2P, Yaskawa HC10 and MPX3500, ABB CRB 15000,
#: UR5e) by 47-81 mm.
WRIST_GAP_TOL_MM = 1e-3
#: Fixed-point corrections of a wrist that is not exactly spherical, at most (see the module
#: docstring).  Measured on 5,000 random poses per KUKA file: the median flange misses by
#: 3e-10 mm after one step, the worst by 1e-5 mm after one, 4e-8 after two, 2e-10 after
#: three.  Within 3e-5 rad of a wrist singularity (q5 = 0), where q4 and q6 are
#: ill-conditioned, a branch can need up to 10 (2 poses of 100,000 per file).
CORRECTION_STEPS = 12
#: ... stop once the flange is this close to its pose (the check allows 1e-6 mm) ...
CORRECTION_CONVERGED_MM = 1e-8
#: ... and do not start on a branch whose flange misses by more than this: the branch does
#: not exist (the model and the file differ by micrometres).
CORRECTABLE_MM = 10 * WRIST_GAP_TOL_MM
#: A wrist gap below this (rounding) needs no correction.
EXACT_GAP_MM = 1e-9
#: Every solution reproduces its pose to these (as ``identify.POSITION_TOL_MM`` and
#: ``identify.ROTATION_TOL_RAD``).
POSITION_TOL_MM = 1e-6
ROTATION_TOL_RAD = 1e-9
#: Two solutions closer than this on every joint (modulo 2 pi) are one.
DUPLICATE_TOL_RAD = 1e-6
#: Angles this close below -pi wrap to +pi (``opw.ANGLE_TOLERANCE_DEG`` in radians).
WRAP_TOL_RAD = np.radians(1e-9)


@dataclass(frozen=True)
class Constants:
    """What :func:`inverse` derives from the arm once.

    Attributes
    ----------
    params : poe.ChainParameters
        The arm as given: the check uses it.
    model : poe.ChainParameters
        The same arm with its wrist axes moved through the wrist centre (the same arm
        when the wrist is exactly spherical).
    P_01, P_12, P_23 : ndarray, shape (3,)
        Base to axis 1, axis 1 to axis 2, axis 2 to axis 3 points, mm.
    P_3W : ndarray, shape (3,)
        Axis 3 point to the wrist centre, mm.
    P_WT : ndarray, shape (3,)
        Wrist centre to the flange at zero joint values, mm.
    wrist_gap_mm : float
        Largest distance from the wrist centre to axes 4, 5, 6 (0 for an exact
        spherical wrist).
    correction_steps : int
        :data:`CORRECTION_STEPS`, or 0 when the wrist is exactly spherical.
    v6 : ndarray, shape (3,)
        A unit vector perpendicular to axis 6 (q6 is read from its turn).
    kernel : ndarray
        The same numbers for the compiled kernel
        (:func:`.spherical_wrist_kernel.constants_vector`).
    """

    params: poe.ChainParameters
    model: poe.ChainParameters
    P_01: np.ndarray
    P_12: np.ndarray
    P_23: np.ndarray
    P_3W: np.ndarray
    P_WT: np.ndarray
    wrist_gap_mm: float
    correction_steps: int
    v6: np.ndarray
    kernel: np.ndarray


def _nearest_common_point(points, directions):
    """The point nearest to lines (least squares) and its largest distance to them, mm."""
    projectors = np.eye(3)[None] - directions[:, :, None] * directions[:, None, :]
    centre = np.linalg.solve(projectors.sum(axis=0), np.einsum("nij,nj->i", projectors, points))
    gaps = np.linalg.norm(np.einsum("nij,nj->ni", projectors, centre - points), axis=1)
    return centre, float(gaps.max())


def _require_not_parallel(H, i, j, why):
    if np.linalg.norm(np.cross(H[i], H[j])) <= DIRECTION_TOL:
        raise ValueError("axes %d and %d are parallel: %s" % (i + 1, j + 1, why))


def recognise(params):
    """The constants of an arm of the class, or why it is not one.

    Parameters
    ----------
    params : poe.ChainParameters

    Returns
    -------
    Constants

    Raises
    ------
    ValueError
        Axes 2 and 3 are not parallel, axes 4, 5, 6 do not pass within
        :data:`WRIST_GAP_TOL_MM` of one point, or axes 1 and 2 (or neighbouring wrist
        axes) are parallel.
    """
    H = np.asarray(params.H, dtype=float)
    sin_23 = np.linalg.norm(np.cross(H[1], H[2]))
    if sin_23 > DIRECTION_TOL:
        raise ValueError("axes 2 and 3 are not parallel (%.6g deg apart)"
                         % np.degrees(np.arcsin(min(sin_23, 1.0))))
    _require_not_parallel(H, 0, 1, "q1 would not move the arm's plane")
    _require_not_parallel(H, 3, 4, "the wrist has fewer than three degrees of freedom")
    _require_not_parallel(H, 4, 5, "the wrist has fewer than three degrees of freedom")
    points = axis_points(params)
    centre, gap = _nearest_common_point(points[3:6], H[3:6])
    if gap > WRIST_GAP_TOL_MM:
        raise ValueError("axes 4, 5 and 6 do not meet in one point: they pass %.6g mm from the "
                         "nearest common point (an offset wrist)" % gap)
    v6 = np.cross(H[5], np.eye(3)[np.argmin(np.abs(H[5]))])
    v6 /= np.linalg.norm(v6)
    P_3W, P_WT = centre - points[2], params.P.sum(axis=0) - centre
    model = poe.ChainParameters(H=H, P=np.vstack([params.P[:3], P_3W, np.zeros((2, 3)), P_WT]),
                                R_6T=np.asarray(params.R_6T, dtype=float))
    constants = dict(params=params, model=model, P_01=points[0].copy(), P_12=params.P[1],
                     P_23=params.P[2], P_3W=P_3W, P_WT=P_WT, wrist_gap_mm=gap,
                     correction_steps=CORRECTION_STEPS if gap > EXACT_GAP_MM else 0, v6=v6)
    return Constants(kernel=spherical_wrist_kernel.constants_vector(constants), **constants)


def inverse(constants, T_0T):
    """Every solution of each flange pose.

    Parameters
    ----------
    constants : Constants
        From :func:`recognise`.
    T_0T : array_like, shape (N, 4, 4) or (4, 4)
        Flange poses in the arm's base frame, mm (proper rotations).

    Returns
    -------
    q_rad : ndarray, shape (N, MAX_SOLUTIONS, 6) or (MAX_SOLUTIONS, 6)
        Joint values (URDF's), radians, each in (-pi, pi]; distinct solutions first
        (branch order: q1 root, q3 root, q5 root), NaN rows after them.  Every row
        reproduces its pose to :data:`POSITION_TOL_MM` and :data:`ROTATION_TOL_RAD`.
        Joint limits are not applied.
    """
    T = np.asarray(T_0T, dtype=float)
    single = T.ndim == 2
    T = np.ascontiguousarray(T.reshape((-1, 4, 4)))
    if spherical_wrist_kernel.available():
        q = np.empty((T.shape[0], MAX_SOLUTIONS, 6))
        spherical_wrist_kernel.inverse_into(constants.kernel, T, q)
    else:
        q = _inverse_numpy(constants, T)
    return q[0] if single else q


def inverse_numpy(constants, T_0T):
    """:func:`inverse` computed with numpy only (the reference for the compiled kernel)."""
    T = np.asarray(T_0T, dtype=float)
    single = T.ndim == 2
    q = _inverse_numpy(constants, T.reshape((-1, 4, 4)))
    return q[0] if single else q


def _inverse_numpy(k, T):
    n = len(T)
    T_rows = np.repeat(T, MAX_SOLUTIONS, axis=0)
    q = branches(k, T)[0].reshape(-1, 6)
    moving = np.arange(n * MAX_SOLUTIONS)             # rows still corrected
    for _ in range(k.correction_steps):
        flange, model = flanges(k, q[moving])
        miss = np.linalg.norm(flange - T_rows[moving, :3, 3], axis=1)
        keep = (miss > CORRECTION_CONVERGED_MM) & (miss <= CORRECTABLE_MM)
        moving, offset = moving[keep], (flange - model)[keep]
        if moving.size == 0:
            break
        poses, pose_of_row = np.unique(moving // MAX_SOLUTIONS, return_inverse=True)
        branch = moving % MAX_SOLUTIONS
        offsets = np.zeros((len(poses), MAX_SOLUTIONS, 3))
        offsets[pose_of_row, branch] = offset
        q_poses = branches(k, T[poses], offsets.reshape(-1, 2, 2, 2, 3))[0]
        q[moving] = q_poses.reshape(-1, MAX_SOLUTIONS, 6)[pose_of_row, branch]
    # A least-squares root that reproduces the pose is a solution too: at an elbow or wrist
    # fold the roots meet, and rounding can put the pose a hair beyond it.
    valid = reproduces(k.params, T_rows, q)
    return distinct_first(wrap_rad(q.reshape(n, MAX_SOLUTIONS, 6)), valid.reshape(n, MAX_SOLUTIONS))


def flanges(k, q):
    """The flange of the arm as given and that of its spherical model (their difference
    is what the correction moves the pose by), mm.

    Parameters
    ----------
    k : Constants
    q : ndarray, shape (M, 6)
        Radians.

    Returns
    -------
    flange, model : ndarray, shape (M, 3)
        The same rotation goes with both.
    """
    return poe.fk(k.params, q)[:, :3, 3], poe.fk(k.model, q)[:, :3, 3]


#: Masks of the first root of each subproblem, over the branch axes (q1, q3, q5 root).
_FIRST_ROOT = [np.arange(2).reshape(shape) == 0 for shape in ((2, 1, 1), (2, 1), (2,))]


def _root(roots, level):
    """The root of each branch, (N, 2, 2, 2), from both roots (N, 2, 2, 2, 2)."""
    return np.where(_FIRST_ROOT[level], roots[..., 0], roots[..., 1])


def branches(k, T, offset=None):
    """The closed form's eight branches, unchecked.

    Parameters
    ----------
    k : Constants
    T : ndarray, shape (N, 4, 4)
    offset : ndarray, shape (N, 2, 2, 2, 3), optional
        Per branch, the flange of the arm as given minus that of the spherical model
        (:func:`flanges`), mm: the model is solved for the flange moved back by it.

    Returns
    -------
    q : ndarray, shape (N, 2, 2, 2, 6)
        Radians, indexed [pose, q1 root, q3 root, q5 root, joint].
    exact : ndarray of bool, shape (N, 2, 2, 2)
        False where a subproblem has no root (its least-squares angle is used).
    """
    H = k.params.H
    R_06 = T[:, :3, :3] @ k.params.R_6T.T
    p_w = (T[:, :3, 3] - R_06 @ k.P_WT - k.P_01)[:, None, None, None]  # wrist centre
    p_w = p_w - (0.0 if offset is None else offset)
    p_w = np.broadcast_to(p_w, (len(T), 2, 2, 2, 3))
    roots, ok1 = sp4(H[1], p_w, -H[0], H[1] @ (k.P_12 + k.P_23 + k.P_3W))
    q1 = _root(roots, 0)
    reach = rotate(-H[0], q1, p_w) - k.P_12
    roots, ok3 = sp3(k.P_3W, -k.P_23, H[2], np.linalg.norm(reach, axis=-1))
    q3 = _root(roots, 1)
    q2, _ = sp1(k.P_23 + rotate(H[2], q3, k.P_3W), reach, H[1])
    # R_36 = rot(h3, -q3) rot(h2, -q2) rot(h1, -q1) R_06, applied to h6 and v6 only.
    seen = np.swapaxes(R_06 @ np.stack([H[5], k.v6], axis=-1), -1, -2)[:, None, None, None]
    for axis, angle in ((H[0], q1), (H[1], q2), (H[2], q3)):
        seen = rotate(axis, -angle[..., None], seen)
    h6_in_3, v6_in_3 = seen[..., 0, :], seen[..., 1, :]                 # (N, 2, 2, 2, 3)
    roots, ok5 = sp4_unit(H[3], H[5], H[4], h6_in_3)
    q5 = _root(roots, 2)
    q4, _ = sp1(rotate(H[4], q5, H[5]), h6_in_3, H[3])
    q6, _ = sp1(k.v6, rotate(H[4], -q5, rotate(H[3], -q4, v6_in_3)), H[5])
    return np.stack([q1, q2, q3, q4, q5, q6], axis=-1), ok1 & ok3 & ok5


def reproduces(params, T, q):
    """True where the flange at `q` (M, 6) rad is within the tolerances of `T` (M, 4, 4)."""
    position, rotation = pose_errors(params, T, np.nan_to_num(q))
    return (position <= POSITION_TOL_MM) & (rotation <= ROTATION_TOL_RAD) & ~np.isnan(q[:, 0])


def pose_errors(params, T, q):
    """How far the flange at `q` is from `T`.

    Parameters
    ----------
    params : poe.ChainParameters
    T : ndarray, shape (M, 4, 4)
    q : ndarray, shape (M, 6)
        Radians.

    Returns
    -------
    position_mm, rotation_rad : ndarray, shape (M,)
    """
    T_q = poe.fk(params, q)
    position = np.linalg.norm(T_q[:, :3, 3] - T[:, :3, 3], axis=1)
    E = T[:, :3, :3] @ np.swapaxes(T_q[:, :3, :3], 1, 2)
    sin2 = np.linalg.norm(np.stack([E[:, 2, 1] - E[:, 1, 2], E[:, 0, 2] - E[:, 2, 0],
                                    E[:, 1, 0] - E[:, 0, 1]], axis=-1), axis=1)
    return position, np.arctan2(sin2, np.trace(E, axis1=1, axis2=2) - 1.0)


def wrap_rad(q):
    """Angles wrapped into (-pi, pi] (one within :data:`WRAP_TOL_RAD` of -pi gives +pi)."""
    return q - 2.0 * np.pi * np.ceil((q - np.pi - WRAP_TOL_RAD) / (2.0 * np.pi))


def distinct_first(q, valid):
    """Duplicates removed, the distinct solutions first in their order, NaN rows last.

    Parameters
    ----------
    q : ndarray, shape (N, K, 6)
        Radians, wrapped.
    valid : ndarray of bool, shape (N, K)

    Returns
    -------
    ndarray, shape (N, K, 6)
    """
    gap = np.abs(wrap_rad(q[:, :, None] - q[:, None])).max(axis=-1)    # (N, K, K)
    earlier = np.tril(np.ones(gap.shape[1:], dtype=bool), -1)
    duplicate = ((gap <= DUPLICATE_TOL_RAD) & earlier & valid[:, None, :]).any(axis=2)
    keep = valid & ~duplicate
    order = np.argsort(~keep, axis=1, kind="stable")
    q = np.take_along_axis(q, order[..., None], axis=1)
    q[~np.take_along_axis(keep, order, axis=1)] = np.nan
    return q
