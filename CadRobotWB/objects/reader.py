"""Reading the document tree into the core's input (paper section 3.1).

Everything the generator needs is gathered and checked here, so that every
problem is reported once, naming the document object at fault and what to do
about it. Nothing here changes the document.
"""

import os
from collections import deque, namedtuple

import numpy as np
import Part

from ..core import geometry, mechanisms, rotations
from ..core.generate import CellSpec, FrameSpec, PathSpec, RiskAreaSpec
from ..core.mechanisms import ExternalAxes
from ..core.program import ToolData
from ..core.progress import Steps, report_now, stage
from ..errors import (CadRobotError, FrameError, GeometryError, InputError, MarkerError, RiskAreaError,
                      UnknownNameError)
from .. import preferences
from ..robots.catalog import catalog
from .base import describe, global_placement, objects_of_type, type_of
from . import edge_identity, path_cache, robot_path
from . import mechanism as mech_object
from . import obstacles
from .calibration_frame import taught_transform
from .convert import array_from_vector, matrix_from_placement
from .links import missing_link_file, refuse_cycle_in
from .segment_locator import SegmentLocator
from .validate import check_rigid, finite_values

# Two markers on one segment agree when their orientations differ by less than this.
MARKER_AGREEMENT_RAD = np.radians(0.01)


# --- paths -----------------------------------------------------------------------------

def source_edges(path):
    """The edges a path follows, in {U}, with a readable source for each.

    Returns
    -------
    list of (Part.Edge, str)
        Edges with every container placement applied, and names like
        ``"WeldSketch.Edge3"``.
    """
    links = path.Source or []
    if not links:
        raise GeometryError("Path %s has no source geometry. Set its Source to a sketch or edges."
                            % describe(path), path.Name)
    out = []
    for obj, subs in links:
        shape = getattr(obj, "Shape", None)
        if shape is None or shape.isNull() or not shape.Edges:
            _refuse_missing_file(path, obj)
            raise GeometryError(
                "Path %s: source %s has no edges (an empty sketch?). Draw the path in it or "
                "remove it from the path's Source." % (describe(path), describe(obj)), path.Name)
        shape = shape.copy()
        shape.Placement = global_placement(obj)
        subs = [s for s in (subs or []) if s]
        if not subs:
            out.extend((e, "%s.Edge%d" % (obj.Label, i + 1)) for i, e in enumerate(shape.Edges))
            continue
        for sub in subs:
            sub = edge_identity.current_name(path, obj, sub)
            if not sub.startswith("Edge"):
                raise GeometryError(
                    "Path %s: %s.%s is not an edge. Select edges or a whole sketch."
                    % (describe(path), obj.Label, sub), path.Name)
            try:
                edge = shape.getElement(sub)
            except Exception:  # OCC raises a bare Part.OCCError / ValueError by version
                raise GeometryError("Path %s: %s has no %s (was the geometry changed?). "
                                    "Select the path's edges again." % (describe(path), describe(obj), sub),
                                    path.Name) from None
            out.append((edge, "%s.%s" % (obj.Label, sub)))
    return out


def _refuse_missing_file(path, source):
    """GeometryError naming the file when `source` is a link into a document file that
    could not be loaded."""
    missing = missing_link_file(source)
    if missing is not None:
        raise GeometryError(
            "Path %s: source %s links into '%s', which %s. Put the file back there, or link the "
            "path to geometry of this document." % (
                describe(path), describe(source), missing,
                "cannot be read" if os.path.exists(missing) else "does not exist"), path.Name)


def segment_from_edge(edge, source, chord_tol_mm):
    """The core segment of one FreeCAD edge (in the curve's own direction).

    Lines become :class:`geometry.Line`, circles and arcs :class:`geometry.Arc`,
    every other curve (B-spline, Bézier, ellipse, ...) a
    :class:`geometry.Polyline` within `chord_tol_mm`.
    """
    first, last = edge.FirstParameter, edge.LastParameter
    start = array_from_vector(edge.valueAt(first))
    curve = edge.Curve
    if isinstance(curve, (Part.Line, Part.LineSegment)):
        return geometry.Line(start, array_from_vector(edge.valueAt(last)), source=source)
    if isinstance(curve, Part.Circle):
        sweep = last - first  # a circle's parameter is its angle, counter-clockwise about Axis
        center = array_from_vector(curve.Center)
        normal = array_from_vector(curve.Axis)
        return geometry.Arc(center, normal / np.linalg.norm(normal), start, sweep, source=source)
    return geometry.Polyline(sample_edge(edge, chord_tol_mm), kind="spline", source=source)


def sample_edge(edge, chord_tol_mm, probes=5, max_depth=24):
    """Points along `edge` whose chords stay within `chord_tol_mm` of the curve.

    Each chord is checked at `probes` interior parameters and split in two
    while any of them is farther than the tolerance (OCC's own deflection
    sampling may overshoot it slightly).

    Returns
    -------
    ndarray, shape (N, 3)
        From the curve's first to its last parameter, mm.
    """
    def point(t):
        return array_from_vector(edge.valueAt(t))

    def deviation(a, pa, b, pb):
        chord = pb - pa
        length2 = float(chord @ chord)
        worst = 0.0
        for k in range(1, probes + 1):
            q = point(a + (b - a) * k / (probes + 1))
            u = 0.0 if length2 == 0 else min(max(float((q - pa) @ chord) / length2, 0.0), 1.0)
            worst = max(worst, float(np.linalg.norm(q - (pa + u * chord))))
        return worst

    first, last = edge.FirstParameter, edge.LastParameter
    knots = np.linspace(first, last, 9)
    out = [point(first)]
    todo = [(a, b, 0) for a, b in zip(knots[:-1], knots[1:])][::-1]  # intervals, next one last
    while todo:
        a, b, depth = todo.pop()
        pb = point(b)
        if depth < max_depth and deviation(a, out[-1], b, pb) > chord_tol_mm:
            middle = (a + b) / 2.0
            todo += [(middle, b, depth + 1), (a, middle, depth + 1)]
            continue
        out.append(pb)
    return np.array(out)


def path_geometry(path, progress=None):
    """Ordered core segments of a path in {U}, in travel order.

    Read again only when the path or its source geometry changed
    (:mod:`path_cache`); `progress` (:mod:`..core.progress`) is told every few
    edges of a reading.

    Returns
    -------
    segments : list of geometry segments
    closed : bool
    edges : dict of str to Part.Edge
        The FreeCAD edge of each segment's source.
    """
    if progress is None:
        return path_cache.reading(path, _read_path_geometry)
    return path_cache.reading(path, lambda p: _read_path_geometry(p, progress))


def _read_path_geometry(path, progress=None):
    """:func:`path_geometry` read from the document."""
    chord_tol = _positive(path, "ChordTolerance", float(path.ChordTolerance))
    for prop in ("ConnectTolerance", "MarkerTolerance"):
        _positive(path, prop, float(getattr(path, prop)), allow_zero=True)
    pairs = source_edges(path)
    steps = Steps(progress, len(pairs), "reading path '%s'" % path.Label)
    segments = []
    for i, (e, src) in enumerate(pairs):
        steps(i)
        segments.append(segment_from_edge(e, src, chord_tol))
    ordered, closed = geometry.chain_segments(segments, float(path.ConnectTolerance), path.Label)
    if path.Reversed:
        ordered = [s.reversed() for s in reversed(ordered)]
    return ordered, closed, {src: e for e, src in pairs}


def path_edges(path):
    """The FreeCAD edges of a path in {U}, in travel order (for display)."""
    segments, _, edges = path_geometry(path)
    return [edges[s.source] for s in segments]


# --- links that may point to deleted objects ----------------------------------------------

def _linked_frame(obj, what):
    frame = getattr(obj, "CalibrationFrame", None)
    if frame is None and getattr(obj, "CalibrationFrameRef", ""):
        raise FrameError(
            "%s %s refers to calibration frame '%s', which was deleted. Link another frame in its "
            "CalibrationFrame property or create one." % (what, describe(obj), obj.CalibrationFrameRef),
            obj.Name)
    return frame


# --- the cell ----------------------------------------------------------------------------

def cell_members(cell):
    """Every object in the cell's group, nested groups included."""
    out, todo = [], deque(cell.Group)
    while todo:
        obj = todo.popleft()
        out.append(obj)
        todo.extend(getattr(obj, "Group", []) or [])
    return out


def cell_paths(cell):
    """The cell's paths, in tree order."""
    return [o for o in cell_members(cell) if type_of(o) == "RobotPath"]


def _marker_segment(marker, cell, paths, geometries, origin, locators=None):
    """(path index, segment index) that `marker` sets: the path and segment it
    names, or else the segment its origin lies on.

    `locators` (one :class:`SegmentLocator` per path, made when None) find
    that segment without testing every segment of a long path."""
    names = [p.Name for p in paths]
    if marker.Path is not None:
        if marker.Path.Name not in names:
            raise MarkerError(
                "Tool marker %s is linked to path %s, which is not in cell %s. Link it to one "
                "of the cell's paths or clear its Path property."
                % (describe(marker), describe(marker.Path), describe(cell)), marker.Name)
        candidates = [names.index(marker.Path.Name)]
    else:
        candidates = list(range(len(paths)))
    if marker.Segment > 0:
        if len(candidates) != 1:
            raise MarkerError(
                "Tool marker %s sets segment %d but names no path, and cell %s has %d paths. "
                "Set its Path property." % (describe(marker), marker.Segment, describe(cell),
                                            len(paths)), marker.Name)
        i = candidates[0]
        count = len(geometries[i][0])
        if marker.Segment > count:
            raise MarkerError(
                "Tool marker %s sets segment %d, but path %s has %d segments. Set its Segment "
                "between 1 and %d, or 0 to use the segment its origin lies on."
                % (describe(marker), marker.Segment, describe(paths[i]), count, count), marker.Name)
        return i, marker.Segment - 1
    locators = locators or _segment_locators(paths, geometries)
    for i in candidates:
        k = locators[i].segment_of(origin)
        if k is not None:
            return i, k
    distance, i = min((min(s.closest(origin)[0] for s in geometries[i][0]), i) for i in candidates)
    raise MarkerError(
        "Tool marker %s lies %.3f mm from the nearest path %s (tolerance %.3f mm). Move its "
        "origin onto the path, or set its Path and Segment properties."
        % (describe(marker), distance, describe(paths[i]), float(paths[i].MarkerTolerance)),
        marker.Name)


def _segment_locators(paths, geometries):
    """One SegmentLocator per path (its MarkerTolerance), kept with the path's reading."""
    out = []
    for path, (segments, _, _) in zip(paths, geometries):
        tol = float(path.MarkerTolerance)
        out.append(path_cache.derived(path, segments, ("locator", tol),
                                      lambda segments=segments, tol=tol: SegmentLocator(segments, tol)))
    return out


def _paths_and_markers(cell):
    """(paths, tool markers) of `cell`, its group read once (see :func:`cell_markers`)."""
    typed = [(o, type_of(o)) for o in cell_members(cell)]
    paths = [o for o, kind in typed if kind == "RobotPath"]
    markers = [o for o, kind in typed if kind == "ToolMarker"]
    in_group = {o.Name for o in markers}
    # A marker outside the group counts when linked to a path: it is in that path's InList.
    if not any(o.Name not in in_group and type_of(o) == "ToolMarker" for p in paths for o in p.InList):
        return paths, markers
    path_names = {p.Name for p in paths}
    return paths, markers + [o for o in objects_of_type(cell.Document, "ToolMarker")
                             if o.Name not in in_group and o.Path is not None
                             and o.Path.Name in path_names]


def cell_markers(cell):
    """The tool markers of `cell`: those in its group, then those elsewhere
    linked to one of its paths (document order)."""
    return _paths_and_markers(cell)[1]


def _markers_by_segment(cell, paths, geometries):
    """The tool markers of the cell (:func:`cell_markers`), by the segment their origin
    lies on or they name.

    Returns
    -------
    dict of (int, int) to list of (marker, R_u_t (3, 3), origin (3,))
        Keyed by (path index, segment index), both 0-based; {U}, mm.
    """
    locators = _segment_locators(paths, geometries)
    assigned = {}
    for marker in cell_markers(cell):
        T_u_t = object_pose(marker)
        key = _marker_segment(marker, cell, paths, geometries, T_u_t[:3, 3], locators)
        assigned.setdefault(key, []).append((marker, T_u_t[:3, :3], T_u_t[:3, 3]))
    return assigned


def _segments_named(segments, count):
    """``"segment 1 (line, S.Edge1)"`` or ``"segments 1-3 (S.Edge1 to S.Edge3)"``:
    the first `count` segments, with where they come from."""
    if count == 1:
        return "segment 1 (%s, %s)" % (segments[0].kind, segments[0].source)
    return "segments 1-%d (%s to %s)" % (count, segments[0].source, segments[count - 1].source)


def _unoriented_error(path, segments, first_marker=None, first_marked=None):
    """MarkerError for the segments of `path` before `first_marker`, its first
    tool marker, on segment `first_marked` (0-based); all of them without one."""
    count = len(segments) if first_marker is None else first_marked
    named, one = _segments_named(segments, count), count == 1
    if first_marker is None:
        problem = "Path %s has no tool marker, so %s %s no tool orientation." % (
            describe(path), named, "has" if one else "have")
        fix = "Place one on segment 1 (api.make_tool_marker or the CadRobot_ToolMarker command)"
    else:
        problem = "Path %s: %s %s before its first tool marker %s (on segment %d), so %s no " \
            "tool orientation." % (describe(path), named, "comes" if one else "come",
                                   describe(first_marker), first_marked + 1,
                                   "it has" if one else "they have")
        fix = ("Place a tool marker on segment 1 (api.make_tool_marker or the CadRobot_ToolMarker "
               "command), or move %s onto segment 1" % describe(first_marker))
    return MarkerError("%s %s; a marker sets its segment and every following one up to the "
                       "next marker." % (problem, fix), path.Name)


def _agreed_orientation(path, k, markers):
    """R_u_t (3, 3) of the markers on segment `k` (0-based) of `path`, which
    must agree within MARKER_AGREEMENT_RAD."""
    first_marker, R_first = markers[0][:2]
    for other, R_other, _origin in markers[1:]:
        angle = rotations.rotation_angle_between(R_first, R_other)
        if angle > MARKER_AGREEMENT_RAD:
            raise MarkerError(
                "Tool markers %s and %s both set segment %d of path %s but differ by %.2f°. "
                "Delete one or give them the same orientation."
                % (describe(first_marker), describe(other), k + 1, describe(path),
                   np.degrees(angle)), other.Name)
    return R_first


def _segment_orientations(path, index, segments, assigned):
    """One TCP orientation R_u_t (3, 3) per segment: its own marker's, else that of
    the nearest marker before it on the path.

    Raises
    ------
    MarkerError
        Segments before the path's first marker (naming them all), or two
        markers on one segment that disagree.
    """
    marked = sorted(k for i, k in assigned if i == index)
    if not marked:
        raise _unoriented_error(path, segments)
    if marked[0] > 0:
        raise _unoriented_error(path, segments, assigned[(index, marked[0])][0][0], marked[0])
    out, R_u_t = [], None
    for k in range(len(segments)):
        markers = assigned.get((index, k))
        if markers:
            R_u_t = _agreed_orientation(path, k, markers)
        out.append(R_u_t)
    return out


def _marker_positions(index, segments, assigned):
    """Per segment of path `index`, the arc length (mm from the segment's start) of
    the origin of its first tool marker, None where it inherits its orientation."""
    out = [None] * len(segments)
    for (i, k), markers in assigned.items():
        if i == index:
            out[k] = float(segments[k].closest(markers[0][2])[1])
    return out


def _check_orphan_risk_areas(cell):
    for risk in cell_members(cell):
        if type_of(risk) == "RiskArea" and risk.Path is None:
            was = " '%s'" % risk.PathRef if risk.PathRef else ""
            raise RiskAreaError(
                "Risk area %s refers to a path%s that was deleted. Link it to a path in its Path "
                "property or delete it." % (describe(risk), was), risk.Name)


def _risk_areas(path, n_segments, closed=False):
    out = []
    for risk in objects_of_type(path.Document, "RiskArea"):
        if risk.Path is None or risk.Path.Name != path.Name:
            continue
        first, last = int(risk.FirstSegment), int(risk.LastSegment)
        closing = closed and n_segments > 1 and (first, last) == (n_segments, 1)
        if first > last and not closing:
            loop = (" (on this closed path, %d-1 is the corner where the loop closes)" % n_segments
                    if closed else "")
            raise RiskAreaError(
                "Risk area %s: FirstSegment %d comes after LastSegment %d; a risk area covers "
                "consecutive segments first..last%s. Swap them." % (describe(risk), first, last, loop),
                risk.Name)
        if first < 1 or last > n_segments:
            raise RiskAreaError(
                "Risk area %s covers segments %d-%d, but path %s has segments 1-%d. Set FirstSegment "
                "and LastSegment within that range." % (describe(risk), first, last, describe(path),
                                                        n_segments), risk.Name)
        step = _positive(risk, "Step", float(risk.Step), allow_zero=True) or None
        span = _positive(risk, "CornerSpan", float(risk.CornerSpan), allow_zero=True) or None
        out.append(RiskAreaSpec(risk.Name, risk.Label, first, last, step, span, str(risk.AtCorner)))
    return out


#: What each checked type is called in messages, and the error it raises.
_POSE_OWNERS = {"ToolMarker": ("Tool marker", MarkerError), "CalibrationFrame": ("Calibration frame", FrameError),
                "Cell": ("Cell", InputError)}


def _check_orphan_welds(cell):
    from . import weld
    for obj in cell_members(cell):
        if type_of(obj) == "Weld":
            weld.check_path(obj)


def _welds(path, n_segments):
    """The :class:`core.welding.WeldSpec` of every Weld of `path`, in document order."""
    from . import weld
    return [weld.spec_of(obj, n_segments) for obj in objects_of_type(path.Document, "Weld")
            if obj.Path is not None and obj.Path.Name == path.Name]


def object_pose(obj, prop="Placement"):
    """The rigid 4x4 pose of `obj` in {U} (its `prop`, in {U} for ``Placement``), mm.

    Raises
    ------
    InputError
        (MarkerError for a tool marker, FrameError for a calibration frame)
        naming the object when the placement holds NaN or infinity.
    """
    kind, error = _POSE_OWNERS.get(type_of(obj), (type_of(obj) or "Object", InputError))
    placement = global_placement(obj) if prop == "Placement" else getattr(obj, prop)
    what = "%s %s%s" % (kind, describe(obj), "" if prop == "Placement" else " " + prop)
    return check_rigid(matrix_from_placement(placement), what, error, obj.Name)


def _positive(obj, prop, value, allow_zero=False):
    finite_values(value, "%s %s: %s" % (type_of(obj), describe(obj), prop), obj_name=obj.Name)
    if value < 0 or (value == 0 and not allow_zero):
        raise InputError("%s %s: %s must be %s 0." % (type_of(obj), describe(obj), prop,
                                                     ">=" if allow_zero else ">"), obj.Name)
    return value


def frame_spec(frame):
    """The FrameSpec of a calibration frame: drawn, or taught when UseTaught is set
    (FrameError naming the frame when its points cannot be fitted)."""
    taught = taught_transform(frame)
    return FrameSpec(frame.Name, frame.Label, object_pose(frame),
                     T_r_b=None if taught is None else taught[0])


def marker_assignment(cell, marker):
    """(path object, segment number 1-based) that tool `marker` sets in `cell`.

    Raises
    ------
    MarkerError
        The marker names a path outside the cell, a missing segment, or lies
        on no path.
    """
    paths = cell_paths(cell)
    if not paths:
        raise MarkerError("Cell %s has no paths for tool marker %s to set. Add a path first."
                          % (describe(cell), describe(marker)), marker.Name)
    geometries = [path_geometry(p) for p in paths]
    origin = object_pose(marker)[:3, 3]
    index, segment = _marker_segment(marker, cell, paths, geometries, origin)
    return paths[index], segment + 1


# A tool marker's reach on its path: segments first..last (1-based, inclusive).
Governed = namedtuple("Governed", "path first last")


def _readable_paths(cell_paths):
    """(paths, their path_geometry, {name: error} of `cell_paths` that cannot be read)."""
    paths, geometries, broken = [], [], {}
    for path in cell_paths:
        try:
            geometries.append(path_geometry(path))
        except CadRobotError as err:
            broken[path.Name] = err
            continue
        paths.append(path)
    return paths, geometries, broken


def _marked_segments(cell, markers, paths, geometries, broken):
    """({(path index, segment index): [markers]}, {marker name: why it sets no segment})."""
    locators = _segment_locators(paths, geometries)
    marked, failed = {}, {}
    for marker in markers:
        linked = marker.Path.Name if marker.Path is not None else None
        if linked in broken:
            failed[marker.Name] = broken[linked]
        elif not paths:
            failed[marker.Name] = MarkerError(
                "Cell %s has no path that can be read for tool marker %s to set."
                % (describe(cell), describe(marker)), marker.Name)
        else:
            try:
                origin = tuple(object_pose(marker)[:3, 3])
                key = _marker_segment(marker, cell, paths, geometries, origin, locators)
            except MarkerError as err:
                failed[marker.Name] = err
                continue
            marked.setdefault(key, []).append(marker)
    return marked, failed


def governed_segments(cell):
    """The segments whose tool orientation each tool marker of `cell` sets.

    A marker sets the segment it lies on (or names) and every following one
    up to the next marked segment of its path. Nothing is raised: a path that
    cannot be read, or a marker on no path, is reported per marker.

    Returns
    -------
    dict of str to Governed or CadRobotError
        By marker name (every marker of :func:`cell_markers`): its path and
        segments first..last (1-based, inclusive), or why it sets none.
    """
    all_paths, markers = _paths_and_markers(cell)
    paths, geometries, broken = _readable_paths(all_paths)
    marked, out = _marked_segments(cell, markers, paths, geometries, broken)
    for index, path in enumerate(paths):
        starts = sorted(k for i, k in marked if i == index)
        for first, following in zip(starts, starts[1:] + [len(geometries[index][0])]):
            for marker in marked[(index, first)]:
                out[marker.Name] = Governed(path, first + 1, following)
    return out


def path_orientations(cell):
    """[(path, R_u_t per segment, [(first, last) of its risk areas])] of the cell's
    paths, without the checks generating needs beyond them (MarkerError for the
    segments before a path's first tool marker)."""
    paths = cell_paths(cell)
    geometries = [path_geometry(p) for p in paths]
    assigned = _markers_by_segment(cell, paths, geometries)
    out = []
    for index, path in enumerate(paths):
        segments = geometries[index][0]
        areas = [(r.first, r.last) for r in _risk_areas(path, len(segments), geometries[index][1])]
        out.append((path, _segment_orientations(path, index, segments, assigned), areas))
    return out


# One path's tool orientations as generate reads them (see path_tool_orientations).
PathOrientation = namedtuple("PathOrientation",
                             "path segments closed R_u_t marker_s_mm tool_on_arcs risk_areas")


def path_tool_orientations(cell):
    """[PathOrientation] of the cell's paths: segments, closed, R_u_t per segment, the
    markers' arc-length positions, ToolOnArcs and the RiskAreaSpecs, without the checks
    generating needs beyond them (MarkerError for segments before a path's first marker)."""
    paths = cell_paths(cell)
    geometries = [path_geometry(p) for p in paths]
    assigned = _markers_by_segment(cell, paths, geometries)
    out = []
    for index, path in enumerate(paths):
        segments, closed, _ = geometries[index]
        out.append(PathOrientation(path, segments, closed,
                                   _segment_orientations(path, index, segments, assigned),
                                   _marker_positions(index, segments, assigned), str(path.ToolOnArcs),
                                   _risk_areas(path, len(segments), closed)))
    return out


def read_cell(cell, progress=None):
    """Read a cell and everything in it into a :class:`CellSpec`.

    `progress` (:mod:`..core.progress`) is told path by path; returning False
    raises ``Cancelled`` (nothing in the document is changed by reading).

    Raises
    ------
    CadRobotError
        The first problem found, naming the object and the fix.
    """
    preferences.use_user_robot_folder()
    refuse_cycle_in(cell.Document)     # before any shape is read: FreeCAD would crash
    try:
        catalog.get(cell.Robot)
    except UnknownNameError as err:
        raise UnknownNameError("Cell %s: %s" % (describe(cell), err), cell.Name) from None
    cell_frame = _linked_frame(cell, "Cell")
    sample_time = _positive(cell, "SampleTime", float(cell.SampleTime))
    paths = cell_paths(cell)
    if not paths:
        raise InputError("Cell %s has no paths. Add one with api.make_path or the CadRobot_MarkPath "
                         "command." % describe(cell), cell.Name)
    _check_orphan_risk_areas(cell)
    _check_orphan_welds(cell)
    geometries = [path_geometry(p, stage(progress, k / len(paths), (k + 0.9) / len(paths)))
                  for k, p in enumerate(paths)]
    report_now(progress, 0.9, "reading tool markers")
    assigned = _markers_by_segment(cell, paths, geometries)

    frames, specs = {}, []
    for index, path in enumerate(paths):
        frame = _linked_frame(path, "Path") or cell_frame
        if frame is None:
            raise FrameError(
                "Cell %s has no calibration frame for path %s. Create one (api.make_calibration_frame "
                "or CadRobot_CalibrationFrame) and link it in the cell's CalibrationFrame property."
                % (describe(cell), describe(path)), cell.Name)
        frames[frame.Name] = frame_spec(frame)
        segments, closed, _ = geometries[index]
        specs.append(PathSpec(
            name=path.Name, label=path.Label, segments=segments,
            R_u_t=_segment_orientations(path, index, segments, assigned),
            frame=frame.Name,
            speed_mm_s=_positive(path, "Speed", float(path.Speed)),
            zone_mm=_zone_setting(path),
            zone_tolerance_mm=_positive(path, "ChordTolerance", float(path.ChordTolerance)),
            approach_mm=_positive(path, "ApproachDistance", float(path.ApproachDistance), True),
            retract_mm=_positive(path, "RetractDistance", float(path.RetractDistance), True),
            approach_speed_mm_s=_positive(path, "ApproachSpeed", float(path.ApproachSpeed)),
            sample_time_s=sample_time,
            step_mm=_positive(path, "InterpolationStep", float(path.InterpolationStep), True) or None,
            risk_areas=_risk_areas(path, len(segments), closed),
            welds=_welds(path, len(segments)),
            closed=closed,
            marker_s_mm=_marker_positions(index, segments, assigned),
            tool_on_arcs=str(path.ToolOnArcs)))

    tool = read_tool(cell)
    doc = cell.Document
    source = "%s / %s" % (os.path.basename(doc.FileName) or doc.Label, cell.Label)
    return CellSpec(name=cell.ProgramName or cell.Label, label=cell.Label, robot=cell.Robot,
                    T_u_r=object_pose(cell), tool=tool, frames=frames,
                    paths=specs, source=source)


def _zone_setting(path):
    """None (automatic), 0 (fine) or the path's Zone radius (mm, checked)."""
    zone = robot_path.zone_setting(path)
    return zone if zone is None else _positive(path, "Zone", zone, allow_zero=True)


def read_tool(cell):
    """The tool of `cell` as the program carries it: name, TCP, mass, CoG and body.

    Returns
    -------
    ToolData
        ``label`` and ``body_vertices_mm`` / ``body_faces`` (in {F}) from
        :mod:`.tool_body`; no body for a custom tool without a ToolBody.
    """
    from . import tool_body
    body = tool_body.cell_tool_mesh(cell)
    return ToolData(name=cell.ToolName or "tTool",
                    T_f_t=object_pose(cell, "ToolTCP"),
                    mass_kg=_positive(cell, "ToolMass", float(cell.ToolMass)),
                    cog_mm=finite_values(array_from_vector(cell.ToolCenterOfGravity),
                                         "Cell %s ToolCenterOfGravity" % describe(cell),
                                         obj_name=cell.Name),
                    label=tool_body.cell_tool_label(cell),
                    body_vertices_mm=None if body is None else body[0],
                    body_faces=None if body is None else body[1])


# --- external axes (issue 23) -------------------------------------------------------------

def read_external(cell):
    """The track and positioner of `cell`, checked, or None when it has neither.

    Returns
    -------
    core.mechanisms.ExternalAxes or None
        ``T_u_r`` the cell's robot base (the track at its ShowAt);
        ``moving_frames`` the names of the calibration-frame objects riding on
        the positioner (:func:`workflow.mechanisms` turns them into the
        program's frame names), ``riding_solids`` the labels of the document's
        solids riding on it.

    Raises
    ------
    InputError
        Naming the object and the fix: two positioners (or tracks) in the
        cell, a kind or model that is not the object's, ShowAt or fixed
        values of the wrong count, not finite or outside the limits, a
        positioner without parts, a path whose part and calibration frame do
        not both ride (or both stand), a tool marker of a riding path that
        does not ride, a solid standing still that a riding path's seam
        touches.
    """
    found = {kind: [o for o in cell_members(cell) if type_of(o) == kind]
             for kind in (mech_object.TRACK, mech_object.POSITIONER)}
    for objects in found.values():
        if len(objects) > 1:
            raise InputError(
                "Cell %s has two %ss, %s and %s: a cell drives one. Delete one or move it to "
                "another cell." % (describe(cell), type_of(objects[0]).lower(), describe(objects[0]),
                                   describe(objects[1])), objects[1].Name)
    track, positioner = (_read_mechanism(objects[0]) if objects else None
                         for objects in found.values())
    if track is None and positioner is None:
        return None
    _refuse_taught_frames(cell)
    moving, riding, tolerance = (), (), None
    if positioner is not None:
        obj = found[mech_object.POSITIONER][0]
        moving = _moving_frames(cell, obj)
        riding = _riding_solids(obj)
        tolerance = _positive(obj, "Tolerance", float(obj.Tolerance), allow_zero=True) or None
    return ExternalAxes(T_u_r=object_pose(cell), track=track, positioner=positioner,
                        moving_frames=moving, riding_solids=riding, tolerance_deg=tolerance)


def _read_mechanism(obj):
    """The checked core Mechanism of a Positioner or Track object, shown at its ShowAt."""
    what = "%s %s" % (type_of(obj), describe(obj))
    kinds = mech_object.POSITIONER_KINDS if type_of(obj) == mech_object.POSITIONER \
        else (mechanisms.TRACK,)
    kind = str(obj.Kind)
    if kind not in kinds:
        raise InputError("%s: Kind '%s' is not one of %s: make it again with api.add_%s."
                         % (what, kind, ", ".join(kinds), type_of(obj).lower()), obj.Name)
    problem = mech_object.model_problem(kind, str(obj.Model))
    if problem:
        raise InputError("%s: %s" % (what, problem[0].upper() + problem[1:]), obj.Name)
    if type_of(obj) == mech_object.TRACK:
        _positive(obj, "Length", float(obj.Length))
    count = mechanisms.AXIS_COUNTS[kind]
    show_at = _axis_values(obj, "ShowAt", list(obj.ShowAt), count, what)
    try:
        mechanism = mech_object.core_mechanism(obj, show_at, object_pose(obj))
    except InputError as err:
        raise InputError("%s: %s" % (what, err), obj.Name) from None
    _within_limits(obj, mechanism.axes, show_at, "ShowAt", what)
    for axis, value in _fixed_values(obj, mechanism, what).items():
        mechanism.axes[axis].fixed = value
    return mechanism


def _axis_values(obj, prop, values, count, what):
    """`values` of property `prop`, checked: `count` finite numbers, as an ndarray."""
    if len(values) != count:
        raise InputError("%s: %s holds %d values, but a %s has %d axes: give one value per axis "
                         "(base to flange)." % (what, prop, len(values), obj.Kind, count), obj.Name)
    return finite_values(np.array(values, dtype=float), "%s %s" % (what, prop), obj_name=obj.Name)


def _within_limits(obj, axes, values, prop, what):
    """InputError naming `obj` when a value of `prop` is outside its axis's limits."""
    for axis, value in zip(axes, values):
        if not axis.lower <= value <= axis.upper:
            raise InputError("%s: %s puts axis '%s' at %g %s, outside its limits %g..%g: give a "
                             "value within them." % (what, prop, axis.name, value, axis.unit,
                                                     axis.lower, axis.upper), obj.Name)


def _fixed_values(obj, mechanism, what):
    """{axis index (0-based): value} of FixedAxes / FixedValues, checked."""
    axes, values = list(obj.FixedAxes), list(obj.FixedValues)
    count = len(mechanism.axes)
    if len(axes) != len(values) or len(set(axes)) != len(axes) \
            or not all(1 <= a <= count for a in axes):
        raise InputError("%s: FixedAxes %s and FixedValues %s do not match: give distinct axis "
                         "numbers 1..%d and one value for each." % (what, axes, values, count),
                         obj.Name)
    values = finite_values(np.array(values, dtype=float), "%s FixedValues" % what, obj_name=obj.Name)
    _within_limits(obj, [mechanism.axes[a - 1] for a in axes], values, "FixedValues", what)
    return dict(zip([a - 1 for a in axes], values.tolist()))


def _moving_frames(cell, positioner):
    """Names of the calibration frames riding on `positioner`, each path checked: its
    part (the objects it is drawn on) and its frame both ride or both stand, and so
    do the tool markers setting its segments."""
    parts = [p for p in (positioner.Parts or []) if p is not None]
    if not parts:
        raise InputError("Positioner %s holds no parts: set its Parts to the solids, frames and "
                         "tool markers it carries (api.add_positioner(..., parts=[...]))."
                         % describe(positioner), positioner.Name)
    names = {p.Name for p in parts}
    moving = []
    for path, frame in path_frames(cell):
        on_part = _path_rides(path, positioner, names)
        if on_part:
            _refuse_standing_at_seam(path, positioner, names)
        if frame is not None and mech_object.rides(frame, names) != on_part:
            raise InputError(
                "Path %s is drawn on %s, but its calibration frame %s %s: add both to positioner "
                "%s's Parts, or neither." % (
                    describe(path), "the positioner's parts" if on_part else "parts that stand still",
                    describe(frame), "stands still" if on_part else "rides on the positioner",
                    describe(positioner)), path.Name)
        if on_part and frame is not None and frame.Name not in moving:
            moving.append(frame.Name)
    _check_riding_markers(cell, positioner, names)
    return tuple(moving)


#: How near (mm) a solid standing still may come to a riding path before it counts as a part
#: welded to the riding ones.
SEAM_TOUCH_MM = 0.01


def _refuse_standing_at_seam(path, positioner, names):
    """InputError naming the first solid that stands still but touches `path`, which rides
    on `positioner`: the seam joins it to the riding parts, so it must ride too."""
    seam = path.Shape
    if seam.isNull():
        return
    near = seam.BoundBox
    near.enlarge(SEAM_TOUCH_MM)
    for obj in positioner.Document.Objects:
        if not obstacles.is_final_solid(obj) or mech_object.rides(obj, names) \
                or not near.intersect(obj.Shape.BoundBox):
            continue
        if seam.distToShape(obj.Shape)[0] <= SEAM_TOUCH_MM:
            raise InputError("Path %s rides on positioner %s, but its seam touches %s, which stands "
                             "still: add %s to the positioner's Parts (what the seam joins rides "
                             "with it)." % (describe(path), describe(positioner), describe(obj),
                                            describe(obj)), obj.Name)


def _riding_solids(positioner):
    """Labels of the document's final solids (the collision obstacles) riding on `positioner`."""
    names = {p.Name for p in positioner.Parts or [] if p is not None}
    return tuple(o.Label for o in positioner.Document.Objects
                 if obstacles.is_final_solid(o) and mech_object.rides(o, names))


def path_frames(cell):
    """[(path, its calibration frame or None)] of the cell's paths."""
    cell_frame = getattr(cell, "CalibrationFrame", None)
    return [(path, getattr(path, "CalibrationFrame", None) or cell_frame) for path in cell_paths(cell)]


def unused_frames(cell):
    """The calibration frames among `cell`'s members that none of its paths uses
    (:func:`path_frames`) other than the cell's own (the paths' default), in tree order."""
    used = {frame.Name for _path, frame in path_frames(cell) if frame is not None}
    if getattr(cell, "CalibrationFrame", None) is not None:
        used.add(cell.CalibrationFrame.Name)
    return [o for o in cell_members(cell)
            if type_of(o) == "CalibrationFrame" and o.Name not in used]


def _refuse_taught_frames(cell):
    """FrameError naming the first taught frame a path of `cell` (with external axes) uses."""
    for _, frame in path_frames(cell):
        if frame is not None and getattr(frame, "UseTaught", False):
            raise FrameError("Calibration frame %s is taught (UseTaught), but cell %s has external "
                             "axes, which do not move a taught frame yet: clear UseTaught on %s to "
                             "plan with the drawn frame." % (describe(frame), describe(cell),
                                                              describe(frame)), frame.Name)


def _path_rides(path, positioner, names):
    """Whether the objects `path` is drawn on ride on `positioner` (InputError when
    some do and some do not)."""
    sources = [obj for obj, _ in (path.Source or []) if obj is not None]
    riding = [mech_object.rides(obj, names) for obj in sources]
    if any(riding) and not all(riding):
        standing = sources[riding.index(False)]
        raise InputError("Path %s is drawn on objects that ride on positioner %s and on %s, which "
                         "stands still: add %s to the positioner's Parts, or draw the path on one "
                         "part." % (describe(path), describe(positioner), describe(standing),
                                    describe(standing)), path.Name)
    return bool(riding) and all(riding)


def _check_riding_markers(cell, positioner, names):
    """InputError naming the first tool marker whose path rides and it does not (or the
    other way round)."""
    for marker_name, governed in governed_segments(cell).items():
        if isinstance(governed, CadRobotError):
            continue
        marker = cell.Document.getObject(marker_name)
        on_part = _path_rides(governed.path, positioner, names)
        if mech_object.rides(marker, names) != on_part:
            raise InputError(
                "Tool marker %s sets path %s, which %s, but the marker %s: add both to "
                "positioner %s's Parts, or neither." % (
                    describe(marker), describe(governed.path),
                    "rides on the positioner" if on_part else "stands still",
                    "does not" if on_part else "does", describe(positioner)), marker.Name)


def marker_external_values(cell, external):
    """The external axis values tool markers of `cell` give (their ExternalAxes).

    Parameters
    ----------
    external : core.mechanisms.ExternalAxes
        The cell's (:func:`read_external`).

    Returns
    -------
    list of (Governed, ndarray of shape (K,))
        The segments each such marker governs and its values (program order:
        track mm, then positioner deg); markers with none left out.

    Raises
    ------
    InputError
        Naming the marker: not one value per axis, not finite, outside an axis's limits.
    """
    axes = [axis for _, axis in external.axes()]
    governed, out = None, []
    for marker in cell_markers(cell):
        values = list(getattr(marker, "ExternalAxes", None) or [])
        if not values:
            continue
        what = "Tool marker %s" % describe(marker)
        if len(values) != len(axes):
            raise InputError("%s: ExternalAxes holds %d values, but cell %s has %d external axes "
                             "(%s): give one per axis, or none to have them chosen."
                             % (what, len(values), describe(cell), len(axes),
                                ", ".join(external.axis_names())), marker.Name)
        values = finite_values(np.array(values, dtype=float), "%s ExternalAxes" % what,
                               obj_name=marker.Name)
        _within_limits(marker, axes, values, "ExternalAxes", what)
        governed = governed or governed_segments(cell)
        if isinstance(governed[marker.Name], CadRobotError):
            raise governed[marker.Name]
        out.append((governed[marker.Name], values))
    return out
