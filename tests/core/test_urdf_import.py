"""Reading URDF arms (robots/urdf/urdf.py) and recognising their kinematics (robots/urdf/identify.py).

The reference numbers are hand-derived: a URDF is written here from the ABB
IRB 2400/10's published OPW parameters (REFERENCE.md: a1 100, a2 -135, b 0,
c1 615, c2 705, c3 755, c4 85 mm, offsets 0, 0, -90, 0, 0, 0 deg) in
ROS-Industrial's layout, then changed the ways real files differ (a moved and
turned root, reversed axes, a lateral offset, a turned tool0), and the
extracted model must give back those numbers and the file's own flange.
"""

import os

import numpy as np
import pytest

from CadRobotWB.errors import InputError
from CadRobotWB.robots.kinematics import models
from CadRobotWB.robots.urdf import from_urdf, identify, urdf
from required import ROBOT_DATA as DATA


def joint(name, parent, child, xyz="0 0 0", rpy="0 0 0", axis="0 0 1", kind="revolute",
          extra=""):
    limit = '<limit lower="-3" upper="3" velocity="2.5" effort="0"/>' if kind != "fixed" else ""
    return ('<joint name="%s" type="%s"><parent link="%s"/><child link="%s"/>'
            '<origin xyz="%s" rpy="%s"/><axis xyz="%s"/>%s%s</joint>'
            % (name, kind, parent, child, xyz, rpy, axis, limit, extra))


def irb2400_urdf(axis2="0 1 0", b=0.0, joint5_y=0.0, root=None, tool_rpy="0 1.5707963267948966 0",
                 extra_joint=False, mimic=False, rpy1="0 0 0", rpy2="0 0 0", rpy3="0 0 0"):
    """ROS-Industrial's irb2400 layout (metres), with the changes asked for."""
    links = ["base_link", "link_1", "link_2", "link_3", "link_4", "link_5", "link_6", "tool0"]
    joints = [
        joint("joint_1", "base_link", "link_1", rpy=rpy1),
        joint("joint_2", "link_1", "link_2", "0.1 0 0.615", rpy=rpy2, axis=axis2),
        joint("joint_3", "link_2", "link_3", "0 0 0.705", rpy=rpy3, axis="0 1 0"),
        joint("joint_4", "link_3", "link_4", "0.258 %r 0.135" % b, axis="1 0 0"),
        joint("joint_5", "link_4", "link_5", "0.497 %r 0" % joint5_y, axis="0 1 0",
              extra='<mimic joint="joint_4"/>' if mimic else ""),
        joint("joint_6", "link_5", "link_6", "0.085 0 0", axis="1 0 0"),
        joint("joint_6-tool0", "link_6", "tool0", rpy=tool_rpy, kind="fixed"),
    ]
    if extra_joint:
        links.append("link_7")
        joints[-1] = joint("joint_7", "link_6", "link_7", axis="1 0 0")
        joints.append(joint("link_7-tool0", "link_7", "tool0", kind="fixed"))
    if root is not None:
        links.append("world")
        joints.append(joint("world-base", "world", "base_link", *root, kind="fixed"))
    return ('<robot name="test_arm">%s%s</robot>'
            % ("".join('<link name="%s"/>' % n for n in links), "".join(joints)))


def chain_of(text):
    return urdf.serial_chain(urdf.read_urdf(text))


def test_urdf_origin_is_translation_then_yaw_pitch_roll():
    """R = Rz(yaw) Ry(pitch) Rx(roll): rpy (90, 0, 90 deg) maps x to z... by hand."""
    T = urdf.transform_from_xyz_rpy([1.0, 2.0, 3.0], [np.pi / 2, 0.0, np.pi / 2])
    # Rx(90): y -> z, z -> -y; then Rz(90): x -> y, y -> -x.
    np.testing.assert_allclose(T[:3, :3] @ [1, 0, 0], [0, 1, 0], atol=1e-15)
    np.testing.assert_allclose(T[:3, :3] @ [0, 1, 0], [0, 0, 1], atol=1e-15)
    np.testing.assert_allclose(T[:3, :3] @ [0, 0, 1], [1, 0, 0], atol=1e-15)
    np.testing.assert_allclose(T[:3, 3], [1, 2, 3])


def test_chain_flange_at_zero_is_the_irb2400_reference_flange():
    """REFERENCE.md: flange at (940, 0, 1455) mm, its Z along base +X, at q = 0."""
    T = urdf.chain_fk(chain_of(irb2400_urdf()), np.zeros((1, 6)))[0]
    np.testing.assert_allclose(T[:3, 3], [940.0, 0.0, 1455.0], atol=1e-9)
    np.testing.assert_allclose(T[:3, 2], [1.0, 0.0, 0.0], atol=1e-12)


def test_opw_parameters_of_the_irb2400_layout_are_the_published_ones():
    found = identify.identify(chain_of(irb2400_urdf()))
    p = found.params
    assert found.kind == "opw"
    assert (p.a1, p.a2, p.b, p.c1, p.c2, p.c3, p.c4) == (100.0, -135.0, 0.0, 615.0, 705.0, 755.0, 85.0)
    assert p.offsets_deg == (0.0, 0.0, -90.0, 0.0, 0.0, 0.0)
    assert p.signs == (1, 1, 1, 1, 1, 1)
    np.testing.assert_allclose(found.T_root_base, np.eye(4), atol=1e-12)


def test_ros_industrial_irb2400_gives_the_published_parameters_and_the_catalog_model():
    chain = urdf.serial_chain(urdf.read_urdf(os.path.join(DATA, "abb_irb2400", "robot.urdf")))
    found = identify.identify(chain)
    p = found.params
    assert (p.a1, p.a2, p.b, p.c1, p.c2, p.c3, p.c4) == (100.0, -135.0, 0.0, 615.0, 705.0, 755.0, 85.0)
    q = np.random.default_rng(1).uniform(-90, 90, (200, 6))
    # The catalog's hand-written IRB 2400 is the same arm: same flange position;
    # the frames differ by tool0's turn about the flange's Y (OPW flange Z = tool0 Z).
    np.testing.assert_allclose(found.fk(q)[:, :3, 3], models.model("ABB_IRB2400").fk(q)[:, :3, 3],
                               atol=1e-9)


def test_ur5e_gives_universal_robots_published_dh_lengths():
    """UR's published UR5e table: d1 162.5, a2 -425, a3 -392.2, d4 133.3, d5 99.7, d6 99.6 mm."""
    chain = urdf.serial_chain(urdf.read_urdf(os.path.join(DATA, "ur5e", "robot.urdf")))
    found = identify.identify(chain)
    p = found.params
    assert found.kind == "ur"
    np.testing.assert_allclose([p.d1, p.a2, p.a3, p.d4, p.d5, p.d6],
                               [162.5, -425.0, -392.2, 133.3, 99.7, 99.6], atol=1e-6)
    assert p.offsets_deg == (0.0,) * 6 and p.signs == (1,) * 6


@pytest.mark.parametrize("variant", [
    dict(axis2="0 -1 0"),
    dict(b=0.02),
    dict(root=("1 2 0.5", "0.1 -0.2 0.3")),
    dict(tool_rpy="0.3 -1.2 2.0"),
    dict(rpy1="0 0 0.7", axis2="0 -1 0", b=-0.015, root=("0 0 -0.4", "3.14159 0 0")),
])
def test_model_equals_the_chain_whatever_the_frame_conventions(variant):
    """The flange of the model equals the file's on random joint sets, in the file's joints."""
    chain = chain_of(irb2400_urdf(**variant))
    found = identify.identify(chain)
    worst_mm, worst_rad = identify.verify(found, chain, samples=2000, seed=3)
    assert worst_mm < 1e-9 and worst_rad < 1e-12
    assert found.params.c2 == 705.0 and found.params.c4 == 85.0
    if "b" in variant and "root" not in variant:
        assert found.params.b == pytest.approx(variant["b"] * 1000.0, abs=1e-9)
    if variant.get("axis2") == "0 -1 0":
        assert found.params.signs[1] == -1


def test_inverse_returns_the_joints_that_made_the_pose():
    chain = chain_of(irb2400_urdf(axis2="0 -1 0", b=0.02, root=("1 2 0.5", "0.1 -0.2 0.3"),
                                  tool_rpy="0.3 -1.2 2.0"))
    found = identify.identify(chain)
    q = identify.random_joints(chain, 300, seed=4)
    solutions = found.ik(urdf.chain_fk(chain, q))
    difference = np.abs((solutions - np.degrees(q)[:, None] + 180.0) % 360.0 - 180.0).max(axis=2)
    assert (np.nanmin(difference, axis=1) < 1e-7).all()


@pytest.mark.parametrize("change, message", [
    (dict(joint5_y=0.05), r"axes 4, 5 and 6 do not meet in a point \(50 mm apart\): not a spherical wrist"),
    (dict(rpy2="0.01 0 0"), r"axes 1 and 2 are not perpendicular \(0.572958 deg from it\)"),
    # 1.5708 written for pi/2 is 3.67e-6 rad off.
    (dict(rpy2="%r 0 0" % (1.5708 - np.pi / 2)), r"0.00021\d* deg from it, most likely an angle "
                                                 r"rounded in the file"),
])
def test_other_kinematics_are_refused_saying_what_the_arm_is(change, message):
    """Not OPW, saying why; these arms (axes 2 and 3 still parallel) are chains (issue 24)."""
    chain = chain_of(irb2400_urdf(**change))
    with pytest.raises(identify.KinematicsError, match=message):
        identify.opw_from_chain(chain)
    assert identify.identify(chain, samples=20).kind == "chain"


def test_an_arm_of_no_class_is_refused_saying_why_for_each():
    chain = chain_of(irb2400_urdf(rpy3="0.1 0 0"))
    with pytest.raises(identify.KinematicsError) as refused:
        identify.identify(chain, samples=20)
    text = str(refused.value)
    assert text.startswith("not an OPW arm (axes 2 and 3 are not parallel (5.72958 deg apart)); "
                           "not a UR arm (")
    assert "; not an offset-wrist arm (" in text and "; not a spherical-wrist arm (" in text


@pytest.mark.parametrize("text, message", [
    ("<robot", "is not valid XML"),
    ("<sdf/>", "is not a URDF"),
    ('<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:macro name="m"/></robot>',
     "still contains xacro macros"),
    ('<robot name="r"><link name="a"/><joint name="j" type="fixed"><parent link="a"/><child link="b"/>'
     '</joint></robot>', "names the link 'b'"),
])
def test_bad_files_give_one_clear_error(text, message):
    with pytest.raises(InputError, match=message):
        urdf.read_urdf(text)


def test_missing_file_names_it(tmp_path):
    with pytest.raises(InputError, match="Cannot read the URDF file .*nothing.urdf"):
        urdf.read_urdf(str(tmp_path / "nothing.urdf"))


def test_seven_axes_and_mimic_joints_on_the_chain_are_refused():
    with pytest.raises(InputError, match="7 movable joints .*CadRobot takes six-axis arms"):
        chain_of(irb2400_urdf(extra_joint=True))
    with pytest.raises(InputError, match="joint 'joint_5' copies joint 'joint_4' inside the arm"):
        chain_of(irb2400_urdf(mimic=True))


def test_without_tool0_the_last_link_is_the_flange_and_the_note_says_so():
    text = irb2400_urdf().replace('<link name="tool0"/>', "").replace(
        joint("joint_6-tool0", "link_6", "tool0", rpy="0 1.5707963267948966 0", kind="fixed"), "")
    chain = chain_of(text)
    assert chain.tip == "link_6"
    assert "no tool0 link: the last link 'link_6' became the flange" in chain.tip_note


def test_imported_spec_takes_limits_and_flags_placeholder_speeds(tmp_path):
    path = tmp_path / "arm.urdf"
    path.write_text(irb2400_urdf(b=0.02))
    imported = from_urdf.spec_from_urdf(str(path), "TEST_ARM", maker="ABB")
    spec = imported.spec
    assert spec.joint_min_deg == (-171.89,) * 6 and spec.joint_max_deg == (171.89,) * 6
    assert spec.joint_speed_deg_s == (143.24,) * 6
    assert "joint_speed_deg_s" in spec.uncertain and "placeholder" in spec.notes
    model = models.as_model(spec)
    q = np.random.default_rng(5).uniform(-150, 150, (100, 6))
    np.testing.assert_allclose(model.fk(q), urdf.chain_fk(imported.chain, np.radians(q)), atol=1e-9)


@pytest.mark.parametrize("maker, model, kg", [
    ("ABB", "irb1600_6_12", 6.0), ("ABB", "abb_irb4600_60_205", 60.0), ("ABB", "irb2400", None),
    ("KUKA", "kr16_r2010_2", 16.0), ("KUKA", "kr210l150", 150.0), ("KUKA", "kr6r900sixx", 6.0),
    ("Universal Robots", "ur10e", 10.0), ("Yaskawa Motoman", "gp180_120", 120.0),
    ("Yaskawa Motoman", "ma2010", None), ("Kawasaki", "rs007n", 7.0), ("FANUC", "cr35ia", 35.0),
    ("FANUC", "m20ia", None), ("Staubli", "tx2_90", None),
])
def test_payload_only_where_the_designation_states_it(maker, model, kg):
    assert from_urdf.payload_from_model(maker, model) == kg
