"""A pipe welded to a flange all round, flat, on a tilt-and-turn positioner (issue 23).

The part: a DN 100 pipe (EN 10220 / ASME B36.10 schedule 40: outside diameter
114.3 mm, wall 6.02 mm), 150 mm long, standing on a 250 mm flange plate 20 mm
thick. The fillet at the pipe's foot is a circle of 360 mm (radius 57.15 mm).

Standing on the table, that fillet is horizontal-vertical (PB) everywhere: the
torch's bisector points 45 degrees below the horizontal all round, whatever
the robot does. On a tilt-and-turn positioner the chooser tilts the part 45
degrees and turns it under the torch, so every point of the seam is welded
flat (PA): the bisector points straight down.

The cell in {U} (Z up): the robot base at the origin facing +X; the
positioner's base at ``POSITIONER_AT_MM``; the part on its flange as the
document shows it (``ShowAt``: every axis at 0). The positioner carries the
flange plate and the pipe, and with them the calibration frame on the flange's
top and the tool markers (``api.add_positioner`` adds them).

Run in FreeCAD's Python console or with ``freecadcmd``::

    import pipe_flange_cell
    cell = pipe_flange_cell.build(FreeCAD.newDocument("PipeFlange"))

:func:`build_polishing` builds the same pipe on the positioner polished all round by a
ball tool under force control (``cadrobot simulate --sensor force``).
"""

import numpy as np

import FreeCAD
import Part

from CadRobotWB import api

V = FreeCAD.Vector

#: DN 100 schedule 40 pipe (EN 10220 / ASME B36.10M): outside radius, wall, length, mm.
PIPE_RADIUS_MM, PIPE_WALL_MM, PIPE_LENGTH_MM = 114.3 / 2.0, 6.02, 150.0
#: The flange plate: radius and thickness, mm.
FLANGE_RADIUS_MM, FLANGE_THICKNESS_MM = 125.0, 20.0
#: The positioner's base in {U}, mm.
POSITIONER_AT_MM = (1200.0, 0.0, 0.0)
#: Catalog model of the positioner (`cadrobot mechanisms`; None: the generic tilt-and-turn
#: one, turn +-3600 deg).
POSITIONER_MODEL = "YASKAWA_MOTOPOS_D500"
#: How far the part stands turned on the table, counter-clockwise seen from above, deg:
#: where the seam (the circle's start, at +X before the turn) begins. The weld all round
#: needs 360 deg of the D500's 400 deg of turn (counted clockwise, as Yaskawa does); from
#: the circle's start at +X it would run from -90 to +270 deg, and Check says "turn the
#: part on the positioner's table by -90 deg (counter-clockwise seen from above the
#: table)": then it runs from -180 to +180 deg.
PART_TURN_DEG = -90.0
ROBOT = "ABB_IRB2400"
#: The library's fillet row for the 6.02 mm pipe wall, the row the joint reader picks too
#: (it measured both walls, 12.04 mm, and picked fillet_t12 before it stopped at the bore).
SCHEDULE = "fillet_t6"


def positioner_placement():
    """The positioner's base in {U}: at POSITIONER_AT_MM, axes along {U}'s."""
    return FreeCAD.Placement(V(*POSITIONER_AT_MM), FreeCAD.Rotation())


def table_centre():
    """The positioner's flange (its table's centre) in {U} at its drawn values, mm (3,)."""
    from CadRobotWB.objects.convert import matrix_from_placement
    from CadRobotWB.robots.mechanisms import catalog
    mechanism = catalog.build("tilt_turn", POSITIONER_MODEL,
                              T_u_base=matrix_from_placement(positioner_placement()))
    return mechanism.T_u_p(mechanism.drawn_at)[:3, 3]


def build_part(doc, centre):
    """The flange plate and the pipe standing on it, the plate's underside centred at
    `centre` ({U}, mm), turned by PART_TURN_DEG about the vertical; returns (flange, pipe)."""
    x, y, z = (float(c) for c in centre)
    flange = doc.addObject("Part::Feature", "Flange")
    flange.Shape = Part.makeCylinder(FLANGE_RADIUS_MM, FLANGE_THICKNESS_MM, V(x, y, z))
    z_top = z + FLANGE_THICKNESS_MM
    outer = Part.makeCylinder(PIPE_RADIUS_MM, PIPE_LENGTH_MM, V(x, y, z_top))
    inner = Part.makeCylinder(PIPE_RADIUS_MM - PIPE_WALL_MM, PIPE_LENGTH_MM, V(x, y, z_top))
    pipe = doc.addObject("Part::Feature", "Pipe")
    pipe.Shape = outer.cut(inner)
    turned = FreeCAD.Placement(V(), FreeCAD.Rotation(V(0, 0, 1), PART_TURN_DEG), V(x, y, z))
    for solid in (flange, pipe):
        solid.Placement = turned.multiply(solid.Placement)
    doc.recompute()
    return flange, pipe


def foot_edge(pipe, z_foot):
    """Name of the pipe's outer circle at its foot (``"EdgeN"``): the fillet's root."""
    for k, edge in enumerate(pipe.Shape.Edges, start=1):
        box = edge.BoundBox
        if abs(box.ZMin - z_foot) < 1e-6 and abs(box.ZMax - z_foot) < 1e-6 \
                and abs(box.XLength - 2 * PIPE_RADIUS_MM) < 1e-6:
            return "Edge%d" % k
    raise RuntimeError("the pipe has no outer circle at z = %g mm" % z_foot)


def build(doc, positioner=True):
    """Build the cell in `doc` and return it.

    The part on the positioner's table, the robot at the origin, a calibration
    frame on the flange's top at the pipe's axis, the path round the pipe's
    foot, its tool markers from the faces, the weld (the library's fillet
    schedule for the 6 mm wall) and, with `positioner`, the tilt-and-turn
    positioner carrying all of it (False: the same part and weld on a fixed
    table, welded horizontal-vertical).
    """
    centre = table_centre()
    flange, pipe = build_part(doc, centre)
    cell = api.make_cell(doc, robot=ROBOT, name="PipeCell", placement=FreeCAD.Placement())
    z_foot = float(centre[2]) + FLANGE_THICKNESS_MM
    api.make_calibration_frame(
        doc, cell, FreeCAD.Placement(V(float(centre[0]), float(centre[1]), z_foot),
                                     FreeCAD.Rotation()), name="FlangeFrame")
    path = api.make_path(doc, cell, (pipe, foot_edge(pipe, z_foot)), name="PipeSeam")
    api.make_tool_markers_auto(doc, cell, path)
    api.make_weld(doc, cell, path, schedule=SCHEDULE, name="PipeWeld")
    if positioner:
        api.add_positioner(cell, kind="tilt_turn", placement=positioner_placement(),
                           parts=[flange, pipe], model=POSITIONER_MODEL)
    doc.recompute()
    return cell


#: The polishing ring (:func:`build_polishing`): its height above the flange plate, mm, and
#: the ball's speed round it, mm/s.
RING_HEIGHT_MM, POLISH_SPEED_MM_S = 130.0, 20.0
#: Where the ring starts, turned counter-clockwise seen from above, deg. A path without a
#: weld keeps the tool as near straight down as it goes: the table tilts to -90 deg and
#: turns each point of the ring to the top. Started where PART_TURN_DEG puts the seam,
#: the turn would run from 0 to +360 deg; Check says to turn the part by -180 deg: then
#: it runs from -180 to +180 deg.
RING_TURN_DEG = PART_TURN_DEG - 180.0


def build_polishing(doc):
    """The same pipe on the positioner, polished all round under force control: a ball
    tool follows the circle on the pipe's outside RING_HEIGHT_MM above the flange plate
    while the positioner turns the pipe under it (force following suits a surface: the
    fillet of :func:`build` is a seam for the laser or the arc). Returns the cell."""
    centre = table_centre()
    flange, pipe = build_part(doc, centre)
    x, y, z = (float(c) for c in centre)
    z_plate = z + FLANGE_THICKNESS_MM
    ring = doc.addObject("Part::Feature", "PolishRing")
    ring.Shape = Part.makeCircle(PIPE_RADIUS_MM, V(x, y, z_plate + RING_HEIGHT_MM))
    ring.Placement = FreeCAD.Placement(V(), FreeCAD.Rotation(V(0, 0, 1), RING_TURN_DEG), V(x, y, z))
    cell = api.make_cell(doc, robot=ROBOT, name="PolishCell", placement=FreeCAD.Placement(),
                         tool="Ball tool")
    cell.Workpiece = [pipe]
    api.make_calibration_frame(doc, cell, FreeCAD.Placement(V(x, y, z_plate), FreeCAD.Rotation()),
                               name="FlangeFrame")
    path = api.make_path(doc, cell, (ring, "Edge1"), speed_mm_s=POLISH_SPEED_MM_S, name="PipePolish")
    api.make_tool_markers_auto(doc, cell, path, travel_angle_deg=0.0, shape="Ball")
    api.add_positioner(cell, kind="tilt_turn", placement=positioner_placement(),
                       parts=[flange, pipe, ring], model=POSITIONER_MODEL)
    doc.recompute()
    return cell


def gravity_angles_deg(program):
    """The gravity angle of every welded target of `program`, deg (issue 23's plan, section 1):
    ``choose.gravity_angles`` (NaN where not welded) without the NaNs."""
    from CadRobotWB.robots.mechanisms import choose
    angles = np.asarray(choose.gravity_angles(program), dtype=float)
    return angles[np.isfinite(angles)]
