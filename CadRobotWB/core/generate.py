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
* a risk area is re-sampled at ``step_mm`` (eqs 8-13) and its orientations
  are slerped from its first to its last segment's orientation by
  arc-length fraction (eqs 14-15).

Pure numpy; never imports FreeCAD.
"""

import re
from dataclasses import dataclass, field
from typing import Dict, List, Optional

import numpy as np

from ..errors import FrameError, GeometryError, InputError, MarkerError, RiskAreaError
from . import frames as tf
from . import interpolation, rotations, zones
from .progress import Steps, stage
from .program import (CIRCULAR, JOINT, LINEAR, ROLE_APPROACH, ROLE_ENTRY, ROLE_PATH,
                      ROLE_REORIENT, ROLE_RETRACT, ROLE_RISK, Move, Program,
                      ProgramPath, Target, ToolData, WorkFrame)

# Two tool orientations closer than this (radians) count as the same.
ORIENTATION_TOL_RAD = 1e-6
# Longest identifier we make (RAPID allows 32 characters).
MAX_NAME_LEN = 24
# Upper bound on the interpolated points of one risk area (guards against a
# step typed in metres instead of millimetres).
MAX_RISK_POINTS = 100000


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
        1-based, inclusive segment numbers, ``1 <= first <= last <= n``.
    step_mm : float or None
        Spacing of the interpolated points, mm; None uses the path's step.
    """

    name: str
    label: str
    first: int
    last: int
    step_mm: Optional[float] = None


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
        The path ends where it starts (information only).
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
        A speed, zone, distance or sample time out of range.
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
    paths = []
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
        writer = _PathWriter(spec, name, frame, used)
        part = stage(progress, done / n_segments, (done + len(spec.segments)) / n_segments)
        moves = zones.limit_zones(writer.write(part), writer.zone_tolerance)
        paths.append(ProgramPath(name=name, label=spec.label, moves=moves))
        done += len(spec.segments)

    return Program(name=program_name, robot=cell.robot, tool=cell.tool,
                   frames=work_frames, paths=paths, source=cell.source)


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
        self.risk_of = self._check_risk_areas()

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

    def _check_risk_areas(self):
        """Validate the risk areas; return {0-based first segment index: area}."""
        spec, n = self.spec, len(self.segments)
        areas = []
        for area in spec.risk_areas:
            first, last = area.first, area.last
            if (int(first) != first or int(last) != last
                    or not 1 <= int(first) <= int(last) <= n):
                raise RiskAreaError(
                    "Risk area '%s' covers segments %s-%s, but path '%s' has segments 1-%d. "
                    "Set its first and last segment within 1-%d, first <= last."
                    % (area.label, first, last, spec.label, n, n))
            areas.append(area)
        areas.sort(key=lambda a: int(a.first))
        for a, b in zip(areas, areas[1:]):
            if int(b.first) <= int(a.last):
                raise RiskAreaError(
                    "Risk areas '%s' (segments %d-%d) and '%s' (segments %d-%d) overlap on "
                    "path '%s'. Make them disjoint or merge them into one."
                    % (a.label, a.first, a.last, b.label, b.first, b.last, spec.label))
        return {int(a.first) - 1: a for a in areas}

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

    def _add(self, kind, p_u, R_u_t, role, segment, comment, speed=None, zone=None, via=None):
        via_target = self._target(via, R_u_t) if via is not None else None
        move = Move(kind=kind, target=self._target(p_u, R_u_t),
                    speed_mm_s=self.speed if speed is None else speed,
                    zone_mm=self.zone if zone is None else zone,
                    frame=self.frame.name, via=via_target, role=role,
                    segment=segment, comment=comment)
        self.moves.append(move)
        return move

    def _reorient_if_needed(self, R_now, R_next, p_u, segment, why):
        if R_now is R_next:     # one marker's orientation, inherited: nothing turns
            return
        angle = rotations.rotation_angle_between(R_now, R_next)
        if angle <= ORIENTATION_TOL_RAD:
            return
        # Stop exactly at the junction so the tool turns there, not before.
        if self.moves and self.moves[-1].role in (ROLE_PATH, ROLE_RISK):
            self.moves[-1].zone_mm = 0.0
        self._add(LINEAR, p_u, R_next, ROLE_REORIENT, segment,
                  "segment %d: reorient tool %.1f deg %s" % (segment, np.degrees(angle), why),
                  zone=0.0)

    def write(self, progress=None):
        """Return the list of moves of the path (`progress` told every few segments)."""
        spec, segs, Rs = self.spec, self.segments, self.rotations
        p0, R0 = segs[0].start, Rs[0]
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

        R_now = R0
        i = 0
        steps = Steps(progress, len(segs), "writing moves of path '%s'" % spec.label)
        while i < len(segs):
            steps(i)
            area = self.risk_of.get(i)
            if area is not None:
                R_first = Rs[int(area.first) - 1]
                self._reorient_if_needed(R_now, R_first, segs[i].start, i + 1,
                                         "entering risk area '%s'" % area.label)
                self._write_risk_area(area)
                R_now = Rs[int(area.last) - 1]
                i = int(area.last)
                continue
            self._reorient_if_needed(R_now, Rs[i], segs[i].start, i + 1, "at junction")
            self._write_segment(i)
            R_now = Rs[i]
            i += 1

        if len(self.moves) > n_body_start:
            self.moves[-1].zone_mm = 0.0      # stop exactly at the end of the path
        p_end = segs[-1].end
        if self.retract_mm > 0.0:
            self._add(LINEAR, p_end - self.retract_mm * R_now[:, 2], R_now, ROLE_RETRACT, None,
                      "retract from path '%s': %g mm" % (spec.label, self.retract_mm),
                      speed=self.approach_speed, zone=0.0)
        return self.moves

    def _write_segment(self, i):
        seg, R, number = self.segments[i], self.rotations[i], i + 1
        comment = "segment %d: %s %s" % (number, seg.kind, seg.source)
        if seg.kind == "line":
            self._add(LINEAR, seg.end, R, ROLE_PATH, number, comment)
        elif seg.kind == "arc":
            pieces = max(1, int(np.ceil(seg.sweep_rad / np.pi - 1e-9)))
            piece_len = seg.length / pieces
            for m in range(pieces):
                part = " (part %d of %d)" % (m + 1, pieces) if pieces > 1 else ""
                end = seg.end if m == pieces - 1 else seg.point_at((m + 1) * piece_len)
                self._add(CIRCULAR, end, R, ROLE_PATH, number, comment + part,
                          via=seg.point_at((m + 0.5) * piece_len))
        elif hasattr(seg, "points"):
            for p in seg.points[1:]:
                self._add(LINEAR, p, R, ROLE_PATH, number, comment)
        else:
            raise GeometryError("Path '%s': %s is a %r, which CadRobot cannot follow."
                                % (self.spec.label, self._seg_name(i), seg.kind))

    def _write_risk_area(self, area):
        """Linear moves through the re-sampled risk area (eqs 8-15)."""
        spec, segs = self.spec, self.segments
        first, last = int(area.first), int(area.last)
        if area.step_mm is not None:
            step = area.step_mm
        elif spec.step_mm is not None:
            step = spec.step_mm
        else:
            step = self.speed * _positive(spec.sample_time_s, "Sample time", spec.label)
        step = float(step)
        if not (np.isfinite(step) and step > 0.0):
            raise RiskAreaError("Risk area '%s' on path '%s' has step %g mm; it must be > 0. "
                                "Fix the step of the risk area or of the path."
                                % (area.label, spec.label, step))
        lengths = [segs[j].length for j in range(first - 1, last)]
        n_points = sum(int(np.ceil(L / step)) for L in lengths)
        if n_points > MAX_RISK_POINTS:
            raise RiskAreaError(
                "Risk area '%s' on path '%s' would need %d points at step %g mm (at most %d). "
                "Use a larger step." % (area.label, spec.label, n_points, step, MAX_RISK_POINTS))
        offsets = np.concatenate([[0.0], np.cumsum(lengths)])
        total = offsets[-1]
        q_first = rotations.quaternion_from_matrix(self.rotations[first - 1])
        q_last = rotations.quaternion_from_matrix(self.rotations[last - 1])
        for k, j in enumerate(range(first - 1, last)):
            seg = segs[j]
            s = interpolation.stations(seg.length, step)[1:]
            points = seg.points_at(s)
            fractions = np.clip((offsets[k] + s) / total, 0.0, 1.0)
            quats = interpolation.interpolate_orientations(q_first, q_last, fractions)
            mats = rotations.matrix_from_quaternion(np.reshape(quats, (-1, 4)))
            comment = "risk area '%s' segments %d-%d: segment %d %s %s" % (
                area.label, first, last, j + 1, seg.kind, seg.source)
            for p, R in zip(points, np.reshape(mats, (-1, 3, 3))):
                self._add(LINEAR, p, R, ROLE_RISK, j + 1, comment)
