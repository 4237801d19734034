"""Add positioner / Add track and the player with external axes, in the FreeCAD window (issue 23).

The cell is examples/pipe_flange_cell.py: a DN 100 pipe (outside radius 57.15 mm)
standing on a flange plate on the table of a generic tilt-and-turn positioner whose
base is at POSITIONER_AT_MM (1200, 0, 0); the generic positioner's table is 800 mm above its base at
tilt = turn = 0 and the generic track's carriage 250 mm above its base
(``catalog.build`` with model None). The robot base is the origin.
"""

import numpy as np
import pytest

import FreeCAD
import FreeCADGui

from CadRobotWB.gui import mechanism_panel, robot_view, simulation_player
from CadRobotWB.objects import base as objects_base
import test_commands
from conftest import close_panels, non_white_pixels, process_events, render

import pipe_flange_cell

journal = test_commands.journal
V = FreeCAD.Vector
#: The generic tilt-and-turn's table above its base, and the generic track's carriage, mm.
TABLE_HEIGHT_MM, CARRIAGE_HEIGHT_MM = 800.0, 250.0
#: Where the example stands the positioner (and so the part's axis), x in mm.
X_MM = pipe_flange_cell.POSITIONER_AT_MM[0]


@pytest.fixture
def pipe_doc(gui_doc):
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    close_panels()
    yield gui_doc
    simulation_player.close_player()
    mechanism_panel.close_panel()
    close_panels()


def accepted_calls(panel, journal):
    """OK on `panel`; the API calls it journaled."""
    del journal[:]
    assert panel.accept()
    process_events()
    return [line for line in journal if "api." in line]


def only(doc, type_name):
    found = objects_base.objects_of_type(doc, type_name)
    assert len(found) == 1, found
    return found[0]


def test_add_positioner_and_track_through_their_panels(pipe_doc, journal):
    cell = pipe_flange_cell.build(pipe_doc, positioner=False)
    parts = [pipe_doc.getObject(n) for n in ("Flange", "Pipe", "FlangeFrame")]
    FreeCADGui.Selection.clearSelection()
    for part in parts + [cell]:          # the cell selected too: it never rides
        FreeCADGui.Selection.addSelection(pipe_doc.Name, part.Name)
    assert test_commands.active("CadRobot_AddPositioner")
    test_commands.run("CadRobot_AddPositioner")
    panel = mechanism_panel.active_panel()
    assert panel is not None and panel.kind() == "tilt_turn" and panel.parts == parts
    # the table under the parts: the flange plate's underside is the table, 800 mm up
    z_table = pipe_doc.getObject("Flange").Shape.BoundBox.ZMin
    # turned a quarter turn: the robot (the origin, at -X of the table) faces the table across
    # the tilt axis, which runs along +Y
    assert (panel.x.value(), panel.y.value(), panel.z.value(), panel.rotation.value()) == \
        pytest.approx((X_MM, 0.0, z_table - TABLE_HEIGHT_MM, 90.0), abs=1e-6)
    calls = accepted_calls(panel, journal)
    assert len(calls) == 1 and calls[0].startswith("positioner = api.add_positioner(")
    positioner = only(pipe_doc, "Positioner")
    assert positioner in cell.Group and positioner.Kind == "tilt_turn"
    # the parts selected, and the tool marker on the path drawn on them (add_positioner adds it)
    assert [p.Name for p in positioner.Parts] == ["Flange", "Pipe", "FlangeFrame", "ToolMarker"]
    assert positioner.Placement.Base == V(X_MM, 0.0, z_table - TABLE_HEIGHT_MM)
    test_commands.undo_redo(pipe_doc, [positioner.Name])

    FreeCADGui.Selection.clearSelection()
    test_commands.run("CadRobot_AddTrack")
    panel = mechanism_panel.active_panel()
    assert panel.kind() == "track" and panel.model() is None
    # the carriage under the robot (the origin): the track's base 250 mm below it
    assert (panel.x.value(), panel.y.value(), panel.z.value()) == (0.0, 0.0, -CARRIAGE_HEIGHT_MM)
    panel.length.setValue(2000.0)
    calls = accepted_calls(panel, journal)
    assert len(calls) == 1 and calls[0].startswith("track = api.add_track(")
    track = only(pipe_doc, "Track")
    assert track in cell.Group and track.Length == 2000.0
    assert cell.Placement.Base == V(0, 0, 0)           # the robot stays where it stood


def _transform(obj):
    """The coin transform of `obj`'s view provider, 4x4."""
    return robot_view.matrix_from_transform(obj.ViewObject.RootNode.getChild(0))


def _angle_deg(a, b):
    return float(np.degrees(np.arccos(np.clip(np.dot(a, b) / np.linalg.norm(a) / np.linalg.norm(b),
                                              -1.0, 1.0))))


def test_the_player_turns_the_part_with_the_positioner(pipe_doc, tmp_path):
    cell = pipe_flange_cell.build(pipe_doc)
    pipe = pipe_doc.getObject("Pipe")
    drawn_box = pipe.Shape.BoundBox
    placement = FreeCAD.Placement(pipe.Placement)
    foot_centre = np.array([X_MM, 0.0, drawn_box.ZMin])     # the seam circle's centre
    player = simulation_player.open_player(cell)
    timeline = player.timeline
    assert timeline.external is not None and timeline.external.shape[1] == 2
    moves = player.program.moves()
    welding = [i for i, k in enumerate(timeline.move_index) if moves[k].weld and moves[k].role == "path"]
    first, half = welding[0], welding[len(welding) // 2]
    turned = []
    for i in (first, half):
        player.show_frame(i)
        T = _transform(pipe)
        tilt, turn = timeline.external[i]
        # the pipe's axis, drawn vertical, leans by the tilt
        assert _angle_deg(T[:3, 2], [0, 0, 1]) == pytest.approx(abs(tilt), abs=0.01)
        # and the panel shows that lean as E1, the positioner's tilt, to its 0.1 deg
        shown = [label.text() for label in player.external_labels]
        assert len(shown) == 2 and all(text.endswith("\u00b0") for text in shown)
        assert abs(float(shown[0][:-1])) == pytest.approx(_angle_deg(T[:3, 2], [0, 0, 1]), abs=0.051)
        # the torch is on the seam as the part is shown: back in the drawing, the TCP is
        # on the circle of radius 57.15 mm round the pipe's foot
        tcp_drawn = np.linalg.inv(T)[:3, :3] @ timeline.tcp_u[i] + np.linalg.inv(T)[:3, 3]
        radial = tcp_drawn - foot_centre
        assert np.hypot(radial[0], radial[1]) == pytest.approx(pipe_flange_cell.PIPE_RADIUS_MM, abs=0.5)
        assert radial[2] == pytest.approx(0.0, abs=0.5)
        turned.append(turn)
    image = render(FreeCADGui.getDocument(pipe_doc.Name).activeView(), tmp_path / "player.png")
    assert non_white_pixels(image) > 10000
    # halfway round the circle the table has turned about half a turn more
    assert abs(turned[1] - turned[0]) == pytest.approx(180.0, abs=30.0)
    simulation_player.close_player()
    process_events()
    assert np.allclose(_transform(pipe), np.array(placement.toMatrix().A).reshape(4, 4), atol=1e-9)
    assert pipe.Placement == placement                   # the document never moved
    assert pipe.Shape.BoundBox.ZMin == drawn_box.ZMin


def test_the_default_positioner_stands_its_pillars_beside_the_table_not_in_the_robot(pipe_doc):
    """A new user's cell: the robot where the New cell panel stands it beside a part on a
    MOTOPOS D500 (836 mm from the table's centre, as for a box frame and a tube on it), Add
    positioner with the defaults. The D500's pillars reach 770 mm from the table's centre
    along its tilt axis and 150 mm across it: along the line to the robot they would stand
    66 mm from its axis 1, inside its base; across it, 686 mm away, clear of its footprint."""
    from CadRobotWB.robots.placement import default_base as robot_default_base
    cell = pipe_flange_cell.build(pipe_doc, positioner=False)
    cell.Placement = FreeCAD.Placement(V(X_MM - 836.0, 0, 75.0), FreeCAD.Rotation())
    parts = [pipe_doc.getObject(n) for n in ("Flange", "Pipe")]
    FreeCADGui.Selection.clearSelection()
    for part in parts:
        FreeCADGui.Selection.addSelection(pipe_doc.Name, part.Name)
    test_commands.run("CadRobot_AddPositioner")
    panel = mechanism_panel.active_panel()
    panel.set_model("YASKAWA_MOTOPOS_D500")
    process_events()
    assert panel.rotation.value() == pytest.approx(90.0)
    placement = FreeCAD.Placement(V(panel.x.value(), panel.y.value(), panel.z.value()),
                                  FreeCAD.Rotation(V(0, 0, 1), panel.rotation.value()))
    panel.reject()
    from CadRobotWB.objects.convert import matrix_from_placement
    from CadRobotWB.robots.mechanisms import catalog
    mechanism = catalog.build("tilt_turn", "YASKAWA_MOTOPOS_D500",
                              T_u_base=matrix_from_placement(placement))
    # the base's solids, and the robot's axis 1, in the positioner's base frame: the distance
    # across the floor from the robot's axis to the box round the pillars
    T_base_u = np.linalg.inv(mechanism.T_u_base)
    pillars = catalog.solids(mechanism)[0][0] @ T_base_u[:3, :3].T + T_base_u[:3, 3]
    robot = (T_base_u @ [X_MM - 836.0, 0.0, 0.0, 1.0])[:2]
    nearest = np.linalg.norm(robot - np.clip(robot, pillars[:, :2].min(0), pillars[:, :2].max(0)))
    assert nearest == pytest.approx(836.0 - 150.0, abs=1.0)
    assert nearest > robot_default_base.footprint_radius_mm("ABB_IRB2400")


def test_the_new_cell_panel_adds_a_positioner_under_the_parts(pipe_doc, journal):
    from CadRobotWB.gui import new_cell_panel
    flange, pipe = pipe_flange_cell.build_part(pipe_doc, pipe_flange_cell.table_centre())
    FreeCADGui.Selection.clearSelection()             # no selection: every solid rides
    panel = new_cell_panel.open_panel(pipe_doc)
    panel.set_external_axes("tilt_turn")
    calls = accepted_calls(panel, journal)
    assert [c.split("(")[0] for c in calls] == ["cell = api.make_cell", "positioner = api.add_positioner"]
    positioner = only(pipe_doc, "Positioner")
    assert positioner in only(pipe_doc, "Cell").Group
    assert [p.Name for p in positioner.Parts] == [flange.Name, pipe.Name]
    # the table (800 mm above the base) under the parts' bottom centre
    box = flange.Shape.BoundBox
    assert positioner.Placement.Base == V(box.Center.x, box.Center.y, box.ZMin - TABLE_HEIGHT_MM)


def test_the_commands_are_after_weld_with_icons_and_tips(pipe_doc, monkeypatch, tmp_path):
    from CadRobotWB.commands import TOOLBARS
    names = TOOLBARS[0][1]
    assert names[names.index("CadRobot_Weld") + 1:][:2] == ["CadRobot_AddPositioner", "CadRobot_AddTrack"]
    assert not test_commands.active("CadRobot_AddPositioner")      # no cell yet
    for name in ("CadRobot_AddPositioner", "CadRobot_AddTrack"):
        info = FreeCADGui.Command.get(name).getInfo()
        assert info["menuText"] and len(info["toolTip"]) > 40 and info["statusTip"]
    monkeypatch.setattr(test_commands, "MY_COMMANDS", ("CadRobot_AddPositioner", "CadRobot_AddTrack"))
    test_commands.test_icons_are_drawn(tmp_path)


# --- the preview while the panel is open -------------------------------------------------------

#: Half-widths and height of each mechanism's solids about its base at every axis 0, mm, by hand
#: from the catalog's geometry (catalog._tilt_turn_bodies: the pillars stand table radius + 50
#: (yoke gap) + 150 (yoke arm) + 20 (pillar gap) from the centre and are 150 mm wide, their tops
#: 75 mm above the tilt axis; the table disc's top is tilt axis height + table offset up):
#: generic tilt-and-turn (tilt axis 800 mm up, table 1000 mm across): x 500 + 370, y the table's
#: 500, z the pillars' top 800 + 75; MOTOPOS D500 (tilt axis 380 mm, table 150 mm above it,
#: 800 mm across): x 400 + 370, y 400, z the table's top 380 + 150.
TILT_TURN_BOX_MM = {None: (870.0, 500.0, 875.0), "YASKAWA_MOTOPOS_D500": (770.0, 400.0, 530.0)}


def _preview_box(doc):
    """(min, max) of the mechanism previews in `doc`'s active view, mm, and how many there are
    (found by name in the scene graph, measured by coin)."""
    from pivy import coin
    scene = FreeCADGui.getDocument(doc.Name).activeView().getSceneGraph()
    search = coin.SoSearchAction()
    search.setName(coin.SbName("CadRobotMechanismPreview"))
    search.setInterest(coin.SoSearchAction.ALL)
    search.apply(scene)
    paths = search.getPaths()
    if paths.getLength() == 0:
        return None, 0
    action = coin.SoGetBoundingBoxAction(coin.SbViewportRegion())
    action.apply(paths[0])
    box = action.getBoundingBox()
    return (np.array(box.getMin().getValue()), np.array(box.getMax().getValue())), paths.getLength()


def _type_base(panel, x, y, z, rz):
    for spin, value in zip((panel.x, panel.y, panel.z, panel.rotation), (x, y, z, rz)):
        spin.setValue(value)          # each signal redraws the preview at once


def _assert_box(doc, low, high):
    (lo, hi), count = _preview_box(doc)
    assert count == 1
    assert lo == pytest.approx(low, abs=0.01) and hi == pytest.approx(high, abs=0.01)


def test_the_panels_preview_the_mechanism_at_the_base_typed_until_closed(pipe_doc, journal, tmp_path):
    from CadRobotWB import api
    cell = api.make_cell(pipe_doc)                       # the robot at the origin, no parts
    pipe_doc.recompute()
    FreeCADGui.Selection.clearSelection()
    objects, undo = test_commands.names(pipe_doc), list(pipe_doc.UndoNames)
    touched = [o.Name for o in pipe_doc.Objects if "Touched" in o.State]
    test_commands.run("CadRobot_AddPositioner")
    panel = mechanism_panel.active_panel()
    assert panel.preview is not None and panel.preview.shown
    # the generic tilt-and-turn at the base typed, then turned a quarter turn (x and y swap)
    hx, hy, hz = TILT_TURN_BOX_MM[None]
    _type_base(panel, 1000.0, 200.0, 50.0, 0.0)
    _assert_box(pipe_doc, (1000.0 - hx, 200.0 - hy, 50.0), (1000.0 + hx, 200.0 + hy, 50.0 + hz))
    _type_base(panel, -300.0, 400.0, -20.0, 90.0)
    _assert_box(pipe_doc, (-300.0 - hy, 400.0 - hx, -20.0), (-300.0 + hy, 400.0 + hx, -20.0 + hz))
    # another model: its own solids, at the same base (typed, so not recomputed)
    assert panel.set_model("YASKAWA_MOTOPOS_D500")
    hx, hy, hz = TILT_TURN_BOX_MM["YASKAWA_MOTOPOS_D500"]
    _assert_box(pipe_doc, (-300.0 - hy, 400.0 - hx, -20.0), (-300.0 + hy, 400.0 + hx, -20.0 + hz))
    view = FreeCADGui.getDocument(pipe_doc.Name).activeView()
    view.viewIsometric()
    view.fitAll()
    image = render(view, tmp_path / "positioner_preview.png", 320, 240)
    assert non_white_pixels(image) > 2500
    # a generic turntable: its 1000 mm table 750 mm up (catalog.GENERIC)
    panel.set_kind("turntable")
    _assert_box(pipe_doc, (-800.0, -100.0, -20.0), (200.0, 900.0, 730.0))
    panel.reject()
    process_events()
    assert _preview_box(pipe_doc)[1] == 0 and mechanism_panel.active_panel() is None
    # the document as it was: no object, no undo step, nothing touched
    assert test_commands.names(pipe_doc) == objects and list(pipe_doc.UndoNames) == undo
    assert [o.Name for o in pipe_doc.Objects if "Touched" in o.State] == touched

    # a track: the generic carriage under the robot (the origin), 250 mm above the base; its
    # rail runs from -400 to travel + 400 (the 800 mm carriage's half-length) and is 800 mm wide
    test_commands.run("CadRobot_AddTrack")
    panel = mechanism_panel.active_panel()
    _assert_box(pipe_doc, (-400.0, -400.0, -CARRIAGE_HEIGHT_MM), (3400.0, 400.0, 0.0))
    panel.length.setValue(2000.0)
    _assert_box(pipe_doc, (-400.0, -400.0, -CARRIAGE_HEIGHT_MM), (2400.0, 400.0, 0.0))
    # a model whose travel (1000 mm) is shorter than the 2000 mm asked: no preview, one line why
    assert panel.set_model("KUKA_KL_100_2")
    assert _preview_box(pipe_doc)[1] == 0 and "KUKA_KL_100_2" in panel.message.text()
    assert panel.set_model(None)
    assert len(accepted_calls(panel, journal)) == 1
    assert _preview_box(pipe_doc)[1] == 0                # OK takes it away too
    assert only(pipe_doc, "Track") in cell.Group
