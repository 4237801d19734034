"""Fuzzing the URDF import (robots/urdf/): a hostile file is imported or refused in one line.

The property: any mutation of a valid URDF arm (a value replaced by NaN,
infinity, 1e308, text, nothing, a negative number or a wrong count of numbers;
an attribute or an element removed; a name made empty, long or non-ASCII; a DTD
or an entity; a mesh path that leaves the package) is either

* imported, into a robot whose limits are finite and ordered and whose speeds
  are finite and positive, or
* refused with ONE :class:`CadRobotError` whose message is one line and, for a
  malformed value, names the joint or link that holds it,

never another exception; and no file of the folder beside the package (where
the escaping mesh paths point) or of ``/etc`` is opened (``open``, ``os.open``
and ``trimesh.load`` are watched). A value that makes the file bad XML (a control
character) is refused naming the file, not an element.

The import is the one of ``api.import_robot`` without FreeCAD: read, guess the
maker, name, recognise and check the kinematics (20 joint sets, not 1000: the
tolerances are the same), write the link hulls and the table row into a robot
folder, and read that row back as the catalog does.
"""

import builtins
import contextlib
import os
import re
import xml.etree.ElementTree as ET
from unittest import mock

import numpy as np
import pytest

import fuzzing

fuzzing.require()

from hypothesis import example, given, strategies as st  # noqa: E402

from CadRobotWB.errors import CadRobotError  # noqa: E402
from CadRobotWB.robots.catalog import catalog_table  # noqa: E402
from CadRobotWB.robots.kinematics import models  # noqa: E402
from CadRobotWB.robots.urdf import from_urdf, link_meshes  # noqa: E402

#: Joint sets on which the recognised model is compared with the file's chain.
SAMPLES = 20

STL_TETRAHEDRON = ("solid s\n" + "".join(
    "facet normal 0 0 0\nouter loop\n%sendloop\nendfacet\n" % "".join(
        "vertex %s\n" % v for v in face)
    for face in [("0 0 0", "0 0.2 0", "0.1 0 0"), ("0 0 0", "0.1 0 0", "0 0 0.3"),
                 ("0 0 0", "0 0 0.3", "0 0.2 0"), ("0.1 0 0", "0 0.2 0", "0 0 0.3")])
    + "endsolid s\n")


def joint(name, parent, child, xyz, axis, kind="revolute", extra=""):
    limit = ('<limit lower="-3" upper="3" velocity="2.5" effort="0"/>'
             if kind != "fixed" else "")
    return ('<joint name="%s" type="%s"><parent link="%s"/><child link="%s"/>'
            '<origin xyz="%s" rpy="0 0 0"/><axis xyz="%s"/>%s%s</joint>'
            % (name, kind, parent, child, xyz, axis, limit, extra))


def link(name, shape):
    return ('<link name="%s"><collision><origin xyz="0 0 0.01" rpy="0 0 0"/><geometry>%s'
            '</geometry></collision></link>' % (name, shape))


#: ROS-Industrial's IRB 2400 layout (metres): a mesh, a scaled mesh, a box, a
#: cylinder and a sphere on the links, a lever that mimics joint_3 off the chain.
BASE_URDF = '<robot name="abb_irb2400">%s%s</robot>' % ("".join([
    link("base_link", '<mesh filename="package://pkg/meshes/link.stl"/>'),
    link("link_1", '<box size="0.2 0.2 0.3"/>'),
    link("link_2", '<cylinder radius="0.08" length="0.7"/>'),
    link("link_3", '<sphere radius="0.1"/>'),
    link("link_4", '<mesh filename="../meshes/link.stl" scale="1 1 2"/>'),
    link("link_5", '<mesh filename="package://pkg/meshes/link.stl"/>'),
    link("link_6", '<box size="0.05 0.05 0.02"/>'),
    '<link name="tool0"/>', '<link name="lever"/>']), "".join([
    joint("joint_1", "base_link", "link_1", "0 0 0", "0 0 1"),
    joint("joint_2", "link_1", "link_2", "0.1 0 0.615", "0 1 0"),
    joint("joint_3", "link_2", "link_3", "0 0 0.705", "0 1 0"),
    joint("joint_4", "link_3", "link_4", "0.258 0 0.135", "1 0 0"),
    joint("joint_5", "link_4", "link_5", "0.497 0 0", "0 1 0"),
    joint("joint_6", "link_5", "link_6", "0.085 0 0", "1 0 0"),
    joint("joint_6-tool0", "link_6", "tool0", "0 0 0", "1 0 0", kind="fixed"),
    joint("lever_joint", "link_1", "lever", "0 0.1 0", "0 1 0",
          extra='<mimic joint="joint_3" multiplier="1" offset="0"/>')]))


def addresses(text):
    """Every element of a URDF as a path ``find`` takes, and its attributes.

    Returns
    -------
    list of (str, tuple of str)
        E.g. ``("joint[@name='joint_2']/origin", ("xyz", "rpy"))``; the robot
        element is ``"."``.
    """
    found = []

    def walk(element, path):
        found.append((path, tuple(element.attrib)))
        counts = {}
        for child in element:
            counts[child.tag] = counts.get(child.tag, 0) + 1
            name = child.get("name")
            step = ("%s[@name='%s']" % (child.tag, name) if name and child.tag in ("link", "joint")
                    else "%s[%d]" % (child.tag, counts[child.tag]))
            walk(child, step if path == "." else path + "/" + step)

    walk(ET.fromstring(text), ".")
    return found


ELEMENTS = addresses(BASE_URDF)
ATTRIBUTES = [(path, name) for path, names in ELEMENTS for name in names]

#: Values a URDF should not hold where numbers belong (Python's float() reads '\u0661',
#: an Arabic-Indic one, as 1).
MALFORMED = ["nan", "NaN", "inf", "-inf", "1e308", "-1e308", "abc", "", "1 2", "1 2 3 4",
             "0x10", "1,5", "\u0661", "\u00e9"]
#: Numbers a file may hold that make an odd robot: imported or refused, one line either way.
ODD_NUMBERS = ["0", "-0", "-1", "-3.5", "1e-300", "1e6", "0 0 0", "-1 -1 -1"]
#: Names no robot, link or joint should have.
ODD_NAMES = ["", " ", "x" * 300, "\u00e9l\u00e9ment", "\u202eright-to-left", "a/b", "..", "\"'<>",
             "joint_1", "tool0", "base_link"]
#: Mesh references that leave the package (`{secret}`: an absolute path outside it).
ESCAPES = ["package://pkg/meshes/../../outside/secret.stl", "../../outside/secret.stl",
           "{secret}", "file://{secret}", "package://pkg/meshes/linked.stl",
           "package://other/secret.stl", "package://pkg/../../../../../../etc/passwd", "/etc/passwd",
           "", "package://", "meshes/", "\u00e9.stl"]
#: Text put before the robot element.
DECLARATIONS = ['<!DOCTYPE robot [<!ENTITY s SYSTEM "file://{secret}">]>',
                '<!DOCTYPE robot [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;">]>',
                '<!DOCTYPE robot SYSTEM "file://{secret}">',
                '<?xml-stylesheet href="file://{secret}"?>']


#: Attributes that hold text, not numbers.
TEXT_ATTRIBUTES = ("name", "filename", "link", "joint", "type")


def owner(path):
    """The name of the link or joint an element belongs to ("" for the robot element)."""
    match = re.match(r"(?:link|joint)\[@name='([^']*)'\]", path)
    return match.group(1) if match else ""


# ------------------------------------------------------------- mutations

def set_value(root, path, attribute, value):
    root.find(path).set(attribute, value)


def drop_attribute(root, path, attribute):
    del root.find(path).attrib[attribute]


def drop_element(root, path):
    parent_path, _, _ = path.rpartition("/")
    parent = root.find(parent_path or ".")
    parent.remove(root.find(path))


def mutated(mutation, secret):
    """The URDF text of BASE_URDF changed by `mutation`.

    Parameters
    ----------
    mutation : tuple
        ``("value", path, attribute, text)``, ``("component", path, attribute,
        index, text)``, ``("drop attribute", path, attribute)``, ``("drop
        element", path)``, ``("mesh", path, reference)`` or ``("declare", text)``.
    secret : str
        The file outside the package (put in place of ``{secret}``).
    """
    kind, args = mutation[0], [a.replace("{secret}", secret) if isinstance(a, str) else a
                               for a in mutation[1:]]
    root = ET.fromstring(BASE_URDF)
    if kind == "value":
        set_value(root, *args)
    elif kind == "component":
        path, attribute, index, text = args
        numbers = root.find(path).get(attribute).split()
        numbers[index % len(numbers)] = text
        set_value(root, path, attribute, " ".join(numbers))
    elif kind == "drop attribute":
        drop_attribute(root, *args)
    elif kind == "drop element":
        drop_element(root, *args)
    elif kind == "mesh":
        set_value(root, args[0], "filename", args[1])
    body = ET.tostring(root, encoding="unicode")
    return (args[0] + "\n" + body) if kind == "declare" else body


def number(text):
    """The number `text` spells as Python reads it (NaN and infinities too), else None."""
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


def plain_numbers(text, count):
    """True for `count` finite numbers below 1e300 in size, as Python reads them (it reads
    '\u0661', an Arabic-Indic one, as 1: taken as the number it spells)."""
    values = [number(word) for word in text.split()]
    return len(values) == count and all(v is not None and abs(v) < 1e300 for v in values)


def malformed_value(mutation):
    """True when the mutation puts text, NaN, an infinity, 1e300 or more, or a wrong count
    of numbers where numbers belong (the refusal must name their holder)."""
    if mutation[0] not in ("value", "component") or mutation[2] in TEXT_ATTRIBUTES:
        return False
    if mutation[0] == "component":
        return not plain_numbers(mutation[4], 1)
    original = ET.fromstring(BASE_URDF).find(mutation[1]).get(mutation[2])
    return not plain_numbers(mutation[3], len(original.split()))


# ------------------------------------------------------------- the import

@contextlib.contextmanager
def files_opened():
    """The real paths opened (``open``, ``os.open``, ``trimesh.load``) inside the block."""
    paths = []
    real_open, real_os_open, real_load = builtins.open, os.open, link_meshes.trimesh.load

    def note(path):
        if isinstance(path, (str, bytes, os.PathLike)):
            paths.append(os.path.realpath(os.fsdecode(path)))

    def watched_open(file, *args, **kwargs):
        note(file)
        return real_open(file, *args, **kwargs)

    def watched_os_open(path, *args, **kwargs):
        note(path)
        return real_os_open(path, *args, **kwargs)

    def watched_load(file_obj, *args, **kwargs):
        note(file_obj)
        return real_load(file_obj, *args, **kwargs)

    with mock.patch("builtins.open", watched_open), mock.patch("os.open", watched_os_open), \
            mock.patch.object(link_meshes.trimesh, "load", watched_load):
        yield paths


def import_urdf(path, folder):
    """What ``api.import_robot`` does with a URDF file, without FreeCAD; the spec read back."""
    robot = from_urdf.read_robot(path)
    maker = from_urdf.guess_maker(robot)
    name = from_urdf.name_from(robot.name or "robot")
    default_post, j23_factor = from_urdf.maker_defaults(maker, robot.name)
    imported = from_urdf.spec_from_urdf(path, name, maker=maker, model=robot.name,
                                        j23_factor=j23_factor, default_post=default_post,
                                        robot=robot, samples=SAMPLES)
    from_urdf.save_user_robot(imported, folder)
    spec, = catalog_table.read_table(os.path.join(folder, name + ".csv"))
    return spec


def assert_sane(spec):
    """An imported robot has finite, ordered limits, finite positive speeds and a flange."""
    lower, upper = np.array(spec.joint_min_deg), np.array(spec.joint_max_deg)
    speeds = np.array(spec.joint_speed_deg_s)
    assert np.isfinite(lower).all() and np.isfinite(upper).all() and (lower < upper).all(), (
        "limits", lower, upper)
    assert np.isfinite(speeds).all() and (speeds > 0).all(), ("speeds", speeds)
    assert np.isfinite(models.as_model(spec).fk(np.zeros((1, 6)))).all()


@pytest.fixture(scope="module")
def package(tmp_path_factory):
    """pkg/package.xml, pkg/meshes/link.stl (+ linked.stl -> outside), outside/secret.stl."""
    top = tmp_path_factory.mktemp("fuzz_urdf")
    for folder in ("pkg/meshes", "pkg/urdf", "outside", "robots"):
        os.makedirs(str(top / folder))
    (top / "pkg" / "package.xml").write_text("<package><name>pkg</name></package>")
    (top / "pkg" / "meshes" / "link.stl").write_text(STL_TETRAHEDRON)
    secret = top / "outside" / "secret.stl"
    secret.write_text(STL_TETRAHEDRON)
    os.symlink(str(secret), str(top / "pkg" / "meshes" / "linked.stl"))
    return top


def well_formed(text):
    """True when `text` parses as XML (a control character in a value makes it not: then
    the refusal names the file, not an element)."""
    try:
        ET.fromstring(text)
    except ET.ParseError:
        return False
    return True


def check_mutation(package, mutation):
    """The property for one mutation (see the module docstring)."""
    secret = str(package / "outside" / "secret.stl")
    path = str(package / "pkg" / "urdf" / "robot.urdf")
    text = mutated(mutation, secret)
    with open(path, "w", encoding="utf-8") as handle:
        handle.write(text)
    with files_opened() as opened:
        try:
            spec = import_urdf(path, str(package / "robots"))
        except CadRobotError as exc:
            message, spec = str(exc), None
    forbidden = (os.path.realpath(str(package / "outside")) + os.sep, "/etc/")
    assert not [p for p in opened if p.startswith(forbidden)], opened
    if spec is not None:
        assert_sane(spec)
        return
    assert message.splitlines() == [message], message
    if malformed_value(mutation) and owner(mutation[1]) and well_formed(text):
        assert owner(mutation[1]) in message, message


# ------------------------------------------------------------- the property

def mesh_paths():
    return [path for path, names in ELEMENTS if "filename" in names]


def vector_attributes():
    return [(path, name) for path, name in ATTRIBUTES if name in ("xyz", "rpy", "size", "scale")]


VALUES = MALFORMED + ODD_NUMBERS

mutations = st.one_of(
    st.sampled_from(ATTRIBUTES).flatmap(lambda pa: st.tuples(
        st.just("value"), st.just(pa[0]), st.just(pa[1]),
        st.sampled_from(VALUES + ODD_NAMES) | st.text(max_size=12))),
    st.sampled_from(vector_attributes()).flatmap(lambda pa: st.tuples(
        st.just("component"), st.just(pa[0]), st.just(pa[1]), st.integers(0, 2),
        st.sampled_from(VALUES))),
    st.sampled_from(ATTRIBUTES).map(lambda pa: ("drop attribute",) + pa),
    st.sampled_from([path for path, _ in ELEMENTS[1:]]).map(lambda path: ("drop element", path)),
    st.tuples(st.just("mesh"), st.sampled_from(mesh_paths()), st.sampled_from(ESCAPES)),
    st.sampled_from(DECLARATIONS).map(lambda text: ("declare", text)),
)


#: Seeds: every hostile class of issue 21 the URDF reader meets.
SEEDS = [
    ("value", ".", "name", ""),
    ("value", ".", "name", "\u00e9l\u00e9ment"),
    ("drop attribute", ".", "name"),
    ("value", "joint[@name='joint_2']/origin[1]", "xyz", "nan"),
    ("value", "joint[@name='joint_2']/origin[1]", "rpy", "1 2"),
    ("value", "joint[@name='joint_2']/origin[1]", "xyz", "\n"),   # quoted as \n: one line
    ("value", "joint[@name='joint_5']/parent[1]", "link", "0\x85"),   # a name: the same
    ("value", "link[@name='link_3']/collision[1]/geometry[1]/sphere[1]", "radius", "1e-300"),
    ("value", "joint[@name='joint_3']/axis[1]", "xyz", "0 0 0"),
    ("value", "joint[@name='joint_4']", "name", ""),
    ("value", "joint[@name='joint_4']", "type", "prismatic"),
    ("value", "link[@name='link_3']", "name", "x" * 300),
    ("drop element", "joint[@name='joint_5']"),
    ("drop element", "joint[@name='joint_3']/limit[1]"),
    ("drop element", "link[@name='tool0']"),
    ("mesh", "link[@name='base_link']/collision[1]/geometry[1]/mesh[1]",
     "package://pkg/meshes/../../outside/secret.stl"),
    ("mesh", "link[@name='link_4']/collision[1]/geometry[1]/mesh[1]", "../../outside/secret.stl"),
    ("mesh", "link[@name='link_5']/collision[1]/geometry[1]/mesh[1]", "{secret}"),
    ("mesh", "link[@name='link_5']/collision[1]/geometry[1]/mesh[1]", "file://{secret}"),
    ("mesh", "link[@name='link_5']/collision[1]/geometry[1]/mesh[1]",
     "package://pkg/meshes/linked.stl"),
] + [("declare", text) for text in DECLARATIONS]


def with_seeds(test):
    for mutation in SEEDS:
        test = example(mutation=mutation)(test)
    return test


@with_seeds
@given(mutation=mutations)
@fuzzing.examples(100, shared_fixtures=True)
def test_a_mutated_urdf_is_imported_or_refused_in_one_line(package, mutation):
    check_mutation(package, mutation)

