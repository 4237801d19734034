"""The OPW inverse compiled with numba: the fast path of :func:`opw.inverse`.

numba is a dependency in ``package.xml`` (the Addon Manager installs it), but not a
hard one: without it, or where it fails to compile, :func:`opw.inverse` runs its
numpy code, which stays the reference. The tests compare the two on every OPW arm
of the catalog, at wrist singularities and out of reach.

The equations are those of ``opw._inverse_block`` (see it for the derivation),
arranged for vector instructions:

* poses are solved in blocks, each quantity one row of a work buffer, and every loop
  over a block's poses is straight-line code (selects, no branches or calls), so the
  compiler runs four poses at a time (AVX2);
* angles are carried as unit vectors (cos, sin) wherever only their sine and cosine
  are needed: the elbow's sine follows from its cosine, theta4's from the vector it
  is the angle of; only the joint values themselves take an arctangent;
* that arctangent is :func:`_atan2`, a branch-free rational approximation accurate to
  5e-16 rad (libm's ``atan2`` is a call, which stops vectorisation).

The answers have the same NaN rows as the numpy code's and joint values within 1e-7
degrees of them where the equations are well conditioned; at and next to an elbow or
wrist singularity, where rounding decides how the motion splits between joints, both
give the same flange pose (tests/core/test_opw_inverse_equivalence.py).

The first call in a session loads the compiled code from numba's cache (about 0.5 s,
most of it importing numba), or compiles it (6 to 8 s, once per installation and
Python version).
"""

import math

import numpy as np

from . import numba_kernel
from .numba_kernel import compile_in_place


#: Layout of the constants vector the kernel takes (see :func:`constants_vector`).
(A1, B, C1, C2, C4, B_SQ, TWO_A1, KAPPA, C2_SQ, KAPPA_SQ, ELBOW_DENOMINATOR, PSI3,
 COS_PSI3, SIN_PSI3, ACOS_LIMIT, SINGULAR_SQ, WRAP_AT) = range(17)
OFFSETS = 17        # 6 joint offsets, radians
SCALES = 23         # 6 factors sign * 180 / pi
N_CONSTANTS = 29


#: Why the compiled kernel is not used ("" while it is, None before the first call
#: of :func:`available`).
why_not = None


def available():
    """True when the compiled kernel can be used.

    The first call imports numba and loads or compiles the kernel; a failure there
    (numba missing, switched off, or unable to compile) is kept in :data:`why_not`
    and the numpy code is used from then on.
    """
    return numba_kernel.available(globals(), _compile)


def _compile():
    """Compile the kernel in place (:func:`.numba_kernel.compile_in_place`); "" or why not."""
    inlined = ("_atan2", "_acos", "_degrees", "_unit")
    return compile_in_place(globals(), inlined + ("_arm_branch", "_solve_block", "_solve"),
                            lambda: _solve(np.zeros(N_CONSTANTS), np.eye(4)[None],
                                           np.empty((1, 8, 6))), inlined)


def constants_vector(k, acos_tolerance, wrist_singular_sin, angle_tolerance_deg):
    """The kernel's constants from ``opw._InverseConstants`` and opw's tolerances.

    Returns
    -------
    ndarray, shape (29,)
    """
    c = np.zeros(N_CONSTANTS)
    c[[A1, B, C1, C2, C4, B_SQ, TWO_A1, KAPPA, C2_SQ, KAPPA_SQ, ELBOW_DENOMINATOR, PSI3]] = (
        k.a1, k.b, k.c1, k.c2, k.c4, k.b_sq, k.two_a1, k.kappa, k.c2_sq, k.kappa_sq,
        k.elbow_denominator, k.psi3)
    c[COS_PSI3], c[SIN_PSI3] = np.cos(k.psi3), np.sin(k.psi3)
    c[ACOS_LIMIT] = 1.0 + acos_tolerance
    c[SINGULAR_SQ] = wrist_singular_sin ** 2
    c[WRAP_AT] = 180.0 + angle_tolerance_deg
    for rows, offset in k.offsets:
        c[OFFSETS + _joint_of_row(rows.start)] = offset
    c[SCALES:SCALES + 6] = k.scale_rows[[0, 2, 6, 10, 18, 26], 0]
    return c


def _joint_of_row(row):
    """Joint of a row of the numpy code's 34-row block (2, 4, 4, 8, 8, 8 rows)."""
    return int(np.searchsorted(np.cumsum((2, 4, 4, 8, 8, 8)), row, side="right"))


#: Poses solved per block: the block's work rows (68 rows of doubles, 272 kB) stay in
#: the core's cache between the passes of :func:`_solve`.
BLOCK_POSES = 512

#: Rows of the work buffer (:func:`_solve_block`): 12 of input, 8 per-shoulder values,
#: 48 of output.  The buffer is one flat array indexed
#: ``row * BLOCK_POSES + pose``: with the row stride a compile-time constant, the
#: compiler can prove that a pose's reads and writes do not overlap the next poses'
#: and vectorises the loops (with a runtime stride it gives up).
S_ROWS, Q_ROWS, WORK_ROWS = 12, 20, 68

# atan on [-tan(pi/8), tan(pi/8)] as t + t z P(z) / Q(z), z = t^2: the rational
# approximation of Cephes' atan.c (S. L. Moshier), relative error below 3e-16.
_P0, _P1, _P2, _P3, _P4 = (-8.750608600031904122785e-1, -1.615753718733365076637e1,
                           -7.500855792314704667340e1, -1.228866684490136173410e2,
                           -6.485021904942025371773e1)
_Q0, _Q1, _Q2, _Q3, _Q4 = (2.485846490142306297962e1, 1.650270098316988542046e2,
                           4.328810604912902668951e2, 4.853903996359136964868e2,
                           1.945506571482613964425e2)
_TAN_PI_8 = 0.41421356237309504880
_PI_4_LOW = 6.123233995736765886130e-17     # pi/4 - float(pi/4)


def _atan2(y, x):
    """atan2 without branches, so a loop over poses compiles to vector instructions.

    Agrees with ``math.atan2`` to 5e-16 rad for finite arguments (signed zeros
    included); NaN in, NaN out; two infinities give NaN (the IK never sees them).
    """
    ax, ay = abs(x), abs(y)
    steep = ay > ax
    hi = ay if steep else ax
    lo = ax if steep else ay
    big = lo > _TAN_PI_8 * hi
    t = (lo - hi if big else lo) / (lo + hi if big else hi)
    z = t * t
    p = (((_P0 * z + _P1) * z + _P2) * z + _P3) * z + _P4
    q = ((((z + _Q0) * z + _Q1) * z + _Q2) * z + _Q3) * z + _Q4
    a = t + t * (z * p / q)
    a = a + (0.25 * math.pi + _PI_4_LOW) if big else a
    a = 0.5 * math.pi - a if steep else a
    negative_x = math.copysign(1.0, x) < 0.0
    a = 0.0 if hi == 0.0 else a
    a = math.pi - a if negative_x else a
    a = math.copysign(a, y)
    return a if x == x and y == y else math.nan


def _acos(x):
    """arccos of x in [-1, 1], through :func:`_atan2` (accurate near +-1 too)."""
    return _atan2(math.sqrt((1.0 - x) * (1.0 + x)), x)


def _degrees(theta, offset, scale, wrap_at):
    """A model angle (radians) in the controller's degrees, wrapped into (-180, 180]
    as ``opw.wrap_deg`` wraps (`wrap_at` = 180 + its tolerance: an angle within the
    tolerance of -180 comes out +180)."""
    q = (theta + offset) * scale
    return q - 360.0 * np.ceil((q - wrap_at) / 360.0)


def _unit(y, x):
    """(cos, sin) of atan2(y, x): (x, y) normalised, (1, 0) for the zero vector."""
    norm = math.sqrt(x * x + y * y)
    zero = norm == 0.0
    inverse = 1.0 / (1.0 if zero else norm)
    return (1.0 if zero else x * inverse), (0.0 if zero else y * inverse)


def _solve_block(c, W, m):
    """Solve the poses of one block.

    Each loop over the poses runs straight-line code (no branch, no call), so it
    compiles to vector instructions: four poses at a time with AVX2.

    Parameters
    ----------
    c : ndarray, shape (29,)
        :func:`constants_vector`.
    W : ndarray, shape (WORK_ROWS * BLOCK_POSES,)
        The work buffer, ``W[row * BLOCK_POSES + pose]``.  Rows 0-11 (in): r00 r01 r02
        r10 r11 r12 r20 r21 r22 px py pz of the flange poses, mm.  Rows S_ROWS + 0-7
        (work): theta1, cos theta1, sin theta1 of the front, then of the back shoulder,
        the horizontal distance nx1 - a1 from axis 2 to the wrist centre, its height dz.
        Rows Q_ROWS + 0-47 (out): row 12 * arm branch + 6 * wrist + joint, degrees
        (NaN for a branch that does not exist).
    m : int
        Poses in the block, at most BLOCK_POSES.
    """
    a1, b, c1, c4, two_a1 = c[A1], c[B], c[C1], c[C4], c[TWO_A1]
    b_sq = c[B_SQ]
    # Views, so that the compiler sees each loop's reads and writes in separate arrays
    # at constant row offsets.
    stride = BLOCK_POSES
    poses = W[:S_ROWS * stride]
    work = W[S_ROWS * stride:Q_ROWS * stride]
    for i in range(m):
        cx = poses[9 * stride + i] - c4 * poses[2 * stride + i]
        cy = poses[10 * stride + i] - c4 * poses[5 * stride + i]
        rho_sq = cx * cx + cy * cy
        nx1 = math.sqrt(rho_sq - b_sq)                # NaN inside the lateral offset
        phi = _atan2(cy, cx)
        cos_phi, sin_phi = _unit(cy, cx)
        # beta = atan2(b, nx1), whose hypotenuse is rho.
        beta = _atan2(b, nx1)
        inverse_rho = 1.0 / math.sqrt(rho_sq)
        cos_beta = 1.0 if b == 0.0 else nx1 * inverse_rho
        sin_beta = 0.0 if b == 0.0 else b * inverse_rho
        work[i] = phi - beta                            # the front shoulder
        work[stride + i] = cos_phi * cos_beta + sin_phi * sin_beta
        work[2 * stride + i] = sin_phi * cos_beta - cos_phi * sin_beta
        work[3 * stride + i] = phi + beta - math.pi     # the back shoulder
        work[4 * stride + i] = sin_phi * sin_beta - cos_phi * cos_beta
        work[5 * stride + i] = -(sin_phi * cos_beta + cos_phi * sin_beta)
        work[6 * stride + i] = nx1 - a1
        work[7 * stride + i] = poses[11 * stride + i] - c4 * poses[8 * stride + i] - c1
    common = work[6 * stride:]
    for branch in range(4):
        back = branch >= 2
        shoulder = work[3 * back * stride:(3 * back + 3) * stride]
        rows = W[(Q_ROWS + 12 * branch) * stride:(Q_ROWS + 12 * branch + 12) * stride]
        _arm_branch(c, poses, shoulder, common, rows, m, two_a1 if back else 0.0,
                    -1.0 if back else 1.0, -1.0 if branch % 2 else 1.0)


def _arm_branch(c, poses, shoulder, common, rows, m, planar_add, reach_sign, elbow_sign):
    """One arm branch of every pose of the block (views of :func:`_solve_block`'s work
    buffer, row r of a view at ``r * stride``): `poses` the 12 input rows,
    `shoulder` theta1, cos and sin of its shoulder, `common` nx1 - a1 and dz; filled:
    the 12 rows of `rows`, 6 joints with the wrist as solved, then 6 with it flipped.

    The planar distance is nx1 - a1 + `planar_add`, the reach `reach_sign` times it;
    `elbow_sign` +1 or -1 picks the elbow.  Angles are carried as unit vectors (cos, sin) where
    only their sine and cosine are needed.
    """
    c2_sq_kappa_sq = c[C2_SQ] + c[KAPPA_SQ]
    elbow_denominator, acos_limit, psi3 = c[ELBOW_DENOMINATOR], c[ACOS_LIMIT], c[PSI3]
    kappa, c2, cos_psi3, sin_psi3 = c[KAPPA], c[C2], c[COS_PSI3], c[SIN_PSI3]
    singular_sq, wrap_at = c[SINGULAR_SQ], c[WRAP_AT]
    o1, o2, o3, o4, o5, o6 = c[OFFSETS], c[OFFSETS + 1], c[OFFSETS + 2], c[OFFSETS + 3], \
        c[OFFSETS + 4], c[OFFSETS + 5]
    k1, k2, k3, k4, k5, k6 = c[SCALES], c[SCALES + 1], c[SCALES + 2], c[SCALES + 3], \
        c[SCALES + 4], c[SCALES + 5]
    stride = BLOCK_POSES
    for i in range(m):
        theta1, cos1, sin1 = shoulder[i], shoulder[stride + i], shoulder[2 * stride + i]
        planar = common[i] + planar_add
        reach = reach_sign * planar
        dz = common[stride + i]
        r00, r01, r02 = poses[i], poses[1 * stride + i], poses[2 * stride + i]
        r10, r11, r12 = poses[3 * stride + i], poses[4 * stride + i], poses[5 * stride + i]
        r20, r21, r22 = poses[6 * stride + i], poses[7 * stride + i], poses[8 * stride + i]
        cos_elbow = (planar * planar + dz * dz - c2_sq_kappa_sq) / elbow_denominator
        reachable = abs(cos_elbow) <= acos_limit
        cos_elbow = min(max(cos_elbow, -1.0), 1.0)
        sin_elbow = elbow_sign * math.sqrt((1.0 - cos_elbow) * (1.0 + cos_elbow))
        theta3 = elbow_sign * _acos(cos_elbow) - psi3
        # theta2 = aim - atan2(kappa sin(elbow), c2 + kappa cos(elbow)), aim = atan2(reach, dz)
        cos_aim, sin_aim = _unit(reach, dz)
        cos_g, sin_g = _unit(kappa * sin_elbow, c2 + kappa * cos_elbow)
        cos2 = cos_aim * cos_g + sin_aim * sin_g
        sin2 = sin_aim * cos_g - cos_aim * sin_g
        theta2 = _atan2(sin2, cos2)
        cos3 = cos_elbow * cos_psi3 + sin_elbow * sin_psi3
        sin3 = sin_elbow * cos_psi3 - cos_elbow * sin_psi3
        c23 = cos2 * cos3 - sin2 * sin3
        s23 = sin2 * cos3 + cos2 * sin3
        # The wrist: R_ce = Rz(theta4) Ry(theta5) Rz(theta6) = R_0c^T R.  u, v are the
        # rows 0, 1 of Rz(theta1)^T R; v is also row 1 of R_ce.
        u0 = cos1 * r00 + sin1 * r10
        u1 = cos1 * r01 + sin1 * r11
        u2 = cos1 * r02 + sin1 * r12
        v0 = cos1 * r10 - sin1 * r00
        v1 = cos1 * r11 - sin1 * r01
        v2 = cos1 * r12 - sin1 * r02
        ce0x = c23 * u0 - s23 * r20
        ce0y = c23 * u1 - s23 * r21
        ce0z = c23 * u2 - s23 * r22
        ce22 = s23 * u2 + c23 * r22
        sin5_sq = ce0z * ce0z + v2 * v2
        singular = sin5_sq < singular_sq               # theta4 = 0, theta6 takes the rest
        along = math.sqrt(sin5_sq)
        theta4 = 0.0 if singular else _atan2(v2, ce0z)
        inverse_along = 1.0 / (1.0 if singular else along)
        sin4 = 0.0 if singular else v2 * inverse_along
        cos4 = 1.0 if singular else ce0z * inverse_along
        theta5 = _atan2(ce0z if singular else along, ce22)
        theta6 = _atan2(cos4 * v0 - sin4 * ce0x, cos4 * v1 - sin4 * ce0y)
        nan_row = (0.0 if reachable else math.nan) + theta1 + theta2 + theta3 + theta4 \
            + theta5 + theta6
        nan_row -= nan_row                             # +0.0, or NaN where no branch
        q1 = _degrees(theta1, o1, k1, wrap_at) + nan_row
        q2 = _degrees(theta2, o2, k2, wrap_at) + nan_row
        q3 = _degrees(theta3, o3, k3, wrap_at) + nan_row
        rows[i] = q1
        rows[1 * stride + i] = q2
        rows[2 * stride + i] = q3
        rows[3 * stride + i] = _degrees(theta4, o4, k4, wrap_at) + nan_row
        rows[4 * stride + i] = _degrees(theta5, o5, k5, wrap_at) + nan_row
        rows[5 * stride + i] = _degrees(theta6, o6, k6, wrap_at) + nan_row
        rows[6 * stride + i] = q1
        rows[7 * stride + i] = q2
        rows[8 * stride + i] = q3
        rows[9 * stride + i] = _degrees(theta4 + math.pi, o4, k4, wrap_at) + nan_row
        rows[10 * stride + i] = _degrees(-theta5, o5, k5, wrap_at) + nan_row
        rows[11 * stride + i] = _degrees(theta6 - math.pi, o6, k6, wrap_at) + nan_row


def _solve(c, T, out):
    """Fill out (n, 8, 6) with the eight branches of each pose T (n, 4, 4), degrees."""
    n = T.shape[0]
    stride = BLOCK_POSES
    W = np.empty(WORK_ROWS * stride)
    for start in range(0, n, stride):
        m = min(stride, n - start)
        for row in range(3):
            for column in range(4):
                k = (9 + row if column == 3 else 3 * row + column) * stride
                for i in range(m):
                    W[k + i] = T[start + i, row, column]
        _solve_block(c, W, m)
        for branch in range(8):     # work row 12 * arm branch + 6 * wrist + joint
            k = (Q_ROWS + 12 * (branch % 4) + 6 * (branch // 4)) * stride
            for joint in range(6):
                for i in range(m):
                    out[start + i, branch, joint] = W[k + joint * stride + i]


def inverse_into(c, T, out):
    """Solve poses T (n, 4, 4) float64 C-contiguous into out (n, 8, 6), degrees."""
    _solve(c, T, out)
