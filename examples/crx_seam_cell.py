"""The paper's seam-tracking cell welded by a FANUC CRX-10iA/L (issue 24).

The cell of ``seam_tracking_cell`` (an L-shaped butt seam on a table turned 10
degrees, the torch square to the plates and pushing 10 degrees) with a FANUC
CRX-10iA/L, a collaborative arm with an offset wrist, in place of the paper's ABB
IRB 2400.  Standing where the IRB 2400 stands (the origin), the CRX does not reach
the seam; Place robot searches the floor around the table (:data:`REGION_MM`, the
defaults otherwise: the base at floor level, facing the seam), the best base is
applied, Check passes there, and the program is written in the five languages:
FANUC LS with the CRX's CONFIG strings; the others say in their header that they
were written for another maker's robot (``api.other_maker_note``).

Run with ``tools/freecad_run.py examples/crx_seam_cell.py [OUT]`` (writes OUT, default
``out/crx_seam``), or in FreeCAD's Python console::

    import crx_seam_cell
    cell = crx_seam_cell.build(FreeCAD.newDocument("CrxSeam"))
    found, seconds = crx_seam_cell.place(cell)
"""

import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import seam_tracking_cell  # noqa: E402
from CadRobotWB import api  # noqa: E402
from CadRobotWB.core import program as ir  # noqa: E402

ROBOT = "FANUC_CRX10IAL"
#: Place robot's floor region, (xmin, ymin, xmax, ymax) in {U}, mm: 1 m round the
#: table (which covers x 610..1290, y -250..340).
REGION_MM = (-400.0, -1250.0, 2300.0, 1350.0)
#: The five languages the program is written in.
POSTS = ("fanuc_ls", "abb_rapid", "kuka_krl", "motoman_inform", "ur_script")


def build(doc):
    """The seam cell in `doc` with the CRX-10iA/L at the origin, its seam welded with the
    library's schedule for the plates (``api.make_weld``); returns the cell."""
    cell = seam_tracking_cell.build(doc, robot=ROBOT)
    api.make_weld(doc, cell, doc.getObjectsByLabel("Seam")[0], name="SeamWeld")
    doc.recompute()
    return cell


def place(cell, region=REGION_MM):
    """Place robot over `region` (mm in {U}) with the defaults, and the best base applied.

    Returns
    -------
    (Placements, float)
        The candidates best first (empty when no base works: the cell is left as it was)
        and the search's wall time, s.
    """
    start = time.perf_counter()
    found = api.place_robot(cell, region=region)
    seconds = time.perf_counter() - start
    if found:
        api.set_robot_placement(cell, found[0].placement)
        cell.Document.recompute()
    return found, seconds


def torch_angles_deg(program):
    """Work and travel angles of the torch at every target on the seam, deg.

    Measured from the program's targets in {B} (the table-top frame, +Z the plates'
    normal), approach and retract left out: travel angle = the torch axis's tilt towards
    the travel direction (positive pushing), work angle = its angle from the plate in the
    plane normal to the travel (``core.tool_orientation.tool_rotation`` inverted).  The
    travel direction at a target is that of the move arriving there (at the seam's start:
    of the move leaving).

    Returns
    -------
    (ndarray, ndarray), each shape (N,)
        Work and travel angles, deg.
    """
    off_seam = (ir.ROLE_APPROACH, ir.ROLE_RETRACT)
    T = np.array([move.target.T_b_t for path in program.paths for move in path.moves
                  if move.role not in off_seam])
    steps = np.diff(T[:, :3, 3], axis=0)
    travel = np.vstack([steps[:1], steps])
    travel /= np.linalg.norm(travel, axis=1)[:, None]
    normal = np.array([0.0, 0.0, 1.0])
    side = np.cross(travel, normal)
    z = T[:, :3, 2]
    tilt = np.einsum("ij,ij->i", z, travel)
    square = z - tilt[:, None] * travel
    work = np.degrees(np.arctan2(-square @ normal, np.einsum("ij,ij->i", square, side)))
    return work, np.degrees(np.arcsin(np.clip(tilt, -1.0, 1.0)))


def write_programs(cell, out_dir):
    """The program in every language of :data:`POSTS` into `out_dir`.

    Returns
    -------
    dict
        post -> list of written paths, or the one-line refusal (str).
    """
    written = {}
    for post in POSTS:
        try:
            written[post] = api.export(cell, post=post, output_dir=out_dir)
        except api.CadRobotError as exc:
            written[post] = str(exc)
    return written


def run(out_dir):
    """Build, place, check and write; prints the numbers; returns the number of failures."""
    import FreeCAD
    os.makedirs(out_dir, exist_ok=True)
    doc = FreeCAD.newDocument("CrxSeam")
    try:
        cell = build(doc)
        found, seconds = place(cell)
        print("Place robot, %s: %s" % (ROBOT, found.lines()[0]))
        if not found:
            return 1
        best = found[0]
        base = best.placement
        print("best base: x %.0f, y %.0f, z %.0f mm, turn %.0f deg, score %.3f"
              % (base.Base.x, base.Base.y, base.Base.z, base.Rotation.toEuler()[0], best.score))
        check = api.check(cell)
        print(check.report.lines()[-1] if check.report.lines() else "")
        work, travel = torch_angles_deg(check.program)
        j5 = check.solution.joints()[:, 4]
        print("torch: work angle %.1f..%.1f deg, travel angle %.1f..%.1f deg; J5 %.1f..%.1f deg"
              % (work.min(), work.max(), travel.min(), travel.max(), j5.min(), j5.max()))
        saved = os.path.join(out_dir, "crx_seam.FCStd")
        if os.path.exists(saved):     # a fresh file, not FreeCAD's .FCStd1 backup of the last
            os.remove(saved)
        doc.saveAs(saved)
        written = write_programs(cell, out_dir)
        for post, result in written.items():
            print("%-15s %s" % (post, ", ".join(os.path.basename(p) for p in result)
                                if isinstance(result, list) else "refused: " + result))
        print("Place robot took %.1f s" % seconds)
        return int(not check.ok) + sum(isinstance(r, str) for r in written.values())
    finally:
        FreeCAD.closeDocument(doc.Name)


if __name__ == "__main__":
    sys.exit(run(os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                                 os.path.join("out", "crx_seam"))))
