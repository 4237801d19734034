"""Where to stand the robot: the kinematic search of base placements (issue 12).

A cell's targets are drawn in {U}, so their flange poses ``T_u_f`` do not
depend on where the robot stands; a candidate base ``T_u_r`` sees them at
``T_r_f = inv(T_u_r) @ T_u_f``.  This module screens many candidate bases
against every target at once with the model's vectorised inverse
kinematics; :mod:`.placement_search` then runs the full check (the engine of
``api.check``: joints chosen along the paths, moves sampled, collisions) on
the candidates that pass, best first.

Candidate bases (:class:`SearchSpace`)
--------------------------------------
Positions on a grid over a rectangle of the floor (x, y in {U}, mm), at one
or more heights z (mm), each turned about the vertical Z axis of {U} by one
or more angles -- or, without a turn range, turned so that the robot's X axis
points at the centre of the targets.  The robot keeps its mounting: the base
rotation is ``Rz(turn) @ M``, ``M`` being the cell's present base rotation
with its turn about Z taken out (the identity for a robot standing upright).

The screen (:func:`screen`)
---------------------------
For one candidate and one target, an IK row (one of the eight arm
configurations) is *usable* when

* it exists (the pose is in reach),
* every controller joint, shifted by a multiple of 360 degrees, lies at
  least ``margin_deg`` inside its limits (:func:`limit_margin_deg`), and
* (when singularity margins are given) the wrist centre, the elbow and the
  wrist bend are at least those margins away from the shoulder, elbow and
  wrist singularities (:func:`.configuration.arm_geometry`).

A candidate passes when every *run* (the moves from one joint move to the
next: a generated path is one run, and the robot keeps one arm configuration
along it) has a configuration family usable at all of its targets.  With
``margin_deg = 0`` and no singularity margins this is exactly the condition
"every target has a family valid within the limits, and each run keeps one"
of :func:`.configuration.solve_program`, so the screen never rejects a base
the full check would accept; what only the full check sees (joints wound
past their range along a run, configuration changes between targets, joint
speeds, collisions) is left to it.

The screen runs in two phases with early rejection: a few targets spread over
each run (the first, the last and evenly spaced ones) for every candidate,
then every target, in order, for the candidates still alive, dropping a
candidate as soon as one target or run fails.

Score (:func:`score`)
---------------------
Higher is better, in [0, 1]::

    score = w_time   * t_fastest / t                      (cycle time)
          + w_margin * min(1, margin_deg / 45)            (joint-limit margin)
          + w_manip  * manipulability

with default weights 0.4, 0.3, 0.3 (:class:`Weights`), where

* ``t`` is the program's cycle time at that base (the screen estimates it:
  each step between targets takes the longer of its programmed time and
  ``max_i |dq_i| / speed_i``; the full check takes
  :func:`.timing.cycle_time`), ``t_fastest`` the shortest among the
  candidates compared;
* ``margin_deg`` is the smallest distance of any controller joint from its
  nearer limit over all targets, degrees;
* ``manipulability`` is the smallest over all targets of
  ``sin(elbow) * sin(wrist) * min(1, shoulder / (reach / 2))``: the elbow's
  and wrist's angles from stretched/folded and from straight and the wrist
  centre's distance from axis 1 -- the three factors of ``|det J|`` of a
  spherical-wrist arm -- in [0, 1], 0 at a singularity.

A robot on a track (issue 23)
-----------------------------
A candidate base is where the robot stands with the track at its drawn
travel; the track moves with it.  At each target the robot rides to the
travel that puts the target's flange at the robot's preferred distance from
axis 1 (:func:`.default_base.model_reach_distance_mm`, the middle of its reach;
:func:`track_offsets_mm`), within the track's limits (or at the fixed travel,
when the user fixed the axis): a target counts as reached when it is reached
from there.  The screen and the full check (:func:`program_at` sets each
target's travel so) use that rule; the time estimate leaves the track's own
motion out, and the chooser picks the travels again when the program is
generated.  Positioner values stay as the program has them.

Pure numpy: never imports FreeCAD.
"""

import dataclasses
from dataclasses import dataclass
from typing import List, Optional

import numpy as np

from ...core import frames as tf
from ...core import program as ir
from ...core.progress import Cancelled
from ...errors import InputError
from ..catalog import catalog
from ..checks import checks
from ..kinematics import models
from ..motion import configuration as cfg
from ..motion import move_sampling
from ..motion.joint_shifts import limit_margin_deg  # noqa: F401  (placement.limit_margin_deg)
from . import default_base

#: Why a target, a run or a candidate fails the screen (codes of :func:`screen`).
OK = 0
SINGULARITY = 1
LIMIT_MARGIN = 2
JOINT_LIMIT = 3
UNREACHABLE = 4
CONFIGURATION = 5

KIND_NAMES = {OK: "ok", SINGULARITY: "singularity", LIMIT_MARGIN: "limit_margin",
              JOINT_LIMIT: "joint_limit", UNREACHABLE: "unreachable",
              CONFIGURATION: "configuration"}

#: A joint this far (deg) from its limit scores full marks for the margin.
MARGIN_FULL_DEG = 45.0
#: Most candidate bases a search takes (a finer grid: raise the step).
MAX_CANDIDATES = 250_000
#: Poses (candidates x targets) evaluated per numpy call: bounds the memory (about 40 MB).
CHUNK_POSES = 40_000
#: Targets per run in the first phase of the screen.
PROBES_PER_RUN = 12
#: Targets per run the screen measures the score on.
SCORED_PER_RUN = 100

_TOL_DEG = 1e-9


# --- what is searched --------------------------------------------------------------------------

@dataclass
class Criteria:
    """What a placement must satisfy besides reaching every target.

    Attributes
    ----------
    margin_deg : float
        Every controller joint at least this far inside its limits at every
        target, degrees.  Default 5.
    shoulder_mm, elbow_deg, wrist_deg : float or None
        Least distances from the shoulder, elbow and wrist singularities
        (those of :class:`.checks.Margins`, whose warnings they avoid); None
        leaves singularities out.
    """

    margin_deg: float = 5.0
    shoulder_mm: Optional[float] = checks.Margins.shoulder_mm
    elbow_deg: Optional[float] = checks.Margins.elbow_deg
    wrist_deg: Optional[float] = checks.Margins.wrist_deg

    @property
    def singularities(self):
        """bool: singularity margins apply."""
        return self.shoulder_mm is not None


@dataclass
class Weights:
    """Weights of the score's parts (see the module docstring); they need not add up to 1."""

    time: float = 0.4
    margin: float = 0.3
    manipulability: float = 0.3


@dataclass
class SearchSpace:
    """The candidate bases: a grid of positions, heights and turns.

    Attributes
    ----------
    x_mm : ndarray, shape (nx,)
    y_mm : ndarray, shape (ny,)
    z_mm : ndarray, shape (nz,)
        Grid lines in {U}, mm.
    turn_deg : ndarray, shape (nt,), or None
        Turns about the Z axis of {U}, degrees; None: each position faces
        the centre of the targets.
    R_mount : ndarray, shape (3, 3)
        The mounting rotation ``M`` (see the module docstring).
    xy_mask : ndarray of bool, shape (ny, nx), or None
        Positions to search (e.g. those on a face); None: all.
    """

    x_mm: np.ndarray
    y_mm: np.ndarray
    z_mm: np.ndarray
    turn_deg: Optional[np.ndarray]
    R_mount: np.ndarray
    xy_mask: Optional[np.ndarray] = None

    @property
    def turns(self):
        """int: turns per position (1 when facing the targets)."""
        return 1 if self.turn_deg is None else len(self.turn_deg)

    def index(self):
        """Grid indices of every candidate, shape (M, 4): (iy, ix, iz, it), in the order
        of :meth:`bases`."""
        iy, ix, iz, it = np.meshgrid(np.arange(len(self.y_mm)), np.arange(len(self.x_mm)),
                                     np.arange(len(self.z_mm)), np.arange(self.turns), indexing="ij")
        index = np.stack([iy.ravel(), ix.ravel(), iz.ravel(), it.ravel()], axis=1)
        if self.xy_mask is not None:
            index = index[self.xy_mask[index[:, 0], index[:, 1]]]
        return index

    def bases(self, centre_mm):
        """Every candidate base.

        Parameters
        ----------
        centre_mm : array_like, shape (3,)
            Where a base without a turn range faces (the targets' centre), {U}, mm.

        Returns
        -------
        T_u_r : ndarray, shape (M, 4, 4)
            Robot bases in {U}, mm.
        index : ndarray of int, shape (M, 4)
            (iy, ix, iz, it) of each.
        turn_deg : ndarray, shape (M,)
            The turn of each, degrees.
        """
        index = self.index()
        x, y, z = self.x_mm[index[:, 1]], self.y_mm[index[:, 0]], self.z_mm[index[:, 2]]
        if self.turn_deg is None:
            turn = np.degrees(np.arctan2(centre_mm[1] - y, centre_mm[0] - x))
        else:
            turn = self.turn_deg[index[:, 3]]
        T = np.zeros((len(index), 4, 4))
        T[:, :3, :3] = rotation_z(np.radians(turn)) @ self.R_mount
        T[:, :3, 3] = np.stack([x, y, z], axis=1)
        T[:, 3, 3] = 1.0
        return T, index, turn


def rotation_z(angle_rad):
    """Rotations about Z, shape (..., 3, 3), of angles (...) in radians."""
    a = np.asarray(angle_rad, dtype=float)
    c, s = np.cos(a), np.sin(a)
    R = np.zeros(a.shape + (3, 3))
    R[..., 0, 0], R[..., 0, 1], R[..., 1, 0], R[..., 1, 1] = c, -s, s, c
    R[..., 2, 2] = 1.0
    return R


def mounting(R_u_r):
    """The turn about Z of a base rotation and its mounting.

    Parameters
    ----------
    R_u_r : array_like, shape (3, 3)

    Returns
    -------
    turn_deg : float
        The heading of the base's X axis seen from above (0 when it is vertical).
    M : ndarray, shape (3, 3)
        ``Rz(-turn) @ R_u_r``: the identity for an upright robot.
    """
    R = np.asarray(R_u_r, dtype=float)
    x = R[:2, 0]
    turn = float(np.arctan2(x[1], x[0])) if np.hypot(*x) > 1e-9 else 0.0
    return float(np.degrees(turn)), rotation_z(-turn) @ R


def _numbers(value, count, what, example, name):
    try:
        values = [float(v) for v in value]
    except (TypeError, ValueError):
        values = []
    if len(values) != count or not np.all(np.isfinite(values)):
        raise InputError("%s: %s must be %d numbers, e.g. %s; not %r."
                         % (name, what, count, example, value))
    return values


def _range(value, what, example, name, unit):
    lo, hi = _numbers(value, 2, what, example, name)
    if lo > hi:
        raise InputError("%s: the %s %g..%g %s runs backwards: give the lower value first (%g,%g)."
                         % (name, what, lo, hi, unit, hi, lo))
    return lo, hi


def _steps(lo, hi, step, what, name, unit):
    """Grid lines from lo to hi, both included, about `step` apart."""
    if not (step is not None and np.isfinite(step) and step > 0):
        raise InputError("%s: the %s step must be a number > 0 %s, not %r." % (name, what, unit, step))
    if hi == lo:
        return np.array([float(lo)])
    lines = (float(hi) - float(lo)) / step + 1.0     # a float: 1e308 / 1e-300 is infinity, not an error
    if not lines <= MAX_CANDIDATES:
        raise InputError("%s: a %s step of %g %s over %g..%g makes %.3g grid lines, more than the %d "
                         "bases a search takes: raise the step." % (name, what, step, unit, lo, hi,
                                                                     lines, MAX_CANDIDATES))
    return np.linspace(lo, hi, max(2, int(round(lines))))


def make_space(region, T_u_r_now, z_mm=None, turn_deg=None, step_mm=None, z_step_mm=None,
               turn_step_deg=None, name="Place robot", max_candidates=MAX_CANDIDATES):
    """The candidate bases of a search, the arguments checked.

    Parameters
    ----------
    region : sequence of 4 float
        ``(xmin, ymin, xmax, ymax)``: the rectangle of the floor, {U}, mm.
    T_u_r_now : array_like, shape (4, 4)
        The present base: its height and mounting are the defaults.
    z_mm : (float, float), optional
        Height range of the base, mm; default the present height.
    turn_deg : (float, float), optional
        Range of turns about Z, degrees; default: each position faces the
        targets' centre.
    step_mm : float, optional
        Grid step in x and y; default the longer side / 20.
    z_step_mm : float, optional
        Default: 5 heights over the range.
    turn_step_deg : float, optional
        Default 30.
    name : str
        Who asks (the cell), for messages.
    max_candidates : int

    Returns
    -------
    SearchSpace

    Raises
    ------
    InputError
        Not four numbers, no area, a side or range given backwards, a step
        <= 0, or more than `max_candidates` bases.
    """
    xmin, ymin, xmax, ymax = _numbers(region, 4, "the region (xmin, ymin, xmax, ymax)",
                                      "0,-500,1000,500 (mm)", name)
    for lo, hi, axis in ((xmin, xmax, "x"), (ymin, ymax, "y")):
        if lo > hi:
            raise InputError("%s: the region's %smin (%g) is greater than its %smax (%g): give "
                             "xmin, ymin, xmax, ymax." % (name, axis, lo, axis, hi))
    if xmax == xmin or ymax == ymin:
        raise InputError("%s: the region %g,%g,%g,%g is empty (no area): give xmax > xmin and "
                         "ymax > ymin, mm." % (name, xmin, ymin, xmax, ymax))
    T_now = np.asarray(T_u_r_now, dtype=float)
    R_mount = mounting(T_now[:3, :3])[1]
    z_lo, z_hi = (T_now[2, 3],) * 2 if z_mm is None else _range(z_mm, "height range z", "0,300",
                                                                  name, "mm")
    step = step_mm if step_mm is not None else max(xmax - xmin, ymax - ymin) / 20.0
    xs = _steps(xmin, xmax, step, "grid", name, "mm")
    ys = _steps(ymin, ymax, step, "grid", name, "mm")
    zs = _steps(z_lo, z_hi, z_step_mm if z_step_mm is not None else (z_hi - z_lo) / 4.0 or 1.0,
                "height", name, "mm")
    turns = None
    if turn_deg is not None:
        t_lo, t_hi = _range(turn_deg, "turn range", "-90,90", name, "deg")
        turns = _steps(t_lo, t_hi, turn_step_deg if turn_step_deg is not None else 30.0,
                       "turn", name, "deg")
        if len(turns) > 1 and turns[-1] - turns[0] >= 360.0 - 1e-9:
            turns = turns[:-1]                     # the full circle: the last is the first
    space = SearchSpace(xs, ys, zs, turns, R_mount)
    count = len(xs) * len(ys) * len(zs) * space.turns
    if count > max_candidates:
        raise InputError("%s: %d candidate bases (%d x %d positions, %d heights, %d turns) are "
                         "more than %d: raise the grid step or narrow the ranges."
                         % (name, count, len(xs), len(ys), len(zs), space.turns, max_candidates))
    return space


# --- the program's targets ---------------------------------------------------------------------

@dataclass
class TargetSet:
    """The targets of a program as the screen sees them, in execution order.

    Attributes
    ----------
    T_u_f : ndarray, shape (N, 4, 4)
        Flange poses in {U}, mm.
    run : ndarray of int, shape (N,)
        Index of the run (one arm configuration) of each target, non-decreasing.
    run_paths : list of str
        Path label of each run.
    names : list of str
        Target names.
    step_s : ndarray, shape (N,)
        Programmed time of the linear or circular step to each target, s (0
        at the start of a run).
    travel : Travel or None
        The track carrying the robot (None: the robot stands still).
    """

    T_u_f: np.ndarray
    run: np.ndarray
    run_paths: List[str]
    names: List[str]
    step_s: np.ndarray
    travel: Optional["Travel"] = None

    @property
    def centre_mm(self):
        """ndarray, shape (3,): the middle of the flange positions' bounding box, {U}, mm."""
        p = self.T_u_f[:, :3, 3]
        return 0.5 * (p.min(axis=0) + p.max(axis=0))

    def run_slices(self):
        """list of (run index, first, end) of each run's targets."""
        starts = np.flatnonzero(np.r_[True, np.diff(self.run) != 0])
        ends = np.r_[starts[1:], len(self.run)]
        return [(int(self.run[s]), int(s), int(e)) for s, e in zip(starts, ends)]


@dataclass
class Travel:
    """A track as the screen sees it, in the robot base {R} with the track at its drawn value.

    Attributes
    ----------
    direction_r : ndarray, shape (3,)
        Unit direction the robot base moves in as the travel grows.
    lower_mm, upper_mm : float
        The travel's range from its drawn value, mm (equal: a fixed travel).
    drawn_mm : float
        The drawn travel.
    preferred_mm : float
        The distance from axis 1 the robot rides to keep each target at, mm.
    """

    direction_r: np.ndarray
    lower_mm: float
    upper_mm: float
    drawn_mm: float
    preferred_mm: float


def track_travel(external, robot):
    """The :class:`Travel` of a program's track, or None without one.

    Parameters
    ----------
    external : core.mechanisms.ExternalAxes or None
    robot : str
        The robot's catalog name (its preferred reach,
        :func:`.default_base.model_reach_distance_mm`).
    """
    if external is None or external.track is None:
        return None
    track = external.track
    t0 = float(track.drawn_at[0])
    step_u = track.motion(track.drawn_at + 1.0)[:3, 3]                  # 1 mm of travel in {U}
    direction = np.asarray(external.T_u_r, dtype=float)[:3, :3].T @ step_u
    axis = track.axes[0]
    lower, upper = (axis.fixed, axis.fixed) if axis.fixed is not None else (axis.lower, axis.upper)
    return Travel(direction / np.linalg.norm(direction), float(lower) - t0, float(upper) - t0, t0,
                  float(default_base.model_reach_distance_mm(models.model(robot)) or 1000.0))


def track_offsets_mm(T_r_f, travel):
    """The travel from the drawn value that keeps each flange pose at the preferred
    horizontal distance from axis 1 (ahead of or behind the robot, whichever comes
    nearer to it within the limits; the nearer travel on a tie).  The track is taken
    as horizontal in {R} (a robot standing on it).

    Parameters
    ----------
    T_r_f : ndarray, shape (..., 4, 4)
        Flange poses in {R} with the track at its drawn value.
    travel : Travel

    Returns
    -------
    ndarray, shape (...)
        mm, within ``[lower_mm, upper_mm]``.
    """
    p = np.asarray(T_r_f, dtype=float)[..., :3, 3]
    along = p @ travel.direction_r
    side = np.linalg.norm((p - along[..., None] * travel.direction_r)[..., :2], axis=-1)
    ahead = np.sqrt(np.maximum(travel.preferred_mm ** 2 - side ** 2, 0.0))
    options = np.clip(np.stack([along - ahead, along + ahead]), travel.lower_mm, travel.upper_mm)
    miss = np.abs(np.hypot(side, along - options) - travel.preferred_mm)
    nearer = miss[1] + 1e-6 < miss[0]
    tie = np.abs(miss[1] - miss[0]) <= 1e-6
    pick = nearer | (tie & (np.abs(options[1]) < np.abs(options[0])))
    return np.where(pick, options[1], options[0])


def _on_track(T_r_f, travel):
    """Flange poses (..., 4, 4) seen from the robot moved by :func:`track_offsets_mm`."""
    if travel is None:
        return T_r_f
    out = np.array(T_r_f, dtype=float, copy=True)
    out[..., :3, 3] -= track_offsets_mm(T_r_f, travel)[..., None] * travel.direction_r
    return out


def base_of(program):
    """The robot base {R} in {U} all of a program's work frames agree on.

    Returns
    -------
    ndarray, shape (4, 4)

    Raises
    ------
    InputError
        Work frames place the robot differently: a calibration frame is taught
        (its pose relative to the robot is measured, so moving the robot in
        the drawing does not move the targets).
    """
    bases = [np.asarray(f.T_u_b, float) @ tf.invert_transform(np.asarray(f.T_r_b, float))
             for f in program.frames.values()]
    if not bases:
        return np.eye(4)
    for frame, T in zip(program.frames.values(), bases):
        if not np.allclose(T, bases[0], atol=1e-6):
            label = frame.source or frame.name
            raise InputError(
                "Calibration frame '%s' is taught (UseTaught): it fixes the part relative to the "
                "robot where the robot measured it, so moving the robot changes nothing. To plan "
                "the robot's place with the drawn frame instead: turn UseTaught off on '%s', place "
                "the robot (Place robot), then teach the frame again." % (label, label),
                frame.source or None)
    return bases[0]


def program_at(program, T_u_r):
    """A copy of `program` for the robot standing at `T_u_r` (4x4 in {U}): its work
    frames' ``T_r_b`` follow the base; targets (in {B}) and moves are shared.

    With external axes the robot base of ``program.external`` moves there too,
    and a track with it; each target's travel then is the rule of the module
    docstring (:func:`track_offsets_mm`), in copies of the moves and targets.
    """
    T_u_r = np.asarray(T_u_r, dtype=float)
    T_r_u = tf.invert_transform(T_u_r)
    frames = {name: dataclasses.replace(frame, T_r_b=T_r_u @ np.asarray(frame.T_u_b, float))
              for name, frame in program.frames.items()}
    moved = dataclasses.replace(program, frames=frames)
    external = getattr(program, "external", None)
    if external is None:
        return moved
    track = external.track
    if track is not None:
        shift = T_u_r @ tf.invert_transform(np.asarray(external.T_u_r, dtype=float))
        track = dataclasses.replace(track, T_u_base=shift @ track.T_u_base)
    moved.external = dataclasses.replace(external, T_u_r=T_u_r, track=track)
    if track is not None:
        travel = track_travel(moved.external, program.robot)
        moved.paths = [dataclasses.replace(path, moves=[_move_on_track(moved, move, travel)
                                                         for move in path.moves])
                       for path in moved.paths]
    return moved


def _move_on_track(program, move, travel):
    """A copy of `move` whose target (and via) ride to the travel of :func:`track_offsets_mm`."""
    T_t_f = tf.invert_transform(np.asarray(program.tool.T_f_t, dtype=float))
    frame = program.frames[move.frame]

    def placed(target):
        if target is None:
            return None
        values = move_sampling.external_values(program, target).copy()
        values[0] = travel.drawn_mm
        T_r_f = program.external.T_r_b(frame, values) @ np.asarray(target.T_b_t, float) @ T_t_f
        values[0] += float(track_offsets_mm(T_r_f, travel))
        return dataclasses.replace(target, external=values)

    return dataclasses.replace(move, target=placed(move.target), via=placed(move.via))


def target_set(program, solution):
    """The targets of `program` for the screen.

    Parameters
    ----------
    program : Program
        With untaught work frames (:func:`base_of`).
    solution : JointSolution
        ``configuration.solve_program(program, ...)`` at any base: its entries'
        flange poses and runs.

    Returns
    -------
    TargetSet
    """
    entries = solution.entries
    if not entries:
        raise InputError("Program '%s' has no targets: add a path to the cell." % program.name)
    external = getattr(program, "external", None)
    T_u_r = base_of(program)
    if external is not None:        # each target's robot base: the track's travel there
        T_u_r = external.T_u_r_at(np.array([move_sampling.external_values(program, e.target)
                                            for e in entries]))
    T_u_f = T_u_r @ np.array([e.T_r_f for e in entries])
    run = np.array([e.run for e in entries], dtype=int)
    run_paths = [""] * (int(run.max()) + 1)
    for e in entries:
        run_paths[e.run] = run_paths[e.run] or e.path_label
    p = T_u_f[:, :3, 3]
    step = np.zeros(len(entries))
    for i in range(1, len(entries)):
        move = entries[i].move
        if run[i] == run[i - 1] and move.kind != ir.JOINT:
            step[i] = float(np.linalg.norm(p[i] - p[i - 1])) / float(move.speed_mm_s)
    return TargetSet(T_u_f, run, run_paths, [e.target.name for e in entries], step,
                     track_travel(external, program.robot))


# --- measures of one IK row --------------------------------------------------------------------

def manipulability(distances, reach_mm):
    """The manipulability measure of the module docstring, in [0, 1].

    Parameters
    ----------
    distances : (ndarray, ndarray, ndarray), each of shape (...)
        Distances from the shoulder (mm), elbow and wrist (deg) singularities:
        ``configuration.arm_geometry(q, robot).singularity_distances()``.
    reach_mm : float
        The robot's reach.

    Returns
    -------
    ndarray, shape (...)
    """
    shoulder, elbow, wrist = distances
    return (np.sin(np.radians(elbow)) * np.sin(np.radians(wrist))
            * np.minimum(1.0, shoulder / (0.5 * reach_mm)))


# --- the screen --------------------------------------------------------------------------------

@dataclass
class Screen:
    """What :func:`screen` found, per candidate (arrays of shape (M,) unless said).

    Attributes
    ----------
    status : ndarray of int
        :data:`OK` or why the candidate fails (the first failure met).
    fail_run : ndarray of int
        The run that fails (-1 when none).
    fail_target : ndarray of int
        Index of the first failing target (-1 when none, or for
        :data:`CONFIGURATION`).
    bad_fraction : ndarray
        Fraction of the targets evaluated that fail (how close a failing
        candidate comes).
    time_s, margin_deg, manipulability : ndarray
        The score's parts for candidates that pass (NaN otherwise).
    families : ndarray of int, shape (M, R)
        Family kept per run by a candidate that passes (-1 otherwise).
    """

    status: np.ndarray
    fail_run: np.ndarray
    fail_target: np.ndarray
    bad_fraction: np.ndarray
    time_s: np.ndarray
    margin_deg: np.ndarray
    manipulability: np.ndarray
    families: np.ndarray

    @property
    def passed(self):
        """ndarray of bool, shape (M,)."""
        return self.status == OK


#: The progress callback asked to stop (the engine's one cancel error).
SearchCancelled = Cancelled


class _Poses:
    """IK of candidates x targets and what the screen needs of it (one numpy pass).

    Parameters
    ----------
    model, T_r_u (C, 4, 4), T_u_f (n, 4, 4), criteria, reach_mm
    scored : ndarray of bool, shape (n,), optional
        Targets whose per-family joints and measures are kept for the score.

    Attributes
    ----------
    kind : ndarray of int, shape (C, n)
        OK when some IK row is usable, else why not.
    families : ndarray of uint8, shape (C, n)
        Bit f set when family f has a usable row.
    q : ndarray, shape (C, m, 8, 6)
        At the m scored targets: per family its first usable row (NaN where none).
    margin, manip : ndarray, shape (C, m, 8)
        :func:`limit_margin_deg` and :func:`manipulability` of those rows.
    """

    def __init__(self, model, T_r_u, T_u_f, criteria, reach_mm, scored=None, travel=None):
        C, n = len(T_r_u), len(T_u_f)
        T_r_f = _on_track(np.matmul(T_r_u[:, None], T_u_f[None]), travel)
        Q = model.ik(T_r_f.reshape(-1, 4, 4))                                      # (P, M, 6)
        exists = ~np.isnan(Q[..., 0])                                              # (P, 8)
        with np.errstate(invalid="ignore"):
            margin = np.where(exists, limit_margin_deg(model, Q), -np.inf)
            geometry = cfg.arm_geometry(Q, model)
            distances = geometry.singularity_distances()                          # 3 x (P, 8)
            usable = margin >= criteria.margin_deg - _TOL_DEG
            kind = np.where(usable.any(axis=1), SINGULARITY, np.where(
                (margin >= -_TOL_DEG).any(axis=1), LIMIT_MARGIN,
                np.where(exists.any(axis=1), JOINT_LIMIT, UNREACHABLE)))
            if criteria.singularities:
                shoulder, elbow, wrist = distances
                usable &= ((shoulder >= criteria.shoulder_mm) & (elbow >= criteria.elbow_deg)
                           & (wrist >= criteria.wrist_deg))
        family = geometry.family()                                                  # (P, 8)
        bits = np.bitwise_or.reduce(np.where(usable, np.left_shift(1, np.maximum(family, 0)), 0),
                                    axis=1).astype(np.uint8)
        kind[bits != 0] = OK
        self.kind = kind.reshape(C, n)
        self.families = bits.reshape(C, n)
        if scored is None or not scored.any():
            return
        pick = np.zeros((C, n), dtype=bool)
        pick[:, scored] = True
        pick = pick.ravel()
        m = int(scored.sum())
        Qs, fam, ok = Q[pick], family[pick], usable[pick]                           # (Ps, 8, ...)
        row_of = np.full((len(Qs), 8), -1)
        for r in range(Q.shape[1] - 1, -1, -1):             # the first usable row of a family wins
            hit = np.flatnonzero(ok[:, r])
            row_of[hit, fam[hit, r]] = r
        has = row_of >= 0
        take = np.arange(len(Qs))[:, None]
        rows = np.maximum(row_of, 0)
        q = np.where(has[..., None], Qs[take, rows], np.nan)
        self.q = q.reshape(C, m, 8, 6)
        self.margin = np.where(has, margin[pick][take, rows], np.nan).reshape(C, m, 8)
        manip = manipulability([d[pick] for d in distances], reach_mm)
        self.manip = np.where(has, manip[take, rows], np.nan).reshape(C, m, 8)


class _Runs:
    """Per candidate and run: the families still usable (bits) and, per family, the score's
    parts so far (over the scored targets)."""

    def __init__(self, count, runs):
        shape = (count, runs, 8)
        self.families = np.full((count, runs), 255, dtype=np.uint8)
        self.margin = np.full(shape, np.inf)
        self.manip = np.full(shape, np.inf)
        self.time = np.zeros(shape)
        self.q_first = np.full(shape + (6,), np.nan)
        self.q_last = np.full(shape + (6,), np.nan)
        self.last = np.full((count, runs), -1)       # index of the last scored target folded in


def _scored_targets(targets):
    """ndarray of bool, shape (N,): the targets the score is measured on: about
    :data:`SCORED_PER_RUN` spread over each run, its first and last included."""
    scored = np.zeros(len(targets.names), dtype=bool)
    for _, first, end in targets.run_slices():
        scored[np.round(np.linspace(first, end - 1, min(end - first, SCORED_PER_RUN))).astype(int)] = True
    return scored


def _chunks(targets, probe):
    """(run, target indices) to evaluate in order: every target in pieces, or (probe) a few
    spread over each run."""
    out = []
    for run, first, end in targets.run_slices():
        if probe:
            picks = np.unique(np.round(np.linspace(first, end - 1, PROBES_PER_RUN)).astype(int))
            out.append((run, picks))
        else:
            size = max(8, CHUNK_POSES // 64)
            out += [(run, np.arange(s, min(s + size, end))) for s in range(first, end, size)]
    return out


def _evaluate(model, targets, T_r_u, criteria, alive_idx, probe, state, progress, done, total):
    """One phase of :func:`screen` over the candidates `alive_idx`; returns (alive_idx, done,
    runs): the candidates still alive, the work done and (every target) the runs' parts."""
    reach = catalog.reach_mm(model.spec) or 1000.0
    runs = None if probe else _Runs(len(T_r_u), len(targets.run_paths))
    scored_all = None if probe else _scored_targets(targets)
    step_sum = np.cumsum(targets.step_s)
    for run, idx in _chunks(targets, probe):
        if alive_idx.size == 0:
            break
        scored = None if probe else scored_all[idx]
        block = max(1, CHUNK_POSES // len(idx))
        keep = []
        for start in range(0, alive_idx.size, block):
            cand = alive_idx[start:start + block]
            poses = _Poses(model, T_r_u[cand], targets.T_u_f[idx], criteria, reach, scored,
                           targets.travel)
            bad = poses.kind != OK                                          # (C, n)
            state.evaluated[cand] += len(idx)
            state.bad[cand] += bad.sum(axis=1)
            first_bad = np.argmax(bad, axis=1)
            new = bad.any(axis=1)
            state.status[cand[new]] = poses.kind[new, first_bad[new]]
            state.fail_run[cand[new]] = run
            state.fail_target[cand[new]] = idx[first_bad[new]]
            store = state.families if probe else runs.families
            store[cand, run] &= np.bitwise_and.reduce(poses.families, axis=1)
            if not probe and scored.any():
                _accumulate(model, runs, cand, run, idx[scored], poses, step_sum)
            config = ~new & (store[cand, run] == 0)
            state.status[cand[config]] = CONFIGURATION
            state.fail_run[cand[config]] = run
            keep.append(cand[state.status[cand] == OK])
            done += len(cand) * len(idx)
            if progress is not None and progress(min(done / total, 1.0)) is False:
                raise SearchCancelled()
        alive_idx = np.concatenate(keep) if keep else alive_idx[:0]
    return alive_idx, done, runs


def _accumulate(model, runs, cand, run, idx, poses, step_sum):
    """Fold the scored targets `idx` (m,) of one piece of a run into its per-family parts."""
    runs.margin[cand, run] = np.minimum(runs.margin[cand, run], np.min(poses.margin, axis=1))
    runs.manip[cand, run] = np.minimum(runs.manip[cand, run], np.min(poses.manip, axis=1))
    q = poses.q                                                             # (C, m, 8, 6)
    last = runs.last[cand[0], run]                                          # the same for all
    if last < 0:
        runs.q_first[cand, run] = q[:, 0]
        previous, q_next, ends = q[:, :-1], q[:, 1:], idx
    else:
        previous = np.concatenate([runs.q_last[cand, run][:, None], q[:, :-1]], axis=1)
        q_next, ends = q, np.r_[last, idx]
    if len(ends) > 1:
        programmed = np.diff(step_sum[ends])                                # (m',) s
        moved = cfg.joint_travel_s(model, previous, cfg.continue_joints(previous, q_next))
        runs.time[cand, run] += np.sum(np.maximum(moved, programmed[None, :, None]), axis=1)
    runs.q_last[cand, run] = q[:, -1]
    runs.last[cand, run] = idx[-1]


class _State:
    def __init__(self, count, runs):
        self.status = np.full(count, OK)
        self.fail_run = np.full(count, -1)
        self.fail_target = np.full(count, -1)
        self.evaluated = np.zeros(count)
        self.bad = np.zeros(count)
        self.families = np.full((count, runs), 255, dtype=np.uint8)


def screen(model, targets, T_u_r, criteria=None, q_start_deg=None, progress=None):
    """Screen candidate bases against every target (see the module docstring).

    Parameters
    ----------
    model : RobotModel
    targets : TargetSet
    T_u_r : ndarray, shape (M, 4, 4)
        Candidate bases in {U}, mm.
    criteria : Criteria, optional
    q_start_deg : array_like, shape (6,), optional
        Where the robot starts (the cell's StartJoints): the first joint move
        counts in the time estimate only with it, as in :func:`.timing.cycle_time`.
    progress : callable, optional
        ``progress(fraction)``, fraction of the work done in [0, 1]; returning
        False stops the screen (:class:`SearchCancelled`).

    Returns
    -------
    Screen
        The score's parts are measured on about :data:`SCORED_PER_RUN` targets
        spread over each run (pass or fail looks at every target).
    """
    criteria = criteria or Criteria()
    T_r_u = tf.invert_transform(np.asarray(T_u_r, dtype=float))
    M, R = len(T_r_u), len(targets.run_paths)
    state = _State(M, R)
    n_probe = sum(len(i) for _, i in _chunks(targets, True))
    total = M * (n_probe + len(targets.names))
    alive, done, _ = _evaluate(model, targets, T_r_u, criteria, np.arange(M), True, state,
                               progress, 0, total)
    total = done + alive.size * len(targets.names)
    state.evaluated[alive] = 0
    state.bad[alive] = 0
    alive, done, runs = _evaluate(model, targets, T_r_u, criteria, alive, False, state, progress,
                                  done, total)
    time_s, margin, manip = np.full(M, np.nan), np.full(M, np.nan), np.full(M, np.nan)
    families = np.full((M, R), -1)
    if alive.size:
        families[alive], time_s[alive], margin[alive], manip[alive] = _choose_families(
            model, runs, alive, q_start_deg)
    bad_fraction = state.bad / np.maximum(state.evaluated, 1)
    return Screen(state.status, state.fail_run, state.fail_target, bad_fraction, time_s, margin,
                  manip, families)


def _choose_families(model, runs, alive, q_start_deg):
    """Per candidate, the family each run keeps, as :func:`.configuration.solve_program` breaks
    ties: the one quickest to reach from where the robot is (the previous run's end, or the start
    joints, or the middle of the joint ranges).  Returns families (C, R), time, margin, manip (C,)."""
    C, R = alive.size, runs.families.shape[1]
    rows = np.arange(C)
    q_ref = np.broadcast_to(cfg.reference_joints(model) if q_start_deg is None
                            else np.asarray(q_start_deg, float), (C, 6)).copy()
    families = np.full((C, R), -1)
    time, margin, manip = np.zeros(C), np.full(C, np.inf), np.full(C, np.inf)
    for r in range(R):
        alive_f = (runs.families[alive, r][:, None] >> np.arange(8)) & 1 == 1   # (C, 8)
        q_first = runs.q_first[alive, r]                                        # (C, 8, 6)
        reach_s = cfg.joint_travel_s(model, q_ref[:, None], q_first)            # (C, 8)
        f = np.argmin(np.where(alive_f, np.nan_to_num(reach_s, nan=np.inf), np.inf), axis=1)
        families[:, r] = f
        if r > 0 or q_start_deg is not None:
            time += reach_s[rows, f]
        time += runs.time[alive, r][rows, f]
        margin = np.minimum(margin, runs.margin[alive, r][rows, f])
        manip = np.minimum(manip, runs.manip[alive, r][rows, f])
        q_ref = runs.q_last[alive, r][rows, f]
    return families, time, margin, manip


# --- the score ---------------------------------------------------------------------------------

def score(time_s, margin_deg, manip, weights=None):
    """The score of the module docstring and its parts.

    Parameters
    ----------
    time_s, margin_deg, manip : array_like, shape (K,)
        Cycle times (s), joint-limit margins (deg) and manipulabilities of
        the candidates compared (NaN: not scored).
    weights : Weights, optional

    Returns
    -------
    score : ndarray, shape (K,)
        NaN where a part is NaN.
    parts : dict of str to ndarray, shape (K,)
        ``time``, ``margin``, ``manipulability``: each in [0, 1], before weighting.
    """
    w = weights or Weights()
    time_s = np.asarray(time_s, dtype=float)
    with np.errstate(invalid="ignore", divide="ignore"):
        fastest = np.nanmin(time_s) if np.isfinite(time_s).any() else np.nan
        time_part = np.where(time_s > 0, fastest / time_s, 1.0)
        time_part = np.where(np.isnan(time_s), np.nan, time_part)
        margin_part = np.minimum(1.0, np.asarray(margin_deg, float) / MARGIN_FULL_DEG)
        manip_part = np.clip(np.asarray(manip, float), 0.0, 1.0)
    total = w.time * time_part + w.margin * margin_part + w.manipulability * manip_part
    return total, {"time": time_part, "margin": margin_part, "manipulability": manip_part}


def explain(model, targets, T_u_r, criteria=None):
    """Why one base fails the screen, every target evaluated.

    Parameters
    ----------
    model : RobotModel
    targets : TargetSet
    T_u_r : array_like, shape (4, 4)
    criteria : Criteria, optional

    Returns
    -------
    (int, str) or None
        The kind (a code of this module) and a sentence, e.g. ``"unreachable:
        3 of 13 targets of path 'Seam' (first 'Seam_130')"``; None when it passes.
    """
    criteria = criteria or Criteria()
    T_r_u = tf.invert_transform(np.asarray(T_u_r, dtype=float))[None]
    poses = _Poses(model, T_r_u, targets.T_u_f, criteria, catalog.reach_mm(model.spec) or 1000.0,
                   travel=targets.travel)
    kind, families = poses.kind[0], poses.families[0]
    worst = None
    for run, first, end in targets.run_slices():
        bad = np.flatnonzero(kind[first:end] != OK) + first
        label = targets.run_paths[run]
        if bad.size:
            code = int(np.max(kind[bad]))
            hits = bad[kind[bad] == code]
            text = "%s: %d of %d targets of path '%s' %s (first '%s')" % (
                KIND_NAMES[code], hits.size, end - first, label, _KIND_TEXT[code] % criteria.__dict__,
                targets.names[hits[0]])
            candidate = (code, text)
        elif np.bitwise_and.reduce(families[first:end]) == 0:
            candidate = (CONFIGURATION, "configuration: no one arm configuration reaches all %d "
                         "targets of path '%s'" % (end - first, label))
        else:
            continue
        if worst is None or candidate[0] > worst[0]:
            worst = candidate
    return worst


_KIND_TEXT = {
    UNREACHABLE: "are out of reach",
    JOINT_LIMIT: "need a joint beyond its limits",
    LIMIT_MARGIN: "need a joint within %(margin_deg)g deg of its limit",
    SINGULARITY: "are near a singularity (margins %(shoulder_mm)s mm, %(elbow_deg)s deg, "
                 "%(wrist_deg)s deg)",
}
