"""Installing python-fcl from inside FreeCAD: which Python runs pip, the command, what a
failure says, and the headline of a result that left collisions out (no FreeCAD, no network)."""

import subprocess
import sys

import pytest

from CadRobotWB import dependencies, package_install
from CadRobotWB.errors import MissingPackageError

OURS = "%d.%d" % sys.version_info[:2]


def answering(answers):
    """A stand-in for subprocess.run: `answers` maps an interpreter to its `-m pip --version` line."""
    asked = []

    def run(argv, **kwargs):
        asked.append(argv[0])
        text = answers[argv[0]]
        return subprocess.CompletedProcess(argv, 0 if text.startswith("pip ") else 1, text, "")
    return run, asked


def test_the_python_that_runs_pip_is_freecads_own_version_never_another(monkeypatch):
    # Inside FreeCAD sys.executable is FreeCAD; the PATH's python3 may be another Python
    # (a pyenv shim on the project's machine): only a pip of FreeCAD's Python version will do.
    monkeypatch.setattr(package_install, "python_candidates",
                        lambda: ["/pyenv/python3", "/usr/bin/python-nopip", "/usr/bin/python" + OURS])
    run, asked = answering({
        "/pyenv/python3": "pip 24.0 from /pyenv/lib/site-packages/pip (python 3.9)",
        "/usr/bin/python-nopip": "/usr/bin/python-nopip: No module named pip",
        "/usr/bin/python" + OURS: "pip 23.0.1 from /usr/lib/python3/dist-packages/pip (python %s)" % OURS})
    found = package_install.pip_python(run)
    assert (found.executable, found.pip_version) == ("/usr/bin/python" + OURS, "23.0.1")
    assert asked == ["/pyenv/python3", "/usr/bin/python-nopip", "/usr/bin/python" + OURS]


def test_no_python_with_pip_is_one_error_naming_what_was_tried_and_the_fix(monkeypatch):
    monkeypatch.setattr(package_install, "python_candidates", lambda: ["/pyenv/python3"])
    run, _ = answering({"/pyenv/python3": "pip 24.0 from /x (python 3.9)"})
    with pytest.raises(MissingPackageError) as caught:
        package_install.pip_python(run)
    text = str(caught.value)
    assert "no Python %s with pip" % OURS in text and "/pyenv/python3 (pip 24.0 from /x (python 3.9))" in text
    assert "python3-pip" in text


def test_the_pip_command_targets_the_folder_and_skips_numpy_and_cython():
    command = package_install.pip_command("python-fcl", "/usr/bin/python3.14", "/home/u/py314")
    assert command[:3] == ["/usr/bin/python3.14", "-m", "pip"] and command[-1] == "python-fcl"
    assert command[command.index("--target") + 1] == "/home/u/py314"
    assert "--no-deps" in command       # numpy is FreeCAD's; Cython only builds from source
    assert "--no-deps" not in package_install.pip_command("matplotlib", "py", "/t")


@pytest.mark.parametrize("last_line, why", [
    ("ERROR: No matching distribution found for python-fcl",
     "PyPI has no python-fcl for Python %s on this system" % OURS),
    ("ERROR: Failed to build installable wheels for some pyproject.toml based projects (python-fcl)",
     "PyPI has no ready-made python-fcl for Python %s on this system, and building it from its "
     "source failed" % OURS),
    ("WARNING: Retrying ... Failed to establish a new connection: [Errno -3] Temporary failure "
     "in name resolution", "pip could not reach PyPI"),
    ("error: something else", "pip failed (exit code 1)"),
])
def test_a_failure_says_why_shows_pips_last_lines_and_the_command_to_run(last_line, why):
    result = package_install.InstallResult(
        "python-fcl", command=package_install.pip_command("python-fcl", "/usr/bin/python3", "/t/py3"),
        output=["line %d" % k for k in range(20)] + ["", last_line])
    text = package_install.failure_message(result, 1)
    assert text.startswith("python-fcl was not installed: " + why)
    shown = text.split("pip's last lines:\n", 1)[1].split("\n\n", 1)[0].splitlines()
    assert shown == ["line %d" % k for k in range(13, 20)] + [last_line]   # 8 lines, blanks dropped
    assert text.endswith("/usr/bin/python3 -m pip install --disable-pip-version-check --no-input "
                         "--upgrade --target /t/py3 --no-deps python-fcl")


def test_the_headline_names_the_check_left_out_and_why():
    assert dependencies.headline({}) is None
    assert dependencies.headline({"collisions": "..."}) == \
        "Collisions NOT checked: python-fcl is not installed."
