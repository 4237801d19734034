"""View providers: how CadRobot objects look in the 3D view and the tree.

Attached when an object is made with the GUI up, and when a document saved
without the GUI (FreeCADCmd, the CLI) is opened in it. The class path is
saved in every GuiDocument.xml: do not move or rename it without a shim.
"""

import os

# Per CadRobot type: (line colour, line width, shape colour, transparency %).
STYLES = {
    "CalibrationFrame": ((0.0, 0.0, 0.0), 3.0, None, 0),
    "RobotPath": ((0.0, 0.33, 1.0), 4.0, None, 0),
    "ToolMarker": ((0.2, 0.2, 0.2), 1.0, (1.0, 0.55, 0.0), 40),
    "RiskArea": ((1.0, 0.0, 0.0), 7.0, None, 0),
}


class ViewProvider:
    """The view provider of every CadRobot object (style by the object's type)."""

    def __init__(self, vobj):
        vobj.Proxy = self
        self.apply_style(vobj)

    def attach(self, vobj):
        self.Object = vobj.Object

    def apply_style(self, vobj):
        from ..objects.base import type_of
        style = STYLES.get(type_of(vobj.Object))
        if style is None:
            return
        line_color, line_width, shape_color, transparency = style
        for prop, value in (("LineColor", line_color), ("PointColor", line_color),
                            ("LineWidth", line_width), ("ShapeColor", shape_color),
                            ("Transparency", transparency)):
            if value is not None and prop in vobj.PropertiesList:
                setattr(vobj, prop, value)

    def getIcon(self):
        return os.path.join(os.path.dirname(os.path.dirname(__file__)), "resources", "icons",
                            "CadRobot.svg")

    def claimChildren(self):
        return list(getattr(self.Object, "Group", []) or [])

    def dumps(self):
        return None

    def loads(self, state):
        return None

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None


def attach(obj):
    """Give `obj` a CadRobot view provider unless it has one already."""
    vobj = getattr(obj, "ViewObject", None)
    if vobj is not None and not isinstance(getattr(vobj, "Proxy", None), ViewProvider):
        ViewProvider(vobj)
