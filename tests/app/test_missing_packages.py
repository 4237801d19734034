"""The CLI on a FreeCAD without an optional package: everything else works, and
one line on stderr says what is missing and how to install it."""

import json
import os

from conftest import run_cadrobot


def warning_lines(stderr):
    return [line for line in stderr.splitlines() if line.startswith("cadrobot: warning: ")]


def test_check_without_fcl_checks_everything_but_collisions_and_says_so(seam_file):
    run = run_cadrobot("check", seam_file, without=["fcl"])
    assert run.returncode == 0, run.stderr
    lines = run.stdout.splitlines()
    # The first line says it: never "0 errors, 0 warnings" alone.
    assert lines[0].startswith("SeamCell: NOT CHECKED: collisions: python-fcl is not installed "
                               "for FreeCAD's Python"), run.stdout
    assert lines[1].startswith("SeamCell: OK: 13 targets")
    assert run.stderr.strip().splitlines() == warning_lines(run.stderr)
    [warning] = warning_lines(run.stderr)
    assert warning.startswith("cadrobot: warning: collisions not checked: python-fcl is not installed")
    assert "Addon Manager" in warning and "-m pip install --target" in warning
    as_json = run_cadrobot("check", seam_file, "--json", without=["fcl"])
    cell = json.loads(as_json.stdout)["cells"][0]
    assert cell["ok"] and cell["not_checked"]["collisions"].startswith("python-fcl is not installed")
    assert cell["headline"] == "Collisions NOT checked: python-fcl is not installed."


def test_export_without_fcl_writes_the_program_and_warns_once(seam_file, tmp_path):
    run = run_cadrobot("export", seam_file, "-o", str(tmp_path), without=["fcl"])
    assert run.returncode == 0, run.stderr
    assert run.stdout == "SeamCell: wrote %s\n" % (tmp_path / "SeamWeld.mod")
    assert len(warning_lines(run.stderr)) == 1 and "collisions not checked" in run.stderr
    assert "Traceback" not in run.stderr and "internal error" not in run.stderr


def test_simulate_without_matplotlib_writes_the_report_and_programs_but_no_plots(seam_file, tmp_path):
    out = tmp_path / "out"
    run = run_cadrobot("simulate", seam_file, "--sensor", "laser", "--deviation", "0,5,2,0,0,1",
                       "-o", str(out), without=["matplotlib"])
    assert run.returncode == 0, run.stderr
    assert sorted(e for e in os.listdir(out) if not e.startswith(".")) == [
        "SeamWeld_corrected.mod", "report.json"]
    report = json.loads((out / "report.json").read_text())
    assert report["plots_not_written"].startswith("plots not written: matplotlib is not installed")
    [warning] = warning_lines(run.stderr)
    assert warning == "cadrobot: warning: " + report["plots_not_written"]


def test_a_cluster_sweep_without_dask_is_one_clear_error(seam_file, tmp_path):
    run = run_cadrobot("sweep", seam_file, "--sensor", "laser", "--ranges", "y=-1:1", "--runs", "2",
                       "--scheduler", "local", "-o", str(tmp_path), without=["dask", "distributed"])
    assert run.returncode == 2, run.stderr
    [line] = run.stderr.strip().splitlines()
    assert line.startswith("cadrobot: error: no sweep on a Dask cluster: distributed is not installed")
    assert line.endswith("or run the sweep without a scheduler, on this computer's cores.")
    assert os.listdir(tmp_path) == []
