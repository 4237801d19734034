"""Zones (blending radii) of a path's interior targets: continuous motion.

:func:`limit_zones` runs on one path's moves after they are written
(:mod:`.generate`). The writer gives every move the zone the user asked for
(:data:`AUTOMATIC` for the automatic rule) and 0 where the process needs an
exact stop (the approach, the entry, the end of the path, a reorientation
and the move before it, the retract); this module keeps those stops and
bounds every other zone.

The rule, for the target ending move ``k`` when moves ``k`` and ``k+1`` are
both linear or circular path moves:

* **cap**: at most half the shorter of the two moves, so neighbouring zones
  never overlap (URScript refuses overlapping blends; ABB and KUKA shrink a
  zone that is too big on their own);
* **automatic** (:data:`AUTOMATIC`): the largest zone ``r`` within the cap
  whose corner cut stays within the path's tolerance. A blend entering ``r``
  before the target and leaving ``r`` after it, round a turn of the travel
  direction by ``theta``, deviates from the programmed corner by at most
  ``r * tan(theta / 4)`` (a circular arc tangent at both ends; a parabolic
  blend deviates less, ``r * sin(theta / 2) / 2``). ``theta`` is the turn
  between the two moves' tangents at the target plus, for a circular move,
  the turn of its own tangent over the ``r`` mm inside the zone (``r / R``).
  Collinear moves give ``theta = 0``: the cap alone decides;
* **a given zone** (the path's ``Blend`` set to a radius): that radius as it
  is, or the cap where it is larger;
* a zone the rule chose (automatic, or the cap) is rounded down to
  :data:`ZONE_STEP_MM` (0.1 mm), so a program names few distinct zones (2.1 mm
  spacing gives 1.0 mm: ABB's predefined ``z1``); below 0.1 mm to
  :data:`FINE_ZONE_STEP_MM` (0.01 mm), so the closely spaced moves of a corner
  area (0.04 mm apart where the torch turns 90 degrees over 2 mm) still blend
  instead of stopping at every target; below 0.01 mm it is an exact stop.

Every other move (joint moves, a move before a joint move or a retract,
zero-length moves) keeps or gets zone 0. Each post writes the zone in its
controller's terms (``docs/controllers.md``, "Zones").

Pure numpy: never imports FreeCAD.
"""

import math

import numpy as np

from ..errors import GeometryError
from .geometry import Arc
from .program import CIRCULAR, LINEAR, ROLE_PATH, ROLE_RISK

#: Zone a writer gives a move whose zone the automatic rule chooses.
AUTOMATIC = math.inf
#: Zones are rounded down to multiples of this, mm.
ZONE_STEP_MM = 0.1
#: ... and zones below ZONE_STEP_MM to multiples of this, mm.
FINE_ZONE_STEP_MM = 0.01
#: Roles of the moves whose end may be blended.
_BLENDED_ROLES = (ROLE_PATH, ROLE_RISK)


def limit_zones(moves, tolerance_mm):
    """Bound the zone of every move of one path in place (see the module's rule).

    Parameters
    ----------
    moves : list of Move
        One path's moves in order, zones as the writer gave them: 0 = exact
        stop (kept), :data:`AUTOMATIC` or a radius in mm.
    tolerance_mm : float
        > 0: the largest corner cut the automatic rule allows, mm (the path's
        ChordTolerance).

    Returns
    -------
    list of Move
        `moves`, each ``zone_mm`` now finite and >= 0.
    """
    for k, move in enumerate(moves):
        asked = move.zone_mm
        nxt = moves[k + 1] if k + 1 < len(moves) else None
        if asked <= 0.0 or k == 0 or not _blendable(move, nxt):
            move.zone_mm = 0.0
            continue
        before = move_shape(moves[k - 1].target.position_mm, move)
        after = move_shape(move.target.position_mm, nxt)
        cap = 0.5 * min(before.length, after.length)
        if asked == AUTOMATIC:
            move.zone_mm = round_down_zone(automatic_zone_mm(before, after, cap, tolerance_mm))
        elif asked > cap:
            move.zone_mm = round_down_zone(cap)
    return moves


def _blendable(move, nxt):
    """Whether the target ending `move` is an interior target of a path."""
    return (nxt is not None and move.role in _BLENDED_ROLES and nxt.role in _BLENDED_ROLES
            and move.kind in (LINEAR, CIRCULAR) and nxt.kind in (LINEAR, CIRCULAR))


def round_down_zone(zone_mm):
    """`zone_mm` rounded down (never up) to :data:`ZONE_STEP_MM`, or below it to
    :data:`FINE_ZONE_STEP_MM`, mm."""
    step = ZONE_STEP_MM if zone_mm >= ZONE_STEP_MM else FINE_ZONE_STEP_MM
    steps = math.floor(zone_mm / step + 1e-9)
    return round(max(steps, 0) * step, 6)


def automatic_zone_mm(before, after, cap_mm, tolerance_mm):
    """The largest zone within `cap_mm` whose corner cut stays within `tolerance_mm`.

    Parameters
    ----------
    before, after : MoveShape
        The moves ending and starting at the target.
    cap_mm, tolerance_mm : float
        Upper bound of the zone, and of its corner cut ``r tan(theta(r) / 4)``, mm.

    Returns
    -------
    float
        mm, in [0, cap_mm]; found by bisection (the cut grows with r).
    """
    turn = turn_rad(before, after)
    curvature = before.curvature + after.curvature          # 1/mm, 0 for lines

    def cut(r):
        return r * math.tan(min(turn + r * curvature, math.pi * 0.999) / 4.0)

    if cut(cap_mm) <= tolerance_mm:
        return cap_mm
    lo, hi = 0.0, cap_mm
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if cut(mid) <= tolerance_mm else (lo, mid)
    return lo


def blend_radius_mm(zone_mm, turn_rad):
    """Radius of the arc that blends a turn of `turn_rad` entering `zone_mm` before
    the corner and leaving `zone_mm` after it: ``zone / tan(turn / 2)``, mm
    (inf for no turn, 0 for no zone)."""
    if zone_mm <= 0.0:
        return 0.0
    half = 0.5 * turn_rad
    return math.inf if half < 1e-12 else zone_mm / math.tan(min(half, 0.5 * math.pi - 1e-12))


def turn_rad(before, after):
    """Turn of the travel direction from the end of `before` to the start of `after`
    (MoveShapes), rad."""
    return _angle_between(before.end_tangent, after.start_tangent)


def _angle_between(u, v):
    """Angle between two unit vectors, rad, in [0, pi]."""
    return math.acos(max(-1.0, min(1.0, float(np.dot(u, v)))))


class MoveShape:
    """What the zone rule needs of one move: length, end tangents, curvature.

    Attributes
    ----------
    length : float
        mm travelled (0 for a joint move or a move that only turns the tool).
    start_tangent, end_tangent : ndarray, shape (3,)
        Unit travel directions at its start and end (zeros when it does not travel).
    curvature : float
        1 / radius of a circular move, 1/mm; 0 for a line.
    """

    def __init__(self, length=0.0, start_tangent=None, end_tangent=None, curvature=0.0):
        self.length = float(length)
        self.start_tangent = np.zeros(3) if start_tangent is None else start_tangent
        self.end_tangent = np.zeros(3) if end_tangent is None else end_tangent
        self.curvature = float(curvature)


def move_shape(start, move):
    """The :class:`MoveShape` of `move` from `start` ((3,) mm, the previous target)."""
    end = move.target.position_mm
    if move.kind == CIRCULAR and move.via is not None:
        try:
            arc = Arc.from_three_points(start, move.via.position_mm, end)
        except GeometryError:      # collinear via: the controller moves straight
            arc = None
        if arc is not None:
            return MoveShape(arc.length, arc.tangent_at(0.0), arc.tangent_at(arc.length),
                             1.0 / arc.radius)
    if move.kind not in (LINEAR, CIRCULAR):
        return MoveShape()
    chord = end - start
    length = float(np.linalg.norm(chord))
    if length <= 1e-9:
        return MoveShape()
    direction = chord / length
    return MoveShape(length, direction, direction)
