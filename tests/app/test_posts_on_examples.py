"""Every post on the paper's two example cells: golden files, and the same program
read back from each language.

Dates are pinned with SOURCE_DATE_EPOCH so the files compare byte for byte;
CADROBOT_UPDATE_GOLDEN=1 rewrites them after a reviewed change.
"""

import os

import numpy as np
import pytest

from CadRobotWB import api, posts
from rapid_check import assert_rapid_ok, needs_rapidchecker

GOLDEN = os.path.join(os.path.dirname(__file__), "golden", "posts")
EPOCH = "946684800"   # 2000-01-01 00:00:00 UTC


def exported(cell, post, folder, monkeypatch):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", EPOCH)
    return {os.path.basename(p): open(p, newline="").read()
            for p in api.export(cell, post=post, output_dir=str(folder))}


def compare_with_golden(files, prefix):
    os.makedirs(GOLDEN, exist_ok=True)
    for name, text in files.items():
        path = os.path.join(GOLDEN, "%s_%s" % (prefix, name))
        if os.environ.get("CADROBOT_UPDATE_GOLDEN"):
            with open(path, "w", newline="") as handle:
                handle.write(text)
        with open(path, newline="") as handle:
            assert text == handle.read(), "%s differs from its golden file" % name


@pytest.mark.parametrize("post", posts.BUILTIN)
def test_seam_cell_in_every_language(seam_cell, tmp_path, monkeypatch, post):
    files = exported(seam_cell, post, tmp_path, monkeypatch)
    compare_with_golden(files, "seam_" + post)
    text = "".join(files.values())
    assert "Seam" in text or "SEAM" in text            # comments name the source path


@pytest.mark.parametrize("post", posts.BUILTIN)
def test_profile_cell_in_every_language(doc, tmp_path, monkeypatch, post):
    import profile_following_cell
    cell = profile_following_cell.build(doc)
    compare_with_golden(exported(cell, post, tmp_path, monkeypatch), "profile_" + post)


@needs_rapidchecker
def test_seam_cell_rapid_passes_rapidchecker(seam_cell, tmp_path, monkeypatch):
    for text in exported(seam_cell, "abb_rapid", tmp_path, monkeypatch).values():
        assert_rapid_ok(text)


def test_motoman_job_positions_are_the_seam_in_the_user_frame(seam_cell, tmp_path, monkeypatch):
    """The NX100 job's C positions, read back, are the seam corners in the table-corner frame."""
    text = exported(seam_cell, "motoman_inform", tmp_path, monkeypatch)["SEAMWELD.JBI"]
    rows = [line.split("=", 1)[1] for line in text.splitlines() if line.startswith("C0")]
    xyz = np.array([[float(v) for v in row.split(",")[:3]] for row in rows])
    for corner in ((100, 150, 8), (300, 150, 8), (320, 150, 8), (320, 170, 8), (320, 350, 8)):
        assert np.min(np.linalg.norm(xyz - corner, axis=1)) < 1e-3
