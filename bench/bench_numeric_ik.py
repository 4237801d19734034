#!/usr/bin/env python3
r"""Numerical IK benchmark: :func:`CadRobotWB.robots.urdf.numeric_ik.solve` on URDF arms of the
robot data folder (tests/data/robots), against the closed form where the arm has one.

Run it with FreeCAD's Python (numpy only)::

    /usr/bin/python3 bench/bench_numeric_ik.py [--n 200] [--data tests/data/robots]

What is measured (one core: the process is pinned to one CPU and BLAS to one
thread), one call per arm on N poses, FK of random joint values within the
limits:

* "poses/s": N / seconds of one ``solve`` call (every seed of every pose in
  one array; all solutions, up to 16 per pose);
* "sols/pose": distinct solutions found per pose, on average;
* "joints found": share of poses whose generating joint set is among them;
* for OPW / UR arms, "closed form": the closed form's solutions found by the
  numerical IK (within 1e-4 deg: near singularities the closed forms' own
  error reaches 2e-5 deg), and the closed form's own poses/s on the same poses.
Without the data folder the benchmark says so and exits 0.
"""

import argparse
import os
import sys
import time

import one_core  # noqa: F401,E402  (one core, one thread; before numpy)

import numpy as np  # noqa: E402

from CadRobotWB.robots.urdf import identify, numeric_ik, urdf  # noqa: E402

ARMS = ["fanuc_crx10ial", "motoman_hc10", "abb_crb15000_5_95", "kuka_kr16_r1100_3",
        "motoman_mpx3500", "abb_irb2400", "ur5e"]
CLOSED_TOL_DEG = 1e-4
DEFAULT_DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "data",
                            "robots")


def distance_deg(a, b):
    return np.abs((a - b + 180.0) % 360.0 - 180.0).max(axis=-1)


def bench_arm(folder, data, n, seed):
    chain = urdf.serial_chain(urdf.read_urdf(os.path.join(data, folder, "robot.urdf")))
    rng = np.random.default_rng(seed)
    q = rng.uniform(np.maximum(chain.lower_rad, -np.pi), np.minimum(chain.upper_rad, np.pi), (n, 6))
    T = urdf.chain_fk(chain, q)
    start = time.perf_counter()
    Q = numeric_ik.solve(chain, T, max_solutions=16)
    seconds = time.perf_counter() - start
    valid = ~np.isnan(Q[:, :, 0])
    d = np.where(valid, distance_deg(Q, np.degrees(q)[:, None, :]), np.inf)
    row = dict(arm=folder, n=n, seconds=seconds, per_pose=valid.sum() / n,
               found=float(np.mean(d.min(axis=1) <= 1e-6)), closed="", closed_rate="")
    try:
        model = identify.identify(chain, samples=100)
    except identify.KinematicsError:
        return row
    model.ik(T[:1])                 # the session's first call loads the compiled IK
    start = time.perf_counter()
    C = model.ik(T)
    closed_seconds = time.perf_counter() - start
    c_valid = ~np.isnan(C[:, :, 0])
    dc = distance_deg(C[:, :, None, :], Q[:, None, :, :])                   # (n, 8, 16)
    dc = np.where(valid[:, None, :], dc, np.inf).min(axis=2)
    # 1e-4 deg: near singularities the closed forms' own error reaches 2e-5 deg (UR5e: its
    # model fits the URDF to 2e-7 mm and 7e-10 rad; see tests/core/test_numeric_ik.py).
    row["closed"] = "%d/%d" % ((c_valid & (dc <= CLOSED_TOL_DEG)).sum(), c_valid.sum())
    row["closed_rate"] = "{:,.0f}".format(n / closed_seconds)
    return row


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=200, help="poses per arm")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--data", default=DEFAULT_DATA)
    args = parser.parse_args()
    if not os.path.isdir(args.data):
        print("numeric IK benchmark skipped: no robot data folder at %s"
              % os.path.abspath(args.data))
        return 0
    print("numerical IK (numeric_ik.solve, all solutions), one core, %d poses per arm" % args.n)
    line = "%-20s %8s %9s %10s %13s %13s %16s"
    print(line % ("arm", "time s", "poses/s", "sols/pose", "joints found", "closed form",
                  "closed poses/s"))
    for folder in ARMS:
        r = bench_arm(folder, args.data, args.n, args.seed)
        print(line % (r["arm"], "%.2f" % r["seconds"], "{:,.0f}".format(r["n"] / r["seconds"]),
                      "%.2f" % r["per_pose"], "%.1f%%" % (100 * r["found"]), r["closed"],
                      r["closed_rate"]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
