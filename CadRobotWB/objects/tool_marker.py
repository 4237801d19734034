"""Tool marker: a simplified tool model placed on a path segment; its
placement is the TCP pose the robot must hold on that segment and on every
following segment up to the next marker (paper section 3, Figure 2)."""

import FreeCAD
import numpy as np
import Part

from .base import Proxy, type_of

#: "Cell tool" draws the cell's tool body (its TCP on the marker); the others
#: are the simple shapes of files saved before the tool library.
CELL_TOOL = "Cell tool"
SHAPES = [CELL_TOOL, "Torch", "Cone", "Ball"]


def tool_shape(style, length_mm, diameter_mm):
    """A simple solid of the tool in its TCP frame: the tip (or the ball's
    centre) at the origin, the body along -Z, so +Z points into the work."""
    length = max(float(length_mm), 4.0)
    radius = max(float(diameter_mm), 0.5) / 2.0
    back = FreeCAD.Vector(0, 0, -1)

    def at(z):
        return FreeCAD.Vector(0, 0, -z)

    if style == "Ball":
        return Part.makeSphere(radius).fuse(Part.makeCylinder(radius / 3.0, length, at(0), back))
    if style == "Cone":
        return Part.makeCone(0.0, radius, length, at(0), back)
    # Torch: wire stick-out at the tip, a nozzle cone, a cylindrical body.
    nozzle = 0.3 * length
    wire = Part.makeCylinder(min(0.6, radius / 2.0), 2.0, at(0), back)
    cone = Part.makeCone(radius * 0.35, radius, nozzle, at(2.0), back)
    body = Part.makeCylinder(radius, length - nozzle - 2.0, at(2.0 + nozzle), back)
    return body.fuse([cone, wire])


class ToolMarker(Proxy):
    """Proxy of a ``Part::FeaturePython`` whose Placement is the TCP pose {T}
    (in its container; the reader uses the global placement)."""

    TYPE = "ToolMarker"
    PROPERTIES = (
        ("App::PropertyEnumeration", "ToolShape", "Tool marker",
         "Shape drawn for the tool: 'Cell tool' is the cell's tool body with its TCP on the marker "
         "(a cell without a tool body: a torch of ToolLength and ToolDiameter)", SHAPES),
        ("App::PropertyLength", "ToolLength", "Tool marker",
         "Length of the drawn tool (Torch, Cone, Ball)", 80.0),
        ("App::PropertyLength", "ToolDiameter", "Tool marker",
         "Diameter of the drawn tool (Torch, Cone, Ball)", 16.0),
        ("App::PropertyLink", "Path", "Assignment",
         "Path this marker belongs to (empty: the path its origin lies on)", None),
        ("App::PropertyInteger", "Segment", "Assignment",
         "Segment number (1-based) this marker sets (0: the segment its origin lies on)", 0),
        ("App::PropertyString", "Governs", "Assignment",
         "Segments whose tool orientation this marker sets: its own and the following ones up to "
         "the next marker (read only, updated on recompute)", ""),
    )

    def setup(self, obj):
        obj.setEditorMode("Governs", 1)
        # Written by the cell's recompute: changing it must not touch the marker again.
        obj.setPropertyStatus("Governs", "Output")
        # Files saved before the tool library offer three shapes: add "Cell tool", keep the choice.
        if list(obj.getEnumerationsOfProperty("ToolShape") or []) != SHAPES:
            current = obj.ToolShape
            obj.ToolShape = SHAPES
            obj.ToolShape = current if current in SHAPES else SHAPES[1]

    def execute(self, obj):
        shape = marker_shape(obj)
        shape.Placement = obj.Placement
        obj.Shape = shape
        update_linked_cell(obj)


def marker_cell(marker):
    """The cell `marker` belongs to: the one holding it, else the one holding its Path; or None."""
    cell = holding_cell(marker)
    path = getattr(marker, "Path", None)
    if cell is None and path is not None:
        cell = holding_cell(path)
    return cell


def cell_tool_in_tcp(cell):
    """`cell`'s tool body placed in its TCP frame {T} (a Part.Compound), or None without a body.

    ``T_t_f = inv(T_f_t)`` places the flange: a marker at ``T_u_marker`` then
    draws the tool at ``T_u_marker @ inv(T_f_t)``, its TCP on the marker."""
    from . import tool_body
    from .convert import matrix_from_placement, placement_from_matrix
    try:
        shape = tool_body.cell_tool_shape(cell)
        T_f_t = matrix_from_placement(cell.ToolTCP)
        if shape is None or not np.isfinite(T_f_t).all():
            return None
        placed = shape.copy()
        placed.Placement = placement_from_matrix(np.linalg.inv(T_f_t)).multiply(shape.Placement)
        return Part.makeCompound([placed])
    except Exception as err:  # noqa: BLE001 -- a broken body: the marker falls back to a torch
        FreeCAD.Console.PrintWarning("CadRobot: the tool of %s cannot be drawn: %s\n"
                                     % (cell.Label, err))
        return None


def marker_shape(marker):
    """The shape `marker` draws in its own frame (the TCP frame, +Z into the work)."""
    if marker.ToolShape == CELL_TOOL:
        cell = marker_cell(marker)
        shape = cell_tool_in_tcp(cell) if cell is not None else None
        if shape is not None:
            return shape
        return tool_shape("Torch", marker.ToolLength, marker.ToolDiameter)
    return tool_shape(marker.ToolShape, marker.ToolLength, marker.ToolDiameter)


def cell_markers(cell):
    """Every tool marker that belongs to `cell` (:func:`marker_cell`), in document order."""
    return [o for o in cell.Document.Objects
            if type_of(o) == "ToolMarker" and marker_cell(o) is not None
            and marker_cell(o).Name == cell.Name]


def make(doc, name):
    obj = doc.addObject("Part::FeaturePython", name)
    ToolMarker(obj)
    return obj


def governs_text(governed):
    """The Governs text of a marker: ``"segments 3-17 of Path001"``, or why it sets none.

    Parameters
    ----------
    governed : reader.Governed or CadRobotError
        An entry of :func:`reader.governed_segments`.
    """
    if isinstance(governed, Exception):
        return "nothing: %s" % governed
    first, last = governed.first, governed.last
    where = "segment %d" % first if first == last else "segments %d-%d" % (first, last)
    return "%s of %s" % (where, governed.path.Label)


def update_governs(cell):
    """Set the Governs property of every tool marker of `cell` (only where it changed)."""
    from . import reader  # reader reads these objects; imported when first used
    document = cell.Document
    for name, governed in reader.governed_segments(cell).items():
        marker = document.getObject(name)
        text = governs_text(governed)
        if getattr(marker, "Governs", text) != text:
            marker.Governs = text


def holding_cell(obj):
    """The cell whose group holds `obj`, directly or in a nested group; None if none does."""
    todo, seen = [obj], set()
    while todo:
        child = todo.pop()
        for parent in child.InList:
            if parent.Name in seen or child not in (getattr(parent, "Group", None) or []):
                continue
            if type_of(parent) == "Cell":
                return parent
            seen.add(parent.Name)
            todo.append(parent)
    return None


def update_linked_cell(marker):
    """Governs of the cell of `marker`'s Path, when `marker` lies outside every cell's group.

    A marker in a cell's group is followed by the cell's own recompute
    (:meth:`Cell.execute`); one only linked to a path is not, so it updates that cell."""
    path = getattr(marker, "Path", None)
    if path is None or holding_cell(marker) is not None:
        return
    cell = holding_cell(path)
    if cell is not None:
        update_governs_safely(cell)


def update_governs_safely(cell):
    """:func:`update_governs` from a recompute: a failure is a warning, never a traceback."""
    try:
        update_governs(cell)
    except Exception as err:  # a half-built cell; generating reports what is wrong
        FreeCAD.Console.PrintWarning("CadRobot: tool markers of %s not updated: %s\n"
                                     % (cell.Label, err))
