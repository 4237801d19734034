"""App-tier fixtures: real FreeCAD documents (these tests run inside FreeCADCmd)."""

import hashlib
import os
import subprocess
import sys
import tempfile

import pytest

import FreeCAD

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "examples"))


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


def run_cadrobot(*args, cwd=None, without=()):
    """Run the real `cadrobot` launcher; returns CompletedProcess (text).

    Parameters
    ----------
    without : sequence of str
        Modules that cannot be imported in that FreeCAD (``sys.modules[name]
        = None`` from a ``sitecustomize`` on PYTHONPATH), as on a user's
        machine without the package.
    """
    env = dict(os.environ)
    env.pop("PYTEST_CURRENT_TEST", None)
    with tempfile.TemporaryDirectory() as blocker:
        if without:
            with open(os.path.join(blocker, "sitecustomize.py"), "w") as handle:
                handle.write("import sys\nfor name in %r:\n    sys.modules[name] = None\n" % (list(without),))
            env["PYTHONPATH"] = os.pathsep.join(filter(None, [blocker, env.get("PYTHONPATH")]))
        return subprocess.run([os.path.join(REPO, "cadrobot")] + [str(a) for a in args],
                              cwd=cwd, env=env, capture_output=True, text=True, timeout=300)
