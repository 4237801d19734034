"""Risk areas: make them, suggest them where the tool turns sharply, their step and the
moves they add.

Part of the scripting API: :mod:`CadRobotWB.api` re-exports its public names.
"""

import math

from .. import preferences
from ..core import risk_suggestions
from ..core.generate import AT_CORNER, WELD_THROUGH
from ..core.segment_orientation import segment_orientations
from ..errors import RiskAreaError
from ..objects import base, reader, risk_area, validate
from .arguments import Arguments

#: What at_corner is, in messages.
AT_CORNER_TEXT = 'None or one of %s (a str)' % ', '.join('"%s"' % c for c in AT_CORNER)
from .program import generate


def make_risk_area(doc, cell, path, first_segment, last_segment, step_mm=None, name="RiskArea",
                   corner_span_mm=None, at_corner=None):
    """Add a risk area over segments `first_segment`..`last_segment` (1-based) of `path`.

    Parameters
    ----------
    step_mm : float, optional
        Interpolation step, mm; default the path's (speed × sample time).
    corner_span_mm : float, optional
        Cover only the last `corner_span_mm` of the first segment and the first
        of the last (the corner between them), mm; default 0: whole segments.
    at_corner : {"Weld through", "Stop and reorient"}, optional
        Weld on while the tool turns (default), or stop exactly, turn in place
        and go on (the move is marked for arc off/on).

    On a closed path, `first_segment` = its last segment and `last_segment` = 1
    is the corner where the loop closes: the tool turns round the end point.
    """
    args = Arguments("make_risk_area")
    args.open_document("doc", doc)
    _check_area_arguments(args, cell, path, first_segment, last_segment, step_mm, corner_span_mm,
                          at_corner)
    args.text("name", name)
    what = "Risk area '%s': " % name
    first, last = _segment_numbers(first_segment, last_segment, what)
    step = validate.number_in_range(step_mm or 0.0, what + "step_mm", 0.0, error=RiskAreaError)
    span = validate.number_in_range(corner_span_mm or 0.0, what + "corner_span_mm", 0.0, error=RiskAreaError)
    corner = WELD_THROUGH if at_corner is None else _at_corner(at_corner, what)
    obj = risk_area.make(doc, name)
    obj.Path = path
    obj.FirstSegment = first
    obj.LastSegment = last
    obj.Step = step
    obj.CornerSpan = span
    obj.AtCorner = corner
    cell.addObject(obj)
    doc.recompute()
    return obj


def _check_area_arguments(args, cell, path, first_segment, last_segment, step_mm, corner_span_mm,
                          at_corner):
    """Check with `args` the types of the arguments that say a risk area of `cell`'s `path`."""
    args.cell(cell)
    args.document_object("path", path, "RobotPath")
    for argument, value in (("first_segment", first_segment), ("last_segment", last_segment)):
        args.number(argument, value, expected="a segment number (a whole number)")
    args.number("step_mm", step_mm, optional=True, expected="None or a step in mm (a number)")
    args.number("corner_span_mm", corner_span_mm, optional=True, expected="None or a length in mm (a number)")
    args.text("at_corner", at_corner, optional=True, expected=AT_CORNER_TEXT)


def _segment_numbers(first_segment, last_segment, what):
    """(first, last) as ints; RiskAreaError naming `what` for numbers that are not whole."""
    return tuple(validate.whole_in_range(v, what + w, -math.inf, error=RiskAreaError)
                 for v, w in ((first_segment, "first_segment"), (last_segment, "last_segment")))


def _at_corner(value, what):
    """The AT_CORNER choice `value` names (case and spacing as typed do not matter)."""
    for choice in AT_CORNER:
        if str(value).strip().lower() == choice.lower():
            return choice
    raise RiskAreaError("%sat_corner is %r; use one of %s." % (what, value, ", ".join('"%s"' % c for c in AT_CORNER)))


def _path_step_mm(cell, path):
    """The paper's step of `path` as generate uses it: its InterpolationStep, else
    speed × the cell's sample time (eqs 8-13), mm."""
    return float(path.InterpolationStep) or (
        reader._positive(path, "Speed", float(path.Speed))
        * reader._positive(cell, "SampleTime", float(cell.SampleTime)))


def suggest_risk_areas(cell, threshold_deg=None, at_corner=None):
    """Where the tool turns sharply between consecutive segments of `cell`'s paths.

    Parameters
    ----------
    threshold_deg : float, optional
        Smallest orientation change that needs a risk area, degrees;
        default the ``RiskThreshold`` preference.
    at_corner : {"Weld through", "Stop and reorient"}, optional
        What the suggested areas do at their corners (default "Weld
        through"); their moves_added follow it.

    Returns
    -------
    list of RiskSuggestion
        One per junction turning by more than the threshold (on a closed path
        also where the loop closes: segments n..1), in path order:
        ``(path, first_segment, last_segment, jump_deg, step_mm, step_rule,
        moves_added, corner_span_mm, at_corner, turn_deg)``. Junctions inside
        an existing risk area, or next to a whole-segment one, are left out.
        ``corner_span_mm`` is :func:`core.risk_suggestions.corner_span_mm` of
        the two segments (0 where a loop closes: the tool turns round the end
        point), ``at_corner`` as given, ``turn_deg`` the turn the area
        makes (summed through its keyframes), ``step_mm`` the step to give it
        (:func:`core.risk_suggestions.area_step_mm`), ``step_rule`` which term
        decided it, ``moves_added`` the moves the area adds to the program at
        that step (exactly as :func:`generate` writes it).

    Raises
    ------
    MarkerError
        Two tool markers set one segment with different orientations, or
        segments come before a path's first marker (the message names them).
    """
    args = Arguments("suggest_risk_areas")
    args.cell(cell)
    args.number("threshold_deg", threshold_deg, optional=True, expected="None or an angle in degrees (a number)")
    args.text("at_corner", at_corner, optional=True, expected=AT_CORNER_TEXT)
    threshold = preferences.get("RiskThreshold") if threshold_deg is None else float(threshold_deg)
    corner = WELD_THROUGH if at_corner is None else _at_corner(at_corner, "Risk area suggestions: ")
    out = []
    for found in reader.path_tool_orientations(cell):
        segments, path = found.segments, found.path
        laws = segment_orientations(segments, found.R_u_t, found.marker_s_mm, found.tool_on_arcs,
                                    found.closed)
        jumps = risk_suggestions.junction_turns_deg(laws, found.closed)
        closing = jumps[-1] if found.closed and len(segments) > 1 else None
        inner = jumps[:-1] if closing is not None else jumps
        existing = [(a.first, a.last, a.corner_span_mm or 0.0) for a in found.risk_areas]
        base_step = _path_step_mm(cell, path)
        for suggestion in risk_suggestions.suggest(inner, threshold, existing, path=path,
                                                   closing_jump_deg=closing):
            first, last = suggestion.first_segment, suggestion.last_segment
            span = risk_suggestions.corner_span_mm([segments[first - 1].length,
                                                    segments[last - 1].length])
            out.append(_sized(cell, found, suggestion._replace(corner_span_mm=span, at_corner=corner),
                              base_step))
    return out


def _sized(cell, found, suggestion, base_step):
    """`suggestion` with its turn, step, step rule and the moves it adds."""
    first, last, span = suggestion.first_segment, suggestion.last_segment, suggestion.corner_span_mm
    turn = risk_suggestions.area_turn_deg(found.segments, found.R_u_t, first, last, span,
                                          found.marker_s_mm, found.tool_on_arcs, found.closed)
    if first > last and not span:       # the pivot round the end point has no step of its own
        step, rule = base_step, "the tool turns in place, at most %g° per move" % (
            risk_suggestions.MAX_TURN_PER_MOVE_DEG)
    else:
        step, rule = risk_suggestions.area_step_mm(found.segments, found.R_u_t, first, last, base_step,
                                                   float(found.path.ChordTolerance), corner_span_mm=span,
                                                   turn_deg=turn)
    added = risk_suggestions.moves_added(found.segments, found.R_u_t, first, last, step, span,
                                         suggestion.at_corner, found.marker_s_mm, found.tool_on_arcs,
                                         found.closed)
    return suggestion._replace(step_mm=step, step_rule=rule, moves_added=added, turn_deg=turn)


def risk_area_step(cell, path, first_segment, last_segment, step_mm=None, corner_span_mm=None,
                   at_corner=None):
    """The default step of a risk area over segments first..last (1-based) of `path`,
    and the moves it adds (the rule of :func:`suggest_risk_areas`).

    Parameters
    ----------
    step_mm : float, optional
        A step to count the moves at instead (mm, > 0).
    corner_span_mm, at_corner : optional
        As :func:`make_risk_area`'s.

    Returns
    -------
    (step_mm, rule, moves_added) : (float, str, int)
    """
    _check_area_arguments(Arguments("risk_area_step"), cell, path, first_segment, last_segment, step_mm,
                          corner_span_mm, at_corner)
    first, last = _segment_numbers(first_segment, last_segment, "Risk area: ")
    for found in reader.path_tool_orientations(cell):
        if found.path.Name != path.Name:
            continue
        segments = found.segments
        closing = found.closed and (first, last) == (len(segments), 1) and len(segments) > 1
        if not (1 <= first <= last <= len(segments) or closing):
            raise RiskAreaError("Path %s has segments 1-%d; a risk area over %d-%d does not fit. "
                                "Choose consecutive segments within 1-%d."
                                % (base.describe(path), len(segments), first, last, len(segments)),
                                path.Name)
        corner = WELD_THROUGH if at_corner is None else _at_corner(at_corner, "Risk area: ")
        suggestion = risk_suggestions.RiskSuggestion(path, first, last, None, corner_span_mm=corner_span_mm or 0.0,
                                                     at_corner=corner)
        sized = _sized(cell, found, suggestion, _path_step_mm(cell, path))
        if step_mm is None:
            return sized.step_mm, sized.step_rule, sized.moves_added
        step = validate.number_in_range(step_mm, "Risk area step_mm", 0.0, low_open=True,
                                        error=RiskAreaError)
        return step, "given", risk_suggestions.moves_added(
            segments, found.R_u_t, first, last, step, corner_span_mm, corner, found.marker_s_mm,
            found.tool_on_arcs, found.closed)
    raise RiskAreaError("Path %s is not in cell %s." % (base.describe(path), base.describe(cell)), path.Name)


def program_move_count(cell):
    """How many moves :func:`generate` writes for `cell` now (its existing risk areas included).

    With :func:`suggest_risk_areas`, the program's size with suggestions
    taken is this plus their ``moves_added``.

    Raises
    ------
    CadRobotError
        What keeps the cell from generating.
    """
    Arguments("program_move_count").cell(cell)
    return len(generate(cell).moves())
