"""Review fixes of the App layer: each test shows a defect found in review."""

import math

import FreeCAD
import pytest

from CadRobotWB import api
from CadRobotWB.errors import FrameError

V = FreeCAD.Vector


def test_teaching_with_a_nan_point_is_a_frame_error_and_changes_nothing(doc):
    # "nan" is a float to Python: typed in the teaching panel or passed by a macro it
    # reached numpy's SVD and came out as LinAlgError (a traceback, and a failed recompute).
    cell = api.make_cell(doc)
    frame = api.make_calibration_frame(doc, cell, FreeCAD.Placement())
    cad = [V(0, 0, 0), V(100, 0, 0), V(0, 100, 0)]
    measured = [(0, 0, 0), (math.nan, 0, 0), (0, 100, 0)]
    with pytest.raises(FrameError):
        api.teach_calibration_frame(frame, cad, measured)
    assert not frame.UseTaught and len(frame.CadPoints) == 0
    with pytest.raises(FrameError):
        api.teach_calibration_frame(frame, cad, [(0, 0, 0), (math.inf, 0, 0), (0, 100, 0)])
