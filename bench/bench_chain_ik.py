#!/usr/bin/env python3
r"""IK benchmark of the arms that are neither OPW nor UR: the offset-wrist search
(:mod:`CadRobotWB.robots.kinematics.offset_wrist`, every solution) on the URDF arms of
the robot data folder (tests/data/robots), against the numerical IK of the same
chain, and the OPW closed form of the IRB 2400 in the same run (how fast this machine
is now: the same code measures 9-10 million poses/s on an idle core).

Run it with FreeCAD's Python::

    /usr/bin/python3 bench/bench_chain_ik.py [--n 20000] [--n-numpy 300] [--n-peer 100]

What is measured (one core, one thread), poses FK of random joint values within the
limits:

* "poses/s": N / seconds of one ``offset_wrist.inverse`` call, best of 3, after a
  first call that loads the compiled code ("numpy": ``inverse_numpy``, what runs
  without numba, on --n-numpy poses);
* "sols/pose": solutions per pose; "joints found": share of poses whose generating
  joint set is among them;
* peer: ``numeric_ik.solve(chain, T, max_solutions=16)`` on --n-peer poses; "x peer"
  is the ratio of the two speeds.
Without the data folder the benchmark says so and exits 0.
"""

import argparse
import os
import sys
import time

import one_core  # noqa: F401,E402  (one core, one thread; before numpy)

import numpy as np  # noqa: E402

from CadRobotWB.robots.kinematics import (  # noqa: E402
    models, offset_wrist, offset_wrist_kernel, poe)
from CadRobotWB.robots.urdf import numeric_ik, urdf  # noqa: E402

ARMS = ["fanuc_crx10ial", "fanuc_m430ia2p", "motoman_hc10", "motoman_hc10dt",
        "motoman_hc10dt_b10", "motoman_hc10dtp_b00", "abb_crb15000_5_95"]
DEFAULT_DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "data",
                            "robots")


def best_seconds(function, runs=3):
    best = float("inf")
    for _ in range(runs):
        start = time.perf_counter()
        function()
        best = min(best, time.perf_counter() - start)
    return best


def joints_found(Q, q):
    """Share of poses whose joints q (n, 6) are among the solutions Q (n, 16, 6), rad."""
    d = np.abs(offset_wrist.wrap_rad(Q - q[:, None, :])).max(axis=2)
    return float(np.mean(np.where(np.isnan(d), np.inf, d).min(axis=1) < 1e-9))


def bench_arm(folder, data, n, n_numpy, n_peer, seed):
    chain = urdf.serial_chain(urdf.read_urdf(os.path.join(data, folder, "robot.urdf")))
    params = poe.from_chain(chain)
    k = offset_wrist.recognise(params)
    rng = np.random.default_rng(seed)
    q = rng.uniform(np.maximum(chain.lower_rad, -np.pi), np.minimum(chain.upper_rad, np.pi), (n, 6))
    T = poe.fk(params, q)
    offset_wrist.inverse(k, T[:2])
    Q = offset_wrist.inverse(k, T)
    seconds = best_seconds(lambda: offset_wrist.inverse(k, T))
    numpy_seconds = best_seconds(lambda: offset_wrist.inverse_numpy(k, T[:n_numpy]), runs=1)
    start = time.perf_counter()
    numeric_ik.solve(chain, T[:n_peer], max_solutions=16)
    peer_rate = n_peer / (time.perf_counter() - start)
    return dict(arm=folder, rate=n / seconds, numpy_rate=n_numpy / numpy_seconds,
                per_pose=float((~np.isnan(Q[:, :, 0])).sum(axis=1).mean()),
                found=joints_found(Q, q), peer_rate=peer_rate)


def opw_rate(n, seed):
    """The IRB 2400's closed form (all 8 branches, compiled) on n poses, poses/s."""
    robot = models.model("ABB_IRB2400")
    q = np.random.default_rng(seed).uniform(-90.0, 90.0, (n, 6))
    T = robot.fk(q)
    robot.ik(T[:2])
    return n / best_seconds(lambda: robot.ik(T))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=20000, help="poses per arm")
    parser.add_argument("--n-numpy", type=int, default=300, help="poses for the numpy rows")
    parser.add_argument("--n-peer", type=int, default=100, help="poses for the numerical IK")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--data", default=DEFAULT_DATA)
    args = parser.parse_args()
    if not os.path.isdir(args.data):
        print("chain IK benchmark skipped: no robot data folder at %s" % os.path.abspath(args.data))
        return 0
    compiled = offset_wrist_kernel.available()
    print("offset-wrist IK (offset_wrist.inverse, all solutions, %s), one core, %d poses per arm"
          % ("compiled" if compiled else "numpy: " + offset_wrist_kernel.why_not, args.n))
    line = "%-20s %11s %11s %10s %13s %14s %9s"
    print(line % ("arm", "poses/s", "numpy p/s", "sols/pose", "joints found", "numeric p/s",
                  "x peer"))
    for folder in ARMS:
        r = bench_arm(folder, args.data, args.n, args.n_numpy, args.n_peer, args.seed)
        print(line % (r["arm"], "{:,.0f}".format(r["rate"]), "{:,.0f}".format(r["numpy_rate"]),
                      "%.2f" % r["per_pose"], "%.2f%%" % (100 * r["found"]),
                      "{:,.0f}".format(r["peer_rate"]), "%.0f" % (r["rate"] / r["peer_rate"])))
    print("machine now: OPW closed form (ABB_IRB2400, 8 branches) %s poses/s"
          % "{:,.0f}".format(opw_rate(200000, args.seed)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
