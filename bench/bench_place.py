"""Placement search speed (issue 12; target: 10,000 bases x 1,000 targets in <= 60 s).

A weld seam of 1,000 targets (a wavy line over a 600 x 300 mm field on a
table, the torch pointing down and tilted 15 degrees) for an ABB IRB 2400;
10,000 candidate bases: 25 x 25 positions over a 3 x 3 m square of floor
around the table, 4 heights (-300..300 mm) and 4 turns about Z.  Times
``robots.placement.placement_search.search`` as ``api.place_robot`` and ``cadrobot
place`` run it: the kinematic screen of every base against every target,
then the full check (joints along the path, moves, collisions with the
table, cycle time) of the best ones until 5 pass (the default).

The same run times a FANUC CRX-10iA/L (issue 24: an offset-wrist cobot, solved by
``robots.kinematics.offset_wrist``) on the same seam, table and bases, unchanged: its
smaller reach (catalog.reach_mm: 1,250 mm against the IRB 2400's 1,572 mm) only leaves
fewer bases passing the screen.
"x IRB 2400" is its time over the IRB 2400's.  ``--tilt-deg 0`` puts the torch straight
down, where the CRX's axis 6 is upright and its solutions come from the closed forms of
``offset_wrist_polish`` (on 2026-11-28, load 1.2: IRB 2400 15.3 s, CRX 33.0 s; at 15 deg
13.9 s and 43.3 s).

    /usr/bin/python3 bench/bench_place.py [--bases 10000] [--targets 1000]
                                          [--robots ABB_IRB2400,FANUC_CRX10IAL]
                                          [--tilt-deg 15]   (0: the torch straight down)

One core (the process is pinned to one CPU, BLAS to one thread).  Printed,
never asserted.  (`make bench` runs it with FreeCAD's package folder on
PYTHONPATH for trimesh and python-fcl.)
"""

import argparse
import time

import one_core  # noqa: F401,E402  (one core, one thread; before numpy)

import numpy as np  # noqa: E402
import trimesh  # noqa: E402

from CadRobotWB.core import program as ir  # noqa: E402
from CadRobotWB.robots.kinematics import models  # noqa: E402
from CadRobotWB.robots.placement import placement, placement_search  # noqa: E402

TARGET_S = 60.0
ROBOTS = "ABB_IRB2400,FANUC_CRX10IAL"
DOWN = np.diag([1.0, -1.0, -1.0])       # tool Z pointing down, X along +X of {U}


#: The torch's tilt from straight down (about X of {U}) unless --tilt-deg says otherwise, deg.
TILT_DEG = 15.0


def seam_program(n_targets, robot="ABB_IRB2400", tilt_deg=TILT_DEG):
    """One path of `n_targets` (a joint move, then linear moves) for `robot`, {B} = {U},
    robot at {U}, the torch tilted `tilt_deg` from straight down."""
    t = np.linspace(0.0, 1.0, n_targets)
    x = 800.0 + 600.0 * t
    y = 150.0 * np.sin(6.0 * np.pi * t)
    tilt = np.radians(tilt_deg)
    R = DOWN @ np.array([[1, 0, 0], [0, np.cos(tilt), -np.sin(tilt)], [0, np.sin(tilt), np.cos(tilt)]])
    moves = []
    for k in range(n_targets):
        T = np.eye(4)
        T[:3, :3] = R
        T[:3, 3] = (x[k], y[k], 700.0)
        moves.append(ir.Move(ir.JOINT if k == 0 else ir.LINEAR, ir.Target("p%d" % k, T), 20.0, 1.0, "B"))
    tool = ir.ToolData("torch", np.eye(4))
    tool.T_f_t[:3, 3] = (0.0, 0.0, 250.0)
    frame = ir.WorkFrame("B", np.eye(4), np.eye(4))
    return ir.Program("Bench", robot, tool, {"B": frame}, [ir.ProgramPath("Seam", "Seam", moves)])


def table():
    mesh = trimesh.creation.box(extents=(800.0, 600.0, 690.0))
    mesh.apply_translation((1100.0, 0.0, 345.0))        # top 10 mm under the seam's TCP plane
    return [("Table", mesh)]


def space(n_bases):
    """About `n_bases` bases: n x n positions, 4 heights, 4 turns."""
    side = max(2, int(round(np.sqrt(n_bases / 16.0))))
    step = 3000.0 / (side - 1)
    return placement.make_space((-400.0, -1500.0, 2600.0, 1500.0), np.eye(4), z_mm=(-300.0, 300.0),
                                turn_deg=(-135.0, 135.0), step_mm=step, z_step_mm=200.0,
                                turn_step_deg=90.0)


def place(robot, n_targets, n_bases, tilt_deg=TILT_DEG):
    """The search for `robot`: placement_search.Placements (timed inside)."""
    return placement_search.search(seam_program(n_targets, robot, tilt_deg), models.model(robot),
                                   space(n_bases), table())


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bases", type=int, default=10000)
    parser.add_argument("--targets", type=int, default=1000)
    parser.add_argument("--robots", default=ROBOTS, help="catalog names; the first is the "
                        "reference of the 'x' column")
    parser.add_argument("--tilt-deg", type=float, default=TILT_DEG,
                        help="torch tilt from straight down, deg (about X; 0: straight down)")
    args = parser.parse_args()
    print("placement search, one core, torch %g deg from straight down (seconds)" % args.tilt_deg)
    line = "%-16s %7s %8s %8s %8s %8s %8s %7s %8s %6s"
    print(line % ("robot", "bases", "targets", "screen", "passed", "checked", "passed", "total",
                  "target", "x " + args.robots.split(",")[0]))
    reference_s = None
    for robot in args.robots.split(","):
        found = place(robot, args.targets, args.bases, args.tilt_deg)
        c = found.counts
        reference_s = reference_s or found.elapsed_s
        print(line % (robot, c["candidates"], args.targets, "%.1f" % found.screen_s,
                      c["passed_screen"], c["checked"], c["passed"], "%.1f" % found.elapsed_s,
                      "<= %.0f" % TARGET_S, "%.2f" % (found.elapsed_s / reference_s)))
    print("(screen: every base against every target; then the full check of 'cadrobot check', "
          "best first, until 5 pass)")


if __name__ == "__main__":
    main()
