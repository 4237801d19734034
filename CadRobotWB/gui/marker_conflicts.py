"""Marker conflicts in the GUI: ask the user when a tool marker lands on a segment
another marker already sets with another orientation (issue 14, item 4).

Three moments ask:

* the Tool marker command, before it adds the marker (:func:`ask_user`);
* the automatic markers command, before it adds any (:func:`ask_user_auto`);
* a marker moved afterwards, by dragging it or editing its Placement, Path or
  Segment (:class:`MarkerWatch`, a document observer): once per edit, never
  while a document is being restored or undone, never for our own writes.

The answers are the API's ``on_conflict`` values: "replace" deletes the other
marker, "next" links this marker to the following segment so a new stretch
starts there (see :mod:`CadRobotWB.objects.tool_marker`), None cancels.
Tests replace :func:`ask_user` / :func:`ask_user_auto` with a function returning
the answer.
"""

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from .. import api
from ..objects import base as objects_base
from ..objects import tool_marker

translate = FreeCAD.Qt.translate

# The properties that move a marker to another segment.
MOVING_PROPERTIES = ("Placement", "Path", "Segment")
# How often a pending check looks again while the marker is being dragged, ms.
EDIT_POLL_MS = 300


def _choose(title, text, informative, choices):
    """A modal question; `choices` are (answer, button text, enabled); None when cancelled."""
    box = QtGui.QMessageBox(FreeCADGui.getMainWindow())
    box.setIcon(QtGui.QMessageBox.Question)
    box.setWindowTitle(title)
    box.setText(text)
    box.setInformativeText(informative)
    buttons = {}
    for answer, label, enabled in choices:
        button = box.addButton(label, QtGui.QMessageBox.AcceptRole)
        button.setEnabled(enabled)
        buttons[answer] = button
    cancel = box.addButton(QtGui.QMessageBox.Cancel)
    box.setDefaultButton(cancel)
    box.exec_()
    clicked = box.clickedButton()
    return next((answer for answer, button in buttons.items() if button is clicked), None)


def question_texts(conflict, moved=False):
    """(text, informative text, replace label, next label) of the dialog for `conflict`."""
    others = conflict.others_text()
    text = conflict.describe_problem() + " " + translate(
        "CadRobot_ToolMarker", "A marker sets its segment and the following ones up to the next "
        "marker, so one segment cannot take two orientations.")
    lines = [translate("CadRobot_ToolMarker", "Replace: delete {0}; '{1}' sets segment {2}.").format(
        others, conflict.name, conflict.segment)]
    if conflict.next_free is not None:
        lines.append(translate(
            "CadRobot_ToolMarker", "New stretch: '{0}' is linked to segment {1} (its Path and Segment "
            "properties); segment {2} keeps the orientation of {3}, and '{0}' sets segment {1} and "
            "the following ones up to the next marker.").format(
                conflict.name, conflict.next_free, conflict.segment, others))
    else:
        lines.append(translate("CadRobot_ToolMarker", "New stretch is not possible: {0}.").format(
            conflict.next_blocked))
    lines.append(translate("CadRobot_ToolMarker", "Cancel: {0}.").format(
        translate("CadRobot_ToolMarker", "put the marker back where it was") if moved
        else translate("CadRobot_ToolMarker", "add no marker")))
    replace = translate("CadRobot_ToolMarker", "Replace {0}").format(others)
    stretch = translate("CadRobot_ToolMarker", "New stretch from segment {0}").format(
        conflict.next_free if conflict.next_free is not None else conflict.segment + 1)
    return text, "\n\n".join(lines), replace, stretch


def ask_user(conflict, moved=False):
    """Ask what to do about `conflict`: "replace", "next", or None (cancel)."""
    text, informative, replace, stretch = question_texts(conflict, moved)
    return _choose(translate("CadRobot_ToolMarker", "Two markers on one segment"), text, informative,
                   [("replace", replace, True), ("next", stretch, conflict.next_free is not None)])


def auto_question_texts(path, conflicts):
    """(text, informative text) of the automatic markers' question."""
    listed = "\n".join(
        translate("CadRobot_AutoToolMarkers", "segment {0}: {1}, {2:.1f}\u00b0 apart").format(
            k, c.others_text(), max(c.angles_deg)) for k, c in sorted(conflicts.items())[:8])
    if len(conflicts) > 8:
        listed += "\n" + translate("CadRobot_AutoToolMarkers", "... and {0} more").format(len(conflicts) - 8)
    text = translate(
        "CadRobot_AutoToolMarkers", "{0} segments of path {1} already have a tool marker whose "
        "orientation differs from the automatic one.").format(len(conflicts), objects_base.describe(path))
    informative = listed + "\n\n" + translate(
        "CadRobot_AutoToolMarkers", "Replace: delete those markers and add a marker on every segment. "
        "Keep them: add markers only on the other segments. Cancel: add nothing.")
    return text, informative


def ask_user_auto(path, conflicts):
    """Ask what to do about the automatic markers' `conflicts`: "replace", "skip" or None."""
    text, informative = auto_question_texts(path, conflicts)
    return _choose(translate("CadRobot_AutoToolMarkers", "Existing tool markers"), text, informative,
                   [("replace", translate("CadRobot_AutoToolMarkers", "Replace them"), True),
                    ("skip", translate("CadRobot_AutoToolMarkers", "Keep them"), True)])


# --- a marker moved after it was placed --------------------------------------------------------

def cell_of_marker(marker):
    """The cell whose markers include `marker` (its group's, or its linked path's), or None."""
    cell = tool_marker.holding_cell(marker)
    if cell is None and getattr(marker, "Path", None) is not None:
        cell = tool_marker.holding_cell(marker.Path)
    return cell


class MarkerWatch:
    """Document observer: a tool marker moved onto a conflicting segment asks once.

    A change of Placement, Path or Segment is noted (with the values before the
    first change of the edit); the check runs when control is back in the event
    loop, after the whole edit, and while the marker is in edit mode (being
    dragged) it waits until the edit ends. Ignored: documents being restored or
    undone/redone, markers created in that same turn (their command asked), and
    the changes this watch makes itself.
    """

    def __init__(self):
        self.before = {}        # (doc name, marker name) -> {property: value before the edit}
        self.pending = []       # (doc name, marker name) in the order they changed
        self.fresh = set()      # (doc name, name) created since the last check
        self.quiet = 0          # > 0 while we write to markers ourselves
        self.scheduled = False

    # -- observer slots --
    def _watched(self, obj, prop=None):
        if prop is not None and prop not in MOVING_PROPERTIES:
            return False
        if self.quiet or objects_base.type_of(obj) != "ToolMarker":
            return False
        doc = obj.Document
        return not (getattr(doc, "Restoring", False) or getattr(doc, "Transacting", False)
                    or getattr(obj, "Removing", False))

    def slotCreatedObject(self, obj):
        self.fresh.add((obj.Document.Name, obj.Name))
        self._schedule(0)

    def slotBeforeChangeObject(self, obj, prop):
        if not self._watched(obj, prop):
            return
        values = self.before.setdefault((obj.Document.Name, obj.Name), {})
        if prop not in values:
            value = getattr(obj, prop)
            values[prop] = FreeCAD.Placement(value) if prop == "Placement" else value

    def slotChangedObject(self, obj, prop):
        if not self._watched(obj, prop):
            return
        key = (obj.Document.Name, obj.Name)
        if key not in self.pending:
            self.pending.append(key)
        self._schedule(0)

    # -- checking --
    def _schedule(self, delay_ms):
        if not self.scheduled:
            self.scheduled = True
            QtCore.QTimer.singleShot(delay_ms, self.check_pending)

    def _in_edit(self, doc_name, name):
        gui_doc = FreeCADGui.getDocument(doc_name) if doc_name in FreeCAD.listDocuments() else None
        vp = gui_doc.getInEdit() if gui_doc is not None else None
        return vp is not None and getattr(vp, "Object", None) is not None and vp.Object.Name == name

    def check_pending(self):
        """Check every marker changed since the last call (asking at most once each)."""
        self.scheduled = False
        fresh, self.fresh = self.fresh, set()
        waiting = []
        for key in list(self.pending):
            if key in fresh:        # created by a command (that asked) or a script: not a move
                self.before.pop(key, None)
                continue
            if self._in_edit(*key):
                waiting.append(key)
                continue
            self.check(key)
        self.pending = waiting
        if waiting:
            self._schedule(EDIT_POLL_MS)

    def check(self, key):
        """Ask about marker `key` (doc name, name) if it now conflicts; undo the move on Cancel."""
        before = self.before.pop(key, {})
        doc_name, name = key
        if doc_name not in FreeCAD.listDocuments():
            return None
        doc = FreeCAD.getDocument(doc_name)
        marker = doc.getObject(name)
        cell = cell_of_marker(marker) if marker is not None else None
        if cell is None:
            return None
        conflict = api.tool_marker_conflict(cell, marker=marker)
        if conflict is None:
            return None
        answer = ask_user(conflict, moved=True)
        self.quiet += 1
        try:
            if answer is None:
                self._restore(doc, marker, before)
            else:
                from ..commands import base as command_base
                command_base.run_journaled(
                    doc, translate("CadRobot_ToolMarker", "Resolve tool marker conflict"),
                    [command_base.call("api.resolve_marker_conflict", cell, marker, answer)])
        finally:
            self.quiet -= 1
        return answer

    def _restore(self, doc, marker, before):
        """Put `marker`'s moving properties back (one undo step)."""
        if not before:
            return
        doc.openTransaction(translate("CadRobot_ToolMarker", "Put tool marker back"))
        try:
            for prop, value in before.items():
                setattr(marker, prop, value)
            doc.recompute()
        except Exception:
            doc.abortTransaction()
            raise
        doc.commitTransaction()


_watch = None


def install():
    """Start watching documents for moved markers (once; later calls do nothing)."""
    global _watch
    if _watch is None:
        _watch = MarkerWatch()
        FreeCAD.addDocumentObserver(_watch)
    return _watch


def watch():
    """The installed MarkerWatch, or None."""
    return _watch
