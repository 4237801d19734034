"""How the time of `check` grows with the number of targets (issues 4 and 12).

Builds programs of 1k, 10k and 100k targets (a weld path zig-zagging over a
table in front of an IRB 2400, torch pointing down, 2 mm between targets),
then times the engine behind ``cadrobot check``: choosing the joints of every
target, the per-target and per-move checks, and the collision check against
the table. Prints seconds per 1k targets for each size: flat means linear.

The same run times a FANUC CRX-10iA/L (issue 24: an offset-wrist cobot, solved by
``robots.kinematics.offset_wrist``) on the same program and table, 200 mm closer to the
robot (:data:`FIELD_X_MM`: from x = 900 mm, 45 % of the field's targets are beyond its
reach); the "x" column is its total over the IRB 2400's.  A program the robot cannot
run is timed all the same, and its row says why it is not valid.  With the torch
straight down (the default) every CRX pose has axis 6 upright, where the search is
blind: ``offset_wrist_polish`` solves those in closed form; ``--tilt-deg`` tilts it
(on 2026-11-28, load 1.1, CRX over IRB 2400: 0.29 at 1k targets, 1.48 at 10k, 1.78 at
100k; before, 11.5 s against 1.2 s at 1k).

    /usr/bin/python3 bench/bench_check.py [--sizes 1000,10000,100000]
                                          [--robots ABB_IRB2400,FANUC_CRX10IAL]
                                          [--tilt-deg 0]

(`make bench` runs it with FreeCAD's Python and its package folder.)
"""

import argparse
import time

import one_core  # noqa: F401  (one core, one thread; before numpy)

import numpy as np  # noqa: E402

from CadRobotWB.core import program as ir  # noqa: E402
from CadRobotWB.robots.checks import checks, collision  # noqa: E402
from CadRobotWB.robots.kinematics import models  # noqa: E402
from CadRobotWB.robots.motion import configuration, move_sampling  # noqa: E402

DOWN = np.diag([1.0, -1.0, -1.0])  # tool Z pointing down, X along +X


def zigzag_program(n_targets, step_mm=2.0, robot="ABB_IRB2400", tilt_deg=0.0):
    """A program of `n_targets` linear moves in a 300 x 300 mm field for `robot`
    (from x = ``field_x_mm(robot)``), {B} = {R}, the torch pointing down, tilted
    `tilt_deg` about X of {R}."""
    x0 = field_x_mm(robot)
    c, s = np.cos(np.radians(tilt_deg)), np.sin(np.radians(tilt_deg))
    torch = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]) @ DOWN
    per_row = 150
    moves = []
    for k in range(n_targets):
        row, col = divmod(k, per_row)
        x = col * step_mm if row % 2 == 0 else (per_row - 1 - col) * step_mm
        y = (row % 150) * step_mm
        T = np.eye(4)
        T[:3, :3] = torch
        T[:3, 3] = (x0 + x, -150 + y, 500)
        kind = ir.JOINT if k == 0 else ir.LINEAR
        moves.append(ir.Move(kind, ir.Target("p%d" % k, T), 50.0, 1.0, "B"))
    frame = ir.WorkFrame("B", np.eye(4), np.eye(4))
    tool = ir.ToolData("t", np.eye(4) @ np.diag([1, 1, 1, 1.0]))
    tool.T_f_t[:3, 3] = (0, 0, 250)
    return ir.Program("Bench", robot, tool, {"B": frame}, [ir.ProgramPath("p", "p", moves)])


#: Where the field starts (its edge nearest the robot), x in {R}, mm; default 900.
FIELD_X_MM = {"FANUC_CRX10IAL": 700.0}


def field_x_mm(robot):
    return FIELD_X_MM.get(robot, 900.0)


def table_obstacle(robot):
    import trimesh
    table = trimesh.creation.box(extents=(600, 600, 40))
    table.apply_translation((field_x_mm(robot) + 150, 0, 460))  # top 20 mm under the TCP plane
    return [("Table", table)]


def time_check(n_targets, model, checker, tilt_deg):
    """Seconds (solve, checks, collisions) of the zigzag of `n_targets` and what makes it
    invalid for `model` ("" when it is valid)."""
    program = zigzag_program(n_targets, robot=model.name, tilt_deg=tilt_deg)
    start = time.perf_counter()
    solution = configuration.solve_program(program, model)
    solved = time.perf_counter()
    # Sampled once for both, as api.check does.
    sampled = move_sampling.sample_program(program, model, solution, checks.Margins())
    report = checks.check_program(program, model, solution, sampled=sampled)
    checked = time.perf_counter()
    hits = collision.program_collision_findings(program, solution, checker, sampled=sampled)
    done = time.perf_counter()
    return (solved - start, checked - solved, done - checked), invalid_note(solution, report, hits)


def invalid_note(solution, report, hits):
    """Why the benchmark's program is not valid for the robot, or ""."""
    if not solution.ok or not report.ok:
        first = next((line for line in report.lines() if "ERROR" in line), "")
        return "NOT valid: " + first.split(";")[0]
    return "NOT valid: %d collisions" % len(hits) if hits else ""


#: Issue 12's targets (every check on, one core) and its figures before the work, s.
TARGET_S = {10000: 1.0, 100000: 10.0}
BEFORE_S = {10000: 16.0, 100000: 160}
ROBOTS = "ABB_IRB2400,FANUC_CRX10IAL"


def robot_rows(robot, sizes, tilt_deg):
    """One row per size for `robot`: (size, (solve, checks, collisions) s, invalid note)."""
    model = models.model(robot)
    checker = collision.RobotCollisionChecker(model, table_obstacle(robot),
                                              tool_T_f_t=zigzag_program(1).tool.T_f_t)
    return [(n,) + time_check(n, model, checker, tilt_deg) for n in sizes]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="1000,10000,100000")
    parser.add_argument("--robots", default=ROBOTS, help="catalog names; the first is the "
                        "reference of the 'x' column")
    parser.add_argument("--tilt-deg", type=float, default=0.0,
                        help="torch tilt from straight down, deg (about X)")
    args = parser.parse_args()
    sizes = [int(s) for s in args.sizes.split(",")]
    robots = args.robots.split(",")
    print("check engine, one core, torch %g deg from straight down (seconds; 'per 1k' flat = "
          "linear growth)" % args.tilt_deg)
    line = "%-16s %9s %10s %10s %11s %10s %10s %6s   %s"
    print(line % ("robot", "targets", "solve", "checks", "collisions", "total", "per 1k",
                  "x " + robots[0], ""))
    reference = {}
    for robot in robots:
        for n, seconds, invalid in robot_rows(robot, sizes, args.tilt_deg):
            total = sum(seconds)
            reference.setdefault(n, total)
            target = TARGET_S.get(n) if robot == robots[0] else None
            note = invalid or ("" if target is None else
                               "target <= %g s: %s (issue's figure before: %s s)"
                               % (target, "met" if total <= target else "NOT met", BEFORE_S[n]))
            print(line % ((robot, n) + tuple("%.2f" % s for s in seconds)
                          + ("%.2f" % total, "%.3f" % (1000.0 * total / n),
                             "%.2f" % (total / reference[n]), note)))


if __name__ == "__main__":
    main()
