"""Sensor run on the demo's positioner cell (examples/pipe_flange_cell.py, the MOTOPOS
D500) in the FreeCAD window: the laser run with the part shifted, then Play, which turns
the positioner as the run did while the robot follows the corrected path."""

import numpy as np
import pytest

import FreeCADGui

from CadRobotWB import simulation
from CadRobotWB.gui import robot_view, sensor_run_panel, simulation_player
from conftest import close_panels, process_events

import pipe_flange_cell


@pytest.fixture
def pipe_cell(gui_doc):
    FreeCADGui.activateWorkbench("CadRobotWorkbench")
    close_panels()
    cell = pipe_flange_cell.build(gui_doc)
    process_events()
    yield cell
    sensor_run_panel.close_panel()
    simulation_player.close_player()
    close_panels()


def test_play_turns_the_part_and_keeps_the_torch_on_the_corrected_path(pipe_cell):
    """The panel's Play on a run made as its Run makes it (without the plots, which
    cost 4 s and are tested in test_sensor_run.py)."""
    panel = sensor_run_panel.open_panel(pipe_cell)
    panel.scene, _, panel.runs = simulation.simulate_cell(pipe_cell, "laser", ("pi",),
                                                          deviation=(2, 0, 1, 0, 0, 0))
    run = panel.runs[0]
    assert not run.aborted and run.metrics["rms_error_after_20mm_mm"] < 0.1
    corrected = sensor_run_panel.player_trajectories(panel.scene, run)[-1][1]  # part's frame
    player = panel.play()
    assert player is not None
    timeline = player.timeline
    assert timeline.failure is None and len(timeline) == len(run.time_s)
    assert timeline.external.shape == (len(run.time_s), 2)
    pipe = pipe_cell.Document.getObject("Pipe")
    T_u_pipe = np.array(pipe.Placement.toMatrix().A).reshape(4, 4)
    for i in (0, len(timeline) // 2, len(timeline) - 1):
        player.show_frame(i)
        shown = robot_view.matrix_from_transform(pipe.ViewObject.RootNode.getChild(0))
        T = shown @ np.linalg.inv(T_u_pipe)            # how the part is moved from its drawing
        tilt = timeline.external[i][0]
        # the pipe's axis, drawn vertical, leans by the run's tilt
        lean = np.degrees(np.arccos(np.clip(T[2, 2], -1.0, 1.0)))
        assert lean == pytest.approx(abs(tilt), abs=0.01)
        # back in the drawing, the robot's TCP is on the corrected path
        tcp_drawn = np.linalg.inv(T) @ np.append(timeline.tcp_u[i], 1.0)
        np.testing.assert_allclose(tcp_drawn[:3], corrected[i, :3, 3], atol=1e-3)
