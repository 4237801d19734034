"""A straight fillet weld on a T-joint: the cell where laser and through-arc
tracking are compared (issue 22).

A 10 mm web plate stands on a 10 mm base plate; the fillet along the web's
foot, on its front side, is 250 mm long. Everything else is the defaults a new
user gets: the robot beside the part, the default torch, a calibration frame
on the base plate's corner, tool markers from the faces (on the fillet's
bisector, the cell's GMAW angles).

Run in FreeCAD's Python console or with ``freecadcmd``::

    import tee_joint_cell
    cell = tee_joint_cell.build(FreeCAD.newDocument("TeeJoint"))
"""

import FreeCAD
import Part

from CadRobotWB import api

V = FreeCAD.Vector

BASE_MM = (400.0, 250.0, 10.0)
WEB_MM = (250.0, 10.0, 120.0)
#: The web's front face stands at y = WEB_Y_MM on the base plate; the fillet runs along x.
WEB_X_MM, WEB_Y_MM = 75.0, 150.0


def build_drawing(doc):
    """The two plates; returns (base, web)."""
    base = doc.addObject("Part::Box", "BasePlate")
    base.Length, base.Width, base.Height = BASE_MM
    web = doc.addObject("Part::Box", "WebPlate")
    web.Length, web.Width, web.Height = WEB_MM
    web.Placement.Base = V(WEB_X_MM, WEB_Y_MM, BASE_MM[2])
    doc.recompute()
    return base, web


def root_edge(web):
    """Name of the web's bottom edge on its front face (the fillet's root)."""
    for i, edge in enumerate(web.Shape.Edges, start=1):
        a, b = (v.Point for v in edge.Vertexes)
        if abs(a.y - WEB_Y_MM) < 1e-6 and abs(b.y - WEB_Y_MM) < 1e-6 \
                and abs(a.z - BASE_MM[2]) < 1e-6 and abs(b.z - BASE_MM[2]) < 1e-6:
            return "Edge%d" % i
    raise RuntimeError("the web plate has no front bottom edge")


def build(doc, robot="ABB_IRB2400"):
    """Build the cell in `doc`: the part, the cell with the defaults, a frame
    on the base plate's corner, the path along the root and its tool markers.
    Returns the cell."""
    base, web = build_drawing(doc)
    cell = api.make_cell(doc, robot=robot, name="TeeCell")
    api.make_calibration_frame(doc, cell, FreeCAD.Placement(V(0, 0, BASE_MM[2]),
                                                            FreeCAD.Rotation()), name="PlateFrame")
    path = api.make_path(doc, cell, (web, root_edge(web)), name="Fillet")
    api.make_tool_markers_auto(doc, cell, path)
    doc.recompute()
    return cell
