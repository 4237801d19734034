#!/usr/bin/env python3
r"""Closed-form IK of the arms that are neither OPW nor UR (issue 24), against the numerical IK.

Run it with FreeCAD's Python (numpy, numba)::

    /usr/bin/python3 bench/bench_chain_ik.py [--n 100000] [--n-numeric 100]

What is measured (one core: the process is pinned to one CPU and BLAS to one thread),
per arm of the robot data folder (tests/data/robots), on poses that are FK of random
joint values within the limits:

* "poses/s": N / CPU seconds of this process (``time.process_time``: on a machine shared
  with other jobs wall time also counts their turns on the core) of one
  ``chain_classes.Solver.inverse`` call on N poses (what the
  catalog's models run: for an offset wrist the search and its repair next to the wrist
  alignment, :mod:`.offset_wrist_polish`), best of 3 after a call that loads the compiled
  kernel, every solution of every pose; "numpy": the class's numpy code, which the kernel
  falls back to, alone (fewer poses);
* "found": share of poses whose generating joint set is among the solutions (1e-6 rad;
  next to a singularity, 1e-8 mm of the pose can leave the joints looser than that);
* "numeric poses/s": ``numeric_ik.solve(..., max_solutions=16)`` on the first poses, and
  "x numeric" the ratio.
Each class of arm has its own function (``offset_wrist_rows``, ``spherical_wrist_rows``).
The seven UR arms of the catalog (``ur_rows``: :mod:`CadRobotWB.robots.kinematics.ur`,
numpy, no compiled kernel; "numpy p/s" is the same call) close the table, so that it
shows every catalog arm that is not OPW.
Without the data folder the benchmark says so and exits 0.
"""

import argparse
import os
import sys
import time

import one_core  # noqa: F401,E402  (one core, one thread; before numpy)

import numpy as np  # noqa: E402

from CadRobotWB.robots.catalog import catalog  # noqa: E402
from CadRobotWB.robots.kinematics import (  # noqa: E402
    chain_classes, models, offset_wrist, offset_wrist_kernel, poe, spherical_wrist, spherical_wrist_kernel)
from CadRobotWB.robots.urdf import numeric_ik, urdf  # noqa: E402

DEFAULT_DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "data",
                            "robots")
TARGET_POSES_S = 100000
LINE = "%-22s %-16s %-8s %8s %11s %11s %7s %11s %10s"


def best_seconds(solve, T, runs=3):
    """The least CPU seconds of `runs` calls solve(T), after one that loads the kernel."""
    solve(T[:1])
    best = float("inf")
    for _ in range(runs):
        start = time.process_time()
        solve(T)
        best = min(best, time.process_time() - start)
    return best


def arm_row(module, kernel, folder, data, args):
    """One arm solved by `module` (spherical_wrist, ...; its numba kernel `kernel`): the
    row's values."""
    chain = urdf.serial_chain(urdf.read_urdf(os.path.join(data, folder, "robot.urdf")))
    params = poe.from_chain(chain)
    solver = chain_classes.Solver(params)        # what the catalog's models call
    assert solver.module is module, folder
    constants = solver.constants
    rng = np.random.default_rng(args.seed)
    q = rng.uniform(np.maximum(chain.lower_rad, -np.pi), np.minimum(chain.upper_rad, np.pi),
                    (args.n, 6))
    T = poe.fk(params, q)
    compiled = kernel.available()
    seconds = best_seconds(solver.inverse, T)
    Q = solver.inverse(T)
    valid = ~np.isnan(Q[..., 0])
    gap = np.abs((Q - q[:, None] + np.pi) % (2 * np.pi) - np.pi).max(axis=2)
    found = np.mean(np.where(valid, gap, np.inf).min(axis=1) <= 1e-6)
    n_numpy = min(args.n, args.n_numpy)
    numpy_seconds = best_seconds(lambda T: module.inverse_numpy(constants, T), T[:n_numpy], 1)
    n_numeric = min(args.n, args.n_numeric)
    start = time.process_time()
    numeric_ik.solve(chain, T[:n_numeric], max_solutions=16)
    numeric_rate = n_numeric / (time.process_time() - start)
    rate = args.n / seconds
    return dict(arm=folder, kind=module.KIND, how="numba" if compiled else "numpy", n=args.n,
                rate=rate, numpy_rate=n_numpy / numpy_seconds, per_pose=valid.sum() / args.n,
                found=found, numeric_rate=numeric_rate)


def spherical_wrist_rows(data, args):
    """The five KUKA files that round pi/2 to 1.5708, and the IRB 2400 (exact OPW) for scale."""
    arms = ["kuka_kr10_r1100_3", "kuka_kr120_r2700_2", "kuka_kr13_r900_3", "kuka_kr16_r1100_3",
            "kuka_kr20_r1820_2_e", "abb_irb2400"]
    return [arm_row(spherical_wrist, spherical_wrist_kernel, folder, data, args)
            for folder in arms]


#: The numpy rows of the offset-wrist search: at most this many poses (about 1,000 poses/s).
OFFSET_WRIST_NUMPY_POSES = 1000


def offset_wrist_rows(data, args):
    """The seven offset-wrist cobots (FANUC CRX-10iA/L, M-430iA/2P, Yaskawa HC10 family, ABB
    CRB 15000) and the Yaskawa MPX3500 (oblique wrist)."""
    arms = ["fanuc_crx10ial", "fanuc_m430ia2p", "motoman_hc10", "motoman_hc10dt",
            "motoman_hc10dt_b10", "motoman_hc10dtp_b00", "abb_crb15000_5_95", "motoman_mpx3500"]
    fewer = argparse.Namespace(**vars(args))
    fewer.n_numpy = min(args.n_numpy, OFFSET_WRIST_NUMPY_POSES)
    return [arm_row(offset_wrist, offset_wrist_kernel, folder, data, fewer) for folder in arms]


def ur_row(name, folder, data, args):
    """One UR arm of the catalog: ``model.ik`` (degrees in and out) on the poses of its
    URDF's random joints, and the numerical IK on the URDF."""
    model = models.model(name)
    chain = urdf.serial_chain(urdf.read_urdf(os.path.join(data, folder, "robot.urdf")))
    rng = np.random.default_rng(args.seed)
    q = np.degrees(rng.uniform(np.maximum(chain.lower_rad, -np.pi),
                               np.minimum(chain.upper_rad, np.pi), (args.n, 6)))
    T = model.fk(q)
    seconds = best_seconds(model.ik, T)
    Q = model.ik(T)
    valid = ~np.isnan(Q[..., 0])
    gap = np.abs((Q - q[:, None] + 180.0) % 360.0 - 180.0).max(axis=2)
    found = np.mean(np.where(valid, gap, np.inf).min(axis=1) <= 1e-4)
    n_numeric = min(args.n, args.n_numeric)
    T_chain = urdf.chain_fk(chain, np.radians(q[:n_numeric]))
    start = time.process_time()
    numeric_ik.solve(chain, T_chain, max_solutions=16)
    numeric_rate = n_numeric / (time.process_time() - start)
    return dict(arm=name, kind="ur", how="numpy", n=args.n, rate=args.n / seconds,
                numpy_rate=args.n / seconds, per_pose=valid.sum() / args.n, found=found,
                numeric_rate=numeric_rate)


def ur_rows(data, args):
    """The UR arms of the catalog (kind "ur"), each with its URDF folder (name in lower case)."""
    names = sorted(n for n in catalog.builtin_names() if models.model(n).kind == "ur")
    return [ur_row(name, name.lower(), data, args) for name in names]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100000, help="poses per arm")
    parser.add_argument("--n-numpy", type=int, default=10000, help="poses for the numpy rows")
    parser.add_argument("--n-numeric", type=int, default=100, help="poses for the numerical IK")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--data", default=DEFAULT_DATA)
    args = parser.parse_args()
    if not os.path.isdir(args.data):
        print("chain IK benchmark skipped: no robot data folder at %s" % os.path.abspath(args.data))
        return 0
    print("closed-form IK of non-OPW arms, all solutions, one core, %d poses per arm" % args.n)
    print(LINE % ("arm", "class", "kernel", "sols/pose", "poses/s", "numpy p/s", "found",
                  "numeric p/s", "x numeric"))
    rows = (offset_wrist_rows(args.data, args) + spherical_wrist_rows(args.data, args)
            + ur_rows(args.data, args))
    for r in rows:
        print(LINE % (r["arm"], r["kind"], r["how"], "%.2f" % r["per_pose"],
                      "{:,.0f}".format(r["rate"]), "{:,.0f}".format(r["numpy_rate"]),
                      "%.3f%%" % (100 * r["found"]), "{:,.0f}".format(r["numeric_rate"]),
                      "%.0fx" % (r["rate"] / r["numeric_rate"])))
    slow = [r["arm"] for r in rows if r["rate"] < TARGET_POSES_S]
    print("issue 24 target >= %s poses/s with all solutions: %s"
          % ("{:,}".format(TARGET_POSES_S), "met" if not slow else "NOT met by " + ", ".join(slow)))
    for kernel in (offset_wrist_kernel, spherical_wrist_kernel):
        if not kernel.available():
            print("numba kernel not used (%s): %s" % (kernel.__name__, kernel.why_not))
    return 0


if __name__ == "__main__":
    sys.exit(main())
