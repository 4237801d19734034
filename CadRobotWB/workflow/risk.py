"""Risk areas: make them, suggest them where the tool turns sharply, their step and the
moves they add.

Part of the scripting API: :mod:`CadRobotWB.api` re-exports its public names.
"""

import math

from .. import preferences
from ..core import risk_suggestions
from ..errors import RiskAreaError
from ..objects import base, reader, risk_area, validate
from .common import check_type
from .program import generate


def make_risk_area(doc, cell, path, first_segment, last_segment, step_mm=None, name="RiskArea"):
    """Add a risk area over segments `first_segment`..`last_segment` (1-based) of `path`."""
    check_type(cell, "Cell", "cell")
    check_type(path, "RobotPath", "path")
    what = "Risk area '%s': " % name
    first, last = (validate.whole_in_range(v, what + w, -math.inf, error=RiskAreaError)
                   for v, w in ((first_segment, "first_segment"), (last_segment, "last_segment")))
    step = validate.number_in_range(step_mm or 0.0, what + "step_mm", 0.0, error=RiskAreaError)
    obj = risk_area.make(doc, name)
    obj.Path = path
    obj.FirstSegment = first
    obj.LastSegment = last
    obj.Step = step
    cell.addObject(obj)
    doc.recompute()
    return obj


def _path_step_mm(cell, path):
    """The paper's step of `path` as generate uses it: its InterpolationStep, else
    speed × the cell's sample time (eqs 8-13), mm."""
    return float(path.InterpolationStep) or (
        reader._positive(path, "Speed", float(path.Speed))
        * reader._positive(cell, "SampleTime", float(cell.SampleTime)))


def suggest_risk_areas(cell, threshold_deg=None):
    """Where the tool turns sharply between consecutive segments of `cell`'s paths.

    Parameters
    ----------
    threshold_deg : float, optional
        Smallest orientation change that needs a risk area, degrees;
        default the ``RiskThreshold`` preference.

    Returns
    -------
    list of RiskSuggestion
        ``(path, first_segment, last_segment, jump_deg, step_mm, step_rule,
        moves_added)``; junctions inside or next to an existing risk area are
        left out (it would overlap). ``step_mm`` is the step to give the area
        (:func:`core.risk_suggestions.area_step_mm`: the paper's speed × sample
        time, coarsened so the tool turns by at most
        ``risk_suggestions.MAX_TURN_PER_MOVE_DEG`` per move, within the path's
        chord tolerance on arcs and splines), ``step_rule`` says which term
        decided, ``moves_added`` how many moves the area adds to the program
        at that step (exactly as :func:`generate` writes it).

    Raises
    ------
    MarkerError
        Two tool markers set one segment with different orientations, or
        segments come before a path's first marker (the message names them).
    """
    check_type(cell, "Cell", "cell")
    threshold = preferences.get("RiskThreshold") if threshold_deg is None else float(threshold_deg)
    out = []
    for path, R_u_t, areas in reader.path_orientations(cell):
        segments = reader.path_geometry(path)[0]
        base_step = _path_step_mm(cell, path)
        jumps = risk_suggestions.junction_jumps_deg(R_u_t)
        for found in risk_suggestions.suggest(jumps, threshold, areas, path=path):
            first, last = found.first_segment, found.last_segment
            step, rule = risk_suggestions.area_step_mm(segments, R_u_t, first, last, base_step,
                                                       float(path.ChordTolerance))
            out.append(found._replace(step_mm=step, step_rule=rule, moves_added=risk_suggestions.moves_added(
                segments, R_u_t, first, last, step)))
    return out


def risk_area_step(cell, path, first_segment, last_segment, step_mm=None):
    """The default step of a risk area over segments first..last (1-based) of `path`,
    and the moves it adds (the rule of :func:`suggest_risk_areas`).

    Parameters
    ----------
    step_mm : float, optional
        A step to count the moves at instead (mm, > 0).

    Returns
    -------
    (step_mm, rule, moves_added) : (float, str, int)
    """
    check_type(cell, "Cell", "cell")
    check_type(path, "RobotPath", "path")
    for found, R_u_t, _areas in reader.path_orientations(cell):
        if found.Name != path.Name:
            continue
        segments = reader.path_geometry(path)[0]
        first, last = int(first_segment), int(last_segment)
        if not 1 <= first <= last <= len(segments):
            raise RiskAreaError("Path %s has segments 1-%d; a risk area over %d-%d does not fit. "
                                "Choose consecutive segments within 1-%d."
                                % (base.describe(path), len(segments), first, last, len(segments)),
                                path.Name)
        if step_mm is None:
            base_step = _path_step_mm(cell, path)
            step, rule = risk_suggestions.area_step_mm(segments, R_u_t, first, last, base_step,
                                                       float(path.ChordTolerance))
        else:
            step = validate.number_in_range(step_mm, "Risk area step_mm", 0.0, low_open=True,
                                            error=RiskAreaError)
            rule = "given"
        return step, rule, risk_suggestions.moves_added(segments, R_u_t, first, last, step)
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
    return len(generate(cell).moves())
