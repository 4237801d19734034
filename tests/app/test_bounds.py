"""Bounded work, link cycles and outputs checked before the work, through the CLI and the API.

Every refusal: exit 2 (a CadRobotError in the API), one line naming the option, argument
or objects and what to give, nothing written, the input unchanged.  The option cases run
``cli.main`` in this process (as test_cli_fuzz does); the link cycle also through the real
launcher, where FreeCAD crashed (exit -11) before.
"""

import io
import os
import shutil

import pytest

import FreeCAD
import bad_documents
from CadRobotWB import api, cli, limits, simulation
from CadRobotWB.errors import CadRobotError, DocumentError, InputError
from conftest import run_cadrobot, sha256
from helpers import polyline, sketch_of


@pytest.fixture(scope="module")
def files(seam_file, tmp_path_factory):
    """The seam document, the link-cycle document and one whose path links into a missing file."""
    folder = tmp_path_factory.mktemp("bounds")
    return {"doc": seam_file, "cycle": bad_documents.save_defect("link_cycle", folder),
            "missing": _link_into_a_missing_file(folder)}


def _link_into_a_missing_file(folder):
    """main.FCStd, whose path follows an App::Link to a sketch of parts.FCStd, then deleted."""
    parts = FreeCAD.newDocument("Parts")
    main = FreeCAD.newDocument("Main")
    try:
        sketch = sketch_of(parts, polyline([(0, 0), (50, 0), (50, 40)]), name="PartSeam")
        parts.saveAs(str(folder / "parts.FCStd"))
        main.saveAs(str(folder / "main.FCStd"))        # a link into another file needs a saved owner
        _, path = bad_documents.good_cell(main)
        link = main.addObject("App::Link", "SeamLink")
        link.LinkedObject = sketch
        path.Source = [(link, [""])]
        main.recompute()
        main.save()
    finally:
        FreeCAD.closeDocument(main.Name)
        FreeCAD.closeDocument(parts.Name)
    os.remove(str(folder / "parts.FCStd"))
    return str(folder / "main.FCStd")


def run_cli(argv, capfd):
    """(exit code, stderr lines) of cli.main(argv) in this process; fd 2 counted too."""
    out, err = io.StringIO(), io.StringIO()
    capfd.readouterr()
    code = cli.main(argv, out=out, err=err)
    return code, (err.getvalue() + capfd.readouterr().err).splitlines()


#: (argv template, words of the one line). {doc}: the seam document; {out}: a new folder.
CASES = [
    (["sweep", "{doc}", "--sensor", "laser", "--ranges", "y=-1:1", "--runs", "100000", "-o", "{out}"],
     ["--runs", "<= 10000"]),
    (["sweep", "{doc}", "--sensor", "laser", "--ranges", "y=-1:1", "--workers", "256", "-o", "{out}"],
     ["--workers", "<= %d" % limits.cores()]),
    (["sweep", "{doc}", "--sensor", "laser", "--ranges", "y=-1:1", "--rate", "5e-324", "-o", "{out}"],
     ["--rate", ">= 0.1"]),
    (["simulate", "{doc}", "--sensor", "laser", "--rate", "5e-324", "-o", "{out}"], ["--rate", ">= 0.1"]),
    (["simulate", "{doc}", "--sensor", "laser", "--rate", "1e308", "-o", "{out}"], ["rate", "<= 100"]),
    (["place", "{doc}", "--region=-1e308,-1e308,1e308,1e308"], ["--region", "<= 1000000"]),
    (["place", "{doc}", "--region=-1500,-400,-300,400", "--turn=-1e308,1e308", "--turn-step", "1e307"],
     ["--turn", "<= 360"]),
    (["place", "{doc}", "--region=-1e6,-1e6,1e6,1e6", "--step", "1e-300"],
     ["'SeamCell'", "grid step of 1e-300 mm", "more than the 250000 bases"]),
    (["place", "{doc}", "--region=-1500,-400,-300,400", "--count", "2147483647"], ["--count", "<= 100"]),
    (["simulate", "{doc}", "--sensor", "laser", "-o", "{doc}"],
     ["Cannot create output folder", "it is a file (the input document)"]),
    (["sweep", "{doc}", "--sensor", "laser", "--ranges", "y=-1:1", "--runs", "2", "--workers", "1",
      "-o", "{doc}"], ["Cannot create output folder", "it is a file (the input document)"]),
    (["check", "{missing}"], ["'SeamLink'", "links into '", "parts.FCStd', which does not exist"]),
    (["export", "{missing}", "-o", "{out}"], ["parts.FCStd', which does not exist"]),
]


CASE_IDS = ["sweep-runs", "sweep-workers", "sweep-rate", "simulate-rate-tiny", "simulate-rate-huge",
            "place-region-1e308", "place-turn-1e308", "place-step-1e-300", "place-count",
            "simulate-o-input", "sweep-o-input", "check-missing-file", "export-missing-file"]


@pytest.mark.parametrize("argv, words", CASES, ids=CASE_IDS)
def test_a_value_past_its_limit_is_refused_in_one_line_before_any_work(files, tmp_path, capfd,
                                                                     monkeypatch, argv, words):
    monkeypatch.setattr(simulation, "simulate_cell", _no_work)
    monkeypatch.setattr(simulation, "read_scene", _no_work)
    out = tmp_path / "out"
    argv = [a.format(out=str(out), **files) for a in argv]
    inputs = {p: sha256(p) for p in argv if os.path.isfile(p)}
    code, lines = run_cli(argv, capfd)
    assert code == 2 and len(lines) == 1 and lines[0].startswith("cadrobot: error: "), (code, lines)
    for word in words:
        assert word in lines[0], lines[0]
    assert not out.exists()
    assert {p: sha256(p) for p in inputs} == inputs


def _no_work(*args, **kwargs):
    raise AssertionError("the run started before its arguments were checked")


@pytest.mark.parametrize("name, words", [
    ("report.json", ["Writing 'report.json' into", "would overwrite the input"]),
    ("paths.png", ["Writing 'paths.png' into", "would overwrite the input"]),
])
def test_simulate_refuses_an_input_among_its_outputs_before_it_runs(files, tmp_path, capfd,
                                                                    monkeypatch, name, words):
    monkeypatch.setattr(simulation, "simulate_cell", _no_work)
    document = tmp_path / "in" / name
    document.parent.mkdir()
    shutil.copy(files["doc"], str(document))
    before = sha256(str(document))
    code, lines = run_cli(["simulate", str(document), "--sensor", "laser", "-o", str(document.parent)],
                          capfd)
    assert code == 2 and len(lines) == 1, lines
    for word in words:
        assert word in lines[0], lines[0]
    assert os.listdir(str(document.parent)) == [name] and sha256(str(document)) == before


@pytest.mark.parametrize("command", ["check", "export"])
def test_a_link_cycle_is_one_line_through_the_real_launcher_not_a_crash(files, tmp_path, command):
    out = tmp_path / "out"
    before = sha256(files["cycle"])
    result = run_cadrobot(command, files["cycle"], *(["-o", out] if command == "export" else []),
                          env={"CADROBOT_PROGRESS_DELAY_S": "3600"})
    assert result.returncode == 2, (result.returncode, result.stderr[-300:])
    assert result.stderr.splitlines() == [
        "cadrobot: error: Document '%s': the links of 'SeamLink' (LinkA) -> 'BackLink' (LinkB) -> "
        "'SeamLink' (LinkA) form a cycle, which FreeCAD cannot follow. Open it in FreeCAD and point "
        "one of these links at another object." % files["cycle"]]
    assert not out.exists() and sha256(files["cycle"]) == before


def test_the_api_refuses_a_link_cycle_of_an_open_document_before_reading_shapes(files):
    doc = FreeCAD.openDocument(files["cycle"])
    try:
        with pytest.raises(DocumentError, match=r"'SeamLink' \(LinkA\) -> 'BackLink' \(LinkB\)"):
            api.check(api.find_cells(doc)[0])
    finally:
        FreeCAD.closeDocument(doc.Name)


@pytest.mark.parametrize("kwargs, words", [
    ({"region": (-1e308, -1e308, 1e308, 1e308)}, "region (xmin, ymin, xmax, ymax) must hold numbers >= "
                                                  "-1000000 and <= 1000000 mm"),
    ({"region": (0, 0, 1, 1), "z_mm": (float("nan"), 0)}, "z_mm (the height range) must hold numbers"),
    ({"region": (0, 0, 1, 1), "turn_deg": (-1e308, 1e308)}, "turn_deg (the turn range) must hold "
                                                             "numbers >= -360 and <= 360 deg"),
    ({"region": (0, 0, 1, 1), "count": 1000}, "count (placements to find) must be a whole number >= 1 "
                                               "and <= 100, not 1000"),
])
def test_place_robot_refuses_sizes_past_their_limits_before_reading_the_cell(seam_cell, monkeypatch,
                                                                           kwargs, words):
    from CadRobotWB.workflow import place
    monkeypatch.setattr(place.reader, "read_cell", _no_work)
    with pytest.raises(InputError) as caught:
        api.place_robot(seam_cell, **kwargs)
    assert "Cell 'SeamCell'" in str(caught.value) and words in str(caught.value)


@pytest.mark.parametrize("rate", [5e-324, 0.05, 1e308])
def test_simulate_refuses_a_rate_past_its_limits(seam_cell, rate):
    with pytest.raises(CadRobotError, match="The laser correction rate \\(Hz\\) must be a finite "
                                            "number >= 0.1 and <= 100"):
        api.simulate(seam_cell, "laser", rate_hz=rate)
