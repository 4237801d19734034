"""The `cadrobot` launcher as a user runs it: real processes, real files."""

import json
import os

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
    assert {"FANUC_CRX10IAL", "MOTOMAN_HC10", "ABB_CRB15000_5_95", "KUKA_KR10_R1100_3",
            "MOTOMAN_MPX3500"} <= set(names)       # neither OPW nor UR (issue 24)
    crx = next(line for line in robots.stdout.splitlines() if line.startswith("FANUC_CRX10IAL "))
    assert "FANUC CRX10IAL 10 kg reach 1250 mm" in crx
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


def test_no_arguments_is_one_usage_line_on_stderr():
    run = run_cadrobot()
    assert run.returncode == 2 and run.stdout == ""
    [line] = run.stderr.splitlines()
    assert line.startswith("cadrobot: error: give a command: usage: cadrobot ")
    assert "export, check, simulate, sweep, place, posts, robots" in line


def test_a_damaged_document_gives_our_line_only(seam_file, tmp_path):
    import bad_documents
    damaged = bad_documents.write_damaged_file("truncated_xml", tmp_path, seam_file)
    before = sha256(damaged)
    run = run_cadrobot("export", damaged, "-o", str(tmp_path / "out"))
    assert run.returncode == 2, run.stderr
    # FreeCAD's own parser says "Fatal Error at file ..." first unless we check the file ourselves.
    assert run.stderr.splitlines() == [
        "cadrobot: error: '%s' is damaged: Document.xml (unclosed token: line %s) cannot be read. "
        "Open a backup (FreeCAD keeps 'truncated_xml.FCBak' files) or save the document again "
        "from FreeCAD." % (damaged, run.stderr.split("unclosed token: line ")[1].split(")")[0])]
    assert not (tmp_path / "out").exists() and sha256(damaged) == before


@pytest.mark.parametrize("package, words", [
    ("numpy", ["the Python package 'numpy' cannot be imported by FreeCAD's Python"]),
    ("trimesh", ["CadRobot cannot run: trimesh is not installed", "Addon Manager"]),
])
def test_a_missing_package_is_one_error_line_not_an_internal_error(seam_file, tmp_path, package, words):
    run = run_cadrobot("export", seam_file, "-o", str(tmp_path / "out"), without=[package])
    assert run.returncode == 2, run.stderr
    [line] = run.stderr.splitlines()
    assert line.startswith("cadrobot: error: ") and "internal error" not in line
    for word in words:
        assert word in line
    assert not (tmp_path / "out").exists()


def test_posts_lists_every_option_of_a_post_that_declares_them():
    from CadRobotWB import posts
    run = run_cadrobot("posts", "--json")
    listed = {p["name"]: p["options"] for p in json.loads(run.stdout)}
    assert list(listed) == list(posts.BUILTIN)
    for name in posts.BUILTIN:
        assert listed[name] == dict(getattr(posts.get(name), "OPTIONS", None) or {})
    text = run_cadrobot("posts").stdout
    for name, options in listed.items():
        for option, help_text in options.items():
            assert "  --option %s=...  %s\n" % (option, help_text) in text


def test_a_user_post_that_declares_options_refuses_others_in_one_line(seam_file, tmp_path,
                                                                      monkeypatch, capfd):
    import io
    from CadRobotWB import api, cli
    from CadRobotWB.workflow import export as api_export
    (tmp_path / "strict_post.py").write_text(
        "from CadRobotWB.posts import abb_rapid, common\n"
        "NAME = 'strict'\nDESCRIPTION = 'RAPID that takes one option'\n"
        "OPTIONS = {'date': 'export date', 'verbose': 'true or false'}\n"
        "def export(program, options):\n"
        "    common.bool_option(options, 'verbose', False)\n"
        "    return abb_rapid.export(program, {'date': options['date']})\n")
    # api.user_post_dirs for the CLI's own calls, workflow.export's for post_names and export
    for module in (api, api_export):
        monkeypatch.setattr(module, "user_post_dirs", lambda: [str(tmp_path)])

    def run(*argv):
        out, err = io.StringIO(), io.StringIO()
        capfd.readouterr()
        code = cli.main(list(argv), out=out, err=err)
        return code, (err.getvalue() + capfd.readouterr().err).splitlines(), out.getvalue()

    assert "  --option verbose=...  true or false\n" in run("posts")[2]
    out = tmp_path / "out"
    for option, word in (("verbos=true", "verbos"), ("verbose=maybe", "verbose")):
        code, lines, _ = run("export", seam_file, "--post", "strict", "--option", option, "-o", str(out))
        assert code == 2 and len(lines) == 1, lines
        assert lines[0].startswith("cadrobot: error: ") and word in lines[0]
        assert not out.exists()
    code, lines, _ = run("export", seam_file, "--post", "strict", "--option", "verbose=true",
                         "-o", str(out))
    assert code == 0 and os.listdir(out) == ["SeamWeld.mod"], lines


def test_export_with_another_makers_post_says_so_in_the_program(seam_file, tmp_path):
    """--post kuka_krl for the seam cell's ABB IRB 2400: written, with the note in its header."""
    run = run_cadrobot("export", seam_file, "--post", "kuka_krl", "-o", str(tmp_path), "--json")
    assert run.returncode == 0, run.stderr
    src = (tmp_path / "SeamWeld.src").read_text()
    assert "; Written for a KUKA KR C4 controller, but the cell's robot is an ABB IRB\n" in src
    assert json.loads(run.stdout)["cells"][0]["post"] == "kuka_krl"
