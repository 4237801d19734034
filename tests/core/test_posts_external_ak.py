"""External axes in the ABB RAPID and KUKA KRL posts (issue 23).

The pipe-to-flange weld all round of ``external_fixtures`` (a tilt-and-turn
positioner; with ``track=True`` the robot on a track too) is written by both
posts. The goldens are read back as the welder and the controller would: the
arc strikes at the seam start with the positioner where the seam is flat, the
external values are the ones computed by hand below and run continuously, and
the work frame on the positioner is coordinated with it (ABB: a wobjdata moved
by its mechanical unit; KUKA: a base coupled with EK).

To rewrite the golden files after a reviewed change of the output:
``CADROBOT_UPDATE_GOLDEN=1 python3 -m pytest tests/core/test_posts_external_ak.py``.
"""

import copy
import re

import numpy as np
import pytest

import external_fixtures as ef
from CadRobotWB import posts
from CadRobotWB.core import program as ir
from CadRobotWB.errors import PostError
from CadRobotWB.posts import abb_rapid, kuka_krl
from post_programs import pose

from rapid_check import arc_record_problems, assert_rapid_ok, needs_rapidchecker
from test_posts_weld_postsak import _golden   # the goldens of issue 22's weld programs

ABB, KUKA = "ABB_IRB2400", "KUKA_KR16"

#: Seam angle (deg) of each target along the weld, by name: approach and entry at the
#: seam start, vias at 45, 135, ..., targets at 90, ..., 360, the retract at the end.
PHI_DEG = {"t1": 0, "t2": 0, "v3": 45, "t3": 90, "v4": 135, "t4": 180, "v5": 225, "t5": 270,
           "v6": 315, "t6": 360, "t7": 360}


def by_hand(name, track):
    """The external values of a target, by hand: tilt -45 and turn -90 - phi keep the
    seam flat (the fixture's module docstring); the track runs 0 -> 300 mm."""
    phi = PHI_DEG[name]
    values = [-45.0, -90.0 - phi]
    return [300.0 * phi / 360.0] + values if track else values


@pytest.fixture(scope="module")
def solved():
    """The four solved programs (robot, track) -> Program, built once."""
    return {(robot, track): ef.positioner_weld_program(robot, track=track, solve=True)
            for robot in (ABB, KUKA) for track in (False, True)}


def rapid(program, options=None):
    (_, text), = posts.run(abb_rapid, program, options or {})
    return text


def krl(program, options=None):
    """(src, dat) with LF line ends."""
    files = posts.run(kuka_krl, program, options or {})
    assert [name for name, _ in files] == [program.name + ".src", program.name + ".dat"]
    return [text.replace("\r\n", "\n") for _, text in files]


def numbers(text):
    return [float(v) for v in re.findall(r"-?\d+(?:\.\d+)?(?:E[+-]?\d+)?", text)]


def abb_extax(text, kind, name):
    """The six extax numbers of a robtarget / jointtarget (target v5 is ``v5_2`` in
    RAPID: ``v5`` is ABB's predefined speed)."""
    name = {"v5": "v5_2"}.get(name, name)
    literal = re.search(rf"LOCAL CONST {kind} {name} := (\[.*\]);", text).group(1)
    return numbers(literal.rsplit("[", 1)[1])


def main_lines(text):
    body = text.split("PROC main()")[1].split("ENDPROC")[0]
    return [line.strip() for line in body.splitlines() if line.strip()]


def krl_e_values(dat, kind, name):
    """E1..E6 of a point in the data list."""
    literal = re.search(rf"DECL {kind} {name}=\{{(.*)\}}", dat).group(1)
    return [float(v) for v in re.findall(r"E\d (-?[\d.]+)", literal)]


def offset_frame_program(robot, track=False):
    """The fixture with its work frame 100 mm along X_U from the table centre and
    turned 90 degrees about Z: in the positioner's flange (at (1200, 0, 800), axes
    those of {U} at tilt = turn = 0) it is [[100, 0, 0], q = (cos 45, 0, 0, sin 45)]."""
    program = ef.positioner_weld_program(robot, track=track)
    T_u_b = pose((0, 0, 90), (1300.0, 0.0, 800.0))
    program.frames["B"] = ir.WorkFrame("B", T_u_b.copy(), T_u_b, "CalibrationFrame")
    return program


# --- ABB RAPID -------------------------------------------------------------------------

@pytest.mark.parametrize("track, golden", [(False, "ext_abb_rapid_positioner.mod"),
                                           (True, "ext_abb_rapid_track.mod")])
def test_abb_golden_and_values_by_hand(solved, track, golden):
    program = solved[(ABB, track)]
    text = rapid(program)
    _golden(golden, text)
    assert arc_record_problems(text) == ([], 2)
    unused = [9e9] * (6 - len(by_hand("t2", track)))
    for name in PHI_DEG:
        kind = "jointtarget" if name == "t1" else "robtarget"
        assert abb_extax(text, kind, name) == by_hand(name, track) + unused, name
    # the arc strikes at the seam start (phi = 0, at (60, 0, 0) on the pipe) with the
    # seam flat, and every move of the seam is in the coordinated work object
    assert re.search(r"robtarget t2 := \[\[60\.000,0\.000,0\.000\]", text)
    assert 'LOCAL PERS wobjdata B := [FALSE,FALSE,"STN1",[[0,0,0],[1,0,0,0]],' in text
    body = text.split("PROC Seam()")[1]
    assert body.count("\\WObj:=B;") == 7 and "ArcLStart t2," in body


def test_abb_main_activates_the_units_around_the_moves(solved):
    assert main_lines(rapid(solved[(ABB, False)])) == [
        "ConfJ \\On;", "ConfL \\On;", "ActUnit STN1;", "Seam;", "DeactUnit STN1;"]
    assert main_lines(rapid(solved[(ABB, True)], {"track_unit": "T7", "positioner_unit": "P2"}))[
        2:] == ["ActUnit T7;", "ActUnit P2;", "Seam;", "DeactUnit T7;", "DeactUnit P2;"]


def test_abb_coordinated_work_object_is_the_frame_in_the_flange():
    text = rapid(offset_frame_program(ABB), {"positioner_unit": "STN_2"})
    wobj = re.search(r"LOCAL PERS wobjdata B := (.*);", text).group(1)
    c = np.cos(np.radians(45.0))
    assert wobj.startswith('[FALSE,FALSE,"STN_2",[[0,0,0],[1,0,0,0]],')
    np.testing.assert_allclose(numbers(wobj.split("]],", 1)[1]), [100, 0, 0, c, 0, 0, c],
                               atol=1e-6)
    # the unit's calibration in the header: its base in the world (the robot base)
    assert "[[1200.000,0.000,0.000],[1.000000,0.000000,0.000000,0.000000]]" in text


def test_abb_fixed_frame_with_a_track_is_in_the_world_at_track_0():
    """A fixed frame at (900, 0, 400) in {U}, the track drawn at 100 mm (the robot
    base there): the world is the robot base at travel 0, (0, 0, 0) in {U}, so the
    uframe is (900, 0, 400), not (800, 0, 400) from the drawn base."""
    program = ef.positioner_weld_program(ABB, track=True)
    external = program.external
    external.track.drawn_at = np.array([100.0])
    external.T_u_r = pose((0, 0, 0), (100.0, 0.0, 0.0))
    T_u_f = pose((0, 0, 0), (900.0, 0.0, 400.0))
    program.frames["F"] = ir.WorkFrame("F", np.linalg.inv(external.T_u_r) @ T_u_f, T_u_f, "Fix")
    wobj = re.search(r"LOCAL PERS wobjdata F := (.*);", rapid(program)).group(1)
    assert wobj == ('[FALSE,TRUE,"",[[900.000,0.000,400.000],'
                    '[1.000000,0.000000,0.000000,0.000000]],[[0,0,0],[1,0,0,0]]]')


@needs_rapidchecker
def test_rapidchecker_accepts_the_external_axes_modules(solved):
    """One module (about 1 s): extax, a coordinated wobjdata, ActUnit and DeactUnit."""
    assert_rapid_ok(rapid(solved[(ABB, True)]))


def test_abb_split_main_activates_units_before_the_parts(solved):
    program = solved[(ABB, False)]
    files = posts.run(abb_rapid, program, {"max_lines": 60})
    main = main_lines(files[0][1])
    assert main[2] == "ActUnit STN1;" and main[-1] == "DeactUnit STN1;"
    assert all(line.endswith("_run;") for line in main[3:-1]) and len(main) == len(files) + 3
    loading = main_lines(posts.run(abb_rapid, program, {"max_lines": 60,
                                                        "part_folder": "HOME:/P"})[0][1])
    assert loading[2] == "ActUnit STN1;" and loading[-1] == "DeactUnit STN1;"
    assert loading[-2].startswith("UnLoad ")


@pytest.mark.parametrize("options, word", [
    ({"positioner_unit": "1STN"}, "positioner_unit"),
    ({"positioner_unit": 3}, "positioner_unit"),
    ({"track_unit": "MODULE"}, "track_unit"),
    ({"positioner_unit": "main"}, "positioner_unit main is a name"),
    ({"track_unit": "STN1"}, "positioner_unit STN1 is a name"),
])
def test_abb_bad_unit_names_are_refused_in_one_line(options, word):
    program = ef.positioner_weld_program(ABB, track=True)
    with pytest.raises(PostError, match=word) as error:
        rapid(program, options)
    assert "\n" not in str(error.value)


# --- KUKA KRL --------------------------------------------------------------------------

@pytest.mark.parametrize("track, golden", [(False, "ext_kuka_krl_positioner"),
                                           (True, "ext_kuka_krl_track")])
def test_kuka_golden_and_values_by_hand(solved, track, golden):
    program = solved[(KUKA, track)]
    files = posts.run(kuka_krl, program, {})
    for (_, text), extension in zip(files, (".src", ".dat")):
        _golden(golden + extension, text)
    src, dat = (text.replace("\r\n", "\n") for _, text in files)
    zeros = [0.0] * (6 - len(by_hand("t2", track)))
    for name in PHI_DEG:
        kind, point = (("E6AXIS", name) if name == "t1" else
                       ("E6POS", name if name == "t7" else "X" + name))
        assert krl_e_values(dat, kind, point) == by_hand(name, track) + zeros, name
    count = 3 if track else 2
    setup = src.split("; Setup")[1].split("PTP $AXIS_ACT")[0]
    assert f"$ACT_EX_AX = {count}\n" in setup and f"$VEL_EXTAX[{count}] = 20" in setup
    ek = "$BASE = EK(MACHINE_DEF[2].ROOT, MACHINE_DEF[2].MECH_TYPE, BASE_DATA[1])"
    seam = src.split("DEF Seam( )")[1]
    assert seam.index(ek) < seam.index("PTP t1") < seam.index("LIN Xt2")


def test_kuka_machine_data_comments_by_hand(solved):
    src, _ = krl(solved[(KUKA, True)])
    # the positioner: base at (1200, 0, 0); tilt about the base's X at 800 mm
    # (its joint frame turned +90 about Y), turn about the table's normal (-90 back)
    for line in ("$ET2: Positioner, root (base in the world) {X 1200.0000,Y 0.0000,"
                 "Z 0.0000,A 0.00000,B 0.00000,C 0.00000}",
                 "$ET2_AX = {TR_A1 #E2,TR_A2 #E3,TR_A3 #NONE}",
                 "$ET2_TA1KR = {X 0.0000,Y 0.0000,Z 800.0000,A 0.00000,B 90.00000,C 0.00000} "
                 "(tilt, deg)",
                 "$ET2_TA2A1 = {X 0.0000,Y 0.0000,Z 0.0000,A 0.00000,B -90.00000,C 0.00000} "
                 "(turn, deg)",
                 "$ET2_TFLA3 = {X 0.0000,Y 0.0000,Z 0.0000,A 0.00000,B 0.00000,C 0.00000}",
                 # the track: base 250 mm below the robot base, travel along X_U
                 "$ET1: Track, root (base in the world) {X 0.0000,Y 0.0000,Z -250.0000,"
                 "A 0.00000,B 0.00000,C 0.00000}",
                 "$ET1_AX = {TR_A1 #E1,TR_A2 #NONE,TR_A3 #NONE}",
                 "$EX_KIN = {ET1 #ERSYS,ET2 #EASYS,ET3 #NONE,ET4 #NONE,ET5 #NONE,ET6 #NONE}"):
        assert "; " + line + "\n" in src, line


def test_kuka_coupled_frame_is_the_frame_in_the_flange():
    program = offset_frame_program(KUKA)
    program.paths[0].welds = []
    for move in program.paths[0].moves:
        move.weld = None
    src, dat = krl(program, {"positioner_machine": 3})
    assert "DECL FRAME B={X 100.0000,Y 0.0000,Z 0.0000,A 90.00000,B 0.00000,C 0.00000}" in dat
    assert "$BASE = EK(MACHINE_DEF[3].ROOT, MACHINE_DEF[3].MECH_TYPE, B)" in src
    assert "$BASE = B\n" not in src


@pytest.mark.parametrize("value", [1, 17, "two", 2.5])
def test_kuka_bad_positioner_machine_is_refused(value):
    with pytest.raises(PostError, match="positioner_machine") as error:
        krl(ef.positioner_weld_program(KUKA), {"positioner_machine": value})
    assert "\n" not in str(error.value)


# --- both -------------------------------------------------------------------------------

@pytest.mark.parametrize("export", [rapid, krl])
@pytest.mark.parametrize("values, shown", [([1.0], "[1.0]"), ([np.nan, 0.0], "[nan, 0.0]")])
def test_bad_external_values_are_refused_naming_the_target(export, values, shown):
    program = ef.positioner_weld_program(ABB)
    program.targets()[3].external = np.array(values)
    with pytest.raises(PostError, match=re.escape(f"Target 't3' has external-axis values "
                                                  f"{shown} that are not 2 finite")):
        export(program)


def test_a_target_without_values_takes_the_drawn_ones_and_the_input_is_unchanged():
    program = ef.positioner_weld_program(ABB)
    program.external.positioner.drawn_at = np.array([-30.0, 10.0])
    program.targets()[0].external = None
    before = copy.deepcopy(program)
    text = rapid(program)
    src, dat = krl(program)
    assert abb_extax(text, "robtarget", "t1") == [-30.0, 10.0] + [9e9] * 4
    assert krl_e_values(dat, "E6POS", "t1") == [-30.0, 10.0, 0, 0, 0, 0]
    assert [t.external is None for t in program.targets()] == [
        t.external is None for t in before.targets()]
    for target, old in zip(program.targets()[1:], before.targets()[1:]):
        np.testing.assert_array_equal(target.external, old.external)


def test_the_positioner_calibration_is_in_the_world_frame():
    """The robot base at (0, 500, 0) in {U}: the positioner's base (1200, 0, 0) in {U}
    is (1200, -500, 0) in the world (the robot base), in both posts' headers."""
    program = ef.positioner_weld_program(ABB)
    program.external.T_u_r = pose((0, 0, 0), (0.0, 500.0, 0.0))
    assert "[[1200.000,-500.000,0.000],[1.000000,0.000000,0.000000,0.000000]]" in rapid(program)
    src, _ = krl(program)
    assert ("; $ET1: Positioner, root (base in the world) {X 1200.0000,Y -500.0000,Z 0.0000,"
            "A 0.00000,B 0.00000,C 0.00000}\n") in src


@pytest.mark.parametrize("export", [rapid, krl])
def test_more_external_axes_than_the_language_carries_are_refused(export):
    """A positioner of 7 axes: RAPID's extjoint and KRL's E1..E6 hold 6."""
    program = ef.positioner_weld_program(ABB)
    positioner = program.external.positioner
    positioner.axes = positioner.axes[1:] * 7
    positioner.drawn_at = np.zeros(7)
    for target in program.targets():
        target.external = np.zeros(7)
    with pytest.raises(PostError, match=r"carries at most 6 external axes and the cell's "
                                        r"mechanisms have 7: remove a mechanism"):
        export(program)
