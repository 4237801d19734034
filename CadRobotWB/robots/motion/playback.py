"""Joint values in time: what the 3D-view player animates.

:func:`joint_timeline` turns a program whose joints
:func:`.configuration.solve_program` has chosen into joint vectors sampled
in time, as the robot would run it:

* a **joint move** is interpolated in joint space, linearly in time, from
  the joints the robot is at to the target's joints, in the time of the
  synchronised joint move (:func:`.timing.joint_move_time`: each joint's
  trapezoid, the slowest one sets the time);
* **linear and circular moves** follow the TCP poses of
  :func:`~CadRobotWB.core.trajectory.tcp_trajectory` (programmed TCP
  speed, tool orientation slerped, circles through their via point), and
  at each sample the joints come from the inverse kinematics in the arm
  configuration the robot is in, continued from the previous sample
  (:func:`.move_sampling.follow_family`), so the robot really follows the
  TCP path, wrist flips and all: the motion the checks, the collision check
  and the cycle time sample (:func:`.move_sampling.sample_program`), here
  at time steps.

**Welds** (issue 22): the welded moves of a weld run with a weave follow the
woven TCP path (:func:`~CadRobotWB.core.weave.woven_trajectory`), sampled at
least :data:`~CadRobotWB.core.weave.SAMPLES_PER_CYCLE` times per weave cycle
whatever ``dt_s``; :func:`woven_polylines` gives each run's woven path to draw.

**External axes** (issue 23): a coordinated linear or circular move takes
the TCP poses of :func:`~CadRobotWB.core.trajectory.tcp_trajectory` (in the
drawn {U}) into its work frame and places them where the axes' values, linear
in time from the previous target's to this one's, put that frame
(``ExternalAxes.T_r_b``, as :mod:`.move_sampling` does). Where an axis would
need more than its ``max_speed`` at the programmed TCP speed, the move is slowed
to that axis's time, as the controller slows the TCP (:func:`_axes_time`; Check
reports it: ``external_speed``). A joint move moves the
axes in step with the arm, from rest to rest, and lasts at least their time
(:func:`.timing.external_move_time`). :attr:`Timeline.external` holds the values
per sample (the player turns the positioner by ``positioner.motion(values)``) and
:attr:`Timeline.base_u` the robot base carried by a track
(:func:`base_along_track`). The timeline starts with the axes at the first
target's values.

The robot starts from the solution's start joints (the cell's
StartJoints, or the middle of the joint ranges).  Playback stops at the
**first failing target**: a target the solution could not give joints in
its path's configuration (status other than ``"ok"``), a point along a
move the configuration cannot take, or - when a :class:`.checks.Report` is
given - the target of the first move with an error finding (collision,
joint speed, ...).  The timeline then ends at the last pose the robot can
take and :class:`Failure` says where and why.

:func:`timeline_from_tcp` does the same for a TCP path handed in as poses
(a sensor simulation's nominal or corrected path): inverse kinematics at
every sample in one continuous configuration.

Joint values are the model's (what ``model.fk`` and
:func:`.links.link_frames` take); ``model.controller_joints`` gives the
controller's for display.  Times in seconds, lengths in mm, angles in
degrees.  Acceleration is not modelled along linear and circular moves, so
the timeline's length differs from :func:`.timing.cycle_time`.

Pure numpy: never imports FreeCAD.
"""

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from ...core import frames as tf
from ...core import program as ir
from ...core import weave as weaving
from ...core.trajectory import tcp_trajectory
from . import move_sampling, timing
from . import configuration as cfg

#: Default sampling time of the timeline, s.
DEFAULT_DT_S = 0.1

_STATUS_TEXT = {
    cfg.UNREACHABLE: "is out of reach: no arm configuration reaches it",
    cfg.JOINT_LIMIT: "needs a joint beyond its limits",
    cfg.CONFIG_CHANGE: ("can only be reached in another arm configuration, and a linear or "
                        "circular move cannot change configuration"),
}


@dataclass
class Failure:
    """Where playback stops, and why.

    Attributes
    ----------
    sample : int
        Index of the last sample of the timeline (the pose the robot stops in).
    time_s : float
        Its time.
    move_index : int
        0-based index in ``program.moves()`` of the move that fails; -1 for
        a TCP path (:func:`timeline_from_tcp`).
    target : str
        Name of the failing target ('' for a TCP path).
    kind : str
        ``"unreachable"``, ``"joint_limit"``, ``"config_change"``, or the
        kind of the report's finding (``"collision"``, ``"joint_speed"``...).
    reason : str
        One sentence for the user.
    """

    sample: int
    time_s: float
    move_index: int
    target: str
    kind: str
    reason: str


@dataclass
class Timeline:
    """Joint vectors sampled in time.

    Attributes
    ----------
    time_s : ndarray, shape (N,)
        Increasing, from 0 (or the first time of a TCP path).
    q_deg : ndarray, shape (N, 6)
        Model joints, degrees.
    tcp_u : ndarray, shape (N, 3)
        TCP position in {U} of those joints (forward kinematics), mm.
    move_index : ndarray of int, shape (N,)
        Index in ``program.moves()`` of the move each sample lies on; -1 on
        a TCP path.
    failure : Failure or None
        Where and why playback stops early; None when the whole program
        (or path) can be run.
    external : ndarray, shape (N, E), or None
        The external axis values at each sample (``Program.external`` order:
        track mm, then positioner deg); None without external axes.  The
        player turns the positioner (and what it carries) by
        ``positioner.motion(values)``.
    base_u : ndarray, shape (N, 4, 4), or None
        The robot base in {U} at each sample when a track carries it
        (:func:`base_along_track`); None when the base stands still.
    """

    time_s: np.ndarray
    q_deg: np.ndarray
    tcp_u: np.ndarray
    move_index: np.ndarray
    failure: Optional[Failure] = None
    external: Optional[np.ndarray] = None
    base_u: Optional[np.ndarray] = None

    def __len__(self):
        return len(self.time_s)

    @property
    def duration_s(self):
        """float: time from the first to the last sample."""
        return float(self.time_s[-1] - self.time_s[0])

    def sample_at(self, time_s):
        """Index of the last sample at or before `time_s` (clamped to the timeline);
        ``external[index]`` and ``base_u[index]`` are the axes and the base there."""
        index = int(np.searchsorted(self.time_s, time_s + 1e-9, side="right")) - 1
        return min(max(index, 0), len(self.time_s) - 1)

    def external_at(self, time_s):
        """ndarray, shape (E,), or None: the external axis values at :meth:`sample_at`."""
        return None if self.external is None else self.external[self.sample_at(time_s)]


#: Two bases closer than this are the same (mm, degrees): rounding of a taught fit.
SAME_BASE_MM, SAME_BASE_DEG = 0.01, 0.001
#: Taught frames whose bases differ by more than this are reported as disagreeing.
CONFLICT_MM, CONFLICT_DEG = 1.0, 0.1


@dataclass
class RobotBase:
    """Where the robot stands relative to the part: the one answer every command uses.

    Attributes
    ----------
    T_u_r : ndarray, shape (4, 4)
        The robot base {R} in {U}, mm, as the programs see it.
    taught_frame : str or None
        Label of the taught calibration frame that puts it there; None when
        the drawn base (the cell's Placement) holds.
    T_u_r_drawn : ndarray, shape (4, 4) or None
        The drawn base (the cell's Placement), when known.
    conflicts : list of (str, float, float)
        Other taught frames that imply another base: ``(label, distance mm,
        angle deg)`` from `T_u_r`.
    """

    T_u_r: np.ndarray
    taught_frame: Optional[str] = None
    T_u_r_drawn: Optional[np.ndarray] = None
    conflicts: list = field(default_factory=list)

    @property
    def moved(self):
        """bool: the effective base differs from the drawn one."""
        return self.taught_frame is not None


def _distance(T_a, T_b):
    """(distance mm, angle deg) between two rigid transforms."""
    d = float(np.linalg.norm(T_a[:3, 3] - T_b[:3, 3]))
    c = (np.trace(T_a[:3, :3].T @ T_b[:3, :3]) - 1.0) / 2.0
    return d, float(np.degrees(np.arccos(np.clip(c, -1.0, 1.0))))


def effective_base(T_u_r_drawn, frames):
    """The robot base {R} in {U} the programs imply: the one rule of CadRobot.

    A calibration frame fixes the part relative to the robot: its work
    object is ``T_r_b``.  Drawn (not taught), ``T_r_b = inv(T_u_r) @ T_u_b``
    with ``T_u_r`` the cell's Placement, so the robot stands where it is
    drawn.  Taught, ``T_r_b`` is what the robot measured, and the robot
    stands at ``T_u_b @ inv(T_r_b)`` relative to the drawn part, wherever
    the cell's Placement puts it.

    Rule for several frames: the **first taught frame in path order**
    decides (a frame whose taught pose equals the drawn one is as good as
    drawn); other taught frames that imply a base more than
    :data:`CONFLICT_MM` / :data:`CONFLICT_DEG` away are listed in
    ``conflicts`` (their programs still run as taught; only the one robot
    drawn, and the collision check, follow the first).

    Parameters
    ----------
    T_u_r_drawn : array_like, shape (4, 4), or None
        The cell's Placement.  None: every frame counts as taught (the
        first frame decides), as for a program alone.
    frames : iterable of (str, array_like (4, 4), array_like (4, 4) or None)
        ``(label, T_u_b, T_r_b)`` in path order; ``T_r_b`` None when drawn.

    Returns
    -------
    RobotBase
    """
    drawn = None if T_u_r_drawn is None else np.asarray(T_u_r_drawn, float)
    taught = []
    for label, T_u_b, T_r_b in frames:
        if T_r_b is None:
            continue
        implied = np.asarray(T_u_b, float) @ tf.invert_transform(np.asarray(T_r_b, float))
        if drawn is not None:
            d, a = _distance(implied, drawn)
            if d <= SAME_BASE_MM and a <= SAME_BASE_DEG:
                continue
        taught.append((label, implied))
    if not taught:
        return RobotBase(np.eye(4) if drawn is None else drawn, None, drawn, [])
    label, T_u_r = taught[0]
    conflicts = []
    for other, implied in taught[1:]:
        d, a = _distance(implied, T_u_r)
        if d > CONFLICT_MM or a > CONFLICT_DEG:
            conflicts.append((other, d, a))
    return RobotBase(T_u_r, label, drawn, conflicts)


def robot_base(program, T_u_r_drawn=None):
    """:func:`effective_base` of a program's work frames.

    Parameters
    ----------
    program : Program
    T_u_r_drawn : array_like, shape (4, 4), optional
        The cell's Placement (the drawn base).  Without it the first work
        frame decides.

    Returns
    -------
    RobotBase
        With a track: the base at the track's drawn travel
        (:func:`base_along_track` moves it to other values).
    """
    return effective_base(T_u_r_drawn, [(f.source or f.name, f.T_u_b, f.T_r_b)
                                        for f in program.frames.values()])


def base_in_assembly(program, T_u_r_drawn=None):
    """The robot base {R} in {U} of a program (:func:`robot_base`).

    Returns
    -------
    ndarray, shape (4, 4)
        The identity for a program without work frames and no drawn base.
    """
    return robot_base(program, T_u_r_drawn).T_u_r


def base_along_track(program, T_u_r, values):
    """The robot base in {U} at external axis values: moved by the track.

    Parameters
    ----------
    program : Program
    T_u_r : array_like, shape (4, 4)
        The base with the track at its drawn values (:func:`base_in_assembly`).
    values : array_like, shape (N, E)
        External axis values in program order.

    Returns
    -------
    ndarray, shape (N, 4, 4), or None
        ``track.motion(travel) @ T_u_r`` per row; None when no track carries the robot.
    """
    external = getattr(program, "external", None)
    if external is None or external.track is None:
        return None
    travel, _ = external.split(np.asarray(values, dtype=float).reshape(-1, len(external.axes())))
    return external.track.motion(travel) @ np.asarray(T_u_r, dtype=float)


def tcp_positions(model, q_deg, T_u_r, T_f_t):
    """TCP positions in {U} of joint vectors, shape (N, 3), mm (NaN rows stay NaN);
    `T_u_r` (4, 4), or (N, 4, 4) for a base that moves."""
    q = np.atleast_2d(np.asarray(q_deg, dtype=float))
    T_u_t = np.asarray(T_u_r, float) @ model.fk(np.nan_to_num(q)) @ np.asarray(T_f_t, float)
    return np.where(np.isnan(q).any(axis=1)[:, None], np.nan, T_u_t[:, :3, 3])


# --- reasons ---------------------------------------------------------------------------------

def _limit_detail(model, q_deg):
    """' (J2 at 152.0 deg, limit +150 deg)' for the joint furthest out, or ''."""
    if q_deg is None or not np.all(np.isfinite(q_deg)):
        return ""
    q = model.controller_joints(q_deg)
    excess = model.limit_excess(q, controller=True)
    j = int(np.argmax(excess))
    if excess[j] <= 0.0:
        return ""
    limit = model.joint_max_deg[j] if q[j] > model.joint_max_deg[j] else model.joint_min_deg[j]
    return " (%s at %.1f deg, limit %+.0f deg)" % (model.joint_label(j), q[j], limit)


def _status_reason(what, status, model, q_deg=None):
    """A sentence for a pose whose configuration status is not ``"ok"``."""
    text = "%s %s" % (what, _STATUS_TEXT.get(status, "cannot be reached"))
    if status == cfg.JOINT_LIMIT:
        text += _limit_detail(model, q_deg)
    return text + "."


def _entry_where(entry):
    return "%starget '%s' (path '%s', move %d)" % ("via point of " if entry.is_via else "",
                                                   entry.target.name, entry.path_label,
                                                   entry.move_index + 1)


def _report_errors(report):
    """{move_index: [error findings]} of a Report (empty without one)."""
    out = {}
    for finding in (report.errors if report is not None else []):
        out.setdefault(finding.move_index, []).append(finding)
    return out


# --- the program -----------------------------------------------------------------------------

class _Builder:
    """Collects samples (and the external axis values, `ext_start` not None) and ends
    the timeline at a failure."""

    def __init__(self, q_start, move_index, ext_start=None):
        self.times, self.q, self.moves = [0.0], [np.asarray(q_start, float)], [move_index]
        self.ext = None if ext_start is None else [np.asarray(ext_start, float)]
        self.failure = None

    @property
    def t(self):
        return self.times[-1]

    def add(self, times, q, move_index, ext=None):
        self.times.extend(times)
        self.q.extend(q)
        self.moves.extend([move_index] * len(times))
        if self.ext is not None:
            self.ext.extend(ext)

    def fail(self, move_index, target, kind, reason):
        self.failure = Failure(len(self.times) - 1, self.times[-1], move_index, target, kind,
                               reason)

    def timeline(self, program, model, T_u_r, T_f_t):
        q = np.array(self.q)
        ext = None if self.ext is None else np.array(self.ext)
        base_u = None if ext is None else base_along_track(program, T_u_r, ext)
        return Timeline(np.array(self.times), q,
                        tcp_positions(model, q, T_u_r if base_u is None else base_u, T_f_t),
                        np.array(self.moves, dtype=int), self.failure, ext, base_u)


def _time_grid(duration_s, dt_s):
    """Local sample times of a move: every dt_s, and its end."""
    local = np.arange(dt_s, duration_s, dt_s)
    return np.append(local[local < duration_s - 1e-9], duration_s)


def _joint_move(build, program, model, q_to, ext_to, move_index, dt_s):
    """Samples of a synchronised joint move from the last sample to `q_to` (the
    external axes, if any, to `ext_to` in step, from rest to rest)."""
    q_from = build.q[-1]
    speeds = np.asarray(model.spec.joint_speed_deg_s, dtype=float)
    duration, _ = timing.joint_move_time(model.controller_joints(q_from),
                                         model.controller_joints(q_to), speeds,
                                         speeds / timing.ACCEL_TIME_S)
    ext_step = None
    if build.ext is not None:
        ext_step = np.asarray(ext_to, float) - build.ext[-1]
        duration = max(duration, timing.external_move_time(program, ext_step)[0])
    if duration <= 0.0:
        return
    local = _time_grid(duration, dt_s)
    fractions = (local / duration)[:, None]
    build.add(build.t + local, q_from + fractions * (np.asarray(q_to, float) - q_from), move_index,
              None if ext_step is None else build.ext[-1] + fractions * ext_step)


def _cartesian_move(build, program, model, move_index, dt_s, T_r_u, T_t_f, clocks):
    """Samples of a linear or circular move in the robot's configuration (on the
    woven path, every ``clock.step_s`` or finer, when `clocks` has the move).

    Returns
    -------
    (int, str, ndarray or None) or None
        The sample index within the move, configuration status and joints
        of the first pose the robot cannot take; None when it takes all.
    """
    clock = clocks.get(move_index)
    step = dt_s if clock is None else min(dt_s, clock.step_s)
    traj = tcp_trajectory(program, step, first_move=move_index, last_move=move_index)
    slower = 1.0
    if build.ext is not None and traj.time_s[-1] > traj.time_s[0]:
        slower = max(1.0, _axes_time(build.ext[-1], program, move_index)
                     / (traj.time_s[-1] - traj.time_s[0]))
        if slower > 1.0:            # as finely sampled in time as at the programmed speed
            traj = tcp_trajectory(program, step / slower, first_move=move_index,
                                  last_move=move_index)
    if clock is not None:
        traj = weaving.woven_trajectory(program, traj)
    if len(traj.time_s) < 2:
        return None
    time_s = traj.time_s[0] + (traj.time_s - traj.time_s[0]) * slower
    ext = None
    if build.ext is None:
        T_r_f = T_r_u @ traj.T_u_t[1:] @ T_t_f
    else:
        ext = _coordinated_values(build.ext[-1], program, move_index, time_s)[1:]
        T_r_f = _coordinated_base_poses(program, move_index, traj.T_u_t[1:], ext) @ T_t_f
    q_start = build.q[-1]
    q, status = move_sampling.follow_family(model, T_r_f, int(cfg.family(q_start, model)), q_start)
    bad = [i for i, s in enumerate(status) if s != cfg.OK]
    stop = bad[0] if bad else len(status)
    build.add(build.t + time_s[1:stop + 1] - time_s[0], q[:stop], move_index,
              None if ext is None else ext[:stop])
    return (stop, status[stop], q[stop]) if bad else None


def _axes_time(ext_from, program, move_index):
    """Seconds the slowest external axis needs on a coordinated move at its ``max_speed``.

    A controller slows the TCP of a move on which an axis would otherwise exceed its
    speed; the player stretches the move to this time (acceleration is not modelled
    along linear and circular moves, as for the TCP)."""
    ext_to = move_sampling.external_values(program, program.moves()[move_index].target)
    return max((abs(float(d)) / axis.max_speed
                for d, (_, axis) in zip(ext_to - ext_from, program.external.axes())),
               default=0.0)


def _coordinated_values(ext_from, program, move_index, times):
    """External values (M, E) along a coordinated move sampled at `times` (from its
    start to its end): linear in the travelled time, from `ext_from` to its target's."""
    ext_to = move_sampling.external_values(program, program.moves()[move_index].target)
    span = times[-1] - times[0]
    fraction = (times - times[0]) / span if span > 0 else np.ones(len(times))
    return ext_from + fraction[:, None] * (ext_to - ext_from)


def external_along(program, trajectory):
    """The external axis values at each sample of a :func:`tcp_trajectory` of `program`.

    Each move's values run linearly in time from the previous target's to its own
    (:func:`_coordinated_values`, as the player moves them along a coordinated move).

    Parameters
    ----------
    program : Program
        With ``program.external``.
    trajectory : core.trajectory.Trajectory
        Samples of some of its moves (``move_index``; the first sample is the first
        move's start).

    Returns
    -------
    ndarray, shape (N, E)
        Program order (track mm, then positioner deg).
    """
    moves = program.moves()
    index = np.asarray(trajectory.move_index)
    times = np.asarray(trajectory.time_s, dtype=float)
    out = np.empty((len(index), len(program.external.axes())))
    starts = np.flatnonzero(np.r_[True, index[1:] != index[:-1]])
    for a, b in zip(starts, np.r_[starts[1:], len(index)]):
        k = int(index[a])
        ext_from = move_sampling.external_values(program, moves[max(k - 1, 0)].target)
        first = max(a - 1, 0)           # the move's start: the previous move's last sample
        values = _coordinated_values(ext_from, program, k, times[first:b])
        out[a:b] = values[a - first:]
    return out


def _coordinated_base_poses(program, move_index, T_u_t_drawn, ext):
    """TCP poses in {R} of a coordinated move: the poses `tcp_trajectory` gives in
    the drawn {U}, taken into the move's work frame and placed where the external
    axes put that frame (``ExternalAxes.T_r_b``), shape (M, 4, 4)."""
    frame = program.frames[program.moves()[move_index].frame]
    T_b_u = tf.invert_transform(np.asarray(frame.T_u_b, dtype=float))
    return program.external.T_r_b(frame, ext) @ T_b_u @ T_u_t_drawn


def joint_timeline(program, model, solution, dt_s=DEFAULT_DT_S, report=None, T_u_r=None):
    """Joint vectors of a program sampled in time, up to its first failing target.

    Parameters
    ----------
    program : Program
    model : RobotModel
        ``robots.kinematics.models.model(program.robot)``.
    solution : JointSolution
        From :func:`.configuration.solve_program` for this program and model.
    dt_s : float
        Sampling time, s (> 0); every move's end is a sample too.
    report : checks.Report, optional
        From :func:`.checks.check_program` (or ``api.check``): its error
        findings also stop playback (at the target of the move they are
        about) and give the reasons.
    T_u_r : array_like, shape (4, 4), optional
        The robot base in {U} (``api.robot_base``); default
        :func:`base_in_assembly` of the program.

    Returns
    -------
    Timeline
        Starts at ``solution.q_start_deg`` (or ``solution.reference_deg``)
        at t = 0.  ``failure`` is None when every move can be run.
    """
    if not dt_s > 0:
        raise ValueError("dt_s must be > 0, got %r" % (dt_s,))
    T_u_r = base_in_assembly(program) if T_u_r is None else np.asarray(T_u_r, float)
    T_r_u = tf.invert_transform(T_u_r)
    T_f_t = np.asarray(program.tool.T_f_t, dtype=float)
    T_t_f = tf.invert_transform(T_f_t)
    q_start = solution.q_start_deg if solution.q_start_deg is not None else solution.reference_deg
    moves = program.moves()
    first = solution.entries[0] if solution.entries else None
    if moves and moves[0].kind != ir.JOINT and first is not None and first.joints_deg is not None:
        q_start = first.joints_deg        # no joint move to get there: start on the first target
    coordinated = getattr(program, "external", None) is not None
    build = _Builder(q_start, 0, move_sampling.external_values(program, moves[0].target)
                     if coordinated and moves else None)
    errors = _report_errors(report)
    clocks = weaving.run_clocks(program)
    groups = {}
    for entry in solution.entries:
        groups.setdefault(entry.move_index, []).append(entry)

    for index, move in enumerate(moves):
        group = groups.get(index, [])
        failing = [e for e in group if e.status != cfg.OK or e.joints_deg is None]
        found = errors.get(index, [])
        reason = found[0].message if found else ""
        if move.kind == ir.JOINT:
            if failing:
                entry = failing[0]
                build.fail(index, entry.target.name, entry.status, reason or _status_reason(
                    _entry_where(entry), entry.status, model, entry.attempt_deg))
                break
            _joint_move(build, program, model, group[-1].joints_deg,
                        move_sampling.external_values(program, move.target)
                        if coordinated else None, index, dt_s)
        else:
            stopped = _cartesian_move(build, program, model, index, dt_s, T_r_u, T_t_f,
                                      clocks)
            if stopped is not None or failing:
                if failing:
                    entry = failing[0]
                    status, q_bad, what = entry.status, entry.attempt_deg, _entry_where(entry)
                else:
                    entry = group[-1]
                    _, status, q_bad = stopped
                    what = ("a point of the %s move to target '%s' (path '%s', move %d)"
                            % (move.kind, entry.target.name, entry.path_label, index + 1))
                build.fail(index, entry.target.name, status,
                           reason or _status_reason(what, status, model, q_bad))
                break
        if found:
            build.fail(index, move.target.name, found[0].kind, reason)
            break
    return build.timeline(program, model, T_u_r, T_f_t)


def woven_polylines(program):
    """The woven TCP path of each weld run with a weave, to draw in the 3D view.

    Returns
    -------
    list of (str, ndarray (N, 3))
        ``("Weld 'label' (woven)", positions in {U}, mm)`` per run, in execution
        order, from its seam start to its end, sampled every
        :attr:`~CadRobotWB.core.weave.RunClock.step_s`; empty without woven runs.
    """
    out, seen = [], set()
    for clock in weaving.run_clocks(program).values():
        if id(clock) in seen:
            continue
        seen.add(id(clock))
        traj = tcp_trajectory(program, clock.step_s, first_move=int(clock.moves[0]),
                              last_move=int(clock.moves[-1]))
        part = " part %d" % clock.run.part if clock.run.part > 1 else ""
        out.append(("Weld '%s'%s (woven)" % (clock.run.label, part),
                    weaving.woven_trajectory(program, traj).position_mm))
    return out


# --- a TCP path ------------------------------------------------------------------------------

def _first_joints(model, T_r_f):
    """The IK solution within the limits nearest the middle of the joint ranges, or None."""
    reference = cfg.reference_joints(model)
    rows = model.ik(T_r_f[None])[0]
    rows = rows[~np.isnan(rows).any(axis=1)]
    if not len(rows):
        return None
    rows = cfg.unwrap_joints(rows, reference, model)
    cost = cfg.joint_travel_s(model, reference, rows) + np.where(model.within_limits(rows), 0, 1e9)
    return rows[int(np.argmin(cost))]


def timeline_from_tcp(T_u_t, times, model, T_u_r, T_f_t, q_start=None):
    """Joint vectors that take the TCP along given poses, in one continuous configuration.

    Parameters
    ----------
    T_u_t : array_like, shape (N, 4, 4)
        TCP poses in {U}, mm (e.g. a sensor simulation's corrected path).
    times : array_like, shape (N,)
        Their times, s, increasing.
    model : RobotModel
    T_u_r : array_like, shape (4, 4) or (N, 4, 4)
        Robot base {R} in {U}; one per pose for a base that moves (a track).
    T_f_t : array_like, shape (4, 4)
        TCP in the flange frame.
    q_start : array_like, shape (6,), optional
        Model joints before the first pose; they set the configuration kept
        along the path.  Default: the solution at the first pose nearest the
        middle of the joint ranges.

    Returns
    -------
    Timeline
        ``move_index`` is -1 throughout.  When a pose cannot be taken in the
        configuration (out of reach, a joint past its limit, another
        configuration needed) the timeline ends at the pose before it and
        ``failure`` says why; if the first pose cannot be taken the timeline
        holds `q_start` alone.
    """
    T_u_t = np.asarray(T_u_t, dtype=float).reshape(-1, 4, 4)
    times = np.asarray(times, dtype=float).reshape(-1)
    if len(times) != len(T_u_t) or not len(times):
        raise ValueError("need one time per pose, got %d poses and %d times"
                         % (len(T_u_t), len(times)))
    T_r_f = (tf.invert_transform(np.asarray(T_u_r, float)) @ T_u_t
             @ tf.invert_transform(np.asarray(T_f_t, float)))
    if q_start is None:
        q_start = _first_joints(model, T_r_f[0])
    failure = None
    if q_start is None:
        q, status = np.full((len(times), 6), np.nan), [cfg.UNREACHABLE] * len(times)
        q_start = cfg.reference_joints(model)
    else:
        q_start = np.asarray(q_start, dtype=float)
        q, status = move_sampling.follow_family(model, T_r_f, int(cfg.family(q_start, model)), q_start)
    bad = [i for i, s in enumerate(status) if s != cfg.OK]
    stop = bad[0] if bad else len(times)
    q_run, t_run = q[:stop], times[:stop]
    if stop == 0:
        q_run, t_run = q_start[None], times[:1]
    if bad:
        what = "The TCP path at t = %.2f s" % times[stop]
        failure = Failure(len(t_run) - 1, float(t_run[-1]), -1, "", status[stop],
                          _status_reason(what, status[stop], model, q[stop]))
    T_u_r = np.asarray(T_u_r, float)
    bases = T_u_r if T_u_r.ndim == 2 else T_u_r[:len(q_run)]
    return Timeline(t_run, q_run, tcp_positions(model, q_run, bases, T_f_t),
                    np.full(len(t_run), -1, dtype=int), failure)
