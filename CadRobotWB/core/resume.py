"""A program that restarts a path where a run stopped (paper section 4.3).

After an abort the torch must go back to the exact point where the robot
stopped before the weld can restart: approach above that point along the
tool axis, enter it, then finish the path's remaining moves.
"""

import dataclasses

import numpy as np

from ..errors import InputError
from . import frames, geometry
from .program import (CIRCULAR, JOINT, LINEAR, ROLE_APPROACH, ROLE_ENTRY, Move, Program,
                      ProgramPath, Target)


def resume_program(program, move_index, T_u_stop, approach_mm=50.0, approach_speed_mm_s=None,
                   external_at_stop=None):
    """The program that finishes a path from a stop point.

    Parameters
    ----------
    program : Program
        The program that was running.
    move_index : int
        Index in ``program.moves()`` of the move the robot was on when it stopped.
    T_u_stop : ndarray, shape (4, 4)
        TCP pose where it stopped, in {U}, mm.
    approach_mm : float
        Approach distance above the stop point, along the tool's -Z.
    approach_speed_mm_s : float, optional
        Speed of the approach and entry; default that of the path's entry move.
    external_at_stop : array_like, shape (E,), optional
        The external axes where the robot stopped (a program with
        ``program.external``): the approach and the entry take them, the rest
        of the interrupted circular move's via the mean of them and its end's
        (it lies halfway, and the axes move linearly in time along a move).

    Returns
    -------
    Program
        Named ``<name>_resume``, one path: approach, entry to the stop pose,
        the rest of the interrupted move, the path's remaining moves (retract
        included). A weld the robot stopped in strikes its arc again at the
        stop pose (the entry); the welds after it are kept.
    """
    moves = program.moves()
    if not 0 <= move_index < len(moves):
        raise InputError("The stop lies on move %d, but the program has %d moves." % (move_index, len(moves)))
    stopped = moves[move_index]
    path = next(p for p in program.paths if any(m is stopped for m in p.moves))
    stop_index = [i for i, m in enumerate(path.moves) if m is stopped][0]
    rest = path.moves[stop_index:]
    frame = program.frames[stopped.frame]
    T_b_stop = frames.invert_transform(frame.T_u_b) @ np.asarray(T_u_stop, dtype=float)
    speed = approach_speed_mm_s or next((m.speed_mm_s for m in path.moves if m.role == ROLE_ENTRY),
                                        stopped.speed_mm_s)
    above = T_b_stop.copy()
    above[:3, 3] -= approach_mm * T_b_stop[:3, 2]

    def renamed(target, tag):
        return Target("%s_%s" % (target.name, tag)[:32], target.T_b_t, external=target.external)

    at_stop = None if external_at_stop is None else np.asarray(external_at_stop, dtype=float)
    out = [Move(JOINT, Target("rs_above", above, external=at_stop), speed, 0.0, stopped.frame,
                role=ROLE_APPROACH, comment="resume: %g mm above the stop point" % approach_mm),
           Move(LINEAR, Target("rs_stop", T_b_stop, external=at_stop), speed, 0.0, stopped.frame,
                role=ROLE_ENTRY, comment="resume: back to where the robot stopped")]
    for k, move in enumerate(rest):
        via = move.via
        if k == 0 and move.kind == CIRCULAR:
            full = geometry.Arc.from_three_points(_previous_target(path, move).T_b_t[:3, 3],
                                                  move.via.T_b_t[:3, 3], move.target.T_b_t[:3, 3])
            _, s_stop = full.closest(T_b_stop[:3, 3])
            T_via = move.via.T_b_t.copy()
            T_via[:3, 3] = full.point_at((s_stop + full.length) / 2.0)
            halfway = (None if at_stop is None or move.target.external is None
                       else (at_stop + np.asarray(move.target.external, dtype=float)) / 2.0)
            via = Target("rs_via", T_via, external=halfway)
        elif via is not None:
            via = renamed(via, "r")
        out.append(Move(move.kind, renamed(move.target, "r"), move.speed_mm_s, move.zone_mm,
                        move.frame, via=via, role=move.role, segment=move.segment,
                        comment=move.comment, weld=move.weld))
    return Program(program.name + "_resume", program.robot, program.tool, program.frames,
                   [ProgramPath(path.name, path.label, out, _resumed_welds(path, stop_index))],
                   source=program.source, external=program.external)


def _resumed_welds(path, stop_index):
    """The weld runs of `path` still to weld when the robot stopped on its move
    `stop_index`, re-indexed for the resumed path (whose move 2 is that move):
    a run the robot stopped inside starts again at the entry to the stop pose."""
    shift = 2 - stop_index
    runs = []
    for run in path.welds:
        if run.end < stop_index:
            continue
        start = max(run.start + shift, 1)
        runs.append(dataclasses.replace(run, start=start, end=run.end + shift))
    return runs


def _previous_target(path, move):
    index = [i for i, m in enumerate(path.moves) if m is move][0]
    if index == 0:
        raise InputError("A circular move cannot open a path.")
    return path.moves[index - 1].target
