"""Shoulder, elbow and wrist of a 6R arm given as a chain (:mod:`.poe`), from its own geometry.

The arms that are neither OPW nor UR (offset wrists: FANUC CRX-10iA/L and
M-430iA/2P, the Yaskawa HC10 family, ABB CRB 15000; spherical wrists off the
OPW form: KUKA KR 10/13/16/20/120 R...; the Yaskawa MPX3500's oblique wrist)
get the three measures of :class:`.arm_families.ArmGeometry` as OPW arms do,
from points and axes of the chain instead of the OPW lengths (on the 137 OPW
arms whose URDF is in tests/data the two agree on 131):

* the **wrist point** W: the point of axis 4 nearest axis 5 (where they meet on
  all these arms).  On a spherical wrist it is the wrist centre (axes 4, 5, 6
  meet there), as for OPW arms.  On an offset wrist axis 6 misses it by the
  offset (CRX-10iA/L 150 mm, HC10 162 mm, CRB 15000 80 mm, MPX3500 99 mm):
  there is no wrist centre, and W, on axis 4 where axis 5 crosses it, is taken
  in its place.  It moves with axes 1-3 only.  No maker's document at hand says
  which point front/back and up/down refer to on these arms.  For FANUC's CRX a
  third party's table of ROBOGUIDE and published solutions (see
  :func:`..motion.configuration_data.fanuc_configs`) reads Front/Back at the
  point where axes 5 and 6 meet instead (:func:`axis56_shoulder_mm`), and
  Up/Down the same at either point; for the others W stays unverified;
* **shoulder_mm**: W's distance along the arm's forward direction from axis
  1 (x of W in the frame that turns with axis 1).  Forward is perpendicular
  to axes 1 and 2 (a sideways offset along axis 2 does not count), on the
  side W is at zero joints or, on an arm that stands straight up at zero
  (HC10, M-430iA/2P), the side a growing J2 leans it to (unverified: the
  makers' positive J2 leans their arms forward on the OPW arms checked, and
  this is the URDFs' +x on both);
* **elbow_deg**: the angle at axis 3 between the lower arm (axis 2 to axis 3)
  and the line from axis 3 to W, seen along axis 2: 0 stretched, +-180
  folded, positive with the elbow up (turning about ``up x forward``, the
  sense in which the OPW model's elbow angle grows);
* **wrist_deg**: axis 5 from the straight wrist (the value at which axes 4
  and 6 are parallel with the flange out along the forearm, 0 on all these
  arms), positive
  when it turns about ``up x forward`` at zero joints (the sense of the OPW
  model's theta5): -J5 on the CRX-10iA/L and HC10, whose J5 axis points the
  other way, so "wrist flipped" is FANUC's F (J5 > 0); J5 itself on the CRB
  15000 (ABB: cfx odd for J5 < 0) and the KUKA arms (A5 < 0).  The
  MPX3500's oblique axis 5 is across that direction: its J5 is taken as it is.
  The chain's joints are the URDF's, which are the controller's on these
  arms (unverified for each arm: the ROS-Industrial descriptions' convention,
  as for every imported arm).

The three signs are the families' bits (:mod:`.arm_families`).  On a
spherical wrist their zeros are the three singularities, as on OPW arms.
On an offset wrist they are the boundaries where the makers' configuration
data changes (FANUC's Flip/Up/Front, ABB's cfx, Yaskawa's ///RCONF), but not
singularities: measured on 20,000 random joint vectors of the CRX-10iA/L and
the HC10, the smallest singular value of the Jacobian (mm scaled to m) within
0.5 deg (5 mm) of each boundary has a median 5 to 8 times below that of all
vectors, but reaches the overall median (about 0.1), where on the KR 16 R1100
it stays below 0.004.  The MPX3500's wrist is oblique and offset (axis 5 at
60 deg to axes 4 and 6; axis 6 meets axis 5 114 mm from axis 4): axes 4 and 6
are parallel at the straight wrist only (120 deg apart at 180).

Pure numpy: never imports FreeCAD.
"""

from dataclasses import dataclass

import numpy as np

from . import poe
from .opw import wrap_deg

#: Below this reach (mm) from axis 1 at zero joints the arm stands upright (HC10, M-430iA/2P).
ON_AXIS_MM = 1.0

#: Axis 6 this far (mm) from where axes 4 and 5 meet makes an offset wrist (as offset_wrist.py).
SPHERICAL_WRIST_TOL_MM = 1e-3

#: Axes 4 and 5 (or 5 and 6) farther than this from perpendicular (deg) make an oblique wrist.
OBLIQUE_DEG = 1.0

#: A straight-wrist angle this close (deg) to a multiple of 90 is that multiple: URDF files
#: round their angles (the KR 16 R1100-3's gives 0.0002 deg).
STRAIGHT_SNAP_DEG = 0.01


@dataclass(frozen=True)
class ChainArm:
    """What the measures need of an arm, computed once from its chain parameters.

    Attributes
    ----------
    params : poe.ChainParameters
    up : ndarray, shape (3,)
        Axis 1's direction from the base towards the shoulder (base frame).
    forward : ndarray, shape (3,)
        Unit vector perpendicular to axis 1 towards which the arm reaches at
        zero joints (turns with axis 1).
    wrist_from_axis4 : ndarray, shape (3,)
        The wrist point W minus axis 4's point (``P[0] + ... + P[3]``), at zero
        joints, mm: fixed in the link that axis 3 turns.
    q5_straight_deg : float
        Axis 5's value at which axes 4 and 6 are parallel with the flange out
        along the forearm.
    wrist_sign : float
        +1 or -1: the sign that turns axis 5 from straight into ``wrist_deg``.
    wrist_offset_mm : float
        Distance between axis 6 and W: 0 on a spherical wrist.
    oblique : bool
        Axis 5 is not perpendicular to axes 4 and 6 (MPX3500).
    shoulder_terms : ndarray, shape (3, 3)
        ``shoulder_mm = shoulder_at_axis2_mm + g M h`` with ``g = (1, cos J3,
        sin J3)``, ``h = (1, cos J2, sin J2)`` (see :func:`measures`).
    shoulder_at_axis2_mm : float
        Axis 2's point along the forward direction from axis 1.
    elbow_terms : ndarray, shape (3, 2)
        ``g E`` is (sine, cosine) of the elbow angle times the lengths.
    axis5_point_from_axis4 : ndarray, shape (3,)
        The point of axis 5 nearest axis 6 (where they meet on the CRX) minus
        axis 4's point, at zero joints, mm: fixed in the link that axis 4
        turns (:func:`axis56_shoulder_mm`).  W itself on a spherical wrist.
    """

    params: object
    up: np.ndarray
    forward: np.ndarray
    wrist_from_axis4: np.ndarray
    q5_straight_deg: float
    wrist_sign: float
    wrist_offset_mm: float
    oblique: bool
    shoulder_terms: np.ndarray
    shoulder_at_axis2_mm: float
    elbow_terms: np.ndarray
    axis5_point_from_axis4: np.ndarray

    @property
    def offset_wrist(self):
        """bool: axes 4, 5 and 6 do not meet in one point (or axis 5 is oblique): the three
        measures' zeros are not the arm's singularities."""
        return self.oblique or self.wrist_offset_mm > SPHERICAL_WRIST_TOL_MM

    @property
    def wrist_singular_at_180(self):
        """bool: axes 4 and 6 are parallel at 180 deg from the straight wrist too (not on an
        oblique wrist)."""
        return not self.oblique


def _unit(v):
    return np.asarray(v, dtype=float) / np.linalg.norm(v)


def _off_axis(v, axis):
    """The part of vector(s) `v` (..., 3) perpendicular to unit `axis` (..., 3)."""
    return v - np.sum(v * axis, axis=-1, keepdims=True) * axis


def _nearest_on_line(p, d, q, e):
    """Parameter t of the point ``p + t d`` of line (p, d) nearest line (q, e); unit d, e."""
    w = p - q
    b = d @ e
    if 1.0 - b * b < 1e-12:            # parallel lines: every point is as near
        return 0.0
    return (b * (e @ w) - d @ w) / (1.0 - b * b)


def _angle_deg(a, b):
    return np.degrees(np.arccos(np.clip(abs(a @ b), 0.0, 1.0)))


#: (what, id(obj)) -> (obj, value) computed from obj so far (each holds its obj, so the id
#: cannot be taken by another object); emptied when it reaches _KEPT_MAX.
_KEPT = {}
_KEPT_MAX = 64


def _kept(what, obj, make):
    """``make(obj)``, computed once per object."""
    known = _KEPT.get((what, id(obj)))
    if known is not None and known[0] is obj:
        return known[1]
    if len(_KEPT) >= _KEPT_MAX:
        _KEPT.clear()
    value = make(obj)
    _KEPT[(what, id(obj))] = (obj, value)
    return value


def parameters_of_axes(chain):
    """The :class:`.poe.ChainParameters` of a catalog entry's ``chain`` (part E's
    ``catalog.ChainAxes``: ``axes`` (6, 3), ``steps_mm`` (7, 3)), made once per entry;
    ``R_6T`` the identity (the measures do not use it).
    """
    return _kept("params", chain, lambda c: poe.ChainParameters(
        H=np.array(c.axes, dtype=float), P=np.array(c.steps_mm, dtype=float), R_6T=np.eye(3)))


def arm_of(params):
    """The :class:`ChainArm` of chain parameters, computed once per parameters object.

    Parameters
    ----------
    params : poe.ChainParameters

    Returns
    -------
    ChainArm

    Raises
    ------
    ValueError
        Axes 1 and 2 are parallel (not an arm of these classes).
    """
    return _kept("arm", params, _arm_of)


def _arm_of(params):
    """:func:`arm_of`, computed."""
    H, P = params.H, params.P
    points = np.cumsum(P[:6], axis=0)                  # a point of each axis, zero joints
    up = H[0] if H[0] @ points[1] >= 0.0 else -H[0]
    wrist = points[3] + _nearest_on_line(points[3], H[3], points[4], H[4]) * H[3]
    across = np.cross(H[1], H[0])                      # in the arm's plane, off axis 1
    if np.linalg.norm(across) < 1e-9:
        raise ValueError("axes 1 and 2 are parallel: not an arm of these classes")
    across = _unit(across)
    reach = (wrist - points[0]) @ across
    if abs(reach) < ON_AXIS_MM:                        # upright at zero: lean it with J2
        reach = np.cross(H[1], wrist - points[1]) @ across
    forward = across if reach >= 0.0 else -across
    six = _off_axis(wrist - points[5], H[5])           # W from axis 6
    q5 = _straight_wrist_deg(params, wrist - points[2])
    oblique = max(abs(90.0 - _angle_deg(H[3], H[4])),
                  abs(90.0 - _angle_deg(H[4], H[5]))) > OBLIQUE_DEG
    shoulder_terms, elbow_terms = _terms(params, up, forward, wrist - points[3])
    bend = H[4] @ np.cross(up, forward)                # which way axis 5 turns theta5
    axis56 = points[4] + _nearest_on_line(points[4], H[4], points[5], H[5]) * H[4]
    return ChainArm(params=params, up=up, forward=forward,
                    wrist_from_axis4=wrist - points[3], q5_straight_deg=float(q5),
                    wrist_sign=-1.0 if bend < -0.5 else 1.0,
                    wrist_offset_mm=float(np.linalg.norm(six)), oblique=bool(oblique),
                    shoulder_terms=shoulder_terms, shoulder_at_axis2_mm=float(forward @ P[1]),
                    elbow_terms=elbow_terms, axis5_point_from_axis4=axis56 - points[3])


def _straight_wrist_deg(params, elbow_to_wrist):
    """Axis 5's value at which axes 4 and 6 are parallel with the flange out along the
    forearm (of the two values that make them parallel, the one that puts the flange
    farther from the elbow): IK-Geo subproblem 1 on the axes' directions.

    Parameters
    ----------
    params : poe.ChainParameters
    elbow_to_wrist : ndarray, shape (3,)
        From axis 3's point to W at zero joints, mm.
    """
    H, P = params.H, params.P
    h4, h6 = _off_axis(H[3], H[4]), _off_axis(H[5], H[4])
    q5 = np.arctan2(H[4] @ np.cross(h6, h4), h6 @ h4)
    out = H[3] if H[3] @ elbow_to_wrist >= 0.0 else -H[3]      # along the forearm, outwards
    flange = P[5] + P[6]                                        # from axis 5's point
    if _turning_at(H[4], flange, q5 + np.pi) @ out > _turning_at(H[4], flange, q5) @ out:
        q5 += np.pi
    q5 = float(wrap_deg(np.degrees(q5)))
    if abs(q5 - 90.0 * np.round(q5 / 90.0)) < STRAIGHT_SNAP_DEG:
        q5 = 90.0 * np.round(q5 / 90.0) + 0.0
    return q5


def _turning_at(axis, v, angle_rad):
    """v turned about unit `axis` by `angle_rad`, (3,)."""
    along, across, side = _turning(axis, v)
    return along + across * np.cos(angle_rad) + side * np.sin(angle_rad)


def _turning(axis, v):
    """v turned about unit `axis` by q is ``a + b cos q + c sin q``: (a, b, c), each (3,)."""
    along = axis * (axis @ v)
    return along, v - along, np.cross(axis, v)


def _terms(params, up, forward, wrist_from_axis4):
    """The constant terms of the shoulder and elbow (:class:`ChainArm`), by Rodrigues'
    formula: axis 3 turns the forearm (axis 3 -> W), axis 2 the upper arm and the forearm;
    axes 2 and 3 are parallel on these arms, so the elbow depends on J3 alone."""
    H, P = params.H, params.P
    forearm = _turning(H[2], P[3] + wrist_from_axis4)            # (1, cos J3, sin J3) terms
    upper_arm = (P[2] + forearm[0], forearm[1], forearm[2])
    shoulder = np.array([[forward @ t for t in _turning(H[1], u)] for u in upper_arm])
    normal = np.cross(up, forward)
    lower = _off_axis(P[2], H[1])
    elbow = np.array([[normal @ np.cross(lower, _off_axis(u, H[1])), lower @ _off_axis(u, H[1])]
                      for u in forearm])
    return shoulder, elbow


def measures(arm, q_deg):
    """Shoulder, elbow and wrist of joint vectors (see the module docstring).

    Axis 1 turns the whole arm with the forward direction, so the measures are
    taken in the frame it turns (J1 does not enter); axes 2 and 3 are parallel
    on these arms, so the elbow depends on J3 alone.

    Parameters
    ----------
    arm : ChainArm
    q_deg : ndarray, shape (N, 6)
        The chain's joints, degrees; NaN rows give NaN.

    Returns
    -------
    shoulder_mm, elbow_deg, wrist_deg : ndarray, shape (N,)
        elbow and wrist in (-180, 180].
    """
    q_deg = np.asarray(q_deg, dtype=float)
    q2, q3 = np.radians(q_deg[:, 1]), np.radians(q_deg[:, 2])
    g = np.stack([np.ones_like(q3), np.cos(q3), np.sin(q3)], axis=1)
    h = np.stack([np.ones_like(q2), np.cos(q2), np.sin(q2)], axis=1)
    shoulder = arm.shoulder_at_axis2_mm + np.sum((g @ arm.shoulder_terms) * h, axis=1)
    sine, cosine = (g @ arm.elbow_terms).T
    elbow = np.degrees(np.arctan2(sine, cosine))
    wrist = wrap_deg(arm.wrist_sign * axis5_from_straight(arm, q_deg[:, 4]))
    return shoulder, wrap_deg(elbow), wrist


def axis56_shoulder_mm(arm, q_deg):
    """Distance along the forward direction from axis 1 of the point where axes 5 and 6
    meet (of axis 5 nearest axis 6), in the frame axis 1 turns, mm.

    FANUC's Front/Back of the CRX-10iA is read at that point, not at W (where axes
    4 and 5 meet): see :func:`..motion.configuration_data.fanuc_configs`.  The
    point is fixed in the link axis 4 turns, so axes 2, 3 and 4 move it; on a
    spherical wrist it is W and this equals ``measures(...)[0]``.

    Parameters
    ----------
    arm : ChainArm
    q_deg : ndarray, shape (N, 6)
        The chain's joints, degrees.

    Returns
    -------
    ndarray, shape (N,)
    """
    H, P = arm.params.H, arm.params.P
    points = np.cumsum(P[:6], axis=0)
    q = np.radians(np.asarray(q_deg, dtype=float))
    x = np.broadcast_to(points[3] + arm.axis5_point_from_axis4, (len(q), 3))
    for k in (3, 2, 1):                          # innermost joint first; axis 1 is not turned
        x = points[k] + _turned(H[k], x - points[k], q[:, k])
    return (x - points[0]) @ arm.forward


def _turned(axis, v, angle_rad):
    """Vectors `v` (N, 3) turned about unit `axis` by `angle_rad` (N,), Rodrigues."""
    c, s = np.cos(angle_rad)[:, None], np.sin(angle_rad)[:, None]
    return v * c + np.cross(axis, v) * s + np.outer(v @ axis, axis) * (1.0 - c)


def axis5_from_straight(arm, q5_deg):
    """Axis 5 (deg, the joint's own direction) from the straight wrist, in (-180, 180]."""
    return wrap_deg(np.asarray(q5_deg, dtype=float) - arm.q5_straight_deg)
