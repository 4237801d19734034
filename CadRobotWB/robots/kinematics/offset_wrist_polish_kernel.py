"""The offset-wrist repair's two costly loops compiled with numba (:mod:`.offset_wrist_polish`).

They are the forward kinematics with the error of each row against its pose (each
Newton step and the final check of :func:`offset_wrist_polish.polish`), and the merge
of the rows found into the search's (:func:`offset_wrist_polish._merged`). Per row and
per pose in scalars they cost a ninth (the errors: 0.018 s against 0.166 s for 50,000
rows) and an eightieth (the merge: 0.009 s against 0.78 s for 20,000 poses) of the numpy
code, whose arrays of 3 x 3 products and row comparisons are walked once per operation.

numba is optional, as for :mod:`.opw_kernel` and :mod:`.offset_wrist_kernel`: without
it, switched off by ``CADROBOT_NUMBA=0``, or where it fails to compile,
:mod:`.offset_wrist_polish` runs its numpy code, which stays the reference; the tests
compare the two. The first call in a session loads the compiled code from numba's
cache (0.2 s of CPU), or compiles it (6.4 s of CPU on this project's machine, once per
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

_KERNEL = ("_errors", "_seen", "_merge")


def available():
    """True when the compiled kernel can be used (the first call compiles or loads it;
    a failure is kept in :data:`why_not` and the numpy code is used from then on)."""
    return numba_kernel.available(globals(), _compile)


def _compile():
    """Compile the kernel in place (:func:`.numba_kernel.compile_in_place`); "" or why not."""
    return compile_in_place(globals(), _KERNEL, _warm_up)


def _warm_up():
    errors(np.eye(3).repeat(2, axis=0), np.zeros((7, 3)), np.eye(3), np.zeros((1, 6)),
           np.eye(4)[None])
    merged(np.full((1, 2, 6), np.nan), np.zeros((1, 1, 6)), 1e-6)


def errors(H, P, R_6T, q, T):
    """Each row's flange against its pose: as ``offset_wrist_polish._errors``.

    Parameters
    ----------
    H : ndarray, shape (6, 3)
    P : ndarray, shape (7, 3)
    R_6T : ndarray, shape (3, 3)
        The arm (:class:`poe.ChainParameters`), mm.
    q : ndarray, shape (M, 6)
        rad.
    T : ndarray, shape (M, 4, 4)
        The poses, mm.

    Returns
    -------
    e : ndarray, shape (M, 6)
        Position error (mm, pose minus flange) and rotation error (rad: the axis times
        the sine of the angle of ``R_pose R_flange^T``), in the base frame.
    near : ndarray of bool, shape (M,)
        The rotation error is under a quarter turn (where e measures it).
    p : ndarray, shape (M, 3)
        The flange's position, mm.
    """
    m = q.shape[0]
    e, near, p = np.empty((m, 6)), np.empty(m, dtype=np.bool_), np.empty((m, 3))
    _errors(np.ascontiguousarray(H, dtype=float), np.ascontiguousarray(P, dtype=float),
            np.ascontiguousarray(R_6T, dtype=float), np.ascontiguousarray(q, dtype=float),
            np.ascontiguousarray(T, dtype=float), e, near, p)
    return e, near, p


def _errors(H, P, R_6T, q, T, e, near, p):
    """:func:`errors` into e (M, 6), near (M,), p (M, 3)."""
    R, turn, F, E = np.empty((3, 3)), np.empty((3, 3)), np.empty((3, 3)), np.empty((3, 3))
    for row in range(q.shape[0]):
        for i in range(3):
            for j in range(3):
                R[i, j] = 1.0 if i == j else 0.0
            p[row, i] = P[0, i]
        for k in range(6):
            x, y, z = H[k, 0], H[k, 1], H[k, 2]
            c, s = math.cos(q[row, k]), math.sin(q[row, k])
            v = 1.0 - c
            turn[0, 0], turn[0, 1], turn[0, 2] = c + x * x * v, x * y * v - z * s, x * z * v + y * s
            turn[1, 0], turn[1, 1], turn[1, 2] = y * x * v + z * s, c + y * y * v, y * z * v - x * s
            turn[2, 0], turn[2, 1], turn[2, 2] = z * x * v - y * s, z * y * v + x * s, c + z * z * v
            for i in range(3):                       # R <- R turn, one row at a time
                r0, r1, r2 = R[i, 0], R[i, 1], R[i, 2]
                for j in range(3):
                    R[i, j] = r0 * turn[0, j] + r1 * turn[1, j] + r2 * turn[2, j]
            for i in range(3):
                p[row, i] += R[i, 0] * P[k + 1, 0] + R[i, 1] * P[k + 1, 1] + R[i, 2] * P[k + 1, 2]
        for i in range(3):
            for j in range(3):
                F[i, j] = R[i, 0] * R_6T[0, j] + R[i, 1] * R_6T[1, j] + R[i, 2] * R_6T[2, j]
        for i in range(3):                           # E = R_pose F^T
            for j in range(3):
                E[i, j] = T[row, i, 0] * F[j, 0] + T[row, i, 1] * F[j, 1] + T[row, i, 2] * F[j, 2]
        for i in range(3):
            e[row, i] = T[row, i, 3] - p[row, i]
        e[row, 3] = 0.5 * (E[2, 1] - E[1, 2])
        e[row, 4] = 0.5 * (E[0, 2] - E[2, 0])
        e[row, 5] = 0.5 * (E[1, 0] - E[0, 1])
        near[row] = E[0, 0] + E[1, 1] + E[2, 2] > 1.0


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
