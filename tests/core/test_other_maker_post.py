"""A program written by another maker's post than its robot's says so in its header
(issue 20 item 9): every built-in post, and nothing when the makers agree."""

import numpy as np
import pytest

from CadRobotWB import posts
from CadRobotWB.core.generate import CellSpec, FrameSpec, PathSpec, generate
from CadRobotWB.core.geometry import Line
from CadRobotWB.core.program import ToolData
from CadRobotWB.posts import common

DOWN = np.diag([1.0, -1.0, -1.0])


def program_for(robot):
    path = PathSpec(name="Weld", label="Weld", segments=[Line((0, 0, 0), (50, 0, 0))],
                    R_u_t=[DOWN], frame="F")
    T_u_b = np.eye(4)
    T_u_b[:3, 3] = (800, 0, 300)
    cell = CellSpec(name="Cell", label="Cell", robot=robot, T_u_r=np.eye(4),
                    tool=ToolData(name="torch", T_f_t=np.eye(4)),
                    frames={"F": FrameSpec(name="F", label="F", T_u_b=T_u_b)}, paths=[path])
    return generate(cell)


def header_text(post, robot):
    """All the files' lines, without comment marks, joined by single spaces."""
    text = "\n".join(text for _, text in posts.get(post).export(program_for(robot), {}))
    lines = [line.strip().split(":", 1)[-1] if line[:5].strip().rstrip(":").isdigit() else line
             for line in text.splitlines()]               # Fanuc's numbered lines
    return " ".join(line.strip().lstrip("!;'# ").rstrip(" ;") for line in lines)


@pytest.mark.parametrize("post, controller", [
    ("kuka_krl", "KUKA KR C4"), ("fanuc_ls", "FANUC R-30iA/R-30iB"),
    ("motoman_inform", "Yaskawa Motoman NX100"), ("ur_script", "Universal Robots")])
def test_another_makers_post_says_whose_controller_it_is_for(post, controller):
    assert ("Written for a %s controller, but the cell's robot is an ABB IRB 2400/10 "
            "(ABB_IRB2400). Chosen explicitly: that robot's controller takes abb_rapid."
            % controller) in header_text(post, "ABB_IRB2400")


def test_rapid_for_a_kuka_arm_says_so_and_the_makers_own_post_says_nothing():
    assert ("Written for an ABB IRC5 controller, but the cell's robot is a KUKA KR 16 "
            "(KUKA_KR16)") in header_text("abb_rapid", "KUKA_KR16")
    assert "Written for" not in header_text("abb_rapid", "ABB_IRB2400")
    assert "Written for" not in header_text("kuka_krl", "KUKA_KR16")


def test_unknown_makers_say_nothing():
    assert common.other_maker_note("ABB_IRB2400", "my_post") == ""          # a user post
    assert common.other_maker_note("NO_SUCH_ROBOT", "kuka_krl") == ""
    assert common.post_maker("kuka_krl") == "KUKA"
    assert common.robot_maker("MOTOMAN_HP6") == "Yaskawa Motoman"
