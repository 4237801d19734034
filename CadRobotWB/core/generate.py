"""Turn a cell read from the CAD document into a language-neutral :class:`Program`.

The input is plain data (:class:`CellSpec` and friends) filled by the App
layer (``objects/reader.py``); the output is the program IR of
:mod:`.program` that every post-processor reads. This module follows
section 3 of Neto et al. 2012:

* targets are the tool marker poses expressed in the calibration frame,
  ``T_b_t = inv(T_u_b) @ T_u_t`` (eqs 1-7, eq 16);
* the move type follows the line type: line -> linear move, arc -> circular
  moves (each at most 180 degrees, via point in the middle), spline ->
  linear moves through its samples;
* on an arc the tool keeps its orientation, or turns with the arc
  (:mod:`.segment_orientation`, the path's ``tool_on_arcs``);
* a risk area is re-sampled at ``step_mm`` (eqs 8-13) and its orientations
  are slerped by arc-length fraction (eqs 14-15) through keyframes: its
  start, every tool marker governing a segment strictly inside it, its end
  (see :meth:`_PathWriter._write_risk_area`). A corner area covers only the
  last ``corner_span_mm`` of its first segment and the first of its last;
  on a closed path an area from the last segment to the first turns the
  tool round the end point, so the loop ends as it started.

Pure numpy; never imports FreeCAD.
"""

import re
from dataclasses import dataclass, field
from typing import Dict, List, Optional

import numpy as np

from ..errors import FrameError, GeometryError, InputError, MarkerError, RiskAreaError
from . import frames as tf
from . import interpolation, rotations, zones
from .segment_orientation import CONSTANT, segment_orientations
from .progress import Steps, stage
from .welding import POSITIONS, Tracking, WeldSchedule, WeldSpec
from .weld_runs import CORNER_SLOWDOWN, check_runs
from .program import (CIRCULAR, JOINT, LINEAR, ROLE_APPROACH, ROLE_ENTRY, ROLE_PATH,
                      ROLE_REORIENT, ROLE_RETRACT, ROLE_RISK, Move, Program,
                      ProgramPath, Target, ToolData, WeldRun, WorkFrame)

# Two tool orientations closer than this (radians) count as the same.
ORIENTATION_TOL_RAD = 1e-6
# Longest identifier we make (RAPID allows 32 characters).
MAX_NAME_LEN = 24
# Upper bound on the interpolated points of one risk area (guards against a
# step typed in metres instead of millimetres).
MAX_RISK_POINTS = 100000
#: Largest change of the tool's orientation from one move of a risk area to the next, degrees
#: (the suggested step and the pivot round a closed loop's end point keep to it).
MAX_TURN_PER_MOVE_DEG = 2.0
#: Fastest turn of the tool through a corner area (a corner span > 0) while it welds on,
#: deg/s: the TCP slows down so that a 90-degree corner takes at least 2.25 s. Near a
#: wrist singularity the wrist turns up to about 9 times faster than the tool (8.2 times
#: measured at the angle cleat's corners with the default base); at 40 deg/s that stays
#: within the catalog arms' wrist speeds (J4, J6 >= 360 deg/s).
CORNER_TURN_DEG_S = 40.0
#: What a risk area does at its corner (RiskArea.AtCorner), the default first: weld on while
#: the tool turns, or stop exactly, turn in place, and go on (where arc off/on will go).
WELD_THROUGH = "Weld through"
STOP_AND_REORIENT = "Stop and reorient"
AT_CORNER = (WELD_THROUGH, STOP_AND_REORIENT)
#: Comment prefix of the reorientation move of a "Stop and reorient" corner, and the words after
#: it that a weld through the corner replaces by where its arc goes off and on.
CORNER_STOP = "corner stop"
CORNER_STOP_ARC = "(arc off/on here)"


@dataclass
class FrameSpec:
    """A calibration (work-object) frame {B} as drawn in the CAD model.

    Attributes
    ----------
    name : str
        Internal name of the document object.
    label : str
        User-visible label.
    T_u_b : ndarray, shape (4, 4)
        {B} in the CAD assembly frame {U}, mm.
    T_r_b : ndarray, shape (4, 4), optional
        {B} taught on the real part, in the robot base frame {R}, mm; the
        programs' work object / user frame. None: as drawn, ``inv(T_u_r) @ T_u_b``.
        Targets ``T_b_t`` stay as drawn either way.
    """

    name: str
    label: str
    T_u_b: np.ndarray
    T_r_b: Optional[np.ndarray] = None


@dataclass
class RiskAreaSpec:
    """Consecutive path segments where the tool turns sharply (section 3.3).

    Attributes
    ----------
    name, label : str
        Internal name and user-visible label of the document object.
    first, last : int
        1-based, inclusive segment numbers, ``1 <= first <= last <= n``; on a
        closed path also ``first = n, last = 1``: the corner where the loop
        closes (the tool turns round the end point after the last segment).
    step_mm : float or None
        Spacing of the interpolated points, mm; None uses the path's step.
    corner_span_mm : float or None
        The area covers only the last `corner_span_mm` of segment `first` and
        the first `corner_span_mm` of segment `last` (whole segments between),
        at most the whole segment; None or 0: whole segments (the paper's case).
    at_corner : {WELD_THROUGH, STOP_AND_REORIENT}
        Weld on while the tool turns (re-sampled, slerped), or stop exactly at
        each junction inside, turn in place (zone 0) and go on: the segments
        are then written as outside an area (the span does not matter), each
        such reorientation a move commented "corner stop (arc off/on here)".
    """

    name: str
    label: str
    first: int
    last: int
    step_mm: Optional[float] = None
    corner_span_mm: Optional[float] = None
    at_corner: str = WELD_THROUGH


@dataclass
class PathSpec:
    """One robot path: chained segments and the tool orientation on each.

    Attributes
    ----------
    name, label : str
        Internal name and user-visible label of the document object.
    segments : list of geometry.Line, geometry.Arc or geometry.Polyline
        In travel order, chained (see :func:`geometry.chain_segments`), {U}, mm.
    R_u_t : list of ndarray, shape (3, 3)
        Tool (TCP) orientation in {U} on each segment, one per segment.
    frame : str
        Key in :attr:`CellSpec.frames` of the frame the targets are given in.
    speed_mm_s : float
        TCP speed along the path, mm/s.
    zone_mm : float or None
        Blending radius of the path's interior targets, mm (0 = stop at every
        target); None = chosen by :func:`.zones.limit_zones` from the point
        spacing and ``zone_tolerance_mm``. A given radius is kept within half
        the neighbouring moves too.
    zone_tolerance_mm : float
        Largest corner cut of an automatic zone, mm (the path's ChordTolerance).
    approach_mm, retract_mm : float
        Distance of the approach / retract point from the first / last
        target, back along the tool +Z axis, mm; 0 = no such point.
    approach_speed_mm_s : float
        Speed of the approach, entry and retract moves, mm/s.
    sample_time_s : float
        Sampling width Δt of eqs 8-13, s.
    step_mm : float or None
        Risk-area point spacing |v|·Δt, mm; None = ``speed_mm_s * sample_time_s``.
    risk_areas : list of RiskAreaSpec
    closed : bool
        The path ends where it starts (an area from its last segment to its
        first is then allowed).
    marker_s_mm : list of (float or None), optional
        Per segment, the arc length (mm from its start) of the origin of the
        tool marker that sets it, None where it inherits the orientation
        (risk areas pass through these markers). None: unknown, no markers
        inside areas.
    tool_on_arcs : {segment_orientation.TURNS_WITH_ARC, segment_orientation.CONSTANT}
        Whether the tool turns with arcs; default CONSTANT (the paper's rule).
    welds : list of welding.WeldSpec
        The welds along this path, on segments that do not overlap (issue 22).
        A weld's moves run at its schedule's travel speed (a corner area's
        slow-down where slower); the arc ignites at the target where its first
        segment begins (the entry target for segment 1), which stops exactly,
        and goes out where its last segment ends. A turn in place inside a
        weld (a "Stop and reorient" corner, or a junction where the
        orientation changes outside a risk area) puts the arc out before it
        and strikes it again after it: one :class:`.program.WeldRun` per
        stretch.
    """

    name: str
    label: str
    segments: list
    R_u_t: list
    frame: str
    speed_mm_s: float = 10.0
    zone_mm: Optional[float] = None
    zone_tolerance_mm: float = 0.1
    approach_mm: float = 50.0
    retract_mm: float = 50.0
    approach_speed_mm_s: float = 100.0
    sample_time_s: float = 0.2
    step_mm: Optional[float] = None
    risk_areas: List[RiskAreaSpec] = field(default_factory=list)
    closed: bool = False
    marker_s_mm: Optional[list] = None
    tool_on_arcs: str = CONSTANT
    welds: List[WeldSpec] = field(default_factory=list)


@dataclass
class CellSpec:
    """Everything :func:`generate` needs, read from one cell of the document.

    Attributes
    ----------
    name, label : str
        Internal name and user-visible label of the cell.
    robot : str
        Catalog name of the robot, e.g. ``"ABB_IRB2400"``.
    T_u_r : ndarray, shape (4, 4)
        Robot base frame {R} in {U}, mm.
    tool : ToolData
    frames : dict of str to FrameSpec
        Calibration frames by key (the key :attr:`PathSpec.frame` names).
    paths : list of PathSpec
        In execution order.
    source : str
        Document and cell, for program headers.
    """

    name: str
    label: str
    robot: str
    T_u_r: np.ndarray
    tool: ToolData
    frames: Dict[str, FrameSpec]
    paths: List[PathSpec]
    source: str = ""


def sanitize_identifier(text, fallback="x", max_len=MAX_NAME_LEN):
    """A robot-language identifier made from ``text``.

    Characters outside ``[A-Za-z0-9_]`` become ``_`` (runs collapsed, none
    at the ends); a name not starting with a letter gets ``fallback + "_"``
    in front; the result is cut to ``max_len`` characters.

    Parameters
    ----------
    text : str
    fallback : str
        Used alone when nothing is left, or as a prefix; must start with a
        letter.
    max_len : int

    Returns
    -------
    str
        E.g. ``"Weld seam #2"`` -> ``"Weld_seam_2"``, ``"2nd"`` -> ``"x_2nd"``.
    """
    name = re.sub(r"[^A-Za-z0-9_]+", "_", str(text))
    name = re.sub(r"_+", "_", name).strip("_")
    if not name:
        name = fallback
    elif not name[0].isalpha():
        name = fallback + "_" + name
    return name[:max_len].rstrip("_") or fallback


def _unique(name, used, max_len=MAX_NAME_LEN):
    """``name``, or ``name`` with ``_2``, ``_3``, ... if taken; added to ``used``."""
    candidate, n = name, 1
    while candidate.lower() in used:     # RAPID and KRL are case-insensitive
        n += 1
        suffix = "_%d" % n
        candidate = name[:max_len - len(suffix)] + suffix
    used.add(candidate.lower())
    return candidate


def _positive(value, what, path_label, allow_zero=False):
    value = float(value)
    ok = value >= 0.0 if allow_zero else value > 0.0
    if not (np.isfinite(value) and ok):
        raise InputError("Path '%s': %s must be %s, got %g. Fix it in the path's properties."
                         % (path_label, what, ">= 0" if allow_zero else "> 0", value))
    return value


def generate(cell, progress=None):
    """Generate the robot program of a cell.

    Parameters
    ----------
    cell : CellSpec
    progress : callable, optional
        ``progress(fraction, text)`` (:mod:`.progress`), told every few
        segments; returning False raises :class:`.progress.Cancelled`.

    Returns
    -------
    Program
        Targets in the paths' calibration frames {B}, mm.

    Raises
    ------
    FrameError
        A path names a frame the cell does not have.
    GeometryError
        A path without segments.
    MarkerError
        Not one tool orientation per segment, or one that is not a rotation.
    RiskAreaError
        A risk area outside the path's segments, overlapping another one, or
        with a step <= 0.
    InputError
        A speed, zone, distance or sample time out of range; a weld outside
        its path's segments, with first > last, on a path without segments,
        without a schedule, or overlapping another weld; a weld run breaking
        the rules of :func:`.weld_runs.check_runs`.
    """
    used = set()
    program_name = _unique(sanitize_identifier(cell.name, "Cell"), used)
    used.add(sanitize_identifier(cell.tool.name, "tool").lower())

    T_r_u = tf.invert_transform(np.asarray(cell.T_u_r, dtype=float))
    work_frames = {}
    frame_names = {}          # CellSpec.frames key -> WorkFrame name
    for key, spec in cell.frames.items():
        name = _unique(sanitize_identifier(spec.name or key, "wobj"), used)
        T_u_b = np.asarray(spec.T_u_b, dtype=float)
        T_r_b = T_r_u @ T_u_b if spec.T_r_b is None else np.asarray(spec.T_r_b, dtype=float)
        if not tf.is_rigid_transform(T_r_b):
            raise FrameError("Calibration frame '%s': its taught pose is not a rigid transform. "
                             "Teach it again." % spec.label, spec.name)
        work_frames[name] = WorkFrame(name=name, T_r_b=T_r_b, T_u_b=T_u_b, source=spec.label)
        frame_names[key] = name

    path_names = [_unique(sanitize_identifier(p.name, "path"), used) for p in cell.paths]
    paths, writers, welds = [], [], []
    n_segments = max(sum(len(spec.segments) for spec in cell.paths), 1)
    done = 0
    for spec, name in zip(cell.paths, path_names):
        if spec.frame not in frame_names:
            raise FrameError(
                "Path '%s' uses calibration frame '%s', which is not in cell '%s' "
                "(frames: %s). Link the path to one of the cell's calibration frames."
                % (spec.label, spec.frame, cell.label,
                   ", ".join(sorted(frame_names)) or "none"))
        frame = work_frames[frame_names[spec.frame]]
        welds.append(_placed_welds(spec))
        writer = _PathWriter(spec, name, frame, used)
        part = stage(progress, done / n_segments, (done + len(spec.segments)) / n_segments)
        moves = zones.limit_zones(writer.write(part), writer.zone_tolerance)
        paths.append(ProgramPath(name=name, label=spec.label, moves=moves))
        writers.append(writer)
        done += len(spec.segments)
    # Weld names are taken after every target's, so a path without welds keeps its names.
    for path, writer, placed in zip(paths, writers, welds):
        path.welds = _weld_runs(writer, path.moves, placed, used)

    program = Program(name=program_name, robot=cell.robot, tool=cell.tool,
                      frames=work_frames, paths=paths, source=cell.source)
    check_runs(program)
    return program


# -- welds (issue 22) ----------------------------------------------------------

def _placed_welds(spec):
    """The welds of path `spec` (PathSpec), checked, in path order.

    Returns
    -------
    list of (WeldSpec, int, int)
        Each weld with its schedule, weave and tracking validated, and its
        first and last segment (1-based, inclusive; None read as the path's
        first / last).

    Raises
    ------
    InputError
        A weld on a path without segments, with segments outside the path or
        first > last, without a schedule, or two welds sharing a segment.
    """
    n = len(spec.segments)
    placed = []
    for weld in spec.welds:
        if n == 0:
            raise InputError("Weld '%s' is on path '%s', which has no segments: give the path a "
                             "sketch, wire or edges to follow, or delete the weld."
                             % (weld.label, spec.label), weld.name)
        first = 1 if weld.first_segment is None else weld.first_segment
        last = n if weld.last_segment is None else weld.last_segment
        if not (_is_whole(first) and _is_whole(last) and 1 <= first <= n and 1 <= last <= n):
            raise InputError("Weld '%s' covers segments %s-%s, but path '%s' has segments 1-%d: "
                             "set its first and last segment within 1-%d."
                             % (weld.label, first, last, spec.label, n, n), weld.name)
        if first > last:
            raise InputError("Weld '%s' on path '%s': its first segment %d comes after its last "
                             "segment %d: set first <= last." % (weld.label, spec.label, first, last),
                             weld.name)
        placed.append((_validated_weld(weld, spec.label), int(first), int(last)))
    placed.sort(key=lambda item: item[1])
    for (a, a0, a1), (b, b0, b1) in zip(placed, placed[1:]):
        if b0 <= a1:
            raise InputError("Welds '%s' (segments %d-%d) and '%s' (segments %d-%d) overlap on path "
                             "'%s': make their segments disjoint or merge them into one weld."
                             % (a.label, a0, a1, b.label, b0, b1, spec.label), b.name)
    return placed


def _is_whole(number):
    return (not isinstance(number, bool) and isinstance(number, (int, float, np.integer, np.floating))
            and float(number).is_integer())


def _validated_weld(weld, path_label):
    """`weld` (WeldSpec) with its schedule, weave and tracking validated."""
    what = "Weld '%s' on path '%s'" % (weld.label, path_label)
    if not isinstance(weld.schedule, WeldSchedule):
        raise InputError("%s has no schedule: give it a library schedule or the schedule's "
                         "values." % what, weld.name)
    return WeldSpec(weld.name, weld.label, weld.schedule.validated(what + ", schedule"),
                    None if weld.weave is None else weld.weave.validated(what + ", weave"),
                    (weld.tracking or Tracking()).validated(what + ", tracking"), weld.first_segment,
                    weld.last_segment, _position(weld.position, what, weld.name))


def _position(position, what, weld_name):
    """`position` if it is one of ``welding.POSITIONS``, else InputError naming the weld."""
    if position not in POSITIONS:
        raise InputError("%s: position '%s' is not one of %s: give one of them."
                         % (what, position, ", ".join(POSITIONS)), weld_name)
    return position


def _weld_runs(writer, moves, placed, used):
    """Mark the welded moves of one path and return its weld runs, in path order.

    A weld's runs are the stretches of consecutive path and risk-area moves on
    its segments; a reorientation in place (a corner stop) ends one and starts
    the next at its own target. Each run starts at the move before its first
    welded move (the entry, a reorientation, or the last move before the
    weld's first segment) and ends at its last welded move.

    Parameters
    ----------
    writer : _PathWriter
        The path's writer (its corner speeds and closing-corner overlap).
    moves : list of Move
        The path's moves, zones already limited; changed in place.
    placed : list of (WeldSpec, int, int)
        From :func:`_placed_welds`.
    used : set of str
        Identifiers taken (lower case); the run names are added.
    """
    runs = []
    if not placed:
        return runs
    for weld, first, last in placed:
        on = [_welds_along(writer, k, move, first, last) for k, move in enumerate(moves)]
        stretches = _stretches(on)
        if not stretches:
            raise InputError("Weld '%s' on path '%s': segments %d-%d give no move to weld along: "
                             "choose other segments." % (weld.label, writer.spec.label, first, last),
                             weld.name)
        name = _unique(sanitize_identifier(weld.name, "Weld"), used)
        for part, (k0, k1) in enumerate(stretches, start=1):
            run_name = name if part == 1 else _unique(
                sanitize_identifier("%s_%d" % (name, part), "Weld"), used)
            run = WeldRun(run_name, weld.label, weld.schedule, weld.weave, weld.tracking,
                          start=k0 - 1, end=k1, first_segment=_segment_of(writer, k0, moves),
                          last_segment=_segment_of(writer, k1, moves), part=part,
                          position=weld.position)
            _weld_moves(writer, moves, run)
            runs.append(run)
    runs.sort(key=lambda run: run.start)
    _comment_arc_on_off(moves, runs)
    return runs


def _welds_along(writer, k, move, first, last):
    """Whether move `k` of the path welds for a weld on segments `first`..`last`."""
    if move.role not in (ROLE_PATH, ROLE_RISK):
        return False
    if k in writer.loop_overlap:        # over the first segment again, where a loop closes
        return first == 1 and last == len(writer.segments)
    return first <= move.segment <= last


def _segment_of(writer, k, moves):
    """The segment move `k` welds along (a closing corner's overlap counts as the last)."""
    return len(writer.segments) if k in writer.loop_overlap else moves[k].segment


def _stretches(flags):
    """[(first, last)] index ranges of the consecutive True items of `flags`."""
    out = []
    for k, flag in enumerate(flags):
        if flag and (k == 0 or not flags[k - 1]):
            out.append([k, k])
        elif flag:
            out[-1][1] = k
    return [tuple(pair) for pair in out]


def _weld_moves(writer, moves, run):
    """Give the moves of `run` its name and travel speed (a corner area's slow-down where
    slower, said in the comment), and exact stops at its start and end."""
    travel = run.schedule.travel_speed_mm_s
    for k in range(run.start + 1, run.end + 1):
        move = moves[k]
        move.weld = run.name
        limit = writer.corner_speeds.get(k)
        if limit is not None and limit < travel:
            move.speed_mm_s = limit
            move.comment += " (%s to %.1f mm/s: the tool turns at most %g deg/s)" % (
                CORNER_SLOWDOWN, limit, CORNER_TURN_DEG_S)
        else:
            move.speed_mm_s = travel
    moves[run.start].zone_mm = 0.0
    moves[run.end].zone_mm = 0.0


def _comment_arc_on_off(moves, runs):
    """Say in the comments where each run's arc goes on and off."""
    starts = {run.start: run for run in runs}
    ends = {run.end: run for run in runs}
    for k, move in enumerate(moves):
        run_on, run_off = starts.get(k), ends.get(k - 1)
        if CORNER_STOP_ARC in move.comment and (run_on or run_off):
            said = ["arc off at the previous target: %s" % run_off.name] if run_off else []
            said += ["arc on here after the turn: %s" % run_on.name] if run_on else []
            move.comment = move.comment.replace(CORNER_STOP_ARC, "(%s)" % "; ".join(said))
        elif run_on and move.role == ROLE_REORIENT:
            move.comment += " (arc on here after the turn: %s)" % run_on.name
        elif run_on and move.role in (ROLE_PATH, ROLE_RISK):
            move.comment += " (arc on: %s, reached along the path)" % run_on.name
        elif run_on:
            move.comment += " (arc on: %s)" % run_on.name
        if k in ends:
            move.comment += " (arc off: %s)" % ends[k].name


class _PathWriter:
    """Builds the moves of one path (see :func:`generate`)."""

    def __init__(self, spec, name, frame, used):
        self.spec = spec
        self.frame = frame
        self.T_b_u = tf.invert_transform(frame.T_u_b)
        self.used = used
        self.prefix = sanitize_identifier(name, "path", MAX_NAME_LEN - 9)
        self.counter = 0
        self.moves = []
        # Index of a corner area's move -> the fastest the tool may go there (CORNER_TURN_DEG_S),
        # mm/s; the moves of a closed loop's closing corner that weld over its first segment again.
        self.corner_speeds = {}
        self.loop_overlap = set()
        label = spec.label
        self.speed = _positive(spec.speed_mm_s, "Speed", label)
        self.zone = (zones.AUTOMATIC if spec.zone_mm is None
                     else _positive(spec.zone_mm, "Zone", label, allow_zero=True))
        self.zone_tolerance = _positive(spec.zone_tolerance_mm, "Zone tolerance", label)
        self.approach_mm = _positive(spec.approach_mm, "Approach distance", label, True)
        self.retract_mm = _positive(spec.retract_mm, "Retract distance", label, True)
        self.approach_speed = _positive(spec.approach_speed_mm_s, "Approach speed", label)
        self.segments = list(spec.segments)
        if not self.segments:
            raise GeometryError("Path '%s' has no segments. Give it a sketch, wire or edges "
                                "to follow." % label)
        self.rotations = self._check_orientations()
        self.laws = segment_orientations(self.segments, self.rotations, spec.marker_s_mm,
                                         spec.tool_on_arcs, spec.closed)
        self.areas, self.closing = self._check_risk_areas()

    # -- validation ----------------------------------------------------------
    def _seg_name(self, i):
        seg = self.segments[i]
        return "segment %d (%s)" % (i + 1, seg.source) if seg.source else "segment %d" % (i + 1)

    def _check_orientations(self):
        """The tool orientations, one per segment, each checked to be a rotation.

        Segments that inherit their orientation from a tool marker before them
        share one array: it is checked once (a 20,000-segment path with one
        marker costs one check)."""
        spec = self.spec
        if len(spec.R_u_t) != len(self.segments):
            raise MarkerError(
                "Path '%s' has %d segments but %d tool orientations: give every segment one "
                "(a tool marker sets its segment's and the following ones' up to the next marker)."
                % (spec.label, len(self.segments), len(spec.R_u_t)))
        out, checked = [], {}
        for i, given in enumerate(spec.R_u_t):
            R = checked.get(id(given))
            if R is None:
                R = np.asarray(given, dtype=float)
                if R.shape != (3, 3) or not tf.is_rigid_transform(tf.make_transform(R=R)):
                    raise MarkerError(
                        "Path '%s': the tool orientation of %s is not a rotation matrix. "
                        "Check its tool marker's placement." % (spec.label, self._seg_name(i)))
                checked[id(given)] = R
            out.append(R)
        return out

    def _is_closing(self, first, last):
        """True for the area from the last segment of a closed path to its first."""
        n = len(self.segments)
        return bool(self.spec.closed) and n > 1 and first == n and last == 1

    def _check_risk_areas(self):
        """Validate the risk areas.

        Returns
        -------
        areas : list of _Area
            In path order, not overlapping (touching is allowed).
        closing : _Area or None
            The area round a closed path's end point.
        """
        spec, n = self.spec, len(self.segments)
        areas, closing = [], None
        for area in spec.risk_areas:
            first, last = area.first, area.last
            whole = int(first) == first and int(last) == last
            if not (whole and (1 <= int(first) <= int(last) <= n
                               or self._is_closing(int(first), int(last)))):
                raise RiskAreaError(
                    "Risk area '%s' covers segments %s-%s, but path '%s' has segments 1-%d. "
                    "Set its first and last segment within 1-%d, first <= last%s."
                    % (area.label, first, last, spec.label, n, n,
                       " (or %d-1: the corner where the loop closes)" % n if spec.closed else ""))
            if area.at_corner not in AT_CORNER:
                raise RiskAreaError("Risk area '%s' on path '%s': AtCorner is %r; use one of %s."
                                    % (area.label, spec.label, area.at_corner,
                                       ", ".join('"%s"' % c for c in AT_CORNER)))
            span = 0.0 if area.corner_span_mm is None else float(area.corner_span_mm)
            if not (np.isfinite(span) and span >= 0.0):
                raise RiskAreaError("Risk area '%s' on path '%s' has corner span %g mm; it must be "
                                    ">= 0 (0: whole segments)." % (area.label, spec.label, span))
            if area.at_corner == STOP_AND_REORIENT:
                span = 0.0          # nothing is re-sampled: the segments are written whole
            first, last = int(first) - 1, int(last) - 1
            if self._is_closing(first + 1, last + 1):
                L_last, L_first = self.segments[first].length, self.segments[last].length
                closing = _Area(area, (first, L_last - min(span, L_last)), (last, min(span, L_first)))
                continue
            start = (first, self.segments[first].length - min(span, self.segments[first].length)
                     if span > 0.0 else 0.0)
            end = (last, min(span, self.segments[last].length) if span > 0.0 else self.segments[last].length)
            areas.append(_Area(area, start, end))
        areas.sort(key=lambda a: a.start)
        for a, b in zip(areas, areas[1:]):
            if b.start < a.end:
                raise RiskAreaError(
                    "Risk areas '%s' (segments %d-%d) and '%s' (segments %d-%d) overlap on "
                    "path '%s'. Make them disjoint (or their corner spans shorter) or merge them "
                    "into one." % (a.spec.label, a.spec.first, a.spec.last, b.spec.label,
                                   b.spec.first, b.spec.last, spec.label))
        if closing is not None and areas and (closing.start < areas[-1].end
                                              or (closing.end[1] > 0.0 and areas[0].start < closing.end)):
            other = areas[-1] if closing.start < areas[-1].end else areas[0]
            raise RiskAreaError(
                "Risk areas '%s' (segments %d-%d) and '%s' (segments %d-1, where the loop closes) "
                "overlap on path '%s'. Make their corner spans shorter or remove one."
                % (other.spec.label, other.spec.first, other.spec.last, closing.spec.label, n, spec.label))
        return areas, closing

    # -- building moves ------------------------------------------------------
    def _target(self, p_u, R_u_t):
        while True:
            self.counter += 10
            name = "%s_%d" % (self.prefix, self.counter)
            if name.lower() not in self.used:
                break
        self.used.add(name.lower())
        T_u_t = tf.make_transform(R=R_u_t, p=p_u)
        return Target(name=name, T_b_t=self.T_b_u @ T_u_t)

    def _add(self, kind, p_u, R_u_t, role, segment, comment, speed=None, zone=None, via=None, R_via=None):
        via_target = self._target(via, R_u_t if R_via is None else R_via) if via is not None else None
        move = Move(kind=kind, target=self._target(p_u, R_u_t),
                    speed_mm_s=self.speed if speed is None else speed,
                    zone_mm=self.zone if zone is None else zone,
                    frame=self.frame.name, via=via_target, role=role,
                    segment=segment, comment=comment)
        self.moves.append(move)
        return move

    def _reorient_if_needed(self, R_now, R_next, p_u, segment, why, corner_stop=False):
        if R_now is R_next:     # one marker's orientation, inherited: nothing turns
            return
        angle = rotations.rotation_angle_between(R_now, R_next)
        if angle <= ORIENTATION_TOL_RAD:
            return
        # Stop exactly at the junction so the tool turns there, not before.
        if self.moves and self.moves[-1].role in (ROLE_PATH, ROLE_RISK):
            self.moves[-1].zone_mm = 0.0
        stop = "%s %s: " % (CORNER_STOP, CORNER_STOP_ARC) if corner_stop else ""
        self._add(LINEAR, p_u, R_next, ROLE_REORIENT, segment,
                  "%ssegment %d: reorient tool %.1f deg %s" % (stop, segment, np.degrees(angle), why),
                  zone=0.0)

    def write(self, progress=None):
        """Return the list of moves of the path (`progress` told every few segments)."""
        spec, segs = self.spec, self.segments
        p0, R0 = segs[0].start, self.laws[0].start
        if self.approach_mm > 0.0:
            self._add(JOINT, p0 - self.approach_mm * R0[:, 2], R0, ROLE_APPROACH, None,
                      "approach path '%s': %g mm above its start" % (spec.label, self.approach_mm),
                      speed=self.approach_speed, zone=0.0)
            self._add(LINEAR, p0, R0, ROLE_ENTRY, None,
                      "entry to path '%s'" % spec.label, speed=self.approach_speed, zone=0.0)
        else:
            self._add(JOINT, p0, R0, ROLE_APPROACH, None,
                      "approach path '%s' at its start" % spec.label,
                      speed=self.approach_speed, zone=0.0)
        n_body_start = len(self.moves)

        self.R_now = R0
        steps = Steps(progress, len(segs), "writing moves of path '%s'" % spec.label)
        position = (0, 0.0)
        for area in self.areas:
            self._write_stretch(position, area.start, steps)
            (i, s), R_start = area.start, self.laws[area.start[0]].at(area.start[1])
            self._reorient_if_needed(self.R_now, R_start, segs[i].point_at(s) if s > 0.0 else segs[i].start,
                                     i + 1, "entering risk area '%s'" % area.spec.label)
            self.R_now = R_start
            if area.spec.at_corner == STOP_AND_REORIENT:
                self._write_stretch(area.start, area.end, steps, corner_stop=area.spec.label)
            else:
                self._write_risk_area(area)
            position = area.end
        end = self.closing.start if self.closing is not None else (len(segs) - 1, segs[-1].length)
        self._write_stretch(position, end, steps)
        p_end = segs[-1].end
        if self.closing is not None:
            p_end = self._write_closing_corner(self.closing)

        if len(self.moves) > n_body_start:
            self.moves[-1].zone_mm = 0.0      # stop exactly at the end of the path
        if self.retract_mm > 0.0:
            R_now = self.R_now
            self._add(LINEAR, p_end - self.retract_mm * R_now[:, 2], R_now, ROLE_RETRACT, None,
                      "retract from path '%s': %g mm" % (spec.label, self.retract_mm),
                      speed=self.approach_speed, zone=0.0)
        return self.moves

    def _write_stretch(self, start, end, steps, corner_stop=None):
        """Moves along the path from `start` to `end`, each (segment index, arc length mm),
        outside risk areas: a reorientation at each junction where the orientation
        changes (a corner stop inside a "Stop and reorient" area named `corner_stop`)."""
        segs = self.segments
        for i in range(start[0], end[0] + 1):
            lo = start[1] if i == start[0] else 0.0
            hi = end[1] if i == end[0] else segs[i].length
            if hi <= lo:
                continue
            steps(i)
            if lo == 0.0:
                why = ("inside risk area '%s'" % corner_stop) if corner_stop else "at junction"
                self._reorient_if_needed(self.R_now, self.laws[i].start, segs[i].start, i + 1, why,
                                         corner_stop=bool(corner_stop))
            self._write_portion(i, lo, hi)
            self.R_now = self.laws[i].at(hi)

    def _write_portion(self, i, lo, hi):
        """The moves of segment `i` (0-based) from arc length `lo` to `hi` (mm), with a
        target at each of its law's breaks between them (where a lead into a concave arc
        ends, :mod:`.segment_orientation`): each piece's orientation then turns about one
        axis in proportion to its length, as a linear or circular move interpolates it."""
        cuts = [lo] + [s for s in self.laws[i].breaks if lo < s < hi] + [hi]
        for a, b in zip(cuts[:-1], cuts[1:]):
            self._write_piece(i, a, b)

    def _write_piece(self, i, lo, hi):
        """The moves of segment `i` (0-based) from arc length `lo` to `hi` (mm).

        On a turning arc (:mod:`.segment_orientation`) each circular move's
        start, via and end carry the orientation of the arc's law there, each
        move sweeping at most 90 degrees: the orientation then turns about
        the arc's axis in proportion to the swept angle, and every controller's
        circular interpolation reproduces exactly that turn between them:
        ABB MoveC and KUKA CIRC interpolate the orientation from start to end
        (the via's orientation only picks the way round, here the short one,
        which is the arc's); Fanuc C and Motoman MOVC pass through the via's
        orientation, which lies on the same turn; UR movec (mode 0,
        unconstrained) interpolates from start to end. At most 90 degrees per
        move keeps the short way unique (at 180 it would not be)."""
        seg, law, number = self.segments[i], self.laws[i], i + 1
        whole = lo == 0.0 and hi == seg.length
        comment = "segment %d: %s %s" % (number, seg.kind, seg.source)
        if not whole:
            comment += " (%.1f to %.1f mm)" % (lo, hi)
        end_point = seg.end if hi == seg.length else seg.point_at(hi)
        if seg.kind == "line":
            self._add(LINEAR, end_point, law.at(hi), ROLE_PATH, number, comment)
        elif seg.kind == "arc":
            most = np.pi / 2.0 if law.turns else np.pi
            pieces = max(1, int(np.ceil((hi - lo) / seg.radius / most - 1e-9)))
            piece_len = (hi - lo) / pieces
            for m in range(pieces):
                part = " (part %d of %d)" % (m + 1, pieces) if pieces > 1 else ""
                s_end, s_via = lo + (m + 1) * piece_len, lo + (m + 0.5) * piece_len
                end = end_point if m == pieces - 1 else seg.point_at(s_end)
                self._add(CIRCULAR, end, law.at(hi if m == pieces - 1 else s_end), ROLE_PATH,
                          number, comment + part, via=seg.point_at(s_via), R_via=law.at(s_via))
        elif hasattr(seg, "points"):
            if whole:
                points, s_points = seg.points[1:], seg._cum[1:]
            else:
                s_inside = seg._cum[(seg._cum > lo) & (seg._cum < hi)]
                points, s_points = list(seg.points_at(s_inside)) + [end_point], list(s_inside) + [hi]
            for p, s in zip(points, s_points):
                self._add(LINEAR, p, law.at(s), ROLE_PATH, number, comment)
        else:
            raise GeometryError("Path '%s': %s is a %r, which CadRobot cannot follow."
                                % (self.spec.label, self._seg_name(i), seg.kind))

    def _area_speed(self, area):
        """The TCP speed |v| of eqs 8-13 in `area`, mm/s: the travel speed of the weld
        welding its first segment, else the path's speed."""
        n = len(self.segments)
        for weld in self.spec.welds:
            first = 1 if weld.first_segment is None else weld.first_segment
            last = n if weld.last_segment is None else weld.last_segment
            if first <= area.first <= last and isinstance(weld.schedule, WeldSchedule):
                return float(weld.schedule.travel_speed_mm_s)
        return self.speed

    def _area_step(self, area):
        """The step of `area` (RiskAreaSpec), mm: its own, else the path's, else |v|·Δt
        (eqs 8-13) with the speed of :meth:`_area_speed`."""
        spec = self.spec
        if area.step_mm is not None:
            step = area.step_mm
        elif spec.step_mm is not None:
            step = spec.step_mm
        else:
            step = self._area_speed(area) * _positive(spec.sample_time_s, "Sample time", spec.label)
        step = float(step)
        if not (np.isfinite(step) and step > 0.0):
            raise RiskAreaError("Risk area '%s' on path '%s' has step %g mm; it must be > 0. "
                                "Fix the step of the risk area or of the path."
                                % (area.label, spec.label, step))
        return step

    def _area_portions(self, area):
        """[(segment index, lo mm, hi mm)] the area covers, in path order."""
        (i0, lo0), (i1, hi1) = area.start, area.end
        return [(j, lo0 if j == i0 else 0.0, hi1 if j == i1 else self.segments[j].length)
                for j in range(i0, i1 + 1)]

    def _keyframes(self, portions):
        """(positions (K,) mm from the start of `portions`, quaternions (K, 4)) the
        orientation passes through: the start, every marker governing a segment
        strictly between the first and the last portion, the end."""
        offsets = np.concatenate([[0.0], np.cumsum([hi - lo for _, lo, hi in portions])])
        (i0, lo0, _), (i1, _, hi1) = portions[0], portions[-1]
        positions = [0.0]
        Rs = [self.laws[i0].at(lo0)]
        marker_s = self.spec.marker_s_mm
        for k, (j, _lo, _hi) in enumerate(portions[1:-1], start=1):
            if marker_s is not None and marker_s[j] is not None:
                positions.append(offsets[k] + float(marker_s[j]))
                Rs.append(self.rotations[j])
        positions.append(offsets[-1])
        Rs.append(self.laws[i1].at(hi1))
        return np.array(positions), np.array([rotations.quaternion_from_matrix(R) for R in Rs])

    def _write_risk_area(self, area_span):
        """Linear moves through the re-sampled risk area (eqs 8-15).

        Positions are re-sampled per segment at the area's step (eqs 8-13,
        segment ends kept). Orientations are slerped (eqs 14-15) by arc-length
        fraction within each stretch between consecutive keyframes
        (:meth:`_keyframes`), the short way per stretch: the tool passes
        through every marker in the area in path order and never turns the
        short way past one. With no marker between the area's first and last
        segment this is exactly the paper's slerp from first to last.
        """
        area = area_span.spec
        comment = "risk area '%s' segments %d-%d: segment %%d %%s %%s" % (
            area.label, int(area.first), int(area.last))
        self._write_resampled(area, self._area_portions(area_span), comment)

    def _write_resampled(self, area, portions, comment):
        """Linear moves at `area`'s step along `portions` [(segment index, lo mm, hi mm)],
        orientations slerped through :meth:`_keyframes`; `comment` % (segment number,
        kind, source) per move. A corner area (a corner span > 0) is driven no faster
        than the tool turns CORNER_TURN_DEG_S."""
        step = self._area_step(area)
        lengths = [hi - lo for _, lo, hi in portions]
        n_points = sum(np.ceil(L / step) for L in lengths)    # a float: a 1e-320 step is infinity
        if not n_points <= MAX_RISK_POINTS:
            raise RiskAreaError(
                "Risk area '%s' on path '%s' would need %.3g points at step %g mm (at most %d). "
                "Use a larger step." % (area.label, self.spec.label, n_points, step, MAX_RISK_POINTS))
        offsets = np.concatenate([[0.0], np.cumsum(lengths)])
        positions, quats_key = self._keyframes(portions)
        speed = None
        if area.corner_span_mm:
            turn_deg = np.degrees(sum(rotations.rotation_angle_between(
                *rotations.matrix_from_quaternion(quats_key[k:k + 2])) for k in range(len(quats_key) - 1)))
            if turn_deg > 0.0:
                slowest = np.floor(offsets[-1] * CORNER_TURN_DEG_S / turn_deg * 10.0 + 1e-6) / 10.0
                speed = min(self.speed, max(0.1, slowest))      # 0.1 mm/s steps
                first_move = len(self.moves)
        for k, (j, lo, hi) in enumerate(portions):
            seg = self.segments[j]
            if hi <= lo:
                continue
            s = lo + interpolation.stations(hi - lo, step)[1:]
            points = seg.points_at(s)
            quats = _slerp_through(positions, quats_key, offsets[k] + (s - lo))
            mats = rotations.matrix_from_quaternion(np.reshape(quats, (-1, 4)))
            text = comment % (j + 1, seg.kind, seg.source)
            for p, R in zip(points, np.reshape(mats, (-1, 3, 3))):
                self._add(LINEAR, p, R, ROLE_RISK, j + 1, text, speed=speed)
        if speed is not None:
            for k in range(first_move, len(self.moves)):
                self.corner_speeds[k] = max(0.1, slowest)
        j, _lo, hi = portions[-1]
        self.R_now = self.laws[j].at(hi)

    def _write_closing_corner(self, closing):
        """Turn the tool round a closed path's start and end point (`closing`, an _Area)
        from the last segment's orientation to the first's; returns the point (3,) {U}
        where the path now ends.

        With a corner span ("Weld through"), the tool turns over the last span of the
        last segment and welds on over the first span of the first segment: the end
        overlaps the start by the span, so the crater lands on the first leg, not on
        the corner, and the loop ends as it started. With span 0 it pivots on the end
        point in steps of at most MAX_TURN_PER_MOVE_DEG; "Stop and reorient" is one
        corner stop there.
        """
        area, segs, n = closing.spec, self.segments, len(self.segments)
        R_first = self.laws[0].start
        if area.at_corner == STOP_AND_REORIENT:
            self._reorient_if_needed(self.R_now, R_first, segs[-1].end, n,
                                     "where the loop closes (risk area '%s')" % area.label,
                                     corner_stop=True)
            self.R_now = R_first
            return segs[-1].end
        (i_last, lo), (i_first, hi) = closing.start, closing.end
        if hi > 0.0:
            comment = "risk area '%s' segments %d-1, where the loop closes: segment %%d %%s %%s" % (
                area.label, n)
            first_move = len(self.moves)
            self._write_resampled(area, [(i_last, lo, segs[i_last].length), (i_first, 0.0, hi)], comment)
            self.loop_overlap.update(k for k in range(first_move, len(self.moves))
                                     if self.moves[k].segment == 1)
            return segs[i_first].point_at(hi)
        angle = rotations.rotation_angle_between(self.R_now, R_first)
        if angle <= ORIENTATION_TOL_RAD:
            return segs[-1].end
        count = int(np.ceil(np.degrees(angle) / MAX_TURN_PER_MOVE_DEG - 1e-9))
        quats = interpolation.interpolate_orientations(
            rotations.quaternion_from_matrix(self.R_now), rotations.quaternion_from_matrix(R_first),
            np.arange(1, count + 1) / count)
        comment = "risk area '%s' segments %d-1: the tool turns %.1f deg round the end point" % (
            area.label, n, np.degrees(angle))
        for R in rotations.matrix_from_quaternion(quats):
            self._add(LINEAR, segs[-1].end, R, ROLE_RISK, n, comment)
        self.R_now = R_first
        return segs[-1].end


@dataclass
class _Area:
    """A risk area placed on its path: from `start` to `end`, each (segment index
    0-based, arc length on it mm)."""

    spec: RiskAreaSpec
    start: tuple
    end: tuple


def _slerp_through(positions, quats, s):
    """Orientations at `s` (N,) mm, slerped within each stretch between keyframes.

    Parameters
    ----------
    positions : ndarray, shape (K,)
        Increasing keyframe positions, mm, K >= 2.
    quats : ndarray, shape (K, 4)
    s : ndarray, shape (N,)

    Returns
    -------
    ndarray, shape (N, 4)
        Per stretch k (positions[k]..positions[k+1]) eq 15 at the fraction
        (s - positions[k]) / (positions[k+1] - positions[k]), clipped to [0, 1].
    """
    s = np.atleast_1d(np.asarray(s, dtype=float))
    stretch = np.clip(np.searchsorted(positions, s, side="left") - 1, 0, len(positions) - 2)
    out = np.empty((len(s), 4))
    for k in np.unique(stretch):
        here = stretch == k
        width = positions[k + 1] - positions[k]
        fractions = np.clip((s[here] - positions[k]) / width, 0.0, 1.0) if width > 0 else np.ones(here.sum())
        out[here] = interpolation.interpolate_orientations(quats[k], quats[k + 1], fractions)
    return out
