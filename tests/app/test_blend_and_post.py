"""A path's Blend (issue 20 item 4) and the post a cell's program is written with
(item 9), through the API on a small document."""

import os

import pytest

import FreeCAD
from CadRobotWB import api
from CadRobotWB.core import program as ir
from CadRobotWB.errors import InputError
from helpers import polyline, simple_cell, sketch_of

SAVED = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "saved_documents")


@pytest.fixture(scope="module")
def cell_doc():
    """An ABB cell whose path runs straight through x = 0, 10, 20, 30 mm (one marker)."""
    doc = FreeCAD.newDocument("BlendTest")
    sketch = sketch_of(doc, polyline([(0, 0), (10, 0), (20, 0), (30, 0)]))
    cell, path = simple_cell(doc, sketch, markers=[(5, 0, 0)])
    yield doc, cell, path
    FreeCAD.closeDocument(doc.Name)


def path_zones(cell):
    return [m.zone_mm for m in api.generate(cell).moves() if m.role == ir.ROLE_PATH]


def test_a_new_path_blends_its_interior_targets(cell_doc):
    doc, cell, path = cell_doc
    assert path.Blend == "Automatic"
    assert path_zones(cell) == [5.0, 5.0, 0.0]       # half the 10 mm moves; the end stops
    path.Blend = "Fine"
    assert path_zones(cell) == [0.0, 0.0, 0.0]
    assert path.getEditorMode("Zone") == ["ReadOnly"]     # used only with Blend = Zone
    path.Blend, path.Zone = "Zone", 2.0
    assert path.getEditorMode("Zone") == []
    assert path_zones(cell) == [2.0, 2.0, 0.0]
    path.Blend = "Automatic"


def test_make_path_takes_a_blend(cell_doc):
    doc, cell, path = cell_doc
    made = [api.make_path(doc, cell, path.Source, blend=blend, name="P")
            for blend in ("fine", "Automatic", 1.5, 0)]
    assert [(p.Blend, float(p.Zone)) for p in made] == [("Fine", 0.0), ("Automatic", 0.0),
                                                       ("Zone", 1.5), ("Fine", 0.0)]
    for p in made:
        doc.removeObject(p.Name)
    count = len(doc.Objects)
    with pytest.raises(InputError, match="Path 'P': blend 'smooth' is not one of 'automatic'"):
        api.make_path(doc, cell, path.Source, blend="smooth", name="P")
    assert len(doc.Objects) == count                  # nothing added


def test_a_path_saved_before_blend_existed_blends_automatically():
    doc = FreeCAD.openDocument(os.path.join(SAVED, "seam_cell.FCStd"))
    try:
        paths = [o for o in doc.Objects if "Blend" in o.PropertiesList]
        assert paths and all(p.Blend == "Automatic" and float(p.Zone) == 0.0 for p in paths)
    finally:
        FreeCAD.closeDocument(doc.Name)


def test_export_without_a_post_writes_the_robot_makers_language(cell_doc):
    doc, cell, path = cell_doc
    cell.PostProcessor = "kuka_krl"                   # left from a KUKA robot, say
    try:
        assert api.default_post_name(cell) == "abb_rapid"
        files = api.program_files(cell, check_first=False)
        assert [name for name, _ in files] == ["Cell.mod"]
        assert "Written for" not in files[0][1]
        cell.PostProcessor = "my_post"                # a user post: the user's own choice
        assert api.default_post_name(cell) == "my_post"
    finally:
        cell.PostProcessor = "abb_rapid"


def test_another_makers_post_is_written_when_asked_and_says_so(cell_doc):
    doc, cell, path = cell_doc
    src = dict(api.program_files(cell, post="kuka_krl", check_first=False))["Cell.src"]
    assert ("Written for a KUKA KR C4 controller, but the cell's robot is an ABB IRB 2400/10 "
            "(ABB_IRB2400).") in " ".join(line.lstrip("; ") for line in src.splitlines())
    assert api.other_maker_note(cell, "abb_rapid") == ""


def test_a_path_saved_before_blend_with_a_zone_keeps_its_zone(tmp_path):
    doc = FreeCAD.newDocument("OldZones")
    sketch = sketch_of(doc, polyline([(0, 0), (10, 0)]))
    cell, zoned = simple_cell(doc, sketch)
    plain = api.make_path(doc, cell, sketch, name="Plain")
    zoned.Zone = 3.0
    zoned_name = zoned.Name
    for path in (zoned, plain):                       # as files saved before Blend existed
        path.removeProperty("Blend")
    file_name = str(tmp_path / "old.FCStd")
    doc.saveAs(file_name)
    FreeCAD.closeDocument(doc.Name)
    doc = FreeCAD.openDocument(file_name)
    try:
        blends = {o.Name: (o.Blend, float(o.Zone)) for o in doc.Objects
                  if "Blend" in o.PropertiesList}
        assert blends == {zoned_name: ("Zone", 3.0), "Plain": ("Automatic", 0.0)}
    finally:
        FreeCAD.closeDocument(doc.Name)
