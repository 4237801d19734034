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
* **Height**: on the floor (the bottom of the solids' box), unless the
  work's centre is then less than the shoulder height (``shoulder_z``) above
  the base; then lower, with the shoulder (axis 2) level with the work's
  centre, as if the part stood on a table of that height.  A robot standing on
  the floor beside a part lying on the floor reaches down to it with its
  forearm near vertical, beyond joint 3's range: the IRB 2400 with the
  straight torch reaches no fillet of an angle cleat on a 10 mm plate from
  any base on the plate's floor (88 bases: 8 sides x 500-1500 mm), and every
  one from 7 of 8 sides 500-900 mm away with its base 600 mm lower.
* **Turn**: the robot's +X toward the work's centre.

Arms without annulus (numeric URDF arms) stand half the catalog reach away,
on the floor; arms without a reach at all get no default (None).

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
    if ring is not None:
        return ring["shoulder_radial_mm"] + max(ring["far_mm"] / 2.0, ring["near_mm"])
    return None if reach is None else reach / 2.0


def side_direction(work_lo, work_hi):
    """Unit vector (3,) from the work's centre toward the robot: -Y, or -X when the
    work's box is longer in Y than in X."""
    size = np.asarray(work_hi, float) - np.asarray(work_lo, float)
    return np.array([-1.0, 0.0, 0.0]) if size[1] > size[0] else np.array([0.0, -1.0, 0.0])


def default_base(robot, work_lo, work_hi, solids_lo=None, solids_hi=None):
    """The default robot base {R} in {U} beside the work (rule in the module docstring).

    Parameters
    ----------
    robot : str
        A catalog name.
    work_lo, work_hi : array_like, shape (3,)
        Corners of the work's box in {U} (the paths', else the solids'), mm.
    solids_lo, solids_hi : array_like, shape (3,), optional
        Corners of the box of all the document's solids in {U}, mm; default the
        work's box.  Its bottom is the floor.

    Returns
    -------
    ndarray, shape (4, 4), or None
        ``T_u_r``: the base on its side of the work, turned about Z only; None
        for an arm whose reach the catalog does not know.
    """
    work_lo, work_hi = np.asarray(work_lo, float), np.asarray(work_hi, float)
    solids_lo = work_lo if solids_lo is None else np.asarray(solids_lo, float)
    solids_hi = work_hi if solids_hi is None else np.asarray(solids_hi, float)
    reach = reach_distance_mm(robot)
    if reach is None:
        return None
    centre = (work_lo + work_hi) / 2.0
    away = side_direction(work_lo, work_hi)
    axis = int(np.argmax(np.abs(away)))
    # Distance from the work's centre to the solids' box edge on the robot's side.
    to_edge = centre[axis] - solids_lo[axis]
    distance = max(reach, to_edge + footprint_radius_mm(robot) + CLEARANCE_MM)
    z_mm = min(solids_lo[2], centre[2] - shoulder_height_mm(robot))
    T_u_r = np.eye(4)
    T_u_r[:3, 3] = [centre[0] + distance * away[0], centre[1] + distance * away[1], z_mm]
    x_axis = -away                                   # +X of the robot toward the work
    T_u_r[:3, 0] = x_axis
    T_u_r[:3, 1] = np.cross([0.0, 0.0, 1.0], x_axis)
    return T_u_r
