"""Weld programs of the ABB RAPID (RobotWare Arc) and KUKA KRL (ArcTech) posts (issue 22).

The woven fillet and the corner-stop programs of ``weld_fixtures`` are written
by both posts; the goldens are read back here as the welder and the controller
would: the arc strikes on the seam start (a fine stop), the moves in between
blend, the crater is a fine stop, and the numbers of the schedule and the weave
are the ones computed by hand below. Every RAPID module goes through the arc
record-shape check (``rapid_check.arc_record_problems``); each kind of module
(linear and circular welds, a corner stop, a restart, a split part) also through
rapidchecker in one test, which checks grammar and layout only (about 1 s a module
here): the variants that change only numbers inside the arc records are not run
through it again.

To rewrite the golden files after a reviewed change of the output:
``CADROBOT_UPDATE_GOLDEN=1 python3 -m pytest tests/core/test_posts_weld_postsak.py``.
"""

import dataclasses
import os
import pickle
import re
from pathlib import Path

import numpy as np
import pytest

import weld_fixtures as wf
from CadRobotWB import fileio, posts
from CadRobotWB.core import program as ir
from CadRobotWB.core.welding import Tracking, Weave
from CadRobotWB.errors import PostError
from CadRobotWB.posts import abb_rapid, common, kuka_krl

from rapid_check import arc_record_problems, assert_arc_records_ok, needs_rapidchecker

GOLDEN_DIR = Path(__file__).parent / "golden"
ABB, KUKA = "ABB_IRB2400", "KUKA_KR16"

# The fixture's numbers, by hand: fillet_t6 at 7.5 mm/s, zigzag 4 mm at 2 Hz, 0.1 s dwells.
CYCLE_MM = 7.5 / 2.0                 # 3.75 mm of travel per weave cycle
DWELL_MM = 0.1 * 7.5                 # 0.75 mm of travel during each 0.1 s dwell
WIRE_MM_S = 6.7 * 1000 / 60          # 111.67 mm/s (SI_UNITS), written 111.7
CRATER_MM_S = 4.5 * 1000 / 60        # 75 mm/s


def assert_arc_records_shaped(text):
    """The arc record shapes (every tier); rapidchecker runs on each kind of module in
    test_rapidchecker_accepts_every_kind_of_weld_module."""
    problems, count = arc_record_problems(text)
    assert count and not problems, problems


def _golden(name, text):
    golden = GOLDEN_DIR / name
    if os.environ.get("CADROBOT_UPDATE_GOLDEN"):
        golden.write_bytes(text.encode("ascii"))
    assert golden.exists(), f"missing {golden}; see this file's docstring"
    assert text == golden.read_bytes().decode("ascii"), golden.name


def rapid(program, options=None):
    """The module, through posts.run (option names and the output checked)."""
    (_, text), = posts.run(abb_rapid, program, options or {})
    return text


def proc_lines(text, proc="Seam"):
    """The instruction lines of a PROC, stripped, comments left out."""
    body = text.split(f"PROC {proc}()")[1].split("ENDPROC")[0]
    return [line.strip() for line in body.splitlines() if line.strip()
            and not line.strip().startswith("!")]


def arc_literal(text, kind, name):
    return re.search(rf"LOCAL PERS {kind} {name} := (\[.*\]);", text).group(1)


def numbers(literal):
    """The scalars of a RAPID literal, in order, as floats (TRUE/FALSE left out)."""
    return [float(v) for v in re.findall(r"-?\d+(?:\.\d+)?(?:E[+-]?\d+)?", literal)]


def circular_weld_program(robot):
    """The woven fillet with its middle welded move a circle through (25, 5, 0) and its
    last move a circle through (75, 5, 0): ArcC / ArcCEnd, ARCSWI CIRC / ARCOFF CIRC."""
    program = wf.woven_fillet_program(robot)
    moves = program.paths[0].moves
    for index, via in ((2, (25.0, 5.0, 0.0)), (3, (75.0, 5.0, 0.0))):
        moves[index].kind = ir.CIRCULAR
        moves[index].via = ir.Target(f"c{index}", wf.torch_pose(via))
    return program


def long_weld_program(robot, extra):
    """The woven fillet with `extra` more welded moves between t3 and t4."""
    program = wf.woven_fillet_program(robot)
    path = program.paths[0]
    path.moves[3:3] = [dataclasses.replace(path.moves[2], target=ir.Target(
        f"w{k}", wf.torch_pose((50.0 + k * 0.5, 0.0, 0.0)))) for k in range(extra)]
    path.welds[0].end += extra
    return program


def meeting_runs_program(robot):
    """The woven fillet welded as two runs that meet at t3: ``Weld`` ends there (crater)
    and ``Weld_2`` strikes there again."""
    program = wf.woven_fillet_program(robot)
    path = program.paths[0]
    path.moves[2].zone_mm = 0.0
    path.moves[3].weld = "Weld_2"
    first = path.welds[0]
    path.welds = [dataclasses.replace(first, end=2),
                  dataclasses.replace(first, name="Weld_2", start=2, end=3, part=2)]
    return program


def circular_start_program(robot):
    """The weld starts on t3, reached by an unwelded circle through (25, 5, 0)."""
    program = wf.woven_fillet_program(robot)
    path = program.paths[0]
    path.moves[2].kind, path.moves[2].via = ir.CIRCULAR, ir.Target("c2", wf.torch_pose(
        (25.0, 5.0, 0.0)))
    path.moves[2].zone_mm, path.moves[2].weld = 0.0, None
    path.welds[0].start = 2
    return program


def slowed_corner_program(robot):
    """The woven fillet whose last welded move is a corner slow-down at 5 mm/s
    (core/weld_runs allows a risk-area move named so to be slower)."""
    program = wf.woven_fillet_program(robot)
    move = program.paths[0].moves[3]
    move.role, move.speed_mm_s = ir.ROLE_RISK, 5.0
    move.comment = "segment 1: corner slow-down"
    return program


# --- ABB: goldens, read as the controller reads them ----------------------------------

def test_abb_fillet_golden_and_checks():
    text = rapid(wf.woven_fillet_program(ABB, tracking=Tracking("arc"), solve=True))
    _golden("weld_fillet_abb_rapid.mod", text)
    assert_arc_records_shaped(text)
    assert proc_lines(text) == [
        "MoveAbsJ t1, v200, z10, Torch \\WObj:=B;",
        "ArcLStart t2, v50, smWeld, wdWeld \\Weave:=wvWeld, fine, Torch \\WObj:=B "
        "\\Track:=trWeld;",
        "ArcL t3, v7_5, smWeld, wdWeld \\Weave:=wvWeld, z1, Torch \\WObj:=B \\Track:=trWeld;",
        "ArcLEnd t4, v7_5, smWeld, wdWeld \\Weave:=wvWeld, fine, Torch \\WObj:=B "
        "\\Track:=trWeld;",
        "MoveL t5, v200, fine, Torch \\WObj:=B;"]
    # the arc strikes on the seam start: ArcLStart's robtarget is the seam's origin
    start = re.search(r"robtarget t2 := \[\[([^\]]*)\]", text).group(1)
    np.testing.assert_allclose(np.array(start.split(","), float), [0, 0, 0])
    assert "option 633-4 Arc" in text and "SI_UNITS" in text


def test_abb_arc_data_values_are_the_schedule_and_weave():
    text = rapid(wf.woven_fillet_program(ABB, tracking=Tracking("arc", lateral_gain=0.4)))
    seam = numbers(arc_literal(text, "seamdata", "smWeld"))
    # flat: purge 0, preflow 1, ign_arc 2-10, ign_move_delay .. heat_distance 11-15,
    # heat_arc 16-24, cool 25, fill_time 26, fill_arc 27-35, bback 36, rback 37,
    # bback_arc 38-46, postflow 47
    assert len(seam) == 48 and seam[1] == 0.2 and seam[26] == 0.3 and seam[47] == 0.5
    assert seam[36:38] == [0.05, 0.0]
    assert seam[27:36] == [0, 0, 22.0, round(CRATER_MM_S, 1), 0, 0, 0, 0, 0]
    weld = numbers(arc_literal(text, "welddata", "wdWeld"))
    assert weld[:6] == [7.5, 0, 0, 0, 27.5, round(WIRE_MM_S, 1)]
    weave = numbers(arc_literal(text, "weavedata", "wvWeld"))
    assert weave == [1, 0, CYCLE_MM, 4.0, 0, DWELL_MM, 0, DWELL_MM, 0, 0, 0, 0, 0, 0, 0]
    track = arc_literal(text, "trackdata", "trWeld")
    assert track == "[0,FALSE,15,[0,40,50,0,0,0,0,0,0],[0,0,0,0,0,0,0]]"


@pytest.mark.parametrize("weave, expected", [
    # triangle: shape 3, apex height 3 mm; 2 Hz at 7.5 mm/s = 3.75 mm per cycle
    (Weave("triangle", width_mm=4.0, height_mm=3.0, frequency_hz=2.0),
     [3, 0, 3.75, 4, 3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]),
    # circle: shape 4, the radius (width / 2), the cycle given as 2.5 mm
    (Weave("circle", width_mm=4.0, length_mm=2.5), [4, 0, 2.5, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]),
    # 1 Hz = 7.5 mm; centre dwell 0.2 s a cycle = 0.1 s at each crossing = 0.75 mm;
    # the angle in weave_ori (the 11th field)
    (Weave("zigzag", width_mm=6.0, frequency_hz=1.0, dwell_center_s=0.2, angle_deg=20.0),
     [1, 0, 7.5, 6, 0, 0, 0.75, 0, 0, 0, 20, 0, 0, 0, 0]),
])
def test_abb_weave_patterns(weave, expected):
    text = rapid(wf.woven_fillet_program(ABB, weave=weave.validated()))
    assert numbers(arc_literal(text, "weavedata", "wvWeld")) == expected
    assert arc_record_problems(text) == ([], 3)


@pytest.mark.parametrize("units, speed, wire, cycle", [
    ("WELD_UNITS", "7.5", "6.7", "3.75"),
    # 7.5 mm/s = 17.72 in/min; 6.7 m/min = 263.8 in/min; 3.75 mm = 0.148 in
    ("US_UNITS", "17.72", "263.8", "0.148"),
])
def test_abb_arc_units(units, speed, wire, cycle):
    text = rapid(wf.woven_fillet_program(ABB), {"arc_units": units})
    assert arc_record_problems(text) == ([], 3)
    assert arc_literal(text, "welddata", "wdWeld").startswith(f"[{speed},0,[0,0,27.5,{wire},")
    assert arc_literal(text, "weavedata", "wvWeld").startswith(f"[1,0,{cycle},")
    assert units in text


def test_abb_job_mode_writes_only_the_job():
    schedule = dataclasses.replace(wf.FILLET_T6, job_number=12)
    text = rapid(wf.woven_fillet_program(ABB, schedule=schedule), {"arc_data": "job"})
    assert arc_record_problems(text) == ([], 3)
    assert arc_literal(text, "welddata", "wdWeld") == (
        "[7.5,0,[12,0,0,0,0,0,0,0,0],[0,0,0,0,0,0,0,0,0]]")
    assert "(option arc_data=job)" in text


def test_abb_corner_stop_ends_and_restarts_the_arc_with_one_set_of_data():
    text = rapid(wf.corner_stop_program(ABB, solve=True))
    _golden("weld_corner_abb_rapid.mod", text)
    assert_arc_records_shaped(text)
    assert [line.split(" ")[0] + " " + line.split(" ")[1] for line in proc_lines(text)] == [
        "MoveAbsJ t1,", "ArcLStart t2,", "ArcLEnd t3,", "ArcLStart t4,", "ArcLEnd t5,",
        "MoveL t6,"]
    assert all(", fine, " in line for line in proc_lines(text)[1:5])
    # both runs have the same schedule and weave: declared once, no trackdata, no \Track
    assert text.count("PERS seamdata") == text.count("PERS welddata") == 1
    assert "trackdata" not in text and "\\Track" not in text


def test_abb_circular_moves_weld_with_arcc_and_arccend():
    text = rapid(circular_weld_program(ABB))
    assert_arc_records_shaped(text)
    lines = proc_lines(text)
    assert lines[2].startswith("ArcC c2, t3, v7_5, smWeld, wdWeld \\Weave:=wvWeld, z1,")
    assert lines[3].startswith("ArcCEnd c3, t4, v7_5, smWeld, wdWeld \\Weave:=wvWeld, fine,")


def test_abb_arc_strikes_again_where_a_run_ended_or_after_a_circle():
    text = rapid(meeting_runs_program(ABB))
    assert_arc_records_shaped(text)
    assert proc_lines(text)[1:5] == [
        "ArcLStart t2, v50, smWeld, wdWeld \\Weave:=wvWeld, fine, Torch \\WObj:=B;",
        "ArcLEnd t3, v7_5, smWeld, wdWeld \\Weave:=wvWeld, fine, Torch \\WObj:=B;",
        "ArcLStart t3, v7_5, smWeld, wdWeld \\Weave:=wvWeld, fine, Torch \\WObj:=B;",
        "ArcLEnd t4, v7_5, smWeld, wdWeld \\Weave:=wvWeld, fine, Torch \\WObj:=B;"]
    lines = proc_lines(rapid(circular_start_program(ABB)))
    assert lines[1:5] == [
        "MoveL t2, v50, fine, Torch \\WObj:=B;",
        "MoveC c2, t3, v7_5, fine, Torch \\WObj:=B;",
        "ArcLStart t3, v7_5, smWeld, wdWeld \\Weave:=wvWeld, fine, Torch \\WObj:=B;",
        "ArcLEnd t4, v7_5, smWeld, wdWeld \\Weave:=wvWeld, fine, Torch \\WObj:=B;"]


def test_abb_corner_slow_down_welds_at_its_own_speed():
    text = rapid(slowed_corner_program(ABB))
    assert arc_record_problems(text) == ([], 4)
    assert "LOCAL PERS welddata wdWeld_2 := [5,0,[0,0,27.5,111.7," in text
    assert proc_lines(text)[3].startswith("ArcLEnd t4, v5, smWeld, wdWeld_2 \\Weave:=wvWeld,")
    assert proc_lines(text)[2].startswith("ArcL t3, v7_5, smWeld, wdWeld \\Weave:=wvWeld,")


def test_abb_distinct_schedules_get_their_own_data_and_no_weave_no_argument():
    program = wf.corner_stop_program(ABB)
    second = program.paths[0].welds[1]
    second.schedule = dataclasses.replace(second.schedule, voltage_v=26.0)
    second.weave = None
    text = rapid(program)
    assert arc_record_problems(text) == ([], 4)
    assert text.count("PERS seamdata") == 1 and text.count("PERS welddata") == 2
    assert "LOCAL PERS welddata wdWeld_2 := [7.5,0,[0,0,26,111.7," in text
    assert proc_lines(text)[3] == "ArcLStart t4, v7_5, smWeld, wdWeld_2, fine, Torch \\WObj:=B;"


def test_abb_split_never_cuts_a_weld():
    program = wf.woven_fillet_program(ABB)
    path = program.paths[0]
    path.moves += [dataclasses.replace(path.moves[0], target=ir.Target(
        f"a{k}", path.moves[0].target.T_b_t.copy())) for k in range(40)]
    for max_lines in range(rapid(program).count("\n"), 50, -1):
        files = abb_rapid.export(program, {"max_lines": max_lines})
        parts = [text for name, text in files if name != "Fillet.mod"]
        if len(parts) > 1:
            break
    assert len(parts) == 2
    holding = [text for text in parts if "ArcLStart" in text]
    assert len(holding) == 1 and "ArcLEnd" in holding[0] and "PERS seamdata" in holding[0]
    assert_arc_records_shaped(holding[0])
    with pytest.raises(PostError, match=r"^Weld 'Fillet weld' \(run Weld\) of path 'Fillet "
                                        r"seam' needs \d+ lines .* raise max_lines"):
        abb_rapid.export(long_weld_program(ABB, 60), {"max_lines": 50})


def split_part_with_weld():
    """A part module of a split program, the one holding the weld."""
    program = wf.woven_fillet_program(ABB)
    path = program.paths[0]
    path.moves += [dataclasses.replace(path.moves[0], target=ir.Target(
        f"a{k}", path.moves[0].target.T_b_t.copy())) for k in range(40)]
    files = abb_rapid.export(program, {"max_lines": 60})
    return next(text for _, text in files[1:] if "\n    ArcLStart" in text)


@needs_rapidchecker
def test_rapidchecker_accepts_every_kind_of_weld_module():
    """Linear and circular welds, arc tracking, a corner stop, a restart after a circle,
    a part of a split program: grammar and layout (rapidchecker) and record shapes."""
    for text in (rapid(wf.woven_fillet_program(ABB, tracking=Tracking("arc"))),
                 rapid(wf.corner_stop_program(ABB)), rapid(circular_weld_program(ABB)),
                 rapid(circular_start_program(ABB)), split_part_with_weld()):
        assert_arc_records_ok(text)


def test_record_shape_check_catches_bad_records():
    text = rapid(wf.woven_fillet_program(ABB))
    assert arc_record_problems(text) == ([], 3)
    bad = text.replace("LOCAL PERS welddata", "LOCAL CONST welddata")
    bad = bad.replace("[7.5,0,[0,0,27.5,111.7,0,0,0,0,0],", "[7.5,[0,0,27.5,111.7,0,0,0,0,0],")
    problems, _ = arc_record_problems(bad)
    assert problems == ["welddata wdWeld is CONST: RobotWare Arc needs PERS",
                        "welddata wdWeld has 3 fields, not 4"]
    short = text.replace("[1,0,3.75,4,0,0.75,0,0.75,0,0,0,0,0,0,0]",
                         "[1,0,3.75,4,0,0.75,0,0.75,0,0,0,0,0,0]")
    assert arc_record_problems(short)[0] == ["weavedata wvWeld has 14 fields, not 15"]


# --- KUKA: goldens, read as the controller reads them ---------------------------------

def krl(program, options=None):
    files = posts.run(kuka_krl, program, options or {})
    return {name[-4:]: text.replace("\r\n", "\n") for name, text in files}


def folds(src):
    """(instruction, WDAT, motion line) of every ArcTech fold, in order."""
    out = []
    for line in src.splitlines():
        fold = re.match(r";FOLD (ARC\w+) (WDAT\d+) ", line)
        if fold:
            out.append(fold.groups())
        elif re.match(r"(LIN|CIRC) ", line) and out and len(out[-1]) == 2:
            out[-1] += (line,)
    return out


def header_text(src):
    """The comment lines of a .src as one line of words."""
    return " ".join(re.findall(r"^  ; (.*)$", src, re.MULTILINE))


def assert_folds_balanced(src):
    depth = 0
    for line in src.splitlines():
        depth += line.startswith(";FOLD") - line.startswith(";ENDFOLD")
        assert depth in (0, 1, 2), line
    assert depth == 0


def assert_every_name_declared_once(src, dat):
    """Every weld datum and point a fold uses is declared once in the data list."""
    used = set(re.findall(r"^(?:LDAT_ACT|FDAT_ACT) = (\w+)$", src, re.MULTILINE))
    for args in re.findall(r"ArcMainNG\(#\w+, ([\w, ]+)\)", src):
        used |= set(args.split(", "))
    for points in re.findall(r"^(?:LIN|CIRC) ([\w, ]+?)(?: C_DIS)?$", src, re.MULTILINE):
        used |= set(points.split(", "))
    assert used
    for name in used:
        assert len(re.findall(rf"^  DECL \w+ {name}=", dat, re.MULTILINE)) == 1, name


def test_kuka_fillet_golden_and_folds():
    files = krl(wf.woven_fillet_program(KUKA, tracking=Tracking("arc"), solve=True))
    src, dat = files[".src"], files[".dat"]
    for extension, text in files.items():
        _golden("weld_fillet_kuka_krl" + extension, text.replace("\n", "\r\n"))
    assert_folds_balanced(src)
    assert_every_name_declared_once(src, dat)
    assert folds(src) == [("ARCON", "WDAT1", "LIN Xt2"), ("ARCSWI", "WDAT2", "LIN Xt3 C_DIS"),
                          ("ARCOFF", "WDAT3", "LIN Xt4")]
    assert "BAS(#CP_PARAMS, 0.05)" in src and src.count("gArcBasVelDefinition") == 2
    assert "ArcTech.Basic=3.4.3.1264" in src and "Tool[1]:Torch Base[1]:B" in src
    # the seam start: ARCON's point is the seam origin, its LDAT an exact stop
    assert re.search(r"DECL E6POS Xt2=\{X 0.0000,Y 0.0000,Z 0.0000,", dat)
    assert "DECL LDAT LCPDAT1={VEL 0.05,ACC 100.0,APO_DIST 0.0," in dat
    assert "DECL LDAT LCPDAT2={VEL 0.0075,ACC 100.0,APO_DIST 1.0," in dat


def test_kuka_arc_data_values_are_the_schedule_and_weave():
    dat = krl(wf.woven_fillet_program(KUKA, tracking=Tracking("arc")))[".dat"]
    wdat1 = re.search(r"DECL stArcDat_T WDAT1=(.*)", dat).group(1)
    assert "PreFlowTime 0.2,Channel1 0.0,Channel2 6.7,Channel3 0.0" in wdat1
    assert "Velocity 0.0075," in wdat1                        # 7.5 mm/s in m/s
    assert (f"Weave {{Pattern #Triangle,Length {CYCLE_MM},Amplitude 2.0,Angle 0.0,"
            "LeftSideDelay 0.1,RightSideDelay 0.1}") in wdat1
    assert "Track {IsArcSenseEnabled TRUE," in wdat1
    wdat2 = re.search(r"DECL stArcDat_T WDAT2=(.*)", dat).group(1)
    assert "Strike" not in wdat2 and "Track" not in wdat2 and "Weld {" in wdat2
    wdat3 = re.search(r"DECL stArcDat_T WDAT3=(.*)", dat).group(1)
    assert wdat3 == ('{WdatId[] "WDAT3",Crater {JobModeId[] "Job mode",ParamSetId[] "Set2",'
                     "CraterTime 0.3,PostflowTime 0.5,Channel1 0.0,Channel2 4.5,Channel3 0.0,"
                     "Channel4 0.0,Channel5 0.0,Channel6 0.0,Channel7 0.0,Channel8 0.0,"
                     "BurnBackTime 0.05}}")


def test_kuka_corner_slow_down_welds_at_its_own_speed():
    program = slowed_corner_program(KUKA)
    program.paths[0].moves[2].speed_mm_s = 5.0          # an ARCSWI move slowed too
    program.paths[0].moves[2].role = ir.ROLE_RISK
    program.paths[0].moves[2].comment = "corner slow-down"
    dat = krl(program)[".dat"]
    assert re.search(r"WDAT1=.*Weld \{[^}]*Velocity 0.0075,", dat)    # after ignition
    assert re.search(r"WDAT2=.*Weld \{[^}]*Velocity 0.005,", dat)     # the slowed move


@pytest.mark.parametrize("channels", [{"1": "voltage_v", 3: "current_a"},
                                      "1:voltage_v, 3:current_a"])
def test_kuka_channels_option(channels):
    files = krl(wf.woven_fillet_program(KUKA), {"channels": channels, "arctech_version": 3.4})
    assert "ArcTech.Basic=3.4\n" in files[".src"]
    dat, src = files[".dat"], files[".src"]
    assert "Channel1 27.5,Channel2 0.0,Channel3 265.0," in dat      # weld
    assert "Channel1 22.0,Channel2 0.0,Channel3 185.0," in dat      # crater
    assert "Channel1 = voltage_v, Channel3 = current_a, the others 0" in header_text(src)


def test_kuka_corner_stop_ends_and_restarts_the_arc():
    files = krl(wf.corner_stop_program(KUKA, solve=True))
    src, dat = files[".src"], files[".dat"]
    assert_folds_balanced(src)
    assert_every_name_declared_once(src, dat)
    assert folds(src) == [("ARCON", "WDAT1", "LIN Xt2"), ("ARCOFF", "WDAT2", "LIN Xt3"),
                          ("ARCON", "WDAT3", "LIN Xt4"), ("ARCOFF", "WDAT4", "LIN Xt5")]
    assert "Vel=0.0075 m/s" in src         # the reorientation ignites at travel speed


def test_kuka_arc_strikes_again_where_a_run_ended_or_after_a_circle():
    files = krl(meeting_runs_program(KUKA))
    src, dat = files[".src"], files[".dat"]
    assert_folds_balanced(src)
    assert_every_name_declared_once(src, dat)
    assert folds(src) == [("ARCON", "WDAT1", "LIN Xt2"), ("ARCOFF", "WDAT2", "LIN Xt3"),
                          ("ARCON", "WDAT3", "LIN Xt3"), ("ARCOFF", "WDAT4", "LIN Xt4")]
    files = krl(circular_start_program(KUKA))
    src, dat = files[".src"], files[".dat"]
    assert_every_name_declared_once(src, dat)
    assert folds(src) == [("ARCON", "WDAT1", "LIN Xt3"), ("ARCOFF", "WDAT2", "LIN Xt4")]
    assert "\n  CIRC Xc2, Xt3\n;FOLD ARCON WDAT1 LIN t3 Vel=0.0075 m/s" in src


def test_kuka_circular_moves_are_arcswi_and_arcoff_circ():
    files = krl(circular_weld_program(KUKA))
    src, dat = files[".src"], files[".dat"]
    assert_folds_balanced(src)
    assert_every_name_declared_once(src, dat)
    assert folds(src)[1:] == [("ARCSWI", "WDAT2", "CIRC Xc2, Xt3 C_DIS"),
                              ("ARCOFF", "WDAT3", "CIRC Xc3, Xt4")]
    assert "IlfProvider=kukaroboter.arctech.arcswicirc" in src
    assert "ArcMainNG(#ArcSwiMoveStd, WDAT2, Wt3, Wc2)" in src
    assert "IlfProvider=kukaroboter.arctech.arcoffcirc" in src


def test_kuka_split_never_cuts_a_weld():
    program = wf.woven_fillet_program(KUKA)
    path = program.paths[0]
    for k in range(150):
        path.moves.append(dataclasses.replace(path.moves[0], target=ir.Target(
            f"a{k}", path.moves[0].target.T_b_t.copy())))
    files = kuka_krl.export(program, {"max_lines": 100})
    parts = [text for name, text in files if name.endswith(".src") and name != "Fillet.src"]
    assert len(parts) >= 2
    assert sum(";FOLD ARCON" in text for text in parts) == 1
    name = next(name for name, text in files if ";FOLD ARCON" in text)
    src, dat = (dict(files)[name[:-4] + ext].replace("\r\n", "\n") for ext in (".src", ".dat"))
    assert ";FOLD ARCSWI" in src and ";FOLD ARCOFF" in src
    assert_every_name_declared_once(src, dat)
    with pytest.raises(PostError, match=r"^Weld 'Fillet weld' \(run Weld\) of path 'Fillet "
                                        r"seam' needs more than max_lines 100 lines .* raise"):
        kuka_krl.export(long_weld_program(KUKA, 20), {"max_lines": 100})


@pytest.mark.parametrize("post", [abb_rapid, kuka_krl])
def test_runs_that_meet_stay_in_one_part(post):
    program = meeting_runs_program(ABB if post is abb_rapid else KUKA)
    path = program.paths[0]
    assert common.weld_spans(path) == [[path.welds[0], 1, 3]]   # moves 1..3 kept whole
    path.moves += [dataclasses.replace(path.moves[0], target=ir.Target(
        f"a{k}", path.moves[0].target.T_b_t.copy())) for k in range(150)]
    files = post.export(program, {"max_lines": 100})
    holding = [text for _, text in files[1:] if "\n    ArcLStart" in text or ";FOLD ARCON" in text]
    assert len(files) > 3 and len(holding) == 1
    assert holding[0].count("ArcLEnd") + holding[0].count(";FOLD ARCOFF") == 2


def test_kuka_numbered_tool_and_base_may_be_given():
    src = krl(wf.woven_fillet_program(KUKA), {"tool_number": 4, "base_number": 7})[".src"]
    assert "Tool[4]:Torch Base[7]:B" in src and "$TOOL = TOOL_DATA[4]" in src


# --- refusals: one line, naming the weld and the fix; nothing written ---------------

def _with_weave(**changes):
    return dataclasses.replace(wf.ZIGZAG_4MM, **changes)


@pytest.mark.parametrize("post, build, options, match", [
    (abb_rapid, lambda: wf.woven_fillet_program(ABB, weave=Weave("l").validated()), {},
     r"ABB RobotWare Arc has no l weave here: use zigzag, triangle, circle"),
    (abb_rapid, lambda: wf.woven_fillet_program(ABB), {"path_correction": True},
     r"path_correction \(\\Corr\) on RobotWare Arc instructions is not verified"),
    (abb_rapid, lambda: wf.woven_fillet_program(ABB, tracking=Tracking("laser")), {},
     r"tracks with the laser \(\\Corr\), which the ABB RobotWare Arc post does not write"),
    (abb_rapid, lambda: wf.woven_fillet_program(ABB, weave=None, tracking=Tracking("arc")), {},
     r"through-arc tracking \(\\Track\) needs a weave"),
    (abb_rapid, lambda: wf.woven_fillet_program(ABB), {"arc_data": "job"},
     r"arc_data=job .* give the schedule a job_number"),
    (kuka_krl, lambda: wf.woven_fillet_program(KUKA), {"controller": "krc2"},
     r"ArcTech Analog on KR C2 is not supported: use controller=krc4"),
    (kuka_krl, lambda: wf.woven_fillet_program(KUKA, weave=_with_weave(pattern="triangle")), {},
     r"KUKA ArcTech has no triangle weave here: use zigzag"),
    (kuka_krl, lambda: wf.woven_fillet_program(KUKA, weave=_with_weave(dwell_center_s=0.1)),
     {}, r"no centre dwell: set dwell_center_s to 0"),
    (kuka_krl, lambda: wf.woven_fillet_program(KUKA, tracking=Tracking("laser")), {},
     r"tracks with the laser \(SeamTech\)"),
    (kuka_krl, lambda: wf.woven_fillet_program(KUKA, weave=None, tracking=Tracking("arc")), {},
     r"through-arc tracking \(ArcSense\) needs a weave"),
])
def test_unsupported_welds_are_refused_in_one_line(tmp_path, post, build, options, match):
    program = build()
    before = pickle.dumps(program)
    with pytest.raises(PostError) as error:
        fileio.write_files_atomically(str(tmp_path), posts.run(post, program, options))
    message = str(error.value)
    assert "\n" not in message and re.search(match, message), message
    assert message.startswith("Weld ") and "Fillet weld" in message
    assert not os.listdir(tmp_path) and pickle.dumps(program) == before


@pytest.mark.parametrize("post, options, match", [
    (abb_rapid, {"arc_units": "SI"}, "arc_units must be one of SI_UNITS, WELD_UNITS, US_UNITS"),
    (abb_rapid, {"arc_data": "current"}, "arc_data must be one of voltage_wirefeed, job"),
    (kuka_krl, {"arctech_version": "latest"}, "arctech_version must be dotted numbers"),
    (kuka_krl, {"channels": {9: "job_number"}}, "channels must map channel numbers 1-8"),
    (kuka_krl, {"channels": {1: "wire"}}, "channels must map channel numbers 1-8"),
    (kuka_krl, {"channels": "1=voltage_v"}, "channels must map channel numbers 1-8"),
])
def test_bad_weld_options_name_the_option(post, options, match):
    with pytest.raises(PostError, match=match):
        posts.run(post, wf.woven_fillet_program(ABB if post is abb_rapid else KUKA), options)


@pytest.mark.parametrize("post", [abb_rapid, kuka_krl])
def test_broken_runs_are_refused(post):
    program = wf.woven_fillet_program()
    program.paths[0].moves[1].zone_mm = 5.0
    with pytest.raises(PostError, match=r"start \(ignition\) move 1 has zone 5 mm: .* must "
                                        r"stop exactly \(zone 0\)"):
        post.export(program, {})
    program = wf.woven_fillet_program()
    program.paths[0].moves[2].weld = None
    with pytest.raises(PostError, match=r"welded move 2 is marked weld=None"):
        post.export(program, {})
