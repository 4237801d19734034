"""What the external-axis chooser needs to know about each target of a program.

For every target (``Program.targets()`` order, vias first) a :class:`SeamTable`
holds its pose in its work frame, the direction of travel there, the part vector
the positioner must turn straight down, and the group of targets (a weld run, or a
path without welds) that keeps one positioner branch. Targets off the seam
(approach, entry, retract, moves between runs) copy the values of an *anchor*:
the nearest welded target before them in their path, else the first after.

The gravity angle of a weld target (plan issue 23, section 1): the angle between
the weld frame's Z (``core.weave.frame_axes(travel, tool_z)``: the tool axis with
its travel component removed) in {U} and gravity (0, 0, -1); the slope: the angle
between the weld frame's X (the travel) and the horizontal plane.

Pure numpy: never imports FreeCAD.
"""

from dataclasses import dataclass
from typing import List

import numpy as np

from ...core import program as ir
from ...core.weave import frame_axes
from ...errors import InputError

#: Gravity angle (deg) each welding position asks for (ISO 6947: PA flat, PB
#: horizontal-vertical fillet: the bisector 45 degrees from the vertical, the seam horizontal).
POSITION_GRAVITY_DEG = {"PA": 0.0, "PB": 45.0}

WELDED = 0        # on a weld run: its position is kept
TOOL_DOWN = 1     # on a path without welds: the tool axis kept as near straight down as it goes
ANCHORED = 2      # off the seam: copies the values of its anchor target


@dataclass
class SeamTable:
    """Per-target data for the chooser (N targets, ``Program.targets()`` order).

    Attributes
    ----------
    targets : list of Target
    frames : list of str
        Work frame of each target's move.
    T_b_t : ndarray, shape (N, 4, 4)
        Each target's TCP in its work frame, mm.
    travel_b : ndarray, shape (N, 3)
        Unit direction of travel in the work frame (NaN off the seam).
    role : ndarray of int, shape (N,)
        :data:`WELDED`, :data:`TOOL_DOWN` or :data:`ANCHORED`.
    group : ndarray of int, shape (N,)
        Index in :attr:`group_names` of the weld run (or tool-down path) a
        target belongs to; for an anchored target its anchor's group; -1 when
        its path has no anchor at all.
    anchor : ndarray of int, shape (N,)
        Index of the target whose values an anchored target copies; itself otherwise.
    group_names : list of str
        Weld run names (tool-down paths: ``"path:<name>"``).
    group_positions : list of str
        ``"PA"`` or ``"PB"`` per group (``"PA"`` for a tool-down path).
    """

    targets: list
    frames: List[str]
    T_b_t: np.ndarray
    travel_b: np.ndarray
    role: np.ndarray
    group: np.ndarray
    anchor: np.ndarray
    group_names: List[str]
    group_positions: List[str]

    @property
    def on_seam(self):
        """ndarray of bool, shape (N,): the targets the chooser solves (not anchored)."""
        return self.role != ANCHORED

    @property
    def welded(self):
        """ndarray of bool, shape (N,)."""
        return self.role == WELDED


def circle_tangents(start, via, end, at):
    """Unit tangents of the circles through start, via, end at the points `at`,
    in the sense start -> via -> end.

    Parameters
    ----------
    start, via, end, at : ndarray, shape (M, 3)
        mm.

    Returns
    -------
    ndarray, shape (M, 3)
        NaN rows for degenerate (collinear) circles.
    """
    a, b = start - end, via - end
    axb = np.cross(a, b)
    den = 2.0 * np.sum(axb * axb, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        centre = end + np.cross(np.sum(a * a, axis=1)[:, None] * b
                                - np.sum(b * b, axis=1)[:, None] * a, axb) / den[:, None]
        normal = np.cross(via - start, end - via)
        tangent = np.cross(normal, at - centre)
        return tangent / np.linalg.norm(tangent, axis=1)[:, None]


def _unit(v):
    with np.errstate(invalid="ignore", divide="ignore"):
        return v / np.linalg.norm(v, axis=-1)[..., None]


def _move_travel(moves, starts, vias, ends):
    """Travel directions of each move at its via, its end and its start.

    Parameters
    ----------
    moves : list of Move
    starts, vias, ends : ndarray, shape (M, 3)
        Positions (mm, work frame); `vias` NaN for non-circular moves.

    Returns
    -------
    at_via, at_end, at_start : ndarray, shape (M, 3)
        Unit vectors (NaN at a via of a linear move).
    """
    line = _unit(ends - starts)
    circular = np.array([m.kind == ir.CIRCULAR and m.via is not None for m in moves])
    at_via, at_end, at_start = np.full_like(line, np.nan), line.copy(), line.copy()
    if circular.any():
        s, v, e = starts[circular], vias[circular], ends[circular]
        at_via[circular] = circle_tangents(s, v, e, v)
        at_end[circular] = circle_tangents(s, v, e, e)
        at_start[circular] = circle_tangents(s, v, e, s)
    return at_via, at_end, at_start


def seam_table(program):
    """The :class:`SeamTable` of `program`.

    Travel at a welded move's via and end: the move's tangent there (a linear
    move's direction, a circular move's circle tangent); at a weld run's start
    target (the arc ignites there): the first welded move's direction at its start.

    Parameters
    ----------
    program : Program

    Returns
    -------
    SeamTable
    """
    targets, frames, poses, travels, roles, groups = [], [], [], [], [], []
    group_names, group_positions = [], []
    path_of = []
    for path_index, path in enumerate(program.paths):
        moves = path.moves
        if not moves:
            continue
        ends = np.array([m.target.T_b_t[:3, 3] for m in moves], dtype=float)
        starts = np.vstack([ends[:1], ends[:-1]])
        vias = np.array([m.via.T_b_t[:3, 3] if m.via is not None else (np.nan,) * 3
                         for m in moves], dtype=float)
        at_via, at_end, at_start = _move_travel(moves, starts, vias, ends)
        role = np.full(len(moves), ANCHORED)
        group = np.full(len(moves), -1)
        travel_end = np.full((len(moves), 3), np.nan)
        if path.welds:
            for run in path.welds:
                group_names.append(run.name)
                group_positions.append(_position(run))
                k = len(group_names) - 1
                role[run.start:run.end + 1] = WELDED
                group[run.start:run.end + 1] = k
                travel_end[run.start + 1:run.end + 1] = at_end[run.start + 1:run.end + 1]
                if run.start + 1 < len(moves):
                    travel_end[run.start] = at_start[run.start + 1]
        else:
            group_names.append("path:%s" % path.name)
            group_positions.append("PA")
            role[:] = TOOL_DOWN
            group[:] = len(group_names) - 1
        for i, move in enumerate(moves):
            if move.frame not in program.frames:
                raise InputError("Move to target '%s' in path '%s' uses work frame '%s', which "
                                 "the program does not define; regenerate the program."
                                 % (move.target.name, path.label or path.name, move.frame))
            pairs = [(move.via, at_via[i])] if move.via is not None else []
            for target, travel in pairs + [(move.target, travel_end[i])]:
                targets.append(target)
                frames.append(move.frame)
                poses.append(np.asarray(target.T_b_t, dtype=float))
                travels.append(travel if role[i] == WELDED else (np.nan,) * 3)
                roles.append(role[i])
                groups.append(group[i])
                path_of.append(path_index)
    role = np.array(roles, dtype=int)
    group = np.array(groups, dtype=int)
    anchor = _anchors(role, np.array(path_of, dtype=int))
    group = np.where(anchor >= 0, group[np.maximum(anchor, 0)], -1)
    return SeamTable(targets, frames, np.array(poses).reshape(-1, 4, 4),
                     np.array(travels, dtype=float).reshape(-1, 3), role, group, anchor,
                     group_names, group_positions)


def _position(run):
    """The run's welding position, checked: "PA" or "PB"."""
    position = run.position or "PA"
    if position not in POSITION_GRAVITY_DEG:
        raise InputError("Weld '%s' asks for welding position '%s': a positioner keeps a seam "
                         "in %s; choose one of them." % (run.label or run.name, position,
                                                         " or ".join(POSITION_GRAVITY_DEG)))
    return position


def _anchors(role, path_of):
    """Index of the target each target copies: itself on the seam, else the
    nearest seam target before it in its path, else the first after; -1: none."""
    n = len(role)
    index = np.arange(n)
    on = role != ANCHORED
    before = np.maximum.accumulate(np.where(on, index, -1)) if n else index
    after = (np.minimum.accumulate(np.where(on, index, n)[::-1])[::-1]) if n else index
    same_before = (before >= 0) & (path_of[np.maximum(before, 0)] == path_of)
    same_after = (after < n) & (path_of[np.minimum(after, n - 1)] == path_of)
    # Before the first seam target of a path (approach, entry): the first one after.
    first_in_path = np.where(same_after & ~same_before, after, -1)
    return np.where(on, index, np.where(same_before, before, first_in_path))


def down_vectors(table):
    """The part vector each solved target needs straight down, in its work frame.

    PA (and a tool-down path): the weld frame's Z (the tool axis for a tool-down
    target). PB: ``cos 45 Z + s sin 45 Y`` for both signs ``s``: then Z is 45
    degrees from gravity and the seam (X, perpendicular to both) horizontal.

    Parameters
    ----------
    table : SeamTable

    Returns
    -------
    ndarray, shape (N, S, 3)
        S = 2 sides (equal for PA and tool-down targets); NaN rows off the seam.
    """
    n = len(table.targets)
    out = np.full((n, 2, 3), np.nan)
    tool_z = table.T_b_t[:, :3, 2]
    down = table.role == TOOL_DOWN
    out[down] = tool_z[down][:, None, :]
    weld = table.welded
    if weld.any():
        _, Y, Z = frame_axes(table.travel_b[weld], tool_z[weld])
        gravity = np.radians([POSITION_GRAVITY_DEG[table.group_positions[g]]
                              for g in table.group[weld]])
        c, s = np.cos(gravity)[:, None], np.sin(gravity)[:, None]
        out[weld, 0] = c * Z + s * Y
        out[weld, 1] = c * Z - s * Y
    return out


def gravity_and_slope(table, R_u_b):
    """Gravity angle and slope of every welded target, deg.

    Parameters
    ----------
    table : SeamTable
    R_u_b : ndarray, shape (N, 3, 3)
        Each target's work frame orientation in {U} at its external values.

    Returns
    -------
    gravity_deg, slope_deg : ndarray, shape (N,)
        NaN where the target is not welded.
    """
    n = len(table.targets)
    gravity, slope = np.full(n, np.nan), np.full(n, np.nan)
    weld = table.welded
    if weld.any():
        X, _, Z = frame_axes(table.travel_b[weld], table.T_b_t[weld, :3, 2])
        Z_u = np.einsum("nij,nj->ni", R_u_b[weld], Z)
        X_u = np.einsum("nij,nj->ni", R_u_b[weld], X)
        gravity[weld] = np.degrees(np.arccos(np.clip(-Z_u[:, 2], -1.0, 1.0)))
        slope[weld] = np.degrees(np.arcsin(np.clip(np.abs(X_u[:, 2]), 0.0, 1.0)))
    return gravity, slope
