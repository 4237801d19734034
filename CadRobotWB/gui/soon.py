"""Work on a document object once the event loop runs again, if the object still exists.

FreeCAD draws a new shape, and restores an opened file's view providers,
after the call that changed them returns; what must follow those steps is
queued here.
"""

import FreeCAD
from PySide import QtCore


def call_soon(obj, action):
    """Call ``action(obj)`` from the event loop, unless `obj` or its document is gone by then.

    Parameters
    ----------
    obj : App.DocumentObject
    action : callable
        Takes the object (looked up again by document and internal name).
    """
    doc_name, name = obj.Document.Name, obj.Name

    def run():
        doc = FreeCAD.listDocuments().get(doc_name)
        again = doc.getObject(name) if doc is not None else None
        if again is not None:
            action(again)

    QtCore.QTimer.singleShot(0, run)
