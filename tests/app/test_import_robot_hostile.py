"""Hostile URDFs, names and robot folders through the CLI: one line, exit 2, nothing written.

The import cases run ``cli.main`` in this FreeCAD (the CLI's own code, its
argument parsing and error lines, without a process each); one run of the
real ``cadrobot`` launcher then checks a refusal and a robot folder with a
broken file end to end (the listing: exit 0, one warning, every other robot).
Before issue 21 these ended as "internal error" (exit 3), or were accepted.
"""

import io
import os

import pytest

from CadRobotWB import cli, preferences
from conftest import run_cadrobot, sha256
from urdf_template import arm

#: (case id, file text, --name, words of the one line).
IMPORTS = [
    ("nan origin", arm(xyz="nan 0 0.615"), None, "URDF joint 'joint_2' origin xyz is 'nan 0 0.615'"),
    ("1e308 rpy", arm(rpy="0 0 1e308"), None, "URDF joint 'joint_2' origin rpy"),
    ("text axis", arm(axis="y"), None, "URDF joint 'joint_2' axis xyz is 'y'"),
    ("reversed limit", arm(lower="2", upper="-2"), None, "limit lower '2' is not below upper"),
    ("zero speed", arm(velocity='velocity="0"'), None, "URDF joint 'joint_2' limit velocity"),
    ("zero scale", arm(scale='scale="0 0 0"'), None, "link 'link_2' collision mesh scale"),
    ("nan box", arm(box='size="nan 1 1"'), None, "link 'base_link' collision box size"),
    ("cylinder without radius", arm(radius=""), None, "cylinder has no radius attribute"),
    ("empty robot name", arm(robot_name='name=""'), None, "<robot> element of"),
    ("300-character --name", arm(), "A" * 300, "has 300 characters: give at most 64"),
    ("empty --name", arm(), "", "Robot name '' is empty"),
    ("--name with a path", arm(), "../x", "use letters, digits and _ only"),
    ("--name CON", arm(), "CON", "is a device name on Windows"),
]


@pytest.fixture
def user_folder(tmp_path, monkeypatch):
    folder = tmp_path / "robots"
    monkeypatch.setenv("CADROBOT_ROBOT_FOLDER", str(folder))
    yield folder
    monkeypatch.delenv("CADROBOT_ROBOT_FOLDER")
    preferences.use_user_robot_folder()


def cadrobot(*args):
    """``cli.main`` in this process: (exit code, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    code = cli.main([str(a) for a in args], out, err)
    return code, out.getvalue(), err.getvalue()


@pytest.mark.parametrize("text, name, words", [case[1:] for case in IMPORTS],
                         ids=[case[0] for case in IMPORTS])
def test_a_hostile_import_is_one_line_exit_2_and_nothing_written(tmp_path, user_folder, text,
                                                                 name, words):
    path = tmp_path / "arm.urdf"
    path.write_text(text)
    before = sha256(str(path))
    code, out, err = cadrobot("robots", "--import", path, *(() if name is None else ("--name", name)))
    assert (code, out) == (2, ""), err
    assert err.startswith("cadrobot: error: ") and err.count("\n") == 1
    assert words in err
    assert not user_folder.exists() or os.listdir(str(user_folder)) == []
    assert sha256(str(path)) == before


def test_a_robot_folder_that_cannot_be_written_is_one_line_naming_it(tmp_path, monkeypatch):
    """Root writes into read-only folders, so the folder is a file here (one line either way)."""
    folder = tmp_path / "robots"
    folder.write_text("a file, not a folder")
    monkeypatch.setenv("CADROBOT_ROBOT_FOLDER", str(folder))
    (tmp_path / "arm.urdf").write_text(arm())
    try:
        code, out, err = cadrobot("robots", "--import", tmp_path / "arm.urdf")
    finally:
        monkeypatch.delenv("CADROBOT_ROBOT_FOLDER")
        preferences.use_user_robot_folder()
    assert (code, out, err.count("\n")) == (2, "", 1)
    assert "into the robot folder '%s'" % folder in err and "nothing was written" in err
    assert folder.read_text() == "a file, not a folder"


def test_the_real_cli_refuses_in_one_line_and_lists_past_a_broken_robot_file(tmp_path, user_folder):
    env = {"CADROBOT_ROBOT_FOLDER": str(user_folder)}
    (tmp_path / "arm.urdf").write_text(arm())
    (tmp_path / "bad.urdf").write_text(arm(lower="nan"))
    assert cadrobot("robots", "--import", tmp_path / "arm.urdf", "--name", "GOOD_ARM")[0] == 0
    (user_folder / "BROKEN.csv").write_text((user_folder / "GOOD_ARM.csv").read_text().replace(
        "GOOD_ARM", "BROKEN").replace("143.24", "nan"))
    refused = run_cadrobot("robots", "--import", tmp_path / "bad.urdf", env=env)
    assert (refused.returncode, refused.stdout) == (2, "")
    assert refused.stderr == ("cadrobot: error: URDF joint 'joint_2' limit lower is 'nan': give a "
                              "finite number within +-62.83; fix the URDF.\n")
    listing = run_cadrobot("robots", env=env)
    assert listing.returncode == 0, listing.stderr
    names = [line.split()[0] for line in listing.stdout.splitlines()]
    assert "GOOD_ARM" in names and "BROKEN" not in names and len(names) >= 151
    warning, = listing.stderr.splitlines()
    assert warning.startswith("cadrobot: warning: Robot file skipped: %s" % (user_folder / "BROKEN.csv"))
    assert "column 'joint_max_deg' must hold 6 finite numbers" in warning


def test_edits_that_make_an_impossible_robot_are_refused(tmp_path, user_folder):
    from CadRobotWB import api
    from CadRobotWB.errors import InputError
    (tmp_path / "arm.urdf").write_text(arm())
    api.import_robot(str(tmp_path / "arm.urdf"), name="EDITED")
    before = (user_folder / "EDITED.csv").read_bytes()
    for bad in (dict(payload_kg=float("nan")), dict(payload_kg=-1), dict(payload_kg="heavy"),
                dict(joint_speed_deg_s=("fast",) * 6), dict(joint_speed_deg_s=(0,) * 6),
                dict(joint_max_deg=(float("inf"),) * 6), dict(joint_min_deg=None,
                                                              joint_max_deg=(-170,) * 6)):
        # A wrong type is the API's own refusal (workflow/arguments), a bad value the robot's.
        with pytest.raises(InputError, match="Robot EDITED|^edit_robot: %s must be" % next(iter(bad))):
            api.edit_robot("EDITED", **bad)
    assert (user_folder / "EDITED.csv").read_bytes() == before


def test_in_the_gui_a_skipped_robot_file_is_one_report_view_warning(user_folder, monkeypatch):
    import FreeCAD
    from CadRobotWB import api
    from CadRobotWB.workflow import robot_catalog
    user_folder.mkdir()
    (user_folder / "BROKEN.csv").write_text("name,kind\nBROKEN,scara\n")
    warnings = []
    monkeypatch.setattr(FreeCAD, "GuiUp", 1, raising=False)
    monkeypatch.setattr(FreeCAD.Console, "PrintWarning", warnings.append)
    monkeypatch.setattr(robot_catalog, "_reported", set())
    assert len(api.robot_names()) == len(api.robot_names()) == 163   # twice: warned once
    assert len(warnings) == 1 and "BROKEN.csv" in warnings[0] and "column 'kind'" in warnings[0]
