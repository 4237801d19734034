"""Opening files saved without the GUI (by ``cadrobot`` or FreeCADCmd).

FreeCAD before 1.1 hides every object of a file that has no GuiDocument.xml
when it opens it in the GUI (FreeCAD issues #28555 and #28714), and leaves
the camera where it was. When such a file holds CadRobot objects, their
restore schedules :func:`repair`: it shows what Document.xml says is visible
(origin axes and planes stay hidden, as the GUI keeps them) and fits the view.
"""

import xml.etree.ElementTree as ElementTree
import zipfile

import FreeCAD

_pending = set()


def saved_visibility(path):
    """{object name: bool} from a headless-saved .FCStd, or None when the file
    has a GuiDocument.xml (FreeCAD restores those itself)."""
    try:
        with zipfile.ZipFile(path) as archive:
            if "GuiDocument.xml" in archive.namelist():
                return None
            root = ElementTree.fromstring(archive.read("Document.xml"))
    except (OSError, KeyError, zipfile.BadZipFile, ElementTree.ParseError):
        return None
    visible = {}
    for obj in root.iter("Object"):
        prop = obj.find("./Properties/Property[@name='Visibility']/Bool")
        if obj.get("name") and prop is not None:
            visible[obj.get("name")] = prop.get("value") == "true"
    return visible


def schedule_repair(doc):
    """Repair `doc` once, after FreeCAD's own GUI restore has run."""
    if doc.Name in _pending:
        return
    _pending.add(doc.Name)
    from PySide import QtCore
    QtCore.QTimer.singleShot(0, lambda name=doc.Name: repair(name))


def repair(doc_name):
    """Give our objects their view providers (the GUI restore may reset the
    group's), apply the saved visibility and fit the view if the file needs it."""
    import FreeCADGui
    from ..objects.base import type_of
    from . import view_providers
    _pending.discard(doc_name)
    doc = FreeCAD.listDocuments().get(doc_name)
    if doc is None or FreeCADGui.getDocument(doc_name) is None:
        return
    for obj in doc.Objects:
        if type_of(obj):
            view_providers.attach(obj)
    visible = saved_visibility(doc.FileName)
    if visible is None:
        return
    for obj in doc.Objects:
        hidden_by_gui = obj.TypeId in ("App::Origin", "App::Line", "App::Plane")
        if obj.Name in visible and obj.ViewObject is not None and not hidden_by_gui:
            obj.ViewObject.Visibility = visible[obj.Name]
    view = FreeCADGui.getDocument(doc_name).activeView()
    if hasattr(view, "fitAll"):
        view.viewIsometric()
        view.fitAll()
