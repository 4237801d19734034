"""Malformed URDFs: each is one CadRobotError naming the element and the attribute.

Every case is a small valid arm (the ABB IRB 2400's layout, with a box, a
cylinder, a mesh and a sphere as collision shapes) with one value changed the
way a broken or hostile file has it: NaN, inf, 1e308 or text where a number
belongs, the wrong count of numbers, a zero axis, a reversed or empty limit, a
speed that is not above 0, a scale or size below a micrometre, a missing
required attribute, a cycle, too many links.  Before issue 21 about half of
them ended in a ValueError, TypeError or OverflowError deep inside (the CLI's
"internal error", exit 3), or were accepted.
"""

import pytest

from CadRobotWB.errors import CadRobotError
from CadRobotWB.robots.urdf import from_urdf, urdf
from urdf_template import arm

J2 = "joint 'joint_2'"
LINK_1 = "link 'link_1' collision cylinder"
LINK_2 = "link 'link_2' collision mesh"
BASE = "link 'base_link' collision box"
CHAIN = "".join('<link name="extra_%d"/><joint name="extra_%d" type="fixed"><parent link="%s"/>'
                '<child link="extra_%d"/></joint>' % (i, i, "tool0" if i == 0 else "extra_%d" % (i - 1), i)
                for i in range(urdf.MAX_LINKS))

#: (case id, changed fields, words the one line must hold: the element, the attribute).
CASES = [
    ("xyz nan", dict(xyz="nan 0 0.615"), [J2, "origin xyz", "nan 0 0.615"]),
    ("xyz inf", dict(xyz="0.1 inf 0.615"), [J2, "origin xyz"]),
    ("xyz -inf", dict(xyz="0.1 0 -inf"), [J2, "origin xyz"]),
    ("xyz 1e308", dict(xyz="1e308 0 0.615"), [J2, "origin xyz", "100"]),
    ("xyz text", dict(xyz="0.1 zero 0.615"), [J2, "origin xyz", "zero"]),
    ("xyz two numbers", dict(xyz="1 2"), [J2, "origin xyz", "'1 2'", "3 finite numbers"]),
    ("xyz four numbers", dict(xyz="1 2 3 4"), [J2, "origin xyz"]),
    ("xyz empty", dict(xyz=""), [J2, "origin xyz"]),
    ("xyz comma", dict(xyz="0.1,0,0.615"), [J2, "origin xyz"]),
    ("rpy nan", dict(rpy="0 nan 0"), [J2, "origin rpy"]),
    ("rpy inf", dict(rpy="inf 0 0"), [J2, "origin rpy"]),
    ("rpy 1e308", dict(rpy="0 0 1e308"), [J2, "origin rpy"]),
    ("rpy text", dict(rpy="0 0 ninety"), [J2, "origin rpy"]),
    ("rpy one number", dict(rpy="1.57"), [J2, "origin rpy"]),
    ("axis nan", dict(axis="0 nan 0"), [J2, "axis xyz"]),
    ("axis inf", dict(axis="0 inf 0"), [J2, "axis xyz"]),
    ("axis 1e308", dict(axis="0 1e308 0"), [J2, "axis xyz"]),
    ("axis zero", dict(axis="0 0 0"), [J2, "zero axis"]),
    ("axis text", dict(axis="y"), [J2, "axis xyz"]),
    ("lower nan", dict(lower="nan"), [J2, "limit lower"]),
    ("upper inf", dict(upper="inf"), [J2, "limit upper"]),
    ("lower -inf", dict(lower="-inf"), [J2, "limit lower"]),
    ("upper 1e308", dict(upper="1e308"), [J2, "limit upper"]),
    ("lower text", dict(lower="-pi"), [J2, "limit lower", "-pi"]),
    ("limits reversed", dict(lower="2", upper="-2"), [J2, "limit lower", "not below upper"]),
    ("limits equal", dict(lower="1", upper="1"), [J2, "limit lower", "not below upper"]),
    ("velocity zero", dict(velocity='velocity="0"'), [J2, "limit velocity", "above 0"]),
    ("velocity negative", dict(velocity='velocity="-2"'), [J2, "limit velocity", "above 0"]),
    ("velocity nan", dict(velocity='velocity="nan"'), [J2, "limit velocity"]),
    ("velocity inf", dict(velocity='velocity="inf"'), [J2, "limit velocity"]),
    ("velocity 1e308", dict(velocity='velocity="1e308"'), [J2, "limit velocity"]),
    ("velocity text", dict(velocity='velocity="fast"'), [J2, "limit velocity", "fast"]),
    ("scale zero", dict(scale='scale="0 0 0"'), [LINK_2, "scale", "at least 1e-06"]),
    ("scale nan", dict(scale='scale="nan 1 1"'), [LINK_2, "scale"]),
    ("scale negative", dict(scale='scale="-0.001 0.001 0.001"'), [LINK_2, "scale", "at least 1e-06"]),
    ("scale text", dict(scale='scale="mm"'), [LINK_2, "scale"]),
    ("scale 1e308", dict(scale='scale="1e308 1 1"'), [LINK_2, "scale"]),
    ("mesh without filename", dict(filename=""), [LINK_2, "filename"]),
    ("box nan", dict(box='size="nan 0.2 0.1"'), [BASE, "size"]),
    ("box negative", dict(box='size="0.2 -0.2 0.1"'), [BASE, "size", "at least 1e-06 m"]),
    ("box two numbers", dict(box='size="0.2 0.2"'), [BASE, "size"]),
    ("box without size", dict(box=""), [BASE, "size"]),
    ("cylinder without radius", dict(radius=""), [LINK_1, "radius"]),
    ("cylinder without length", dict(length=""), [LINK_1, "length"]),
    ("cylinder radius nan", dict(radius='radius="nan"'), [LINK_1, "radius"]),
    ("cylinder length text", dict(length='length="long"'), [LINK_1, "length"]),
    ("cylinder radius zero", dict(radius='radius="0"'), [LINK_1, "radius", "at least 1e-06 m"]),
    ("sphere without radius", dict(sphere=""), ["link 'link_3' collision sphere", "radius"]),
    ("collision origin inf", dict(collision_xyz="0 0 inf"), ["link 'link_1' collision", "origin xyz"]),
    ("robot without name", dict(robot_name=""), ["<robot>", "name"]),
    ("robot with empty name", dict(robot_name='name=""'), ["<robot>", "name"]),
    ("robot with blank name", dict(robot_name='name="  "'), ["<robot>", "name"]),
    ("link without name", dict(link_4=""), ["<link>", "name"]),
    ("joint without name", dict(joint_4_name=""), ["<joint>", "name"]),
    ("joint without type", dict(joint_2_type=""), [J2, "type"]),
    ("joint of unknown type", dict(joint_2_type='type="hinge"'), [J2, "type", "hinge"]),
    ("child without link", dict(joint_2_child=""), [J2, "child", "link"]),
    ("mimic multiplier nan", dict(mimic='<mimic joint="joint_2" multiplier="nan"/>'),
     ["joint 'joint_3' mimic", "multiplier"]),
    ("mimic without joint", dict(mimic='<mimic multiplier="1"/>'), ["joint 'joint_3' mimic", "joint"]),
    ("two links of one name", dict(extra='<link name="link_5"/>'), ["two links", "link_5"]),
    ("two joints of one name", dict(joint_4_name='name="joint_5"'), ["two joints", "joint_5"]),
    ("a cycle off the root", dict(extra=(
        '<link name="a"/><link name="b"/>'
        '<joint name="ab" type="fixed"><parent link="a"/><child link="b"/></joint>'
        '<joint name="ba" type="fixed"><parent link="b"/><child link="a"/></joint>')),
     ["a, b", "not reached from the root link 'base_link'", "cycle"]),
    ("too many links", dict(extra=CHAIN), ["%d links" % (urdf.MAX_LINKS + 8), "%d" % urdf.MAX_LINKS]),
]


def test_the_template_is_a_valid_arm():
    """The cases fail because of their one change, not because the template is wrong."""
    robot = urdf.read_urdf(arm())
    imported = from_urdf.spec_from_urdf("safe_arm.urdf", "SAFE_ARM", robot=robot, samples=50)
    assert imported.spec.opw is not None
    assert imported.spec.joint_max_deg[1] == 143.24   # 2.5 rad
    assert imported.spec.joint_speed_deg_s[1] == 143.24


@pytest.mark.parametrize("changes, words", [case[1:] for case in CASES],
                         ids=[case[0] for case in CASES])
def test_a_malformed_value_is_one_line_naming_the_element_and_the_attribute(changes, words):
    with pytest.raises(CadRobotError) as error:
        urdf.serial_chain(urdf.read_urdf(arm(**changes)))
    message = str(error.value)
    assert "\n" not in message
    for word in words:
        assert word in message, (word, message)


def test_a_file_past_the_size_bound_is_refused_before_it_is_parsed(tmp_path):
    path = tmp_path / "huge.urdf"
    path.write_bytes(arm().encode() + b" " * urdf.MAX_FILE_BYTES)
    with pytest.raises(CadRobotError, match="'%s' is larger than 10 MB" % path):
        urdf.read_urdf(str(path))


def test_the_robot_keeps_its_own_name():
    assert urdf.read_urdf(arm()).name == "safe_arm"
