"""The corrected path of a sensor run, as a robot program.

Once a sensor has found where the real seam or surface is, the corrected
TCP path can be run again without the sensor (the next part of a batch
placed the same way, or a controller without path correction). Its samples
(one per simulation step) are fitted with the fewest lines and circular arcs
that stay within a tolerance of every sample (:mod:`core.path_fitting`).
"""

import dataclasses
from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation, Slerp

from ..core import frames
from ..core.path_fitting import ARC, fit_path
from ..core.program import (CIRCULAR, JOINT, LINEAR, ROLE_APPROACH, ROLE_ENTRY, ROLE_PATH, ROLE_RETRACT,
                            Move, Program, ProgramPath, Target)
from ..core import rotations
from ..errors import InputError

# Default fitting tolerance, mm: five steps of the resolution the sensor loops
# correct the robot in (0.01 mm, ``seam_tracking``'s ``resolution_mm``), a tenth
# of the laser loop's largest correction step (0.5 mm), and about the laser
# run's own RMS tracking error once settled (0.043 mm on the paper's seam): a
# closer fit would replay the loop's noise, not the seam.
DEFAULT_TOLERANCE_MM = 0.05
# Default orientation tolerance, degrees: the run keeps the program's
# orientations, so this only has to follow the tool's own turns (risk areas).
DEFAULT_ANGLE_TOLERANCE_DEG = 0.1


@dataclass
class CorrectedPath:
    """A corrected path fitted with lines and arcs.

    Attributes
    ----------
    T_u_t : ndarray, shape (N, 4, 4)
        The corrected TCP poses in {U}, mm: the run's positions, the
        program's orientations at the same times.
    moves : list of core.path_fitting.FittedMove
    tolerance_mm, angle_tolerance_deg : float
        The tolerances the moves were fitted within.
    """

    T_u_t: np.ndarray
    moves: list
    tolerance_mm: float
    angle_tolerance_deg: float

    def counts(self):
        """dict: ``samples`` (corrected poses before fitting), ``moves``
        (path moves after), ``lines``, ``arcs``."""
        arcs = sum(m.kind == ARC for m in self.moves)
        return {"samples": len(self.T_u_t), "moves": len(self.moves), "lines": len(self.moves) - arcs,
                "arcs": arcs}


def nearest_samples(trajectory_time_s, time_s):
    """Indices (N,) of the trajectory samples nearest in time to `time_s` (N,), s.

    A run's clock (``k * dt`` from the loop's start) and the trajectory's (move
    by move) differ by rounding, and a loop may step at another rate than the
    trajectory was sampled: the nearest sample, not the next one."""
    times = np.asarray(trajectory_time_s, dtype=float)
    after = np.clip(np.searchsorted(times, time_s), 1, len(times) - 1)
    before = after - 1
    return np.where(np.abs(times[after] - time_s) < np.abs(time_s - times[before]), after, before)


def program_orientations(trajectory, time_s):
    """ndarray (N, 3, 3): the program's tool orientation at `time_s` (N,), s, slerped
    between the trajectory's samples (the first of two at one time), as the force loop
    takes them.

    Not the next sample's: one 10 ms step late, a tool turning round a pipe at 30 mm/s is
    0.29 degrees off, beyond the fit's 0.1 degree tolerance, and the fit made a move per
    sample."""
    times = np.asarray(trajectory.time_s, dtype=float)
    keep = np.concatenate([[True], np.diff(times) > 1e-12])
    if keep.sum() < 2:
        return np.repeat(np.asarray(trajectory.T_u_t)[:1, :3, :3], len(time_s), axis=0)
    turning = Slerp(times[keep], Rotation.from_matrix(np.asarray(trajectory.T_u_t)[keep, :3, :3]))
    return turning(np.clip(time_s, times[0], times[-1])).as_matrix()


def corrected_poses(scene, run):
    """ndarray (N, 4, 4): the corrected TCP poses of `run` in {U}, mm (up to
    the stop of an aborted run), with the program's orientation at each time."""
    end = (run.stop_index + 1) if run.aborted and run.stop_index is not None else len(run.time_s)
    T_u_t = np.repeat(np.eye(4)[None], end, axis=0)
    T_u_t[:, :3, :3] = program_orientations(scene.trajectory, run.time_s[:end])
    T_u_t[:, :3, 3] = run.actual_mm[:end]
    return T_u_t


def fit_corrected_path(scene, run, tolerance_mm=DEFAULT_TOLERANCE_MM,
                       angle_tolerance_deg=DEFAULT_ANGLE_TOLERANCE_DEG):
    """Fit lines and arcs to `run`'s corrected path.

    Parameters
    ----------
    scene : SensorScene
    run : SensorRun
    tolerance_mm : float
        Largest distance between a corrected sample and the fitted moves, mm
        (default :data:`DEFAULT_TOLERANCE_MM`, 0.05 mm).
    angle_tolerance_deg : float
        Largest angle between a sample's orientation and the orientation the
        controller interpolates along its move, degrees (default 0.1).

    Returns
    -------
    CorrectedPath
    """
    T_u_t = corrected_poses(scene, run)
    if len(T_u_t) < 2:
        raise InputError("The %s run has fewer than 2 samples: there is no corrected path to write."
                         % run.sensor)
    moves = fit_path(T_u_t[:, :3, 3], T_u_t[:, :3, :3], tolerance_mm, angle_tolerance_deg)
    return CorrectedPath(T_u_t, moves, float(tolerance_mm), float(angle_tolerance_deg))


def _via_pose(T_start, T_end, via_mm):
    """Pose at an arc's via point: halfway in orientation (the via is halfway along the arc)."""
    T = np.eye(4)
    q = rotations.quaternion_slerp(rotations.quaternion_from_matrix(T_start[:3, :3]),
                                   rotations.quaternion_from_matrix(T_end[:3, :3]), 0.5)
    T[:3, :3] = rotations.matrix_from_quaternion(q)
    T[:3, 3] = via_mm
    return T


def _lifted(T, distance):
    """`T` moved back along its tool axis by `distance` mm."""
    T = T.copy()
    T[:3, 3] -= distance * T[:3, 2]
    return T


def _path_moves(fitted, T_b_u, frame, sensor, sources):
    """The program's path moves of a CorrectedPath, in work frame `frame` ({B}); each
    fitted move takes the speed, zone and weld of the program move its end lies on
    (`sources` (N,): that program move per sample), the last one stopping exactly."""
    out = []
    comment = "path corrected by the %s sensor" % sensor
    for n, m in enumerate(fitted.moves, 1):
        T_end = T_b_u @ fitted.T_u_t[m.end]
        via = None
        if m.kind == ARC:
            T_via = _via_pose(fitted.T_u_t[m.start], fitted.T_u_t[m.end], m.via_mm)
            via = Target("cr_%d_via" % n, T_b_u @ T_via)
        source = sources[m.end]
        out.append(Move(CIRCULAR if via is not None else LINEAR, Target("cr_%d" % n, T_end),
                        source.speed_mm_s, source.zone_mm, frame, via=via, role=ROLE_PATH,
                        comment=comment, weld=source.weld))
    out[-1].zone_mm = 0.0
    return out


def _corrected_runs(path, moves):
    """The weld runs of `path` along the corrected `moves` (the whole path,
    entry first): each stretch of moves welding in one run becomes that run,
    struck at the target before it, both ends stopping exactly, the welded
    moves at the run's travel speed."""
    by_name = {run.name: run for run in path.welds}
    runs = []
    for i, move in enumerate(moves):
        if move.weld is None:
            continue
        run = by_name[move.weld]
        move.speed_mm_s = run.schedule.travel_speed_mm_s
        if runs and runs[-1].name == run.name and runs[-1].end == i - 1:
            runs[-1].end = i
        else:
            moves[i - 1].zone_mm = 0.0
            runs.append(dataclasses.replace(run, start=i - 1, end=i))
    for run in runs:
        moves[run.end].zone_mm = 0.0
    return runs


def _give_axes(moves, fitted, time_s, axes):
    """Each target of the corrected `moves` (approach, entry, the fitted moves, a
    retract) gets the external axis values of the time of the sample it lies on
    (a via: halfway between its move's ends), so the positioner turns the part
    as it did in the run; nothing without external axes (`axes` None)."""
    if axes is None:
        return
    first, last = time_s[0], time_s[fitted.moves[-1].end]
    for move in moves[:2]:
        move.target.external = axes.values_at(first)
    for move, fit in zip(moves[2:], fitted.moves):
        move.target.external = axes.values_at(time_s[fit.end])
        if move.via is not None:
            move.via.external = axes.values_at(0.5 * (time_s[fit.start] + time_s[fit.end]))
    for move in moves[2 + len(fitted.moves):]:
        move.target.external = axes.values_at(last)


def corrected_program(scene, run, tolerance_mm=DEFAULT_TOLERANCE_MM,
                      angle_tolerance_deg=DEFAULT_ANGLE_TOLERANCE_DEG, fitted=None):
    """The program that follows `run`'s corrected TCP path.

    Parameters
    ----------
    scene : SensorScene
        With its ``program`` (the program the run came from).
    run : SensorRun
        Aborted runs give the path up to the stop.
    tolerance_mm, angle_tolerance_deg : float
        See :func:`fit_corrected_path`.
    fitted : CorrectedPath, optional
        The fit already made (then the tolerances are not used).

    Returns
    -------
    Program
        ``<name>_corrected``: approach and entry like the original path,
        the fitted lines and arcs (circular moves with their via points)
        through the corrected path, a retract along the tool. A fitted move
        welds in the run of the program move its end lies on (so a run's ends
        move to the fitted move ends nearest them). With external axes, the
        program's, each target at the values of its time in the run.
    """
    program, traj = scene.program, scene.trajectory
    if program is None:
        raise InputError("This sensor scene has no program to correct.")
    if fitted is None:
        fitted = fit_corrected_path(scene, run, tolerance_mm, angle_tolerance_deg)

    first = program.moves()[int(traj.move_index[0])]
    path = next(p for p in program.paths if any(m is first for m in p.moves))
    entry = next(m for m in path.moves if m.role == ROLE_ENTRY)
    approach = next(m for m in path.moves if m.role == ROLE_APPROACH)
    retract = next((m for m in path.moves if m.role == ROLE_RETRACT), None)
    T_b_u = frames.invert_transform(program.frames[first.frame].T_u_b)

    approach_mm = float(np.linalg.norm(approach.target.T_b_t[:3, 3] - entry.target.T_b_t[:3, 3]))
    start = T_b_u @ fitted.T_u_t[0]
    out = [Move(JOINT, Target("cr_above", _lifted(start, approach_mm)), approach.speed_mm_s, 0.0,
                first.frame, role=ROLE_APPROACH, comment="approach the corrected path"),
           Move(LINEAR, Target("cr_0", start), entry.speed_mm_s, 0.0, first.frame, role=ROLE_ENTRY,
                comment="entry to the corrected path")]
    program_moves = program.moves()
    sources = [program_moves[int(traj.move_index[k])]
               for k in nearest_samples(traj.time_s, run.time_s)]
    out += _path_moves(fitted, T_b_u, first.frame, run.sensor, sources)
    if retract is not None:
        up = float(np.linalg.norm(retract.target.T_b_t[:3, 3] - path.moves[-2].target.T_b_t[:3, 3]))
        out.append(Move(LINEAR, Target("cr_up", _lifted(out[-1].target.T_b_t, up)), retract.speed_mm_s,
                        0.0, first.frame, role=ROLE_RETRACT, comment="retract"))
    runs = _corrected_runs(path, out)
    _give_axes(out, fitted, run.time_s, scene.robot.axes)
    return Program(program.name + "_corrected", program.robot, program.tool, program.frames,
                   [ProgramPath(path.name, path.label + " (corrected)", out, runs)],
                   source=program.source, external=program.external)
