"""Hand-made programs the post-processor tests share (the same program in
every language, so the posts can be compared)."""

import numpy as np
from scipy.spatial.transform import Rotation

from CadRobotWB.core import program as ir

# Torch pointing down (+Z of the tool into the table), and tilted 30 deg.
DOWN = (180, 0, 0)
DOWN_TILTED = (180, 30, 0)


def pose(euler_xyz_deg=(0, 0, 0), position=(0, 0, 0)):
    """4x4 transform from extrinsic x, y, z angles (deg) and a position (mm)."""
    T = np.eye(4)
    T[:3, :3] = Rotation.from_euler("xyz", euler_xyz_deg, degrees=True).as_matrix()
    T[:3, 3] = position
    return T


def two_frame_program(robot, table_mm=(800.0, -200.0, 400.0), fixture_mm=(600.0, 300.0, 350.0)):
    """A line, an arc with its via point, a reorientation, two frames, speeds
    12.5 and 100 mm/s, zones 10, 0.3, 2.5 and 0 mm."""
    tool = ir.ToolData("Torch", pose((0, 30, 0), (10.0, 0.0, 250.0)),
                       mass_kg=1.5, cog_mm=np.array([0.0, 0.0, 120.0]))
    frames = {
        "Table": ir.WorkFrame("Table", pose((0, 0, 90), table_mm), np.eye(4), "CalibrationFrame"),
        "Fixture": ir.WorkFrame("Fixture", pose((10, 0, -45), fixture_mm), np.eye(4),
                                "CalibrationFrame001"),
    }

    def target(name, position, euler):
        return ir.Target(name, pose(euler, position))

    seam = ir.ProgramPath("Seam", "Weld seam", [
        ir.Move(ir.JOINT, target("p1", (0, 0, 50), DOWN), 100.0, 10.0, "Table",
                role=ir.ROLE_APPROACH, comment="approach"),
        ir.Move(ir.LINEAR, target("p2", (0, 0, 0), DOWN), 12.5, 0.3, "Table",
                role=ir.ROLE_ENTRY, comment="entry"),
        ir.Move(ir.LINEAR, target("p3", (100, 0, 0), DOWN), 12.5, 0.3, "Table", segment=1,
                comment="segment 1: line Sketch.Edge1"),
        ir.Move(ir.LINEAR, target("p4", (100, 0, 0), DOWN_TILTED), 12.5, 0.3, "Table",
                role=ir.ROLE_REORIENT, segment=2, comment="segment 2: reorient"),
        ir.Move(ir.CIRCULAR, target("p6", (100, 100, 0), DOWN_TILTED), 12.5, 0.0, "Table",
                via=target("p5", (150, 50, 0), DOWN_TILTED), segment=2,
                comment="segment 2: arc Sketch.Edge2"),
        ir.Move(ir.LINEAR, target("p7", (100, 100, 50), DOWN_TILTED), 100.0, 0.0, "Table",
                role=ir.ROLE_RETRACT, comment="retract"),
    ])
    contour = ir.ProgramPath("Contour", "Edge contour", [
        ir.Move(ir.JOINT, target("q1", (0, 0, 30), (180, 0, 45)), 100.0, 10.0, "Fixture",
                role=ir.ROLE_APPROACH, comment="approach"),
        ir.Move(ir.LINEAR, target("q2", (0, 0, 0), (180, 0, 45)), 12.5, 2.5, "Fixture",
                role=ir.ROLE_ENTRY, comment="entry"),
        ir.Move(ir.LINEAR, target("q3", (-40.25, 20.5, 0), (180, 0, 45)), 12.5, 0.0,
                "Fixture", segment=1, comment="segment 1: line Sketch001.Edge1"),
        ir.Move(ir.LINEAR, target("q4", (-40.25, 20.5, 30), (180, 0, 45)), 100.0, 0.0,
                "Fixture", role=ir.ROLE_RETRACT, comment="retract"),
    ])
    return ir.Program("Cell", robot, tool, frames, [seam, contour], source="demo.FCStd / Cell")


def minimal_program(robot, move_kind=ir.LINEAR, via=None, frame="B", name="P"):
    """One frame, one move."""
    tool = ir.ToolData("Tool", pose(position=(0, 0, 100)))
    frames = {"B": ir.WorkFrame("B", np.eye(4), np.eye(4))}
    move = ir.Move(move_kind, ir.Target("t1", pose(DOWN, (1, 2, 3))), 10.0, 0.0, frame, via=via)
    return ir.Program(name, robot, tool, frames, [ir.ProgramPath("Path", "Path", [move])])


#: Work frame origins (mm, robot base frame) that put long_program's field within reach.
LONG_PROGRAM_FRAME_MM = {"ABB_IRB2400": (900.0, 0.0, 600.0), "UR5E": (400.0, 0.0, 100.0),
                         "MOTOMAN_HP6": (500.0, 0.0, 200.0)}


def long_program(robot, n_moves, frame_mm=None, solve=True):
    """A program of `n_moves` moves in one path: a joint approach, then a
    zigzag of linear moves and arcs over a 200 x 200 mm field, then a retract.

    Every fourth move along the path is an arc (with its via point), zones
    alternate between 0 and 1 mm, and the torch tilts between 0 and 20 deg,
    so a split part starts with any move kind. With `solve` the targets get
    the joints ``robots.motion.configuration.solve_program`` chooses for `robot`.

    Parameters
    ----------
    robot : str
        A catalog robot; `frame_mm` must put the field within its reach.
    n_moves : int
        At least 3.
    frame_mm : sequence of 3 float, optional
        The work frame's origin in the robot base frame, mm; default from
        :data:`LONG_PROGRAM_FRAME_MM`, else (700, 0, 300).
    solve : bool, optional

    Returns
    -------
    Program
    """
    if frame_mm is None:
        frame_mm = LONG_PROGRAM_FRAME_MM.get(robot, (700.0, 0.0, 300.0))
    tool = ir.ToolData("Torch", pose((0, 0, 0), (0.0, 0.0, 150.0)),
                       mass_kg=2.0, cog_mm=np.array([0.0, 0.0, 80.0]))
    frames = {"B": ir.WorkFrame("B", pose((0, 0, 0), frame_mm), np.eye(4), "CalibrationFrame")}

    def point(i):
        # a boustrophedon over a 200 x 200 mm field, 2 mm between points
        row, col = divmod(i, 100)
        x = 2.0 * (col if row % 2 == 0 else 99 - col)
        y = 2.0 * (row % 100)
        return (x - 100.0, y - 100.0, 0.0), (180, 20.0 * ((i // 50) % 2), 0)

    moves = [ir.Move(ir.JOINT, ir.Target("p0", pose(DOWN, (-100.0, -100.0, 50.0))), 200.0, 5.0,
                     "B", role=ir.ROLE_APPROACH, comment="approach")]
    for i in range(1, n_moves - 1):
        position, euler = point(i)
        target = ir.Target(f"p{i}", pose(euler, position))
        if i % 4 == 0:
            via_position, via_euler = point(i - 1)
            via_position = (via_position[0], via_position[1], 1.0)
            moves.append(ir.Move(ir.CIRCULAR, target, 20.0, float(i % 2), "B",
                                 via=ir.Target(f"v{i}", pose(via_euler, via_position)), segment=i))
        else:
            moves.append(ir.Move(ir.LINEAR, target, 20.0, float(i % 2), "B", segment=i))
    last_position, last_euler = point(n_moves - 2)
    moves.append(ir.Move(ir.LINEAR, ir.Target(f"p{n_moves - 1}",
                                              pose(last_euler, last_position[:2] + (50.0,))),
                         200.0, 0.0, "B", role=ir.ROLE_RETRACT, comment="retract"))
    program = ir.Program("Long", robot, tool, frames, [ir.ProgramPath("Seam", "Long seam", moves)],
                         source="long.FCStd / Long")
    if solve:
        from CadRobotWB.robots.kinematics import models
        from CadRobotWB.robots.motion import configuration
        configuration.solve_program(program, models.model(robot))
    return program
