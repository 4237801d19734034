"""Collision checks of a robot's links and tool against the cell's solids.

::

    checker = RobotCollisionChecker("ABB_IRB2400", [("Table", table_mesh)],
                                    tool_T_f_t=T_f_t, margin_mm=5.0)
    findings = checker.check(q_deg)          # (N, 6) deg -> one list per pose
    for link, obstacle, distance_mm in findings[0]:
        ...

The robot is the convex pieces of :func:`.links.link_parts` (and the tool of
:func:`.links.tool_solid`), placed per pose with :func:`.links.link_frames`.
Distances come from FCL (python-fcl, through trimesh's mesh conversions):

* pieces are given to FCL as convex shapes, so a distance is exact for the
  meshes and a negative one is the penetration depth (the shortest
  translation that separates them), also when a small link lies wholly
  inside a large obstacle;
* each obstacle is split into its connected bodies; a convex body (a box, a
  plate, a cylinder) is treated the same way, a non-convex body as a
  triangle surface: its penetration depth is FCL's contact depth, and a
  piece wholly inside a non-convex body without touching its surface is not
  seen -- give such solids as convex parts (FreeCAD's tessellation of a
  compound of boxes already splits into them).

Which pairs are checked, per pose:

* links 1-6 and the tool against every obstacle;
* the tool is the cell's tool body when one is given (``tool_mesh``: the
  library tool's solids or a document solid, in {F}), else a torch-like
  cylinder towards the TCP (:func:`.links.tool_solid`).  Either way the part
  within `tool_clearance_mm` (:data:`TIP_CLEARANCE_MM`) of the TCP along the
  tool's approach axis is left out (:func:`tool_pieces`): the tip touches the
  work there by design (a welding wire, a ball pressing on the surface), so
  it is not a collision;
* the base (link 0) never moves, so it is checked once, when the checker is
  made: obstacles it touches or intersects (the floor, the pedestal it is
  bolted to, or a misplaced solid through its foot) are listed in
  :attr:`RobotCollisionChecker.base_contacts` and not reported per pose;
* with ``self_collision=True`` also every pair of bodies that are not
  neighbours in the chain (base, link1..link6, tool: bodies i and j with
  ``|i - j| >= 2``).  The solids are coarse, so near some joint limits they
  may touch where the real arm does not (e.g. the flange against the
  forearm at |J5| close to 120 degrees); off by default.

Speed: a vectorised bounding-box test over all poses first; FCL only runs on
the pairs whose boxes come within the margin, with the FCL objects made once
and only their transforms set per pose.

Without python-fcl (an optional package) :func:`is_available` is False and
callers leave collisions out, saying so (``dependencies.warn_missing``).

Pure numpy + trimesh + python-fcl: never imports FreeCAD.
"""

import collections

import numpy as np

from ... import dependencies
from ...core import frames as tf
from ...core import program as ir
from ...core.progress import report_now
from ...errors import InputError, MissingPackageError
from ..motion import move_sampling
from . import links, mechanism_solids

trimesh = dependencies.require("trimesh")
from trimesh.collision import mesh_to_BVH, mesh_to_convex  # noqa: E402 -- after the clear error

#: The pip name of FCL's Python binding; without it collisions are not checked.
FCL_PACKAGE = "python-fcl"
fcl = dependencies.import_optional(FCL_PACKAGE)   # None: see is_available()

#: One finding: `link` ("link1".."link6" or "tool") is `distance_mm` from
#: `obstacle` (an obstacle's name, or a link's name for a self-collision).
#: ``distance_mm <= 0``: in collision, ``-distance_mm`` is the penetration depth.
Finding = collections.namedtuple("Finding", "link obstacle distance_mm")

#: Name of the tool body in findings.
TOOL_NAME = "tool"

#: The base counts as standing on an obstacle it is this close to (mm).
BASE_TOUCH_MM = 1.0

#: How much of a tool body next to the TCP the collision check leaves out, mm
#: along the approach axis: the welding wire's stick-out, a ball tool's ball
#: and the tip of a burr touch the work there by design.
TIP_CLEARANCE_MM = 15.0


def tool_arguments(tool):
    """The tool keywords of :class:`RobotCollisionChecker` for a program's tool.

    Parameters
    ----------
    tool : core.program.ToolData

    Returns
    -------
    dict
        ``tool_T_f_t``, and ``tool_mesh`` / ``tool_label`` when the tool has a body.
    """
    arguments = {"tool_T_f_t": np.asarray(tool.T_f_t, dtype=float),
                 "tool_label": getattr(tool, "label", "") or ""}
    vertices = getattr(tool, "body_vertices_mm", None)
    if vertices is not None and len(vertices):
        arguments["tool_mesh"] = (vertices, tool.body_faces)
    return arguments


def _clip_convex(mesh, depth, keep):
    """The convex `mesh` cut where `depth` (per vertex) crosses 0, the side
    ``depth <= 0`` kept, as a convex mesh; None when nothing solid is left."""
    points = [mesh.vertices[keep]]
    edges = mesh.edges_unique
    da, db = depth[edges[:, 0]], depth[edges[:, 1]]
    crossing = (da < 0.0) != (db < 0.0)
    if crossing.any():
        a, b = mesh.vertices[edges[crossing, 0]], mesh.vertices[edges[crossing, 1]]
        t = (da[crossing] / (da[crossing] - db[crossing]))[:, None]
        points.append(a + t * (b - a))
    points = np.vstack(points)
    if len(points) < 4 or np.linalg.matrix_rank(points - points.mean(axis=0), tol=1e-6) < 3:
        return None
    try:
        return trimesh.convex.convex_hull(points)
    except Exception:  # noqa: BLE001 -- qhull on a sliver: nothing solid left
        return None


def _clip_surface(mesh, depth):
    """The triangles of `mesh` cut where `depth` (per vertex) crosses 0, the side
    ``depth <= 0`` kept, as an open triangle surface; None when nothing is left."""
    out = []
    for face in mesh.faces:
        corners, d = mesh.vertices[face], depth[face]
        if (d <= 0.0).all():
            out.append(corners)
            continue
        polygon = []
        for k in range(3):               # Sutherland-Hodgman against the plane depth = 0
            a, b, da, db = corners[k], corners[(k + 1) % 3], d[k], d[(k + 1) % 3]
            if da <= 0.0:
                polygon.append(a)
            if (da <= 0.0) != (db <= 0.0):
                polygon.append(a + da / (da - db) * (b - a))
        out += [np.array([polygon[0], polygon[i], polygon[i + 1]])
                for i in range(1, len(polygon) - 1)]
    if not out:
        return None
    triangles = np.array(out)
    return trimesh.Trimesh(triangles.reshape(-1, 3), np.arange(3 * len(out)).reshape(-1, 3),
                           process=True)


def _connected_pieces(mesh):
    """The connected bodies of `mesh` (vertices along face seams merged), each a Trimesh.

    Not ``Trimesh.split``: that repairs pieces that are not closed, which
    needs networkx."""
    mesh = mesh.copy()
    mesh.merge_vertices()
    labels = trimesh.graph.connected_component_labels(mesh.face_adjacency,
                                                      node_count=len(mesh.faces))
    groups = [np.flatnonzero(labels == k) for k in np.unique(labels)]
    return mesh.submesh(groups, only_watertight=False, repair=False) if len(groups) > 1 else [mesh]


def tool_pieces(tool_mesh, T_f_t, clearance_mm=TIP_CLEARANCE_MM):
    """A tool body for the collision check: cut `clearance_mm` short of the TCP.

    The body is split into its connected pieces (a library tool's solids
    each stay one convex piece).  Everything closer to the TCP than
    `clearance_mm`, measured back along the TCP's Z axis (the half-space
    ``z_T > -clearance_mm`` of the TCP frame), is removed: a convex piece is
    cut and closed again (the convex hull of what is left), any other piece
    is cut as an open triangle surface (FCL checks it as one).

    Parameters
    ----------
    tool_mesh : trimesh.Trimesh or (ndarray (N, 3), ndarray (M, 3))
        The tool body in the flange frame {F}, mm.
    T_f_t : array_like, shape (4, 4)
        TCP in {F}, mm.
    clearance_mm : float

    Returns
    -------
    list of trimesh.Trimesh
        Pieces in {F}; empty when nothing is left.
    """
    if not isinstance(tool_mesh, trimesh.Trimesh):
        vertices, faces = tool_mesh
        tool_mesh = trimesh.Trimesh(np.asarray(vertices, dtype=float), np.asarray(faces, dtype=int),
                                    process=True)
    T = np.asarray(T_f_t, dtype=float)
    axis, tcp = T[:3, 2], T[:3, 3]
    pieces = []
    for piece in _connected_pieces(tool_mesh):
        depth = (piece.vertices - tcp) @ axis + clearance_mm       # <= 0: kept
        keep = depth <= 0.0
        if keep.all():
            pieces.append(piece)
        elif not keep.any():
            continue
        elif piece.is_convex:
            clipped = _clip_convex(piece, depth, keep)
            if clipped is not None:
                pieces.append(clipped)
        else:
            cut = _clip_surface(piece, depth)
            if cut is not None:
                pieces.append(cut)
    return pieces


def is_available():
    """bool: python-fcl is installed, so collisions can be checked."""
    return fcl is not None


class _Body:
    """One convex piece of a robot body, or one connected body of an obstacle."""

    def __init__(self, name, mesh, frame_index=None):
        self.name = name
        self.frame_index = frame_index              # link frame it moves with; None = static
        self.convex = bool(mesh.is_convex)
        geometry = mesh_to_convex(mesh) if self.convex else mesh_to_BVH(mesh)
        self.obj = fcl.CollisionObject(geometry, fcl.Transform())
        lo, hi = mesh.bounds
        self.corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                                 for z in (lo[2], hi[2])])   # (8, 3) local bounding box
        self.bounds = mesh.bounds.copy()            # (2, 3), valid for static bodies

    def place(self, T):
        """Set the pose (4, 4) of the body."""
        self.obj.setRotation(T[:3, :3])
        self.obj.setTranslation(T[:3, 3])


def in_contact(a, b):
    """Whether two placed bodies touch or overlap (FCL's collide, no contact data)."""
    return fcl.collide(a.obj, b.obj, fcl.CollisionRequest(), fcl.CollisionResult()) > 0


def signed_distance(a, b):
    """Signed distance between two placed bodies, mm (negative: penetration depth).

    Parameters
    ----------
    a, b : _Body

    Returns
    -------
    float
    """
    result = fcl.DistanceResult()
    d = fcl.distance(a.obj, b.obj, fcl.DistanceRequest(enable_signed_distance=True), result)
    if d < 0.0 and not (a.convex and b.convex):
        # With a triangle mesh FCL only says "in contact" (-1): take the deepest contact.
        request = fcl.CollisionRequest(num_max_contacts=64, enable_contact=True)
        contacts = fcl.CollisionResult()
        fcl.collide(a.obj, b.obj, request, contacts)
        d = -max([c.penetration_depth for c in contacts.contacts], default=0.0)
    return d


class RobotCollisionChecker:
    """Collisions of a robot's links and tool with the cell, for many poses.

    Parameters
    ----------
    robot : str, RobotSpec or RobotModel
        The robot (see :func:`.links.robot_model`).
    obstacles : sequence of (str, trimesh.Trimesh)
        Named solids of the cell in the robot base frame {R}, mm.
    tool_T_f_t : array_like, shape (4, 4), optional
        TCP in the flange frame, mm; adds the tool: `tool_mesh` if given,
        else the solid of :func:`.links.tool_solid` (None: no tool).
    margin_mm : float
        Report pairs closer than this (0: only pairs in contact).
    tool_radius_mm, tool_clearance_mm : float
        The cylinder tool's radius; how far short of the TCP the tool is
        left out (:func:`tool_pieces`; the cylinder stops there).
    self_collision : bool
        Also check non-neighbouring robot bodies against each other.
    tool_mesh : trimesh.Trimesh or (ndarray (N, 3), ndarray (M, 3)), optional
        The tool body in {F}, mm (needs `tool_T_f_t`).
    tool_label : str
        What the user calls the tool, for messages (:attr:`tool_label`).

    Attributes
    ----------
    model : RobotModel
    link_names : tuple of str
        The moving bodies checked per pose: ``link1..link6`` and ``tool``.
    has_tool : bool
        Whether a tool body is checked.
    tool_label : str
    base_contacts : list of Finding
        Obstacles the base touches (within :data:`BASE_TOUCH_MM`, or
        `margin_mm` if larger); they are where the robot stands and are not
        reported per pose.

    Raises
    ------
    MissingPackageError
        When python-fcl is not installed (see :func:`is_available`).
    InputError
        For an obstacle without triangles.
    """

    def __init__(self, robot, obstacles, tool_T_f_t=None, margin_mm=0.0,
                 tool_radius_mm=20.0, tool_clearance_mm=TIP_CLEARANCE_MM, self_collision=False,
                 tool_mesh=None, tool_label=""):
        if fcl is None:
            raise MissingPackageError(dependencies.missing_message(FCL_PACKAGE))
        self.model = links.robot_model(robot)
        self.margin_mm = float(margin_mm)
        self.self_collision = bool(self_collision)

        parts = links.link_parts(self.model)
        self._base = [_Body(links.LINK_NAMES[0], piece) for piece in parts[0]]
        self._moving = [_Body(links.LINK_NAMES[i], piece, frame_index=i)
                        for i in range(1, 7) for piece in parts[i]]
        tool = []
        if tool_T_f_t is not None and tool_mesh is not None:
            tool = tool_pieces(tool_mesh, tool_T_f_t, tool_clearance_mm)
        elif tool_T_f_t is not None:
            tool = [links.tool_solid(tool_T_f_t, tool_radius_mm, tool_clearance_mm)]
        self._moving += [_Body(TOOL_NAME, piece, frame_index=6) for piece in tool if piece is not None]
        self.has_tool = tool_T_f_t is not None and any(piece is not None for piece in tool)
        self.tool_label = str(tool_label or "")
        self.link_names = tuple(dict.fromkeys(body.name for body in self._moving))

        self._corners = np.array([b.corners for b in self._moving])          # (P, 8, 3)
        self._frame_index = np.array([b.frame_index for b in self._moving])  # (P,)
        self._obstacles = []
        self._moved = set()          # obstacle bodies an obstacle pose has moved
        self.add_obstacles(obstacles)
        self._self_pairs = self._non_neighbour_pairs() if self.self_collision else []

    # ------------------------------------------------------------------ set-up
    def add_obstacles(self, obstacles):
        """Add named solids (sequence of (str, trimesh.Trimesh) in {R}, mm) to the check.

        Raises
        ------
        InputError
            For an obstacle without triangles.
        """
        self._restore_obstacles()
        for name, mesh in obstacles:
            if mesh is None or len(mesh.faces) == 0:
                raise InputError("Obstacle '%s' has no triangles: give it a solid shape." % name,
                                 obj_name=name)
            mesh = mesh.copy()
            mesh.merge_vertices()    # tessellations may repeat vertices along face seams
            bodies = mesh.split(only_watertight=False) or [mesh]
            self._obstacles += [_Body(name, body) for body in bodies]
        self._obstacle_lo = np.array([b.bounds[0] for b in self._obstacles]).reshape(-1, 3)
        self._obstacle_hi = np.array([b.bounds[1] for b in self._obstacles]).reshape(-1, 3)
        self._obstacle_corners = np.array([b.corners for b in self._obstacles]).reshape(-1, 8, 3)
        self._obstacle_names = np.array([b.name for b in self._obstacles], dtype=object)
        self.base_contacts = self._base_contacts()

    def _restore_obstacles(self):
        """Put the obstacles an obstacle pose moved back where they were given."""
        for o in self._moved:
            self._obstacles[o].place(np.eye(4))
        self._moved = set()

    @property
    def obstacle_names(self):
        """list of str: the obstacles' names, each once, in the order given."""
        return list(dict.fromkeys(self._obstacle_names.tolist()))

    def _base_contacts(self):
        limit = max(self.margin_mm, BASE_TOUCH_MM)
        nearest = {}
        for base in self._base:
            for body in self._obstacles:
                d = signed_distance(base, body)
                if d <= limit:
                    nearest[body.name] = min(d, nearest.get(body.name, np.inf))
        return [Finding(self._base[0].name, name, d) for name, d in nearest.items()]

    def _non_neighbour_pairs(self):
        """Index pairs into self._moving (b >= 0) or self._base (b = -1 - index)."""
        order = {name: i for i, name in enumerate(links.LINK_NAMES + (TOOL_NAME,))}
        pairs = []
        for a, body_a in enumerate(self._moving):
            for b, body_b in enumerate(self._moving[a + 1:], start=a + 1):
                if abs(order[body_a.name] - order[body_b.name]) >= 2:
                    pairs.append((a, b))
            if order[body_a.name] >= 2:
                pairs += [(a, -1 - k) for k in range(len(self._base))]
        return pairs

    # ------------------------------------------------------------------ checks
    def _boxes(self, frames):
        """Axis-aligned boxes in {R} of every moving body, (N, P, 3) low and high."""
        T = frames[:, self._frame_index]                                  # (N, P, 4, 4)
        corners = (np.einsum("npij,pkj->npki", T[..., :3, :3], self._corners)
                   + T[:, :, None, :3, 3])                                # (N, P, 8, 3)
        return corners.min(axis=2), corners.max(axis=2)

    def _obstacle_boxes(self, poses, count):
        """Obstacle boxes (N, O, 3) low and high, and the per-pose transforms
        (N, O, 4, 4) of the obstacles `poses` moves (None when none moves)."""
        if not poses:
            return self._obstacle_lo[None], self._obstacle_hi[None], None
        T = np.broadcast_to(np.eye(4), (count, len(self._obstacles), 4, 4)).copy()
        for name, T_name in poses.items():
            T[:, self._obstacle_names == name] = np.asarray(T_name, dtype=float)[:, None]
        corners = (np.einsum("noij,okj->noki", T[..., :3, :3], self._obstacle_corners)
                   + T[:, :, None, :3, 3])                                # (N, O, 8, 3)
        return corners.min(axis=2), corners.max(axis=2), T

    def check(self, q_deg, obstacle_poses=None):
        """Pairs in collision, or closer than the margin, per pose.

        Parameters
        ----------
        q_deg : array_like, shape (N, 6) or (6,)
            Joint values in the controller's convention, degrees.
        obstacle_poses : dict of str to array_like (N, 4, 4), optional
            Obstacles that move (external axes): per pose, the transform of
            the named obstacle's mesh as given, in {R}.  Others stand still.

        Returns
        -------
        findings : list of N lists of Finding (one list for q_deg of shape (6,))
            Per pose, each (link, obstacle) pair with ``distance_mm <= 0`` (in
            collision; ``-distance_mm`` is the penetration depth) or
            ``distance_mm < margin_mm``, the smallest distance over the
            pair's pieces, sorted by distance.  An empty list: the pose is clear.
        """
        q_deg = np.asarray(q_deg, dtype=float)
        single = q_deg.ndim == 1
        frames = links.link_frames(self.model, np.atleast_2d(q_deg))
        lo, hi = self._boxes(frames)
        o_lo, o_hi, o_T = self._obstacle_boxes(obstacle_poses, frames.shape[0])
        self._restore_obstacles()
        m = self.margin_mm
        nearest = [dict() for _ in range(frames.shape[0])]
        placed = {}
        placed_obstacle = {}

        def place(n, p):
            if placed.get(p) != n:
                body = self._moving[p]
                body.place(frames[n, body.frame_index])
                placed[p] = n

        def place_obstacle(n, o):
            if o_T is not None and placed_obstacle.get(o) != n:
                self._obstacles[o].place(o_T[n, o])
                placed_obstacle[o] = n
                self._moved.add(o)

        def measure(n, a, b):
            # Without a margin, only pairs in contact need a distance (collide is cheaper).
            if m <= 0.0 and not in_contact(a, b):
                return
            d = signed_distance(a, b)
            if d <= 0.0 or d < m:
                key = (a.name, b.name)
                nearest[n][key] = min(d, nearest[n].get(key, np.inf))

        near = ((lo[:, :, None] <= o_hi[:, None] + m)
                & (o_lo[:, None] <= hi[:, :, None] + m)).all(axis=-1)       # (N, P, O)
        for n, p, o in zip(*np.nonzero(near)):
            place(n, p)
            place_obstacle(n, o)
            measure(n, self._moving[p], self._obstacles[o])

        for a, b in self._self_pairs:
            if b >= 0:
                b_lo, b_hi, other = lo[:, b], hi[:, b], self._moving[b]
            else:
                other = self._base[-1 - b]
                b_lo, b_hi = other.bounds
            close = ((lo[:, a] <= b_hi + m) & (b_lo <= hi[:, a] + m)).all(axis=-1)
            for n in np.nonzero(close)[0]:
                place(n, a)
                if b >= 0:
                    place(n, b)
                measure(n, self._moving[a], other)

        findings = [sorted((Finding(a, b, float(d)) for (a, b), d in pose.items()),
                           key=lambda f: f.distance_mm) for pose in nearest]
        return findings[0] if single else findings

    def colliding(self, q_deg):
        """Whether each pose has a body in contact with an obstacle (or itself).

        Parameters
        ----------
        q_deg : array_like, shape (N, 6)
            Joint values, degrees.

        Returns
        -------
        ndarray of bool, shape (N,)
        """
        findings = self.check(np.atleast_2d(np.asarray(q_deg, dtype=float)))
        return np.array([any(f.distance_mm <= 0.0 for f in pose) for pose in findings], dtype=bool)


#: Joint sets checked for collisions between two progress reports.
CHUNK_POSES = 100


def collision_poses(solution, sampled, step_deg=2.0):
    """The joint sets where the robot is checked along a solved program.

    * Every solved target (fraction 1 of its move).
    * Linear and circular moves: the inner samples of `sampled`, i.e. as the
      controller moves the robot (TCP along the line or arc, orientation
      slerped, joints by the IK of each sample in the move's configuration:
      :mod:`..motion.move_sampling`).  The joints interpolated between the
      ends of such a move may pass far from where the arm really goes: a
      90-degree turn of the tool about a fixed TCP swings the flange hundreds
      of millimetres in joint space while the tip stays put.  Samples without
      joints (out of reach, another configuration) are left out: the checks
      report them.  A move `sampled` does not hold (its start has no joints)
      is checked at its target only.
    * Joint moves: interpolated in joint space from the previous target's
      joints, as the controller runs them, no joint more than `step_deg` per
      step.

    Parameters
    ----------
    solution : configuration.JointSolution
    sampled : move_sampling.SampledMoves
        :func:`..motion.move_sampling.sample_program` of this solution.
    step_deg : float
        Largest joint step between two samples of a joint move, degrees.

    Returns
    -------
    q_deg : ndarray, shape (P, 6)
        Model joints of each pose.
    owner : ndarray of int, shape (P,)
        Index into ``solution.entries`` of the target a hit there is reported at
        (a move's samples belong to its end target).
    fraction : ndarray, shape (P,)
        Where along that target's move, 0 to 1 (1: at the target).
    """
    q, owner, fraction, _ = _collision_poses(solution, sampled, step_deg)
    return q, owner, fraction


def _collision_poses(solution, sampled, step_deg, program=None):
    """:func:`collision_poses`, and with a `program` that has external axes their
    values at each pose, shape (P, E) (else None): a target's own, linear along a
    joint move, the sampled ones along a linear or circular move."""
    q = solution.joints()                                        # (N, 6), NaN: none
    solved = ~np.isnan(q).any(axis=1)
    kinds = np.array([entry.move.kind for entry in solution.entries], dtype=object)
    parts = [(q[solved], np.flatnonzero(solved), np.ones(int(solved.sum())))]
    parts.append(_joint_move_poses(q, solved, kinds == ir.JOINT, step_deg))
    q_moves, owner_moves, fraction_moves, rows = _cartesian_move_poses(solution, sampled)
    parts.append((q_moves, owner_moves, fraction_moves))
    external = None
    if getattr(program, "external", None) is not None:
        values = np.array([move_sampling.external_values(program, entry.target)
                           for entry in solution.entries]).reshape(len(solution.entries), -1)
        (_, targets, _), (_, joint_owner, joint_fraction) = parts[0], parts[1]
        previous = values[joint_owner - 1]
        external = np.concatenate([
            values[targets],
            previous + joint_fraction[:, None] * (values[joint_owner] - previous),
            sampled.external[rows] if len(rows) else np.zeros((0, values.shape[1]))])
    return (np.concatenate([p[0] for p in parts]).reshape(-1, 6),
            np.concatenate([p[1] for p in parts]).astype(int),
            np.concatenate([p[2] for p in parts]), external)


def _joint_move_poses(q, solved, joint_move, step_deg):
    """Inner joint-space samples of the joint moves between two solved entries."""
    i = np.flatnonzero(solved & joint_move & np.roll(solved, 1))
    i = i[i > 0]
    delta = q[i] - q[i - 1]
    count = np.maximum(1, np.ceil(np.abs(delta).max(axis=1, initial=0.0) / step_deg)).astype(int)
    inner = count - 1                                            # samples strictly inside
    piece = np.repeat(np.arange(i.size), inner)
    step = np.arange(piece.size) - np.repeat(np.cumsum(inner) - inner, inner) + 1
    fraction = step / count[piece]
    return q[i - 1][piece] + fraction[:, None] * delta[piece], i[piece], fraction


def _cartesian_move_poses(solution, sampled):
    """Inner samples of the sampled linear and circular moves, owned by each move's end:
    joints, owner, fraction and the rows of `sampled` they are."""
    if sampled is None or len(sampled) == 0:
        return np.zeros((0, 6)), np.zeros(0, int), np.zeros(0), np.zeros(0, int)
    index_of = {id(entry): k for k, entry in enumerate(solution.entries)}
    offsets = sampled.offsets
    move_of = np.repeat(np.arange(len(sampled)), np.diff(offsets))
    rows = np.arange(offsets[-1])
    inner = ((rows > offsets[move_of]) & (rows < offsets[move_of + 1] - 1)
             & ~np.isnan(sampled.q_deg).any(axis=1))
    end = np.array([index_of[id(group[-1])] for group in sampled.groups], dtype=int)
    return (sampled.q_deg[inner], end[move_of[inner]], sampled.fractions[inner],
            np.flatnonzero(inner))


def program_collision_findings(program, solution, checker, sampled=None, step_deg=2.0,
                               progress=None):
    """Collisions along a solved program, as check findings.

    The robot is checked where the controller moves it (:func:`collision_poses`):
    at every solved target, along linear and circular moves at the samples of
    :mod:`..motion.move_sampling` (the sampler of the other checks, the cycle
    time and the player), along joint moves in joint space.

    With external axes (``program.external``) the mechanisms' solids are added
    to `checker` (:func:`external_scene`) and, at each pose, the obstacles are
    where the axes' values there put them (:mod:`.mechanism_solids`): the
    positioner's bodies and the solids riding on it turned with it, everything
    moved in the robot base when a track carries the robot.

    Parameters
    ----------
    program : Program
        The program `solution` solves.
    solution : configuration.JointSolution
    checker : RobotCollisionChecker
    sampled : move_sampling.SampledMoves, optional
        :func:`..motion.move_sampling.sample_program` of this program and
        solution, when the caller has it (``api.check`` samples once for every
        check); sampled here with the default margins otherwise.
    step_deg : float
        Largest joint step between two samples of a joint move, degrees.
    progress : callable, optional
        ``progress(fraction, text)``, told between chunks of
        :data:`CHUNK_POSES` poses; returning False raises
        :class:`..core.progress.Cancelled`.

    Returns
    -------
    list of checks.Finding
        One ``"collision"`` error per target whose pose, or whose move, collides:
        the deepest hit, naming the body, the obstacle, the target and where
        along the move ("at 40% of the move").
    """
    from . import checks  # checks does not import this module; keep it that way
    if sampled is None:
        sampled = move_sampling.sample_program(program, checker.model, solution, checks.Margins())
    samples, owner, fraction, external = _collision_poses(solution, sampled, step_deg, program)
    scene = None if external is None else external_scene(program.external, checker)
    hits = []
    for start in range(0, len(samples), CHUNK_POSES):
        report_now(progress, start / len(samples), "checking collisions")
        chunk = slice(start, start + CHUNK_POSES)
        hits += checker.check(samples[chunk],
                              None if scene is None else scene.poses(external[chunk]))
    worst = {}                       # entry index -> (deepest hit, its fraction)
    for k, f, pose in zip(owner.tolist(), fraction.tolist(), hits):
        for hit in pose:
            if hit.distance_mm <= 0.0 and (k not in worst
                                           or hit.distance_mm < worst[k][0].distance_mm):
                worst[k] = (hit, f)
    return [_collision_finding(checks, checker, solution.entries[k], *worst[k])
            for k in sorted(worst)]


def external_scene(external, checker):
    """Add the mechanisms' solids to `checker` (those not there yet, in {R0}: the
    robot base with the track at its drawn value) and say how the obstacles move.

    Parameters
    ----------
    external : core.mechanisms.ExternalAxes
    checker : RobotCollisionChecker
        Its obstacles in {R0}; the positioner's riding solids named as in
        ``external.riding_solids``.

    Returns
    -------
    mechanism_solids.SceneMotion
        Mechanisms whose solids cannot be checked are left out
        (:func:`.checks.check_program` reports them as not checked).
    """
    solids, _ = mechanism_solids.mechanism_solids(external)
    T_r0_u = tf.invert_transform(np.asarray(external.T_u_r, dtype=float))
    present = set(checker.obstacle_names)
    checker.add_obstacles([(name, trimesh.Trimesh(tf.transform_points(T_r0_u, vertices), faces,
                                                  process=True))
                           for name, vertices, faces in solids if name not in present])
    return mechanism_solids.SceneMotion(external, checker.obstacle_names)


def _collision_finding(checks, checker, entry, hit, fraction):
    """The check finding of the deepest `hit` on the move to `entry`, at `fraction` of it."""
    if fraction >= 1.0:
        where = "at target %s" % entry.target.name
    else:
        # Inside the move: never "0%" or "100%" (those are the targets themselves).
        where = "on the %s move to target %s, at %.0f%% of the move" % (
            entry.move.kind, entry.target.name, min(max(100.0 * fraction, 1.0), 99.0))
    return checks.Finding(
        kind="collision", severity=checks.ERROR, target=entry.target.name,
        move_index=entry.move_index, path=entry.path_label,
        message="%s: %s hits %s (%.1f mm deep) %s. Move the part or the robot, %s%s." % (
            entry.path_label, hitting_body(checker, hit.link), hit.obstacle, -hit.distance_mm,
            where, _collision_fix(entry, fraction), _no_tool_hint(checker)),
        value=float(-hit.distance_mm))


def _collision_fix(entry, fraction):
    """What else a collision finding asks for: inside an air (joint) move, a longer approach
    (its ends farther from the part, where the joints swing less near it)."""
    if entry.move.kind == ir.JOINT and fraction < 1.0:
        return ("change the tool orientation, or lengthen the approach (ApproachDistance of path "
                "'%s', and of the path before it) so this air move keeps away from the part"
                % entry.path_label)
    return "or change the tool orientation"


def hitting_body(checker, link):
    """How a finding names the body that hits: "the tool 'Straight torch'", "the robot's link6"."""
    if link == TOOL_NAME:
        label = getattr(checker, "tool_label", "")
        return "the tool '%s'" % label if label else "the tool"
    return "the robot's %s" % link


def _no_tool_hint(checker):
    """A clause telling that the robot carries no tool, when it does not (else "")."""
    if getattr(checker, "has_tool", True):
        return ""
    return (" (the cell has no tool: its TCP is the flange; give it one with CadRobot_EditTool "
            "or api.set_tool)")
