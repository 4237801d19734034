"""The placement search end to end: screen every candidate base, then run the full check on
the best ones (:func:`search`).

1. :func:`.placement.screen` keeps the bases where every target of every path
   is reachable in one arm configuration per path, within the joint limits
   with a margin, away from singularities, and estimates their score.
2. Those are checked in the order of that score with the engine of
   ``api.check`` (:func:`check_at`): the joints chosen along each path
   (:func:`.configuration.solve_program`), every target and sampled move
   checked (:func:`.checks.check_program`), collisions of the links and the
   tool with the document's solids (:mod:`.collision`), and the cycle time
   (:func:`.timing.cycle_time`) -- until `count` bases pass or `max_checks`
   were checked.  A base passes when that check finds no error, no
   singularity warning (when singularities count) and every joint stays
   ``margin_deg`` inside its limits at every target: so ``api.check`` of the
   cell moved there passes.
3. The bases that pass are scored again with the full check's numbers
   (:func:`.placement.score`) and returned best first.

Pure numpy (and trimesh / python-fcl for collisions): never imports FreeCAD.
"""

import time
from dataclasses import dataclass, field
from typing import Dict, Optional

import numpy as np

from ... import dependencies
from ...core import frames as tf
from ...core import program as ir
from . import placement
from ..checks import checks, collision
from ..motion import move_sampling, timing
from ..catalog.catalog import reach_mm
from ..motion import configuration as cfg

#: States of a cell of the heat map (:class:`HeatMap`).
FAILS_SCREEN, FAILS_CHECK, NOT_CHECKED, PASSES = 0, 1, 2, 3


@dataclass
class Candidate:
    """One base that passes, or one that fails, and why.

    Attributes
    ----------
    T_u_r : ndarray, shape (4, 4)
        The robot base {R} in {U}, mm.
    x_mm, y_mm, z_mm, turn_deg : float
        Its position and turn about Z of {U}.
    score : float
        See :mod:`.placement` (NaN for a base that fails).
    parts : dict
        ``cycle_time_s``, ``limit_margin_deg``, ``manipulability`` and their
        parts of the score in [0, 1], before weighting: ``time_part``,
        ``margin_part``, ``manipulability_part``.
    kind : str
        ``"ok"``, or why it fails: ``"unreachable"``, ``"joint_limit"``,
        ``"limit_margin"``, ``"singularity"``, ``"configuration"`` (screen),
        or the kind of the full check's first error (``"collision"``,
        ``"joint_speed"``...).
    reason : str
        What failed where ('' when it passes).
    report : checks.Report or None
        The full check's findings, when it was checked.
    solution : configuration.JointSolution or None
    cycle_time : dict or None
        :func:`.timing.cycle_time` of the full check.
    preview_joints_deg : ndarray, shape (6,), or None
        Model joints at the first target of the first path (to draw the robot there).
    placement : object
        ``api.place_robot`` puts the base here as a ``FreeCAD.Placement``.
    """

    T_u_r: np.ndarray
    x_mm: float
    y_mm: float
    z_mm: float
    turn_deg: float
    score: float = float("nan")
    parts: Dict[str, float] = field(default_factory=dict)
    kind: str = "ok"
    reason: str = ""
    report: Optional[checks.Report] = None
    solution: Optional[cfg.JointSolution] = None
    cycle_time: Optional[dict] = None
    preview_joints_deg: Optional[np.ndarray] = None
    placement: object = None

    @property
    def ok(self):
        """bool: the base passes."""
        return self.kind == "ok"

    def where(self):
        """``"x 1200, y -300, z 0 mm, turn 90 deg"``."""
        return "x %.0f, y %.0f, z %.0f mm, turn %.0f deg" % (self.x_mm, self.y_mm, self.z_mm,
                                                            self.turn_deg)

    def to_dict(self):
        """dict of plain values for JSON."""
        out = {"x_mm": self.x_mm, "y_mm": self.y_mm, "z_mm": self.z_mm, "turn_deg": self.turn_deg,
               "T_u_r": self.T_u_r.tolist(), "kind": self.kind}
        if self.ok:
            out.update(score=_plain(self.score), parts={k: _plain(v) for k, v in self.parts.items()})
        else:
            out["reason"] = self.reason
        return out


def _plain(value):
    value = float(value)
    return value if np.isfinite(value) else None


@dataclass
class HeatMap:
    """The search over the floor, for drawing: one cell per (x, y) position, the best of its
    heights and turns.

    Attributes
    ----------
    x_mm : ndarray, shape (nx,)
    y_mm : ndarray, shape (ny,)
    z_mm : float
        The lowest height searched (where to draw it), {U}, mm.
    state : ndarray of int, shape (ny, nx)
        :data:`PASSES` (a base passes the full check), :data:`NOT_CHECKED`
        (passes the screen, full check not run), :data:`FAILS_CHECK`,
        :data:`FAILS_SCREEN`; -1 outside the searched face.
    score : ndarray, shape (ny, nx)
        The screen's score of the best base there, NaN where none passes it.
    """

    x_mm: np.ndarray
    y_mm: np.ndarray
    z_mm: float
    state: np.ndarray
    score: np.ndarray


class Placements(list):
    """The bases that pass, best first (a list of :class:`Candidate`), and what the search found.

    Attributes
    ----------
    failures : list of Candidate
        The failing bases that came closest (those the full check refused
        first, then those the screen refused with the fewest failing
        targets), with their reasons; at most `report_failures`.
    counts : dict of str to int
        ``candidates``, ``passed_screen``, ``checked``, ``passed``, and per
        failure kind the number of bases it stopped.
    heat : HeatMap
    elapsed_s, screen_s : float
        Seconds the whole search and its screen took.
    not_checked : dict of str to str
        Checks left out (collisions without python-fcl), and why.
    robot : str
    """

    SCORE_TEXT = ("score = %.2f x fastest cycle time / cycle time + %.2f x min(1, joint-limit margin "
                  "/ %g deg) + %.2f x manipulability")

    def __init__(self, items=(), **attributes):
        super().__init__(items)
        self.failures, self.counts, self.heat = [], {}, None
        self.elapsed_s, self.screen_s, self.not_checked, self.robot = 0.0, 0.0, {}, ""
        self.weights = placement.Weights()
        self.__dict__.update(attributes)

    @property
    def ok(self):
        """bool: some base passes."""
        return len(self) > 0

    def score_text(self):
        """The score's formula with its weights (str)."""
        w = self.weights
        return self.SCORE_TEXT % (w.time, w.margin, placement.MARGIN_FULL_DEG, w.manipulability)

    def lines(self):
        """Printable lines: the checks left out (first: a reader must not miss them), the
        bases that pass with their score's parts, the counts, the closest failures."""
        c = self.counts
        out = ["NOT CHECKED: %s: %s" % item for item in self.not_checked.items()]
        out += ["%d candidate bases, %d pass the reach screen, %d fully checked, %d pass (%.1f s)."
               % (c.get("candidates", 0), c.get("passed_screen", 0), c.get("checked", 0),
                  c.get("passed", 0), self.elapsed_s)]
        out.append(self.score_text())
        for rank, cand in enumerate(self, 1):
            p = cand.parts
            out.append("%2d. score %.3f at %s: cycle time %.1f s, joint-limit margin %.1f deg, "
                       "manipulability %.2f" % (rank, cand.score, cand.where(), p["cycle_time_s"],
                                                p["limit_margin_deg"], p["manipulability"]))
        stopped = ["%d %s" % (n, kind) for kind, n in sorted(c.items())
                   if kind not in ("candidates", "passed_screen", "checked", "passed") and n]
        if stopped:
            out.append("Failed: " + ", ".join(stopped) + ".")
        for cand in self.failures:
            out.append("FAILS at %s: %s" % (cand.where(), cand.reason))
        return out

    def to_dict(self):
        """dict for JSON."""
        return {"ok": self.ok, "robot": self.robot, "score": self.score_text(),
                "counts": dict(self.counts), "elapsed_s": self.elapsed_s,
                "candidates": [c.to_dict() for c in self],
                "failures": [c.to_dict() for c in self.failures],
                "not_checked": dict(self.not_checked)}


# --- the full check of one base ----------------------------------------------------------------

def check_at(program, model, T_u_r, obstacles_u=(), q_start_deg=None, criteria=None):
    """The full check of `program` with the robot at `T_u_r`: what ``api.check`` finds there.

    Parameters
    ----------
    program : Program
        Untaught work frames (the targets stay in {U} when the robot moves).
    model : RobotModel
    T_u_r : array_like, shape (4, 4)
    obstacles_u : sequence of (str, trimesh.Trimesh)
        Named solids in {U}, mm.
    q_start_deg : array_like, shape (6,), optional
    criteria : placement.Criteria, optional

    Returns
    -------
    Candidate
        ``kind`` "ok" or the first problem, with report, solution, cycle time
        and the score's raw parts (``parts`` without the parts in [0, 1]).
        Collisions are checked first: where they fail, the report holds only
        them (the verdict is the same).
    """
    criteria = criteria or placement.Criteria()
    T_u_r = np.asarray(T_u_r, dtype=float)
    moved = placement.program_at(program, T_u_r)
    solution = cfg.solve_program(moved, model, q_start_deg=q_start_deg, assign=False)
    x, y, z = (float(v) for v in T_u_r[:3, 3])
    turn = float(np.degrees(np.arctan2(T_u_r[1, 0], T_u_r[0, 0])))
    report = checks.Report(robot=model.name)
    cand = Candidate(T_u_r, x, y, z, turn, report=report, solution=solution)
    # The moves sampled once, as for api.check: collisions along them, the checks, the cycle time.
    sampled = move_sampling.sample_program(moved, model, solution, checks.Margins())
    # Collisions first: where they fail, the per-move checks are not needed for the verdict.
    if obstacles_u and not collision.is_available():
        report.not_checked["collisions"] = dependencies.reason(collision.FCL_PACKAGE)
    elif obstacles_u:
        T_r_u = tf.invert_transform(T_u_r)
        solids = [(name, mesh.copy().apply_transform(T_r_u)) for name, mesh in obstacles_u]
        checker = collision.RobotCollisionChecker(model, solids,
                                                  **collision.tool_arguments(moved.tool))
        report.findings += collision.program_collision_findings(moved, solution, checker,
                                                                sampled=sampled)
    if not report.errors:
        full = checks.check_program(moved, model, solution, sampled=sampled, weave_fixes=False)
        report.findings = sorted(full.findings + report.findings, key=lambda f: f.move_index)
        report.targets, report.moves = full.targets, full.moves
        report.weld_positions = full.weld_positions
        report.position_tolerance_deg = full.position_tolerance_deg
        for what, why in full.not_checked.items():
            report.not_checked.setdefault(what, why)
    joints = solution.joints()
    solved = ~np.isnan(joints).any(axis=1)
    margin = float(np.min(placement.limit_margin_deg(model, joints[solved]))) if solved.any() else np.nan
    if report.errors:
        first = report.errors[0]
        cand.kind, cand.reason = first.kind, "%s: %s" % (first.kind, first.message)
        return cand
    singular = [f for f in report.warnings if f.kind == checks.SINGULARITY]
    if criteria.singularities and singular:
        cand.kind, cand.reason = "singularity", "singularity: " + singular[0].message
        return cand
    if margin < criteria.margin_deg - 1e-9:
        cand.kind = "limit_margin"
        cand.reason = ("limit_margin: a joint comes within %.1f deg of its limit (margin %g deg)"
                       % (max(margin, 0.0), criteria.margin_deg))
        return cand
    cand.cycle_time = timing.cycle_time(moved, model, solution, sampled=sampled)
    distances = cfg.arm_geometry(joints[solved], model).singularity_distances()
    cand.parts = {"cycle_time_s": float(cand.cycle_time["total_s"]), "limit_margin_deg": margin,
                  "manipulability": float(np.min(placement.manipulability(
                      distances, reach_mm(model.spec) or 1000.0)))}
    cand.preview_joints_deg = _preview_joints(moved, solution)
    return cand


def _preview_joints(program, solution):
    moves = program.moves()
    entries = [e for e in solution.entries if e.joints_deg is not None]
    for entry in entries:
        if moves[entry.move_index].role in (ir.ROLE_ENTRY, ir.ROLE_PATH):
            return np.array(entry.joints_deg, dtype=float)
    return np.array(entries[0].joints_deg, dtype=float) if entries else None


# --- the search --------------------------------------------------------------------------------

def search(program, model, space, obstacles_u=(), q_start_deg=None, criteria=None, weights=None,
           count=5, max_checks=None, report_failures=5, progress=None):
    """Search the bases of `space` for `program` (see the module docstring).

    Parameters
    ----------
    program : Program
        Generated at any base, untaught work frames.
    model : RobotModel
    space : placement.SearchSpace
    obstacles_u : sequence of (str, trimesh.Trimesh)
        The document's solids in {U}, mm (empty: no collision check).
    q_start_deg : array_like, shape (6,), optional
        The cell's StartJoints.
    criteria : placement.Criteria, optional
    weights : placement.Weights, optional
    count : int or None
        Stop after this many bases pass the full check; None checks every
        base that passes the screen (for tests and small grids).
    max_checks : int, optional
        Most full checks; default ``max(4 * count, 20)``.
    report_failures : int
        How many of the closest failures to explain.
    progress : callable, optional
        ``progress(fraction, text)``; returning False stops the search
        (:class:`.placement.SearchCancelled`).

    Returns
    -------
    Placements
    """
    started = time.perf_counter()
    criteria = criteria or placement.Criteria()
    weights = weights or placement.Weights()
    solution = cfg.solve_program(program, model, q_start_deg=q_start_deg, assign=False)
    targets = placement.target_set(program, solution)
    T_u_r, index, turns = space.bases(targets.centre_mm)

    def tell(fraction, text):
        if progress is not None and progress(fraction, text) is False:
            raise placement.SearchCancelled()

    tell(0.0, "Screening %d bases against %d targets" % (len(T_u_r), len(targets.names)))
    found = placement.screen(model, targets, T_u_r, criteria, q_start_deg,
                             None if progress is None else
                             lambda f: progress(0.8 * f, "Screening %d bases" % len(T_u_r)))
    screened = time.perf_counter()
    passed = np.flatnonzero(found.passed)
    screen_score = np.full(len(T_u_r), np.nan)
    if passed.size:
        screen_score[passed] = placement.score(found.time_s[passed], found.margin_deg[passed],
                                               found.manipulability[passed], weights)[0]
    order = passed[np.argsort(-screen_score[passed], kind="stable")]
    limit = len(order) if count is None else min(len(order), max_checks or max(4 * count, 20))
    good, refused, checked = [], [], []
    for k, i in enumerate(order[:limit]):
        tell(0.8 + 0.2 * k / max(limit, 1), "Checking base %d of %d in full" % (k + 1, limit))
        cand = check_at(program, model, T_u_r[i], obstacles_u, q_start_deg, criteria)
        checked.append(i)
        (good if cand.ok else refused).append((i, cand))
        if count is not None and len(good) >= count:
            break
    tell(1.0, "Done")

    result = Placements(weights=weights, robot=model.name)
    if good:
        parts = np.array([[c.parts["cycle_time_s"], c.parts["limit_margin_deg"],
                           c.parts["manipulability"]] for _, c in good])
        total, normalised = placement.score(parts[:, 0], parts[:, 1], parts[:, 2], weights)
        for k, (_, cand) in enumerate(good):
            cand.score = float(total[k])
            cand.parts.update({name + "_part": float(v[k]) for name, v in normalised.items()})
        result.extend(sorted((c for _, c in good), key=lambda c: -c.score))
    result.counts = _counts(found, len(checked), refused, len(good))
    result.failures = _closest_failures(model, targets, T_u_r, turns, found, refused, criteria,
                                        report_failures)
    result.heat = _heat_map(space, index, found, screen_score, checked, refused)
    for _, cand in good + refused:
        result.not_checked.update(cand.report.not_checked)
    result.elapsed_s = time.perf_counter() - started
    result.screen_s = screened - started
    return result


def _counts(found, checked, refused, passed):
    counts = {"candidates": len(found.status), "passed_screen": int(found.passed.sum()),
              "checked": checked, "passed": passed}
    for code, name in placement.KIND_NAMES.items():
        if code != placement.OK:
            counts[name] = int(np.sum(found.status == code))
    for _, cand in refused:
        counts[cand.kind] = counts.get(cand.kind, 0) + 1
    return counts


def _closest_failures(model, targets, T_u_r, turns, found, refused, criteria, limit):
    out = [cand for _, cand in refused[:limit]]
    failed = np.flatnonzero(~found.passed)
    order = failed[np.lexsort((found.status[failed], found.bad_fraction[failed]))]
    for i in order[:max(0, limit - len(out))]:
        x, y, z = (float(v) for v in T_u_r[i, :3, 3])
        code, text = placement.explain(model, targets, T_u_r[i], criteria) or (
            int(found.status[i]), placement.KIND_NAMES[int(found.status[i])])
        out.append(Candidate(T_u_r[i], x, y, z, float(turns[i]), kind=placement.KIND_NAMES[code],
                             reason=text))
    return out


def _heat_map(space, index, found, screen_score, checked, refused):
    ny, nx = len(space.y_mm), len(space.x_mm)
    state = np.full((ny, nx), -1)
    best = np.full((ny, nx), np.nan)
    per_base = np.where(found.passed, NOT_CHECKED, FAILS_SCREEN)
    per_base[checked] = PASSES
    per_base[[i for i, _ in refused]] = FAILS_CHECK
    for (iy, ix, _, _), s, value in zip(index, per_base, screen_score):
        state[iy, ix] = max(state[iy, ix], s)
        if np.isfinite(value) and s != FAILS_CHECK and not value <= best[iy, ix]:
            best[iy, ix] = value
    return HeatMap(space.x_mm, space.y_mm, float(space.z_mm[0]), state, best)
