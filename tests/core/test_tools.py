"""The tool library (robots/catalog/tools.py) and the collision check with a tool body
(robots/checks/collision.py: tool_pieces, tool_arguments, messages naming the tool)."""

import numpy as np
import pytest
import trimesh

from CadRobotWB.core.program import ToolData
from CadRobotWB.errors import UnknownNameError
from CadRobotWB.robots.catalog import tools
from CadRobotWB.robots.checks import collision
from CadRobotWB.sensors import force_following

NAMES = ["Straight torch", "Bent torch", "Ball tool", "Deburring spindle"]


def in_tcp(tool, points):
    """Points (N, 3) in {F} expressed in the TCP frame {T}."""
    T = tool.T_f_t
    return (np.asarray(points) - T[:3, 3]) @ T[:3, :3]


def test_the_library_has_the_four_names_other_code_relies_on():
    assert tools.names() == NAMES
    assert tools.tool_types() == NAMES + ["Custom body"]
    assert tools.DEFAULT == "Straight torch"
    with pytest.raises(UnknownNameError, match="Unknown tool 'Laser'.*Straight torch"):
        tools.get("Laser")


@pytest.mark.parametrize("name", NAMES)
def test_the_body_ends_at_the_tcp_and_lies_behind_it(name):
    tool = tools.get(name)
    vertices, faces = tool.mesh()
    assert vertices.shape[1] == 3 and faces.shape[1] == 3 and faces.max() < len(vertices)
    local = in_tcp(tool, vertices)
    # The tip: nothing beyond the TCP along the approach axis, and the body reaches it.
    assert local[:, 2].max() == pytest.approx(0.0, abs=0.5)
    assert np.linalg.norm(local, axis=1).min() < 0.5
    # +Z points away from the body: the flange (and the body's bulk) is behind the TCP.
    assert in_tcp(tool, [[0.0, 0.0, 0.0]])[0, 2] < -100.0
    assert in_tcp(tool, [tool.cog_mm])[0, 2] < -50.0
    # Every solid is a closed convex piece.
    assert all(m.is_watertight and m.is_convex for m in tool.meshes())
    # The body starts on the flange face (z = 0 in {F}) and not behind it.
    assert vertices[:, 2].min() == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize("name", NAMES)
def test_mass_and_centre_of_gravity(name):
    tool = tools.get(name)
    vertices, _ = tool.mesh()
    assert tool.mass_kg > 0.0
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    assert np.all(tool.cog_mm >= lo) and np.all(tool.cog_mm <= hi)


def test_realistic_sizes():
    torch = tools.get("Straight torch")
    assert 350.0 <= torch.T_f_t[2, 3] <= 400.0 and 1.5 <= torch.mass_kg <= 2.5
    np.testing.assert_allclose(torch.T_f_t[:3, :3], np.eye(3), atol=1e-12)
    spindle = tools.get("Deburring spindle")
    assert 230.0 <= np.linalg.norm(spindle.T_f_t[:3, 3]) <= 300.0 and 3.0 <= spindle.mass_kg <= 5.0
    # The bent torch's approach axis is tilted 22 degrees from the flange axis.
    bent = tools.get("Bent torch")
    assert np.degrees(np.arccos(bent.T_f_t[2, 2])) == pytest.approx(22.0, abs=1e-9)
    assert 1.5 <= bent.mass_kg <= 2.5


def test_ball_tool_has_the_force_simulation_ball():
    ball = tools.get("Ball tool")
    sphere = [s for s in ball.solids if s.kind == "sphere"]
    assert len(sphere) == 1
    assert sphere[0].size_mm[0] == tools.BALL_RADIUS_MM == 5.0
    # force_following models the ball with this radius by default; its centre is r behind the TCP.
    import inspect
    parameters = inspect.signature(force_following.simulate_force_following).parameters
    assert parameters["radius_mm"].default == tools.BALL_RADIUS_MM
    centre = sphere[0].T_f_p[:3, 3]
    assert in_tcp(ball, [centre])[0] == pytest.approx([0.0, 0.0, -5.0])


def test_cog_is_the_mass_weighted_centroid_of_the_solids():
    # Straight torch, by hand: mount 0.9 kg at 47.5, tube 0.7 kg at 205, nozzle cone
    # (r 13 -> 8 over 55 mm from z = 315) 0.25 kg, wire 0.001 kg at 377.5.
    r0, r1, h = 13.0, 8.0, 55.0
    cone_z = 315.0 + h * (r0 ** 2 + 2 * r0 * r1 + 3 * r1 ** 2) / (4 * (r0 ** 2 + r0 * r1 + r1 ** 2))
    expected = (0.9 * 47.5 + 0.7 * 205.0 + 0.25 * cone_z + 0.001 * 377.5) / 1.851
    assert tools.get("Straight torch").cog_mm == pytest.approx([0.0, 0.0, expected])


# --- the collision check with the tool body ------------------------------------------------

def test_tool_pieces_are_cut_short_of_the_tcp():
    torch = tools.get("Straight torch")
    pieces = collision.tool_pieces(torch.mesh(), torch.T_f_t, clearance_mm=20.0)
    vertices = np.vstack([p.vertices for p in pieces])
    # The wire (the last 15 mm) is gone, the nozzle cut 20 mm before the TCP (z = 365).
    assert vertices[:, 2].max() == pytest.approx(365.0, abs=1e-6)
    assert len(pieces) == 3 and all(p.is_convex for p in pieces)
    # The cut nozzle is the cone between z = 315 and 365: radius 13 -> 8 + 5 * 5 / 55.
    nozzle = max(pieces, key=lambda p: p.bounds[1, 2])
    radius_at_cut = np.hypot(*nozzle.vertices[nozzle.vertices[:, 2] > 364.9][:, :2].T).max()
    assert radius_at_cut == pytest.approx(8.0 + 5.0 * 5.0 / 55.0, rel=0.02)


def test_tool_pieces_of_a_non_convex_body_are_cut_too():
    # A spool (a groove between two collars): one connected, non-convex body, tip at z = 100.
    spool = trimesh.creation.revolve([[0, 0], [20, 0], [20, 40], [8, 40], [8, 60], [20, 60],
                                      [20, 100], [0, 100]], sections=16)
    assert spool.is_watertight and not spool.is_convex
    T = np.eye(4)
    T[2, 3] = 100.0
    pieces = collision.tool_pieces(spool, T, clearance_mm=15.0)
    assert len(pieces) == 1 and not pieces[0].is_convex
    vertices = pieces[0].vertices
    assert vertices[:, 2].max() == pytest.approx(85.0, abs=1e-6)
    assert vertices[:, 2].min() == pytest.approx(0.0, abs=1e-6)
    # The cut surface keeps the collar's wall up to the cut: points at radius 20 at z = 85.
    at_cut = vertices[np.isclose(vertices[:, 2], 85.0)]
    assert np.hypot(at_cut[:, 0], at_cut[:, 1]).max() == pytest.approx(20.0, rel=1e-6)


def test_tool_arguments_from_a_program_tool():
    plain = ToolData("tTool", np.eye(4))
    assert set(collision.tool_arguments(plain)) == {"tool_T_f_t", "tool_label"}
    torch = tools.get("Straight torch")
    vertices, faces = torch.mesh()
    data = ToolData("tTool", torch.T_f_t, 1.85, torch.cog_mm, "Straight torch", vertices, faces)
    arguments = collision.tool_arguments(data)
    assert arguments["tool_label"] == "Straight torch"
    assert arguments["tool_mesh"][0] is vertices


ROBOT = "ABB_IRB2400"
Q0 = np.zeros(6)          # flange face at x = 940, z = 1455, facing +X (test_collision.py)


def flange_to_x():
    """{F} at q = 0 in {R}: z_F along +X of the base."""
    from CadRobotWB.robots.checks import links
    from CadRobotWB.robots.kinematics import models
    return links.link_frames(models.model(ROBOT), Q0[None, :])[0, 6]


def box(lo, hi):
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    return trimesh.creation.box(hi - lo, transform=trimesh.transformations.translation_matrix(
        0.5 * (lo + hi)))


@pytest.mark.skipif(not collision.is_available(), reason="python-fcl not installed")
def test_the_spindle_body_hits_where_the_old_cylinder_did_not():
    spindle = tools.get("Deburring spindle")
    T_r_f = flange_to_x()
    # The spindle motor lies 50 mm off the flange axis (along x_F); put a small block
    # beside the motor, 45-60 mm off the axis along x_F, 100-120 mm out from the flange.
    centre_f = np.array([75.0, 0.0, 110.0])
    centre_r = T_r_f[:3, :3] @ centre_f + T_r_f[:3, 3]
    block = box(centre_r - 10.0, centre_r + 10.0)
    old = collision.RobotCollisionChecker(ROBOT, [("Block", block)], tool_T_f_t=spindle.T_f_t)
    assert old.check(Q0) == []            # the old cylinder (radius 20) runs to the TCP
    new = collision.RobotCollisionChecker(ROBOT, [("Block", block)], tool_T_f_t=spindle.T_f_t,
                                          tool_mesh=spindle.mesh(), tool_label=spindle.name)
    hits = new.check(Q0)
    assert [f.link for f in hits] == ["tool"] and hits[0].distance_mm < 0
    assert collision.hitting_body(new, "tool") == "the tool 'Deburring spindle'"
    assert collision.hitting_body(new, "link6") == "the robot's link6"


@pytest.mark.skipif(not collision.is_available(), reason="python-fcl not installed")
def test_a_surface_touching_the_tip_is_not_a_collision():
    torch = tools.get("Straight torch")
    T_r_f = flange_to_x()
    tcp_x = (T_r_f @ torch.T_f_t)[0, 3]                   # 940 + 385
    plate = box([tcp_x, -200, 1255], [tcp_x + 20, 200, 1655])   # its face through the TCP
    checker = collision.RobotCollisionChecker(ROBOT, [("Plate", plate)], tool_T_f_t=torch.T_f_t,
                                              tool_mesh=torch.mesh(), tool_label=torch.name)
    assert checker.check(Q0) == []
    # 30 mm closer it meets the nozzle (the cut is 15 mm short of the TCP).
    closer = box([tcp_x - 30, -200, 1255], [tcp_x, 200, 1655])
    checker = collision.RobotCollisionChecker(ROBOT, [("Plate", closer)], tool_T_f_t=torch.T_f_t,
                                              tool_mesh=torch.mesh(), tool_label=torch.name)
    hits = checker.check(Q0)
    assert [f.link for f in hits] == ["tool"]
    assert hits[0].distance_mm == pytest.approx(-15.0, abs=1e-3)
