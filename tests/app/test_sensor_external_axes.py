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


def test_force_following_polishes_the_pipe_the_positioner_turns():
    """A ball polishing round the pipe (pipe_flange_cell.build_polishing), the part moved
    1 mm across the pipe (and 1 mm along it, which a cylinder does not show).

    By hand, in the part's frame (n radial from the pipe's axis, R = 57.15, r = 5, the
    preload p = 1 mm): the ball presses the moved pipe by the preload where its centre
    is at c n with ``|c n - s_xy| = R + r - p``, an offset ``o = R + r - c`` along the
    tool axis (about 1 - cos(angle) mm); the PI lags the moving normal by s v / R * T / 0.4
    = 0.044 mm (0.87 N) at most once settled, give or take the tessellation's sag (the
    run's ``drawn_contact_mm``, 0.018 mm) on the drawn and the real part. The corrected program fits the corrected
    circle in a few arcs (one move a sample when its orientations were a sample late)."""
    doc = FreeCAD.newDocument("PipePolishRun")
    try:
        cell = pipe_flange_cell.build_polishing(doc)
        run = api.simulate(cell, sensor="force", deviation=(1.0, 0.0, 1.0, 0.0, 0.0, 0.0),
                           seed=1, force_noise_n=0.0, dt_s=0.01)
        axis_mm = pipe_flange_cell.table_centre()[:2]
    finally:
        FreeCAD.closeDocument(doc.Name)
    assert not run.aborted, run.reason
    assert run.time_s[1] - run.time_s[0] == pytest.approx(0.01)         # the dt_s given
    assert any("part's frame" in note for note in run.notes), run.notes
    assert not any("asked for although" in note for note in run.notes), run.notes
    settled = run.time_s * pipe_flange_cell.POLISH_SPEED_MM_S >= 60.0
    radial = run.nominal_mm[settled, :2] - axis_mm
    normal = radial / np.linalg.norm(radial, axis=1)[:, None]
    reach = pipe_flange_cell.PIPE_RADIUS_MM + 5.0
    along = normal[:, 0] * 1.0                                      # n . s_xy, s_xy = (1, 0)
    hand_mm = reach - (along + np.sqrt((reach - 1.0) ** 2 - (1.0 - along ** 2)))
    offsets = -np.einsum("ij,ij->i", run.correction_mm[settled, :2], normal)
    facets_mm = run.metrics["drawn_contact_mm"]     # the tessellation's sag, drawn and real
    error_mm = 0.044 + 2 * facets_mm
    assert np.abs(offsets - hand_mm).max() < error_mm
    forces = np.linalg.norm(run.force_n[settled, :3], axis=1)
    assert np.abs(forces - 20.0).max() < 20.0 * error_mm
    assert run.metrics["corrected_moves"] <= 12, run.metrics["corrected_moves"]
