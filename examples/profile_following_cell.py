"""The paper's profile-following cell (Neto et al. 2012, section 4.2, Figure 13).

A Motoman HP6 with a 10 mm ball tool on a force/torque sensor follows the
curved top of a workpiece while holding a constant contact force. The top
is an arc of radius 600 mm over a 300 mm span, drawn as a sketch on the
workpiece's middle plane, so the program is one circular move. The tool
stays vertical; the surface tilts at most 14.5° under it, and the ball's
contact shifts by less than 0.2 mm because of it.

    import profile_following_cell
    cell = profile_following_cell.build(FreeCAD.newDocument("ProfileFollowing"))
"""

import math

import FreeCAD
import Part

from CadRobotWB import api

V = FreeCAD.Vector

SPAN_MM = 300.0
RADIUS_MM = 600.0
DEPTH_MM = 100.0
BASE_HEIGHT_MM = 40.0
BALL_DIAMETER_MM = 10.0
BALL_TCP_MM = (0.0, 0.0, 180.0)   # ball's lowest point, from the flange
SPEED_MM_S = 20.0


def _sagitta():
    return RADIUS_MM - math.sqrt(RADIUS_MM ** 2 - (SPAN_MM / 2) ** 2)


def _profile_solid():
    """The workpiece in its own frame: x along the span, the arc's top at z = base + sagitta."""
    h, top = BASE_HEIGHT_MM, BASE_HEIGHT_MM + _sagitta()
    arc = Part.Arc(V(0, 0, h), V(SPAN_MM / 2, 0, top), V(SPAN_MM, 0, h))
    edges = [Part.makeLine(V(0, 0, 0), V(SPAN_MM, 0, 0)), Part.makeLine(V(SPAN_MM, 0, 0), V(SPAN_MM, 0, h)),
             arc.toShape(), Part.makeLine(V(0, 0, h), V(0, 0, 0))]
    face = Part.Face(Part.Wire(Part.__sortEdges__(edges)))
    return face.extrude(V(0, DEPTH_MM, 0))


def build(doc):
    """Build the cell in `doc` and return the CadRobot cell object."""
    fixture = doc.addObject("App::Part", "Fixture")
    fixture.Placement = FreeCAD.Placement(V(550, -DEPTH_MM / 2, 300), FreeCAD.Rotation())
    table = doc.addObject("Part::Box", "Stand")
    table.Length, table.Width, table.Height = SPAN_MM + 100, DEPTH_MM + 100, 300
    table.Placement.Base = V(-50, -50, -300)
    profile = doc.addObject("Part::Feature", "Profile")
    profile.Shape = _profile_solid()
    sketch = doc.addObject("Sketcher::SketchObject", "ProfileLine")
    # The sketch plane is the workpiece's middle plane (XZ at y = depth / 2).
    sketch.Placement = FreeCAD.Placement(V(0, DEPTH_MM / 2, 0), FreeCAD.Rotation(V(1, 0, 0), 90))
    top = BASE_HEIGHT_MM + _sagitta()
    sketch.addGeometry(Part.ArcOfCircle(Part.Circle(V(SPAN_MM / 2, top - RADIUS_MM, 0), V(0, 0, 1),
                                                    RADIUS_MM),
                                        math.pi / 2 - math.asin(SPAN_MM / 2 / RADIUS_MM),
                                        math.pi / 2 + math.asin(SPAN_MM / 2 / RADIUS_MM)), False)
    for obj in (table, profile, sketch):
        fixture.addObject(obj)
    doc.recompute()

    # The paper's cell: the robot stands at the origin and the fixture was placed for it.
    cell = api.make_cell(doc, robot="MOTOMAN_HP6", name="ProfileCell", tool="Ball tool",
                         placement=FreeCAD.Placement())
    cell.ProgramName = "PROFILE"
    cell.ToolName = "BallTool"
    cell.ToolTCP = FreeCAD.Placement(V(*BALL_TCP_MM), FreeCAD.Rotation())
    cell.ToolMass = 1.2
    cell.ToolCenterOfGravity = V(0, 0, 60)
    cell.SampleTime = 0.05   # the paper's 20 Hz force loop
    cell.Workpiece = [profile]
    corner = fixture.Placement.multiply(FreeCAD.Placement(V(0, 0, 0), FreeCAD.Rotation()))
    api.make_calibration_frame(doc, cell, corner, name="FixtureFrame")
    path = api.make_path(doc, cell, sketch, speed_mm_s=SPEED_MM_S, name="Profile")
    path.ApproachDistance = 30
    path.RetractDistance = 30
    summit = fixture.Placement.multVec(V(SPAN_MM / 2, DEPTH_MM / 2, top))
    down = api.tool_placement(summit, V(1, 0, 0), V(0, 0, 1), 90.0, 0.0)
    marker = api.make_tool_marker(doc, cell, down, name="Ball", shape="Ball")
    marker.ToolDiameter = BALL_DIAMETER_MM
    doc.recompute()
    return cell
