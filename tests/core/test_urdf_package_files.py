"""A URDF reads meshes only inside its own package (robots/urdf/package_files.py).

The layout is a ROS package beside a folder the URDF must not read:

    tmp/pkg/package.xml
    tmp/pkg/urdf/robot.urdf        one link whose collision mesh is the reference under test
    tmp/pkg/meshes/link.stl        a tetrahedron (0,0,0) (0.1,0,0) (0,0.2,0) (0,0,0.3) m
    tmp/outside/secret.stl         a triangle at x = 0.4242 m: must never be opened

Every escape form is refused with one line naming the link and the mesh, before
trimesh opens any file; the package's own mesh loads with its bounds in mm
(0..100, 0..200, 0..300, by hand from the metres above).
"""

import os

import numpy as np
import pytest

from CadRobotWB.errors import InputError
from CadRobotWB.robots.urdf import from_urdf, link_meshes, urdf
from CadRobotWB.robots.urdf.package_files import MeshPathError


def ascii_stl(triangles_m):
    """An ASCII STL of (n, 3, 3) vertices in metres."""
    # float(): numpy 2 writes repr(np.float64(0.1)) as "np.float64(0.1)"
    facets = "".join("facet normal 0 0 0\nouter loop\n%s\nendloop\nendfacet\n"
                     % "\n".join("vertex %r %r %r" % tuple(float(c) for c in v) for v in t)
                     for t in triangles_m)
    return "solid s\n%sendsolid s\n" % facets


TETRAHEDRON_M = np.array([[0, 0, 0], [0.1, 0, 0], [0, 0.2, 0], [0, 0, 0.3]])
FACES = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]


def write(path, text):
    os.makedirs(os.path.dirname(str(path)), exist_ok=True)
    with open(str(path), "w") as handle:
        handle.write(text)
    return str(path)


def robot_urdf(reference):
    return ('<robot name="r"><link name="link_1"><collision><geometry><mesh filename="%s"/>'
            '</geometry></collision></link></robot>' % reference)


@pytest.fixture
def package(tmp_path):
    """The layout of the module docstring; returns (urdf folder, secret path)."""
    write(tmp_path / "pkg" / "package.xml", "<package><name>pkg</name></package>")
    write(tmp_path / "pkg" / "meshes" / "link.stl", ascii_stl(TETRAHEDRON_M[FACES]))
    secret = write(tmp_path / "outside" / "secret.stl",
                   ascii_stl([[[0.4242, 0, 0], [0.4242, 1, 0], [0.4242, 0, 1]]]))
    return tmp_path / "pkg" / "urdf", secret


@pytest.fixture
def opened(monkeypatch):
    """The paths trimesh is asked to load during the test."""
    paths = []
    load = link_meshes.trimesh.load

    def recording_load(path, **options):
        paths.append(os.path.realpath(path))
        return load(path, **options)

    monkeypatch.setattr(link_meshes.trimesh, "load", recording_load)
    return paths


def link_mesh(folder, reference):
    """The collision mesh of link_1 of a URDF written in `folder` with `reference`."""
    robot = urdf.read_urdf(write(folder / "robot.urdf", robot_urdf(reference)))
    geometry, = robot.collisions["link_1"]
    return link_meshes.shape_mesh(geometry, robot.path, "link_1")


@pytest.mark.parametrize("form, words", [
    ("package://pkg/meshes/../../outside/secret.stl", "leaves the URDF's folder and package"),
    ("../../outside/secret.stl", "leaves the URDF's folder and package"),
    ("{secret}", "is an absolute path"),
    ("file://{secret}", "is a file:// URL"),
    ("package://pkg/meshes/linked.stl", "is a link to '{secret}', outside"),
])
def test_every_escape_is_refused_naming_link_and_mesh_before_anything_is_read(
        package, opened, form, words):
    folder, secret = package
    os.symlink(secret, str(folder.parent / "meshes" / "linked.stl"))
    reference = form.format(secret=secret)
    with pytest.raises(MeshPathError) as error:
        link_mesh(folder, reference)
    message = str(error.value)
    assert isinstance(error.value, InputError) and "\n" not in message
    assert message.startswith("URDF link 'link_1': mesh '%s' %s" % (reference,
                                                                     words.format(secret=secret)))
    assert os.path.realpath(secret) not in opened


@pytest.mark.parametrize("reference, package_xml", [
    ("package://pkg/meshes/link.stl", True),
    ("../meshes/link.stl", True),           # '..' that stays inside the package root
    ("package://pkg/meshes/link.stl", False),   # root = the folder named like the package
])
def test_a_mesh_inside_the_package_still_loads_in_mm(package, opened, reference, package_xml):
    folder, secret = package
    if not package_xml:
        os.remove(str(folder.parent / "package.xml"))
    mesh = link_mesh(folder, reference)
    np.testing.assert_allclose(mesh.bounds, [[0, 0, 0], [100, 200, 300]], atol=1e-9)
    assert opened == [os.path.realpath(str(folder.parent / "meshes" / "link.stl"))]


def test_without_package_xml_a_relative_climb_out_of_the_urdf_folder_is_refused(package, opened):
    folder, _ = package
    os.remove(str(folder.parent / "package.xml"))
    with pytest.raises(MeshPathError, match="mesh '../meshes/link.stl' leaves"):
        link_mesh(folder, "../meshes/link.stl")
    assert opened == []


@pytest.mark.parametrize("suffix, encoding", [(".urdf", "utf-8"), (".urdf", "utf-16"),
                                              (".xacro", "utf-8")])
def test_a_dtd_with_an_entity_is_refused_before_parsing(package, suffix, encoding):
    folder, secret = package
    text = ('<?xml version="1.0" encoding="%s"?>\n<!DOCTYPE robot [<!ENTITY s SYSTEM "file://%s">]>'
            '\n<robot name="&s;"><link name="link_1"/></robot>' % (encoding, secret))
    path = str(folder / ("robot" + suffix))
    os.makedirs(str(folder))
    with open(path, "wb") as handle:
        handle.write(text.encode(encoding))
    with pytest.raises(InputError) as error:
        from_urdf.read_robot(path)
    assert str(error.value) == (
        "'%s' declares an XML DOCTYPE: CadRobot refuses DTDs and entities in a URDF; remove "
        "the declaration (a URDF needs none)." % path)
    with pytest.raises(InputError, match="declares an XML ENTITY"):
        urdf.read_urdf('<robot name="r"><!ENTITY s "x"><link name="a"/></robot>')
