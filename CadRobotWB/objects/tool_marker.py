"""Tool marker: a simplified tool model placed on a path segment; its
placement is the TCP pose the robot must hold on that segment and on every
following segment up to the next marker (paper section 3, Figure 2)."""

import FreeCAD
import Part

from .base import Proxy, type_of

SHAPES = ["Torch", "Cone", "Ball"]


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
        ("App::PropertyEnumeration", "ToolShape", "Tool marker", "Shape drawn for the tool", SHAPES),
        ("App::PropertyLength", "ToolLength", "Tool marker", "Length of the drawn tool", 80.0),
        ("App::PropertyLength", "ToolDiameter", "Tool marker", "Diameter of the drawn tool", 16.0),
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

    def execute(self, obj):
        shape = tool_shape(obj.ToolShape, obj.ToolLength, obj.ToolDiameter)
        shape.Placement = obj.Placement
        obj.Shape = shape
        update_linked_cell(obj)


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
