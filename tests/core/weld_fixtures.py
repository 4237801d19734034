"""Hand-built weld programs the weld tests share (issue 22): the same woven
fillet weld for every post, the checks and the simulation.

The part: a T-joint, the floor plate in the X-Y plane of frame B, the wall in
its X-Z plane on the +Y side of the seam; the seam runs along +X at the origin.
The torch comes from -Y, +Z on the bisector (work angle 45 degrees) and pushes
10 degrees along the travel.
"""

import numpy as np

from CadRobotWB.core import program as ir
from CadRobotWB.core.welding import Tracking, Weave, WeldSchedule

from post_programs import pose

#: Fillet, 6 mm plate, leg 5-6 mm (Daihen OTC CPTX-i 400-2W section 9.5.1), the library's
#: midpoints: 265 A, 27.5 V, 45 cm/min; wire feed from Miller's rule (1.0 in/min per A).
FILLET_T6 = WeldSchedule(
    name="fillet_t6", wire_mm=1.2, wire_feed_m_min=6.7, voltage_v=27.5, current_a=265.0,
    travel_speed_mm_s=7.5, gas_preflow_s=0.2, gas_postflow_s=0.5, crater_fill_s=0.3,
    crater_current_a=185.0, crater_voltage_v=22.0, crater_wire_feed_m_min=4.5, burnback_s=0.05,
    ctwd_mm=15.0, source="Daihen OTC CPTX-i 400-2W section 9.5.1, plate 6 mm, leg 5-6 mm",
    wire_feed_estimated=True).validated()
#: Zigzag 4 mm wide at 2 Hz (3.75 mm per cycle at 7.5 mm/s), 0.1 s at each end.
ZIGZAG_4MM = Weave("zigzag", width_mm=4.0, frequency_hz=2.0, dwell_left_s=0.1,
                   dwell_right_s=0.1).validated()
#: Torch orientation: tool +Z = (0, 1, -1)/sqrt(2) turned 10 degrees to push along +X.
TORCH_EULER = (-135.0, 0.0, 0.0)
PUSH_DEG = 10.0


def torch_pose(position):
    """4x4 pose of the torch on the fillet at `position` (mm, frame B)."""
    T = pose(TORCH_EULER, position)
    c, s = np.cos(np.radians(PUSH_DEG)), np.sin(np.radians(PUSH_DEG))
    push = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])   # about the tool's own Y
    T[:3, :3] = T[:3, :3] @ push
    return T


def _target(name, position, T=None):
    return ir.Target(name, torch_pose(position) if T is None else T)


def woven_fillet_program(robot="ABB_IRB2400", weave=ZIGZAG_4MM, tracking=Tracking(),
                         schedule=FILLET_T6, frame_mm=(900.0, 0.0, 400.0), solve=False):
    """A 100 mm fillet weld in one run: approach above the start, entry down
    the tool axis to the seam start (the arc ignites there), two welded moves
    (start -> middle blended, middle -> end fine), retract.

    Parameters
    ----------
    robot : str
        Catalog name; with `solve` the targets get the robot's joints.
    weave : welding.Weave or None
    tracking : welding.Tracking
    schedule : welding.WeldSchedule
    frame_mm : sequence of 3 float
        Origin of work frame B in the robot base frame, mm.

    Returns
    -------
    Program
        ``paths[0].welds == [WeldRun("Weld", start=1, end=3)]``; moves 2 and 3
        weld at the schedule's travel speed.
    """
    tool = ir.ToolData("Torch", pose((0, 0, 0), (0.0, 0.0, 350.0)), mass_kg=3.0,
                       cog_mm=np.array([0.0, 0.0, 150.0]), label="Straight torch")
    frames = {"B": ir.WorkFrame("B", pose((0, 0, 0), frame_mm), np.eye(4), "CalibrationFrame")}
    T_start = torch_pose((0.0, 0.0, 0.0))
    T_above = T_start.copy()
    T_above[:3, 3] -= 50.0 * T_start[:3, 2]
    T_end = torch_pose((100.0, 0.0, 0.0))
    T_after = T_end.copy()
    T_after[:3, 3] -= 50.0 * T_end[:3, 2]
    speed = schedule.travel_speed_mm_s
    moves = [
        ir.Move(ir.JOINT, _target("t1", None, T_above), 200.0, 10.0, "B",
                role=ir.ROLE_APPROACH, comment="approach"),
        ir.Move(ir.LINEAR, _target("t2", None, T_start), 50.0, 0.0, "B",
                role=ir.ROLE_ENTRY, comment="entry: seam start (arc on)"),
        ir.Move(ir.LINEAR, _target("t3", (50.0, 0.0, 0.0)), speed, 1.0, "B", segment=1,
                comment="segment 1: line Sketch.Edge1", weld="Weld"),
        ir.Move(ir.LINEAR, _target("t4", None, T_end), speed, 0.0, "B", segment=1,
                comment="segment 1: line Sketch.Edge1 (arc off)", weld="Weld"),
        ir.Move(ir.LINEAR, _target("t5", None, T_after), 200.0, 0.0, "B",
                role=ir.ROLE_RETRACT, comment="retract"),
    ]
    run = ir.WeldRun("Weld", "Fillet weld", schedule, weave, tracking, start=1, end=3,
                     first_segment=1, last_segment=1)
    path = ir.ProgramPath("Seam", "Fillet seam", moves, welds=[run])
    program = ir.Program("Fillet", robot, tool, frames, [path], source="fillet.FCStd / Cell")
    if solve:
        _solve(program)
    return program


def corner_stop_program(robot="ABB_IRB2400", weave=ZIGZAG_4MM, solve=False):
    """Two fillet legs at a right angle with a "Stop and reorient" corner: the
    weld is split into runs ``Weld`` (part 1, segment 1) and ``Weld_2`` (part 2,
    segment 2); the arc goes out at the corner, the torch turns in place, and
    the arc strikes again on the reorientation move's target. (The second leg is
    the first turned 90 degrees about Z of B: a fixture for the instructions,
    not a part whose plates meet at the corner.)

    Returns
    -------
    Program
        moves: approach, entry (0, 1), leg 1 (2), reorient (3, start of
        ``Weld_2``), leg 2 (4), retract (5).
    """
    program = woven_fillet_program(robot, weave=weave, solve=False)
    path = program.paths[0]
    speed = FILLET_T6.travel_speed_mm_s
    T_corner = torch_pose((100.0, 0.0, 0.0))
    turn = pose((0, 0, 90))   # the second leg runs along +Y of B, the torch turned with it
    T_corner2 = turn @ torch_pose((0.0, -100.0, 0.0))
    T_end2 = turn @ torch_pose((100.0, -100.0, 0.0))
    T_after = T_end2.copy()
    T_after[:3, 3] -= 50.0 * T_end2[:3, 2]
    path.moves = [
        path.moves[0], path.moves[1],
        ir.Move(ir.LINEAR, _target("t3", None, T_corner), speed, 0.0, "B", segment=1,
                comment="segment 1: line Sketch.Edge1", weld="Weld"),
        ir.Move(ir.LINEAR, _target("t4", None, T_corner2), speed, 0.0, "B",
                role=ir.ROLE_REORIENT, segment=2, comment="corner stop (arc off/on here)"),
        ir.Move(ir.LINEAR, _target("t5", None, T_end2), speed, 0.0, "B", segment=2,
                comment="segment 2: line Sketch.Edge2", weld="Weld_2"),
        ir.Move(ir.LINEAR, _target("t6", None, T_after), 200.0, 0.0, "B",
                role=ir.ROLE_RETRACT, comment="retract"),
    ]
    first = path.welds[0]
    path.welds = [
        ir.WeldRun("Weld", first.label, first.schedule, weave, first.tracking, start=1, end=2,
                   first_segment=1, last_segment=1, part=1),
        ir.WeldRun("Weld_2", first.label, first.schedule, weave, first.tracking, start=3,
                   end=4, first_segment=2, last_segment=2, part=2),
    ]
    if solve:
        _solve(program)
    return program


def _solve(program):
    from CadRobotWB.robots.kinematics import models
    from CadRobotWB.robots.motion import configuration
    configuration.solve_program(program, models.model(program.robot))
