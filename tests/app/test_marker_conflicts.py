"""A second tool marker on a segment another marker sets (issue 14, item 4).

The path is the five-segment polyline of test_marker_inheritance: segment 1
(0,0)-(50,0), 2 up to (50,50), 3 to (100,50), 4 down to (100,0), 5 to (150,0).
"First" lies on segment 1 pointing down; a tool turned 30 deg about Y on
segment 1 differs from it by 30 deg (the angle of the turn), one turned by
0 deg agrees with it and is no conflict.
"""

import pytest

from CadRobotWB import api
from CadRobotWB.errors import InputError, MarkerError
from helpers import polyline, simple_cell, sketch_of
from test_marker_inheritance import FIVE, Q_DOWN, Q_TILTED, placement


def first_marker_cell(doc):
    cell, path = simple_cell(doc, sketch_of(doc, polyline(FIVE)))
    first = api.make_tool_marker(doc, cell, placement((25, 0, 0), Q_DOWN), name="First")
    return cell, path, first


def markers(doc):
    return sorted(o.Label for o in doc.Objects if getattr(o, "Proxy", None).__class__.__name__ == "ToolMarker")


def test_default_refuses_naming_both_markers_and_the_fixes(doc):
    cell, path, first = first_marker_cell(doc)
    with pytest.raises(MarkerError) as caught:
        api.make_tool_marker(doc, cell, placement((40, 0, 0), Q_TILTED), name="Second")
    text = str(caught.value)
    for words in ("'Second'", "segment 1 of path 'Path'", "'First'", "30.00°",
                  'on_conflict="replace" deletes \'First\'', 'on_conflict="next" links it to segment 2',
                  "Nothing was added"):
        assert words in text
    assert markers(doc) == ["First"]
    api.generate(cell)          # the document is as before: it still generates


def test_agreeing_marker_is_no_conflict(doc):
    cell, path, first = first_marker_cell(doc)
    assert api.tool_marker_conflict(cell, placement=placement((40, 0, 0), Q_DOWN)) is None
    api.make_tool_marker(doc, cell, placement((40, 0, 0), Q_DOWN), name="Same")
    assert markers(doc) == ["First", "Same"]


def test_replace_deletes_the_other_marker(doc):
    cell, path, first = first_marker_cell(doc)
    second = api.make_tool_marker(doc, cell, placement((40, 0, 0), Q_TILTED), name="Second",
                                  on_conflict="replace")
    assert markers(doc) == ["Second"]
    assert second.Governs == "segments 1-5 of Path"
    api.generate(cell)


def test_next_starts_a_new_stretch_at_the_following_segment(doc):
    cell, path, first = first_marker_cell(doc)
    second = api.make_tool_marker(doc, cell, placement((40, 0, 0), Q_TILTED), name="Second",
                                  on_conflict="next")
    assert (second.Path, second.Segment) == (path, 2)
    doc.recompute()
    assert first.Governs == "segment 1 of Path"
    assert second.Governs == "segments 2-5 of Path"
    assert api.marker_segment(cell, second) == (path, 2)
    api.generate(cell)


def test_next_is_refused_on_the_last_segment_and_when_the_next_is_taken(doc):
    cell, path, first = first_marker_cell(doc)
    api.make_tool_marker(doc, cell, placement((125, 0, 0), Q_DOWN), name="Last")       # segment 5
    with pytest.raises(MarkerError) as caught:
        api.make_tool_marker(doc, cell, placement((140, 0, 0), Q_TILTED), name="X", on_conflict="next")
    assert "segment 5 is the last of path 'Path'" in str(caught.value)
    api.make_tool_marker(doc, cell, placement((50, 25, 0), Q_DOWN), name="Up")          # segment 2
    with pytest.raises(MarkerError) as caught:
        api.make_tool_marker(doc, cell, placement((40, 0, 0), Q_TILTED), name="Y", on_conflict="next")
    assert "tool marker 'Up' sets segment 2" in str(caught.value)
    assert markers(doc) == ["First", "Last", "Up"]


def test_keep_adds_it_and_generating_refuses(doc):
    cell, path, first = first_marker_cell(doc)
    api.make_tool_marker(doc, cell, placement((40, 0, 0), Q_TILTED), name="Second", on_conflict="keep")
    with pytest.raises(MarkerError, match="both set segment 1"):
        api.generate(cell)


def test_bad_on_conflict_is_one_clear_error(doc):
    cell, path, first = first_marker_cell(doc)
    with pytest.raises(InputError, match='"error", "replace", "next", "keep"'):
        api.make_tool_marker(doc, cell, placement((40, 0, 0), Q_TILTED), on_conflict="merge")


def test_moved_marker_conflict_and_its_resolution(doc):
    cell, path, first = first_marker_cell(doc)
    fourth = api.make_tool_marker(doc, cell, placement((100, 25, 0), Q_TILTED), name="Fourth")
    assert api.tool_marker_conflict(cell, marker=fourth) is None
    fourth.Placement = placement((30, 0, 0), Q_TILTED)            # dragged onto segment 1
    doc.recompute()
    conflict = api.tool_marker_conflict(cell, marker=fourth)
    assert [o.Name for o in conflict.others] == ["First"]
    assert (conflict.path, conflict.segment, conflict.next_free) == (path, 1, 2)
    assert conflict.angles_deg == [pytest.approx(30.0)]
    assert api.resolve_marker_conflict(cell, fourth, "next")
    assert (fourth.Segment, fourth.Governs) == (2, "segments 2-5 of Path")
    assert api.tool_marker_conflict(cell, marker=fourth) is None
    assert not api.resolve_marker_conflict(cell, fourth, "replace")
    # Linked explicitly (Segment property) onto segment 1: replace deletes First.
    fourth.Segment = 1
    doc.recompute()
    assert api.resolve_marker_conflict(cell, fourth, "replace")
    assert markers(doc) == ["Fourth"]


def seam_with_travel_angle_0(seam_cell):
    """The seam example, Torch3 deleted; its torches push 10 deg, the automatic markers at
    travel angle 0 do not: they differ by 10 deg on segments 1, 2 and 4 (Torch2 sets 2-3)."""
    doc = seam_cell.Document
    doc.removeObject("Torch3")
    doc.recompute()
    seam_cell.WorkAngle, seam_cell.TravelAngle = 90.0, 0.0
    return doc, next(o for o in seam_cell.Group if o.Label == "Seam")


def test_auto_markers_refuse_existing_markers_by_default(seam_cell):
    doc, path = seam_with_travel_angle_0(seam_cell)
    before = markers(doc)
    conflicts = api.auto_marker_conflicts(seam_cell, path)
    assert sorted(conflicts) == [1, 2, 4]
    assert [o.Name for o in conflicts[4].others] == ["Torch4"]
    assert conflicts[4].angles_deg == [pytest.approx(10.0)]
    with pytest.raises(MarkerError) as caught:
        api.make_tool_markers_auto(doc, seam_cell, path)
    for words in ("3 of its segments", "segment 1: 'Torch1' (10.0°)", "segment 4: 'Torch4'",
                  "Nothing was added", 'on_conflict="replace"', 'on_conflict="skip"'):
        assert words in str(caught.value)
    assert markers(doc) == before


def test_auto_markers_skip_keeps_the_existing_ones(seam_cell):
    doc, path = seam_with_travel_angle_0(seam_cell)
    added = api.make_tool_markers_auto(doc, seam_cell, path, on_conflict="skip")
    assert [m.Label for m in added] == ["Seam_Tool3"]
    assert sorted(markers(doc)) == ["Seam_Tool3", "Torch1", "Torch2", "Torch4"]
    assert added[0].Governs == "segment 3 of Seam"


def test_auto_markers_replace_deletes_the_existing_ones(seam_cell):
    doc, path = seam_with_travel_angle_0(seam_cell)
    added = api.make_tool_markers_auto(doc, seam_cell, path, on_conflict="replace")
    assert markers(doc) == ["Seam_Tool%d" % k for k in range(1, 5)]
    assert [m.Segment for m in added] == [1, 2, 3, 4]


def test_a_kept_conflict_shows_in_governs_and_warns(doc, monkeypatch):
    import FreeCAD
    warnings = []
    monkeypatch.setattr(FreeCAD.Console, "PrintWarning", lambda text: warnings.append(text))
    cell, path, first = first_marker_cell(doc)
    second = api.make_tool_marker(doc, cell, placement((40, 0, 0), Q_TILTED), name="Second",
                                  on_conflict="keep")
    doc.recompute()
    assert second.Governs.startswith("segments 1-5 of Path; CONFLICT: 'First' also sets segment 1 "
                                     "with another orientation (30.00°)")
    assert first.Governs.startswith("segments 1-5 of Path; CONFLICT: 'Second' also sets segment 1")
    assert sum("CONFLICT" in w for w in warnings) == 2        # once per marker, not per recompute
    doc.recompute()
    assert sum("CONFLICT" in w for w in warnings) == 2
    # A script moves Second onto segment 2: the conflict is gone from both.
    second.Placement = placement((50, 25, 0), Q_TILTED)
    doc.recompute()
    assert (first.Governs, second.Governs) == ("segment 1 of Path", "segments 2-5 of Path")
