"""Calibration frame {B}: the frame the real robot is taught, linking the
drawing to the cell (paper section 3.2)."""

import FreeCAD
import Part

from .base import Proxy

AXIS_COLORS = ((1.0, 0.0, 0.0), (0.0, 0.7, 0.0), (0.0, 0.0, 1.0))


class CalibrationFrame(Proxy):
    """Proxy of a ``Part::FeaturePython`` whose Placement is {B} in its
    container; the shape is an X/Y/Z axis triad. Attachable to geometry
    (e.g. a table corner vertex) like any Part primitive."""

    TYPE = "CalibrationFrame"
    PROPERTIES = (
        ("App::PropertyLength", "AxisLength", "Frame", "Length of the drawn axes", 100.0),
    )

    def setup(self, obj):
        if not obj.hasExtension("Part::AttachExtension"):
            try:
                obj.addExtension("Part::AttachExtensionPython")
            except TypeError:  # FreeCAD 0.20 wants the (unused) proxy argument
                obj.addExtension("Part::AttachExtensionPython", None)

    def execute(self, obj):
        # "Support" became "AttachmentSupport" in FreeCAD 1.0.
        support = getattr(obj, "AttachmentSupport", None) or getattr(obj, "Support", None)
        if support:
            obj.positionBySupport()
        length = max(float(obj.AxisLength), 1e-3)
        origin = FreeCAD.Vector()
        axes = [Part.makeLine(origin, FreeCAD.Vector(*(length * c for c in row)))
                for row in ((1, 0, 0), (0, 1, 0), (0, 0, 1))]
        shape = Part.makeCompound(axes)
        shape.Placement = obj.Placement
        obj.Shape = shape


def make(doc, name):
    obj = doc.addObject("Part::FeaturePython", name)
    CalibrationFrame(obj)
    return obj
