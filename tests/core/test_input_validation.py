"""Numbers and transforms checked where they are parsed (no FreeCAD needed).

objects/validate.py: finite, in range, rigid; cli.py: every number option
refuses NaN, infinities and out-of-range values at parse time.
"""

import math

import numpy as np
import pytest

from CadRobotWB import cli, limits
from CadRobotWB.errors import FrameError, InputError
from CadRobotWB.objects import validate


def rotation_about_z(deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    T = np.eye(4)
    T[:2, :2] = [[c, -s], [s, c]]
    T[:3, 3] = (1.0, -2.0, 3.0)
    return T


@pytest.mark.parametrize("deg", [0.0, 30.0, 179.999, -90.0])
def test_rotations_are_rigid(deg):
    assert validate.rigid_problem(rotation_about_z(deg)) is None


def test_round_off_of_many_products_is_still_rigid():
    T = np.eye(4)
    for _ in range(1000):
        T = T @ rotation_about_z(0.36)     # 1000 x 0.36 deg = one full turn
    assert validate.rigid_problem(T) is None
    assert np.allclose(T[:3, :3], np.eye(3), atol=1e-9)


@pytest.mark.parametrize("change, phrase", [
    (lambda T: T.__setitem__((slice(0, 3), slice(0, 3)), 0.0), "zero column"),
    (lambda T: T.__setitem__((slice(0, 3), 0), T[:3, 0] * 1.001), "column lengths 1.001, 1, 1"),
    (lambda T: T.__setitem__((slice(0, 3), 2), -T[:3, 2]), "mirror (determinant -1)"),
    (lambda T: T.__setitem__((0, 3), np.inf), "NaN or infinite"),
    (lambda T: T.__setitem__((1, 1), np.nan), "NaN or infinite"),
    (lambda T: T.__setitem__((3, 0), 0.5), "last row is 0.5 0 0 1"),
])
def test_what_keeps_a_matrix_from_being_rigid_is_said(change, phrase):
    T = rotation_about_z(30.0)
    change(T)
    assert phrase in validate.rigid_problem(T)


def test_shear_with_unit_columns():
    T = np.eye(4)
    T[:3, 1] = (math.sqrt(0.5), math.sqrt(0.5), 0.0)   # unit length, 45 deg from X
    assert validate.rigid_problem(T) == "its rotation block shears (columns not perpendicular)"


def test_check_rigid_names_the_object_and_raises_the_error_asked():
    T = np.diag([1.0, 1.0, -1.0, 1.0])
    with pytest.raises(FrameError) as caught:
        validate.check_rigid(T, "Calibration frame 'B'", FrameError, "Frame001")
    assert str(caught.value).startswith("Calibration frame 'B': the placement is not a rigid transform: ")
    assert caught.value.obj_name == "Frame001"


@pytest.mark.parametrize("value, low, high, low_open, ok", [
    ("5", 0, math.inf, True, 5.0), (0.0, 0, math.inf, True, None), (0.0, 0, math.inf, False, 0.0),
    ("nan", -math.inf, math.inf, False, None), ("-inf", -math.inf, math.inf, False, None),
    ("1e999", -math.inf, math.inf, False, None), ("x", 0, 1, False, None), (100.0, 0, 100, True, 100.0),
    (100.0001, 0, 100, True, None),
])
def test_number_in_range(value, low, high, low_open, ok):
    if ok is None:
        with pytest.raises(InputError, match="^--rate must be a"):
            validate.number_in_range(value, "--rate", low, high, low_open)
    else:
        assert validate.number_in_range(value, "--rate", low, high, low_open) == ok


def test_finite_values_says_which_value():
    with pytest.raises(InputError, match=r"^Cell 'C' StartJoints is not finite: nan \(value 2 of 6\)"):
        validate.finite_values([0, np.nan, 0, 0, np.inf, 0], "Cell 'C' StartJoints")


@pytest.mark.parametrize("value", [-1, 1.5, True, "3", np.nan, np.inf, None, [1]])
def test_whole_in_range_refuses_what_is_not_a_whole_number_in_range(value):
    with pytest.raises(InputError, match="whole number >= 0"):
        validate.whole_in_range(value, "seed", 0)


@pytest.mark.parametrize("value", [7, np.int64(7), 7.0, np.float64(7.0)])
def test_whole_in_range_takes_whole_numbers_of_any_type(value):
    assert type(validate.whole_in_range(value, "seed", 0)) is int


def parse(*argv):
    return cli.build_parser().parse_args(cli._join_negative_values(list(argv)))


@pytest.mark.parametrize("argv, words", [
    (["simulate", "d", "--sensor", "laser", "--rate", "0"], ["argument --rate", ">= 0.1", "'0'"]),
    (["simulate", "d", "--sensor", "laser", "--rate", "nan"], ["argument --rate"]),
    (["simulate", "d", "--sensor", "laser", "--seed", "-1"], ["argument --seed", ">= 0"]),
    (["simulate", "d", "--sensor", "laser", "--deviation=1,2,nan,0,0,0"], ["6 finite numbers"]),
    (["sweep", "d", "--sensor", "laser", "--ranges", "x=0:1", "--workers", "0"],
     [">= 1 and <= %d" % limits.cores()]),
    (["sweep", "d", "--sensor", "laser", "--ranges", "x=0:1", "--tolerance", "inf"], ["--tolerance"]),
    (["sweep", "d", "--sensor", "laser", "--ranges", "x=0:1", "--runs", "0"], ["--runs", ">= 1"]),
    (["place", "d", "--region", "0,0,1e999,1"], ["4 finite numbers"]),
    (["place", "d", "--region", "0,0,1,1", "--margin", "-1"], ["--margin", ">= 0 and <= 180"]),
    (["place", "d", "--region", "0,0,1,1", "--count", "0"], ["--count"]),
    (["place", "d", "--region", "0,0,1,1", "--step", "0"], ["--step", "> 0"]),
])
def test_number_options_are_checked_where_they_are_parsed(argv, words):
    with pytest.raises(InputError) as caught:
        parse(*argv)
    for word in words:
        assert word in str(caught.value)


def test_valid_numbers_are_parsed_as_numbers():
    args = parse("simulate", "d", "--sensor", "laser", "--rate", "2.5", "--seed", "4",
                 "--deviation", "-1,0,0.5,0,0,1")
    assert (args.rate, args.seed, args.deviation) == (2.5, 4, [-1.0, 0.0, 0.5, 0.0, 0.0, 1.0])


@pytest.mark.parametrize("text, value", [
    ("path_correction=true", True), ("n=3", 3), ("r=0.25", 0.25), ("w=maybe", "maybe"),
    ("x=nan", "nan"), ("y=inf", "inf"), ("z=1e999", "1e999"),
])
def test_post_options_keep_non_finite_numbers_as_text_for_the_post_to_refuse(text, value):
    key, parsed = cli.parse_post_option(text)
    assert (key, parsed) == (text.split("=")[0], value) and type(parsed) is type(value)


def test_json_output_has_no_nan_tokens():
    text = cli._to_json({"a": float("nan"), "b": [np.float64(np.inf), 1.5], "c": np.array([1.0, np.nan])})
    assert text.replace(" ", "").replace("\n", "") == '{"a":null,"b":[null,1.5],"c":[1.0,null]}'


def test_cells_writing_the_same_file_are_refused():
    with pytest.raises(InputError, match="Cells 'A' and 'B' both write 'W.mod'"):
        cli._refuse_shared_names([{"cell": "A", "files": ["W.mod"]}, {"cell": "B", "files": ["W.mod"]}])
    cli._refuse_shared_names([{"cell": "A", "files": ["A.mod"]}, {"cell": "B", "files": ["B.mod"]}])
