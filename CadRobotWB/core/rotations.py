"""Rotations: quaternions, slerp (eqs 14-15), axis-angle and Euler conventions.

Quaternions are numpy arrays ``(w, x, y, z)`` (Hamilton convention, scalar
first).  Angles are in radians.  Rotation matrices are proper (det = +1) and
act on column vectors, ``p_a = R_a_b @ p_b``.

Every function accepts a single item or a stack of N items, as stated in its
docstring, and returns the same kind.  Pure numpy: no FreeCAD, no scipy.
"""

import numpy as np

from ..errors import InputError


def _sinc(x):
    """sin(x) / x, exact at x = 0 (numpy's sinc is sin(pi x) / (pi x))."""
    return np.sinc(np.asarray(x) / np.pi)


def _normalize(q):
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


# Below this size a number is rounding noise (FreeCAD versions, numpy versions
# and a save/reopen differ in the last bits, ~1e-16) and never decides a sign.
SIGN_TOLERANCE = 1e-9


def choose_quaternion_sign(q, q_previous=None, tol=SIGN_TOLERANCE):
    """q or -q (the same rotation), by the one rule every output follows.

    1. Continuous: when there is a previous quaternion and ``|q · q_previous|
       > tol``, the sign that makes ``q · q_previous > 0`` (the short way from
       the previous orientation, as slerp takes it).
    2. Canonical otherwise (no previous quaternion, or the two rotations are
       180 degrees apart so ``q · q_previous`` is 0 up to noise): the first
       component, in the order w, x, y, z, with ``|c| > tol`` is positive.

    Numbers within ``tol`` of 0 never decide, so last-bit differences between
    FreeCAD / numpy versions, or after a document is saved and reopened,
    cannot flip the sign (a 180-degree turn has w = ±1e-17, not 0).

    Parameters
    ----------
    q : array_like, shape (4,) or (N, 4)
        Quaternions ``(w, x, y, z)``, unit (or nearly).
    q_previous : array_like, shape (4,) or (N, 4), optional
        The quaternion each one follows; broadcast against ``q``.
    tol : float, optional

    Returns
    -------
    q : ndarray, shape (4,) or (N, 4)
        ``q`` with each row's sign chosen.
    """
    q = np.asarray(q, dtype=float)
    # Canonical: sign of the first component larger than tol (1 if none is).
    big = np.abs(q) > tol
    first = np.argmax(big, axis=-1)[..., np.newaxis]
    sign = np.where(np.take_along_axis(q, first, axis=-1) < 0.0, -1.0, 1.0)
    if q_previous is not None:
        dot = np.sum(q * np.asarray(q_previous, dtype=float), axis=-1, keepdims=True)
        sign = np.where(np.abs(dot) > tol, np.where(dot < 0.0, -1.0, 1.0), sign)
    return sign * q


def quaternion_sequence_from_matrices(R):
    """Quaternions of a sequence of rotations, each sign continuous with the one before.

    The first is canonical, each next one follows :func:`choose_quaternion_sign`
    with its predecessor, so a program's targets read without sign jumps.

    Parameters
    ----------
    R : array_like, shape (N, 3, 3)
        Rotation matrices, in program order.

    Returns
    -------
    q : ndarray, shape (N, 4)
        Unit quaternions ``(w, x, y, z)``.
    """
    q = quaternion_from_matrix(np.reshape(np.asarray(R, dtype=float), (-1, 3, 3)))
    for i in range(1, len(q)):
        q[i] = choose_quaternion_sign(q[i], q[i - 1])
    return q


def quaternion_from_matrix(R):
    """Unit quaternion of a rotation matrix (Shepperd's method).

    The component with the largest magnitude is computed first, from the
    largest of ``trace(R)`` and the diagonal entries, so the result stays
    accurate for every rotation angle, including 180 degrees.

    Parameters
    ----------
    R : array_like, shape (3, 3) or (N, 3, 3)
        Rotation matrices.

    Returns
    -------
    q : ndarray, shape (4,) or (N, 4)
        Unit quaternions ``(w, x, y, z)``, sign canonical
        (:func:`choose_quaternion_sign`): ``w > 0`` unless w is 0 up to
        rounding noise (a 180-degree turn), then the first of x, y, z that
        is not 0 is positive.
    """
    R = np.asarray(R, dtype=float)
    single = R.ndim == 2
    R = R.reshape(-1, 3, 3)
    n = R.shape[0]

    diag = np.diagonal(R, axis1=1, axis2=2)               # (N, 3)
    trace = diag.sum(axis=1)
    branch = np.argmax(np.column_stack([diag, trace]), axis=1)

    # Each row below is 4 * (largest component) * q, hence not yet unit.
    q = np.empty((n, 4))
    t = branch == 3                                       # trace largest: w first
    q[t, 0] = 1.0 + trace[t]
    q[t, 1] = R[t, 2, 1] - R[t, 1, 2]
    q[t, 2] = R[t, 0, 2] - R[t, 2, 0]
    q[t, 3] = R[t, 1, 0] - R[t, 0, 1]
    for i in range(3):                                    # R[i, i] largest: x, y or z first
        j, k = (i + 1) % 3, (i + 2) % 3
        m = branch == i
        q[m, 0] = R[m, k, j] - R[m, j, k]
        q[m, 1 + i] = 1.0 - trace[m] + 2.0 * R[m, i, i]
        q[m, 1 + j] = R[m, j, i] + R[m, i, j]
        q[m, 1 + k] = R[m, k, i] + R[m, i, k]

    q = choose_quaternion_sign(_normalize(q))
    return q[0] if single else q


def matrix_from_quaternion(q):
    """Rotation matrix of a quaternion.

    Parameters
    ----------
    q : array_like, shape (4,) or (N, 4)
        Quaternions ``(w, x, y, z)``; normalised here, so they need not be unit.

    Returns
    -------
    R : ndarray, shape (3, 3) or (N, 3, 3)
    """
    w, x, y, z = np.moveaxis(_normalize(np.asarray(q, dtype=float)), -1, 0)
    R = np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=-1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], axis=-1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1),
    ], axis=-2)
    return R


def quaternion_multiply(q1, q2):
    """Hamilton product ``q1 * q2`` (the rotation q2 first, then q1).

    ``matrix_from_quaternion(q1 * q2) == matrix_from_quaternion(q1) @ matrix_from_quaternion(q2)``.

    Parameters
    ----------
    q1, q2 : array_like, shape (4,) or (N, 4)
        Quaternions ``(w, x, y, z)``; broadcast against each other.

    Returns
    -------
    q : ndarray, shape (4,) or (N, 4)
    """
    w1, x1, y1, z1 = np.moveaxis(np.asarray(q1, dtype=float), -1, 0)
    w2, x2, y2, z2 = np.moveaxis(np.asarray(q2, dtype=float), -1, 0)
    return np.stack([
        w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
        w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
        w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
        w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
    ], axis=-1)


def quaternion_conjugate(q):
    """Conjugate ``(w, -x, -y, -z)``: the inverse rotation of a unit quaternion.

    Parameters
    ----------
    q : array_like, shape (4,) or (N, 4)

    Returns
    -------
    q_conj : ndarray, shape (4,) or (N, 4)
    """
    return np.asarray(q, dtype=float) * np.array([1.0, -1.0, -1.0, -1.0])


def quaternion_slerp(q0, q1, t):
    """Spherical linear interpolation from q0 to q1 (eqs 14-15).

    Eq 14, with the paper's fraction ``(k-1)/(n-1)`` written ``t``::

        q(t) = sin((1 - t) θ) / sin θ · q0 + sin(t θ) / sin θ · q1
        cos θ = q0 · q1                                                 (eq 15)

    Two details the paper leaves out:

    - q1 and -q1 are the same rotation; when ``q0 · q1 < 0`` -q1 is used so
      the interpolation takes the short way round (θ <= π/2).  When the two
      are 180 degrees apart (``q0 · q1`` is 0 up to noise) both ways are
      equally short, and q1's canonical sign decides
      (:func:`choose_quaternion_sign`), so noise cannot pick the way.
    - The weights are written ``(1 - t) sinc((1 - t) θ) / sinc θ`` and
      ``t sinc(t θ) / sinc θ`` (``sinc x = sin x / x``), which equal eq 14 but
      never divide by a small ``sin θ``: as θ -> 0 they tend smoothly to the
      linear weights ``1 - t`` and ``t``.  θ itself is computed as
      ``2 atan2(|q0 - q1|, |q0 + q1|)``, which is accurate for small angles
      where ``arccos(q0 · q1)`` is not.

    Parameters
    ----------
    q0, q1 : array_like, shape (4,) or (N, 4)
        Start and end quaternions ``(w, x, y, z)``; normalised here.
    t : float or array_like, shape (N,)
        Interpolation parameter, 0 at q0 and 1 at q1.

    Returns
    -------
    q : ndarray, shape (4,) or (N, 4)
        Unit quaternions.
    """
    q0 = _normalize(np.asarray(q0, dtype=float))
    q1 = _normalize(np.asarray(q1, dtype=float))
    t = np.asarray(t, dtype=float)[..., np.newaxis]

    q1 = choose_quaternion_sign(q1, q0)
    theta = 2.0 * np.arctan2(np.linalg.norm(q0 - q1, axis=-1, keepdims=True),
                             np.linalg.norm(q0 + q1, axis=-1, keepdims=True))
    sinc_theta = _sinc(theta)                            # >= 2/π since θ <= π/2
    w0 = (1.0 - t) * _sinc((1.0 - t) * theta) / sinc_theta
    w1 = t * _sinc(t * theta) / sinc_theta
    return _normalize(w0 * q0 + w1 * q1)


def rotation_angle_between(R1, R2):
    """Angle of the rotation that turns R1 into R2, i.e. of ``R1ᵀ R2``.

    Computed from the quaternion of ``R1ᵀ R2`` as ``2 atan2(|(x, y, z)|, w)``,
    accurate near 0 and near π (unlike ``arccos((trace - 1) / 2)``).

    Parameters
    ----------
    R1, R2 : array_like, shape (3, 3) or (N, 3, 3)
        Rotation matrices.

    Returns
    -------
    angle : float or ndarray, shape (N,)
        Radians, in [0, π].
    """
    R1 = np.asarray(R1, dtype=float)
    R2 = np.asarray(R2, dtype=float)
    q = quaternion_from_matrix(np.swapaxes(R1, -1, -2) @ R2)
    return 2.0 * np.arctan2(np.linalg.norm(q[..., 1:], axis=-1), np.abs(q[..., 0]))


def matrix_from_axis_angle(axis, angle_rad):
    """Rotation matrix of a rotation by ``angle_rad`` about ``axis`` (Rodrigues).

    Parameters
    ----------
    axis : array_like, shape (3,) or (N, 3)
        Rotation axis; normalised here.
    angle_rad : float or array_like, shape (N,)
        Rotation angle in radians, right-handed about ``axis``.

    Returns
    -------
    R : ndarray, shape (3, 3) or (N, 3, 3)

    Raises
    ------
    CadRobotWB.errors.InputError
        If an axis has zero length.
    """
    axis = np.asarray(axis, dtype=float)
    norm = np.linalg.norm(axis, axis=-1, keepdims=True)
    if np.any(norm == 0.0):
        raise InputError("Rotation axis has zero length: give a non-zero axis vector.")
    half = 0.5 * np.asarray(angle_rad, dtype=float)[..., np.newaxis]
    xyz = np.sin(half) * axis / norm
    w = np.broadcast_to(np.cos(half), xyz.shape[:-1] + (1,))
    return matrix_from_quaternion(np.concatenate([w, xyz], axis=-1))


def rotvec_from_matrix(R):
    """Rotation vector ``angle · axis`` of a rotation matrix (UR's pose format).

    Parameters
    ----------
    R : array_like, shape (3, 3) or (N, 3, 3)
        Rotation matrices.

    Returns
    -------
    rotvec : ndarray, shape (3,) or (N, 3)
        Radians; norm in [0, π] (up to rounding).  At π, where ``±axis · π``
        are the same rotation, the quaternion's canonical sign decides
        (:func:`choose_quaternion_sign`): the first non-zero of x, y, z is
        positive, whatever the rounding noise in R.
    """
    q = quaternion_from_matrix(R)
    # With w >= 0 (or w = ±noise at π), |(x, y, z)| = sin(half), half in
    # [0, π/2]; dividing by sinc(half) instead of sin(half) keeps small
    # angles exact.
    half = np.arctan2(np.linalg.norm(q[..., 1:], axis=-1), q[..., 0])[..., np.newaxis]
    return 2.0 * q[..., 1:] / _sinc(half)


def matrix_from_euler_zyx(a, b, c):
    """Rotation matrix ``R = Rz(a) · Ry(b) · Rx(c)`` (KUKA A, B, C).

    Equivalently intrinsic rotations about z, then the new y, then the new x.

    Parameters
    ----------
    a, b, c : float or array_like, shape (N,)
        Angles in radians about z, y and x.

    Returns
    -------
    R : ndarray, shape (3, 3) or (N, 3, 3)
    """
    a, b, c = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (a, b, c)))
    ca, sa = np.cos(a), np.sin(a)
    cb, sb = np.cos(b), np.sin(b)
    cc, sc = np.cos(c), np.sin(c)
    return np.stack([
        np.stack([ca * cb, ca * sb * sc - sa * cc, ca * sb * cc + sa * sc], axis=-1),
        np.stack([sa * cb, sa * sb * sc + ca * cc, sa * sb * cc - ca * sc], axis=-1),
        np.stack([-sb, cb * sc, cb * cc], axis=-1),
    ], axis=-2)


def euler_zyx_from_matrix(R):
    """KUKA angles A, B, C of ``R = Rz(a) · Ry(b) · Rx(c)``.

    Parameters
    ----------
    R : array_like, shape (3, 3) or (N, 3, 3)
        Rotation matrices.

    Returns
    -------
    abc : ndarray, shape (3,) or (N, 3)
        ``(a, b, c)`` in radians; a, c in (-π, π], b in [-π/2, π/2].  At
        gimbal lock (b = ±π/2) only a ∓ c is defined; c = 0 is returned.
        An angle within :data:`SIGN_TOLERANCE` of -π is returned as +π, so
        rounding noise cannot turn 180 into -180.
    """
    R = np.asarray(R, dtype=float)
    cos_b = np.hypot(R[..., 0, 0], R[..., 1, 0])
    b = np.arctan2(-R[..., 2, 0], cos_b)
    locked = cos_b < 1e-9
    # With c = 0 the matrix's second column is (-sin a, cos a, 0).
    a = np.where(locked, np.arctan2(-R[..., 0, 1], R[..., 1, 1]),
                 np.arctan2(R[..., 1, 0], R[..., 0, 0]))
    c = np.where(locked, 0.0, np.arctan2(R[..., 2, 1], R[..., 2, 2]))
    return np.stack([_wrap_to_pi(a), b, _wrap_to_pi(c)], axis=-1)


def _wrap_to_pi(angle):
    """Angles of (-π - tol, π] as (-π + tol, π]: ±π from noise reads as +π."""
    return np.where(angle <= -np.pi + SIGN_TOLERANCE, angle + 2.0 * np.pi, angle)


def matrix_from_euler_xyz_fixed(rx, ry, rz):
    """Rotation matrix of fixed-axis rotations about X, then Y, then Z.

    ``R = Rz(rz) · Ry(ry) · Rx(rx)`` (Fanuc W, P, R; Motoman Rx, Ry, Rz): the
    same matrix as :func:`matrix_from_euler_zyx` with the angles reversed.

    Parameters
    ----------
    rx, ry, rz : float or array_like, shape (N,)
        Angles in radians about the fixed x, y and z axes.

    Returns
    -------
    R : ndarray, shape (3, 3) or (N, 3, 3)
    """
    return matrix_from_euler_zyx(rz, ry, rx)


def euler_xyz_fixed_from_matrix(R):
    """Fixed-axis angles ``(rx, ry, rz)`` of ``R = Rz(rz) · Ry(ry) · Rx(rx)``.

    Parameters
    ----------
    R : array_like, shape (3, 3) or (N, 3, 3)
        Rotation matrices.

    Returns
    -------
    rxyz : ndarray, shape (3,) or (N, 3)
        ``(rx, ry, rz)`` in radians; rx, rz in (-π, π], ry in [-π/2, π/2].
        At gimbal lock (ry = ±π/2) rx = 0 is returned.
    """
    return euler_zyx_from_matrix(R)[..., ::-1].copy()
