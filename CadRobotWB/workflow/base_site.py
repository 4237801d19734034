"""Where a cell's robot stands against the document's solids: a new cell's default base
beside the work (:func:`default_placement`), and the check's finding when the robot
stands inside a part (:func:`inside_finding`).

Both read the document's solids as :func:`.common.obstacle_objects` gives them (the
collision check's obstacles); neither needs python-fcl.
"""

import FreeCAD
import numpy as np
import Part

from ..objects import base
from ..objects.convert import placement_from_matrix
from ..objects.picking import global_shape
from ..robots.checks import checks
from ..robots.placement import default_base
from .common import obstacle_objects

#: The robot's base column may overlap a solid by this much and still stand on or beside
#: it (touching faces, rounding), mm^3.
INSIDE_MIN_MM3 = 1000.0


def _boxes(shapes):
    """(N, 2, 3) lower and upper corners of the shapes' bounding boxes, mm."""
    return np.array([[(b.XMin, b.YMin, b.ZMin), (b.XMax, b.YMax, b.ZMax)]
                     for b in (s.BoundBox for s in shapes if not s.isNull())]).reshape(-1, 2, 3)


def solid_boxes(doc):
    """(N, 2, 3) boxes of the document's solids in {U}, mm."""
    return _boxes([global_shape(o) for o in obstacle_objects(doc)])


def paths_box(doc):
    """(2, 3) box of the document's robot paths in {U}, mm, or None when it has none."""
    return default_base.union_box(_boxes([p.Shape for p in base.objects_of_type(doc, "RobotPath")
                                          if getattr(p, "Shape", None) is not None]))


def default_placement(doc, robot):
    """Where a new cell's robot stands when no placement is given.

    Beside the work, facing it (``robots.placement.default_base``: a
    geometric rule, no search): the work is the document's robot paths when
    it has any, else its solids; the robot stands clear of the solids' box,
    on their floor or lower when the work is too low for the arm (or on the
    top of a floor slab drawn under everything).

    Parameters
    ----------
    doc : App.Document
    robot : str
        A catalog name.

    Returns
    -------
    FreeCAD.Placement
        The robot base {R} in {U}; the identity (the origin) when the
        document has no solids (paths or not) or only a floor, or the arm's
        reach is unknown.
    """
    boxes = solid_boxes(doc)
    T_u_r = default_base.default_base(robot, boxes, paths_box(doc)) if len(boxes) else None
    return FreeCAD.Placement() if T_u_r is None else placement_from_matrix(T_u_r)


def base_column(robot, T_u_r):
    """The robot's base as a solid in {U}: a cylinder of its footprint's radius about
    axis 1, from the base up to the shoulder (axis 2).

    Parameters
    ----------
    robot : str
    T_u_r : ndarray, shape (4, 4)
        The robot base {R} in {U}, mm.

    Returns
    -------
    Part.Solid
    """
    radius = default_base.footprint_radius_mm(robot)
    height = max(default_base.shoulder_height_mm(robot), radius)
    column = Part.makeCylinder(radius, height)
    column.Placement = placement_from_matrix(T_u_r)
    return column


def parts_inside(doc, robot, T_u_r):
    """The solids of `doc` the robot's base column (:func:`base_column`) stands in.

    Returns
    -------
    list of (str, float)
        Label and overlap volume (mm^3, over :data:`INSIDE_MIN_MM3`) of each,
        in document order.
    """
    column = base_column(robot, T_u_r)
    box = column.BoundBox
    out = []
    for obj in obstacle_objects(doc):
        shape = global_shape(obj)
        if not box.intersect(shape.BoundBox):
            continue
        volume = column.common(shape).Volume
        if volume > INSIDE_MIN_MM3:
            out.append((obj.Label, volume))
    return out


def inside_finding(cell, T_u_r):
    """The check's error when `cell`'s robot stands inside a part, else None.

    Parameters
    ----------
    cell : Cell
    T_u_r : ndarray, shape (4, 4)
        Where the robot stands ({R} in {U}, mm), as the check sees it.

    Returns
    -------
    robots.checks.checks.Finding or None
        Kind ``robot_inside``, before every target (move index -1).
    """
    parts = parts_inside(cell.Document, cell.Robot, T_u_r)
    if not parts:
        return None
    x, y, z = T_u_r[:3, 3]
    message = ("the robot %s stands inside %s (its base at (%.1f, %.1f, %.1f) mm is within the "
               "part): move the robot beside it (Place robot), or give the cell another Placement."
               % (cell.Robot, "/".join(label for label, _volume in parts), x, y, z))
    return checks.Finding(checks.ROBOT_INSIDE, checks.ERROR, "", -1, "", message)
