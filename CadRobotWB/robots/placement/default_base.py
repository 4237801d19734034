"""Where a new cell's robot stands by default: beside the work, facing it (a rule, no search).

The rule (:func:`default_base`), from the work's box (the paths', else the
solids'), the solids' box and the arm's wrist-centre annulus
(:func:`..checks.reach_advice.annulus`):

* **Side**: in front of the work as FreeCAD's front view shows it (the robot
  on the work's -Y side, looking along +Y), or on its -X side when the work is
  longer in Y than in X (the robot faces the long side).
* **Distance** of axis 1 from the work's centre, horizontally:
  ``shoulder_radial + far / 2`` (the shoulder's offset from axis 1 plus half
  the wrist centre's reach from the shoulder: the middle of the reach, where
  the far and the near side of a part up to the arm's size stay in the
  annulus), but at least far enough that the base's footprint
  (:func:`footprint_radius_mm`) clears the solids' box by
  :data:`CLEARANCE_MM`.
* **Floor**: a solid under that spot and under every other solid (a floor
  slab, a table larger than the robot's distance) is the floor the robot
  stands on, on its top; it is neither the work nor kept clear of.
* **Height** without such a floor: on the bottom of the solids' box, unless
  the work's top is then less than the shoulder height (``shoulder_z``) above
  the base; then lower, with the shoulder (axis 2) level with the work's top,
  as if the part stood on a table of that height.  A robot standing on the
  floor beside a part lying on the floor reaches down to it with its forearm
  near vertical, beyond joint 3's range: the IRB 2400 with the straight torch
  reaches no fillet of an angle cleat on a 10 mm plate from any base on the
  plate's floor (88 bases: 8 sides x 500-1500 mm), and every one from 7 of 8
  sides 500-900 mm away with its base 600 mm lower.
* **Turn**: the robot's +X toward the work's centre.

Arms without annulus (numeric URDF arms) stand half the catalog reach away,
on the floor; arms without a reach at all get no default (None), nor does a
document whose only solid is a floor (one solid under the spot: a part larger
than the robot's distance counts as one).

Pure numpy: never imports FreeCAD.
"""

import functools

import numpy as np

from ..catalog import catalog
from ..checks import reach_advice

#: Least gap between the robot's footprint and the solids' box, mm.
CLEARANCE_MM = 100.0


@functools.lru_cache(maxsize=64)
def _footprint_and_shoulder(name):
    from ..checks import links   # trimesh: only when a default base is asked for
    from ..kinematics import models
    model = models.model(name)
    base_link = links.link_solids(model)[0]         # link 0 = {R}
    radius = float(np.hypot(base_link.vertices[:, 0], base_link.vertices[:, 1]).max())
    ring = reach_advice.annulus(model)
    return radius, ring, catalog.reach_mm(model.spec)


def footprint_radius_mm(robot):
    """Radius of the robot's fixed base (link 0's solid) about axis 1, mm.

    Parameters
    ----------
    robot : str
        A catalog name.
    """
    return _footprint_and_shoulder(robot)[0]


def shoulder_height_mm(robot):
    """Height of axis 2 above the base, mm (0 for an arm without annulus)."""
    ring = _footprint_and_shoulder(robot)[1]
    return 0.0 if ring is None else ring["shoulder_z_mm"]


def reach_distance_mm(robot):
    """Horizontal distance from axis 1 to the work's centre by the rule, mm (None: no reach known).

    ``shoulder_radial + far / 2`` from the wrist-centre annulus, else half the
    catalog reach.
    """
    _radius, ring, reach = _footprint_and_shoulder(robot)
    return _reach_distance(ring, reach)


def model_reach_distance_mm(model):
    """:func:`reach_distance_mm` of a robot model, without its solids (cheap)."""
    return _reach_distance(reach_advice.annulus(model), catalog.reach_mm(model.spec))


def _reach_distance(ring, reach):
    if ring is not None:
        return ring["shoulder_radial_mm"] + max(ring["far_mm"] / 2.0, ring["near_mm"])
    return None if reach is None else reach / 2.0


def side_direction(work_lo, work_hi):
    """Unit vector (3,) from the work's centre toward the robot: -Y, or -X when the
    work's box is longer in Y than in X."""
    size = np.asarray(work_hi, float) - np.asarray(work_lo, float)
    return np.array([-1.0, 0.0, 0.0]) if size[1] > size[0] else np.array([0.0, -1.0, 0.0])


def union_box(boxes):
    """(2, 3) box holding every box of `boxes` (N, 2, 3), or None for none."""
    return None if len(boxes) == 0 else np.array([boxes[:, 0].min(axis=0), boxes[:, 1].max(axis=0)])


def _floors(boxes, spot_xy):
    """(N,) bool: the boxes the robot would stand on at `spot_xy`: under the spot and
    under every other box (top at or below their lowest bottom)."""
    over = ((boxes[:, 0, :2] <= spot_xy) & (spot_xy <= boxes[:, 1, :2])).all(axis=1)
    out = np.zeros(len(boxes), bool)
    for k in np.flatnonzero(over):
        others = np.delete(boxes, k, axis=0)
        out[k] = len(others) == 0 or boxes[k, 1, 2] <= others[:, 0, 2].min() + 1e-6
    return out


def _spot(robot, work, parts):
    """(position (3,) without height, unit vector work -> robot) of the base beside `work`,
    clear of the box `parts` (or None)."""
    centre = work.mean(axis=0)
    away = side_direction(work[0], work[1])
    distance = reach_distance_mm(robot)
    if parts is not None:
        axis = int(np.argmax(np.abs(away)))
        to_edge = centre[axis] - parts[0, axis]      # work's centre to the parts' box edge
        distance = max(distance, to_edge + footprint_radius_mm(robot) + CLEARANCE_MM)
    return centre + distance * away, away


def default_base(robot, solid_boxes, work_box=None):
    """The default robot base {R} in {U} beside the work (rule in the module docstring).

    A solid under the base's spot and under every other solid (a floor, a
    table larger than the robot's distance) is the floor the robot stands on:
    it is neither the work nor kept clear of.

    Parameters
    ----------
    robot : str
        A catalog name.
    solid_boxes : array_like, shape (N, 2, 3)
        Bounding boxes (lower, upper corner) of the document's solids in {U}, mm.
    work_box : array_like, shape (2, 3), optional
        The box of the work (the paths') in {U}, mm; default the solids' box
        (floors left out).

    Returns
    -------
    ndarray, shape (4, 4), or None
        ``T_u_r``: the base on its side of the work, turned about Z only; None
        for no work (no solids, or only a floor) or an arm whose reach the
        catalog does not know.
    """
    if reach_distance_mm(robot) is None:
        return None
    boxes = np.asarray(solid_boxes, float).reshape(-1, 2, 3)
    given = None if work_box is None else np.asarray(work_box, float).reshape(2, 3)
    work = given if given is not None else union_box(boxes)
    if work is None:
        return None
    spot, _away = _spot(robot, work, None)           # where it would stand, clearance aside
    floors = _floors(boxes, spot[:2])
    parts = union_box(boxes[~floors])
    work = given if given is not None else parts
    if work is None:
        return None
    spot, away = _spot(robot, work, parts)
    if floors.any():
        z_mm = boxes[floors, 1, 2].max()
    else:
        bottom = (work if parts is None else parts)[0, 2]
        z_mm = min(bottom, work[1, 2] - shoulder_height_mm(robot))
    T_u_r = np.eye(4)
    T_u_r[:3, 3] = [spot[0], spot[1], z_mm]
    T_u_r[:3, 0] = -away                             # +X of the robot toward the work
    T_u_r[:3, 1] = np.cross([0.0, 0.0, 1.0], -away)
    return T_u_r
