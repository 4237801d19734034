"""The offset-wrist search compiled with numba: the fast path of :func:`offset_wrist.inverse`.

numba is optional (as for :mod:`.opw_kernel`): without it, switched off by
``CADROBOT_NUMBA=0``, or where it fails to compile, :func:`offset_wrist.inverse` runs
its numpy code, which stays the reference; the tests compare the two.

The search is that of :mod:`.offset_wrist` (see it for the geometry), written per
pose as scalar code with no array allocated per pose, in the base frame
(:func:`_shoulder_residuals`: two square roots and two divisions, no rotation back into
link 1's frame).  What makes it fast:

* vectorised loops: the grid, a window's and an edge's samples are one loop per shoulder
  over arrays (:func:`_samples`; 64 samples 0.80 against 2.11 us a CRX pose sample by
  sample), and the brackets of a grid are refined together, each regula falsi step one
  loop over them (:func:`_refine_brackets`, :func:`_lane_residuals`), as are the
  middles of the intervals a dip may hide in (:func:`_dips`).  Each gives the same
  numbers, to the last bit, as sample by sample;
* sin and cos by fdlibm's polynomials (:func:`_sincos`, within an ulp, inlined so that
  the loops above vectorise);
* fewer evaluations than :mod:`.offset_wrist`'s numpy code, which stays the reference:
  a window's minimum by Brent's method from the grid's three samples (about 4.5
  evaluations where golden section took 20) and a branch's edge by Illinois regula
  falsi (about 10 where bisection took 45); on 3 x 20,000 random poses of the 8 arms
  these gave the same number of solutions per pose as golden section and bisection,
  within 5.5e-9 rad;
* a root repeated by a window or a dip is dropped before its joints are computed; each
  candidate is checked by the forward kinematics in scalars, from the joints' cosines
  and sines (no trigonometric call), a joint on a base axis turning two columns;
* on mirror-symmetric arms one shoulder is searched, and the other shoulder's solutions
  are the first's joints mapped (:func:`_mirror`); on the others both shoulders share
  subproblem 4's terms at each sample.

With a screen (:func:`inverse_into`) the same pass flags the poses offset_wrist_polish
must repair, so that ``Solver.inverse`` runs no numpy over the rows.  The numbers (grid,
windows, dips, tolerances) are :mod:`.offset_wrist`'s, passed in :func:`settings_vector`.

The first call in a session loads the compiled code from numba's cache (0.5 s), or
compiles it (40-42 s of CPU on this project's machine, once per installation and Python
version; measured with an empty ``NUMBA_CACHE_DIR``, against 27.1 s before the
vectorised loops and 20 s before the base-frame residual).
"""

import math

import numpy as np

from . import numba_kernel
from .numba_kernel import compile_in_place


#: The constants vector: name -> (start, size).
_NAMES = (("H1", 3), ("H2", 3), ("H4", 3), ("H5", 3), ("H24", 3), ("A1", 3), ("P1", 3),
          ("H2P", 3), ("H12", 3), ("H1H2", 1), ("D", 1), ("P3_H2", 1), ("P3_H4", 1),
          ("P3_H24", 1), ("UPPER", 3), ("UPPER_SQ", 1), ("INV_TWO_UPPER", 1), ("SIGMA3", 1),
          ("B0", 3), ("B1", 3), ("B2", 3), ("Z0", 3), ("Z1", 3), ("Z2", 3), ("T6", 3),
          ("H6P", 3), ("REACH", 1), ("SYMMETRIC", 1), ("C45", 1), ("H5P", 3),
          ("P1_ALONG", 1), ("P1_PERP", 3), ("H1_P1", 3), ("MIRROR_Q2", 1), ("MIRROR_Q3", 1),
          ("MIRROR_CS", 4))
LAYOUT = {}
_start = 0
for _name, _size in _NAMES:
    LAYOUT[_name] = (_start, _size)
    _start += _size
N_CONSTANTS = _start
(H1, H2, H4, H5, H24, A1, P1, H2P, H12, H1H2, D, P3_H2, P3_H4, P3_H24, UPPER, UPPER_SQ,
 INV_TWO_UPPER, SIGMA3, B0, B1, B2, Z0, Z1, Z2, T6, H6P, REACH, SYMMETRIC, C45, H5P,
 P1_ALONG, P1_PERP, H1_P1, MIRROR_Q2, MIRROR_Q3, MIRROR_CS) = (
    LAYOUT[name][0] for name, _ in _NAMES)

#: The settings vector (:func:`settings_vector`).
(GRID, Q6_TOL, POSITION_TOL, ROTATION_TOL, DEDUP_TOL, DIP_STEPS, DIP_SCALE, WINDOW_STEPS,
 WINDOW_SAMPLES, WINDOW_GOLDEN_STEPS, RESIDUAL_TOL, REFINE_STEPS, EDGE_STEPS,
 EDGE_SAMPLES) = range(14)
N_SETTINGS = 14
#: The screen vector of offset_wrist_polish.screen_vector: the sines of the tilts from
#: upright below which a pose is not searched (FREE_SIN, -1: always searched) and is
#: upright (UPRIGHT_SIN); the sine of SUSPECT_DEG; the aligned joint 4 values (N_ALIGNED
#: of 2); axis 1's point (BASE) and R_6T^T P6 (FLANGE), mm, and the links' total length
#: (LINKS), mm: beyond_reach.
(FREE_SIN, UPRIGHT_SIN, SUSPECT_SIN, N_ALIGNED, ALIGNED, BASE, FLANGE, LINKS) = (
    0, 1, 2, 3, 4, 6, 9, 12)
N_SCREEN = 13
#: The flags: searched and nothing to repair; upright (offset_wrist_polish.upright);
#: suspect (offset_wrist_polish.suspect, not upright, not beyond reach).
PLAIN, UPRIGHT, SUSPECT = 0, 1, 2
#: No screening: every pose searched, every flag PLAIN.
NO_SCREEN = np.array([-1.0, -1.0, -1.0] + [0.0] * (N_SCREEN - 4) + [np.inf])
#: Candidates kept per pose before the check (more are dropped; 16 solutions need 16).
MAX_CANDIDATES = 96
MAX_SOLUTIONS = 16

#: Why the compiled kernel is not used ("" while it is, None before the first call of
#: :func:`available`).
why_not = None


def settings_vector(module):
    """The search's numbers from :mod:`.offset_wrist` (its module object)."""
    s = np.zeros(N_SETTINGS)
    s[[GRID, Q6_TOL, POSITION_TOL, ROTATION_TOL, DEDUP_TOL, DIP_STEPS, DIP_SCALE,
       WINDOW_STEPS, WINDOW_SAMPLES, WINDOW_GOLDEN_STEPS, RESIDUAL_TOL, REFINE_STEPS,
       EDGE_STEPS, EDGE_SAMPLES]] = (
        module.GRID_SAMPLES, module.Q6_TOL_RAD, module.POSITION_TOL_MM,
        module.ROTATION_TOL_RAD, module.DEDUP_TOL_RAD, module.DIP_STEPS, module.DIP_SCALE,
        module.WINDOW_STEPS, module.WINDOW_SAMPLES, module.WINDOW_GOLDEN_STEPS,
        module.RESIDUAL_TOL_MM, module.REFINE_STEPS, module.EDGE_STEPS, module.EDGE_SAMPLES)
    return s


def available():
    """True when the compiled kernel can be used (the first call compiles or loads it;
    a failure is kept in :data:`why_not` and the numpy code is used from then on)."""
    return numba_kernel.available(globals(), _compile)


#: Every function of the kernel.  All are compiled alike: numba's own inlining
#: (``inline="always"``) tripled the compile time (60 s instead of 19 s) for no speed,
#: LLVM inlines the small ones anyway.
_KERNEL = ("_v", "_sqrt", "_sincos", "_residual_parts", "_lane_residuals", "_dot", "_cross",
           "_rotate_back", "_wrist_line", "_wrist_line_cs", "_shoulder", "_link1",
           "_axis4_frame", "_axis4", "_shoulder_residuals", "_subproblem4",
           "_residuals_at_root", "_wrap", "_before", "_norm_sq", "_narrow", "_found_before",
           "_residual", "_grid", "_samples", "_sampled", "_margins", "_edge_point",
           "_window_minimum", "_regula_falsi", "_add_brackets", "_refine_brackets", "_dips",
           "_interval_dip", "_dip", "_known", "_parabolic_minimum", "_window", "_edge",
           "_angle", "_joints", "_reproduces", "_turned", "_mirror", "_keep", "_pose_terms",
           "_tilt", "_beyond_reach", "_suspect", "_solve_pose", "_solve")


def _compile():
    """Compile the kernel in place (:func:`.numba_kernel.compile_in_place`); "" or why not."""
    return compile_in_place(globals(), _KERNEL, lambda: _solve(
        np.zeros(N_CONSTANTS), np.zeros(N_SETTINGS), np.zeros((6, 3)), np.zeros((7, 3)),
        np.eye(3), np.eye(4)[None], np.linspace(-3.0, 3.0, 8), np.empty((1, 16, 6)), NO_SCREEN,
        np.empty(1, dtype=np.int8)), inlined=("_sincos", "_residual_parts"))


# ------------------------------------------------------------------ vectors as tuples

def _v(c, i):
    return c[i], c[i + 1], c[i + 2]


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _rotate_back(h, cos_q, sin_q, v):
    """rot(h, -q) v."""
    along = _dot(h, v)
    hv = _cross(h, v)
    return (along * h[0] + cos_q * (v[0] - along * h[0]) - sin_q * hv[0],
            along * h[1] + cos_q * (v[1] - along * h[1]) - sin_q * hv[1],
            along * h[2] + cos_q * (v[2] - along * h[2]) - sin_q * hv[2])


def _sqrt(x):
    """math.sqrt as the processor's instruction: numba calls libm's sqrt for math.sqrt,
    ``** 0.5`` compiles to vsqrtsd (the same value; NaN below zero)."""
    return x ** 0.5


#: pi/2 in three parts, the first two of 33 bits (k times them is exact for |k| < 2^20;
#: fdlibm's e_rem_pio2.c), and 2/pi.
_PIO2_1 = 1.57079632673412561417e+00
_PIO2_2 = 6.07710050630396597660e-11
_PIO2_2T = 2.02226624879595063154e-21
_TWO_OVER_PI = 0.63661977236758134308
#: fdlibm's minimax polynomials of sin and cos on [-pi/4, pi/4] (k_sin.c, k_cos.c).
_S1, _S2, _S3, _S4, _S5, _S6 = (-1.66666666666666324348e-01, 8.33333333332248946124e-03,
                                -1.98412698298579493134e-04, 2.75573137070700676789e-06,
                                -2.50507602534068634195e-08, 1.58969099521155010221e-10)
_C1, _C2, _C3, _C4, _C5, _C6 = (4.16666666666666019037e-02, -1.38888888888741095749e-03,
                                2.48015872894767294178e-05, -2.75573143513906633035e-07,
                                2.08757232129817482790e-09, -1.13596475577881948265e-11)


def _sincos(x):
    """sin x, cos x for |x| up to a few turns, within 1 ulp (relative error 2.2e-16 on 10^6
    points in (-3.3, 3.3) against libm): one reduction by pi/2 and fdlibm's polynomials,
    14 ns for both against 23 for libm's sin and cos (numba calls them one by one)."""
    k = math.floor(x * _TWO_OVER_PI + 0.5)
    r = ((x - k * _PIO2_1) - k * _PIO2_2) - k * _PIO2_2T
    z = r * r
    sin_r = r + z * r * (_S1 + z * (_S2 + z * (_S3 + z * (_S4 + z * (_S5 + z * _S6)))))
    half = 0.5 * z
    w = 1.0 - half
    cos_r = w + (((1.0 - w) - half)
                 + z * z * (_C1 + z * (_C2 + z * (_C3 + z * (_C4 + z * (_C5 + z * _C6))))))
    quadrant = int(k) & 3               # selects, not branches: vectorised in a loop
    odd = quadrant & 1
    sin_x = cos_r if odd else sin_r
    cos_x = sin_r if odd else cos_r
    sin_x = -sin_x if quadrant >= 2 else sin_x
    cos_x = -cos_x if quadrant == 1 or quadrant == 2 else cos_x
    return sin_x, cos_x


def _wrap(q):
    """Into (-pi, pi]."""
    return q - 2.0 * math.pi * math.ceil((q - math.pi) / (2.0 * math.pi))


# ------------------------------------------------------------------ the residual

def _wrist_line(pt, q6):
    """p45 - a1 and z5 at q6; pt the pose terms (21,) of :func:`_solve_pose`."""
    sin_q6, cos_q6 = _sincos(q6)
    return _wrist_line_cs(pt, cos_q6, sin_q6)


def _wrist_line_cs(pt, c, s):
    """:func:`_wrist_line` from cos q6, sin q6."""
    x = (pt[0] - c * pt[3] + s * pt[6], pt[1] - c * pt[4] + s * pt[7],
         pt[2] - c * pt[5] + s * pt[8])
    z5 = (pt[9] + c * pt[12] - s * pt[15], pt[10] + c * pt[13] - s * pt[16],
          pt[11] + c * pt[14] - s * pt[17])
    return x, z5


def _shoulder(c, x, shoulder):
    """cos q1, sin q1 of subproblem 4's root `shoulder`, and rho^2 (NaN: no root)."""
    a = _dot(_v(c, H2P), x)
    b = _dot(_v(c, H12), x)
    rho_sq = a * a + b * b
    rho = _sqrt(rho_sq)
    cos_alpha = (c[D] - c[H1H2] * _dot(_v(c, H1), x)) / rho
    sin_alpha = shoulder * _sqrt(1.0 - cos_alpha * cos_alpha)
    cos_phi, sin_phi = a / rho, b / rho
    return (cos_phi * cos_alpha - sin_phi * sin_alpha,
            sin_phi * cos_alpha + cos_phi * sin_alpha, rho_sq)


def _link1(c, x, z5, cos1, sin1):
    """In link 1's frame: X - P1 - P3_H2 h2 (the part of W that does not depend on the
    sign of axis 4), z2 x Z5 (unnormalised), Z5."""
    h1, h2 = _v(c, H1), _v(c, H2)
    X = _rotate_back(h1, cos1, sin1, x)
    Z5 = _rotate_back(h1, cos1, sin1, z5)
    n = _cross(h2, Z5)
    p3 = c[P3_H2]
    base = (X[0] - c[P1] - p3 * h2[0], X[1] - c[P1 + 1] - p3 * h2[1],
            X[2] - c[P1 + 2] - p3 * h2[2])
    return base, n, Z5


def _axis4_frame(c, n):
    """e1, e2 and the two components of axis 4 along them (offset_wrist._axis4):
    ``U = ce e1 +- se e2``; NaN where axis 5 is too close to h2 for the angle."""
    inverse = 1.0 / _sqrt(_dot(n, n))
    e2 = (n[0] * inverse, n[1] * inverse, n[2] * inverse)
    e1 = _cross(e2, _v(c, H2))
    ce = c[C45] * inverse
    return e1, e2, ce, _sqrt(1.0 - ce * ce)


def _axis4(c, base, n, sign):
    """Axis 4 (U) of the sign of axis 4, h2 x U and W (axis 2 -> axis 3) in link 1's
    frame, from :func:`_link1`'s terms."""
    e1, e2, ce, se = _axis4_frame(c, n)
    se *= sign
    U = (ce * e1[0] + se * e2[0], ce * e1[1] + se * e2[1], ce * e1[2] + se * e2[2])
    hU = _cross(_v(c, H2), U)
    a, b = c[P3_H4], c[P3_H24]
    W = (base[0] - a * U[0] - b * hU[0], base[1] - a * U[1] - b * hU[1],
         base[2] - a * U[2] - b * hU[2])
    return U, hU, W


def _residual(c, pt, q6, branch):
    """The residual of branch (0-3: shoulder +-1, then sign of axis 4 +-1) at q6."""
    x, z5 = _wrist_line(pt, q6)
    plus, minus, _, _ = _shoulder_residuals(c, x, z5, branch // 2)
    return plus if branch % 2 == 0 else minus


def _shoulder_residuals(c, x, z5, shoulder):
    """Residuals of both signs of axis 4 of the shoulder (0, 1), rho^2 and |z2 x z5|^2.

    offset_wrist.residual's value, computed in the base frame (dot products do not
    change under the rotation by q1) with two square roots and two divisions: with
    ``r = +-sqrt(rho^2 - d^2)`` (subproblem 4, d = D - h1.h2 h1.x), ``rho^2 cos q1 =
    a d - b r`` and ``rho^2 sin q1 = b d + a r``; axis 2 ``z2 = R_01 h2`` and
    ``p = x - R_01 P1 - P3_H2 z2``; with ``n = z2 x z5`` and U = ce e1 +- se e2
    (e2 = n / |n|, e1 = e2 x z2, ce = h4.h5 / |n|)::

        |W_perp|^2 = |p_perp|^2 + a3^2 + b3^2 - 2 (h4.h5 (a3 B1 + b3 B2)
                     -+ sqrt(|n|^2 - (h4.h5)^2) (a3 B2 - b3 B1)) / |n|^2

    where a3, b3 = P3_H4, P3_H24, B1 = p . (n x z2), B2 = p . n.  NaN where the branch
    does not exist (rho < |d|, |n| < |h4.h5|).
    """
    a, b, rho_sq, d, root = _subproblem4(c, x)
    minus, plus, n_sq = _residuals_at_root(c, x, z5, a, b, rho_sq, d,
                                           (1.0 - 2.0 * shoulder) * root)
    return minus, plus, rho_sq, n_sq


def _subproblem4(c, x):
    """Subproblem 4's terms at p45 - a1 = x, shared by both shoulders: a, b, rho^2, d and
    sqrt(rho^2 - d^2) (NaN: no root)."""
    a = _dot(_v(c, H2P), x)
    b = _dot(_v(c, H12), x)
    rho_sq = a * a + b * b
    d = c[D] - c[H1H2] * _dot(_v(c, H1), x)
    return a, b, rho_sq, d, _sqrt(rho_sq - d * d)


def _residuals_at_root(c, x, z5, a, b, rho_sq, d, r):
    """:func:`_shoulder_residuals`' two residuals and |z2 x z5|^2 at the shoulder whose
    root is r (+-sqrt(rho^2 - d^2))."""
    h1 = _v(c, H1)
    inverse = 1.0 / rho_sq
    cos1, sin1 = (a * d - b * r) * inverse, (b * d + a * r) * inverse
    h2p, h12, h1h2 = _v(c, H2P), _v(c, H12), c[H1H2]
    p1_perp, h1_p1, p1_along, p3 = _v(c, P1_PERP), _v(c, H1_P1), c[P1_ALONG], c[P3_H2]
    z2 = (h1h2 * h1[0] + cos1 * h2p[0] + sin1 * h12[0],
          h1h2 * h1[1] + cos1 * h2p[1] + sin1 * h12[1],
          h1h2 * h1[2] + cos1 * h2p[2] + sin1 * h12[2])
    p = (x[0] - p1_along * h1[0] - cos1 * p1_perp[0] - sin1 * h1_p1[0] - p3 * z2[0],
         x[1] - p1_along * h1[1] - cos1 * p1_perp[1] - sin1 * h1_p1[1] - p3 * z2[1],
         x[2] - p1_along * h1[2] - cos1 * p1_perp[2] - sin1 * h1_p1[2] - p3 * z2[2])
    n = _cross(z2, z5)
    n_sq = _dot(n, n)
    along = _dot(p, z2)
    B1, B2 = _dot(p, _cross(n, z2)), _dot(p, n)
    a3, b3 = c[P3_H4], c[P3_H24]
    inverse = 2.0 / n_sq
    common = (_dot(p, p) - along * along + a3 * a3 + b3 * b3 - c[UPPER_SQ]
              - c[C45] * (a3 * B1 + b3 * B2) * inverse)
    mixed = _sqrt(n_sq - c[C45] * c[C45]) * (a3 * B2 - b3 * B1) * inverse
    return (common - mixed) * c[INV_TWO_UPPER], (common + mixed) * c[INV_TWO_UPPER], n_sq


def _grid(c, pt, cos_t, sin_t, first, last, F, start, R2, N2):
    """The residuals of the branches of shoulders first .. last - 1 into F[:, start:start
    + G] (F C-contiguous (4, >= start + G)), rho^2 into R2 (G,) and |z2 x z5|^2 per
    shoulder into N2 (2, G), at the samples whose cos and sin of q6 are cos_t, sin_t (G,)."""
    G = cos_t.shape[0]
    for shoulder in range(first, last):    # rows F[i, a:b]: contiguous, so vectorised
        _samples(c, pt, cos_t, sin_t, 1.0 - 2.0 * shoulder, F[2 * shoulder, start:start + G],
                 F[2 * shoulder + 1, start:start + G], R2, N2[shoulder])


def _residual_parts(c, pt, co, si, root_sign):
    """:func:`_shoulder_residuals`' terms at cos q6 = co, sin q6 = si, subproblem 4's root
    root_sign (+-1): ``common``, ``mixed`` (the residuals are (common -+ mixed) *
    INV_TWO_UPPER), rho^2 and |z2 x z5|^2.  Scalar arithmetic only, no call and no
    branch, inlined (numba's ``inline="always"``) into the loops of :func:`_samples` and
    :func:`_lane_residuals`, which LLVM then vectorises: the same values to the last bit
    as :func:`_shoulder_residuals`."""
    h1x, h1y, h1z = c[H1], c[H1 + 1], c[H1 + 2]
    h2px, h2py, h2pz = c[H2P], c[H2P + 1], c[H2P + 2]
    h12x, h12y, h12z = c[H12], c[H12 + 1], c[H12 + 2]
    p1px, p1py, p1pz = c[P1_PERP], c[P1_PERP + 1], c[P1_PERP + 2]
    hp1x, hp1y, hp1z = c[H1_P1], c[H1_P1 + 1], c[H1_P1 + 2]
    h1h2, p1_along, p3 = c[H1H2], c[P1_ALONG], c[P3_H2]
    a3, b3, c45 = c[P3_H4], c[P3_H24], c[C45]
    x0, x1, x2 = (pt[0] - co * pt[3] + si * pt[6], pt[1] - co * pt[4] + si * pt[7],
                  pt[2] - co * pt[5] + si * pt[8])
    z0, z1, z2 = (pt[9] + co * pt[12] - si * pt[15], pt[10] + co * pt[13] - si * pt[16],
                  pt[11] + co * pt[14] - si * pt[17])
    a = h2px * x0 + h2py * x1 + h2pz * x2
    b = h12x * x0 + h12y * x1 + h12z * x2
    r_sq = a * a + b * b
    d = c[D] - h1h2 * (h1x * x0 + h1y * x1 + h1z * x2)
    r = root_sign * (r_sq - d * d) ** 0.5
    inverse = 1.0 / r_sq
    cos1, sin1 = (a * d - b * r) * inverse, (b * d + a * r) * inverse
    ax = h1h2 * h1x + cos1 * h2px + sin1 * h12x          # axis 2, z2
    ay = h1h2 * h1y + cos1 * h2py + sin1 * h12y
    az = h1h2 * h1z + cos1 * h2pz + sin1 * h12z
    px = x0 - p1_along * h1x - cos1 * p1px - sin1 * hp1x - p3 * ax
    py = x1 - p1_along * h1y - cos1 * p1py - sin1 * hp1y - p3 * ay
    pz = x2 - p1_along * h1z - cos1 * p1pz - sin1 * hp1z - p3 * az
    nx, ny, nz = ay * z2 - az * z1, az * z0 - ax * z2, ax * z1 - ay * z0
    nn = nx * nx + ny * ny + nz * nz
    along = px * ax + py * ay + pz * az
    B1 = px * (ny * az - nz * ay) + py * (nz * ax - nx * az) + pz * (nx * ay - ny * ax)
    B2 = px * nx + py * ny + pz * nz
    inverse = 2.0 / nn
    common = (px * px + py * py + pz * pz - along * along + a3 * a3 + b3 * b3 - c[UPPER_SQ]
              - c45 * (a3 * B1 + b3 * B2) * inverse)
    mixed = (nn - c45 * c45) ** 0.5 * (a3 * B2 - b3 * B1) * inverse
    return common, mixed, r_sq, nn


def _samples(c, pt, cos_t, sin_t, root_sign, minus, plus, rho_sq, n_sq):
    """:func:`_shoulder_residuals` at every sample of one shoulder (root_sign +-1), as one
    vectorised loop (:func:`_residual_parts`: the grid of 64 samples 3.4-3.8x faster
    than sample by sample)."""
    scale = c[INV_TWO_UPPER]
    for j in range(cos_t.shape[0]):
        common, mixed, rho_sq[j], n_sq[j] = _residual_parts(c, pt, cos_t[j], sin_t[j],
                                                            root_sign)
        minus[j], plus[j] = (common - mixed) * scale, (common + mixed) * scale


def _lane_residuals(c, pt, t, root_sign, axis_sign, f):
    """The residual of each lane j (q6 = t[j], subproblem 4's root root_sign[j] +-1, axis
    4's sign axis_sign[j] +-1, i.e. branch 2 * shoulder + (axis_sign > 0)) into f (n,):
    :func:`_residual` of n points in one vectorised loop (:func:`_residual_parts`), for
    regula falsi run on every bracket of a pose at once (:func:`_refine_brackets`)."""
    scale = c[INV_TWO_UPPER]
    for j in range(t.shape[0]):
        si, co = _sincos(t[j])
        common, mixed, _, _ = _residual_parts(c, pt, co, si, root_sign[j])
        f[j] = (common + axis_sign[j] * mixed) * scale


def _sampled(c, pt, t, first, last, f, work):
    """:func:`_grid` at the samples t (K,) of q6: residuals into f (4, K); work (5, K)
    holds cos, sin, rho^2 and |z2 x z5|^2 of both shoulders."""
    for i in range(t.shape[0]):
        work[1, i], work[0, i] = _sincos(t[i])
    _grid(c, pt, work[0], work[1], first, last, f, 0, work[2], work[3:5])


# ------------------------------------------------------------------ the search

_GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0
_GOLDEN_STEP = 1.0 - _GOLDEN


def _window_minimum(c, pt, lo, hi, f_lo, f_middle, f_hi, steps, what, shoulder, curvature):
    """The minimum on [lo, hi] of rho^2 (what 1) or |z2 x z5|^2 of `shoulder` (what 2), to
    WINDOW_RESOLUTION of the window's width ``sqrt(value / curvature)``: Brent's method
    (parabolic interpolation, golden section where it does not progress; R. P. Brent,
    "Algorithms for minimization without derivatives", 1973, ch. 5), from the grid's
    samples lo, the middle and hi (values f_lo, f_middle, f_hi): its first step is their
    parabola's vertex.  On a norm's smooth minimum about 5 evaluations where golden
    section took 20.

    Returns
    -------
    q6, value : float
    """
    a, b = lo, hi
    x, fx = 0.5 * (lo + hi), f_middle
    (w, fw), (v, fv) = ((lo, f_lo), (hi, f_hi)) if f_lo <= f_hi else ((hi, f_hi), (lo, f_lo))
    d, e = 0.0, hi - lo                        # e: a parabolic step is allowed at once
    for _ in range(steps):
        middle = 0.5 * (a + b)
        tol1 = WINDOW_RESOLUTION * _sqrt(max(fx, 0.0) / curvature) + 1e-15
        tol2 = 2.0 * tol1
        if abs(x - middle) <= tol2 - 0.5 * (b - a):
            break
        golden = True
        if abs(e) > tol1:                        # a parabola through x, w, v
            r = (x - w) * (fx - fv)
            q = (x - v) * (fx - fw)
            p = (x - v) * q - (x - w) * r
            q = 2.0 * (q - r)
            if q > 0.0:
                p = -p
            q = abs(q)
            if abs(p) < abs(0.5 * q * e) and q * (a - x) < p < q * (b - x):
                e, d = d, p / q
                golden = False
                if x + d - a < tol2 or b - x - d < tol2:
                    d = tol1 if middle >= x else -tol1
        if golden:
            e = (a - x) if x >= middle else (b - x)
            d = _GOLDEN_STEP * e
        u = x + d if abs(d) >= tol1 else x + (tol1 if d >= 0.0 else -tol1)
        fu = _norm_sq(c, pt, u, what, shoulder)
        if fu <= fx:
            if u >= x:
                a = x
            else:
                b = x
            v, fv, w, fw, x, fx = w, fw, x, fx, u, fu
        else:
            if u < x:
                a = u
            else:
                b = u
            if fu <= fw or w == x:
                v, fv, w, fw = w, fw, u, fu
            elif fu <= fv or v == x or v == w:
                v, fv = u, fu
    return x, fx


#: Windows: the minimum of the norm is found to this fraction of the window's width.
WINDOW_RESOLUTION = 1e-3


def _norm_sq(c, pt, q6, what, shoulder):
    """rho^2 (what 1) or |z2 x z5|^2 of `shoulder` (what 2) at q6."""
    x, z5 = _wrist_line(pt, q6)
    if what == 1:
        a, b = _dot(_v(c, H2P), x), _dot(_v(c, H12), x)
        return a * a + b * b
    return _shoulder_residuals(c, x, z5, shoulder)[3]


def _regula_falsi(c, pt, s, lo, hi, f_lo, f_hi, branch):
    """A root of the residual of `branch` in [lo, hi] where it changes sign: regula falsi
    with the Anderson-Bjoerck scaling of the end that stays (offset_wrist._refine).  Where
    the bracket closes first, the point evaluated nearest zero: on a steep residual
    (1e7 mm/rad where a direction turns fast) the last point can be the worse end."""
    if f_lo == 0.0:
        return lo
    if f_hi == 0.0:
        return hi
    a, fa, b, fb = lo, f_lo, hi, f_hi      # a: the end kept, b: the last point
    best, f_best = (lo, abs(f_lo)) if abs(f_lo) < abs(f_hi) else (hi, abs(f_hi))
    for _ in range(int(s[REFINE_STEPS])):
        middle = (a * fb - b * fa) / (fb - fa)
        if not min(a, b) < middle < max(a, b):
            middle = 0.5 * (a + b)
        f_middle = _residual(c, pt, middle, branch)
        if abs(f_middle) < s[RESIDUAL_TOL] or f_middle != f_middle:
            return middle
        if abs(f_middle) < f_best:
            best, f_best = middle, abs(f_middle)
        if f_middle * fb < 0.0:
            a, fa = b, fb
        else:
            m = 1.0 - f_middle / fb
            fa *= m if m > 0.0 else 0.5
        b, fb = middle, f_middle
        if abs(b - a) < s[Q6_TOL]:
            break
    return best


#: Rows of the work array of :func:`_refine_brackets`.
(RF_LO, RF_HI, RF_F_LO, RF_F_HI, RF_BEST, RF_F_BEST, RF_T, RF_F, RF_ROOT_SIGN,
 RF_AXIS_SIGN) = range(10)
N_RF = 10


def _add_brackets(c, pt, s, t, f, first, last, cand_q6, cand_branch, count, rf, lane):
    """Roots in the sign changes of rows first .. last - 1 of f (4, K) (the branches'
    residuals) between neighbouring samples t (K,) (sorted), refined together
    (:func:`_refine_brackets`; rf (N_RF, MAX_CANDIDATES), lane (MAX_CANDIDATES,) int:
    its work arrays)."""
    start = count
    for branch in range(first, last):
        for j in range(t.shape[0] - 1):
            if f[branch, j] * f[branch, j + 1] <= 0.0 and count < MAX_CANDIDATES:
                rf[RF_LO, count], rf[RF_HI, count] = t[j], t[j + 1]
                rf[RF_F_LO, count], rf[RF_F_HI, count] = f[branch, j], f[branch, j + 1]
                cand_branch[count] = branch
                count += 1
    _refine_brackets(c, pt, s, start, count, cand_q6, cand_branch, rf, lane)
    return count


def _refine_brackets(c, pt, s, start, stop, cand_q6, cand_branch, rf, lane):
    """:func:`_regula_falsi` of the brackets start .. stop - 1 into cand_q6, a step on all
    of them at once: a step's residuals are one vectorised :func:`_lane_residuals` call.
    Each bracket goes through the steps of :func:`_regula_falsi` alone, in the same
    arithmetic (the same root to the last bit).

    rf's columns start .. stop - 1 hold the brackets: a, b (RF_LO, RF_HI; a the end kept,
    b the last point) and their residuals; they are compacted as brackets finish, column
    start + j then being candidate lane[j]."""
    n = 0
    for k in range(start, stop):
        if rf[RF_F_LO, k] == 0.0:
            cand_q6[k] = rf[RF_LO, k]
        elif rf[RF_F_HI, k] == 0.0:
            cand_q6[k] = rf[RF_HI, k]
        else:
            j = start + n
            for row in (RF_LO, RF_HI, RF_F_LO, RF_F_HI):
                rf[row, j] = rf[row, k]
            if abs(rf[RF_F_LO, j]) < abs(rf[RF_F_HI, j]):
                rf[RF_BEST, j], rf[RF_F_BEST, j] = rf[RF_LO, j], abs(rf[RF_F_LO, j])
            else:
                rf[RF_BEST, j], rf[RF_F_BEST, j] = rf[RF_HI, j], abs(rf[RF_F_HI, j])
            rf[RF_ROOT_SIGN, j] = 1.0 if cand_branch[k] < 2 else -1.0
            rf[RF_AXIS_SIGN, j] = 1.0 if cand_branch[k] % 2 == 1 else -1.0
            lane[n] = k
            n += 1
    for _ in range(int(s[REFINE_STEPS])):
        if n == 0:
            break
        end = start + n
        for j in range(start, end):
            a, fa, b, fb = rf[RF_LO, j], rf[RF_F_LO, j], rf[RF_HI, j], rf[RF_F_HI, j]
            middle = (a * fb - b * fa) / (fb - fa)
            if not min(a, b) < middle < max(a, b):
                middle = 0.5 * (a + b)
            rf[RF_T, j] = middle
        _lane_residuals(c, pt, rf[RF_T, start:end], rf[RF_ROOT_SIGN, start:end],
                        rf[RF_AXIS_SIGN, start:end], rf[RF_F, start:end])
        kept = 0
        for j in range(start, end):
            k = lane[j - start]
            middle, f_middle = rf[RF_T, j], rf[RF_F, j]
            if abs(f_middle) < s[RESIDUAL_TOL] or f_middle != f_middle:
                cand_q6[k] = middle
                continue
            if abs(f_middle) < rf[RF_F_BEST, j]:
                rf[RF_BEST, j], rf[RF_F_BEST, j] = middle, abs(f_middle)
            fb = rf[RF_F_HI, j]
            if f_middle * fb < 0.0:
                rf[RF_LO, j], rf[RF_F_LO, j] = rf[RF_HI, j], fb
            else:
                m = 1.0 - f_middle / fb
                rf[RF_F_LO, j] *= m if m > 0.0 else 0.5
            rf[RF_HI, j], rf[RF_F_HI, j] = middle, f_middle
            if abs(rf[RF_HI, j] - rf[RF_LO, j]) < s[Q6_TOL]:
                cand_q6[k] = rf[RF_BEST, j]
                continue
            to = start + kept                     # the bracket goes on: compact it
            if to != j:
                for row in range(N_RF):
                    rf[row, to] = rf[row, j]
            lane[kept] = k
            kept += 1
        n = kept
    for j in range(n):                            # out of steps: the best point
        cand_q6[lane[j]] = rf[RF_BEST, start + j]


def _dips(c, pt, s, t, f, first, last, cand_q6, cand_branch, count, work):
    """Two roots close together or a double root hidden between samples of one sign
    (see offset_wrist._dips) on rows first .. last - 1 of f (4, K) at t (K,): a split gives
    two brackets, a touch a candidate.  The middles of the intervals to search are
    evaluated first, in one vectorised :func:`_lane_residuals` call (work (4, 4 K): their
    q6, signs and residuals)."""
    step = 2.0 * math.pi / s[GRID]
    limit = s[DIP_SCALE] * c[REACH] * step * step
    n = 0
    for branch in range(first, last):
        for j in range(t.shape[0] - 1):
            if _interval_dip(f[branch, j], f[branch, j + 1], limit):
                work[0, n] = 0.5 * (t[j] + t[j + 1])
                work[1, n] = 1.0 if branch < 2 else -1.0
                work[2, n] = 1.0 if branch % 2 == 1 else -1.0
                n += 1
    _lane_residuals(c, pt, work[0, :n], work[1, :n], work[2, :n], work[3, :n])
    i = 0
    for branch in range(first, last):
        row = f[branch]
        for j in range(t.shape[0] - 1):
            if j >= 1:
                f_prev, f_mid, f_next = row[j - 1], row[j], row[j + 1]
                if (abs(f_mid) <= limit and f_mid * f_prev > 0.0 and f_mid * f_next > 0.0
                        and abs(f_mid) <= abs(f_prev) and abs(f_mid) <= abs(f_next)):
                    count = _dip(c, pt, s, t[j - 1], t[j], t[j + 1], f_prev, f_mid, f_next,
                                 branch, cand_q6, cand_branch, count)
            if _interval_dip(row[j], row[j + 1], limit):
                count = _dip(c, pt, s, t[j], work[0, i], t[j + 1], row[j], work[3, i],
                             row[j + 1], branch, cand_q6, cand_branch, count)
                i += 1
    return count


def _interval_dip(f_lo, f_hi, limit):
    """True when two roots may hide between neighbouring samples of one sign."""
    return min(abs(f_lo), abs(f_hi)) <= limit and f_lo * f_hi > 0.0


def _dip(c, pt, s, left, middle, right, f_left, f_middle, f_right, branch, cand_q6,
         cand_branch, count):
    """One triple of :func:`_dips` (f_left and f_right of one sign)."""
    if count + 2 > MAX_CANDIDATES:
        return count
    scale = 1.0 if f_left > 0.0 else -1.0
    m, f_m = middle, scale * f_middle
    searched = 0.0 <= f_m <= min(scale * f_left, scale * f_right)
    if searched:
        m, f_m = _parabolic_minimum(c, pt, s, left, m, right, scale * f_left, f_m,
                                    scale * f_right, branch, scale)
    if f_m < 0.0:
        f_at = scale * f_m
        cand_q6[count] = _regula_falsi(c, pt, s, left, m, f_left, f_at, branch)
        cand_q6[count + 1] = _regula_falsi(c, pt, s, m, right, f_at, f_right, branch)
        cand_branch[count] = branch
        cand_branch[count + 1] = branch
        count += 2
    elif searched and f_m <= s[POSITION_TOL]:     # a touch: FK can pass only this close
        cand_q6[count] = m
        cand_branch[count] = branch
        count += 1
    return count


def _parabolic_minimum(c, pt, s, a, m, b, fa, fm, fb, branch, scale):
    """Parabolic interpolation alternating with golden section on scale * residual from
    a < m < b with f(m) <= f(a), f(b), until it goes below zero
    (offset_wrist._parabolic_minimum)."""
    for step in range(int(s[DIP_STEPS])):
        if fm < 0.0 or not b - a > s[Q6_TOL]:
            break
        p = (m - a) ** 2 * (fm - fb) - (m - b) ** 2 * (fm - fa)
        q = (m - a) * (fm - fb) - (m - b) * (fm - fa)
        u = m - 0.5 * p / q
        if step % 2 == 1 or not (a < u < b and abs(u - m) > 1e-3 * (b - a)):
            u = m + _GOLDEN_STEP * ((a if m - a > b - m else b) - m)
        fu = scale * _residual(c, pt, u, branch)
        if fu < fm:
            if u < m:
                b, fb = m, fm
            else:
                a, fa = m, fm
            m, fm = u, fu
        elif u < m:
            a, fa = u, fu
        else:
            b, fb = u, fu
    return m, fm


def _narrow(norm_sq, j, step, window_steps):
    """The curvature (~|v'|^2) where sample j of norm_sq (G,) is a local minimum whose
    window is narrower than window_steps grid steps, else 0."""
    G = norm_sq.shape[0]
    mid = norm_sq[j]
    before = norm_sq[j - 1] if j > 0 else norm_sq[G - 1]       # no integer division
    after = norm_sq[j + 1] if j < G - 1 else norm_sq[0]
    if not (mid <= before and mid < after):
        return 0.0
    curvature = (before - 2.0 * mid + after) / (2.0 * step * step)
    if not curvature > 0.0:
        return 0.0
    vertex = mid - (before - after) ** 2 / (16.0 * step * step * curvature)
    if not max(vertex, 0.0) < (window_steps * step) ** 2 * curvature:
        return 0.0
    return curvature


def _window(c, pt, s, norm_sq, j, what, shoulder, t_grid, t, f, work, cand_q6, cand_branch,
            count, rf, lane, dip_work):
    """Extra samples where a direction turns fast (see offset_wrist._windows), around
    grid sample j of `norm_sq` (G,): rho^2 (what 1, the branches of the first `shoulder`
    shoulders) or |z2 x z5|^2 (what 2, the branches of `shoulder`).  t (K + 2,),
    f (4, K + 2), work (6, K + 2): work arrays (:func:`_sampled`), work[5, :K] holding
    the tangents of the samples' angles (:func:`_solve`)."""
    G = t_grid.shape[0]
    step = 2.0 * math.pi / G
    curvature = _narrow(norm_sq, j, step, s[WINDOW_STEPS])
    if curvature == 0.0:
        return count
    centre = t_grid[j]
    before = norm_sq[j - 1] if j > 0 else norm_sq[G - 1]
    after = norm_sq[j + 1] if j < G - 1 else norm_sq[0]
    t_min, norm_sq_min = _window_minimum(c, pt, centre - step, centre + step, before,
                                         norm_sq[j], after, int(s[WINDOW_GOLDEN_STEPS]), what,
                                         shoulder, curvature)
    width = _sqrt(max(norm_sq_min, 0.0) / curvature)
    K = int(s[WINDOW_SAMPLES])
    t[0], t[K + 1] = centre - step, centre + step
    for i in range(K):
        t[i + 1] = min(max(t_min + width * work[5, i], centre - step), centre + step)
    first, last = (shoulder, shoulder + 1) if what == 2 else (0, shoulder)
    _sampled(c, pt, t, first, last, f, work)
    count = _add_brackets(c, pt, s, t, f, 2 * first, 2 * last, cand_q6, cand_branch, count, rf,
                          lane)
    return _dips(c, pt, s, t, f, 2 * first, 2 * last, cand_q6, cand_branch, count, dip_work)


def _edge(c, pt, s, t_in, t_out, shoulder, t, f, work, cand_q6, cand_branch, count, rf, lane,
          dip_work):
    """Where the shoulder's branches end between a grid sample that exists (t_in) and one
    that does not (t_out) (offset_wrist._edges): the edge by bisection, samples spaced as
    squares from it to t_in, brackets and dips of both signs.  t (EDGE_SAMPLES + 1,),
    f (4, EDGE_SAMPLES + 1), work (5, EDGE_SAMPLES + 1): work arrays."""
    inside = _edge_point(c, pt, s, t_in, t_out, shoulder)
    S = t.shape[0] - 1
    for i in range(S + 1):
        u = (i / S) ** 2
        t[i if t_in > inside else S - i] = inside + (t_in - inside) * u
    _sampled(c, pt, t, shoulder, shoulder + 1, f, work)
    count = _add_brackets(c, pt, s, t, f, 2 * shoulder, 2 * shoulder + 2, cand_q6, cand_branch,
                          count, rf, lane)
    return _dips(c, pt, s, t, f, 2 * shoulder, 2 * shoulder + 2, cand_q6, cand_branch, count,
                 dip_work)


#: The edge is found to this, rad (bisection's EDGE_STEPS halvings of a grid step end
#: within 3e-15).
EDGE_TOL_RAD = 1e-14


def _margins(c, pt, q6, shoulder):
    """What ends the shoulder's branches at q6: rho^2 - d^2 (subproblem 4 has roots where
    it is >= 0, mm^2) and |z2 x z5|^2 - (h4 . h5)^2 (axis 4 exists where >= 0; NaN where
    subproblem 4 has no root)."""
    x, z5 = _wrist_line(pt, q6)
    a, b, rho_sq, d, root = _subproblem4(c, x)
    n_sq = _residuals_at_root(c, x, z5, a, b, rho_sq, d, (1.0 - 2.0 * shoulder) * root)[2]
    return rho_sq - d * d, n_sq - c[C45] * c[C45]


def _edge_point(c, pt, s, inside, outside, shoulder):
    """The last q6 from `inside` (the shoulder's branches exist) towards `outside` (they do
    not) where they exist (``|z2 x z5|^2 >= (h4 . h5)^2``, as offset_wrist._edges'
    bisection), to EDGE_TOL_RAD: regula falsi with the Illinois halving on the margin
    that ends them at `outside` (:func:`_margins`), a halving wherever that margin's sign
    and the existence disagree.  About 10 evaluations where bisection took EDGE_STEPS
    (45)."""
    g_in = _margins(c, pt, inside, shoulder)
    g_out = _margins(c, pt, outside, shoulder)
    kind = 0 if g_out[0] < 0.0 else 1              # which margin ends them at outside
    f_in, f_out = g_in[kind], g_out[kind]
    secant = f_in >= 0.0 and f_out < 0.0
    last = 0                                      # the end moved last: 1 inside, -1 outside
    for _ in range(int(s[EDGE_STEPS])):
        if not abs(outside - inside) > EDGE_TOL_RAD:
            break
        middle = 0.5 * (inside + outside)
        if secant:
            guess = inside + f_in * (outside - inside) / (f_in - f_out)
            if min(inside, outside) < guess < max(inside, outside):
                middle = guess
        g = _margins(c, pt, middle, shoulder)
        exists = g[1] >= 0.0
        secant = secant and exists == (g[kind] >= 0.0)
        if exists:
            if last == 1:
                f_out *= 0.5
            inside, f_in, last = middle, g[kind], 1
        else:
            if last == -1:
                f_in *= 0.5
            outside, f_out, last = middle, g[kind], -1
    return inside


# ------------------------------------------------------------------ joints and checks

def _angle(y, x, cs, i):
    """atan2(y, x), with its cosine and sine into cs[i] (no trigonometric call)."""
    r = _sqrt(x * x + y * y)
    cs[i, 0], cs[i, 1] = (x / r, y / r) if r > 0.0 else (1.0, 0.0)
    return math.atan2(y, x)


def _joints(c, pt, q6, branch, q, cs):
    """The joint values of `branch` at q6 into q (6,), wrapped (offset_wrist.joints), and
    their cosines and sines into cs (6, 2) for :func:`_reproduces`."""
    h1, h2, h4, h5, h24 = _v(c, H1), _v(c, H2), _v(c, H4), _v(c, H5), _v(c, H24)
    cs[5, 1], cs[5, 0] = _sincos(q6)
    x, z5 = _wrist_line_cs(pt, cs[5, 0], cs[5, 1])
    cos1, sin1, _ = _shoulder(c, x, 1.0 if branch < 2 else -1.0)
    base, n, Z5 = _link1(c, x, z5, cos1, sin1)
    U, hU, W = _axis4(c, base, n, 1.0 if branch % 2 == 0 else -1.0)
    along = _dot(W, h2)
    W_perp = (W[0] - along * h2[0], W[1] - along * h2[1], W[2] - along * h2[2])
    upper = _v(c, UPPER)
    q2 = _angle(_dot(_cross(upper, W_perp), h2), _dot(upper, W_perp), cs, 1)
    psi = _angle(_dot(_cross(h4, U), h2), _dot(h4, U), cs, 2)
    # q3 = SIGMA3 (psi - q2): cs[2] holds psi's until here.
    cos_psi, sin_psi = cs[2, 0], cs[2, 1]
    cs[2, 0] = cos_psi * cs[1, 0] + sin_psi * cs[1, 1]
    cs[2, 1] = c[SIGMA3] * (sin_psi * cs[1, 0] - cos_psi * cs[1, 1])
    q3 = c[SIGMA3] * (psi - q2)
    # rot(h2, -psi) v = (v.h2) h2 + (v.U) h4 + (v.(h2 x U)) (h2 x h4)
    V = (_dot(Z5, h2), _dot(Z5, U), _dot(Z5, hU))
    V = (V[0] * h2[0] + V[1] * h4[0] + V[2] * h24[0], V[0] * h2[1] + V[1] * h4[1]
         + V[2] * h24[1], V[0] * h2[2] + V[1] * h4[2] + V[2] * h24[2])
    h5p = _v(c, H5P)                    # h5 across h4
    q4 = _angle(_dot(_cross(h5p, V), h4), _dot(h5p, V), cs, 3)
    Z6 = _rotate_back(h1, cos1, sin1, (pt[18], pt[19], pt[20]))
    Y = (_dot(Z6, h2), _dot(Z6, U), _dot(Z6, hU))
    Y = (Y[0] * h2[0] + Y[1] * h4[0] + Y[2] * h24[0], Y[0] * h2[1] + Y[1] * h4[1]
         + Y[2] * h24[1], Y[0] * h2[2] + Y[1] * h4[2] + Y[2] * h24[2])
    Y = _rotate_back(h4, cs[3, 0], cs[3, 1], Y)
    h6p = _v(c, H6P)
    q5 = _angle(_dot(_cross(h6p, Y), h5), _dot(h6p, Y), cs, 4)
    cs[0, 0], cs[0, 1] = cos1, sin1
    q[0], q[1], q[2] = math.atan2(sin1, cos1), _wrap(q2), _wrap(q3)
    q[3], q[4], q[5] = q4, q5, _wrap(q6)


def _reproduces(H, P, R_6T, T, cs, s):
    """True when poe.fk(q) is the pose T (4, 4) within the tolerances, from the joints'
    cosines and sines cs (6, 2) (:func:`_joints`: no trigonometric call; they match the
    returned angles to rounding); scalar code: no array is allocated.  A joint whose axis
    is a base axis (+-x, y or z at zero joint values, as on most URDFs) turns two columns
    of the rotation (12 products instead of 27 and the matrix's 15)."""
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0
    px, py, pz = P[0, 0], P[0, 1], P[0, 2]
    for i in range(6):
        x, y, z = H[i, 0], H[i, 1], H[i, 2]
        cq, sq = cs[i, 0], cs[i, 1]
        # rot(+-e_k, q): columns k+1 and k+2 (mod 3) turn, c' = c cos +- d sin.
        if y == 0.0 and z == 0.0 and abs(x) == 1.0:
            sq *= x
            r01, r02 = cq * r01 + sq * r02, cq * r02 - sq * r01
            r11, r12 = cq * r11 + sq * r12, cq * r12 - sq * r11
            r21, r22 = cq * r21 + sq * r22, cq * r22 - sq * r21
        elif x == 0.0 and z == 0.0 and abs(y) == 1.0:
            sq *= y
            r02, r00 = cq * r02 + sq * r00, cq * r00 - sq * r02
            r12, r10 = cq * r12 + sq * r10, cq * r10 - sq * r12
            r22, r20 = cq * r22 + sq * r20, cq * r20 - sq * r22
        elif x == 0.0 and y == 0.0 and abs(z) == 1.0:
            sq *= z
            r00, r01 = cq * r00 + sq * r01, cq * r01 - sq * r00
            r10, r11 = cq * r10 + sq * r11, cq * r11 - sq * r10
            r20, r21 = cq * r20 + sq * r21, cq * r21 - sq * r20
        else:
            r00, r01, r02, r10, r11, r12, r20, r21, r22 = _turned(
                r00, r01, r02, r10, r11, r12, r20, r21, r22, x, y, z, cq, sq)
        a, b, c = P[i + 1, 0], P[i + 1, 1], P[i + 1, 2]
        px += r00 * a + r01 * b + r02 * c
        py += r10 * a + r11 * b + r12 * c
        pz += r20 * a + r21 * b + r22 * c
    tol = s[POSITION_TOL]
    if not (abs(px - T[0, 3]) <= tol and abs(py - T[1, 3]) <= tol and abs(pz - T[2, 3]) <= tol):
        return False
    rows = ((r00, r01, r02), (r10, r11, r12), (r20, r21, r22))
    for a in range(3):
        for b in range(3):
            value = rows[a][0] * R_6T[0, b] + rows[a][1] * R_6T[1, b] + rows[a][2] * R_6T[2, b]
            if not abs(value - T[a, b]) <= s[ROTATION_TOL]:
                return False
    return True


def _turned(r00, r01, r02, r10, r11, r12, r20, r21, r22, x, y, z, cq, sq):
    """The rotation (rows r) times rot((x, y, z), q) (Rodrigues), as 9 scalars."""
    v = 1.0 - cq
    m00, m01, m02 = cq + x * x * v, x * y * v - z * sq, x * z * v + y * sq
    m10, m11, m12 = y * x * v + z * sq, cq + y * y * v, y * z * v - x * sq
    m20, m21, m22 = z * x * v - y * sq, z * y * v + x * sq, cq + z * z * v
    r00, r01, r02 = (r00 * m00 + r01 * m10 + r02 * m20, r00 * m01 + r01 * m11 + r02 * m21,
                     r00 * m02 + r01 * m12 + r02 * m22)
    r10, r11, r12 = (r10 * m00 + r11 * m10 + r12 * m20, r10 * m01 + r11 * m11 + r12 * m21,
                     r10 * m02 + r11 * m12 + r12 * m22)
    r20, r21, r22 = (r20 * m00 + r21 * m10 + r22 * m20, r20 * m01 + r21 * m11 + r22 * m21,
                     r20 * m02 + r21 * m12 + r22 * m22)
    return r00, r01, r02, r10, r11, r12, r20, r21, r22


def _mirror(c, q, cs, q_out, cs_out):
    """The other shoulder's solution of a mirror-symmetric arm from one solution q (6,)
    and its cosines and sines cs (6, 2), into q_out, cs_out: the arm turned half a turn
    about axis 1 (J1 + pi) reflects its plane across axis 1, so J2 -> MIRROR_Q2 - J2,
    J3 -> MIRROR_Q3 - J3, J4 + pi, J5 and J6 unchanged (the constants: offset_wrist._mirror_angles)."""
    q_out[0], q_out[1] = _wrap(q[0] + math.pi), _wrap(c[MIRROR_Q2] - q[1])
    q_out[2], q_out[3] = _wrap(c[MIRROR_Q3] - q[2]), _wrap(q[3] + math.pi)
    q_out[4], q_out[5] = q[4], q[5]
    for j in range(6):
        cs_out[j, 0], cs_out[j, 1] = cs[j, 0], cs[j, 1]
    for j in (0, 3):
        cs_out[j, 0], cs_out[j, 1] = -cs[j, 0], -cs[j, 1]
    for j in (1, 2):
        cos_c, sin_c = c[MIRROR_CS + 2 * j - 2], c[MIRROR_CS + 2 * j - 1]
        cs_out[j, 0] = cos_c * cs[j, 0] + sin_c * cs[j, 1]
        cs_out[j, 1] = sin_c * cs[j, 0] - cos_c * cs[j, 1]


def _found_before(cand_q6, cand_branch, i, tol):
    """True when candidate i repeats an earlier one of its branch (the same root found
    from a window or a dip too): its joints need not be computed again."""
    for r in range(i):
        if cand_branch[r] == cand_branch[i] and abs(cand_q6[r] - cand_q6[i]) < 1e3 * tol:
            return True
    return False


def _known(out, kept, q, tol):
    """True when one of out[:kept] is within tol of q on every joint (both wrapped into
    (-pi, pi], so a difference d is |d| or 2 pi - |d| apart)."""
    for r in range(kept):
        same = True
        for j in range(6):
            d = abs(out[r, j] - q[j])
            if min(d, 2.0 * math.pi - d) > tol:
                same = False
                break
        if same:
            return True
    return False


def _pose_terms(c, T, pt):
    """The pose terms of T (4, 4) into pt (21,): p_T - a1 - R B0, then R times B1, B2, Z0,
    Z1, Z2 and T6 (axis 6 in the base frame)."""
    for a in range(3):
        pt[a] = T[a, 3] - c[A1 + a]
        for b in range(3):
            pt[a] -= T[a, b] * c[B0 + b]
        for k, start in enumerate((B1, B2, Z0, Z1, Z2, T6)):
            value = 0.0
            for b in range(3):
                value += T[a, b] * c[start + b]
            pt[3 * (k + 1) + a] = value


def _tilt(c, pt):
    """|axis 6 x axis 1|: the sine of axis 6's angle from upright."""
    h6, h1 = (pt[18], pt[19], pt[20]), _v(c, H1)
    return _sqrt(_dot(_cross(h6, h1), _cross(h6, h1)))


def _beyond_reach(screen, T):
    """offset_wrist_polish.beyond_reach of one pose T (4, 4)."""
    total = 0.0
    for a in range(3):
        x = T[a, 3] - screen[BASE + a]
        for b in range(3):
            x -= T[a, b] * screen[FLANGE + b]
        total += x * x
    return total > screen[LINKS] ** 2


def _suspect(screen, out, T):
    """offset_wrist_polish.suspect of one pose's rows out (16, 6), unless beyond reach."""
    if _beyond_reach(screen, T):
        return False
    if out[0, 0] != out[0, 0]:
        return True
    for r in range(out.shape[0]):
        if out[r, 0] != out[r, 0]:
            break
        for a in range(int(screen[N_ALIGNED])):
            if abs(math.sin(out[r, 3] - screen[ALIGNED + a])) < screen[SUSPECT_SIN]:
                return True
    return False


def _solve_pose(c, s, H, P, R_6T, T, t_grid, cos_t, sin_t, out, pt, F, R2, N2, loop_t,
                cand_q6, cand_branch, cand_new, cand_q, cand_cs, q, cs, window_t, window_f,
                window_work, edge_t, edge_f, edge_work, rf, lane, dip_work):
    """Every solution of one pose T (4, 4) into out (16, 6), sorted, NaN rows last; pt its
    :func:`_pose_terms`; the other arrays are work space (see :func:`_solve`)."""
    G = t_grid.shape[0]
    # Mirror-symmetric arms: branches 3 and 2 have the residuals of 0 and 1.
    shoulders = 1 if c[SYMMETRIC] != 0.0 else 2
    _grid(c, pt, cos_t, sin_t, 0, shoulders, F, 1, R2, N2)
    for branch in range(2 * shoulders):
        F[branch, 0], F[branch, G + 1] = F[branch, G], F[branch, 1]
    count = _add_brackets(c, pt, s, loop_t[1:], F[:, 1:], 0, 2 * shoulders, cand_q6,
                          cand_branch, 0, rf, lane)
    count = _dips(c, pt, s, loop_t[1:], F[:, 1:], 0, 2 * shoulders, cand_q6, cand_branch, count,
                  dip_work)
    step = 2.0 * math.pi / G
    for j in range(G):
        # The local-minimum test of _narrow first, here: a call per sample costs more.
        before, after = j - 1 if j > 0 else G - 1, j + 1 if j < G - 1 else 0
        if R2[j] <= R2[before] and R2[j] < R2[after] and \
                _narrow(R2, j, step, s[WINDOW_STEPS]) != 0.0:
            count = _window(c, pt, s, R2, j, 1, shoulders, t_grid, window_t, window_f,
                            window_work, cand_q6, cand_branch, count, rf, lane, dip_work)
        for shoulder in range(shoulders):
            norm_sq = N2[shoulder]
            if norm_sq[j] <= norm_sq[before] and norm_sq[j] < norm_sq[after] and \
                    _narrow(norm_sq, j, step, s[WINDOW_STEPS]) != 0.0:
                count = _window(c, pt, s, N2[shoulder], j, 2, shoulder, t_grid, window_t,
                                window_f, window_work, cand_q6, cand_branch, count, rf, lane,
                                dip_work)
    for shoulder in range(shoulders):
        row = F[2 * shoulder]
        for j in range(1, G + 1):
            if (row[j] == row[j]) != (row[j + 1] == row[j + 1]):
                t_in, t_out = (loop_t[j], loop_t[j + 1]) if row[j] == row[j] else \
                    (loop_t[j + 1], loop_t[j])
                count = _edge(c, pt, s, t_in, t_out, shoulder, edge_t, edge_f, edge_work,
                              cand_q6, cand_branch, count, rf, lane, dip_work)
    out[:, :] = np.nan
    kept = 0
    for i in range(count):
        cand_new[i] = not _found_before(cand_q6, cand_branch, i, s[Q6_TOL])
        if not cand_new[i]:
            continue
        _joints(c, pt, cand_q6[i], cand_branch[i], cand_q[i], cand_cs[i])
        kept = _keep(H, P, R_6T, T, s, cand_q[i], cand_cs[i], out, kept)
    # Mirror-symmetric arms: the other shoulder's candidates (branch 3 - b at the same
    # q6, as many as MAX_CANDIDATES leaves room for) are the first's mirrored.
    for i in range(min(count, MAX_CANDIDATES - count) if shoulders == 1 else 0):
        if cand_new[i]:
            _mirror(c, cand_q[i], cand_cs[i], q, cs)
            kept = _keep(H, P, R_6T, T, s, q, cs, out, kept)
    for i in range(1, kept):        # insertion sort, joint 1 first
        q[:] = out[i]
        r = i
        while r > 0 and _before(q, out[r - 1]):
            out[r] = out[r - 1]
            r -= 1
        out[r] = q


def _keep(H, P, R_6T, T, s, q, cs, out, kept):
    """Append solution q (6,) to out[:kept] unless known, not reproducing T or out is
    full; the new count."""
    if not _known(out, kept, q, s[DEDUP_TOL]) and _reproduces(H, P, R_6T, T, cs, s) \
            and kept < MAX_SOLUTIONS:
        out[kept, :] = q
        kept += 1
    return kept


def _before(a, b):
    for j in range(6):
        if a[j] != b[j]:
            return a[j] < b[j]
    return False


def _solve(c, s, H, P, R_6T, T, t_grid, out, screen, flags):
    """Every pose of T (n, 4, 4) into out (n, 16, 6) and its flag into flags (n,) (see
    :func:`inverse_into`); the work space is allocated once."""
    G = t_grid.shape[0]
    cos_t, sin_t = np.cos(t_grid), np.sin(t_grid)
    loop_t = np.empty(G + 2)
    loop_t[1:G + 1] = t_grid
    loop_t[0], loop_t[G + 1] = t_grid[G - 1] - 2.0 * math.pi, t_grid[0] + 2.0 * math.pi
    pt, F, R2, N2 = np.empty(21), np.empty((4, G + 2)), np.empty(G), np.empty((2, G))
    cand_q6 = np.empty(MAX_CANDIDATES)
    cand_branch = np.empty(MAX_CANDIDATES, dtype=np.int64)
    cand_new = np.empty(MAX_CANDIDATES, dtype=np.bool_)
    cand_q, cand_cs = np.empty((MAX_CANDIDATES, 6)), np.empty((MAX_CANDIDATES, 6, 2))
    q, cs = np.empty(6), np.empty((6, 2))
    window_t = np.empty(int(s[WINDOW_SAMPLES]) + 2)
    window_f = np.empty((4, int(s[WINDOW_SAMPLES]) + 2))
    window_work = np.empty((6, int(s[WINDOW_SAMPLES]) + 2))
    for i in range(int(s[WINDOW_SAMPLES])):      # uniform in the window's angle
        window_work[5, i] = math.tan(math.pi * ((i + 0.5) / s[WINDOW_SAMPLES] - 0.5))
    edge_t = np.empty(int(s[EDGE_SAMPLES]) + 1)
    edge_f = np.empty((4, int(s[EDGE_SAMPLES]) + 1))
    edge_work = np.empty((5, int(s[EDGE_SAMPLES]) + 1))
    rf, lane = np.empty((N_RF, MAX_CANDIDATES)), np.empty(MAX_CANDIDATES, dtype=np.int64)
    dip_work = np.empty((4, 4 * (max(G, int(s[WINDOW_SAMPLES]), int(s[EDGE_SAMPLES])) + 2)))
    for i in range(T.shape[0]):
        _pose_terms(c, T[i], pt)
        tilt = _tilt(c, pt)
        flags[i] = PLAIN
        if tilt < screen[FREE_SIN]:
            out[i] = np.nan
            flags[i] = UPRIGHT
            continue
        _solve_pose(c, s, H, P, R_6T, T[i], t_grid, cos_t, sin_t, out[i], pt, F, R2, N2, loop_t,
                    cand_q6, cand_branch, cand_new, cand_q, cand_cs, q, cs, window_t, window_f,
                    window_work, edge_t, edge_f, edge_work, rf, lane, dip_work)
        if tilt < screen[UPRIGHT_SIN]:
            flags[i] = UPRIGHT
        elif _suspect(screen, out[i], T[i]):
            flags[i] = SUSPECT


def inverse_into(c, s, params, T, t_grid, out, screen=None, flags=None):
    """Solve poses T (n, 4, 4) float64 C-contiguous into out (n, 16, 6), rad; with a
    `screen` (:data:`SCREEN_LAYOUT`) each pose's :data:`PLAIN`, :data:`UPRIGHT` (not
    searched where upright within ``screen[FREE_SIN]``) or :data:`SUSPECT` into flags (n,)
    int8 (offset_wrist_polish.solve's screening, in the same pass)."""
    if screen is None:
        screen, flags = NO_SCREEN, np.empty(len(T), dtype=np.int8)
    _solve(c, s, np.ascontiguousarray(params.H, dtype=float),
           np.ascontiguousarray(params.P, dtype=float),
           np.ascontiguousarray(params.R_6T, dtype=float), T, t_grid, out, screen, flags)
