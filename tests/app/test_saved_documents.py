"""Documents saved by an older CadRobot open and export the programs recorded beside them.

``data/saved_documents/`` holds the paper's two example cells as saved by commit 2b7afb2
(before ``robots/`` was split into subpackages and ``api.py`` into one module per job),
and the programs exported from them in every built-in language, with SOURCE_DATE_EPOCH
pinned. A saved document keeps the module paths of its objects' proxies and every
property the old code wrote: moving code must not change what such a file gives. The
documents are never rewritten; CADROBOT_UPDATE_GOLDEN=1 rewrites the programs after a
reviewed change of the output (issue 20: zones on the paths' interior targets, which old
documents get too, and the other-maker note in the headers; their tools keep a constant
orientation on arcs, as when they were saved).
"""

import hashlib
import os
import shutil

import pytest

import FreeCAD
from CadRobotWB import api, posts

SAVED = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "saved_documents")
EPOCH = "946684800"   # 2000-01-01 00:00:00 UTC, as when the programs were written


def digest(path):
    with open(path, "rb") as stream:
        return hashlib.sha256(stream.read()).hexdigest()


@pytest.mark.parametrize("name", ["seam_cell", "profile_cell"])
def test_a_document_saved_before_opens_and_exports_the_same_programs(name, tmp_path, monkeypatch):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", EPOCH)
    saved = os.path.join(SAVED, name + ".FCStd")
    document_path = str(tmp_path / (name + ".FCStd"))     # same base name: programs name it
    shutil.copy(saved, document_path)
    before = digest(document_path)
    doc = FreeCAD.openDocument(document_path)
    try:
        cells = api.find_cells(doc)
        assert len(cells) == 1
        # Saved before paths could turn the tool with their arcs: they keep the marker's orientation.
        assert [p.ToolOnArcs for p in doc.Objects if hasattr(p, "ToolOnArcs")] == ["Constant"]
        for post in posts.BUILTIN:
            folder = tmp_path / post
            written = api.export(cells[0], post=post, output_dir=str(folder))
            expected_folder = os.path.join(SAVED, name, post)
            assert sorted(os.path.basename(p) for p in written) == sorted(os.listdir(expected_folder))
            for path in written:
                expected = os.path.join(expected_folder, os.path.basename(path))
                if os.environ.get("CADROBOT_UPDATE_GOLDEN"):
                    shutil.copy(path, expected)
                with open(path, "rb") as got, open(expected, "rb") as want:
                    assert got.read() == want.read(), "%s (%s) differs from what %s.FCStd gave " \
                        "when it was saved" % (os.path.basename(path), post, name)
    finally:
        FreeCAD.closeDocument(doc.Name)
    assert digest(document_path) == before, "exporting changed the input document"
