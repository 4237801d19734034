"""A small valid six-axis arm as URDF text, with fields to break (hostile-file tests).

The ABB IRB 2400's layout (metres, as ROS-Industrial writes it) with a box, a
cylinder, a mesh and a sphere as collision shapes.  ``arm(**changes)`` gives
its text with some fields replaced, e.g. ``arm(xyz="nan 0 0")``.
"""

#: The valid arm; each {field} is a whole attribute or value a case replaces.
TEMPLATE = """<robot {robot_name}>
  <link name="base_link"><collision><geometry><box {box}/></geometry></collision></link>
  <link name="link_1"><collision><origin xyz="{collision_xyz}" rpy="0 0 0"/>
    <geometry><cylinder {radius} {length}/></geometry></collision></link>
  <link name="link_2"><collision><geometry><mesh {filename} {scale}/></geometry></collision></link>
  <link name="link_3"><collision><geometry><sphere {sphere}/></geometry></collision></link>
  <link {link_4}/><link name="link_5"/><link name="link_6"/><link name="tool0"/>
  <joint name="joint_1" type="revolute"><parent link="base_link"/><child link="link_1"/>
    <origin xyz="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" velocity="2.5" effort="0"/></joint>
  <joint name="joint_2" {joint_2_type}><parent link="link_1"/><child {joint_2_child}/>
    <origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="{axis}"/>
    <limit lower="{lower}" upper="{upper}" {velocity} effort="0"/></joint>
  <joint name="joint_3" type="revolute"><parent link="link_2"/><child link="link_3"/>
    <origin xyz="0 0 0.705"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" velocity="2.5" effort="0"/>{mimic}</joint>
  <joint {joint_4_name} type="revolute"><parent link="link_3"/><child link="link_4"/>
    <origin xyz="0.258 0 0.135"/><axis xyz="1 0 0"/>
    <limit lower="-3" upper="3" velocity="2.5" effort="0"/></joint>
  <joint name="joint_5" type="revolute"><parent link="link_4"/><child link="link_5"/>
    <origin xyz="0.497 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" velocity="2.5" effort="0"/></joint>
  <joint name="joint_6" type="revolute"><parent link="link_5"/><child link="link_6"/>
    <origin xyz="0.085 0 0"/><axis xyz="1 0 0"/>
    <limit lower="-3" upper="3" velocity="2.5" effort="0"/></joint>
  <joint name="joint_6-tool0" type="fixed"><parent link="link_6"/><child link="tool0"/>
    <origin xyz="0 0 0" rpy="0 1.5707963267948966 0"/></joint>{extra}
</robot>"""

VALID = dict(
    robot_name='name="safe_arm"', box='size="0.2 0.2 0.1"', collision_xyz="0 0 0.1",
    radius='radius="0.05"', length='length="0.3"', filename='filename="meshes/link_2.stl"',
    scale='scale="0.001 0.001 0.001"', sphere='radius="0.05"', link_4='name="link_4"',
    joint_2_type='type="revolute"', joint_2_child='link="link_2"', xyz="0.1 0 0.615",
    rpy="0 0 0", axis="0 1 0", lower="-1.5", upper="2.5", velocity='velocity="2.5"',
    mimic="", joint_4_name='name="joint_4"', extra="")


def arm(**changes):
    """The template's text with some fields changed."""
    return TEMPLATE.format(**dict(VALID, **changes))
