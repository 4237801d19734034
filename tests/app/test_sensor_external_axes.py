"""A sensor run on the demo's positioner cell (examples/pipe_flange_cell.py, the pipe
welded all round on the MOTOPOS D500): ``api.simulate`` turns the part with the
program's external values while the laser tracks the seam.

By hand: the real part is moved (2, 0, 1) mm where the document draws it; the
torch sees that shift less its part along the travel, so the open-loop error runs
round the circle as sqrt(5 - 4 sin^2 phi) (phi: the travel's angle from Y), between
1 mm and sqrt(5) = 2.236 mm, its RMS over the circle sqrt(3) = 1.732 mm, whatever the
positioner does.
"""

import numpy as np
import pytest

import FreeCAD

from CadRobotWB import api
from CadRobotWB.errors import InputError

import pipe_flange_cell

SHIFT = (2.0, 0.0, 1.0, 0.0, 0.0, 0.0)


def test_a_laser_run_turns_the_part_and_tracks_the_shifted_seam():
    doc = FreeCAD.newDocument("PipeSensorRun")
    try:
        cell = pipe_flange_cell.build(doc)
        run = api.simulate(cell, sensor="laser", deviation=SHIFT, seed=1)
        # a foreign object standing in the cell, not on the positioner's table: refused
        post = doc.addObject("Part::Box", "Post")
        with pytest.raises(InputError) as refused:
            api.simulate(cell, sensor="laser", foreign_objects=[post])
    finally:
        FreeCAD.closeDocument(doc.Name)
    assert str(refused.value) == (
        "Foreign object 'Post' does not ride on positioner 'Positioner' of cell 'PipeCell': a "
        "sensor run with a positioner takes foreign objects on the part only; add it to the "
        "positioner's Parts or leave it out.")
    assert not run.aborted, run.reason
    assert any("part's frame" in note for note in run.notes), run.notes
    assert run.metrics["open_loop_max_error_mm"] == pytest.approx(np.sqrt(5.0), abs=0.01)
    assert run.metrics["open_loop_rms_error_mm"] == pytest.approx(np.sqrt(3.0), abs=0.01)
    assert run.metrics["rms_error_after_20mm_mm"] < 0.1
    assert run.metrics["corrected_moves"] >= 1
