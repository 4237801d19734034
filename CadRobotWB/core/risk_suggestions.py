"""Where a path needs a risk area: junctions where the tool turns sharply (pure numpy).

Junction j (1-based) joins segments j and j + 1. A junction whose tool
orientations differ by more than a threshold needs its orientation change
spread over the neighbouring segments (paper section 3.3); neighbouring
sharp junctions merge into one area.
"""

from collections import namedtuple

import numpy as np

from . import interpolation
from .generate import MAX_TURN_PER_MOVE_DEG, ORIENTATION_TOL_RAD
from .rotations import rotation_angle_between

# A suggested risk area over segments first..last (1-based, inclusive) of a path;
# jump_deg is the largest orientation change at one junction inside it, degrees.
# step_mm: the suggested interpolation step (mm, see area_step_mm), step_rule: why that
# step (text), moves_added: the moves the area adds to the program at that step
# (see moves_added). The last three are None from suggest() alone.
RiskSuggestion = namedtuple("RiskSuggestion",
                            "path first_segment last_segment jump_deg step_mm step_rule moves_added",
                            defaults=(None, None, None))



def junction_jumps_deg(R_u_t):
    """Angles between consecutive tool orientations.

    Parameters
    ----------
    R_u_t : sequence of ndarray, shape (3, 3)
        One tool orientation per segment, in travel order.

        Segments that inherit one tool marker's orientation share one array:
        no jump between them (and nothing to compute).

    Returns
    -------
    ndarray, shape (N - 1,)
        Degrees; element j - 1 is the jump at junction j (segments j, j + 1).
    """
    return np.array([0.0 if a is b else np.degrees(rotation_angle_between(a, b))
                     for a, b in zip(R_u_t[:-1], R_u_t[1:])])


def suggest(jumps_deg, threshold_deg, existing=(), path=None):
    """Risk areas for the junctions turning by more than `threshold_deg`.

    Parameters
    ----------
    jumps_deg : array_like, shape (N - 1,)
        Orientation jump at each junction, degrees (see :func:`junction_jumps_deg`).
    threshold_deg : float
        Jumps strictly above this need an area.
    existing : sequence of (int, int)
        Risk areas already on the path, (first, last) 1-based inclusive.
        Junctions touching one of their segments are left out (already
        smoothed, or an area there would overlap it).
    path : object, optional
        Stored in each suggestion's ``path``.

    Returns
    -------
    list of RiskSuggestion
        In path order; runs of neighbouring sharp junctions j..k become one
        area over segments j..k + 1.
    """
    covered = set()
    for first, last in existing:
        covered.update(range(int(first), int(last) + 1))
    out, run = [], []
    for j, jump in enumerate(np.asarray(jumps_deg, dtype=float), start=1):
        sharp = jump > threshold_deg and j not in covered and j + 1 not in covered
        if sharp:
            run.append((j, jump))
        if run and (not sharp or j == len(jumps_deg)):
            out.append(RiskSuggestion(path, run[0][0], run[-1][0] + 1, max(a for _, a in run)))
            run = []
    return out


# --- how many moves a risk area adds, and at which step -------------------------------------
#
# Counted exactly as core.generate writes a path: outside a risk area a line is one
# linear move, an arc one circular move per half turn begun, a spline (Polyline) one
# linear move per sample; a junction where the orientation changes (two different
# markers' orientations) adds a reorientation move. Inside an area each segment of
# length L is re-sampled at `step` (eqs 8-13): len(stations(L, step)) - 1 = ceil(L / step)
# linear moves, and no reorientation inside it. Entering and leaving the area, the
# reorientation moves are the same with or without it.

def segment_moves(segment):
    """Moves generate writes for `segment` outside a risk area (int)."""
    if segment.kind == "line":
        return 1
    if segment.kind == "arc":
        return max(1, int(np.ceil(segment.sweep_rad / np.pi - 1e-9)))
    if hasattr(segment, "points"):
        return len(segment.points) - 1
    raise ValueError("segment of kind %r" % (segment.kind,))


def area_moves(segments, step_mm):
    """Linear moves generate writes for `segments` (the area's) re-sampled at `step_mm` (mm)."""
    return sum(len(interpolation.stations(seg.length, step_mm)) - 1 for seg in segments)


def reorient_moves(R_u_t, first, last):
    """Reorientation moves at the junctions inside segments first..last (1-based) without an area.

    Parameters
    ----------
    R_u_t : sequence of ndarray, shape (3, 3)
        One orientation per segment of the path (shared arrays: one marker's).
    """
    count = 0
    for j in range(first, last):            # junction j joins segments j and j + 1
        a, b = R_u_t[j - 1], R_u_t[j]
        if a is not b and rotation_angle_between(a, b) > ORIENTATION_TOL_RAD:
            count += 1
    return count


def moves_added(segments, R_u_t, first, last, step_mm):
    """Moves a risk area over segments first..last (1-based) at `step_mm` adds to the program.

    Parameters
    ----------
    segments : sequence of core segments
        The whole path, in travel order, mm.
    R_u_t : sequence of ndarray, shape (3, 3)
        One orientation per segment.
    step_mm : float
        The area's interpolation step, mm.

    Returns
    -------
    int
        Moves with the area minus moves without it (negative when it has fewer).
    """
    inside = list(segments[first - 1:last])
    without = sum(segment_moves(seg) for seg in inside) + reorient_moves(R_u_t, first, last)
    return area_moves(inside, step_mm) - without


def chord_step_mm(segments, chord_tol_mm):
    """Longest step whose linear moves stay within `chord_tol_mm` of curved `segments`, mm.

    Lines: no limit (inf). An arc of radius r: the arc length 2 r acos(1 - tol / r)
    whose chord lies `tol` from the arc at most. A spline (Polyline, already within the
    chord tolerance of the curve): its shortest sample spacing, so a move skips at most
    one sample.
    """
    tol = float(chord_tol_mm)
    limit = np.inf
    for seg in segments:
        if seg.kind == "arc":
            r = seg.radius
            limit = min(limit, 2.0 * r * np.arccos(max(-1.0, 1.0 - tol / r)))
        elif hasattr(seg, "points") and len(seg.points) > 1:
            limit = min(limit, float(np.linalg.norm(np.diff(seg.points, axis=0), axis=1).min()))
    return limit


def area_step_mm(segments, R_u_t, first, last, base_step_mm, chord_tol_mm,
                 max_turn_deg=MAX_TURN_PER_MOVE_DEG):
    """The default step of a risk area over segments first..last (1-based), and why.

    The rule: ``step = max(|v|·Δt, min(L·δ/θ, chord step))`` rounded down to 0.1 mm
    (never below |v|·Δt), where

    * ``|v|·Δt`` is the paper's step (eqs 8-13: one target per sample time at the
      path's speed; the path's InterpolationStep when set). It is the finest step
      used, and kept whenever the terms below do not allow a coarser one (then the
      tool may turn by more than δ per move, as the paper's program would);
    * ``L·δ/θ`` coarsens it so the tool turns by at most δ = `max_turn_deg` per
      move: the slerp turns it by θ (first to last orientation) evenly over the
      area's length L. The controller interpolates between targets itself; a
      target every |v|·Δt (1 mm at 10 mm/s and 0.1 s) only lengthens the program
      (764 moves for 0.8 m) without making the motion more exact;
    * the chord step (:func:`chord_step_mm`) keeps the linear moves on arcs and
      splines within the path's chord tolerance.

    Why it matters (docs/controllers.md): the posts split long programs at 999
    positions per Motoman job, 2,500 lines per KUKA file and 5,000 moves per UR
    script; at 1 mm a 0.8 m path with risk areas is about 800 moves, several
    jobs on a Motoman for no gain in accuracy. At δ = 2° a 90° corner takes 45
    moves whatever its length.

    Returns
    -------
    step_mm : float
    rule : str
        Which term decided, in words.
    """
    base = float(base_step_mm)
    inside = list(segments[first - 1:last])
    length = sum(seg.length for seg in inside)
    turn_deg = float(np.degrees(rotation_angle_between(R_u_t[first - 1], R_u_t[last - 1])))
    by_turn = length * max_turn_deg / turn_deg if turn_deg > 0.0 else np.inf
    by_chord = chord_step_mm(inside, chord_tol_mm)
    coarse = min(by_turn, by_chord, length if length > 0 else np.inf)
    if not np.isfinite(coarse) or coarse <= base:
        return base, "speed × sample time"
    step = max(base, np.floor(coarse * 10.0 + 1e-9) / 10.0)
    if step == base:
        return base, "speed × sample time"
    if by_chord <= by_turn and by_chord <= length:
        return float(step), "chord tolerance %.3g mm" % chord_tol_mm
    if by_turn <= length:
        return float(step), "at most %.3g° turn per move" % max_turn_deg
    return float(step), "one move per segment"
