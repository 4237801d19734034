"""What the 3D view and the tree show: frame triads, path arrows and numbers,
target triads, semi-transparent markers, tree icons and edit modes.

Scenes are built by script, rendered with ``saveImage`` on white and judged
by the pixels of each colour: where they are, and that they go away when the
thing drawing them is switched off.
"""

import os
import sys
import types

import FreeCAD
import FreeCADGui
import numpy as np
import Part
import pytest
from pivy import coin
from PySide import QtGui

from conftest import process_events, render

from CadRobotWB import api, compat
from CadRobotWB.gui import path_display, target_display, triad_display

V = FreeCAD.Vector


# --- pixels --------------------------------------------------------------------------------

def rgb(image):
    """ndarray (H, W, 3) uint8 of a QImage."""
    image = image.convertToFormat(QtGui.QImage.Format_RGB32)
    raw = np.frombuffer(image.constBits(), np.uint8, count=compat.qimage_size_in_bytes(image))
    bgra = raw.reshape(image.height(), image.bytesPerLine() // 4, 4)[:, :image.width()]
    return bgra[:, :, 2::-1].astype(int)


def masks(pixels):
    """Boolean masks (H, W) of the colours we draw with."""
    r, g, b = pixels[..., 0], pixels[..., 1], pixels[..., 2]
    return {
        "red": (r > 200) & (g < 70) & (b < 70),
        "green": (g > 130) & (r < 70) & (b < 70),
        "blue": (b > 200) & (r < 70) & (g < 70),
        "pale_red": (r > 225) & (g > 110) & (g < 185) & (b > 110) & (b < 185),
        "arrow": (abs(r - 0) < 20) & (abs(g - 51) < 20) & (abs(b - 191) < 20),
        "dark": pixels.max(axis=-1) < 90,
        "white": pixels.min(axis=-1) > 245,
    }


def top_render(doc, tmp_path, name, fit=True):
    view = FreeCADGui.getDocument(doc.Name).activeView()
    view.viewTop()
    if fit:
        view.fitAll()
    return masks(rgb(render(view, tmp_path / ("%s.png" % name), 480, 360)))


def extent(mask):
    """(x_min, x_max, y_min, y_max) of the True pixels (image y grows downwards)."""
    ys, xs = np.nonzero(mask)
    assert len(xs), "no pixels of this colour"
    return xs.min(), xs.max(), ys.min(), ys.max()


# --- scenes --------------------------------------------------------------------------------

def polyline(doc, points, name="Polyline"):
    """A Part::Feature of straight edges through `points` (mm, in {U})."""
    feature = doc.addObject("Part::Feature", name)
    feature.Shape = Part.makePolygon([V(*p) for p in points])
    doc.recompute()
    return feature


def cell_without_robot(doc):
    """A cell whose robot is not drawn: it would cover the frames and markers at its base."""
    cell = api.make_cell(doc)
    cell.ViewObject.ShowRobot = False
    return cell


def only_visible(doc, *objects):
    for obj in doc.Objects:
        if getattr(obj, "ViewObject", None) is not None:
            obj.ViewObject.Visibility = obj in objects


def arrow_directions(display):
    """Unit direction of each arrow cone (its +Y), in drawing order."""
    group = display.arrows.getChild(0)
    out = []
    for i in range(group.getNumChildren()):
        child = group.getChild(i)
        if child.isOfType(coin.SoSeparator.getClassTypeId()):
            rotation = child.getChild(0).rotation.getValue()
            out.append(np.array(rotation.multVec(coin.SbVec3f(0, 1, 0)).getValue()))
    return out


# --- calibration frames --------------------------------------------------------------------

def test_frame_is_an_rgb_triad_with_x_right_and_y_up_from_the_top(gui_doc, tmp_path):
    cell = cell_without_robot(gui_doc)
    frame = api.make_calibration_frame(gui_doc, cell, FreeCAD.Placement(), name="TableFrame")
    frame.AxisLength = 100.0
    gui_doc.recompute()
    pixels = top_render(gui_doc, tmp_path, "frame_top")
    red, green = pixels["red"], pixels["green"]
    assert red.sum() > 150 and green.sum() > 150
    rx0, rx1, ry0, ry1 = extent(red)
    gx0, gx1, gy0, gy1 = extent(green)
    assert rx1 - rx0 > 100 and ry1 - ry0 < 20, "X is not drawn along the image's x axis"
    assert gy1 - gy0 > 100 and gx1 - gx0 < 20, "Y is not drawn along the image's y axis"
    assert abs(rx0 - (gx0 + gx1) / 2) < 10, "X does not start at the origin"
    assert abs(gy1 - (ry0 + ry1) / 2) < 10, "Y does not start at the origin"

    view = FreeCADGui.getDocument(gui_doc.Name).activeView()
    view.viewFront()           # X to the right, Z up
    view.fitAll()
    front = masks(rgb(render(view, tmp_path / "frame_front.png", 480, 360)))
    bx0, bx1, by0, by1 = extent(front["blue"])
    fx0, fx1, fy0, fy1 = extent(front["red"])
    assert by1 - by0 > 100, "Z is not drawn upwards in the front view"
    assert by0 < fy0 and abs(by1 - (fy0 + fy1) / 2) < 10 and abs(fx0 - (bx0 + bx1) / 2) < 10


def test_frame_labels_are_text_at_the_tips_and_its_label(gui_doc, tmp_path):
    cell = cell_without_robot(gui_doc)
    frame = api.make_calibration_frame(gui_doc, cell, FreeCAD.Placement(), name="F")
    display = frame.ViewObject.Proxy.frame_display
    assert triad_display.texts_in(display.switch) == ["X", "Y", "Z", "F"]
    short = top_render(gui_doc, tmp_path, "label_short")["dark"].sum()
    frame.Label = "WeldingTableCorner"
    gui_doc.recompute()
    assert triad_display.texts_in(display.switch) == ["X", "Y", "Z", "WeldingTableCorner"]
    long = top_render(gui_doc, tmp_path, "label_long", fit=False)["dark"].sum()
    assert short > 30, "no text drawn"
    assert long > short + 100, "the frame's label is not written"


def test_frame_axis_length_sizes_the_triad(gui_doc, tmp_path):
    cell = cell_without_robot(gui_doc)
    api.make_calibration_frame(gui_doc, cell, FreeCAD.Placement())
    other = api.make_calibration_frame(gui_doc, cell, FreeCAD.Placement(V(300, 0, 0), FreeCAD.Rotation()),
                                       name="Other")
    other.AxisLength = 50.0
    gui_doc.recompute()
    pixels = top_render(gui_doc, tmp_path, "lengths")
    xs = np.nonzero(pixels["red"])[1]
    split = (xs.min() + xs.max()) / 2     # the two red axes, left and right
    left, right = (xs < split).sum(), (xs >= split).sum()
    assert 1.5 < left / right < 2.6, "red pixels %d vs %d: AxisLength 100 vs 50" % (left, right)


def test_taught_frame_is_drawn_dashed_where_the_robot_uses_it(gui_doc, tmp_path):
    cell = cell_without_robot(gui_doc)
    frame = api.make_calibration_frame(gui_doc, cell, FreeCAD.Placement(), name="Corner")
    cad = [(0, 0, 0), (100, 0, 0), (0, 100, 0), (0, 0, 50)]
    # The real part lies 250 mm further along X; the robot base is at {U}'s origin.
    measured = [(x + 250.0, y, z) for x, y, z in cad]
    display = frame.ViewObject.Proxy.frame_display
    assert not display.taught_shown()
    untaught = top_render(gui_doc, tmp_path, "untaught")
    assert untaught["pale_red"].sum() < 5

    if hasattr(api, "teach_calibration_frame"):
        api.teach_calibration_frame(frame, [V(*p) for p in cad], [V(*p) for p in measured])
    else:
        frame.CadPoints, frame.MeasuredPoints, frame.UseTaught = \
            [V(*p) for p in cad], [V(*p) for p in measured], True
    gui_doc.recompute()
    assert display.taught_shown()
    assert "Corner (taught)" in triad_display.texts_in(display.switch)
    taught = top_render(gui_doc, tmp_path, "taught")
    pale = taught["pale_red"]
    assert pale.sum() > 30, "the taught triad is not drawn"
    assert extent(pale)[0] > extent(taught["red"])[1] - 5, "the taught X axis is not right of the CAD one"

    def taught_origin():
        return np.array(display.taught.getChild(1).translation.getValue().getValue())

    np.testing.assert_allclose(taught_origin(), [250, 0, 0], atol=1e-6)
    cell.Placement = FreeCAD.Placement(V(0, 100, 0), FreeCAD.Rotation())   # robot base T_u_r
    gui_doc.recompute()
    np.testing.assert_allclose(taught_origin(), [250, 100, 0], atol=1e-6)

    frame.UseTaught = False
    gui_doc.recompute()
    assert not display.taught_shown()


# --- paths ---------------------------------------------------------------------------------

def test_path_arrows_point_along_travel_and_switch_off(gui_doc, tmp_path):
    cell = api.make_cell(gui_doc)
    edges = polyline(gui_doc, [(0, 0, 0), (200, 0, 0), (200, 120, 0), (360, 120, 0)])
    path = api.make_path(gui_doc, cell, edges, name="Seam")
    only_visible(gui_doc, path)
    display = path.ViewObject.Proxy.path_display
    directions = arrow_directions(display)
    np.testing.assert_allclose(directions, [(1, 0, 0), (0, 1, 0), (1, 0, 0)], atol=1e-6)

    on = top_render(gui_doc, tmp_path, "arrows_on")["arrow"].sum()
    path.ViewObject.ShowArrows = False
    off = top_render(gui_doc, tmp_path, "arrows_off", fit=False)["arrow"].sum()
    assert on > 40 and off == 0, "arrow pixels: %d on, %d off" % (on, off)

    path.ViewObject.ShowArrows = True
    path.Reversed = True
    gui_doc.recompute()
    np.testing.assert_allclose(arrow_directions(display), [(-1, 0, 0), (0, -1, 0), (-1, 0, 0)], atol=1e-6)


def test_segment_numbers_follow_the_path_and_switch_off(gui_doc, tmp_path):
    cell = api.make_cell(gui_doc)
    edges = polyline(gui_doc, [(0, 0, 0), (200, 0, 0), (200, 120, 0)])
    path = api.make_path(gui_doc, cell, edges, name="Seam")
    display = path.ViewObject.Proxy.path_display
    assert path.SegmentCount == 2
    assert triad_display.texts_in(display.switch) == ["1", "2"]

    edges.Shape = Part.makePolygon([V(0, 0, 0), V(200, 0, 0), V(200, 120, 0), V(50, 120, 0)])
    gui_doc.recompute()                                    # the path recomputes: redrawn
    assert path.SegmentCount == 3
    assert triad_display.texts_in(display.switch) == ["1", "2", "3"]
    only_visible(gui_doc, path)
    path.ViewObject.ShowArrows = False
    with_numbers = top_render(gui_doc, tmp_path, "numbers_on")["dark"].sum()
    path.ViewObject.ShowSegmentNumbers = False
    assert triad_display.texts_in(display.switch) == []
    without = top_render(gui_doc, tmp_path, "numbers_off", fit=False)["dark"].sum()
    assert with_numbers > 15 and without == 0


def test_marks_sit_at_mid_length_of_arcs_too():
    from CadRobotWB.core import geometry
    arc = geometry.Arc(np.zeros(3), np.array([0.0, 0.0, 1.0]), np.array([100.0, 0.0, 0.0]), np.pi)
    line = geometry.Line(np.array([-100.0, 0.0, 0.0]), np.array([-100.0, -50.0, 0.0]))
    (mid_arc, t_arc, _), (mid_line, t_line, length) = path_display.segment_marks([arc, line])
    np.testing.assert_allclose(mid_arc, [0, 100, 0], atol=1e-9)      # half way round, counter-clockwise
    np.testing.assert_allclose(t_arc, [-1, 0, 0], atol=1e-9)
    np.testing.assert_allclose(mid_line, [-100, -25, 0], atol=1e-9)
    np.testing.assert_allclose(t_line, [0, -1, 0], atol=1e-9)
    assert length == pytest.approx(min(path_display.ARROW_FRACTION * np.hypot(200, 150), 25.0))


def test_path_overlay_hides_with_the_path(gui_doc, tmp_path):
    cell = api.make_cell(gui_doc)
    path = api.make_path(gui_doc, cell, polyline(gui_doc, [(0, 0, 0), (100, 0, 0)]))
    only_visible(gui_doc, path)
    assert top_render(gui_doc, tmp_path, "shown")["arrow"].sum() > 10
    path.ViewObject.Visibility = False
    assert top_render(gui_doc, tmp_path, "hidden", fit=False)["white"].all()


# --- generated targets ---------------------------------------------------------------------

def seam_cell(doc):
    import seam_tracking_cell
    cell = seam_tracking_cell.build(doc)
    doc.recompute()
    return cell, doc.getObjectsByLabel("Seam")[0]


def test_target_triads_appear_after_recompute_and_switch_off(gui_doc, tmp_path):
    cell, path = seam_cell(gui_doc)
    display = path.ViewObject.Proxy.path_display
    program = api.generate(cell)
    expected = [target_display.target_in_u(program, move, target)[:3, 3]
                for move in program.paths[0].moves for target in (move.via, move.target) if target]
    assert display.target_count == len(expected) > 5
    drawn = display.targets.getChild(0)
    origins = np.array([v.getValue() for v in drawn.getChild(1).getChild(2).point.getValues()])[::2]
    np.testing.assert_allclose(origins, expected, atol=1e-3)

    only_visible(gui_doc, path)
    path.ViewObject.ShowArrows = False
    shown = top_render(gui_doc, tmp_path, "targets_on")
    assert shown["red"].sum() > 20 and shown["green"].sum() > 20
    cell.ViewObject.ShowTargets = False
    assert display.target_count == 0
    hidden = top_render(gui_doc, tmp_path, "targets_off", fit=False)
    assert hidden["red"].sum() == 0 and hidden["green"].sum() == 0
    cell.ViewObject.ShowTargets = True
    assert display.target_count == len(expected)


def test_no_targets_when_the_cell_does_not_generate(gui_doc):
    cell, path = seam_cell(gui_doc)
    display = path.ViewObject.Proxy.path_display
    assert display.target_count > 0
    torch = gui_doc.getObjectsByLabel("Torch1")[0]
    gui_doc.removeObject(torch.Name)                # segment 1 loses its tool marker
    gui_doc.recompute()
    with pytest.raises(Exception):
        api.generate(cell)
    assert display.target_count == 0


def test_targets_are_not_regenerated_when_nothing_changed(gui_doc, monkeypatch):
    cell, path = seam_cell(gui_doc)
    path.Speed = 15.0
    gui_doc.recompute()                              # drawing the targets changes nothing
    assert not [o.Name for o in gui_doc.Objects if "Touched" in o.State]
    calls = []
    monkeypatch.setattr(target_display, "refresh", lambda doc: calls.append(doc.Name))
    gui_doc.recompute()
    assert calls == []
    path.Speed = 20.0
    gui_doc.recompute()
    assert calls == [gui_doc.Name]


def test_a_saved_cell_is_drawn_again_when_opened(gui_doc, tmp_path):
    cell, path = seam_cell(gui_doc)
    counts = path.ViewObject.Proxy.path_display.target_count
    name = str(tmp_path / "seam.FCStd")
    gui_doc.saveAs(name)
    FreeCAD.closeDocument(gui_doc.Name)
    doc = FreeCAD.openDocument(name)
    try:
        process_events()
        path = doc.getObjectsByLabel("Seam")[0]
        display = path.ViewObject.Proxy.path_display
        assert display.segment_count == path.SegmentCount == 4
        assert display.target_count == counts > 0
        assert triad_display.texts_in(display.switch) == ["1", "2", "3", "4"]
        frame = doc.getObjectsByLabel("TableFrame")[0]
        assert triad_display.texts_in(frame.ViewObject.RootNode) == ["X", "Y", "Z", "TableFrame"]
    finally:
        FreeCAD.closeDocument(doc.Name)


# --- tool markers and risk areas -----------------------------------------------------------

def marker_pixels(doc, tmp_path, name):
    pixels = rgb(render(FreeCADGui.getDocument(doc.Name).activeView(), tmp_path / name, 480, 360))
    r, g, b = pixels[..., 0], pixels[..., 1], pixels[..., 2]
    orange = (r > 90) & (g < 0.8 * r) & (b < 0.8 * g) & (pixels.min(axis=-1) < 245)
    return pixels[orange]


def test_tool_markers_are_semi_transparent(gui_doc, tmp_path):
    cell = cell_without_robot(gui_doc)
    marker = api.make_tool_marker(gui_doc, cell, FreeCAD.Placement())
    assert marker.ViewObject.Transparency == 40
    view = FreeCADGui.getDocument(gui_doc.Name).activeView()
    view.viewIsometric()
    view.fitAll()
    see_through = marker_pixels(gui_doc, tmp_path, "marker.png")
    marker.ViewObject.Transparency = 0
    opaque = marker_pixels(gui_doc, tmp_path, "opaque.png")
    assert len(see_through) > 1000 and len(opaque) > 1000
    # Blending adds what lies behind (the back faces, the background) to the orange.
    assert see_through[:, 2].mean() > opaque[:, 2].mean() + 15


def test_risk_area_is_drawn_in_red(gui_doc, tmp_path):
    cell = api.make_cell(gui_doc)
    path = api.make_path(gui_doc, cell, polyline(gui_doc, [(0, 0, 0), (100, 0, 0), (100, 100, 0), (0, 100, 0)]))
    risk = api.make_risk_area(gui_doc, cell, path, 2, 2)
    only_visible(gui_doc, risk)
    red = top_render(gui_doc, tmp_path, "risk")["red"]
    x0, x1, y0, y1 = extent(red)
    assert red.sum() > 100 and y1 - y0 > 5 * (x1 - x0), "segment 2 (along Y) is not drawn in red"


# --- tree icons ----------------------------------------------------------------------------

def test_tree_icons_exist_and_differ_per_type(gui_doc):
    cell = api.make_cell(gui_doc)
    frame = api.make_calibration_frame(gui_doc, cell, FreeCAD.Placement())
    path = api.make_path(gui_doc, cell, polyline(gui_doc, [(0, 0, 0), (100, 0, 0), (100, 100, 0)]))
    marker = api.make_tool_marker(gui_doc, cell, FreeCAD.Placement())
    risk = api.make_risk_area(gui_doc, cell, path, 1, 2)
    images = {}
    for obj, kind in ((cell, "Cell"), (frame, "CalibrationFrame"), (path, "RobotPath"),
                      (marker, "ToolMarker"), (risk, "RiskArea")):
        icon = obj.ViewObject.Proxy.getIcon()
        assert os.path.isfile(icon) and icon.endswith(os.path.join("tree", kind + ".svg"))
        image = QtGui.QIcon(icon).pixmap(32, 32).toImage()
        assert not image.isNull()
        images[kind] = rgb(image).tobytes()
    assert len(set(images.values())) == 5


# --- edit modes ----------------------------------------------------------------------------

def test_marker_opens_the_transform_dragger(gui_doc):
    cell = api.make_cell(gui_doc)
    marker = api.make_tool_marker(gui_doc, cell, FreeCAD.Placement())
    gui = FreeCADGui.getDocument(gui_doc.Name)
    assert gui.setEdit(marker, 1)
    process_events()
    try:
        assert FreeCADGui.Control.activeDialog()
        search = coin.SoSearchAction()
        search.setType(compat.transform_dragger_type())
        search.setInterest(coin.SoSearchAction.ALL)
        search.setSearchingAll(True)
        search.apply(gui.activeView().getSceneGraph())
        assert search.getPaths().getLength() == 1
    finally:
        gui.resetEdit()
        process_events()
    assert not FreeCADGui.Control.activeDialog()


def test_double_click_on_a_frame_opens_the_real_teaching_panel(gui_doc):
    cell = api.make_cell(gui_doc)
    frame = api.make_calibration_frame(gui_doc, cell, FreeCAD.Placement())
    from CadRobotWB.gui import calibration_panel
    gui = FreeCADGui.getDocument(gui_doc.Name)
    assert gui.setEdit(frame, 0)
    process_events()
    try:
        assert FreeCADGui.Control.activeDialog()
        assert gui.getInEdit().Object == frame
    finally:
        gui.resetEdit()
        process_events()
    assert not FreeCADGui.Control.activeDialog()
    assert getattr(calibration_panel, "active_panel", lambda: None)() is None


def test_double_click_on_a_frame_opens_the_teaching_panel(gui_doc, monkeypatch):
    cell = api.make_cell(gui_doc)
    frame = api.make_calibration_frame(gui_doc, cell, FreeCAD.Placement())
    opened = []
    fake = types.ModuleType("CadRobotWB.gui.calibration_panel")

    def edit(obj):
        opened.append(obj.Name)
        panel = _Panel()
        FreeCADGui.Control.showDialog(panel)
        return panel

    fake.edit = edit
    monkeypatch.setitem(sys.modules, "CadRobotWB.gui.calibration_panel", fake)
    import CadRobotWB.gui
    monkeypatch.setattr(CadRobotWB.gui, "calibration_panel", fake, raising=False)
    gui = FreeCADGui.getDocument(gui_doc.Name)
    assert gui.setEdit(frame, 0)
    process_events()
    assert opened == [frame.Name] and FreeCADGui.Control.activeDialog()
    gui.resetEdit()
    process_events()
    assert not FreeCADGui.Control.activeDialog()
    fake.edit = lambda obj: None                   # the panel refused (another one is open)
    assert not gui.setEdit(frame, 0)
    # Other objects keep FreeCAD's own default edit.
    assert frame.ViewObject.Proxy.setEdit(cell.ViewObject, 0) is None


class _Panel:
    def __init__(self):
        self.form = QtGui.QWidget()
