"""Small builders shared by the App-tier tests."""

import FreeCAD
import numpy as np
import Part

from CadRobotWB import api

V = FreeCAD.Vector


def sketch_of(doc, geometries, placement=None, name="Sketch", container=None):
    """A sketch holding `geometries` (Part geometry in sketch coordinates)."""
    sketch = doc.addObject("Sketcher::SketchObject", name)
    if container is not None:
        container.addObject(sketch)
    if placement is not None:
        sketch.Placement = placement
    for geometry in geometries:
        sketch.addGeometry(geometry, False)
    doc.recompute()
    return sketch


def polyline(points):
    """Line segments through `points` (list of (x, y[, z]))."""
    vectors = [V(*(tuple(p) + (0,) * (3 - len(p)))) for p in points]
    return [Part.LineSegment(a, b) for a, b in zip(vectors[:-1], vectors[1:])]


def down_placement(point, travel=(1, 0, 0)):
    """A TCP placement at `point` pointing straight down (-Z of {U})."""
    return api.tool_placement(V(*point), V(*travel), V(0, 0, 1), 90.0, 0.0)


def simple_cell(doc, sketch, frame_at=(0, 0, 0), markers=None, robot="ABB_IRB2400"):
    """A cell with one frame, a path on `sketch` and one down-pointing marker
    at each given point. The robot stands 900 mm behind and 600 mm below the
    origin, so paths drawn near the origin are in its reach."""
    cell = api.make_cell(doc, robot=robot)
    cell.Placement = FreeCAD.Placement(V(-900, 0, -600), FreeCAD.Rotation())
    api.make_calibration_frame(doc, cell, FreeCAD.Placement(V(*frame_at), FreeCAD.Rotation()))
    path = api.make_path(doc, cell, sketch)
    for point in markers or []:
        api.make_tool_marker(doc, cell, down_placement(point))
    return cell, path


def target_positions(program):
    return np.array([m.target.position_mm for m in program.moves()])


#: The T joint of :func:`fillet_cell`: the web's thickness and the root's height, mm.
WEB_MM = 6.0
ROOT_Z_MM = 8.0


def fillet_cell(doc):
    """A T joint: a WEB_MM web standing on an 8 mm base plate; the path "Root" runs
    along the root (y 0, z 8) from x 50 to 250 in two 100 mm segments, the torch at
    45 degrees into the corner. Returns (cell, path, web)."""
    base = doc.addObject("Part::Box", "Base")
    base.Length, base.Width, base.Height = 300, 200, ROOT_Z_MM
    base.Placement.Base = V(0, -100, 0)
    web = doc.addObject("Part::Box", "Web")
    web.Length, web.Width, web.Height = 300, WEB_MM, 100
    web.Placement.Base = V(0, -WEB_MM, ROOT_Z_MM)
    root = sketch_of(doc, polyline([(50, 0), (150, 0), (250, 0)]),
                     FreeCAD.Placement(V(0, 0, ROOT_Z_MM), FreeCAD.Rotation()), name="RootSketch")
    cell = api.make_cell(doc, robot="ABB_IRB2400", name="FilletCell",
                         placement=FreeCAD.Placement(V(-700, 300, -400), FreeCAD.Rotation()))
    cell.ToolTCP = FreeCAD.Placement(V(0, 0, 300), FreeCAD.Rotation())
    api.make_calibration_frame(doc, cell, FreeCAD.Placement())
    path = api.make_path(doc, cell, root, speed_mm_s=10.0, name="Root")
    into_corner = V(0, 1, 1).normalize()
    api.make_tool_marker(doc, cell, api.tool_placement(V(100, 0, ROOT_Z_MM), V(1, 0, 0), into_corner,
                                                       90.0, 0.0))
    doc.recompute()
    return cell, path, web
