"""The weave is what the robot does, so it is checked (issue 22, WP5).

The fixture weld (weld_fixtures.woven_fillet_program): the seam runs 100 mm
along +X of frame B; the torch's axis without its push is (0, 1, -1)/sqrt(2),
so the weave frame's lateral axis is Y = Z x X = (0, -1, -1)/sqrt(2) (B's axes
are the robot's). The zigzag 4 mm wide at 2 Hz with 0.1 s dwells at each end
moves 8 mm per 0.3 s of moving time: 0.075 s per 2 mm leg, so one cycle is
(arc time in the cycle -> lateral offset, mm)::

    0 -> 0,  0.075 -> -2,  0.175 -> -2,  0.25 -> 0,  0.325 -> +2,  0.425 -> +2,  0.5 -> 0

and the amplitude ramps in and out over the first and last 0.25 s. The arc
starts when the entry move ends: 50 mm at 50 mm/s after the approach (which
starts on its own target), at t = 1 s; the weld lasts 100 / 7.5 = 13.333 s.
"""

import dataclasses
import re

import numpy as np
import pytest
import trimesh

from CadRobotWB.core import frames as tf
from CadRobotWB.core import program as ir
from CadRobotWB.core.trajectory import tcp_trajectory
from CadRobotWB.core.weave import woven_trajectory
from CadRobotWB.core.welding import Weave
from CadRobotWB.robots.checks import checks, collision, weave_advice
from CadRobotWB.robots.kinematics import models
from CadRobotWB.robots.motion import configuration as cfg
from CadRobotWB.robots.motion import move_sampling, playback, timing

from post_programs import pose
from weld_fixtures import FILLET_T6, ZIGZAG_4MM, torch_pose, woven_fillet_program

LATERAL_B = np.array([0.0, -1.0, -1.0]) / np.sqrt(2.0)
ARC_START_S, ARC_S = 1.0, 100.0 / 7.5
CYCLE_KNOTS_S = [0.0, 0.075, 0.175, 0.25, 0.325, 0.425, 0.5]
CYCLE_OFFSETS_MM = [0.0, -2.0, -2.0, 0.0, 2.0, 2.0, 0.0]


def hand_lateral_mm(arc_s):
    """The fixture weave's lateral offset at arc times (N,), from the table above."""
    ramp = np.clip(np.minimum(arc_s, ARC_S - arc_s) / 0.25, 0.0, 1.0)
    return np.interp(np.mod(arc_s, 0.5), CYCLE_KNOTS_S, CYCLE_OFFSETS_MM) * ramp


def solved(program):
    model = models.model(program.robot)
    return model, cfg.solve_program(program, model, assign=False)


def test_woven_trajectory_adds_the_weave_across_the_seam_inside_the_run_only():
    program = woven_fillet_program()
    plain = tcp_trajectory(program, 0.0025)
    woven = woven_trajectory(program, plain)
    welded = np.isin(plain.move_index, [2, 3])
    shift_b = woven.position_mm - plain.position_mm          # B's axes are {U}'s
    assert np.abs(shift_b[~welded]).max() == 0.0
    expected = hand_lateral_mm(plain.time_s[welded] - ARC_START_S)[:, None] * LATERAL_B
    assert np.abs(shift_b[welded] - expected).max() < 1e-9
    assert shift_b[welded] @ LATERAL_B == pytest.approx(expected @ LATERAL_B)
    assert (shift_b[welded] @ LATERAL_B).max() == pytest.approx(2.0)
    assert np.array_equal(woven.T_u_t[:, :3, :3], plain.T_u_t[:, :3, :3])
    assert np.array_equal(woven.s_mm, plain.s_mm) and np.array_equal(woven.time_s, plain.time_s)
    # One move alone (the player samples move by move) keeps the run's arc clock.
    alone = tcp_trajectory(program, 0.0025, first_move=3, last_move=3)
    shift = woven_trajectory(program, alone).position_mm - alone.position_mm
    expected = hand_lateral_mm(alone.time_s + 50.0 / 7.5)[:, None] * LATERAL_B
    assert np.abs(shift - expected).max() < 1e-9


def test_the_checks_sample_the_woven_path_and_its_joint_speeds_match_hand_placed_poses():
    program = woven_fillet_program()
    model, solution = solved(program)
    sampled = move_sampling.sample_program(program, model, solution, move_sampling.Margins())
    k = 1                                                    # the first welded move (move 2)
    assert sampled.groups[k][-1].move_index == 2 and sampled.clocks[k] is not None
    steps = np.diff(sampled.offsets)[k] - 1
    assert sampled.time_s[k] / steps <= 0.5 / 40 and steps == 534   # ceil(6.667 s / 12.5 ms)
    assert [c is None for c in sampled.clocks] == [True, False, False, True]

    # Independently: the woven TCP placed by hand (the seam point at 7.5 mm/s plus the
    # table's lateral offset), its joints by IK (the solution nearest the move's start):
    # at the sampled times they are the sampled joints; every 2 ms, by finite
    # differences, they give the joint speeds.
    rows = slice(sampled.offsets[k], sampled.offsets[k + 1])
    start = sampled.q_deg[sampled.offsets[k]]

    def hand_joints(t):
        T_b_t = np.repeat(torch_pose((0.0, 0.0, 0.0))[None], len(t), axis=0)
        T_b_t[:, :3, 3] += 7.5 * t[:, None] * [1.0, 0.0, 0.0]
        T_b_t[:, :3, 3] += hand_lateral_mm(t)[:, None] * LATERAL_B
        Q = model.ik(program.frames["B"].T_r_b @ T_b_t @ tf.invert_transform(program.tool.T_f_t))
        return Q[np.arange(len(t)), np.nanargmin(np.nansum((Q - start) ** 2, axis=2), axis=1)]

    np.testing.assert_allclose(sampled.q_deg[rows],
                               hand_joints(sampled.fractions[rows] * 50.0 / 7.5), atol=1e-6)
    q = model.controller_joints(hand_joints(np.arange(0.0, 50.0 / 7.5, 0.002)))
    hand_peak = np.abs(np.diff(q, axis=0)).max(axis=0) / 0.002
    needed, _ = move_sampling.peak_joint_speeds(model, sampled)
    assert needed[k] == pytest.approx(hand_peak, rel=0.02, abs=0.01)


# --- the weave_speed finding ----------------------------------------------------------------

#: A KUKA KR 300 R2800-2 MT (J4 limit 90 deg/s) whose wrist is 2 deg from straight at the
#: middle of the seam (J5 -4.4, -2.0, -2.2 deg at its three targets): the weave's sideways
#: motion turns J4 and J6 fast there, the plain seam hardly at all.
NEAR_WRIST_ROBOT = "KUKA_KR300_R2800_2_MT"
NEAR_WRIST_JOINTS = (0.0, -55.0, 32.5, 120.0, 2.0, 0.0)
#: The fixture's weave given by its length per cycle (3.75 mm = 7.5 mm/s / 2 Hz).
ZIGZAG_BY_LENGTH = Weave("zigzag", width_mm=4.0, length_mm=3.75, dwell_left_s=0.1,
                         dwell_right_s=0.1).validated()


def near_wrist_program(weave=ZIGZAG_BY_LENGTH, travel_mm_s=7.5):
    """The fixture weld placed so the seam's middle target has NEAR_WRIST_JOINTS."""
    model = models.model(NEAR_WRIST_ROBOT)
    schedule = dataclasses.replace(FILLET_T6, travel_speed_mm_s=travel_mm_s)
    program = woven_fillet_program(robot=NEAR_WRIST_ROBOT, weave=weave, schedule=schedule)
    T_r_t = model.fk(np.array([NEAR_WRIST_JOINTS]))[0] @ program.tool.T_f_t
    T_r_b = T_r_t @ tf.invert_transform(torch_pose((50.0, 0.0, 0.0)))
    program.frames["B"].T_u_b = program.frames["B"].T_r_b = T_r_b
    for move in program.moves()[2:4]:
        move.speed_mm_s = travel_mm_s
    return program


def weld_errors(program):
    model = models.model(program.robot)
    return [f for f in checks.check_program(program, model).errors]


def test_a_weave_too_fast_for_j4_is_one_finding_naming_the_weld_and_segment_with_three_fixes():
    plain = weld_errors(near_wrist_program(weave=None))
    assert plain == []                                       # the plain seam is slow enough

    found = weld_errors(near_wrist_program())
    assert [(f.kind, f.severity, f.target, f.move_index, f.joint) for f in found] == [
        ("weave_speed", "error", "t4", 3, 4)]
    finding = found[0]
    assert finding.value > finding.limit == 90.0
    fixes = finding.fixes
    assert set(fixes) == {"width_mm", "length_mm", "travel_speed_mm_s"}
    assert finding.message == (
        "Weld 'Fillet weld' (segment 1): J4 needs %.0f deg/s on the woven path (limit 90 deg/s): "
        "narrow the weave (4 -> %g mm), lengthen its cycle (3.75 -> %g mm) or slow the travel "
        "(7.5 -> %g mm/s)." % (finding.value, fixes["width_mm"], fixes["length_mm"],
                               fixes["travel_speed_mm_s"]))
    assert 0.2 < fixes["width_mm"] < 4.0 and 3.75 < fixes["length_mm"] < 50.0
    assert 0.5 < fixes["travel_speed_mm_s"] < 7.5
    group = checks.Report("r", found).to_dict()["groups"][0]
    assert group["kind"] == "weave_speed" and group["line"].startswith("ERROR: weave_speed: Weld")
    assert checks.Report("r", found).to_dict()["findings"][0]["fixes"] == fixes


def test_without_fixes_the_same_error_names_what_to_change_without_the_values():
    program = near_wrist_program()
    model = models.model(program.robot)
    finding, = checks.check_program(program, model, weave_fixes=False).errors
    assert (finding.kind, finding.target, finding.joint, finding.fixes) == (
        "weave_speed", "t4", 4, None)
    assert finding.message.endswith(": narrow the weave, lower its frequency or slow the travel "
                                    "(Check gives the values).")


def test_each_suggested_fix_alone_clears_the_finding_and_is_the_least_change():
    finding, = weld_errors(near_wrist_program())
    width, length = finding.fixes["width_mm"], finding.fixes["length_mm"]
    travel = finding.fixes["travel_speed_mm_s"]
    fixed = [near_wrist_program(dataclasses.replace(ZIGZAG_BY_LENGTH, width_mm=width)),
             near_wrist_program(dataclasses.replace(ZIGZAG_BY_LENGTH, length_mm=length)),
             near_wrist_program(travel_mm_s=travel)]
    assert [weld_errors(p) for p in fixed] == [[], [], []]
    # One step (0.1) less of each change is not enough: the suggestions are the least
    # changes (measured as the check measures, on the run's woven samples).
    program = near_wrist_program()
    model, solution = solved(program)
    sampled = move_sampling.sample_program(program, model, solution, move_sampling.Margins())
    run_moves = [(sampled.starts[k], sampled.groups[k]) for k in (1, 2)]

    def ratio(weave, travel):
        return weave_advice.speed_ratio(program, model, run_moves, move_sampling.Margins(),
                                        "Weld", weave, travel)

    assert ratio(dataclasses.replace(ZIGZAG_BY_LENGTH, width_mm=width + 0.1), 7.5) > 1.0
    assert ratio(dataclasses.replace(ZIGZAG_BY_LENGTH, length_mm=length - 0.1), 7.5) > 1.0
    assert ratio(ZIGZAG_BY_LENGTH, travel + 0.1) > 1.0
    assert ratio(ZIGZAG_BY_LENGTH, 7.5) == pytest.approx(finding.value / 90.0)


def test_a_weave_by_frequency_keeps_it_and_a_faster_one_cannot_be_fixed_by_travel_alone():
    finding, = weld_errors(near_wrist_program(weave=ZIGZAG_4MM))
    fixes = finding.fixes
    assert set(fixes) == {"width_mm", "frequency_hz", "travel_speed_mm_s"}
    assert "lower its frequency (2 -> %g Hz)" % fixes["frequency_hz"] in finding.message
    assert weld_errors(near_wrist_program(
        dataclasses.replace(ZIGZAG_4MM, frequency_hz=fixes["frequency_hz"]))) == []
    assert weld_errors(near_wrist_program(ZIGZAG_4MM, fixes["travel_speed_mm_s"])) == []

    # At 3 Hz the weave alone is too fast for J4: even the slowest travel does not help.
    fast = dataclasses.replace(ZIGZAG_4MM, frequency_hz=3.0)
    program = near_wrist_program(weave=fast)
    finding, = weld_errors(program)
    assert set(finding.fixes) == {"width_mm", "frequency_hz"}
    assert finding.message.endswith(
        "narrow the weave (4 -> %g mm) or lower its frequency (3 -> %g Hz) (a slower travel "
        "alone is not enough)." % (finding.fixes["width_mm"], finding.fixes["frequency_hz"]))
    model, solution = solved(program)
    sampled = move_sampling.sample_program(program, model, solution, move_sampling.Margins())
    run_moves = [(sampled.starts[k], sampled.groups[k]) for k in (1, 2)]
    assert weave_advice.speed_ratio(program, model, run_moves, move_sampling.Margins(), "Weld",
                                    fast, weave_advice.MIN_TRAVEL_MM_S) > 1.0


def test_a_run_no_weave_change_can_fix_says_so_and_names_its_part():
    program = near_wrist_program()
    model, solution = solved(program)
    sampled = move_sampling.sample_program(program, model, solution, move_sampling.Margins())
    clock = dataclasses.replace(sampled.clocks[2], run=dataclasses.replace(
        program.paths[0].welds[0], part=2))
    finding = checks._weave_speed_finding(model, sampled.groups[2][-1], clock,
                                          weave_advice.WeaveFix(), 3, 120.4, 90.0)
    assert finding.message == (
        "Weld 'Fillet weld' (segment 1, part 2): J4 needs 120 deg/s on the woven path (limit 90 "
        "deg/s): no narrower weave, lower frequency or slower travel in their ranges fixes it: "
        "change the torch orientation along the weld or move the part.")
    assert (finding.kind, finding.joint, finding.fixes) == ("weave_speed", 4, {})


# --- reach and collisions on the woven path -------------------------------------------------

def box_in_b(lo, hi, origin=(900.0, 0.0, 400.0)):
    """Box mesh between corners lo and hi of frame B (the fixture's B is at `origin` in {R})."""
    lo, hi = np.add(lo, origin), np.add(hi, origin)
    return trimesh.creation.box(hi - lo, transform=trimesh.transformations.translation_matrix(
        0.5 * (lo + hi)))


def test_a_weave_wide_enough_to_put_the_torch_into_the_wall_collides():
    """The torch's tip stops 15 mm short of the TCP on its 45 degree axis: 10.6 mm from
    the wall plate. A 26 mm zigzag turned -45 deg moves the TCP 13 mm straight toward
    the wall (+Y of B) at its left end: about 2.4 mm into it; 20 mm (10 mm) stays clear."""
    plates = [("Wall plate", box_in_b([-50, 0, 0], [150, 10, 150])),
              ("Floor plate", box_in_b([-50, -150, -10], [150, 10, 0]))]

    def hits(weave):
        program = woven_fillet_program(weave=weave)
        model, solution = solved(program)
        checker = collision.RobotCollisionChecker(program.robot, plates,
                                                  tool_T_f_t=program.tool.T_f_t,
                                                  tool_label="Straight torch")
        return collision.program_collision_findings(program, solution, checker)

    assert hits(None) == []
    assert hits(Weave("zigzag", 20.0, frequency_hz=1.0, angle_deg=-45.0)) == []
    found = hits(Weave("zigzag", 26.0, frequency_hz=1.0, angle_deg=-45.0))
    assert [(f.kind, f.target) for f in found] == [("collision", "t3"), ("collision", "t4")]
    depth = float(re.search(r"\(([0-9.]+) mm deep\)", found[0].message).group(1))
    assert "hits Wall plate" in found[0].message and 2.0 <= depth <= 3.0


def test_a_weave_past_a_joint_limit_is_an_error_the_plain_path_has_not():
    """The seam turned to run along +Y of {R} and moved out along X to where its plain
    targets and moves just keep J5 within its limit (bisection on the plain program's
    check of moves 1-3: the entry, the two welded moves): the woven path takes J5 past
    it, between the targets."""
    def program_at(x, weave):
        program = woven_fillet_program(weave=weave)
        program.frames["B"].T_u_b = program.frames["B"].T_r_b = pose((0, 0, 90), (x, -50, 400))
        return program

    model = models.model("ABB_IRB2400")

    def seam_errors(program):
        return [f for f in checks.check_program(program, model).errors
                if f.move_index in (1, 2, 3)]

    good, bad = 500.0, 2500.0
    for _ in range(16):
        middle = 0.5 * (good + bad)
        good, bad = (middle, bad) if not seam_errors(program_at(middle, None)) else (good, middle)
    assert [(f.kind, f.joint) for f in seam_errors(program_at(bad, None))] == [("joint_limit", 5)]
    found = seam_errors(program_at(good, ZIGZAG_4MM))
    assert [(f.kind, f.move_index, f.joint) for f in found] == [("joint_limit", 2, 5)]
    assert "The linear move from 't2' to 't3'" in found[0].message
    assert "would take J5 to 120.0 deg, beyond its limit of +120 deg" in found[0].message


# --- cycle time, plain programs, playback ----------------------------------------------------

def test_cycle_time_adds_preflow_at_the_start_and_crater_burnback_postflow_at_the_end():
    program = woven_fillet_program()
    model, solution = solved(program)
    waited = timing.cycle_time(program, model, solution)
    none = dataclasses.replace(FILLET_T6, gas_preflow_s=0.0, crater_fill_s=0.0, burnback_s=0.0,
                               gas_postflow_s=0.0)
    program.paths[0].welds[0].schedule = none
    bare = timing.cycle_time(program, model, solution)
    assert waited["total_s"] - bare["total_s"] == pytest.approx(0.2 + 0.3 + 0.05 + 0.5, abs=1e-12)
    by_move = {m["move_index"]: m for m in waited["moves"]}
    assert by_move[1]["process_s"] == 0.2 and by_move[3]["process_s"] == pytest.approx(0.85)
    assert "process_s" not in by_move[2]
    assert by_move[1]["time_s"] - {m["move_index"]: m for m in bare["moves"]}[1]["time_s"] == \
        pytest.approx(0.2)
    # Welded moves at the travel speed: 100 mm at 7.5 mm/s from rest to rest at 2000 mm/s^2.
    weld, = waited["welds"]
    assert weld["arc_s"] == pytest.approx(100.0 / 7.5 + 7.5 / 2000.0 / 2 * 2, abs=1e-9)
    assert (weld["preflow_s"], weld["crater_fill_s"], weld["burnback_s"], weld["postflow_s"]) == (
        0.2, 0.3, 0.05, 0.5)


def unwelded(program):
    """`program` with its welds taken out (a plain motion program)."""
    for path in program.paths:
        path.welds = []
        for move in path.moves:
            move.weld = None
    return program


def test_a_plain_program_and_a_weld_without_weave_check_and_time_as_before():
    plain = unwelded(woven_fillet_program())
    model, solution = solved(plain)
    report = checks.check_program(plain, model, solution).to_dict()
    sampled = move_sampling.sample_program(plain, model, solution, move_sampling.Margins())
    assert sampled.clocks is None and list(np.diff(sampled.offsets) - 1) == [10, 10, 10, 10]
    cycle = timing.cycle_time(plain, model, solution)
    assert "welds" not in cycle and all("process_s" not in m for m in cycle["moves"])
    assert all("fixes" not in f for f in report["findings"])

    no_weave = woven_fillet_program(weave=None)
    model, solution = solved(no_weave)
    assert checks.check_program(no_weave, model, solution).to_dict() == report
    assert move_sampling.sample_program(no_weave, model, solution,
                                        move_sampling.Margins()).clocks is None


def test_the_player_follows_the_woven_path_and_draws_it():
    program = woven_fillet_program()
    model, solution = solved(program)
    timeline = playback.joint_timeline(program, model, solution, dt_s=0.1)
    assert timeline.failure is None
    welded = np.isin(timeline.move_index, [2, 3])
    assert np.diff(timeline.time_s[welded]).max() <= 0.5 / 40 + 1e-9
    arc_start_s = timeline.time_s[np.flatnonzero(timeline.move_index == 1)[-1]]
    B = program.frames["B"].T_u_b
    lateral = (timeline.tcp_u[welded] - B[:3, 3]) @ B[:3, :3] @ LATERAL_B
    expected = hand_lateral_mm(timeline.time_s[welded] - arc_start_s)
    assert np.abs(lateral - expected).max() < 1e-6            # FK of the joints played

    (label, points), = playback.woven_polylines(program)
    assert label == "Weld 'Fillet weld' (woven)"
    along = (points - B[:3, 3]) @ B[:3, 0]                   # the seam's X, every <= cycle / 40
    assert along[[0, -1]] == pytest.approx([0.0, 100.0]) and np.diff(along).max() <= 0.09375 + 1e-9
    assert np.abs((points - B[:3, 3]) @ LATERAL_B).max() == pytest.approx(2.0, abs=1e-9)
    assert playback.woven_polylines(unwelded(program)) == []


def test_a_weld_slowed_down_through_a_corner_is_one_warning_with_its_heat_input():
    program = woven_fillet_program(weave=None)
    for move in program.moves()[2:4]:
        move.role, move.comment = ir.ROLE_RISK, "corner slow-down"
    program.moves()[2].speed_mm_s, program.moves()[3].speed_mm_s = 5.0, 3.0
    report = checks.check_program(program, models.model(program.robot))
    slow = [f for f in report.findings if f.kind == "weld_slowdown"]
    assert [(f.severity, f.target, f.value, f.limit) for f in slow] == [("warning", "t4", 3.0, 7.5)]
    assert slow[0].message.startswith("Weld 'Fillet weld' slows from 7.5 to 3 mm/s at target 't4' "
                                      "(path 'Fillet seam', move 4), where the torch turns through "
                                      "a corner: 2.5 times the heat input per mm")
    plain = woven_fillet_program(weave=None)
    assert not [f for f in checks.check_program(plain, models.model(plain.robot)).findings
                if f.kind == "weld_slowdown"]
