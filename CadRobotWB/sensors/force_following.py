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
* every ``1 / rate_hz`` the controller takes the mean force of the period's
  readings (the anti-alias filter of a PC reading the sensor faster than it
  commands the robot), and its increment is added to the commanded offset.

What the loop holds (``follow``). The ball is friction-free, so the force it
reads is the normal force of the contact, along the real surface's normal.
On a surface met square (the paper's profile) that normal is the tool axis
and ``Fz = |F|``. On a convex edge it is not: the tool axis is the bisector
of the two faces, and the ball touches the real edge wherever the part has
moved to, anywhere in the 90 degrees between the faces' normals (more at an
acute edge), or the top face beside it. ``follow="normal"`` (default) holds
the normal force ``|F|`` and moves along the tool axis by the increment
divided by ``cos(theta) = Fz / |F|`` (a move along the axis changes the
normal force by that share; at most 1 / :data:`MIN_AXIS_SHARE`).
``follow="tool_axis"`` holds Fz as before: on FreeCAD's Drilling_1 loop
(a part 1 mm / 0.5 degree off) it held Fz = 20 N while the ball pressed
the edge at 62 degrees off the axis with 48 N, and at the corners the
normal force passed the 50 N limit (s = 363 mm, 50.3 N) with Fz = 32 N.

The drawn contact (``drawn_mesh``). A program made from the CAD has one
tool orientation per segment; on an arc (the orientation of its middle)
and at a concave corner (the ball cannot reach into it) its ball cuts into
the drawn part: 0.6 mm at the ends of Drilling_1's quarter arcs, 1.46 mm in
its notch (29 N more than the preload, at up to 0.5 mm per mm of travel, 5
mm/s at 10 mm/s: faster than the 20 Hz loop follows). Given the drawn part,
the robot starts from the offset along the tool axis where its ball just
touches it (:func:`drawn_contact_mm`, what a ball-centre path planner does)
and the loop only corrects what the real part adds.

The command only changes at the end of a period (or at a force-limit
back-off), so the robot's offsets over a period are known at its start and
the period's contacts are computed together (:class:`_FollowingLoop`); the
checks and the controller still go step by step.

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
from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np
from scipy.spatial.transform import Rotation, Slerp

from ..core.progress import REPORTS_PER_LOOP, report_now
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
#: What the controller holds and the direction it corrects along (see simulate_force_following).
FOLLOW = ("normal", "tool_axis")
#: Below this fraction of the set force a period's mean force gives no direction (no contact):
#: the correction goes along the tool axis.
DIRECTION_FRACTION_OF_SET = 0.25
#: Newton steps of drawn_contact_mm.
DRAWN_CONTACT_ITERATIONS = 4
#: drawn_contact_mm leaves a step alone where the tool axis meets the surface this obliquely.
MIN_AXIS_COSINE = 0.2
#: follow="normal": a move along the tool axis changes the normal force by its share
#: ``cos(theta) = Fz / |F|`` (theta between the measured force and the axis); the increment
#: is divided by that share, at most by 1 / MIN_AXIS_SHARE (theta up to 69.5 degrees).
MIN_AXIS_SHARE = 0.35
#: Most control periods whose contacts are computed in one batch while the
#: command holds (open loop): longer batches save little and waste more at a change.
MAX_PERIODS_PER_BATCH = 16


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


def _moved(T_u_t, offset_t):
    """The pose (4, 4) moved by `offset_t` (3,), mm, given in its own axes."""
    T = T_u_t.copy()
    T[:3, 3] += T_u_t[:3, :3] @ offset_t
    return T


def _along_axis(offset_mm):
    """(3,) an offset of `offset_mm` along the tool axis, in tool axes."""
    return np.array([0.0, 0.0, float(offset_mm)])


def drawn_contact_mm(ball, drawn, tcp_mm, tool_z, limit_mm, iterations=None):
    """Offsets along the tool axis that put the ball just on the drawn part, mm.

    A program made from the CAD puts the ball's contact point (the TCP) on
    the drawn edge or surface with the tool along a normal picked once per
    segment; where that normal is not the local one (the ends of an arc
    set by one tool marker, a concave corner the ball cannot reach into)
    the ball of the program cuts into the drawn part. The robot is given
    the drawn part too, so its force loop starts from where the ball just
    touches it (the offset a ball-centre path planner would apply) and only
    corrects what the real part adds. Newton steps on the gap along the
    tool axis: ``offset += gap / (n . -z)``, n the drawn surface's normal at
    the contact (steps where ``n . -z`` is below :data:`MIN_AXIS_COSINE`,
    the axis within 12 degrees of the surface, are left as they are).

    Parameters
    ----------
    ball : contact.BallContact
    drawn : contact.MeshSurface
        The part as drawn, {U}.
    tcp_mm, tool_z : ndarray, shape (N, 3)
        The program's TCPs and tool axes, {U}.
    limit_mm : float
        Largest offset either way, mm.
    iterations : int, optional
        Newton steps; default :data:`DRAWN_CONTACT_ITERATIONS`.

    Returns
    -------
    ndarray, shape (N,)
        Positive = further into the part; 0 where the program's ball just
        touches the drawn part.
    """
    offsets = np.zeros(len(tcp_mm))
    for _ in range(iterations or DRAWN_CONTACT_ITERATIONS):
        gaps, normals = ball.gaps_mm(drawn, tcp_mm + offsets[:, None] * tool_z, tool_z)
        along = -np.einsum("ij,ij->i", normals, tool_z)     # gap closed per mm along the axis
        steered = along >= MIN_AXIS_COSINE
        step = np.where(steered, gaps / np.where(steered, along, 1.0), 0.0)
        offsets = np.clip(offsets + step, -limit_mm, limit_mm)
    return offsets


def simulate_force_following(trajectory, real_mesh, reality, force_set_n=20.0, rate_hz=20.0,
                             dt_s=0.005, controller="pi", gains=None, radius_mm=5.0,
                             stiffness_n_mm=20.0, damping_n_s_mm=0.0, max_force_n=None,
                             max_correction_mm=15.0, max_step_mm=None, approach_mm=5.0,
                             robot_lag_s=0.05, reach_check=None, on_failure="abort",
                             retract_mm=50.0, retract_speed_mm_s=20.0,
                             contact_loss_limit_s=0.5, follow="normal", drawn_mesh=None,
                             progress=None):
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
    follow : str
        ``"normal"`` (hold the normal force ``|F|``, the increment along the
        tool axis divided by ``Fz / |F|``) or ``"tool_axis"`` (hold Fz);
        see the module's docstring.
    drawn_mesh : trimesh.Trimesh, optional
        The part as drawn, {U}: the robot starts from where its ball just
        touches it (:func:`drawn_contact_mm`). None: from the program's TCP.
    reach_check : callable, optional
        ``reach_check(T_u_t (4, 4), time_s) -> str or None``: why the robot
        cannot take a commanded pose at that time (unreachable, singular), None
        when it can.
    on_failure : str
        ``"abort"`` (stop, retract along the tool axis) or ``"reactive"``.
    retract_mm, retract_speed_mm_s : float
        The retract after an abort.
    contact_loss_limit_s : float
        Closed loop: contact lost longer than this is a failure, s.
    progress : callable, optional
        ``progress(fraction, text)`` (:mod:`..core.progress`), told every few
        batches of steps; returning False raises ``Cancelled``.

    Returns
    -------
    SensorRun
        ``sensor="force"``; ``force_n`` (N, 6) the sensor readings in the
        tool frame (Fz > 0 pressing); ``error_mm`` the gap from the ball to
        the real surface along its normal (negative = pressed in); metrics
        from :func:`force_metrics` plus ``events`` (one dict per failure:
        kind, action, message, index, time_s, s_mm), ``force_limit_n``,
        ``preload_mm``, ``max_step_mm``, ``rate_hz``, the controller's
        ``gains``, ``follow``, ``drawn_contact_mm`` (largest offset of the
        drawn contact, mm), and ``stop_s_mm`` (path distance of the stop)
        when aborted. ``correction_mm`` includes the drawn contact.
    """
    if not dt_s > 0 or not rate_hz > 0 or rate_hz * dt_s > 1.0 + 1e-9:
        raise InputError("The control rate (%r Hz) must be > 0 and at most 1/dt (dt = %r s)."
                         % (rate_hz, dt_s))
    if on_failure not in ON_FAILURE:
        raise InputError("on_failure must be one of %s, got %r."
                         % (", ".join(ON_FAILURE), on_failure))
    if follow not in FOLLOW:
        raise InputError("follow must be one of %s, got %r." % (", ".join(FOLLOW), follow))
    if not force_set_n > 0:
        raise InputError("The set force must be > 0 N, got %r." % force_set_n)
    steps_per_period = max(1, int(round(1.0 / (rate_hz * dt_s))))
    period_s = steps_per_period * dt_s
    force_limit_n = FORCE_LIMIT_FACTOR * force_set_n if max_force_n is None else float(max_force_n)
    preload_mm = force_set_n / stiffness_n_mm if stiffness_n_mm > 0 else 0.0
    if max_step_mm is None:
        max_step_mm = STEP_FRACTION_OF_PRELOAD * preload_mm
    closed_loop = controller != "none"

    steps = _NominalSteps(*_resample(trajectory, dt_s), reality)
    ball = BallContact(radius_mm, stiffness_n_mm, damping_n_s_mm)
    if drawn_mesh is not None:
        steps.drawn_mm = drawn_contact_mm(ball, MeshSurface(drawn_mesh), steps.tcp_mm,
                                          steps.tool_z, max_correction_mm)
    surface = MeshSurface(real_mesh)
    sensor = ForceTorqueSensor(reality.force_noise_n, reality.seed)
    retract_local_s = _retract_times(dt_s, retract_mm, retract_speed_mm_s)
    noise_n = sensor.next_noise(len(steps.time_s) + len(retract_local_s))
    obstacles = [(name, MeshSurface(mesh)) for name, mesh in reality.foreign_objects]
    probe = _Probe(steps, ball, surface, obstacles, noise_n, dt_s)
    params = default_tuning(controller, stiffness_n_mm, 1.0 / period_s, max_step_mm,
                            max_correction_mm)
    params.update(gains or {})
    settings = _LoopSettings(
        closed_loop=closed_loop, on_failure=on_failure, force_set_n=force_set_n,
        force_limit_n=force_limit_n, stiffness_n_mm=stiffness_n_mm,
        max_correction_mm=max_correction_mm, steps_per_period=steps_per_period,
        period_s=period_s, dt_s=dt_s, contact_loss_limit_s=contact_loss_limit_s,
        reach_check=reach_check, follow=follow)
    loop = _FollowingLoop(steps, probe, make_controller(controller, **params), settings)
    offset_cmd = -approach_mm if closed_loop else preload_mm
    loop.start(_along_axis(offset_cmd), 1.0 - math.exp(-dt_s / robot_lag_s) if robot_lag_s > 0 else 1.0)
    loop.run(progress)

    end = len(steps.time_s) if loop.stop is None else loop.stop[0] + 1
    metrics = force_metrics(steps.time_s[:end], loop.readings[:end], loop.gaps[:end] < 0,
                            np.array(loop.cycle_times), np.array(loop.cycle_forces), force_set_n,
                            force_limit_n, contact_loss_limit_s, follow)
    metrics.update({"events": loop.events, "force_limit_n": force_limit_n,
                    "preload_mm": preload_mm, "max_step_mm": max_step_mm, "follow": follow,
                    "drawn_contact_mm": float(np.abs(steps.drawn_mm).max()),
                    "rate_hz": 1.0 / period_s, "gains": params})
    return _finished_run(controller, loop, probe, metrics, retract_local_s, retract_speed_mm_s)


def _finished_run(controller, loop, probe, metrics, retract_local_s, retract_speed_mm_s):
    """The SensorRun of a finished loop: its steps, and after an abort the retract."""
    steps = loop.steps
    end = len(steps.time_s) if loop.stop is None else loop.stop[0] + 1
    columns = [steps.time_s[:end], steps.tcp_mm[:end], loop.actual_mm(end), loop.gaps[:end],
               loop.readings[:end]]
    T_stop = None
    if loop.stop is not None:
        last = end - 1
        metrics["stop_s_mm"] = float(steps.s_mm[last])
        T_stop = _moved(steps.poses[last], loop.offsets[last] + _along_axis(steps.drawn_mm[last]))
        r_times, r_poses = _retract(T_stop, steps.time_s[last], retract_local_s,
                                    retract_speed_mm_s)
        r_gaps, r_readings = probe.sense_retract(r_poses, last)
        # the program retracts too
        r_nominal_mm = steps.tcp_mm[last] + (r_poses[:, :3, 3] - T_stop[:3, 3])
        retract = [r_times, r_nominal_mm, r_poses[:, :3, 3], r_gaps, r_readings]
        columns = [np.concatenate(pair) for pair in zip(columns, retract)]
    time_s, nominal_mm, actual_mm, gaps_mm, readings = columns
    return SensorRun(
        sensor="force", controller=controller, time_s=time_s, nominal_mm=nominal_mm,
        actual_mm=actual_mm, correction_mm=actual_mm - nominal_mm, error_mm=gaps_mm,
        force_n=readings, metrics=metrics, aborted=loop.stop is not None,
        reason="" if loop.stop is None else loop.stop[1],
        stop_index=None if loop.stop is None else int(loop.stop[0]), stop_T_u_t=T_stop)


class _NominalSteps:
    """The program's TCP at every simulation step, and the roughness under it.

    Attributes
    ----------
    time_s, s_mm : ndarray, shape (N,)
        Time from the path's start, s; path distance, mm.
    poses : ndarray, shape (N, 4, 4)
        Nominal TCP poses, {U}, mm.
    tcp_mm, tool_z : ndarray, shape (N, 3)
        Their positions (mm) and tool +Z axes, {U} (contiguous copies).
    rotations : ndarray, shape (N, 3, 3)
        Their orientations (a correction along the tool axis keeps them).
    roughness_mm : ndarray, shape (N,)
        Height of the real surface's roughness at each step's path distance.
    """

    def __init__(self, time_s, poses, s_mm, reality):
        self.time_s, self.poses, self.s_mm = time_s, poses, s_mm
        self.tcp_mm = np.ascontiguousarray(poses[:, :3, 3])
        self.tool_z = np.ascontiguousarray(poses[:, :3, 2])
        self.rotations = np.ascontiguousarray(poses[:, :3, :3])
        self.roughness_mm = RoughnessProfile.from_reality(reality).height_mm(s_mm)
        self.drawn_mm = np.zeros(len(time_s))

    def moved_mm(self, rows, offsets_t):
        """TCPs (B, 3) of steps `rows` moved by `offsets_t` (B, 3, tool axes, mm) and the
        drawn contact (:func:`drawn_contact_mm`, along the tool axis)."""
        offsets_t = np.array(offsets_t, dtype=float)
        offsets_t[:, 2] += self.drawn_mm[rows]
        return self.tcp_mm[rows] + np.einsum("nij,nj->ni", self.rotations[rows], offsets_t)


class _Probe:
    """What the ball and the F/T sensor give for a run of steps, all at once.

    Parameters
    ----------
    steps : _NominalSteps
    ball : BallContact
    surface : MeshSurface
        The real workpiece.
    obstacles : list of (str, MeshSurface)
        Foreign objects.
    noise_n : ndarray, shape (N + M, 3)
        The sensor's force noise for every step, then for every retract sample.
    dt_s : float
    """

    def __init__(self, steps, ball, surface, obstacles, noise_n, dt_s):
        self.steps, self.ball, self.surface = steps, ball, surface
        self.obstacles, self.noise_n, self.dt_s = obstacles, noise_n, dt_s

    def sense(self, first, offsets_mm, previous_gap_mm):
        """Steps ``first ..`` with the TCP moved `offsets_mm` along the tool axis.

        Parameters
        ----------
        first : int
            Index of the first step.
        offsets_mm : ndarray, shape (B, 3)
            The robot's correction at each step, tool axes, mm.
        previous_gap_mm : float or None
            The gap of step ``first - 1`` (None: no step before, rate 0).

        Returns
        -------
        gaps_mm : ndarray, shape (B,)
        readings : ndarray, shape (B, 6)
            F/T readings, tool frame (N, N·m).
        force_read_n : ndarray, shape (B,)
            ``|F|`` of each reading, N.
        hits : list of str or None, length B
            The first foreign object the ball touches at each step.
        """
        rows = slice(first, first + len(offsets_mm))
        tool_z = self.steps.tool_z[rows]
        tcp_mm = self.steps.moved_mm(rows, offsets_mm)
        gaps, normals = self.ball.gaps_mm(self.surface, tcp_mm, tool_z,
                                          self.steps.roughness_mm[rows])
        before = np.concatenate([[gaps[0] if previous_gap_mm is None else previous_gap_mm],
                                 gaps[:-1]])
        forces = self.ball.normal_forces_n(gaps, (gaps - before) / self.dt_s)
        readings = self.ball.wrenches(self.steps.rotations[rows], normals, forces)
        forces_read = readings[:, :3] + self.noise_n[rows]
        readings[:, :3] = forces_read
        return (gaps, readings, np.sqrt(np.einsum("ij,ij->i", forces_read, forces_read)),
                self._hits(tcp_mm, tool_z))

    def _hits(self, tcp_mm, tool_z):
        """The first foreign object the ball touches at each TCP (B, 3), or None (list, length B)."""
        hits = [None] * len(tcp_mm)
        if not self.obstacles:
            return hits
        centres_mm = tcp_mm - self.ball.radius_mm * tool_z
        for name, body in reversed(self.obstacles):
            for row in np.flatnonzero(body.touches_balls(centres_mm, self.ball.radius_mm)):
                hits[row] = name
        return hits

    def sense_retract(self, poses, last):
        """Gaps (M,) and readings (M, 6) along the retract poses (M, 4, 4) after step `last`."""
        gaps, normals = self.ball.gaps_mm(self.surface, poses[:, :3, 3], poses[:, :3, 2],
                                          self.steps.roughness_mm[last])
        readings = self.ball.wrenches(poses[:, :3, :3], normals, self.ball.normal_forces_n(gaps))
        readings[:, :3] += self.noise_n[last + 1:last + 1 + len(poses)]
        return gaps, readings


@dataclass
class _LoopSettings:
    """The fixed settings of a force-following loop (see simulate_force_following)."""

    closed_loop: bool
    on_failure: str
    force_set_n: float
    force_limit_n: float
    stiffness_n_mm: float
    max_correction_mm: float
    steps_per_period: int
    period_s: float
    dt_s: float
    contact_loss_limit_s: float
    reach_check: Optional[Callable]
    follow: str = "normal"


class _FollowingLoop:
    """The control loop, step by step, with the contact computed a period at a time.

    Within a control period the commanded offset stays as it is unless a
    force-limit back-off changes it, so the robot's (lagged) offsets of the
    period's remaining steps are known at its start and their contacts are
    computed together; the failure checks and the controller then go
    through the steps one by one, as the robot would, and a changed command
    starts a new batch at the next step.

    Attributes
    ----------
    offsets, gaps : ndarray, shape (N,)
        The robot's offset along the tool axis (mm) and the gap (mm) per step.
    readings : ndarray, shape (N, 6)
    cycle_times, cycle_forces : list of float
        End of each control period and the mean Fz the controller acted on.
    events : list of dict
    stop : (int, str) or None
        Step and reason of an abort.
    """

    def __init__(self, steps, probe, control, settings):
        n = len(steps.time_s)
        self.steps, self.probe, self.control, self.settings = steps, probe, control, settings
        self.offsets, self.gaps, self.readings = (np.zeros((n, 3)), np.full(n, np.nan),
                                                  np.zeros((n, 6)))
        self.cycle_times, self.cycle_forces, self.events = [], [], []
        self.episodes = set()           # failures under way, reported once each
        self.period_sum, self.period_count = np.zeros(3), 0
        self.first_contact, self.loss_start, self.previous_gap = None, None, None
        self.stop = None
        self.offset = self.offset_cmd = self.lag = None
        self.batches_held = 0           # batches in a row the command held all through

    def start(self, offset_cmd_mm, lag):
        """Command `offset_cmd_mm` (3,), tool axes, with the robot there; `lag`: its step
        response per step."""
        self.offset = self.offset_cmd = np.array(offset_cmd_mm, dtype=float)
        self.control.reset(self.offset_cmd[2])
        self.lag = lag

    def run(self, progress=None):
        """Every step until the end of the path or an abort (`progress` told every
        ``n / REPORTS_PER_LOOP`` steps or so)."""
        first, n = 0, len(self.steps.time_s)
        next_report = 0
        while first < n and self.stop is None:
            if first >= next_report:
                report_now(progress, first / n, "force following")
                next_report = first + max(1, n // REPORTS_PER_LOOP)
            first = self._run_batch(first)

    def actual_mm(self, end):
        """(end, 3) the TCP where the robot really took it, steps ``0 .. end - 1``."""
        return self.steps.moved_mm(slice(0, end), self.offsets[:end])

    def _run_batch(self, first):
        """Steps from `first` while the command holds (see :meth:`_batch_length`); the next step."""
        count = self._batch_length(first)
        offsets = self._lagged_offsets(count)
        gaps, readings, force_read, hits = self.probe.sense(first, offsets, self.previous_gap)
        end = first + count
        self.offsets[first:end], self.gaps[first:end], self.readings[first:end] = (
            offsets, gaps, readings)
        for k, (gap, force_norm) in enumerate(zip(gaps.tolist(), force_read.tolist())):
            i = first + k
            self.offset, self.previous_gap = offsets[k], gap
            command = self.offset_cmd
            if self._step(i, gap, readings[k, :3], force_norm, hits[k]):
                return end
            if self.offset_cmd is not command:
                self.batches_held = 0
                return i + 1
        self.batches_held += 1
        return end

    def _batch_length(self, first):
        """How many steps to compute at once from step `first`.

        To the end of the control period, plus one more period for each
        batch in a row the command held all through (open loop, a held
        offset), up to :data:`MAX_PERIODS_PER_BATCH` more: the steps after a
        change of the command are computed again.
        """
        periods = min(self.batches_held, MAX_PERIODS_PER_BATCH)
        count = self.settings.steps_per_period * (1 + periods) - self.period_count
        return min(count, len(self.steps.time_s) - first)

    def _lagged_offsets(self, count):
        """The robot's offsets (`count`, 3), tool axes, following the command held from now, mm."""
        offsets, offset = np.empty((count, 3)), self.offset
        for k in range(count):
            offset = offset + (self.offset_cmd - offset) * self.lag
            offsets[k] = offset
        return offsets

    def _step(self, i, gap, force, force_read, hit):
        """Step `i`'s failure checks and, at a period's end, the controller; True to stop.

        `force` (3,) the reading's force (tool axes, N), `force_read` its magnitude.
        """
        return (self._check_contact(i, gap) or self._check_collision(i, hit)
                or self._check_force(i, force, force_read) or self._end_of_step(i, force))

    def _direction(self, force, magnitude):
        """Unit direction (3,), tool axes, to press along: the measured force's
        (``follow="normal"``, in contact) or the tool axis."""
        if (self.settings.follow == "normal"
                and magnitude >= DIRECTION_FRACTION_OF_SET * self.settings.force_set_n):
            return _along_axis(1.0 / max(force[2] / magnitude, MIN_AXIS_SHARE))
        return _along_axis(1.0)

    def _fail(self, kind, index, message, action):
        """Record a failure; return True when the run must stop."""
        if kind in self.episodes:
            return False
        self.episodes.add(kind)
        aborting = self.settings.on_failure == "abort" or action is None
        self.events.append({"kind": kind, "action": "abort" if aborting else action,
                            "message": message, "index": int(index),
                            "time_s": float(self.steps.time_s[index]),
                            "s_mm": float(self.steps.s_mm[index])})
        if aborting:
            self.stop = (index, message)
        return aborting

    def _where(self, i):
        """'t = ... s (path ... mm)' of step `i`, for the messages."""
        return "t = %.2f s (path %.1f mm)" % (self.steps.time_s[i], self.steps.s_mm[i])

    def _check_contact(self, i, gap):
        """First contact, and contact lost for too long (closed loop): True to stop."""
        if gap < 0:
            self.first_contact = i if self.first_contact is None else self.first_contact
            self.loss_start = None
            self.episodes.discard("contact_lost")
            return False
        if self.first_contact is None:
            return False
        self.loss_start = i if self.loss_start is None else self.loss_start
        lost_s = (i - self.loss_start + 1) * self.settings.dt_s
        return (self.settings.closed_loop
                and lost_s > self.settings.contact_loss_limit_s + 1e-9
                and self._fail("contact_lost", i, "contact lost for %.2f s at %s"
                               % (lost_s, self._where(i)), "search"))

    def _check_collision(self, i, hit):
        """The ball on a foreign object: always stops."""
        return hit is not None and self._fail("collision", i, "the ball hits %s at %s"
                                              % (hit, self._where(i)), None)

    def _check_force(self, i, force, force_read):
        """The force limit: stop, or back off (closed loop), or go on; True to stop."""
        settings = self.settings
        limit = settings.force_limit_n
        if not force_read > limit:
            self.episodes.discard("force_limit")
            return False
        if self._fail("force_limit", i, "force %.1f N over the %.1f N limit at %s"
                      % (force_read, limit, self._where(i)),
                      "back off" if settings.closed_loop else "go on"):
            return True
        if force_read > HARD_FORCE_LIMIT_FACTOR * limit and self._fail(
                "force_hard_limit", i, "force %.1f N over twice the %.1f N limit at %s: the "
                "reactive task could not hold it" % (force_read, limit, self._where(i)), None):
            return True
        if settings.closed_loop:        # back off by the excess, ahead of where the robot is
            direction = self._direction(force, force_read)
            backed = self.offset - ((force_read - settings.force_set_n) / settings.stiffness_n_mm
                                    * direction)
            if (self.offset_cmd - backed) @ direction > 0:
                self.offset_cmd = backed
            self.control.reset(self.offset_cmd[2])
        return False

    def _end_of_step(self, i, force):
        """Add the step's force (3,) to its period; at the period's end, run the controller
        on the period's mean: its magnitude and direction (``follow="normal"``) or its
        Fz along the tool axis."""
        self.period_sum = self.period_sum + force
        self.period_count += 1
        if (self.period_count < self.settings.steps_per_period
                or i + 1 >= len(self.steps.time_s)):
            return False
        mean = self.period_sum / self.period_count
        self.period_sum, self.period_count = np.zeros(3), 0
        magnitude = float(np.sqrt(mean @ mean))
        measured = magnitude if self.settings.follow == "normal" else float(mean[2])
        self.cycle_times.append(self.steps.time_s[i])
        self.cycle_forces.append(measured)
        return self._correct(i, measured, self._direction(mean, magnitude))

    def _pose(self, i, offset_t):
        """Step `i`'s program pose (4, 4) moved by the drawn contact and `offset_t` (3,)."""
        return _moved(self.steps.poses[i], offset_t + _along_axis(self.steps.drawn_mm[i]))

    def _correct(self, i, measured, direction):
        """The controller on the period's force, its increment along `direction` (3,),
        then the reach and correction limits."""
        settings = self.settings
        wanted = self.offset_cmd + self.control.step(settings.force_set_n - measured,
                                                     settings.period_s) * direction
        if settings.reach_check is not None:
            when = self.steps.time_s[i + 1]
            why = settings.reach_check(self._pose(i + 1, wanted), when)
            if why:
                message = "corrected target not reachable at %s: %s" % (self._where(i), why)
                still = settings.reach_check(self._pose(i + 1, self.offset_cmd), when)
                if self._fail("unreachable", i, message, None if still else "hold offset"):
                    return True
                self.control.reset(self.offset_cmd[2])
                return False
            self.episodes.discard("unreachable")
        self.offset_cmd = wanted
        limit = settings.max_correction_mm
        size = float(np.sqrt(wanted @ wanted))
        if not size >= limit - 1e-9:
            self.episodes.discard("correction_limit")
            return False
        if self._fail("correction_limit", i, "correction %.2f mm reached the %.1f mm limit at %s"
                      % (math.copysign(size, wanted[2]), limit, self._where(i)), "hold at limit"):
            return True
        self.offset_cmd = wanted * min(1.0, limit / size)
        self.control.reset(self.offset_cmd[2])
        return False


def _retract_times(dt_s, retract_mm, speed_mm_s):
    """Times (M,) of the retract's samples after the stop, s (none when `retract_mm` <= 0)."""
    if not retract_mm > 0:
        return np.zeros(0)
    duration = retract_mm / speed_mm_s
    return np.append(np.arange(1, int(math.ceil(duration / dt_s - 1e-9))) * dt_s, duration)


def _retract(T_stop, t_stop, local_s, speed_mm_s):
    """Times (M,) and poses (M, 4, 4) moving back along tool -Z at `local_s` (M,) after the stop."""
    poses = np.repeat(T_stop[None], len(local_s), axis=0)
    poses[:, :3, 3] -= (speed_mm_s * local_s)[:, None] * T_stop[:3, 2]
    return t_stop + local_s, poses


def force_metrics(time_s, force_n, in_contact, cycle_time_s, cycle_force_n, force_set_n,
                  force_limit_n, contact_loss_limit_s, follow="tool_axis"):
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
    follow : str
        The force held: ``"normal"`` the readings' magnitude ``|F|`` (the
        normal force of the friction-free ball), ``"tool_axis"`` their Fz.

    Returns
    -------
    dict
        ``first_contact_s`` (None: never touched); after first contact,
        from the force held (``|F|`` or Fz, see `follow`): ``rms_force_error_pct``
        (RMS of ``(F - F_set) / F_set``, %), ``mean_force_n``, ``std_force_n``;
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
    force_z = np.linalg.norm(force_n[:, :3], axis=1) if follow == "normal" else force_n[:, 2]
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
