"""Risk area: consecutive path segments where the tool turns sharply; the
generator re-samples them and slerps the orientation through the markers in
it (paper section 3.3). On a closed path, FirstSegment = the last segment and
LastSegment = 1 is the corner where the loop closes."""

import Part

from ..core.generate import AT_CORNER
from ..errors import CadRobotError
from .base import Proxy


class RiskArea(Proxy):
    """Proxy of a ``Part::FeaturePython`` covering segments FirstSegment..LastSegment
    (1-based, inclusive) of Path; its shape is those edges, for display."""

    TYPE = "RiskArea"
    PROPERTIES = (
        ("App::PropertyLink", "Path", "Risk area", "The path this risk area belongs to", None),
        ("App::PropertyString", "PathRef", "Risk area",
         "Internal name of the last path linked (to report a deleted one)", ""),
        ("App::PropertyInteger", "FirstSegment", "Risk area", "First segment covered (1-based)", 1),
        ("App::PropertyInteger", "LastSegment", "Risk area", "Last segment covered (1-based)", 2),
        ("App::PropertyLength", "Step", "Risk area",
         "Interpolation step; 0 uses the path's step (speed × sample time)", 0.0),
        ("App::PropertyLength", "CornerSpan", "Risk area",
         "Covers only this length at the end of the first segment and at the start of the last "
         "(the torch turns there and keeps its angles elsewhere); 0: whole segments", 0.0),
        ("App::PropertyEnumeration", "AtCorner", "Risk area",
         "Weld through the corner while the tool turns, or stop exactly, turn in place and go on "
         "(where arc off/on goes)", list(AT_CORNER)),
    )

    def setup(self, obj):
        obj.setEditorMode("PathRef", 2)
        obj.setEditorMode("Placement", 2)

    def onChanged(self, obj, prop):
        if prop == "Path" and getattr(obj, "Path", None) is not None:
            if obj.PathRef != obj.Path.Name:
                obj.PathRef = obj.Path.Name

    def execute(self, obj):
        from . import reader  # reader imports the proxies' modules
        edges = []
        if obj.Path is not None:
            try:
                ordered = reader.path_edges(obj.Path)
                first, last = obj.FirstSegment, obj.LastSegment
                if first > last >= 1:           # the corner where a loop closes
                    edges = ordered[first - 1:] + ordered[:last]
                else:
                    edges = ordered[first - 1:last] if first >= 1 else []
            except CadRobotError:  # reported when generating; display nothing here
                edges = []
        obj.Shape = Part.makeCompound(edges)


def make(doc, name):
    obj = doc.addObject("Part::FeaturePython", name)
    RiskArea(obj)
    return obj
