"""Choosing external axes: 1,000 seam targets in at most 1 s on one core (issue 23).

The seam: tests/core/external_fixtures.py's pipe-to-flange fillet welded all round
on the generic tilt-and-turn positioner, as 500 circular moves (1,000 seam targets
with their vias, 1,003 targets with the approach, the entry's and the retract),
once without and once with the robot on a track. Rows:

* ``choose_external``: the chooser (closed form, every candidate's IK in one call,
  the track, the retries, the speed pass); its worst gravity angle over the seam;
  once more with the seam welded at 98 mm/s, where the exact flat values need the
  turn at 93.6 deg/s (limit 90): the speed pass moves them within the tolerance
  (one linear programme over the 1,000 targets), so the worst gravity angle is
  no longer 0;
* peer, ``scipy.optimize.minimize`` per target: the same flat position found by a
  general optimiser, one solve per seam target (Nelder-Mead on (tilt, turn), each
  started from the previous answer, the gravity angle as the cost; no arm, no
  track): what the chooser replaces; its worst gravity angle;
* for scale, ``solve_program``: the arm's own joint solve of the same program
  afterwards (what ``cadrobot check`` runs next).

    /usr/bin/python3 bench/bench_external.py [--arcs 500] [--repeat 3]

One core (the process is pinned to one CPU, BLAS to one thread); best of
`--repeat` (the peer once, on its first `--peer-targets` seam targets, its time
scaled to the whole program). Printed, never asserted.
"""

import argparse
import os
import sys
import time

import one_core  # noqa: F401  (one core, one thread; before numpy)

import numpy as np  # noqa: E402
from scipy.optimize import minimize  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                "tests", "core"))

from external_fixtures import T_U_B, positioner_weld_program  # noqa: E402

from CadRobotWB.robots.kinematics import models  # noqa: E402
from CadRobotWB.robots.mechanisms.choose import choose_external  # noqa: E402
from CadRobotWB.robots.motion import configuration  # noqa: E402

TARGET_S = 1.0
#: A welding speed at which the seam's exact flat values turn the table too fast.
FAST_MM_S = 98.0


def cleared(program):
    for target in program.targets():
        target.external = None
    return program


def best_time(function, repeat):
    """(best wall time of `repeat` calls, s; the last result)."""
    best, result = np.inf, None
    for _ in range(repeat):
        start = time.perf_counter()
        result = function()
        best = min(best, time.perf_counter() - start)
    return best, result


def peer_minimize(program, count):
    """Per seam target, Nelder-Mead on the positioner's (tilt, turn) minimising the
    angle of the torch axis (perpendicular to the travel on this seam) to gravity,
    started from the previous target's answer (the first from the drawn values
    plus 5 degrees each: at tilt 0 the cost does not depend on the turn).

    Returns
    -------
    worst gravity angle (deg), targets solved (the first `count` seam targets)
    """
    positioner = program.external.positioner
    _, drawn = program.external.split(program.external.drawn_at())
    seam = program.targets()[1:1 + count]
    worst, start = 0.0, drawn + 5.0
    for target in seam:
        z_b = target.T_b_t[:3, 2]

        def cost(v):            # 1 - cos(gravity angle): smooth at the optimum
            z_u = (positioner.motion(v) @ T_U_B)[:3, :3] @ z_b
            return 1.0 + z_u[2]

        result = minimize(cost, start, method="Nelder-Mead",
                          options={"xatol": 1e-4, "fatol": 1e-12, "maxiter": 2000})
        angle = np.degrees(np.arccos(np.clip(1.0 - result.fun, -1.0, 1.0)))
        worst, start = max(worst, float(angle)), result.x
    return worst, len(seam)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--arcs", type=int, default=500)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--peer-targets", type=int, default=100,
                        help="seam targets the peer solves (its time is scaled to 1,000)")
    args = parser.parse_args()
    model = models.model("ABB_IRB2400")
    model.ik(np.eye(4)[None])                                   # load the compiled IK
    n = len(positioner_weld_program(arcs=args.arcs).targets())
    print("choosing external axes, %d targets (%d seam), ABB_IRB2400, one core, best of %d"
          % (n, n - 3, args.repeat))
    print("%-62s %9s %10s %12s" % ("case", "wall s", "per 1k s", "worst grav."))
    rows = []
    for track, speed in ((False, None), (True, None), (False, FAST_MM_S)):
        program = positioner_weld_program(arcs=args.arcs, track=track)
        label = "choose_external, positioner%s" % (" + track" if track else "")
        if speed is not None:
            for move in program.paths[0].moves[2:-1]:
                move.speed_mm_s = speed
            label += ", %g mm/s (turn limited)" % speed
        wall, choice = best_time(lambda: choose_external(cleared(program), model), args.repeat)
        rows.append((label, wall, choice.worst_gravity_deg["Weld"]))
        if not track and speed is None:
            chooser_s = wall
            solve_s, _ = best_time(lambda: configuration.solve_program(program, model, assign=False),
                                   args.repeat)
    program = positioner_weld_program(arcs=args.arcs)
    start = time.perf_counter()
    worst, solved = peer_minimize(program, args.peer_targets)
    peer_s = (time.perf_counter() - start) * n / solved          # scaled to the whole program
    rows.append(("peer: scipy minimize per target (%d, scaled)" % solved, peer_s, worst))
    rows.append(("for scale: solve_program (arm joints)", solve_s, np.nan))
    for label, wall, grav in rows:
        print("%-62s %9.3f %10.3f %12s" % (label, wall, 1000.0 * wall / n,
                                           "-" if np.isnan(grav) else "%.2g deg" % grav))
    chooser_worst_s = max(r[1] for r in rows[:3])
    print("chooser %.0fx faster than the peer; target <= %g s per 1,000 targets: %s"
          % (peer_s / chooser_s, TARGET_S,
             "met" if chooser_worst_s * 1000.0 / n <= TARGET_S else "NOT met"))


if __name__ == "__main__":
    main()
