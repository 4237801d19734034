"""Risk-area suggestions say their step and the moves they add (issue 14, item 8).

The five-segment path of test_marker_inheritance: 50 mm lines, "First" (down) on
segment 1, "Fourth" (turned 30 deg) on segment 4, so the tool turns 30 deg at
junction 3 only. Speed 10 mm/s, sample time 0.1 s: the paper's step is 1 mm.

Hand counts (generate's rules, see tests/core/test_risk_sizes.py): an area over
segments 3-4 (100 mm) replaces 2 line moves and 1 reorientation by
ceil(50 / s) twice. Default step: 100 mm * 2 deg / 30 deg = 6.667 -> 6.6 mm,
so 8 + 8 - 3 = +13 moves; at the paper's 1 mm it would be 100 - 3 = +97.
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
    assert found.jump_deg == pytest.approx(30.0)
    assert found.step_mm == pytest.approx(6.6)
    assert "2° turn per move" in found.step_rule
    assert found.moves_added == 13
    assert api.risk_area_step(cell, path, 3, 4) == (pytest.approx(6.6), found.step_rule, 13)
    assert api.risk_area_step(cell, path, 3, 4, step_mm=1.0)[2] == 97


def test_generate_makes_exactly_the_predicted_program(doc):
    cell, path = five_segment_cell(doc)[:2]
    now = api.program_move_count(cell)
    (found,) = api.suggest_risk_areas(cell, 10.0)
    api.make_risk_area(doc, cell, path, found.first_segment, found.last_segment, step_mm=found.step_mm)
    program = api.generate(cell)
    assert len(program.moves()) == now + found.moves_added
    assert sum(m.role == "risk" for m in program.moves()) == 16
    # The existing area now covers the corner: no more suggestions.
    assert api.suggest_risk_areas(cell, 10.0) == []


def test_the_paper_step_is_kept_where_it_is_coarse_enough(doc):
    cell, path = five_segment_cell(doc)[:2]
    path.Speed = 100.0                  # 100 mm/s * 0.1 s = 10 mm: 3 deg per move at 30 deg / 100 mm
    doc.recompute()
    (found,) = api.suggest_risk_areas(cell, 10.0)
    assert (found.step_mm, found.step_rule) == (pytest.approx(10.0), "speed × sample time")
    assert found.moves_added == 5 + 5 - 3


def test_bad_ranges_are_one_clear_error(doc):
    cell, path = five_segment_cell(doc)[:2]
    with pytest.raises(RiskAreaError, match="segments 1-5"):
        api.risk_area_step(cell, path, 4, 6)
    with pytest.raises(RiskAreaError, match="step_mm"):
        api.risk_area_step(cell, path, 3, 4, step_mm=0.0)
