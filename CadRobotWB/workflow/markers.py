"""Tool markers: the TCP pose on a path, its conflicts with other markers, markers placed
from the faces along a path.

Part of the scripting API: :mod:`CadRobotWB.api` re-exports its public names.
"""

import numpy as np

from ..core.tool_orientation import tool_rotation
from ..errors import MarkerError
from ..objects import base, edge_markers, reader, tool_marker, validate
from ..objects.convert import matrix_from_placement, placement_from_matrix
from .arguments import Arguments
from .common import as_placement

#: make_tool_markers_auto's choices of on_conflict.
AUTO_ON_CONFLICT = ("error", "replace", "skip", "keep")


def make_tool_marker(doc, cell, placement, name="ToolMarker", path=None, segment=0,
                     shape=tool_marker.CELL_TOOL, on_conflict="error"):
    """Add a tool marker whose placement is the TCP pose in {U}.

    The marker sets the segment its origin lies on, unless `path` and
    `segment` (1-based) name one explicitly, and every following segment of
    that path up to the next marker (its ``Governs`` property names them).

    `shape` is what it draws: "Cell tool" (the cell's tool body, its TCP on
    the marker), or one of the simple shapes "Torch", "Cone", "Ball".

    Parameters
    ----------
    on_conflict : {"error", "replace", "next", "keep"}
        What to do when another marker already sets that segment with another
        orientation (the segment would have two):

        * ``"error"`` (default): raise MarkerError naming both markers and the
          fixes; nothing is added.
        * ``"replace"``: delete the other marker(s) on that segment.
        * ``"next"``: this marker starts a new stretch at the following
          segment: its Path and Segment link it to segment k + 1 (segment k
          keeps the other marker's orientation). MarkerError when segment
          k + 1 does not exist or another marker sets it; nothing is added.
        * ``"keep"``: add it anyway; generating refuses the path until fixed.
    """
    args = Arguments("make_tool_marker")
    args.open_document("doc", doc)
    args.cell(cell)
    args.placement("placement", placement)
    args.text("name", name)
    args.document_object("path", path, "RobotPath", optional=True)
    args.number("segment", segment, expected="a segment number (a whole number, 0: the one under the origin)")
    args.choice("shape", shape, tool_marker.SHAPES)
    args.choice("on_conflict", on_conflict, tool_marker.ON_CONFLICT)
    pl = as_placement(placement, "Tool marker '%s'" % name, MarkerError)
    segment = validate.whole_in_range(segment, "Tool marker '%s': segment" % name, 0, error=MarkerError)
    conflict = None
    if on_conflict != "keep":
        conflict = tool_marker.proposed_conflict(cell, matrix_from_placement(pl), name, path, segment)
    if conflict is not None and on_conflict == "error":
        raise tool_marker.conflict_error(conflict, added=False)
    if conflict is not None and on_conflict == "next" and conflict.next_free is None:
        raise MarkerError("%s Tool marker '%s': on_conflict=\"next\" is not possible, %s. Use "
                          "on_conflict=\"replace\" to delete %s, or place it on another segment. "
                          "Nothing was added." % (conflict.describe_problem(), name,
                                                  conflict.next_text(), conflict.others_text()),
                          conflict.others[0].Name)
    obj = tool_marker.make(doc, name)
    obj.Placement = pl
    obj.ToolShape = shape
    if path is not None:
        obj.Path = path
    obj.Segment = segment
    cell.addObject(obj)
    if conflict is not None:
        tool_marker.resolve_conflict(conflict, obj, on_conflict)
    doc.recompute()
    return obj


def tool_marker_conflict(cell, marker=None, placement=None, path=None, segment=0, name="ToolMarker"):
    """Whether a tool marker sets a segment another marker of `cell` already sets
    with another orientation.

    Give `marker` (one in the cell, e.g. just moved) or the `placement` (TCP
    pose in {U}), `path` and `segment` a new marker would get (as
    :func:`make_tool_marker` takes them).

    Returns
    -------
    tool_marker.Conflict or None
        ``.others`` (the markers already there), ``.path``, ``.segment``
        (1-based), ``.next_free`` (the segment "next" would link to, or None),
        ``.describe_problem()``, ``.next_text()``. None also when the marker
        lies on no path (generating reports that).
    """
    args = Arguments("tool_marker_conflict")
    args.cell(cell)
    if marker is not None:
        args.document_object("marker", marker, "ToolMarker")
        return tool_marker.marker_conflict(cell, marker)
    args.placement("placement", placement)
    args.document_object("path", path, "RobotPath", optional=True)
    args.whole_number("segment", segment)
    args.text("name", name)
    pl = as_placement(placement, "Tool marker '%s'" % name, MarkerError)
    return tool_marker.proposed_conflict(cell, matrix_from_placement(pl), name, path, segment)


def resolve_marker_conflict(cell, marker, action):
    """Resolve the conflict of tool `marker` with the markers on its segment.

    Parameters
    ----------
    action : {"replace", "next"}
        ``"replace"`` deletes the other markers on its segment; ``"next"``
        links `marker` to the following segment (a new stretch starts there).

    Returns
    -------
    bool
        True when there was a conflict to resolve.
    """
    args = Arguments("resolve_marker_conflict")
    args.cell(cell)
    args.document_object("marker", marker, "ToolMarker")
    args.choice("action", action, ("replace", "next"))
    conflict = tool_marker.marker_conflict(cell, marker)
    if conflict is None:
        return False
    tool_marker.resolve_conflict(conflict, marker, action)
    marker.Document.recompute()
    return True


def tool_placement(point, travel_dir, surface_normal, work_angle_deg=90.0, travel_angle_deg=0.0):
    """A TCP placement on `point` from welding angles (see core.tool_orientation).

    Parameters
    ----------
    point, travel_dir, surface_normal : FreeCAD.Vector or array_like (3,)
        In {U}, mm.
    """
    args = Arguments("tool_placement")
    point, travel_dir, surface_normal = (args.point(argument, value) for argument, value in (
        ("point", point), ("travel_dir", travel_dir), ("surface_normal", surface_normal)))
    work_angle_deg = args.number("work_angle_deg", work_angle_deg, expected="an angle in degrees (a number)")
    travel_angle_deg = args.number("travel_angle_deg", travel_angle_deg,
                                   expected="an angle in degrees (a number)")
    T = np.eye(4)
    T[:3, :3] = tool_rotation(travel_dir, surface_normal, work_angle_deg, travel_angle_deg)
    T[:3, 3] = point
    return placement_from_matrix(T)


def edge_tool_placement(obj, edge_name, point=None, face=None, work_angle_deg=90.0,
                        travel_angle_deg=0.0, path=None):
    """The TCP pose on an edge, from welding angles.

    Parameters
    ----------
    obj : App.DocumentObject
        Owner of the edge; `edge_name` is ``"EdgeN"``.
    point : FreeCAD.Vector or 3 floats, optional
        {U}, mm: the pose is at the edge point nearest it; default mid-length.
    face : (App.DocumentObject, str), optional
        ``(obj, "FaceN")`` whose normal the tool faces. Default: the faces
        meeting at the edge (of `obj`, and the document's solids whose
        surface holds the edge); several give their bisector.
    work_angle_deg, travel_angle_deg : float
        See :func:`tool_placement`.
    path : RobotPath, optional
        +X follows its travel direction (Reversed, chaining); default the edge's.

    Returns
    -------
    FreeCAD.Placement
        In {U}. InputError "select a face too" when no face meets the edge.
    """
    args = Arguments("edge_tool_placement")
    args.shape_object("obj", obj)
    args.text("edge_name", edge_name, expected="an edge name (a str, 'EdgeN')")
    args.point("point", point, optional=True)
    args.sub_element("face", face, optional=True)
    args.number("work_angle_deg", work_angle_deg, expected="an angle in degrees (a number)")
    args.number("travel_angle_deg", travel_angle_deg, expected="an angle in degrees (a number)")
    args.document_object("path", path, "RobotPath", optional=True)
    p, tangent, normal = edge_markers.edge_pose(obj, edge_name, point, face, path)
    return tool_placement(p, tangent, normal, work_angle_deg, travel_angle_deg)


def make_tool_markers_auto(doc, cell, path, work_angle_deg=None, travel_angle_deg=None,
                           shape=tool_marker.CELL_TOOL, on_conflict="error"):
    """One tool marker per segment of `path`, at its mid-length, from the faces there.

    Labels are ``"<path label>_Tool<k>"``; each marker's Path and Segment are
    set. The angles default to the cell's WorkAngle / TravelAngle (degrees).
    Nothing is added when a segment has no adjacent face (InputError naming it).

    Parameters
    ----------
    on_conflict : {"error", "replace", "skip", "keep"}
        When markers already set some of the path's segments with another
        orientation than the automatic one: ``"error"`` (default) raises
        MarkerError naming them and adds nothing; ``"replace"`` deletes them;
        ``"skip"`` keeps them and adds no automatic marker on their segments;
        ``"keep"`` adds all (generating then refuses those segments).

    Returns
    -------
    list of ToolMarker objects
    """
    args = Arguments("make_tool_markers_auto")
    args.open_document("doc", doc)
    args.cell(cell)
    args.document_object("path", path, "RobotPath")
    angle = "an angle in degrees (a number) or None (the cell's)"
    work_angle_deg = args.number("work_angle_deg", work_angle_deg, optional=True, expected=angle)
    travel_angle_deg = args.number("travel_angle_deg", travel_angle_deg, optional=True, expected=angle)
    args.choice("shape", shape, tool_marker.SHAPES)
    args.choice("on_conflict", on_conflict, AUTO_ON_CONFLICT)
    work = float(cell.WorkAngle) if work_angle_deg is None else work_angle_deg
    travel = float(cell.TravelAngle) if travel_angle_deg is None else travel_angle_deg
    placed = [(k, tool_placement(p, t, n, work, travel))      # all computed before adding any
              for k, _source, p, t, n in edge_markers.segment_poses(path)]
    conflicts = {} if on_conflict == "keep" else auto_marker_conflicts(cell, path, placed)
    if conflicts and on_conflict == "error":
        listed = "; ".join("segment %d: %s (%.1f°)" % (k, c.others_text(), max(c.angles_deg))
                           for k, c in sorted(conflicts.items())[:5])
        more = " and %d more" % (len(conflicts) - 5) if len(conflicts) > 5 else ""
        raise MarkerError(
            "Path %s: %d of its segments already have a tool marker with another orientation than "
            "the automatic one (%s%s). Nothing was added. Use on_conflict=\"replace\" to delete "
            "those markers, or on_conflict=\"skip\" to keep them and add markers only on the "
            "other segments." % (base.describe(path), len(conflicts), listed, more),
            next(iter(sorted(conflicts.items())))[1].others[0].Name)
    if on_conflict == "replace":
        for conflict in conflicts.values():
            for other in conflict.others:
                if doc.getObject(other.Name) is not None:
                    doc.removeObject(other.Name)
    markers = []
    for k, marker_placement in placed:
        if on_conflict == "skip" and k in conflicts:
            continue
        marker = make_tool_marker(doc, cell, marker_placement, path=path, segment=k, shape=shape,
                                  on_conflict="keep")
        marker.Label = "%s_Tool%d" % (path.Label, k)
        markers.append(marker)
    return markers


def auto_marker_conflicts(cell, path, placed=None):
    """The segments where automatic markers on `path` would meet a marker with another orientation.

    Parameters
    ----------
    placed : list of (int, FreeCAD.Placement), optional
        (segment 1-based, TCP pose in {U}) of the automatic markers; default
        those of :func:`make_tool_markers_auto` at the cell's angles.

    Returns
    -------
    dict of int to tool_marker.Conflict
        By segment number (1-based).
    """
    args = Arguments("auto_marker_conflicts")
    args.cell(cell)
    args.document_object("path", path, "RobotPath")
    if placed is not None and not isinstance(placed, (list, tuple)):
        args.refuse("placed", "None or a list of (segment, FreeCAD.Placement)", placed)
    for k, item in enumerate(placed or []):
        if not (isinstance(item, (list, tuple)) and len(item) == 2):
            args.refuse("placed[%d]" % k, "a (segment, FreeCAD.Placement) pair", item)
        args.whole_number("placed[%d] segment" % k, item[0])
        args.placement("placed[%d] placement" % k, item[1])
    if placed is None:
        work, travel = float(cell.WorkAngle), float(cell.TravelAngle)
        placed = [(k, tool_placement(p, t, n, work, travel))
                  for k, _source, p, t, n in edge_markers.segment_poses(path)]
    known = tool_marker._segment_markers(cell)
    out = {}
    for k, marker_placement in placed:
        conflict = tool_marker.proposed_conflict(cell, matrix_from_placement(marker_placement),
                                                 "%s_Tool%d" % (path.Label, k), path, k, known=known)
        if conflict is not None:
            out[k] = conflict
    return out


def marker_segment(cell, marker):
    """(RobotPath, segment number 1-based) that tool `marker` sets in `cell`."""
    args = Arguments("marker_segment")
    args.cell(cell)
    args.document_object("marker", marker, "ToolMarker")
    return reader.marker_assignment(cell, marker)
