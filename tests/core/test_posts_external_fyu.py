"""External axes in the FANUC LS, Yaskawa INFORM and UR posts (issue 23).

The program is the pipe-to-flange weld all round of external_fixtures.py: a
fillet of radius 60 mm about the work frame B's Z, on a tilt-and-turn
positioner (E tilt, E turn), optionally with the robot on a track (E1), solved
for a robot of the post's maker.  The values expected are worked out here by
hand from the fixture's geometry:

* a target at the seam angle ``phi`` has tilt -45 deg, turn ``-90 - phi`` deg and,
  with the track, travel ``300 * phi / 360`` mm;
* the positioner brings every seam point to the same place of the work frame
  as drawn (the user frame, standing still): turned by ``-90 - phi`` the point
  ``60 (cos phi, sin phi, 0)`` lies at ``(0, -60, 0)``, tilted by -45 deg about
  X at ``(0, -60 cos 45, 60 sin 45) = (0, -42.426, 42.426)`` mm, with the torch
  straight down (tool X along B's X, Z = -Z: W, P, R = 180, 0, 0); the
  approach and retract are 50 mm above it (Z 92.426).

Each language is read as the controller and the welder read it: the group of
each axis, the coordinated moves, the arc on at the seam start only.

To rewrite the golden files after a reviewed change of the output:
``CADROBOT_UPDATE_GOLDEN=1 python3 -m pytest tests/core/test_posts_external_fyu.py``.
"""

import copy
import dataclasses
import functools
import math
import os
import re
from pathlib import Path

import numpy as np
import pytest

from CadRobotWB import posts
from CadRobotWB.core.mechanisms import ExternalAxes
from CadRobotWB.core.welding import Tracking
from CadRobotWB.errors import PostError
from CadRobotWB.posts import fanuc_ls, motoman_inform, ur_script

import external_fixtures as ef
import weld_fixtures as wf

GOLDEN_DIR = Path(__file__).parent / "golden"
ROBOTS = {"fanuc_ls": "FANUC_M20IA", "motoman_inform": "MOTOMAN_MA2010", "ur_script": "UR10E"}
POSTS = {m.NAME: m for m in (fanuc_ls, motoman_inform, ur_script)}
#: Station pulses per degree of tilt and turn (a made-up station: the sign is the direction).
STATION = {"station_pulses_per_degree": "1000,-500.5"}
NO_DWELLS = dataclasses.replace(wf.ZIGZAG_4MM, dwell_left_s=0.0, dwell_right_s=0.0)
#: Seam angle (deg) of each FANUC position P[1..11]: approach, entry, then via and end of
#: the four quarter circles, retract.
FANUC_PHI = [0, 0, 45, 90, 135, 180, 225, 270, 315, 360, 360]
#: Seam angle of each INFORM step C00000..: approach, entry, each arc's start (the robot is
#: there), via and end, a MOVL between two arcs, retract.
INFORM_PHI = [0, 0, 0, 45, 90, 90, 90, 135, 180, 180, 180, 225, 270, 270, 270, 315, 360, 360]
SEAM_XYZ = (0.0, -60.0 * math.cos(math.radians(45)), 60.0 * math.sin(math.radians(45)))


@functools.lru_cache(maxsize=None)
def _solved(robot, track):
    return ef.positioner_weld_program(robot, track=track, solve=True)


def program(post, track=False, weave=None, tracking=None):
    """A fresh copy of the solved fixture for `post`'s robot, with a weave (and tracking)."""
    result = copy.deepcopy(_solved(ROBOTS[post], track))
    run = result.paths[0].welds[0]
    run.weave = weave
    if tracking is not None:
        run.tracking = tracking
    return result


def text_of(post, prog, options=None, index=0):
    return posts.run(POSTS[post], prog, dict(options or {}))[index][1].replace("\r\n", "\n")


def tilt_turn(phi):
    return -45.0, -90.0 - phi


# --- golden files -------------------------------------------------------------------------------

GOLDEN = [
    ("ext_fanuc_positioner.LS", "fanuc_ls",
     lambda: program("fanuc_ls", weave=wf.ZIGZAG_4MM, tracking=Tracking(sensor="arc")), {}),
    ("ext_fanuc_track_positioner.LS", "fanuc_ls", lambda: program("fanuc_ls", track=True), {}),
    ("ext_yaskawa_positioner.JBI", "motoman_inform",
     lambda: program("motoman_inform", weave=NO_DWELLS), STATION),
    ("ext_yaskawa_track_positioner.JBI", "motoman_inform",
     lambda: program("motoman_inform", track=True), STATION),
]


@pytest.mark.parametrize("name, post, build, options", GOLDEN, ids=[g[0] for g in GOLDEN])
def test_golden_external_axes_programs(name, post, build, options):
    plain = text_of(post, build(), options)
    golden = GOLDEN_DIR / name
    if os.environ.get("CADROBOT_UPDATE_GOLDEN"):
        golden.write_text(plain, newline="\n")
    assert golden.exists(), f"missing {golden}; see this file's docstring"
    assert plain == golden.read_text()


def test_every_fixture_target_is_solved_for_the_posts_robots():
    for post in ("fanuc_ls", "motoman_inform"):
        for track in (False, True):
            assert all(t.joints_deg is not None for t in _solved(ROBOTS[post], track).targets())


# --- FANUC --------------------------------------------------------------------------------------

RECORD = re.compile(r"P\[(\d+)\]\{\n(.*?)\n\};", re.S)
NUMBER = r"(-?\d+\.\d+)"


def fanuc_records(text):
    """{n: (group 1 text, group 2 text or '')} of the /POS section."""
    out = {}
    for number, body in RECORD.findall(text[text.index("/POS\n"):]):
        gp1, _, gp2 = body.partition("   GP2:\n")
        out[int(number)] = (gp1, gp2)
    return out


def values_of(text, names, unit):
    return [float(re.search(rf"\b{name} ?= *{NUMBER} +{unit}", text).group(1)) for name in names]


@pytest.mark.parametrize("track", [False, True])
def test_fanuc_positioner_is_group_2_and_track_e1_of_group_1(track):
    text = text_of("fanuc_ls", program("fanuc_ls", track=track))
    assert "DEFAULT_GROUP\t= 1,1,*,*,*;\n" in text
    records = fanuc_records(text)
    assert sorted(records) == list(range(1, 12))
    for n, phi in enumerate(FANUC_PHI, start=1):
        gp1, gp2 = records[n]
        assert gp2.startswith("\tUF : 1, UT : 1,"), gp2
        assert values_of(gp2, ["J1", "J2"], "deg") == pytest.approx(tilt_turn(phi), abs=1e-4)
        if track:
            assert values_of(gp1, ["E1"], "mm") == pytest.approx([300.0 * phi / 360.0],
                                                                 abs=1e-3)
        else:
            assert "E1" not in gp1
        if n > 1:   # P[1] is the approach's joint position
            xyz = values_of(gp1, ["X", "Y", "Z"], "mm")
            lift = 50.0 if n == 11 else 0.0
            assert xyz == pytest.approx([SEAM_XYZ[0], SEAM_XYZ[1], SEAM_XYZ[2] + lift],
                                        abs=1e-3)
            assert values_of(gp1, ["W", "P", "R"], "deg") == pytest.approx([180, 0, 0],
                                                                          abs=1e-4)


def test_fanuc_coord_on_the_path_moves_only_and_the_arc_at_the_seam():
    prog = program("fanuc_ls", weave=wf.ZIGZAG_4MM, tracking=Tracking(sensor="arc"))
    text = text_of("fanuc_ls", prog)
    body = text[text.index("/MN\n"):text.index("/POS\n")].replace("\n    :  ", " | ")
    moves = [line.split(":", 1)[1] for line in body.splitlines()[1:]
             if re.match(r" *\d+:[JLC] ", line)]
    assert [m.split()[0] for m in moves] == ["J", "L", "C", "C", "C", "C", "L"]
    coordinated = [("COORD" in m) for m in moves]
    assert coordinated == [False, False, True, True, True, True, False]
    assert "Arc Start[1]" in moves[1] and "Arc End[1]" in moves[5]
    instructions = [line for line in body.splitlines()[1:] if "!" not in line]
    assert sum("Arc Start[" in line for line in instructions) == 1
    assert sum("Arc End[" in line for line in instructions) == 1
    after = body[body.index("Arc Start[1]"):]
    assert after.splitlines()[1:3] == ["  64:  Weave Sine[2.0Hz,2.0mm,0.100s,0.100s] ;",
                                       "  65:  Track TAST[1] ;"]


def test_fanuc_track_alone_keeps_one_group_and_no_coord():
    prog = program("fanuc_ls", track=True)
    external = prog.external
    prog.external = ExternalAxes(external.T_u_r, track=external.track)
    for target in prog.targets():
        target.external = target.external[:1]
    text = text_of("fanuc_ls", prog)
    assert "DEFAULT_GROUP\t= 1,*,*,*,*;" in text
    assert "GP2" not in text and "COORD" not in text
    assert values_of(fanuc_records(text)[4][0], ["E1"], "mm") == pytest.approx([75.0])


# --- Yaskawa ------------------------------------------------------------------------------------

def inform_positions(text, prefix):
    """{n: [values]} of the //POS lines ``<prefix>nnnnn=..``."""
    return {int(n): [float(v) for v in values.split(",")]
            for n, values in re.findall(rf"^{prefix}(\d{{5}})=(.*)$", text, re.M)}


def inform_instructions(text):
    return [line for line in text[text.index("NOP\n"):].splitlines()[1:]
            if not line.startswith("'")]


@pytest.mark.parametrize("track", [False, True])
def test_inform_station_pulses_base_mm_and_header(track):
    text = text_of("motoman_inform", program("motoman_inform", track=track), STATION)
    n = len(INFORM_PHI)
    assert f"///NPOS {n},{n if track else 0},{n},0,0,0\n" in text
    groups = "///GROUP1 RB1,BS1\n" if track else "///GROUP1 RB1\n"
    assert groups + "///GROUP2 ST1\nNOP\n" in text
    station = inform_positions(text, "EC")
    assert sorted(station) == list(range(n))
    for k, phi in enumerate(INFORM_PHI):
        tilt, turn = tilt_turn(phi)
        # round half up of pulses per degree times degrees: 1000 * tilt, -500.5 * turn
        assert station[k] == [-45000, math.floor(-500.5 * turn + 0.5)], k
    assert station[3] == [-45000, 67568]                      # phi 45: 67567.5 up
    base = inform_positions(text, "BC")
    if track:
        assert [v for (v,) in base.values()] == pytest.approx(
            [300.0 * phi / 360.0 for phi in INFORM_PHI], abs=1e-3)
        assert "///POSTYPE BASE\n///RECTAN\nBC00000=0.000\n" in text
    else:
        assert not base and "BS1" not in text
    cartesian = inform_positions(text, "C")
    for k in range(1, n - 1):
        assert cartesian[k] == pytest.approx([*SEAM_XYZ, 180, 0, 0], abs=1e-3), k
    assert cartesian[n - 1][2] == pytest.approx(SEAM_XYZ[2] + 50.0, abs=1e-3)


def test_inform_path_moves_are_synchronized_with_the_station():
    prog = program("motoman_inform", weave=NO_DWELLS)
    lines = inform_instructions(text_of("motoman_inform", prog, STATION))
    moves = [line for line in lines if "MOV" in line]
    assert [m.split()[0] for m in moves] == (["MOVJ", "MOVL"] + ["SMOVC"] * 3
                                             + (["SMOVL"] + ["SMOVC"] * 3) * 3 + ["MOVL"])
    for k, move in enumerate(moves):
        station = f"+MOVJ EC{k:05d}"
        assert move.split()[1] == f"C{k:05d}"
        if move.startswith("S"):
            assert move.endswith(station), move
        else:
            assert re.search(rf"PL=\d \+MOVJ EC{k:05d} VJ=\d+\.\d\d$", move), move
    assert moves[0] == "MOVJ C00000 VJ=20.00 PL=1 +MOVJ EC00000 VJ=20.00"
    assert moves[-1] == "MOVL C00017 V=200.0 PL=0 +MOVJ EC00017 VJ=20.00"
    # the arc strikes after the entry, weaving flat (ANGL 180 = horizontal), and goes out
    # after the last synchronized step
    assert lines[lines.index(moves[1]) + 1:lines.index(moves[1]) + 3] == [
        "ARCON AC=265 AV=27.5", "WVON AMP=2.0 FREQ=2.0 ANGL=180.0 DIR=0"]
    assert lines[lines.index(moves[-2]) + 1:lines.index(moves[-2]) + 3] == [
        "WVOF", "ARCOF AC=185 AV=22.0 T=0.30"]
    assert sum("ARCON" in line for line in lines) == 1


def test_inform_station_zero_offset():
    options = dict(STATION, station_pulse_zero_deg="-45,-90")
    text = text_of("motoman_inform", program("motoman_inform"), options)
    assert inform_positions(text, "EC")[4] == [0, math.floor(-500.5 * -90.0 + 0.5)]


@pytest.mark.parametrize("options, words", [
    ({}, ["Positioner", "station_pulses_per_degree", "2 numbers"]),
    ({"station_pulses_per_degree": "1000"}, ["station_pulses_per_degree", "2"]),
    ({"station_pulses_per_degree": "1000,0"}, ["non-zero"]),
    (dict(STATION, relative_job=True, controller="dx100"), ["relative_job"]),
])
def test_inform_refusals_name_the_option(options, words):
    with pytest.raises(PostError) as error:
        posts.run(motoman_inform, program("motoman_inform"), options)
    message = str(error.value)
    assert "\n" not in message and all(w in message for w in words), message


def test_inform_station_option_without_a_positioner_is_refused():
    plain = wf.woven_fillet_program("MOTOMAN_HP6", frame_mm=(700.0, 0.0, 200.0))
    with pytest.raises(PostError, match="station_pulses_per_degree is for a program with a "
                                        "positioner"):
        posts.run(motoman_inform, plain, STATION)


# --- shared: values as drawn, refusals ----------------------------------------------------------

def test_targets_without_values_are_written_at_the_drawn_values():
    prog = program("fanuc_ls")
    for target in prog.targets():
        target.external = None
    records = fanuc_records(text_of("fanuc_ls", prog))
    assert values_of(records[4][1], ["J1", "J2"], "deg") == [0.0, 0.0]
    # the drawn pose is the frame's own: the seam point at phi = 90, torch on the bisector
    assert values_of(records[4][0], ["X", "Y", "Z"], "mm") == pytest.approx([0, 60, 0],
                                                                            abs=1e-3)


@pytest.mark.parametrize("post", ["fanuc_ls", "motoman_inform"])
def test_a_target_with_the_wrong_number_of_values_is_refused(post):
    prog = program(post)
    prog.paths[0].moves[3].target.external = np.array([1.0])
    with pytest.raises(PostError, match="Target 't4' holds 1 external axis values, the cell "
                                        "has 2"):
        posts.run(POSTS[post], prog, STATION if post == "motoman_inform" else {})


@pytest.mark.parametrize("track, named", [
    (False, "positioner 'Positioner' cannot be written"),
    (True, "track 'Track' and positioner 'Positioner' cannot be written")])
def test_ur_refuses_external_axes_naming_the_mechanism(track, named):
    prog = ef.positioner_weld_program(ROBOTS["ur_script"], track=track)
    with pytest.raises(PostError) as error:
        posts.run(ur_script, prog, {})
    message = str(error.value)
    assert message.startswith("URScript has no external axes: the cell's ")
    assert named in message and "\n" not in message


def test_a_split_program_keeps_the_external_axes_in_every_part():
    files = posts.run(fanuc_ls, program("fanuc_ls", track=True), {"max_positions": 10})
    assert len(files) == 3          # the main program and two parts: the weld's 9 in one
    for _, text in files:
        assert "DEFAULT_GROUP\t= 1,1,*,*,*;" in text
        records = fanuc_records(text.replace("\r\n", "\n"))
        assert all("E1=" in gp1 and "J2=" in gp2 for gp1, gp2 in records.values())
    assert sum(len(fanuc_records(t.replace("\r\n", "\n"))) for _, t in files) == 11
    jobs = posts.run(motoman_inform, program("motoman_inform", track=True),
                     dict(STATION, max_positions=16))
    counts = [int(re.search(r"///NPOS (\d+),", t).group(1)) for _, t in jobs]
    assert counts == [0, 1, 16, 1]
    for (_, text), n in zip(jobs, counts):
        assert f"///NPOS {n},{n},{n},0,0,0" in text
        assert "///GROUP1 RB1,BS1\r\n///GROUP2 ST1\r\n" in text
    assert "EC00000=-45000,225225" in jobs[-1][1]      # the retract, phi 360
