"""How the time of `check` grows with the number of targets (issues 4 and 12).

Builds programs of 1k, 10k and 100k targets (a weld path zig-zagging over a
table in front of an IRB 2400, torch pointing down, 2 mm between targets),
then times the engine behind ``cadrobot check``: choosing the joints of every
target, the per-target and per-move checks, and the collision check against
the table. Prints seconds per 1k targets for each size: flat means linear.

    /usr/bin/python3 bench/bench_check.py [--sizes 1000,10000,100000]

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


def zigzag_program(n_targets, step_mm=2.0):
    """A program of `n_targets` linear moves in a 300 x 300 mm field, {B} = {R}."""
    per_row = 150
    moves = []
    for k in range(n_targets):
        row, col = divmod(k, per_row)
        x = col * step_mm if row % 2 == 0 else (per_row - 1 - col) * step_mm
        y = (row % 150) * step_mm
        T = np.eye(4)
        T[:3, :3] = DOWN
        T[:3, 3] = (900 + x, -150 + y, 500)
        kind = ir.JOINT if k == 0 else ir.LINEAR
        moves.append(ir.Move(kind, ir.Target("p%d" % k, T), 50.0, 1.0, "B"))
    frame = ir.WorkFrame("B", np.eye(4), np.eye(4))
    tool = ir.ToolData("t", np.eye(4) @ np.diag([1, 1, 1, 1.0]))
    tool.T_f_t[:3, 3] = (0, 0, 250)
    return ir.Program("Bench", "ABB_IRB2400", tool, {"B": frame}, [ir.ProgramPath("p", "p", moves)])


def table_obstacle():
    import trimesh
    table = trimesh.creation.box(extents=(600, 600, 40))
    table.apply_translation((1050, 0, 460))  # top face 20 mm under the TCP plane z = 500
    return [("Table", table)]


def time_check(n_targets, model, checker):
    program = zigzag_program(n_targets)
    start = time.perf_counter()
    solution = configuration.solve_program(program, model)
    solved = time.perf_counter()
    # Sampled once for both, as api.check does.
    sampled = move_sampling.sample_program(program, model, solution, checks.Margins())
    report = checks.check_program(program, model, solution, sampled=sampled)
    checked = time.perf_counter()
    hits = collision.program_collision_findings(program, solution, checker, sampled=sampled)
    done = time.perf_counter()
    assert solution.ok and report.ok and not hits, "the benchmark program must be valid"
    return solved - start, checked - solved, done - checked


#: Issue 12's targets (every check on, one core) and its figures before the work, s.
TARGET_S = {10000: 1.0, 100000: 10.0}
BEFORE_S = {10000: 16.0, 100000: 160}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="1000,10000,100000")
    args = parser.parse_args()
    model = models.model("ABB_IRB2400")
    checker = collision.RobotCollisionChecker(model, table_obstacle(), tool_T_f_t=zigzag_program(1).tool.T_f_t)
    print("check engine, ABB_IRB2400, one core (seconds; 'per 1k' flat = linear growth)")
    print("%9s %10s %10s %11s %10s %10s" % ("targets", "solve", "checks", "collisions", "total",
                                           "per 1k"))
    for n in (int(s) for s in args.sizes.split(",")):
        solve_s, checks_s, collide_s = time_check(n, model, checker)
        total = solve_s + checks_s + collide_s
        target = TARGET_S.get(n)
        print("%9d %10.2f %10.2f %11.2f %10.2f %10.3f   %s" % (
            n, solve_s, checks_s, collide_s, total, 1000.0 * total / n,
            "" if target is None else "target <= %g s: %s (issue's figure before: %s s)" % (
                target, "met" if total <= target else "NOT met", BEFORE_S[n])))


if __name__ == "__main__":
    main()
