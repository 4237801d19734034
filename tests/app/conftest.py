"""App-tier fixtures: real FreeCAD documents (these tests run inside FreeCADCmd)."""

import hashlib
import os
import subprocess
import sys

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


def run_cadrobot(*args, cwd=None):
    """Run the real `cadrobot` launcher; returns CompletedProcess (text)."""
    env = dict(os.environ)
    env.pop("PYTEST_CURRENT_TEST", None)
    return subprocess.run([os.path.join(REPO, "cadrobot")] + [str(a) for a in args],
                          cwd=cwd, env=env, capture_output=True, text=True, timeout=300)
