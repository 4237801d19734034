"""Tracks and positioners a user can pick, with their published data.

The catalog is ``resources/mechanisms.json``: one entry per real mechanism,
every number ``[value, unit]`` in the unit its source gives, with the source
(title, URL, where in it, the date read) and the fields that are ``estimated``
(not found in a reachable source: a conservative generic value, with the
reason). :data:`_UNITS` converts them to mm, degrees and kg: the one place.
An axis without a stop in its source (``-INF..INF``) is ``"endless": true``
there, with no limits; :data:`ENDLESS_DEG` bounds it here. A rotary axis whose maker
counts it the other way round (its positive values turn about -Z of the frames below:
the table turning clockwise seen from above its face) is ``"reversed": true``, so the
values the programs carry are the maker's.

``model=None`` builds a generic mechanism of a kind (:data:`GENERIC`, the
same structure in mm and degrees):

* track: travel 0..3000 mm (``length_mm``) along base X at 1000 mm/s,
  2000 mm/s^2; the carriage's mounting face 250 mm above the base;
* turntable: a 1000 mm table 750 mm above the base, +-3600 deg at 90 deg/s,
  180 deg/s^2;
* tilt_turn: tilt about base X at 800 mm, +-135 deg at 70 deg/s,
  140 deg/s^2; turn about the table's normal, the table face on the tilt
  axis, +-3600 deg at 90 deg/s, 180 deg/s^2.

The kinematics, per kind (values 0 = the pose drawn in the docs):

* track: the carriage moves along base +X; the flange (where the robot base
  is bolted) is ``carriage_height`` above the base, Z up;
* turntable: turn about base +Z; the flange is the table face's centre,
  ``table_height`` above the base;
* tilt_turn: tilt about base +X through ``(0, 0, tilt_axis_height)``, then
  turn about the table's normal; at tilt 0 the flange (table face centre)
  is at ``(0, eccentricity, tilt_axis_height + table_offset)``, Z up.

:func:`solids` gives boxes and cylinders sized from the same data, one mesh
per moving body; :func:`obstacles` gives them named, as
``robots.checks.collision.RobotCollisionChecker`` takes obstacles.

Pure numpy + trimesh: never imports FreeCAD.
"""

import json
import math
import os

import numpy as np

from ... import dependencies
from ...core import mechanisms as mech
from ...errors import InputError, UnknownNameError

CATALOG_PATH = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(__file__))),
                            "resources", "mechanisms.json")

#: Published unit -> (the unit used here, factor).
_UNITS = {
    "mm": ("mm", 1.0), "m": ("mm", 1000.0),
    "deg": ("deg", 1.0), "rad": ("deg", 180.0 / math.pi), "pi rad": ("deg", 180.0),
    "mm/s": ("mm/s", 1.0), "m/s": ("mm/s", 1000.0),
    "deg/s": ("deg/s", 1.0), "rad/s": ("deg/s", 180.0 / math.pi),
    "rpm": ("deg/s", 6.0),
    "mm/s^2": ("mm/s^2", 1.0), "m/s^2": ("mm/s^2", 1000.0),
    "deg/s^2": ("deg/s^2", 1.0), "rad/s^2": ("deg/s^2", 180.0 / math.pi),
    "kg": ("kg", 1.0), "t": ("kg", 1000.0),
}

#: Axis names of each kind, base to flange.
AXIS_NAMES = {mech.TRACK: ("travel",), mech.TURNTABLE: ("turn",), mech.TILT_TURN: ("tilt", "turn")}
#: Geometry fields of each kind (mm).
GEOMETRY = {mech.TRACK: ("carriage_height", "carriage_length", "carriage_width", "rail_width"),
            mech.TURNTABLE: ("table_height", "table_diameter"),
            mech.TILT_TURN: ("tilt_axis_height", "table_offset", "eccentricity", "table_diameter")}
_AXIS_FIELDS = ("lower", "upper", "max_speed", "max_accel")
#: The limits of an endless axis here (``"endless": true``: no stop in its source), deg:
#: ten turns either way, the generic turn's range.
ENDLESS_DEG = 3600.0


def _axis(lower, upper, speed, accel):
    return {"lower": lower, "upper": upper, "max_speed": speed, "max_accel": accel}


#: The generic mechanism of each kind (model=None), mm and degrees.
GENERIC = {
    mech.TRACK: {"payload_kg": 0.0,
                 "geometry": {"carriage_height": 250.0, "carriage_length": 800.0,
                              "carriage_width": 800.0, "rail_width": 600.0},
                 "axes": {"travel": _axis(0.0, 3000.0, 1000.0, 2000.0)}},
    mech.TURNTABLE: {"payload_kg": 0.0,
                     "geometry": {"table_height": 750.0, "table_diameter": 1000.0},
                     "axes": {"turn": _axis(-3600.0, 3600.0, 90.0, 180.0)}},
    mech.TILT_TURN: {"payload_kg": 0.0,
                     "geometry": {"tilt_axis_height": 800.0, "table_offset": 0.0,
                                  "eccentricity": 0.0, "table_diameter": 1000.0},
                     "axes": {"tilt": _axis(-135.0, 135.0, 70.0, 140.0),
                              "turn": _axis(-3600.0, 3600.0, 90.0, 180.0)}},
}

_entries = None


# ----------------------------------------------------------------------- the catalog
def _catalog():
    """{name: entry} as the JSON holds them (read once)."""
    global _entries
    if _entries is None:
        with open(CATALOG_PATH, "r", encoding="utf-8") as f:
            _entries = {e["name"]: e for e in json.load(f)["mechanisms"]}
    return _entries


def names(kind=None):
    """Catalog names, sorted; only those of `kind` (one of ``core.mechanisms.KINDS``) if given."""
    if kind is not None:
        _check_kind(kind)
    return sorted(n for n, e in _catalog().items() if kind is None or e["kind"] == kind)


def entry(name):
    """The published data of catalog mechanism `name`, with units and sources.

    Returns
    -------
    dict
        A copy of the JSON entry: ``name``, ``maker``, ``model``, ``kind``,
        ``payload``, ``geometry`` and ``axes`` (``[value, unit]`` as
        published; an axis without a stop ``"endless": true`` instead of
        ``lower``/``upper``), ``sources`` (``title``, ``url``, ``where``, ``read``),
        ``estimated`` (``fields``, ``reason``), optional ``notes``.

    Raises
    ------
    UnknownNameError
        For a name not in the catalog.
    """
    catalog = _catalog()
    if name not in catalog:
        raise UnknownNameError("Mechanism model '%s' is not in the catalog: use one of %s "
                               "(cadrobot mechanisms lists them)." % (name, ", ".join(sorted(catalog))),
                               obj_name=str(name))
    return json.loads(json.dumps(catalog[name]))


def listing(name):
    """What ``cadrobot mechanisms`` shows of catalog mechanism `name`.

    Returns
    -------
    dict
        ``name``, ``maker``, ``model``, ``kind``, ``payload_kg``, ``axes``
        (list of {``name``, ``unit``, ``lower``, ``upper``, ``max_speed``,
        ``max_accel`` in mm / deg, ``endless``, ``reversed``}), ``geometry_mm``, ``sources``,
        ``estimated`` (field names), ``estimated_reason``.
    """
    published = entry(name)
    data = spec(published["kind"], name)
    unit = "mm" if published["kind"] == mech.TRACK else "deg"
    return {"name": name, "maker": published["maker"], "model": published["model"],
            "kind": published["kind"], "payload_kg": data["payload_kg"],
            "axes": [dict(name=a, unit=unit, endless=bool(published["axes"][a].get("endless")),
                          reversed=a in data["reversed"], **data["axes"][a])
                     for a in AXIS_NAMES[published["kind"]]],
            "geometry_mm": data["geometry"], "sources": published["sources"],
            "estimated": published["estimated"]["fields"],
            "estimated_reason": published["estimated"]["reason"]}


def quantity(pair):
    """A published ``[value, unit]`` in mm, deg, mm/s, deg/s, ..., kg.

    Returns
    -------
    (float, str)
        The value and its unit here.
    """
    value, unit = pair
    if unit not in _UNITS:
        raise InputError("Unit '%s' is not known to the mechanism catalog: use one of %s."
                         % (unit, ", ".join(sorted(_UNITS))))
    to_unit, factor = _UNITS[unit]
    return float(value) * factor, to_unit


def spec(kind, model=None):
    """The data `build` uses, in mm, degrees and kg.

    Parameters
    ----------
    kind : str
    model : str or None
        Catalog name; None or "": :data:`GENERIC` of `kind`.

    Returns
    -------
    dict
        ``payload_kg``, ``geometry`` {field: mm}, ``axes`` {axis name:
        {"lower", "upper", "max_speed", "max_accel"}} (deg or mm based), ``reversed``
        (the names of the axes counted clockwise; the generic ones have none).
    """
    _check_kind(kind)
    if not model:
        return json.loads(json.dumps(GENERIC[kind]))
    published = entry(model)
    if published["kind"] != kind:
        raise InputError("Mechanism model '%s' is a %s, not a %s: pick a %s model (%s) or none."
                         % (model, published["kind"], kind, kind,
                            ", ".join(names(kind)) or "none in the catalog"), obj_name=model)
    return {"payload_kg": quantity(published["payload"])[0],
            "geometry": {f: quantity(published["geometry"][f])[0] for f in GEOMETRY[kind]},
            "axes": {a: _axis_data(published["axes"][a]) for a in AXIS_NAMES[kind]},
            "reversed": [a for a in AXIS_NAMES[kind] if published["axes"][a].get("reversed")]}


def _axis_data(axis):
    """An axis' published ``[value, unit]`` fields in mm / deg; an endless one +-ENDLESS_DEG."""
    if axis.get("endless"):
        axis = dict(axis, lower=[-ENDLESS_DEG, "deg"], upper=[ENDLESS_DEG, "deg"])
    return {f: quantity(axis[f])[0] for f in _AXIS_FIELDS}


def _check_kind(kind):
    if kind not in mech.KINDS:
        raise InputError("Mechanism kind '%s' is unknown: use one of %s."
                         % (kind, ", ".join(mech.KINDS)))


# ----------------------------------------------------------------------- build
def _rot_y(deg):
    T = np.eye(4)
    a = np.radians(deg)
    T[:3, :3] = [[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]]
    return T


#: Half a turn about X.
_ROT_X_180 = np.diag([1.0, -1.0, -1.0, 1.0])


def _at(x=0.0, y=0.0, z=0.0, T=None):
    T = np.eye(4) if T is None else T.copy()
    T[:3, 3] = (x, y, z)
    return T


def build(kind, model=None, name="Positioner", label="", T_u_base=None, drawn_at=None,
          length_mm=None):
    """A Mechanism of `kind`, from the catalog entry `model` or generic values.

    Parameters
    ----------
    kind : str
        ``"track"``, ``"turntable"`` or ``"tilt_turn"``.
    model : str or None
        Catalog name (:func:`names`); None or "": a generic mechanism of that kind.
    name, label : str
    T_u_base : ndarray, shape (4, 4), optional
        Its base in {U}; identity if omitted.
    drawn_at : array_like, shape (K,), optional
        Axis values the document shows; zeros if omitted.
    length_mm : float, optional
        A track's travel (its upper limit), mm; at most the model's.

    Returns
    -------
    core.mechanisms.Mechanism

    Raises
    ------
    InputError
        An unknown kind, a model of another kind, a travel <= 0 or longer
        than the model's (one line naming the model).
    UnknownNameError
        A model not in the catalog.
    """
    data = spec(kind, model)
    if kind == mech.TRACK and length_mm is not None:
        _limit_travel(data["axes"]["travel"], length_mm, model)
    T_u_base = np.eye(4) if T_u_base is None else np.asarray(T_u_base, dtype=float)
    joints, flange = _CHAINS[kind](data["geometry"])
    for k, axis_name in enumerate(AXIS_NAMES[kind]):
        if axis_name in data.get("reversed", ()):
            # Turn the joint frame half a turn about its X (its Z now points the maker's
            # way) and back after it: the bodies beyond stay where they were at value 0.
            joints[k] = joints[k] @ _ROT_X_180
            if k + 1 < len(joints):
                joints[k + 1] = _ROT_X_180 @ joints[k + 1]
            else:
                flange = _ROT_X_180 @ flange
    axes = [mech.Axis(axis_name, mech.LINEAR if kind == mech.TRACK else mech.ROTARY, T_joint,
                      **data["axes"][axis_name])
            for axis_name, T_joint in zip(AXIS_NAMES[kind], joints)]
    return mech.Mechanism(name=name, label=label or name, kind=kind, model=model or "",
                          axes=axes, T_last_flange=flange, T_u_base=T_u_base, drawn_at=drawn_at,
                          payload_kg=data["payload_kg"])


def _limit_travel(travel, length_mm, model):
    """Set a track's upper limit to `length_mm` (refused beyond the model's travel)."""
    length = float(length_mm)
    longest = travel["upper"]
    if not math.isfinite(length) or length <= 0.0:
        raise InputError("Track length %s mm: give a travel above 0 mm." % length_mm)
    if model is not None and length > longest + 1e-9:
        raise InputError("Track length %g mm is longer than the travel of model '%s' (%g mm): "
                         "give at most %g mm or another model." % (length, model, longest, longest),
                         obj_name=model)
    travel["upper"] = length


def _track_chain(g):
    return [_rot_y(90.0)], _rot_y(-90.0) @ _at(0.0, 0.0, g["carriage_height"])


def _turntable_chain(g):
    return [_at(0.0, 0.0, g["table_height"])], np.eye(4)


def _tilt_turn_chain(g):
    tilt = _at(0.0, 0.0, g["tilt_axis_height"], _rot_y(90.0))
    turn = _rot_y(-90.0) @ _at(0.0, g["eccentricity"], g["table_offset"])
    return [tilt, turn], np.eye(4)


#: Joint frames (at value 0, each in the previous frame) and the flange, from the geometry.
_CHAINS = {mech.TRACK: _track_chain, mech.TURNTABLE: _turntable_chain,
           mech.TILT_TURN: _tilt_turn_chain}


# ----------------------------------------------------------------------- solids
#: Thickness of a table disc and of a track's carriage plate, mm.
PLATE_MM = 60.0
#: Cylinder sections of the meshes.
SECTIONS = 32


def _body_frames(mechanism, values):
    """{U} poses of the base and of each axis' body (its joint frame after the motion)."""
    T = np.asarray(mechanism.T_u_base, dtype=float)
    frames = [T]
    for axis, v in zip(mechanism.axes, values):
        T = T @ axis.T_prev_joint @ mech._joint_transforms(axis.kind, [v])[0]
        frames.append(T)
    return frames


def _box(lo, hi):
    trimesh = dependencies.require("trimesh")      # here: listing the catalog needs no meshes
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    return trimesh.creation.box(hi - lo, transform=_at(*((lo + hi) / 2.0)))


def _disc(radius, z_lo, z_hi):
    trimesh = dependencies.require("trimesh")
    return trimesh.creation.cylinder(radius=radius, height=z_hi - z_lo, sections=SECTIONS,
                                     transform=_at(0.0, 0.0, (z_lo + z_hi) / 2.0))


def _track_bodies(mechanism, g):
    """Rail in the base frame; carriage in the flange frame."""
    half_l, half_w = g["carriage_length"] / 2.0, g["carriage_width"] / 2.0
    travel = mechanism.axes[0]
    rail = _box((travel.lower - half_l, -g["rail_width"] / 2.0, 0.0),
                (travel.upper + half_l, g["rail_width"] / 2.0, g["carriage_height"] - PLATE_MM))
    carriage = _box((-half_l, -half_w, -PLATE_MM), (half_l, half_w, 0.0))
    return [rail], [carriage]


def _turntable_bodies(mechanism, g):
    """Pedestal in the base frame; table disc in the flange frame."""
    radius = g["table_diameter"] / 2.0
    pedestal = _disc(0.6 * radius, 0.0, g["table_height"] - PLATE_MM)
    return [pedestal], [_disc(radius, -PLATE_MM, 0.0)]


def _tilt_turn_bodies(mechanism, g):
    """Two pillars holding the tilt axis (base), the yoke under the table (tilt), the table."""
    radius = g["table_diameter"] / 2.0
    h, d, e = g["tilt_axis_height"], g["table_offset"], g["eccentricity"]
    inner = radius + 50.0                          # the yoke clears the table by 50 mm
    arm = 150.0
    outer = inner + arm + 20.0                     # the pillars clear the yoke by 20 mm
    pillars = [_box((outer, -arm, 0.0), (outer + arm, arm, h + arm / 2.0)),
               _box((-outer - arm, -arm, 0.0), (-outer, arm, h + arm / 2.0))]
    floor = d - PLATE_MM - arm                     # the yoke's beam, under the table
    low, high = min(floor, -arm / 2.0), max(floor + arm, arm / 2.0)
    yoke = [_box((-inner - arm, e - arm / 2.0, floor), (inner + arm, e + arm / 2.0, floor + arm)),
            _box((-inner - arm, -arm / 2.0, low), (-inner, arm / 2.0, high)),
            _box((inner, -arm / 2.0, low), (inner + arm, arm / 2.0, high))]
    return pillars, yoke, [_disc(radius, -PLATE_MM, 0.0)]


_BODIES = {mech.TRACK: _track_bodies, mech.TURNTABLE: _turntable_bodies,
           mech.TILT_TURN: _tilt_turn_bodies}


def _geometry(mechanism):
    """The geometry `mechanism` was built from (its model's, else the generic)."""
    return spec(mechanism.kind, mechanism.model)["geometry"]


def solids(mechanism, values=None):
    """The mechanism's solids at `values` (its drawn pose if None), in {U}.

    Parameters
    ----------
    mechanism : core.mechanisms.Mechanism
        Built by :func:`build`.
    values : array_like, shape (K,), optional
        deg / mm.

    Returns
    -------
    list of (vertices, faces)
        vertices : ndarray, shape (V, 3), mm in {U}; faces : ndarray, shape (F, 3), int.
        One mesh per moving body, base first: track rail, carriage;
        turntable pedestal, table; tilt_turn pillars, yoke, table. Each mesh
        is a set of closed convex pieces (boxes, cylinders).
    """
    return [(mesh.vertices, mesh.faces) for _, mesh in _placed_meshes(mechanism, values)]


def obstacles(mechanism, values=None, T_r_u=None):
    """The solids named, as ``RobotCollisionChecker(robot, obstacles)`` takes them.

    Parameters
    ----------
    mechanism : core.mechanisms.Mechanism
    values : array_like, shape (K,), optional
        deg / mm; the drawn pose if None.
    T_r_u : ndarray, shape (4, 4), optional
        {U} in the frame wanted (the robot base {R} for the checker); {U} if None.

    Returns
    -------
    list of (str, trimesh.Trimesh)
        ``"<label> base"``, ``"<label> <axis name>"`` (the body that axis moves).
    """
    placed = _placed_meshes(mechanism, values)
    if T_r_u is not None:
        for _, mesh in placed:
            mesh.apply_transform(np.asarray(T_r_u, dtype=float))
    return placed


def _placed_meshes(mechanism, values):
    trimesh = dependencies.require("trimesh")
    v = mechanism.drawn_at if values is None else np.asarray(values, dtype=float).reshape(-1)
    frames = _body_frames(mechanism, v)
    bodies = _BODIES[mechanism.kind](mechanism, _geometry(mechanism))
    frames[-1] = frames[-1] @ mechanism.T_last_flange
    if mechanism.kind == mech.TILT_TURN:
        frames[1] = frames[1] @ _rot_y(-90.0)      # the yoke is drawn base-aligned at tilt 0
    names = ["%s base" % mechanism.label] + ["%s %s" % (mechanism.label, a.name)
                                              for a in mechanism.axes]
    placed = []
    for body_name, pieces, T in zip(names, bodies, frames):
        mesh = trimesh.util.concatenate(pieces)
        mesh.apply_transform(T)
        placed.append((body_name, mesh))
    return placed
