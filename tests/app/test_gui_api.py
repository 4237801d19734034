"""The App-level API the GUI commands call (issue 3), on real documents in FreeCADCmd.

Expected frames, normals and taught poses are derived by hand in the comments;
the seam example's hand-placed torches are the reference for automatic markers.
"""

import contextlib
import math
import os
import re

import FreeCAD
import numpy as np
import pytest

from CadRobotWB import api, preferences
from CadRobotWB.errors import FrameError, InputError
from helpers import polyline, sketch_of

V = FreeCAD.Vector
S = 1.0 / math.sqrt(2.0)
EPOCH = "946684800"
GOLDEN = os.path.join(os.path.dirname(__file__), "golden", "posts")


def rotation_matrix(placement):
    return np.array(placement.toMatrix().A).reshape(4, 4)[:3, :3]


def assert_placement(placement, base, R, atol=1e-9):
    assert np.allclose(tuple(placement.Base), base, atol=atol), placement
    assert np.allclose(rotation_matrix(placement), R, atol=atol), placement


def same_placement(a, b, tol=1e-9):
    A, B = (np.array(p.toMatrix().A).reshape(4, 4) for p in (a, b))
    return np.allclose(A, B, atol=tol)


def sub_at(obj, kind, point, tol=1e-6):
    """Name of `obj`'s vertex / edge / face whose (global) centre is `point`."""
    shape = obj.Shape.copy()
    shape.Placement = obj.getGlobalPlacement()
    items = {"Vertex": shape.Vertexes, "Edge": shape.Edges, "Face": shape.Faces}[kind]
    for i, item in enumerate(items, start=1):
        centre = item.Point if kind == "Vertex" else item.CenterOfMass
        if (centre - V(*point)).Length < tol:
            return "%s%d" % (kind, i)
    raise AssertionError("no %s at %s" % (kind, point))


def seam_path(cell):
    return next(o for o in cell.Group if o.Label == "Seam")


# --- cells --------------------------------------------------------------------------------

def test_make_cell_places_the_robot_base(doc):
    pl = FreeCAD.Placement(V(-900, 10, -600), FreeCAD.Rotation(V(0, 0, 1), 30))
    cell = api.make_cell(doc, placement=pl)
    assert same_placement(cell.Placement, pl, 1e-12)
    T = np.eye(4)
    T[:3, 3] = [1, 2, 3]
    assert tuple(api.make_cell(doc, name="Other", placement=T).Placement.Base) == (1, 2, 3)
    count = len(doc.Objects)
    with pytest.raises(InputError, match="robot base placement"):
        api.make_cell(doc, placement="here")
    assert len(doc.Objects) == count
    # GMAW practice (robots/catalog/tools.py): square to the fillet's bisector, 10 deg push.
    assert float(cell.WorkAngle) == 90.0 and float(cell.TravelAngle) == 10.0


# --- calibration frames from selections ----------------------------------------------------

@pytest.fixture
def turned_box(doc):
    """Box 10 x 20 x 30 turned 90 deg about Z and moved to (100, 50, 0): a local point
    (x, y, z) is at (100 - y, 50 + x, z) in {U}."""
    box = doc.addObject("Part::Box", "Box")
    box.Length, box.Width, box.Height = 10, 20, 30
    box.Placement = FreeCAD.Placement(V(100, 50, 0), FreeCAD.Rotation(V(0, 0, 1), 90))
    doc.recompute()
    return box


def test_frame_from_three_vertices_of_a_box(turned_box):
    # Local (0,0,0), (10,0,0), (0,20,0) -> (100,50,0), (100,60,0), (80,50,0):
    # X = +Y_u, the XY point lies towards -X_u, so Z = +Z_u and Y = -X_u: Rz(90).
    points = [(100, 50, 0), (100, 60, 0), (80, 50, 0)]
    items = [(turned_box, sub_at(turned_box, "Vertex", p)) for p in points]
    expected_R = [[0, -1, 0], [1, 0, 0], [0, 0, 1]]
    assert_placement(api.frame_placement_from_selection(items), (100, 50, 0), expected_R)
    assert_placement(api.frame_placement_from_points(*[V(*p) for p in points]), (100, 50, 0), expected_R)
    assert_placement(api.frame_placement_from_points(*points), (100, 50, 0), expected_R)


def test_frame_from_top_face_and_edge(turned_box):
    # Top face: normal +Z. Edge local (0,0,30)-(10,0,30) = (100,50,30)-(100,60,30);
    # picked near (100,61,30) -> origin (100,60,30), X towards (100,50,30) = -Y_u,
    # Y = Z x X = (0,0,1) x (0,-1,0) = (1,0,0).
    face = sub_at(turned_box, "Face", (90, 55, 30))
    edge = sub_at(turned_box, "Edge", (100, 55, 30))
    pl = api.frame_placement_from_selection([(turned_box, edge), (turned_box, face)], near=V(100, 61, 30))
    assert_placement(pl, (100, 60, 30), [[0, 1, 0], [-1, 0, 0], [0, 0, 1]])


def test_frame_from_bottom_face_points_out_of_the_box(turned_box):
    # Bottom face: outward normal -Z. Edge (100,50,0)-(100,60,0), picked near (100,49,0):
    # origin (100,50,0), X = +Y_u, Y = (0,0,-1) x (0,1,0) = (1,0,0).
    face = sub_at(turned_box, "Face", (90, 55, 0))
    edge = sub_at(turned_box, "Edge", (100, 55, 0))
    pl = api.frame_placement_from_selection([(turned_box, face), (turned_box, edge)], near=(100, 49, 0))
    assert_placement(pl, (100, 50, 0), [[0, 1, 0], [1, 0, 0], [0, 0, -1]])


@pytest.mark.parametrize("case, error, message", [
    ("two faces", InputError, "Select three vertices"),
    ("repeated vertex", FrameError, "X-axis point"),
    ("edge off the face", FrameError, "off the plane"),
    ("curved face", FrameError, "not planar"),
    ("four vertices", InputError, "Select three vertices"),
])
def test_degenerate_selections_say_what_to_select(doc, turned_box, case, error, message):
    cylinder = doc.addObject("Part::Cylinder", "Cylinder")
    doc.recompute()
    top = sub_at(turned_box, "Face", (90, 55, 30))
    vertical = sub_at(turned_box, "Edge", (100, 50, 15))
    v = [sub_at(turned_box, "Vertex", p) for p in [(100, 50, 0), (100, 60, 0), (80, 50, 0), (80, 60, 0)]]
    items = {
        "two faces": [(turned_box, top), (turned_box, sub_at(turned_box, "Face", (90, 55, 0)))],
        "repeated vertex": [(turned_box, v[0]), (turned_box, v[0]), (turned_box, v[2])],
        "edge off the face": [(turned_box, top), (turned_box, vertical)],
        "curved face": [(cylinder, "Face1"), (turned_box, vertical)],
        "four vertices": [(turned_box, name) for name in v],
    }[case]
    count = len(doc.Objects)
    with pytest.raises(error, match=message):
        api.frame_placement_from_selection(items)
    assert len(doc.Objects) == count


# --- tool markers from edges ----------------------------------------------------------------

def test_edge_tool_placement_on_a_box_edge_bisects_its_faces(doc):
    # Box 10 x 20 x 30 at the origin; edge (0,0,30)-(10,0,30) between the -Y and +Z faces:
    # bisector (0,-1,1)/sqrt(2), tool +Z = -bisector at work angle 90; mid-length (5,0,30).
    box = doc.addObject("Part::Box", "Box")
    box.Length, box.Width, box.Height = 10, 20, 30
    doc.recompute()
    edge = sub_at(box, "Edge", (5, 0, 30))
    pl = api.edge_tool_placement(box, edge)
    R = rotation_matrix(pl)
    assert np.allclose(tuple(pl.Base), (5, 0, 30))
    assert np.allclose(R[:, 2], [0, S, -S], atol=1e-12)
    assert np.allclose(abs(R[0, 0]), 1.0, atol=1e-12)          # X along the edge
    # At the point nearest (2, 0, 31), and square to a chosen face (top: tool +Z = -Z).
    top = (box, sub_at(box, "Face", (5, 10, 30)))
    pl = api.edge_tool_placement(box, edge, point=V(2, 0, 31), face=top)
    assert np.allclose(tuple(pl.Base), (2, 0, 30))
    assert np.allclose(rotation_matrix(pl)[:, 2], [0, 0, -1], atol=1e-12)


def test_edge_tool_placement_at_a_t_joint_uses_the_free_faces(doc):
    # Vertical plate (y 45..55, z 10..60) standing on a horizontal plate (z 0..10). Its
    # bottom edge at y = 45 meets its -Y face and the base plate's top; its own bottom
    # face lies on the base plate and does not count: bisector (0,-1,1)/sqrt(2).
    base = doc.addObject("Part::Box", "Base")
    base.Length, base.Width, base.Height = 200, 100, 10
    web = doc.addObject("Part::Box", "Web")
    web.Length, web.Width, web.Height = 200, 10, 50
    web.Placement.Base = V(0, 45, 10)
    doc.recompute()
    pl = api.edge_tool_placement(web, sub_at(web, "Edge", (100, 45, 10)))
    assert np.allclose(rotation_matrix(pl)[:, 2], [0, S, -S], atol=1e-9)


@pytest.fixture
def tilted_plate(doc):
    """A plate 200 x 100 x 8 and a sketch line on its top, (20,50)-(180,50), both in an
    App::Part turned 30 deg about X: the top normal is (0, -sin 30, cos 30)."""
    part = doc.addObject("App::Part", "Fixture")
    part.Placement = FreeCAD.Placement(V(0, 0, 100), FreeCAD.Rotation(V(1, 0, 0), 30))
    plate = doc.addObject("Part::Box", "Plate")
    plate.Length, plate.Width, plate.Height = 200, 100, 8
    part.addObject(plate)
    sketch = sketch_of(doc, polyline([(20, 50), (180, 50)]), FreeCAD.Placement(V(0, 0, 8), FreeCAD.Rotation()),
                       container=part)
    doc.recompute()
    return sketch


def test_edge_tool_placement_on_a_sketch_line_lying_on_a_plate(doc, tilted_plate):
    up = np.array([0, -0.5, math.sqrt(3) / 2])
    pl = api.edge_tool_placement(tilted_plate, "Edge1")
    R = rotation_matrix(pl)
    # Mid-length (100, 50, 8) in the part: (100, 50 c - 8 s, 100 + 50 s + 8 c), c = cos 30, s = sin 30.
    c, s = math.sqrt(3) / 2, 0.5
    assert np.allclose(tuple(pl.Base), (100, 50 * c - 8 * s, 100 + 50 * s + 8 * c), atol=1e-9)
    assert np.allclose(R[:, 2], -up, atol=1e-9)
    assert np.allclose(R[:, 0], [1, 0, 0], atol=1e-9)


def test_edge_tool_placement_follows_a_reversed_path(doc, tilted_plate):
    cell = api.make_cell(doc)
    path = api.make_path(doc, cell, tilted_plate, Reversed=True)
    R = rotation_matrix(api.edge_tool_placement(tilted_plate, "Edge1", path=path))
    assert np.allclose(R[:, 0], [-1, 0, 0], atol=1e-9)
    assert np.allclose(R[:, 2], [0, 0.5, -math.sqrt(3) / 2], atol=1e-9)


def test_auto_markers_on_the_seam_match_the_hand_placed_torches(doc, seam_cell):
    # The example places each torch at its segment's middle, square to the plates
    # (work angle 90) pushing 10 deg; the plates' top faces either side of the root gap
    # give the same normal.
    seam_cell.WorkAngle, seam_cell.TravelAngle = 90.0, 10.0
    path = seam_path(seam_cell)
    markers = api.make_tool_markers_auto(doc, seam_cell, path)
    assert [m.Label for m in markers] == ["Seam_Tool%d" % k for k in range(1, 5)]
    for k, marker in enumerate(markers, start=1):
        torch = doc.getObject("Torch%d" % k)
        assert marker.Path == path and marker.Segment == k
        assert np.allclose(rotation_matrix(marker.Placement), rotation_matrix(torch.Placement), atol=1e-9)
        assert (marker.Placement.Base - torch.Placement.Base).Length < 1e-9
        assert api.marker_segment(seam_cell, marker) == (path, k)
    api.generate(seam_cell)                 # the auto markers agree with the torches


def test_auto_markers_take_explicit_angles(doc, seam_cell):
    path = seam_path(seam_cell)
    # The example's torches push 10 deg: these differ from them, so they replace them.
    marker = api.make_tool_markers_auto(doc, seam_cell, path, work_angle_deg=90.0, travel_angle_deg=0.0,
                                        on_conflict="replace")[0]
    # Travel angle 0: tool +Z straight down the fixture's up axis.
    up = seam_cell.Document.getObject("Fixture").Placement.Rotation.multVec(V(0, 0, 1))
    assert np.allclose(rotation_matrix(marker.Placement)[:, 2], -np.array(tuple(up)), atol=1e-9)


def test_path_without_faces_adds_no_markers(doc):
    sketch = sketch_of(doc, polyline([(0, 0), (100, 0), (100, 50)]),
                       FreeCAD.Placement(V(0, 0, 500), FreeCAD.Rotation()))
    cell = api.make_cell(doc)
    path = api.make_path(doc, cell, sketch)
    count = len(doc.Objects)
    with pytest.raises(InputError, match="segment 1 .*select a face too") as info:
        api.make_tool_markers_auto(doc, cell, path)
    assert info.value.obj_name == path.Name
    assert len(doc.Objects) == count
    with pytest.raises(InputError, match="select a face too"):
        api.edge_tool_placement(sketch, "Edge2")


def test_marker_segment_of_the_hand_placed_torches(seam_cell):
    path = seam_path(seam_cell)
    for k in range(1, 5):
        assert api.marker_segment(seam_cell, seam_cell.Document.getObject("Torch%d" % k)) == (path, k)


# --- risk-area suggestions ---------------------------------------------------------------------

def test_suggest_risk_areas_finds_the_seam_corner(doc, seam_cell):
    path = seam_path(seam_cell)
    assert api.suggest_risk_areas(seam_cell, 30.0) == []        # the example's Corner covers it
    doc.removeObject("Corner")
    doc.recompute()
    # Torches 2 and 3 differ by the 90 deg turn of the seam about the plates' normal.
    (found,) = api.suggest_risk_areas(seam_cell, 30.0)
    assert (found.path, found.first_segment, found.last_segment) == (path, 2, 3)
    assert found.jump_deg == pytest.approx(90.0, abs=1e-6)
    assert api.suggest_risk_areas(seam_cell, 90.5) == []
    with stored_preference("Float", "RiskThreshold", 89.5):       # the default threshold
        assert len(api.suggest_risk_areas(seam_cell)) == 1
    with stored_preference("Float", "RiskThreshold", 90.5):
        assert api.suggest_risk_areas(seam_cell) == []


# --- teaching ----------------------------------------------------------------------------------

# The real part is the drawing turned 90 deg about Z of {U} and moved by T: p_r = Rz90 p_u + T
# (the cell's robot base is {U}). The example's {B} is at (700,-250,600) turned 10 deg about Z,
# so the taught T_r_b = Rz90 T_u_b: rotation Rz(100), position Rz90 (700,-250,600) + T =
# (250, 700, 600) + (5, -3, 2) = (255, 697, 602); quaternion (cos 50, 0, 0, sin 50).
T_REAL = np.array([5.0, -3.0, 2.0])
RZ90 = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1.0]])
CENTRE = np.array([800.0, -150.0, 620.0])
OFFSETS = np.array([[100, 0, 0], [-100, 0, 0], [0, 60, 0], [0, -60, 0], [0, 0, 40], [0, 0, -40.0]])
# Noise: the measured points spread by 1e-4 about their centre. A scaling about the centroid
# does not change the least-squares rotation or translation (the cross-covariance only grows
# by 1 + eps), so the fit stays exact and each residual is eps * |p - centre|.
EPS = 1e-4


def measured_points():
    cad = CENTRE + OFFSETS
    measured = (CENTRE + (1 + EPS) * OFFSETS) @ RZ90.T + T_REAL
    return cad, measured


def rapid_of(cell):
    (name, text), = api.program_files(cell, "abb_rapid", options={"date": "2000-01-01"}, check_first=False)
    return text


def test_teaching_a_frame_moves_the_work_object_only(doc, seam_cell):
    frame = doc.getObject("TableFrame")
    before = rapid_of(seam_cell)
    drawn = FreeCAD.Placement(frame.Placement)
    cad, measured = measured_points()
    residuals = api.teach_calibration_frame(frame, [V(*p) for p in cad], measured.tolist())
    assert np.allclose(residuals, EPS * np.array([100, 100, 60, 60, 40, 40]), atol=1e-9)
    pl, again = api.taught_frame(frame)
    rz100 = rotation_matrix(FreeCAD.Placement(V(), FreeCAD.Rotation(V(0, 0, 1), 100)))
    assert_placement(pl, (255, 697, 602), rz100, atol=1e-7)
    assert again == pytest.approx(residuals)
    assert frame.UseTaught and same_placement(frame.Placement, drawn, 1e-12)
    assert same_placement(frame.TaughtPlacement, pl) and list(frame.Residuals) == pytest.approx(residuals)

    after = rapid_of(seam_cell)
    assert ('PERS wobjdata TableFrame := [FALSE,TRUE,"",[[255.000,697.000,602.000],'
            '[0.642788,0.000000,0.000000,0.766044]]' in after)
    pose = re.compile(r"CONST robtarget (\w+) := (\[\[[^]]*\],\[[^]]*\])")
    assert pose.findall(after) == pose.findall(before) and len(pose.findall(after)) > 5
    assert api.generate(seam_cell).frames["TableFrame"].T_r_b[:3, 3] == pytest.approx([255, 697, 602])


def test_check_meets_the_part_where_the_teaching_puts_it(doc, seam_cell):
    # The real table is 30 mm lower than drawn: the torch goes 30 mm below the drawn
    # plates (deeper than the tool solid's 15 mm clearance), but not into the real ones.
    frame = doc.getObject("TableFrame")
    cad, _measured = measured_points()
    lower = [(x, y, z - 30.0) for x, y, z in cad]
    api.teach_calibration_frame(frame, cad, lower)
    result = api.check(seam_cell)
    assert [f.message for f in result.report.findings if f.kind == "collision"] == []
    T_u_r = api.matrix_from_placement(seam_cell.Placement)
    T_u_b = api.matrix_from_placement(frame.Placement)
    T_r_b = api.generate(seam_cell).frames["TableFrame"].T_r_b
    assert T_r_b[:3, 3] == pytest.approx((np.linalg.inv(T_u_r) @ T_u_b)[:3, 3] - (0, 0, 30), abs=1e-9)


def test_teaching_survives_save_and_reopen(doc, seam_cell, tmp_path):
    cad, measured = measured_points()
    api.teach_calibration_frame(doc.getObject("TableFrame"), cad, measured)
    file_name = str(tmp_path / "taught.FCStd")
    doc.saveAs(file_name)
    FreeCAD.closeDocument(doc.Name)
    reopened = FreeCAD.openDocument(file_name)
    try:
        frame = reopened.getObject("TableFrame")
        assert frame.UseTaught and len(frame.CadPoints) == 6
        assert np.allclose([tuple(v) for v in frame.MeasuredPoints], measured, atol=1e-9)
        pl, residuals = api.taught_frame(frame)
        assert tuple(pl.Base) == pytest.approx((255, 697, 602), abs=1e-7)
        assert same_placement(frame.TaughtPlacement, pl)
    finally:
        FreeCAD.closeDocument(reopened.Name)


def test_bad_teaching_points_leave_the_frame_unchanged(doc, seam_cell):
    frame = doc.getObject("TableFrame")
    cad, measured = measured_points()
    collinear = [(0, 0, 0), (10, 0, 0), (20, 0, 0)]
    with pytest.raises(FrameError, match="collinear") as info:
        api.teach_calibration_frame(frame, collinear, collinear)
    assert info.value.obj_name == frame.Name and "TableFrame" in str(info.value)
    with pytest.raises(FrameError, match="6 CAD points but 5 measured"):
        api.teach_calibration_frame(frame, cad, measured[:5])
    assert not frame.UseTaught and len(frame.CadPoints) == 0
    assert api.taught_frame(frame) is None
    # Points made bad by hand: generating names the frame.
    frame.CadPoints, frame.MeasuredPoints, frame.UseTaught = collinear, collinear, True
    doc.recompute()
    with pytest.raises(FrameError, match="TableFrame") as info:
        api.generate(seam_cell)
    assert info.value.obj_name == frame.Name


def test_teaching_with_a_nan_point_is_a_frame_error_and_changes_nothing(doc):
    # "nan" is a float to Python, typed in the teaching panel or passed by a macro.
    cell = api.make_cell(doc)
    frame = api.make_calibration_frame(doc, cell, FreeCAD.Placement())
    cad = [V(0, 0, 0), V(100, 0, 0), V(0, 100, 0)]
    measured = [(0, 0, 0), (math.nan, 0, 0), (0, 100, 0)]
    with pytest.raises(FrameError):
        api.teach_calibration_frame(frame, cad, measured)
    assert not frame.UseTaught and len(frame.CadPoints) == 0
    with pytest.raises(FrameError):
        api.teach_calibration_frame(frame, cad, [(0, 0, 0), (math.inf, 0, 0), (0, 100, 0)])


# --- program files and preferences ---------------------------------------------------------------

def test_program_files_are_what_export_writes(seam_cell, tmp_path, monkeypatch):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", EPOCH)
    files = api.program_files(seam_cell, "abb_rapid")
    written = api.export(seam_cell, post="abb_rapid", output_dir=str(tmp_path))
    assert [name for name, _ in files] == [os.path.basename(p) for p in written]
    for (name, text), path in zip(files, written):
        with open(path, newline="") as handle:
            assert handle.read() == text
        with open(os.path.join(GOLDEN, "seam_abb_rapid_" + name), newline="") as handle:
            assert handle.read() == text
    assert os.listdir(str(tmp_path)) == ["SeamWeld.mod"]


@contextlib.contextmanager
def stored_preference(kind, name, value):
    """Preference `name` set to `value` in FreeCAD's parameters, restored afterwards."""
    group = FreeCAD.ParamGet(preferences.PATH)
    had, old = name in getattr(group, "Get%ss" % kind)(), getattr(group, "Get" + kind)(name)
    getattr(group, "Set" + kind)(name, value)
    try:
        yield
    finally:
        _restore(group, kind, name, had, old)


def _restore(group, kind, name, had, old):
    if had:
        getattr(group, "Set" + kind)(name, old)
    else:
        getattr(group, "Rem" + kind)(name)


def test_preferences_round_trip(tmp_path):
    group = FreeCAD.ParamGet(preferences.PATH)
    saved = [(kind, name, name in getattr(group, "Get%ss" % kind)(), getattr(group, "Get" + kind)(name))
             for kind, name in (("Float", "RiskThreshold"), ("String", "DefaultPost"), ("String", "PostFolder"))]
    try:
        for kind, name, _, _ in saved:
            getattr(group, "Rem" + kind)(name)
        assert preferences.get("RiskThreshold") == 30.0 and preferences.get("DefaultPost") == ""
        preferences.set("RiskThreshold", "12.5")
        preferences.set("DefaultPost", "kuka_krl")
        preferences.set("PostFolder", str(tmp_path))
        assert preferences.get("RiskThreshold") == 12.5 and preferences.get("DefaultPost") == "kuka_krl"
        assert group.GetFloat("RiskThreshold") == 12.5
        assert str(tmp_path) in api.user_post_dirs()
        assert api.PREFERENCES == preferences.PATH
        with pytest.raises(KeyError, match="RiskThreshhold"):
            preferences.get("RiskThreshhold")
    finally:
        for kind, name, had, old in saved:
            _restore(group, kind, name, had, old)
