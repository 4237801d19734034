"""A six-revolute arm as joint axes and the vectors between them (product of exponentials).

The arms that are neither OPW nor UR (offset wrists: FANUC CRX, Yaskawa HC10, ABB
CRB 15000; oblique wrists: Yaskawa MPX3500) are described this way, in the
convention of IK-Geo (A. J. Elias, J. T. Wen, "IK-Geo: Unified robot inverse
kinematics using subproblem decomposition", Mechanism and Machine Theory 209, 2025;
arXiv:2211.05737, section 2):

* at zero joint values every axis ``i`` is the line through a point along the unit
  direction ``H[i]``, both in the base frame;
* ``P[0]`` goes from the base origin to the point of axis 1, ``P[i]`` from the point
  of axis ``i`` to that of axis ``i + 1`` (i = 1..5), ``P[6]`` from the point of
  axis 6 to the flange origin;
* with ``R_0i = rot(H[0], q1) ... rot(H[i-1], qi)``, the flange is at
  ``p = P[0] + R_01 P[1] + ... + R_06 P[6]`` with rotation ``R_06 R_6T``.

The joint values are the URDF's own (no offsets, no signs: a reversed axis is a
reversed ``H``).  Solvers of the classes take these parameters.

Pure numpy: never imports FreeCAD.
"""

from dataclasses import dataclass

import numpy as np



@dataclass(frozen=True)
class ChainParameters:
    """The kinematics of a 6R arm at zero joint values.

    Attributes
    ----------
    H : ndarray, shape (6, 3)
        Unit direction of each joint axis, in the base frame.
    P : ndarray, shape (7, 3)
        Base -> axis 1 point, axis i -> axis i+1 points, axis 6 point -> flange, mm.
    R_6T : ndarray, shape (3, 3)
        The flange's rotation in the base frame at zero joint values.
    """

    H: np.ndarray
    P: np.ndarray
    R_6T: np.ndarray


def rotations(params, q_rad):
    """``R_0i`` for i = 1..6.

    Parameters
    ----------
    params : ChainParameters
    q_rad : array_like, shape (N, 6)

    Returns
    -------
    ndarray, shape (N, 6, 3, 3)
    """
    q = np.atleast_2d(np.asarray(q_rad, dtype=float))
    R = np.empty((q.shape[0], 6, 3, 3))
    R_0i = None
    for i in range(6):
        K = _cross_matrix(params.H[i])
        s, c = np.sin(q[:, i])[:, None, None], np.cos(q[:, i])[:, None, None]
        turn = np.eye(3) + s * K + (1.0 - c) * (K @ K)          # Rodrigues
        R_0i = turn if R_0i is None else R_0i @ turn
        R[:, i] = R_0i
    return R


def _cross_matrix(h):
    """(3, 3) K with K v = h x v."""
    return np.array([[0.0, -h[2], h[1]], [h[2], 0.0, -h[0]], [-h[1], h[0], 0.0]])


def fk(params, q_rad):
    """The flange pose.

    Parameters
    ----------
    params : ChainParameters
    q_rad : array_like, shape (N, 6)
        Joint values, radians.

    Returns
    -------
    T_0T : ndarray, shape (N, 4, 4)
        mm.
    """
    R = rotations(params, q_rad)
    n = R.shape[0]
    T = np.zeros((n, 4, 4))
    T[:, :3, 3] = params.P[0] + np.einsum("nkij,kj->ni", R, params.P[1:])
    T[:, :3, :3] = R[:, 5] @ params.R_6T
    T[:, 3, 3] = 1.0
    return T


def from_chain(chain):
    """The parameters of a URDF chain, in its root link's frame.

    Parameters
    ----------
    chain : urdf.Chain

    Returns
    -------
    ChainParameters
        Its :func:`fk` equals ``urdf.chain_fk(chain, q)`` for every q (to rounding).
    """
    from ..urdf import urdf   # the URDF package imports the kinematics, not the reverse

    points, directions = urdf.joint_lines(chain)
    T_tip = urdf.chain_fk(chain, np.zeros((1, 6)))[0]
    P = np.diff(np.vstack([np.zeros(3), points, T_tip[:3, 3]]), axis=0)
    H = directions / np.linalg.norm(directions, axis=1)[:, None]
    return ChainParameters(H=H, P=P, R_6T=T_tip[:3, :3].copy())
