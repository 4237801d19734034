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
