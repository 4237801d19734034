"""External axes (issue 23): a positioner holding the part, a track carrying the robot,
and how a cell's program uses them (read, values given per marker, chosen).

Part of the scripting API: :mod:`CadRobotWB.api` re-exports its public names.
"""

import numpy as np

from ..core import mechanisms as core_mechanisms
from ..errors import CadRobotError, InputError
from ..objects import base, reader, validate
from ..objects import mechanism as mechanism_object
from ..objects.convert import matrix_from_placement
from ..robots.mechanisms import catalog, choose
from .arguments import Arguments
from .common import as_placement

#: CadRobot objects that cannot ride on a positioner, and what to give instead.
NOT_PARTS = {
    "Cell": "a cell",
    "RobotPath": "a path: give the objects it is drawn on (its Source)",
    "RiskArea": "a risk area: it follows its path",
    "Weld": "a weld: it follows its path",
    "Positioner": "a positioner",
    "Track": "a track",
}


def add_positioner(cell, kind, placement, parts, model=None, name="Positioner"):
    """Add a positioner holding `parts` to `cell`.

    Parameters
    ----------
    cell : App.DocumentObject
        The cell (one positioner per cell).
    kind : {"turntable", "tilt_turn"}
        A turntable (1 axis: turn) or a tilt-and-turn positioner (2 axes:
        tilt, then turn).
    placement : FreeCAD.Placement or array_like, shape (4, 4)
        The positioner's base in the document {U}, mm.
    parts : list of App.DocumentObject
        What rides on its flange: the solids, the objects the paths are drawn
        on. The calibration frames and tool markers of the cell's paths drawn
        on them are added (they ride too). Everything stays where it is drawn:
        the positioner is shown with every axis at 0.
    model : str, optional
        A catalog name (``robots.mechanisms.catalog.names(kind)``); None:
        generic values.
    name : str

    Returns
    -------
    App.DocumentObject
        The Positioner, in the cell's group.

    Raises
    ------
    ArgumentError
        An argument of the wrong type.
    InputError
        A model of another kind or not in the catalog, no parts, a part that
        cannot ride (a path, a weld, a cell...), a second positioner.
    """
    args = Arguments("add_positioner")
    args.cell(cell)
    args.choice("kind", kind, mechanism_object.POSITIONER_KINDS)
    args.placement("placement", placement, "positioner's base")
    parts = _part_objects(args, parts)
    args.text("model", model, optional=True)
    args.text("name", name)
    what = "Positioner '%s'" % name
    _refuse_model(kind, model, what)
    _refuse_parts(parts, what)
    _refuse_second(cell, mechanism_object.POSITIONER, what)
    pl = as_placement(placement, what, placement="base placement")
    obj = _make(cell, mechanism_object.POSITIONER, name, kind, model, pl)
    obj.Parts = parts + companions(cell, parts)
    obj.ShowAt = mechanism_object.zeros(obj)
    cell.Document.recompute()
    return obj


def add_track(cell, length_mm, placement, model=None, name="Track"):
    """Put the robot of `cell` on a linear track.

    The robot stays where it is (the cell's Placement): the track is shown
    with its carriage at the travel nearest the robot base (its ShowAt).

    Parameters
    ----------
    cell : App.DocumentObject
        The cell (one track per cell).
    length_mm : float
        The carriage's travel, mm (> 0).
    placement : FreeCAD.Placement or array_like, shape (4, 4)
        The track's base in the document {U}, mm.
    model : str, optional
        A catalog name (``robots.mechanisms.catalog.names("track")``); None:
        generic values.
    name : str

    Returns
    -------
    App.DocumentObject
        The Track, in the cell's group.

    Raises
    ------
    ArgumentError
        An argument of the wrong type.
    InputError
        A length <= 0, a model not a track, the robot base beyond the
        track's travel or off its carriage (more than ON_CARRIAGE_MM above or
        below its mounting face, or beside it), a second track.
    """
    args = Arguments("add_track")
    args.cell(cell)
    length = args.number("length_mm", length_mm)
    args.placement("placement", placement, "track's base")
    args.text("model", model, optional=True)
    args.text("name", name)
    what = "Track '%s'" % name
    validate.number_in_range(length, "%s: length_mm" % what, low=0.0, low_open=True)
    _refuse_second(cell, mechanism_object.TRACK, what)
    _refuse_model(core_mechanisms.TRACK, model, what)
    pl = as_placement(placement, what, placement="base placement")
    mechanism = catalog.build(core_mechanisms.TRACK, model, T_u_base=matrix_from_placement(pl),
                              length_mm=length)
    travel = _travel_at_robot(mechanism, cell, what)
    _refuse_off_carriage(mechanism, travel, catalog.spec(core_mechanisms.TRACK, model), cell, what)
    obj = _make(cell, mechanism_object.TRACK, name, core_mechanisms.TRACK, model, pl)
    obj.Length = length
    obj.ShowAt = [travel]
    cell.Document.recompute()
    return obj


def _part_objects(args, parts):
    """`parts` checked: a non-empty list of objects of the call's document."""
    if isinstance(parts, (str, bytes)) or not isinstance(parts, (list, tuple)) or not parts:
        args.refuse("parts", "a non-empty list of document objects (the solids, frames and "
                    "markers that ride)", parts)
    return [args.document_object("parts[%d]" % k, p) for k, p in enumerate(parts)]


def _refuse_second(cell, type_name, what):
    for obj in reader.cell_members(cell):
        if base.type_of(obj) == type_name:
            raise InputError("%s: cell %s has a %s already, %s; a cell drives one. Delete it "
                             "first, or add this one to another cell."
                             % (what, base.describe(cell), type_name.lower(), base.describe(obj)),
                             cell.Name)


def _refuse_model(kind, model, what):
    problem = mechanism_object.model_problem(kind, model or "")
    if problem:
        raise InputError("%s: %s" % (what, problem))


def _refuse_parts(parts, what):
    names = set()
    for part in parts:
        kind = base.type_of(part)
        if kind in NOT_PARTS:
            raise InputError("%s: %s is %s, not a part that rides." % (what, base.describe(part),
                                                                       NOT_PARTS[kind]), part.Name)
        if "Placement" not in part.PropertiesList:
            raise InputError("%s: %s has no placement to move: give the solids, frames and "
                             "markers that ride." % (what, base.describe(part)), part.Name)
        if part.Name in names:
            raise InputError("%s: %s is given twice in parts: give it once."
                             % (what, base.describe(part)), part.Name)
        names.add(part.Name)


def companions(cell, parts):
    """The calibration frames and tool markers of the paths of `cell` drawn on `parts`
    (all their sources riding), less those among `parts`, in tree order."""
    names = {p.Name for p in parts}
    riding_paths = {path.Name for path in reader.cell_paths(cell)
                    if path.Source and all(mechanism_object.rides(obj, names)
                                           for obj, _ in path.Source)}
    frame_of = dict((path.Name, frame) for path, frame in reader.path_frames(cell))
    out = [frame_of[name] for name in riding_paths if frame_of[name] is not None]
    for marker_name, governed in reader.governed_segments(cell).items():
        if not isinstance(governed, CadRobotError) and governed.path.Name in riding_paths:
            out.append(cell.Document.getObject(marker_name))
    unique = {obj.Name: obj for obj in out if obj.Name not in names}
    return sorted(unique.values(), key=lambda obj: cell.Document.Objects.index(obj))


def _make(cell, type_name, name, kind, model, placement):
    obj = mechanism_object.make(cell.Document, type_name, name)
    obj.Kind = kind
    obj.Model = model or ""
    obj.Placement = placement
    cell.addObject(obj)
    return obj


def _travel_at_robot(mechanism, cell, what):
    """The travel (mm) at which the carriage of the track `mechanism` is nearest the
    cell's robot base."""
    start = mechanism.T_u_p([0.0])[:3, 3]
    direction = mechanism.T_u_p([1.0])[:3, 3] - start
    robot = reader.object_pose(cell)[:3, 3]
    travel = float((robot - start) @ direction)
    axis = mechanism.axes[0]
    if not axis.lower - 1e-6 <= travel <= axis.upper + 1e-6:
        raise InputError("%s: the robot base of cell %s is %.1f mm along the track, outside its "
                         "travel %g..%g mm: place the track so the robot stands over it."
                         % (what, base.describe(cell), travel, axis.lower, axis.upper), cell.Name)
    return min(max(travel, axis.lower), axis.upper)


#: How far (mm) the robot base may stand above or below the carriage's mounting face.
ON_CARRIAGE_MM = 1.0


def _refuse_off_carriage(mechanism, travel, spec, cell, what):
    """InputError when the cell's robot base does not stand on the carriage of the track
    `mechanism` at `travel` (mm): within ON_CARRIAGE_MM of its mounting face, and over
    the carriage (half its ``carriage_width`` from the rail's line)."""
    T_u_carriage = mechanism.T_u_p([travel])
    robot = reader.object_pose(cell)[:3, 3]
    _, side, up = (robot - T_u_carriage[:3, 3]) @ T_u_carriage[:3, :3]
    half_width = spec["geometry"]["carriage_width"] / 2.0
    if abs(up) <= ON_CARRIAGE_MM and abs(side) <= half_width:
        return
    shift = T_u_carriage[:3, :3] @ np.array([0.0, side if abs(side) > half_width else 0.0, up])
    raise InputError("%s: the robot base of cell %s does not stand on the track's carriage: it is "
                     "%.1f mm %s its mounting face and %.1f mm to its side (the carriage is %g mm "
                     "wide); move the track's base by (%.1f, %.1f, %.1f) mm so the robot stands "
                     "on it." % (what, base.describe(cell), abs(up), "above" if up > -0.05 else "below",
                                 abs(side), 2.0 * half_width, *shift), cell.Name)


# --- the program of a cell with external axes --------------------------------------------------

def use_external_axes(cell, spec, program, model, q_start_deg=None, progress=None):
    """Give `program` the cell's external axes and choose their value at every target.

    Sets ``program.external`` (None without a track or positioner), presets
    ``Target.external`` of the targets on segments governed by a tool marker
    with ExternalAxes, then runs ``choose.choose_external`` (which keeps
    given numbers and chooses the rest) with the positioner's Tolerance
    when one is given (0: the chooser's default).

    Parameters
    ----------
    spec : core.generate.CellSpec
        What `program` was generated from.
    program : core.program.Program
    model : robots.kinematics.models.RobotModel
    """
    external = reader.read_external(cell)
    if external is None:
        return
    external.moving_frames = tuple(program_frame_names(spec, program)[name]
                                   for name in external.moving_frames
                                   if name in spec.frames)
    program.external = external
    for governed, values in reader.marker_external_values(cell, external):
        preset_values(spec, program, governed, values)
    tolerance = {} if external.tolerance_deg is None else {"tolerance_deg": external.tolerance_deg}
    choose.choose_external(program, model, q_start_deg=q_start_deg, progress=progress, **tolerance)


def program_frame_names(spec, program):
    """{calibration frame object name: its name in ``program.frames``}: generate names
    the work frames in the order of ``spec.frames``."""
    return dict(zip(spec.frames, program.frames))


def preset_values(spec, program, governed, values):
    """Set ``Target.external`` of every move (and via) on segments
    ``governed.first..governed.last`` of ``governed.path`` to `values` (K,)."""
    paths = {path_spec.name: path for path_spec, path in zip(spec.paths, program.paths)}
    for move in paths[governed.path.Name].moves:
        if move.segment is not None and governed.first <= move.segment <= governed.last:
            for target in (move.target, move.via):
                if target is not None:
                    target.external = np.array(values, dtype=float)
