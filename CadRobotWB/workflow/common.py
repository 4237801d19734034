"""What the API's modules share: placements given as arguments, the cell's start joints
and the document's obstacles (the types of arguments: :mod:`.arguments`).

Used by the other modules of this package; :mod:`CadRobotWB.api` re-exports ROBOT_BASE.
"""

import FreeCAD
import numpy as np

from ..errors import InputError
from ..objects import base, obstacles, tool_body, validate
from ..objects.convert import matrix_from_placement, placement_from_matrix


#: What a cell's placement is, in messages.
ROBOT_BASE = "robot base placement"


def as_placement(value, what, error=InputError, obj_name=None, placement="placement"):
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


def obstacle_objects(doc):
    """The document's final solids, less the cells' tool bodies (and what they are made of)."""
    skip = set()
    for body in tool_body.tool_body_objects(doc):
        skip.add(body.Name)
        skip.update(o.Name for o in body.OutListRecursive)
    return [o for o in doc.Objects if obstacles.is_final_solid(o) and o.Name not in skip]


def start_joints(cell):
    values = list(cell.StartJoints or [])
    if values and len(values) != 6:
        raise InputError("Cell %s: StartJoints must hold 6 joint values in degrees (or none)."
                         % base.describe(cell), cell.Name)
    if values:
        validate.finite_values(values, "Cell %s StartJoints" % base.describe(cell), obj_name=cell.Name)
    return np.array(values, dtype=float) if values else None
