"""The chooser's speed pass moves a track (issue 23): Check on a small document.

The cell: the ABB IRB 2400 at the origin on the generic track (``catalog.build("track")``:
0..3000 mm along +X at 1000 mm/s and 2000 mm/s^2; base 250 mm below the robot, so
travel 0 is where the robot stands); a path without welds (a bead laid at 400 mm/s,
the tool straight down) along one line from (1000, 1000, 400) to (1100, 1170, 400),
running away from the track near the outer edge of the reach band the chooser keeps
(0.75 x 1572 = 1179 mm). Keeping each end just within that band (the travel the
chooser gave before its speed pass moved tracks, and keeps where riding abreast ranks
worse) takes the track from 375.5 to 954.8 mm while the TCP runs 197.2 mm (0.49 s): 1175
mm/s, over the track's 1000. Riding abreast (the chooser's choice here) it moves 100 mm.
"""

import numpy as np
import pytest

import FreeCAD
from CadRobotWB import api
from CadRobotWB.robots.catalog import catalog
from CadRobotWB.robots.kinematics import models
from CadRobotWB.robots.mechanisms import arm_fit, choose

V = FreeCAD.Vector
START, END = (1000.0, 1000.0, 400.0), (1100.0, 1170.0, 400.0)
SPEED_MM_S = 400.0
#: The bead's move lasts its length in the part frame over its speed: 197.2 mm in 0.493 s.
MOVE_S = float(np.linalg.norm(np.subtract(END, START))) / SPEED_MM_S


def build(doc):
    """The cell of the module docstring; returns it."""
    line = doc.addObject("Part::Line", "Bead")
    (line.X1, line.Y1, line.Z1), (line.X2, line.Y2, line.Z2) = START, END
    doc.recompute()
    cell = api.make_cell(doc, robot="ABB_IRB2400", name="TrackCell")
    api.make_calibration_frame(doc, cell, FreeCAD.Placement())
    api.make_path(doc, cell, (line, "Edge1"), speed_mm_s=SPEED_MM_S, name="Bead")
    down = FreeCAD.Rotation(V(1, 0, 0), 180)
    api.make_tool_marker(doc, cell, FreeCAD.Placement(V(*START), down))
    api.add_track(cell, 3000.0, FreeCAD.Placement(V(0, 0, -250), FreeCAD.Rotation()))
    return cell


def track_speed_by_hand(program):
    """The track's speed (mm/s) on the bead's move: the change of travel between the line's
    ends over the move's time (its length in the part frame over its speed)."""
    travel = [t.external[0] for t in program.targets()]      # approach, start, end, retract
    return abs(travel[2] - travel[1]) / MOVE_S


def test_check_reports_no_track_speed_once_the_pass_moves_the_track(doc, monkeypatch):
    """Without moving the track (the chooser before this pass) Check reports the track at
    1175 mm/s; with it, Check passes (every target reached, no finding at all) and the
    travel over the move (by hand) is within 1000."""
    cell = build(doc)
    # The lazy travel, which the chooser keeps where riding abreast ranks worse (a seam
    # across the track): here it rides abreast (test_abreast_the_track_follows_the_bead).
    monkeypatch.setattr(choose, "_run_travel", lambda ctx, values, given, rows, lazy, *_: lazy)
    with monkeypatch.context() as patch:
        patch.setattr(choose, "_limit_track", lambda *args: [])
        before = api.check(cell)
    reach = arm_fit.GOOD_REACH[1] * catalog.reach_mm(models.model("ABB_IRB2400").spec)
    ends = [x - np.sqrt(reach ** 2 - y ** 2) for x, y, _ in (START, END)]   # 375.5, 954.8
    lazy = abs(ends[1] - ends[0]) / MOVE_S
    assert track_speed_by_hand(before.program) == pytest.approx(lazy, abs=1e-6)
    [finding] = [f for f in before.report.findings if f.kind == "external_speed"]
    assert finding.value == pytest.approx(lazy, abs=1e-6) and lazy > 1170.0
    after = api.check(cell)
    assert after.ok and after.report.findings == [], after.lines()
    assert track_speed_by_hand(after.program) <= 1000.0


def test_abreast_the_track_follows_the_bead(doc):
    """Riding abreast, the travel changes as the bead's x does (100 mm over the move: 203
    mm/s, by hand), within the track's 1000 mm/s: Check passes without the speed pass."""
    after = api.check(build(doc))
    assert after.ok and after.report.findings == [], after.lines()
    run_x = END[0] - START[0]
    assert track_speed_by_hand(after.program) == pytest.approx(run_x / MOVE_S, abs=1e-6)
