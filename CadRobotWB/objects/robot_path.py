"""Robot path: sketches or edges the tool must follow, with the process
options a user edits in the property editor."""

import FreeCAD
import Part

from ..core.segment_orientation import CONSTANT, TOOL_ON_ARCS
from ..errors import CadRobotError
from .base import Proxy, restoring


#: The choices of a path's Blend property (the first is a new path's).
AUTOMATIC, FINE, ZONE = BLEND_CHOICES = ("Automatic", "Fine", "Zone")


class RobotPath(Proxy):
    """Proxy of a ``Part::FeaturePython``; its shape is the path's edges in
    {U}, in travel order, shown for reference (generation always reads the
    source geometry afresh)."""

    TYPE = "RobotPath"
    PROPERTIES = (
        ("App::PropertyLinkSubListGlobal", "Source", "Path",
         "Sketches, Part objects or their edges the path follows", None),
        ("App::PropertyPythonObject", "SourceEdgePoints", "Path",
         "Where each linked edge was when it was linked (start, middle, end, in its object's "
         "own frame), to find it again when a recompute renumbers the object's edges", None),
        ("App::PropertyBool", "Reversed", "Path", "Travel the path in the opposite direction", False),
        ("App::PropertySpeed", "Speed", "Motion", "TCP speed along the path", 10.0),
        ("App::PropertyEnumeration", "Blend", "Motion",
         "How the robot passes the path's interior targets: Automatic = the largest zone "
         "within ChordTolerance and half the neighbouring moves; Fine = stop at every "
         "target; Zone = the Zone radius (at most half the neighbouring moves). The first "
         "and last targets and reorientations always stop", list(BLEND_CHOICES)),
        ("App::PropertyLength", "Zone", "Motion",
         "Blending (corner) radius of the interior targets when Blend is Zone", 0.0),
        ("App::PropertyLength", "ApproachDistance", "Motion",
         "Approach and entry along the tool axis before the first target (0: none)", 50.0),
        ("App::PropertyLength", "RetractDistance", "Motion",
         "Retract along the tool axis after the last target (0: none)", 50.0),
        ("App::PropertySpeed", "ApproachSpeed", "Motion", "TCP speed of approach, entry and retract", 100.0),
        ("App::PropertyEnumeration", "ToolOnArcs", "Motion",
         "On an arc the tool turns with the arc about its axis (keeping its angles to the faces "
         "round it; round a concave arc it leans from push to drag, away from the walls), or keeps "
         "its tool marker's orientation (files made before this choice)",
         list(TOOL_ON_ARCS)),
        ("App::PropertyLength", "InterpolationStep", "Interpolation",
         "Step inside risk areas; 0 uses Speed × the cell's SampleTime (eqs 8-13)", 0.0),
        ("App::PropertyLength", "ChordTolerance", "Tolerances",
         "Largest distance between a spline/ellipse and the straight moves that replace it", 0.1),
        ("App::PropertyLength", "ConnectTolerance", "Tolerances",
         "Largest gap between edge ends that still counts as connected", 0.01),
        ("App::PropertyLength", "MarkerTolerance", "Tolerances",
         "Largest distance from a tool marker's origin to the path it sets", 0.1),
        ("App::PropertyLinkGlobal", "CalibrationFrame", "Program",
         "Calibration frame {B} for this path; empty uses the cell's", None),
        ("App::PropertyString", "CalibrationFrameRef", "Program",
         "Internal name of the last calibration frame linked (to report a deleted one)", ""),
        ("App::PropertyInteger", "SegmentCount", "Result", "Number of segments (read only)", 0),
        ("App::PropertyLength", "PathLength", "Result", "Length of the path (read only)", 0.0),
    )
    RESTORED_DEFAULTS = {"ToolOnArcs": CONSTANT}

    def onDocumentRestored(self, obj):
        had_blend = "Blend" in obj.PropertiesList
        super().onDocumentRestored(obj)
        if not had_blend:
            upgrade_blend(obj)

    def setup(self, obj):
        obj.setEditorMode("CalibrationFrameRef", 2)
        obj.setEditorMode("SourceEdgePoints", 2)
        obj.setEditorMode("Placement", 2)
        for name in ("SegmentCount", "PathLength"):
            obj.setEditorMode(name, 1)
        _zone_editable(obj)

    def onChanged(self, obj, prop):
        if prop == "Blend":
            _zone_editable(obj)
        if prop == "Source" and not restoring(obj):
            from .edge_identity import remembered_points
            obj.SourceEdgePoints = remembered_points(obj.Source or [],
                                                     getattr(obj, "SourceEdgePoints", None))
        if prop == "CalibrationFrame" and getattr(obj, "CalibrationFrame", None) is not None:
            if obj.CalibrationFrameRef != obj.CalibrationFrame.Name:
                obj.CalibrationFrameRef = obj.CalibrationFrame.Name

    def execute(self, obj):
        from . import reader
        try:
            edges = reader.path_edges(obj)
            segments = reader.path_geometry(obj)[0]
        except CadRobotError as err:
            FreeCAD.Console.PrintError("CadRobot: %s\n" % err)
            obj.Shape = Part.Shape()
            return
        obj.SegmentCount = len(segments)
        obj.PathLength = sum(s.length for s in segments)
        obj.Shape = Part.makeCompound(edges)
        obj.Placement = FreeCAD.Placement()


def _zone_editable(obj):
    """Zone is read only unless Blend is Zone (it is used only then)."""
    if "Zone" in obj.PropertiesList and "Blend" in obj.PropertiesList:
        obj.setEditorMode("Zone", 0 if obj.Blend == ZONE else 1)


def upgrade_blend(obj):
    """Blend of a path saved before it existed: its Zone radius where one was set,
    else Automatic (continuous motion; such files stopped at every target)."""
    obj.Blend = ZONE if float(obj.Zone) > 0.0 else AUTOMATIC
    FreeCAD.Console.PrintLog("CadRobot: path '%s' saved before Blend existed: Blend = %s\n"
                             % (obj.Label, obj.Blend))


def zone_setting(obj):
    """The path's zone as :class:`~..core.generate.PathSpec` takes it: None
    (automatic), 0 (fine) or the Zone radius, mm."""
    if obj.Blend == AUTOMATIC:
        return None
    return 0.0 if obj.Blend == FINE else float(obj.Zone)


def make(doc, name):
    obj = doc.addObject("Part::FeaturePython", name)
    RobotPath(obj)
    return obj
