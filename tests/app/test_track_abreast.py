"""A track rides abreast of a long fillet (issue 23): Check on the new user's document.

The document of a new user's trial: a 2500 x 10 x 150 mm web standing on a 2600 x 300 x 10
mm base plate, the fillet along the web's foot (y 0, z 10, x 50 to 2550) welded at 45
degrees into the corner; the ABB IRB 2400 where ``api.make_cell`` puts it by default
(beside the work, facing it), on the generic 4000 mm track with its carriage under the
robot (the New cell panel's default base: ``mechanism_panel.default_base``). Before the
track rode abreast, it moved only when the seam left the reach band, the arm swung along
the seam and Check failed with J4 at -204.9 deg (the trial's robot stood 886 mm from the
seam: -201.1 deg).
"""

import numpy as np

import FreeCAD
from CadRobotWB import api
from CadRobotWB.objects.convert import matrix_from_placement

from helpers import polyline, sketch_of

V = FreeCAD.Vector
#: The generic track's carriage (the robot's mounting face) above its base, mm.
CARRIAGE_MM = 250.0


def build(doc):
    """The cell of the module docstring; returns it."""
    plate = doc.addObject("Part::Box", "Plate")
    plate.Length, plate.Width, plate.Height = 2600, 300, 10
    plate.Placement.Base = V(0, -150, 0)
    web = doc.addObject("Part::Box", "Web")
    web.Length, web.Width, web.Height = 2500, 10, 150
    web.Placement.Base = V(50, 0, 10)
    root = sketch_of(doc, polyline([(50, 0), (2550, 0)]),
                     FreeCAD.Placement(V(0, 0, 10), FreeCAD.Rotation()), name="RootSketch")
    cell = api.make_cell(doc, robot="ABB_IRB2400", name="TrackCell")
    api.make_calibration_frame(doc, cell, FreeCAD.Placement())
    api.make_path(doc, cell, root, speed_mm_s=10.0, name="Fillet")
    into_corner = V(0, -1, 1).normalize()
    api.make_tool_marker(doc, cell, api.tool_placement(V(1000, 0, 10), V(1, 0, 0), into_corner,
                                                       90.0, 0.0))
    robot = cell.Placement
    api.add_track(cell, 4000.0, FreeCAD.Placement(robot.Base - V(2000, 0, CARRIAGE_MM),
                                                  FreeCAD.Rotation()))
    doc.recompute()
    return cell


def test_the_track_rides_abreast_of_the_fillet_and_check_passes(doc):
    """The robot stands 836 mm from the seam (``make_cell``'s default), 45 degrees into the
    corner. The travel less the seam's x is one number along the weld (the carriage
    carries the arm in one pose), and Check finds nothing (before: J4 at -204.9 deg)."""
    cell = build(doc)
    robot = matrix_from_placement(cell.Placement)
    assert abs(robot[1, 3]) > 800.0 and abs(robot[1, 0]) > 0.999   # facing the seam, beside it
    result = api.check(cell)
    assert result.ok and result.report.findings == [], result.lines()
    seam = [t for t in result.program.targets() if abs(t.position_mm[1]) < 1e-6]
    offsets = [t.external[0] - t.position_mm[0] for t in seam]
    assert len(seam) == 2 and abs(offsets[1] - offsets[0]) < 1e-6


def test_with_the_lazy_travel_the_wrist_family_that_does_not_wind_is_taken(doc, monkeypatch):
    """The travel that moves only when the seam leaves the reach band (the chooser's before
    riding abreast): families 0 and 1 (wrist flipped) are each valid at all 4 targets and 0
    is the quicker from the middle of the ranges, but followed along the linear moves it
    winds J4 to -291.5 deg (Check: "J4 to -204.9 deg at 52%"). Family 1 stays within +-200:
    Check passes (it samples the moves), every target in family 1 (J5 < 0)."""
    from CadRobotWB.robots.mechanisms import choose
    monkeypatch.setattr(choose, "_run_travel", lambda ctx, values, given, rows, lazy, *_: lazy)
    result = api.check(build(doc))
    assert result.ok and result.report.findings == [], result.lines()
    joints = np.array([t.joints_deg for t in result.program.targets()])       # (4, 6)
    assert joints.shape == (4, 6) and (joints[:, 4] < 0.0).all()
