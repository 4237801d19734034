"""Panels that cannot compute their list say why (issue 14, item 4): the calibration
panel's residuals and the place panel's candidates, on an error of any kind."""

import FreeCAD
import pytest

from conftest import process_events
from CadRobotWB import api
from CadRobotWB.gui import calibration_panel, place_panel
from CadRobotWB.objects import calibration_frame
import test_place_panel
from test_place_panel import open_from_toolbar, small_search

V = FreeCAD.Vector
far_cell = test_place_panel.far_cell          # the fixture: the seam cell, robot far away


@pytest.fixture
def frame_with_points(gui_doc):
    cell = api.make_cell(gui_doc)
    frame = api.make_calibration_frame(gui_doc, cell, FreeCAD.Placement())
    cad = [V(0, 0, 0), V(100, 0, 0), V(0, 100, 0)]
    api.teach_calibration_frame(frame, cad, [V(900, 0, 600) + p for p in cad])
    yield frame
    calibration_panel.close_panel()


def test_calibration_panel_says_why_residuals_are_missing(frame_with_points):
    frame = frame_with_points
    frame.Residuals = [0.0, 0.0]            # points edited outside the panel: 3 points, 2 residuals
    panel = calibration_panel.CalibrationPanel(frame)
    assert panel.residuals is None and "Residuals (mm)" not in panel.result.text()
    assert "3 points but 2 stored residuals" in panel.result.text() and "press Fit" in panel.result.text()


def test_calibration_fit_shows_any_failure(frame_with_points, monkeypatch):
    panel = calibration_panel.CalibrationPanel(frame_with_points)

    def singular(*_args):
        raise ValueError("SVD did not converge")
    monkeypatch.setattr(calibration_frame, "fit_points", singular)
    assert panel.fit() is None
    assert "SVD did not converge" in panel.result.text() and "red" in panel.result.styleSheet()


def test_place_search_failure_is_shown_and_the_panel_stays_usable(far_cell, monkeypatch):
    panel = open_from_toolbar()

    def broken(*_args, **_kwargs):
        raise RuntimeError("no memory for the grid")
    monkeypatch.setattr(api, "place_robot", broken)
    assert small_search(panel) is None
    process_events()
    assert "no memory for the grid" in panel.message.text() and "red" in panel.message.styleSheet()
    assert panel.search_button.isEnabled() and panel.list.count() == 0
    place_panel.close_panel()
