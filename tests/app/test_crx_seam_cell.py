"""examples/crx_seam_cell.py, issue 24's cobot cell: the paper's seam cell welded by a
FANUC CRX-10iA/L (an offset wrist, solved by ``robots.kinematics.offset_wrist``).

Where the IRB 2400 stands (the origin) the CRX does not reach the seam; Place robot on a
small region in front of the table (the example searches 1 m round it) finds a base,
Check passes there, and the joints it chose put the torch on every target (forward
kinematics, computed here); the FANUC program carries CONFIG strings of one
configuration along the seam, with the arc on at the seam's start.
"""

import re

import numpy as np
import pytest

from CadRobotWB import api
from CadRobotWB.robots.kinematics import models

import crx_seam_cell

#: Floor in front of the table (the example's best bases lie there), mm in {U}.
REGION_MM = (700.0, -900.0, 1500.0, -300.0)
CONFIG = re.compile(r"CONFIG : '([NF] [UD] [TB], -?\d+, -?\d+, -?\d+)'")


@pytest.fixture(scope="module")
def placed(tmp_path_factory):
    import FreeCAD
    doc = FreeCAD.newDocument("CrxSeamCell")
    cell = crx_seam_cell.build(doc)
    at_origin = api.check(cell, collisions=False)
    found, _ = crx_seam_cell.place(cell, region=REGION_MM)
    check = api.check(cell)
    out = tmp_path_factory.mktemp("crx")
    written = api.export(cell, post="fanuc_ls", output_dir=str(out))
    yield cell, at_origin, found, check, written
    FreeCAD.closeDocument(doc.Name)


def test_the_crx_does_not_reach_the_seam_from_the_irb_2400s_base(placed):
    _, at_origin, _, _, _ = placed
    assert not at_origin.ok
    assert any("out of reach" in f.message for f in at_origin.report.findings)


def test_place_robot_finds_a_base_in_the_region_and_applies_it(placed):
    cell, _, found, _, _ = placed
    assert len(found) >= 1
    base = cell.Placement.Base
    assert REGION_MM[0] <= base.x <= REGION_MM[2] and REGION_MM[1] <= base.y <= REGION_MM[3]
    assert base.z == pytest.approx(0.0)
    np.testing.assert_allclose(api.matrix_from_placement(cell.Placement), found[0].T_u_r,
                               atol=1e-9)


def test_check_passes_and_its_joints_put_the_torch_on_every_target(placed):
    cell, _, _, check, _ = placed
    assert check.ok, check.report.lines()
    model = models.model("FANUC_CRX10IAL")
    entries = check.solution.entries
    q = np.array([e.joints_deg for e in entries])
    T_r_t = model.fk(q) @ check.program.tool.T_f_t
    T_wanted = np.array([e.T_r_f for e in entries]) @ check.program.tool.T_f_t
    assert np.abs(T_r_t[:, :3, 3] - T_wanted[:, :3, 3]).max() < 1e-6
    assert np.abs(T_r_t[:, :3, :3] - T_wanted[:, :3, :3]).max() < 1e-9
    assert len(set(np.sign(q[:, 4]))) == 1          # J5 does not flip along the seam


def test_the_fanuc_program_has_one_crx_configuration_and_the_arc_on_at_the_start(placed):
    _, _, _, check, written = placed
    (ls,) = [p for p in written if p.endswith(".LS")]
    with open(ls) as handle:
        text = handle.read()
    configs = CONFIG.findall(text)
    cartesian = text.count("X =")
    assert len(configs) == cartesian > 10
    assert len(set(configs)) == 1
    assert "the checked arm config" in text
    moves = re.findall(r"^\s*\d+:([JL]) P\[(\d+)\][^;]*?(Arc Start\[1\])?\s*;", text, re.M)
    assert moves[0][0] == "J" and moves[1][2] == "Arc Start[1]"      # entry move: arc on
