"""What no post can write: each one refuses it with a PostError naming the problem.

One table for every built-in post; what only one language refuses (Fanuc's
1 cm/min, Motoman's circle without a start) stays in that post's tests.
"""

import re

import numpy as np
import pytest

from CadRobotWB.core import program as ir
from CadRobotWB.errors import PostError
from CadRobotWB import posts
from CadRobotWB.posts import abb_rapid, fanuc_ls, kuka_krl, motoman_inform, ur_script

from post_programs import minimal_program, pose

#: post module -> robot its minimal program is made for.
POSTS = {abb_rapid: "ABB_IRB2400", kuka_krl: "KUKA_KR16", ur_script: "UR5E",
         fanuc_ls: "MOTOMAN_HP6", motoman_inform: "MOTOMAN_HP6"}


def first_move(program):
    return program.paths[0].moves[0]


def set_pose_value(row, column, value):
    return lambda p: first_move(p).target.T_b_t.__setitem__((row, column), value)


BAD_MOVES = [
    ("spline", lambda p: setattr(first_move(p), "kind", "spline"), "spline"),
    ("circle without via", lambda p: setattr(first_move(p), "kind", ir.CIRCULAR), "via"),
    ("unknown frame", lambda p: setattr(first_move(p), "frame", "Nowhere"), "'Nowhere'"),
    ("zero speed", lambda p: setattr(first_move(p), "speed_mm_s", 0.0), "speed"),
    ("nan speed", lambda p: setattr(first_move(p), "speed_mm_s", float("nan")), "speed"),
    ("infinite speed", lambda p: setattr(first_move(p), "speed_mm_s", float("inf")), "speed"),
    ("negative zone", lambda p: setattr(first_move(p), "zone_mm", -1.0), "zone"),
    ("infinite zone", lambda p: setattr(first_move(p), "zone_mm", np.inf), "zone"),
    ("infinite x", set_pose_value(0, 3, np.inf), "finite"),
    ("nan y", set_pose_value(1, 3, np.nan), "finite"),
    ("nan rotation", set_pose_value(2, 2, np.nan), "finite"),
]


def add_other_target_named_t1(program):
    program.paths[0].moves.append(
        ir.Move(ir.LINEAR, ir.Target("t1", pose(position=(9, 9, 9))), 10, 0, "B"))


#: Only the posts that write the tool's load and declare targets by name.
BAD_DATA = [
    ("tool without mass", lambda p: setattr(p.tool, "mass_kg", 0.0), "mass"),
    ("two targets named t1", add_other_target_named_t1, "'t1'"),
]


@pytest.mark.parametrize("post", POSTS, ids=lambda m: m.NAME)
@pytest.mark.parametrize("case, change, match", BAD_MOVES, ids=[c[0] for c in BAD_MOVES])
def test_every_post_refuses_moves_it_cannot_write(post, case, change, match):
    program = minimal_program(POSTS[post])
    change(program)
    with pytest.raises(PostError, match=match):
        post.export(program, {})


@pytest.mark.parametrize("post", [abb_rapid, kuka_krl, ur_script], ids=lambda m: m.NAME)
@pytest.mark.parametrize("case, change, match", BAD_DATA, ids=[c[0] for c in BAD_DATA])
def test_posts_with_named_targets_and_tool_load_refuse_bad_data(post, case, change, match):
    program = minimal_program(POSTS[post])
    change(program)
    with pytest.raises(PostError, match=match):
        post.export(program, {})


def declared_options():
    """(post, option) for every option a built-in post declares in OPTIONS (but ``date``)."""
    return [(post, option) for post in POSTS for option in sorted(post.OPTIONS)
            if option != "date"]


@pytest.mark.parametrize("post", POSTS, ids=lambda m: m.NAME)
def test_every_built_in_post_declares_its_options(post):
    assert isinstance(post.OPTIONS, dict) and post.OPTIONS
    assert all(isinstance(text, str) and text for text in post.OPTIONS.values())


@pytest.mark.parametrize("post, option", declared_options(),
                         ids=["%s-%s" % (p.NAME, o) for p, o in declared_options()])
@pytest.mark.parametrize("value", [float("nan"), float("inf"), -float("inf")], ids=["nan", "inf", "-inf"])
def test_every_declared_option_refuses_non_finite_numbers_naming_itself(post, option, value):
    """No option of any post takes NaN or infinity: a number option wants a finite
    number, a switch true/false, a name text. The message names the option, as
    its key or in words ("program_name" or "Program name")."""
    named = re.compile("%s|%s" % (option, option.replace("_", " ")), re.IGNORECASE)
    with pytest.raises(PostError, match=named):
        posts.run(post, minimal_program(POSTS[post]), {option: value})


@pytest.mark.parametrize("post", POSTS, ids=lambda m: m.NAME)
def test_an_option_a_post_does_not_declare_is_refused_naming_it(post):
    with pytest.raises(PostError, match="path_corection"):
        posts.run(post, minimal_program(POSTS[post]), {"path_corection": True})
