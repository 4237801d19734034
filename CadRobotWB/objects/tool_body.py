"""A cell's tool body in the flange frame {F}: as a FreeCAD shape (tool
markers draw it) and as a triangle mesh (the collision check uses it).

The body is the library tool's solids (``robots/catalog/tools.py``) when the cell's
``ToolType`` names one, the solid in ``ToolBody`` for "Custom body", and
nothing for a custom tool without a body (the cells saved before the tool
library: only a TCP and a mass).

A library tool's body sits so that its tip is on the cell's TCP: a TCP set
apart from the library's (a calibrated TCP, a longer wire stick-out) moves
the body with it (:func:`library_offset`).

A custom body is read in its own coordinates: the shape with its placement
taken off, so the flange {F} is the solid's own origin, whatever its
placement in the drawing (``ToolTCP`` is given in the same coordinates).
"""

import FreeCAD
import numpy as np
import Part

from ..errors import InputError
from ..robots.catalog import tools
from .base import describe
from .convert import matrix_from_placement, placement_from_matrix

#: Tessellation tolerance of a custom tool body, mm.
TOLERANCE_MM = 0.5


def solid_shape(solid):
    """Part.Shape of a :class:`tools.Solid` in {F}."""
    size = [float(v) for v in solid.size_mm]
    if solid.kind == "cylinder":
        shape = Part.makeCylinder(size[0], size[1])
    elif solid.kind == "cone":
        shape = Part.makeCone(size[0], size[1], size[2])
    elif solid.kind == "sphere":
        shape = Part.makeSphere(size[0])
    else:
        shape = Part.makeBox(size[0], size[1], size[2], FreeCAD.Vector(-size[0] / 2, -size[1] / 2, 0))
    shape.Placement = placement_from_matrix(solid.T_f_p)
    return shape


def library_shape(name):
    """Part.Compound of library tool `name`'s solids, in {F} (at the library's TCP)."""
    return Part.makeCompound([solid_shape(s) for s in tools.get(name).solids])


def library_offset(cell):
    """ndarray (4, 4): ``T_f_t(cell) @ inv(T_f_t(library))``, what moves the library
    body of `cell`'s tool so that its tip sits on the cell's TCP (identity when the
    cell has the library's TCP)."""
    T_f_t = matrix_from_placement(cell.ToolTCP)
    if not np.isfinite(T_f_t).all():
        return np.eye(4)
    return T_f_t @ np.linalg.inv(tools.get(cell.ToolType).T_f_t)


def own_shape(body):
    """A copy of `body`'s shape in its own coordinates (its placement taken off)."""
    shape = body.Shape.copy()
    shape.Placement = FreeCAD.Placement()
    return shape


def check_body(cell, body):
    """Raise InputError unless `body` is a document object with a solid shape.

    Parameters
    ----------
    cell : the cell the body is for (named in the message)
    body : App.DocumentObject
    """
    shape = getattr(body, "Shape", None)
    name = getattr(body, "Label", None) or repr(body)
    if shape is None or not hasattr(body, "Document"):
        raise InputError("Cell %s: the tool body '%s' is not a document object with a shape. "
                         "Give a solid of the document (e.g. a Part or PartDesign body)."
                         % (describe(cell), name), cell.Name)
    if shape.isNull() or not shape.Solids:
        raise InputError("Cell %s: the tool body %s has no solid (it is a sketch, a wire or a "
                         "surface). Give a closed solid, e.g. a Pad or a Part primitive."
                         % (describe(cell), describe(body)), cell.Name)


def cell_tool_shape(cell):
    """Part.Shape of `cell`'s tool body in {F}, or None (no body)."""
    kind = getattr(cell, "ToolType", tools.CUSTOM)
    if kind in tools.LIBRARY:
        shape = Part.makeCompound([library_shape(kind)])
        shape.Placement = placement_from_matrix(library_offset(cell))
        return shape
    body = getattr(cell, "ToolBody", None)
    shape = getattr(body, "Shape", None)
    if shape is None or shape.isNull() or not shape.Solids:
        return None
    return own_shape(body)


def shape_mesh(shape, tolerance_mm=TOLERANCE_MM):
    """(vertices (N, 3) mm, faces (M, 3) int) of `shape` as placed, or None when it has none."""
    points, faces = shape.tessellate(tolerance_mm)
    if not faces:
        return None
    return (np.array([(p.x, p.y, p.z) for p in points], dtype=float), np.array(faces, dtype=int))


def cell_tool_mesh(cell):
    """(vertices (N, 3) mm in {F}, faces (M, 3) int) of `cell`'s tool body, or None."""
    kind = getattr(cell, "ToolType", tools.CUSTOM)
    if kind in tools.LIBRARY:
        vertices, faces = tools.get(kind).mesh()
        T = library_offset(cell)
        return vertices @ T[:3, :3].T + T[:3, 3], faces
    shape = cell_tool_shape(cell)
    return None if shape is None else shape_mesh(shape)


def cell_tool_label(cell):
    """What the user calls `cell`'s tool: the library name, the body's label, or ""."""
    kind = getattr(cell, "ToolType", tools.CUSTOM)
    if kind in tools.LIBRARY:
        return kind
    body = getattr(cell, "ToolBody", None)
    return body.Label if body is not None else ""


def tool_body_objects(doc):
    """The document objects some cell of `doc` uses as its tool body (never obstacles)."""
    from .base import objects_of_type
    return [c.ToolBody for c in objects_of_type(doc, "Cell")
            if getattr(c, "ToolBody", None) is not None and getattr(c, "ToolType", "") == tools.CUSTOM]
