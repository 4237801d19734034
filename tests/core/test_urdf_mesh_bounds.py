"""Collision meshes are read within stated bounds (robots/urdf/link_meshes.py).

A binary STL is read TRIANGLES_PER_READ triangles at a time, each part cut to
its convex hull's points: the result is the hull trimesh makes of the whole
file (a link solid is that hull).  Measured on this machine before and after
issue 21: one 200 MB STL (4,000,000 triangles) on one link took 3.9 GB and
169 s through trimesh.load; read in parts, 129 MB and 10 s.  The bounds are
checked from the header before anything else is read: a forged count, more
triangles than MAX_STL_TRIANGLES, a text mesh past MAX_OTHER_MESH_BYTES and NaN
corners are one line naming the link and the mesh.
"""

import numpy as np
import pytest

from CadRobotWB.errors import CadRobotError
from CadRobotWB.robots.urdf import link_meshes, urdf

TRIANGLE = np.dtype([("normal", "<f4", (3,)), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])


def binary_stl(path, corners, count=None):
    """Write a binary STL of (N, 3, 3) corners; `count` forges its header."""
    triangles = np.zeros(len(corners), dtype=TRIANGLE)
    triangles["corners"] = corners
    with open(str(path), "wb") as stream:
        stream.write(b"\0" * 80 + np.uint32(len(corners) if count is None else count).tobytes())
        stream.write(triangles.tobytes())
    return path


def link_mesh(folder, name="link.stl"):
    """The mesh of link_1 of a URDF in `folder` naming meshes/`name`, scale 1 (mm = 1000 x)."""
    text = ('<robot name="r"><link name="link_1"><collision><geometry><mesh filename="meshes/%s"/>'
            '</geometry></collision></link></robot>' % name)
    (folder / "robot.urdf").write_text(text)
    robot = urdf.read_urdf(str(folder / "robot.urdf"))
    return link_meshes.shape_mesh(robot.collisions["link_1"][0], robot.path, "link_1")


@pytest.fixture
def folder(tmp_path):
    (tmp_path / "meshes").mkdir()
    return tmp_path


def test_a_big_stl_read_in_parts_gives_the_hull_of_the_whole_file(folder, monkeypatch):
    corners = np.random.default_rng(3).normal(size=(500, 3, 3)).astype(np.float32)
    binary_stl(folder / "meshes" / "link.stl", corners)
    monkeypatch.setattr(link_meshes, "TRIANGLES_PER_READ", 7)
    mesh = link_mesh(folder)
    whole = link_meshes.trimesh.Trimesh(corners.reshape(-1, 3).astype(float) * 1000.0).convex_hull
    assert len(mesh.vertices) == len(whole.vertices)
    np.testing.assert_allclose(np.sort(mesh.vertices, axis=0), np.sort(whole.vertices, axis=0),
                               atol=1e-9)
    assert mesh.volume == pytest.approx(whole.volume, rel=1e-9)


@pytest.mark.parametrize("case, words", [
    ("forged count", "header says 4000000000 triangles (200000000084 bytes) but the file has 234 "
                     "bytes"),
    ("count short by one", "header says 4 triangles"),
    ("too many triangles", "has 5 triangles, more than the 4"),
    ("nan corner", "points that are not finite"),
    ("text mesh too big", "is 0 MB, more than the 0 MB"),
])
def test_a_mesh_past_its_bound_is_one_line_naming_link_and_mesh(folder, monkeypatch, case, words):
    corners = np.arange(45, dtype=np.float32).reshape(5, 3, 3)
    path = folder / "meshes" / "link.stl"
    if case == "forged count":
        binary_stl(path, corners[:3], count=4 * 10 ** 9)
    elif case == "count short by one":
        binary_stl(path, corners, count=4)
    elif case == "too many triangles":
        binary_stl(path, corners)
        monkeypatch.setattr(link_meshes, "MAX_STL_TRIANGLES", 4)
    elif case == "nan corner":
        corners[2, 1, 0] = np.nan
        binary_stl(path, corners)
    else:
        path.write_text("solid s\n" + "facet normal 0 0 1\n" * 10 + "endsolid s\n")
        monkeypatch.setattr(link_meshes, "MAX_OTHER_MESH_BYTES", 100)
    with pytest.raises(CadRobotError) as error:
        link_mesh(folder)
    message = str(error.value)
    assert message.startswith("URDF link 'link_1': mesh 'meshes/link.stl' ")
    assert words in message and "\n" not in message


def test_the_meshes_of_one_robot_are_bounded_together(folder, monkeypatch):
    """Each file is read once, however many shapes name it; past the total, one line."""
    corners = np.random.default_rng(4).normal(size=(5, 3, 3)).astype(np.float32)
    for name in ("a.stl", "b.stl"):
        binary_stl(folder / "meshes" / name, corners)   # 334 bytes each
    robot = urdf.read_urdf('<robot name="r"><link name="link_1">%s</link></robot>' % "".join(
        '<collision><geometry><mesh filename="meshes/%s"/></geometry></collision>' % name
        for name in ("a.stl", "a.stl", "b.stl")))
    shapes = robot.collisions["link_1"]
    monkeypatch.setattr(link_meshes, "MAX_TOTAL_MESH_BYTES", 400)
    cache = {}
    for geometry in shapes[:2]:
        link_meshes.shape_mesh(geometry, str(folder / "robot.urdf"), "link_1", cache)
    assert len(cache) == 1
    with pytest.raises(CadRobotError, match="URDF link 'link_1': mesh 'meshes/b.stl': the robot's "
                                            "mesh files together are more than 0 MB"):
        link_meshes.shape_mesh(shapes[2], str(folder / "robot.urdf"), "link_1", cache)
