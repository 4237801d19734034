"""Through-arc tracking from the document (issue 22): a path without a weld is refused in one
line; a weld without a weave is refused with the sentence; a woven weld runs the arc tracker
through api.simulate and the CLI, on a butt joint (named as one it cannot sense) and on a T-joint
fillet (the issue's case: 3 mm across and 2 mm up, corrected).
"""

import numpy as np
import pytest

from CadRobotWB import api, simulation
from CadRobotWB.errors import InputError
from CadRobotWB.objects import base
from CadRobotWB.sensors.joint_detection import ARC_NO_SIDEWALLS, NO_WEAVE
from conftest import run_cadrobot
import helpers

SCHEDULE = {"wire_feed_m_min": 6.7, "voltage_v": 27.5, "current_a": 265.0,
            "travel_speed_mm_s": 10.0, "ctwd_mm": 15.0}
WEAVE = {"pattern": "zigzag", "width_mm": 4.0, "frequency_hz": 2.0}


@pytest.fixture
def welded(seam_cell):
    """Weld the seam cell's path with SCHEDULE and the weave given (None: no weave)."""
    def with_weld(weave):
        doc = seam_cell.Document
        path = base.objects_of_type(doc, "RobotPath")[0]
        api.make_weld(doc, seam_cell, path, schedule=SCHEDULE, weave=weave,
                      tracking="arc" if weave else None, name="SeamWeld")
    return with_weld


def test_a_path_without_a_weld_is_refused_in_one_line(seam_cell):
    with pytest.raises(InputError) as refused:
        api.simulate(seam_cell, sensor="arc")
    assert str(refused.value).startswith("Path '")
    assert "has no weld: through-arc tracking senses the arc of a weld; add a Weld with a " \
           "weave to the path." in str(refused.value)
    assert simulation.arc_why_not(seam_cell).startswith("the path has no weld")


def test_a_weld_without_a_weave_is_refused_with_the_sentence(seam_cell, welded):
    welded(None)
    with pytest.raises(InputError) as refused:
        api.simulate(seam_cell, sensor="arc")
    assert str(refused.value) == "Weld 'SeamWeld': %s." % NO_WEAVE
    assert simulation.arc_why_not(seam_cell) == NO_WEAVE


def test_a_woven_weld_runs_the_arc_tracker_and_the_butt_joint_is_named(seam_cell, welded):
    welded(WEAVE)
    detection = simulation.path_fit(seam_cell)
    assert simulation.arc_why_not(seam_cell, detection) == ARC_NO_SIDEWALLS
    run = api.simulate(seam_cell, sensor="arc", controller="none", arc_current_noise_a=0.0)
    assert run.sensor == "arc" and run.controller == "none" and not run.aborted, run.reason
    assert run.metrics["weave_cycles"] >= 10
    assert np.nanmax(run.error_mm) < 1e-6          # as drawn: the weave centre is on the seam
    assert any(ARC_NO_SIDEWALLS in note for note in run.notes)
    with pytest.raises(InputError, match="once per weave cycle"):
        api.simulate(seam_cell, sensor="arc", rate_hz=5.0)


def test_the_cli_refuses_an_unwelded_path_in_one_line(seam_file, tmp_path):
    result = run_cadrobot("simulate", str(seam_file), "--sensor", "arc", "-o", str(tmp_path))
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("cadrobot: error: Path 'Seam'"), result.stderr
    assert "has no weld" in lines[0]


def test_the_arc_tracks_a_fillet_moved_3_mm_across_and_2_mm_up(doc, tmp_path):
    cell, path, _ = helpers.fillet_cell(doc)
    api.make_weld(doc, cell, path, weave=dict(WEAVE, dwell_left_s=0.1, dwell_right_s=0.1),
                  tracking="arc")
    run = api.simulate(cell, sensor="arc", deviation=(0, 3, 2, 0, 0, 0), seed=1)
    assert not run.aborted, run.reason
    open_loop = run.metrics["open_loop_rms_error_mm"]
    assert open_loop == pytest.approx(np.hypot(3, 2), abs=0.01)
    assert run.metrics["rms_error_after_20mm_mm"] < open_loop / 5
    saved = str(tmp_path / "fillet.FCStd")
    doc.saveAs(saved)
    result = run_cadrobot("simulate", saved, "--sensor", "arc", "--controller", "pi",
                          "--deviation", "0,3,2,0,0,0", "-o", str(tmp_path / "out"))
    assert result.returncode == 0, result.stderr
    assert "a joint through-arc tracking can follow: its walls change the current across the " \
           "weave" in result.stdout.splitlines()[0]
