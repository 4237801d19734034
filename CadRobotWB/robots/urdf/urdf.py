"""Read a URDF robot description and the serial chain of a six-axis arm in it.

A URDF (ROS's Unified Robot Description Format, an XML file) describes a robot
as links joined by joints; each joint has an ``origin`` (the pose of the joint
frame in its parent link's frame, ``xyz`` in metres and ``rpy`` in radians,
``R = Rz(yaw) Ry(pitch) Rx(roll)``), an ``axis`` and ``limit`` values
(``lower``/``upper`` in rad, ``velocity`` in rad/s).  See
http://wiki.ros.org/urdf/XML/joint.

:func:`read_urdf` parses the file into plain data (lengths converted to mm
here, once); :func:`serial_chain` picks the chain from the root link to the
flange (``tool0``, else the last link) with its six actuated joints;
:func:`chain_frames` computes the pose of every link of that chain for
arrays of joint values.  The chain is the reference every kinematic model
built from a URDF is checked against (:mod:`.identify`).

Pure Python and numpy: never imports FreeCAD.
"""

import xml.etree.ElementTree as ElementTree
from dataclasses import dataclass, field
from typing import Optional, Tuple

import numpy as np

from ...core.rotations import matrix_from_axis_angle
from ...errors import InputError, one_line
from .package_files import refuse_declarations

#: Metres to millimetres.
MM_PER_M = 1000.0

# Bounds of what a URDF may hold (README, "Your own arm from its URDF"): past one,
# the file is refused with one line naming the element and attribute.
#: Largest URDF (or xacro) file read, bytes: the biggest arm of the data folder is 40 kB.
MAX_FILE_BYTES = 10 * 10 ** 6
#: Most links in a file (industrial arms have 8-20; the chain search is quadratic in them).
MAX_LINKS = 200
#: Most collision shapes in a file (each may name a mesh to read).
MAX_COLLISIONS = 1000
#: Largest length (origin xyz, box size, cylinder and sphere dimensions), metres.
MAX_LENGTH_M = 100.0
#: Largest angle of an origin rpy or mimic offset, radians (any turn is within +-2 pi).
MAX_ANGLE_RAD = 100.0
#: Largest joint limit, radians (10 turns each way).
MAX_JOINT_LIMIT_RAD = 20 * np.pi
#: Largest joint speed, rad/s (about 5700 deg/s; arms move at most about 1000 deg/s).
MAX_JOINT_SPEED_RAD_S = 100.0
#: Largest mesh scale factor, axis component and mimic multiplier.
MAX_SCALE = 1000.0
#: Smallest box side, cylinder or sphere dimension (metres) and mesh scale factor: below
#: a micrometre a link's solid has no volume to check collisions with.
MIN_SIZE = 1e-6
#: The joint types of the URDF specification.
JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")


@dataclass(frozen=True)
class Geometry:
    """A collision shape of a link, in the link's frame (mm).

    Attributes
    ----------
    kind : str
        ``"mesh"``, ``"box"``, ``"cylinder"`` or ``"sphere"``.
    T_link_geom : ndarray, shape (4, 4)
        Pose of the shape in its link's frame, mm.
    filename : str
        The mesh reference as the URDF writes it (``package://...``), for meshes.
    scale : tuple of 3 float
        Mesh scale factors (a mesh's own unit is usually metres).
    size_mm : tuple of float
        Box sides (3), cylinder (radius, length) or sphere (radius,), mm.
    """

    kind: str
    T_link_geom: np.ndarray
    filename: str = ""
    scale: Tuple[float, float, float] = (1.0, 1.0, 1.0)
    size_mm: Tuple[float, ...] = ()


@dataclass(frozen=True)
class Joint:
    """One URDF joint.

    Attributes
    ----------
    name, kind, parent, child : str
        ``kind`` is the URDF type: revolute, continuous, prismatic, fixed, ...
    T_parent_joint : ndarray, shape (4, 4)
        The joint frame in the parent link's frame at joint value 0, mm.
    axis : ndarray, shape (3,)
        Unit rotation axis in the joint frame.
    lower_rad, upper_rad : float or None
        Position limits (None for a continuous joint).
    velocity_rad_s : float or None
    mimic : tuple (str, float, float) or None
        ``(joint, multiplier, offset_rad)``: this joint's value is
        ``multiplier * value(joint) + offset``.
    """

    name: str
    kind: str
    parent: str
    child: str
    T_parent_joint: np.ndarray
    axis: np.ndarray
    lower_rad: Optional[float] = None
    upper_rad: Optional[float] = None
    velocity_rad_s: Optional[float] = None
    mimic: Optional[Tuple[str, float, float]] = None

    @property
    def movable(self):
        """bool: True unless the joint is fixed."""
        return self.kind != "fixed"


@dataclass(frozen=True)
class UrdfRobot:
    """A parsed URDF: its name, links (with collision shapes) and joints.

    Attributes
    ----------
    name : str
    collisions : dict of str to tuple of Geometry
        Collision shapes per link name (empty tuple for a link without any).
    joints : dict of str to Joint
    path : str
        The file it was read from ("" for text).
    """

    name: str
    collisions: dict
    joints: dict
    path: str = ""

    @property
    def root(self):
        """str: the link that is no joint's child."""
        children = {j.child for j in self.joints.values()}
        roots = [name for name in self.collisions if name not in children]
        return roots[0]


@dataclass(frozen=True)
class Chain:
    """The serial chain of a six-axis arm, from the root link to the flange.

    Attributes
    ----------
    root, tip : str
        First and last link names; ``tip`` is the flange frame.
    joint_names : tuple of 6 str
        The actuated joints, base to flange.
    T_prev_joint : ndarray, shape (6, 4, 4)
        Joint i's frame in the frame of joint i - 1 (of the root link for
        i = 0) at zero joint values, mm: the fixed joints between are folded in.
    axes : ndarray, shape (6, 3)
        Unit axis of each joint in its own frame.
    T_joint6_tip : ndarray, shape (4, 4)
        The flange (tip link) in joint 6's frame, mm.
    lower_rad, upper_rad : ndarray, shape (6,)
        Joint limits (+-2 pi for a continuous joint).
    velocity_rad_s : ndarray, shape (6,)
        Joint speed limits (NaN where the URDF gives none).
    body_links : tuple of 7 tuples of (str, ndarray (4, 4))
        The links rigidly attached to the root (body 0) and to each joint's
        frame (bodies 1-6), each with its pose in that frame, mm.
    tip_note : str
        How the flange was chosen, for messages ("tool0", or which link
        became the flange when there is no tool0).
    """

    root: str
    tip: str
    joint_names: Tuple[str, ...]
    T_prev_joint: np.ndarray
    axes: np.ndarray
    T_joint6_tip: np.ndarray
    lower_rad: np.ndarray
    upper_rad: np.ndarray
    velocity_rad_s: np.ndarray
    body_links: Tuple = field(default_factory=tuple)
    tip_note: str = ""


# ------------------------------------------------------------------ parsing

def transform_from_xyz_rpy(xyz_mm, rpy_rad):
    """The URDF origin transform ``Trans(xyz) Rz(yaw) Ry(pitch) Rx(roll)``.

    Parameters
    ----------
    xyz_mm : array_like, shape (3,)
    rpy_rad : array_like, shape (3,)
        Roll, pitch, yaw (fixed axes X, Y, Z), radians.

    Returns
    -------
    ndarray, shape (4, 4)
    """
    r, p, y = rpy_rad
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    T = np.eye(4)
    T[:3, :3] = [[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                 [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                 [-sp, cp * sr, cp * cr]]
    T[:3, 3] = xyz_mm
    return T


def _floats(text, count, what, default, bound=MAX_LENGTH_M):
    """`count` finite numbers of an attribute, each within +-`bound` (`default` when absent)."""
    if text is None:
        return default
    try:
        values = tuple(float(v) for v in text.split())
    except ValueError:
        values = ()
    if len(values) != count or not all(abs(v) <= bound for v in values):   # NaN fails too
        wanted = ("a finite number" if count == 1 else "%d finite numbers, each" % count)
        raise InputError("%s is '%s': give %s within +-%.4g; fix the URDF."
                         % (what, _shown(text), wanted, bound))
    return values


def _shown(text):
    """`text` of an attribute for a one-line message: control characters escaped
    (a line break as ``\\n``), cut to 40 characters."""
    text = one_line(text)
    return text if len(text) <= 40 else text[:37] + "..."


def _required(element, attribute, what):
    """The text of a required attribute; InputError naming it when missing or empty."""
    value = element.get(attribute)
    if not value or not value.strip():
        raise InputError("%s has no %s attribute: a URDF requires it; add it." % (what, attribute))
    return value


def _positive(element, attribute, what, bound):
    """A required number in (0, `bound`]."""
    text = _required(element, attribute, what)
    value, = _floats(text, 1, "%s %s" % (what, attribute), None, bound)
    if value < MIN_SIZE:
        raise InputError("%s %s is '%s': it must be at least %g m; fix the URDF."
                         % (what, attribute, _shown(text), MIN_SIZE))
    return value


def _origin(element, what):
    origin = element.find("origin") if element is not None else None
    if origin is None:
        return np.eye(4)
    xyz = _floats(origin.get("xyz"), 3, what + " origin xyz", (0.0, 0.0, 0.0))
    rpy = _floats(origin.get("rpy"), 3, what + " origin rpy", (0.0, 0.0, 0.0), MAX_ANGLE_RAD)
    return transform_from_xyz_rpy(np.multiply(xyz, MM_PER_M), rpy)


def _geometry(collision, what):
    T = _origin(collision, what)
    geometry = collision.find("geometry")
    shape = list(geometry)[0] if geometry is not None and len(geometry) else None
    if shape is None:
        return None
    what = "%s %s" % (what, shape.tag)
    if shape.tag == "mesh":
        scale = _floats(shape.get("scale"), 3, what + " scale", (1.0, 1.0, 1.0), MAX_SCALE)
        if min(scale) < MIN_SIZE:
            raise InputError("%s scale is '%s': every factor must be at least %g; fix the URDF."
                             % (what, _shown(shape.get("scale")), MIN_SIZE))
        return Geometry("mesh", T, filename=_required(shape, "filename", what), scale=scale)
    if shape.tag == "box":
        size = _floats(_required(shape, "size", what), 3, what + " size", None)
        if min(size) < MIN_SIZE:
            raise InputError("%s size is '%s': every side must be at least %g m; fix the URDF."
                             % (what, _shown(shape.get("size")), MIN_SIZE))
        return Geometry("box", T, size_mm=tuple(np.multiply(size, MM_PER_M)))
    if shape.tag == "cylinder":
        radius = _positive(shape, "radius", what, MAX_LENGTH_M)
        length = _positive(shape, "length", what, MAX_LENGTH_M)
        return Geometry("cylinder", T, size_mm=(radius * MM_PER_M, length * MM_PER_M))
    if shape.tag == "sphere":
        return Geometry("sphere", T, size_mm=(_positive(shape, "radius", what, MAX_LENGTH_M) * MM_PER_M,))
    return None


def _limits(limit, kind, what):
    """``(lower_rad, upper_rad, velocity_rad_s)`` of a joint's ``<limit>`` (None where absent).

    Refuses values that are not finite or out of bounds, an empty range
    (lower >= upper) on a revolute joint and a negative speed (a speed of 0,
    which real files give passive joints, is refused on the arm's joints by
    :func:`serial_chain`)."""
    if limit is None:
        return None, None, None
    what = what + " limit"
    lower, upper = (None if limit.get(side) is None else
                    _floats(limit.get(side), 1, "%s %s" % (what, side), None, MAX_JOINT_LIMIT_RAD)[0]
                    for side in ("lower", "upper"))
    if kind == "revolute" and lower is not None and upper is not None and lower >= upper:
        raise InputError("%s lower '%s' is not below upper '%s': the joint could not move; give "
                         "lower < upper (radians)." % (what, _shown(limit.get("lower")), _shown(limit.get("upper"))))
    velocity = limit.get("velocity")
    if velocity is not None:
        velocity, = _floats(velocity, 1, what + " velocity", None, MAX_JOINT_SPEED_RAD_S)
        if velocity < 0:
            raise InputError("%s velocity is '%s': it must be above 0; fix the URDF."
                             % (what, _shown(limit.get("velocity"))))
    return lower, upper, velocity


def _mimic(element, what):
    if element is None:
        return None
    what += " mimic"
    multiplier, = _floats(element.get("multiplier"), 1, what + " multiplier", (1.0,), MAX_SCALE)
    offset, = _floats(element.get("offset"), 1, what + " offset", (0.0,), MAX_ANGLE_RAD)
    return _required(element, "joint", what), multiplier, offset


def _joint(element):
    name = _required(element, "name", "A URDF <joint>")
    what = "URDF joint '%s'" % name
    kind = _required(element, "type", what)
    if kind not in JOINT_TYPES:
        raise InputError("%s type is '%s': a URDF joint is one of %s; fix the URDF."
                         % (what, _shown(kind), ", ".join(JOINT_TYPES)))
    parent, child = element.find("parent"), element.find("child")
    if parent is None or child is None:
        raise InputError("%s has no parent or child link: the file is not a valid URDF." % what)
    axis_element = element.find("axis")
    axis = np.array(_floats(None if axis_element is None else axis_element.get("xyz"), 3,
                            what + " axis xyz", (1.0, 0.0, 0.0), MAX_SCALE))
    if kind != "fixed":
        length = np.linalg.norm(axis)
        if length < 1e-12:
            raise InputError("%s has a zero axis: give it a direction (axis xyz)." % what)
        axis = axis / length
    lower, upper, velocity = _limits(element.find("limit"), kind, what)
    return Joint(
        name=name, kind=kind, parent=_required(parent, "link", what + " parent"),
        child=_required(child, "link", what + " child"),
        T_parent_joint=_origin(element, what), axis=axis,
        lower_rad=lower, upper_rad=upper, velocity_rad_s=velocity,
        mimic=_mimic(element.find("mimic"), what))


def _read_text(source):
    """``(text, path)`` of a URDF path or text, refused past :data:`MAX_FILE_BYTES`."""
    if source.lstrip().startswith("<"):
        text, path = source, ""
    else:
        path = source
        try:
            with open(source, "rb") as stream:
                text = stream.read(MAX_FILE_BYTES + 1)
        except OSError as exc:
            raise InputError("Cannot read the URDF file '%s': %s." % (source, exc.strerror)) from None
    if len(text) > MAX_FILE_BYTES:
        raise InputError("%s is larger than %d MB, the most CadRobot reads of a URDF: a robot arm "
                         "needs far less; give the arm's own URDF."
                         % ("'%s'" % path if path else "The URDF text", MAX_FILE_BYTES // 10 ** 6))
    return text, path


def _unique(names, kind, label):
    """Refuse a name given to two links (or joints)."""
    seen = set()
    for name in names:
        if name in seen:
            raise InputError("%s defines two %ss named '%s': each needs its own name; fix the "
                             "URDF." % (label, kind, name))
        seen.add(name)


def _check_counts(xml, label):
    """Refuse more links or collision shapes than the bounds, and two links of one name."""
    links = xml.findall("link")
    shapes = sum(len(link.findall("collision")) for link in links)
    for count, bound, what in ((len(links), MAX_LINKS, "links"),
                               (shapes, MAX_COLLISIONS, "collision shapes")):
        if count > bound:
            raise InputError("%s has %d %s, more than the %d CadRobot reads: give a six-axis "
                             "arm's own URDF." % (label, count, what, bound))
    _unique((link.get("name") for link in links), "link", label)
    _unique((joint.get("name") for joint in xml.findall("joint")), "joint", label)


def read_urdf(source):
    """Parse a URDF file (or its text).

    Parameters
    ----------
    source : str
        A file path, or the XML text itself (starting with ``<``).

    Returns
    -------
    UrdfRobot

    Raises
    ------
    InputError
        The file cannot be read, is larger than :data:`MAX_FILE_BYTES`,
        declares a DTD or entities, is not XML, is a xacro file (expand it
        first), has more than :data:`MAX_LINKS` links, a value that is not a
        finite number within its bound (the message names the element and
        the attribute), a missing required attribute, an empty joint range
        or a speed not above 0, or its links and joints do not form one tree.
    """
    text, path = _read_text(source)
    label = "'%s'" % path if path else "the URDF text"
    refuse_declarations(text, label)
    try:
        xml = ElementTree.fromstring(text)
    except ElementTree.ParseError as exc:
        raise InputError("%s is not valid XML (%s): give a URDF file." % (label, exc)) from None
    if xml.tag != "robot":
        raise InputError("%s is not a URDF: its top element is <%s>, not <robot>." % (label, xml.tag))
    if any(element.tag.startswith("{http://www.ros.org/wiki/xacro}") for element in xml.iter()):
        raise InputError("%s still contains xacro macros: expand it first "
                         "(xacro FILE.xacro -o FILE.urdf) or import the .xacro file "
                         "with the 'xacro' Python package installed." % label)
    robot_name = _required(xml, "name", "The <robot> element of %s" % label)
    _check_counts(xml, label)
    collisions = {}
    for link in xml.findall("link"):
        name = _required(link, "name", "A URDF <link>")
        shapes = (_geometry(c, "URDF link '%s' collision" % name) for c in link.findall("collision"))
        collisions[name] = tuple(s for s in shapes if s is not None)
    joints = {}
    for element in xml.findall("joint"):
        joint = _joint(element)
        for link in (joint.parent, joint.child):
            if link not in collisions:
                raise InputError("URDF joint '%s' names the link '%s', which the file does not "
                                 "define." % (joint.name, link))
        joints[joint.name] = joint
    _check_tree(collisions, joints, label)
    return UrdfRobot(robot_name, collisions, joints, path)


def _check_tree(links, joints, label):
    """Refuse links and joints that are not one tree: one root, one parent joint per
    link, every link reached from the root (a cycle is not)."""
    children = [j.child for j in joints.values()]
    roots = [name for name in links if name not in children]
    if len(roots) != 1 or len(set(children)) != len(children):
        raise InputError("%s: its links do not form one tree (roots: %s); a URDF has one root "
                         "link and each link one parent joint." % (label, ", ".join(roots) or "none"))
    reached, queue = set(roots), list(roots)
    while queue:
        parent = queue.pop()
        for joint in joints.values():
            if joint.parent == parent and joint.child not in reached:
                reached.add(joint.child)
                queue.append(joint.child)
    cut_off = [name for name in links if name not in reached]
    if cut_off:
        raise InputError("%s: the links %s are not reached from the root link '%s' (their "
                         "joints form a cycle); a URDF's links form one tree."
                         % (label, ", ".join(cut_off), roots[0]))


# ------------------------------------------------------------------ the serial chain

def _path_to(robot, tip):
    """The joints from the root to link `tip`, root first."""
    parent_joint = {j.child: j for j in robot.joints.values()}
    path = []
    link = tip
    while link in parent_joint:
        joint = parent_joint[link]
        path.append(joint)
        link = joint.parent
    return path[::-1]


def _default_tip(robot):
    """``tool0`` if present, else the deepest link: (name, note)."""
    if "tool0" in robot.collisions:
        return "tool0", "tool0"
    def movable_depth(link):
        return sum(1 for j in _path_to(robot, link) if j.movable)
    deepest = max(robot.collisions, key=lambda link: (movable_depth(link), len(_path_to(robot, link))))
    return deepest, ("the file has no tool0 link: the last link '%s' became the flange" % deepest)


def serial_chain(robot, tip=None):
    """The chain of a six-axis arm from the root link to the flange.

    Parameters
    ----------
    robot : UrdfRobot
    tip : str, optional
        The flange link; default ``tool0``, else the last link of the
        longest chain (:attr:`Chain.tip_note` says which).

    Returns
    -------
    Chain

    Raises
    ------
    InputError
        The chain does not have exactly six revolute joints, has a prismatic
        joint, or a joint on it copies another (a mimic joint inside the arm).
    """
    label = "URDF robot '%s'" % robot.name
    if tip is None:
        tip, note = _default_tip(robot)
    elif tip not in robot.collisions:
        raise InputError("%s has no link '%s' to use as the flange." % (label, tip))
    else:
        note = tip
    path = _path_to(robot, tip)
    movable = [j for j in path if j.movable]
    for joint in movable:
        if joint.mimic is not None:
            raise InputError("%s: joint '%s' copies joint '%s' inside the arm's chain (a mimic "
                             "joint): CadRobot does not model such arms." % (label, joint.name,
                                                                            joint.mimic[0]))
        if joint.velocity_rad_s == 0:
            raise InputError("URDF joint '%s' limit velocity is '0': it must be above 0 on the "
                             "arm's joints; give the joint's speed in rad/s." % joint.name)
        if joint.kind not in ("revolute", "continuous"):
            raise InputError("%s: joint '%s' on the chain to '%s' is %s; a six-axis arm has only "
                             "revolute joints." % (label, joint.name, tip, joint.kind))
    if len(movable) != 6:
        raise InputError("%s has %d movable joints from '%s' to '%s' (%s): CadRobot takes "
                         "six-axis arms." % (label, len(movable), robot.root, tip,
                                             ", ".join(j.name for j in movable) or "none"))
    T_prev_joint = np.empty((6, 4, 4))
    bodies = [[(robot.root, np.eye(4))]]
    T_fixed = np.eye(4)   # pose of the current link in the current body frame
    index = 0
    for joint in path:
        T = T_fixed @ joint.T_parent_joint
        if joint.movable:
            T_prev_joint[index] = T
            index += 1
            T_fixed = np.eye(4)
            bodies.append([(joint.child, np.eye(4))])
        else:
            T_fixed = T
            bodies[-1].append((joint.child, T))
    _attach_fixed_branches(robot, bodies)
    lower = np.array([-2 * np.pi if j.kind == "continuous" or j.lower_rad is None else j.lower_rad
                      for j in movable])
    upper = np.array([2 * np.pi if j.kind == "continuous" or j.upper_rad is None else j.upper_rad
                      for j in movable])
    velocity = np.array([np.nan if j.velocity_rad_s is None else j.velocity_rad_s for j in movable])
    return Chain(root=robot.root, tip=tip, joint_names=tuple(j.name for j in movable),
                 T_prev_joint=T_prev_joint, axes=np.array([j.axis for j in movable]),
                 T_joint6_tip=T_fixed, lower_rad=lower, upper_rad=upper,
                 velocity_rad_s=velocity,
                 body_links=tuple(tuple(body) for body in bodies), tip_note=note)


def _attach_fixed_branches(robot, bodies):
    """Add to each body the links hanging off it by fixed joints only (e.g. ``base``,
    ``flange``); links moved by joints off the chain (mimic levers, cylinders) are left out."""
    for body in bodies:
        queue = list(body)
        known = {name for name, _ in body}
        while queue:
            link, T = queue.pop()
            for joint in robot.joints.values():
                if joint.parent == link and joint.kind == "fixed" and joint.child not in known:
                    entry = (joint.child, T @ joint.T_parent_joint)
                    known.add(joint.child)
                    body.append(entry)
                    queue.append(entry)


def chain_frames(chain, q_rad):
    """Poses of the seven bodies' frames and of the flange, in the root link's frame.

    Parameters
    ----------
    chain : Chain
    q_rad : array_like, shape (N, 6)
        Joint values as the URDF defines them, radians.

    Returns
    -------
    T_root_body : ndarray, shape (N, 7, 4, 4)
        Frame 0 is the root link (the identity), frame i the frame of joint i
        (it moves with joint i), mm.
    T_root_tip : ndarray, shape (N, 4, 4)
        The flange, mm.
    """
    q = np.atleast_2d(np.asarray(q_rad, dtype=float))
    n = q.shape[0]
    frames = np.empty((n, 7, 4, 4))
    frames[:, 0] = np.eye(4)
    T = np.broadcast_to(np.eye(4), (n, 4, 4))
    for i in range(6):
        T = T @ chain.T_prev_joint[i]
        rotation = np.zeros((n, 4, 4))
        rotation[:, :3, :3] = matrix_from_axis_angle(chain.axes[i], q[:, i])
        rotation[:, 3, 3] = 1.0
        T = T @ rotation
        frames[:, i + 1] = T
    return frames, T @ chain.T_joint6_tip


def chain_fk(chain, q_rad):
    """The flange pose of the URDF chain.

    Parameters
    ----------
    chain : Chain
    q_rad : array_like, shape (N, 6)

    Returns
    -------
    T_root_tip : ndarray, shape (N, 4, 4)
        mm.
    """
    return chain_frames(chain, q_rad)[1]


def joint_lines(chain, q_rad=None):
    """Every joint axis as a line in the root frame.

    Parameters
    ----------
    chain : Chain
    q_rad : array_like, shape (6,), optional
        Joint values (default all zero).

    Returns
    -------
    points : ndarray, shape (6, 3)
        A point of each axis (the joint frame's origin), mm.
    directions : ndarray, shape (6, 3)
        Unit axis directions.
    """
    q = np.zeros(6) if q_rad is None else np.asarray(q_rad, dtype=float)
    frames = chain_frames(chain, q[None])[0][0]
    points = frames[1:, :3, 3]
    directions = np.einsum("nij,nj->ni", frames[1:, :3, :3], chain.axes)
    return points, directions
