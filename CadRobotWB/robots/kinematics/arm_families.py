"""Configuration families of a 6-axis arm, from its joint values.

A 6-axis arm reaches most poses in up to eight ways (the rows of ``model.ik``).
A *family* is one of the eight arm configurations, numbered 0..7 by three
bits that are computed **from the joint values** (never from the IK row
index), with the robot's own geometry:

=====  ==================  ==============================================
value  name                set when
=====  ==================  ==============================================
4      shoulder back       the wrist centre is behind axis 1: its x in
                           the frame that turns with axis 1 is < 0
2      elbow down          the wrist centre is behind the lower arm (the
                           line through axes 2 and 3), i.e. the elbow
                           angle ``theta3 + atan2(a2, c3)`` of the OPW
                           model is < 0 (0 = stretched, +-180 = folded)
1      wrist flipped       the model's wrist angle ``theta5`` is < 0
=====  ==================  ==============================================

For an OPW robot (:mod:`.opw`) the eight IK rows are, in that numbering,
row ``r`` -> family ``4 * (r % 4 >= 2) + 2 * (r % 2) + (r >= 4)``
(front/back shoulder, the two elbows, the flipped wrist); with the elbow and
wrist bits the other way round (``2 * (1 - r % 2) + (r < 4)``) when the
model's base height ``c1`` is negative (its z axis points down the arm:
KUKA's and some Kawasaki arms read from their URDFs), as "elbow down" and
"wrist flipped" are the real arm's.
A Universal Robots arm (:mod:`.ur`, non-spherical wrist) gets the same
three bits from its own singularities: the wrist point (frame 5) behind the
plane of axis 1 and axis 2, ``q3 < 0``, ``q5 < 0``.

An arm that is neither (a "chain" model: offset wrists such as FANUC's
CRX-10iA/L, Yaskawa's HC10, ABB's CRB 15000, and spherical wrists off the OPW
form) gets the same three measures from the points and axes of its chain
(:mod:`.chain_families`): the wrist point is where axes 4 and 5 meet, the
wrist bit the sign of axis 5 from the straight wrist, turned the way the OPW
model's theta5 turns (on the 137 OPW arms whose URDF is in tests/data, the
three measures equal the OPW ones on 131; the other 6 are upright at zero or
have the flange behind the wrist centre in their OPW model).  On an offset wrist
these boundaries are the makers' configuration boundaries, not singularities
(:meth:`ArmGeometry.singularity_distances` measures those on the Jacobian there),
and two to four of its up to sixteen IK solutions can share a family (on 200
random poses, joints uniform in +-180 deg: CRX-10iA/L 53 poses, up to 3 in a
family; M-430iA/2P 35, 3; HC10 55, 3; CRB 15000 45, 4).  The CRX is cuspidal:
such solutions are joined without crossing a singularity, so no bit that
stays constant along singularity-free motions tells them apart; the motion
code keeps the one nearest the previous joints (:mod:`.joint_shifts`).

Family 0 (front, elbow up, wrist not flipped) is what ABB calls ``cfx = 0``
and KUKA ``S = 'B010'`` (with A5 > 0).  On OPW, UR and spherical-wrist arms the
boundaries between families are exactly the three singularities (:func:`arm_geometry`
measures the distance to each), so a move that must change family passes through one.

Pure numpy: never imports FreeCAD.
"""

from dataclasses import dataclass
from typing import Optional

import numpy as np

from . import chain_families, opw, poe, singularity, ur

#: The bits of a family number (see the module docstring).
SHOULDER_BACK = 4
ELBOW_DOWN = 2
WRIST_FLIPPED = 1


def family_name(family):
    """Plain words for a family number, e.g. ``"front, elbow up, wrist not flipped"``.

    Parameters
    ----------
    family : int
        0..7 (see the module docstring); anything else gives ``"none"``.

    Returns
    -------
    str
    """
    if family is None or not 0 <= int(family) <= 7:
        return "none"
    family = int(family)
    return "%s, %s, %s" % ("shoulder back" if family & SHOULDER_BACK else "front",
                           "elbow down" if family & ELBOW_DOWN else "elbow up",
                           "wrist flipped" if family & WRIST_FLIPPED else "wrist not flipped")


def _spec(robot):
    """The RobotSpec of a RobotModel or RobotSpec."""
    return getattr(robot, "spec", robot)


def _wrap(angle_deg):
    return opw.wrap_deg(angle_deg)


def _on_angle_grid(angle_deg):
    """Angles (deg) rounded to the grid of ``opw.ANGLE_TOLERANCE_DEG``, -0 made 0:
    rounding noise then cannot tell two equal values apart (two turns of a joint
    equally far from where it should be tie exactly, and ``argmin`` takes the first)."""
    tol = opw.ANGLE_TOLERANCE_DEG
    return np.round(np.asarray(angle_deg, dtype=float) / tol) * tol + 0.0


@dataclass
class ArmGeometry:
    """Where an arm stands relative to its three singularities (arrays, shape (...)).

    Attributes
    ----------
    shoulder_mm : ndarray
        Signed distance of the wrist centre from axis 1, measured along the
        arm's forward direction (x of the frame turning with axis 1), mm.
        Negative: the wrist centre is behind axis 1 (reaching over the
        shoulder).  0 is the shoulder singularity.
    elbow_deg : ndarray
        Elbow angle in (-180, 180] degrees: 0 with the arm stretched (wrist
        centre on the line of the lower arm, outwards), +-180 folded;
        positive with the wrist centre in front of the lower arm.
    wrist_deg : ndarray
        The model's wrist bend ``theta5`` in (-180, 180] degrees (negated
        when its z points down the arm, ``c1 < 0``); 0 and 180 are the wrist
        singularity (axes 4 and 6 in line).
    wrist_singular_at_180 : bool
        False on an oblique wrist (MPX3500), whose axes 4 and 6 line up at 0 only.
    jacobian_of : tuple or None
        On an offset wrist, ``(params, q_deg)``: its singularities are not where the
        three measures are zero, and :meth:`singularity_distances` measures them on
        the Jacobian (:mod:`.singularity`) when asked. None elsewhere.
    """

    shoulder_mm: np.ndarray
    elbow_deg: np.ndarray
    wrist_deg: np.ndarray
    wrist_singular_at_180: bool = True
    jacobian_of: Optional[tuple] = None

    def family(self):
        """ndarray of int, shape (...): 0..7, -1 where the joints are NaN."""
        with np.errstate(invalid="ignore"):
            fam = (SHOULDER_BACK * (self.shoulder_mm < 0)
                   + ELBOW_DOWN * (self.elbow_deg < 0)
                   + WRIST_FLIPPED * (self.wrist_deg < 0)).astype(int)
        nan = np.isnan(self.shoulder_mm) | np.isnan(self.elbow_deg) | np.isnan(self.wrist_deg)
        return np.where(nan, -1, fam)

    def singularity_distances(self):
        """Distances to the three singularities.

        Returns
        -------
        shoulder_mm, elbow_deg, wrist_deg : ndarray, shape (...)
            ``|shoulder_mm|``; the elbow's angle from stretched or folded,
            ``min(|e|, 180 - |e|)``; the wrist's angle from 0 or 180 degrees.
            On an offset wrist (:attr:`jacobian_of`): infinity and 90 degrees (no
            shoulder or elbow singularity of their own), and the joint-space
            distance to the nearest singularity (:func:`.singularity.distance_deg`)
            in the wrist's place, capped at 90 degrees.
        """
        if self.jacobian_of is not None:
            d = singularity.distance_deg(*self.jacobian_of)
            nan = np.isnan(d)
            return (np.where(nan, np.nan, np.inf), np.where(nan, np.nan, 90.0),
                    np.minimum(d, 90.0))
        e, w = np.abs(self.elbow_deg), np.abs(self.wrist_deg)
        wrist = np.minimum(w, 180.0 - w) if self.wrist_singular_at_180 else w
        return np.abs(self.shoulder_mm), np.minimum(e, 180.0 - e), wrist


def arm_geometry(q_deg, robot):
    """Shoulder, elbow and wrist measures of joint vectors (see :class:`ArmGeometry`).

    Parameters
    ----------
    q_deg : array_like, shape (..., 6)
        Model joints, degrees (NaN rows allowed).
    robot : RobotModel or RobotSpec
        OPW robots (``spec.opw``), Universal Robots (``spec.ur``) and chain
        arms (:func:`chain_parameters`).

    Returns
    -------
    ArmGeometry
        Arrays of shape (...).
    """
    spec = _spec(robot)
    q_deg = np.asarray(q_deg, dtype=float)
    if spec.ur is not None:
        return _ur_geometry(spec.ur, q_deg)
    if spec.opw is None:
        params = chain_parameters(robot)
        if params is None:
            raise ValueError("robot %s has no OPW, UR or chain parameters" % spec.name)
        return _chain_geometry(params, q_deg)
    p = spec.opw
    signs = np.asarray(p.signs, dtype=float)
    q = np.radians(q_deg) * signs - np.radians(np.asarray(p.offsets_deg, dtype=float))
    psi3 = np.arctan2(p.a2, p.c3)
    k = np.hypot(p.a2, p.c3)
    q2, q3, q5 = q[..., 1], q[..., 2], q[..., 4]
    # Same expressions as opw.forward: the wrist centre in the arm's own plane.
    shoulder = p.c2 * np.sin(q2) + k * np.sin(q2 + q3 + psi3) + p.a1
    # c1 < 0: the model's z points down the arm (a URDF whose axis 1 points down, e.g.
    # KUKA's), so its elbow and wrist angles turn the other way round the real arm.
    real = -1.0 if p.c1 < 0 else 1.0
    elbow = _wrap(np.degrees(q3 + psi3) * real)
    wrist = _wrap(np.degrees(q5) * real)
    return ArmGeometry(shoulder, elbow, wrist)


def chain_parameters(robot):
    """The chain parameters of an arm that is neither OPW nor UR; None for OPW and UR arms.

    The one place that tells a "chain" arm from the others: a model of kind
    ``"chain"`` (``models.ChainModel``) has them as ``params``, its catalog
    entry as ``spec.chain`` (axes and steps: :func:`.chain_families.parameters_of_axes`).

    Parameters
    ----------
    robot : RobotModel or RobotSpec

    Returns
    -------
    poe.ChainParameters or None
    """
    if getattr(robot, "kind", None) == "chain":
        return robot.params
    spec = _spec(robot)
    if spec.opw is not None or spec.ur is not None:
        return None
    chain = getattr(spec, "chain", None)
    if chain is None or isinstance(chain, poe.ChainParameters):
        return chain
    return chain_families.parameters_of_axes(chain)


def _chain_geometry(params, q_deg):
    shape = q_deg.shape[:-1]
    arm = chain_families.arm_of(params)
    shoulder, elbow, wrist = chain_families.measures(arm, q_deg.reshape(-1, 6))
    return ArmGeometry(shoulder.reshape(shape), elbow.reshape(shape), wrist.reshape(shape),
                       wrist_singular_at_180=arm.wrist_singular_at_180,
                       jacobian_of=(params, q_deg) if arm.offset_wrist else None)


def singular_on_jacobian(robot):
    """True for an offset wrist: its singularity distance is the Jacobian's, not the wrist's,
    shoulder's or elbow's (:attr:`ArmGeometry.jacobian_of`)."""
    params = chain_parameters(robot)
    return params is not None and chain_families.arm_of(params).offset_wrist


def _ur_geometry(params, q_deg):
    shape = q_deg.shape[:-1]
    q = q_deg.reshape(-1, 6)
    T = ur.forward(params, np.nan_to_num(q))
    p05 = T[:, :3, 3] - params.d6 * T[:, :3, 2]      # wrist point, frame 5 origin
    q1 = np.radians(q[:, 0])
    # x of the wrist point in frame 1: ±sqrt(r² - d4²); 0 is the shoulder singularity.
    shoulder = np.cos(q1) * p05[:, 0] + np.sin(q1) * p05[:, 1]
    shoulder = np.where(np.isnan(q).any(axis=1), np.nan, shoulder)
    return ArmGeometry(shoulder.reshape(shape), _wrap(q[:, 2]).reshape(shape),
                       _wrap(q[:, 4]).reshape(shape))


def family(q_deg, robot):
    """Configuration family of joint vectors (see the module docstring).

    Parameters
    ----------
    q_deg : array_like, shape (..., 6)
        Model joints, degrees.
    robot : RobotModel or RobotSpec

    Returns
    -------
    ndarray of int, shape (...)
        0..7; -1 for NaN rows.
    """
    return arm_geometry(q_deg, robot).family()
