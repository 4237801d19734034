"""What a calibration frame shows in the 3D view, besides its own shape.

The frame's shape (three edges, coloured X red, Y green, Z blue through the
view provider's ``LineColorArray``) gets arrow heads, "X"/"Y"/"Z" labels at
the tips and the frame's label at its origin.  When the frame has been
taught, a paler dashed triad labelled "<label> (taught)" shows where the
real robot will put {B}: ``T_u_r @ T_r_b``, with ``T_u_r`` the Placement of
the frame's cell and ``T_r_b`` from ``api.taught_frame``.

Scene graph (under the view provider's root, after its placement
transform, so the CAD triad sits at the frame's origin)::

    SoSwitch  visibility (the object's Visibility)
    +-- SoSeparator
        +-- SoPickStyle UNPICKABLE    picking goes to the frame's edges
        +-- cad (SoSeparator)         arrow heads and labels
        +-- taught (SoSeparator)      SoResetTransform, T_u_b taught, dashed triad
"""

from pivy import coin

from ..errors import CadRobotError
from ..objects.base import type_of
from ..objects.convert import matrix_from_placement
from . import triad_display


def cell_of(frame):
    """The cell `frame` belongs to: the one whose group holds it, else one linking it; or None."""
    cells = [o for o in getattr(frame, "InListRecursive", []) if type_of(o) == "Cell"]
    holding = [c for c in cells if frame in (getattr(c, "Group", None) or [])
               or any(frame in (getattr(g, "Group", None) or []) for g in c.Group)]
    return (holding or cells or [None])[0]


def taught_pose_u(frame):
    """Where the real robot will use `frame`: T_u_b (4, 4) in {U}, mm; None when not taught.

    None too when the frame belongs to no cell or its points cannot be
    fitted (generating reports that; the view just shows nothing).
    """
    if not getattr(frame, "UseTaught", False):
        return None
    from .. import api
    taught_frame = getattr(api, "taught_frame", None)
    cell = cell_of(frame)
    if taught_frame is None or cell is None:
        return None
    try:
        taught = taught_frame(frame)
    except CadRobotError:
        return None
    if taught is None:
        return None
    return matrix_from_placement(cell.Placement) @ matrix_from_placement(taught[0])


class FrameDisplay:
    """Arrow heads, labels and the taught triad of one calibration frame.

    Parameters
    ----------
    root : coin.SoGroup
        The view provider's root node; the display adds its switch to it.

    Attributes
    ----------
    switch : coin.SoSwitch
        On while the frame is visible.
    cad, taught : coin.SoSeparator
        The drawn frame's decorations, the taught triad (empty when not taught).
    """

    def __init__(self, root):
        self.switch, sep = triad_display.overlay(root, "CadRobotFrameDisplay")
        self.cad = coin.SoSeparator()
        self.taught = coin.SoSeparator()
        sep.addChild(self.cad)
        sep.addChild(self.taught)

    def set_visible(self, visible):
        triad_display.set_visible(self.switch, visible)

    def update(self, frame):
        """Redraw from `frame`'s AxisLength, Label and teaching properties."""
        length = float(getattr(frame, "AxisLength", 100.0))
        self.cad.removeAllChildren()
        self.cad.addChild(triad_display.triad_node(length, frame.Label, lines=False))
        self.taught.removeAllChildren()
        T_u_b = taught_pose_u(frame)
        if T_u_b is None:
            return
        self.taught.addChild(coin.SoResetTransform())   # the taught pose is in {U}
        self.taught.addChild(triad_display.transform_node(T_u_b))
        self.taught.addChild(triad_display.triad_node(
            length, "%s (taught)" % frame.Label, colors=triad_display.TAUGHT_AXIS_COLORS,
            pattern=triad_display.DASHED, text_color=(0.35, 0.35, 0.35), line_width=2.0,
            title_at=(0.04, -0.15, 0.0)))   # below the X axis: the drawn frame's title is above

    def taught_shown(self):
        """bool: a taught triad is drawn."""
        return self.taught.getNumChildren() > 0

