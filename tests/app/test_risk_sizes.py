"""Risk-area suggestions say their step and the moves they add (issues 14 item 8, 20 item 1).

The five-segment path of test_marker_inheritance: 50 mm lines, "First" (down) on
segment 1, "Fourth" (turned 30 deg) on segment 4, so the tool turns 30 deg at
junction 3 only. Speed 10 mm/s, sample time 0.1 s: the paper's step is 1 mm.

Hand counts (generate's rules, see tests/core/test_risk_sizes.py). The suggestion
is a corner area: span min(5 mm, 50 mm / 4) = 5 mm at the end of segment 3 and the
start of segment 4, 10 mm turning 30 deg: step 10 mm * 2 deg / 30 deg = 0.667 ->
0.66 mm (finer than the paper's 1 mm, so no move turns more than 2 deg). It writes
segment 3 to 45 mm (1 move), ceil(5 / 0.66) = 8 risk moves twice, segment 4 from
5 mm (1 move): 18 moves for the 2 lines and 1 reorientation before, +15.
A whole-segment area over 3-4 (100 mm, the paper's case) keeps the old rule:
100 mm * 2 deg / 30 deg = 6.667 -> 6.6 mm, so 8 + 8 - 3 = +13 moves; at the paper's
1 mm it would be 100 - 3 = +97.
"""

import pytest

from CadRobotWB import api
from CadRobotWB.errors import RiskAreaError
from test_marker_inheritance import five_segment_cell


def test_suggestion_states_step_and_moves_added(doc):
    cell, path = five_segment_cell(doc)[:2]
    assert float(cell.SampleTime) == pytest.approx(0.1) and float(path.Speed) == pytest.approx(10.0)
    (found,) = api.suggest_risk_areas(cell, 10.0)
    assert (found.first_segment, found.last_segment) == (3, 4)
    assert found.jump_deg == pytest.approx(30.0) and found.turn_deg == pytest.approx(30.0)
    assert (found.corner_span_mm, found.at_corner) == (5.0, "Weld through")
    assert found.step_mm == pytest.approx(0.66)
    assert "2° turn per move round the corner" in found.step_rule
    assert found.moves_added == 15
    assert api.risk_area_step(cell, path, 3, 4, corner_span_mm=5.0) == (pytest.approx(0.66), found.step_rule, 15)
    # Whole segments (the paper's case): the rule of issue 14.
    step, rule, added = api.risk_area_step(cell, path, 3, 4)
    assert (step, added) == (pytest.approx(6.6), 13) and "2° turn per move" in rule
    assert api.risk_area_step(cell, path, 3, 4, step_mm=1.0)[2] == 97


def test_generate_makes_exactly_the_predicted_program(doc):
    cell, path = five_segment_cell(doc)[:2]
    now = api.program_move_count(cell)
    (found,) = api.suggest_risk_areas(cell, 10.0)
    api.make_risk_area(doc, cell, path, found.first_segment, found.last_segment, step_mm=found.step_mm,
                       corner_span_mm=found.corner_span_mm, at_corner=found.at_corner)
    program = api.generate(cell)
    assert len(program.moves()) == now + found.moves_added
    assert sum(m.role == "risk" for m in program.moves()) == 16
    # The existing area now covers the corner: no more suggestions.
    assert api.suggest_risk_areas(cell, 10.0) == []


def test_the_paper_step_is_kept_where_it_is_coarse_enough(doc):
    cell, path = five_segment_cell(doc)[:2]
    path.Speed = 100.0                  # 100 mm/s * 0.1 s = 10 mm: 3 deg per move at 30 deg / 100 mm
    doc.recompute()
    assert api.risk_area_step(cell, path, 3, 4) == (pytest.approx(10.0), "speed × sample time", 5 + 5 - 3)
    # The corner area turns 30 deg over 10 mm: finer than the paper's step, 2 deg per move.
    (found,) = api.suggest_risk_areas(cell, 10.0)
    assert found.step_mm == pytest.approx(0.66)


def test_bad_ranges_are_one_clear_error(doc):
    cell, path = five_segment_cell(doc)[:2]
    with pytest.raises(RiskAreaError, match="segments 1-5"):
        api.risk_area_step(cell, path, 4, 6)
    with pytest.raises(RiskAreaError, match="step_mm"):
        api.risk_area_step(cell, path, 3, 4, step_mm=0.0)
