"""Collision checks (robots/checks/collision.py) for the ABB IRB 2400 at hand-made poses.

Numbers used below (REFERENCE.md and links.py): at q = 0 the forearm axis runs
at z = 1455 mm from x = 100 to the wrist centre (855, 0, 1455), the flange
face is the plane x = 940 facing +X; the flange disc is 0.15 * c4 = 12.75 mm
thick, so the J6 housing of link 5 ends at x = 927.25.
"""

import numpy as np
import pytest
import trimesh

from CadRobotWB.core import program as ir
from CadRobotWB.errors import InputError
from CadRobotWB.robots.checks import collision
from CadRobotWB.robots.kinematics import models

ROBOT = "ABB_IRB2400"
Q0 = np.zeros(6)


def box(lo, hi):
    """Axis-aligned box mesh between corners lo and hi (mm)."""
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    return trimesh.creation.box(hi - lo, transform=trimesh.transformations.translation_matrix(
        0.5 * (lo + hi)))


def tool_along_z(length_mm=250.0):
    T = np.eye(4)
    T[2, 3] = length_mm
    return T


def as_dict(findings):
    return {(f.link, f.obstacle): f.distance_mm for f in findings}


def test_box_on_the_forearm_collides_and_moved_away_does_not():
    on_forearm = box([450, -50, 1405], [550, 50, 1505])
    hits = collision.RobotCollisionChecker(ROBOT, [("Box", on_forearm)]).check(Q0)
    assert {f.link for f in hits} <= {"link3", "link4"} and hits
    assert all(f.obstacle == "Box" and f.distance_mm < -50.0 for f in hits)

    moved = box([450, -50, 1705], [550, 50, 1805])        # 300 mm higher
    assert collision.RobotCollisionChecker(ROBOT, [("Box", moved)]).check(Q0) == []


def test_distances_to_a_wall_in_front_of_the_flange():
    wall = box([970, -500, 1000], [1200, 500, 2000])       # 30 mm in front of the flange face
    findings = collision.RobotCollisionChecker(ROBOT, [("Wall", wall)], margin_mm=50.0).check(Q0)
    assert as_dict(findings) == pytest.approx({("link6", "Wall"): 30.0,
                                               ("link5", "Wall"): 970.0 - 927.25}, abs=1e-6)
    assert [f.link for f in findings] == ["link6", "link5"]  # nearest first
    # Within the margin but not touching: not a collision.
    assert collision.RobotCollisionChecker(ROBOT, [("Wall", wall)]).check(Q0) == []

    pressed = box([935, -500, 1000], [1200, 500, 2000])    # the flange disc 5 mm into it
    findings = collision.RobotCollisionChecker(ROBOT, [("Wall", pressed)]).check(Q0)
    assert as_dict(findings) == pytest.approx({("link6", "Wall"): -5.0}, abs=1e-6)


def tool_down_pose(tcp_mm):
    """Joints putting a 250 mm straight tool's TCP at tcp_mm, pointing down."""
    robot = models.model(ROBOT)
    T_r_t = np.eye(4)
    T_r_t[:3, :3] = np.diag([-1.0, 1.0, -1.0])
    T_r_t[:3, 3] = tcp_mm
    solutions = robot.ik(T_r_t @ np.linalg.inv(tool_along_z()))
    return solutions[robot.within_limits(solutions)][0]


def test_table_below_the_tool_clears_when_the_tcp_is_above_it():
    table = box([600, -400, 0], [1300, 400, 700])          # top at z = 700
    checker = collision.RobotCollisionChecker(ROBOT, [("Table", table)],
                                              tool_T_f_t=tool_along_z(), margin_mm=20.0)
    q = np.array([tool_down_pose([900, 0, z]) for z in (750.0, 700.0, 690.0, 640.0)])
    above, touching, into, deep = checker.check(q)
    assert above == []                                     # tip 65 mm above the table
    # TCP on the table: the tool stops 15 mm short of it (the clearance rule).
    assert as_dict(touching) == pytest.approx({("tool", "Table"): 15.0}, abs=1e-6)
    assert as_dict(into) == pytest.approx({("tool", "Table"): 5.0}, abs=1e-6)
    assert as_dict(deep)[("tool", "Table")] == pytest.approx(-45.0, abs=1e-6)
    assert checker.colliding(q).tolist() == [False, False, False, True]


def test_tilted_torch_on_a_fillet_seam_clears_both_plates():
    """A fillet weld: TCP in the corner of two plates, torch at 45 degrees to both."""
    corner = np.array([900.0, 0.0, 700.0])
    floor_plate = box([700, -200, 690], [1100, 200, 700])   # top face z = 700
    wall_plate = box([900, -200, 700], [910, 200, 900])     # face x = 900, on the floor plate
    # Tool z (approach) points down and towards the wall: (1, 0, -1)/sqrt(2).
    c, s = np.cos(np.radians(45.0)), np.sin(np.radians(45.0))
    R = np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]]) @ np.diag([-1.0, 1.0, -1.0])
    assert np.allclose(R[:, 2], [s, 0.0, -c])
    T_r_t = np.eye(4)
    T_r_t[:3, :3], T_r_t[:3, 3] = R, corner
    robot = models.model(ROBOT)
    solutions = robot.ik(T_r_t @ np.linalg.inv(tool_along_z()))
    q = solutions[robot.within_limits(solutions)][0]
    checker = collision.RobotCollisionChecker(
        ROBOT, [("Floor plate", floor_plate), ("Wall plate", wall_plate)],
        tool_T_f_t=tool_along_z(), margin_mm=20.0)
    # The tool's tip is 15 mm back along the 45 degree axis: 15 / sqrt(2) from each plate.
    assert as_dict(checker.check(q)) == pytest.approx(
        {("tool", "Floor plate"): 15.0 / np.sqrt(2.0), ("tool", "Wall plate"): 15.0 / np.sqrt(2.0)},
        abs=1e-6)
    # The same torch pushed 20 mm further along its axis hits them.
    T_r_t[:3, 3] = corner + 20.0 * R[:, 2]
    solutions = robot.ik(T_r_t @ np.linalg.inv(tool_along_z()))
    q_in = solutions[robot.within_limits(solutions)][0]
    assert {f.obstacle for f in checker.check(q_in) if f.distance_mm <= 0} == {
        "Floor plate", "Wall plate"}


def test_base_standing_on_the_floor_is_not_reported():
    floor = box([-2000, -2000, -20], [2000, 2000, 0])
    pedestal_side = box([200, -300, 0], [260, 300, 300])   # clear of the base (radius 125)
    checker = collision.RobotCollisionChecker(ROBOT, [("Floor", floor), ("Post", pedestal_side)])
    assert [(f.link, f.obstacle) for f in checker.base_contacts] == [("base", "Floor")]
    assert checker.base_contacts[0].distance_mm == pytest.approx(0.0, abs=1e-6)
    assert checker.check(Q0) == []
    # The flange 5 mm into the floor: links are still checked against it.
    robot = models.model(ROBOT)
    T = np.eye(4)
    T[:3, 3] = [1300.0, 0.0, -5.0]        # within reach with J3 = q2 + q3 >= -60 deg
    T[:3, :3] = np.diag([-1.0, 1.0, -1.0])
    q = robot.ik(T)
    q = q[robot.within_limits(q)][0]
    assert as_dict(checker.check(q)) == pytest.approx({("link6", "Floor"): -5.0}, abs=1e-6)


def test_non_convex_obstacle_uses_its_surface():
    """A tube around the forearm with room inside: no collision though its box overlaps."""
    to_x = trimesh.transformations.rotation_matrix(np.pi / 2, [0, 1, 0])
    at_forearm = trimesh.transformations.translation_matrix([500.0, 0.0, 1455.0])
    wide = trimesh.creation.annulus(100.0, 150.0, 100.0, transform=at_forearm @ to_x)
    narrow = trimesh.creation.annulus(50.0, 150.0, 100.0, transform=at_forearm @ to_x)
    assert not wide.is_convex
    assert collision.RobotCollisionChecker(ROBOT, [("Tube", wide)]).check(Q0) == []
    hits = collision.RobotCollisionChecker(ROBOT, [("Tube", narrow)]).check(Q0)
    assert hits and all(f.distance_mm < 0 for f in hits)


def test_obstacle_split_into_bodies_and_named_once():
    legs = trimesh.util.concatenate([box([1500, y, 0], [1550, y + 50, 700]) for y in (-300, 250)])
    top = box([1400, -400, 700], [1700, 400, 740])
    table = trimesh.util.concatenate([legs, top])
    checker = collision.RobotCollisionChecker(ROBOT, [("Table", table)])
    assert len(checker._obstacles) == 3
    robot = models.model(ROBOT)
    T = np.eye(4)
    T[:3, :3] = np.diag([-1.0, 1.0, -1.0])
    T[:3, 3] = [1500.0, 0.0, 720.0]                        # flange inside the table top
    q = robot.ik(T)
    q = q[robot.within_limits(q)][0]
    hits = checker.check(q)
    assert ("link6", "Table") in as_dict(hits)
    assert len({(f.link, f.obstacle) for f in hits}) == len(hits)


def test_many_poses_same_as_one_by_one():
    table = box([600, -400, 0], [1300, 400, 700])
    wall = box([1000, -500, 700], [1050, 500, 1600])
    checker = collision.RobotCollisionChecker(ROBOT, [("Table", table), ("Wall", wall)],
                                              tool_T_f_t=tool_along_z(), margin_mm=25.0,
                                              self_collision=True)
    robot = models.model(ROBOT)
    rng = np.random.default_rng(11)
    q = rng.uniform(robot.joint_min_deg, robot.joint_max_deg, (60, 6))
    together = checker.check(q)
    assert len(together) == 60 and any(together)
    for k in range(0, 60, 7):
        assert checker.check(q[k]) == together[k]
    assert checker.colliding(q).tolist() == [any(f.distance_mm <= 0 for f in pose)
                                             for pose in together]


def test_self_collision_is_opt_in():
    folded = np.array([20.0, 110.0, 60.0, 0.0, 110.0, 0.0])    # wrist down into the base
    plain = collision.RobotCollisionChecker(ROBOT, [], tool_T_f_t=tool_along_z())
    selfish = collision.RobotCollisionChecker(ROBOT, [], tool_T_f_t=tool_along_z(),
                                              self_collision=True)
    assert plain.check(folded) == []
    hits = as_dict(selfish.check(folded))
    assert ("link5", "base") in hits and hits[("link5", "base")] < 0
    assert selfish.check(Q0) == []
    assert selfish.link_names == ("link1", "link2", "link3", "link4", "link5", "link6", "tool")


def test_obstacle_without_triangles_is_an_input_error():
    with pytest.raises(InputError, match="Empty"):
        collision.RobotCollisionChecker(ROBOT, [("Empty", trimesh.Trimesh())])


# --- along the moves: where the controller moves the robot, not the joint interpolation ---------

DOWN = np.diag([-1.0, 1.0, -1.0])        # tool Z (approach) pointing down, X along -X


def one_path_program(tcp_poses):
    """A joint move to the first TCP pose ({R} = {B}), then linear moves through the others."""
    from CadRobotWB.core import program as ir
    moves = [ir.Move(ir.JOINT if k == 0 else ir.LINEAR, ir.Target("ABCDEFGH"[k], T), 50.0, 0.0, "B")
             for k, T in enumerate(tcp_poses)]
    return ir.Program("Moves", ROBOT, ir.ToolData("Straight torch", tool_along_z()),
                      {"B": ir.WorkFrame("B", np.eye(4), np.eye(4))},
                      [ir.ProgramPath("P", "P", moves)])


def pose(R, p):
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p
    return T


def solved_ends(program):
    """The solution of `program` and the joints at its first and last targets."""
    from CadRobotWB.robots.motion import configuration
    solution = configuration.solve_program(program, models.model(ROBOT), assign=False)
    assert solution.ok
    return solution, solution.entries[0].joints_deg, solution.entries[-1].joints_deg


def tool_axis_points(q_deg, from_tcp_mm):
    """Points (N, M, 3) on the tool's axis, `from_tcp_mm` (M,) back from the TCP, at joints (N, 6).
    The tool solid's cone ends 15 mm before the TCP, so axis points 20-235 mm back lie inside it."""
    T_r_t = models.model(ROBOT).fk(q_deg) @ tool_along_z()
    return T_r_t[:, None, :3, 3] - np.asarray(from_tcp_mm)[None, :, None] * T_r_t[:, None, :3, 2]


def inside(points, lo, hi):
    return ((points >= lo) & (points <= hi)).all(axis=-1)


def test_turning_the_tool_about_a_fixed_tcp_is_clear_where_joint_interpolation_would_hit():
    """A 90-degree turn of the tool about the world X axis with the TCP held at (900, 0, 600).

    The controller turns the tool about the TCP: the tool's axis stays in the plane x = 900,
    going up from the TCP (z >= 600), so the tool (radius 20 mm) stays above z = 580.  A box
    whose top is at z = 575 is clear.  Interpolating the joints between the two ends instead
    dips the TCP about 60 mm down and 80 mm towards the robot: the tool enters the box.
    """
    lo, hi = np.array([760.0, 0.0, 450.0]), np.array([880.0, 100.0, 575.0])
    turned = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]) @ DOWN
    program = one_path_program([pose(DOWN, (900, 0, 600)), pose(turned, (900, 0, 600))])
    solution, q_a, q_b = solved_ends(program)
    swing = q_a + np.linspace(0.0, 1.0, 41)[:, None] * (q_b - q_a)
    assert inside(tool_axis_points(swing, np.arange(20.0, 236.0, 5.0)), lo, hi).any()

    checker = collision.RobotCollisionChecker(ROBOT, [("Box", box(lo, hi))],
                                              tool_T_f_t=tool_along_z(), tool_label="Straight torch")
    assert checker.colliding(swing).any()                  # what a joint-space sampler reports
    assert collision.program_collision_findings(program, solution, checker) == []


def test_an_air_move_through_a_box_asks_for_a_longer_approach():
    """The 90-degree turn of the test above as a joint (air) move: its joints' swing enters
    the box (as measured there), and the finding asks for a longer approach of the path."""
    lo, hi = np.array([760.0, 0.0, 450.0]), np.array([880.0, 100.0, 575.0])
    turned = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]) @ DOWN
    program = one_path_program([pose(DOWN, (900, 0, 600)), pose(turned, (900, 0, 600))])
    program.paths[0].moves[1].kind = ir.JOINT
    solution, _, _ = solved_ends(program)
    checker = collision.RobotCollisionChecker(ROBOT, [("Box", box(lo, hi))],
                                              tool_T_f_t=tool_along_z(), tool_label="Straight torch")
    found = collision.program_collision_findings(program, solution, checker)
    assert found and all("on the joint move to target B" in f.message and
                         "lengthen the approach (ApproachDistance of path 'P', and of the path "
                         "before it)" in f.message for f in found)


def test_a_linear_move_through_a_box_hits_where_joint_interpolation_would_pass():
    """A linear move from y = -400 to y = +400 at x = 900, z = 600, tool pointing down.

    The TCP line passes through a box at its middle (x 880..920, |y| <= 20, z 550..700): the
    tool from z = 615 up runs into it, at 50% of the move.  Interpolating the joints between
    the two ends (by symmetry only axes 1 and 6 differ, by +-23.96 deg) turns the TCP about
    axis 1 on the circle of radius hypot(900, 400) = 984.9 mm: the tool stays 964.9 mm or more
    from axis 1, the box within hypot(920, 20) = 920.2 mm of it.
    """
    lo, hi = np.array([880.0, -20.0, 550.0]), np.array([920.0, 20.0, 700.0])
    program = one_path_program([pose(DOWN, (900, -400, 600)), pose(DOWN, (900, 400, 600))])
    solution, q_a, q_b = solved_ends(program)
    swing = q_a + np.linspace(0.0, 1.0, 81)[:, None] * (q_b - q_a)
    T_r_t = models.model(ROBOT).fk(swing) @ tool_along_z()
    assert np.hypot(T_r_t[:, 0, 3], T_r_t[:, 1, 3]) == pytest.approx(np.hypot(900, 400), abs=1e-6)
    assert T_r_t[:, :3, 2] == pytest.approx(np.tile([0.0, 0.0, -1.0], (81, 1)), abs=1e-9)
    assert q_b - q_a == pytest.approx([47.92, 0, 0, 0, 0, 47.92], abs=0.01)

    checker = collision.RobotCollisionChecker(ROBOT, [("Box", box(lo, hi))],
                                              tool_T_f_t=tool_along_z(), tool_label="Straight torch")
    assert not checker.colliding(swing).any()              # what a joint-space sampler reports
    found = collision.program_collision_findings(program, solution, checker)
    assert [(f.kind, f.target, f.move_index) for f in found] == [("collision", "B", 1)]
    assert ("the tool 'Straight torch' hits Box" in found[0].message
            and "on the linear move to target B, at 50% of the move" in found[0].message)
