"""examples/pipe_flange_cell.py, the demo of issue 23: a pipe welded to its flange all
round, flat on a tilt-and-turn positioner, and horizontal-vertical without it.

By hand: the fillet at the foot of a standing pipe is the corner between a vertical
wall and a horizontal plate; its bisector points 45 degrees below the horizontal
wherever the torch is round the pipe, so without a positioner every welded target's
gravity angle is 45 degrees. On the positioner the table tilts 45 degrees (tilt = -45,
the plan's hand values in tests/core/external_fixtures.py) and turns once round, 360
degrees, while the torch goes round the seam; the bisector then points straight down.
"""

import numpy as np
import pytest

import FreeCAD

from CadRobotWB import api
from CadRobotWB.errors import PostError

import pipe_flange_cell

#: The welded targets of the seam: the start, 4 circular moves' via and end points.
WELDED_TARGETS = 9


def test_the_pipe_is_welded_flat_on_the_positioner_and_not_without_it(doc, tmp_path):
    fixed = FreeCAD.newDocument("PipeOnATable")
    try:
        table = pipe_flange_cell.build(fixed, positioner=False)
        without = pipe_flange_cell.gravity_angles_deg(api.generate(table))
    finally:
        FreeCAD.closeDocument(fixed.Name)
    assert len(without) == WELDED_TARGETS
    np.testing.assert_allclose(without, 45.0, atol=0.01)

    cell = pipe_flange_cell.build(doc)
    pipe = doc.getObject("Pipe")
    drawn = FreeCAD.Placement(pipe.Placement)
    result = api.check(cell, collisions=False)
    assert result.ok, [f.message for f in result.report.findings if f.severity == "error"]
    program = result.program
    flat = pipe_flange_cell.gravity_angles_deg(program)
    assert len(flat) == WELDED_TARGETS and flat.max() < 0.01
    values = np.array([t.external for t in program.targets()])       # (tilt, turn) per target
    np.testing.assert_allclose(np.abs(values[:, 0]), 45.0, atol=0.01)
    assert abs(values[-1, 1] - values[0, 1]) == pytest.approx(360.0, abs=0.01)
    assert np.all(np.abs(np.diff(values[:, 1])) <= 45.0 + 1e-6)      # 45 deg per via, no jump
    assert pipe.Placement == drawn                  # choosing moved nothing in the document

    # UR has no external axes: one line naming the positioner, nothing written
    with pytest.raises(PostError) as refused:
        api.export(cell, post="ur_script", output_dir=str(tmp_path))
    assert "'Positioner'" in str(refused.value) and "\n" not in str(refused.value)
    assert list(tmp_path.iterdir()) == []
