"""Which segments a tool marker governs, as the user sees it (issue 12, part 5).

A marker sets its own segment and the following ones up to the next marker.
Selecting it (in the tree or the 3D view) draws those segments of its path
thick and orange; its read-only property ``Governs`` says the same in words.
Checked in the scene graph (which segments are drawn) and in a rendered top
view (where the orange pixels are).
"""

import FreeCAD
import FreeCADGui
import numpy as np
import Part
from pivy import coin

from conftest import process_events, render
from test_view_display import rgb

from CadRobotWB import api
from CadRobotWB.gui import path_display

V = FreeCAD.Vector
# Five segments: 1 along +X, 2 up, 3 along +X, 4 down, 5 along +X.
FIVE = [(0, 0, 0), (100, 0, 0), (100, 100, 0), (200, 100, 0), (200, 0, 0), (300, 0, 0)]


def down_at(point):
    return api.tool_placement(V(*point), V(1, 0, 0), V(0, 0, 1), 90.0, 0.0)


def five_segments(doc):
    """A cell (no robot drawn) with the five-segment path and markers on segments 1 and 4."""
    cell = api.make_cell(doc)
    cell.ViewObject.ShowRobot = False
    api.make_calibration_frame(doc, cell, FreeCAD.Placement())
    feature = doc.addObject("Part::Feature", "Polyline")
    feature.Shape = Part.makePolygon([V(*p) for p in FIVE])
    path = api.make_path(doc, cell, feature)
    first = api.make_tool_marker(doc, cell, down_at((50, 0, 0)), name="First")
    fourth = api.make_tool_marker(doc, cell, down_at((200, 50, 0)), name="Fourth")
    for obj in doc.Objects:
        obj.ViewObject.Visibility = obj == path       # markers and frame would cover the pixels
    return cell, path, first, fourth


def drawn_chords(display):
    """(N, 2, 3) start and end of each highlighted line, mm."""
    search = coin.SoSearchAction()
    search.setType(coin.SoCoordinate3.getClassTypeId())
    search.apply(display.governed.getChild(0))
    coords = search.getPath().getTail()
    points = np.array([p.getValue() for p in coords.point.getValues()])
    return points.reshape(-1, 2, 3)


def top_view(doc, tmp_path, name):
    """Masks (H, W) of the highlight's orange and of the path's blue in a top view."""
    view = FreeCADGui.getDocument(doc.Name).activeView()
    view.viewTop()
    view.fitAll()
    pixels = rgb(render(view, tmp_path / name, 600, 300))
    r, g, b = pixels[..., 0], pixels[..., 1], pixels[..., 2]
    return {"orange": (r > 220) & (g > 110) & (g < 170) & (b < 60),
            "blue": (r < 60) & (g > 50) & (g < 120) & (b > 200)}


def x_fraction(columns, extent):
    """Image columns as fractions of the path's width (0 at x = 0 mm, 1 at x = 300 mm)."""
    x0, x1 = extent
    return (np.asarray(columns) - x0) / float(x1 - x0)


def select_only(*objects):
    FreeCADGui.Selection.clearSelection()
    for obj in objects:
        FreeCADGui.Selection.addSelection(obj.Document.Name, obj.Name)
    process_events()


def test_selecting_a_marker_shows_the_segments_it_governs(gui_doc, tmp_path):
    cell, path, first, fourth = five_segments(gui_doc)
    display = path.ViewObject.Proxy.path_display
    assert first.Governs == "segments 1-3 of Path" and fourth.Governs == "segments 4-5 of Path"
    select_only()
    nothing = top_view(gui_doc, tmp_path, "none.png")
    assert display.governed_ranges == () and not nothing["orange"].any()
    columns = np.nonzero(nothing["blue"])[1]
    extent = (columns.min(), columns.max())

    select_only(fourth)
    assert display.governed_ranges == ((4, 5),)
    np.testing.assert_allclose(drawn_chords(display), [[FIVE[3], FIVE[4]], [FIVE[4], FIVE[5]]])
    rows, columns = np.nonzero(top_view(gui_doc, tmp_path, "fourth.png")["orange"])
    # Segments 4-5 are x = 200..300 mm; segment 4 runs 100 mm along y (up the image).
    assert len(columns) > 200 and x_fraction(columns.min(), extent) > 0.6
    assert x_fraction(columns.max(), extent) > 0.95 and rows.max() - rows.min() > 0.25 * (extent[1] - extent[0])

    select_only(first)
    assert display.governed_ranges == ((1, 3),)
    columns = np.nonzero(top_view(gui_doc, tmp_path, "first.png")["orange"])[1]
    assert x_fraction(columns.min(), extent) < 0.05 and 0.6 < x_fraction(columns.max(), extent) < 0.72

    select_only(first, fourth)
    assert display.governed_ranges == ((1, 3), (4, 5))
    select_only()
    assert display.governed_ranges == () and display.governed.whichChild.getValue() == -1


def test_the_highlight_follows_a_moved_marker(gui_doc):
    cell, path, first, fourth = five_segments(gui_doc)
    display = path.ViewObject.Proxy.path_display
    select_only(first)
    assert display.governed_ranges == ((1, 3),)
    fourth.Placement = down_at((150, 100, 0))                     # onto segment 3
    gui_doc.recompute()
    process_events()
    assert fourth.Governs == "segments 3-5 of Path" and first.Governs == "segments 1-2 of Path"
    assert display.governed_ranges == ((1, 2),)
    np.testing.assert_allclose(drawn_chords(display), [[FIVE[0], FIVE[1]], [FIVE[1], FIVE[2]]])


def test_arcs_are_drawn_as_arcs():
    from CadRobotWB.core.geometry import Arc
    arc = Arc((0, 0, 0), (0, 0, 1), (10, 0, 0), np.pi / 2)
    points = path_display.segment_points(arc)
    assert len(points) == 19                                         # every 5 degrees of 90
    np.testing.assert_allclose(np.linalg.norm(points, axis=1), 10.0)
    np.testing.assert_allclose(points[[0, -1]], [[10, 0, 0], [0, 10, 0]], atol=1e-12)
