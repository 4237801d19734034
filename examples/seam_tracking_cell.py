"""The paper's seam-tracking cell (Neto et al. 2012, section 4.1, Figure 9).

Two 8 mm plates meet in an L-shaped butt joint with a 1.5 mm root gap on a
table; an ABB IRB 2400 welds the seam at 10 mm/s. The table, plates and the seam sketch sit in an
App::Part turned 10° on the floor, so every placement is nested. The torch
is square to the plates (work angle 90°) and pushes 10° forward; it turns
90° at the corner, the one abrupt orientation change, which a risk area
over the two short segments around the corner smooths (eqs 8-15).

Run in FreeCAD's Python console or with ``freecadcmd``::

    import seam_tracking_cell
    cell = seam_tracking_cell.build(FreeCAD.newDocument("SeamTracking"))
"""

import FreeCAD
import Part
import Sketcher

from CadRobotWB import api

V = FreeCAD.Vector

TABLE_SIZE_MM = (600.0, 500.0, 600.0)
PLATE_MM = 8.0
ROOT_GAP_MM = 1.5
# Seam corners in the fixture frame (table corner, floor level); the seam lies on the plates' top.
SEAM_XY_MM = ((100, 150), (300, 150), (320, 150), (320, 170), (320, 350))
TORCH_TCP_MM = (0.0, 0.0, 350.0)
WORK_ANGLE_DEG = 90.0
TRAVEL_ANGLE_DEG = 10.0


def _plates(doc, fixture, top):
    """The plates either side of the seam, half the root gap away from it."""
    g = ROOT_GAP_MM / 2.0
    inner = doc.addObject("Part::Box", "PlateA")
    inner.Length, inner.Width, inner.Height = 220 - g, 200 - g, PLATE_MM
    inner.Placement.Base = V(100, 150 + g, top)
    outline = [V(x, y, top) for x, y in ((100, 50), (420, 50), (420, 350), (320 + g, 350),
                                         (320 + g, 150 - g), (100, 150 - g), (100, 50))]
    outer = doc.addObject("Part::Feature", "PlateB")
    outer.Shape = Part.Face(Part.makePolygon(outline)).extrude(V(0, 0, PLATE_MM))
    fixture.addObject(inner)
    fixture.addObject(outer)


def _seam_sketch(doc, fixture, z):
    sketch = doc.addObject("Sketcher::SketchObject", "WeldSeam")
    fixture.addObject(sketch)
    sketch.Placement = FreeCAD.Placement(V(0, 0, z), FreeCAD.Rotation())
    points = [V(x, y, 0) for x, y in SEAM_XY_MM]
    for i in range(len(points) - 1):
        sketch.addGeometry(Part.LineSegment(points[i], points[i + 1]), False)
        if i:
            sketch.addConstraint(Sketcher.Constraint("Coincident", i - 1, 2, i, 1))
    return sketch


def build_drawing(doc):
    """The CAD drawing only (table, plates, seam sketch in an App::Part).

    Returns
    -------
    (App::Part, Sketcher::SketchObject)
        The fixture and the seam sketch.
    """
    fixture = doc.addObject("App::Part", "Fixture")
    fixture.Placement = FreeCAD.Placement(V(700, -250, 0), FreeCAD.Rotation(V(0, 0, 1), 10))
    table = doc.addObject("Part::Box", "Table")
    table.Length, table.Width, table.Height = TABLE_SIZE_MM
    fixture.addObject(table)
    top = TABLE_SIZE_MM[2]
    _plates(doc, fixture, top)
    sketch = _seam_sketch(doc, fixture, top + PLATE_MM)
    doc.recompute()
    return fixture, sketch


def setup_tool(cell):
    """The torch and program settings of the paper's cell (property editor values)."""
    cell.ProgramName = "SeamWeld"
    cell.ToolName = "tTorch"
    cell.ToolTCP = FreeCAD.Placement(V(*TORCH_TCP_MM), FreeCAD.Rotation())
    cell.ToolMass = 2.5
    cell.ToolCenterOfGravity = V(0, 0, 120)
    cell.SampleTime = 0.5


def build(doc, robot="ABB_IRB2400"):
    """Build the cell in `doc` and return the CadRobot cell object (the paper's
    robot, or any other of the catalog that reaches the seam)."""
    fixture, sketch = build_drawing(doc)
    top = TABLE_SIZE_MM[2]

    # The paper's cell: the robot stands at the origin and the table was placed for it.
    cell = api.make_cell(doc, robot=robot, name="SeamCell", placement=FreeCAD.Placement())
    setup_tool(cell)

    # {B} at the table's top corner, axes along the table edges.
    corner = fixture.Placement.multiply(FreeCAD.Placement(V(0, 0, top), FreeCAD.Rotation()))
    api.make_calibration_frame(doc, cell, corner, name="TableFrame")

    path = api.make_path(doc, cell, sketch, speed_mm_s=10.0, name="Seam")
    up = fixture.Placement.Rotation.multVec(V(0, 0, 1))
    z = top + PLATE_MM
    for k in range(len(SEAM_XY_MM) - 1):
        (x0, y0), (x1, y1) = SEAM_XY_MM[k], SEAM_XY_MM[k + 1]
        middle = fixture.Placement.multVec(V((x0 + x1) / 2.0, (y0 + y1) / 2.0, z))
        travel = fixture.Placement.Rotation.multVec(V(x1 - x0, y1 - y0, 0))
        placement = api.tool_placement(middle, travel, up, WORK_ANGLE_DEG, TRAVEL_ANGLE_DEG)
        api.make_tool_marker(doc, cell, placement, name="Torch%d" % (k + 1))

    api.make_risk_area(doc, cell, path, 2, 3, name="Corner")
    doc.recompute()
    return cell
