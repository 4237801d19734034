"""Rigid transforms between the cell's frames (eqs 1-7) and frame teaching.

A transform ``T_a_b`` is the 4x4 homogeneous pose of frame b expressed in
frame a, in millimetres, so that ``p_a = T_a_b @ p_b``.  In the paper's
notation ``T_a_b`` is :math:`{}^{a}_{b}T`.

Pure numpy: no FreeCAD, no scipy.
"""

import numpy as np

from ..errors import FrameError


def make_transform(R=None, p=None):
    """Homogeneous transform from a rotation and a translation (eq 2).

    Parameters
    ----------
    R : array_like, shape (3, 3), optional
        Rotation matrix; identity if omitted.
    p : array_like, shape (3,), optional
        Position of the frame's origin, mm; zero if omitted.

    Returns
    -------
    T : ndarray, shape (4, 4)
    """
    T = np.eye(4)
    if R is not None:
        T[:3, :3] = R
    if p is not None:
        T[:3, 3] = p
    return T


def invert_transform(T):
    """Inverse of a rigid transform, eq 7: ``[[Rᵀ, -Rᵀ p], [0, 1]]``.

    Uses the rotation's transpose rather than a general matrix inverse, so
    ``invert_transform(T_u_b)`` is ``T_b_u`` exactly as eqs 2-7 derive it.

    Parameters
    ----------
    T : array_like, shape (4, 4) or (N, 4, 4)
        Rigid transforms ``T_a_b``.

    Returns
    -------
    T_inv : ndarray, shape (4, 4) or (N, 4, 4)
        ``T_b_a``.
    """
    T = np.asarray(T, dtype=float)
    R_t = np.swapaxes(T[..., :3, :3], -1, -2)
    T_inv = np.zeros_like(T)
    T_inv[..., :3, :3] = R_t
    T_inv[..., :3, 3] = -(R_t @ T[..., :3, 3, np.newaxis])[..., 0]   # eq 6
    T_inv[..., 3, 3] = 1.0
    return T_inv


def relative_transform(T_u_b, T_u_c):
    """Pose of frame c in frame b from both poses in frame u (eq 1).

    ``T_b_c = T_b_u @ T_u_c`` with ``T_b_u = invert_transform(T_u_b)`` (eq 7).

    Parameters
    ----------
    T_u_b, T_u_c : array_like, shape (4, 4) or (N, 4, 4)
        Poses of frames b and c in the common frame u (e.g. the CAD
        assembly frame {U}); broadcast against each other.

    Returns
    -------
    T_b_c : ndarray, shape (4, 4) or (N, 4, 4)
    """
    return invert_transform(T_u_b) @ np.asarray(T_u_c, dtype=float)


def transform_points(T, P):
    """Express points given in frame b in frame a (eq 3): ``R p + t``.

    Parameters
    ----------
    T : array_like, shape (4, 4)
        Transform ``T_a_b``.
    P : array_like, shape (3,) or (N, 3)
        Points in frame b, mm.

    Returns
    -------
    P_a : ndarray, shape (3,) or (N, 3)
        The same points in frame a, mm.
    """
    T = np.asarray(T, dtype=float)
    return np.asarray(P, dtype=float) @ T[:3, :3].T + T[:3, 3]


def transform_vectors(T, V):
    """Express direction vectors given in frame b in frame a (rotation only).

    Parameters
    ----------
    T : array_like, shape (4, 4)
        Transform ``T_a_b``; its translation is ignored.
    V : array_like, shape (3,) or (N, 3)
        Vectors in frame b.

    Returns
    -------
    V_a : ndarray, shape (3,) or (N, 3)
    """
    T = np.asarray(T, dtype=float)
    return np.asarray(V, dtype=float) @ T[:3, :3].T


def frame_from_three_points(origin, on_x, in_xy, tol_mm=1e-6):
    """Frame taught by three points, as on a robot controller.

    The X axis points from ``origin`` to ``on_x``; the XY plane contains
    ``in_xy``, on the side of positive Y; Z completes a right-handed frame.

    Parameters
    ----------
    origin, on_x, in_xy : array_like, shape (3,)
        Points in a common frame a, mm.
    tol_mm : float, optional
        Smallest accepted distance from ``origin`` to ``on_x`` and from
        ``in_xy`` to the X axis, mm.

    Returns
    -------
    T_a_f : ndarray, shape (4, 4)
        Pose of the taught frame in frame a.

    Raises
    ------
    CadRobotWB.errors.FrameError
        If ``on_x`` coincides with ``origin`` or the three points are collinear.
    """
    origin, on_x, in_xy = (np.asarray(v, dtype=float) for v in (origin, on_x, in_xy))
    x = on_x - origin
    x_len = np.linalg.norm(x)
    if x_len < tol_mm:
        raise FrameError(
            f"Frame points: the X-axis point is only {x_len:.3g} mm from the origin; "
            "pick a point farther along the X axis.")
    x = x / x_len
    z = np.cross(x, in_xy - origin)
    off_axis = np.linalg.norm(z)   # distance of in_xy from the X axis, mm
    if off_axis < tol_mm:
        raise FrameError(
            f"Frame points are collinear: the XY-plane point is only {off_axis:.3g} mm "
            "from the X axis; pick a point off the line through the other two.")
    z = z / off_axis
    y = np.cross(z, x)
    return make_transform(np.column_stack([x, y, z]), origin)


def _check_not_collinear(P, what, tol_mm):
    spread = np.linalg.svd(P - P.mean(axis=0), compute_uv=False)
    # spread[1] / sqrt(N) is the RMS distance of the points from their best-fit line.
    off_line = spread[1] / np.sqrt(len(P))
    if off_line < tol_mm:
        raise FrameError(
            f"Frame fit: the {what} points are collinear (RMS {off_line:.3g} mm off "
            "their common line), so the rotation about that line is undefined; "
            "add a point off the line.")


def fit_frame(points_frame, points_measured, tol_mm=1e-6):
    """Least-squares rigid transform from point pairs (Kabsch, no scaling).

    Finds the proper rotation R and translation t minimising
    ``sum |R p_frame + t - p_measured|²``, e.g. to teach a calibration frame
    {B} from points touched up on the real part.

    Parameters
    ----------
    points_frame : array_like, shape (N, 3)
        Points in the frame being fitted (e.g. from the CAD, in {B}), mm.
    points_measured : array_like, shape (N, 3)
        The same points as measured (e.g. in the robot base frame), mm.
    tol_mm : float, optional
        Smallest accepted RMS distance of either point set from a line, mm.

    Returns
    -------
    T_measured_frame : ndarray, shape (4, 4)
        Pose of the fitted frame in the measuring frame; det(R) = +1.
    residuals_mm : ndarray, shape (N,)
        Distance from each measured point to its fitted frame point, mm.

    Raises
    ------
    CadRobotWB.errors.FrameError
        If the arrays do not match, hold fewer than 3 points, or the points
        are collinear.
    """
    P = np.asarray(points_frame, dtype=float)
    M = np.asarray(points_measured, dtype=float)
    if P.ndim != 2 or P.shape[1] != 3 or P.shape != M.shape:
        raise FrameError(
            f"Frame fit: expected two (N, 3) point arrays of the same size, got "
            f"{P.shape} and {M.shape}.")
    if len(P) < 3:
        raise FrameError(
            f"Frame fit: {len(P)} point(s) given; at least 3 non-collinear points are needed.")
    if not (np.all(np.isfinite(P)) and np.all(np.isfinite(M))):
        raise FrameError("Frame fit: a coordinate is not a finite number (nan or inf); "
                         "give every point as three numbers in mm.")
    _check_not_collinear(P, "frame", tol_mm)
    _check_not_collinear(M, "measured", tol_mm)

    p_mean, m_mean = P.mean(axis=0), M.mean(axis=0)
    H = (P - p_mean).T @ (M - m_mean)
    U, _, Vt = np.linalg.svd(H)
    # Flip the least significant axis if the best orthogonal fit is a reflection.
    d = np.sign(np.linalg.det(Vt.T @ U.T))
    R = Vt.T @ np.diag([1.0, 1.0, d]) @ U.T
    T = make_transform(R, m_mean - R @ p_mean)
    residuals = np.linalg.norm(transform_points(T, P) - M, axis=1)
    return T, residuals


def is_rigid_transform(T, tol=1e-6):
    """Whether T is a 4x4 rigid transform (proper rotation, last row 0 0 0 1).

    Parameters
    ----------
    T : array_like
        Candidate transform.
    tol : float, optional
        Absolute tolerance on ``RᵀR = I``, ``det R = 1`` and the last row.

    Returns
    -------
    bool
    """
    T = np.asarray(T)
    if T.shape != (4, 4) or not np.all(np.isfinite(T)):
        return False
    R = T[:3, :3]
    return bool(np.allclose(T[3], [0.0, 0.0, 0.0, 1.0], rtol=0.0, atol=tol)
                and np.allclose(R.T @ R, np.eye(3), rtol=0.0, atol=tol)
                and abs(np.linalg.det(R) - 1.0) <= tol)
