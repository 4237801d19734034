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
import re

import numpy as np

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


# --------------------------------------------------------------------------
# The torch against the fillet, read back from a written RAPID module
# --------------------------------------------------------------------------
ROBTARGET = r"robtarget\s+(\w+)\s*:=\s*\[\[([^\]]*)\],\s*\[([^\]]*)\]"


def rapid_targets(module_text):
    """[(name, p_b (3,) mm, R_b_t (3, 3))] of every robtarget declared in a RAPID module,
    in the order declared (positions and quaternions in the target's work object)."""
    out = []
    for name, pos, quat in re.findall(ROBTARGET, module_text):
        w, x, y, z = (float(v) for v in quat.split(","))
        R = FreeCAD.Rotation(x, y, z, w).toMatrix()
        out.append((name, np.array([float(v) for v in pos.split(",")]),
                    np.array([[R.A11, R.A12, R.A13], [R.A21, R.A22, R.A23], [R.A31, R.A32, R.A33]])))
    return out


def torch_against_fillet(cleat, targets, T_u_b, corner_radius_mm=6.0):
    """The torch of each target against the fillet between the plate and `cleat`.

    Parameters
    ----------
    cleat : the cleat's document object (its side faces stand on the plate's top face).
    targets : list of (name, p_b (3,), R_b_t (3, 3)), in program order (:func:`rapid_targets`).
    T_u_b : ndarray (4, 4), the targets' work frame in the document, mm.
    corner_radius_mm : float
        Targets closer than this to a sharp corner of the foot loop are "corner" targets.

    Returns
    -------
    list of dict
        Per target on the seam (within 0.05 mm of the foot loop): ``name``, ``edge``
        (the nearest foot edge), ``corner`` (bool), ``work_off_deg`` (angle between the
        torch axis, seen along the travel, and the fillet bisector), ``travel_deg``
        (tilt of the torch axis towards the travel: positive pushing).
    """
    foot = [cleat.Shape.getElement(name) for name in foot_loop_edges(cleat)]
    z_plate = PLATE_MM[2]
    sides = [f for f in cleat.Shape.Faces
             if abs(f.BoundBox.ZMin - z_plate) < 1e-6 and f.BoundBox.ZMax > z_plate + 1.0]
    corners = [np.array(point) for point in _sharp_corners(foot)]
    placed = []
    for name, p_b, R_b_t in targets:
        p_u = T_u_b[:3, :3] @ p_b + T_u_b[:3, 3]
        z_u = T_u_b[:3, :3] @ R_b_t[:, 2]
        vertex = Part.Vertex(FreeCAD.Vector(*p_u))
        dist, edge = min((e.distToShape(vertex)[0], k) for k, e in enumerate(foot, 1))
        if dist > 0.05:
            continue
        placed.append((name, p_u, z_u, edge))
    out = []
    for k, (name, p_u, z_u, edge) in enumerate(placed):
        ahead = next((q for _, q, _, _ in placed[k + 1:] if np.linalg.norm(q - p_u) > 0.5), None)
        behind = next((q for _, q, _, _ in reversed(placed[:k]) if np.linalg.norm(q - p_u) > 0.5), None)
        travel = (ahead - p_u) if ahead is not None else (p_u - behind)
        vertex = Part.Vertex(FreeCAD.Vector(*p_u))
        face = min(sides, key=lambda f: f.distToShape(vertex)[0])
        u, w = face.Surface.parameter(FreeCAD.Vector(*p_u))
        n_cleat = np.array(face.normalAt(u, w))
        n_cleat[2] = 0.0
        n_cleat /= np.linalg.norm(n_cleat)
        bisector = -(n_cleat + np.array([0.0, 0.0, 1.0]))
        bisector /= np.linalg.norm(bisector)
        d = travel - np.dot(travel, bisector) * bisector
        d = np.cross(np.cross(bisector, d), bisector)       # along the seam, normal to the bisector
        d /= np.linalg.norm(d)
        across = z_u - np.dot(z_u, d) * d
        work_off = np.degrees(np.arccos(np.clip(np.dot(across / np.linalg.norm(across), bisector), -1, 1)))
        out.append(dict(name=name, edge=edge, work_off_deg=float(work_off),
                        travel_deg=float(np.degrees(np.arcsin(np.clip(np.dot(z_u, d), -1, 1)))),
                        corner=any(np.linalg.norm(p_u - c) < corner_radius_mm for c in corners)))
    return out


def _sharp_corners(edges):
    """Points (FreeCAD.Vector) where consecutive `edges` of a closed loop meet at an angle."""
    def direction(edge, point):
        return edge.tangentAt(edge.Curve.parameter(point)).normalize()
    corners = []
    for a, b in zip(edges, edges[1:] + edges[:1]):
        joint = next(v.Point for v in a.Vertexes
                     if any((v.Point - w.Point).Length < 1e-6 for w in b.Vertexes))
        if abs(direction(a, joint).dot(direction(b, joint))) < 0.999:
            corners.append(joint)
    return corners


def torch_statistics(rows):
    """One line per group (legs / corners): targets, work-angle deviation min/mean/max, travel angle range."""
    lines = []
    for label, pick in (("legs", False), ("corners", True)):
        group = [r for r in rows if r["corner"] == pick]
        if not group:
            lines.append("%s: no targets" % label)
            continue
        off = np.array([r["work_off_deg"] for r in group])
        travel = np.array([r["travel_deg"] for r in group])
        lines.append("%s: %d targets, torch off the fillet bisector %.1f/%.1f/%.1f deg (min/mean/max), "
                     "travel angle %.1f..%.1f deg" % (label, len(group), off.min(), off.mean(), off.max(),
                                                     travel.min(), travel.max()))
    return lines
