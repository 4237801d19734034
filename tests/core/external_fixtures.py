"""Hand-built programs with external axes that the issue-23 tests share.

The cell, in the CAD frame {U} (Z up, gravity along -Z): the robot base at the
origin; a generic tilt-and-turn positioner (``catalog.build("tilt_turn")``:
tilt about the base's X at 800 mm, turn about the table's normal) with its
base at (1200, 0, 0); the part on its table. Work frame B sits on the table
centre, (1200, 0, 800) in {U} at tilt = turn = 0, and rides on the positioner.

The part: a pipe of radius 60 mm standing on a flange; the fillet between
them is a circle of radius 60 mm about B's Z, welded all round counter-
clockwise seen from above (4 circular moves of 90 degrees). The torch lies
on the joint's bisector: tool +Z (into the work) ``-(radial + Z_B)/sqrt(2)``.

External values by hand: at the seam point at angle ``phi`` (about Z_B, from
X_B), tilt = -45 deg and turn = -90 - phi deg bring the bisector to point
straight down (-Z_U): the seam is welded flat (PA). Approach and entry take
the first seam target's values, the retract the last one's.
With ``track=True`` the robot rides a generic track (base (0, 0, -250),
carriage at the robot base for travel 0); travel runs 0 -> 300 mm along the weld.
"""

import numpy as np

from CadRobotWB.core import mechanisms as mech
from CadRobotWB.core import program as ir
from CadRobotWB.core.mechanisms import ExternalAxes
from CadRobotWB.robots.mechanisms import catalog

from post_programs import pose
from weld_fixtures import FILLET_T6

RADIUS_MM = 60.0
TILT_DEG = -45.0
T_U_POSITIONER = pose((0, 0, 0), (1200.0, 0.0, 0.0))
T_U_B = pose((0, 0, 0), (1200.0, 0.0, 800.0))


def seam_pose(phi_deg):
    """4x4 torch pose in B at the seam point at angle `phi_deg`: X along the
    travel (counter-clockwise), Z on the bisector into the work."""
    phi = np.radians(phi_deg)
    radial = np.array([np.cos(phi), np.sin(phi), 0.0])
    x = np.array([-np.sin(phi), np.cos(phi), 0.0])
    z = -(radial + np.array([0.0, 0.0, 1.0])) / np.sqrt(2.0)
    T = np.eye(4)
    T[:3, :3] = np.column_stack([x, np.cross(z, x), z])
    T[:3, 3] = RADIUS_MM * radial
    return T


def flat_values(phi_deg):
    """(tilt, turn) in degrees welding the seam point at `phi_deg` flat."""
    return np.array([TILT_DEG, -90.0 - phi_deg])


def positioner_weld_program(robot="ABB_IRB2400", track=False, solve=False, arcs=4,
                            pose_at=seam_pose):
    """The pipe-to-flange weld all round on the positioner (see the module).

    `arcs` circular moves of ``360 / arcs`` degrees each weld the circle (4 by
    default; the benchmark takes 500: 1,000 seam targets with their vias).
    `pose_at(phi_deg)` gives the TCP pose in B at the circle's angle phi
    (default :func:`seam_pose`, the fillet's torch; test_force_external_axes
    gives a ball tool on the pipe's side).

    Returns
    -------
    Program
        moves: approach (joint), entry (arc on at phi = 0), 4 circular moves
        (via at phi = 45, 135, ...; targets at 90, 180, 270, 360), retract
        (with `arcs`: vias and targets every ``180 / arcs`` degrees).
        ``program.external``: the positioner (E1 tilt, E2 turn), or with
        `track` the track (E1 travel, mm) then the positioner (E2, E3).
    """
    positioner = catalog.build("tilt_turn", name="Positioner", T_u_base=T_U_POSITIONER)
    mechanism_track = (catalog.build("track", name="Track", T_u_base=pose((0, 0, 0),
                                                                        (0.0, 0.0, -250.0)))
                       if track else None)
    T_u_r = np.eye(4)
    external = ExternalAxes(T_u_r=T_u_r, track=mechanism_track, positioner=positioner,
                            moving_frames=("B",))
    tool = ir.ToolData("Torch", pose((0, 0, 0), (0.0, 0.0, 350.0)), mass_kg=3.0,
                       cog_mm=np.array([0.0, 0.0, 150.0]), label="Straight torch")
    frames = {"B": ir.WorkFrame("B", T_U_B.copy(), T_U_B.copy(), "CalibrationFrame")}

    def values(phi_deg):
        v = flat_values(phi_deg)
        if track:
            v = np.concatenate([[300.0 * phi_deg / 360.0], v])
        return v

    def target(name, phi_deg, back_off_mm=0.0):
        T = pose_at(phi_deg)
        T[:3, 3] -= back_off_mm * T[:3, 2]
        return ir.Target(name, T, external=values(phi_deg))

    speed = FILLET_T6.travel_speed_mm_s
    moves = [ir.Move(ir.JOINT, target("t1", 0.0, 50.0), 200.0, 10.0, "B",
                     role=ir.ROLE_APPROACH, comment="approach"),
             ir.Move(ir.LINEAR, target("t2", 0.0), 50.0, 0.0, "B", role=ir.ROLE_ENTRY,
                     comment="entry: seam start (arc on)")]
    step = 360.0 / arcs
    for k in range(arcs):
        end = step * (k + 1)
        moves.append(ir.Move(ir.CIRCULAR, target("t%d" % (k + 3), end), speed,
                             0.0 if k == arcs - 1 else 1.0, "B",
                             via=target("v%d" % (k + 3), end - step / 2),
                             segment=k + 1, comment="segment %d: arc Sketch.Edge%d" % (k + 1, k + 1),
                             weld="Weld"))
    moves.append(ir.Move(ir.LINEAR, target("t%d" % (arcs + 3), 360.0, 50.0), 200.0, 0.0, "B",
                         role=ir.ROLE_RETRACT, comment="retract"))
    run = ir.WeldRun("Weld", "Pipe to flange", FILLET_T6, None, start=1, end=arcs + 1,
                     first_segment=1, last_segment=arcs)
    path = ir.ProgramPath("Seam", "Pipe seam", moves, welds=[run])
    program = ir.Program("PipeFlange", robot, tool, frames, [path],
                         source="pipe_flange.FCStd / Cell", external=external)
    if solve:
        from CadRobotWB.robots.kinematics import models
        from CadRobotWB.robots.motion import configuration
        configuration.solve_program(program, models.model(program.robot))
    return program


def check_corrected_targets(program, fitted, angles_deg):
    """Assert that the corrected `program` turns the part as its run did: each fitted
    move's end (``fitted.moves[k].end``, a run sample) carries the flat values of that
    sample's angle in `angles_deg` (one per run sample, deg), and the robot reaches
    every target of `program` with the part turned there."""
    from CadRobotWB.robots.kinematics import models
    from CadRobotWB.robots.motion import configuration
    ends = [m.end for m in fitted.moves]
    path_moves = program.moves()[2:2 + len(ends)]
    np.testing.assert_allclose([m.target.external for m in path_moves],
                               [flat_values(a) for a in np.asarray(angles_deg)[ends]], atol=1e-6)
    solution = configuration.solve_program(program, models.model(program.robot))
    assert all(e.status == "ok" for e in solution.entries), \
        [(e.target.name, e.status) for e in solution.entries if e.status != "ok"]


def track_program(x_mm, y_mm=800.0, speed_mm_s=7.5, track_limits=(1000.0, 2000.0),
                  travel_mm=3000.0, R_tcp=None):
    """A weld along +X at y = `y_mm` (a scalar, or one per point), z = 400 mm in {U} = {B},
    the torch at `R_tcp` (3, 3) (default straight down), at `speed_mm_s` (zone 1 mm, the
    last 0), the robot (at the origin at travel 0) on a hand-built track moving it along +X
    over 0..`travel_mm` mm at `track_limits` (mm/s, mm/s^2)."""
    axis = mech.Axis("travel", mech.LINEAR, pose((0, 90, 0)), 0.0, travel_mm, *track_limits)
    track = mech.Mechanism("Track", "Track", mech.TRACK, "", [axis], T_last_flange=pose((0, -90, 0)))
    down = np.diag([1.0, -1.0, -1.0]) if R_tcp is None else R_tcp
    ys = np.broadcast_to(np.asarray(y_mm, dtype=float), np.shape(x_mm))

    def target(name, k, up=0.0):
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = down, (x_mm[k], ys[k], 400.0 + up)
        return ir.Target(name, T)

    moves = [ir.Move(ir.JOINT, target("a", 0, 50.0), 200.0, 10.0, "B", role=ir.ROLE_APPROACH),
             ir.Move(ir.LINEAR, target("s0", 0), 50.0, 0.0, "B", role=ir.ROLE_ENTRY)]
    last = len(x_mm) - 1          # the arc ends at a fine point, as core.generate ends a run
    moves += [ir.Move(ir.LINEAR, target("s%d" % k, k), speed_mm_s, 0.0 if k == last else 1.0,
                      "B", segment=k, weld="W") for k in range(1, len(x_mm))]
    moves.append(ir.Move(ir.LINEAR, target("r", last, 50.0), 200.0, 0.0, "B",
                         role=ir.ROLE_RETRACT))
    run = ir.WeldRun("W", "Long seam", FILLET_T6, None, start=1, end=len(x_mm),
                     first_segment=1, last_segment=len(x_mm) - 1)
    tool = ir.ToolData("Torch", pose((0, 0, 0), (0.0, 0.0, 350.0)), mass_kg=3.0)
    frames = {"B": ir.WorkFrame("B", np.eye(4), np.eye(4))}
    external = ExternalAxes(T_u_r=np.eye(4), track=track)
    return ir.Program("Long", "ABB_IRB2400", tool, frames,
                      [ir.ProgramPath("P", "P", moves, welds=[run])], external=external)
