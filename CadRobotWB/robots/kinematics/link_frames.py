"""Link frames of the catalog robots: the pose of each of the seven bodies.

A robot is drawn and collision-checked as seven rigid bodies: the fixed base
(link 0) and links 1 to 6, link i being the body that joint i moves.
:func:`link_frames` gives, for joint values, the pose in the robot base
frame {R} of a frame attached to each body, ``(N, 7, 4, 4)``.  Frame 0 is
{R} itself and frame 6 is the flange {F}: ``link_frames(...)[:, 6]`` equals
``model.fk(q)`` (the fixed offset from link 6 to the flange is the
identity).  The solids placed in these frames are in
:mod:`CadRobotWB.robots.checks.links`.

Frame conventions per kind of model (``model.kind``):

``opw``
    A chain built from the OPW parameters, in the conventions of
    :func:`.opw.forward` (model angles ``theta = q * sign - offset``)::

        F1 = Rz(theta1)                                  J1 = z of F1, at the base origin
        F2 = F1 Trans(a1, b, c1) Ry(theta2)              J2 = y of F2, origin on J2
        F3 = F2 Trans(0, 0, c2) Ry(theta3)               J3 = y of F3, origin on J3 (elbow)
        F4 = F3 Trans(a2, 0, c3) Rz(theta4)              J4 = z of F4, origin at the wrist centre
        F5 = F4 Ry(theta5)                               J5 = y of F5, same origin
        F6 = F5 Rz(theta6) Trans(0, 0, c4)               J6 = z of F6, origin on the flange

``dh+opw`` (FreeCAD Robot workbench robots, e.g. ``KUKA_KR16``)
    The standard DH frames of the CSV rows, exactly as :func:`.dh.forward`
    multiplies them: frame i is the product of rows 1..i.
``ur``
    UR's standard DH frames, exactly as :func:`.ur.forward` multiplies them.
``chain``
    Frame i has the rotation ``R_0i`` of :func:`.poe.rotations` and its origin
    on axis i (:func:`.chain_geometry.link_frames`).

Lengths in mm, angles in degrees at the interface.  Pure numpy: never
imports FreeCAD.
"""

import numpy as np

from ..catalog import catalog
from . import chain_geometry, dh, models, ur

#: Names of the seven bodies, in the order of :func:`link_frames`.
LINK_NAMES = ("base", "link1", "link2", "link3", "link4", "link5", "link6")


# ------------------------------------------------------------------ the robot model

def robot_model(robot):
    """The kinematic model of `robot`.

    Parameters
    ----------
    robot : str, RobotSpec or RobotModel
        A catalog name, a catalog entry (also one not in the catalog) or a
        model from :func:`.models.model`.

    Returns
    -------
    RobotModel
    """
    if isinstance(robot, models.RobotModel):
        return robot
    if isinstance(robot, str):
        return models.model(robot)
    if isinstance(robot, catalog.RobotSpec):
        return models.as_model(robot)
    raise TypeError("expected a robot name, RobotSpec or RobotModel, got %r" % (robot,))


# ------------------------------------------------------------------ link frames

def _rot_z(theta):
    """(N, 4, 4) rotations about z by theta (N,) radians."""
    c, s = np.cos(theta), np.sin(theta)
    T = np.zeros(theta.shape + (4, 4))
    T[..., 0, 0] = c
    T[..., 0, 1] = -s
    T[..., 1, 0] = s
    T[..., 1, 1] = c
    T[..., 2, 2] = 1.0
    T[..., 3, 3] = 1.0
    return T


def _rot_y(theta):
    """(N, 4, 4) rotations about y by theta (N,) radians."""
    c, s = np.cos(theta), np.sin(theta)
    T = np.zeros(theta.shape + (4, 4))
    T[..., 0, 0] = c
    T[..., 0, 2] = s
    T[..., 1, 1] = 1.0
    T[..., 2, 0] = -s
    T[..., 2, 2] = c
    T[..., 3, 3] = 1.0
    return T


def _translation(x, y, z):
    """(4, 4) translation by (x, y, z) mm."""
    T = np.eye(4)
    T[:3, 3] = (x, y, z)
    return T


def opw_link_frames(params, q_deg):
    """Link frames of the OPW chain (see the module docstring).

    Parameters
    ----------
    params : OPWParameters
        Lengths in mm, ``offsets_deg`` and ``signs``.
    q_deg : array_like, shape (N, 6)
        Joint values in the controller's convention, degrees.

    Returns
    -------
    T_r_link : ndarray, shape (N, 7, 4, 4)
        Base frame, F1..F6 in {R}, mm; F6 is the flange of :func:`.opw.forward`.
    """
    p = params
    q = (np.radians(q_deg) * np.asarray(p.signs, dtype=float)
         - np.radians(np.asarray(p.offsets_deg, dtype=float)))
    frames = np.empty((q.shape[0], 7, 4, 4))
    frames[:, 0] = np.eye(4)
    frames[:, 1] = _rot_z(q[:, 0])
    frames[:, 2] = frames[:, 1] @ _translation(p.a1, p.b, p.c1) @ _rot_y(q[:, 1])
    frames[:, 3] = frames[:, 2] @ _translation(0.0, 0.0, p.c2) @ _rot_y(q[:, 2])
    frames[:, 4] = frames[:, 3] @ _translation(p.a2, 0.0, p.c3) @ _rot_z(q[:, 3])
    frames[:, 5] = frames[:, 4] @ _rot_y(q[:, 4])
    frames[:, 6] = frames[:, 5] @ _rot_z(q[:, 5]) @ _translation(0.0, 0.0, p.c4)
    return frames


def _dh_link_frames(rows, q_deg):
    """Cumulative DH frames of FreeCAD Robot workbench rows, as dh.forward multiplies them."""
    frames = np.empty((q_deg.shape[0], 7, 4, 4))
    frames[:, 0] = np.eye(4)
    for i, row in enumerate(rows):
        joint_rad = np.radians(row.rot_dir * q_deg[:, i] + row.theta)
        frames[:, i + 1] = frames[:, i] @ dh.dh_transforms(row.a, np.radians(row.alpha), row.d,
                                                           joint_rad)
    return frames


def ur_link_frames(params, q_deg):
    """Cumulative UR DH frames, as ur.forward multiplies them."""
    q = np.radians(q_deg) * np.asarray(params.signs) - np.radians(params.offsets_deg)
    frames = np.empty((q.shape[0], 7, 4, 4))
    frames[:, 0] = np.eye(4)
    frames[:, 1] = ur._joint(params, 0, q[:, 0])
    for i in range(1, 6):
        frames[:, i + 1] = frames[:, i] @ ur._joint(params, i, q[:, i])
    return frames


def link_frames(model, q_deg):
    """Pose of the base and of each link's frame.

    Parameters
    ----------
    model : RobotModel, RobotSpec or str
        The robot (see :func:`robot_model`).
    q_deg : array_like, shape (N, 6) or (6,)
        Joint values in the controller's convention, degrees.

    Returns
    -------
    T_r_link : ndarray, shape (N, 7, 4, 4) or (7, 4, 4)
        Frame of the base (the identity) and of links 1..6 in the robot
        base frame {R}, mm.  Frame i moves with joint i; frame 6 is the
        flange, equal to ``model.fk(q_deg)``.  Conventions per kind of model
        in the module docstring.
    """
    robot = robot_model(model)
    q_deg = np.asarray(q_deg, dtype=float)
    single = q_deg.ndim == 1
    q_deg = np.atleast_2d(q_deg)
    if q_deg.shape[-1] != 6:
        raise ValueError("q_deg must have shape (N, 6), got %s" % (q_deg.shape,))
    if robot.kind == "ur":
        frames = ur_link_frames(robot.spec.ur, q_deg)
    elif robot.kind == "dh+opw":
        frames = _dh_link_frames(robot.spec.dh, q_deg)
    elif robot.kind == "opw":
        frames = opw_link_frames(robot.spec.opw, q_deg)
    elif robot.kind == "chain":
        frames = chain_geometry.link_frames(robot.params, np.radians(q_deg))
    else:
        raise ValueError("no link frames for robot kind %r" % robot.kind)
    if robot.spec.T_root_base is not None:   # frame 0 stays {R}: the base body is fixed
        frames[:, 1:] = np.array(robot.spec.T_root_base) @ frames[:, 1:]
    if robot.spec.T_flange_tip is not None:
        frames[:, 6] = frames[:, 6] @ np.array(robot.spec.T_flange_tip)
    return frames[0] if single else frames
