"""The tool library: the tools a new cell can carry, as numbers and a body.

::

    tool = tools.get("Straight torch")
    tool.T_f_t            # (4, 4) TCP {T} in the flange frame {F}, mm
    tool.mass_kg          # kg
    tool.cog_mm           # (3,) centre of gravity in {F}, mm
    vertices, faces = tool.mesh()     # the body, (N, 3) mm in {F} and (M, 3) int

Every tool is a handful of simple solids (:class:`Solid`: cylinders, cones,
spheres, boxes), each placed in {F} with its own mass.  The tool's mass is
their sum and its centre of gravity their mass-weighted centroid, so the
numbers a post-processor writes (RAPID ``tooldata``, KRL ``$LOAD`` ...)
match the body drawn and checked for collisions.  The tip of every body ends
exactly at the TCP, and the TCP's +Z (the approach direction) points out of
the tool, into the work.

Dimensions and masses are typical of their kind, not one maker's datasheet:

* welding torches: a robot torch with its collision sensor / mounting flange
  (about 65 mm across, 95 mm long, ~0.9 kg), a 28 mm torch tube, a gas nozzle
  tapering to 16 mm and 15 mm of wire stick-out (the contact-tip-to-work
  distance of MIG/MAG welding); about 385-400 mm from flange to TCP and
  1.8-2.0 kg, as catalogue robot torches with 0, 22 or 45 degree necks are;
* the ball tool of force-controlled profile following (the paper, section 5.2:
  a ball-shaped tool behind a force/torque sensor): an 80 mm F/T sensor, a
  16 mm steel stem and a ball of radius :data:`BALL_RADIUS_MM` (the radius
  ``sensors/force_following.py`` models the contact with); the TCP is the
  ball's front point, where it touches the surface;
* the deburring spindle: a 70 mm electric spindle of about 2.6 kg on a
  bracket that offsets it 50 mm from the flange axis, a collet and a 8 mm
  ball-nosed burr; about 260 mm long and 3.3 kg.

Pure numpy + trimesh: never imports FreeCAD.
"""

from dataclasses import dataclass

import numpy as np

# --- torch angles of GMAW (MIG/MAG) on steel: the defaults of a new cell's tool markers ----
#
# Work angle: 45 degrees to each plate of a T-joint fillet (Goodheart-Willcox, "Modern
# Welding", 2020, section 8.11.2 "Fillet Weld on a T- or Inside Corner Joint": "The electrode
# should be held at a 45 deg work angle"; https://www.g-wonlinetextbooks.com/modern-welding-2020/249).
# A tool marker placed on an edge measures its work angle from the surface whose normal the
# picking finds; on a fillet that normal is the bisector of the two faces (objects/picking.py
# adjacent_normals), so 90 degrees to it *is* 45 degrees to each plate.
#
# Travel angle: a push angle of 5-15 degrees (machine makers' GMAW guides: "A travel angle of
# 5-15 deg is ideal and produces a good level of control over the weld pool. A travel angle
# greater than 20 deg will give an unstable arc", ArcCaptain MIG130 manual p. 14,
# https://www.easymanua.ls/arccaptain/mig130/manual?p=17, and Viper XCEL-ARC manual p. 17;
# Miller Electric OM-1318, section 7-4 "Gun angles and weld bead profiles", draws the push
# angle at 10 deg, https://www.manualsdir.com/manuals/120209/miller-electric-172-m-10-gun.html?page=31).
# The default is the middle of that range, pushing (the tool leans towards the travel direction).

#: Default work angle of a torch marker to the surface picked (on a fillet: its bisector), degrees.
GMAW_WORK_ANGLE_DEG = 90.0
#: Default travel (push) angle of a torch marker, degrees; positive = pushing.
GMAW_TRAVEL_ANGLE_DEG = 10.0

from ... import dependencies
from ...errors import UnknownNameError

#: The choice of a cell whose tool is a document solid (or only numbers).
CUSTOM = "Custom body"

#: The tool a new cell gets.
DEFAULT = "Straight torch"

#: Radius of the ball tool's ball, mm (the force-following simulation's default).
BALL_RADIUS_MM = 5.0

#: Sections of a revolved solid's mesh (enough for collisions and drawing).
SECTIONS = 24

#: Kinds of :class:`Solid` and what their ``size_mm`` holds.
KINDS = {"cylinder": ("radius", "length"), "cone": ("radius at 0", "radius at length", "length"),
         "sphere": ("radius",), "box": ("x", "y", "z")}


@dataclass(frozen=True)
class Solid:
    """One simple solid of a tool body.

    In its own frame {P}: a cylinder or cone runs along +Z from z = 0 to its
    length; a sphere is centred on the origin; a box is centred on the Z axis
    and runs from z = 0 to its z size.

    Attributes
    ----------
    kind : str
        ``"cylinder"``, ``"cone"``, ``"sphere"`` or ``"box"``.
    size_mm : tuple of float
        See :data:`KINDS`: (radius, length), (radius at 0, radius at length,
        length), (radius,) or (x, y, z).
    T_f_p : ndarray, shape (4, 4)
        The solid's frame {P} in the flange frame {F}, mm.
    mass_kg : float
    """

    kind: str
    size_mm: tuple
    T_f_p: np.ndarray
    mass_kg: float

    def centroid_mm(self):
        """ndarray (3,): the solid's centroid (uniform density) in {F}, mm."""
        if self.kind == "cylinder":
            z = self.size_mm[1] / 2.0
        elif self.kind == "cone":
            r0, r1, h = self.size_mm
            z = h * (r0 * r0 + 2.0 * r0 * r1 + 3.0 * r1 * r1) / (4.0 * (r0 * r0 + r0 * r1 + r1 * r1))
        elif self.kind == "box":
            z = self.size_mm[2] / 2.0
        else:
            z = 0.0
        return (self.T_f_p @ np.array([0.0, 0.0, z, 1.0]))[:3]

    def mesh(self):
        """trimesh.Trimesh: the solid in {F}, mm (convex, watertight)."""
        trimesh = dependencies.require("trimesh")
        if self.kind == "box":
            x, y, z = self.size_mm
            mesh = trimesh.creation.box((x, y, z), transform=pose((0.0, 0.0, z / 2.0)))
        else:
            mesh = trimesh.creation.revolve(self.profile_mm(), sections=SECTIONS)
        return mesh.apply_transform(self.T_f_p)

    def profile_mm(self):
        """ndarray (K, 2): (radius, z) outline revolved about Z, from the axis to the axis."""
        if self.kind == "cylinder":
            r, h = self.size_mm
            return np.array([[0.0, 0.0], [r, 0.0], [r, h], [0.0, h]])
        if self.kind == "cone":
            r0, r1, h = self.size_mm
            points = [[0.0, 0.0], [r0, 0.0], [r1, h], [0.0, h]]
            return np.array([p for k, p in enumerate(points)
                             if not (p[0] == 0.0 and 0 < k < 3)])   # a pointed end: one apex
        if self.kind == "sphere":
            r = self.size_mm[0]
            a = np.linspace(-np.pi / 2.0, np.pi / 2.0, SECTIONS // 2 + 1)
            profile = np.column_stack([r * np.cos(a), r * np.sin(a)])
            profile[[0, -1], 0] = 0.0       # the poles exactly on the axis
            return profile
        raise ValueError("unknown solid kind %r" % self.kind)


def pose(translation_mm=(0.0, 0.0, 0.0), rotation_y_deg=0.0):
    """ndarray (4, 4): a frame at `translation_mm` turned `rotation_y_deg` about Y."""
    a = np.radians(rotation_y_deg)
    T = np.eye(4)
    T[:3, :3] = [[np.cos(a), 0.0, np.sin(a)], [0.0, 1.0, 0.0], [-np.sin(a), 0.0, np.cos(a)]]
    T[:3, 3] = translation_mm
    return T


@dataclass(frozen=True)
class Tool:
    """A tool of the library.

    Attributes
    ----------
    name : str
        One of :func:`names`.
    description : str
        One sentence for the user.
    T_f_t : ndarray, shape (4, 4)
        TCP {T} in the flange frame {F}, mm; +Z is the approach direction.
    solids : tuple of Solid
        The body, in {F}.
    """

    name: str
    description: str
    T_f_t: np.ndarray
    solids: tuple

    @property
    def mass_kg(self):
        """float: the sum of the solids' masses, kg."""
        return float(sum(s.mass_kg for s in self.solids))

    @property
    def cog_mm(self):
        """ndarray (3,): the mass-weighted centroid of the solids in {F}, mm."""
        masses = np.array([s.mass_kg for s in self.solids])
        centroids = np.array([s.centroid_mm() for s in self.solids])
        return masses @ centroids / masses.sum()

    def meshes(self):
        """list of trimesh.Trimesh: one convex mesh per solid, in {F}, mm."""
        return [s.mesh() for s in self.solids]

    def mesh(self):
        """(vertices (N, 3) float mm in {F}, faces (M, 3) int): the whole body.

        The solids' meshes put together (they overlap; not a boolean union),
        so each solid stays a connected, convex piece.  Made once per tool;
        each call returns fresh copies.
        """
        if self.name not in _MESHES:
            meshes = self.meshes()
            offsets = np.cumsum([0] + [len(m.vertices) for m in meshes[:-1]])
            vertices = np.vstack([m.vertices for m in meshes])
            faces = np.vstack([m.faces + k for m, k in zip(meshes, offsets)])
            _MESHES[self.name] = (vertices, faces)
        vertices, faces = _MESHES[self.name]
        return vertices.copy(), faces.copy()


#: Tool name -> (vertices, faces) of :meth:`Tool.mesh`, made when first asked for.
_MESHES = {}


def _torch(name, neck_deg, description):
    """A MIG/MAG robot torch whose neck is bent `neck_deg` about the flange's Y axis."""
    mount = Solid("cylinder", (32.5, 95.0), pose((0, 0, 0)), 0.90)      # collision sensor + flange
    if neck_deg == 0.0:
        straight = Solid("cylinder", (14.0, 220.0), pose((0, 0, 95.0)), 0.70)
        bend = pose((0, 0, 315.0))
        body = [mount, straight]
        neck_mm = 0.0
    else:
        straight = Solid("cylinder", (14.0, 140.0), pose((0, 0, 95.0)), 0.45)
        elbow = Solid("sphere", (14.0,), pose((0, 0, 235.0)), 0.05)
        neck_mm = 110.0
        bend = pose((0, 0, 235.0), neck_deg)
        neck = Solid("cylinder", (12.0, neck_mm), bend, 0.25)
        body = [mount, straight, elbow, neck]
    nozzle_at = bend @ pose((0, 0, neck_mm))
    body.append(Solid("cone", (13.0, 8.0, 55.0), nozzle_at, 0.25))               # gas nozzle
    wire_at = nozzle_at @ pose((0, 0, 55.0))
    body.append(Solid("cylinder", (0.6, 15.0), wire_at, 0.001))                  # wire stick-out
    return Tool(name, description, wire_at @ pose((0, 0, 15.0)), tuple(body))


def _ball_tool():
    r = BALL_RADIUS_MM
    body = (Solid("cylinder", (40.0, 35.0), pose((0, 0, 0)), 0.35),             # F/T sensor
            Solid("cylinder", (25.0, 15.0), pose((0, 0, 35.0)), 0.15),          # adapter
            Solid("cylinder", (8.0, 140.0), pose((0, 0, 50.0)), 0.22),          # steel stem
            Solid("cone", (8.0, 3.0, 10.0), pose((0, 0, 190.0)), 0.01),
            Solid("sphere", (r,), pose((0, 0, 200.0 + r)), 0.004))
    return Tool("Ball tool", "Ball (r %g mm) behind a force sensor, for force following; TCP "
                "on its front, 210 mm out, 0.7 kg." % r,
                pose((0, 0, 200.0 + 2.0 * r)), body)


def _spindle():
    x = 50.0                                                                   # spindle axis offset
    body = (Solid("box", (130.0, 80.0, 15.0), pose((25.0, 0, 0)), 0.40),         # bracket
            Solid("cylinder", (35.0, 185.0), pose((x, 0, 15.0)), 2.60),          # motor
            Solid("cone", (20.0, 10.0, 25.0), pose((x, 0, 200.0)), 0.20),        # nose
            Solid("cylinder", (6.0, 15.0), pose((x, 0, 225.0)), 0.05),           # collet
            Solid("cylinder", (3.0, 10.0), pose((x, 0, 240.0)), 0.01),           # burr shank
            Solid("cylinder", (4.0, 16.0), pose((x, 0, 250.0)), 0.01),           # burr
            Solid("sphere", (4.0,), pose((x, 0, 266.0)), 0.002))                 # its ball nose
    return Tool("Deburring spindle", "Deburring spindle 50 mm off axis: burr tip 270 mm out, 3.3 kg.", pose((x, 0, 270.0)), body)


def _library():
    tools = (
        _torch("Straight torch", 0.0, "Straight MIG/MAG torch: wire tip 385 mm out, 1.9 kg."),
        _torch("Bent torch", 22.0, "MIG/MAG torch, 22\u00b0 neck: wire tip 402 mm out, 67 mm "
               "off axis, 1.9 kg."),
        _ball_tool(),
        _spindle(),
    )
    return {tool.name: tool for tool in tools}


LIBRARY = _library()


def names():
    """list of str: the library's tool names, in the order a user is offered them."""
    return list(LIBRARY)


def tool_types():
    """list of str: what a cell's ``ToolType`` can be: the library names and :data:`CUSTOM`."""
    return names() + [CUSTOM]


def get(name):
    """The library tool `name`.

    Raises
    ------
    UnknownNameError
        For a name not in the library.
    """
    try:
        return LIBRARY[name]
    except (KeyError, TypeError):
        raise UnknownNameError("Unknown tool '%s'; use one of %s, or give a document solid as the "
                               "tool body." % (name, ", ".join(names()))) from None
