"""App-tier fixtures: real FreeCAD documents (these tests run inside FreeCADCmd)."""

import hashlib
import os
import shutil
import subprocess
import sys
import tempfile

import pytest

import FreeCAD

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "examples"))


@pytest.fixture(autouse=True)
def no_progress_lines(monkeypatch):
    """``cli.main`` run in-process prints progress lines after 2 s of work, which a
    loaded machine (parallel test workers) may reach in any test: only tests that
    ask for them (``test_cli_progress``) get them."""
    monkeypatch.setenv("CADROBOT_PROGRESS_DELAY_S", "3600")


@pytest.fixture
def doc():
    document = FreeCAD.newDocument("CadRobotTest")
    name = document.Name
    yield document
    if name in FreeCAD.listDocuments():  # a test may have closed it to reopen the file
        FreeCAD.closeDocument(name)


@pytest.fixture
def seam_cell(doc):
    import seam_tracking_cell
    return seam_tracking_cell.build(doc)


def sha256(path):
    with open(path, "rb") as handle:
        return hashlib.sha256(handle.read()).hexdigest()


@pytest.fixture(scope="module")
def seam_file(tmp_path_factory):
    """The example seam-tracking cell saved as a document (built once per test module)."""
    import seam_tracking_cell
    folder = tmp_path_factory.mktemp("doc")
    doc = FreeCAD.newDocument("SavedSeam")
    try:
        seam_tracking_cell.build(doc)
        path = str(folder / "seam.FCStd")
        doc.saveAs(path)
    finally:
        FreeCAD.closeDocument(doc.Name)
    return path


def run_cadrobot(*args, cwd=None, without=(), env=None):
    """Run the real `cadrobot` launcher; returns CompletedProcess (text).

    Parameters
    ----------
    env : dict, optional
        Extra environment variables.
    without : sequence of str
        Modules that cannot be imported in that FreeCAD, as on a user's machine
        without the package: the CLI then runs through the launcher's runner
        (``tools/freecad_run.py``) from a script that first sets ``sys.modules[name]
        = None``. (Not a ``sitecustomize`` on PYTHONPATH: FreeCAD 1.x starts Python
        ignoring the environment.)
    """
    # Progress lines appear after 2 s of work, and on a loaded machine (parallel test
    # workers) any run may take that long: only tests that ask for them get them.
    env = dict(dict(os.environ, CADROBOT_PROGRESS_DELAY_S="3600"), **(env or {}))
    env.pop("PYTEST_CURRENT_TEST", None)
    with tempfile.TemporaryDirectory() as blocker:
        command = [os.path.join(REPO, "cadrobot")]
        if without:
            script = os.path.join(blocker, "cadrobot_without.py")
            with open(script, "w") as handle:
                handle.write("import sys\nfor name in %r:\n    sys.modules[name] = None\n"
                             "from CadRobotWB import cli\nsys.exit(cli.main(sys.argv[1:]))\n"
                             % (list(without),))
            # Not sys.executable: inside FreeCAD 1.x that is FreeCAD itself.
            command = [shutil.which("python3"), os.path.join(REPO, "tools", "freecad_run.py"),
                       "--clean-stdout", "--prog", "cadrobot", script]
        return subprocess.run(command + [str(a) for a in args],
                              cwd=cwd, env=env, capture_output=True, text=True, timeout=300)
