"""Forward kinematics of robots defined like FreeCAD's Robot workbench (DH rows).

FreeCAD's ``Robot::Robot6Axis`` (``src/Mod/Robot/App/Robot6Axis.cpp``) reads a
CSV file with one row per axis -- ``a, alpha, d, theta, rotDir, maxAngle,
minAngle, AxisVelocity`` in mm and degrees -- and builds a KDL chain of six
segments ``Segment(Joint(RotZ), Frame::DH(a, alpha, d, theta))``.  Setting
``AxisN`` to ``q`` degrees sets the KDL joint to ``rotDir * q``.  Segment i
therefore contributes::

    Rz(rotDir_i * q_i) @ Rz(theta_i) @ Tz(d_i) @ Tx(a_i) @ Rx(alpha_i)

(``KDL::Frame::DH`` is the standard Denavit-Hartenberg frame), and the TCP is
the product of the six, in the robot's base frame {R}.  This module computes
exactly that, vectorised, without FreeCAD.

Pure numpy: never imports FreeCAD.
"""

import numpy as np

from ..catalog.catalog import DHRow


def rows_from_csv(text):
    """Parse a FreeCAD Robot workbench kinematic CSV.

    Parameters
    ----------
    text : str
        File contents: one header line, then six lines
        ``a, alpha, d, theta, rotDir, maxAngle, minAngle, AxisVelocity``
        (mm, degrees, degrees per second).

    Returns
    -------
    rows : tuple of 6 DHRow
    """
    lines = [line for line in text.splitlines()[1:] if line.strip()]
    rows = []
    for line in lines[:6]:
        a, alpha, d, theta, rot_dir, max_deg, min_deg, speed = (
            float(v) for v in line.split(",")[:8])
        rows.append(DHRow(a, alpha, d, theta, int(rot_dir), max_deg, min_deg, speed))
    if len(rows) != 6:
        raise ValueError("a FreeCAD robot CSV needs 6 axis rows, got %d" % len(rows))
    return tuple(rows)


def dh_transforms(a_mm, alpha_rad, d_mm, theta_rad):
    """Standard DH frames ``Rz(theta) Tz(d) Tx(a) Rx(alpha)`` (``KDL::Frame::DH``).

    Parameters
    ----------
    a_mm, alpha_rad, d_mm : float or array_like, broadcastable with `theta_rad`
    theta_rad : array_like, shape (N,)
        Joint rotation about the previous z axis, radians.

    Returns
    -------
    T : ndarray, shape (N, 4, 4)
        Homogeneous transforms, mm.
    """
    theta_rad = np.asarray(theta_rad, dtype=float)
    ct, st = np.cos(theta_rad), np.sin(theta_rad)
    ca, sa = np.cos(alpha_rad), np.sin(alpha_rad)
    T = np.zeros(theta_rad.shape + (4, 4))
    T[..., 0, 0] = ct
    T[..., 0, 1] = -st * ca
    T[..., 0, 2] = st * sa
    T[..., 0, 3] = a_mm * ct
    T[..., 1, 0] = st
    T[..., 1, 1] = ct * ca
    T[..., 1, 2] = -ct * sa
    T[..., 1, 3] = a_mm * st
    T[..., 2, 1] = sa
    T[..., 2, 2] = ca
    T[..., 2, 3] = d_mm
    T[..., 3, 3] = 1.0
    return T


def forward(rows, q_deg):
    """Flange pose of a FreeCAD Robot workbench robot, as ``Robot6Axis`` computes its TCP.

    Parameters
    ----------
    rows : sequence of 6 DHRow
        The robot's CSV rows (``a, alpha, d, theta, rot_dir``; mm, degrees).
    q_deg : array_like, shape (N, 6) or (6,)
        Axis values ``Axis1..Axis6`` in degrees, as typed into FreeCAD.

    Returns
    -------
    T_r_f : ndarray, shape (N, 4, 4) or (4, 4)
        Flange (FreeCAD's ``Tcp``) in the robot base frame {R}, mm.
    """
    q_deg = np.asarray(q_deg, dtype=float)
    single = q_deg.ndim == 1
    q_deg = np.atleast_2d(q_deg)
    if q_deg.shape[-1] != 6:
        raise ValueError("q_deg must have shape (N, 6), got %s" % (q_deg.shape,))
    T_r_f = np.broadcast_to(np.eye(4), (q_deg.shape[0], 4, 4)).copy()
    for i, row in enumerate(rows):
        joint_rad = np.radians(row.rot_dir * q_deg[:, i] + row.theta)
        T_r_f = T_r_f @ dh_transforms(row.a, np.radians(row.alpha), row.d, joint_rad)
    return T_r_f[0] if single else T_r_f


def opw_from_dh(rows, tol_mm=1e-9):
    """The OPW model of a FreeCAD Robot workbench robot, so its IK is closed form.

    FreeCAD's KUKA files (``kr_16.csv``, ``kr_125.csv``, ...) describe
    ortho-parallel arms with a spherical wrist in DH form.  The OPW lengths
    are read off the rows (``a1 = a_1``, ``c1 = d_1``, ``c2 = a_2``,
    ``|a2| = a_3``, ``c3 = |d_4|``, ``c4 = |d_6|``, ``|b| = d_2 + d_3``); the
    signs of ``a2`` and ``b`` and every joint's sign and offset (a multiple
    of 90 degrees) are then found by comparing the two forward kinematics:
    first the wrist centre (joints 1-3), then the flange orientation
    (joints 4-6).  The result is checked on random joint values.

    Parameters
    ----------
    rows : sequence of 6 DHRow
    tol_mm : float
        Largest flange position or (x 1 m) orientation difference accepted.

    Returns
    -------
    OPWParameters
        With ``forward(rows, q) == opw.forward(result, q)`` for every q.

    Raises
    ------
    ValueError
        When the chain is not an OPW robot with offsets in steps of 90 degrees.
    """
    from itertools import product

    from . import opw
    from ..catalog.catalog import OPWParameters

    rows = tuple(rows)
    rng = np.random.default_rng(0)
    q_deg = rng.uniform(-180.0, 180.0, (16, 6))
    q_deg[0] = 0.0
    T_dh = forward(rows, q_deg)
    centre_dh = forward(rows[:4], q_deg)[:, :3, 3]  # a_4 = d_5 = 0: frame 4 is the wrist centre
    lengths = dict(a1=rows[0].a, c1=rows[0].d, c2=rows[1].a, c3=abs(rows[3].d), c4=abs(rows[5].d))
    b_abs = rows[1].d + rows[2].d
    steps = (0.0, 90.0, -90.0, 180.0)

    def error(params, centre_only):
        T = opw.forward(params, q_deg)
        if centre_only:
            return np.abs(T[:, :3, 3] - params.c4 * T[:, :3, 2] - centre_dh).max()
        return max(np.abs(T[:, :3, 3] - T_dh[:, :3, 3]).max(),
                   1000.0 * np.abs(T[:, :3, :3] - T_dh[:, :3, :3]).max())

    for a2, b, s1, s2, s3, o1, o2, o3 in product(
            (-rows[2].a, rows[2].a), (b_abs, -b_abs), (1, -1), (1, -1), (1, -1), steps, steps, steps):
        arm = OPWParameters(a2=a2, b=b, offsets_deg=(o1, o2, o3, 0, 0, 0),
                            signs=(s1, s2, s3, 1, 1, 1), **lengths)
        if error(arm, centre_only=True) > tol_mm:
            continue
        for s4, s5, s6, o4, o5, o6 in product((1, -1), (1, -1), (1, -1), steps, steps, steps):
            params = OPWParameters(a2=a2, b=b, offsets_deg=(o1, o2, o3, o4, o5, o6),
                                   signs=(s1, s2, s3, s4, s5, s6), **lengths)
            if error(params, centre_only=False) <= tol_mm:
                return params
    raise ValueError("these DH rows are not an ortho-parallel robot with a spherical wrist "
                     "(or their offsets are not multiples of 90 degrees)")
