"""The offset-wrist repair's costly loops compiled with numba (:mod:`.offset_wrist_polish`).

They are the Newton polish of rows onto their poses (:func:`polished_onto`: per row the
forward kinematics, the error against the pose, the geometric Jacobian and the
pseudo-inverse step, as ``offset_wrist_polish.polish``) and the merge of the rows
found into the search's (:func:`merged`). Per row and per pose in scalars they cost a
small part of the numpy code, whose arrays of 3 x 3 products, batched SVDs and row
comparisons are walked once per operation (the polish of the 1,128 rows one nudge gives
the 129 suspect poses of 50,000 random CRX poses: 3 ms against 47 ms; the merge: 0.009 s
against 0.78 s for 20,000 poses).

The step ``pinv(J, rcond) e`` of a 6 x 6 Jacobian is solved by Householder QR with column
pivoting where that QR shows J regular (:data:`REGULAR`): no singular value is then
dropped and the pseudo-inverse is the inverse. Otherwise (next to a singularity, where
the polish deliberately works) it is the SVD's, by one-sided Jacobi rotations (Hestenes),
singular values under ``rcond`` times the largest dropped as numpy's ``pinv`` drops them.

numba is optional, as for :mod:`.opw_kernel` and :mod:`.offset_wrist_kernel`: without
it, switched off by ``CADROBOT_NUMBA=0``, or where it fails to compile,
:mod:`.offset_wrist_polish` runs its numpy code, which stays the reference; the tests
compare the two. The first call in a session loads the compiled code from numba's
cache (0.2 s of CPU), or compiles it (12 s of CPU on this project's machine, once per
installation and Python version).

Pure numpy (and numba): never imports FreeCAD.
"""

import math

import numpy as np

from . import numba_kernel
from .numba_kernel import compile_in_place


#: Why the compiled kernel is not used ("" while it is, None before the first call of
#: :func:`available`).
why_not = None

#: A Jacobian whose pivoted QR has ``|r_66| >= REGULAR |r_11|`` is inverted by that QR:
#: its smallest singular value is then at least ``|r_66| / sqrt(342)`` (the truncation
#: error of pivoted QR, here ``|r_66|``, is at most ``sqrt((4^k - 1) (n - k) / 3 + 1)``
#: times the SVD's, k = 5, n = 6: H. Kawamura and R. Suda, Japan J. Indust. Appl. Math.
#: 38, 757-779, 2021) and its largest at most ``sqrt(6) |r_11|`` (|r_11| is the largest
#: column norm), so their ratio is at least REGULAR / 45.3 = 2.2e-8, far above the
#: polish's ``rcond`` (1e-10): numpy's pinv keeps all six and is the inverse.
REGULAR = 1e-6
#: One-sided Jacobi: columns whose cosine is under this are orthogonal.
JACOBI_TOL = 1e-15
JACOBI_SWEEPS = 60

_KERNEL = ("_polish_rows", "_polish_row", "_pose_error", "_jacobian", "_pinv_step",
           "_qr_solve", "_jacobi_pinv_step", "_rotate_columns", "_column_norm_sq", "_seen",
           "_merge")


def available():
    """True when the compiled kernel can be used (the first call compiles or loads it;
    a failure is kept in :data:`why_not` and the numpy code is used from then on)."""
    return numba_kernel.available(globals(), _compile)


def _compile():
    """Compile the kernel in place (:func:`.numba_kernel.compile_in_place`); "" or why not."""
    return compile_in_place(globals(), _KERNEL, _warm_up)


def _warm_up():
    H = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0],
                  [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])
    P = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 500.0], [100.0, 0.0, 0.0],
                  [400.0, 0.0, 0.0], [0.0, 0.0, 0.0], [80.0, 0.0, 0.0]])
    q = np.array([[0.1, 0.2, 0.3, 0.4, 0.5, 0.6], [0.1, 0.2, 0.3, 0.0, 0.0, 0.0]])
    polished_onto(H, P, np.eye(3), q[None], np.eye(4)[None], 2, 1, 1e4, 1e-6,
                  1e-9, 1e-10)
    merged(np.full((1, 2, 6), np.nan), np.zeros((1, 1, 6)), 1e-6)


def polished_onto(H, P, R_6T, found, T, steps, give_up_step, give_up_tol, position_tol,
                  rotation_tol, rcond):
    """Rows moved onto their poses by Newton steps: ``offset_wrist_polish._polished_onto``.

    Parameters
    ----------
    H : ndarray, shape (6, 3)
    P : ndarray, shape (7, 3)
    R_6T : ndarray, shape (3, 3)
        The arm (:class:`poe.ChainParameters`), mm.
    found : ndarray, shape (S, K, 6)
        rad; NaN rows are left NaN.
    T : ndarray, shape (S, 4, 4)
        Each row's pose, mm.
    steps, give_up_step : int
    give_up_tol, position_tol, rotation_tol : float
        As ``offset_wrist_polish.STEPS``, ``GIVE_UP_STEP``, ``GIVE_UP_TOL``,
        ``POSITION_TOL_MM`` (mm) and ``ROTATION_TOL_RAD`` (rad).
    rcond : float
        Singular values under rcond times the largest are dropped from each step.

    Returns
    -------
    ndarray, shape (S, K, 6)
        rad, wrapped into (-pi, pi]; NaN rows where the pose is not reproduced to the
        tolerances.
    """
    out = np.ascontiguousarray(found, dtype=float).copy()
    _polish_rows(np.ascontiguousarray(H, dtype=float), np.ascontiguousarray(P, dtype=float),
                 np.ascontiguousarray(R_6T, dtype=float), np.ascontiguousarray(T, dtype=float),
                 int(steps), int(give_up_step), float(give_up_tol), float(position_tol),
                 float(rotation_tol), float(rcond), out)
    return out


def _polish_rows(H, P, R_6T, T, steps, give_up_step, give_up_tol, position_tol, rotation_tol,
                 rcond, q):
    """:func:`polished_onto` in place on q (S, K, 6)."""
    e, dq, p = np.empty(6), np.empty(6), np.empty(3)
    axes, origins, R = np.empty((6, 3)), np.empty((6, 3)), np.empty((3, 3, 3))
    J, A, V, b = np.empty((6, 6)), np.empty((6, 6)), np.empty((6, 6)), np.empty(6)
    order = np.empty(6, dtype=np.int64)
    for pose in range(q.shape[0]):
        for r in range(q.shape[1]):
            row = q[pose, r]
            if math.isnan(row[0]):
                continue
            if _polish_row(H, P, R_6T, T[pose], steps, give_up_step, give_up_tol,
                           position_tol, rotation_tol, rcond, row, e, dq, p, axes, origins,
                           R, J, A, V, b, order):
                for i in range(6):               # into (-pi, pi], as offset_wrist_polish._wrap
                    row[i] = math.pi - (math.pi - row[i]) % (2.0 * math.pi)
            else:
                row[:] = np.nan


def _polish_row(H, P, R_6T, T, steps, give_up_step, give_up_tol, position_tol, rotation_tol,
                rcond, q, e, dq, p, axes, origins, R, J, A, V, b, order):
    """Newton steps on one row q (6,) in place, as ``offset_wrist_polish.polish`` takes
    them (a row stops where it is at rounding, and is given up after `give_up_step`
    steps when still far); True when it reproduces its pose T (4, 4)."""
    near = False
    for step in range(steps + 1):
        near = _pose_error(H, P, R_6T, q, T, e, p, axes, origins, R)
        if step == steps:
            break
        size = 0.0
        for i in range(3):
            if math.isnan(e[i]) or math.isnan(e[i + 3]):
                return False                 # (numpy's SVD raises on a NaN Jacobian)
            size = max(size, abs(e[i]) / position_tol, abs(e[i + 3]) / rotation_tol)
        if step >= give_up_step and not (near and size < give_up_tol):
            return False
        if near and size <= 0.01:
            break
        _jacobian(axes, origins, p, J)
        _pinv_step(J, e, rcond, dq, A, V, b, order)
        for i in range(6):
            q[i] += dq[i]
    position_sq = e[0] * e[0] + e[1] * e[1] + e[2] * e[2]
    rotation_sq = e[3] * e[3] + e[4] * e[4] + e[5] * e[5]
    finite = True
    for i in range(6):
        finite = finite and math.isfinite(q[i])
    return (near and math.sqrt(position_sq) <= position_tol
            and math.sqrt(rotation_sq) <= rotation_tol and finite)



def merged(rows, extra, same_rad):
    """`rows` plus the rows of `extra` found neither there nor earlier in `extra`.

    Parameters
    ----------
    rows : ndarray, shape (S, K, 6)
        rad, wrapped into (-pi, pi], NaN rows anywhere.
    extra : ndarray, shape (S, M, 6)
        rad, wrapped into (-pi, pi], NaN rows anywhere.
    same_rad : float
        Rows this close on every joint (modulo a turn) are one.

    Returns
    -------
    ndarray, shape (S, K, 6)
        Per pose the live rows of `rows`, then the new ones of `extra`, in order, then
        NaN rows (at most K).
    """
    out = np.full(rows.shape, np.nan)
    _merge(np.ascontiguousarray(rows, dtype=float), np.ascontiguousarray(extra, dtype=float),
           same_rad, out)
    return out


def _merge(rows, extra, same_rad, out):
    """:func:`merged` into out (S, K, 6), NaN on entry."""
    width = out.shape[1]
    for pose in range(rows.shape[0]):
        kept = 0
        for r in range(rows.shape[1]):               # the search's rows: distinct already
            if kept < width and not math.isnan(rows[pose, r, 0]):
                out[pose, kept] = rows[pose, r]
                kept += 1
        for r in range(extra.shape[1]):
            if kept < width and not math.isnan(extra[pose, r, 0]) and not _seen(
                    extra[pose, r], out[pose], kept, same_rad):
                out[pose, kept] = extra[pose, r]
                kept += 1


def _seen(row, rows, count, same_rad):
    """True when `row` (6,) is within `same_rad` of one of rows[:count] on every joint."""
    for k in range(count):
        same = True
        for j in range(6):
            d = abs(row[j] - rows[k, j])
            if min(d, 2.0 * math.pi - d) > same_rad:
                same = False
                break
        if same:
            return True
    return False


def _pose_error(H, P, R_6T, q, T, e, p, axes, origins, scratch):
    """The flange of joint values q (6,) against the pose T (4, 4), as
    ``offset_wrist_polish._errors``: e (6,) position (mm, pose minus flange) and rotation
    error (rad, the axis times the sine of the angle of ``R_pose R_flange^T``) in the base
    frame, p (3,) the flange's position (mm), and for the Jacobian each axis's direction
    and a point of it, axes and origins (6, 3) (base frame, mm). Returns whether the
    rotation error is under a quarter turn (where e measures it). scratch: (3, 3, 3)."""
    R, turn, F = scratch[0], scratch[1], scratch[2]
    for i in range(3):
        for j in range(3):
            R[i, j] = 1.0 if i == j else 0.0
        p[i] = P[0, i]
    for k in range(6):
        x, y, z = H[k, 0], H[k, 1], H[k, 2]
        for i in range(3):
            axes[k, i] = R[i, 0] * x + R[i, 1] * y + R[i, 2] * z
            origins[k, i] = p[i]
        c, s = math.cos(q[k]), math.sin(q[k])
        v = 1.0 - c
        turn[0, 0], turn[0, 1], turn[0, 2] = c + x * x * v, x * y * v - z * s, x * z * v + y * s
        turn[1, 0], turn[1, 1], turn[1, 2] = y * x * v + z * s, c + y * y * v, y * z * v - x * s
        turn[2, 0], turn[2, 1], turn[2, 2] = z * x * v - y * s, z * y * v + x * s, c + z * z * v
        for i in range(3):                           # R <- R turn, one row at a time
            r0, r1, r2 = R[i, 0], R[i, 1], R[i, 2]
            for j in range(3):
                R[i, j] = r0 * turn[0, j] + r1 * turn[1, j] + r2 * turn[2, j]
        for i in range(3):
            p[i] += R[i, 0] * P[k + 1, 0] + R[i, 1] * P[k + 1, 1] + R[i, 2] * P[k + 1, 2]
    for i in range(3):
        for j in range(3):
            F[i, j] = R[i, 0] * R_6T[0, j] + R[i, 1] * R_6T[1, j] + R[i, 2] * R_6T[2, j]
    E = turn                                         # E = R_pose F^T (turn is free now)
    for i in range(3):
        for j in range(3):
            E[i, j] = T[i, 0] * F[j, 0] + T[i, 1] * F[j, 1] + T[i, 2] * F[j, 2]
    for i in range(3):
        e[i] = T[i, 3] - p[i]
    e[3] = 0.5 * (E[2, 1] - E[1, 2])
    e[4] = 0.5 * (E[0, 2] - E[2, 0])
    e[5] = 0.5 * (E[1, 0] - E[0, 1])
    return E[0, 0] + E[1, 1] + E[2, 2] > 1.0


def _jacobian(axes, origins, p, J):
    """J (6, 6): the geometric Jacobian, columns (h_k x (p - o_k), h_k) in the base frame,
    of the axes h_k through the points o_k (6, 3) at the flange point p (3,), mm."""
    for k in range(6):
        hx, hy, hz = axes[k, 0], axes[k, 1], axes[k, 2]
        dx, dy, dz = p[0] - origins[k, 0], p[1] - origins[k, 1], p[2] - origins[k, 2]
        J[0, k], J[1, k], J[2, k] = hy * dz - hz * dy, hz * dx - hx * dz, hx * dy - hy * dx
        J[3, k], J[4, k], J[5, k] = hx, hy, hz


def _pinv_step(J, e, rcond, dq, A, V, b, order):
    """dq (6,) = pinv(J, rcond) e for J (6, 6): by pivoted QR where that shows J regular
    (:data:`REGULAR`), else by the SVD (:func:`_jacobi_pinv_step`). A, V (6, 6), b (6,)
    and order (6,) are scratch."""
    if not _qr_solve(J, e, dq, A, b, order):
        _jacobi_pinv_step(J, e, rcond, dq, A, V)


def _qr_solve(J, e, dq, A, b, order):
    """dq (6,) = J^-1 e by Householder QR with column pivoting, when J (6, 6) is regular
    by :data:`REGULAR`; False (dq untouched) when it is not."""
    n = 6
    for i in range(n):
        b[i] = e[i]
        order[i] = i
        for j in range(n):
            A[i, j] = J[i, j]
    for k in range(n):
        best, pivot = -1.0, k                    # the remaining column of largest norm
        for j in range(k, n):
            norm_sq = _column_norm_sq(A, j, k)
            if norm_sq > best:
                best, pivot = norm_sq, j
        if pivot != k:
            for i in range(n):
                A[i, k], A[i, pivot] = A[i, pivot], A[i, k]
            order[k], order[pivot] = order[pivot], order[k]
        if k == n - 1:                           # r_66 = A[5, 5] as it stands
            break
        alpha = -math.sqrt(best) if A[k, k] >= 0.0 else math.sqrt(best)
        v0 = A[k, k] - alpha                     # reflector v = (v0, A[k+1:, k])
        v_sq = v0 * v0 + best - A[k, k] * A[k, k]
        if v_sq > 0.0:
            for j in range(k + 1, n):
                dot = v0 * A[k, j]
                for i in range(k + 1, n):
                    dot += A[i, k] * A[i, j]
                f = 2.0 * dot / v_sq
                A[k, j] -= f * v0
                for i in range(k + 1, n):
                    A[i, j] -= f * A[i, k]
            dot = v0 * b[k]
            for i in range(k + 1, n):
                dot += A[i, k] * b[i]
            f = 2.0 * dot / v_sq
            b[k] -= f * v0
            for i in range(k + 1, n):
                b[i] -= f * A[i, k]
        A[k, k] = alpha
    if not abs(A[n - 1, n - 1]) >= REGULAR * abs(A[0, 0]):
        return False
    for k in range(n - 1, -1, -1):               # R y = Q^T e, dq[order] = y
        y = b[k]
        for j in range(k + 1, n):
            y -= A[k, j] * dq[order[j]]
        dq[order[k]] = y / A[k, k]
    return True


def _jacobi_pinv_step(J, e, rcond, dq, A, V):
    """dq (6,) = pinv(J, rcond) e for J (6, 6) by the SVD from one-sided Jacobi rotations:
    ``J V = A`` with orthogonal columns, the singular values their norms; those under
    rcond times the largest are dropped, as numpy's pinv drops them."""
    n = 6
    for i in range(n):
        for j in range(n):
            A[i, j] = J[i, j]
            V[i, j] = 1.0 if i == j else 0.0
    for sweep in range(JACOBI_SWEEPS):
        rotated = False
        for i in range(n - 1):
            for j in range(i + 1, n):
                if _rotate_columns(A, V, i, j):
                    rotated = True
        if not rotated:
            break
    largest_sq = 0.0
    for k in range(n):
        largest_sq = max(largest_sq, _column_norm_sq(A, k, 0))
    for i in range(n):
        dq[i] = 0.0
    for k in range(n):
        sigma_sq = _column_norm_sq(A, k, 0)
        if sigma_sq > rcond * rcond * largest_sq:
            along = 0.0                          # (u_k . e) / sigma_k, u_k = A_k / sigma_k
            for i in range(n):
                along += A[i, k] * e[i]
            along /= sigma_sq
            for i in range(n):
                dq[i] += V[i, k] * along


def _rotate_columns(A, V, i, j):
    """One Jacobi rotation making columns i and j of A (6, 6) orthogonal, applied to V
    too; False when they already are (to :data:`JACOBI_TOL`)."""
    alpha = beta = gamma = 0.0
    for k in range(A.shape[0]):
        alpha += A[k, i] * A[k, i]
        beta += A[k, j] * A[k, j]
        gamma += A[k, i] * A[k, j]
    if abs(gamma) <= JACOBI_TOL * math.sqrt(alpha * beta):
        return False
    zeta = (beta - alpha) / (2.0 * gamma)
    t = (1.0 if zeta >= 0.0 else -1.0) / (abs(zeta) + math.sqrt(1.0 + zeta * zeta))
    c = 1.0 / math.sqrt(1.0 + t * t)
    s = c * t
    for k in range(A.shape[0]):
        a_i, a_j = A[k, i], A[k, j]
        A[k, i], A[k, j] = c * a_i - s * a_j, s * a_i + c * a_j
        v_i, v_j = V[k, i], V[k, j]
        V[k, i], V[k, j] = c * v_i - s * v_j, s * v_i + c * v_j
    return True


def _column_norm_sq(A, j, start):
    """The squared norm of column j of A from row `start` down."""
    norm_sq = 0.0
    for i in range(start, A.shape[0]):
        norm_sq += A[i, j] * A[i, j]
    return norm_sq
