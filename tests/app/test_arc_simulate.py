"""Through-arc tracking from the document (issue 22): a path without a weld is refused in one
line; a weld with a weave runs the arc tracker through api.simulate; Sensor run's reason.

The Weld document object and the generator's WeldRuns are other parts of issue 22: until they
are merged, the weld is added to the generated program here (simulation.generate_program
wrapped, reader.read_cell's PathSpec.welds filled).
"""

import numpy as np
import pytest

from CadRobotWB import api, simulation
from CadRobotWB.core import program as ir
from CadRobotWB.core.welding import Tracking, Weave, WeldSchedule, WeldSpec
from CadRobotWB.errors import InputError
from CadRobotWB.objects import reader
from CadRobotWB.sensors.joint_detection import ARC_NO_SIDEWALLS, NO_WEAVE
from conftest import run_cadrobot

SCHEDULE = WeldSchedule(name="butt_t8", wire_feed_m_min=6.7, voltage_v=27.5, current_a=265.0,
                        travel_speed_mm_s=10.0, ctwd_mm=15.0).validated()
WEAVE = Weave("zigzag", width_mm=4.0, frequency_hz=2.0).validated()


@pytest.fixture
def welded(monkeypatch):
    """Every generated path gets one weld from its entry to its last path move."""
    def with_weld(weave):
        generate = simulation.generate_program
        read_cell = reader.read_cell

        def generate_with_weld(spec, **kwargs):
            program = generate(spec, **kwargs)
            for path in program.paths:
                roles = [m.role for m in path.moves]
                start = roles.index(ir.ROLE_ENTRY)
                end = max(i for i, r in enumerate(roles) if r in simulation.PATH_ROLES)
                path.welds = [ir.WeldRun("Weld", "Seam weld", SCHEDULE, weave, Tracking("arc"),
                                         start=start, end=end)]
            return program

        def read_with_weld(cell, progress=None):
            spec = read_cell(cell, progress=progress)
            for path in spec.paths:
                path.welds = [WeldSpec("Weld", "Seam weld", SCHEDULE, weave, Tracking("arc"))]
            return spec

        monkeypatch.setattr(simulation, "generate_program", generate_with_weld)
        monkeypatch.setattr(reader, "read_cell", read_with_weld)
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
    assert str(refused.value) == "Weld 'Seam weld': %s." % NO_WEAVE
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
