"""Shape queries behind the picking commands: points, faces and normals in {U}.

Everything is returned in the document's global frame {U} (container
placements applied), mm, as numpy arrays; the vector math lives in
``core.surface_normals``.
"""

import numpy as np
import Part

import FreeCAD

from ..errors import InputError
from .base import describe, global_placement
from .convert import array_from_vector, vector_from_array
from .obstacles import is_final_solid

# A point lies on a face's surface when closer than this, mm.
SURFACE_TOL_MM = 1e-3
# A seam may lie this far from the faces it joins (half a root gap), mm.
GAP_TOL_MM = 2.0
# Step of the probes that tell material from free space next to a face, mm.
PROBE_MM = 0.05


def global_shape(obj):
    """`obj`'s shape with its global placement ({U}); InputError if it has none."""
    shape = getattr(obj, "Shape", None)
    if shape is None or shape.isNull():
        raise InputError("%s has no shape to pick from." % describe(obj), obj.Name)
    shape = shape.copy()
    shape.Placement = global_placement(obj)
    return shape


def element(shape, obj, name):
    """Sub-element `name` (``"Edge3"``, ``"Face1"``, ...) of `obj`'s `shape`."""
    try:
        return shape.getElement(name)
    except Exception:   # OCC raises Part.OCCError / ValueError by version
        raise InputError("%s has no %s; select it again." % (describe(obj), name), obj.Name) from None


def outer_edge_names(obj, face_name):
    """Names (``"EdgeN"``) of the edges of the outer boundary of face `face_name` of
    `obj`'s shape, each once, in the order they join when OCC gives that order whole;
    None when it is not a face of that shape."""
    try:
        shape = obj.Shape
        face = shape.getElement(face_name)
    except Exception:  # noqa: BLE001 -- "Pocket.Face3" or a stale name: not a face of obj
        return None
    wire = face.OuterWire
    ordered = _edge_names(shape, wire.OrderedEdges)
    every = _edge_names(shape, wire.Edges)
    # OCC's wire explorer (OrderedEdges) has been seen to give an edge twice (Drilling_1's
    # top face on FreeCAD 1.1); the wire's own edge map has each edge once. The path
    # chains its segments itself, so the joining order is a courtesy.
    names = ordered if sorted(ordered) == sorted(every) else every
    return names or None


def _edge_names(shape, edges):
    """``"EdgeN"`` names of `edges` in `shape`, in their order, each once."""
    names = []
    for edge in edges:
        names += ["Edge%d" % k for k, candidate in enumerate(shape.Edges, 1)
                  if candidate.isSame(edge) and "Edge%d" % k not in names]
    return names


def plane_of(face):
    """(point (3,), unit normal (3,)) of a planar face, the normal honouring the
    face's orientation (outward on a valid solid); None for other faces."""
    surface = face.Surface
    if not isinstance(surface, Part.Plane):
        return None
    u, v = surface.parameter(face.CenterOfMass)
    return array_from_vector(face.CenterOfMass), array_from_vector(face.normalAt(u, v)).copy()


def normal_at(face, point):
    """Unit normal (3,) of `face` at its point nearest `point` (3,), pointing out
    of the material when the face bounds a solid."""
    u, v = face.Surface.parameter(vector_from_array(point))
    normal = array_from_vector(face.normalAt(u, v))
    return normal / np.linalg.norm(normal)


def nearest_on_face(face, point):
    """(distance mm, nearest point (3,)) of `face` to `point` (3,)."""
    distance, pairs, _ = face.distToShape(Part.Vertex(vector_from_array(point)))
    return distance, array_from_vector(pairs[0][0])


def document_solids(doc, exclude=()):
    """[(obj, shape in {U})] of the document's final solids (CadRobot objects excluded)."""
    names = {o.Name for o in exclude}
    return [(o, global_shape(o)) for o in doc.Objects if o.Name not in names and is_final_solid(o)]


def _inside(point, solids):
    vector = vector_from_array(point)
    return any(s.BoundBox.isInside(vector) and s.isInside(vector, 1e-6, False) for s in solids)


def _faces_containing(shape, point, tangent):
    """Faces of `shape` whose surface holds the line (point, tangent) and that lie
    within GAP_TOL_MM of `point`."""
    box = shape.BoundBox
    box.enlarge(GAP_TOL_MM)
    if not box.isInside(vector_from_array(point)):
        return []
    out = []
    for face in shape.Faces:
        u, v = face.Surface.parameter(vector_from_array(point))
        on_surface = np.linalg.norm(array_from_vector(face.Surface.value(u, v)) - point)
        if on_surface > SURFACE_TOL_MM or nearest_on_face(face, point)[0] > GAP_TOL_MM:
            continue
        if abs(float(np.dot(normal_at(face, point), tangent))) < 1e-3:
            out.append(face)
    return out


def _free_side(face, point, tangent, solids):
    """Whether some part of `face` next to `point` has free space outside it (a
    face pressed against another solid has none)."""
    normal = normal_at(face, point)
    q0 = nearest_on_face(face, point)[1]
    across = np.cross(normal, tangent)
    for sign in (1.0, -1.0):
        q = q0 + sign * PROBE_MM * across
        if nearest_on_face(face, q)[0] < PROBE_MM / 10.0 and not _inside(q + PROBE_MM * normal, solids):
            return True
    return False


def adjacent_normals(doc, point, tangent, owner=None, owner_shape=None, edge=None):
    """Outward normals of the faces meeting along an edge at `point`.

    Parameters
    ----------
    doc : App.Document
    point, tangent : ndarray, shape (3,)
        A point of the edge and its unit tangent, {U}.
    owner, owner_shape, edge : optional
        The object the edge belongs to, its shape in {U} and the edge taken
        from that shape: the edge's own faces come first.

    Returns
    -------
    list of ndarray, shape (3,)
        The faces of the edge's own shape that hold it, and the faces of the
        document's other solids whose surface holds it (within GAP_TOL_MM,
        e.g. the plates either side of a seam's root gap), without faces
        pressed against another solid (the inside of a T-joint).
    """
    solids = [(obj, shape) for obj, shape in document_solids(doc, exclude=[owner] if owner else [])]
    faces = []
    if owner_shape is not None and edge is not None and owner_shape.Faces:
        faces += [(f, owner_shape) for f in owner_shape.ancestorsOfType(edge, Part.Face)]
    for _obj, shape in solids:
        faces += [(f, shape) for f in _faces_containing(shape, point, tangent)]
    all_solids = [s for _o, s in solids]
    if owner_shape is not None and owner_shape.Solids:
        all_solids.append(owner_shape)
    normals = []
    for face, shape in faces:
        others = [s for s in all_solids if s is not shape]
        if _free_side(face, point, tangent, others):
            normals.append(normal_at(face, point))
    return normals


def point_of(value):
    """ndarray (3,) of a FreeCAD.Vector or a 3-sequence (mm)."""
    if isinstance(value, FreeCAD.Vector):
        return array_from_vector(value)
    try:
        point = np.asarray(value, dtype=float).reshape(3)
    except (TypeError, ValueError):
        raise InputError("A point must be a FreeCAD.Vector or three numbers (mm), not %r."
                         % (value,)) from None
    return point
