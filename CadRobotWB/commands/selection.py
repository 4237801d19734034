"""Which cell a command acts on: the selected one, or the document's only one."""

import FreeCAD
import FreeCADGui

from ..objects import base


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
