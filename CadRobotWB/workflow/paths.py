"""Robot paths: a path following a sketch, Part wire or picked edges.

Part of the scripting API: :mod:`CadRobotWB.api` re-exports its public names.
"""

import FreeCAD

from ..errors import CadRobotError, InputError
from ..objects import reader, robot_path, validate
from .arguments import Arguments

#: What a path source is, in messages.
SOURCE = "a sketch, a Part object, (object, 'EdgeN'), (object, ['Edge1', ...]) or a list of these"

#: The CadRobot type of each path property that links to one (make_path's **properties).
LINKED_TYPES = {"CalibrationFrame": "CalibrationFrame"}


def _source_links(source, args):
    """Normalise a path source to [(obj, [sub, ...]), ...], each object checked by `args`."""
    items = source if isinstance(source, list) or (isinstance(source, tuple) and not _is_pair(source)) \
        else [source]
    links = []
    for item in items:
        obj, subs = item if _is_pair(item) else (item, [])
        subs = [subs] if isinstance(subs, str) else list(subs)
        if not isinstance(obj, FreeCAD.DocumentObject) or not all(isinstance(s, str) for s in subs):
            args.refuse("source", SOURCE, item)
        links.append((args.shape_object("source", obj), subs))
    if not links:
        args.refuse("source", SOURCE, source)
    return links


def _is_pair(item):
    """Whether `item` is (object, "EdgeN") or (object, ["Edge1", ...])."""
    return (isinstance(item, tuple) and len(item) == 2 and isinstance(item[0], FreeCAD.DocumentObject)
            and isinstance(item[1], (str, list, tuple)))


def _blend_setting(blend, name, args):
    """``(Blend choice, Zone mm or None)`` of make_path's `blend` argument."""
    if blend is None:
        return robot_path.AUTOMATIC, None
    if isinstance(blend, str):
        for choice in (robot_path.AUTOMATIC, robot_path.FINE):
            if blend.strip().lower() == choice.lower():
                return choice, None
        raise InputError("Path '%s': blend %r is not one of 'automatic', 'fine' or a zone "
                         "radius in mm (e.g. blend=1.0)." % (name, blend))
    args.number("blend", blend, expected="'automatic', 'fine' or a zone radius in mm (a number)")
    zone = validate.number_in_range(blend, "Path '%s': blend (zone radius, mm)" % name, 0.0)
    return (robot_path.ZONE, zone) if zone > 0.0 else (robot_path.FINE, None)


def make_path(doc, cell, source, speed_mm_s=10.0, name="Path", blend=None, **properties):
    """Add a path following `source` to `cell`.

    Parameters
    ----------
    source
        A sketch or Part object (all its edges), ``(obj, "Edge3")``,
        ``(obj, ["Edge1", "Edge2"])``, or a list of any of these.
    speed_mm_s : float
        TCP speed along the path.
    blend : str or float, optional
        How the robot passes the path's interior targets: ``"automatic"``
        (None, the default: the largest zone within ChordTolerance and half the
        neighbouring moves, :mod:`..core.zones`), ``"fine"`` (stop at every
        target) or a zone radius in mm (Blend "Zone"). The first and last
        targets and reorientations stop either way.
    **properties
        Any other path property by name, e.g. ``Zone=1.0``,
        ``ApproachDistance=30``, ``CalibrationFrame=frame``.

    The geometry is checked at once (GeometryError for gaps, branches,
    zero-length edges); on error nothing is added to the document.
    """
    args = Arguments("make_path")
    args.open_document("doc", doc)
    args.cell(cell)
    links = _source_links(source, args)
    args.number("speed_mm_s", speed_mm_s, expected="a speed in mm/s (a number)")
    args.text("name", name)
    speed = validate.number_in_range(speed_mm_s, "Path '%s': speed_mm_s" % name, 0.0, low_open=True)
    blend_choice, zone_mm = _blend_setting(blend, name, args)
    obj = robot_path.make(doc, name)
    try:
        # An empty sub-list must be [""] or FreeCAD drops the whole link.
        obj.Source = [(o, subs or [""]) for o, subs in links]
        obj.Speed = speed
        obj.Blend = blend_choice
        if zone_mm is not None:
            obj.Zone = zone_mm
        for prop, value in properties.items():
            args.set_property(obj, prop, value, LINKED_TYPES.get(prop))
        reader.path_geometry(obj)
    except CadRobotError:
        doc.removeObject(obj.Name)
        raise
    cell.addObject(obj)
    doc.recompute()
    return obj
