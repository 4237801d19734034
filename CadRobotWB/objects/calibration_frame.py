"""Calibration frame {B}: the frame the real robot is taught, linking the
drawing to the cell (paper section 3.2).

Teaching: points of the part as drawn (CadPoints, {U}) and the same points
measured with the robot (MeasuredPoints, {R}) give the real pose of the part;
with UseTaught the programs use ``T_r_b = fit(CAD -> measured) @ T_u_b``
while the frame's Placement stays the CAD frame in the drawing.
"""

import FreeCAD
import numpy as np
import Part

from .. import compat
from ..core import frames
from ..errors import FrameError
from .base import Proxy, describe, global_placement
from .convert import array_from_vector, matrix_from_placement, placement_from_matrix
from .validate import check_rigid, finite_values

AXIS_COLORS = ((1.0, 0.0, 0.0), (0.0, 0.7, 0.0), (0.0, 0.0, 1.0))


def taught_transform(obj):
    """(T_r_b (4, 4), residuals_mm (N,)) of a taught frame, or None when it is not taught.

    Raises
    ------
    FrameError
        Naming the frame, when its points cannot be fitted.
    """
    if not getattr(obj, "UseTaught", False):
        return None
    cad = np.array([array_from_vector(v) for v in obj.CadPoints]).reshape(-1, 3)
    measured = np.array([array_from_vector(v) for v in obj.MeasuredPoints]).reshape(-1, 3)
    return fit_points(obj, cad, measured)


def fit_points(obj, cad_points_u, measured_points_r):
    """(T_r_b, residuals_mm) of frame `obj` taught by point pairs (FrameError naming it)."""
    for points, what in ((cad_points_u, "CadPoints"), (measured_points_r, "MeasuredPoints")):
        finite_values(points, "Calibration frame %s %s" % (describe(obj), what), FrameError, obj.Name)
    try:
        T_r_u, residuals = frames.fit_frame(cad_points_u, measured_points_r)
    except FrameError as err:
        raise FrameError("Calibration frame %s: %s Teach it again with at least 3 pairs of "
                         "non-collinear points, or clear UseTaught." % (describe(obj), err),
                         obj.Name) from None
    T_u_b = check_rigid(matrix_from_placement(global_placement(obj)),
                        "Calibration frame %s" % describe(obj), FrameError, obj.Name)
    return T_r_u @ T_u_b, residuals


class CalibrationFrame(Proxy):
    """Proxy of a ``Part::FeaturePython`` whose Placement is {B} in its
    container; the shape is an X/Y/Z axis triad. Attachable to geometry
    (e.g. a table corner vertex) like any Part primitive."""

    TYPE = "CalibrationFrame"
    PROPERTIES = (
        ("App::PropertyLength", "AxisLength", "Frame", "Length of the drawn axes", 100.0),
        ("App::PropertyVectorList", "CadPoints", "Teaching",
         "Points of the part as drawn, in the document frame {U}, mm", None),
        ("App::PropertyVectorList", "MeasuredPoints", "Teaching",
         "The same points measured with the real robot, in its base frame {R}, mm", None),
        ("App::PropertyBool", "UseTaught", "Teaching",
         "Programs use the frame taught from the points instead of the drawn one", False),
        ("App::PropertyPlacement", "TaughtPlacement", "Teaching",
         "Taught frame {B} in the robot base frame {R} (read only)", None),
        ("App::PropertyFloatList", "Residuals", "Teaching",
         "Distance of each measured point from the fitted CAD point, mm (read only)", None),
    )

    def setup(self, obj):
        compat.make_attachable(obj)
        for name in ("TaughtPlacement", "Residuals"):
            obj.setEditorMode(name, 1)

    def execute(self, obj):
        if compat.attachment_support(obj):
            obj.positionBySupport()
        length = max(float(obj.AxisLength), 1e-3)
        origin = FreeCAD.Vector()
        axes = [Part.makeLine(origin, FreeCAD.Vector(*(length * c for c in row)))
                for row in ((1, 0, 0), (0, 1, 0), (0, 0, 1))]
        shape = Part.makeCompound(axes)
        shape.Placement = obj.Placement
        obj.Shape = shape
        self.update_taught(obj)

    def update_taught(self, obj):
        """Refresh TaughtPlacement and Residuals; problems go to the console
        (generating reports them as errors)."""
        try:
            taught = taught_transform(obj)
        except FrameError as err:
            FreeCAD.Console.PrintError("CadRobot: %s\n" % err)
            taught = None
        T_r_b, residuals = taught if taught is not None else (np.eye(4), [])
        obj.TaughtPlacement = placement_from_matrix(T_r_b)
        obj.Residuals = [float(r) for r in residuals]


def make(doc, name):
    obj = doc.addObject("Part::FeaturePython", name)
    CalibrationFrame(obj)
    return obj
