"""Where the programmed path turns faster than a laser stripe can follow (seam tracking's corners).

A laser seam tracker looks at the joint a few centimetres ahead of the torch.
Where the seam turns sharply (a corner, or an arc of small radius such as the
toe of a rolled section), the stripe runs off the end of the leg or across the
next one: the joint it was following disappears or changes direction for a
few profiles although the seam goes on. Real trackers do not take that for a
lost seam: the robot controller knows where its programmed path turns, holds
the correction it has (a "tracking hold": the torch goes on along the
programmed path moved by the last correction) and the tracker re-acquires
the joint on the next leg. ABB's optical tracking, for example, states its
accuracy for straight seams and radii of 60 mm and names radii below 30 mm
as difficult (ABB "Laser Sensor Training", 2014, slide "Technical Data -
Optical Tracking").

:func:`corner_zones` finds those turns on the nominal path: stretches where
the travel direction turns, grouped when less than ``gap_mm`` apart, kept
when they turn at least ``min_turn_deg`` in all on a mean radius below
``radius_mm``. A larger arc is tracked like a straight seam.

Pure numpy: never imports FreeCAD.
"""

from dataclasses import dataclass

import numpy as np

#: A turn of at least this much (degrees) ...
MIN_TURN_DEG = 30.0
#: ... on a mean radius below this (mm) is a corner the stripe cannot follow.
CORNER_RADIUS_MM = 30.0
#: Turning stretches closer than this (mm) are one corner (a sharp corner next to a toe arc).
CORNER_GAP_MM = 5.0
#: Chord-to-chord turns below this (radians) are straight (rounding).
STRAIGHT_RAD = 1e-6


@dataclass
class CornerZone:
    """One corner of the nominal path.

    Attributes
    ----------
    s_in_mm, s_out_mm : float
        Path distance where the turning starts and ends (equal for a sharp corner), mm.
    turn_deg : float
        How far the travel direction turns in the zone, summed, degrees.
    """

    s_in_mm: float
    s_out_mm: float
    turn_deg: float


def corner_zones(s_mm, travel_u, min_turn_deg=MIN_TURN_DEG, radius_mm=CORNER_RADIUS_MM,
                 gap_mm=CORNER_GAP_MM):
    """The corners of a path given by its chords.

    Parameters
    ----------
    s_mm : ndarray, shape (M,)
        Path distance of each vertex, increasing, mm.
    travel_u : ndarray, shape (M - 1, 3)
        Unit direction of each chord (vertex k to k + 1).
    min_turn_deg, radius_mm, gap_mm : float
        See the module doc.

    Returns
    -------
    list of CornerZone
        In path order.
    """
    s = np.asarray(s_mm, dtype=float)
    x = np.asarray(travel_u, dtype=float)
    turn = np.arccos(np.clip(np.sum(x[:-1] * x[1:], axis=1), -1.0, 1.0))   # at vertices 1..M-2
    turning = np.flatnonzero(turn > STRAIGHT_RAD) + 1
    zones = []
    for group in _groups(turning, s, gap_mm):
        total = float(np.sum(turn[group - 1]))
        length = s[group[-1]] - s[group[0]]
        if np.degrees(total) >= min_turn_deg and length < radius_mm * total:
            zones.append(CornerZone(float(s[group[0]]), float(s[group[-1]]), float(np.degrees(total))))
    return zones


def _groups(vertices, s, gap_mm):
    """Split the turning vertices (K,) where the path runs straight for `gap_mm` or more."""
    if len(vertices) == 0:
        return []
    breaks = np.flatnonzero(np.diff(s[vertices]) >= gap_mm) + 1
    return np.split(vertices, breaks)


def in_hold(zones, s_mm, margin_mm):
    """Whether path distance `s_mm` lies within `margin_mm` of where a corner zone begins or
    ends: where a stripe may miss the joint although the seam goes on.

    A zone shorter than ``2 * margin_mm`` is held all through; inside a longer one (a small
    circle welded all round) the stripe follows the arc like a straight seam, so a miss
    there counts.
    """
    return any(abs(s_mm - z.s_in_mm) <= margin_mm or abs(s_mm - z.s_out_mm) <= margin_mm
               or z.s_in_mm <= s_mm <= z.s_out_mm and z.s_out_mm - z.s_in_mm <= 2 * margin_mm
               for z in zones)
