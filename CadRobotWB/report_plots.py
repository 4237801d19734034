"""PNG plots of sensor runs for `cadrobot simulate` and `cadrobot sweep` (matplotlib, Agg).

Each function returns the PNG as bytes.  matplotlib is optional: check
:func:`is_available` first (without it the plot functions raise
MissingPackageError).
"""

import numpy as np

from . import dependencies

#: The pip name of the plotting package.
PACKAGE = "matplotlib"
#: Titles of the seam trackers' plots.
SEAM_TITLES = {"laser": "Seam tracking", "arc": "Through-arc seam tracking"}


def is_available():
    """bool: matplotlib is installed, so plots can be made."""
    return dependencies.is_available(PACKAGE)


def _pyplot():
    matplotlib = dependencies.require(PACKAGE)
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _png(fig):
    """The figure as PNG bytes (written atomically by the caller)."""
    import io
    import matplotlib.pyplot as plt
    buffer = io.BytesIO()
    fig.tight_layout()
    fig.savefig(buffer, format="png", dpi=110)
    plt.close(fig)
    return buffer.getvalue()


def tool_axes_components(vectors_mm, T_u_t):
    """Components of (N, 3) vectors along the tool's Y (lateral) and Z (stand-off) axes."""
    return (np.einsum("ni,ni->n", vectors_mm, T_u_t[:, :3, 1]),
            np.einsum("ni,ni->n", vectors_mm, T_u_t[:, :3, 2]))


def _nearest_samples(run, trajectory):
    """Indices (N,) of the trajectory's samples nearest the run's in time (a retract after an
    abort keeps the last)."""
    return np.clip(np.searchsorted(trajectory.time_s, run.time_s), 0, len(trajectory.time_s) - 1)


def _tool_frames(run, trajectory):
    """The nominal tool frames at the run's samples (nearest in time)."""
    return trajectory.T_u_t[_nearest_samples(run, trajectory)]


def plot_corrections(runs, trajectory):
    """Like the paper's Figure 11: the lateral (tool Y) and stand-off (tool Z)
    corrections over time, and the seam error, for each run."""
    title = "%s: path corrections (tool frame)" % SEAM_TITLES.get(runs[0].sensor, "Seam tracking")
    return _corrections_figure([(run.time_s, run, trajectory, _run_label(run, False))
                                for run in runs], "time (s)", title)


def plot_laser_and_arc(laser, arc):
    """Laser and through-arc tracking of one seam on one figure: the lateral (tool Y) and
    stand-off (tool Z) corrections and the seam error against the distance along the seam.

    Parameters
    ----------
    laser, arc : (SensorRun, core.trajectory.Trajectory)
        Each run with the nominal trajectory it ran (the arc's is the weld's
        stretch of the path): its tool frames give the components.

    Returns
    -------
    bytes
        The PNG.
    """
    series = [(np.asarray(trajectory.s_mm, dtype=float)[_nearest_samples(run, trajectory)], run,
               trajectory, _run_label(run, True)) for run, trajectory in (laser, arc)]
    return _corrections_figure(series, "distance along the seam from the run's start (mm)",
                               "Laser and through-arc seam tracking of the same seam")


def _run_label(run, with_sensor):
    controller = run.controller if run.controller != "none" else "open loop"
    return "%s, %s" % (run.sensor, controller) if with_sensor else controller


def _corrections_figure(series, x_label, title):
    """Corrections Y, Z and the seam error of each ``(x (N,), run, trajectory, label)``."""
    plt = _pyplot()
    fig, (ax_y, ax_z, ax_e) = plt.subplots(3, 1, figsize=(8, 8), sharex=True)
    for x, run, trajectory, label in series:
        lateral, standoff = tool_axes_components(run.correction_mm, _tool_frames(run, trajectory))
        ax_y.plot(x, lateral, label=label)
        ax_z.plot(x, standoff, label=label)
        ax_e.plot(x, run.error_mm, label=label)
    ax_y.set_ylabel("correction Y (mm)")
    ax_z.set_ylabel("correction Z (mm)")
    ax_e.set_ylabel("seam error (mm)")
    ax_e.set_xlabel(x_label)
    ax_y.set_title(title)
    for ax in (ax_y, ax_z, ax_e):
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best")
    return _png(fig)


def plot_forces(runs, force_set_n):
    """Like the paper's Figure 14: the normal contact force over time for each
    controller, with the set value and its ±10 % band."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(8, 4.5))
    normal = any(run.metrics.get("follow") == "normal" for run in runs)
    for run in runs:
        label = run.controller if run.controller != "none" else "open loop"
        held = (np.linalg.norm(run.force_n[:, :3], axis=1) if run.metrics.get("follow") == "normal"
                else run.force_n[:, 2])                 # the force the loop held
        ax.plot(run.time_s, held, label=label, linewidth=1)
    ax.axhline(force_set_n, color="k", linestyle="--", linewidth=1, label="set value")
    ax.axhspan(0.9 * force_set_n, 1.1 * force_set_n, color="green", alpha=0.1, label="±10 %")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("normal contact force |F| (N)" if normal else "contact force Fz (N)")
    ax.set_title("Force-controlled profile following: PI against Fuzzy-PI")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best")
    return _png(fig)


def plot_paths(run, real_mm):
    """Nominal (CAD), real and corrected TCP paths, seen from above and from the side."""
    plt = _pyplot()
    fig, (top, side) = plt.subplots(1, 2, figsize=(11, 4.5))
    for ax, (i, j), names in ((top, (0, 1), ("X", "Y")), (side, (0, 2), ("X", "Z"))):
        ax.plot(run.nominal_mm[:, i], run.nominal_mm[:, j], "--", label="nominal (CAD)")
        if real_mm is not None:
            ax.plot(real_mm[:, i], real_mm[:, j], ":", linewidth=2, label="real")
        ax.plot(run.actual_mm[:, i], run.actual_mm[:, j], label="corrected (%s)" % run.controller)
        ax.set_xlabel("%s (mm)" % names[0])
        ax.set_ylabel("%s (mm)" % names[1])
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(True, alpha=0.3)
    top.legend(loc="best")
    top.set_title("Top view, {U}")
    side.set_title("Side view, {U}")
    return _png(fig)


def plot_sweep(deviations_mm, residuals_mm, success):
    """Residual error against the size of the deviation, failures marked."""
    plt = _pyplot()
    fig, (ax, hist) = plt.subplots(1, 2, figsize=(11, 4.5))
    success = np.asarray(success, bool)
    ax.scatter(deviations_mm[success], residuals_mm[success], s=12, label="tracked")
    ax.scatter(deviations_mm[~success], np.zeros((~success).sum()), s=20, marker="x",
               color="red", label="failed")
    ax.set_xlabel("deviation size (mm)")
    ax.set_ylabel("residual RMS error (mm)")
    ax.set_title("Success %.0f %% of %d runs" % (100.0 * success.mean(), len(success)))
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best")
    if success.any():
        hist.hist(residuals_mm[success], bins=20)
    hist.set_xlabel("residual RMS error (mm)")
    hist.set_ylabel("runs")
    return _png(fig)
