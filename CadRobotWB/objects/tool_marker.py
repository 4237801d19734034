"""Tool marker: a simplified tool model placed on a path segment; its
placement is the TCP pose the robot must hold on that segment and on every
following segment up to the next marker (paper section 3, Figure 2)."""

import FreeCAD
import numpy as np
import Part

from .base import Proxy, describe, type_of

#: "Cell tool" draws the cell's tool body (its TCP on the marker); the others
#: are the simple shapes of files saved before the tool library.
CELL_TOOL = "Cell tool"
SHAPES = [CELL_TOOL, "Torch", "Cone", "Ball"]


def tool_shape(style, length_mm, diameter_mm):
    """A simple solid of the tool in its TCP frame: the tip (or the ball's
    centre) at the origin, the body along -Z, so +Z points into the work."""
    length = max(float(length_mm), 4.0)
    radius = max(float(diameter_mm), 0.5) / 2.0
    back = FreeCAD.Vector(0, 0, -1)

    def at(z):
        return FreeCAD.Vector(0, 0, -z)

    if style == "Ball":
        return Part.makeSphere(radius).fuse(Part.makeCylinder(radius / 3.0, length, at(0), back))
    if style == "Cone":
        return Part.makeCone(0.0, radius, length, at(0), back)
    # Torch: wire stick-out at the tip, a nozzle cone, a cylindrical body.
    nozzle = 0.3 * length
    wire = Part.makeCylinder(min(0.6, radius / 2.0), 2.0, at(0), back)
    cone = Part.makeCone(radius * 0.35, radius, nozzle, at(2.0), back)
    body = Part.makeCylinder(radius, length - nozzle - 2.0, at(2.0 + nozzle), back)
    return body.fuse([cone, wire])


class ToolMarker(Proxy):
    """Proxy of a ``Part::FeaturePython`` whose Placement is the TCP pose {T}
    (in its container; the reader uses the global placement)."""

    TYPE = "ToolMarker"
    PROPERTIES = (
        ("App::PropertyEnumeration", "ToolShape", "Tool marker",
         "Shape drawn for the tool: 'Cell tool' is the cell's tool body with its TCP on the marker "
         "(a cell without a tool body: a torch of ToolLength and ToolDiameter)", SHAPES),
        ("App::PropertyLength", "ToolLength", "Tool marker",
         "Length of the drawn tool (Torch, Cone, Ball)", 80.0),
        ("App::PropertyLength", "ToolDiameter", "Tool marker",
         "Diameter of the drawn tool (Torch, Cone, Ball)", 16.0),
        ("App::PropertyLink", "Path", "Assignment",
         "Path this marker belongs to (empty: the path its origin lies on)", None),
        ("App::PropertyInteger", "Segment", "Assignment",
         "Segment number (1-based) this marker sets (0: the segment its origin lies on)", 0),
        ("App::PropertyString", "Governs", "Assignment",
         "Segments whose tool orientation this marker sets: its own and the following ones up to "
         "the next marker (read only, updated on recompute)", ""),
        ("App::PropertyFloatList", "ExternalAxes", "External axes",
         "Values of the cell's external axes (track mm, then positioner deg: E1, E2, ...) on the "
         "segments this marker governs; empty: chosen automatically", None),
    )

    def setup(self, obj):
        obj.setEditorMode("Governs", 1)
        # Written by the cell's recompute: changing it must not touch the marker again.
        obj.setPropertyStatus("Governs", "Output")
        # Files saved before the tool library offer three shapes: add "Cell tool", keep the choice.
        if list(obj.getEnumerationsOfProperty("ToolShape") or []) != SHAPES:
            current = obj.ToolShape
            obj.ToolShape = SHAPES
            obj.ToolShape = current if current in SHAPES else SHAPES[1]

    def execute(self, obj):
        shape = marker_shape(obj)
        shape.Placement = obj.Placement
        obj.Shape = shape
        update_linked_cell(obj)


def marker_cell(marker):
    """The cell `marker` belongs to: the one holding it, else the one holding its Path; or None."""
    cell = holding_cell(marker)
    path = getattr(marker, "Path", None)
    if cell is None and path is not None:
        cell = holding_cell(path)
    return cell


def cell_tool_in_tcp(cell):
    """`cell`'s tool body placed in its TCP frame {T} (a Part.Compound), or None without a body.

    ``T_t_f = inv(T_f_t)`` places the flange: a marker at ``T_u_marker`` then
    draws the tool at ``T_u_marker @ inv(T_f_t)``, its TCP on the marker."""
    from . import tool_body
    from .convert import matrix_from_placement, placement_from_matrix
    try:
        shape = tool_body.cell_tool_shape(cell)
        T_f_t = matrix_from_placement(cell.ToolTCP)
        if shape is None or not np.isfinite(T_f_t).all():
            return None
        placed = shape.copy()
        placed.Placement = placement_from_matrix(np.linalg.inv(T_f_t)).multiply(shape.Placement)
        return Part.makeCompound([placed])
    except Exception as err:  # noqa: BLE001 -- a broken body: the marker falls back to a torch
        FreeCAD.Console.PrintWarning("CadRobot: the tool of %s cannot be drawn: %s\n"
                                     % (cell.Label, err))
        return None


def marker_shape(marker):
    """The shape `marker` draws in its own frame (the TCP frame, +Z into the work)."""
    if marker.ToolShape == CELL_TOOL:
        cell = marker_cell(marker)
        shape = cell_tool_in_tcp(cell) if cell is not None else None
        if shape is not None:
            return shape
        return tool_shape("Torch", marker.ToolLength, marker.ToolDiameter)
    return tool_shape(marker.ToolShape, marker.ToolLength, marker.ToolDiameter)


def cell_markers(cell):
    """Every tool marker that belongs to `cell` (:func:`marker_cell`), in document order."""
    return [o for o in cell.Document.Objects
            if type_of(o) == "ToolMarker" and marker_cell(o) is not None
            and marker_cell(o).Name == cell.Name]


def make(doc, name):
    obj = doc.addObject("Part::FeaturePython", name)
    ToolMarker(obj)
    return obj


def governs_text(governed):
    """The Governs text of a marker: ``"segments 3-17 of Path001"``, or why it sets none.

    Parameters
    ----------
    governed : reader.Governed or CadRobotError
        An entry of :func:`reader.governed_segments`.
    """
    if isinstance(governed, Exception):
        return "nothing: %s" % governed
    first, last = governed.first, governed.last
    where = "segment %d" % first if first == last else "segments %d-%d" % (first, last)
    return "%s of %s" % (where, governed.path.Label)


def update_governs(cell):
    """Set the Governs property of every tool marker of `cell` (only where it changed)."""
    from . import reader  # reader reads these objects; imported when first used
    document = cell.Document
    everything = reader.governed_segments(cell)
    notes = conflict_notes(document, everything)
    for name, governed in everything.items():
        marker = document.getObject(name)
        text = governs_text(governed) + notes.get(name, "")
        if getattr(marker, "Governs", text) != text:
            marker.Governs = text
            if name in notes:       # once per change: a script moved it there, or a file has it
                FreeCAD.Console.PrintWarning("CadRobot: tool marker %s: %s\n" % (describe(marker), text))


def holding_cell(obj):
    """The cell whose group holds `obj`, directly or in a nested group; None if none does."""
    todo, seen = [obj], set()
    while todo:
        child = todo.pop()
        for parent in child.InList:
            if parent.Name in seen or child not in (getattr(parent, "Group", None) or []):
                continue
            if type_of(parent) == "Cell":
                return parent
            seen.add(parent.Name)
            todo.append(parent)
    return None


def update_linked_cell(marker):
    """Governs of the cell of `marker`'s Path, when `marker` lies outside every cell's group.

    A marker in a cell's group is followed by the cell's own recompute
    (:meth:`Cell.execute`); one only linked to a path is not, so it updates that cell."""
    path = getattr(marker, "Path", None)
    if path is None or holding_cell(marker) is not None:
        return
    cell = holding_cell(path)
    if cell is not None:
        update_governs_safely(cell)


def update_governs_safely(cell):
    """:func:`update_governs` from a recompute: a failure is a warning, never a traceback."""
    try:
        update_governs(cell)
    except Exception as err:  # a half-built cell; generating reports what is wrong
        FreeCAD.Console.PrintWarning("CadRobot: tool markers of %s not updated: %s\n"
                                     % (cell.Label, err))


# --- conflicts: a marker on a segment another marker already sets -----------------------------
#
# DESIGN.md: a marker sets the orientation of the segment its origin lies on (or the
# segment it is linked to) and of every following segment up to the next marker. Two
# markers on one segment whose orientations differ leave that segment two orientations;
# generating refuses it.  The functions below find such a conflict when a marker is
# created or moved, and resolve it in one of two ways:
#
# * "replace": the other marker(s) on the segment are deleted;
# * "next":    this marker starts a new stretch at the following segment: its Path and
#              Segment link it to segment k + 1, so segment k keeps the other marker's
#              orientation and this one sets k + 1 up to the next marker.  Possible only
#              when segment k + 1 exists and no other marker sets it.

#: How make_tool_marker treats a conflict: refuse (default), delete the other marker,
#: link the new one to the next segment, or add it anyway (generating then refuses).
ON_CONFLICT = ("error", "replace", "next", "keep")


class Conflict:
    """A marker (placed or proposed) on a segment other markers already set, with another orientation.

    Attributes
    ----------
    name : str
        Label of the marker (placed or about to be).
    others : list of App.DocumentObject
        The tool markers already setting that segment, each with another orientation.
    angles_deg : list of float
        Orientation difference to each of `others`, degrees.
    path : App.DocumentObject
        The RobotPath.
    segment : int
        The segment (1-based) both set.
    next_free : int or None
        The following segment (1-based) when it exists and no other marker sets it
        (where "next" links the marker), else None.
    """

    def __init__(self, name, others, angles_deg, path, segment, next_free, next_blocked=""):
        self.name, self.others, self.angles_deg = name, list(others), list(angles_deg)
        self.path, self.segment, self.next_free = path, int(segment), next_free
        self.next_blocked = next_blocked      # why next_free is None

    def others_text(self):
        """``"'A'"`` or ``"'A' and 'B'"``: the markers already on the segment."""
        names = [describe(o) for o in self.others]
        return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]

    def describe_problem(self):
        """One sentence: which markers set which segment, and by how much they differ."""
        return ("Tool marker '%s' sets segment %d of path %s, which %s already set%s, and their "
                "tool orientations differ by %.2f°."
                % (self.name, self.segment, describe(self.path), self.others_text(),
                   "s" if len(self.others) == 1 else "", max(self.angles_deg)))

    def next_text(self):
        """What "next" does, or why it cannot."""
        if self.next_free is None:
            return "it cannot start a new stretch: %s" % self.next_blocked
        return ("start a new stretch: '%s' is linked to segment %d (its Path and Segment), so "
                "segment %d keeps the orientation of %s and '%s' sets segment %d and the "
                "following ones up to the next marker"
                % (self.name, self.next_free, self.segment, self.others_text(), self.name,
                   self.next_free))


class _Proposed:
    """Stand-in for a marker not created yet: what the reader needs to find its segment."""

    def __init__(self, name, path, segment):
        self.Name = self.Label = name
        self.Path, self.Segment = path, int(segment)


def _segment_markers(cell):
    """What the reader knows about where the cell's markers sit.

    Returns
    -------
    paths, geometries, locators, marked
        ``marked`` maps (path index, segment index), 0-based, to the markers setting it
        (markers whose segment cannot be found are left out: generating reports them).
    """
    from . import reader
    all_paths, markers = reader._paths_and_markers(cell)
    paths, geometries, broken = reader._readable_paths(all_paths)
    marked, _failed = reader._marked_segments(cell, markers, paths, geometries, broken)
    locators = reader._segment_locators(paths, geometries)
    return paths, geometries, locators, marked


def _conflict_at(known, key, R_u_t, name, exclude=()):
    """The Conflict of a marker called `name` with orientation R_u_t (3, 3) on segment
    `key` (path index, segment index), or None; markers named in `exclude` do not count."""
    import numpy as np
    from ..core import rotations
    from . import reader
    paths, geometries, _locators, marked = known
    others, angles = [], []
    for other in marked.get(key, []):
        if other.Name in exclude:
            continue
        angle = rotations.rotation_angle_between(R_u_t, reader.object_pose(other)[:3, :3])
        if angle > reader.MARKER_AGREEMENT_RAD:
            others.append(other)
            angles.append(float(np.degrees(angle)))
    if not others:
        return None
    index, k = key
    following = (index, k + 1)
    taken = [m for m in marked.get(following, []) if m.Name not in exclude]
    if k + 1 >= len(geometries[index][0]):
        blocked = "segment %d is the last of path %s" % (k + 1, describe(paths[index]))
    elif taken:
        blocked = "tool marker %s sets segment %d" % (describe(taken[0]), k + 2)
    else:
        blocked = ""
    return Conflict(name, others, angles, paths[index], k + 1, None if blocked else k + 2, blocked)


def proposed_conflict(cell, T_u_t, name, path=None, segment=0, known=None):
    """The Conflict a new marker at pose T_u_t ((4, 4), {U}, mm) would make, or None.

    None too when the marker would lie on no path (generating reports that) or the
    cell's paths cannot be read. `known` is :func:`_segment_markers` of the cell (made
    when None; pass it to check many proposals at once)."""
    from . import reader
    from ..errors import CadRobotError
    try:
        known = known or _segment_markers(cell)
        paths, geometries, locators, _marked = known
        if not paths:
            return None
        key = reader._marker_segment(_Proposed(name, path, segment), cell, paths, geometries,
                                     tuple(T_u_t[:3, 3]), locators)
    except CadRobotError:
        return None
    return _conflict_at(known, key, T_u_t[:3, :3], name)


def marker_conflict(cell, marker):
    """The Conflict of tool `marker` (already in `cell`) with the other markers, or None."""
    from . import reader
    from ..errors import CadRobotError
    try:
        known = _segment_markers(cell)
        paths, geometries, locators, _marked = known
        if not paths:
            return None
        T_u_t = reader.object_pose(marker)
        key = reader._marker_segment(marker, cell, paths, geometries, tuple(T_u_t[:3, 3]), locators)
    except CadRobotError:
        return None
    return _conflict_at(known, key, T_u_t[:3, :3], marker.Label, exclude=(marker.Name,))


def conflict_error(conflict, added=True):
    """The MarkerError of `conflict` for a script: both markers and the fixes.

    `added` False: nothing was added (make_tool_marker refused); True: the marker
    exists and generating refuses the path until it is fixed."""
    from ..errors import MarkerError
    fixes = ['on_conflict="replace" deletes %s' % conflict.others_text()]
    if conflict.next_free is not None:
        fixes.append('on_conflict="next" links it to segment %d, so it starts a new stretch '
                     'there (segment %d keeps the orientation of %s)'
                     % (conflict.next_free, conflict.segment, conflict.others_text()))
    else:
        fixes.append('on_conflict="next" is not possible (%s)' % conflict.next_text())
    outcome = ("Generating refuses the path until it is fixed." if added
               else "Nothing was added.")
    return MarkerError("%s %s Use %s; or place it on another segment."
                       % (conflict.describe_problem(), outcome, "; ".join(fixes)),
                       conflict.others[0].Name)


def resolve_conflict(conflict, marker, action):
    """Apply `action` ("replace" or "next") to `marker` and the markers of `conflict`.

    "replace" deletes the other markers; "next" links `marker` to ``conflict.next_free``.

    Raises
    ------
    MarkerError
        "next" when the next segment is not free (the message says why).
    """
    from ..errors import MarkerError
    if action == "replace":
        doc = marker.Document
        for other in conflict.others:
            doc.removeObject(other.Name)
    elif action == "next":
        if conflict.next_free is None:
            raise MarkerError("%s Tool marker '%s' %s. Replace %s, or place it on another segment."
                              % (conflict.describe_problem(), conflict.name, conflict.next_text(),
                                 conflict.others_text()), marker.Name)
        marker.Path = conflict.path
        marker.Segment = conflict.next_free
    else:
        raise ValueError("action must be 'replace' or 'next', not %r" % (action,))


def conflict_notes(document, governed):
    """{marker name: "; ..."} for markers sharing a first segment with a marker of
    another orientation: what the Governs text adds (generating refuses them).

    `governed` is :func:`reader.governed_segments` of the cell."""
    import numpy as np
    from ..core import rotations
    from . import reader
    starts = {}
    for name, entry in governed.items():
        if not isinstance(entry, Exception):
            starts.setdefault((entry.path.Name, entry.first), []).append(name)
    notes = {}
    for (_path, first), names in starts.items():
        if len(names) < 2:
            continue
        poses = {n: reader.object_pose(document.getObject(n))[:3, :3] for n in names}
        for name in names:
            clashes = [(other, rotations.rotation_angle_between(poses[name], poses[other]))
                       for other in names if other != name]
            clashes = [(o, a) for o, a in clashes if a > reader.MARKER_AGREEMENT_RAD]
            if clashes:
                notes[name] = "; CONFLICT: %s also set%s segment %d with another orientation (%s): " \
                    "generating refuses it until one is deleted or moved (api.resolve_marker_conflict)" % (
                        ", ".join(describe(document.getObject(o)) for o, _ in clashes),
                        "s" if len(clashes) == 1 else "", first,
                        ", ".join("%.2f°" % np.degrees(a) for _, a in clashes))
    return notes
