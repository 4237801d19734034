"""`cadrobot` progress on stderr, --quiet, and Ctrl-C (real processes).

Progress lines appear once the work has run for CADROBOT_PROGRESS_DELAY_S
seconds (default 2) and at most every CADROBOT_PROGRESS_INTERVAL_S (default
1); the tests set both to 0 for a long run (so the lines do not depend on
how fast this machine is) and the delay to an hour for a run that must print
nothing.  Ctrl-C is sent once the sweep has said it is running.
"""

import io
import json
import os
import re
import signal
import subprocess

import pytest

import FreeCAD
import helpers
from conftest import REPO, run_cadrobot, sha256

from CadRobotWB import cli

SEGMENTS = 400
LINE = re.compile(r"^cadrobot: (\w+): (.+) (\d+)%$")
ALWAYS = {"CADROBOT_PROGRESS_DELAY_S": "0", "CADROBOT_PROGRESS_INTERVAL_S": "0"}
NEVER = {"CADROBOT_PROGRESS_DELAY_S": "3600"}


@pytest.fixture(scope="module")
def long_file(tmp_path_factory):
    """A 400 mm seam of 1 mm lines over a block, all in reach: 400 targets."""
    doc = FreeCAD.newDocument("LongSeam")
    try:
        sketch = helpers.sketch_of(doc, helpers.polyline([(k, 0) for k in range(SEGMENTS + 1)]),
                                   name="Seam")
        block = doc.addObject("Part::Box", "Block")
        block.Length, block.Width, block.Height = SEGMENTS, 100, 10
        block.Placement.Base = FreeCAD.Vector(0, -100, -10)     # the seam on its top edge
        cell, _ = helpers.simple_cell(doc, sketch, markers=[(0, 0, 0)])
        cell.Placement = FreeCAD.Placement(FreeCAD.Vector(-700, 0, -950), FreeCAD.Rotation())
        cell.ToolTCP = FreeCAD.Placement(FreeCAD.Vector(0, 0, 150), FreeCAD.Rotation())   # a torch
        doc.recompute()
        path = str(tmp_path_factory.mktemp("long") / "long.FCStd")
        doc.saveAs(path)
    finally:
        FreeCAD.closeDocument(doc.Name)
    return path


def progress_lines(stderr, command):
    lines = stderr.splitlines()
    parsed = [LINE.match(line) for line in lines]
    assert all(parsed), stderr
    assert {m.group(1) for m in parsed} == {command}
    return [(m.group(2), int(m.group(3))) for m in parsed]


def test_a_long_check_prints_progress_lines_and_the_same_report(long_file):
    run = run_cadrobot("check", long_file, "--json", env=ALWAYS)
    assert run.returncode == 0, run.stderr
    lines = progress_lines(run.stderr, "check")
    assert len(lines) > 20
    percents = [p for _, p in lines]
    assert percents == sorted(percents) and percents[-1] == 100
    texts = {t for t, _ in lines}
    assert {"solving joints", "sampling moves", "checking targets", "timing moves"} <= texts, texts
    quiet = run_cadrobot("check", long_file, "--json", "--quiet", env=ALWAYS)
    assert quiet.returncode == 0 and quiet.stderr == ""
    assert json.loads(quiet.stdout) == json.loads(run.stdout)
    assert json.loads(run.stdout)["cells"][0]["targets"] >= SEGMENTS


def test_export_and_simulate_progress_and_quiet(long_file, tmp_path):
    run = run_cadrobot("export", long_file, "-o", str(tmp_path / "a"), env=ALWAYS)
    assert run.returncode == 0, run.stderr
    assert "writing the program (abb_rapid)" in {t for t, _ in progress_lines(run.stderr, "export")}
    run = run_cadrobot("export", long_file, "-o", str(tmp_path / "b"), "--quiet", env=ALWAYS)
    assert run.returncode == 0 and run.stderr == ""
    assert sha256(str(tmp_path / "a" / "Cell.mod")) == sha256(str(tmp_path / "b" / "Cell.mod"))


def test_a_short_run_prints_nothing(long_file):
    run = run_cadrobot("check", long_file, env=NEVER)
    assert run.returncode == 0 and run.stderr == "", run.stderr
    run = run_cadrobot("posts", "--quiet")
    assert run.returncode == 0 and run.stderr == ""


def test_every_subcommand_takes_quiet():
    needs = {"export": ["d"], "check": ["d"], "simulate": ["d", "--sensor", "laser"],
             "sweep": ["d", "--sensor", "laser", "--ranges", "x=0:1"],
             "place": ["d", "--region", "0,0,1,1"]}
    for command in ("export", "check", "simulate", "sweep", "place", "posts", "robots"):
        parser = cli.build_parser()
        assert parser.parse_args([command] + needs.get(command, []) + ["--quiet"]).quiet is True
        assert parser.parse_args([command] + needs.get(command, [])).quiet is False


def test_progress_lines_timing_with_a_clock():
    now = [0.0]
    err = io.StringIO()
    lines = cli.ProgressLines("check", err, delay_s=2.0, interval_s=1.0, clock=lambda: now[0])
    for t, fraction in ((0.5, 0.1), (1.9, 0.2), (2.0, 0.3), (2.5, 0.4), (3.1, 0.5), (3.2, 0.6)):
        now[0] = t
        assert lines(fraction, "sampling moves") is None
    assert err.getvalue() == ("cadrobot: check: sampling moves 30%\n"
                              "cadrobot: check: sampling moves 50%\n")
    quiet = io.StringIO()
    silent = cli.ProgressLines("check", quiet, quiet=True, delay_s=0, interval_s=0)
    silent(0.5, "x")
    assert quiet.getvalue() == ""
    two = cli.ProgressLines("export", io.StringIO(), delay_s=0, interval_s=0)
    part = two.part(1, 2, "Cell2")
    part(0.5, "solving joints")
    assert two.err.getvalue() == "cadrobot: export: Cell2: solving joints 75%\n"


def test_ctrl_c_exits_130_with_one_line_and_writes_nothing(long_file, tmp_path):
    out = tmp_path / "sweep"
    env = dict(os.environ, **ALWAYS)
    env.pop("PYTEST_CURRENT_TEST", None)
    proc = subprocess.Popen(
        [os.path.join(REPO, "cadrobot"), "sweep", long_file, "--sensor", "laser", "--ranges",
         "x=-1:1", "--runs", "500", "--workers", "1", "-o", str(out)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    seen = []
    try:
        for line in proc.stderr:            # wait until the runs are under way
            seen.append(line)
            if " runs " in line:
                break
        proc.send_signal(signal.SIGINT)
        rest = proc.stderr.read()
        proc.wait(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130, (seen, rest)
    others = [line for line in rest.splitlines() if not LINE.match(line)]
    assert others == ["cadrobot: interrupted: nothing was written."], rest
    assert "Traceback" not in rest
    assert not out.exists()
