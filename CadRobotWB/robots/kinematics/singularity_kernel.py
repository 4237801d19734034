"""The singularity distance compiled with numba: the fast path of
:func:`singularity.distance_deg` (Place robot measures it on every solution it screens).

numba is optional, as for :mod:`.opw_kernel`: without it, switched off by
``CADROBOT_NUMBA=0``, or where it fails to compile, :func:`singularity.distance_deg`
runs its numpy code, which stays the reference (the tests compare the two).

Per joint vector, in scalars: the axes' twists as :func:`singularity.spatial_twists`
builds them, ``J``'s LU factors with partial pivoting (the determinant is the product
of the pivots; a zero pivot is a singular J: distance 0), ``adj(J) = det J * J^-1``
from them, and the gradient ``sum_{j > i} adj(J)[j] . [xi_i, xi_j]``.
"""

import math

import numpy as np

from . import numba_kernel
from .numba_kernel import compile_in_place


#: Why the compiled kernel is not used ("" while it is, None before the first call of
#: :func:`available`).
why_not = None


def available():
    """True when the compiled kernel can be used (the first call compiles or loads it;
    a failure is kept in :data:`why_not` and the numpy code is used from then on)."""
    return numba_kernel.available(globals(), _compile)


def _compile():
    """Compile the kernel in place (:func:`.numba_kernel.compile_in_place`); "" or why not."""
    return compile_in_place(globals(), ("_one", "distances"), lambda: distances(
        np.eye(3)[[2, 1, 1, 0, 1, 0]], np.ones((7, 3)), np.zeros((1, 6))))


def distances(H, P, q_rad):
    """:func:`singularity.distance_deg` of rows `q_rad` (M, 6) with no NaN, deg (M,)."""
    out = np.empty(q_rad.shape[0])
    R = np.empty((3, 3))
    J = np.empty((6, 6))
    LU = np.empty((6, 6))
    inv = np.empty((6, 6))
    perm = np.empty(6, dtype=np.int64)
    for n in range(q_rad.shape[0]):
        out[n] = _one(H, P, q_rad[n], R, J, LU, inv, perm)
    return out


def _one(H, P, q, R, J, LU, inv, perm):
    # Twists: column i is (o_i x w_i / 1000, w_i); R turns link i-1 into the base frame.
    for a in range(3):
        for b in range(3):
            R[a, b] = 1.0 if a == b else 0.0
    o0, o1, o2 = 0.0, 0.0, 0.0
    for i in range(6):
        w0 = R[0, 0] * H[i, 0] + R[0, 1] * H[i, 1] + R[0, 2] * H[i, 2]
        w1 = R[1, 0] * H[i, 0] + R[1, 1] * H[i, 1] + R[1, 2] * H[i, 2]
        w2 = R[2, 0] * H[i, 0] + R[2, 1] * H[i, 1] + R[2, 2] * H[i, 2]
        o0 += (R[0, 0] * P[i, 0] + R[0, 1] * P[i, 1] + R[0, 2] * P[i, 2]) / 1000.0
        o1 += (R[1, 0] * P[i, 0] + R[1, 1] * P[i, 1] + R[1, 2] * P[i, 2]) / 1000.0
        o2 += (R[2, 0] * P[i, 0] + R[2, 1] * P[i, 1] + R[2, 2] * P[i, 2]) / 1000.0
        J[0, i], J[1, i], J[2, i] = o1 * w2 - o2 * w1, o2 * w0 - o0 * w2, o0 * w1 - o1 * w0
        J[3, i], J[4, i], J[5, i] = w0, w1, w2
        # R <- R rot(H_i, q_i), Rodrigues: rot = I + s K + (1 - c) K K.
        h0, h1, h2 = H[i, 0], H[i, 1], H[i, 2]
        s, c = math.sin(q[i]), math.cos(q[i])
        t = 1.0 - c
        m00, m01, m02 = c + t * h0 * h0, t * h0 * h1 - s * h2, t * h0 * h2 + s * h1
        m10, m11, m12 = t * h1 * h0 + s * h2, c + t * h1 * h1, t * h1 * h2 - s * h0
        m20, m21, m22 = t * h2 * h0 - s * h1, t * h2 * h1 + s * h0, c + t * h2 * h2
        for a in range(3):
            r0, r1, r2 = R[a, 0], R[a, 1], R[a, 2]
            R[a, 0] = r0 * m00 + r1 * m10 + r2 * m20
            R[a, 1] = r0 * m01 + r1 * m11 + r2 * m21
            R[a, 2] = r0 * m02 + r1 * m12 + r2 * m22
    # LU with partial pivoting; det = sign * product of pivots.
    for a in range(6):
        perm[a] = a
        for b in range(6):
            LU[a, b] = J[a, b]
    det = 1.0
    for k in range(6):
        p = k
        for a in range(k + 1, 6):
            if abs(LU[a, k]) > abs(LU[p, k]):
                p = a
        if LU[p, k] == 0.0:
            return 0.0
        if p != k:
            det = -det
            for b in range(6):
                LU[k, b], LU[p, b] = LU[p, b], LU[k, b]
            perm[k], perm[p] = perm[p], perm[k]
        det *= LU[k, k]
        for a in range(k + 1, 6):
            LU[a, k] /= LU[k, k]
            for b in range(k + 1, 6):
                LU[a, b] -= LU[a, k] * LU[k, b]
    # inv = J^-1, one column of the identity at a time (rows permuted).
    for col in range(6):
        for a in range(6):
            x = 1.0 if perm[a] == col else 0.0
            for b in range(a):
                x -= LU[a, b] * inv[b, col]
            inv[a, col] = x
        for a in range(5, -1, -1):
            x = inv[a, col]
            for b in range(a + 1, 6):
                x -= LU[a, b] * inv[b, col]
            inv[a, col] = x / LU[a, a]
    # grad_i = sum_{j > i} det * inv[j] . [xi_i, xi_j]
    norm_sq = 0.0
    for i in range(6):
        g = 0.0
        for j in range(i + 1, 6):
            vi0, vi1, vi2, wi0, wi1, wi2 = J[0, i], J[1, i], J[2, i], J[3, i], J[4, i], J[5, i]
            vj0, vj1, vj2, wj0, wj1, wj2 = J[0, j], J[1, j], J[2, j], J[3, j], J[4, j], J[5, j]
            b0 = (wi1 * vj2 - wi2 * vj1) - (wj1 * vi2 - wj2 * vi1)
            b1 = (wi2 * vj0 - wi0 * vj2) - (wj2 * vi0 - wj0 * vi2)
            b2 = (wi0 * vj1 - wi1 * vj0) - (wj0 * vi1 - wj1 * vi0)
            b3, b4, b5 = wi1 * wj2 - wi2 * wj1, wi2 * wj0 - wi0 * wj2, wi0 * wj1 - wi1 * wj0
            g += (inv[j, 0] * b0 + inv[j, 1] * b1 + inv[j, 2] * b2 + inv[j, 3] * b3
                  + inv[j, 4] * b4 + inv[j, 5] * b5)
        norm_sq += g * g
    # |det| / |det * g| = 1 / |g|
    return math.degrees(1.0 / math.sqrt(norm_sq)) if norm_sq > 0.0 else math.inf
