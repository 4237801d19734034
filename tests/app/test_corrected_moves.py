"""The corrected program of the paper's seam run: few lines and arcs, within tolerance.

The tolerance is checked on the moves as the robot runs them
(``core.trajectory.tcp_trajectory``, 1 ms steps), not on the fitter's numbers.
"""

import json

import numpy as np
import pytest
from scipy.spatial import cKDTree

from CadRobotWB import api, simulation
from CadRobotWB.core import program as ir
from CadRobotWB.core.trajectory import tcp_trajectory
from CadRobotWB.sensors.corrected_program import DEFAULT_TOLERANCE_MM
from conftest import run_cadrobot

from rapid_check import assert_rapid_ok

PAPER_DEVIATION = (0, 5, 2, 0, 0, 1)


def test_the_seam_runs_corrected_program_has_few_moves_within_tolerance(seam_cell):
    scene, _reality, (run,) = simulation.simulate_cell(seam_cell, "laser", ("pi",), PAPER_DEVIATION)
    corrected = simulation.corrected_after(scene, run)
    path = [m for m in corrected.moves() if m.role == ir.ROLE_PATH]
    assert run.metrics["corrected_samples"] == len(run.time_s) == 4201      # 420 mm at 10 mm/s, 10 ms
    assert run.metrics["corrected_moves"] == len(path) <= 50          # lines only, thinned: 203
    assert run.metrics["corrected_arcs"] == sum(m.kind == ir.CIRCULAR for m in path) > 0
    assert run.metrics["corrected_tolerance_mm"] == DEFAULT_TOLERANCE_MM
    first = corrected.moves().index(path[0])
    dense = tcp_trajectory(corrected, 0.001, first, first + len(path) - 1).position_mm
    distance, _ = cKDTree(dense).query(run.actual_mm)
    assert distance.max() <= DEFAULT_TOLERANCE_MM + 0.01 / 2      # 10 mm/s x 1 ms sampling
    assert all(t.joints_deg is not None for t in corrected.targets())


def test_api_simulate_and_the_cli_report_the_move_counts(seam_cell, tmp_path):
    run = api.simulate(seam_cell, sensor="laser", deviation=PAPER_DEVIATION)
    assert run.metrics["corrected_samples"] == len(run.time_s)
    assert 0 < run.metrics["corrected_moves"] <= 50
    opened = api.simulate(seam_cell, sensor="laser", deviation=PAPER_DEVIATION, controller="none")
    assert "corrected_moves" not in opened.metrics           # open loop: no corrected program
    path = str(tmp_path / "seam.FCStd")
    seam_cell.Document.saveAs(path)
    cli = run_cadrobot("simulate", path, "--sensor", "laser", "--deviation", "0,5,2,0,0,1",
                       "-o", str(tmp_path / "out"))
    assert cli.returncode == 0, cli.stderr
    metrics = json.loads((tmp_path / "out" / "report.json").read_text())["runs"][0]["metrics"]
    moves = metrics["corrected_moves"]          # (the CLI's run, with an open-loop one beside it)
    assert 0 < moves <= 50 and metrics["corrected_samples"] == len(run.time_s)
    assert "corrected_samples=%d, corrected_moves=%d, corrected_arcs=%d, corrected_tolerance_mm=0.05" % (
        len(run.time_s), moves, metrics["corrected_arcs"]) in cli.stdout
    module = (tmp_path / "out" / "SeamWeld_corrected.mod").read_text()
    assert module.count("\n    MoveL ") + module.count("\n    MoveC ") == moves + 2   # + entry, retract
    assert_rapid_ok(module)


@pytest.mark.parametrize("tolerance_mm", [0.02, 0.2])
def test_a_looser_tolerance_gives_fewer_moves(seam_cell, tolerance_mm):
    scene, _reality, (run,) = simulation.simulate_cell(seam_cell, "laser", ("pi",), PAPER_DEVIATION)
    default = run.metrics["corrected_moves"]
    corrected = simulation.corrected_after(scene, run, tolerance_mm=tolerance_mm)
    moves = run.metrics["corrected_moves"]
    assert (moves > default) if tolerance_mm < DEFAULT_TOLERANCE_MM else (moves < default)
    first = next(i for i, m in enumerate(corrected.moves()) if m.role == ir.ROLE_PATH)
    dense = tcp_trajectory(corrected, 0.001, first, first + moves - 1).position_mm
    assert cKDTree(dense).query(run.actual_mm)[0].max() <= tolerance_mm + 0.005
    assert np.isfinite(dense).all()
