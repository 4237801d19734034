"""Closed-form kinematics of ortho-parallel robots with a spherical wrist (OPW).

The model and the equations are those of M. Brandstötter, A. Angerer,
M. Hofbaur, "An analytical solution of the inverse kinematics problem of
industrial serial manipulators with an ortho-parallel basis and a spherical
wrist" (Austrian Robotics Workshop, 2014).  Seven lengths describe the arm
(:class:`~.catalog.OPWParameters`, mm here): ``c1`` base height, ``a1``
shoulder offset, ``b`` lateral offset, ``c2`` lower arm, ``a2`` elbow offset,
``c3`` forearm, ``c4`` wrist centre to flange.  In the model's zero pose the
arm points straight up and the flange frame is parallel to the base frame.

Joint conventions are those of opw_kinematics (Jmeyer1292/opw_kinematics),
so its published parameter sets and test data apply unchanged:

* forward: ``q_model = q * sign - offset``;
* inverse: eight solutions ``(theta + offset) * sign``, each joint wrapped
  into (-180, 180] degrees (opw's ``harmonizeTowardZero``), a whole row NaN
  where that branch does not exist.  Joint limits are not applied here.

Branch order (rows of :func:`inverse`), as in opw_kinematics::

    row  shoulder (theta1)   elbow          wrist
    0    front  (i)          theta2_i       theta5 >= 0
    1    front  (i)          theta2_ii      theta5 >= 0
    2    back   (ii)         theta2_iii     theta5 >= 0
    3    back   (ii)         theta2_iv      theta5 >= 0
    4-7  as rows 0-3 with the wrist flipped: theta4 + 180, -theta5, theta6 - 180

Everything is vectorised over poses: no Python loop runs per pose.  Where
numba is installed, :func:`inverse` runs the same equations compiled
(:mod:`.opw_kernel`, four to five times faster); :func:`inverse_numpy` is
the numpy code it falls back to.  Never imports FreeCAD.
"""

import functools

import numpy as np

from . import opw_kernel

#: Arguments of arccos this far beyond +-1 (rounding at the edge of the
#: workspace) are clipped; further out the branch is unreachable (NaN).
#: 1e-12 of a ratio of lengths is < 1e-9 mm of position for a 1 m arm.
ACOS_TOLERANCE = 1e-12

#: Below this value of sin(theta5) the wrist is singular: theta4 and theta6
#: are coupled, theta4 is set to 0 (model angle) and theta6 takes the rest.
WRIST_SINGULAR_SIN = 1e-12


def _params_arrays(params):
    offsets_rad = np.radians(np.asarray(params.offsets_deg, dtype=float))
    signs = np.asarray(params.signs, dtype=float)
    return offsets_rad, signs


def safe_arccos(x):
    """arccos that forgives rounding just beyond +-1 and is NaN further out.

    Parameters
    ----------
    x : array_like, any shape

    Returns
    -------
    ndarray, same shape, radians in [0, pi] or NaN where ``|x| > 1 + ACOS_TOLERANCE``.
    """
    x = np.asarray(x, dtype=float)
    with np.errstate(invalid="ignore"):
        x = np.where(np.abs(x) <= 1.0 + ACOS_TOLERANCE, np.clip(x, -1.0, 1.0), np.nan)
    return np.arccos(x)


#: Joint angles this close to the ±180 degree seam, or to a joint limit, are on it:
#: rounding noise (1e-14 degrees, different between numpy/FreeCAD versions and after
#: a document is saved and reopened) must not move a joint across.
ANGLE_TOLERANCE_DEG = 1e-9


def wrap_deg(q_deg):
    """Angles wrapped into (-180, 180] degrees (NaN stays NaN).

    An angle within :data:`ANGLE_TOLERANCE_DEG` of -180 wraps to +180 (and one
    that much above 180 stays), so noise never decides between -180 and +180.

    Parameters
    ----------
    q_deg : array_like, any shape

    Returns
    -------
    ndarray, same shape
        In (-180 + tol, 180 + tol].
    """
    q_deg = np.asarray(q_deg, dtype=float)
    return q_deg - 360.0 * np.ceil((q_deg - 180.0 - ANGLE_TOLERANCE_DEG) / 360.0)


def forward(params, q_deg):
    """Flange pose of an OPW robot.

    Parameters
    ----------
    params : OPWParameters
        Lengths in mm, ``offsets_deg`` and ``signs`` per joint.
    q_deg : array_like, shape (N, 6) or (6,)
        Joint values in the controller's convention, degrees.

    Returns
    -------
    T_r_f : ndarray, shape (N, 4, 4) or (4, 4)
        Flange frame {F} in the robot base frame {R}, mm.
    """
    q_deg = np.asarray(q_deg, dtype=float)
    single = q_deg.ndim == 1
    q_deg = np.atleast_2d(q_deg)
    if q_deg.shape[-1] != 6:
        raise ValueError("q_deg must have shape (N, 6), got %s" % (q_deg.shape,))
    offsets_rad, signs = _params_arrays(params)
    q = np.radians(q_deg) * signs - offsets_rad  # model angles, (N, 6)
    p = params

    s = np.sin(q)
    c = np.cos(q)
    s1, s2, s4, s5, s6 = s[:, 0], s[:, 1], s[:, 3], s[:, 4], s[:, 5]
    c1, c2, c4, c5, c6 = c[:, 0], c[:, 1], c[:, 3], c[:, 4], c[:, 5]
    q23 = q[:, 1] + q[:, 2]
    s23, c23 = np.sin(q23), np.cos(q23)

    # Wrist centre: the arm in its own vertical plane, then turned by q1.
    psi3 = np.arctan2(p.a2, p.c3)
    k = np.hypot(p.a2, p.c3)
    cx1 = p.c2 * s2 + k * np.sin(q23 + psi3) + p.a1
    cz1 = p.c2 * c2 + k * np.cos(q23 + psi3)
    cy1 = p.b
    centre = np.stack([cx1 * c1 - cy1 * s1, cx1 * s1 + cy1 * c1, cz1 + p.c1], axis=-1)

    # R_0c = Rz(q1) Ry(q2 + q3);  R_ce = Rz(q4) Ry(q5) Rz(q6).
    n = q.shape[0]
    R_0c = np.empty((n, 3, 3))
    R_0c[:, 0, 0] = c1 * c23
    R_0c[:, 0, 1] = -s1
    R_0c[:, 0, 2] = c1 * s23
    R_0c[:, 1, 0] = s1 * c23
    R_0c[:, 1, 1] = c1
    R_0c[:, 1, 2] = s1 * s23
    R_0c[:, 2, 0] = -s23
    R_0c[:, 2, 1] = 0.0
    R_0c[:, 2, 2] = c23
    R_ce = np.empty((n, 3, 3))
    R_ce[:, 0, 0] = c4 * c5 * c6 - s4 * s6
    R_ce[:, 0, 1] = -c4 * c5 * s6 - s4 * c6
    R_ce[:, 0, 2] = c4 * s5
    R_ce[:, 1, 0] = s4 * c5 * c6 + c4 * s6
    R_ce[:, 1, 1] = -s4 * c5 * s6 + c4 * c6
    R_ce[:, 1, 2] = s4 * s5
    R_ce[:, 2, 0] = -s5 * c6
    R_ce[:, 2, 1] = s5 * s6
    R_ce[:, 2, 2] = c5
    R = R_0c @ R_ce

    T_r_f = np.zeros((n, 4, 4))
    T_r_f[:, :3, :3] = R
    T_r_f[:, :3, 3] = centre + p.c4 * R[:, :, 2]
    T_r_f[:, 3, 3] = 1.0
    return T_r_f[0] if single else T_r_f


def inverse(params, T_r_f):
    """All eight closed-form inverse kinematic solutions of an OPW robot.

    Parameters
    ----------
    params : OPWParameters
        Lengths in mm, ``offsets_deg`` and ``signs`` per joint.
    T_r_f : array_like, shape (N, 4, 4) or (4, 4)
        Flange poses in the robot base frame, mm.  The rotation part must be
        a proper rotation matrix.

    Returns
    -------
    q_deg : ndarray, shape (N, 8, 6) or (8, 6)
        Joint values in the controller's convention, degrees, each in
        (-180, 180].  Row order is opw_kinematics' (see the module
        docstring).  A row is all NaN when that branch does not exist
        (the wrist centre is out of that arm configuration's reach).
        At a wrist singularity (theta5 = 0 or 180 deg) theta4 is set to 0
        in the model and theta6 takes the whole rotation, so every row
        still reproduces the pose.

    Notes
    -----
    Same equations and evaluation order as the straightforward version
    (kept in tests/core/test_opw_inverse_equivalence.py as the reference),
    arranged for throughput (issue #4: over a million poses per second, all
    branches, on one core):

    * poses are solved in blocks of :data:`BLOCK_POSES`
      (:func:`_inverse_block`): numpy makes one pass over memory per
      operation, and a block's arrays stay in cache through those passes;
    * each distinct value is computed once (theta1 has two values per pose,
      theta2 and theta3 four, the wrist angles eight) on contiguous
      ``(..., n)`` rows, and converted to degrees in one sweep;
    * out-of-reach branches are carried as finite numbers and set to NaN
      only when written out (numpy's SIMD sin/cos/arctan2 are several
      times slower on NaN);
    * the result is written by one transposing copy.
    """
    T = np.asarray(T_r_f, dtype=float)
    single = T.ndim == 2
    T = T.reshape((-1, 4, 4))
    k = _inverse_constants(params)
    n = T.shape[0]
    q_deg = np.empty((n, 8, 6))
    if opw_kernel.available():
        opw_kernel.inverse_into(k.kernel, np.ascontiguousarray(T), q_deg)
    else:
        _inverse_numpy(k, T, q_deg)
    return q_deg[0] if single else q_deg


def inverse_numpy(params, T_r_f):
    """:func:`inverse` computed with numpy only (the reference for the compiled kernel)."""
    T = np.asarray(T_r_f, dtype=float)
    single = T.ndim == 2
    T = T.reshape((-1, 4, 4))
    q_deg = np.empty((T.shape[0], 8, 6))
    _inverse_numpy(_inverse_constants(params), T, q_deg)
    return q_deg[0] if single else q_deg


def _inverse_numpy(k, T, q_deg):
    n = T.shape[0]
    # NaN is how a missing branch shows (sqrt and arccos of out-of-reach
    # values): not worth a warning.
    with np.errstate(invalid="ignore"):
        for start in range(0, n, BLOCK_POSES):
            stop = min(start + BLOCK_POSES, n)
            _inverse_block(k, T[start:stop], q_deg[start:stop])


#: Poses per block of :func:`inverse`.  A block makes a hundred-odd numpy
#: calls on arrays of about 200 x n float64 in all (~13 MB, held in cache):
#: smaller blocks pay numpy's per-call overhead more often, bigger ones
#: fall out of the cache.  Measured on the project's 2-core Xeon test machine
#: (2 MB L2 per core, large L3), 100k poses: 8192 ~2.2 M poses/s, 2048 ~1.9 M,
#: 512 ~1.5 M, 32768 ~1.2-1.6 M, one block for all ~1.1 M.
BLOCK_POSES = 8192


class _InverseConstants:
    """What :func:`inverse` derives from the parameters, computed once per robot.

    Scalars are the expressions the equations use, evaluated in the same
    order as before the optimisation, so the same numbers come out;
    ``offsets`` and ``scale_rows`` (34, 1) map the 34 rows of model
    angles that :func:`_inverse_block` keeps per pose to controller degrees:
    ``(theta + offset) * sign * 180 / pi``.
    """

    def __init__(self, params):
        p = params
        self.a1, self.b, self.c1, self.c2, self.c4 = p.a1, p.b, p.c1, p.c2, p.c4
        self.b_sq = p.b * p.b
        self.two_a1 = 2.0 * p.a1
        kappa_sq = p.a2 * p.a2 + p.c3 * p.c3
        self.kappa = np.sqrt(kappa_sq)
        self.c2_sq = p.c2 * p.c2
        self.kappa_sq = kappa_sq
        self.elbow_denominator = 2.0 * p.c2 * self.kappa
        self.psi3 = np.arctan2(p.a2, p.c3)
        offsets_rad, signs = _params_arrays(p)
        # Rows of the model-angle block: theta1 x 2 shoulders, theta2 and
        # theta3 x 4 arm branches, theta4..6 x 8 (4 arm branches x 2 wrists).
        joint = np.repeat(np.arange(6), (2, 4, 4, 8, 8, 8))
        # (rows, offset) of the joints with an offset: adding 0.0 to the
        # others would change nothing but -0.0 into 0.0, which the wrap
        # below turns into 0.0 anyway.
        first = np.concatenate([[0], np.cumsum((2, 4, 4, 8, 8, 8))])
        self.offsets = [(slice(first[j], first[j + 1]), offsets_rad[j])
                        for j in range(6) if offsets_rad[j] != 0.0]
        # np.degrees(x) is x * (180 / pi) exactly, and signs are +-1, so one
        # product gives the same bits as "* sign" and then np.degrees.
        self.scale_rows = (signs * (180.0 / np.pi))[joint][:, None]
        self.kernel = opw_kernel.constants_vector(self, ACOS_TOLERANCE, WRIST_SINGULAR_SIN,
                                                  ANGLE_TOLERANCE_DEG)


@functools.lru_cache(maxsize=64)
def _cached_inverse_constants(params):
    return _InverseConstants(params)


def _inverse_constants(params):
    """:class:`_InverseConstants` of `params`, cached per parameter set
    (``OPWParameters`` is a frozen dataclass, hence hashable; any other
    object with the same attributes is served uncached)."""
    try:
        return _cached_inverse_constants(params)
    except TypeError:  # unhashable
        return _InverseConstants(params)


def _inverse_block(k, T, out):
    """Solve one block of poses into `out` (the work of :func:`inverse`).

    Every array below is laid out with the pose index last and contiguous,
    so each numpy call is one sweep over a few (n,) rows:

    * ``(2, n)``: per shoulder (theta1_i front, theta1_ii back);
    * ``(2, 2, n)``: per arm branch, shoulder then elbow, i.e. rows 0-3 of
      the result in opw_kinematics' order;
    * ``(2, 2, 2, n)`` (or ``(8, n)``): per result row, wrist (theta5 >= 0,
      flipped) then arm branch.

    Parameters
    ----------
    k : _InverseConstants
    T : ndarray, shape (n, 4, 4), any strides
        Flange poses, mm.
    out : ndarray, shape (n, 8, 6), C-contiguous
        Filled with the joint values, degrees (NaN rows where no branch).
    """
    n = T.shape[0]
    # [R | p] with the pose index last: M[i, j] is T[:, i, j], contiguous.
    M = np.empty((3, 4, n))
    np.copyto(M, T[:, :3, :].transpose(1, 2, 0))
    R = M[:, :3]                                   # (3, 3, n)

    # The model angles of all branches, one row each (see _InverseConstants):
    # theta1 (2 rows), theta2 (4), theta3 (4), theta4 (8), theta5 (8), theta6 (8).
    Q = np.empty((34, n))
    theta1 = Q[0:2]                                # (2, n)
    theta2 = Q[2:6].reshape(2, 2, n)
    theta3 = Q[6:10].reshape(2, 2, n)
    theta4 = Q[10:18].reshape(2, 2, 2, n)          # [wrist, shoulder, elbow]
    theta5 = Q[18:26].reshape(2, 2, 2, n)
    theta6 = Q[26:34].reshape(2, 2, 2, n)

    # Wrist centre, the shoulder angle and the arm's planar distances.
    centre = M[:, 3] - k.c4 * M[:, 2]              # (3, n)
    cx, cy, cz = centre
    nx1 = np.sqrt(cx * cx + cy * cy - k.b_sq)
    nx1 -= k.a1
    phi = np.arctan2(cy, cx)
    if k.b == 0.0:
        # beta = atan2(0, nx1 + a1) is 0 (nx1 + a1 >= 0), or NaN where nx1
        # is; such rows come out NaN through the elbow anyway.
        theta1[0] = phi
        np.subtract(phi, np.pi, out=theta1[1])
    else:
        beta = np.arctan2(k.b, nx1 + k.a1)
        np.subtract(phi, beta, out=theta1[0])
        np.add(phi, beta, out=theta1[1])
        theta1[1] -= np.pi

    # Horizontal distance from axis 2 to the wrist centre, per shoulder:
    # nx1 in front of the base, nx1 + 2 a1 behind it.
    dz = cz - k.c1
    planar = np.empty((2, n))
    planar[0] = nx1
    np.add(nx1, k.two_a1, out=planar[1])
    s_sq = planar * planar
    s_sq += dz * dz
    s_sq -= k.c2_sq
    s_sq -= k.kappa_sq
    s_sq /= k.elbow_denominator                    # cos(elbow), (2, n)
    # safe_arccos, split in two: the arm branches out of reach are recorded
    # in `unreachable` (NaN there, else 0) and their elbow is computed from
    # the clipped cosine like the others.  The finite garbage they carry is
    # overwritten by NaN at the end (nan_row); meanwhile every sin, cos and
    # arctan2 below sees finite numbers only, which is several times faster
    # than NaN (numpy's SIMD routines leave the vector path on NaN).
    unreachable = np.where(np.abs(s_sq) <= 1.0 + ACOS_TOLERANCE, 0.0, np.nan)
    np.minimum(s_sq, 1.0, out=s_sq)
    np.maximum(s_sq, -1.0, out=s_sq)
    elbow = np.empty((2, 2, n))
    np.arccos(s_sq, out=elbow[:, 0])
    np.negative(elbow[:, 0], out=elbow[:, 1])
    np.subtract(elbow, k.psi3, out=theta3)

    # theta3 = elbow - psi3 as in the paper; theta2 then aims the elbow
    # triangle at the wrist centre, atan2(reach, dz) - atan2(kappa sin(elbow),
    # c2 + kappa cos(elbow)), which equals the paper's atan2(reach, dz) -+ acos(...)
    # but stays consistent with theta3 where the arm is stretched (acos is
    # ill-conditioned there).  The reach is nx1 in front, -(nx1 + 2 a1) behind.
    planar[1] *= -1.0
    aim = np.arctan2(planar, dz)                   # (2, n)
    y = np.sin(elbow)
    y *= k.kappa
    x = np.cos(elbow)
    x *= k.kappa
    x += k.c2                                      # c2 + kappa cos(elbow)
    np.arctan2(y, x, out=theta2)
    np.subtract(aim[:, None], theta2, out=theta2)

    # Wrist: R_ce = R_0c^T R = Rz(theta4) Ry(theta5) Rz(theta6), with
    # R_0c = Rz(theta1) Ry(theta2 + theta3).  Rows of Rz(theta1)^T R first
    # (theta1 takes only two values): u = its row 0, v = its row 1 (= R_ce row 1).
    sin1 = np.sin(theta1)[:, None]                 # (2, 1, n)
    cos1 = np.cos(theta1)[:, None]
    u = cos1 * R[0]                                # (2, 3, n)
    u += sin1 * R[1]
    v = -sin1 * R[0]
    v += cos1 * R[1]
    theta23 = theta2 + theta3
    s23 = np.sin(theta23)[:, :, None]              # (2, 2, 1, n)
    c23 = np.cos(theta23)[:, :, None]
    ce0 = c23 * u[:, None]                         # R_ce row 0, (2, 2, 3, n)
    ce0 -= s23 * R[2]
    ce1 = v[:, None]                               # R_ce row 1, (2, 1, 3, n)
    ce22 = s23[:, :, 0] * u[:, None, 2]            # R_ce[2, 2] = cos(theta5), (2, 2, n)
    ce22 += c23[:, :, 0] * R[2, 2]
    ce0x, ce0y, ce0z = ce0[:, :, 0], ce0[:, :, 1], ce0[:, :, 2]
    ce1x, ce1y, ce1z = ce1[:, :, 0], ce1[:, :, 1], ce1[:, :, 2]

    # sin(theta5) = hypot(ce0z, ce1z); comparing its square with the square
    # of the threshold saves numpy's hypot (scalar code, ~10x a product).
    # The two tests differ only within rounding of the threshold itself.
    singular = ce0z * ce0z
    singular += ce1z * ce1z
    singular = singular < WRIST_SINGULAR_SIN ** 2
    t4, t5, t6 = theta4[0], theta5[0], theta6[0]   # (2, 2, n) views
    np.arctan2(ce1z, ce0z, out=t4)
    np.copyto(t4, 0.0, where=singular)
    # With theta4 fixed, Rz(-theta4) R_ce = Ry(theta5) Rz(theta6) gives theta5 and
    # theta6 consistently even where sin(theta5) vanishes:
    # its row 0 ends in sin(theta5), its row 1 is (sin(theta6), cos(theta6), 0).
    sin4, cos4 = np.sin(t4), np.cos(t4)
    a = cos4 * ce0z
    a += sin4 * ce1z
    np.arctan2(a, ce22, out=t5)
    np.negative(sin4, out=sin4)                    # -sin(theta4)
    a = sin4 * ce0x
    a += cos4 * ce1x
    b = sin4 * ce0y
    b += cos4 * ce1y
    np.arctan2(a, b, out=t6)

    # A row is NaN where its arm branch is out of reach or any of its values
    # is NaN (only with NaN or inf in the input).  Every model angle is finite
    # or NaN (arctan2, arccos and differences of them), so nan_row is +0.0 or
    # NaN per arm branch; the flipped wrist has the same NaN pattern.  It is
    # added to each value as it is written out: adding +0.0 leaves every
    # value's bits unchanged (a wrapped value is never -0.0).
    nan_row = theta2 + theta1[:, None]             # (2, 2, n)
    nan_row += unreachable[:, None]
    nan_row += theta3
    nan_row += t4
    nan_row += t5
    nan_row += t6
    nan_row -= nan_row

    # The flipped wrist: theta4 + 180, -theta5, theta6 - 180.
    np.add(t4, np.pi, out=theta4[1])
    np.negative(t5, out=theta5[1])
    np.subtract(t6, np.pi, out=theta6[1])

    # To controller degrees, all 34 rows at once, then wrapped into (-180, 180]
    # with wrap_deg's operations (so the same bits, also for values at +-180, which
    # come out +180 whichever side of it rounding put them).
    for rows, offset in k.offsets:
        Q[rows] += offset
    Q *= k.scale_rows
    turns = Q - (180.0 + ANGLE_TOLERANCE_DEG)
    turns /= 360.0
    np.ceil(turns, out=turns)
    turns *= 360.0
    Q -= turns

    # The result with the pose index last, P[wrist, shoulder, elbow, joint],
    # i.e. out[pose, 4 wrist + 2 shoulder + elbow, joint] transposed, then
    # one 2-D transposing copy into out (about twice as fast as writing each
    # joint's strided column of out directly).
    P = np.empty((2, 2, 2, 6, n))
    np.add(theta1[:, None], nan_row, out=P[..., 0, :])
    np.add(theta2, nan_row, out=P[..., 1, :])
    np.add(theta3, nan_row, out=P[..., 2, :])
    wrist = Q[10:34].reshape(3, 2, 2, 2, n).transpose(1, 2, 3, 0, 4)   # (2, 2, 2, 3, n)
    np.add(wrist, nan_row[:, :, None], out=P[..., 3:, :])
    np.copyto(out.reshape(n, 48), P.reshape(48, n).T)
