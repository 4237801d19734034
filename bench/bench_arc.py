"""Through-arc tracking speed: simulated seconds per wall-clock second (issue 22; target >= 100x).

A 60 s weld: a 450 mm fillet (T-joint of two plates) welded at 7.5 mm/s with a
4 mm zigzag weave at 2 Hz (0.1 s dwells), the current sampled every 2 ms
(30 000 samples, 120 weave cycles, each cycle's 250 CTWDs ray-cast on the real
part). The real part is moved 3 mm sideways and 2 mm toward the torch (the
issue's case); 5 A RMS current noise. Rows: open loop, the per-cycle law with a
two-point real seam, and with a dense real seam (one point per sample, what
``sensors.scene.run_scene`` passes) and a robot reach check each cycle.

    /usr/bin/python3 bench/bench_arc.py [--repeat 3]

One core (the process is pinned to one CPU, BLAS to one thread); best of
`--repeat`. Printed, never asserted. (`make bench` runs it with FreeCAD's
package folder on PYTHONPATH for trimesh.)
"""

import argparse

import one_core  # noqa: F401,E402  (one core, one thread; before numpy)

import numpy as np  # noqa: E402
import trimesh  # noqa: E402

from CadRobotWB.core import program as ir  # noqa: E402
from CadRobotWB.core.trajectory import tcp_trajectory  # noqa: E402
from CadRobotWB.core.welding import Weave, WeldSchedule  # noqa: E402
from CadRobotWB.sensors.arc_tracking import simulate_arc_tracking  # noqa: E402
from CadRobotWB.sensors.reality import Reality  # noqa: E402
from bench_seam import box, print_runs, reach_check  # noqa: E402  (the same boxes, reach stand-in, table)

LENGTH_MM = 450.0
TOOL_Z = np.array([0.0, 1.0, -1.0]) / np.sqrt(2)      # into the corner on the bisector
TORCH = np.column_stack([(1.0, 0.0, 0.0), np.cross(TOOL_Z, (1.0, 0.0, 0.0)), TOOL_Z])
#: tests/core/weld_fixtures.py's FILLET_T6 and ZIGZAG_4MM.
SCHEDULE = WeldSchedule(name="fillet_t6", wire_feed_m_min=6.7, voltage_v=27.5, current_a=265.0,
                        travel_speed_mm_s=7.5, ctwd_mm=15.0).validated()
WEAVE = Weave("zigzag", width_mm=4.0, frequency_hz=2.0, dwell_left_s=0.1,
              dwell_right_s=0.1).validated()


def scene():
    """(nominal trajectory, real mesh, reality)."""
    cad = trimesh.util.concatenate([box((-50, -60, -10), (LENGTH_MM + 50, 10, 0)),
                                    box((-50, 0, 0), (LENGTH_MM + 50, 10, 60))])
    moves = []
    for k, x in enumerate((0.0, LENGTH_MM)):
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = TORCH, (x, 0.0, 0.0)
        moves.append(ir.Move(ir.JOINT if k == 0 else ir.LINEAR, ir.Target("p%d" % k, T),
                             SCHEDULE.travel_speed_mm_s, 0.0, "B"))
    program = ir.Program("Bench", "ABB_IRB2400", ir.ToolData("t", np.eye(4)),
                         {"B": ir.WorkFrame("B", np.eye(4), np.eye(4))}, [ir.ProgramPath("p", "p", moves)])
    trajectory = tcp_trajectory(program, 0.002, first_move=1)
    T_u_dev = np.eye(4)
    T_u_dev[:3, 3] = 3.0 * TORCH[:, 1] - 2.0 * TOOL_Z
    reality = Reality(T_u_dev=T_u_dev, arc_current_noise_a=5.0, seed=0)
    real = cad.copy()
    real.apply_transform(T_u_dev)
    return trajectory, real, reality


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    trajectory, real, reality = scene()
    simulated_s = float(trajectory.time_s[-1])
    two_points = reality.rigid_points([(-50.0, 0.0, 0.0), (LENGTH_MM + 50, 0.0, 0.0)])
    dense = reality.rigid_points(trajectory.position_mm)
    rows = [("open loop", "none", two_points, None), ("per-cycle law", "pi", two_points, None),
            ("law, dense seam + reach", "pi", dense, reach_check)]
    print("through-arc tracking, %.0f s weld (%d samples at 2 ms, %d weave cycles), one core, "
          "best of %d" % (simulated_s, len(trajectory.time_s),
                          round(simulated_s * WEAVE.frequency_hz), args.repeat))
    print_runs(rows, simulated_s, args.repeat,
               lambda controller, seam, check: simulate_arc_tracking(
                   trajectory, real, seam, reality, WEAVE, SCHEDULE, controller=controller,
                   reach_check=check))


if __name__ == "__main__":
    main()
