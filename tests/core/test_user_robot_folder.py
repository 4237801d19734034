"""A broken file in the user robot folder is skipped with one warning; the others stay usable.

Before issue 21 one bad row (NaN, a missing column, text that is not CSV)
raised from ``catalog.names()`` and so broke every robot, shipped ones too;
impossible rows (speeds <= 0, a joint whose minimum is its maximum, a meshes
name reaching out of the folder) were accepted.
"""

import errno
import os

import numpy as np
import pytest

from CadRobotWB.errors import CadRobotError, UnknownNameError
from CadRobotWB.robots.catalog import catalog, catalog_table
from CadRobotWB.robots.urdf import from_urdf, link_meshes, urdf
from urdf_template import arm

#: The table's first OPW row (its lengths, offsets and signs are what the cases below break).
GOOD = catalog_table.row_from_spec(next(spec for spec in catalog_table.read_table(catalog.TABLE_PATH)
                                        if spec.opw is not None), "GOOD.npz")


def row(**changes):
    """The CSV text of the good row renamed BROKEN and changed."""
    return catalog_table.table_text([dict(dict(GOOD, name="BROKEN", meshes=""), **changes)])


def without(column):
    return catalog_table.table_text([{k: v for k, v in dict(GOOD, name="BROKEN").items()
                                      if k != column}]).replace(",%s" % column, "")


#: (case id, file text, words of its warning besides the file name).
BROKEN_TABLES = [
    ("not utf-8", b"\xff\xfe\x00garbage", "cannot be read as a table"),
    ("nul bytes", "name,kind\n\0\0\0", "column 'name'"),
    ("yaml, not csv", "name: BROKEN\nkind: opw\n", "column"),
    ("json, not csv", '{"name": "BROKEN"}', "no robot row"),
    ("empty name", row(name=""), "column 'name'"),
    ("name with a path", row(name="../x"), "column 'name'"),
    ("nan speed", row(joint_speed_deg_s="nan 1 1 1 1 1"), "column 'joint_speed_deg_s'"),
    ("zero speed", row(joint_speed_deg_s="0 100 100 100 100 100"), "above 0"),
    ("negative speed", row(joint_speed_deg_s="-5 100 100 100 100 100"), "above 0"),
    ("inf speed", row(joint_speed_deg_s="inf 100 100 100 100 100"), "finite"),
    ("equal limits", row(joint_min_deg="0 0 0 0 0 0", joint_max_deg="0 1 1 1 1 1"),
     "column 'joint_max_deg' must be above joint_min_deg"),
    ("reversed limits", row(joint_min_deg="10 -1 -1 -1 -1 -1", joint_max_deg="-10 1 1 1 1 1"),
     "column 'joint_max_deg'"),
    ("inf limit", row(joint_max_deg="inf 1 1 1 1 1"), "column 'joint_max_deg'"),
    ("five lengths", row(lengths_mm="1 2 3 4 5"), "column 'lengths_mm'"),
    ("nan length", row(lengths_mm="nan 2 3 4 5 6 7"), "column 'lengths_mm'"),
    ("sign 2", row(signs="2 1 1 1 1 1"), "column 'signs'"),
    ("unknown kind", row(kind="scara"), "column 'kind'"),
    ("j23 factor 5", row(j23_factor="5"), "column 'j23_factor'"),
    ("payload nan", row(payload_kg="nan"), "column 'payload_kg'"),
    ("reach negative", row(reach_mm="-1"), "column 'reach_mm'"),
    ("base frame not unit", row(base_frame="0 0 0 2 0 0 0"), "column 'base_frame'"),
    ("meshes outside", row(meshes="../../secret.npz"), "column 'meshes'"),
    ("meshes absolute", row(meshes="/etc/secret.npz"), "column 'meshes'"),
    ("missing joint_max_deg", without("joint_max_deg"), "column 'joint_max_deg'"),
    ("missing kind", without("kind"), "column 'kind'"),
    ("huge file", row(notes="x" * catalog_table.MAX_USER_TABLE_BYTES), "larger than 100 kB"),
]


def broken_npz(path, kind):
    """Write a link hulls file that cannot be used."""
    if kind == "garbage":
        path.write_bytes(b"PK\x03\x04 not a zip at all")
    elif kind == "pickle":
        np.savez(path, vertices_0=np.array([object()], dtype=object))
    elif kind == "nan":
        np.savez(path, vertices_0=np.full((8, 3), np.nan))
    elif kind == "flat":
        np.savez(path, vertices_0=np.zeros((8, 2)))
    elif kind == "other key":
        np.savez(path, secret=np.zeros((8, 3)))


NPZ_KINDS = ["garbage", "pickle", "nan", "flat", "other key", "missing"]


@pytest.fixture
def folder(tmp_path):
    catalog.set_user_folder(str(tmp_path))
    yield tmp_path
    catalog.set_user_folder("")


@pytest.mark.parametrize("text, words", [case[1:] for case in BROKEN_TABLES],
                         ids=[case[0] for case in BROKEN_TABLES])
def test_a_broken_robot_file_is_skipped_with_one_warning_and_the_others_stay(folder, text, words):
    (folder / "GOOD.csv").write_text(catalog_table.table_text([dict(GOOD, name="GOOD",
                                                                    meshes="")]))
    broken = folder / "BROKEN.csv"
    (broken.write_bytes if isinstance(text, bytes) else broken.write_text)(text)
    before = broken.read_bytes()
    names = catalog.names()
    assert "GOOD" in names and "BROKEN" not in names and len(names) >= 151
    problems = catalog.user_folder_problems()
    assert len(problems) == 1 and "\n" not in problems[0]
    assert str(broken) in problems[0] and words in problems[0], problems
    assert "import the robot again" in problems[0] or "delete it" in problems[0]
    with pytest.raises(UnknownNameError, match="skipped"):
        catalog.get("BROKEN")
    assert broken.read_bytes() == before


@pytest.mark.parametrize("kind", NPZ_KINDS)
def test_a_link_solids_file_that_cannot_be_used_leaves_the_robot_with_simple_solids(folder, kind):
    (folder / "GOOD.csv").write_text(catalog_table.table_text([dict(GOOD, name="GOOD")]))
    broken_npz(folder / "GOOD.npz", kind)
    assert catalog.get("GOOD").meshes == ""
    problems = catalog.user_folder_problems()
    assert len(problems) == 1 and "\n" not in problems[0]
    assert "GOOD.npz" in problems[0] and "import its URDF again" in problems[0]


def test_a_good_link_solids_file_is_kept(folder):
    (folder / "GOOD.csv").write_text(catalog_table.table_text([dict(GOOD, name="GOOD")]))
    np.savez_compressed(folder / "GOOD.npz", vertices_0=np.random.default_rng(0).random((20, 3)))
    assert catalog.get("GOOD").meshes == os.path.join(str(folder), "GOOD.npz")
    assert catalog.user_folder_problems() == []


@pytest.fixture(scope="module")
def imported():
    """The malformed-URDF template's valid arm, read (box, cylinder and sphere solids)."""
    robot = urdf.read_urdf(arm())
    return from_urdf.spec_from_urdf("safe_arm.urdf", "SAFE_ARM", robot=robot, samples=20)


def failing(code, half_written):
    """A stand-in for a write (or rename) that fails with OSError(`code`), after writing
    part of its file when `half_written`."""
    def fail(path, *args):
        if half_written:
            with open(path, "w") as stream:
                stream.write("half")
        raise OSError(code, os.strerror(code))
    return fail


@pytest.mark.parametrize("module, function, code", [
    (link_meshes, "save", errno.ENOSPC), (catalog_table, "write_table", errno.ENOSPC),
    (os, "replace", errno.EROFS), (os, "replace", errno.EACCES)],
    ids=["hulls: disk full", "table: disk full", "read-only folder", "no permission"])
def test_a_full_or_read_only_folder_is_one_line_naming_it_and_leaves_it_as_it_was(
        tmp_path, monkeypatch, imported, module, function, code):
    folder = tmp_path / "robots"
    folder.mkdir()
    (folder / "OTHER.csv").write_text("kept")
    monkeypatch.setattr(module, function, failing(code, half_written=module is not os))
    with pytest.raises(CadRobotError) as error:
        from_urdf.save_user_robot(imported, str(folder))
    message = str(error.value)
    assert "\n" not in message and "robot folder '%s'" % folder in message
    assert os.strerror(code) in message and "nothing was written" in message
    assert sorted(os.listdir(folder)) == ["OTHER.csv"]


def test_a_robot_folder_that_is_a_file_is_one_line_naming_it(tmp_path, imported):
    folder = tmp_path / "robots"
    folder.write_text("not a folder")
    with pytest.raises(CadRobotError, match="Cannot write robot SAFE_ARM into the robot folder '%s'"
                       % folder):
        from_urdf.save_user_robot(imported, str(folder))
    assert folder.read_text() == "not a folder"


def test_a_saved_robot_reads_back(tmp_path, imported):
    spec, missing = from_urdf.save_user_robot(imported, str(tmp_path))
    assert sorted(os.listdir(tmp_path)) == ["SAFE_ARM.csv", "SAFE_ARM.npz"]
    assert missing == ["meshes/link_2.stl"] and spec.meshes == str(tmp_path / "SAFE_ARM.npz")
    assert catalog_table.meshes_problem(spec.meshes) == ""
