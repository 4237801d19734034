"""The spherical-wrist inverse (:mod:`.spherical_wrist`) compiled with numba.

The same steps as ``spherical_wrist.inverse_numpy``, one pose and one branch at a time
in scalar code: numpy's version makes a pass over memory per operation on arrays of
(N, 2, 2, 2, 3), which caps it near 10,000 poses per second.  Vectors are tuples of
three floats; rotations are applied by Rodrigues' formula; every angle is carried as its
cosine and sine (from normalised vectors and angle sums, no sin/cos call), and turned
into radians by one atan2 when a solution is written.  The answers agree with numpy's
to rounding (tests/core/test_spherical_wrist.py).

As :mod:`.opw_kernel`: ``CADROBOT_NUMBA=0`` switches it off, a numba that is missing or
cannot compile leaves the numpy code in charge (:data:`why_not` says why), and the
compiled code is cached by numba (the first call in a session loads it, or compiles it
once, a few seconds).  Never imports FreeCAD.
"""

import math

import numpy as np

from . import subproblems
from . import numba_kernel
from .numba_kernel import compile_in_place


#: Layout of the constants vector (see :func:`constants_vector`): start of each field.
H_ = 0            # 6 axes x 3
P_ = 18           # the arm's 7 vectors x 3, mm
R6T_ = 39         # 3 x 3, row-major
P01_, P12_, P23_, P3W_, PWT_, V6_ = 48, 51, 54, 57, 60, 63
D1_ = 66          # h2 . (P_12 + P_23 + P_3W)
(STEPS_, CONVERGED_, CORRECTABLE_, POSITION_TOL_, ROTATION_TOL_, DUPLICATE_TOL_,
 WRAP_AT_, DEGENERATE_) = range(67, 75)
WRIST_HALF_ANGLES_ = 75     # sin, cos of (alpha - beta) / 2 and (alpha + beta) / 2
N_CONSTANTS = 79

#: Why the compiled kernel is not used ("" while it is, None before the first call of
#: :func:`available`).
why_not = None


def available():
    """True when the compiled kernel can be used (the first call compiles or loads it)."""
    return numba_kernel.available(globals(), _compile)


_INLINED = ("_unit", "_plus_minus", "_distance", "_dot", "_cross", "_rotate", "_sp1", "_sp4", "_sp4_unit",
            "_vector", "_matvec", "_matmul", "_rotation", "_wrap", "_shoulder", "_elbow",
            "_undo_arm", "_wrist")
_COMPILED = ("_solve_branch", "_chain", "_checked", "_keep", "_solve")


def _compile():
    """Compile the kernel in place (:func:`.numba_kernel.compile_in_place`); "" or why not."""
    return compile_in_place(globals(), _INLINED + _COMPILED, _warm_up, _INLINED)


def _warm_up():
    c = np.zeros(N_CONSTANTS)
    c[[H_ + 2, H_ + 4, H_ + 7, H_ + 9, H_ + 13, H_ + 15]] = 1.0
    _solve(c, np.eye(4)[None], np.empty((1, 8, 6)))


def constants_vector(k):
    """The kernel's constants from ``spherical_wrist``'s (a dict of its Constants' fields).

    Returns
    -------
    ndarray, shape (N_CONSTANTS,)
    """
    from . import spherical_wrist as sw   # it imports this module first

    c = np.zeros(N_CONSTANTS)
    params = k["params"]
    c[H_:H_ + 18] = np.asarray(params.H, dtype=float).ravel()
    c[P_:P_ + 21] = np.asarray(params.P, dtype=float).ravel()
    c[R6T_:R6T_ + 9] = np.asarray(params.R_6T, dtype=float).ravel()
    for start, name in ((P01_, "P_01"), (P12_, "P_12"), (P23_, "P_23"), (P3W_, "P_3W"),
                        (PWT_, "P_WT"), (V6_, "v6")):
        c[start:start + 3] = k[name]
    c[D1_] = c[H_ + 3:H_ + 6] @ (k["P_12"] + k["P_23"] + k["P_3W"])
    c[STEPS_], c[CONVERGED_] = k["correction_steps"], sw.CORRECTION_CONVERGED_MM
    c[CORRECTABLE_] = sw.CORRECTABLE_MM
    c[DEGENERATE_] = subproblems.DEGENERATE_NORM
    H = c[H_:H_ + 18].reshape(6, 3)
    c[WRIST_HALF_ANGLES_:WRIST_HALF_ANGLES_ + 4] = subproblems.half_angle_sums(H[3], H[4], H[5])
    c[POSITION_TOL_], c[ROTATION_TOL_] = sw.POSITION_TOL_MM, sw.ROTATION_TOL_RAD
    c[DUPLICATE_TOL_], c[WRAP_AT_] = sw.DUPLICATE_TOL_RAD, math.pi + sw.WRAP_TOL_RAD
    return c


# ---- small vector helpers (inlined) -------------------------------------------------

def _vector(c, start):
    return c[start], c[start + 1], c[start + 2]


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _rotate(k, cos, sin, v):
    """rot(k, theta) v from cos and sin of theta (Rodrigues)."""
    kxv = _cross(k, v)
    along = (1.0 - cos) * _dot(k, v)
    return (cos * v[0] + sin * kxv[0] + along * k[0], cos * v[1] + sin * kxv[1] + along * k[1],
            cos * v[2] + sin * kxv[2] + along * k[2])


def _rotation(k, cos, sin):
    """rot(k, theta) as a row-major 9-tuple, from cos and sin of theta."""
    t = 1.0 - cos
    x, y, z = k
    return (cos + t * x * x, t * x * y - sin * z, t * x * z + sin * y,
            t * x * y + sin * z, cos + t * y * y, t * y * z - sin * x,
            t * x * z - sin * y, t * y * z + sin * x, cos + t * z * z)


def _matvec(R, v):
    return (R[0] * v[0] + R[1] * v[1] + R[2] * v[2], R[3] * v[0] + R[4] * v[1] + R[5] * v[2],
            R[6] * v[0] + R[7] * v[1] + R[8] * v[2])


def _matmul(A, B):
    return (A[0] * B[0] + A[1] * B[3] + A[2] * B[6], A[0] * B[1] + A[1] * B[4] + A[2] * B[7],
            A[0] * B[2] + A[1] * B[5] + A[2] * B[8],
            A[3] * B[0] + A[4] * B[3] + A[5] * B[6], A[3] * B[1] + A[4] * B[4] + A[5] * B[7],
            A[3] * B[2] + A[4] * B[5] + A[5] * B[8],
            A[6] * B[0] + A[7] * B[3] + A[8] * B[6], A[6] * B[1] + A[7] * B[4] + A[8] * B[7],
            A[6] * B[2] + A[7] * B[5] + A[8] * B[8])


def _distance(a, b):
    dx, dy, dz = a[0] - b[0], a[1] - b[1], a[2] - b[2]
    return math.sqrt(dx * dx + dy * dy + dz * dz)


def _wrap(q, wrap_at):
    return q - 2.0 * math.pi * math.ceil((q - wrap_at) / (2.0 * math.pi))


def _unit(y, x):
    """cos and sin of atan2(y, x), from the normalised vector ((1, 0) for a zero one)."""
    norm = math.sqrt(x * x + y * y)
    if norm == 0.0:
        return 1.0, 0.0
    return x / norm, y / norm


def _sp1(p1, p2, k, degenerate):
    """Subproblem 1 (``subproblems.sp1``): cos and sin of the angle turning p1 onto p2
    about k ((1, 0) where p1 lies on the axis: ``|k x p1| <= degenerate |p1|``)."""
    kxp1 = _cross(k, p1)
    if _dot(kxp1, kxp1) <= degenerate * degenerate * _dot(p1, p1):
        return 1.0, 0.0
    along = _dot(k, p1)
    perp = (p1[0] - along * k[0], p1[1] - along * k[1], p1[2] - along * k[2])
    return _unit(_dot(kxp1, p2), _dot(perp, p2))


def _sp4(h, p, k, d, root):
    """Subproblem 4 (``subproblems.sp4``): cos and sin of root 0 or 1 of
    h . rot(k, theta) p = d (the least-squares angle where there is none).

    theta = phase +- spread with cos(spread) the clipped ratio below: the cosine and sine
    of the sum come from those of its terms."""
    kxp = _cross(k, p)
    along = _dot(k, p)
    perp = (p[0] - along * k[0], p[1] - along * k[1], p[2] - along * k[2])
    a_sin, a_cos = _dot(h, kxp), _dot(h, perp)
    amplitude = math.sqrt(a_sin * a_sin + a_cos * a_cos)
    if amplitude > 0.0:
        cos_phase, sin_phase = a_cos / amplitude, a_sin / amplitude
        cos_spread = min(max((d - along * _dot(h, k)) / amplitude, -1.0), 1.0)
    else:
        cos_phase, sin_phase, cos_spread = 1.0, 0.0, 0.0
    return _plus_minus(cos_phase, sin_phase, cos_spread,
                       math.sqrt((1.0 - cos_spread) * (1.0 + cos_spread)), root)


def _plus_minus(cos_a, sin_a, cos_b, sin_b, root):
    """cos and sin of a + b (root 0) or a - b (root 1)."""
    if root != 0:
        sin_b = -sin_b
    return cos_a * cos_b - sin_a * sin_b, sin_a * cos_b + cos_a * sin_b


# ---- the stages of a branch: angles as (cos, sin) ---------------------------------------

def _shoulder(c, p_w, i):
    """q1 (root i) for the wrist centre p_w seen from axis 1, and the wrist centre seen
    from axis 2 with q1 undone."""
    h1, P_12 = _vector(c, H_), _vector(c, P12_)
    c1, s1 = _sp4(_vector(c, H_ + 3), p_w, (-h1[0], -h1[1], -h1[2]), c[D1_], i)
    turned = _rotate(h1, c1, -s1, p_w)
    return c1, s1, (turned[0] - P_12[0], turned[1] - P_12[1], turned[2] - P_12[2])


def _elbow(c, reach, j):
    """q3 (root j) by SP3 and q2 by SP1 for the wrist centre `reach` seen from axis 2."""
    P_23, P_3W = _vector(c, P23_), _vector(c, P3W_)
    half = 0.5 * (_dot(P_3W, P_3W) + _dot(P_23, P_23) - _dot(reach, reach))
    c3, s3 = _sp4((-P_23[0], -P_23[1], -P_23[2]), P_3W, _vector(c, H_ + 6), half, j)
    arm = _rotate(_vector(c, H_ + 6), c3, s3, P_3W)
    c2, s2 = _sp1((P_23[0] + arm[0], P_23[1] + arm[1], P_23[2] + arm[2]), reach,
                  _vector(c, H_ + 3), c[DEGENERATE_])
    return c2, s2, c3, s3


def _undo_arm(c, R_06, v, c1, s1, c2, s2, c3, s3):
    """R_36 v = rot(h3, -q3) rot(h2, -q2) rot(h1, -q1) R_06 v."""
    turned = _rotate(_vector(c, H_), c1, -s1, _matvec(R_06, v))
    return _rotate(_vector(c, H_ + 6), c3, -s3, _rotate(_vector(c, H_ + 3), c2, -s2, turned))


def _sp4_unit(c, h, p, k, x, root):
    """``subproblems.sp4_unit`` for the wrist (h4, h6, h5, whose half-angle sums are in
    the constants): cos and sin of root 0 or 1."""
    kxp = _cross(k, p)
    along = _dot(k, p)
    perp = (p[0] - along * k[0], p[1] - along * k[1], p[2] - along * k[2])
    cos_phase, sin_phase = _unit(_dot(h, kxp), _dot(h, perp))
    sin_d, cos_d = c[WRIST_HALF_ANGLES_], c[WRIST_HALF_ANGLES_ + 1]
    sin_e, cos_e = c[WRIST_HALF_ANGLES_ + 2], c[WRIST_HALF_ANGLES_ + 3]
    sin_x = 0.5 * math.sqrt((h[0] - x[0]) ** 2 + (h[1] - x[1]) ** 2 + (h[2] - x[2]) ** 2)
    cos_x = 0.5 * math.sqrt((h[0] + x[0]) ** 2 + (h[1] + x[1]) ** 2 + (h[2] + x[2]) ** 2)
    u = max((sin_x * cos_d + cos_x * sin_d) * (sin_x * cos_d - cos_x * sin_d), 0.0)
    v = max((sin_e * cos_x + cos_e * sin_x) * (sin_e * cos_x - cos_e * sin_x), 0.0)
    cos_spread, sin_spread = _unit(2.0 * math.sqrt(u * v), v - u)
    return _plus_minus(cos_phase, sin_phase, cos_spread, sin_spread, root)


def _wrist(c, h6_in_3, v6_in_3, l):
    """q5 (root l) by SP4, q4 and q6 by SP1, from R_36 h6 and R_36 v6."""
    h4, h5, h6, v6 = _vector(c, H_ + 9), _vector(c, H_ + 12), _vector(c, H_ + 15), _vector(c, V6_)
    degenerate = c[DEGENERATE_]
    c5, s5 = _sp4_unit(c, h4, h6, h5, h6_in_3, l)
    c4, s4 = _sp1(_rotate(h5, c5, s5, h6), h6_in_3, h4, degenerate)
    c6, s6 = _sp1(v6, _rotate(h5, c5, -s5, _rotate(h4, c4, -s4, v6_in_3)), h6, degenerate)
    return c4, s4, c5, s5, c6, s6


def _solve_branch(c, p_w, R_06, i, j, l):
    """The branch (q1 root i, q3 root j, q5 root l) for wrist centre p_w (seen from axis
    1) and R_06 (9-tuple): cosines and sines of the six angles (a root that does not exist
    is the least-squares angle: the check decides)."""
    c1, s1, reach = _shoulder(c, p_w, i)
    c2, s2, c3, s3 = _elbow(c, reach, j)
    c4, s4, c5, s5, c6, s6 = _wrist(c, _undo_arm(c, R_06, _vector(c, H_ + 15), c1, s1, c2, s2,
                                                 c3, s3),
                                    _undo_arm(c, R_06, _vector(c, V6_), c1, s1, c2, s2, c3, s3), l)
    return (c1, c2, c3, c4, c5, c6), (s1, s2, s3, s4, s5, s6)


def _chain(c, cos, sin):
    """R_06 (9-tuple), the flange of the arm as given and that of the spherical model
    (as ``spherical_wrist.flanges``), mm, at the joint values of
    cosines and sines `cos`, `sin` (6-tuples)."""
    R = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
    flange = _vector(c, P_)
    model = flange
    for joint in range(6):
        R = _matmul(R, _rotation(_vector(c, H_ + 3 * joint), cos[joint], sin[joint]))
        step = _matvec(R, _vector(c, P_ + 3 * joint + 3))
        flange = (flange[0] + step[0], flange[1] + step[1], flange[2] + step[2])
        if joint < 2:
            model = flange
        elif joint == 2 or joint == 5:
            step = _matvec(R, _vector(c, P3W_ if joint == 2 else PWT_))
            model = (model[0] + step[0], model[1] + step[1], model[2] + step[2])
    return R, flange, model


def _checked(c, cos, sin, p_w, R_06, p_0T, i, j, l):
    """A branch corrected onto the arm as given (:data:`STEPS_` at most) and checked: its
    cosines and sines, and whether the flange there is within the tolerances of the pose.
    A least-squares root that reproduces the pose is a solution too: at an elbow or wrist
    fold the roots meet, and rounding can put the pose a hair beyond."""
    R, flange, model = _chain(c, cos, sin)
    position = _distance(flange, p_0T)
    for _ in range(int(c[STEPS_])):
        if position <= c[CONVERGED_] or position > c[CORRECTABLE_]:
            break
        moved = (p_w[0] - flange[0] + model[0], p_w[1] - flange[1] + model[1],
                 p_w[2] - flange[2] + model[2])
        cos, sin = _solve_branch(c, moved, R_06, i, j, l)
        R, flange, model = _chain(c, cos, sin)
        position = _distance(flange, p_0T)
    # The angle of E = R_06(target) R_06(q)^T.
    E = _matmul(R_06, (R[0], R[3], R[6], R[1], R[4], R[7], R[2], R[5], R[8]))
    wx, wy, wz = E[7] - E[5], E[2] - E[6], E[3] - E[1]
    rotation = math.atan2(math.sqrt(wx * wx + wy * wy + wz * wz), E[0] + E[4] + E[8] - 1.0)
    return cos, sin, position <= c[POSITION_TOL_] and rotation <= c[ROTATION_TOL_]


def _keep(c, out, n, kept, cos, sin):
    """Write the angles of (cos, sin) into row `kept` of pose n unless an earlier row holds
    the same solution; the rows kept now."""
    wrap_at = c[WRAP_AT_]
    q = (_wrap(math.atan2(sin[0], cos[0]), wrap_at), _wrap(math.atan2(sin[1], cos[1]), wrap_at),
         _wrap(math.atan2(sin[2], cos[2]), wrap_at), _wrap(math.atan2(sin[3], cos[3]), wrap_at),
         _wrap(math.atan2(sin[4], cos[4]), wrap_at), _wrap(math.atan2(sin[5], cos[5]), wrap_at))
    for r in range(kept):
        gap = 0.0
        for joint in range(6):
            gap = max(gap, abs(_wrap(q[joint] - out[n, r, joint], wrap_at)))
        if gap <= c[DUPLICATE_TOL_]:
            return kept
    for joint in range(6):
        out[n, kept, joint] = q[joint]
    return kept + 1


def _solve(c, T, out):
    """Fill out (n, 8, 6) with every solution of each pose T (n, 4, 4), radians.

    The branches share their first stages (q1 per shoulder, q2 and q3 per elbow)."""
    R_T6 = (c[R6T_], c[R6T_ + 3], c[R6T_ + 6], c[R6T_ + 1], c[R6T_ + 4], c[R6T_ + 7],
            c[R6T_ + 2], c[R6T_ + 5], c[R6T_ + 8])
    P_01, P_WT = _vector(c, P01_), _vector(c, PWT_)
    h6, v6 = _vector(c, H_ + 15), _vector(c, V6_)
    for n in range(T.shape[0]):
        R_0T = (T[n, 0, 0], T[n, 0, 1], T[n, 0, 2], T[n, 1, 0], T[n, 1, 1], T[n, 1, 2],
                T[n, 2, 0], T[n, 2, 1], T[n, 2, 2])
        p_0T = (T[n, 0, 3], T[n, 1, 3], T[n, 2, 3])
        R_06 = _matmul(R_0T, R_T6)
        tool = _matvec(R_06, P_WT)
        p_w = (p_0T[0] - tool[0] - P_01[0], p_0T[1] - tool[1] - P_01[1],
               p_0T[2] - tool[2] - P_01[2])
        kept = 0
        for i in range(2):
            c1, s1, reach = _shoulder(c, p_w, i)
            for j in range(2):
                c2, s2, c3, s3 = _elbow(c, reach, j)
                h6_in_3 = _undo_arm(c, R_06, h6, c1, s1, c2, s2, c3, s3)
                v6_in_3 = _undo_arm(c, R_06, v6, c1, s1, c2, s2, c3, s3)
                for l in range(2):
                    c4, s4, c5, s5, c6, s6 = _wrist(c, h6_in_3, v6_in_3, l)
                    cos, sin, good = _checked(c, (c1, c2, c3, c4, c5, c6),
                                              (s1, s2, s3, s4, s5, s6), p_w, R_06, p_0T, i, j, l)
                    if good:
                        kept = _keep(c, out, n, kept, cos, sin)
        for r in range(kept, 8):
            for joint in range(6):
                out[n, r, joint] = math.nan


def inverse_into(c, T, out):
    """Solve poses T (n, 4, 4) float64 C-contiguous into out (n, 8, 6), radians."""
    _solve(c, T, out)
