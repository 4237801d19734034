"""The CLI for Addon Manager users: one FreeCADCmd line, no `cadrobot` launcher.

FreeCAD runs here as on such a user's machine: its user folder (a private
FREECAD_USER_HOME) holds ``Mod/CadRobot`` (this repository, as the Addon
Manager would copy it) and ``AdditionalPythonPackages``; nothing else puts
CadRobot on the path.  The command is the line README.md gives.
"""

import json
import os
import shutil
import subprocess

import pytest

import FreeCAD
from CadRobotWB import dependencies
from conftest import REPO

V = FreeCAD.Vector


def readme_line(arguments):
    """The documented invocation's -c code for `arguments` (one string)."""
    return "from CadRobotWB import cli; cli.run('%s')" % arguments


def freecadcmd():
    found = os.environ.get("CADROBOT_FREECADCMD") or shutil.which("freecadcmd") or shutil.which("FreeCADCmd")
    assert found, "no freecadcmd on PATH"
    return found


@pytest.fixture(scope="module")
def user_env(tmp_path_factory):
    """Environment of a FreeCAD whose user folder has CadRobot as the Addon Manager installs it."""
    home = tmp_path_factory.mktemp("freecad-user")
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("CADROBOT_", "PYTEST_")) and k != "PYTHONPATH"}
    env["FREECAD_USER_HOME"] = str(home)
    env["CADROBOT_PROGRESS_DELAY_S"] = "3600"   # no progress lines, however loaded the machine
    # No `cadrobot` launcher on the PATH (the Addon Manager installs none).
    env["PATH"] = os.pathsep.join(d for d in env.get("PATH", "").split(os.pathsep)
                                  if d and not os.path.exists(os.path.join(d, "cadrobot")))

    def ask(code):
        run = subprocess.run([freecadcmd(), "-c", code], env=env, capture_output=True, text=True,
                             timeout=120)
        return run.stdout.strip().splitlines()[-1]

    data = ask("import FreeCAD; print(FreeCAD.getUserAppDataDir())")
    assert os.path.realpath(data).startswith(os.path.realpath(str(home))), \
        "this FreeCAD ignores FREECAD_USER_HOME (user data in %s)" % data
    os.makedirs(os.path.join(data, "Mod"), exist_ok=True)
    os.symlink(REPO, os.path.join(data, "Mod", "CadRobot"))
    packages = dependencies.packages_folder()
    if packages:
        parts = packages.split(os.sep)
        root = os.sep.join(parts[:parts.index(dependencies.PACKAGES_FOLDER_NAME) + 1])
        os.symlink(root, os.path.join(data, dependencies.PACKAGES_FOLDER_NAME))
    imported = ask("import CadRobotWB; print(CadRobotWB.__file__)")
    assert os.path.realpath(imported) == os.path.join(os.path.realpath(REPO), "CadRobotWB", "__init__.py")
    return env


@pytest.fixture(scope="module")
def documents(tmp_path_factory, seam_file):
    """A folder with part.FCStd (the example cell) and far.FCStd (its robot 3 m away)."""
    folder = tmp_path_factory.mktemp("work")
    shutil.copy(seam_file, folder / "part.FCStd")
    doc = FreeCAD.openDocument(seam_file)
    try:
        cell = doc.getObjectsByLabel("SeamCell")[0]
        cell.Placement = FreeCAD.Placement(V(-3000, 0, 0), FreeCAD.Rotation())
        doc.saveAs(str(folder / "far.FCStd"))
    finally:
        FreeCAD.closeDocument(doc.Name)
    return folder


def run_line(arguments, env, cwd):
    return subprocess.run([freecadcmd(), "-c", readme_line(arguments)], env=env, cwd=str(cwd),
                          capture_output=True, text=True, timeout=300)


def test_export_succeeds_with_only_the_clis_output(user_env, documents):
    run = run_line("export part.FCStd -o out", user_env, documents)
    assert run.returncode == 0, run.stderr
    assert run.stdout == "SeamCell: wrote %s\n" % (documents / "out" / "SeamWeld.mod")
    assert run.stderr == ""
    assert "MoveL" in (documents / "out" / "SeamWeld.mod").read_text()


def test_a_finding_exits_1_with_one_line_whose_hint_runs_as_it_reads(user_env, documents):
    run = run_line("export far.FCStd -o far_out", user_env, documents)
    assert run.returncode == 1, (run.stdout, run.stderr)
    [line] = run.stderr.splitlines()
    assert line.startswith("cadrobot: error: Cell ") and "cannot run" in line
    assert run.stdout == "" and not (documents / "far_out").exists()
    # The hint names the check as this user runs it: the README's FreeCADCmd line ...
    name = os.path.basename(freecadcmd())
    hint = line.split(" Run `", 1)[1].split("` for all of them, or export without checking.")[0]
    assert hint == '%s -c "from CadRobotWB import cli; cli.run(\'check %s\')"' % (
        name, documents / "far.FCStd")
    # ... and it works, typed into a shell: every problem, exit 1.
    check = subprocess.run(hint, shell=True, env=user_env, cwd=str(documents), capture_output=True,
                           text=True, timeout=300)
    assert check.returncode == 1, check.stderr
    assert check.stdout.count("SeamCell: ERROR: unreachable: ") >= 1 and "FAILED" in check.stdout


@pytest.mark.parametrize("arguments, words", [
    ("export missing.FCStd -o out2", "does not exist"),
    ("export part.FCStd --post brand_x -o out2", "Unknown post-processor 'brand_x'"),
    ('export "part.FCStd -o out2', "quote that is not closed"),
])
def test_bad_input_exits_2_with_one_line(user_env, documents, arguments, words):
    run = run_line(arguments, user_env, documents)
    assert run.returncode == 2, (run.stdout, run.stderr)
    [line] = run.stderr.splitlines()
    assert line.startswith("cadrobot: error: ") and words in line
    assert run.stdout == "" and not (documents / "out2").exists()


def test_json_output_is_clean(user_env, documents):
    run = run_line("check part.FCStd --json", user_env, documents)
    assert run.returncode == 0, run.stderr
    assert json.loads(run.stdout)["cells"][0]["cell"] == "SeamCell"
