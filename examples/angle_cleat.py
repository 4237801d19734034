"""An angle cleat standing on a plate: the fillet weld all round it (issue 20).

The part is a hot-rolled equal angle L100x100x10 (EN 10056-1: legs 100 mm,
thickness 10 mm, root radius r1 = 12 mm, toe radius r2 = 6 mm), cut 50 mm long
and standing on its end on a 300 x 250 x 10 mm base plate. The fillet weld
runs all round the cleat's foot: 9 edges (4 lines of the outer and end faces,
2 inner legs, 2 toe arcs, the root arc), 389.7 mm in all, with a convex heel,
two convex leg ends and a concave root.

Plate: x 0..300, y 0..250, z 0..10 mm in the document frame {U}. The cleat's
heel stands at (HEEL_X_MM, HEEL_Y_MM) on the plate's top face, legs along +x and
+y. ``cleat_on_plate`` builds it in a document; ``foot_loop_edges`` names the
cleat's edges on the plate, in the order they join.
"""

import math

import FreeCAD
import Part

#: EN 10056-1 equal angle L100x100x10, mm.
LEG_MM, THICKNESS_MM, ROOT_RADIUS_MM, TOE_RADIUS_MM = 100.0, 10.0, 12.0, 6.0
#: Length cut from the bar: the cleat's height standing on the plate, mm.
HEIGHT_MM = 50.0
#: Base plate, mm.
PLATE_MM = (300.0, 250.0, 10.0)
#: Where the cleat's heel (outer corner) stands on the plate, mm.
HEEL_X_MM, HEEL_Y_MM = 100.0, 75.0
#: Length of the weld all round the foot, mm (4 straight ends + 2 toes + 2 inner legs + root).
SEAM_LENGTH_MM = (2 * LEG_MM + 2 * (THICKNESS_MM - TOE_RADIUS_MM)
                  + 2 * (LEG_MM - THICKNESS_MM - ROOT_RADIUS_MM - TOE_RADIUS_MM)
                  + math.pi / 2 * (ROOT_RADIUS_MM + 2 * TOE_RADIUS_MM))


def angle_profile(z_mm=0.0):
    """The L100x100x10 section as a closed wire in the plane z = `z_mm`, heel at the origin.

    Counter-clockwise seen from +z: heel, leg along +x, its end, toe arc, inner
    leg, root arc, inner leg, toe arc, end, leg along +y back to the heel.
    """
    a, t, r1, r2 = LEG_MM, THICKNESS_MM, ROOT_RADIUS_MM, TOE_RADIUS_MM

    def v(x, y):
        return FreeCAD.Vector(x, y, z_mm)

    def arc(centre, radius, start_deg, end_deg):
        mid = math.radians((start_deg + end_deg) / 2)
        s, e = math.radians(start_deg), math.radians(end_deg)
        return Part.Arc(v(centre[0] + radius * math.cos(s), centre[1] + radius * math.sin(s)),
                        v(centre[0] + radius * math.cos(mid), centre[1] + radius * math.sin(mid)),
                        v(centre[0] + radius * math.cos(e), centre[1] + radius * math.sin(e))
                        ).toShape()

    edges = [
        Part.makeLine(v(0, 0), v(a, 0)),                       # outer face of the x leg
        Part.makeLine(v(a, 0), v(a, t - r2)),                   # end of the x leg
        arc((a - r2, t - r2), r2, 0, 90),                       # toe of the x leg
        Part.makeLine(v(a - r2, t), v(t + r1, t)),              # inner face of the x leg
        arc((t + r1, t + r1), r1, 270, 180),                    # root (concave, clockwise)
        Part.makeLine(v(t, t + r1), v(t, a - r2)),              # inner face of the y leg
        arc((t - r2, a - r2), r2, 0, 90),                       # toe of the y leg
        Part.makeLine(v(t - r2, a), v(0, a)),                   # end of the y leg
        Part.makeLine(v(0, a), v(0, 0)),                        # outer face of the y leg
    ]
    return Part.Wire(edges)


def cleat_on_plate(doc, cleat_name="AngleCleat", plate_name="BasePlate"):
    """Add the base plate and the cleat standing on it to `doc`; returns (cleat, plate)."""
    length, width, thickness = PLATE_MM
    plate = doc.addObject("Part::Feature", plate_name)
    plate.Shape = Part.makeBox(length, width, thickness)
    profile = angle_profile(thickness)
    profile.translate(FreeCAD.Vector(HEEL_X_MM, HEEL_Y_MM, 0))
    cleat = doc.addObject("Part::Feature", cleat_name)
    cleat.Shape = Part.Face(profile).extrude(FreeCAD.Vector(0, 0, HEIGHT_MM))
    doc.recompute()
    return cleat, plate


def foot_face_name(cleat):
    """Name (``"FaceN"``) of the cleat's face standing on the plate (its lowest planar face)."""
    faces = cleat.Shape.Faces
    z_plate = PLATE_MM[2]
    for k, face in enumerate(faces, 1):
        box = face.BoundBox
        if abs(box.ZMin - z_plate) < 1e-6 and abs(box.ZMax - z_plate) < 1e-6:
            return "Face%d" % k
    raise ValueError("%s has no face on the plate (z = %g mm)" % (cleat.Label, z_plate))


def foot_loop_edges(cleat):
    """Edge names of the cleat's foot on the plate, in the order they join: the fillet seam."""
    from CadRobotWB.objects.picking import outer_edge_names
    return outer_edge_names(cleat, foot_face_name(cleat))
