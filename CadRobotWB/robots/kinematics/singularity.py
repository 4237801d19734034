"""How far a 6R arm's joints are from a singularity, from its Jacobian.

On an OPW or UR arm the Jacobian's determinant factors into the wrist, elbow and
shoulder terms, so :class:`.arm_families.ArmGeometry` measures each from its own
angle or distance. On an offset wrist (FANUC CRX, Yaskawa HC10, ABB CRB 15000) it
does not: on the CRX-10iA/L, ``det J`` is zero at J5 = 2.5 deg for one set of J2,
J3, J4 and at J5 = 24 deg for another, and J1 and J6 never matter. There the
distance is measured on the determinant itself:

    d = |det J| / |grad_q det J|

is the distance in joint space (rad, shown in deg) from q to where ``det J`` reaches
zero, to first order: exact where the determinant is linear along the way (as near a
simple singularity), half the distance next to a double one. On an OPW arm it gives
tan(theta5) next to the wrist singularity, the elbow's angle from stretched next to
the elbow's (the tests compare both).

The Jacobian is the spatial one (twists at the base origin, mm scaled to m so both
halves weigh alike); its determinant differs from that of the geometric Jacobian at
the flange by a unimodular change of reference point only, and ``d`` is unchanged by
scaling rows. The gradient is exact: column j's twist depends on the joints before
it, ``d xi_j / d q_i = [xi_i, xi_j]`` (the Lie bracket) for i < j, and
``d det J = tr(adj(J) dJ)``. Where numba is installed the distance runs compiled
(:mod:`.singularity_kernel`: 1.0 us per joint vector against 28 us in numpy, measured
with the machine shared).

Pure numpy: never imports FreeCAD.
"""

import numpy as np

from . import poe, singularity_kernel


def spatial_twists(params, q_rad):
    """Each axis's unit twist in the base frame at joints `q_rad`.

    Parameters
    ----------
    params : poe.ChainParameters
    q_rad : ndarray, shape (N, 6)

    Returns
    -------
    v : ndarray, shape (N, 6, 3)
        ``o_i x h_i`` with ``o_i`` a point of axis i, m (mm / 1000).
    w : ndarray, shape (N, 6, 3)
        Axis i's unit direction ``h_i``.
    """
    R = poe.rotations(params, q_rad)                                  # R_0i, i = 1..6
    n = R.shape[0]
    R_prev = np.concatenate([np.broadcast_to(np.eye(3), (n, 1, 3, 3)), R[:, :5]], axis=1)
    w = np.einsum("nkij,kj->nki", R_prev, params.H)
    origins = np.cumsum(np.einsum("nkij,kj->nki", R_prev, params.P[:6]), axis=1) / 1000.0
    return np.cross(origins, w), w


def distance_deg(params, q_deg):
    """First-order joint-space distance from each joint vector to a singularity, deg.

    Parameters
    ----------
    params : poe.ChainParameters
    q_deg : array_like, shape (..., 6)
        Joints, degrees; rows with a NaN give NaN.

    Returns
    -------
    ndarray, shape (...)
        ``|det J| / |grad det J|`` in degrees; 0 where ``det J`` is exactly 0.
    """
    q_deg = np.asarray(q_deg, dtype=float)
    shape = q_deg.shape[:-1]
    q = np.radians(q_deg.reshape(-1, 6))
    nan = np.isnan(q).any(axis=1)
    d = np.full(len(q), np.nan)
    if singularity_kernel.available():
        d[~nan] = singularity_kernel.distances(params.H, params.P, q[~nan])
    else:
        d[~nan] = distance_deg_numpy(params, q[~nan])
    return d.reshape(shape)


def distance_deg_numpy(params, q_rad):
    """:func:`distance_deg` in numpy (the reference of the compiled kernel).

    ``grad det J / det J = grad log|det J|``, whose i-th part is
    ``tr(J^-1 dJ/dq_i) = sum_{j > i} (J^-1)[j] . [xi_i, xi_j]``: the distance is
    ``1 / |that|``.

    Parameters
    ----------
    params : poe.ChainParameters
    q_rad : ndarray, shape (M, 6)
        No NaN.

    Returns
    -------
    ndarray, shape (M,)
        deg.
    """
    v, w = spatial_twists(params, q_rad)
    J = np.concatenate([v, w], axis=2).transpose(0, 2, 1)             # (M, 6, 6): columns
    singular = np.linalg.det(J) == 0.0
    inv = np.linalg.inv(np.where(singular[:, None, None], np.eye(6), J))
    # [xi_i, xi_j] = (w_i x v_j - w_j x v_i, w_i x w_j): shape (M, i, j, 3) each half.
    bracket_v = np.cross(w[:, :, None], v[:, None, :]) - np.cross(w[:, None, :], v[:, :, None])
    bracket_w = np.cross(w[:, :, None], w[:, None, :])
    bracket = np.concatenate([bracket_v, bracket_w], axis=3)         # (M, 6, 6, 6)
    later = np.triu(np.ones((6, 6)), k=1)                              # j > i
    log_gradient = np.einsum("ij,njk,nijk->ni", later, inv, bracket)
    with np.errstate(divide="ignore"):
        d = np.degrees(1.0 / np.linalg.norm(log_gradient, axis=1))
    return np.where(singular, 0.0, d)
