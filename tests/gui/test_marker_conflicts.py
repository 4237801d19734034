"""A tool marker on a segment another marker sets, in the GUI (issue 14, item 4).

The box of test_commands (100 x 60 x 20 mm); the path runs along its front top
edge (segment 1) and its right top edge (segment 2). "First" sits on the front
edge square to the bisector of the two faces (work angle 90); the Tool marker
command at work angle 60 makes a marker 30 degrees from it (the work angle turns
the tool about the edge). The question is answered by a stand-in for the dialog.
"""

import FreeCAD
import FreeCADGui
import pytest

from conftest import process_events
from test_commands import (FRONT, RIGHT, V, cell_of, element_name, names, new_objects, run,
                           same_placement, select)
import test_commands

from CadRobotWB import api
from CadRobotWB.gui import marker_conflicts, risk_area_panel
from CadRobotWB.objects import base as objects_base
from CadRobotWB.objects import reader

# The fixtures of test_commands: the box, its cell, the journaled lines.
box_doc, cell_doc, journal = test_commands.box_doc, test_commands.cell_doc, test_commands.journal


@pytest.fixture
def asked(monkeypatch):
    """Record the questions; answer with ``asked.answer`` (None = Cancel)."""
    class Asked(list):
        answer = None
    questions = Asked()

    def ask(conflict, moved=False):
        conflict.other_names = [o.Name for o in conflict.others]     # they may be deleted next
        questions.append((conflict, moved))
        return questions.answer

    def ask_auto(path, conflicts):
        questions.append((path, dict(conflicts)))
        return questions.answer
    monkeypatch.setattr(marker_conflicts, "ask_user", ask)
    monkeypatch.setattr(marker_conflicts, "ask_user_auto", ask_auto)
    marker_conflicts.install()
    return questions


def front_right_path(doc):
    box, cell = doc.getObject("Box"), cell_of(doc)
    path = api.make_path(doc, cell, [(box, [element_name(box, "Edge", *e) for e in (FRONT, RIGHT)])])
    first = api.make_tool_marker(doc, cell, api.edge_tool_placement(box, element_name(box, "Edge", *FRONT),
                                                                    point=V(30, 0, 20)), name="First")
    doc.recompute()
    process_events()
    return box, cell, path, first


def markers(doc):
    return sorted(o.Label for o in doc.Objects if objects_base.type_of(o) == "ToolMarker")


def marker_command_at_60_degrees(doc, box, cell):
    cell.WorkAngle = 60.0
    doc.recompute()
    FreeCADGui.Selection.clearSelection()
    select(box, element_name(box, "Edge", *FRONT), V(70, 0, 20))
    before = names(doc)
    run("CadRobot_ToolMarker")
    return new_objects(doc, before)


def test_tool_marker_command_asks_and_replaces(cell_doc, asked, journal):
    box, cell, path, first = front_right_path(cell_doc)
    asked.answer = "replace"
    made = marker_command_at_60_degrees(cell_doc, box, cell)
    ((conflict, moved),) = asked
    assert not moved and conflict.other_names == ["First"]
    assert (conflict.path, conflict.segment, conflict.next_free) == (path, 1, 2)
    assert conflict.angles_deg[0] == pytest.approx(30.0, abs=1e-6)
    assert any("on_conflict='replace'" in line for line in journal)
    assert len(made) == 1 and markers(cell_doc) == [cell_doc.getObject(made[0]).Label]
    reader.path_orientations(cell)      # one orientation per segment: no conflict left


def test_tool_marker_command_new_stretch(cell_doc, asked):
    box, cell, path, first = front_right_path(cell_doc)
    asked.answer = "next"
    (made,) = marker_command_at_60_degrees(cell_doc, box, cell)
    marker = cell_doc.getObject(made)
    assert (marker.Path, marker.Segment) == (path, 2)
    assert first.Governs == "segment 1 of %s" % path.Label
    assert marker.Governs == "segment 2 of %s" % path.Label


def test_tool_marker_command_cancel_adds_nothing(cell_doc, asked):
    box, cell, path, first = front_right_path(cell_doc)
    undo_count = cell_doc.UndoCount
    assert marker_command_at_60_degrees(cell_doc, box, cell) == []
    assert len(asked) == 1 and cell_doc.UndoCount == undo_count
    assert markers(cell_doc) == ["First"]


def test_no_question_without_a_conflict(cell_doc, asked):
    box, cell, path, first = front_right_path(cell_doc)
    FreeCADGui.Selection.clearSelection()
    select(box, element_name(box, "Edge", *FRONT), V(70, 0, 20))     # work angle 90: agrees with First
    run("CadRobot_ToolMarker")
    assert asked == [] and len(markers(cell_doc)) == 2


def second_on_the_right_edge(doc, box, cell):
    right = api.edge_tool_placement(box, element_name(box, "Edge", *RIGHT), point=V(100, 30, 20))
    second = api.make_tool_marker(doc, cell, right, name="Second")
    process_events()                    # created: not a move, nothing asked
    return second


def test_moving_a_marker_onto_another_asks_once_and_cancel_puts_it_back(cell_doc, asked):
    box, cell, path, first = front_right_path(cell_doc)
    second = second_on_the_right_edge(cell_doc, box, cell)
    assert asked == []
    home = FreeCAD.Placement(second.Placement)
    # One edit that sets the Placement twice (as a drag does): one question.
    second.Placement = FreeCAD.Placement(V(60, 0, 20), home.Rotation)
    second.Placement = FreeCAD.Placement(V(70, 0, 20), home.Rotation)
    cell_doc.recompute()
    process_events()
    ((conflict, moved),) = asked
    assert moved and conflict.name == "Second" and conflict.other_names == ["First"]
    assert conflict.angles_deg[0] == pytest.approx(90.0, abs=1e-6)     # right edge's tool vs front's
    assert same_placement(second.Placement, home, 1e-9), "Cancel puts it back"
    process_events()
    assert len(asked) == 1, "our own write asks nothing"
    # Undo of "put back" returns it onto the front edge: undo asks nothing.
    cell_doc.undo()
    cell_doc.recompute()
    process_events()
    assert len(asked) == 1
    assert (second.Placement.Base - V(70, 0, 20)).Length < 1e-9


def test_editing_segment_onto_another_and_replace(cell_doc, asked):
    box, cell, path, first = front_right_path(cell_doc)
    second = second_on_the_right_edge(cell_doc, box, cell)
    asked.answer = "replace"
    second.Path = path
    second.Segment = 1
    cell_doc.recompute()
    process_events()
    assert len(asked) == 1
    assert markers(cell_doc) == ["Second"]
    assert second.Governs == "segments 1-2 of %s" % path.Label


def test_opening_a_document_with_a_conflict_asks_nothing(cell_doc, asked, tmp_path):
    box, cell, path, first = front_right_path(cell_doc)
    api.make_tool_marker(cell_doc, cell, FreeCAD.Placement(V(70, 0, 20), FreeCAD.Rotation(V(1, 0, 0), 150)),
                         name="Kept", on_conflict="keep")
    process_events()
    target = str(tmp_path / "conflict.FCStd")
    cell_doc.saveAs(target)
    reopened = FreeCAD.openDocument(target)
    try:
        reopened.recompute()
        process_events()
        assert asked == []
    finally:
        FreeCAD.closeDocument(reopened.Name)


def test_auto_markers_command_asks_and_keeps_the_existing(cell_doc, asked):
    box, cell, path, first = front_right_path(cell_doc)
    cell.WorkAngle = 60.0                       # the automatic ones now differ from First by 30 deg
    cell_doc.recompute()
    FreeCADGui.Selection.clearSelection()
    select(path)
    asked.answer = "skip"
    before = names(cell_doc)
    run("CadRobot_AutoToolMarkers")
    ((asked_path, conflicts),) = asked
    assert asked_path == path and sorted(conflicts) == [1]
    made = [cell_doc.getObject(n) for n in new_objects(cell_doc, before)]
    assert [m.Segment for m in made] == [2] and "First" in markers(cell_doc)


def test_auto_markers_command_cancel_adds_nothing(cell_doc, asked):
    box, cell, path, first = front_right_path(cell_doc)
    cell.WorkAngle = 60.0
    cell_doc.recompute()
    FreeCADGui.Selection.clearSelection()
    select(path)
    run("CadRobot_AutoToolMarkers")
    assert len(asked) == 1 and markers(cell_doc) == ["First"]


def test_risk_area_panel_says_why_it_has_no_list(cell_doc, asked):
    box, cell, path, first = front_right_path(cell_doc)
    api.make_tool_marker(cell_doc, cell, FreeCAD.Placement(V(70, 0, 20), FreeCAD.Rotation(V(1, 0, 0), 150)),
                         name="Kept", on_conflict="keep")
    process_events()
    panel = risk_area_panel.RiskAreaPanel(cell)
    text = panel.message.text()
    assert panel.list.count() == 0
    assert "'First'" in text and "'Kept'" in text and "both set segment 1" in text
    assert "none needed" not in text


def wait_until(condition, rounds=100):
    """Process events (20 ms at a time) until `condition()` holds or `rounds` pass."""
    from PySide import QtCore
    loop = QtCore.QEventLoop()
    for _ in range(rounds):
        if condition():
            return True
        QtCore.QTimer.singleShot(20, loop.quit)
        loop.exec_()
    return condition()


def test_dragging_asks_once_when_the_edit_ends(cell_doc, asked):
    box, cell, path, first = front_right_path(cell_doc)
    second = second_on_the_right_edge(cell_doc, box, cell)
    gui_doc = FreeCADGui.getDocument(cell_doc.Name)
    gui_doc.setEdit(second.Name, 1)                    # Transform: the dragger is up
    home = FreeCAD.Placement(second.Placement)
    for x in (90, 70, 50):                             # the drag moves it step by step
        second.Placement = FreeCAD.Placement(V(x, 0, 20), home.Rotation)
        process_events()
    assert not wait_until(lambda: asked, rounds=25), "nothing asked while dragging"
    gui_doc.resetEdit()
    assert wait_until(lambda: asked)
    process_events()
    assert len(asked) == 1 and asked[0][1]


def test_the_real_dialog_explains_and_answers(cell_doc, monkeypatch):
    from PySide import QtCore, QtGui
    box, cell, path, first = front_right_path(cell_doc)
    conflict = api.tool_marker_conflict(cell, placement=FreeCAD.Placement(
        V(70, 0, 20), FreeCAD.Rotation(V(1, 0, 0), 150)), name="New")
    text, informative, replace, stretch = marker_conflicts.question_texts(conflict)
    assert "'New' sets segment 1 of path 'Path', which 'First' already sets" in text
    assert "segment 1 keeps the orientation of 'First'" in informative
    assert "'New' is linked to segment 2" in informative and "add no marker" in informative
    seen = []

    def click_new_stretch():
        box_widget = QtGui.QApplication.activeModalWidget()
        seen.append(box_widget.text())
        button = next(b for b in box_widget.buttons() if b.text() == stretch)
        button.click()
    QtCore.QTimer.singleShot(200, click_new_stretch)
    assert marker_conflicts.ask_user(conflict) == "next"
    assert seen == [text]
    QtCore.QTimer.singleShot(200, lambda: QtGui.QApplication.activeModalWidget().reject())
    assert marker_conflicts.ask_user(conflict, moved=True) is None
