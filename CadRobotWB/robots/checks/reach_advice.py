"""Which way, and how far, to move the part (or the robot) so targets come within reach.

A reach or joint-limit finding is only useful if it says what to do.  For a
group of targets that fail for the same cause, :func:`advise` gives the least
move that brings every target of the group within reach:

* **Reach and joints 2 and 3** (:func:`translation_advice`): the wrist centre
  of a target (flange origin minus ``c4`` along the flange Z, OPW terms) must
  lie in the annulus the arm can reach about the shoulder (axis 2): between
  ``near`` and ``far`` of the point ``(a1, c1)`` of the arm's plane, with
  ``far = c2 + hypot(a2, c3)`` and ``near = |c2 - hypot(a2, c3)|`` (law of
  cosines over the elbow angles joint 3's limits allow, see :func:`annulus`).
  The worst target of the group says the direction: from its wrist centre
  straight to the shoulder (too far) or away from it (too near), in the
  vertical plane through axis 1.  The size is its distance outside the
  annulus, then grown in 10 mm steps until every target of the group is
  inside.  The move found is then **verified** with the model's inverse
  kinematics (every target reachable with all joints within their limits);
  when the geometric move does not do it (a joint-2 limit, an orientation
  the wrist cannot take), moves along eight directions (toward/away from the
  robot, up, down and their diagonals) are searched in 10 mm steps up to
  :data:`MAX_MOVE_MM`, and the least that works is given.
* **Joint 1** (:func:`turn_advice`): turning the robot about its own Z axis
  by ``alpha`` turns every target about axis 1 by ``-alpha``, so joint 1
  needs ``alpha`` less; the least turn (5 degree steps) that brings every
  target within all joint limits is given, verified the same way.

Directions are given in the assembly frame {U} the user sees: "toward the
robot" / "away from it" is the horizontal (XY of {U}) direction from the part
to the robot's base, "raise" / "lower" is Z of {U}.  Moving the part by ``d``
is the same as moving the robot by ``-d``.

Arms without OPW parameters: a Universal Robots arm (:mod:`.ur`) has no
spherical wrist, so its annulus is only an estimate (the point ``d6`` behind
the flange, about the shoulder at height ``d1``, reach ``|a2| + |a3| + d5``);
an imported arm with neither parameter set gets no geometric first guess.
In both cases the inverse-kinematics search above still finds (and
verifies) the move, so the advice stays true; only its first guess is
coarser.

Pure numpy: never imports FreeCAD.
"""

from dataclasses import dataclass
from typing import Optional

import numpy as np

#: Moves are rounded up to this step, mm.
STEP_MM = 10.0
#: Turns are rounded up to this step, degrees.
TURN_STEP_DEG = 5.0
#: Largest move searched, mm.
MAX_MOVE_MM = 1500.0
#: Most targets of a group checked by inverse kinematics (the worst always among them).
MAX_VERIFIED_TARGETS = 48


@dataclass
class Advice:
    """A move that brings a group of targets within reach.

    Attributes
    ----------
    move_u_mm : ndarray, shape (3,), or None
        Translation of the part in {U}, mm (the robot moves by minus it).
    turn_deg : float or None
        Turn of the robot base about its own Z axis, degrees,
        counter-clockwise seen from above positive.
    verified : bool
        Every target of the group (or the sample of :data:`MAX_VERIFIED_TARGETS`)
        is reachable within the joint limits after the move.
    text : str
        The advice for the user, one or two sentences.
    """

    move_u_mm: Optional[np.ndarray]
    turn_deg: Optional[float]
    verified: bool
    text: str


def _round_up(value, step):
    return float(np.ceil(max(value, 0.0) / step - 1e-9) * step)


def _opw_frame(model, T_r_f):
    """Flange poses in the frame the closed form uses (``spec.T_root_base`` and
    ``spec.T_flange_tip`` removed)."""
    T_root_base = getattr(model.spec, "T_root_base", None)
    T_flange_tip = getattr(model.spec, "T_flange_tip", None)
    if T_root_base is not None:
        T_r_f = np.linalg.inv(np.asarray(T_root_base, float)) @ T_r_f
    if T_flange_tip is not None:
        T_r_f = T_r_f @ np.linalg.inv(np.asarray(T_flange_tip, float))
    return T_r_f


def annulus(model):
    """Where the wrist centre can be about the shoulder.

    Parameters
    ----------
    model : RobotModel

    Returns
    -------
    dict or None
        ``wrist_mm`` (flange origin to wrist centre along flange Z),
        ``shoulder_radial_mm`` and ``shoulder_z_mm`` (axis 2 in the arm's
        plane: distance from axis 1 and height), ``lateral_mm`` (the arm
        plane's offset from axis 1, OPW ``b``), ``near_mm`` and ``far_mm``
        (the reachable distances of the wrist centre from axis 2, joint 3's
        limits applied), ``estimate`` (True for a UR arm).  None for an arm
        with neither OPW nor UR parameters.
    """
    spec = model.spec
    p = getattr(spec, "opw", None)
    if p is not None:
        k = float(np.hypot(p.a2, p.c3))
        near, far = abs(p.c2 - k), p.c2 + k
        elbow = _elbow_range(model, p, k)
        if elbow is not None:
            # Law of cosines over the elbow angle joint 3 allows.
            lo, hi = elbow
            # cos of the elbow angle is largest at 0 (stretched), smallest at +-pi (folded).
            angles = [lo, hi] + [a for a in (-2 * np.pi, 0.0, 2 * np.pi) if lo < a < hi]
            folded = [a for a in (-np.pi, np.pi) if lo < a < hi]
            d = np.sqrt(p.c2 ** 2 + k ** 2 + 2.0 * p.c2 * k * np.cos(np.array(angles + folded)))
            near, far = float(d.min()), float(d.max())
        return dict(wrist_mm=float(p.c4), shoulder_radial_mm=float(p.a1),
                    shoulder_z_mm=float(p.c1), lateral_mm=float(p.b), near_mm=float(near),
                    far_mm=float(far), estimate=False)
    u = getattr(spec, "ur", None)
    if u is not None:
        return dict(wrist_mm=float(u.d6), shoulder_radial_mm=0.0, shoulder_z_mm=float(u.d1),
                    lateral_mm=float(u.d4), near_mm=0.0,
                    far_mm=float(abs(u.a2) + abs(u.a3) + abs(u.d5)), estimate=True)
    return None


def _elbow_range(model, p, k):
    """(lo, hi) radians of the angle between the lower arm and the shoulder-to-wrist
    line of the forearm that joint 3's limits allow (0: stretched), or None.

    In the OPW model's zero pose the lower arm points up and the forearm
    (a2 forward, c3 up) leans forward by atan2(a2, c3); the model's q3 turns
    the forearm about axis 3, so the angle between the two is
    ``q3 + atan2(a2, c3)`` (sign of q3 as the model takes it).
    """
    try:
        lo_c, hi_c = float(model.joint_min_deg[2]), float(model.joint_max_deg[2])
    except (AttributeError, IndexError, TypeError):
        return None
    if getattr(model.spec, "j23_coupled", False):
        # The limit is on q3 + k q2: over joint 2's range the model's q3 spans more.
        factor = float(getattr(model.spec, "j23_factor", 1.0))
        q2 = np.array([model.joint_min_deg[1], model.joint_max_deg[1]], float) * factor
        lo_c, hi_c = lo_c - q2.max(), hi_c - q2.min()
    sign, offset = float(p.signs[2]), float(p.offsets_deg[2])
    ends = np.array([lo_c, hi_c]) * sign - offset
    lean = np.degrees(np.arctan2(p.a2, p.c3))
    angles = np.radians(np.sort(ends + lean))
    if angles[1] - angles[0] >= 2.0 * np.pi:
        return None
    return float(angles[0]), float(angles[1])


def wrist_geometry(model, T_r_f):
    """Wrist centres and their distances from the shoulder.

    Parameters
    ----------
    model : RobotModel
    T_r_f : array_like, shape (N, 4, 4)
        Flange poses in {R}, mm.

    Returns
    -------
    (ndarray (N, 3), ndarray (N,), ndarray (N,), dict) or None
        Wrist centres in {R} (mm), their distance from axis 2 (mm), the
        distance outside the annulus (mm; <= 0 inside), and :func:`annulus`.
        None when the arm has no such geometry.
    """
    ring = annulus(model)
    if ring is None:
        return None
    T = _opw_frame(model, np.asarray(T_r_f, float).reshape(-1, 4, 4))
    centre = T[:, :3, 3] - ring["wrist_mm"] * T[:, :3, 2]
    radial = np.sqrt(np.maximum(centre[:, 0] ** 2 + centre[:, 1] ** 2 - ring["lateral_mm"] ** 2, 0.0))
    distance = np.hypot(radial - ring["shoulder_radial_mm"], centre[:, 2] - ring["shoulder_z_mm"])
    outside = np.maximum(distance - ring["far_mm"], ring["near_mm"] - distance)
    T_root_base = getattr(model.spec, "T_root_base", None)
    if T_root_base is not None:
        T_root_base = np.asarray(T_root_base, float)
        centre = centre @ T_root_base[:3, :3].T + T_root_base[:3, 3]
    return centre, distance, outside, ring


def reachable(model, T_r_f):
    """Whether each flange pose has an inverse-kinematics solution within the joint limits.

    Parameters
    ----------
    model : RobotModel
    T_r_f : array_like, shape (N, 4, 4)

    Returns
    -------
    ndarray of bool, shape (N,)
    """
    T = np.asarray(T_r_f, float).reshape(-1, 4, 4)
    q = np.asarray(model.ik(T), float)
    return np.asarray(model.within_limits(q), bool).reshape(len(T), -1).any(axis=1)


def _sample(T_r_f, worst):
    n = len(T_r_f)
    if n <= MAX_VERIFIED_TARGETS:
        return T_r_f
    index = np.unique(np.append(np.linspace(0, n - 1, MAX_VERIFIED_TARGETS - 1).round().astype(int),
                                worst))
    return T_r_f[index]


def _moved(T_r_f, shift_r):
    out = np.array(T_r_f, dtype=float, copy=True)
    out[:, :3, 3] += shift_r
    return out


def _horizontal_toward_robot(T_u_r, T_r_f):
    """Unit vector in {U}: horizontal, from the targets' centre to the robot base."""
    centre_u = (T_u_r[:3, :3] @ T_r_f[:, :3, 3].mean(axis=0)) + T_u_r[:3, 3]
    v = T_u_r[:3, 3] - centre_u
    v[2] = 0.0
    n = np.linalg.norm(v)
    return v / n if n > 1e-9 else np.array([1.0, 0.0, 0.0])


def translation_advice(model, T_r_f, T_u_r=None):
    """The least translation of the part that brings every pose within reach.

    Parameters
    ----------
    model : RobotModel
    T_r_f : array_like, shape (N, 4, 4)
        Flange poses of the group's targets in {R}, mm.
    T_u_r : array_like, shape (4, 4), optional
        Robot base in {U} (directions are worded in {U}); default identity.

    Returns
    -------
    Advice
        ``move_u_mm`` the translation of the part in {U}, each component's
        size rounded up to :data:`STEP_MM`; ``verified`` False (and the text
        says so) when no move up to :data:`MAX_MOVE_MM` works.
    """
    T_r_f = np.asarray(T_r_f, float).reshape(-1, 4, 4)
    T_u_r = np.eye(4) if T_u_r is None else np.asarray(T_u_r, float)
    R_u_r = T_u_r[:3, :3]
    toward_u = _horizontal_toward_robot(T_u_r, T_r_f)
    geometry = wrist_geometry(model, T_r_f)
    worst = 0
    candidates = []                                   # (shift in {U}, ...) tried in order
    if geometry is not None:
        centre, distance, outside, ring = geometry
        worst = int(np.argmax(outside))
        if outside[worst] > 0.0:
            c = centre[worst]
            T_root = getattr(model.spec, "T_root_base", None)
            c_arm = c if T_root is None else np.linalg.solve(np.asarray(T_root, float),
                                                            np.append(c, 1.0))[:3]
            radial_xy = c_arm[:2] / max(np.hypot(*c_arm[:2]), 1e-9)
            radial = np.sqrt(max(c_arm[0] ** 2 + c_arm[1] ** 2 - ring["lateral_mm"] ** 2, 0.0))
            d_rad, d_z = radial - ring["shoulder_radial_mm"], c_arm[2] - ring["shoulder_z_mm"]
            d = max(np.hypot(d_rad, d_z), 1e-9)
            sign = -1.0 if distance[worst] > ring["far_mm"] else 1.0     # toward / away
            direction_arm = sign * np.array([d_rad / d * radial_xy[0], d_rad / d * radial_xy[1],
                                             d_z / d])
            if T_root is not None:
                direction_arm = np.asarray(T_root, float)[:3, :3] @ direction_arm
            direction_u = R_u_r @ direction_arm
            size = _round_up(outside[worst], STEP_MM)
            candidates.append((direction_u, size))
    sample_worst = worst
    T_check = _sample(T_r_f, sample_worst)
    R_r_u = R_u_r.T

    def works(shift_u):
        return bool(reachable(model, _moved(T_check, R_r_u @ shift_u)).all())

    def rounded(shift_u):
        return np.array([np.sign(v) * _round_up(abs(v), STEP_MM) for v in shift_u]) + 0.0  # no -0

    # 1. The geometric direction, grown until every target is in.
    for direction_u, size in candidates:
        for s in np.arange(max(size, STEP_MM), MAX_MOVE_MM + 1e-9, STEP_MM):
            shift = rounded(direction_u * s)
            if works(shift):
                return Advice(shift, None, True, _move_text(shift, toward_u))
    # 2. Eight directions in the vertical plane toward the robot, least size first.
    up = np.array([0.0, 0.0, 1.0])
    directions = [toward_u, -toward_u, up, -up]
    directions += [(a + b) / np.sqrt(2.0) for a in (toward_u, -toward_u) for b in (up, -up)]
    for s in np.arange(STEP_MM, MAX_MOVE_MM + 1e-9, STEP_MM):
        for direction_u in directions:
            shift = rounded(direction_u * s)
            if works(shift):
                return Advice(shift, None, True, _move_text(shift, toward_u))
    return Advice(None, None, False,
                  "No move of the part up to %.0f mm brings these targets within reach: change "
                  "the tool orientation (the tool markers) or let Place robot search a base."
                  % MAX_MOVE_MM)


def _move_text(shift_u, toward_u):
    """'Move the part at least 120 mm toward the robot (or the robot 120 mm toward it),
    and lower it by 40 mm.' for a shift of the part in {U}."""
    horizontal = float(np.dot(shift_u, toward_u))
    side = shift_u - horizontal * toward_u
    side[2] = 0.0
    vertical = float(shift_u[2])
    parts = []
    if abs(horizontal) >= 0.5:
        where = "toward the robot" if horizontal > 0 else "away from the robot"
        back = "toward it" if horizontal > 0 else "away from it"
        parts.append("move the part at least %.0f mm %s (or the robot %.0f mm %s)"
                     % (abs(horizontal), where, abs(horizontal), back))
    if abs(vertical) >= 0.5:
        verb = "raise" if vertical > 0 else "lower"
        robot = "lower" if vertical > 0 else "raise"
        if parts:
            parts.append("%s it by %.0f mm (or %s the robot by as much)" % (verb, abs(vertical), robot))
        else:
            parts.append("%s the part by at least %.0f mm (or %s the robot by as much)"
                         % (verb, abs(vertical), robot))
    if np.linalg.norm(side) >= 0.5:
        parts.append("shift it by (%.0f, %.0f) mm in X, Y" % (side[0], side[1]))
    text = ", and ".join(parts)
    return text[0].upper() + text[1:] + "."


def turn_advice(model, T_r_f, joint=1):
    """The least turn of the robot about its own Z axis that brings every pose within limits.

    Turning the robot base by ``alpha`` (counter-clockwise seen from above)
    puts a target that was at ``T_r_f`` at ``Rz(-alpha) @ T_r_f`` in the
    turned base frame.

    Parameters
    ----------
    model : RobotModel
    T_r_f : array_like, shape (N, 4, 4)
        Flange poses in {R}, mm.
    joint : int
        1-based joint the finding is about (for the text).

    Returns
    -------
    Advice
        ``turn_deg`` positive counter-clockwise; ``verified`` False when no
        turn up to 180 degrees works.
    """
    T_r_f = np.asarray(T_r_f, float).reshape(-1, 4, 4)
    T_check = _sample(T_r_f, 0)
    for alpha in np.arange(TURN_STEP_DEG, 180.0 + 1e-9, TURN_STEP_DEG):
        for signed in (alpha, -alpha):
            if bool(reachable(model, _rz(-signed) @ T_check).all()):
                way = "counter-clockwise" if signed > 0 else "clockwise"
                side = "left" if signed < 0 else "right"
                return Advice(None, float(signed), True,
                              "Turn the robot at least %.0f deg %s about its Z axis (seen from "
                              "above), or move the part to the robot's %s by as much about axis 1."
                              % (abs(signed), way, side))
    return Advice(None, None, False,
                  "No turn of the robot about its Z axis brings J%d within its limits: change the "
                  "tool orientation (the tool markers) or let Place robot search a base." % joint)


def _rz(angle_deg):
    a = np.radians(angle_deg)
    T = np.eye(4)
    T[:2, :2] = [[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]]
    return T


def advise(model, T_r_f, kind, joint=None, T_u_r=None):
    """Advice for a group of failing targets, or None when no move helps this kind.

    Parameters
    ----------
    model : RobotModel
    T_r_f : array_like, shape (N, 4, 4)
        Flange poses of the group's targets in {R}, mm.
    kind : str
        ``"unreachable"`` or ``"joint_limit"`` (other kinds: None).
    joint : int, optional
        1-based joint of a joint-limit finding: 1 gets a turn, 2 and 3 a
        translation, 4 to 6 (the wrist) None.
    T_u_r : array_like, shape (4, 4), optional
        Robot base in {U}.

    Returns
    -------
    Advice or None
    """
    if kind == "unreachable" or (kind == "joint_limit" and joint in (2, 3)):
        return translation_advice(model, T_r_f, T_u_r)
    if kind == "joint_limit" and joint == 1:
        return turn_advice(model, T_r_f, joint)
    return None
