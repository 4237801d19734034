"""Seam tracking speed: simulated seconds per wall-clock second (issue 5; target >= 50x).

A 60 s run: a 600 mm straight butt joint (two 8 mm plates, 1.5 mm root gap,
on a table) welded at 10 mm/s, the laser 30 mm ahead at 5 Hz, 10 ms time
step (6000 samples, 286 profiles of 200 rays). The real part is moved 5 mm
sideways, 2 mm up and turned 1° about the seam's middle (about its start,
the 600 mm seam would need more than the 15 mm correction limit). Rows: open
loop, PI and Fuzzy-PI with a two-point real seam, and PI with a dense real
seam (one point per sample, what ``sensors.scene.run_scene`` passes) and a
robot reach check.

    /usr/bin/python3 bench/bench_seam.py [--repeat 3]

One core (the process is pinned to one CPU, BLAS to one thread); best of
`--repeat`. Printed, never asserted. (`make bench` runs it with FreeCAD's
package folder on PYTHONPATH for trimesh.)
"""

import argparse
import time

import one_core  # noqa: F401,E402  (one core, one thread; before numpy)

import numpy as np  # noqa: E402
import trimesh  # noqa: E402
from scipy.spatial.transform import Rotation  # noqa: E402

from CadRobotWB.core import program as ir  # noqa: E402
from CadRobotWB.core.trajectory import tcp_trajectory  # noqa: E402
from CadRobotWB.sensors.reality import Reality  # noqa: E402
from CadRobotWB.sensors.seam_features import JointTemplate  # noqa: E402
from CadRobotWB.sensors.seam_tracking import simulate_seam_tracking  # noqa: E402

LENGTH_MM = 600.0
TOP_MM = 8.0
DOWN = np.diag([1.0, -1.0, -1.0])       # tool Z pointing down, X along the seam


def box(low, high):
    low, high = np.asarray(low, float), np.asarray(high, float)
    return trimesh.creation.box(high - low, trimesh.transformations.translation_matrix((low + high) / 2))


def scene():
    """(nominal trajectory, real mesh, real seam, reality)."""
    g = 0.75
    cad = trimesh.util.concatenate([box((-50, -100, 0), (LENGTH_MM + 50, -g, TOP_MM)),
                                    box((-50, g, 0), (LENGTH_MM + 50, 100, TOP_MM)),
                                    box((-50, -100, -20), (LENGTH_MM + 50, 100, 0))])
    moves = []
    for k, x in enumerate((0.0, LENGTH_MM)):
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = DOWN, (x, 0.0, TOP_MM)
        moves.append(ir.Move(ir.JOINT if k == 0 else ir.LINEAR, ir.Target("p%d" % k, T), 10.0, 0.0, "B"))
    program = ir.Program("Bench", "ABB_IRB2400", ir.ToolData("t", np.eye(4)),
                         {"B": ir.WorkFrame("B", np.eye(4), np.eye(4))}, [ir.ProgramPath("p", "p", moves)])
    trajectory = tcp_trajectory(program, 0.01, first_move=1)
    middle = np.array([LENGTH_MM / 2, 0.0, TOP_MM])
    T_u_dev = np.eye(4)
    T_u_dev[:3, :3] = Rotation.from_euler("z", 1.0, degrees=True).as_matrix()
    T_u_dev[:3, 3] = middle - T_u_dev[:3, :3] @ middle + [0.0, 5.0, 2.0]
    reality = Reality(T_u_dev=T_u_dev, laser_noise_mm=0.02, seed=0)
    real = cad.copy()
    real.apply_transform(T_u_dev)
    return trajectory, real, reality


def reach_check(T_u_t):
    """A stand-in for the robot's reach check (about the cost of one IK call)."""
    return None if np.linalg.norm(T_u_t[:3, 3]) < 2000.0 else "out of reach"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    trajectory, real, reality = scene()
    simulated_s = float(trajectory.time_s[-1])
    two_points = reality.rigid_points([(-50.0, 0.0, TOP_MM), (LENGTH_MM + 50, 0.0, TOP_MM)])
    dense = reality.rigid_points(trajectory.position_mm)
    rows = [("open loop", "none", two_points, None), ("PI", "pi", two_points, None),
            ("Fuzzy-PI", "fuzzy_pi", two_points, None), ("PI, dense seam + reach", "pi", dense, reach_check)]
    print("seam tracking, %.0f s run (%d samples at 10 ms, 5 Hz laser), one core, best of %d"
          % (simulated_s, len(trajectory.time_s), args.repeat))
    print_runs(rows, simulated_s, args.repeat,
               lambda controller, seam, check: simulate_seam_tracking(
                   trajectory, real, seam, reality, JointTemplate("butt", gap_mm=1.5),
                   controller=controller, reach_check=check))


def print_runs(rows, simulated_s, repeat, simulate):
    """Time each row's run (best of `repeat`) and print the table.

    Parameters
    ----------
    rows : list of (label, controller, real seam, reach check)
    simulated_s : float
        Simulated time of one run, s.
    simulate : callable
        ``simulate(controller, seam, check) -> SensorRun``.
    """
    print("%-24s %8s %10s %12s %14s" % ("case", "wall s", "x realtime", "rms>20mm mm", "open-loop mm"))
    for label, controller, seam, check in rows:
        best = np.inf
        for _ in range(repeat):
            start = time.perf_counter()
            run = simulate(controller, seam, check)
            best = min(best, time.perf_counter() - start)
        print("%-24s %8.3f %10.0f %12.3f %14.3f" % (label, best, simulated_s / best,
                                                     run.metrics["rms_error_after_20mm_mm"],
                                                     run.metrics["open_loop_rms_error_mm"]))


if __name__ == "__main__":
    main()
