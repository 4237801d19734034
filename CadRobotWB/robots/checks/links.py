"""Link frames and simple link solids of the catalog robots.

A robot is drawn and collision-checked as seven rigid bodies: the fixed base
(link 0) and links 1 to 6, link i being the body that joint i moves.

* :func:`link_frames` (of :mod:`CadRobotWB.robots.kinematics.link_frames`,
  with its frame conventions; also reachable here) gives, for joint values,
  the pose in the robot base frame {R} of a frame attached to each body,
  ``(N, 7, 4, 4)``.  Frame 0 is {R} itself and frame 6 is the flange {F}:
  ``link_frames(...)[:, 6]`` equals ``model.fk(q)`` (the fixed offset from
  link 6 to the flange is the identity).
* :func:`link_solids` gives one watertight mesh per body in its own frame,
  sized from the kinematic parameters: base cylinder, turret and shoulder,
  upper-arm capsule from J2 to J3, elbow housing, forearm capsule from J3 to
  the wrist (OPW robots: its last part, link 4, a fork whose two prongs hold
  the J5 housing, so the flange can swing between them), wrist cylinders and
  the flange disc.  Radii are fractions of the arm length
  (:data:`RADIUS_FRACTIONS`).  Placed with ``frames[n, i] @ vertex`` they
  draw the robot at pose n.  An arm of kind ``chain`` (axes and steps) is a
  capsule per link along the shortest way between its joint axes.  UR arms are
  drawn in the plane of their DH
  model: the real shoulder and elbow side offsets are left out, so the upper
  arm cannot swing past the base as the real one does.
* :func:`link_parts` gives the same solids as convex pieces (what
  :mod:`.collision` hands to FCL).
* :func:`tool_solid` gives a torch-like solid from the flange to
  ``clearance_mm`` short of the TCP.

The solids are laid out once in {R} at the reference pose q = 0 from the
joint positions (for ``dh+opw`` robots from their equivalent OPW chain: same
physical joints) and then expressed in each link's frame, so they are right
in every convention.

Lengths in mm, angles in degrees at the interface.  Pure numpy + trimesh:
never imports FreeCAD.
"""

import numpy as np

from ... import dependencies
from ...core.frames import invert_transform
from ..kinematics import chain_geometry
from ..kinematics.chain_geometry import nearest_between_lines, nearest_on_line
from ..kinematics.link_frames import (LINK_NAMES, link_frames, opw_link_frames,  # noqa: F401
                                      robot_model, ur_link_frames)
from ..urdf import link_meshes

trimesh = dependencies.require("trimesh")

#: Facets around a cylinder or capsule (chord error 2 % of the radius).
SECTIONS = 16


# ------------------------------------------------------------------ primitive solids

def _align_z(origin, direction):
    """(4, 4) frame at `origin` whose z axis is the unit `direction`."""
    T = trimesh.geometry.align_vectors([0.0, 0.0, 1.0], direction)
    T[:3, 3] = origin
    return T


def cylinder(p0, p1, radius):
    """Closed cylinder whose axis runs from `p0` to `p1` (mm).

    Parameters
    ----------
    p0, p1 : array_like, shape (3,)
        Centres of the two end faces.
    radius : float

    Returns
    -------
    trimesh.Trimesh
        Watertight and convex, :data:`SECTIONS` facets around.
    """
    return trimesh.creation.cylinder(radius=radius, segment=np.array([p0, p1], dtype=float),
                                     sections=SECTIONS)


def capsule(p0, p1, radius):
    """Capsule (cylinder with hemispherical ends) whose axis runs from `p0` to `p1`.

    Parameters
    ----------
    p0, p1 : array_like, shape (3,)
        Centres of the two hemispheres, mm (equal points give a sphere).
    radius : float

    Returns
    -------
    trimesh.Trimesh
        Watertight and convex.
    """
    p0, p1 = np.asarray(p0, dtype=float), np.asarray(p1, dtype=float)
    axis = p1 - p0
    length = np.linalg.norm(axis)
    if length < 1e-6:
        axis = np.array([0.0, 0.0, 1.0])
    mesh = trimesh.creation.capsule(height=length, radius=radius, count=[SECTIONS, SECTIONS // 2])
    # Put the first hemisphere's centre on the origin (trimesh versions differ here).
    mesh.apply_translation([0.0, 0.0, -(mesh.bounds[0, 2] + radius)])
    return mesh.apply_transform(_align_z(p0, axis))


def _housing(centre, axis, radius, half_width):
    """Joint housing: a cylinder of `radius` about `axis`, centred on `centre`."""
    axis = np.asarray(axis, dtype=float)
    return cylinder(centre - half_width * axis, centre + half_width * axis, radius)


# ------------------------------------------------------------------ link solids

#: Solid radii as fractions of the arm length L (upper arm + forearm): for a
#: 1.5 m robot (ABB IRB 2400, L = 1472 mm) base 125, turret 110, upper arm 88,
#: forearm 66, wrist 54-59, flange 44 mm.
RADIUS_FRACTIONS = dict(base=0.085, turret=0.075, upper_arm=0.06, forearm=0.045,
                        wrist=0.04, flange=0.03)


def _radii(arm_length, wrist_to_flange):
    r = {name: f * arm_length for name, f in RADIUS_FRACTIONS.items()}
    flange_thickness = 0.15 * wrist_to_flange
    # The wrist housing must stay behind the flange disc.
    r["wrist"] = min(r["wrist"], 0.75 * (wrist_to_flange - flange_thickness))
    r["flange"] = min(r["flange"], r["wrist"])
    return r, flange_thickness


def _fork_prong(tube_end, wrist, x_dir, y_dir, y_offset, thickness, radius):
    """One prong of the wrist fork: from the forearm tube's end to a disc on the J5 axis."""
    centre = 0.5 * (tube_end + wrist) + y_offset * y_dir
    frame = np.eye(4)
    frame[:3, :3] = np.column_stack([x_dir, y_dir, np.cross(x_dir, y_dir)])
    frame[:3, 3] = centre
    length = np.linalg.norm(wrist - tube_end)
    plate = trimesh.creation.box([2.0 * radius, thickness, length], transform=frame)
    disc = _housing(wrist + y_offset * y_dir, y_dir, radius, 0.5 * thickness)
    return trimesh.util.concatenate([plate, disc]).convex_hull


def _opw_parts_in_base(params):
    """Convex pieces of the 7 bodies of an OPW robot, in {R} at q = 0 (list of 7 lists)."""
    p = params
    F = opw_link_frames(p, np.zeros((1, 6)))[0]
    origin = [F[i][:3, 3] for i in range(7)]
    r, t6 = _radii(p.c2 + np.hypot(p.a2, p.c3), p.c4)
    base_top = 0.4 * p.c1
    j2, elbow, wrist, flange = origin[2], origin[3], origin[4], origin[6]
    forearm_start = (F[3] @ [p.a2, 0.0, 0.0, 1.0])[:3]   # on the J4 axis, level with J3
    forearm_dir = F[4][:3, 2]
    j5_dir = F[5][:3, 1]
    j6_dir = F[6][:3, 2]
    flange_back = flange - t6 * j6_dir
    # Link 4 is the wrist fork: a tube ending where the wrist (link 5, flange, tool) can
    # swing past it, and two prongs beside the J5 housing.
    swing = np.hypot(p.c4, r["flange"]) + 0.1 * r["wrist"]
    tube_end = wrist - swing * forearm_dir
    forearm_split = forearm_start + min(0.5 * p.c3, p.c3 - 1.5 * swing) * forearm_dir
    prong = 0.35 * r["wrist"]
    prong_offset = 1.1 * r["wrist"] + 0.5 * prong
    fork_x = np.cross(j5_dir, forearm_dir)
    return [
        [cylinder([0, 0, 0], [0, 0, base_top], r["base"])],
        [cylinder([0, 0, base_top], [0, 0, p.c1], r["turret"]),
         capsule([0, 0, p.c1], j2, r["turret"]),
         _housing(j2, F[2][:3, 1], r["turret"], r["turret"])],
        [capsule(j2, elbow, r["upper_arm"])],
        [_housing(elbow, F[3][:3, 1], r["upper_arm"], r["upper_arm"]),
         capsule(elbow, forearm_start, r["forearm"]),
         capsule(forearm_start, forearm_split, r["forearm"])],
        [cylinder(forearm_split, tube_end, r["wrist"]),
         _fork_prong(tube_end, wrist, fork_x, j5_dir, prong_offset, prong, r["wrist"]),
         _fork_prong(tube_end, wrist, fork_x, j5_dir, -prong_offset, prong, r["wrist"])],
        [_housing(wrist, j5_dir, r["wrist"], r["wrist"]),
         cylinder(wrist, flange_back, r["flange"])],
        [cylinder(flange_back, flange, r["flange"])],
    ]


def _ur_parts_in_base(params):
    """Convex pieces of the 7 bodies of a UR arm, in {R} at q = 0 (list of 7 lists)."""
    p = params
    F = ur_link_frames(p, np.zeros((1, 6)))[0]
    o = [F[i][:3, 3] for i in range(7)]
    z = [F[i][:3, 2] for i in range(7)]   # z of frame i is the axis of joint i + 1
    r, t6 = _radii(abs(p.a2) + abs(p.a3), p.d6)
    base_top = np.array([0.0, 0.0, 0.5 * p.d1])
    flange_back = o[6] - t6 * z[5]
    return [
        [cylinder([0, 0, 0], base_top, r["base"])],
        [cylinder(base_top, o[1], r["turret"]),
         _housing(o[1], z[1], r["turret"], r["turret"])],
        [capsule(o[1], o[2], r["upper_arm"]),
         _housing(o[2], z[2], r["upper_arm"], r["upper_arm"])],
        [capsule(o[2], o[3], r["forearm"]),
         _housing(o[3], z[3], r["forearm"], r["forearm"])],
        [cylinder(o[3], o[4], r["wrist"]),
         _housing(o[4], z[4], r["wrist"], r["wrist"])],
        [cylinder(o[4], o[5], r["wrist"]),
         cylinder(o[5] - r["wrist"] * z[5], flange_back, r["wrist"])],
        [cylinder(flange_back, o[6], r["flange"])],
    ]


def _link(p0, p1, radius, round_ends=True):
    """A capsule (or cylinder) from `p0` to `p1`, or a sphere where they coincide."""
    if np.linalg.norm(p1 - p0) < 1e-3:
        return capsule(p0, p0, radius)
    return capsule(p0, p1, radius) if round_ends else cylinder(p0, p1, radius)


def _chain_parts_in_base(params):
    """Convex pieces of the 7 bodies of an arm given as axes and steps (kind ``chain``),
    in {R} at q = 0 (list of 7 lists): each link a capsule along the shortest way
    from its joint's axis to the next one's, with a housing on every axis."""
    H = params.H
    c = chain_geometry.axis_points(params)
    flange = c[5] + params.P[6]
    foot = nearest_on_line(np.zeros(3), c[0], H[0])
    shoulder_1 = nearest_between_lines(c[0], H[0], c[1], H[1])   # on axis 1, level with axis 2
    shoulder = nearest_between_lines(c[1], H[1], c[0], H[0])     # on axis 2
    elbow = nearest_on_line(shoulder, c[2], H[2])                # on axis 3 (parallel to axis 2)
    forearm = nearest_between_lines(c[3], H[3], c[2], H[2])      # on axis 4
    wrist = chain_geometry.wrist_point(params)                   # axes 4 and 5
    wrist_6 = nearest_between_lines(c[4], H[4], c[5], H[5])      # on axis 5, nearest axis 6
    arm_length = np.linalg.norm(elbow - shoulder) + np.linalg.norm(wrist - elbow)
    r = {name: f * arm_length for name, f in RADIUS_FRACTIONS.items()}
    r["flange"] = r["wrist"] = min(r["wrist"], 0.5 * max(np.linalg.norm(flange - wrist_6), 1.0))
    flange_back = flange - min(0.15 * np.linalg.norm(flange - wrist_6), 0.3 * r["flange"]) * H[5]
    base_top = foot + 0.4 * (shoulder_1 - foot)
    forearm_split = forearm + 0.5 * (wrist - forearm)
    return [
        [cylinder(foot, base_top, r["base"]) if np.linalg.norm(base_top - foot) > 1e-3
         else _housing(foot, H[0], r["base"], 0.05 * r["base"])],
        [_link(base_top, shoulder_1, r["turret"]), _link(shoulder_1, shoulder, r["turret"]),
         _housing(shoulder, H[1], r["turret"], r["turret"])],
        [_link(shoulder, elbow, r["upper_arm"])],
        [_housing(elbow, H[2], r["upper_arm"], r["upper_arm"]),
         _link(elbow, forearm, r["forearm"]), _link(forearm, forearm_split, r["forearm"])],
        [_link(forearm_split, wrist, r["wrist"], round_ends=False),
         _housing(wrist, H[4], r["wrist"], r["wrist"])],
        [_link(wrist, wrist_6, r["wrist"]), _link(wrist_6, flange_back, r["wrist"], round_ends=False)],
        [cylinder(flange_back, flange, r["flange"])],
    ]


def link_parts(spec):
    """Convex pieces of each body, each in its link's frame.

    Parameters
    ----------
    spec : RobotSpec, RobotModel or str
        The robot (see :func:`robot_model`).

    Returns
    -------
    parts : list of 7 lists of trimesh.Trimesh
        ``parts[i]`` are the convex, watertight pieces of body i
        (:data:`LINK_NAMES`) in frame i of :func:`link_frames`, mm.
    """
    robot = robot_model(spec)
    if robot.kind == "ur":
        parts_r = _ur_parts_in_base(robot.spec.ur)
    elif robot.kind == "chain":
        parts_r = _chain_parts_in_base(robot.params)
    else:  # "opw" and "dh+opw": the physical joints are those of the OPW chain
        parts_r = _opw_parts_in_base(robot.spec.opw)
    T_r_base = np.eye(4) if robot.spec.T_root_base is None else np.array(robot.spec.T_root_base)
    T_r_link = link_frames(robot, np.zeros(6))
    parts = []
    for i, pieces in enumerate(parts_r):
        T_link_base = invert_transform(T_r_link[i]) @ T_r_base
        parts.append([piece.apply_transform(T_link_base) for piece in pieces])
    if robot.spec.meshes:
        parts = link_meshes.replace_parts(parts, robot.spec.meshes)
    return parts


def link_solids(spec):
    """One simple solid per body, each in its link's frame.

    Parameters
    ----------
    spec : RobotSpec, RobotModel or str
        The robot (see :func:`robot_model`).

    Returns
    -------
    solids : list of 7 trimesh.Trimesh
        Base and links 1..6 (:data:`LINK_NAMES`), each in frame i of
        :func:`link_frames`, mm.  Each is watertight: the convex pieces of
        :func:`link_parts` put together (they overlap; not a boolean union).
        Draw body i at pose n with ``solids[i].copy().apply_transform(frames[n, i])``.
    """
    return [trimesh.util.concatenate(pieces) for pieces in link_parts(spec)]


def tool_solid(T_f_t, radius_mm=20.0, clearance_mm=15.0):
    """A torch-like tool solid from the flange towards the TCP.

    A cylinder of `radius_mm` starts on the flange face and runs along the
    line from the flange origin to the TCP; its last ``2 * radius_mm`` taper
    to a cone whose tip stops `clearance_mm` short of the TCP.  So every
    point of the solid is at least `clearance_mm` from the TCP, and a surface
    through the TCP (a weld seam's plates) is not touched while it is tilted
    less than ``90 - atan(1/2) = 63.4`` degrees from the tool line.

    Parameters
    ----------
    T_f_t : array_like, shape (4, 4)
        TCP in the flange frame, mm.
    radius_mm : float
    clearance_mm : float

    Returns
    -------
    trimesh.Trimesh or None
        Convex, watertight, in the flange frame; None when the TCP is within
        `clearance_mm` of the flange origin (no tool to check).
    """
    tcp = np.asarray(T_f_t, dtype=float)[:3, 3]
    distance = np.linalg.norm(tcp)
    length = distance - clearance_mm
    if length <= 1e-6:
        return None
    cone = min(2.0 * radius_mm, length)
    profile = [[0.0, 0.0], [radius_mm, 0.0], [radius_mm, length - cone], [0.0, length]]
    if length - cone <= 1e-9:
        profile = [[0.0, 0.0], [radius_mm, 0.0], [0.0, length]]
    mesh = trimesh.creation.revolve(profile, sections=SECTIONS)
    return mesh.apply_transform(_align_z(np.zeros(3), tcp / distance))
