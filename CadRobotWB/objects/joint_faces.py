"""The faces along a cell's path, read from the document for joint detection.

At samples along the path (every ``joint_detection.SAMPLE_STEP_MM`` and at
each segment's middle) this finds the faces of the document's solids whose
surface holds the path there (within ``picking.GAP_TOL_MM``: the plates
either side of a root gap), on which side of the path each reaches, how far,
and whether that side is free (not pressed against another solid), and
hands them to :func:`sensors.joint_detection.detect_joint`.

App layer: FreeCAD and Part, no GUI.
"""

import numpy as np

from ..errors import CadRobotError, InputError
from ..core.segment_orientation import segment_orientations
from ..sensors.joint_detection import (FaceSide, PathSample, SAMPLE_STEP_MM, approaches_at,
                                       detect_joint)
from . import reader
from .base import describe
from .convert import vector_from_array
from .picking import (GAP_TOL_MM, PROBE_MM, _faces_containing, _inside, document_solids, global_shape,
                      nearest_on_face, normal_at)

#: Samples closer than this to a segment's end are moved inside it (corners are ambiguous), mm.
END_MARGIN_MM = 0.5
#: Distances from the path at which a face's reach is probed, mm (lap steps are short).
EXTENT_PROBES_MM = (1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0, 13.0)
#: A probe lies on a face when this close to it, mm.
ON_FACE_MM = 0.01


def cell_path(cell, path=None):
    """The path object Sensor run uses: `path` (label or name), default the cell's first.

    Raises
    ------
    InputError
        The cell has no paths, or none called `path`.
    """
    paths = reader.cell_paths(cell)
    if not paths:
        raise InputError("Cell %s has no paths. Add one with api.make_path or the CadRobot_MarkPath "
                         "command." % describe(cell), cell.Name)
    if path is None:
        return paths[0]
    for p in paths:
        if path in (p.Label, p.Name):
            return p
    raise InputError("Cell %s has no path '%s'. Paths: %s." % (
        describe(cell), path, ", ".join(p.Label for p in paths)), cell.Name)


def sample_stations(segments, step_mm=SAMPLE_STEP_MM):
    """Where to sample a chain of segments: every `step_mm` (the first half a step
    in) and at each segment's middle, kept ``END_MARGIN_MM`` off segment ends.

    Returns
    -------
    list of (float, int, float)
        (path distance mm, 0-based segment index, distance within it mm), sorted.
    """
    stations, start = [], 0.0
    for index, seg in enumerate(segments):
        length = float(seg.length)
        local = set([length / 2.0])
        k = int(np.ceil((start - step_mm / 2.0) / step_mm - 1e-9))
        while k * step_mm + step_mm / 2.0 < start + length:
            local.add(k * step_mm + step_mm / 2.0 - start)
            k += 1
        margin = min(END_MARGIN_MM, length / 4.0)
        for s in sorted(local):
            s = min(max(s, margin), length - margin)
            stations.append((start + s, index, s))
        start += length
    unique = {}
    for station in stations:      # a middle that falls on a step station counts once
        unique.setdefault(round(station[0], 6), station)
    return [unique[key] for key in sorted(unique)]


def _on_face(face, point):
    return nearest_on_face(face, point)[0] <= ON_FACE_MM


def _extent(face, start, into):
    """How far (mm) the face reaches from `start` along `into`, to 0.1 mm (inf past
    the last probe): probes outward, then halves the interval it left the face in."""
    reached = 0.0
    for distance in EXTENT_PROBES_MM:
        if not _on_face(face, start + distance * into):
            low, high = reached, distance
            while high - low > 0.1:
                middle = 0.5 * (low + high)
                low, high = (middle, high) if _on_face(face, start + middle * into) else (low, middle)
            return low
        reached = distance
    return float("inf")


def face_sides(point, tangent, solids):
    """The :class:`FaceSide` of every face touching the path at `point`.

    Parameters
    ----------
    point, tangent : ndarray, shape (3,)
        Path point (mm) and unit travel direction, {U}.
    solids : list of (App.DocumentObject, Part.Shape in {U})

    Returns
    -------
    list of FaceSide
        One per side of the path a face reaches with free space above it.
    """
    import Part
    out = []
    shapes = [shape for _obj, shape in solids]
    vector = vector_from_array(point)
    for obj, shape in solids:
        near = [(i, f) for i, f in enumerate(shape.Faces) if _box(f).isInside(vector)]
        if not near:
            continue
        for face in _faces_containing(Part.Compound([f for _i, f in near]), point, tangent):
            name = next(("Face%d" % (i + 1) for i, f in near if f.isSame(face)), "Face?")
            normal = normal_at(face, point)
            across = np.cross(normal, tangent)
            across /= np.linalg.norm(across)
            gap, nearest = nearest_on_face(face, point)
            others = [s for s in shapes if s is not shape]
            for into in (across, -across):
                if gap > ON_FACE_MM and np.dot(nearest - point, into) < 0:
                    continue                      # the face lies on the other side
                probe = nearest + PROBE_MM * into
                if not _on_face(face, probe) or _inside(probe + PROBE_MM * normal, others):
                    continue                      # no face that way, or pressed against a solid
                out.append((FaceSide(obj.Label, name, normal, into, float(gap)), face, nearest))
    if len({side.solid for side, _f, _n in out}) > 1:    # a lap joint needs two solids
        for side, face, nearest in out:
            side.extent_mm = _extent(face, nearest, side.into)
    return [side for side, _f, _n in out]


def _box(face):
    """The face's bounding box grown by the largest gap a joint may have."""
    box = face.BoundBox
    box.enlarge(GAP_TOL_MM)
    return box


def _tool_laws(cell, path):
    """The tool's orientation law along each segment of `path`
    (:func:`core.segment_orientation.segment_orientations`, as generate turns the
    tool outside risk areas: with the arc when the path's ToolOnArcs says so), or
    None when the path's markers cannot be read."""
    try:
        for found in reader.path_tool_orientations(cell):
            if found.path.Name == path.Name:
                return segment_orientations(found.segments, found.R_u_t, found.marker_s_mm,
                                            found.tool_on_arcs, found.closed)
    except CadRobotError:
        pass
    return None


def _near(shape, box):
    return shape.BoundBox.intersect(box)


def on_edge(edge, point, tangent):
    """(point (3,), unit tangent (3,)) on the source `edge` nearest `point`, the
    tangent along the travel `tangent`: a spline or ellipse segment is read
    as chords, which leave the faces' surfaces by up to the chord tolerance."""
    if edge is None:
        return point, tangent
    try:
        u = edge.Curve.parameter(vector_from_array(point))
        exact = np.array(tuple(edge.valueAt(u)), float)
        direction = np.array(tuple(edge.tangentAt(u)), float)
    except Exception:   # OCC errors by version: keep the chord
        return point, tangent
    norm = np.linalg.norm(direction)
    if norm < 1e-12 or np.linalg.norm(exact - point) > 1.0:
        return point, tangent
    direction /= norm
    return exact, (direction if np.dot(direction, tangent) >= 0 else -direction)


def workpiece_solids(cell):
    """[(obj, shape in {U})]: the cell's Workpiece solids when it names them (as
    the sensor scene does), else every final solid of the document."""
    if getattr(cell, "Workpiece", None):
        return [(o, global_shape(o)) for o in cell.Workpiece]
    return document_solids(cell.Document)


def path_samples(cell, path=None, step_mm=SAMPLE_STEP_MM):
    """(path object, [PathSample]) along the path Sensor run uses.

    The faces come from the solids near the path (:func:`workpiece_solids`:
    the path's own edges' solid among them), so plates of other solids that
    meet the path count for butt, fillet and lap joints.
    """
    import FreeCAD
    path_obj = cell_path(cell, path)
    segments = reader.path_geometry(path_obj)[0]
    stations = sample_stations(segments, step_mm)
    laws = _tool_laws(cell, path_obj)
    approaches = approaches_at(laws, stations) if laws is not None else [None] * len(stations)
    points = np.array([segments[i].point_at(s) for _, i, s in stations])
    box = FreeCAD.BoundBox(vector_from_array(points.min(axis=0)), vector_from_array(points.max(axis=0)))
    box.enlarge(5.0)
    solids = [(o, shape) for o, shape in workpiece_solids(cell) if _near(shape, box)]
    edges = reader.path_geometry(path_obj)[2]
    samples = []
    for (s_path, index, s), point, approach in zip(stations, points, approaches):
        tangent = np.asarray(segments[index].tangent_at(s), float)
        point, tangent = on_edge(edges.get(segments[index].source), point, tangent)
        samples.append(PathSample(s_path, index + 1, point, tangent, approach,
                                  face_sides(point, tangent, solids)))
    return path_obj, samples


#: The cell's tool types (the cell's ToolType property) and the one force following needs.
BALL_TOOL = "Ball tool"


def tool_notes(cell, sensor):
    """Sentences about the cell's tool for `sensor`: force following needs the
    ball tool on the real robot (the cell's ``ToolType``, or a tool marker drawn
    as a ball when the cell has no ToolType)."""
    if sensor != "force":
        return []
    tool_type = getattr(cell, "ToolType", None)
    if tool_type is None:
        if any(getattr(m, "ToolShape", "") == "Ball" for m in reader.cell_markers(cell)):
            return []
        tool_type = "not a ball tool (no tool marker is drawn as a ball)"
    elif tool_type == BALL_TOOL:
        return []
    else:
        tool_type = "the '%s'" % tool_type
    import inspect
    from ..sensors.force_following import simulate_force_following
    radius = inspect.signature(simulate_force_following).parameters["radius_mm"].default
    return ["Force following needs the ball tool on the real robot; the cell's tool is %s: the "
            "simulation assumes the force model's ball (radius %g mm)." % (tool_type, radius)]


def sensor_notes(cell, sensor, detection):
    """The notes a run's summary says once: the sensor asked for does not suit
    the path (`detection`, may be None), and the tool it needs."""
    notes = []
    if detection is not None and detection.sensor is not None:
        note = detection.run_anyway_note(sensor)
        if note:
            notes.append(note)
    return notes + tool_notes(cell, sensor)


def detect(cell, path=None):
    """The :class:`~sensors.joint_detection.JointDetection` of the path Sensor run uses."""
    path_obj, samples = path_samples(cell, path)
    return detect_joint(samples, path_obj.Label)

