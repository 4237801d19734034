"""Positioner and Track: a cell's external axes in the document (issue 23).

A ``Positioner`` holds the part (its ``Parts``: solids, the objects paths are
drawn on, tool markers, calibration frames) on its flange; a ``Track`` carries
the robot of the cell whose group holds it (the cell's Placement is the robot
base). Both are ``Part::FeaturePython`` objects placed by their base
(``Placement``, {U}) and shown at ``ShowAt``, their axis values (deg for
rotary axes, mm for the track, base to flange). Changing ``ShowAt`` moves what
the mechanism carries by ``motion(new) = T_u_p(new) @ inv(T_u_p(old))``
(:meth:`core.mechanisms.Mechanism.motion`), so the document always shows
everything where the mechanism puts it and the reader reads it as shown.

Their Shape is the catalog's solids (:func:`robots.mechanisms.catalog.solids`)
at ``ShowAt``.

App layer: FreeCAD and Part, no GUI. The module path is saved in documents:
never move it.
"""

import numpy as np
import Part

from .. import compat
from ..core import mechanisms as core_mechanisms
from ..errors import CadRobotError
from ..robots.mechanisms import catalog
from .base import Proxy, global_placement, restoring, type_of
from .convert import matrix_from_placement, placement_from_matrix, vector_from_array

POSITIONER = "Positioner"
TRACK = "Track"
#: The kinds a Positioner may be.
POSITIONER_KINDS = (core_mechanisms.TURNTABLE, core_mechanisms.TILT_TURN)

_COMMON_ROWS = (
    ("App::PropertyString", "Kind", "Mechanism",
     "What the mechanism is: track, turntable or tilt_turn (read only)", ""),
    ("App::PropertyString", "Model", "Mechanism",
     "Catalog name of the real mechanism (robots.mechanisms.catalog.names()); empty: generic values",
     ""),
    ("App::PropertyFloatList", "ShowAt", "Mechanism",
     "Axis values the document shows (deg, mm for a track; base to flange). Changing them moves "
     "what the mechanism carries", None),
    ("App::PropertyFloatList", "ShownAt", "Mechanism",
     "The axis values what it carries was last moved to (internal)", None),
    ("App::PropertyIntegerList", "FixedAxes", "Chooser",
     "Axes (1-based, base to flange) the chooser keeps at FixedValues instead of choosing them",
     None),
    ("App::PropertyFloatList", "FixedValues", "Chooser",
     "The value of each axis of FixedAxes (deg, mm for a track), in the same order", None),
)


class Mechanism(Proxy):
    """What Positioner and Track share: Kind, Model, ShowAt, the fixed axes, the Shape."""

    def setup(self, obj):
        obj.setEditorMode("Kind", 1)
        obj.setEditorMode("ShownAt", 2)

    def onChanged(self, obj, prop):
        if prop == "ShowAt" and not restoring(obj) and "ShownAt" in obj.PropertiesList:
            move_carried(obj)

    def execute(self, obj):
        shape = Part.Shape()
        try:
            shape = shape_at(obj, list(obj.ShowAt))
        except (CadRobotError, ValueError):   # reported when generating; show nothing here
            pass
        shape.Placement = obj.Placement
        obj.Shape = shape


class Positioner(Mechanism):
    """Proxy of a ``Part::FeaturePython`` positioner (turntable or tilt-and-turn) holding Parts."""

    TYPE = POSITIONER
    PROPERTIES = _COMMON_ROWS + (
        ("App::PropertyLinkListGlobal", "Parts", "Mechanism",
         "What rides on the flange: solids, the objects paths are drawn on, tool markers, "
         "calibration frames", None),
        ("App::PropertyAngle", "Tolerance", "Chooser",
         "How far the chooser may leave each weld's position (PA flat, PB) to help the arm, deg; "
         "0: the chooser's default", 0.0),
    )


class Track(Mechanism):
    """Proxy of a ``Part::FeaturePython`` linear track carrying the robot of its cell."""

    TYPE = TRACK
    PROPERTIES = _COMMON_ROWS + (
        ("App::PropertyLength", "Length", "Mechanism", "Travel of the carriage, mm", 3000.0),
    )


def make(doc, type_name, name):
    """A new Positioner or Track (`type_name`) named `name` in `doc`."""
    obj = doc.addObject("Part::FeaturePython", name)
    {POSITIONER: Positioner, TRACK: Track}[type_name](obj)
    return obj


def model_problem(kind, model):
    """Why `model` is not a catalog mechanism of `kind` (a sentence with the fix), or
    None when it is one (or "": generic values)."""
    if not model or model in catalog.names(kind):
        return None
    choices = ", ".join(catalog.names(kind)) or "none in the catalog yet"
    other = [k for k in core_mechanisms.KINDS if model in catalog.names(k)]
    if other:
        return "model '%s' is a %s, not a %s: pick a %s model (%s) or none." % (
            model, other[0], kind, kind, choices)
    return "model '%s' is not in the catalog: pick one of %s, or none for generic values." % (
        model, choices)


# --- the core mechanism of an object ------------------------------------------------------

def core_mechanism(obj, drawn_at, T_u_base=None):
    """The :class:`core.mechanisms.Mechanism` of `obj`, shown at `drawn_at`.

    Parameters
    ----------
    obj : App.DocumentObject
        A Positioner or a Track.
    drawn_at : array_like, shape (K,)
        deg / mm.
    T_u_base : ndarray, shape (4, 4), optional
        Its base in {U}; its global placement if omitted.

    Raises
    ------
    InputError
        An unknown kind or model (``catalog.build``).
    """
    if T_u_base is None:
        T_u_base = matrix_from_placement(global_placement(obj))
    length = float(obj.Length) if "Length" in obj.PropertiesList else None
    return catalog.build(str(obj.Kind), model=str(obj.Model) or None, name=obj.Name,
                         label=obj.Label, T_u_base=T_u_base, drawn_at=drawn_at, length_mm=length)


def shape_at(obj, values):
    """The catalog's solids of `obj` at `values`, in its own frame (its Placement
    undone), as a Part compound (empty without solids)."""
    T_u_base = matrix_from_placement(obj.Placement)
    mechanism = core_mechanism(obj, values, T_u_base)
    T_base_u = np.linalg.inv(T_u_base)
    solids = []
    for vertices, faces in catalog.solids(mechanism, values):
        local = np.asarray(vertices, float) @ T_base_u[:3, :3].T + T_base_u[:3, 3]
        solids += mesh_solids(local, faces)
    return Part.makeCompound(solids) if solids else Part.Shape()


def mesh_solids(vertices, faces):
    """Part solids of a triangle mesh (mm) made of closed pieces, one per piece."""
    sewn = Part.Shape()
    sewn.makeShapeFromMesh(([vector_from_array(v) for v in vertices],
                            [tuple(int(i) for i in f) for f in faces]), 0.05)
    return [Part.Solid(shell) for shell in sewn.Shells]


# --- moving what it carries ---------------------------------------------------------------

def carried(obj):
    """What `obj` moves: a positioner its Parts (less those that follow another
    part: attached to it, or inside its container), a track its cell."""
    if type_of(obj) == TRACK:
        from .tool_marker import holding_cell
        cell = holding_cell(obj)
        return [cell] if cell is not None else []
    parts = [p for p in (obj.Parts or []) if p is not None]
    names = {p.Name for p in parts}
    return [p for p in parts if not any(rides(o, names) for o in _followed(p))]


def rides(thing, part_names, _seen=None):
    """Whether `thing` moves with the objects named `part_names`: it is one of
    them, or attached to or inside a container of something that rides."""
    seen = set() if _seen is None else _seen
    if thing is None or thing.Name in seen:
        return False
    seen.add(thing.Name)
    if thing.Name in part_names:
        return True
    return any(rides(o, part_names, seen) for o in _followed(thing))


def _followed(thing):
    """The objects `thing`'s placement follows: its attachment's supports (when the
    attachment is on) and its container (App::Part, Body)."""
    out = []
    if str(getattr(thing, "MapMode", "Deactivated")) != "Deactivated":
        out += [ref[0] for ref in compat.attachment_support(thing) if ref]
    parent = thing.getParentGeoFeatureGroup() if hasattr(thing, "getParentGeoFeatureGroup") else None
    if parent is not None:
        out.append(parent)
    return out


def move_carried(obj):
    """Move what `obj` carries from ``ShownAt`` to ``ShowAt`` and record ``ShownAt``.

    Values of the wrong count or not finite move nothing (generating reports
    them); an empty ShownAt (a new object) only records ShowAt.
    """
    new, old = list(obj.ShowAt), list(obj.ShownAt)
    if not old or len(old) != len(new) or not np.isfinite(new + old).all():
        obj.ShownAt = new
        return
    try:
        mechanism = core_mechanism(obj, old)
    except CadRobotError:
        return
    if len(mechanism.axes) != len(new):
        return
    motion = mechanism.motion(new)
    for thing in carried(obj):
        move_object(thing, motion)
    obj.ShownAt = new


def move_object(thing, motion):
    """Move `thing` by `motion` (4x4, {U}): its Placement in its container is
    ``inv(P) @ motion @ P @ L`` (P the container's global placement, L its own)."""
    L = matrix_from_placement(thing.Placement)
    G = matrix_from_placement(global_placement(thing))
    P = G @ np.linalg.inv(L)
    thing.Placement = placement_from_matrix(np.linalg.inv(P) @ motion @ G)


def axis_count(obj):
    """The number of axes of `obj`'s kind (0 for an unknown kind)."""
    return core_mechanisms.AXIS_COUNTS.get(str(obj.Kind), 0)


def zeros(obj):
    """ShowAt of a new object: every axis at 0."""
    return [0.0] * axis_count(obj)
