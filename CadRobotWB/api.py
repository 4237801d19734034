"""The public scripting API (stable contract, see DESIGN.md).

Every toolbar command and every CLI subcommand is one call of this module,
so a macro recorded in the GUI replays in FreeCADCmd::

    from CadRobotWB import api
    cell   = api.make_cell(doc, robot="ABB_IRB2400", name="Cell")
    frame  = api.make_calibration_frame(doc, cell, placement)
    path   = api.make_path(doc, cell, sketch, speed_mm_s=10.0)
    marker = api.make_tool_marker(doc, cell, placement)
    risk   = api.make_risk_area(doc, cell, path, 2, 3)
    prog   = api.generate(cell)
    files  = api.export(cell, post="abb_rapid", output_dir="out")

Placements may be given as ``FreeCAD.Placement`` or as 4x4 arrays (mm).
"""

import math
import os
import re

import FreeCAD
import numpy as np

from . import dependencies, fileio, posts, preferences, simulation
from .core import frames, risk_suggestions
from .core import generate as core_generate
from .core import progress as core_progress
from .core.progress import report_now, stage
from .core.tool_orientation import tool_rotation
from .errors import (CadRobotError, FindingError, FrameError, InputError, MarkerError,
                     NameTakenError, RiskAreaError)
from .objects import (base, calibration_frame, cell as cell_module, edge_markers, floor_face,
                      frame_picking, joint_faces, obstacles, reader, risk_area, robot_path, tool_body,
                      tool_marker, validate)
from .objects.convert import matrix_from_placement, placement_from_matrix, vector_from_array
from .objects.picking import point_of
from .robots.catalog import catalog, tools
from .robots.checks import checks, collision
from .robots.kinematics import models
from .robots.motion import configuration, move_sampling, playback, timing
from .robots.placement import placement, placement_search

RiskSuggestion = risk_suggestions.RiskSuggestion
PREFERENCES = preferences.PATH   # kept for older macros


# --- helpers -------------------------------------------------------------------------------

#: What a cell's placement is, in messages.
ROBOT_BASE = "robot base placement"


def _placement(value, what, error=InputError, obj_name=None, placement="placement"):
    """A FreeCAD.Placement from a Placement, a FreeCAD.Matrix or a 4x4 array (mm).

    Parameters
    ----------
    what : str
        Names the object whose placement it is, e.g. ``"Tool marker 'M'"``.
    error : type
        The InputError subclass raised for a value that is not a rigid
        transform (NaN, zero rotation block, scale, shear, mirror).
    placement : str
        What the value is to the object, for the message.
    """
    if isinstance(value, FreeCAD.Placement):
        T = matrix_from_placement(value)
    else:
        if isinstance(value, FreeCAD.Matrix):
            value = np.reshape(value.A, (4, 4))
        try:
            T = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            T = None
        if T is None or T.shape != (4, 4):
            raise error("%s: the %s must be a FreeCAD.Placement or a 4x4 matrix." % (what, placement),
                        obj_name)
    return placement_from_matrix(validate.check_rigid(T, what, error, obj_name, placement))


def _check_type(obj, type_name, argument):
    if base.type_of(obj) != type_name:
        label = getattr(obj, "Label", repr(obj))
        raise InputError("'%s' is not a CadRobot %s; pass one as '%s'." % (label, type_name, argument))


# --- making objects --------------------------------------------------------------------------

def make_cell(doc, robot="ABB_IRB2400", name="Cell", placement=None, tool=None):
    """Add a robot cell. Its ``Placement`` is the robot base {R} in {U}; its
    ``PostProcessor`` is the robot controller's language.

    Parameters
    ----------
    placement : FreeCAD.Placement or array_like (4, 4), optional
        The robot base {R} in {U}, mm; default the identity.
    tool : str, optional
        A tool of the library (:func:`tool_names`); default "Straight torch".
        Its TCP, mass and centre of gravity become the cell's (change them,
        or give a document solid as the tool, with :func:`set_tool`).

    Raises UnknownNameError for a robot not in the catalog (see :func:`robots`)
    or a tool not in the library.
    """
    preferences.use_user_robot_folder()
    spec = catalog.get(robot)
    library_tool = tools.get(tools.DEFAULT if tool is None else tool)
    pl = None if placement is None else _placement(placement, "Cell '%s'" % name,
                                                   placement=ROBOT_BASE)
    obj = cell_module.make(doc, robot, name)
    if pl is not None:
        obj.Placement = pl
    _apply_tool(obj, library_tool.name, None, placement_from_matrix(library_tool.T_f_t),
                library_tool.mass_kg, library_tool.cog_mm)
    if spec.default_post in posts.names():   # the robot's own controller language, once we have it
        obj.PostProcessor = spec.default_post
    doc.recompute()
    return obj


def tool_names():
    """The tool library's names (e.g. "Straight torch"), for :func:`make_cell` and :func:`set_tool`."""
    return tools.names()


def _apply_tool(cell, tool_type, body, tcp, mass_kg, cog_mm):
    """Set the tool properties of `cell` (values already checked)."""
    cell.ToolType = tool_type
    cell.ToolBody = body
    cell.ToolTCP = tcp
    cell.ToolMass = float(mass_kg)
    cell.ToolCenterOfGravity = vector_from_array(np.asarray(cog_mm, dtype=float))


def _body_centre_mm(body):
    """Centre of mass (uniform density) of `body`'s solids in its own coordinates, mm (3,)."""
    solids = tool_body.own_shape(body).Solids
    volume = sum(s.Volume for s in solids)
    return sum((np.array(tuple(s.CenterOfMass)) * s.Volume for s in solids), np.zeros(3)) / volume


def set_tool(cell, tool=None, body=None, tcp=None, mass_kg=None, cog_mm=None):
    """Give `cell` its tool: one of the library, or a solid of the document.

    With `tool`, the library tool's body, TCP, mass and centre of gravity
    (`tcp`, `mass_kg`, `cog_mm` override its numbers, e.g. a longer wire
    stick-out; the body drawn stays the library's).

    With `body`, the solid is the tool (``ToolType`` "Custom body"), read in
    its own coordinates: the robot's flange {F} is the solid's own origin
    (its shape with its placement taken off; draw the tool with the flange
    face at the origin, its axis along +Z), and `tcp` is the TCP in those
    coordinates: its origin at the tool's tip, its +Z the approach direction
    (out of the tool, into the work).  `mass_kg` defaults to the cell's
    present ToolMass, `cog_mm` to the solid's centre of volume.  The solid
    is no longer an obstacle of the collision check.

    With neither, only the numbers given change.

    Tool markers drawing the cell's tool follow (recompute).

    Parameters
    ----------
    cell : Cell
    tool : str, optional
        A name of :func:`tool_names`.
    body : App.DocumentObject, optional
        A document object with a solid Shape.
    tcp : FreeCAD.Placement or array_like (4, 4), optional
        TCP {T} in the flange frame {F}, mm (needed with `body`).
    mass_kg : float, optional
        Tool mass, kg (> 0).
    cog_mm : sequence of 3 float, optional
        Centre of gravity in {F}, mm.

    Returns
    -------
    Cell

    Raises
    ------
    InputError
        Both `tool` and `body`; an unknown tool name; a body without a
        solid; `body` without `tcp`; a TCP that is not a rigid placement; a
        mass that is not a positive finite number; a centre of gravity that
        is not three finite numbers.  The cell is then unchanged.
    """
    _check_type(cell, "Cell", "cell")
    what = "Cell %s" % base.describe(cell)
    if tool is not None and body is not None:
        raise InputError("%s: give either a library tool (tool=) or a document solid (body=), not "
                         "both." % what, cell.Name)
    if tool is not None:
        library_tool = tools.get(tool)
        tool_type, tool_solid = library_tool.name, None
        defaults = (placement_from_matrix(library_tool.T_f_t), library_tool.mass_kg,
                    library_tool.cog_mm)
    elif body is not None:
        tool_body.check_body(cell, body)
        if tcp is None:
            raise InputError("%s: give the TCP of the tool body %s (tcp=, its placement in the "
                             "body's own coordinates: origin at the tip, +Z into the work)."
                             % (what, base.describe(body)), cell.Name)
        tool_type, tool_solid = tools.CUSTOM, body
        defaults = (None, float(cell.ToolMass), _body_centre_mm(body))
    else:
        tool_type, tool_solid = cell.ToolType, cell.ToolBody
        defaults = (cell.ToolTCP, float(cell.ToolMass),
                    np.array(tuple(cell.ToolCenterOfGravity), dtype=float))
    new_tcp = defaults[0] if tcp is None else _placement(tcp, what, obj_name=cell.Name,
                                                         placement="tool's TCP (tcp)")
    mass = defaults[1] if mass_kg is None else mass_kg
    mass = validate.number_in_range(mass, "%s: the tool mass (mass_kg, kg)" % what, 0.0,
                                    low_open=True)
    cog = defaults[2] if cog_mm is None else cog_mm
    try:
        cog = np.asarray(cog, dtype=float).reshape(3)
    except (TypeError, ValueError):
        raise InputError("%s: the tool's centre of gravity (cog_mm) must be 3 numbers (x, y, z "
                         "in mm in the flange frame), not %r." % (what, cog_mm), cell.Name) from None
    validate.finite_values(cog, "%s: the tool's centre of gravity (cog_mm)" % what,
                           obj_name=cell.Name)
    _apply_tool(cell, tool_type, tool_solid, new_tcp, mass, cog)
    for marker in tool_marker.cell_markers(cell):
        marker.touch()
    cell.Document.recompute()
    return cell


def _obstacle_objects(doc):
    """The document's final solids, less the cells' tool bodies (and what they are made of)."""
    skip = set()
    for body in tool_body.tool_body_objects(doc):
        skip.add(body.Name)
        skip.update(o.Name for o in body.OutListRecursive)
    return [o for o in doc.Objects if obstacles.is_final_solid(o) and o.Name not in skip]


def make_calibration_frame(doc, cell, placement, name="CalibrationFrame"):
    """Add a calibration frame {B} at `placement` (in {U}) to `cell`.

    It becomes the cell's calibration frame if the cell has none yet.
    """
    _check_type(cell, "Cell", "cell")
    pl = _placement(placement, "Calibration frame '%s'" % name, FrameError)
    obj = calibration_frame.make(doc, name)
    obj.Placement = pl
    cell.addObject(obj)
    if cell.CalibrationFrame is None:
        cell.CalibrationFrame = obj
    doc.recompute()
    return obj


def _source_links(source):
    """Normalise a path source to [(obj, [sub, ...]), ...]."""
    items = source if isinstance(source, (list, tuple)) and not _is_pair(source) else [source]
    links = []
    for item in items:
        if _is_pair(item):
            obj, subs = item
            subs = [subs] if isinstance(subs, str) else list(subs)
        else:
            obj, subs = item, []
        if not hasattr(obj, "Shape"):
            raise InputError("Path source '%s' has no shape; give a sketch, a Part object or "
                             "(object, 'EdgeN') pairs." % getattr(obj, "Label", obj))
        links.append((obj, subs))
    if not links:
        raise InputError("The path source is empty; give a sketch, a Part object or edges.")
    return links


def _is_pair(item):
    return (isinstance(item, tuple) and len(item) == 2 and hasattr(item[0], "Shape")
            and isinstance(item[1], (str, list, tuple)))


def make_path(doc, cell, source, speed_mm_s=10.0, name="Path", **properties):
    """Add a path following `source` to `cell`.

    Parameters
    ----------
    source
        A sketch or Part object (all its edges), ``(obj, "Edge3")``,
        ``(obj, ["Edge1", "Edge2"])``, or a list of any of these.
    speed_mm_s : float
        TCP speed along the path.
    **properties
        Any other path property by name, e.g. ``Zone=1.0``,
        ``ApproachDistance=30``, ``CalibrationFrame=frame``.

    The geometry is checked at once (GeometryError for gaps, branches,
    zero-length edges); on error nothing is added to the document.
    """
    _check_type(cell, "Cell", "cell")
    links = _source_links(source)
    speed = validate.number_in_range(speed_mm_s, "Path '%s': speed_mm_s" % name, 0.0, low_open=True)
    obj = robot_path.make(doc, name)
    try:
        # An empty sub-list must be [""] or FreeCAD drops the whole link.
        obj.Source = [(o, subs or [""]) for o, subs in links]
        obj.Speed = speed
        for prop, value in properties.items():
            if prop not in obj.PropertiesList:
                raise InputError("Paths have no property '%s'." % prop)
            setattr(obj, prop, value)
        reader.path_geometry(obj)
    except CadRobotError:
        doc.removeObject(obj.Name)
        raise
    cell.addObject(obj)
    doc.recompute()
    return obj


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
    _check_type(cell, "Cell", "cell")
    pl = _placement(placement, "Tool marker '%s'" % name, MarkerError)
    if shape not in tool_marker.SHAPES:
        raise InputError("Unknown tool shape '%s'; use one of %s." % (shape, ", ".join(tool_marker.SHAPES)))
    if on_conflict not in tool_marker.ON_CONFLICT:
        raise InputError("Tool marker '%s': on_conflict is %r; use one of %s."
                         % (name, on_conflict, ", ".join('"%s"' % c for c in tool_marker.ON_CONFLICT)))
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
    _check_type(cell, "Cell", "cell")
    if marker is not None:
        _check_type(marker, "ToolMarker", "marker")
        return tool_marker.marker_conflict(cell, marker)
    pl = _placement(placement, "Tool marker '%s'" % name, MarkerError)
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
    _check_type(cell, "Cell", "cell")
    _check_type(marker, "ToolMarker", "marker")
    if action not in ("replace", "next"):
        raise InputError("resolve_marker_conflict: action is %r; use \"replace\" or \"next\"." % (action,))
    conflict = tool_marker.marker_conflict(cell, marker)
    if conflict is None:
        return False
    tool_marker.resolve_conflict(conflict, marker, action)
    marker.Document.recompute()
    return True


def make_risk_area(doc, cell, path, first_segment, last_segment, step_mm=None, name="RiskArea"):
    """Add a risk area over segments `first_segment`..`last_segment` (1-based) of `path`."""
    _check_type(cell, "Cell", "cell")
    _check_type(path, "RobotPath", "path")
    what = "Risk area '%s': " % name
    first, last = (validate.whole_in_range(v, what + w, -math.inf, error=RiskAreaError)
                   for v, w in ((first_segment, "first_segment"), (last_segment, "last_segment")))
    step = validate.number_in_range(step_mm or 0.0, what + "step_mm", 0.0, error=RiskAreaError)
    obj = risk_area.make(doc, name)
    obj.Path = path
    obj.FirstSegment = first
    obj.LastSegment = last
    obj.Step = step
    cell.addObject(obj)
    doc.recompute()
    return obj


def tool_placement(point, travel_dir, surface_normal, work_angle_deg=90.0, travel_angle_deg=0.0):
    """A TCP placement on `point` from welding angles (see core.tool_orientation).

    Parameters
    ----------
    point, travel_dir, surface_normal : FreeCAD.Vector or array_like (3,)
        In {U}, mm.
    """
    R = tool_rotation(np.array(tuple(travel_dir), dtype=float), np.array(tuple(surface_normal), dtype=float),
                      work_angle_deg, travel_angle_deg)
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = np.array(tuple(point), dtype=float)
    return placement_from_matrix(T)


# --- picking: frames and tool markers from the CAD geometry -----------------------------------

def frame_placement_from_points(origin, on_x, in_xy):
    """The frame taught by three points, as on a robot controller.

    Parameters
    ----------
    origin, on_x, in_xy : FreeCAD.Vector or sequence of 3 floats
        The origin, a point on +X and a point in the XY plane (+Y side), {U}, mm.

    Returns
    -------
    FreeCAD.Placement
        FrameError when the points coincide or are collinear.
    """
    points = [point_of(p) for p in (origin, on_x, in_xy)]
    return placement_from_matrix(frames.frame_from_three_points(*points))


def frame_placement_from_selection(items, near=None):
    """A frame from picked sub-elements, in {U}.

    Parameters
    ----------
    items : list of (App.DocumentObject, str)
        Exactly three ``"VertexN"`` (origin, on +X, in the XY plane), or one
        planar ``"FaceN"`` and one straight ``"EdgeN"`` lying in its plane,
        in any order: Z = the face's outward normal, X along the edge.
    near : FreeCAD.Vector or sequence of 3 floats, optional
        A picked point, mm: the origin is the edge end nearest it (default
        the edge's first vertex), X points to the other end.

    Returns
    -------
    FreeCAD.Placement
        InputError / FrameError saying what to select for anything else.
    """
    return placement_from_matrix(frame_picking.from_selection(items, near))


def teach_calibration_frame(frame, cad_points, measured_points):
    """Teach `frame` from points measured on the real part.

    Parameters
    ----------
    cad_points : sequence of N >= 3 points (FreeCAD.Vector or 3 floats)
        Points of the part as drawn, {U}, mm.
    measured_points : sequence of N points
        The same points measured with the robot, in its base frame {R}, mm.

    Returns
    -------
    list of float
        Distance of each measured point from its fitted CAD point, mm.

    Raises
    ------
    FrameError
        Counts differ, fewer than 3 pairs, or collinear points; the frame is unchanged.
    """
    _check_type(frame, "CalibrationFrame", "frame")
    cad = np.array([point_of(p) for p in cad_points]).reshape(-1, 3)
    measured = np.array([point_of(p) for p in measured_points]).reshape(-1, 3)
    if len(cad) != len(measured):
        raise FrameError("Calibration frame %s: %d CAD points but %d measured points; give one "
                         "measured point per CAD point." % (base.describe(frame), len(cad), len(measured)),
                         frame.Name)
    residuals = calibration_frame.fit_points(frame, cad, measured)[1]
    frame.CadPoints = [vector_from_array(p) for p in cad]
    frame.MeasuredPoints = [vector_from_array(p) for p in measured]
    frame.UseTaught = True
    frame.Document.recompute()
    return [float(r) for r in residuals]


def taught_frame(frame):
    """(T_r_b FreeCAD.Placement, residuals list mm) of a taught frame, or None when it is
    not taught (UseTaught off). T_r_b = fit(CAD points -> measured points) @ T_u_b;
    FrameError when its points cannot be fitted."""
    _check_type(frame, "CalibrationFrame", "frame")
    taught = calibration_frame.taught_transform(frame)
    if taught is None:
        return None
    return placement_from_matrix(taught[0]), [float(r) for r in taught[1]]


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
    if path is not None:
        _check_type(path, "RobotPath", "path")
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
    _check_type(cell, "Cell", "cell")
    _check_type(path, "RobotPath", "path")
    if shape not in tool_marker.SHAPES:
        raise InputError("Unknown tool shape '%s'; use one of %s." % (shape, ", ".join(tool_marker.SHAPES)))
    choices = ("error", "replace", "skip", "keep")
    if on_conflict not in choices:
        raise InputError("Automatic tool markers: on_conflict is %r; use one of %s."
                         % (on_conflict, ", ".join('"%s"' % c for c in choices)))
    work = float(cell.WorkAngle) if work_angle_deg is None else float(work_angle_deg)
    travel = float(cell.TravelAngle) if travel_angle_deg is None else float(travel_angle_deg)
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
    _check_type(cell, "Cell", "cell")
    _check_type(path, "RobotPath", "path")
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
    _check_type(cell, "Cell", "cell")
    _check_type(marker, "ToolMarker", "marker")
    return reader.marker_assignment(cell, marker)


def _path_step_mm(cell, path):
    """The paper's step of `path` as generate uses it: its InterpolationStep, else
    speed × the cell's sample time (eqs 8-13), mm."""
    return float(path.InterpolationStep) or (
        reader._positive(path, "Speed", float(path.Speed))
        * reader._positive(cell, "SampleTime", float(cell.SampleTime)))


def suggest_risk_areas(cell, threshold_deg=None):
    """Where the tool turns sharply between consecutive segments of `cell`'s paths.

    Parameters
    ----------
    threshold_deg : float, optional
        Smallest orientation change that needs a risk area, degrees;
        default the ``RiskThreshold`` preference.

    Returns
    -------
    list of RiskSuggestion
        ``(path, first_segment, last_segment, jump_deg, step_mm, step_rule,
        moves_added)``; junctions inside or next to an existing risk area are
        left out (it would overlap). ``step_mm`` is the step to give the area
        (:func:`core.risk_suggestions.area_step_mm`: the paper's speed × sample
        time, coarsened so the tool turns by at most
        ``risk_suggestions.MAX_TURN_PER_MOVE_DEG`` per move, within the path's
        chord tolerance on arcs and splines), ``step_rule`` says which term
        decided, ``moves_added`` how many moves the area adds to the program
        at that step (exactly as :func:`generate` writes it).

    Raises
    ------
    MarkerError
        Two tool markers set one segment with different orientations, or
        segments come before a path's first marker (the message names them).
    """
    _check_type(cell, "Cell", "cell")
    threshold = preferences.get("RiskThreshold") if threshold_deg is None else float(threshold_deg)
    out = []
    for path, R_u_t, areas in reader.path_orientations(cell):
        segments = reader.path_geometry(path)[0]
        base_step = _path_step_mm(cell, path)
        jumps = risk_suggestions.junction_jumps_deg(R_u_t)
        for found in risk_suggestions.suggest(jumps, threshold, areas, path=path):
            first, last = found.first_segment, found.last_segment
            step, rule = risk_suggestions.area_step_mm(segments, R_u_t, first, last, base_step,
                                                       float(path.ChordTolerance))
            out.append(found._replace(step_mm=step, step_rule=rule, moves_added=risk_suggestions.moves_added(
                segments, R_u_t, first, last, step)))
    return out


def risk_area_step(cell, path, first_segment, last_segment, step_mm=None):
    """The default step of a risk area over segments first..last (1-based) of `path`,
    and the moves it adds (the rule of :func:`suggest_risk_areas`).

    Parameters
    ----------
    step_mm : float, optional
        A step to count the moves at instead (mm, > 0).

    Returns
    -------
    (step_mm, rule, moves_added) : (float, str, int)
    """
    _check_type(cell, "Cell", "cell")
    _check_type(path, "RobotPath", "path")
    for found, R_u_t, _areas in reader.path_orientations(cell):
        if found.Name != path.Name:
            continue
        segments = reader.path_geometry(path)[0]
        first, last = int(first_segment), int(last_segment)
        if not 1 <= first <= last <= len(segments):
            raise RiskAreaError("Path %s has segments 1-%d; a risk area over %d-%d does not fit. "
                                "Choose consecutive segments within 1-%d."
                                % (base.describe(path), len(segments), first, last, len(segments)),
                                path.Name)
        if step_mm is None:
            base_step = _path_step_mm(cell, path)
            step, rule = risk_suggestions.area_step_mm(segments, R_u_t, first, last, base_step,
                                                       float(path.ChordTolerance))
        else:
            step = validate.number_in_range(step_mm, "Risk area step_mm", 0.0, low_open=True,
                                            error=RiskAreaError)
            rule = "given"
        return step, rule, risk_suggestions.moves_added(segments, R_u_t, first, last, step)
    raise RiskAreaError("Path %s is not in cell %s." % (base.describe(path), base.describe(cell)), path.Name)


def program_move_count(cell):
    """How many moves :func:`generate` writes for `cell` now (its existing risk areas included).

    With :func:`suggest_risk_areas`, the program's size with suggestions
    taken is this plus their ``moves_added``.

    Raises
    ------
    CadRobotError
        What keeps the cell from generating.
    """
    return len(generate(cell).moves())


# --- programs ---------------------------------------------------------------------------------

def find_cells(doc):
    """The robot cells of `doc`, in document order."""
    return base.objects_of_type(doc, "Cell")


def _start_joints(cell):
    values = list(cell.StartJoints or [])
    if values and len(values) != 6:
        raise InputError("Cell %s: StartJoints must hold 6 joint values in degrees (or none)."
                         % base.describe(cell), cell.Name)
    if values:
        validate.finite_values(values, "Cell %s StartJoints" % base.describe(cell), obj_name=cell.Name)
    return np.array(values, dtype=float) if values else None


def _solved(cell, progress=None):
    _check_type(cell, "Cell", "cell")
    spec = reader.read_cell(cell, progress=stage(progress, 0.0, 0.4))
    program = core_generate.generate(spec, progress=stage(progress, 0.4, 0.55))
    model = models.model(program.robot)
    solution = configuration.solve_program(program, model, q_start_deg=_start_joints(cell),
                                           progress=stage(progress, 0.55, 1.0))
    return program, model, solution


def generate(cell, progress=None):
    """The core Program of `cell`; nothing is written.

    Targets are in their calibration frames {B}; each target's
    ``joints_deg`` holds the robot's joints there (one arm configuration per
    path, closest to the cell's StartJoints), or None where the robot cannot
    take the pose (see :func:`check`).

    Parameters
    ----------
    progress : callable, optional
        ``progress(fraction, text)``, told often (``core.progress``); return
        False to stop: :data:`Cancelled` is raised.
    """
    progress = core_progress.or_ambient(progress)
    return _solved(cell, progress)[0]


class CellCheck:
    """What :func:`check` found for one cell.

    Attributes
    ----------
    cell : str
        The cell's label.
    program : core Program
        As :func:`generate` returns it.
    solution : robots.motion.configuration.JointSolution
        The joints chosen at every target.
    report : robots.checks.checks.Report
        Reach, joint limits, singularities, joint speeds, configuration
        changes and collisions, per target (``report.groups()``: grouped,
        with advice on which way to move the part or the robot).
    cycle_time : dict
        ``total_s`` and per-move times (robots.motion.timing).
    base : robots.motion.playback.RobotBase, optional
        Where the robot stands relative to the part (:func:`robot_base`).
    """

    def __init__(self, cell, program, solution, report, cycle_time, base=None):
        self.cell, self.program, self.solution = cell, program, solution
        self.report, self.cycle_time = report, cycle_time
        self.base = base

    @property
    def ok(self):
        """bool: no finding is an error."""
        return self.report.ok

    @property
    def cycle_time_s(self):
        """float or None: the cycle time, s; None when the check failed (the program cannot run)."""
        return float(self.cycle_time["total_s"]) if self.ok else None

    def notes(self):
        """Lines about where the robot stands: taught frames that disagree."""
        if self.base is None or not self.base.conflicts:
            return []
        return ["NOTE: taught frame '%s' puts the robot base %.1f mm / %.2f deg from where taught "
                "frame '%s' puts it; the check and the 3D view use '%s' (the first taught frame in "
                "path order). Teach both from the same robot base, or turn UseTaught off on one."
                % (label, d, a, self.base.taught_frame, self.base.taught_frame)
                for label, d, a in self.base.conflicts]

    def to_dict(self):
        """dict for JSON: the report's, ``cell``, ``cycle_time_s`` (null when the check
        failed) and ``cycle_time``, ``robot_base_taught_frame``."""
        return dict(self.report.to_dict(), cell=self.cell, cycle_time_s=self.cycle_time_s,
                    cycle_time=self.cycle_time,
                    robot_base_taught_frame=None if self.base is None else self.base.taught_frame,
                    notes=self.notes())

    def lines(self):
        """Printable lines: the findings (grouped), the summary and, when the check
        passed, the cycle time."""
        out = self.report.lines() + self.notes()
        if self.ok:
            out.append("Cycle time: %.1f s%s." % (
                self.cycle_time["total_s"], "" if self.cycle_time["complete"] else
                " (without the first joint move: no StartJoints)"))
        return ["%s: %s" % (self.cell, line) for line in out]


def _cell_frames(cell):
    """The calibration frames `cell`'s paths use, in path order (the cell's own frame
    when it has no paths), read as reader.read_cell reads them (FrameSpec)."""
    own = getattr(cell, "CalibrationFrame", None)
    frames = [getattr(p, "CalibrationFrame", None) or own for p in reader.cell_paths(cell)] or [own]
    out, seen = [], set()
    for frame in frames:
        if frame is not None and frame.Name not in seen:
            seen.add(frame.Name)
            out.append(reader.frame_spec(frame))
    return out


def _robot_base(cell):
    """playback.RobotBase of `cell`: its Placement and its frames, no paths read."""
    return playback.effective_base(reader.object_pose(cell),
                                   [(f.label, f.T_u_b, f.T_r_b) for f in _cell_frames(cell)])


def robot_base(cell):
    """Where `cell`'s robot stands relative to its part, as every command sees it.

    Without a taught calibration frame: the cell's Placement.  With one
    (UseTaught): ``T_u_b @ inv(T_r_b)`` of the frame as drawn and as taught
    (the part is where the robot measured it, so the robot stands there
    relative to the drawn part, wherever the cell's Placement puts it).
    Several taught frames: the first in path order decides
    (``robots.motion.playback.effective_base``).  Check, Simulate, Sensor run, the
    sweep, the simulation player and the 3D view all use this.

    Returns
    -------
    FreeCAD.Placement
        The robot base {R} in {U}.
    """
    _check_type(cell, "Cell", "cell")
    return placement_from_matrix(_robot_base(cell).T_u_r)


def taught_frame_labels(cell):
    """Labels of `cell`'s calibration frames in use that are taught (UseTaught), in path order."""
    _check_type(cell, "Cell", "cell")
    return [f.label for f in _cell_frames(cell) if f.T_r_b is not None]


def taught_frame_note(cell, frame_label):
    """What a taught frame means for moving `cell`'s robot, and how to plan with the drawn frame."""
    return cell_module.taught_frame_note(cell.Label, frame_label)


def check(cell, collisions=True, progress=None):
    """Check that the robot can run `cell`'s program.

    Parameters
    ----------
    collisions : bool
        Also check the robot's links and tool against every solid of the
        document (CadRobot's own objects excluded).  Without python-fcl they
        are left out: the report's ``not_checked`` says so, and a warning
        says it once per session.
    progress : callable, optional
        ``progress(fraction, text)``, told often (``core.progress``); return
        False to stop: :data:`Cancelled` is raised.  The document is only
        read, so a cancelled check leaves it as it was.

    Returns
    -------
    CellCheck
    """
    progress = core_progress.or_ambient(progress)
    program, model, solution = _solved(cell, stage(progress, 0.0, 0.35))
    robot_base_ = playback.robot_base(program, matrix_from_placement(base.global_placement(cell)))
    # The moves sampled once, for the checks and the cycle time (default margins both).
    sampled = move_sampling.sample_program(program, model, solution, checks.Margins(),
                                           progress=stage(progress, 0.35, 0.5))
    report = checks.check_program(program, model, solution, sampled=sampled,
                                  T_u_r=robot_base_.T_u_r, progress=stage(progress, 0.5, 0.6))
    if collisions:
        # The drawing as the robot meets it: with a taught frame the robot stands where the
        # teaching puts it relative to the part (as the player draws it), else at cell.Placement.
        T_r_u = frames.invert_transform(robot_base_.T_u_r)
        solids = obstacles.solid_meshes(cell.Document, T_r_u, _obstacle_objects(cell.Document),
                                        progress=stage(progress, 0.6, 0.65))
        if solids and not collision.is_available():
            dependencies.warn_missing(collision.FCL_PACKAGE)
            report.not_checked["collisions"] = dependencies.reason(collision.FCL_PACKAGE)
        elif solids:
            checker = collision.RobotCollisionChecker(model, solids,
                                                      **collision.tool_arguments(program.tool))
            report.findings += collision.program_collision_findings(
                solution, checker, progress=stage(progress, 0.65, 0.95))
            report.findings.sort(key=lambda f: f.move_index)
    cycle = timing.cycle_time(program, model, solution, sampled=sampled,
                              progress=stage(progress, 0.95, 1.0))
    report_now(progress, 1.0, "done")
    return CellCheck(cell.Label, program, solution, report, cycle, robot_base_)



# --- robot placement ------------------------------------------------------------------------

#: Raised by every long call when its ``progress`` callback returns False
#: (``core.progress.Cancelled``, an error with exit code 130).
Cancelled = core_progress.Cancelled
#: The same class (older name, from :func:`place_robot`).
SearchCancelled = placement.SearchCancelled


def place_robot(cell, region=None, z_mm=None, turn_deg=None, step_mm=None, z_step_mm=None,
                turn_step_deg=None, margin_deg=5.0, singularities=True, count=5, collisions=True,
                weights=None, face=None, progress=None):
    """Search where `cell`'s robot can stand to run the cell's program.

    Candidate bases lie on a grid over a rectangle of the floor (or a
    horizontal face), at one or more heights, turned about Z.  Every base is
    screened against every target of every path at once (vectorised inverse
    kinematics: each target reachable, each path in one arm configuration,
    every joint `margin_deg` inside its limits, away from singularities);
    the best that pass are then checked in full, as :func:`check` does
    (moves sampled, joint speeds, collisions with the document's solids),
    until `count` pass.  See ``robots/placement/placement.py`` and
    ``robots/placement/placement_search.py``.

    The score (higher is better, in [0, 1])::

        0.4 * fastest cycle time / cycle time
      + 0.3 * min(1, joint-limit margin / 45 deg)
      + 0.3 * manipulability

    cycle time from :func:`check` (``robots.motion.timing``); joint-limit margin =
    the smallest distance of a joint from its nearer limit over all targets;
    manipulability = the smallest over all targets of ``sin(elbow) *
    sin(wrist) * min(1, shoulder / (reach / 2))`` (the factors of ``|det J|``
    of a spherical-wrist arm; 0 at a singularity).  ``fastest`` is the best
    of the bases that pass.

    Parameters
    ----------
    cell : Cell
    region : sequence of 4 float, optional
        ``(xmin, ymin, xmax, ymax)`` in {U}, mm.  Needed unless `face` is given.
    z_mm : (float, float), optional
        Height range of the base, mm; default the cell's present height
        (with `face`: the face's height).
    turn_deg : (float, float), optional
        Range of the base's turn about Z of {U}, degrees; default: at each
        position the robot faces the centre of the targets.
    step_mm, z_step_mm, turn_step_deg : float, optional
        Grid steps; defaults: the region's longer side / 20, 5 heights, 30 deg.
    margin_deg : float
        Least distance of every joint from its limits at every target, deg.
    singularities : bool
        Refuse bases where a target (or a move) comes within the check's
        singularity margins (those of its warnings).
    count : int
        How many passing bases to find.
    collisions : bool
        Check collisions with the document's solids (needs python-fcl;
        without it they are left out and ``not_checked`` says so).
    weights : (float, float, float), optional
        Weights of cycle time, joint-limit margin and manipulability.
    face : (App.DocumentObject, str), optional
        ``(obj, "FaceN")``: a horizontal face the robot stands on; only grid
        positions on it are searched, at its height; its bounding box is the
        default region.
    progress : callable, optional
        ``progress(fraction, text)``; return False to stop (raises
        :data:`SearchCancelled`, the same class as :data:`Cancelled`).

    Returns
    -------
    robots.placement.placement_search.Placements
        A list of candidates best first: each with ``.placement`` (the robot
        base in {U}, a FreeCAD.Placement), ``.score``, ``.parts`` (the
        score's parts), ``.report`` (the full check); and ``.failures`` (the
        failing bases that came closest, each with ``.reason``: what failed
        where), ``.counts``, ``.heat`` (for drawing), ``.lines()``,
        ``.to_dict()``.  Empty when no base works.

    Raises
    ------
    InputError
        A bad region, range or step; a cell without paths; a robot not in
        the catalog; a taught calibration frame (the part is where the robot
        measured it, wherever the robot stands).
    """
    _check_type(cell, "Cell", "cell")
    spec = reader.read_cell(cell)
    taught = [f for f in spec.frames.values() if f.T_r_b is not None]
    if taught:
        frame = taught[0]
        raise FrameError(taught_frame_note(cell, frame.label) + " Place robot searches only "
                         "with drawn frames.", frame.name)
    program = core_generate.generate(spec)
    model = models.model(program.robot)
    name = "Cell %s" % base.describe(cell)
    floor = None
    if face is not None:
        floor, face_box, face_z = floor_face.floor_face(face)
        region = face_box if region is None else region
        z_mm = (face_z, face_z) if z_mm is None else z_mm
    if region is None:
        raise InputError("%s: give the region to search, (xmin, ymin, xmax, ymax) in mm, or a face "
                         "for the robot to stand on." % name, cell.Name)
    if int(count) < 1:
        raise InputError("%s: count must be at least 1, not %r." % (name, count), cell.Name)
    space = placement.make_space(region, matrix_from_placement(cell.Placement), z_mm, turn_deg,
                                 step_mm, z_step_mm, turn_step_deg, name=name)
    if floor is not None:
        space.xy_mask = floor_face.positions_on(floor, space.x_mm, space.y_mm, float(space.z_mm[0]))
        if not space.xy_mask.any():
            raise InputError("%s: no grid position lies on the face; use a smaller step." % name,
                             cell.Name)
    solids = (obstacles.solid_meshes(cell.Document, np.eye(4), _obstacle_objects(cell.Document))
              if collisions else [])
    if solids and not collision.is_available():
        dependencies.warn_missing(collision.FCL_PACKAGE)
    criteria = placement.Criteria(margin_deg=validate.number_in_range(margin_deg, name + ": margin_deg",
                                                                      0.0, 180.0))
    if not singularities:
        criteria.shoulder_mm = criteria.elbow_deg = criteria.wrist_deg = None
    result = placement_search.search(
        program, model, space, solids, _start_joints(cell), criteria,
        placement.Weights(*weights) if weights is not None else None, int(count), progress=progress)
    for candidate in list(result) + result.failures:
        candidate.placement = placement_from_matrix(candidate.T_u_r)
    return result


def set_robot_placement(cell, placement):
    """Stand `cell`'s robot at `placement` (e.g. ``place_robot(cell, ...)[0].placement``).

    Parameters
    ----------
    placement : FreeCAD.Placement or array_like (4, 4)
        The robot base {R} in {U}, mm.

    Returns
    -------
    FreeCAD.Placement
        The cell's new Placement.
    """
    _check_type(cell, "Cell", "cell")
    cell.Placement = _placement(placement, "Cell %s" % base.describe(cell), obj_name=cell.Name,
                                placement=ROBOT_BASE)
    cell.Document.recompute()
    return cell.Placement


def simulate(cell, sensor="laser", deviation=None, rate_hz=None, controller="pi", progress=None,
             **options):
    """Run a cell's (first) path with a sensor correcting it in a real cell
    that differs from the drawing (paper section 4).

    Parameters
    ----------
    sensor : str
        ``"laser"`` (seam tracking, 5 Hz by default) or ``"force"``
        (profile following with a ball tool, 20 Hz by default).
    deviation : FreeCAD.Placement, 4x4 array or (x, y, z, rx, ry, rz), optional
        Rigid displacement of the real workpiece from its CAD pose, in {U}.
        Six numbers are mm and degrees (about the fixed X, Y, Z axes), the
        rotation turning the part about the path's start.
    rate_hz : float, optional
        Correction rate.
    controller : str
        ``"pi"``, ``"fuzzy_pi"`` or ``"none"`` (open loop, for comparison).
    progress : callable, optional
        ``progress(fraction, text)``, told often (``core.progress``); return
        False to stop: :data:`Cancelled` is raised.  Nothing is written into
        the document.
    **options
        ``path`` (label), ``foreign_objects`` (document solids in the real
        cell only), reality settings (``roughness_mm``, ``laser_noise_mm``,
        ``force_noise_n``, ``bend_mm``, ``seed``), ``dt_s``, and options of
        the sensor loop (limits, ``on_failure="abort"|"reactive"``, ...).

    Returns
    -------
    sensors.run.SensorRun
        ``time_s``, ``nominal_mm``, ``actual_mm``, ``correction_mm``,
        ``force_n``, ``metrics``, ``aborted``, ``reason``, ``notes`` (said once
        in the summary: the sensor does not suit the path, see
        :func:`sensor_fit`, or the cell's tool is not the one it needs; the
        run still runs as asked), ...
    """
    progress = core_progress.or_ambient(progress)
    _check_type(cell, "Cell", "cell")
    return simulation.simulate_cell(cell, sensor, (controller,), deviation, rate_hz,
                                    progress=progress, **options)[2][0]


def sensor_fit(cell, path=None):
    """Which sensor suits the path Sensor run would use: is there a joint a
    laser can track (butt, fillet, lap, V-groove), or a surface to follow
    with force?

    Parameters
    ----------
    cell : App.DocumentObject
        A CadRobot cell.
    path : str, optional
        Label or name of the path; default the cell's first.

    Returns
    -------
    sensors.joint_detection.JointDetection
        ``.kind`` (``"butt"``, ``"fillet"``, ``"lap"``, ``"v_groove"``,
        ``"surface"``, ``"convex_edge"`` or ``"none"``), ``.sensor``
        (``"laser"``, ``"force"`` or None), ``.fraction`` of the path's
        length where the kind holds, ``.reason`` (one sentence),
        ``.why_not(sensor)``, ``.template()`` (the laser's joint template).
    """
    _check_type(cell, "Cell", "cell")
    return joint_faces.detect(cell, path)


def user_post_dirs():
    """Folders searched for user posts ``<name>_post.py``: FreeCAD's macro
    folder and the ``PostFolder`` preference."""
    dirs = [FreeCAD.getUserMacroDir(True)]
    extra = preferences.get("PostFolder")
    if extra:
        dirs.append(extra)
    return [d for d in dirs if d and os.path.isdir(d)]


def post_names():
    """Names of every post-processor available (built-in and user posts)."""
    return posts.names(extra_dirs=user_post_dirs())


def robot_names():
    """Names of every robot a user can pick: the catalog's and the imported ones."""
    preferences.use_user_robot_folder()
    return catalog.names()


def import_robot(path, name=None, maker=None, j23_factor=None):
    """Register the six-axis arm of a URDF file; it stays in the catalog in later sessions.

    The file's serial chain from its root link to ``tool0`` (else its last
    link) is read and its kinematics recognised (OPW or UR type); the model
    is compared with the URDF's own chain on 1000 random joint sets within
    the limits and refused when they differ by more than 1e-6 mm or 1e-9 rad.
    Joint limits and speeds come from the file (placeholder speeds are
    flagged in the robot's notes); link solids are the convex hulls of its
    collision meshes (found beside the file; simple solids otherwise).

    Parameters
    ----------
    path : str
        A ``.urdf`` file, or a ``.xacro`` file when the Python package
        ``xacro`` is installed.
    name : str, optional
        Catalog name; default from the URDF's robot name.  Importing again
        under the same name replaces the earlier import.
    maker : str, optional
        Default: guessed from the file (its robot name and mesh paths); it
        chooses the default post-processor.
    j23_factor : int, optional
        ``k`` of the controller's ``J3 = q3 + k * q2`` in the file's joints: 1 for
        a parallel-arm robot whose controller counts J3 against the base (ABB's
        J23_coupled), -1 for FANUC's J3 from the horizontal, 0 when the
        controller's joints are the file's.  Default: the maker's convention
        (``robots.catalog.makers``).

    The robot is stored in the user robot folder
    (``preferences.user_robot_folder()``: ``$CADROBOT_ROBOT_FOLDER``, else the
    ``UserRobotFolder`` preference, else ``CadRobot/robots`` in FreeCAD's user
    data folder) as ``NAME.csv`` (a row of the catalog table, editable: limits,
    speeds, payload) and ``NAME.npz`` (link hulls).

    Returns
    -------
    str
        The catalog name it registered; its ``fk``/``ik`` take the URDF's joint
        values (degrees), base = the URDF's root link, flange = ``tool0``.

    Raises
    ------
    InputError
        The file cannot be read, is not a six-axis arm, its kinematics is
        neither OPW nor UR type (the message says what it is), or `name` is a
        built-in robot's.
    """
    from .robots.urdf import from_urdf
    folder = preferences.user_robot_folder()
    if not os.path.isfile(path):
        raise InputError("There is no file '%s': give the path of a .urdf file." % path)
    robot = from_urdf.read_robot(path)
    maker = from_urdf.guess_maker(robot) if maker is None else maker
    name = name or from_urdf.name_from(robot.name or os.path.splitext(os.path.basename(path))[0])
    if not re.fullmatch(r"[A-Za-z0-9_]+", name):
        raise InputError("Robot name '%s': use letters, digits and _ only (e.g. '%s')."
                         % (name, from_urdf.name_from(name)))
    if name in catalog.builtin_names():
        raise NameTakenError("'%s' is the name of a robot that ships with CadRobot: import the "
                             "file under another name (name='MY_%s', or --name on the command "
                             "line)." % (name, name), "MY_" + name)
    default_post, maker_j23 = from_urdf.maker_defaults(maker, robot.name)
    if j23_factor is None:
        j23_factor = maker_j23
    elif j23_factor not in (-1, 0, 1):
        raise InputError("j23_factor must be -1, 0 or 1, not %r." % (j23_factor,))
    imported = from_urdf.spec_from_urdf(
        path, name, maker=maker, model=robot.name, j23_factor=j23_factor,
        payload_kg=from_urdf.payload_from_model(maker, robot.name),
        default_post=default_post, source=os.path.abspath(path), robot=robot)
    from_urdf.save_user_robot(imported, folder)
    catalog.set_user_folder(folder)
    catalog.forget_user_robots()
    return name


def program_files(cell, post=None, options=None, check_first=True, progress=None):
    """The files :func:`export` would write for `cell`; nothing is written.

    Parameters
    ----------
    post : str, optional
        Post-processor name; default the cell's ``PostProcessor``.
    options : dict, optional
        Post-specific options (``date`` defaults to now, or SOURCE_DATE_EPOCH).
    check_first : bool
        Run :func:`check` first and raise FindingError if it finds an error.
        False makes the program whatever the robot can do.
    progress : callable, optional
        ``progress(fraction, text)``, told often (``core.progress``); return
        False to stop: :data:`Cancelled` is raised.

    Returns
    -------
    list of (str, str)
        File name and text, in the post's order.
    """
    progress = core_progress.or_ambient(progress)
    _check_type(cell, "Cell", "cell")
    module = posts.get(cell.PostProcessor if post is None else post, extra_dirs=user_post_dirs())
    options = dict(options or {})
    options.setdefault("date", _export_date())
    if check_first:
        result = check(cell, progress=stage(progress, 0.0, 0.9))
        if not result.ok:
            errors = result.report.errors
            raise FindingError(
                "Cell %s: %d problem(s) the robot cannot run, first: %s Run 'cadrobot check' for "
                "all of them, or export without checking." % (base.describe(cell), len(errors),
                                                               errors[0].message), cell.Name)
        program = result.program
    else:
        program = generate(cell, progress=stage(progress, 0.0, 0.9))
    report_now(progress, 0.9, "writing the program (%s)" % module.__name__.rsplit(".", 1)[-1])
    files = posts.run(module, program, options)
    report_now(progress, 1.0, "done")
    return files


def export(cell, post=None, output_dir=".", options=None, check_first=True, progress=None):
    """Generate `cell`'s program and write it with post-processor `post`.

    Parameters
    ----------
    post : str, optional
        Post-processor name; default the cell's ``PostProcessor``.
    output_dir : str
        Created if missing; files are written all-or-nothing.
    options : dict, optional
        Post-specific options.
    check_first : bool
        Run :func:`check` first and write nothing if it finds an error
        (FindingError). False writes the program whatever the robot can do.
    progress : callable, optional
        ``progress(fraction, text)``, told often (``core.progress``); return
        False to stop: :data:`Cancelled` is raised and nothing is written.

    Returns
    -------
    list of str
        Paths of the written files.
    """
    progress = core_progress.or_ambient(progress)
    files = program_files(cell, post=post, options=options, check_first=check_first,
                          progress=progress)
    return fileio.write_files_atomically(output_dir, files)


def edit_robot(name, joint_min_deg=None, joint_max_deg=None, joint_speed_deg_s=None,
               payload_kg=None, j23_factor=None):
    """Change the limits, speeds, payload or J2/J3 convention of an imported robot.

    Parameters
    ----------
    name : str
        A robot imported with :func:`import_robot` (robots that ship with
        CadRobot keep their data).
    joint_min_deg, joint_max_deg, joint_speed_deg_s : sequence of 6 float, optional
        Degrees and degrees per second, in the controller's convention.
    payload_kg : float, optional
    j23_factor : int, optional
        -1, 0 or 1 (see :func:`import_robot`).

    Returns
    -------
    RobotSpec
        The robot as stored now.

    Raises
    ------
    InputError
        Not an imported robot, or a value out of range (nothing is changed).
    """
    import dataclasses

    from .robots.catalog import catalog_table
    preferences.use_user_robot_folder()
    spec = catalog.get(name)
    path = os.path.join(catalog.user_folder(), name + ".csv")
    if name in catalog.builtin_names() or not os.path.isfile(path):
        raise InputError("Robot %s ships with CadRobot: its data stay as they are. Import its "
                         "URDF under another name to change them." % name)
    changes = {}
    for field, values in (("joint_min_deg", joint_min_deg), ("joint_max_deg", joint_max_deg),
                          ("joint_speed_deg_s", joint_speed_deg_s)):
        if values is not None:
            values = tuple(float(v) for v in values)
            if len(values) != 6 or not all(np.isfinite(values)):
                raise InputError("Robot %s: %s needs 6 numbers, not %r." % (name, field, values))
            changes[field] = values
    low = changes.get("joint_min_deg", spec.joint_min_deg)
    high = changes.get("joint_max_deg", spec.joint_max_deg)
    if any(a >= b for a, b in zip(low, high)):
        raise InputError("Robot %s: every joint's minimum must be below its maximum (%s, %s)."
                         % (name, low, high))
    if any(v <= 0 for v in changes.get("joint_speed_deg_s", (1,))):
        raise InputError("Robot %s: joint speeds must be positive." % name)
    if payload_kg is not None:
        changes["payload_kg"] = float(payload_kg)
    if j23_factor is not None:
        if j23_factor not in (-1, 0, 1):
            raise InputError("Robot %s: j23_factor must be -1, 0 or 1, not %r." % (name, j23_factor))
        changes.update(j23_coupled=bool(j23_factor), j23_factor=j23_factor or 1)
    edited = [f for f in ("joint_speed_deg_s", "j23_factor") if f in changes]
    changes["uncertain"] = tuple(f for f in spec.uncertain if f not in edited)
    spec = dataclasses.replace(spec, **changes)
    catalog_table.write_table(path, [catalog_table.row_from_spec(spec, os.path.basename(spec.meshes))])
    catalog.forget_user_robots()
    return catalog.get(name)


def _export_date():
    """Now, or SOURCE_DATE_EPOCH when set (reproducible output, as in reproducible builds)."""
    import datetime
    epoch = os.environ.get("SOURCE_DATE_EPOCH")
    if epoch:
        return datetime.datetime.fromtimestamp(int(epoch), datetime.timezone.utc).replace(tzinfo=None)
    return datetime.datetime.now().replace(microsecond=0)


def robot(name):
    """The kinematic model of catalog robot `name`.

    ``fk(q_deg)``: (N, 6) degrees -> (N, 4, 4) flange poses in {R}, mm;
    ``ik(T_r_f)``: (N, 4, 4) -> (N, 8, 6) degrees, NaN rows where a branch does
    not exist; ``within_limits(q_deg)``; ``spec`` is the catalog entry.
    """
    preferences.use_user_robot_folder()
    return models.model(name)


__all__ = [
    "make_cell", "set_tool", "tool_names", "make_calibration_frame", "make_path", "make_tool_marker",
    "make_risk_area",
    "tool_placement", "find_cells", "generate", "check", "simulate", "export", "post_names", "robot_names", "robot",
    "import_robot", "edit_robot",
    "user_post_dirs", "matrix_from_placement", "placement_from_matrix",
    "frame_placement_from_points", "frame_placement_from_selection", "teach_calibration_frame",
    "taught_frame", "edge_tool_placement", "make_tool_markers_auto", "marker_segment",
    "suggest_risk_areas", "RiskSuggestion", "program_files",
    "place_robot", "set_robot_placement", "SearchCancelled", "Cancelled",
]
