"""Robustness sweep: how large a calibration or placement error can the sensor absorb?

Many runs of one :class:`sensors.scene.SensorScene`, each with a random rigid
deviation of the workpiece, on all local cores or on a Dask cluster. No
FreeCAD here: the scene is read from the document once, then shipped to the
workers as plain data (and this package with it, to a remote cluster).

Local workers are forked on Linux and spawned elsewhere (Windows, macOS):
:func:`run_one` is a top-level function of a module that does not import
FreeCAD, and its arguments are picklable, so a spawned worker imports only
this package.  A Dask cluster needs the optional package ``distributed``.
"""

import contextlib
import multiprocessing
import os
import socket
import shutil
import sys
import tempfile
import zipfile
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from . import dependencies, limits
from .core import rotations
from .core.progress import report_now
from .errors import InputError, MissingPackageError
from .objects.validate import number_in_range
from .sensors.reality import Reality
from .sensors.run import SEAM_SENSORS

AXES = ("x", "y", "z", "rx", "ry", "rz")

#: The pip name of the package a Dask cluster needs.
DASK_PACKAGE = "distributed"


def parse_ranges(text):
    """``"x=-5:5,rz=-2:2"`` -> {"x": (-5, 5), "rz": (-2, 2)} (mm, degrees)."""
    ranges = {}
    for item in filter(None, (part.strip() for part in text.split(","))):
        name, _, span = item.partition("=")
        lo, _, hi = span.partition(":")
        try:
            if name not in AXES:
                raise ValueError
            ranges[name] = (float(lo), float(hi))
            if not np.isfinite(ranges[name]).all() or not np.isfinite(ranges[name][1] - ranges[name][0]):
                raise ValueError
        except ValueError:
            raise InputError("Bad range '%s': write axis=low:high with axis one of %s and finite "
                             "numbers, e.g. x=-5:5,rz=-2:2 (mm, degrees)." % (item, ", ".join(AXES))) \
                from None
        if ranges[name][0] > ranges[name][1]:
            raise InputError("Range '%s' runs backwards; write low:high." % item)
    if not ranges:
        raise InputError("Give at least one range, e.g. --ranges x=-5:5,y=-5:5.")
    return ranges


def sample_deviations(ranges, count, seed=0):
    """(count, 6) deviations x, y, z (mm), rx, ry, rz (degrees), uniform in `ranges`;
    `count` at most ``limits.MAX_SWEEP_RUNS``."""
    count = limits.sweep_runs(count, "The sweep's runs")
    rng = np.random.default_rng(limits.seed(seed, "The sweep's seed"))
    rows = np.zeros((count, 6))
    for k, axis in enumerate(AXES):
        if axis in ranges:
            rows[:, k] = rng.uniform(*ranges[axis], size=int(count))
    return rows


def deviation_transform(row, centre_mm=(0.0, 0.0, 0.0)):
    """4x4 in {U} of x, y, z (mm), rx, ry, rz (degrees about the fixed X, Y, Z
    axes), the rotation turning about `centre_mm`."""
    row = np.asarray(row, dtype=float)
    centre = np.asarray(centre_mm, dtype=float)
    T = np.eye(4)
    T[:3, :3] = rotations.matrix_from_euler_xyz_fixed(*np.radians(row[3:]))
    T[:3, 3] = row[:3] + centre - T[:3, :3] @ centre
    return T


def run_one(scene, row, controller, rate_hz, seed, tolerance):
    """One run of the sweep; returns a small summary dict (picklable)."""
    from .sensors.scene import run_scene
    centre = scene.trajectory.position_mm[0]   # turn the part about the path's start
    run = run_scene(scene, Reality(T_u_dev=deviation_transform(row, centre), seed=seed), controller,
                    rate_hz)
    metrics = run.metrics
    if scene.sensor in SEAM_SENSORS:
        residual = float(metrics.get("rms_error_after_20mm_mm", np.nan))
    else:
        residual = float(metrics.get("rms_force_error_pct", np.nan))
    return {"deviation": [float(v) for v in row], "aborted": bool(run.aborted), "reason": run.reason,
            "residual": residual,
            "success": bool(not run.aborted and np.isfinite(residual) and residual <= tolerance)}


def _python_for_workers():
    """The interpreter for spawned worker processes (str).

    Inside FreeCAD ``sys.executable`` is FreeCAD itself: then the Python its
    bundle ships beside it (Windows ``bin/python.exe``, macOS
    ``Contents/Resources/bin/python``), else a Python of the same version on
    PATH.

    Raises
    ------
    InputError
        No such interpreter was found.
    """
    if not os.path.basename(sys.executable).lower().startswith("freecad"):
        return sys.executable
    here = os.path.dirname(os.path.abspath(sys.executable))
    folders = (here, os.path.join(os.path.dirname(here), "Resources", "bin"))
    names = ("python.exe", "python3.exe", "python3", "python")
    for path in (os.path.join(folder, name) for folder in folders for name in names):
        if os.path.isfile(path):
            return path
    version = "python%d.%d" % sys.version_info[:2]
    found = shutil.which(version) or shutil.which("python3")
    if found is None:
        raise InputError("The sweep's worker processes need a %s interpreter beside FreeCAD or on "
                         "PATH and none was found; install one, or run the sweep with one worker."
                         % version)
    return found


def process_context(start_method=None):
    """The multiprocessing context of the local workers.

    Parameters
    ----------
    start_method : str, optional
        ``"fork"`` or ``"spawn"``; default fork on Linux (the workers start
        at once, without importing anything), spawn elsewhere (Windows and
        macOS, where fork is missing or unsafe).

    Returns
    -------
    multiprocessing.context.BaseContext
    """
    if start_method is None:
        start_method = "fork" if sys.platform.startswith("linux") else "spawn"
    context = multiprocessing.get_context(start_method)
    if start_method != "fork":
        context.set_executable(_python_for_workers())
    return context


def _package_zip(folder):
    """This package as a zip a Dask worker can import (Client.upload_file)."""
    root = os.path.dirname(os.path.abspath(__file__))
    path = os.path.join(folder, "CadRobotWB.zip")
    with zipfile.ZipFile(path, "w") as archive:
        for dirpath, _, files in os.walk(root):
            for name in files:
                if name.endswith(".py"):
                    full = os.path.join(dirpath, name)
                    archive.write(full, os.path.relpath(full, os.path.dirname(root)))
    return path


def run_sweep(scene, deviations, controller="pi", rate_hz=None, tolerance=None, workers=None,
              scheduler=None, seed=0, start_method=None, progress=None):
    """Run the scene once per deviation row.

    Parameters
    ----------
    deviations : ndarray, shape (N, 6)
    tolerance : float, optional
        Largest residual that counts as success: RMS seam error after 20 mm
        in mm (laser, default 0.5) or RMS force error in % (force, default 10).
    workers : int, optional
        Local processes (default: every core; 1 runs in this process).
        Ignored with `scheduler`.
    scheduler : str, optional
        Address of a Dask scheduler (``tcp://host:8786``), whose workers get
        this package uploaded; or ``"local"`` for a Dask cluster of `workers`
        processes on this machine.
    start_method : str, optional
        How local workers start (see :func:`process_context`).
    progress : callable, optional
        ``progress(fraction, text)`` (:mod:`.core.progress`), told as the runs
        finish (in order); returning False raises ``Cancelled`` and drops the
        runs not started yet.

    Returns
    -------
    list of dict
        Per run: deviation, aborted, reason, residual, success.

    Raises
    ------
    MissingPackageError
        `scheduler` is given and dask's ``distributed`` is not installed.
    """
    tolerance = tolerance if tolerance is not None else (0.5 if scene.sensor in SEAM_SENSORS else 10.0)
    check_settings(workers, tolerance)
    args = [(scene, row, controller, rate_hz, seed + i, tolerance) for i, row in enumerate(deviations)]
    if scheduler:
        distributed = check_scheduler(scheduler)
        Client, LocalCluster = distributed.Client, distributed.LocalCluster
        cluster = None
        if scheduler == "local":
            multiprocessing.set_executable(_python_for_workers())
            cluster = scheduler = LocalCluster(n_workers=workers or limits.cores(),
                                               threads_per_worker=1, dashboard_address=None)
        try:
            with _connected(Client, scheduler) as client, tempfile.TemporaryDirectory() as folder:
                client.upload_file(_package_zip(folder))
                futures = [client.submit(run_one, *a, pure=False) for a in args]
                try:
                    return _in_order(futures, progress)
                except BaseException:
                    client.cancel(futures)
                    raise
        finally:
            if cluster is not None:
                cluster.close()
    report_now(progress, 0.0, "%d runs" % len(args))
    if workers == 1:
        results = []
        for a in args:
            results.append(run_one(*a))
            report_now(progress, len(results) / len(args), "%d of %d runs" % (len(results), len(args)))
        return results
    pool = ProcessPoolExecutor(max_workers=workers or limits.cores(),
                               mp_context=process_context(start_method))
    try:
        return _in_order([pool.submit(run_one, *a) for a in args], progress)
    finally:       # on Cancelled or Ctrl-C: the runs not started are dropped
        pool.shutdown(wait=True, cancel_futures=True)


def _in_order(futures, progress):
    """The futures' results in order, `progress` told after each."""
    results = []
    for future in futures:
        results.append(future.result())
        report_now(progress, len(results) / len(futures), "%d of %d runs" % (len(results), len(futures)))
    return results


def check_settings(workers=None, tolerance=None):
    """InputError unless `workers` is None or a whole number in 1..the cores
    (``limits.workers``) and `tolerance` a finite number > 0."""
    limits.workers(workers, "The sweep's workers")
    if tolerance is not None:
        number_in_range(tolerance, "The sweep's tolerance", 0.0, low_open=True)


#: Seconds to wait for a Dask scheduler to answer.
SCHEDULER_TIMEOUT_S = 10.0


def check_scheduler(address, timeout_s=SCHEDULER_TIMEOUT_S):
    """Check a Dask scheduler address before any work; return ``dask.distributed``.

    Parameters
    ----------
    address : str
        ``"local"``, ``tcp://host:port`` or ``host:port``.

    Raises
    ------
    MissingPackageError
        ``distributed`` is not installed.
    InputError
        The address is malformed, or nothing answers there within `timeout_s`.
    """
    distributed = dependencies.import_optional(DASK_PACKAGE)
    if distributed is None:
        raise MissingPackageError("%s; or run the sweep without a scheduler, on this computer's "
                                  "cores." % dependencies.missing_message(DASK_PACKAGE))
    if address == "local":
        return distributed
    host, port = _host_and_port(address)
    try:
        socket.create_connection((host, port), timeout=timeout_s).close()
    except (OSError, ValueError) as err:
        raise InputError("No Dask scheduler answers at '%s' (%s). Start one there (`dask scheduler`), "
                         "give its address, or leave out --scheduler to run on this computer's cores."
                         % (address, getattr(err, "strerror", None) or err)) from None
    return distributed


def _host_and_port(address):
    """(host, port) of ``tcp://host:port`` or ``host:port``; InputError otherwise."""
    rest = address[len("tcp://"):] if address.startswith("tcp://") else address
    host, _, port = rest.rpartition(":")
    host = host.strip("[]")
    if not host or not port.isdigit() or not 0 < int(port) < 65536 or "/" in host:
        raise InputError("Scheduler address '%s': write tcp://host:port (e.g. tcp://10.0.0.5:8786) "
                         "or 'local'." % address)
    return host, int(port)


@contextlib.contextmanager
def _connected(Client, scheduler):
    """A Dask Client of `scheduler`; InputError when it cannot connect."""
    try:
        client = Client(scheduler, timeout="%gs" % SCHEDULER_TIMEOUT_S)
    except (OSError, TimeoutError) as err:
        raise InputError("Cannot connect to the Dask scheduler at '%s': %s. Check that it runs, or "
                         "leave out --scheduler." % (scheduler, " ".join(str(err).split()))) from None
    with client:
        yield client


def summarise(results):
    """Success rate and residual distribution of a sweep (dict)."""
    success = np.array([r["success"] for r in results], bool)
    residual = np.array([r["residual"] for r in results], float)
    size = np.array([np.linalg.norm(r["deviation"][:3]) for r in results])
    good = residual[success]
    return {"runs": len(results), "success_rate": float(success.mean()) if len(results) else 0.0,
            "residual_median": float(np.median(good)) if good.size else None,
            "residual_p95": float(np.percentile(good, 95)) if good.size else None,
            "largest_tracked_deviation_mm": float(size[success].max()) if success.any() else None,
            "smallest_failed_deviation_mm": float(size[~success].min()) if (~success).any() else None}
