"""The corrected path of a sensor run, as a robot program.

Once a sensor has found where the real seam or surface is, the corrected
TCP path can be run again without the sensor (the next part of a batch
placed the same way, or a controller without path correction). Its samples
are thinned to the fewest linear moves that stay within a chord tolerance.
"""

import numpy as np

from ..core import frames, rotations
from ..core.program import (JOINT, LINEAR, ROLE_APPROACH, ROLE_ENTRY, ROLE_PATH, ROLE_RETRACT, Move,
                            Program, ProgramPath, Target)
from ..errors import InputError


def thin_polyline(points_mm, tolerance_mm, keep=None):
    """Indices of the points to keep so the polyline through them stays
    within `tolerance_mm` of every dropped point (Douglas-Peucker).

    Parameters
    ----------
    points_mm : ndarray, shape (N, 3)
    tolerance_mm : float
    keep : ndarray of bool, shape (N,), optional
        Points that must stay (e.g. where the orientation turns).

    Returns
    -------
    ndarray of int
        Sorted indices, first and last included.
    """
    points = np.asarray(points_mm, dtype=float)
    chosen = np.zeros(len(points), bool)
    chosen[[0, -1]] = True
    if keep is not None:
        chosen |= keep
    anchors = list(np.flatnonzero(chosen))
    todo = list(zip(anchors[:-1], anchors[1:]))
    while todo:
        a, b = todo.pop()
        if b - a < 2:
            continue
        chord = points[b] - points[a]
        inner = points[a + 1:b] - points[a]
        length2 = float(chord @ chord)
        u = np.clip(inner @ chord / length2, 0.0, 1.0) if length2 > 0 else np.zeros(len(inner))
        distance = np.linalg.norm(inner - u[:, None] * chord, axis=1)
        worst = int(np.argmax(distance))
        if distance[worst] > tolerance_mm:
            split = a + 1 + worst
            chosen[split] = True
            todo += [(a, split), (split, b)]
    return np.flatnonzero(chosen)


def corrected_program(scene, run, tolerance_mm=0.05, turn_deg=0.5):
    """The program that follows `run`'s corrected TCP path.

    Parameters
    ----------
    scene : SensorScene
        With its ``program`` (the program the run came from).
    run : SensorRun
        Aborted runs give the path up to the stop.
    tolerance_mm : float
        Largest distance between the corrected samples and the moves.
    turn_deg : float
        A target is kept wherever the tool has turned this much since the
        previous kept one.

    Returns
    -------
    Program
        ``<name>_corrected``: approach and entry like the original path,
        linear moves through the corrected path, a retract along the tool.
    """
    program, traj = scene.program, scene.trajectory
    if program is None:
        raise InputError("This sensor scene has no program to correct.")
    end = (run.stop_index + 1) if run.aborted and run.stop_index is not None else len(run.time_s)
    times, actual = run.time_s[:end], run.actual_mm[:end]
    nearest = np.clip(np.searchsorted(traj.time_s, times), 0, len(traj.time_s) - 1)
    T_u_t = traj.T_u_t[nearest].copy()
    T_u_t[:, :3, 3] = actual
    turned = np.zeros(len(times), bool)
    reference = T_u_t[0, :3, :3]
    for i in range(1, len(times)):
        if np.degrees(rotations.rotation_angle_between(reference, T_u_t[i, :3, :3])) >= turn_deg:
            turned[i] = True
            reference = T_u_t[i, :3, :3]
    kept = thin_polyline(actual, tolerance_mm, turned)

    moves = program.moves()
    first = moves[int(traj.move_index[0])]
    path = next(p for p in program.paths if any(m is first for m in p.moves))
    entry = next(m for m in path.moves if m.role == ROLE_ENTRY)
    approach = next(m for m in path.moves if m.role == ROLE_APPROACH)
    retract = next((m for m in path.moves if m.role == ROLE_RETRACT), None)
    T_b_u = frames.invert_transform(program.frames[first.frame].T_u_b)
    speed = first.speed_mm_s

    def lifted(T, distance):
        T = T.copy()
        T[:3, 3] -= distance * T[:3, 2]
        return T

    approach_mm = float(np.linalg.norm(approach.target.T_b_t[:3, 3] - entry.target.T_b_t[:3, 3]))
    start = T_b_u @ T_u_t[kept[0]]
    out = [Move(JOINT, Target("cr_above", lifted(start, approach_mm)), approach.speed_mm_s, 0.0,
                first.frame, role=ROLE_APPROACH, comment="approach the corrected path"),
           Move(LINEAR, Target("cr_0", start), entry.speed_mm_s, 0.0, first.frame, role=ROLE_ENTRY,
                comment="entry to the corrected path")]
    for n, i in enumerate(kept[1:], 1):
        out.append(Move(LINEAR, Target("cr_%d" % n, T_b_u @ T_u_t[i]), speed, first.zone_mm, first.frame,
                        role=ROLE_PATH, comment="path corrected by the %s sensor" % run.sensor))
    out[-1].zone_mm = 0.0
    if retract is not None:
        up = float(np.linalg.norm(retract.target.T_b_t[:3, 3] - path.moves[-2].target.T_b_t[:3, 3]))
        out.append(Move(LINEAR, Target("cr_up", lifted(out[-1].target.T_b_t, up)), retract.speed_mm_s,
                        0.0, first.frame, role=ROLE_RETRACT, comment="retract"))
    return Program(program.name + "_corrected", program.robot, program.tool, program.frames,
                   [ProgramPath(path.name, path.label + " (corrected)", out)], source=program.source)
