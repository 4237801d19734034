"""Coin nodes for coordinate frames: RGB axis triads, arrow cones and text.

X is red, Y green, Z blue everywhere in CadRobot.  These are the building
blocks of :mod:`frame_display` (calibration frames), :mod:`path_display`
(direction arrows, segment numbers) and :mod:`target_display` (the
generated targets); nothing here touches the document.
"""

import numpy as np
from pivy import coin

from .robot_view import set_transform

#: Axis colours X, Y, Z, RGB 0..1 (the calibration frame's shape edges use them too).
AXIS_COLORS = ((1.0, 0.0, 0.0), (0.0, 0.7, 0.0), (0.0, 0.0, 1.0))
#: Paler axis colours for a taught frame (where the real robot puts {B}).
TAUGHT_AXIS_COLORS = ((1.0, 0.55, 0.55), (0.45, 0.85, 0.45), (0.5, 0.55, 1.0))
#: Colour of the labels: dark, readable on FreeCAD's light and dark backgrounds' gradients.
TEXT_COLOR = (0.1, 0.1, 0.1)
AXIS_NAMES = ("X", "Y", "Z")
#: Dash pattern of a taught triad's lines (16 bits, one per screen pixel).
DASHED = 0xF0F0


def base_color(color):
    """A ``SoBaseColor`` of `color` (RGB 0..1)."""
    node = coin.SoBaseColor()
    node.rgb.setValue(*(float(c) for c in color))
    return node


def unlit():
    """A ``SoLightModel`` that draws what follows in its plain colour."""
    node = coin.SoLightModel()
    node.model = coin.SoLightModel.BASE_COLOR
    return node


def switch_node(visible=True):
    """A ``SoSwitch`` showing its first child, or nothing when not `visible`."""
    node = coin.SoSwitch()
    set_visible(node, visible)
    return node


def set_visible(switch, visible):
    """Show the first child of ``SoSwitch`` `switch`, or nothing."""
    switch.whichChild = 0 if visible else coin.SO_SWITCH_NONE


def overlay(root, name):
    """What a view provider draws besides its object's shape, added to `root`.

    Parameters
    ----------
    root : coin.SoGroup
        The view provider's root node.
    name : str
        Name of the switch (found with ``SoSearchAction``).

    Returns
    -------
    switch : coin.SoSwitch
        Shown; :func:`set_visible` follows the object's Visibility.
    separator : coin.SoSeparator
        The switch's child; it starts with an UNPICKABLE ``SoPickStyle``
        (picking goes to the object's own edges): add the overlay's nodes here.
    """
    switch = switch_node()
    switch.setName(name)
    separator = coin.SoSeparator()
    pick = coin.SoPickStyle()
    pick.style = coin.SoPickStyle.UNPICKABLE
    separator.addChild(pick)
    switch.addChild(separator)
    root.addChild(switch)
    return switch, separator


def transform_node(T):
    """A ``SoTransform`` holding the rigid 4x4 transform `T` (mm)."""
    node = coin.SoTransform()
    set_transform(node, T)
    return node


def text_node(text, position, color=TEXT_COLOR, size_px=14):
    """Screen-aligned text whose lower left corner is at `position`.

    Parameters
    ----------
    text : str
    position : array_like, shape (3,)
        In the current coordinate system, mm.
    color : tuple of 3 float
    size_px : float
        Font size in screen pixels (does not change with zoom).

    Returns
    -------
    coin.SoSeparator
        Its ``SoText2`` is the last child.
    """
    sep = coin.SoSeparator()
    translation = coin.SoTranslation()
    translation.translation.setValue(*(float(v) for v in position))
    font = coin.SoFont()
    font.size = float(size_px)
    label = coin.SoText2()
    label.string.setValue(str(text))
    for node in (translation, base_color(color), font, label):
        sep.addChild(node)
    return sep


def cone_node(tip, direction, height_mm, radius_mm):
    """A solid cone whose point is at `tip`, pointing along `direction`.

    Parameters
    ----------
    tip, direction : array_like, shape (3,)
        mm; `direction` need not be unit length (but not zero).
    height_mm, radius_mm : float

    Returns
    -------
    coin.SoSeparator
    """
    direction = np.asarray(direction, dtype=float)
    direction = direction / np.linalg.norm(direction)
    center = np.asarray(tip, dtype=float) - direction * height_mm / 2.0  # SoCone is centred
    sep = coin.SoSeparator()
    transform = coin.SoTransform()
    transform.translation.setValue(*(float(v) for v in center))
    transform.rotation.setValue(coin.SbRotation(coin.SbVec3f(0.0, 1.0, 0.0),
                                                coin.SbVec3f(*(float(v) for v in direction))))
    cone = coin.SoCone()
    cone.height = float(height_mm)
    cone.bottomRadius = float(radius_mm)
    sep.addChild(transform)
    sep.addChild(cone)
    return sep


def segments_node(starts, ends, color, line_width=2.0, pattern=None):
    """Straight lines from each start to the matching end, in one colour.

    Parameters
    ----------
    starts, ends : array_like, shape (N, 3)
        mm.
    color : tuple of 3 float
    line_width : float
        Pixels.
    pattern : int, optional
        16-bit dash pattern (e.g. :data:`DASHED`); None draws solid lines.

    Returns
    -------
    coin.SoSeparator
    """
    starts = np.asarray(starts, dtype=float).reshape(-1, 3)
    ends = np.asarray(ends, dtype=float).reshape(-1, 3)
    sep = coin.SoSeparator()
    style = coin.SoDrawStyle()
    style.lineWidth = float(line_width)
    if pattern is not None:
        style.linePattern = int(pattern)
    coords = coin.SoCoordinate3()
    points = np.stack([starts, ends], axis=1).reshape(-1, 3)
    coords.point.setValues(0, len(points), points.tolist())
    lines = coin.SoLineSet()
    lines.numVertices.setValues(0, len(starts), [2] * len(starts))
    for node in (base_color(color), style, coords, lines):
        sep.addChild(node)
    return sep


def triad_node(length_mm, title="", colors=AXIS_COLORS, lines=True, pattern=None,
               text_color=TEXT_COLOR, line_width=3.0, title_at=(0.04, 0.04, 0.0)):
    """One labelled axis triad at the origin of the current coordinate system.

    Parameters
    ----------
    length_mm : float
        Length of each axis, arrow head included.
    title : str
        Written at the origin (e.g. the frame's label); empty: none.
    colors : sequence of 3 RGB tuples
        X, Y, Z colours.
    lines : bool
        Draw the axis lines; False when something else draws them (the
        calibration frame's own shape edges).
    pattern : int, optional
        Dash pattern of the lines.
    text_color : tuple of 3 float
    line_width : float
    title_at : tuple of 3 float
        Where the title starts, in axis lengths (default beside the origin,
        in the XY quadrant, clear of the axes' labels).

    Returns
    -------
    coin.SoSeparator
        Unlit; its ``SoText2`` nodes hold "X", "Y", "Z" and `title`.
    """
    length = max(float(length_mm), 1e-3)
    head, radius = 0.12 * length, 0.04 * length
    sep = coin.SoSeparator()
    sep.addChild(unlit())
    origin = np.zeros(3)
    for axis, (name, color) in enumerate(zip(AXIS_NAMES, colors)):
        direction = np.eye(3)[axis]
        if lines:
            sep.addChild(segments_node([origin], [direction * (length - head)], color, line_width,
                                       pattern))
        arrow = cone_node(direction * length, direction, head, radius)
        arrow.insertChild(base_color(color), 0)
        sep.addChild(arrow)
        sep.addChild(text_node(name, direction * length * 1.06, text_color))
    if title:
        sep.addChild(text_node(title, np.array(title_at, dtype=float) * length, text_color))
    return sep


def triads_node(poses, length_mm, colors=AXIS_COLORS, line_width=2.0):
    """Many small unlabelled triads, e.g. at every generated target.

    Parameters
    ----------
    poses : array_like, shape (N, 4, 4)
        Frames in the current coordinate system, mm.
    length_mm : float
        Axis length.
    colors : sequence of 3 RGB tuples
    line_width : float

    Returns
    -------
    coin.SoSeparator
        Unlit, three ``SoLineSet`` (one per axis colour) of N lines each.
    """
    poses = np.asarray(poses, dtype=float).reshape(-1, 4, 4)
    sep = coin.SoSeparator()
    sep.addChild(unlit())
    if not len(poses):
        return sep
    origins = poses[:, :3, 3]
    for axis, color in enumerate(colors):
        sep.addChild(segments_node(origins, origins + float(length_mm) * poses[:, :3, axis], color,
                                   line_width))
    return sep


def texts_in(node, hidden=False):
    """The strings of the ``SoText2`` nodes under `node` (tests, debugging).

    Parameters
    ----------
    node : coin.SoNode
    hidden : bool
        Also those under ``SoSwitch`` children that are switched off.

    Returns
    -------
    list of str
        In scene-graph order.
    """
    search = coin.SoSearchAction()
    search.setType(coin.SoText2.getClassTypeId())
    search.setInterest(coin.SoSearchAction.ALL)
    search.setSearchingAll(bool(hidden))
    search.apply(node)
    paths = search.getPaths()
    return [str(paths[i].getTail().string.getValues(0)[0]) for i in range(paths.getLength())]
