"""Place robot: the search of the robot's base placements for a cell.

Part of the scripting API: :mod:`CadRobotWB.api` re-exports its public names.
"""

import numpy as np

from .. import dependencies, limits
from ..core import generate as core_generate
from ..errors import FrameError, InputError
from ..objects import base, floor_face, obstacles, reader, validate
from ..objects.convert import matrix_from_placement, placement_from_matrix
from ..robots.checks import collision
from ..robots.kinematics import models
from ..robots.placement import placement, placement_search
from .cell import taught_frame_note
from .arguments import Arguments
from .mechanisms import use_external_axes
from .common import obstacle_objects, start_joints


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
    _place_arguments(cell, region, z_mm, turn_deg, step_mm, z_step_mm, turn_step_deg, margin_deg,
                     singularities, count, collisions, weights, face, progress)
    name = "Cell %s" % base.describe(cell)
    count = _checked_sizes(name, region, z_mm, turn_deg, count)
    spec = reader.read_cell(cell)
    taught = [f for f in spec.frames.values() if f.T_r_b is not None]
    if taught:
        frame = taught[0]
        raise FrameError(taught_frame_note(cell, frame.label) + " Place robot searches only "
                         "with drawn frames.", frame.name)
    program = core_generate.generate(spec)
    model = models.model(program.robot)
    # The positioner's values are chosen for the robot as drawn; a track's travel follows
    # each candidate base (robots.placement).
    use_external_axes(cell, spec, program, model, start_joints(cell))
    floor = None
    if face is not None:
        floor, face_box, face_z = floor_face.floor_face(face)
        region = face_box if region is None else region
        z_mm = (face_z, face_z) if z_mm is None else z_mm
    if region is None:
        raise InputError("%s: give the region to search, (xmin, ymin, xmax, ymax) in mm, or a face "
                         "for the robot to stand on." % name, cell.Name)
    space = placement.make_space(region, matrix_from_placement(cell.Placement), z_mm, turn_deg,
                                 step_mm, z_step_mm, turn_step_deg, name=name)
    if floor is not None:
        space.xy_mask = floor_face.positions_on(floor, space.x_mm, space.y_mm, float(space.z_mm[0]))
        if not space.xy_mask.any():
            raise InputError("%s: no grid position lies on the face; use a smaller step." % name,
                             cell.Name)
    solids = (obstacles.solid_meshes(cell.Document, np.eye(4), obstacle_objects(cell.Document))
              if collisions else [])
    if solids and not collision.is_available():
        dependencies.warn_missing(collision.FCL_PACKAGE)
    criteria = placement.Criteria(margin_deg=validate.number_in_range(margin_deg, name + ": margin_deg",
                                                                      0.0, 180.0))
    if not singularities:
        criteria.shoulder_mm = criteria.elbow_deg = criteria.wrist_deg = None
    result = placement_search.search(
        program, model, space, solids, start_joints(cell), criteria,
        placement.Weights(*weights) if weights is not None else None, count, progress=progress)
    for candidate in list(result) + result.failures:
        candidate.placement = placement_from_matrix(candidate.T_u_r)
    return result


def _place_arguments(cell, region, z_mm, turn_deg, step_mm, z_step_mm, turn_step_deg, margin_deg,
                     singularities, count, collisions, weights, face, progress):
    """Check the types of :func:`place_robot`'s arguments (their ranges are checked where
    the search space is made)."""
    args = Arguments("place_robot")
    args.cell(cell)
    args.numbers("region", region, 4, optional=True, expected="None or (xmin, ymin, xmax, ymax) in mm")
    args.numbers("z_mm", z_mm, 2, optional=True, expected="None or a height range (low, high) in mm")
    args.numbers("turn_deg", turn_deg, 2, optional=True, expected="None or a turn range (low, high) in degrees")
    for argument, value in (("step_mm", step_mm), ("z_step_mm", z_step_mm), ("turn_step_deg", turn_step_deg)):
        args.number(argument, value, optional=True, expected="None or a grid step (a number)")
    args.number("margin_deg", margin_deg, expected="an angle in degrees (a number)")
    args.flag("singularities", singularities)
    # count's range (at least 1, and at most the limit of counts) is checked with the search space.
    args.whole_number("count", count, expected="a whole number of robot bases to find")
    args.flag("collisions", collisions)
    args.numbers("weights", weights, 3, optional=True,
                 expected="None or 3 weights (cycle time, joint-limit margin, manipulability)")
    args.sub_element("face", face, optional=True)
    args.callback("progress", progress)


def _checked_sizes(name, region, z_mm, turn_deg, count):
    """`count` as an int once the region, height and turn ranges and `count` are within
    their stated limits (``limits``); InputError naming the argument otherwise."""
    if region is not None:
        limits.numbers_within(region, "%s: region (xmin, ymin, xmax, ymax)" % name,
                              limits.MAX_COORDINATE_MM, "mm")
    if z_mm is not None:
        limits.numbers_within(z_mm, "%s: z_mm (the height range)" % name, limits.MAX_COORDINATE_MM, "mm")
    if turn_deg is not None:
        limits.numbers_within(turn_deg, "%s: turn_deg (the turn range)" % name, limits.MAX_TURN_DEG, "deg")
    return limits.placements(count, "%s: count (placements to find)" % name)
