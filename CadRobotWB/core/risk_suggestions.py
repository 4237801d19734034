"""Where a path needs a risk area: junctions where the tool turns sharply (pure numpy).

Junction j (1-based) joins segments j and j + 1; on a closed path junction n
joins the last segment to the first (where the loop closes). Each junction
whose tool orientations differ by more than a threshold gets its own area
(paper section 3.3), short enough that the tool keeps its angles along the
rest of both segments: the area covers the last `corner_span_mm` of segment
j and the first of segment j + 1 (:func:`corner_span_mm`).
"""

from collections import namedtuple

import numpy as np

from . import interpolation
from .generate import (MAX_TURN_PER_MOVE_DEG, ORIENTATION_TOL_RAD, STOP_AND_REORIENT,
                       WELD_THROUGH, PathSpec, RiskAreaSpec, _PathWriter)
from .program import WorkFrame
from .rotations import rotation_angle_between
from .segment_orientation import CONSTANT, segment_orientations

# A suggested risk area over segments first..last (1-based, inclusive; n..1 for the corner
# where a closed path's loop closes) of a path; jump_deg is the largest orientation change at
# one junction inside it, degrees. step_mm: the suggested interpolation step (mm, see
# area_step_mm), step_rule: why that step (text), moves_added: the moves the area adds to the
# program at that step (see moves_added), corner_span_mm: the length of each segment next to
# the corner the area covers (mm; 0: whole segments), at_corner: WELD_THROUGH or
# STOP_AND_REORIENT, turn_deg: the turn the area makes, summed through its keyframes (degrees;
# see area_turn_deg). All but the first four are None from suggest() alone.
RiskSuggestion = namedtuple("RiskSuggestion",
                            "path first_segment last_segment jump_deg step_mm step_rule moves_added "
                            "corner_span_mm at_corner turn_deg",
                            defaults=(None, None, None, None, None, None))

#: Longest corner span a suggestion gives, mm: a torch turning over more leaves the bisector
#: of the fillet along that length.
MAX_CORNER_SPAN_MM = 5.0


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


def junction_turns_deg(laws, closed=False):
    """Jumps of the tool orientation at the junctions, from each segment's end to the next's start.

    Parameters
    ----------
    laws : sequence of segment_orientation.SegmentOrientation
        One per segment (on a turning arc the orientation at its ends differs).
    closed : bool
        Add the junction from the last segment's end to the first's start.

    Returns
    -------
    ndarray, shape (N - 1,) or (N,) when closed
        Degrees, junction j at element j - 1.
    """
    ends = [law.end for law in laws]
    starts = [law.start for law in laws]
    pairs = list(zip(ends[:-1], starts[1:])) + ([(ends[-1], starts[0])] if closed and len(laws) > 1 else [])
    return np.array([0.0 if a is b else np.degrees(rotation_angle_between(a, b)) for a, b in pairs])


def suggest(jumps_deg, threshold_deg, existing=(), path=None, closing_jump_deg=None):
    """One risk area per junction turning by more than `threshold_deg`.

    Parameters
    ----------
    jumps_deg : array_like, shape (N - 1,)
        Orientation jump at each junction, degrees (see :func:`junction_jumps_deg`).
    threshold_deg : float
        Jumps strictly above this need an area.
    existing : sequence of (int, int) or (int, int, float)
        Risk areas already on the path: (first, last) 1-based inclusive, and
        their corner span (mm; 0 or missing: whole segments). A junction inside
        one is left out; so is a junction touching a segment of a whole-segment
        one (an area there would overlap it).
    path : object, optional
        Stored in each suggestion's ``path``.
    closing_jump_deg : float, optional
        On a closed path, the jump from the last segment to the first: above
        the threshold it gets an area over segments n..1, unless one is there.

    Returns
    -------
    list of RiskSuggestion
        In path order, segments j..j + 1 for junction j.
    """
    jumps = np.asarray(jumps_deg, dtype=float)
    n_segments = len(jumps) + 1
    inside, touched, closing_done = set(), set(), False
    for area in existing:
        first, last = int(area[0]), int(area[1])
        span = float(area[2]) if len(area) > 2 and area[2] else 0.0
        if first > last:
            closing_done = True
            continue
        inside.update(range(first, last))
        if span == 0.0:
            touched.update(range(first - 1, last + 1))
    out = [RiskSuggestion(path, j, j + 1, float(jump)) for j, jump in enumerate(jumps, start=1)
           if jump > threshold_deg and j not in inside and j not in touched]
    if closing_jump_deg is not None and closing_jump_deg > threshold_deg and not closing_done:
        out.append(RiskSuggestion(path, n_segments, 1, float(closing_jump_deg)))
    return out


def corner_span_mm(segment_lengths_mm, max_span_mm=MAX_CORNER_SPAN_MM):
    """The corner span a suggestion gives the junction between two segments, mm.

    ``min(max_span_mm, a quarter of the shorter segment)`` rounded down to
    0.1 mm: the torch turns over at most 2 x 5 mm round the corner and keeps
    its angles on the rest of both segments; a quarter keeps the span clear of
    a marker at the segment's middle (automatic markers sit there) and of the
    span of the junction at the segment's other end.
    """
    quarter = min(float(L) for L in segment_lengths_mm) / 4.0
    return float(np.floor(min(max_span_mm, quarter) * 10.0 + 1e-9) / 10.0)


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


def moves_added(segments, R_u_t, first, last, step_mm, corner_span_mm=None, at_corner=WELD_THROUGH,
                marker_s_mm=None, tool_on_arcs=CONSTANT, closed=False):
    """Moves a risk area over segments first..last (1-based) at `step_mm` adds to the program.

    Parameters
    ----------
    segments : sequence of core segments
        The whole path, in travel order, mm.
    R_u_t : sequence of ndarray, shape (3, 3)
        One orientation per segment.
    step_mm : float
        The area's interpolation step, mm.
    corner_span_mm, at_corner :
        The area's (see :class:`core.generate.RiskAreaSpec`).
    marker_s_mm, tool_on_arcs, closed :
        The path's (see :class:`core.generate.PathSpec`).

    Returns
    -------
    int
        Moves with the area minus moves without it (negative when it has fewer).
        A whole-segment area on a path whose tool keeps its orientation on arcs
        is counted by the rules above; any other by writing the segments it
        covers with and without it, as generate does.
    """
    plain = (not corner_span_mm and at_corner == WELD_THROUGH and tool_on_arcs == CONSTANT
             and first <= last)
    if plain:
        inside = list(segments[first - 1:last])
        without = sum(segment_moves(seg) for seg in inside) + reorient_moves(R_u_t, first, last)
        return area_moves(inside, step_mm) - without
    area = RiskAreaSpec("count", "count", first, last, step_mm, corner_span_mm, at_corner)
    if first > last and corner_span_mm and at_corner == WELD_THROUGH:
        # the corner where a closed loop closes, turned over its spans: the whole loop written
        def count(areas):
            spec = PathSpec(name="count", label="count", segments=list(segments), R_u_t=list(R_u_t),
                            frame="B", approach_mm=0.0, retract_mm=0.0, risk_areas=areas, closed=True,
                            marker_s_mm=marker_s_mm, tool_on_arcs=tool_on_arcs)
            frame = WorkFrame(name="B", T_r_b=np.eye(4), T_u_b=np.eye(4))
            return len(_PathWriter(spec, "count", frame, set()).write())
        return count([area]) - count([])
    if first > last:          # the corner where a closed loop closes: only its pivot
        laws = segment_orientations(segments, R_u_t, marker_s_mm, tool_on_arcs, closed)
        angle = np.degrees(rotation_angle_between(laws[-1].end, laws[0].start))
        if angle <= np.degrees(ORIENTATION_TOL_RAD):
            return 0
        return 1 if at_corner == STOP_AND_REORIENT else int(np.ceil(angle / MAX_TURN_PER_MOVE_DEG - 1e-9))
    covered = (segments, R_u_t, marker_s_mm, tool_on_arcs, first, last)
    with_area = len(_covered_writer(*covered, area=area, closed=closed).write())
    return with_area - len(_covered_writer(*covered, closed=closed).write())


def area_turn_deg(segments, R_u_t, first, last, corner_span_mm=None, marker_s_mm=None,
                  tool_on_arcs=CONSTANT, closed=False):
    """The turn a risk area really makes: the angles between its consecutive keyframes
    (start, each marker inside, end; see core.generate), summed, degrees.

    For the corner where a closed loop closes (first > last): the last segment's end
    orientation against the first's start.
    """
    if first > last:
        laws = segment_orientations(segments, R_u_t, marker_s_mm, tool_on_arcs, closed)
        return float(np.degrees(rotation_angle_between(laws[-1].end, laws[0].start)))
    area = RiskAreaSpec("turn", "turn", first, last, None, corner_span_mm)
    writer = _covered_writer(segments, R_u_t, marker_s_mm, tool_on_arcs, first, last, area, closed)
    placed = writer.areas[0]
    _positions, quats = writer._keyframes(writer._area_portions(placed))
    dots = np.clip(np.abs(np.sum(quats[:-1] * quats[1:], axis=1)), 0.0, 1.0)
    return float(np.degrees(np.sum(2.0 * np.arccos(dots))))


def _covered_writer(segments, R_u_t, marker_s_mm, tool_on_arcs, first, last, area=None, closed=False):
    """The path writer of generate on segments first..last (1-based) alone, each with the
    orientation law it has on the whole path (`closed` or not), with `area` (renumbered)
    or none."""
    laws = segment_orientations(segments, R_u_t, marker_s_mm, tool_on_arcs, closed)
    own = [laws[first - 1].R_ref] + list(R_u_t[first:last])
    if marker_s_mm is not None:
        marker_s = [laws[first - 1].s_ref] + list(marker_s_mm[first:last])
    elif tool_on_arcs == CONSTANT:
        marker_s = None
    else:
        marker_s = [laws[first - 1].s_ref] + [None if R_u_t[j] is R_u_t[j - 1] else 0.0
                                              for j in range(first, last)]
    areas = [] if area is None else [RiskAreaSpec(area.name, area.label, 1, last - first + 1, area.step_mm,
                                                  area.corner_span_mm, area.at_corner)]
    spec = PathSpec(name="count", label="count", segments=list(segments[first - 1:last]), R_u_t=own,
                    frame="B", approach_mm=0.0, retract_mm=0.0, risk_areas=areas,
                    marker_s_mm=marker_s, tool_on_arcs=tool_on_arcs)
    frame = WorkFrame(name="B", T_r_b=np.eye(4), T_u_b=np.eye(4))
    writer = _PathWriter(spec, "count", frame, set())
    writer.laws = laws[first - 1:last]      # with the leans and leads the whole path gives them
    return writer


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
                 max_turn_deg=MAX_TURN_PER_MOVE_DEG, corner_span_mm=None, turn_deg=None):
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

    A corner area (`corner_span_mm` > 0: the tool turns over a few mm round
    the corner) takes ``min(|v|·Δt, L·δ/θ)`` rounded down to 0.01 mm instead:
    finer than the paper's step where that is needed to keep every move's
    turn within δ (at 1 mm spans a 90° corner turns over 2 mm: 45 moves of
    0.04 mm), and within the chord step on arcs.

    `turn_deg` is θ when given (the turn summed through the area's markers,
    :func:`area_turn_deg`); default the first against the last orientation.

    Returns
    -------
    step_mm : float
    rule : str
        Which term decided, in words.
    """
    base = float(base_step_mm)
    # a closed loop's closing corner (first = n, last = 1) covers the end of n and the start of 1
    inside = list(segments[first - 1:last]) if first <= last else [segments[first - 1], segments[last - 1]]
    if turn_deg is None:
        turn_deg = float(np.degrees(rotation_angle_between(R_u_t[first - 1], R_u_t[last - 1])))
    if corner_span_mm:
        return _corner_step_mm(inside, float(corner_span_mm), base, chord_tol_mm, max_turn_deg, turn_deg)
    length = sum(seg.length for seg in inside)
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


def _corner_step_mm(inside, span_mm, base_step_mm, chord_tol_mm, max_turn_deg, turn_deg):
    """(step, rule) of a corner area over `inside` segments, `span_mm` into the first and last."""
    ends = [min(span_mm, inside[0].length), min(span_mm, inside[-1].length)]
    length = sum(ends) + sum(seg.length for seg in inside[1:-1])
    by_turn = length * max_turn_deg / turn_deg if turn_deg > 0.0 else np.inf
    limit = min(by_turn, chord_step_mm(inside, chord_tol_mm))
    if limit >= base_step_mm:
        return float(base_step_mm), "speed × sample time"
    step = max(0.01, np.floor(limit * 100.0 + 1e-9) / 100.0)
    if by_turn <= limit:
        return float(step), "at most %.3g° turn per move round the corner" % max_turn_deg
    return float(step), "chord tolerance %.3g mm" % chord_tol_mm
