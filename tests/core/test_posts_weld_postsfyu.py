"""Weld programs of the FANUC ArcTool, Yaskawa INFORM and UR posts (issue 22).

The programs are the hand-built fillet and corner-stop welds of
weld_fixtures.py (fillet_t6: 265 A, 27.5 V, 6.7 m/min, 7.5 mm/s; crater
185 A, 22 V, 4.5 m/min, 0.3 s; zigzag 4 mm wide at 2 Hz, 0.1 s at each end),
solved for a robot of the post's maker.  Each language is read back as the
welder and the controller read it: the arc strikes at the seam start and
nowhere else, the weld and crater values, the weave, the ignition and crater
moves fine, the arc ends and restarts at a corner stop, a weld never cut by
a program split.  The numbers expected are computed here by hand from the
schedule and the weave.

To rewrite the golden files after a reviewed change of the output:
``CADROBOT_UPDATE_GOLDEN=1 python3 -m pytest tests/core/test_posts_weld_postsfyu.py``.
Golden files are stored with LF line ends.
"""

import dataclasses
import os
import re
from pathlib import Path

import numpy as np
import pytest

from CadRobotWB import posts
from CadRobotWB.core import program as ir
from CadRobotWB.core.welding import Tracking, Weave
from CadRobotWB.errors import PostError
from CadRobotWB.posts import fanuc_ls, motoman_inform, ur_script
from CadRobotWB.robots.kinematics import models
from CadRobotWB.robots.motion import configuration

from post_programs import pose
import weld_fixtures as wf

GOLDEN_DIR = Path(__file__).parent / "golden"
#: A robot of each maker and a work frame (mm in its base) where the fixtures are reached.
ROBOTS = {"fanuc_ls": ("FANUC_M20IA", (900.0, 0.0, 400.0)),
          "motoman_inform": ("MOTOMAN_HP6", (700.0, 0.0, 200.0)),
          "ur_script": ("UR5E", (300.0, 100.0, 0.0))}
POSTS = {m.NAME: m for m in (fanuc_ls, motoman_inform, ur_script)}
NO_DWELLS = dataclasses.replace(wf.ZIGZAG_4MM, dwell_left_s=0.0, dwell_right_s=0.0)


def fillet(post, **kwargs):
    robot, frame = ROBOTS[post]
    return wf.woven_fillet_program(robot, frame_mm=frame, solve=True, **kwargs)


def corner(post, weave=wf.ZIGZAG_4MM):
    robot, frame = ROBOTS[post]
    program = wf.corner_stop_program(robot, weave=weave)
    program.frames["B"].T_r_b = pose((0, 0, 0), frame)
    configuration.solve_program(program, models.model(robot))
    return program


def touching(post, weave=wf.ZIGZAG_4MM):
    """The fillet as two welds that touch at its middle (as generate writes two welds on
    neighbouring segments): 'Weld' strikes at the seam start and goes out at 50 mm, where
    'Weld_2' (travel 5 mm/s) strikes; one move ends the first and starts the second."""
    program = fillet(post, weave=weave)
    path = program.paths[0]
    first = path.welds[0]
    slower = dataclasses.replace(first.schedule, name="slower", travel_speed_mm_s=5.0)
    path.moves[2].zone_mm = 0.0
    path.moves[3].weld, path.moves[3].speed_mm_s = "Weld_2", 5.0
    first.end = 2
    path.welds.append(dataclasses.replace(first, name="Weld_2", schedule=slower, start=2,
                                          end=3))
    return program


def with_weave(program, **changes):
    """The program with its runs' weave (or tracking) changed."""
    for _, run in program.weld_runs():
        if "tracking" in changes:
            run.tracking = changes["tracking"]
        else:
            run.weave = dataclasses.replace(run.weave, **changes)
    return program


def text_of(post, program, options=None, index=0):
    return posts.run(POSTS[post], program, dict(options or {}))[index][1].replace("\r\n", "\n")


# --- golden files -------------------------------------------------------------

GOLDEN = [
    ("weld_fillet_fanuc_ls.LS", "fanuc_ls", lambda: fillet("fanuc_ls"), {}, 0),
    ("weld_fillet_motoman_inform.JBI", "motoman_inform", lambda: fillet("motoman_inform"),
     {"conditions": "files"}, 0),
    ("weld_fillet_motoman_inform_CONDITIONS.txt", "motoman_inform",
     lambda: fillet("motoman_inform"), {"conditions": "files"}, 1),
    ("weld_fillet_inline_motoman_inform.JBI", "motoman_inform",
     lambda: fillet("motoman_inform", weave=NO_DWELLS), {}, 0),
    ("weld_fillet_ur_script.script", "ur_script", lambda: fillet("ur_script"), {}, 0),
]


@pytest.mark.parametrize("name, post, build, options, index", GOLDEN, ids=[g[0] for g in GOLDEN])
def test_golden_weld_programs(name, post, build, options, index):
    plain = text_of(post, build(), options, index)
    golden = GOLDEN_DIR / name
    if os.environ.get("CADROBOT_UPDATE_GOLDEN"):
        golden.write_text(plain, newline="\n")
    assert golden.exists(), f"missing {golden}; see this file's docstring"
    assert plain == golden.read_text()


def test_every_fixture_target_is_solved_for_the_posts_robots():
    for post in POSTS:
        for program in (fillet(post), corner(post)):
            assert all(t.joints_deg is not None for t in program.targets()), post


# --- FANUC ArcTool --------------------------------------------------------------

MN_LINE = re.compile(r"^ *(\d+):(.*)$")


def mn_lines(text):
    """The /MN lines: (number, body), a continuation line joined to its line."""
    body = text[text.index("/MN\n") + 4:text.index("/POS\n")].splitlines()
    out = []
    for line in body:
        match = MN_LINE.match(line)
        if match:
            out.append((int(match.group(1)), match.group(2).strip().rstrip(" ;")))
        else:
            assert line.startswith("    :  "), line
            out[-1] = (out[-1][0], out[-1][1] + " | " + line[7:].rstrip(" ;"))
    return out


def mn_instructions(text):
    """The /MN lines that are not comments, after UFRAME_NUM and UTOOL_NUM."""
    return [b for _, b in mn_lines(text) if not b.startswith("!")][2:]


def test_fanuc_weld_lines_read_as_arctool_writes_them():
    text = text_of("fanuc_ls", fillet("fanuc_ls"))
    assert "/APPL\n  ARC : TRUE ;\n  ARC Welding Equipment : 1,*,*,*,*;\n\n/MN\n" in text
    lines = mn_lines(text)
    assert [n for n, _ in lines] == list(range(1, len(lines) + 1))
    assert f"LINE_COUNT\t= {len(lines)};" in text
    assert mn_instructions(text) == [
        "J P[1] 20% CNT100",
        "L P[2] 50mm/sec FINE | Arc Start[1]",              # the entry ends at the seam start
        "Weave Sine[2.0Hz,2.0mm,0.100s,0.100s]",          # 2 Hz, 4 mm / 2, right, left
        "L P[3] WELD_SPEED CNT100",                       # continuous in between
        "L P[4] WELD_SPEED FINE | Arc End[1]",              # crater move fine
        "Weave End",
        "L P[5] 200mm/sec FINE"]


def test_fanuc_weave_values_tracking_speed_and_schedule_numbers():
    program = with_weave(fillet("fanuc_ls"), dwell_right_s=0.2, frequency_hz=None,
                         length_mm=5.0)
    text = text_of("fanuc_ls", program, {"weld_speed": "explicit", "weld_schedule": 7})
    # 5 mm per cycle at 7.5 mm/s: 1.5 Hz; the right dwell first
    assert "Weave Sine[1.5Hz,2.0mm,0.200s,0.100s] ;" in text
    assert "WELD_SPEED" not in text and text.count(" 45cm/min ") == 2   # 7.5 mm/s * 6
    assert "Arc Start[7]" in text and "Arc End[7]" in text
    assert "Track" not in text
    tracked = with_weave(fillet("fanuc_ls"), tracking=Tracking("arc"))
    bodies = mn_instructions(text_of("fanuc_ls", tracked))
    start = bodies.index("L P[2] 50mm/sec FINE | Arc Start[1]")
    assert bodies[start + 1:start + 3] == ["Weave Sine[2.0Hz,2.0mm,0.100s,0.100s]",
                                           "Track TAST[1]"]
    end = next(i for i, b in enumerate(bodies) if "Arc End[1]" in b)
    assert bodies[end + 1:end + 3] == ["Weave End", "Track End"]


def slowed_down(program):
    """`program` with its first welded move a corner slow-down at 4.4 mm/s (core/weld_runs
    allows a risk-area move so named to weld slower than the travel speed)."""
    move = program.paths[0].moves[2]
    move.role, move.speed_mm_s, move.comment = ir.ROLE_RISK, 4.4, "corner slow-down"
    return program


def test_fanuc_a_corner_slow_down_keeps_its_own_speed():
    program = slowed_down(fillet("fanuc_ls"))
    assert mn_instructions(text_of("fanuc_ls", program))[3:5] == [
        "L P[3] 26cm/min CNT100", "L P[4] WELD_SPEED FINE | Arc End[1]"]   # 4.4 * 6 = 26.4


def test_fanuc_two_schedules_take_consecutive_numbers_listed_in_the_header():
    program = corner("fanuc_ls")
    second = program.paths[0].welds[1]
    second.schedule = dataclasses.replace(second.schedule, voltage_v=26.0)
    text = text_of("fanuc_ls", program, {"weld_schedule": 4})
    assert re.findall(r"Arc (Start|End)\[(\d)\]", "\n".join(mn_instructions(text))) == [
        ("Start", "4"), ("End", "4"), ("Start", "5"), ("End", "5")]
    assert "!Weld: 265 A, 27.5 V, wire feed ;" in text and "!Weld: 265 A, 26 V, wire feed 6.7 ;" in text


def test_fanuc_corner_stop_ends_and_restarts_the_arc_at_the_corner():
    bodies = mn_instructions(text_of("fanuc_ls", corner("fanuc_ls")))
    assert bodies == [
        "J P[1] 20% CNT100",
        "L P[2] 50mm/sec FINE | Arc Start[1]",
        "Weave Sine[2.0Hz,2.0mm,0.100s,0.100s]",
        "L P[3] WELD_SPEED FINE | Arc End[1]",               # arc out at the corner
        "Weave End",
        "L P[4] 45cm/min FINE | Arc Start[1]",               # turned in place, arc on again
        "Weave Sine[2.0Hz,2.0mm,0.100s,0.100s]",
        "L P[5] WELD_SPEED FINE | Arc End[1]",
        "Weave End",
        "L P[6] 200mm/sec FINE"]


def copies(path, index, count):
    """Put `count` copies of move `index` after it; the weld runs after it move on."""
    path.moves[index + 1:index + 1] = [dataclasses.replace(path.moves[index])
                                       for _ in range(count)]
    for run in path.welds:
        run.start += count if run.start > index else 0
        run.end += count if run.end >= index else 0


def test_fanuc_touching_welds_end_and_restart_the_arc_at_their_junction():
    assert mn_instructions(text_of("fanuc_ls", touching("fanuc_ls"))) == [
        "J P[1] 20% CNT100",
        "L P[2] 50mm/sec FINE | Arc Start[1]",
        "Weave Sine[2.0Hz,2.0mm,0.100s,0.100s]",
        "L P[3] WELD_SPEED FINE | Arc End[1]",
        "Weave End",
        "Arc Start[2]",                                     # the second schedule strikes here
        "Weave Sine[2.0Hz,2.0mm,0.100s,0.100s]",
        "L P[4] WELD_SPEED FINE | Arc End[2]",
        "Weave End",
        "L P[5] 200mm/sec FINE"]


def test_fanuc_split_never_cuts_a_weld():
    program = fillet("fanuc_ls")
    copies(program.paths[0], 0, 50)         # 51 approach moves before the weld
    files = posts.run(fanuc_ls, program, {"max_lines": 60})
    assert len(files) == 3                  # main, the approach, the weld
    first, second = (mn_instructions(t.replace("\r\n", "\n")) for _, t in files[1:])
    assert len(first) == 51 and not any("Arc" in b for b in first)
    assert second[0] == "L P[1] 50mm/sec FINE | Arc Start[1]"     # cut before the start move
    assert ("/APPL" in files[1][1], "/APPL" in files[2][1]) == (False, True)
    program = fillet("fanuc_ls")
    copies(program.paths[0], 2, 60)         # a weld of 63 moves
    with pytest.raises(PostError, match=r"^Weld 'Weld' \(Fillet weld\) needs 69 lines and 63 "
                                        r"positions, more than one program holds "
                                        r"\(max_lines=60, max_positions=9999\); raise max_lines"):
        posts.run(fanuc_ls, program, {"max_lines": 60})


# --- Yaskawa INFORM -------------------------------------------------------------

def inform_instructions(text):
    body = text[text.index("NOP\n") + 4:text.index("\nEND")].splitlines()
    return [line for line in body if not line.startswith("'")]


def test_inform_inline_weld_values():
    text = text_of("motoman_inform", fillet("motoman_inform", weave=NO_DWELLS))
    assert inform_instructions(text) == [
        "MOVJ C00000 VJ=20.00 PL=1",
        "MOVL C00001 V=50.0 PL=0",                          # the seam start, fine
        "ARCON AC=265 AV=27.5",
        # half of 4 mm; 2 Hz; the weave line rises at 45 degrees (torch on the bisector)
        "WVON AMP=2.0 FREQ=2.0 ANGL=45.0 DIR=0",
        "MOVL C00002 V=7.5 PL=1",
        "MOVL C00003 V=7.5 PL=0",
        "WVOF",
        "ARCOF AC=185 AV=22.0 T=0.30",                      # crater 185 A, 22 V, 0.3 s
        "MOVL C00004 V=200.0 PL=0"]


def test_inform_condition_files_and_their_sheet(tmp_path):
    program = with_weave(fillet("motoman_inform"), pattern="triangle", height_mm=1.5)
    files = posts.run(motoman_inform, program, {"conditions": "files", "condition_file": 12})
    assert [name for name, _ in files] == ["FILLET.JBI", "FILLET_CONDITIONS.txt"]
    job, sheet = (text.replace("\r\n", "\n") for _, text in files)
    assert [i for i in inform_instructions(job) if not i.startswith("MOV")] == [
        "ARCON ASF#(12)", "WVON WEV#(12)", "WVOF", "ARCOF AEF#(12)"]
    assert "'FILLET_CONDITIONS.txt" in job
    assert re.search(r"WEV#\(12\) WEAVING CONDITION\n +mode +Triangular\n +amplitude +2\.0 mm",
                     sheet)
    assert re.search(r"height +1\.5 mm", sheet)
    assert re.search(r"AEF#\(12\) ARC END CONDITION\n +crater current +185 A\n +crater "
                     r"voltage +22\.0 V", sheet)


def test_inform_corner_stop_ends_and_restarts_the_arc_at_the_corner():
    text = text_of("motoman_inform", corner("motoman_inform", weave=NO_DWELLS))
    steps = inform_instructions(text)
    assert steps[1:] == [
        "MOVL C00001 V=50.0 PL=0", "ARCON AC=265 AV=27.5",
        "WVON AMP=2.0 FREQ=2.0 ANGL=45.0 DIR=0",
        "MOVL C00002 V=7.5 PL=0", "WVOF", "ARCOF AC=185 AV=22.0 T=0.30",
        "MOVL C00003 V=7.5 PL=0", "ARCON AC=265 AV=27.5",       # turned, then arc on again
        "WVON AMP=2.0 FREQ=2.0 ANGL=45.0 DIR=0",
        "MOVL C00004 V=7.5 PL=0", "WVOF", "ARCOF AC=185 AV=22.0 T=0.30",
        "MOVL C00005 V=200.0 PL=0"]


def test_inform_touching_welds_end_and_restart_the_arc_at_their_junction():
    program = touching("motoman_inform", weave=NO_DWELLS)
    weave = "WVON AMP=2.0 FREQ=2.0 ANGL=45.0 DIR=0"
    assert inform_instructions(text_of("motoman_inform", program))[1:] == [
        "MOVL C00001 V=50.0 PL=0", "ARCON AC=265 AV=27.5", weave,
        "MOVL C00002 V=7.5 PL=0", "WVOF", "ARCOF AC=185 AV=22.0 T=0.30",
        "ARCON AC=265 AV=27.5", weave,
        "MOVL C00003 V=5.0 PL=0", "WVOF", "ARCOF AC=185 AV=22.0 T=0.30",
        "MOVL C00004 V=200.0 PL=0"]
    files = posts.run(motoman_inform, program, {"max_positions": 4})
    jobs = [inform_instructions(t.replace("\r\n", "\n")) for _, t in files[1:]]
    # approach + both welds (3 positions: the junction is one) | retract
    assert [sum(s.startswith("MOV") for s in job) for job in jobs] == [4, 1]


def test_inform_split_keeps_each_weld_in_one_job():
    files = posts.run(motoman_inform, corner("motoman_inform", weave=NO_DWELLS),
                      {"max_positions": 4})
    jobs = [inform_instructions(t.replace("\r\n", "\n")) for _, t in files[1:]]
    # approach (1 position) + weld 1 (2) | weld 2 (2) + retract (1)
    assert [sum(s.startswith("MOV") for s in job) for job in jobs] == [3, 3]
    for job in jobs:
        assert sum(s.startswith("ARCON") for s in job) == sum(s.startswith("ARCOF") for s in job)
    long = fillet("motoman_inform", weave=NO_DWELLS)
    path = long.paths[0]
    path.moves[3:3] = [dataclasses.replace(path.moves[2]) for _ in range(2)]
    path.welds[0].end = 5
    with pytest.raises(PostError, match=r"^Weld 'Weld' \(Fillet weld\) needs 5 positions .*"
                                        r"raise max_positions or max_lines"):
        posts.run(motoman_inform, long, {"max_positions": 4})


# --- UR ---------------------------------------------------------------------------

TOL = 2e-4
MOVEP = re.compile(r"movep\(pose_trans\(B, p\[([^\]]*)\]\), a=[\d.]+, v=([\d.]+), r=([\d.]+)\)")


def woven(text):
    """Positions (mm, in B), speeds (mm/s) and blend radii (mm) of the movep lines."""
    rows = MOVEP.findall(text)
    xyz = np.array([[float(v) for v in p.split(",")[:3]] for p, _, _ in rows]) * 1000.0
    return xyz, np.array([float(v) for _, v, _ in rows]) * 1000.0, \
        np.array([float(r) for _, _, r in rows]) * 1000.0


def test_ur_woven_points_reproduce_the_weave_and_the_travel_speed():
    xyz, speed, blend = woven(text_of("ur_script", fillet("ur_script")))
    points = np.vstack([[0.0, 0.0, 0.0], xyz])          # from the seam start
    # The seam runs along X of B; the weave line is (0, 1, 1)/sqrt(2) (across the
    # tool axis (0, 1, -1)/sqrt(2)): lateral offset = its projection.
    lateral = points[:, 1:] @ np.array([1.0, 1.0]) / np.sqrt(2)
    across = points[:, 1:] @ np.array([1.0, -1.0]) / np.sqrt(2)
    # poses are written to 0.1 um: TOL 0.2 um
    assert np.max(np.abs(across)) < TOL                 # the weave stays across the tool axis
    assert lateral.max() - lateral.min() == pytest.approx(4.0, abs=TOL)   # full width 4 mm
    at_left = np.isclose(lateral, 2.0, atol=TOL)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], at_left.astype(int), [0]])))
    arrive, leave = points[edges[::2], 0], points[edges[1::2] - 1, 0]
    # cycle k (from 0) reaches the left end at 3.75 k + 0.5625 mm (a quarter of the 0.3 s
    # moving time); the first is inside the ramp in, the last leaves it in the ramp out
    assert arrive == pytest.approx(3.75 * np.arange(1, 27) + 0.5625, abs=TOL)
    assert (leave - arrive)[:-1] == pytest.approx(0.75, abs=TOL)   # 0.1 s dwell at 7.5 mm/s
    segment = np.linalg.norm(np.diff(points, axis=0), axis=1)
    time = segment / speed
    assert time.sum() == pytest.approx(100.0 / 7.5, rel=2e-4)    # the seam at 7.5 mm/s
    # each segment at 7.5 mm/s along the seam (0.1 um poses on 0.06 mm ramp segments: 0.1 %)
    assert np.diff(points[:, 0]) / time == pytest.approx(7.5, rel=1e-3)
    assert points[-1] == pytest.approx([100.0, 0.0, 0.0], abs=TOL)   # ends on the seam end
    shortest = np.minimum(segment, np.append(segment[1:], np.inf))
    assert np.all(blend <= shortest / 2 + 1e-9) and blend[-1] == 0


@pytest.mark.parametrize("pattern", ["circle", "triangle", "l"])
def test_ur_other_weave_patterns_keep_width_and_travel_time(pattern):
    program = with_weave(fillet("ur_script"), pattern=pattern, dwell_left_s=0.0,
                         dwell_right_s=0.0)
    xyz, speed, _ = woven(text_of("ur_script", program))
    points = np.vstack([[0.0, 0.0, 0.0], xyz])
    lateral = points[:, 1:] @ np.array([1.0, 1.0]) / np.sqrt(2)
    assert lateral.max() - lateral.min() == pytest.approx(4.0, abs=TOL)
    time = np.linalg.norm(np.diff(points, axis=0), axis=1) / speed
    assert time.sum() == pytest.approx(100.0 / 7.5, rel=2e-4)
    if pattern == "circle":
        # every 0.5 s / 8 up to 13.333 s: 213 points; the seam's corner at 6.667 s, the
        # ramp out's start at 13.083 s and the seam end (the ramp in ends on a point)
        assert len(xyz) == 213 + 3


def test_ur_woven_motion_keeps_a_corner_slow_down():
    program = slowed_down(fillet("ur_script"))      # the first 50 mm
    xyz, speed, _ = woven(text_of("ur_script", program))
    points = np.vstack([[0.0, 0.0, 0.0], xyz])
    time = np.linalg.norm(np.diff(points, axis=0), axis=1) / speed
    assert time.sum() == pytest.approx(50.0 / 4.4 + 50.0 / 7.5, rel=2e-4)
    along = np.diff(points[:, 0]) / time
    first = points[1:, 0] <= 50.0 + TOL
    assert along[first] == pytest.approx(4.4, rel=1e-3)
    assert along[~first] == pytest.approx(7.5, rel=1e-3)


def test_ur_arc_io_around_the_seam():
    text = text_of("ur_script", fillet("ur_script"), {"arc_ok_input": 3, "arc_output": 5,
                                                      "voltage_output": "none"})
    body = [line.strip().split("  #")[0] for line in text.splitlines()
            if not line.strip().startswith("#") and "movep" not in line]
    start = body.index("movel(pose_trans(B, t2), a=1.2, v=0.05, r=0)")
    assert body[start + 1:start + 4] == ["set_standard_analog_out(0, 0.3350)",   # 6.7 / 20
                                         "set_standard_digital_out(5, True)", "sleep(0.2)"]
    assert body[start + 4:start + 6] == ["arc_wait = 0", "while not get_standard_digital_in(3):"]
    end = body.index("set_standard_analog_out(0, 0.2250)")                       # 4.5 / 20
    assert body[end + 1:end + 5] == ["sleep(0.3)", "set_standard_digital_out(5, False)",
                                     "sleep(0.5)", "movel(pose_trans(B, t5), a=1.2, v=0.2, r=0)"]
    assert "set_standard_analog_out(1," not in text
    plain = text_of("ur_script", fillet("ur_script"))
    assert "set_standard_analog_out(1, 0.5500)" in plain and "set_standard_analog_out(1, 0.4400)" \
        in plain                                                                # 27.5 / 50, 22 / 50
    assert "get_standard_digital_in" not in plain


def test_ur_corner_stop_and_a_weld_without_weave():
    text = text_of("ur_script", corner("ur_script", weave=None))
    events = [line.strip() for line in text.splitlines()
              if "digital_out" in line or line.strip().startswith(("movel", "movep"))]
    assert [e.split("  #")[0] for e in events] == [
        "movel(pose_trans(B, t2), a=1.2, v=0.05, r=0)", "set_standard_digital_out(0, True)",
        "movel(pose_trans(B, t3), a=1.2, v=0.0075, r=0)", "set_standard_digital_out(0, False)",
        "movel(pose_trans(B, t4), a=1.2, v=0.0075, r=0)", "set_standard_digital_out(0, True)",
        "movel(pose_trans(B, t5), a=1.2, v=0.0075, r=0)", "set_standard_digital_out(0, False)",
        "movel(pose_trans(B, t6), a=1.2, v=0.2, r=0)"]


def test_ur_touching_welds_end_and_restart_the_arc_at_their_junction():
    text = text_of("ur_script", touching("ur_script"))
    events = [line.strip().split("  #")[0] for line in text.splitlines()
              if "digital_out" in line or line.strip().startswith("movel")]
    assert events == [
        "movel(pose_trans(B, t2), a=1.2, v=0.05, r=0)", "set_standard_digital_out(0, True)",
        "set_standard_digital_out(0, False)", "set_standard_digital_out(0, True)",
        "set_standard_digital_out(0, False)", "movel(pose_trans(B, t5), a=1.2, v=0.2, r=0)"]
    xyz, speed, _ = woven(text)
    points = np.vstack([[0.0, 0.0, 0.0], xyz])
    time = np.linalg.norm(np.diff(points, axis=0), axis=1) / speed
    assert time.sum() == pytest.approx(50.0 / 7.5 + 50.0 / 5.0, rel=2e-4)
    assert points[np.flatnonzero(time.cumsum() > 50.0 / 7.5 + 1e-3)[0]][0] == \
        pytest.approx(50.0, abs=TOL)      # the first weld ends on the seam at 50 mm
    files = posts.run(ur_script, touching("ur_script"), {"max_moves": 3})
    # approach | both welds (entry, junction, end: 3 moves) | retract
    assert [t.count("digital_out(0, True)") for _, t in files] == [0, 2, 0]


def test_ur_split_never_cuts_a_weld():
    files = posts.run(ur_script, corner("ur_script"), {"max_moves": 3})
    texts = [t for _, t in files]
    assert len(texts) == 2      # approach + weld 1 | weld 2 + retract
    for text in texts:
        assert text.count("set_standard_digital_out(0, True)") == \
            text.count("set_standard_digital_out(0, False)")
    with pytest.raises(PostError, match=r"^Weld 'Weld' \(Fillet weld\) has 3 moves, more than "
                                        r"max_moves=2"):
        posts.run(ur_script, fillet("ur_script"), {"max_moves": 2})


# --- refusals -------------------------------------------------------------------

def turn_in_place(program):
    """The weld's last move turns the torch where the one before ended."""
    moves = program.paths[0].moves
    moves[3].target.T_b_t = moves[3].target.T_b_t.copy()
    moves[3].target.T_b_t[:3, 3] = moves[2].target.T_b_t[:3, 3]
    return program


REFUSED = [
    ("fanuc_ls", lambda p: with_weave(p, pattern="triangle"), {},
     r"FANUC ArcTool has no triangle weave here: use zigzag, circle, l"),
    ("fanuc_ls", lambda p: with_weave(p, dwell_center_s=0.1), {}, r"no centre dwell"),
    ("fanuc_ls", lambda p: with_weave(p, angle_deg=10.0), {}, r"set angle_deg to 0"),
    ("fanuc_ls", lambda p: with_weave(p, tracking=Tracking("laser")), {},
     r"laser seam tracking, which FANUC ArcTool cannot write"),
    ("motoman_inform", lambda p: with_weave(p, pattern="circle", dwell_left_s=0.0,
                                            dwell_right_s=0.0), {"conditions": "files"},
     r"Yaskawa INFORM has no circle weave here: use zigzag, triangle, l"),
    ("motoman_inform", lambda p: p, {}, r"in-line WVON has no weave dwells: use conditions=files"),
    ("motoman_inform", lambda p: with_weave(p, pattern="l", dwell_left_s=0.0,
                                            dwell_right_s=0.0), {},
     r"in-line WVON has no L-type mode \(l weave\): use conditions=files"),
    ("motoman_inform", lambda p: with_weave(p, tracking=Tracking("arc")), {},
     r"does not write Yaskawa COM-ARC"),
    ("ur_script", lambda p: turn_in_place(p), {}, r"turns in place while weaving \(target "
     r"'t4'\): the weave needs travel"),
    ("ur_script", lambda p: with_weave(p, tracking=Tracking("arc")), {},
     r"arc seam tracking, which URScript cannot write"),
    ("ur_script", lambda p: p, {"wire_feed_full_scale_m_min": 5.0},
     r"wire feed 6\.7 m/min is beyond the analogue full scale 5 m/min; raise "
     r"wire_feed_full_scale_m_min"),
]


@pytest.mark.parametrize("post, change, options, match", REFUSED,
                         ids=[f"{r[0]}-{i}" for i, r in enumerate(REFUSED)])
def test_unsupported_welds_are_refused_in_one_line_naming_the_weld(post, change, options, match):
    program = change(fillet(post))
    before = repr(program)
    with pytest.raises(PostError, match=match) as caught:
        posts.run(POSTS[post], program, options)
    message = str(caught.value)
    assert "\n" not in message and message.startswith("Weld 'Weld' (Fillet weld)")
    assert repr(program) == before


def test_inform_inline_needs_the_current():
    program = fillet("motoman_inform", weave=NO_DWELLS)
    program.paths[0].welds[0].schedule = dataclasses.replace(
        program.paths[0].welds[0].schedule, current_a=None)
    with pytest.raises(PostError, match=r"has no current: INFORM's in-line ARCON/ARCOF need "
                                        r"AC=; give the schedule's current_a or use "
                                        r"conditions=files"):
        posts.run(motoman_inform, program, {})
    names = [n for n, _ in posts.run(motoman_inform, program, {"conditions": "files"})]
    assert names == ["FILLET.JBI", "FILLET_CONDITIONS.txt"]


def test_programs_without_welds_do_not_change():
    """No /APPL, arc or weave line without welds (the existing goldens pin the rest)."""
    program = fillet("fanuc_ls")
    program.paths[0].welds = []
    for move in program.moves():
        move.weld = None
    assert "/APPL" not in text_of("fanuc_ls", program)
