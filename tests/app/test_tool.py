"""The cell's tool: a library tool from the start, api.set_tool, old files,
the tool body in markers, in the collision check and in the programs."""

import math

import numpy as np
import pytest

import FreeCAD
from CadRobotWB import api
from CadRobotWB.errors import InputError, UnknownNameError
from CadRobotWB.objects import reader
from CadRobotWB.objects.convert import matrix_from_placement
from CadRobotWB.robots.catalog import tools
from CadRobotWB.robots.checks import collision
from helpers import polyline, simple_cell, sketch_of

V = FreeCAD.Vector

TOOL_PROPERTIES = ("ToolType", "ToolBody", "ToolTCP", "ToolMass", "ToolCenterOfGravity")


def tool_state(cell):
    """The cell's tool properties, comparable."""
    return (cell.ToolType, cell.ToolBody.Name if cell.ToolBody else None,
            tuple(np.round(matrix_from_placement(cell.ToolTCP).ravel(), 9)),
            cell.ToolMass, tuple(cell.ToolCenterOfGravity))


def test_a_new_cell_carries_the_straight_torch(doc):
    cell = api.make_cell(doc)
    torch = tools.get("Straight torch")
    assert cell.ToolType == "Straight torch" and cell.ToolBody is None
    np.testing.assert_allclose(matrix_from_placement(cell.ToolTCP), torch.T_f_t, atol=1e-9)
    assert cell.ToolTCP.Base == V(0, 0, 385)
    assert cell.ToolMass == pytest.approx(torch.mass_kg)
    assert tuple(cell.ToolCenterOfGravity) == pytest.approx(tuple(torch.cog_mm))
    assert cell.getEnumerationsOfProperty("ToolType") == tools.tool_types()
    assert api.tool_names() == tools.names()


def test_make_cell_with_another_library_tool_and_an_unknown_one(doc):
    cell = api.make_cell(doc, name="Force", tool="Ball tool")
    assert cell.ToolType == "Ball tool" and cell.ToolTCP.Base == V(0, 0, 210)
    with pytest.raises(UnknownNameError, match="Unknown tool 'Laser'"):
        api.make_cell(doc, name="Bad", tool="Laser")
    assert doc.getObject("Bad") is None


def test_set_tool_from_the_library_with_overrides(doc):
    cell = api.make_cell(doc)
    api.set_tool(cell, tool="Bent torch")
    bent = tools.get("Bent torch")
    np.testing.assert_allclose(matrix_from_placement(cell.ToolTCP), bent.T_f_t, atol=1e-9)
    assert cell.ToolMass == pytest.approx(bent.mass_kg)
    # A longer stick-out: the TCP and mass given win, the body stays the library's.
    longer = bent.T_f_t @ np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 5.0], [0, 0, 0, 1]])
    api.set_tool(cell, tool="Bent torch", tcp=longer, mass_kg=2.2)
    assert cell.ToolType == "Bent torch" and cell.ToolMass == 2.2
    tool = reader.read_tool(cell)
    np.testing.assert_allclose(tool.T_f_t, longer, atol=1e-9)
    # The body moved with the TCP: its tip is on the new TCP.
    local = (tool.body_vertices_mm - longer[:3, 3]) @ longer[:3, :3]
    assert local[:, 2].max() == pytest.approx(0.0, abs=1e-6)
    # Only numbers: the mass changes, nothing else.
    before = tool_state(cell)
    api.set_tool(cell, mass_kg=3.0)
    assert tool_state(cell)[:3] == before[:3] and cell.ToolMass == 3.0


def _tool_solid(doc):
    """A 40 x 40 x 200 mm block drawn somewhere else than at the origin."""
    block = doc.addObject("Part::Box", "MyTool")
    block.Length, block.Width, block.Height = 40, 40, 200
    block.Placement = FreeCAD.Placement(V(500, 300, 100), FreeCAD.Rotation(V(0, 0, 1), 30))
    doc.recompute()
    return block


def test_set_tool_with_a_document_solid(doc):
    cell = api.make_cell(doc)
    block = _tool_solid(doc)
    tcp = FreeCAD.Placement(V(20, 20, 200), FreeCAD.Rotation())
    api.set_tool(cell, body=block, tcp=tcp)
    assert cell.ToolType == "Custom body" and cell.ToolBody == block
    np.testing.assert_allclose(matrix_from_placement(cell.ToolTCP), matrix_from_placement(tcp))
    # The mass stays the cell's (the torch's); the CoG is the block's centre in its own frame.
    assert cell.ToolMass == pytest.approx(tools.get("Straight torch").mass_kg)
    assert tuple(cell.ToolCenterOfGravity) == pytest.approx((20.0, 20.0, 100.0))
    tool = reader.read_tool(cell)
    assert tool.label == "MyTool"
    # In its own coordinates, wherever it stands in the drawing.
    np.testing.assert_allclose(tool.body_vertices_mm.min(axis=0), [0, 0, 0], atol=1e-6)
    np.testing.assert_allclose(tool.body_vertices_mm.max(axis=0), [40, 40, 200], atol=1e-6)
    api.set_tool(cell, body=block, tcp=tcp, mass_kg=4.5, cog_mm=(20, 20, 80))
    assert cell.ToolMass == 4.5 and tuple(cell.ToolCenterOfGravity) == (20.0, 20.0, 80.0)


@pytest.mark.parametrize("case", ["sketch", "not an object", "nan tcp", "negative mass", "nan mass",
                                  "both", "no tcp", "short cog", "nan cog", "unknown"])
def test_bad_tool_input_is_one_clear_error_and_changes_nothing(doc, case):
    cell = api.make_cell(doc, name="Welder")
    block = _tool_solid(doc)
    sketch = sketch_of(doc, polyline([(0, 0), (100, 0)]))
    tcp = FreeCAD.Placement(V(0, 0, 200), FreeCAD.Rotation())
    nan_tcp = np.eye(4)
    nan_tcp[0, 3] = math.nan
    calls = {
        "sketch": (lambda: api.set_tool(cell, body=sketch, tcp=tcp), "no solid"),
        "not an object": (lambda: api.set_tool(cell, body="MyTool", tcp=tcp), "body must be a document object"),
        "nan tcp": (lambda: api.set_tool(cell, body=block, tcp=nan_tcp), "TCP"),
        "negative mass": (lambda: api.set_tool(cell, tool="Ball tool", mass_kg=-1.0), "mass"),
        "nan mass": (lambda: api.set_tool(cell, mass_kg=math.nan), "mass"),
        "both": (lambda: api.set_tool(cell, tool="Ball tool", body=block, tcp=tcp), "not both"),
        "no tcp": (lambda: api.set_tool(cell, body=block), "give the TCP"),
        "short cog": (lambda: api.set_tool(cell, cog_mm=(1, 2)), "3 numbers"),
        "nan cog": (lambda: api.set_tool(cell, cog_mm=(1, 2, math.nan)), "not finite"),
        "unknown": (lambda: api.set_tool(cell, tool="Laser"), "Unknown tool"),
    }
    before = tool_state(cell)
    call, words = calls[case]
    with pytest.raises(InputError) as info:
        call()
    message = str(info.value)
    assert words in message
    assert "Welder" in message or case == "unknown"
    assert tool_state(cell) == before


def test_save_and_reopen_keeps_the_tool(doc, tmp_path):
    cell = api.make_cell(doc, name="Keeper")
    block = _tool_solid(doc)
    api.set_tool(cell, body=block, tcp=FreeCAD.Placement(V(20, 20, 200), FreeCAD.Rotation()),
                 mass_kg=4.0)
    other = api.make_cell(doc, name="Other", tool="Deburring spindle")
    states = {c.Name: tool_state(c) for c in (cell, other)}
    path = str(tmp_path / "tool.FCStd")
    doc.saveAs(path)
    FreeCAD.closeDocument(doc.Name)
    reopened = FreeCAD.openDocument(path)
    try:
        for name, state in states.items():
            assert tool_state(reopened.getObject(name)) == state
        assert reopened.getObject("Keeper").getEnumerationsOfProperty("ToolType") == \
            tools.tool_types()
    finally:
        FreeCAD.closeDocument(reopened.Name)


def test_an_old_document_keeps_its_zero_tool(doc, tmp_path):
    """A file saved before the tool library: no ToolType/ToolBody, ToolTCP identity,
    markers offering three shapes."""
    sketch = sketch_of(doc, polyline([(0, 0), (100, 0)]))
    cell, _ = simple_cell(doc, sketch, markers=[(50, 0, 0)])
    for prop in ("ToolType", "ToolBody"):
        cell.removeProperty(prop)
    cell.ToolTCP = FreeCAD.Placement()
    cell.ToolMass = 2.0
    cell.ToolCenterOfGravity = V(0, 0, 0)
    marker = [o for o in cell.Group if o.Name.startswith("ToolMarker")][0]
    marker.ToolShape = ["Torch", "Cone", "Ball"]
    marker.ToolShape = "Cone"
    doc.recompute()
    cell_name, marker_name = cell.Name, marker.Name
    path = str(tmp_path / "old.FCStd")
    doc.saveAs(path)
    FreeCAD.closeDocument(doc.Name)
    old = FreeCAD.openDocument(path)
    try:
        cell = old.getObject(cell_name)
        assert cell.ToolType == "Custom body" and cell.ToolBody is None
        assert matrix_from_placement(cell.ToolTCP) == pytest.approx(np.eye(4))
        assert cell.ToolMass == 2.0
        program = api.generate(cell)
        np.testing.assert_allclose(program.tool.T_f_t, np.eye(4))
        assert program.tool.body_vertices_mm is None and program.tool.mass_kg == 2.0
        marker = old.getObject(marker_name)
        assert marker.ToolShape == "Cone"
        assert marker.getEnumerationsOfProperty("ToolShape") == ["Cell tool", "Torch", "Cone", "Ball"]
        # RAPID's tooldata still says the zero tool.
        text = dict(api.program_files(cell, post="abb_rapid", check_first=False))
        assert any("[TRUE,[[0.000,0.000,0.000],[1.000000,0.000000,0.000000,0.000000]],[2,[0,0,0]"
                   in t for t in text.values())
    finally:
        FreeCAD.closeDocument(old.Name)


def test_a_new_cell_writes_the_torch_into_rapid_tooldata(doc):
    sketch = sketch_of(doc, polyline([(0, 0), (100, 0)]))
    cell, _ = simple_cell(doc, sketch, markers=[(50, 0, 0)])
    torch = tools.get("Straight torch")
    program = api.generate(cell)
    assert program.tool.label == "Straight torch" and program.tool.mass_kg == pytest.approx(1.851)
    text = "".join(t for _, t in api.program_files(cell, post="abb_rapid", check_first=False))
    assert torch.cog_mm[2] == pytest.approx(146.5, abs=0.1)
    assert "[TRUE,[[0.000,0.000,385.000],[1.000000,0.000000,0.000000,0.000000]],[1.851,[0,0,146." \
        in text, text[:600]


def test_markers_draw_the_cells_tool_and_follow_it(doc):
    sketch = sketch_of(doc, polyline([(0, 0), (100, 0)]))
    cell, _ = simple_cell(doc, sketch, markers=[(50, 0, 0)])
    marker = [o for o in cell.Group if o.Name.startswith("ToolMarker")][0]
    assert marker.ToolShape == "Cell tool"
    box = marker.Shape.BoundBox
    # Pointing down at (50, 0, 0): the torch goes 385 mm up, 65 mm across.
    assert (box.ZMin, box.ZMax) == pytest.approx((0.0, 385.0), abs=1e-6)
    assert box.XLength == pytest.approx(65.0, abs=1e-6) and box.Center.x == pytest.approx(50.0)
    api.set_tool(cell, tool="Ball tool")
    box = marker.Shape.BoundBox
    assert (box.ZMin, box.ZMax, box.XLength) == pytest.approx((0.0, 210.0, 80.0), abs=1e-6)
    # A custom body: its TCP point lands on the marker.
    block = _tool_solid(doc)
    api.set_tool(cell, body=block, tcp=FreeCAD.Placement(V(20, 20, 200), FreeCAD.Rotation()))
    box = marker.Shape.BoundBox
    assert (box.ZMin, box.ZMax) == pytest.approx((0.0, 200.0), abs=1e-6)
    assert (box.XLength, box.YLength) == pytest.approx((40.0, 40.0), abs=1e-6)
    # The TCP typed in the property editor: the markers follow on recompute.
    cell.ToolTCP = FreeCAD.Placement(V(20, 20, 150), FreeCAD.Rotation())
    doc.recompute()
    assert marker.Shape.BoundBox.ZMax == pytest.approx(150.0, abs=1e-6)
    # The old shapes still work.
    marker.ToolShape = "Cone"
    doc.recompute()
    assert marker.Shape.BoundBox.ZLength == pytest.approx(80.0, abs=1e-6)


@pytest.mark.skipif(not collision.is_available(), reason="python-fcl not installed")
def test_check_reports_the_tool_body_hitting_a_block(doc):
    sketch = sketch_of(doc, polyline([(0, 0), (100, 0)]))
    cell, _ = simple_cell(doc, sketch, markers=[(50, 0, 0)])
    assert api.check(cell).ok, api.check(cell).lines()
    # Beside the torch's mount (radius 32.5 mm, 290-385 mm above the TCP) and off the old
    # cylinder of radius 20: 24-30 mm beside the tool axis, 300-340 mm above the path.
    block = doc.addObject("Part::Box", "Block")
    block.Length, block.Width, block.Height = 200, 6, 40
    block.Placement = FreeCAD.Placement(V(-50, 24, 300), FreeCAD.Rotation())
    doc.recompute()
    result = api.check(cell)
    hits = [f for f in result.report.errors if f.kind == "collision"]
    assert hits, result.lines()
    assert all("the tool 'Straight torch' hits Block" in f.message for f in hits)
    # The same TCP without a body (as old files have): the torch-like cylinder misses it.
    cell.removeProperty("ToolType")
    cell.Proxy.onDocumentRestored(cell)      # what reopening an old file does
    assert cell.ToolType == "Custom body"
    assert not [f for f in api.check(cell).report.errors if f.kind == "collision"]


@pytest.mark.skipif(not collision.is_available(), reason="python-fcl not installed")
def test_the_tool_body_is_not_an_obstacle_and_the_zero_tool_is_named(doc):
    sketch = sketch_of(doc, polyline([(0, 0), (100, 0)]))
    cell, _ = simple_cell(doc, sketch, markers=[(50, 0, 0)])
    # The custom tool drawn at the path itself: it would hit everything if it were an obstacle.
    block = doc.addObject("Part::Box", "MyTorch")
    block.Length, block.Width, block.Height = 30, 30, 300
    block.Placement = FreeCAD.Placement(V(35, -15, 0), FreeCAD.Rotation())
    doc.recompute()
    api.set_tool(cell, body=block, tcp=FreeCAD.Placement(V(15, 15, 300), FreeCAD.Rotation()))
    result = api.check(cell)
    assert result.ok, result.lines()
    # A plate through the wrist with the zero tool: the finding says the cell has no tool.
    api.set_tool(cell, tool="Straight torch")
    cell.ToolType = "Custom body"
    cell.ToolTCP = FreeCAD.Placement()
    plate = doc.addObject("Part::Box", "Plate")
    plate.Length, plate.Width, plate.Height = 300, 300, 20
    plate.Placement = FreeCAD.Placement(V(-100, -150, 30), FreeCAD.Rotation())
    doc.recompute()
    messages = [f.message for f in api.check(cell).report.errors if f.kind == "collision"]
    assert messages and all("the cell has no tool" in m for m in messages)


@pytest.mark.skipif(not collision.is_available(), reason="python-fcl not installed")
def test_place_robot_checks_bases_with_the_tool_body(doc):
    """Place robot's full check of a base (placement_search.check_at) meets the same block."""
    from CadRobotWB.objects import obstacles
    from CadRobotWB.robots.kinematics import models
    from CadRobotWB.robots.placement import placement_search
    sketch = sketch_of(doc, polyline([(0, 0), (100, 0)]))
    cell, _ = simple_cell(doc, sketch, markers=[(50, 0, 0)])
    block = doc.addObject("Part::Box", "Block")
    block.Length, block.Width, block.Height = 200, 6, 40
    block.Placement = FreeCAD.Placement(V(-50, 24, 300), FreeCAD.Rotation())
    doc.recompute()
    program = api.generate(cell)
    model = models.model(program.robot)
    solids = obstacles.solid_meshes(doc, np.eye(4))
    found = placement_search.check_at(program, model, matrix_from_placement(cell.Placement), solids)
    messages = [f.message for f in found.report.errors if f.kind == "collision"]
    assert messages and all("the tool 'Straight torch' hits Block" in m for m in messages)
