"""A program as the robot would run it: TCP poses sampled in time.

Each move is travelled at its programmed speed from the previous target
(linear: a straight line; circular: the arc through its via point; the
orientation slerped by the fraction travelled). Acceleration is not modelled
here (robots.motion.timing estimates it); a joint move is drawn as the straight line
between its ends, which is what the sensor simulations need (they act on path
moves only) and what the 3D view uses between two joint solutions.
"""

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from . import geometry, rotations
from .progress import Steps
from .program import CIRCULAR

# Speed of a move that only turns the tool (its TCP does not travel).
REORIENT_SPEED_DEG_S = 500.0
#: Most samples of one sampled trajectory (about 200 MB of poses; 83 minutes of motion
#: at the force sensor's 5 ms): a path given a speed of micrometres a second is refused
#: before it fills the memory.
MAX_TRAJECTORY_SAMPLES = 1_000_000


@dataclass
class Trajectory:
    """TCP poses in time.

    Attributes
    ----------
    time_s : ndarray, shape (N,)
    T_u_t : ndarray, shape (N, 4, 4)
        TCP pose in the assembly frame {U}, mm.
    s_mm : ndarray, shape (N,)
        Distance travelled by the TCP since the first sample, mm.
    move_index : ndarray of int, shape (N,)
        Index in ``program.moves()`` of the move each sample lies on.
    """

    time_s: np.ndarray
    T_u_t: np.ndarray
    s_mm: np.ndarray
    move_index: np.ndarray

    @property
    def position_mm(self):
        """ndarray, shape (N, 3): TCP positions in {U}, mm."""
        return self.T_u_t[:, :3, 3]


def target_in_u(program, move, target):
    """ndarray, shape (4, 4): a target's TCP pose in {U}, mm."""
    return program.frames[move.frame].T_u_b @ target.T_b_t


def _move_poses(T0, T1, via, fractions):
    """TCP poses along one move at the given fractions (M,) of it."""
    q0 = rotations.quaternion_from_matrix(T0[:3, :3])
    q1 = rotations.quaternion_from_matrix(T1[:3, :3])
    poses = np.repeat(np.eye(4)[None], len(fractions), axis=0)
    poses[:, :3, :3] = rotations.matrix_from_quaternion(rotations.quaternion_slerp(q0, q1, fractions))
    if via is None:
        poses[:, :3, 3] = T0[:3, 3] + fractions[:, None] * (T1[:3, 3] - T0[:3, 3])
    else:
        arc = geometry.Arc.from_three_points(T0[:3, 3], via[:3, 3], T1[:3, 3])
        poses[:, :3, 3] = arc.points_at(fractions * arc.length)
    return poses


def _move_length(T0, T1, via):
    if via is None:
        return float(np.linalg.norm(T1[:3, 3] - T0[:3, 3]))
    return geometry.Arc.from_three_points(T0[:3, 3], via[:3, 3], T1[:3, 3]).length


def move_duration_s(length_mm, angle_deg, speed_mm_s):
    """float: the time :func:`tcp_trajectory` gives a move, s: its length at its
    speed, or its turn at :data:`REORIENT_SPEED_DEG_S`, whichever is longer."""
    return max(length_mm / speed_mm_s, angle_deg / REORIENT_SPEED_DEG_S)


def move_durations_s(program, speed_mm_s=None, indices=None):
    """The time :func:`tcp_trajectory` gives moves of `program`, s.

    Parameters
    ----------
    program : Program
    speed_mm_s : dict of int to float, optional
        Speeds that replace the programmed ones, by index in ``program.moves()``.
    indices : sequence of int, optional
        The moves wanted (indices in ``program.moves()``); default all.

    Returns
    -------
    ndarray, shape (len(indices),)
        Each move from the previous target (the program's first: 0, it starts there).
    """
    moves = program.moves()
    speed_mm_s = speed_mm_s or {}
    indices = range(len(moves)) if indices is None else indices
    out = np.zeros(len(indices))
    for k, index in enumerate(indices):
        move, previous = moves[index], moves[max(index - 1, 0)]
        T0 = target_in_u(program, previous, previous.target)
        T1 = target_in_u(program, move, move.target)
        via = target_in_u(program, move, move.via) if move.kind == CIRCULAR and move.via else None
        angle = np.degrees(rotations.rotation_angle_between(T0[:3, :3], T1[:3, :3]))
        out[k] = move_duration_s(_move_length(T0, T1, via), float(angle),
                                 speed_mm_s.get(index, move.speed_mm_s))
    return out


def tcp_trajectory(program, dt_s, first_move=0, last_move=None, progress=None):
    """Sample the TCP of `program` every `dt_s` seconds.

    Parameters
    ----------
    program : core Program
    dt_s : float
        Sampling time, s (> 0).
    first_move, last_move : int, optional
        Range of ``program.moves()`` indices to sample (inclusive); the pose
        before `first_move` is that move's own start (the previous target),
        or its target when it is the program's first move.
    progress : callable, optional
        ``progress(fraction, text)`` (:mod:`.progress`), told every few
        moves; returning False raises ``Cancelled``.

    Returns
    -------
    Trajectory
        Starts at the start of `first_move`, ends exactly at the target of
        `last_move`.
    """
    if not dt_s > 0:
        raise InputError("The sampling time must be > 0 s, got %r." % dt_s)
    moves = program.moves()
    last_move = len(moves) - 1 if last_move is None else last_move
    if not 0 <= first_move <= last_move < len(moves):
        raise InputError("Move range %d-%d is outside the program's %d moves."
                         % (first_move, last_move, len(moves)))
    previous = moves[first_move - 1] if first_move > 0 else moves[0]
    T_prev = target_in_u(program, previous, previous.target)
    times, poses, s_values, indices = [0.0], [T_prev], [0.0], [first_move]
    t, s = 0.0, 0.0
    steps = Steps(progress, last_move + 1 - first_move, "sampling the trajectory")
    for index in range(first_move, last_move + 1):
        steps(index - first_move)
        move = moves[index]
        T1 = target_in_u(program, move, move.target)
        via = target_in_u(program, move, move.via) if move.kind == CIRCULAR and move.via else None
        length = _move_length(T_prev, T1, via)
        angle = np.degrees(rotations.rotation_angle_between(T_prev[:3, :3], T1[:3, :3]))
        duration = move_duration_s(length, angle, move.speed_mm_s)
        _check_sample_count(program, move, t + duration, dt_s)
        if duration > 0:
            local = np.arange(dt_s - (t % dt_s if t % dt_s > 1e-12 else 0.0), duration, dt_s)
            local = np.append(local[local < duration - 1e-9], duration)
            fractions = local / duration
            poses.extend(_move_poses(T_prev, T1, via, fractions))
            times.extend(t + local)
            s_values.extend(s + fractions * length)
            indices.extend([index] * len(local))
        t += duration
        s += length
        T_prev = T1
    return Trajectory(np.array(times), np.array(poses), np.array(s_values), np.array(indices))


def _check_sample_count(program, move, end_s, dt_s):
    """InputError when sampling up to `end_s` every `dt_s` takes more than
    :data:`MAX_TRAJECTORY_SAMPLES` samples (named after `move`'s path and speed)."""
    samples = end_s / dt_s
    if not samples <= MAX_TRAJECTORY_SAMPLES:           # also NaN and infinity
        raise InputError("Program '%s': sampling its motion every %g s up to move '%s' (%g mm/s) "
                         "takes %.3g samples, more than %d: raise the path's Speed or the sample "
                         "time." % (program.name, dt_s, getattr(move.target, "name", "?"),
                                    move.speed_mm_s, samples, MAX_TRAJECTORY_SAMPLES))
