"""Which cell a command acts on: the selected one, or the document's only one."""

import FreeCAD
import FreeCADGui

from ..objects import base, picking


def _cell_of(obj):
    """`obj` if it is a cell, else the cell holding it (or None)."""
    if base.type_of(obj) == "Cell":
        return obj
    for parent in getattr(obj, "InList", []) or []:
        if base.type_of(parent) == "Cell":
            return parent
    return None


def find_cell():
    """The cell to act on, or None.

    The cell of the first selected object that is a cell or lies in one;
    with no such selection, the active document's cell if it has exactly one.

    Returns
    -------
    App.DocumentObject or None
    """
    doc = FreeCAD.ActiveDocument
    if doc is None:
        return None
    for obj in FreeCADGui.Selection.getSelection(doc.Name):
        cell = _cell_of(obj)
        if cell is not None:
            return cell
    cells = base.objects_of_type(doc, "Cell")
    return cells[0] if len(cells) == 1 else None


# --- what is selected ---------------------------------------------------------------------

class Picked:
    """One selected thing: an object, one of its elements (or "" for the whole
    object) and the point picked on it in {U} (None when there is none).

    Attributes
    ----------
    obj : App.DocumentObject
    sub : str
        ``"Edge3"``, ``"Face1"``, ``"Vertex2"`` or ``""``.
    point : FreeCAD.Vector or None
    """

    def __init__(self, obj, sub="", point=None):
        self.obj, self.sub, self.point = obj, sub, point

    @property
    def kind(self):
        """``"Vertex"``, ``"Edge"``, ``"Face"``, another element type, or ``""``."""
        return self.sub.rstrip("0123456789")

    @property
    def cad_type(self):
        """The CadRobot type of the object (``"RobotPath"``, ...), ``""`` for others."""
        return base.type_of(self.obj)

    def __repr__(self):
        return "Picked(%s, %r, %s)" % (self.obj.Name, self.sub, self.point)


def selected(doc=None):
    """Everything selected in `doc` (default: the active document), in the
    order it was selected; one :class:`Picked` per element or whole object.

    Returns
    -------
    list of Picked
    """
    doc = doc or FreeCAD.ActiveDocument
    if doc is None:
        return []
    items = []
    for sel in FreeCADGui.Selection.getCompleteSelection():
        obj = sel.Object
        if obj is None or obj.Document is not doc:
            continue
        subs = [s for s in sel.SubElementNames if s] or [""]
        points = list(sel.PickedPoints or [])
        for i, sub in enumerate(subs):
            point = points[i] if sub and i < len(points) else None
            items.append(Picked(obj, sub, FreeCAD.Vector(point) if point is not None else None))
    return items


def kinds(items):
    """The sorted element kinds of `items`, e.g. ``["Edge", "Face"]``."""
    return sorted(item.kind for item in items)


def only_objects(items):
    """True when `items` are whole objects (no element picked), possibly none."""
    return all(not item.sub for item in items)


def path_using_edge(cell, obj, sub):
    """The first path of `cell` whose Source holds `obj` whole or its element `sub`, or None."""
    if cell is None:
        return None
    for member in getattr(cell, "Group", []) or []:
        if base.type_of(member) != "RobotPath":
            continue
        for source, subs in member.Source or []:
            if source == obj and (not any(subs) or sub in subs):
                return member
    return None


def global_element(obj, sub):
    """Element `sub` of `obj` in {U} (every enclosing App::Part placement applied).

    `sub` may also be a sub-element path from `obj` (``"Box.Vertex3"`` of a
    Part, as a selection observer gets it); ``getSubObject`` applies the
    placements along it.
    """
    if "." in sub:
        return obj.getSubObject(sub)
    return picking.element(picking.global_shape(obj), obj, sub)


def point_on(obj, sub, point, tol_mm=1.0):
    """`point` if it lies within `tol_mm` of element `sub` of `obj`, else None.

    A point picked in the 3D view lies on the element; one from a script or
    the tree is (0, 0, 0) and says nothing.
    """
    import Part
    if point is None:
        return None
    try:
        element = global_element(obj, sub)
        distance = element.distToShape(Part.Vertex(point))[0]
    except Exception:  # noqa: BLE001 -- no shape or no such element: ignore the point
        return None
    return point if distance <= tol_mm else None


def picked_point(items):
    """A point in {U} from the selection, or None: the first selected vertex, point
    object (a shape of one vertex), or else the point picked on any element."""
    for item in items:
        if item.kind == "Vertex":
            return FreeCAD.Vector(global_element(item.obj, item.sub).Point)
        shape = getattr(item.obj, "Shape", None)
        if not item.sub and shape is not None and len(shape.Vertexes) == 1 and not shape.Edges:
            return FreeCAD.Vector(picking.global_shape(item.obj).Vertexes[0].Point)
    for item in items:
        if item.sub and item.point is not None:
            return FreeCAD.Vector(item.point)
    return None
