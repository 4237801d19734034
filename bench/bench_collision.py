#!/usr/bin/env python3
r"""Collision-check benchmark: ABB IRB 2400 with a welding torch in a cell made of
a floor, a table and two plates welded by a fillet seam.

Run it with FreeCAD's Python and the project's packages (trimesh, python-fcl)::

    PYTHONPATH="$(bash tools/setup.sh --print-packages-dir)" \
        /usr/bin/python3 bench/bench_collision.py [--n 3000]

What is measured (one core: the process is pinned to one CPU and BLAS to one
thread), best of 3, on two sets of poses:

* "seam": the torch on the fillet seam (TCP in the corner of the plates,
  work angle 35-55 degrees, travel angle +-15 degrees): every pose has the
  tool within millimetres of both plates, the hard case for the narrow phase;
* "random": joint values uniform within the joint limits.

Rows: ``RobotCollisionChecker.check`` with margin 0 (collisions only), with a
10 mm margin (distances of every pair closer than 10 mm), with self-collision
on; and, for comparison, trimesh's ``CollisionManager`` used the plain way
(the seven link solids and the tool as FCL meshes, ``set_transform`` each
per pose, then ``in_collision_other``: a yes/no and names per pose, no
distances, surfaces only).
"""

import argparse
import platform
import sys
import time

import one_core  # noqa: F401,E402  (one core, one thread; before numpy)

import numpy as np  # noqa: E402
import trimesh  # noqa: E402

from CadRobotWB.robots.checks import collision, links  # noqa: E402
from CadRobotWB.robots.kinematics import models  # noqa: E402

ROBOT = "ABB_IRB2400"


def box(lo, hi):
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    return trimesh.creation.box(hi - lo, transform=trimesh.transformations.translation_matrix(
        0.5 * (lo + hi)))


def cell():
    """(name, mesh) obstacles in {R}, mm; the seam runs along y at (900, y, 710)."""
    return [("Floor", box([-2000, -2000, -20], [2000, 2000, 0])),
            ("Table", box([600, -500, 0], [1300, 500, 700])),
            ("Plate", box([650, -200, 700], [1150, 200, 710])),
            ("Web", box([900, -200, 710], [910, 200, 910]))]


def tool():
    T_f_t = np.eye(4)
    T_f_t[:3, 3] = (0.0, 0.0, 250.0)
    return T_f_t


def rot_y(deg):
    c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rot_x(deg):
    c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def seam_poses(robot, n, seed):
    """Joint values (<= n, 6) with the torch's TCP on the fillet seam."""
    rng = np.random.default_rng(seed)
    T_r_t = np.tile(np.eye(4), (n, 1, 1))
    for k in range(n):
        work, travel = rng.uniform(35.0, 55.0), rng.uniform(-15.0, 15.0)
        T_r_t[k, :3, :3] = rot_x(travel) @ rot_y(-work) @ np.diag([-1.0, 1.0, -1.0])
        T_r_t[k, :3, 3] = (900.0, rng.uniform(-150.0, 150.0), 710.0)
    solutions = robot.ik(T_r_t @ np.linalg.inv(tool()))
    ok = robot.within_limits(solutions)
    first = [sols[mask][0] for sols, mask in zip(solutions, ok) if mask.any()]
    return np.array(first)


def random_poses(robot, n, seed):
    rng = np.random.default_rng(seed)
    return rng.uniform(robot.joint_min_deg, robot.joint_max_deg, (n, 6))


def best_of(fn, repeats=3):
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        result = fn()
        best = min(best, time.perf_counter() - start)
    return best, result


def bench_checker(q, **options):
    checker = collision.RobotCollisionChecker(ROBOT, cell(), tool_T_f_t=tool(), **options)
    seconds, findings = best_of(lambda: checker.check(q))
    hit = np.mean([any(f.distance_mm <= 0 for f in pose) for pose in findings])
    near = np.mean([bool(pose) for pose in findings])
    return seconds, hit, near


def bench_trimesh_manager(q):
    """trimesh's CollisionManager, the plain way: one object per link, transforms per pose."""
    robot = models.model(ROBOT)
    obstacles = trimesh.collision.CollisionManager()
    for name, mesh in cell():
        obstacles.add_object(name, mesh)
    arm = trimesh.collision.CollisionManager()
    solids = links.link_solids(robot)
    names = links.LINK_NAMES[1:] + ("tool",)
    for name, solid in zip(names, solids[1:] + [links.tool_solid(tool())]):
        arm.add_object(name, solid)
    frame_of = list(range(1, 7)) + [6]

    def run():
        frames = links.link_frames(robot, q)
        out = []
        for pose in frames:
            for name, i in zip(names, frame_of):
                arm.set_transform(name, pose[i])
            _, pairs = arm.in_collision_other(obstacles, return_names=True)
            out.append(pairs)
        return out

    seconds, result = best_of(run)
    return seconds, float(np.mean([bool(r) for r in result])), float("nan")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, default=3000, help="poses per set")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args(argv)

    robot = models.model(ROBOT)
    sets = {"seam": seam_poses(robot, args.n, args.seed),
            "random": random_poses(robot, args.n, args.seed)}
    methods = [
        ("checker, margin 0", lambda q: bench_checker(q)),
        ("checker, margin 10 mm", lambda q: bench_checker(q, margin_mm=10.0)),
        ("checker, margin 0 + self", lambda q: bench_checker(q, self_collision=True)),
        ("trimesh CollisionManager", bench_trimesh_manager),
    ]
    import fcl
    print("Collision benchmark on one core: %s, tool + floor, table, 2 plates "
          "(%s, Python %s, numpy %s, trimesh %s, python-fcl %s)"
          % (ROBOT, platform.processor() or platform.machine(), platform.python_version(),
             np.__version__, trimesh.__version__, getattr(fcl, "__version__", "?")))
    line = "%-26s %-7s %6s %8s %9s %10s %12s"
    print(line % ("method", "poses", "n", "time s", "poses/s", "colliding", "within margin"))
    for label, run in methods:
        for set_name, q in sets.items():
            seconds, hit, near = run(q)
            print(line % (label, set_name, len(q), "%.3f" % seconds,
                          "{:,.0f}".format(len(q) / seconds), "%.1f%%" % (100 * hit),
                          "-" if np.isnan(near) else "%.1f%%" % (100 * near)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
