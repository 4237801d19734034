"""Welds in the generated program (issue 22): which moves weld, where the arc goes on and
off, at what speed and zone; and the rules of the weld runs (core/weld_runs.check_runs).

Every marker here is DOWN turned about Z of {U}, {B} = {U}, so targets read directly in
{U}. The schedule is the fixtures' fillet_t6: travel 7.5 mm/s; the paths run at 10 mm/s
with zone 2 mm (test_generate.make_path), so a welded move is told from an unwelded one by
its speed.
"""

import dataclasses
import math

import numpy as np
import pytest

from CadRobotWB.core import program as ir
from CadRobotWB.core import generate as gen
from CadRobotWB.core.generate import RiskAreaSpec, generate
from CadRobotWB.core.geometry import Arc, Line
from CadRobotWB.core.weld_runs import check_runs
from CadRobotWB.core.welding import WeldSpec
from CadRobotWB.errors import GeometryError, InputError
from test_generate import make_cell, make_path
from test_risk_corners import rz, square_loop
from weld_fixtures import FILLET_T6, ZIGZAG_4MM, corner_stop_program, woven_fillet_program

TRAVEL = FILLET_T6.travel_speed_mm_s          # 7.5 mm/s
PATH_SPEED = 10.0


def three_legs():
    """(0,0) -> (50,0) -> (50,50) -> (0,50): three lines, corners of 90 degrees."""
    return [Line((0, 0, 0), (50, 0, 0), "A"), Line((50, 0, 0), (50, 50, 0), "B"),
            Line((50, 50, 0), (0, 50, 0), "C")]


def weld(first=None, last=None, name="Fillet", label="Fillet weld", schedule=FILLET_T6):
    return WeldSpec(name, label, schedule, ZIGZAG_4MM, first_segment=first, last_segment=last)


def program_of(segments, R, welds, **kw):
    kw.setdefault("name", "Seam")
    return generate(make_cell([make_path(segments, R, welds=welds, **kw)], T_u_b=np.eye(4)))


def xyz(move):
    return tuple(np.round(move.target.T_b_t[:3, 3], 9) + 0.0)


def welded(path, run):
    return path.moves[run.start + 1:run.end + 1]


# --- where the arc goes on and off ------------------------------------------------------------

def test_a_weld_on_the_whole_path_ignites_at_the_entry():
    path = program_of(three_legs(), [rz(0)] * 3, [weld()]).paths[0]
    roles = [m.role for m in path.moves]
    assert roles == ["approach", "entry", "path", "path", "path", "retract"]
    (run,) = path.welds
    assert (run.name, run.label, run.start, run.end, run.part) == ("Fillet", "Fillet weld", 1, 4, 1)
    assert (run.first_segment, run.last_segment) == (1, 3)
    entry = path.moves[run.start]
    assert entry.role == ir.ROLE_ENTRY and xyz(entry) == (0, 0, 0)     # the seam start, on the part
    assert [m.weld for m in path.moves] == [None, None, "Fillet", "Fillet", "Fillet", None]
    assert [m.speed_mm_s for m in path.moves] == [100.0, 100.0, TRAVEL, TRAVEL, TRAVEL, 100.0]
    assert [m.zone_mm for m in path.moves] == [0.0, 0.0, 2.0, 2.0, 0.0, 0.0]   # continuous inside
    assert entry.comment.endswith("(arc on: Fillet)")
    assert path.moves[4].comment.endswith("(arc off: Fillet)")
    assert run.schedule == FILLET_T6 and run.weave == ZIGZAG_4MM


def test_a_weld_from_segment_2_starts_where_segment_1_ends_and_stops_there():
    path = program_of(three_legs(), [rz(0)] * 3, [weld(2, 2)]).paths[0]
    (run,) = path.welds
    assert (run.start, run.end, run.first_segment, run.last_segment) == (2, 3, 2, 2)
    start, only, after = path.moves[2], path.moves[3], path.moves[4]
    assert start.segment == 1 and xyz(start) == (50, 0, 0)          # the end of segment 1
    assert (start.weld, start.speed_mm_s, start.zone_mm) == (None, PATH_SPEED, 0.0)
    assert "reached along the path" in start.comment
    assert (only.weld, only.speed_mm_s, only.zone_mm) == ("Fillet", TRAVEL, 0.0)
    assert xyz(only) == (50, 50, 0)                                 # the end of segment 2
    assert (after.weld, after.speed_mm_s) == (None, PATH_SPEED)    # on without arc


def test_two_welds_that_touch_put_the_arc_out_and_on_again_at_their_junction():
    other = dataclasses.replace(FILLET_T6, name="slower", travel_speed_mm_s=5.0)
    path = program_of(three_legs(), [rz(0)] * 3,
                      [weld(2, 3, name="Second", schedule=other), weld(1, 1)]).paths[0]
    first, second = path.welds                                      # in path order
    assert (first.name, first.start, first.end, second.name, second.start, second.end) == (
        "Fillet", 1, 2, "Second", 2, 4)
    assert [m.speed_mm_s for m in path.moves[2:5]] == [TRAVEL, 5.0, 5.0]
    assert path.moves[2].zone_mm == 0.0 and path.moves[2].weld == "Fillet"


def test_without_an_approach_distance_the_arc_ignites_at_the_approach_target():
    path = program_of(three_legs(), [rz(0)] * 3, [weld()], approach_mm=0.0).paths[0]
    (run,) = path.welds
    assert run.start == 0 and path.moves[0].kind == ir.JOINT and xyz(path.moves[0]) == (0, 0, 0)


def test_a_stop_and_reorient_corner_splits_the_weld_at_the_turn():
    area = RiskAreaSpec("R", "Corner", 1, 2, at_corner=gen.STOP_AND_REORIENT)
    path = program_of(three_legs(), [rz(0), rz(90), rz(90)], [weld()], risk_areas=[area]).paths[0]
    assert [m.role for m in path.moves] == ["approach", "entry", "path", "reorient", "path", "path",
                                           "retract"]
    first, second = path.welds
    assert (first.name, first.start, first.end, first.part) == ("Fillet", 1, 2, 1)
    assert (second.name, second.start, second.end, second.part) == ("Fillet_2", 3, 5, 2)
    assert (first.first_segment, first.last_segment, second.first_segment, second.last_segment) == (
        1, 1, 2, 3)
    turn = path.moves[3]
    assert xyz(turn) == xyz(path.moves[2]) == (50, 0, 0) and turn.weld is None
    assert path.moves[2].zone_mm == 0.0 and turn.zone_mm == 0.0
    assert turn.comment.startswith("corner stop (arc off at the previous target: Fillet; arc on "
                                   "here after the turn: Fillet_2): segment 2: reorient")
    assert [m.weld for m in path.moves] == [None, None, "Fillet", None, "Fillet_2", "Fillet_2", None]
    assert path.moves[4].zone_mm == 2.0


def test_a_junction_turn_without_a_risk_area_restarts_the_arc_too():
    path = program_of(three_legs(), [rz(0), rz(90), rz(90)], [weld()]).paths[0]
    assert [(r.name, r.start, r.end) for r in path.welds] == [("Fillet", 1, 2), ("Fillet_2", 3, 5)]
    assert path.moves[3].comment.endswith("(arc on here after the turn: Fillet_2)")


def test_a_corner_welded_through_keeps_its_slow_down_where_slower():
    area = RiskAreaSpec("R", "Corner", 1, 2, step_mm=1.0, corner_span_mm=5.0)
    path = program_of(three_legs(), [rz(0), rz(90), rz(90)], [weld()], risk_areas=[area]).paths[0]
    (run,) = path.welds
    risk = [m for m in welded(path, run) if m.role == ir.ROLE_RISK]
    # 90 deg over 10 mm at 40 deg/s: 2.25 s, 4.44 mm/s, written in 0.1 mm/s steps down
    assert len(risk) == 10 and {m.speed_mm_s for m in risk} == {4.4}
    assert all("corner slow-down to 4.4 mm/s" in m.comment for m in risk)
    assert all(m.weld == "Fillet" for m in risk) and all(m.zone_mm > 0.0 for m in risk)
    others = [m for m in welded(path, run) if m.role == ir.ROLE_PATH]
    assert {m.speed_mm_s for m in others} == {TRAVEL}
    slow_schedule = dataclasses.replace(FILLET_T6, travel_speed_mm_s=3.0)
    path = program_of(three_legs(), [rz(0), rz(90), rz(90)], [weld(schedule=slow_schedule)],
                      risk_areas=[area]).paths[0]
    assert {m.speed_mm_s for m in welded(path, path.welds[0])} == {3.0}     # slower than the corner
    assert not any("slow-down" in m.comment for m in path.moves)
    # a weld from segment 2 strikes at the junction inside the area, which then stops exactly
    path = program_of(three_legs(), [rz(0), rz(90), rz(90)], [weld(2, 3)], risk_areas=[area]).paths[0]
    (run,) = path.welds
    start = path.moves[run.start]
    assert start.role == ir.ROLE_RISK and xyz(start) == (50, 0, 0) and start.zone_mm == 0.0
    assert start.weld is None and start.speed_mm_s == 4.4 and path.moves[run.start - 1].zone_mm > 0


def test_a_welded_risk_area_is_resampled_at_the_travel_speed_times_the_sample_time():
    area = RiskAreaSpec("R", "Corner", 1, 2)       # whole segments, no step: |v| * 0.2 s
    def risk_steps(welds):
        path = program_of(three_legs(), [rz(0), rz(90), rz(90)], welds, risk_areas=[area],
                          speed_mm_s=PATH_SPEED, sample_time_s=0.2).paths[0]
        risk = [xyz(m) for m in path.moves if m.role == ir.ROLE_RISK]
        return max(round(float(np.linalg.norm(np.subtract(b, a))), 6) for a, b in zip(risk, risk[1:]))
    assert risk_steps([]) == PATH_SPEED * 0.2            # 2 mm
    assert risk_steps([weld()]) == TRAVEL * 0.2          # 1.5 mm (each leg's last step 0.5): the arc's speed
    assert risk_steps([weld(3, 3)]) == PATH_SPEED * 0.2


def test_circular_moves_weld():
    arc = Arc((50, 10, 0), (0, 0, 1), (0, -10, 0), math.pi, "Arc")      # (50,0) round to (50,20)
    path = program_of([Line((0, 0, 0), (50, 0, 0), "A"), arc], [rz(0)] * 2, [weld()]).paths[0]
    kinds = [m.kind for m in welded(path, path.welds[0])]
    assert kinds == [ir.LINEAR, ir.CIRCULAR] and path.moves[3].via is not None
    assert path.moves[3].weld == "Fillet" and path.moves[3].speed_mm_s == TRAVEL


# --- closed paths: the corner where the loop closes --------------------------------------------

LOOP_R = [rz(0), rz(90), rz(180), rz(270)]


def test_a_loop_welded_through_its_closing_corner_ends_on_the_first_leg():
    area = RiskAreaSpec("R", "Heel", 4, 1, step_mm=1.0, corner_span_mm=5.0)
    turns = [RiskAreaSpec("R%d" % k, "C%d" % k, k, k + 1, step_mm=1.0, corner_span_mm=5.0)
             for k in (1, 2, 3)]
    path = program_of(square_loop(), LOOP_R, [weld()], risk_areas=turns + [area], closed=True).paths[0]
    (run,) = path.welds
    assert run.start == 1 and run.end == len(path.moves) - 2 and run.last_segment == 4
    assert xyz(path.moves[run.end]) == (5, 0, 0)     # the crater 5 mm on, over the start
    assert all(m.weld == "Fillet" for m in welded(path, run))
    # welded on segment 1 only: the overlap after the loop's last leg does not weld
    path = program_of(square_loop(), LOOP_R, [weld(1, 1)], risk_areas=turns + [area],
                      closed=True).paths[0]
    (run,) = path.welds
    assert xyz(path.moves[run.end]) == (40, 0, 0) and path.moves[-2].weld is None


def test_a_loop_that_stops_at_its_closing_corner_puts_the_arc_out_before_the_turn():
    stops = [RiskAreaSpec("R%d" % k, "C%d" % k, k, k % 4 + 1, at_corner=gen.STOP_AND_REORIENT)
             for k in (1, 3, 4)]                 # 2-3: a plain junction turn, which splits too
    path = program_of(square_loop(), LOOP_R, [weld()], risk_areas=stops, closed=True).paths[0]
    assert [r.name for r in path.welds] == ["Fillet", "Fillet_2", "Fillet_3", "Fillet_4"]
    last_turn = path.moves[-2]
    assert last_turn.role == ir.ROLE_REORIENT and path.welds[-1].end == len(path.moves) - 3
    assert last_turn.comment.startswith("corner stop (arc off at the previous target: Fillet_4):")


# --- names and programs without welds ---------------------------------------------------------

def test_weld_names_are_unique_in_the_program_and_other_paths_do_not_change():
    plain = make_path(three_legs(), [rz(0)] * 3, name="Other")
    welded_path = make_path(three_legs(), [rz(0), rz(90), rz(90)], name="Seam",
                            welds=[weld(1, 2, name="Seam")])
    program = generate(make_cell([plain, welded_path], T_u_b=np.eye(4)))
    assert [r.name for r in program.paths[1].welds] == ["Seam_2", "Seam_2_2"]   # the path is "Seam"
    alone = generate(make_cell([make_path(three_legs(), [rz(0)] * 3, name="Other")],
                               T_u_b=np.eye(4)))
    fields = lambda m: (m.kind, m.role, m.segment, m.speed_mm_s, m.zone_mm, m.comment, m.weld,
                        m.target.name, m.target.T_b_t.tolist())
    assert [fields(m) for m in program.paths[0].moves] == [fields(m) for m in alone.paths[0].moves]
    assert program.paths[0].welds == []


def test_generate_checks_its_runs(monkeypatch):
    seen = []
    monkeypatch.setattr(gen, "check_runs", seen.append)
    program = program_of(three_legs(), [rz(0)] * 3, [weld()])
    assert seen == [program]


# --- refusals ---------------------------------------------------------------------------------

@pytest.mark.parametrize("welds, message", [
    ([weld(1, 2, label="First"), weld(2, 3, name="W2", label="Second")],
     r"^Welds 'First' \(segments 1-2\) and 'Second' \(segments 2-3\) overlap on path 'Weld seam': "
     r"make their segments disjoint or merge them into one weld\.$"),
    ([weld(2, 4)], r"^Weld 'Fillet weld' covers segments 2-4, but path 'Weld seam' has segments "
                   r"1-3: set its first and last segment within 1-3\.$"),
    ([weld(0, 1)], r"covers segments 0-1, .* within 1-3\.$"),
    ([weld(1.5, 2)], r"covers segments 1.5-2, "),
    ([weld(3, 2)], r"^Weld 'Fillet weld' on path 'Weld seam': its first segment 3 comes after its "
                   r"last segment 2: set first <= last\.$"),
    ([weld(schedule=None)], r"^Weld 'Fillet weld' on path 'Weld seam' has no schedule: "),
    ([dataclasses.replace(weld(), position="PF")],
     r"^Weld 'Fillet weld' on path 'Weld seam': position 'PF' is not one of PA, PB: give one of "
     r"them\.$"),
])
def test_bad_welds_are_refused_in_one_line(welds, message):
    with pytest.raises(InputError, match=message) as caught:
        program_of(three_legs(), [rz(0)] * 3, welds)
    assert "\n" not in str(caught.value) and caught.value.obj_name == welds[-1].name


def test_the_welds_position_reaches_its_runs():
    """Issue 23: a positioner keeps each run's seam in the position its weld asks for."""
    welds = [dataclasses.replace(weld(1, 1), position="PB"), weld(3, 3, name="W2")]
    runs = program_of(three_legs(), [rz(0)] * 3, welds).paths[0].welds
    assert [(run.name, run.position) for run in runs] == [("Fillet", "PB"), ("W2", "PA")]


def test_a_weld_on_a_path_without_segments_is_refused():
    with pytest.raises(InputError, match=r"^Weld 'Fillet weld' is on path 'Weld seam', which has no "
                                         r"segments: .* or delete the weld\.$"):
        program_of([], [], [weld()])
    with pytest.raises(GeometryError):           # without a weld: the path's own refusal
        program_of([], [], [])


# --- check_runs: each rule, broken on the shared fixtures --------------------------------------

def test_the_fixtures_keep_the_rules():
    check_runs(woven_fillet_program())
    check_runs(corner_stop_program())


def _break(change):
    def broken():
        program = corner_stop_program()
        change(program.paths[0])
        return program
    return broken


def _set(obj, **values):
    for key, value in values.items():
        setattr(obj, key, value)


BROKEN = {
    "not an identifier": (_break(lambda p: _set(p.welds[1], name="Weld 2")),
                          r"'Weld 2'.*must be an identifier"),
    "a name twice": (_break(lambda p: (_set(p.welds[1], name="WELD"), _set(p.moves[4], weld="WELD"))),
                     r"'WELD'.*another weld run of the program has the same name"),
    "no schedule": (_break(lambda p: _set(p.welds[0], schedule=None)),
                    r"^Weld run 'Weld' \('Fillet weld', part 1\) on path 'Fillet seam' has no schedule"),
    "start not before end": (_break(lambda p: _set(p.welds[1], start=4, end=4)),
                             r"'Weld_2'.*start 4 and end 4 must be move indices with start < end"),
    "end past the moves": (_break(lambda p: _set(p.welds[1], end=6)), r"'Weld_2'.*end 6 .* < 6"),
    "an index not a whole number": (_break(lambda p: _set(p.welds[1], start=3.0)),
                                    r"'Weld_2'.*start 3.0 and end 4 must be move indices"),
    "runs overlapping": (_break(lambda p: _set(p.welds[1], start=1)),
                         r"'Weld_2'.*starts at move 1, before run 'Weld' ends \(move 2\)"),
    "a joint move welded": (_break(lambda p: _set(p.moves[4], kind=ir.JOINT)),
                            r"'Weld_2'.*welded move 4 is a joint move"),
    "the approach welds": (_break(lambda p: (_set(p.welds[0], start=0), _set(p.moves[1], weld="Weld"))),
                           r"'Weld'.*welded move 1 is an entry move: only path and risk-area moves "
                           r"weld, so the approach ends at the seam start, never in the air"),
    "a welded move unmarked": (_break(lambda p: _set(p.moves[4], weld=None)),
                               r"'Weld_2'.*welded move 4 is marked weld=None"),
    "a mark outside the run": (_break(lambda p: _set(p.moves[3], weld="Weld")),
                               r"move 3 names weld 'Weld' but lies outside that weld's run"),
    "ignition not fine": (_break(lambda p: _set(p.moves[3], zone_mm=1.0)),
                          r"'Weld_2'.*start \(ignition\) move 3 has zone 1 mm"),
    "crater not fine": (_break(lambda p: _set(p.moves[2], zone_mm=0.5)),
                        r"'Weld'.*end \(crater\) move 2 has zone 0.5 mm"),
    "another speed": (_break(lambda p: _set(p.moves[4], speed_mm_s=10.0)),
                      r"'Weld_2'.*welded move 4 runs at 10 mm/s, not the schedule's travel speed "
                      r"7.5 mm/s"),
    "slower but no corner": (_break(lambda p: _set(p.moves[4], speed_mm_s=4.4, role=ir.ROLE_RISK)),
                             r"welded move 4 runs at 4.4 mm/s"),
}


@pytest.mark.parametrize("rule", sorted(BROKEN))
def test_check_runs_names_the_run_and_the_broken_rule(rule):
    make, message = BROKEN[rule]
    with pytest.raises(InputError, match=message) as caught:
        check_runs(make())
    assert "\n" not in str(caught.value)


def test_numpy_indices_are_indices():
    program = corner_stop_program()
    _set(program.paths[0].welds[1], start=np.int64(3), end=np.int64(4))
    check_runs(program)


def test_a_corner_slow_down_may_be_slower():
    program = corner_stop_program()
    move = program.paths[0].moves[4]
    _set(move, speed_mm_s=4.4, role=ir.ROLE_RISK, comment=move.comment + " (corner slow-down)")
    check_runs(program)
