"""Recognise the kinematic class of a URDF arm and extract its closed-form model.

These classes have a closed-form (or semi-analytic) inverse in CadRobot, tried
in this order:

* **OPW** (:mod:`.opw`): axis 1 perpendicular to axis 2, axes 2 and 3
  parallel, axis 4 perpendicular to them, and a spherical wrist (axes 4, 5
  and 6 meet in one point, each perpendicular to the next).  Most
  industrial arms.
* **UR** (:mod:`.ur`): axes 1 and 2 meet at a right angle, axes 2, 3 and 4
  parallel, axis 5 meets axis 4 and axis 6 meets axis 5 at right angles: the
  Universal Robots layout.
* **chain** (:mod:`.poe`, :mod:`.chain_classes`): any other arm a solver
  class recognises (an offset wrist as on the FANUC CRX, Yaskawa HC10 and ABB
  CRB 15000; a spherical wrist at any angles, or on a file that rounds pi/2).
  Its model is the URDF's joint axes and the steps between them at zero joint
  values (:func:`.poe.from_chain`), in the root link's frame: ``T_root_base``
  is the identity and ``T_flange_tip`` the flange's rotation at zero.

The OPW and UR extraction reads the joint axes as lines in the root link's frame at
zero joint values (:func:`.urdf.joint_lines`) and builds the model's base
frame, lengths, per-joint offsets and signs (``q_model = q * sign -
offset``, so the model takes the URDF's own joint values), and two fixed
transforms: ``T_root_base`` (the model's base frame in the URDF's root link)
and ``T_flange_tip`` (the URDF's flange in the model's flange frame).  Then
:func:`verify` compares the model with the URDF chain on random joint sets
within the limits; an arm is accepted only when they agree to
:data:`POSITION_TOL_MM` and :data:`ROTATION_TOL_RAD`.  Never a silent
approximation: a mismatch raises with what the arm is.

Pure numpy: never imports FreeCAD.
"""

from dataclasses import dataclass

import numpy as np

from ...core.frames import invert_transform, make_transform
from ...core.rotations import rotation_angle_between
from ...errors import InputError
from . import urdf
from ..kinematics import chain_classes, opw, poe, ur
from ..catalog.catalog import OPWParameters, URParameters

#: Largest flange position difference accepted between a model and its URDF chain.
POSITION_TOL_MM = 1e-6
#: Largest flange rotation difference accepted (angle of the relative rotation).
ROTATION_TOL_RAD = 1e-9
#: Axes this close to parallel / perpendicular (|sin| or |cos| of their angle)
#: and lines this close (mm) count as such while recognising a class; the
#: sampled comparison then decides.
DIRECTION_TOL = 1e-9
DISTANCE_TOL_MM = 1e-6
#: Extracted lengths (mm) and offsets (deg) are rounded to this many decimals, so
#: 42 mm does not read 41.99999999999997 (1e-9 is far inside the tolerances above).
DECIMALS = 9
#: Joint sets compared in :func:`verify`.
SAMPLES = 1000
#: A joint set with no special alignment (rad): the class is recognised there, as
#: at zero joint values a wrist offset can hide (axis 6 in line with axis 4).
GENERIC_Q_RAD = np.array([0.3, -0.4, 0.5, 0.7, -0.9, 1.1])


class KinematicsError(InputError):
    """The arm's kinematics is not of a class CadRobot solves in closed form."""


@dataclass(frozen=True)
class Identified:
    """A closed-form model of a URDF chain.

    Attributes
    ----------
    kind : str
        ``"opw"``, ``"ur"`` or ``"chain"``.
    params : OPWParameters, URParameters or poe.ChainParameters
        Lengths in mm, offsets in degrees, signs (the URDF's joint values go
        in unchanged); a chain's axes and steps (its ``R_6T`` the identity).
    T_root_base : ndarray, shape (4, 4)
        The model's base frame in the URDF's root link frame, mm.
    T_flange_tip : ndarray, shape (4, 4)
        The URDF's flange link in the model's flange frame, mm.
    """

    kind: str
    params: object
    T_root_base: np.ndarray
    T_flange_tip: np.ndarray

    def fk(self, q_deg):
        """URDF flange pose in the root link frame, (N, 6) deg -> (N, 4, 4) mm."""
        q = np.atleast_2d(q_deg)
        inner = (poe.fk(self.params, np.radians(q)) if self.kind == "chain"
                 else (opw.forward if self.kind == "opw" else ur.forward)(self.params, q))
        return self.T_root_base @ inner @ self.T_flange_tip

    def ik(self, T_root_tip):
        """Every solution, (N, 4, 4) mm -> (N, M, 6) deg (URDF joint values; M = 8, or
        the chain class's ``MAX_SOLUTIONS``)."""
        T = invert_transform(self.T_root_base) @ np.asarray(T_root_tip) @ invert_transform(
            self.T_flange_tip)
        if self.kind == "chain":
            return opw.wrap_deg(np.degrees(chain_classes.Solver(self.params).inverse(T)))
        return (opw.inverse if self.kind == "opw" else ur.inverse)(self.params, T)


# ------------------------------------------------------------------ line geometry

def _unit(v):
    return v / np.linalg.norm(v)


def _closest_points(p1, u1, p2, u2):
    """Closest points of two non-parallel lines, and their distance."""
    w = p1 - p2
    b = u1 @ u2
    d, e = u1 @ w, u2 @ w
    denominator = 1.0 - b * b
    s = (b * e - d) / denominator
    t = (e - b * d) / denominator
    c1, c2 = p1 + s * u1, p2 + t * u2
    return c1, c2, float(np.linalg.norm(c1 - c2))


def _line_distance(p1, u1, p2, u2):
    """Distance between two lines (parallel ones too)."""
    n = np.cross(u1, u2)
    if np.linalg.norm(n) < DIRECTION_TOL:
        w = p2 - p1
        return float(np.linalg.norm(w - (w @ u1) * u1))
    return abs(float((p2 - p1) @ _unit(n)))


def _angle_deg(u, v):
    return float(np.degrees(np.arccos(np.clip(abs(u @ v), 0.0, 1.0))))


def _require_parallel(u, v, i, j):
    if np.linalg.norm(np.cross(u, v)) > DIRECTION_TOL:
        raise KinematicsError("axes %d and %d are not parallel (%.6g deg apart)"
                              % (i, j, _angle_deg(u, v)))


#: Below this many degrees off, a "not perpendicular" is most likely a rounded angle
#: in the file (1.5708 written for pi/2 is 0.00021 deg off); the message says so.
ROUNDED_ANGLE_DEG = 0.01


def _require_perpendicular(u, v, i, j):
    if abs(u @ v) > DIRECTION_TOL:
        off_deg = 90.0 - _angle_deg(u, v)
        hint = (", most likely an angle rounded in the file (1.5708 for pi/2)"
                if off_deg < ROUNDED_ANGLE_DEG else "")
        raise KinematicsError("axes %d and %d are not perpendicular (%.6g deg from it%s)"
                              % (i, j, off_deg, hint))


def _require_meet(p1, u1, p2, u2, i, j, what=""):
    distance = _line_distance(p1, u1, p2, u2)
    if distance > DISTANCE_TOL_MM:
        raise KinematicsError("axes %d and %d do not meet (%.6g mm apart)%s" % (i, j, distance, what))


def _signed_angle(a, b, axis):
    """Angle turning unit vector `a` into `b` about unit `axis` (both perpendicular to it)."""
    return float(np.arctan2(np.cross(a, b) @ axis, a @ b))


def _rounded(values):
    return tuple(float(v) + 0.0 for v in np.round(np.asarray(values, dtype=float), DECIMALS))


def _base_origin(p1, u1):
    """The point of axis 1 nearest the root link's origin."""
    return p1 - (p1 @ u1) * u1


def _closest_to_zero(angle, sign):
    """(angle, sign) or the equivalent (angle + pi, -sign), whichever is nearer zero."""
    flipped = (angle + 2 * np.pi) % (2 * np.pi) - np.pi
    if abs(angle) <= abs(flipped) + 1e-12:
        return angle, sign
    return flipped, -sign


# ------------------------------------------------------------------ OPW

def _spherical_wrist_centre(p, u):
    """The point where axes 4, 5 and 6 meet, or KinematicsError."""
    c45a, c45b, d45 = _closest_points(p[3], u[3], p[4], u[4])
    wrist = 0.5 * (c45a + c45b)
    d6 = float(np.linalg.norm(np.cross(wrist - p[5], u[5])))
    if max(d45, d6) > DISTANCE_TOL_MM:
        raise KinematicsError("axes 4, 5 and 6 do not meet in a point (%.6g mm apart): "
                              "not a spherical wrist" % max(d45, d6))
    return wrist


def _require_opw_layout(p, u):
    _require_perpendicular(u[0], u[1], 1, 2)
    _require_parallel(u[1], u[2], 2, 3)
    _require_perpendicular(u[2], u[3], 3, 4)
    _require_perpendicular(u[3], u[4], 4, 5)
    _require_perpendicular(u[4], u[5], 5, 6)
    _spherical_wrist_centre(p, u)


def opw_from_chain(chain):
    """The OPW model of a chain.

    Parameters
    ----------
    chain : urdf.Chain

    Returns
    -------
    Identified
        ``kind == "opw"``.

    Raises
    ------
    KinematicsError
        With what the arm is, e.g. "axes 4, 5 and 6 do not meet in a point:
        not a spherical wrist".
    """
    _require_opw_layout(*urdf.joint_lines(chain, GENERIC_Q_RAD))
    p, u = urdf.joint_lines(chain)
    wrist = _spherical_wrist_centre(p, u)

    z0 = u[0]
    origin = _base_origin(p[0], z0)
    horizontal = (wrist - origin) - ((wrist - origin) @ z0) * z0
    y0 = u[1]
    if np.cross(y0, z0) @ horizontal < 0:
        y0 = -y0
    x0 = np.cross(y0, z0)
    T_root_base = make_transform(np.column_stack([x0, y0, z0]), origin)

    def in_plane(v):   # x and z of a vector of the arm's plane
        return np.array([v @ x0, v @ z0])

    a1, c1 = in_plane(p[1] - origin)
    elbow = in_plane(p[2] - p[1])
    c2 = float(np.hypot(*elbow))
    if c2 < DISTANCE_TOL_MM:
        raise KinematicsError("axes 2 and 3 coincide: no upper arm")
    q2 = float(np.arctan2(elbow[0], elbow[1]))
    to_wrist = wrist - p[2]
    u4 = u[3] if to_wrist @ u[3] >= 0 else -u[3]
    q23 = float(np.arctan2(u4 @ x0, u4 @ z0))
    forearm_x = np.cos(q23) * x0 - np.sin(q23) * z0
    a2, c3 = float(to_wrist @ forearm_x), float(to_wrist @ u4)
    b = float((wrist - origin) @ y0)

    # The wrist: R_0c = Ry(q23) in the base; axis 5 = R_0c Rz(q4) y; axis 6 = R_0c Rz(q4) Ry(q5) z.
    R_0c = np.array([forearm_x, y0, u4]).T
    u5_c = R_0c.T @ u[4]
    q4, s5 = _closest_to_zero(float(np.arctan2(-u5_c[0], u5_c[1])), 1.0)
    c4_, s4_ = np.cos(q4), np.sin(q4)
    Rz4 = np.array([[c4_, -s4_, 0.0], [s4_, c4_, 0.0], [0.0, 0.0, 1.0]])
    u6_4 = Rz4.T @ (R_0c.T @ u[5])
    q5, s6 = _closest_to_zero(float(np.arctan2(u6_4[0], u6_4[2])), 1.0)
    c4 = float((chain_tip(chain)[:3, 3] - wrist) @ (s6 * u[5]))

    model_q = np.array([0.0, q2, q23 - q2, q4, q5, 0.0])
    signs = np.array([1.0, np.sign(u[1] @ y0), np.sign(u[2] @ y0), np.sign(u[3] @ u4), s5, s6])
    params = OPWParameters(*_rounded((a1, a2, b, c1, c2, c3, c4)),
                           offsets_deg=_rounded(np.degrees(-model_q)),
                           signs=tuple(int(s) for s in signs))
    T_base_flange = opw.forward(params, np.zeros(6))
    T_flange_tip = invert_transform(T_root_base @ T_base_flange) @ chain_tip(chain)
    return Identified("opw", params, T_root_base, T_flange_tip)


def chain_tip(chain, q_rad=None):
    """(4, 4) flange of `chain` at `q_rad` (default zero), mm."""
    q = np.zeros((1, 6)) if q_rad is None else np.atleast_2d(q_rad)
    return urdf.chain_fk(chain, q)[0]


# ------------------------------------------------------------------ UR

def ur_from_chain(chain):
    """The Universal Robots model of a chain.

    Standard DH frames are laid on the axis lines (UR's pattern: ``alpha =
    90, 0, 0, 90, -90, 0`` deg, ``a1 = a4 = a5 = a6 = 0``), the common
    normals between the parallel axes 2-3-4 drawn through the point where
    axes 1 and 2 meet (so ``d2 = d3 = 0`` and the shoulder and elbow side
    offsets add up in ``d4``, as in UR's own table).

    Parameters
    ----------
    chain : urdf.Chain

    Returns
    -------
    Identified
        ``kind == "ur"``.

    Raises
    ------
    KinematicsError
    """
    for q in (GENERIC_Q_RAD, None):
        p, u = urdf.joint_lines(chain, q)
        _require_perpendicular(u[0], u[1], 1, 2)
        _require_meet(p[0], u[0], p[1], u[1], 1, 2)
        _require_parallel(u[1], u[2], 2, 3)
        _require_parallel(u[2], u[3], 3, 4)
        _require_perpendicular(u[3], u[4], 4, 5)
        _require_meet(p[3], u[3], p[4], u[4], 4, 5)
        _require_perpendicular(u[4], u[5], 5, 6)
        _require_meet(p[4], u[4], p[5], u[5], 5, 6)

    z = [u[0], u[1], None, None, u[4], u[5]]
    z[2], z[3] = z[1], z[1]
    signs = [1.0, 1.0, float(np.sign(u[2] @ z[1])), float(np.sign(u[3] @ z[1])), 1.0, 1.0]
    o0 = _base_origin(p[0], z[0])
    o1 = _closest_points(p[0], z[0], p[1], z[1])[1]
    d1 = float((o1 - o0) @ z[0])
    x = [None] * 6
    x[0] = np.cross(z[0], z[1])            # alpha1 = +90 and theta1 = 0 at the URDF's zero
    lengths = {}
    theta = np.zeros(6)
    origin = o1
    for i, name in ((1, "a2"), (2, "a3")):
        w = p[i + 1] - origin
        v = w - (w @ z[1]) * z[1]
        x_candidate = _unit(v)
        angle = _signed_angle(x[i - 1], x_candidate, z[1])
        angle, length_sign = _closest_to_zero(angle, 1.0)
        x[i] = length_sign * x_candidate
        lengths[name] = length_sign * float(np.linalg.norm(v))
        theta[i] = angle
        origin = origin + lengths[name] * x[i]
    o45 = _closest_points(p[3], z[3], p[4], z[4])[1]
    lengths["d4"] = float((o45 - origin) @ z[3])
    x[3] = np.cross(z[3], z[4])            # alpha4 = +90
    theta[3] = _signed_angle(x[2], x[3], z[3])
    o56 = _closest_points(p[4], z[4], p[5], z[5])[1]
    lengths["d5"] = float((o56 - o45) @ z[4])
    x[4] = np.cross(z[5], z[4])            # alpha5 = -90
    theta[4] = _signed_angle(x[3], x[4], z[4])
    lengths["d6"] = float((chain_tip(chain)[:3, 3] - o56) @ z[5])
    T_root_base = make_transform(np.column_stack([x[0], np.cross(z[0], x[0]), z[0]]), o0)
    params = URParameters(*_rounded([d1] + [lengths[k] for k in ("a2", "a3", "d4", "d5", "d6")]),
                          offsets_deg=_rounded(np.degrees(-theta)),
                          signs=tuple(int(s) for s in signs))
    T_base_flange = ur.forward(params, np.zeros(6))
    T_flange_tip = invert_transform(T_root_base @ T_base_flange) @ chain_tip(chain)
    return Identified("ur", params, T_root_base, T_flange_tip)


# ------------------------------------------------------------------ other classes

def chain_model_from_chain(chain):
    """The axes-and-steps model of a chain that a solver class recognises.

    Parameters
    ----------
    chain : urdf.Chain

    Returns
    -------
    Identified
        ``kind == "chain"``.

    Raises
    ------
    KinematicsError
        Saying, for each class, why the arm is not of it.
    """
    params = poe.from_chain(chain)
    try:
        chain_classes.classify(params)
    except ValueError as exc:
        raise KinematicsError(str(exc)) from None
    unrotated = poe.ChainParameters(H=params.H, P=params.P, R_6T=np.eye(3))
    return Identified("chain", unrotated, np.eye(4), make_transform(params.R_6T))


# ------------------------------------------------------------------ checking

def random_joints(chain, count, seed=0):
    """Joint sets spread uniformly within the chain's limits, (count, 6) rad."""
    rng = np.random.default_rng(seed)
    return rng.uniform(chain.lower_rad, chain.upper_rad, size=(count, 6))


def model_errors(identified, chain, q_rad):
    """Flange differences between a model and its chain.

    Parameters
    ----------
    identified : Identified
    chain : urdf.Chain
    q_rad : ndarray, shape (N, 6)

    Returns
    -------
    position_mm, rotation_rad : ndarray, shape (N,)
    """
    T_model = identified.fk(np.degrees(q_rad))
    T_chain = urdf.chain_fk(chain, q_rad)
    position = np.linalg.norm(T_model[:, :3, 3] - T_chain[:, :3, 3], axis=1)
    return position, rotation_angle_between(T_model[:, :3, :3], T_chain[:, :3, :3])


def verify(identified, chain, samples=SAMPLES, seed=0):
    """Compare a model with its URDF chain on `samples` random joint sets.

    Parameters
    ----------
    identified : Identified
    chain : urdf.Chain
    samples : int
    seed : int

    Returns
    -------
    (float, float)
        The largest position (mm) and rotation (rad) differences.

    Raises
    ------
    KinematicsError
        When either is above :data:`POSITION_TOL_MM` / :data:`ROTATION_TOL_RAD`.
    """
    q = np.vstack([np.zeros((1, 6)), random_joints(chain, samples, seed)])
    position, rotation = model_errors(identified, chain, q)
    worst = (float(position.max()), float(rotation.max()))
    if worst[0] > POSITION_TOL_MM or worst[1] > ROTATION_TOL_RAD:
        raise KinematicsError("its %s model differs from the URDF chain by up to %.3g mm and "
                              "%.3g rad on %d joint sets" % (identified.kind.upper(), worst[0],
                                                             worst[1], len(q)))
    return worst


def identify(chain, samples=SAMPLES):
    """The closed-form model of a chain, checked against it.

    Parameters
    ----------
    chain : urdf.Chain
    samples : int
        Random joint sets of the check (:func:`verify`).

    Returns
    -------
    Identified

    Raises
    ------
    KinematicsError
        With why it is of no class, e.g. "not an OPW arm (axes 4, 5 and 6 do
        not meet in a point (12 mm apart): not a spherical wrist); not a UR arm
        (axes 3 and 4 are not parallel ...); not an offset-wrist arm (...); not
        a spherical-wrist arm (...)".
    """
    reasons = []
    for label, extract in (("an OPW arm", opw_from_chain), ("a UR arm", ur_from_chain),
                           ("", chain_model_from_chain)):
        try:
            identified = extract(chain)
            verify(identified, chain, samples)
            return identified
        except KinematicsError as exc:
            reasons.append("not %s (%s)" % (label, exc) if label else str(exc))
    raise KinematicsError("; ".join(reasons))
