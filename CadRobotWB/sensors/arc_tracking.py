"""Through-arc seam tracking: the weld's own current corrects the torch (issue 22).

::

    run = simulate_arc_tracking(trajectory, real_mesh, real_seam_mm, reality, weave, schedule)
    run.metrics["rms_error_after_20mm_mm"]

The torch weaves across the joint (:mod:`core.weave`) while the arc burns.
Where the torch comes closer to a sidewall the contact-tip-to-work distance
(CTWD) shrinks and the current rises (:mod:`.arc`). As FANUC TAST, ABB
WeldGuide and Yaskawa COM-ARC do (plan issue 22, d.2; S30-S34), the tracker
corrects once per weave cycle:

1. Measure, over cycle k: the mean current ``I_L``, ``I_R`` over the left
   and right end zones (the samples whose nominal lateral weave offset is
   beyond ``END_ZONE`` of the half width: the dwells and the outer 25 % of
   each half stroke; S31's area method with a window) and the mean ``I_m``
   over the whole cycle (``height_signal="center"``: over the centre zone,
   FANUC's sample, S34).
2. Estimate, in the weave frame (X travel, Y lateral to the right, Z the
   tool axis into the work)::

       e_y = (I_R - I_L - D) / (2 S_y)    S_y = |dI/dLt| / tan(theta)
       e_z = (I_m - I_ref) / S_z          S_z = |dI/dLt|

   with theta the angle of the walls from the tool axis (45 degrees for a
   T-joint welded on the bisector) and the sensitivities those of the arc
   model at the nominal CTWD of the samples each mean is taken over (the
   CTWD the tracker expects there: ``Lt0 - |w_y| / tan(theta) - w_z`` for a
   weave offset w). ``e_y`` is the torch's offset to the right of the root,
   ``e_z`` how much too close it is. ``D`` is the difference the tracker
   expects on the drawn joint: 0 for a weave square to the torch, not for
   one turned by ``angle_deg`` (one end is then nearer the work).
   ``I_ref``: ``reference="schedule"`` the model's mean current over a
   nominal cycle (corrects an absolute height error, FANUC's CONSTANT);
   ``"learned"`` the first measured cycle's (FANUC's FEEDBACK: a height error
   present at the start stays, and so does the bias a lateral offset at the
   start puts into the mean current: 3 mm lateral and 2 mm height at the
   start end at about 3.6 mm of height error with it, 0.08 mm with
   ``"schedule"``).
3. Correct: ``dy = -g_y e_y``, ``dz = -g_z e_z`` (the tracking's gains),
   each limited to ``max_step_mm`` (1.0 mm per cycle by default: one cycle
   moves 3-4 mm along the seam) and quantised to ``resolution_mm``; applied
   from the start of the next cycle, the robot following with its lag.

In the linear range (the torch less than 3/4 of the half width from the
root) the estimate is exact to second order, so a lateral step ``e0`` decays
as ``e_k = (1 - g_y)^k e0`` cycle by cycle (noise and lags off); beyond it
the estimate saturates with the right sign. Only cycles at full weave
amplitude are measured (not the half-cycle ramps at the ends of the weld).

Reality: the CTWD of every sample of the woven torch path is ray-cast on the
real (deviated, bent) part (:meth:`.arc.ArcScene.ctwd_mm`); the current
follows its steady value with a first-order lag ``current_lag_s`` (20 ms,
[unverified], plan d.1) plus white noise of RMS ``reality.arc_current_noise_a``.

Failures, as the laser loop reports them: ``arc_lost`` (no surface within
``CTWD + 20 mm`` of the contact tip), ``correction_limit``, ``unreachable``
(``reach_check`` of the corrected pose at each cycle start), ``collision``
(the tool against foreign objects). ``on_failure="abort"`` stops and
retracts; ``"reactive"`` records the event and goes on (without the arc: no
correction that cycle).

Measured error: the distance from the weave-centre TCP (nominal plus the
correction) to the real seam, as the laser's (:func:`.seam_tracking.seam_error_mm`).

Pure numpy / scipy: never imports FreeCAD.
"""

import numpy as np
from scipy.signal import lfilter

from ..core.progress import Steps
from ..core.weave import envelope, frame_axes, ramp_time_s, weave_offsets
from ..core.welding import Tracking
from ..errors import InputError
from .arc import ArcModel, ArcScene
from .joint_detection import NO_WEAVE
from .seam_tracking import (FAILURE_MODES, FailureLog, PathFrames, ToolCollision,
                            _quantised_step, check_collision, check_reach, error_metrics,
                            finished_run, resample, robot_follow, seam_error_mm)

CONTROLLERS = ("pi", "none")
HEIGHT_SIGNALS = ("mean", "center")
#: The end zones: samples whose lateral weave offset is beyond this share of the half width.
END_ZONE = 0.75
#: The centre zone (``height_signal="center"``): within this share of the half width.
CENTER_ZONE = 0.25
#: Largest correction change per weave cycle, mm (plan d.2: one cycle moves 3-4 mm along the seam).
MAX_STEP_MM = 1.0
#: Time constant of the current following the CTWD, s (plan d.1 [unverified]).
CURRENT_LAG_S = 0.02


def simulate_arc_tracking(trajectory, real_mesh, real_seam_mm, reality, weave, schedule,
                          tracking=None, controller="pi", dt_s=0.002, wall_angle_deg=45.0,
                          max_step_mm=MAX_STEP_MM, resolution_mm=0.01, current_lag_s=CURRENT_LAG_S,
                          robot_lag_s=0.05, height_signal="mean", reach_check=None,
                          on_failure="abort", retract_mm=50.0, tool_length_mm=150.0,
                          retract_speed_mm_s=50.0, arc_model=None, weld_label="", rate_hz=None,
                          record_every=5, progress=None):
    """Weld the nominal path with the weave, the arc's current correcting it (module doc).

    Parameters
    ----------
    trajectory : core.trajectory.Trajectory
        The weave-centre TCP path of the weld, from where the arc ignites, {U};
        resampled to `dt_s` if needed.
    real_mesh : trimesh.Trimesh
        The real workpiece (and foreign objects), {U}, mm: what the arc burns on.
    real_seam_mm : ndarray, shape (K, 3)
        The real seam polyline, {U}, mm; only to measure the error.
    reality : Reality
        Current noise (``arc_current_noise_a``), foreign objects, seed.
    weave : core.welding.Weave or None
        None: InputError (:data:`NO_WEAVE`).
    schedule : core.welding.WeldSchedule
        Current, wire feed, voltage, CTWD and travel speed.
    tracking : core.welding.Tracking, optional
        Gains, reference and correction limit; default ``Tracking("arc")``.
    controller : str
        ``"pi"`` (the per-cycle law above: each cycle adds a share of the
        error, an integral action) or ``"none"`` (open loop: the arc burns,
        nothing is corrected).
    dt_s : float
        Time step of the current samples, s (2 ms: 250 samples per 0.5 s cycle).
    wall_angle_deg : float
        Angle of the joint's walls from the tool axis, degrees (45: a T-joint
        on the bisector; a fillet or V-groove opening a: a / 2, see
        ``JointDetection.wall_angle_deg``).
    max_step_mm, resolution_mm : float
        Largest correction change per cycle and axis; robot resolution, mm.
    current_lag_s, robot_lag_s : float
        Time constants of the current and of the robot following a
        correction, s (0 = at once).
    height_signal : str
        ``"mean"`` (the cycle's mean current) or ``"center"``.
    reach_check : callable, optional
        ``reach_check(T_u_t (4, 4), time_s) -> str | None`` at each cycle start.
    on_failure : str
        ``"abort"`` or ``"reactive"``.
    retract_mm, retract_speed_mm_s, tool_length_mm : float
        As :func:`.seam_tracking.simulate_seam_tracking`.
    arc_model : ArcModel, optional
        Default ``ArcModel.from_schedule(schedule)``.
    weld_label : str
        The weld's name in messages.
    rate_hz : None
        Through-arc tracking corrects once per weave cycle: any rate is refused.
    record_every : int
        The run records every this many samples (5: every 10 ms, the laser's
        step), and its last; the error is measured there.
    progress : callable, optional
        ``progress(fraction, text)``, told every few cycles.

    Returns
    -------
    SensorRun
        ``sensor="arc"``, sampled every `record_every` time steps; metrics
        as the laser's (``rms_error_mm``,
        ``rms_error_after_20mm_mm``, ``max_error_mm``, ``open_loop_rms_error_mm``,
        ``open_loop_max_error_mm``, ``max_step_mm``, ``max_correction_mm``,
        ``n_corrections``, ``n_measurements`` (cycles measured), ``events``,
        ``stop_s_mm``) and ``arc_lost_count`` (samples without an
        arc), ``weave_cycles``, ``cycle_length_mm``, ``reference_current_a``,
        ``sensitivity_a_per_mm``, ``lateral_sensitivity_a_per_mm``,
        ``mean_current_a``, ``cycle_estimates_mm`` (per measured cycle: s at
        its end, e_y, e_z).
    """
    what = "Weld %r" % weld_label if weld_label else "The weld"
    if weave is None:
        raise InputError("%s: %s." % (what, NO_WEAVE))
    tracking = tracking or Tracking("arc")
    _check_options(controller, rate_hz, on_failure, height_signal, dt_s, resolution_mm,
                   max_step_mm, wall_angle_deg, current_lag_s, robot_lag_s)
    if isinstance(record_every, bool) or not isinstance(record_every, int) or record_every < 1:
        raise InputError("Through-arc tracking: record_every must be a whole number >= 1, got "
                         "%r." % (record_every,))
    model = arc_model or ArcModel.from_schedule(schedule)

    traj = resample(trajectory, dt_s)
    path = PathFrames(traj)
    time_s, s = traj.time_s, traj.s_mm
    n = len(time_s)
    nominal = traj.position_mm
    tool_z = traj.T_u_t[:, :3, 2]
    X, Y, Z = frame_axes(path.at(s)[1], tool_z)
    travel = schedule.travel_speed_mm_s
    cycle_s = weave.cycle_time_s(travel)
    t_arc = time_s - time_s[0]
    duration = float(t_arc[-1])
    offsets = weave_offsets(t_arc, weave, travel)                   # full amplitude, weave frame
    ramp = envelope(t_arc, duration, ramp_time_s(weave, travel))
    woven = offsets * ramp[:, None]
    woven_u = woven[:, :1] * X + woven[:, 1:2] * Y + woven[:, 2:3] * Z
    law = _Law(model, offsets, tracking, wall_angle_deg, height_signal)

    scene = ArcScene(real_mesh)
    tool = ToolCollision(reality.foreign_objects, tool_length_mm)
    rng = reality.rng()
    noise_a = float(reality.arc_current_noise_a)
    lag = 1.0 - np.exp(-dt_s / current_lag_s) if current_lag_s > 0 else 1.0
    cycle_of = np.floor(t_arc / cycle_s + 1e-9).astype(int)
    starts = np.flatnonzero(np.r_[True, np.diff(cycle_of) != 0])
    ends = np.r_[starts[1:], n]

    applied = np.zeros((n, 3))
    current = np.full(n, np.nan)
    a = np.zeros(3)
    command = np.zeros(3)
    current_now = None
    n_meas = n_steps = n_lost = 0
    largest_step = 0.0
    failure = FailureLog(on_failure, time_s, s)
    stop = None
    estimates = []

    steps = Steps(progress, len(starts), "through-arc tracking")
    for k, (i0, i1) in enumerate(zip(starts, ends)):
        steps(k)
        _, stop = check_reach(reach_check, traj.T_u_t[i0], command, s[i0], i0, failure,
                              time_s[i0])
        if stop is not None:
            break
        follow = robot_follow(a, command, time_s[i0:min(i1 + 1, n)] - time_s[i0], robot_lag_s)
        applied[i0:i1] = follow[:i1 - i0]
        a = follow[-1]
        torch = nominal[i0:i1] + applied[i0:i1] + woven_u[i0:i1]
        stop = check_collision(tool, torch, tool_z[i0:i1], i0, s, failure)
        if stop is not None:
            break
        ctwd = scene.ctwd_mm(torch, tool_z[i0:i1], model.ctwd0_mm)
        out = np.isnan(ctwd)
        if out.any():
            n_lost += int(out.sum())
            index = i0 + int(np.argmax(out))
            message = ("arc lost: no surface within %.0f mm of the contact tip at s = %.1f mm "
                       "(the torch is off the part)" % (model.ctwd0_mm + 20.0, s[index]))
            if failure("arc_lost", message, index):
                stop = (index, message)
                break
            continue
        failure.clear("arc_lost")
        steady = model.current(ctwd)
        if current_now is None:
            current_now = steady[0]
        lagged, _ = lfilter([lag], [1.0, lag - 1.0], steady, zi=[(1.0 - lag) * current_now])
        current_now = lagged[-1]
        current[i0:i1] = lagged + (rng.normal(0.0, noise_a, i1 - i0) if noise_a > 0 else 0.0)
        if controller == "none" or not _full_cycle(ramp, t_arc, i0, i1, cycle_s, duration):
            continue
        e_y, e_z = law.estimate(current[i0:i1], slice(i0, i1))
        n_meas += 1
        estimates.append((round(float(s[i1 - 1]), 3), round(e_y, 4), round(e_z, 4)))
        du = _quantised_step(np.array([-law.gain_y * e_y, -law.gain_z * e_z]), resolution_mm,
                             max_step_mm)
        j = min(i1, n - 1)
        new_command = command + du[0] * Y[j] + du[1] * Z[j]
        if np.linalg.norm(new_command) > tracking.max_correction_mm:
            message = ("correction beyond its limit: %.2f mm needed at s = %.1f mm, limit %.2f mm"
                       % (np.linalg.norm(new_command), s[j], tracking.max_correction_mm))
            if failure("correction_limit", message, j):
                stop = (j, message)
                break
            continue
        failure.clear("correction_limit")
        if np.any(du != 0):
            n_steps += 1
            largest_step = max(largest_step, float(np.abs(du).max()))
        command = new_command

    last = n if stop is None else stop[0] + 1
    kept = np.unique(np.r_[np.arange(0, last, record_every), last - 1])     # the record
    actual = nominal[kept] + applied[kept]
    error = seam_error_mm(actual, X[kept], real_seam_mm)
    open_loop = seam_error_mm(nominal[::record_every], X[::record_every], real_seam_mm)
    metrics = {
        **error_metrics(error, s[kept] - s[0], open_loop, largest_step, applied[kept]),
        "n_corrections": n_steps,
        "n_measurements": n_meas,
        "arc_lost_count": n_lost,
        "events": failure.events,
        "weave_cycles": len(starts),
        "cycle_length_mm": weave.cycle_length_mm(travel),
        "reference_current_a": law.reference_a,
        "sensitivity_a_per_mm": model.sensitivity_a_per_mm(),
        "lateral_sensitivity_a_per_mm": law.s_y,
        "mean_current_a": float(np.nanmean(current[:last])) if np.isfinite(current[:last]).any()
        else float("nan"),
        "cycle_estimates_mm": estimates,
        "stop_s_mm": None,
        "notes": [],
    }
    if stop is None:
        run = finished_run("arc", controller, time_s[kept], nominal[kept], actual, error, metrics)
    else:
        run = finished_run("arc", controller, time_s[kept], nominal[kept], actual, error, metrics,
                           stop[1], traj.T_u_t[stop[0]], s[stop[0]], retract_mm,
                           retract_speed_mm_s, dt_s * record_every)
    run.notes.append(model.describe())
    return run


def weld_to_track(program, path, weld=None):
    """The weld of `path` through-arc tracking runs on, and the moves it burns along.

    Parameters
    ----------
    program : core.program.Program
    path : core.program.ProgramPath
        One of the program's paths.
    weld : str, optional
        The weld's name or label; default the path's first.

    Returns
    -------
    run : core.program.WeldRun
    first, last : int
        Indices in ``program.moves()`` of the first and last welded move
        (``run.start + 1 .. run.end`` of the path).

    Raises
    ------
    InputError
        The path has no weld (or none of that name), or the weld does not weave.
    """
    runs = [r for r in path.welds if weld in (None, r.name, r.label)]
    if not runs:
        raise InputError(
            "Path '%s' has no weld%s: through-arc tracking senses the arc of a weld; add a Weld "
            "with a weave to the path." % (path.label, "" if weld is None else " '%s'" % weld))
    run = runs[0]
    if run.weave is None:
        raise InputError("Weld '%s': %s." % (run.label, NO_WEAVE))
    before = next(k for k, p in enumerate(program.paths) if p is path)
    offset = sum(len(p.moves) for p in program.paths[:before])
    return run, offset + run.start + 1, offset + run.end


def _check_options(controller, rate_hz, on_failure, height_signal, dt_s, resolution_mm,
                   max_step_mm, wall_angle_deg, current_lag_s, robot_lag_s):
    """InputError naming the first option that is wrong."""
    if controller not in CONTROLLERS:
        raise InputError("Through-arc tracking: controller %r is not offered: use 'pi' (the "
                         "per-cycle law) or 'none' (open loop)." % (controller,))
    if rate_hz is not None:
        raise InputError("Through-arc tracking corrects once per weave cycle: leave rate_hz out "
                         "(change the weave's frequency instead).")
    if on_failure not in FAILURE_MODES:
        raise InputError("on_failure must be 'abort' or 'reactive', got %r." % (on_failure,))
    if height_signal not in HEIGHT_SIGNALS:
        raise InputError("Through-arc tracking: height_signal %r is unknown: use 'mean' or "
                         "'center'." % (height_signal,))
    for name, value in (("dt_s", dt_s), ("resolution_mm", resolution_mm),
                        ("max_step_mm", max_step_mm)):
        if not value > 0:
            raise InputError("Through-arc tracking: %s must be > 0, got %r." % (name, value))
    if not 5.0 <= wall_angle_deg <= 85.0:
        raise InputError("Through-arc tracking: wall_angle_deg %r is outside 5 to 85 degrees: "
                         "the walls must slope toward the torch axis." % (wall_angle_deg,))
    if not (current_lag_s >= 0 and robot_lag_s >= 0):
        raise InputError("Through-arc tracking: current_lag_s and robot_lag_s must be >= 0.")


def _full_cycle(ramp, t_arc, i0, i1, cycle_s, duration):
    """Whether samples i0:i1 are one whole weave cycle at full amplitude."""
    whole = t_arc[i0] + cycle_s <= duration + 1e-9
    return bool(whole and ramp[i0:i1].min() >= 1.0 - 1e-9)


class _Law:
    """The tracker's estimates (module doc, steps 1-2) and what it expects on the drawn joint.

    Parameters
    ----------
    model : ArcModel
    offsets : ndarray, shape (N, 3)
        Full-amplitude weave offsets of every sample, weave frame, mm.
    tracking : core.welding.Tracking
    wall_angle_deg : float
    height_signal : str
    """

    def __init__(self, model, offsets, tracking, wall_angle_deg, height_signal):
        lateral = offsets[:, 1]
        half = max(float(np.abs(lateral).max()), 1e-9)
        self.right = lateral >= END_ZONE * half
        self.left = lateral <= -END_ZONE * half
        self.height = (np.abs(lateral) <= CENTER_ZONE * half if height_signal == "center"
                       else np.ones(len(lateral), dtype=bool))
        slope = 1.0 / np.tan(np.radians(wall_angle_deg))
        expected_ctwd = model.ctwd0_mm - np.abs(lateral) * slope - offsets[:, 2]
        self.expected_a = model.current(expected_ctwd)
        step = 0.01
        self.sensitivity = (model.current(expected_ctwd - step)
                            - model.current(expected_ctwd + step)) / (2 * step)
        self.slope = slope
        self.gain_y, self.gain_z = tracking.lateral_gain, tracking.height_gain
        self.learn = tracking.reference == "learned"
        self.reference_a = None if self.learn else float("nan")
        self.s_y = float("nan")

    def estimate(self, current_a, cycle):
        """(e_y, e_z) in mm from one cycle's measured currents (M,) at samples `cycle` (a slice)."""
        right, left, height = self.right[cycle], self.left[cycle], self.height[cycle]
        sensitivity, expected = self.sensitivity[cycle], self.expected_a[cycle]
        self.s_y = 0.5 * (sensitivity[right].mean() + sensitivity[left].mean()) * self.slope
        expected_difference = expected[right].mean() - expected[left].mean()   # 0 unless turned
        e_y = (current_a[right].mean() - current_a[left].mean() - expected_difference) / (
            2.0 * self.s_y)
        measured = current_a[height].mean()
        if self.learn and self.reference_a is None:
            self.reference_a = float(measured)
            return float(e_y), 0.0
        reference = self.reference_a if self.learn else float(expected[height].mean())
        if not self.learn:
            self.reference_a = reference
        e_z = (measured - reference) / sensitivity[height].mean()
        return float(e_y), float(e_z)
