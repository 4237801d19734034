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

Everything is vectorised over poses: no Python loop runs per pose.
Pure numpy: never imports FreeCAD.
"""

import numpy as np

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


def wrap_deg(q_deg):
    """Angles wrapped into (-180, 180] degrees (NaN stays NaN).

    Parameters
    ----------
    q_deg : array_like, any shape

    Returns
    -------
    ndarray, same shape
    """
    q_deg = np.asarray(q_deg, dtype=float)
    return q_deg - 360.0 * np.ceil((q_deg - 180.0) / 360.0)


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
    """
    T = np.asarray(T_r_f, dtype=float)
    single = T.ndim == 2
    T = T.reshape((-1, 4, 4))
    p = params
    offsets_rad, signs = _params_arrays(params)
    R = T[:, :3, :3]

    # Wrist centre, the shoulder angle and the arm's planar distances.
    centre = T[:, :3, 3] - p.c4 * R[:, :, 2]
    cx, cy, cz = centre[:, 0], centre[:, 1], centre[:, 2]
    with np.errstate(invalid="ignore"):
        nx1 = np.sqrt(cx * cx + cy * cy - p.b * p.b) - p.a1
    phi = np.arctan2(cy, cx)
    beta = np.arctan2(p.b, nx1 + p.a1)
    theta1_i = phi - beta
    theta1_ii = phi + beta - np.pi

    dz = cz - p.c1
    s1_sq = nx1 * nx1 + dz * dz
    nx2 = nx1 + 2.0 * p.a1
    s2_sq = nx2 * nx2 + dz * dz
    kappa_sq = p.a2 * p.a2 + p.c3 * p.c3
    c2_sq = p.c2 * p.c2
    kappa = np.sqrt(kappa_sq)
    with np.errstate(invalid="ignore"):
        elbow_front = safe_arccos((s1_sq - c2_sq - kappa_sq) / (2.0 * p.c2 * kappa))
        elbow_back = safe_arccos((s2_sq - c2_sq - kappa_sq) / (2.0 * p.c2 * kappa))
    psi3 = np.arctan2(p.a2, p.c3)

    # The four arm configurations, (N, 4) each.  theta3 = elbow - psi3 as in the
    # paper; theta2 then aims the elbow triangle at the wrist centre,
    # atan2(reach, dz) - atan2(kappa sin(elbow), c2 + kappa cos(elbow)), which equals
    # the paper's atan2(reach, dz) -+ acos(...) but stays consistent with theta3 where
    # the arm is stretched (acos is ill-conditioned there).  The horizontal reach
    # from axis 2 is nx1 in front of the base and -(nx1 + 2 a1) behind it.
    theta1 = np.stack([theta1_i, theta1_i, theta1_ii, theta1_ii], axis=1)
    elbow = np.stack([elbow_front, -elbow_front, elbow_back, -elbow_back], axis=1)
    theta3 = elbow - psi3
    reach = np.stack([nx1, nx1, -nx2, -nx2], axis=1)
    theta2 = (np.arctan2(reach, dz[:, None])
              - np.arctan2(kappa * np.sin(elbow), p.c2 + kappa * np.cos(elbow)))

    # Wrist: R_ce = R_0c^T R = Rz(theta4) Ry(theta5) Rz(theta6), R_0c = Rz(theta1) Ry(theta2 + theta3).
    # Rows of Rz(theta1)^T R first (theta1 takes only two values), then Ry(theta2 + theta3)^T.
    sin1 = np.sin(theta1[:, ::2])[..., None]  # (N, 2, 1)
    cos1 = np.cos(theta1[:, ::2])[..., None]
    u = np.repeat(cos1 * R[:, None, 0, :] + sin1 * R[:, None, 1, :], 2, axis=1)   # (N, 4, 3)
    v = np.repeat(-sin1 * R[:, None, 0, :] + cos1 * R[:, None, 1, :], 2, axis=1)
    s23, c23 = np.sin(theta2 + theta3), np.cos(theta2 + theta3)  # (N, 4)
    ce0 = c23[..., None] * u - s23[..., None] * R[:, None, 2, :]  # row 0 of R_ce
    ce1 = v                                                        # row 1
    ce22 = s23 * u[..., 2] + c23 * R[:, None, 2, 2]               # R_ce[2, 2] = cos(theta5)

    sin5 = np.hypot(ce0[..., 2], ce1[..., 2])
    theta4 = np.where(sin5 < WRIST_SINGULAR_SIN, 0.0, np.arctan2(ce1[..., 2], ce0[..., 2]))
    # With theta4 fixed, Rz(-theta4) R_ce = Ry(theta5) Rz(theta6) gives theta5 and
    # theta6 consistently even where sin(theta5) vanishes:
    # its row 0 ends in sin(theta5), its row 1 is (sin(theta6), cos(theta6), 0).
    sin4, cos4 = np.sin(theta4), np.cos(theta4)
    theta5 = np.arctan2(cos4 * ce0[..., 2] + sin4 * ce1[..., 2], ce22)
    theta6 = np.arctan2(-sin4 * ce0[..., 0] + cos4 * ce1[..., 0],
                        -sin4 * ce0[..., 1] + cos4 * ce1[..., 1])

    model = np.empty((T.shape[0], 8, 6))
    for wrist, (t4, t5, t6) in enumerate(((theta4, theta5, theta6),
                                          (theta4 + np.pi, -theta5, theta6 - np.pi))):
        rows = slice(4 * wrist, 4 * wrist + 4)
        model[:, rows, 0] = theta1
        model[:, rows, 1] = theta2
        model[:, rows, 2] = theta3
        model[:, rows, 3] = t4
        model[:, rows, 4] = t5
        model[:, rows, 5] = t6
    q_deg = wrap_deg(np.degrees((model + offsets_rad) * signs))
    q_deg[np.isnan(q_deg).any(axis=-1)] = np.nan
    return q_deg[0] if single else q_deg
