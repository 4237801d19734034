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
