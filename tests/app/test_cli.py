"""The `cadrobot` launcher as a user runs it: real processes, real files."""

import json

import pytest

import FreeCAD
from conftest import run_cadrobot, sha256
from rapid_check import assert_rapid_ok, needs_rapidchecker


@needs_rapidchecker
def test_export_writes_the_module_and_leaves_the_document_unchanged(seam_file, tmp_path):
    before = sha256(seam_file)
    run = run_cadrobot("export", seam_file, "--post", "abb_rapid", "-o", "out", cwd=str(tmp_path))
    assert run.returncode == 0, run.stderr
    module = tmp_path / "out" / "SeamWeld.mod"
    assert run.stdout.strip() == "SeamCell: wrote %s" % module
    assert_rapid_ok(module.read_text())
    assert "MoveL" in module.read_text()
    assert sha256(seam_file) == before


def test_export_json(seam_file, tmp_path):
    run = run_cadrobot("export", seam_file, "-o", str(tmp_path), "--json")
    assert run.returncode == 0, run.stderr
    result = json.loads(run.stdout)   # stdout is clean JSON: no FreeCAD banner
    assert result == {"ok": True, "cells": [{"cell": "SeamCell", "post": "abb_rapid",
                                             "files": [str(tmp_path / "SeamWeld.mod")]}]}


@pytest.mark.parametrize("args, words", [
    (["export", "{doc}", "--post", "brand_x", "-o", "{out}"], ["Unknown post-processor 'brand_x'"]),
    (["export", "{doc}", "--cell", "Nope", "-o", "{out}"], ["no cell 'Nope'", "SeamCell"]),
    (["export", "{text}", "-o", "{out}"], ["is not a FreeCAD document"]),
    (["export", "{missing}", "-o", "{out}"], ["does not exist"]),
    (["export", "{doc}", "--frobnicate", "-o", "{out}"], ["unrecognized arguments: --frobnicate"]),
    (["launch"], ["invalid choice: 'launch'"]),
])
def test_bad_input_is_one_line_and_exit_2(seam_file, tmp_path, args, words):
    text = tmp_path / "notes.FCStd"
    text.write_text("not a zip file")
    values = {"doc": seam_file, "out": str(tmp_path / "out"), "text": str(text),
              "missing": str(tmp_path / "missing.FCStd")}
    run = run_cadrobot(*[a.format(**values) for a in args])
    assert run.returncode == 2, (run.stdout, run.stderr)
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("cadrobot: error: "), run.stderr
    for word in words:
        assert word in lines[0]
    assert "Traceback" not in run.stderr
    assert not (tmp_path / "out").exists()


def test_document_with_a_broken_cell_names_the_object(tmp_path):
    import helpers
    doc = FreeCAD.newDocument("Broken")
    try:
        sketch = helpers.sketch_of(doc, helpers.polyline([(0, 0), (50, 0), (50, 40)]), name="Seam2")
        helpers.simple_cell(doc, sketch, markers=[(50, 20, 0)])     # on segment 2, none on 1
        path = str(tmp_path / "broken.FCStd")
        doc.saveAs(path)
    finally:
        FreeCAD.closeDocument(doc.Name)
    before = sha256(path)
    run = run_cadrobot("export", path, "-o", str(tmp_path / "out"), "--json")
    assert run.returncode == 2
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in run.stderr, run.stderr
    assert "Path 'Path': segment 1 (line, Seam2.Edge" in lines[0]
    assert "comes before its first tool marker 'ToolMarker' (on segment 2)" in lines[0]
    assert "Place a tool marker on segment 1" in lines[0]
    error = json.loads(run.stdout)
    assert error["ok"] is False and error["object"] == "Path" and error["kind"] == "MarkerError"
    assert not (tmp_path / "out").exists()
    assert sha256(path) == before


def test_listings_and_help():
    posts = run_cadrobot("posts", "--json")
    assert posts.returncode == 0 and {"name": "abb_rapid"}.items() <= json.loads(posts.stdout)[0].items()
    robots = run_cadrobot("robots")
    names = [line.split()[0] for line in robots.stdout.splitlines()]
    assert robots.returncode == 0 and {"ABB_IRB2400", "MOTOMAN_HP6", "KUKA_KR16"} <= set(names)
    usage = run_cadrobot("export", "--help")
    assert usage.returncode == 0 and "--post" in usage.stdout and "DOC.FCStd" in usage.stdout
    version = run_cadrobot("--version")
    assert version.returncode == 0 and version.stdout.startswith("cadrobot ")


def test_export_passes_post_options(seam_file, tmp_path):
    run = run_cadrobot("export", seam_file, "-o", str(tmp_path), "--option", "path_correction=true",
                       "--option", "correction_rate_hz=4")
    assert run.returncode == 0, run.stderr
    text = (tmp_path / "SeamWeld.mod").read_text()
    assert "CorrCon cdSensor;" in text and "ITimer 0.25, irSensor;" in text and "\\Corr;" in text
    bad = run_cadrobot("export", seam_file, "-o", str(tmp_path / "x"), "--option", "nonsense")
    assert bad.returncode == 2 and "KEY=VALUE" in bad.stderr
