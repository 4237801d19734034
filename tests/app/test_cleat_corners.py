"""A fillet weld all round an angle cleat, with the defaults (issue 20, items 1, 5 and 10).

The cell is built as a new user does: automatic tool markers on the 9 edges of
the cleat's foot, then every suggested risk area applied. Each written target's
torch axis is then measured against the fillet from the document's own faces
(Part: the nearest face of the cleat at the target and the plate's top face),
not from anything the generator computed:

* work angle: in the plane normal to the travel direction, the angle between
  the torch axis and the fillet bisector (into the work), i.e. the bisector
  of the plate's normal and the cleat face's normal there;
* travel angle: the torch axis's lean towards the travel direction, which for
  this counter-clockwise loop is plate normal x cleat face normal.

Targets inside the corners' risk areas (where the torch turns round a convex
corner of the loop) are reported separately: there the torch is between the
two legs' bisectors on purpose.
"""

import math

import numpy as np
import pytest

import FreeCAD
import Part

from CadRobotWB import api
from CadRobotWB.core import frames, program as ir
from CadRobotWB.robots.checks import collision

PLATE_NORMAL = np.array([0.0, 0.0, 1.0])
TOLERANCE_DEG = 5.0


@pytest.fixture(scope="module")
def cleat_cell():
    import angle_cleat
    doc = FreeCAD.newDocument("CleatCorners")
    cleat, plate = angle_cleat.cleat_on_plate(doc)
    cell = api.make_cell(doc)
    api.make_calibration_frame(doc, cell, FreeCAD.Placement(FreeCAD.Vector(0, 0, 10), FreeCAD.Rotation()))
    path = api.make_path(doc, cell, [(cleat, e) for e in angle_cleat.foot_loop_edges(cleat)])
    api.make_tool_markers_auto(doc, cell, path)
    suggestions = api.suggest_risk_areas(cell)
    for s in suggestions:
        api.make_risk_area(doc, cell, s.path, s.first_segment, s.last_segment, step_mm=s.step_mm,
                           corner_span_mm=s.corner_span_mm, at_corner=s.at_corner)
    yield doc, cell, path, cleat, plate, suggestions
    FreeCAD.closeDocument(doc.Name)


def _side_faces(cleat):
    """The cleat's faces standing on the plate (normals horizontal)."""
    out = []
    for face in cleat.Shape.Faces:
        u0, u1, v0, v1 = face.ParameterRange
        n = face.normalAt((u0 + u1) / 2, (v0 + v1) / 2)
        if abs(n.z) < 1e-9:
            out.append(face)
    return out


def _face_normals_near(faces, p):
    """(distance mm, [normal (3,)]) of the cleat faces nearest `p`: one on a face, two (or
    more) at a convex corner of the foot, where faces with different normals meet."""
    vertex = Part.Vertex(FreeCAD.Vector(*p))
    found = []
    for face in faces:
        distance, pairs, _ = face.distToShape(vertex)
        u, v = face.Surface.parameter(pairs[0][0])
        n = face.normalAt(u, v)
        found.append((distance, np.array([n.x, n.y, n.z])))
    nearest = min(d for d, _ in found)
    normals = []
    for d, n in found:
        if d < nearest + 1e-3 and all(np.degrees(np.arccos(np.clip(n @ m, -1, 1))) > 1.0 for m in normals):
            normals.append(n)
    return nearest, normals


def torch_angles_deg(T_u_t, face_normal):
    """(work deviation from the bisector, travel angle), degrees, of one TCP pose."""
    z = T_u_t[:3, 2]
    travel = np.cross(PLATE_NORMAL, face_normal)
    travel /= np.linalg.norm(travel)
    bisector = PLATE_NORMAL + face_normal
    bisector /= np.linalg.norm(bisector)
    in_plane = z - (z @ travel) * travel
    work = math.degrees(math.acos(np.clip(in_plane @ -bisector / np.linalg.norm(in_plane), -1.0, 1.0)))
    return work, math.degrees(math.asin(np.clip(z @ travel, -1.0, 1.0)))


def written_poses(program):
    """[(T_u_t, move, target)] of every path target (vias first), in {U}."""
    out = []
    for path in program.paths:
        for move in path.moves:
            if move.role not in (ir.ROLE_PATH, ir.ROLE_RISK, ir.ROLE_REORIENT, ir.ROLE_ENTRY):
                continue
            T_u_b = program.frames[move.frame].T_u_b
            for target in ([move.via] if move.via is not None else []) + [move.target]:
                out.append((T_u_b @ target.T_b_t, move, target))
    return out


def _statistics(groups):
    return "\n".join("%-28s n=%3d work dev min/mean/max %.2f/%.2f/%.2f deg, travel min/mean/max %.2f/%.2f/%.2f deg"
                     % (key, len(v), min(w for w, _ in v), np.mean([w for w, _ in v]), max(w for w, _ in v),
                        min(t for _, t in v), np.mean([t for _, t in v]), max(t for _, t in v))
                     for key, v in sorted(groups.items()))


def test_suggestions_one_per_convex_corner(cleat_cell):
    """Tangent line/arc junctions do not turn the tool (it turns with the arcs); the three
    convex 90-degree corners (leg ends 1-2, 8-9, and the heel where the loop closes, 9-1) do."""
    suggestions = cleat_cell[-1]
    assert [(s.first_segment, s.last_segment) for s in suggestions] == [(1, 2), (8, 9), (9, 1)]
    for s in suggestions:
        assert s.turn_deg == pytest.approx(90.0, abs=1e-6) and s.jump_deg == pytest.approx(90.0, abs=1e-6)
    # Segments 2 and 8 are the 4 mm ends of the legs: a quarter of them; the heel between the
    # 100 mm outer faces: 5 mm, welded on over the first leg's start.
    assert [s.corner_span_mm for s in suggestions] == [1.0, 1.0, 5.0]


def test_torch_stays_on_the_fillet_bisector_along_every_leg(cleat_cell):
    doc, cell, path, cleat, plate, _ = cleat_cell
    program = api.generate(cell)
    faces = _side_faces(cleat)
    travel_default = float(cell.TravelAngle)
    legs, corners = {}, {}
    for T_u_t, move, _target in written_poses(program):
        distance, normals = _face_normals_near(faces, T_u_t[:3, 3])
        assert distance < 1e-3, "target %s is %.3f mm off the cleat" % (move.target.name, distance)
        # At a corner point (the ends of segments 1, 8, 9) the leg the move welds is the face
        # the torch is square to: the smaller deviation of the faces meeting there.
        work, travel = min((torch_angles_deg(T_u_t, n) for n in normals), key=lambda a: a[0])
        entry = (work, travel - travel_default)
        if move.role in (ir.ROLE_RISK, ir.ROLE_REORIENT):
            corners.setdefault("corner area, segment %d" % move.segment, []).append(entry)
        elif move.role == ir.ROLE_ENTRY:
            corners.setdefault("start at the heel", []).append(entry)
        else:
            legs.setdefault("segment %d" % move.segment, []).append(entry)
    report = ("legs (work: deviation from the bisector; travel: minus the cell's %g deg):\n%s\n"
              "corners (turning on purpose):\n%s" % (travel_default, _statistics(legs), _statistics(corners)))
    print(report)
    assert sorted(legs) == sorted("segment %d" % k for k in range(1, 10)), report
    worst_work = max(w for v in legs.values() for w, _ in v)
    worst_travel = max(abs(t) for v in legs.values() for _, t in v)
    assert worst_work <= TOLERANCE_DEG and worst_travel <= TOLERANCE_DEG, report


def _part_meshes(*objects):
    import trimesh
    meshes = []
    for obj in objects:
        points, triangles = obj.Shape.tessellate(0.1)
        meshes.append((obj.Label, trimesh.Trimesh(np.array([tuple(p) for p in points]), np.array(triangles))))
    return meshes


def torch_clearances(cell, cleat, plate):
    """[(distance mm, target name, move)] of the cell's torch body (cut 15 mm short of the TCP,
    as Check cuts it) at every written target to the cleat and the plate, with python-fcl;
    negative = penetration depth."""
    import trimesh
    program = api.generate(cell)
    tool = program.tool
    pieces = collision.tool_pieces((tool.body_vertices_mm, tool.body_faces), tool.T_f_t)
    manager = trimesh.collision.CollisionManager()
    for name, mesh in _part_meshes(cleat, plate):
        manager.add_object(name, mesh)
    T_t_f = frames.invert_transform(np.asarray(tool.T_f_t, dtype=float))
    out = []
    for T_u_t, move, target in written_poses(program):
        distance = min(manager.min_distance_single(piece, transform=T_u_t @ T_t_f) for piece in pieces)
        out.append((distance, target.name, move))
    return out


@pytest.fixture(scope="module")
def clearances(cleat_cell):
    if not collision.is_available():
        pytest.skip("python-fcl is not installed: the torch body was not checked against the parts")
    doc, cell, path, cleat, plate, _ = cleat_cell
    return torch_clearances(cell, cleat, plate)


def _root_arc_end(move):
    """The end of the R12 root (segment 5): the torch leans back towards the wall it leaves."""
    return move.segment == 5 and move.kind == ir.CIRCULAR


def test_torch_body_clear_of_both_parts_round_the_convex_corners_and_legs(clearances):
    corner = [d for d, _, m in clearances if m.role in (ir.ROLE_RISK, ir.ROLE_REORIENT)]
    elsewhere = [(d, name) for d, name, m in clearances
                 if m.role not in (ir.ROLE_RISK, ir.ROLE_REORIENT) and not _root_arc_end(m)]
    print("closest approach: %.1f mm round the convex corners (%d targets), %.1f mm elsewhere"
          % (min(corner), len(corner), min(d for d, _ in elsewhere)))
    assert min(corner) > 0.0 and min(d for d, _ in elsewhere) > 0.0, sorted(elsewhere)[:5]


@pytest.mark.xfail(strict=True, reason="the Straight torch's 28 mm tube, 45 deg to the wall at the "
                   "end of the R12 root and leaning back 10 deg, reaches the x leg's inner wall "
                   "12 mm behind it (measured in the report); a later change must lean it away")
def test_torch_body_clear_at_the_end_of_the_concave_root(clearances):
    at_end = [(d, name) for d, name, m in clearances if _root_arc_end(m)]
    print("root arc targets (via, end): %s" % ", ".join("%s %.1f mm" % (n, d) for d, n in at_end))
    assert min(d for d, _ in at_end) > 0.0
