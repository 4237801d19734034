"""Profile following under force control (paper 4.2, failures of 4.3).

The robot runs the nominal trajectory drawn on the CAD surface with a ball
tool; the real part is not where the CAD says (:class:`~.reality.Reality`).
Every control period (20 Hz in the paper) a controller reads the F/T sensor
and moves the tool along its axis (the CAD surface normal) to hold a set
contact force::

    run = simulate_force_following(trajectory, real_mesh, reality,
                                   force_set_n=20.0, controller="fuzzy_pi")
    run.metrics["rms_force_error_pct"], run.metrics["settling_time_s"]

What is simulated, every `dt_s`:

* the robot's offset along the tool axis follows the commanded offset with a
  first-order lag (`robot_lag_s`): the actual TCP is the nominal one moved
  by that offset along tool +Z;
* the ball meets the real (rough) surface: :class:`~.contact.BallContact`
  gives the gap, the normal force and the wrench, the
  :class:`~.contact.ForceTorqueSensor` adds noise;
* every ``1 / rate_hz`` the controller takes the mean Fz of the period's
  readings (the anti-alias filter of a PC reading the sensor faster than it
  commands the robot), and its increment is added to the commanded offset.

Start. Open loop (``controller="none"``) runs the program as drawn, pressed
in by the preload ``force_set_n / stiffness_n_mm``: the set force if the part
were where the CAD says. A closed loop starts `approach_mm` clear of the CAD
surface and finds the contact itself while the robot already travels
(so it also finds a part that is nearer than drawn); before contact it
closes the gap at most `max_step_mm` per period.

Failures (paper 4.3), checked as they happen, and the reactive task each
gets with ``on_failure="reactive"``:

* force limit: the measured ``|F|`` exceeds `max_force_n` (every step).
  Reactive: back off along the tool axis by the excess force / k, ahead of
  where the robot is, and go on (open loop: go on); above twice the limit
  the run aborts all the same ("force_hard_limit").
* correction limit: the commanded offset reaches ``+-max_correction_mm``
  (every period). Reactive: hold it there.
* unreachable: ``reach_check(corrected pose)`` gives a reason (every
  period). Reactive: keep the last offset; abort if that pose is
  unreachable too (the program itself leaves the work area).
* contact lost: closed loop, no contact for longer than
  `contact_loss_limit_s` after the first contact. Reactive: keep searching.
* collision: the ball touches one of ``reality.foreign_objects`` (or lies
  inside a solid one), every step. Always aborts: no reactive task gets
  through a solid.

``on_failure="abort"`` stops at the first failure and retracts `retract_mm`
along the tool axis (at `retract_speed_mm_s`, the samples are part of the
run); the stop pose is recorded for a restart. Reactive tasks are listed in
``metrics["events"]``.

Pure numpy / scipy / trimesh: never imports FreeCAD.
"""

import math

import numpy as np
from scipy.spatial.transform import Rotation, Slerp

from ..errors import InputError
from .contact import BallContact, ForceTorqueSensor, MeshSurface, RoughnessProfile
from .controllers import default_tuning, make_controller
from .run import SensorRun

#: Band around the set force that counts as settled (fraction of the set force).
SETTLE_BAND = 0.10
#: After settling, overshoot is still looked for this long (s).
OVERSHOOT_WINDOW_AFTER_SETTLING_S = 0.5
#: Default force limit as a multiple of the set force.
FORCE_LIMIT_FACTOR = 2.5
#: A reactive run still aborts above this multiple of the force limit.
HARD_FORCE_LIMIT_FACTOR = 2.0
#: Default largest correction per period as a fraction of the preload
#: ``force_set / stiffness``: the force changes at most 30 % of the set value
#: per period, whatever the stiffness (so also at the impact).
STEP_FRACTION_OF_PRELOAD = 0.3

ON_FAILURE = ("abort", "reactive")


def _resample(trajectory, dt_s):
    """Nominal poses every `dt_s`: times (N,), T_u_t (N, 4, 4), s_mm (N,)."""
    times = np.asarray(trajectory.time_s, dtype=float)
    keep = np.concatenate([[True], np.diff(times) > 1e-12])
    times, poses = times[keep], np.asarray(trajectory.T_u_t, dtype=float)[keep]
    s_mm = np.asarray(trajectory.s_mm, dtype=float)[keep]
    if len(times) < 2:
        raise InputError("Force following needs a trajectory of at least two samples in time.")
    t = np.arange(int(math.floor((times[-1] - times[0]) / dt_s + 1e-9)) + 1) * dt_s + times[0]
    out = np.repeat(np.eye(4)[None], len(t), axis=0)
    out[:, :3, :3] = Slerp(times, Rotation.from_matrix(poses[:, :3, :3]))(t).as_matrix()
    for axis in range(3):
        out[:, axis, 3] = np.interp(t, times, poses[:, axis, 3])
    return t - times[0], out, np.interp(t, times, s_mm)


def _moved(T_u_t, offset_mm):
    """The pose (4, 4) moved `offset_mm` along its own Z axis."""
    T = T_u_t.copy()
    T[:3, 3] += offset_mm * T_u_t[:3, 2]
    return T


def simulate_force_following(trajectory, real_mesh, reality, force_set_n=20.0, rate_hz=20.0,
                             dt_s=0.005, controller="pi", gains=None, radius_mm=5.0,
                             stiffness_n_mm=20.0, damping_n_s_mm=0.0, max_force_n=None,
                             max_correction_mm=15.0, max_step_mm=None, approach_mm=5.0,
                             robot_lag_s=0.05, reach_check=None, on_failure="abort",
                             retract_mm=50.0, retract_speed_mm_s=20.0,
                             contact_loss_limit_s=0.5):
    """Run a path with the ball tool under force control.

    Parameters
    ----------
    trajectory : core.trajectory.Trajectory
        The nominal TCP poses in {U}: the ball's contact point on the CAD
        surface, tool +Z along the surface's inward normal. Give the path
        moves only (``tcp_trajectory(program, dt, first_move, last_move)``
        without the approach, entry and retract moves).
    real_mesh : trimesh.Trimesh
        The real workpiece surface in {U} (already displaced as built).
    reality : Reality
        Roughness, force noise, foreign objects, seed (its ``T_u_dev`` is
        not applied here: `real_mesh` is the part as built).
    force_set_n : float
        Contact force to hold, N.
    rate_hz : float
        Control rate, Hz (the paper: 20); a whole number of `dt_s` per period.
    dt_s : float
        Simulation step, s.
    controller : str
        ``"pi"``, ``"fuzzy_pi"`` or ``"none"`` (open loop).
    gains : dict, optional
        Controller parameters overriding :func:`.controllers.default_tuning`
        (derived from the stiffness and the rate).
    radius_mm, stiffness_n_mm, damping_n_s_mm : float
        The ball and the contact law (:class:`.contact.BallContact`).
    max_force_n : float, optional
        Force limit, N; default ``2.5 * force_set_n``.
    max_correction_mm : float
        Largest offset along the tool axis, mm.
    max_step_mm : float, optional
        Largest change of the commanded offset per period, mm; default
        ``0.3 * force_set_n / stiffness_n_mm`` (0.3 mm at 20 N and 20 N/mm:
        an approach at 6 mm/s at 20 Hz).
    approach_mm : float
        Closed loop: how far clear of the CAD surface the tool starts, mm.
    robot_lag_s : float
        Time constant of the robot following a correction, s (0 = at once).
    reach_check : callable, optional
        ``reach_check(T_u_t (4, 4)) -> str or None``: why the robot cannot
        take a commanded pose (unreachable, singular), None when it can.
    on_failure : str
        ``"abort"`` (stop, retract along the tool axis) or ``"reactive"``.
    retract_mm, retract_speed_mm_s : float
        The retract after an abort.
    contact_loss_limit_s : float
        Closed loop: contact lost longer than this is a failure, s.

    Returns
    -------
    SensorRun
        ``sensor="force"``; ``force_n`` (N, 6) the sensor readings in the
        tool frame (Fz > 0 pressing); ``error_mm`` the gap from the ball to
        the real surface along its normal (negative = pressed in); metrics
        from :func:`force_metrics` plus ``events`` (one dict per failure:
        kind, action, message, index, time_s, s_mm), ``force_limit_n``,
        ``preload_mm``, ``max_step_mm``, ``rate_hz``, the controller's
        ``gains``, and ``stop_s_mm`` (path distance of the stop) when
        aborted.
    """
    if not dt_s > 0 or not rate_hz > 0 or rate_hz * dt_s > 1.0 + 1e-9:
        raise InputError("The control rate (%r Hz) must be > 0 and at most 1/dt (dt = %r s)."
                         % (rate_hz, dt_s))
    if on_failure not in ON_FAILURE:
        raise InputError("on_failure must be one of %s, got %r."
                         % (", ".join(ON_FAILURE), on_failure))
    if not force_set_n > 0:
        raise InputError("The set force must be > 0 N, got %r." % force_set_n)
    steps_per_period = max(1, int(round(1.0 / (rate_hz * dt_s))))
    period_s = steps_per_period * dt_s
    force_limit_n = FORCE_LIMIT_FACTOR * force_set_n if max_force_n is None else float(max_force_n)
    preload_mm = force_set_n / stiffness_n_mm if stiffness_n_mm > 0 else 0.0
    if max_step_mm is None:
        max_step_mm = STEP_FRACTION_OF_PRELOAD * preload_mm
    closed_loop = controller != "none"

    time_s, nominal, s_mm = _resample(trajectory, dt_s)
    ball = BallContact(radius_mm, stiffness_n_mm, damping_n_s_mm)
    surface = MeshSurface(real_mesh)
    heights_mm = RoughnessProfile.from_reality(reality).height_mm(s_mm)
    sensor = ForceTorqueSensor(reality.force_noise_n, reality.seed)
    obstacles = [(name, MeshSurface(mesh)) for name, mesh in reality.foreign_objects]
    params = default_tuning(controller, stiffness_n_mm, 1.0 / period_s, max_step_mm,
                            max_correction_mm)
    params.update(gains or {})
    control = make_controller(controller, **params)

    offset_cmd = -approach_mm if closed_loop else preload_mm
    control.reset(offset_cmd)
    offset = offset_cmd
    lag = 1.0 - math.exp(-dt_s / robot_lag_s) if robot_lag_s > 0 else 1.0

    n = len(time_s)
    actual = np.zeros((n, 4, 4))
    gaps = np.full(n, np.nan)
    readings = np.zeros((n, 6))
    cycle_times, cycle_forces = [], []
    events = []
    episodes = set()            # failures under way, reported once each
    period_sum, period_count = 0.0, 0
    first_contact, loss_start = None, None
    previous_gap = None
    stop = None

    def fail(kind, index, message, action):
        """Record a failure; return True when the run must stop."""
        nonlocal stop
        if kind in episodes:
            return False
        episodes.add(kind)
        aborting = on_failure == "abort" or action is None
        events.append({"kind": kind, "action": "abort" if aborting else action,
                       "message": message, "index": int(index),
                       "time_s": float(time_s[index]), "s_mm": float(s_mm[index])})
        if aborting:
            stop = (index, message)
        return aborting

    for i in range(n):
        # the robot follows its command; the sensor reads the contact
        offset += (offset_cmd - offset) * lag
        T = _moved(nominal[i], offset)
        actual[i] = T
        gap, normal = ball.gap_mm(surface, T, heights_mm[i])
        rate = 0.0 if previous_gap is None else (gap - previous_gap) / dt_s
        previous_gap = gap
        force = ball.normal_force_n(gap, rate)
        gaps[i] = gap
        readings[i] = sensor.read(ball.wrench(T, normal, force))

        # failures, every step
        if gap < 0:
            first_contact = i if first_contact is None else first_contact
            loss_start = None
            episodes.discard("contact_lost")
        elif first_contact is not None:
            loss_start = i if loss_start is None else loss_start
            lost_s = (i - loss_start + 1) * dt_s
            if closed_loop and lost_s > contact_loss_limit_s + 1e-9:
                if fail("contact_lost", i, "contact lost for %.2f s at t = %.2f s (path %.1f mm)"
                        % (lost_s, time_s[i], s_mm[i]), "search"):
                    break

        centre = ball.centre_mm(T)
        hit = [name for name, body in obstacles if body.touches_ball(centre, radius_mm)]
        if hit and fail("collision", i, "the ball hits %s at t = %.2f s (path %.1f mm)"
                        % (hit[0], time_s[i], s_mm[i]), None):
            break

        force_read = float(np.linalg.norm(readings[i, :3]))
        if force_read > force_limit_n:
            if fail("force_limit", i, "force %.1f N over the %.1f N limit at t = %.2f s "
                    "(path %.1f mm)" % (force_read, force_limit_n, time_s[i], s_mm[i]),
                    "back off" if closed_loop else "go on"):
                break
            if force_read > HARD_FORCE_LIMIT_FACTOR * force_limit_n and fail(
                    "force_hard_limit", i, "force %.1f N over twice the %.1f N limit at t = %.2f s "
                    "(path %.1f mm): the reactive task could not hold it"
                    % (force_read, force_limit_n, time_s[i], s_mm[i]), None):
                break
            if closed_loop:             # back off by the excess, ahead of where the robot is
                offset_cmd = min(offset_cmd, offset - (force_read - force_set_n) / stiffness_n_mm)
                control.reset(offset_cmd)
        else:
            episodes.discard("force_limit")

        # the controller, once per period, on the period's mean Fz
        period_sum += readings[i, 2]
        period_count += 1
        if period_count < steps_per_period or i + 1 >= n:
            continue
        measured = period_sum / period_count
        period_sum, period_count = 0.0, 0
        cycle_times.append(time_s[i])
        cycle_forces.append(measured)
        wanted = offset_cmd + control.step(force_set_n - measured, period_s)
        if reach_check is not None:
            why = reach_check(_moved(nominal[i + 1], wanted))
            if why:
                message = "corrected target not reachable at t = %.2f s (path %.1f mm): %s" % (
                    time_s[i], s_mm[i], why)
                still = reach_check(_moved(nominal[i + 1], offset_cmd))
                if fail("unreachable", i, message, None if still else "hold offset"):
                    break
                control.reset(offset_cmd)
                continue
            episodes.discard("unreachable")
        offset_cmd = wanted
        if abs(offset_cmd) >= max_correction_mm - 1e-9:
            if fail("correction_limit", i, "correction %.2f mm reached the %.1f mm limit at "
                    "t = %.2f s (path %.1f mm)"
                    % (offset_cmd, max_correction_mm, time_s[i], s_mm[i]), "hold at limit"):
                break
            offset_cmd = float(np.clip(offset_cmd, -max_correction_mm, max_correction_mm))
            control.reset(offset_cmd)
        else:
            episodes.discard("correction_limit")

    last = n - 1 if stop is None else stop[0]
    end = last + 1
    in_contact = gaps[:end] < 0
    metrics = force_metrics(time_s[:end], readings[:end], in_contact, np.array(cycle_times),
                            np.array(cycle_forces), force_set_n, force_limit_n,
                            contact_loss_limit_s)
    metrics.update({"events": events, "force_limit_n": force_limit_n, "preload_mm": preload_mm,
                    "max_step_mm": max_step_mm, "rate_hz": 1.0 / period_s, "gains": params})
    if stop is not None:
        metrics["stop_s_mm"] = float(s_mm[last])

    times, nominal_run = time_s[:end], nominal[:end]
    actual_run, gaps_run, readings_run = actual[:end], gaps[:end], readings[:end]
    if stop is not None:
        r_times, r_poses = _retract(actual[last], time_s[last], dt_s, retract_mm,
                                    retract_speed_mm_s)
        r_gaps, r_readings = np.zeros(len(r_times)), np.zeros((len(r_times), 6))
        for k, T in enumerate(r_poses):
            r_gaps[k], normal = ball.gap_mm(surface, T, heights_mm[last])
            r_readings[k] = sensor.read(ball.wrench(T, normal, ball.normal_force_n(r_gaps[k])))
        r_nominal = np.repeat(nominal[last][None], len(r_times), 0)
        r_nominal[:, :3, 3] += r_poses[:, :3, 3] - actual[last][:3, 3]   # the program retracts too
        times = np.concatenate([times, r_times])
        nominal_run = np.concatenate([nominal_run, r_nominal])
        actual_run = np.concatenate([actual_run, r_poses])
        gaps_run = np.concatenate([gaps_run, r_gaps])
        readings_run = np.concatenate([readings_run, r_readings])
    return SensorRun(
        sensor="force", controller=controller, time_s=times,
        nominal_mm=nominal_run[:, :3, 3], actual_mm=actual_run[:, :3, 3],
        correction_mm=actual_run[:, :3, 3] - nominal_run[:, :3, 3], error_mm=gaps_run,
        force_n=readings_run, metrics=metrics, aborted=stop is not None,
        reason="" if stop is None else stop[1],
        stop_index=None if stop is None else int(last),
        stop_T_u_t=None if stop is None else actual[last].copy())


def _retract(T_stop, t_stop, dt_s, retract_mm, speed_mm_s):
    """Times (M,) and poses (M, 4, 4) moving back `retract_mm` along tool -Z."""
    if not retract_mm > 0:
        return np.zeros(0), np.zeros((0, 4, 4))
    duration = retract_mm / speed_mm_s
    local = np.append(np.arange(1, int(math.ceil(duration / dt_s - 1e-9))) * dt_s, duration)
    poses = np.repeat(T_stop[None], len(local), axis=0)
    poses[:, :3, 3] -= (speed_mm_s * local)[:, None] * T_stop[:3, 2]
    return t_stop + local, poses


def force_metrics(time_s, force_n, in_contact, cycle_time_s, cycle_force_n, force_set_n,
                  force_limit_n, contact_loss_limit_s):
    """The numbers a force-following report prints.

    Parameters
    ----------
    time_s : ndarray, shape (N,)
    force_n : ndarray, shape (N, 6)
        Sensor readings (tool frame).
    in_contact : ndarray of bool, shape (N,)
        The ball touches the real surface.
    cycle_time_s, cycle_force_n : ndarray, shape (K,)
        Each control period's end and the mean Fz the controller acted on.
    force_set_n, force_limit_n, contact_loss_limit_s : float

    Returns
    -------
    dict
        ``first_contact_s`` (None: never touched); after first contact,
        from the readings' Fz: ``rms_force_error_pct`` (RMS of
        ``(Fz - F_set) / F_set``, %), ``mean_force_n``, ``std_force_n``;
        ``max_force_n`` (largest ``|F|`` read); ``contact_lost_s`` (time
        without contact after first contact), ``longest_contact_loss_s``;
        ``contact_lost`` (never touched, or lost for at least
        `contact_loss_limit_s`); ``force_limit_exceeded``; from the period
        means: ``settling_time_s`` (after first contact, until the force
        stays within +-10 % of the set value; None if it never does),
        ``overshoot_pct`` (peak above the set value from first contact to
        0.5 s after settling, %, >= 0), ``rms_force_error_settled_pct``.
    """
    dt_s = float(time_s[1] - time_s[0]) if len(time_s) > 1 else 0.0
    force_z = force_n[:, 2]
    touched = np.flatnonzero(in_contact)
    largest = float(np.linalg.norm(force_n[:, :3], axis=1).max()) if len(force_n) else 0.0
    metrics = {"first_contact_s": None, "rms_force_error_pct": None, "mean_force_n": None,
               "std_force_n": None, "rms_force_error_settled_pct": None, "max_force_n": largest,
               "contact_lost_s": 0.0, "longest_contact_loss_s": 0.0, "contact_lost": True,
               "force_limit_exceeded": False, "settling_time_s": None, "overshoot_pct": None}
    metrics["force_limit_exceeded"] = metrics["max_force_n"] > force_limit_n
    if len(touched) == 0:
        return metrics
    first = int(touched[0])
    t_contact = float(time_s[first])
    after = force_z[first:]
    relative = (after - force_set_n) / force_set_n
    lost = ~in_contact[first:]
    longest = run = 0
    for flag in lost:
        run = run + 1 if flag else 0
        longest = max(longest, run)
    metrics.update({
        "first_contact_s": t_contact,
        "rms_force_error_pct": float(100.0 * np.sqrt(np.mean(relative ** 2))),
        "mean_force_n": float(after.mean()), "std_force_n": float(after.std()),
        "contact_lost_s": float(lost.sum() * dt_s),
        "longest_contact_loss_s": float(longest * dt_s),
        "contact_lost": bool(longest * dt_s >= contact_loss_limit_s - 1e-9)})

    periods = cycle_time_s >= t_contact
    t_cycles, f_cycles = cycle_time_s[periods], cycle_force_n[periods]
    if len(t_cycles) == 0:
        return metrics
    outside = np.flatnonzero(np.abs(f_cycles - force_set_n) > SETTLE_BAND * force_set_n)
    if len(outside) == 0:
        settled_at = t_contact
    elif outside[-1] + 1 < len(t_cycles):
        settled_at = float(t_cycles[outside[-1] + 1])
    else:
        settled_at = None
    window_end = np.inf if settled_at is None else settled_at + OVERSHOOT_WINDOW_AFTER_SETTLING_S
    peak = f_cycles[t_cycles <= window_end].max()
    metrics["overshoot_pct"] = float(max(0.0, 100.0 * (peak - force_set_n) / force_set_n))
    if settled_at is not None:
        metrics["settling_time_s"] = settled_at - t_contact
        settled = (force_z - force_set_n)[time_s >= settled_at] / force_set_n
        if len(settled):
            metrics["rms_force_error_settled_pct"] = float(100.0 * np.sqrt(np.mean(settled ** 2)))
    return metrics
