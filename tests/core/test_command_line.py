"""Hints that name a CadRobot command name it as this user runs it: `cadrobot ...` when the
launcher is on the PATH, else the README's FreeCADCmd line (Addon Manager users), and
nothing in FreeCAD's GUI, where panels and buttons do the job."""

import os
import shlex
import sys
import types

import pytest

from CadRobotWB import cli, command_line, posts
from CadRobotWB.errors import UnknownNameError
from CadRobotWB.robots.catalog import catalog


def executable(folder, name):
    path = os.path.join(str(folder), name)
    with open(path, "w") as handle:
        handle.write("#!/bin/sh\n")
    os.chmod(path, 0o755)


def test_with_the_launcher_on_the_path_the_hint_is_cadrobot(tmp_path, monkeypatch):
    executable(tmp_path, "cadrobot")
    monkeypatch.setenv("PATH", str(tmp_path))
    assert command_line.as_typed("check", "my part.FCStd") == 'cadrobot check "my part.FCStd"'
    assert shlex.split(command_line.as_typed("check", "my part.FCStd"))[1:] == ["check", "my part.FCStd"]


def test_without_it_the_hint_is_the_freecadcmd_line_and_reads_back_as_the_same_arguments(
        tmp_path, monkeypatch):
    executable(tmp_path, "freecadcmd")                  # Debian's name for FreeCADCmd
    monkeypatch.setenv("PATH", str(tmp_path))
    line = command_line.as_typed("place", 'my "best" part.FCStd', "--region", "0,0,1,1")
    program, option, code = shlex.split(line)           # as a POSIX shell splits it
    assert (program, option) == ("freecadcmd", "-c")
    assert code.startswith("from CadRobotWB import cli; cli.run(") and code.endswith(")")
    inner = eval(code[len("from CadRobotWB import cli; cli.run("):-1])     # the Python literal
    assert cli.split_command_line(inner) == ["place", 'my "best" part.FCStd', "--region", "0,0,1,1"]
    monkeypatch.setenv("PATH", "/nowhere")
    assert command_line.as_typed("posts") == \
        'FreeCADCmd -c "from CadRobotWB import cli; cli.run(\'posts\')"'


def test_in_freecads_gui_messages_name_no_command(monkeypatch):
    monkeypatch.setitem(sys.modules, "FreeCAD", types.SimpleNamespace(GuiUp=True))
    assert command_line.outside_gui(" `%s` describes them.", "posts") == ""
    with pytest.raises(UnknownNameError) as info:
        posts.get("xyz")
    assert str(info.value).endswith("ur_script, fanuc_ls.")
    with pytest.raises(UnknownNameError) as info:
        catalog.get("IRB9999")
    assert str(info.value).endswith("robots are known: New cell lists them and imports a URDF "
                                    "(Import URDF...).")
    assert "cadrobot" not in str(info.value) and "FreeCADCmd" not in str(info.value)


def test_an_unknown_robot_outside_the_gui_names_both_commands(tmp_path, monkeypatch):
    monkeypatch.setenv("PATH", "/nowhere")
    with pytest.raises(UnknownNameError) as info:
        catalog.get("IRB9999")
    assert str(info.value).endswith(
        "run `FreeCADCmd -c \"from CadRobotWB import cli; cli.run('robots')\"` to list them, or "
        "import its URDF with `FreeCADCmd -c \"from CadRobotWB import cli; cli.run('robots --import "
        "FILE.urdf')\"`.")


def test_the_launcher_in_freecads_own_path_does_not_count(monkeypatch):
    # FreeCAD puts each Mod folder on its PATH: the Addon Manager's copy of the repository,
    # launcher and all, is one of them, but the user's shell knows nothing of it.
    repository = os.path.dirname(os.path.dirname(os.path.abspath(command_line.__file__)))
    assert os.path.exists(os.path.join(repository, "cadrobot"))
    monkeypatch.setenv("PATH", repository + os.sep + "." + os.pathsep + "/nowhere")
    assert not command_line.launcher_on_path()
    assert command_line.as_typed("posts").startswith("FreeCADCmd -c ")
