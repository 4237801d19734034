"""Checks of a program against a robot: can it run, and where is it fragile?

:func:`check_program` looks at every target and every move of a
:class:`~CadRobotWB.core.program.Program` whose joints
:func:`.configuration.solve_program` has chosen, and returns a
:class:`Report` of findings:

============== ======== ==========================================================
kind           severity when
============== ======== ==========================================================
unreachable    error    no arm configuration reaches a target (or a point
                        between two targets)
joint_limit    error    the pose is reachable only with a joint outside its
                        limits (which joint, by how much)
config_change  error    a target (or a point of a linear/circular move) needs a
                        configuration other than the one its path keeps:
                        a linear or circular move cannot change configuration
joint_speed    error /  at the programmed TCP speed a joint would have to turn
               warning  faster than its limit (error on path and risk moves,
                        where the TCP speed is part of the process; warning on
                        approach, entry, reorient and retract moves); moves are
                        sampled, so a wrist flip in mid-move is caught
singularity    warning  a target, or a point of a move, lies within a margin of
                        the wrist, shoulder or elbow singularity
weave_speed    error    on the woven path of a weld run (issue 22) a joint would
                        have to turn faster than its limit: one finding per run,
                        at its fastest move, naming the weld and the segment,
                        with the narrower weave, lower frequency (or longer
                        cycle) and slower travel that each alone fix it
                        (:mod:`.weave_advice`); the moves of a woven run get no
                        ``joint_speed`` finding
weld_slowdown  warning  a weld run slows below its schedule's travel speed where
                        the torch turns through a corner area (the corner
                        slow-down of core/generate): one finding per run, at its
                        slowest move, with the heat input per mm there against
                        the schedule's
external_limit error    a target puts an external axis (track, positioner) outside
                        its limits (issue 23)
external_speed error /  on a coordinated linear or circular move an external axis
               warning  would have to move faster than its top speed at the
                        programmed TCP speed (relative to the part); severity as
                        ``joint_speed``; the message gives the TCP speed that fits
external_accel warning  at a blended target between two coordinated moves an
                        external axis would have to change speed faster than its
                        ``max_accel`` within the zone; the message gives the
                        speed and the zone that fit
============== ======== ==========================================================

External axes (issue 23): the moves are sampled coordinated
(:mod:`..motion.move_sampling`: the axes linear from target to target, the TCP
in the work frame), so reach, limits, speeds and singularities of the arm are
those of the coordinated motion.  An axis's acceleration is that of
:mod:`..mechanisms.axis_motion`: at a blended corner it changes speed from
the incoming move's to the outgoing one's while the TCP crosses the zone
(``|v_out - v_in|`` over that time); at a fine point the axes stop with the TCP,
each on its own trapezoid at ``max_accel``, which the cycle time counts.

The welded moves of a weld run with a weave are checked on the woven path
(:mod:`..motion.move_sampling` samples them at least 40 times per weave
cycle), so reach, joint limits, singularities and collisions see the woven
torch too.

Move times for the joint-speed check: a linear or circular move takes
``max(length / v_tcp, angle / v_ori)``, with ``v_ori`` the orientation speed
(:attr:`Margins.orientation_speed_deg_s`, 500 deg/s as in ABB's predefined
speed data); samples are spread evenly over that time.  Collisions are
checked elsewhere (``robots/checks/collision.py``), on the same samples.

Joint limits and joint speeds are the controller's, and so are the joint
values findings report: on a parallel-arm robot (``spec.j23_coupled``, the
IRB 2400) J3 is ``q2 + q3`` of the model joints, its limits and its speed
apply to that sum, and messages say so
(:meth:`~.models.RobotModel.limit_excess`,
:meth:`~.models.RobotModel.controller_joints`).

Findings are kept per target (:attr:`Report.findings`: the GUI colours every
failing target, JSON keeps them all); :meth:`Report.lines` and
:meth:`Report.to_dict` also group them (:func:`group_findings`): one line per
run of consecutive targets of a path (consecutive move indices) with the same
kind, severity and joint.  A group of reach or joint-limit errors carries
:mod:`.reach_advice`: which way and how far to move the part or the robot
(computed by :func:`check_program` when given the robot base ``T_u_r``).

Pure numpy: never imports FreeCAD.
"""

from dataclasses import asdict, dataclass, field
from typing import Dict, List, Optional

import numpy as np

from ...core import program as ir
from ...core.progress import Steps, report_now, stage
from ..motion import configuration as cfg
from ..motion import move_sampling
from ..motion.move_sampling import Margins  # noqa: F401 (checks.Margins: the margins of check_program)
from ..mechanisms import axis_motion, choose
from . import mechanism_solids, reach_advice, weave_advice

ERROR = "error"
WARNING = "warning"

UNREACHABLE = "unreachable"
JOINT_LIMIT = "joint_limit"
SINGULARITY = "singularity"
JOINT_SPEED = "joint_speed"
CONFIG_CHANGE = "config_change"
WEAVE_SPEED = "weave_speed"
WELD_SLOWDOWN = "weld_slowdown"
EXTERNAL_LIMIT = "external_limit"
EXTERNAL_SPEED = "external_speed"
EXTERNAL_ACCEL = "external_accel"
WELD_POSITION = "weld_position"
#: ISO 6947 position names, for messages.
POSITION_NAMES = {"PA": "flat (PA)", "PB": "horizontal-vertical (PB)"}
#: The robot's base stands inside a solid of the document (found by the App layer's check).
ROBOT_INSIDE = "robot_inside"
#: A calibration frame of the cell that no path uses (found by the App layer's check).
UNUSED_FRAME = "unused_frame"

#: What to do when a joint is out of its limits, by joint (0-based).
_LIMIT_FIX = (
    "turn or move the part so that it lies within axis 1's range",
    "move the part closer or farther, higher or lower",
    "move the part closer or farther, higher or lower",
    "the wrist has wound up: turn the tool markers about the tool axis, or split the path "
    "with a joint move",
    "tilt the tool less (change the tool markers' orientation) or turn the part",
    "the tool has wound up about its axis: turn the tool markers about the tool axis, or "
    "split the path with a joint move",
)


@dataclass
class Finding:
    """One problem or risk.

    Attributes
    ----------
    kind : str
        ``"unreachable"``, ``"joint_limit"``, ``"singularity"``,
        ``"joint_speed"``, ``"config_change"`` (or ``"robot_inside"``, ``"unused_frame"``, added by
        the App layer's check: target "", move index -1).
    severity : str
        ``"error"`` (the program fails) or ``"warning"``.
    target : str
        Name of the target (for a problem between two targets: the target the
        move goes to).
    move_index : int
        0-based index of the move in ``program.moves()``.
    path : str
        Label of the path.
    message : str
        What, with numbers, and what to do.
    joint : int or None
        1-based joint number the finding is about, if one.
    value, limit : float or None
        The offending number and its limit (deg, deg/s or mm, as the kind
        says); joint values and speeds in the controller's convention.
    fixes : dict or None
        ``weave_speed`` only: :meth:`.weave_advice.WeaveFix.to_dict` (each value
        alone fixes it); left out of :meth:`to_dict` when None.
    """

    kind: str
    severity: str
    target: str
    move_index: int
    path: str
    message: str
    joint: Optional[int] = None
    value: Optional[float] = None
    limit: Optional[float] = None
    fixes: Optional[dict] = None

    def to_dict(self):
        """dict of plain Python values (for JSON); ``fixes`` only when given."""
        return {k: (float(v) if isinstance(v, (np.floating, float)) else v)
                for k, v in asdict(self).items() if k != "fixes" or v is not None}


@dataclass
class Report:
    """The findings of :func:`check_program`.

    Attributes
    ----------
    robot : str
    findings : list of Finding
        In program order.
    targets : int
        Number of targets checked (vias included).
    moves : int
        Number of moves checked.
    not_checked : dict of str to str
        Checks left out, and why: e.g. ``{"collisions": "python-fcl is not
        installed ...; install it with ..."}``.  They do not make the report
        fail, but :meth:`lines` and :meth:`to_dict` say so.
    weld_positions : list of mechanisms.choose.WeldPosition
        With external axes: how far each weld run's seam is from the position
        its weld asks for (beyond ``position_tolerance_deg``: a
        ``weld_position`` warning); empty without external axes.
    position_tolerance_deg : float or None
    """

    robot: str
    findings: List[Finding] = field(default_factory=list)
    targets: int = 0
    moves: int = 0
    not_checked: Dict[str, str] = field(default_factory=dict)
    advice: Dict[tuple, reach_advice.Advice] = field(default_factory=dict)
    weld_positions: list = field(default_factory=list)
    position_tolerance_deg: Optional[float] = None

    @property
    def ok(self):
        """bool: no finding is an error."""
        return not self.errors

    @property
    def errors(self):
        """list of Finding with severity ``"error"``."""
        return [f for f in self.findings if f.severity == ERROR]

    @property
    def warnings(self):
        """list of Finding with severity ``"warning"``."""
        return [f for f in self.findings if f.severity == WARNING]

    def groups(self):
        """The findings grouped (:func:`group_findings`), each with its advice.

        Returns
        -------
        list of FindingGroup
        """
        out = group_findings(self.findings)
        for group in out:
            group.advice = self.advice.get(group.key)
        return out

    @property
    def placement_helps(self):
        """bool: an error is about reach, joint limits or the robot standing inside a part
        (moving the robot may fix it)."""
        return any(f.kind in (UNREACHABLE, JOINT_LIMIT, ROBOT_INSIDE) for f in self.errors)

    def to_dict(self):
        """dict for JSON: ``robot``, ``ok``, counts, ``findings`` (one per target),
        ``groups`` (:meth:`FindingGroup.to_dict`) and ``not_checked``."""
        return {"robot": self.robot, "ok": self.ok, "targets": self.targets,
                "moves": self.moves, "errors": len(self.errors),
                "warnings": len(self.warnings),
                "findings": [f.to_dict() for f in self.findings],
                "groups": [g.to_dict() for g in self.groups()],
                "not_checked": dict(self.not_checked),
                "weld_positions": [asdict(p) for p in self.weld_positions]}

    def lines(self):
        """list of str: one line per check left out (first: a reader must not miss it), one
        per group of findings (:meth:`groups`), then a summary line."""
        out = ["NOT CHECKED: %s: %s" % item for item in self.not_checked.items()]
        out += [g.line() for g in self.groups()]
        out.append("%s: %d targets, %d moves: %d errors, %d warnings."
                   % ("OK" if self.ok else "FAILED", self.targets, self.moves,
                      len(self.errors), len(self.warnings)))
        out += ["Weld '%s': at most %.2f deg from %s over its %d welded targets (at '%s': "
                "gravity angle %.2f deg, slope %.2f deg; tolerance %g deg)."
                % (p.label, p.worst_deg, POSITION_NAMES[p.position], p.targets, p.target,
                   p.gravity_deg, p.slope_deg, self.position_tolerance_deg)
                for p in self.weld_positions]
        return out


@dataclass
class FindingGroup:
    """A run of findings with one cause: consecutive targets of one path.

    Attributes
    ----------
    kind, severity, path : str
    joint : int or None
        As the findings' (1-based).
    findings : list of Finding
        In program order; their move indices follow each other (a gap of at
        most one move).
    advice : reach_advice.Advice or None
        Which way and how far to move the part or the robot (reach and
        joint-limit errors, when :func:`check_program` could compute it).
    """

    kind: str
    severity: str
    path: str
    joint: Optional[int]
    findings: List[Finding]
    advice: Optional[reach_advice.Advice] = None

    @property
    def key(self):
        """Hashable identity: kind, severity, path, joint and the first finding's move and target."""
        first = self.findings[0]
        return (self.kind, self.severity, self.path, self.joint, first.move_index, first.target)

    def line(self):
        """One printable line: ``SEVERITY: kind: what (the first finding) advice``."""
        first, last = self.findings[0], self.findings[-1]
        message = first.message
        if self.advice is not None:     # the advice replaces the finding's general hint
            for fix in _LIMIT_FIX[:3]:
                message = message.replace("): %s." % fix, ").")
        if len(self.findings) == 1:
            text = message
        else:
            text = ("targets '%s'..'%s' of path '%s' (%d targets, moves %d-%d); the first: %s"
                    % (first.target, last.target, self.path, len(self.findings),
                       first.move_index + 1, last.move_index + 1, message))
        if self.advice is not None:
            text += " " + ("Whole group: " if len(self.findings) > 1 else "") + self.advice.text
        return "%s: %s: %s" % (self.severity.upper(), self.kind, text)

    def to_dict(self):
        """dict for JSON: kind, severity, path, joint, first/last target and move, count,
        the printed line, and the advice (``move_mm`` in {U}, ``turn_deg``, ``verified``)."""
        first, last = self.findings[0], self.findings[-1]
        advice = None
        if self.advice is not None:
            move = self.advice.move_u_mm
            advice = {"text": self.advice.text, "verified": bool(self.advice.verified),
                      "move_mm": None if move is None else [float(v) for v in move],
                      "turn_deg": None if self.advice.turn_deg is None
                      else float(self.advice.turn_deg)}
        return {"kind": self.kind, "severity": self.severity, "path": self.path,
                "joint": self.joint, "count": len(self.findings),
                "first_target": first.target, "last_target": last.target,
                "first_move_index": int(first.move_index), "last_move_index": int(last.move_index),
                "line": self.line(), "advice": advice}


def group_findings(findings):
    """Group findings: one group per run of consecutive targets with the same cause.

    A finding joins the open group of its (kind, severity, path, joint) when
    its move index is at most one past that group's last (so findings of
    other kinds between them, as a sort by move mixes them, do not split a
    run); otherwise it starts a new group.

    Parameters
    ----------
    findings : list of Finding
        In program order.

    Returns
    -------
    list of FindingGroup
        Ordered by their first finding.
    """
    groups, open_groups = [], {}
    for finding in findings:
        cause = (finding.kind, finding.severity, finding.path, finding.joint)
        group = open_groups.get(cause)
        if group is not None and 0 <= finding.move_index - group.findings[-1].move_index <= 1:
            group.findings.append(finding)
            continue
        group = FindingGroup(finding.kind, finding.severity, finding.path, finding.joint, [finding])
        open_groups[cause] = group
        groups.append(group)
    return groups


def _add_advice(report, solution, model, T_u_r):
    """Advice of every reach or joint-limit error group of `report` (into ``report.advice``)."""
    poses = {}
    for entry in solution.entries:
        poses.setdefault((entry.move_index, entry.target.name), entry.T_r_f)
    for group in group_findings(report.findings):
        if group.severity != ERROR or group.kind not in (UNREACHABLE, JOINT_LIMIT):
            continue
        T_r_f = [poses[(f.move_index, f.target)] for f in group.findings
                 if (f.move_index, f.target) in poses]
        if not T_r_f:
            continue
        advice = reach_advice.advise(model, np.array(T_r_f, dtype=float), group.kind, group.joint,
                                     T_u_r)
        if advice is not None:
            report.advice[group.key] = advice


def check_program(program, model, solution=None, margins=None, sampled=None, T_u_r=None,
                  progress=None, weave_fixes=True):
    """Check a program against a robot model.

    Parameters
    ----------
    program : Program
    model : RobotModel
    solution : JointSolution, optional
        From :func:`.configuration.solve_program`; solved here (without
        touching ``Target.joints_deg``) when not given.
    margins : Margins, optional
    sampled : move_sampling.SampledMoves, optional
        :func:`.move_sampling.sample_program` of this program, solution and margins,
        when the caller has it (the cycle time takes the same).
    T_u_r : array_like, shape (4, 4), optional
        The robot base in {U}: reach and joint-limit advice is worded in {U}
        (default identity: in {R}).
    progress : callable, optional
        ``progress(fraction, text)`` (:mod:`..core.progress`); returning False
        raises ``Cancelled``.
    weave_fixes : bool
        Compute the three fixes of a ``weave_speed`` error (a search that
        re-samples the run, about 20 times); False: the error names what to
        change without the values (the placement search, where only the
        verdict counts).

    Returns
    -------
    Report
    """
    margins = margins or Margins()
    if solution is None:
        solution = cfg.solve_program(program, model, assign=False, progress=stage(progress, 0.0, 0.3))
    report = Report(robot=model.name, targets=len(solution.entries))
    entries = solution.entries
    distances = _singularity_distances([e.joints_deg for e in entries], model)
    steps = Steps(stage(progress, 0.3, 0.6), len(entries), "checking targets")
    jacobian_only = cfg.singular_on_jacobian(model)
    for i, (entry, distance) in enumerate(zip(entries, distances)):
        steps(i)
        report.findings += _target_findings(entry, model, solution, margins, distance,
                                            jacobian_only)

    report.moves = len(move_sampling.move_groups(entries))
    if sampled is None:
        sampled = move_sampling.sample_program(program, model, solution, margins,
                                               progress=stage(progress, 0.6, 0.9))
    report_now(progress, 0.9, "checking moves")
    report.findings += _move_findings(model, sampled, margins)
    report.findings += _weave_speed_findings(program, model, sampled, margins, weave_fixes)
    report.findings += _weld_slowdown_findings(program, entries)
    if getattr(program, "external", None) is not None:
        report.findings += _external_limit_findings(program, entries)
        report.findings += _external_speed_findings(program, sampled)
        report.findings += _external_accel_findings(program, sampled)
        report.findings += _weld_position_findings(program, entries, report)
        _name_the_track_end(program.external.track, entries, report.findings)
        _name_the_positioner(program.external, entries, report.findings)
        _, problems = mechanism_solids.mechanism_solids(program.external)
        if problems:
            report.not_checked["mechanism collisions"] = "; ".join(problems)
    report.findings.sort(key=lambda f: f.move_index)     # stable: targets before moves
    _add_advice(report, solution, model, T_u_r)
    return report


def _singularity_distances(joints, model):
    """Shoulder (mm), elbow and wrist (deg) distances from singularity of each entry's
    joints (None: NaN), shape (N, 3)."""
    q = np.array([np.full(6, np.nan) if j is None else j for j in joints],
                 dtype=float).reshape(-1, 6)
    return np.stack(cfg.arm_geometry(q, model).singularity_distances(), axis=-1)


# --- per target ----------------------------------------------------------------------------

def _where(entry):
    role = "via point of " if entry.is_via else ""
    return "%starget '%s' (path '%s', move %d)" % (role, entry.target.name, entry.path_label,
                                                   entry.move_index + 1)


def _finding(kind, severity, entry, message, **extra):
    return Finding(kind=kind, severity=severity, target=entry.target.name,
                   move_index=entry.move_index, path=entry.path_label, message=message, **extra)


def _target_findings(entry, model, solution, margins, distances, jacobian_only=False):
    out = []
    where = _where(entry)
    if entry.status == cfg.UNREACHABLE:
        out.append(_finding(UNREACHABLE, ERROR, entry,
                            "%s is out of reach: %s" % (where, _reach_text(model, entry.T_r_f))))
    elif entry.status == cfg.JOINT_LIMIT:
        out += _limit_findings(entry, model, where)
    elif entry.status == cfg.CONFIG_CHANGE:
        kept = solution.run_families[entry.run]
        out.append(_finding(
            CONFIG_CHANGE, ERROR, entry,
            "%s can only be reached in configuration '%s', but its path keeps '%s' "
            "(valid at the most targets) and a linear or circular move cannot change "
            "configuration. Change the tool orientation at this target, move the part, or "
            "split the path with a joint move."
            % (where, cfg.family_name(entry.family), cfg.family_name(kept))))
    if entry.joints_deg is not None:
        out += [_finding(SINGULARITY, WARNING, entry, text % where, value=value, limit=limit)
                for text, value, limit in _singularity_texts(*distances, margins,
                                                             jacobian_only)]
    return out


def _reach_text(model, T_r_f):
    spec = model.spec
    p = spec.opw
    if p is None:
        return "no arm configuration reaches it. Move the part closer to the robot."
    c = T_r_f[:3, 3] - p.c4 * T_r_f[:3, 2]
    radial = np.sqrt(max(c[0] ** 2 + c[1] ** 2 - p.b ** 2, 0.0))
    dz = c[2] - p.c1
    k = np.hypot(p.a2, p.c3)
    far, near = p.c2 + k, abs(p.c2 - k)
    front = np.hypot(radial - p.a1, dz)
    if front > far:
        fix = "Move the part (or the robot) %.0f mm closer." % (front - far)
    elif front < near:
        fix = "Move the part (or the robot) %.0f mm farther away." % (near - front)
    else:
        fix = "Change the tool orientation or move the part."
    return ("its wrist centre is %.0f mm from axis 2, and the arm reaches from %.0f to %.0f mm. %s"
            % (front, near, far, fix))


def _outside_limits(model, q_deg):
    """Joints of model joints `q_deg` (6,) outside their limits.

    Returns
    -------
    list of (int, float, float, float)
        ``(j, value, limit, excess)`` per joint out of range, in joint order:
        0-based joint, the controller's value, the limit it passes, by how
        much (deg).
    """
    q = model.controller_joints(q_deg)
    excess = model.limit_excess(q, controller=True)
    return [(int(j), float(q[j]),
             float(model.joint_max_deg[j] if q[j] > model.joint_max_deg[j]
                   else model.joint_min_deg[j]), float(excess[j]))
            for j in np.flatnonzero(excess > 0.0)]


def _limit_findings(entry, model, where):
    return [_finding(
        JOINT_LIMIT, ERROR, entry,
        "%s needs %s at %.1f deg, %.1f deg beyond its limit of %+.0f deg (in every arm "
        "configuration that reaches it; shown for '%s'): %s."
        % (where, model.joint_label(j), value, excess, limit, cfg.family_name(entry.family),
           _LIMIT_FIX[j]),
        joint=j + 1, value=value, limit=limit)
        for j, value, limit, excess in _outside_limits(model, entry.attempt_deg)]


def _singularity_texts(shoulder, elbow, wrist, margins, jacobian_only=False):
    """(message, value, limit) per singularity closer than its margin; `jacobian_only`: an
    offset wrist, whose one distance (``ArmGeometry.singularity_distances``) is the wrist's."""
    out = []
    if jacobian_only and wrist < margins.wrist_deg:
        out.append(("%%s is %.1f deg (in joint space) from a singularity of the arm (where "
                    "its Jacobian loses rank: on an offset wrist not only at J5 = 0; margin "
                    "%.0f deg): joints turn fast there. Tilt or turn the tool a few degrees, or "
                    "move the part." % (wrist, margins.wrist_deg), wrist, margins.wrist_deg))
    elif wrist < margins.wrist_deg:
        out.append(("%%s is %.1f deg from the wrist singularity (axis 5 near 0; margin %.0f "
                    "deg): axes 4 and 6 turn fast there. Tilt the tool a few degrees more or less."
                    % (wrist, margins.wrist_deg), wrist, margins.wrist_deg))
    if shoulder < margins.shoulder_mm:
        out.append(("%%s puts the wrist centre %.0f mm from axis 1 (shoulder singularity; "
                    "margin %.0f mm): axis 1 turns fast there. Move the part away from the "
                    "robot's axis 1." % (shoulder, margins.shoulder_mm), shoulder,
                    margins.shoulder_mm))
    if elbow < margins.elbow_deg:
        out.append(("%%s has the arm %.1f deg from fully stretched or folded (elbow "
                    "singularity; margin %.0f deg). Move the part so the arm can bend more."
                    % (elbow, margins.elbow_deg), elbow, margins.elbow_deg))
    return out


# --- per move ------------------------------------------------------------------------------

def move_samples(program, model, start, group, margins):
    """Sample one linear or circular move and follow its start configuration
    (:func:`.move_sampling.sample_moves` for one move).

    Parameters
    ----------
    program : Program
    model : RobotModel
    start : TargetSolution
        The target the move starts from (the previous move's end).
    group : list of TargetSolution
        The move's entries: ``[via, target]`` for a circular move, ``[target]``.
    margins : Margins

    Returns
    -------
    dict or None
        None when the start has no joints, else :meth:`.move_sampling.SampledMoves.move`.
    """
    if start.joints_deg is None:
        return None
    return move_sampling.sample_moves(program, model, [(start, group)], margins).move(0)


def _move_findings(model, sampled, margins):
    """Findings between the targets of every sampled move, in move order.

    Per move, the first of: the configuration trouble at the first inner sample
    whose status is not OK (when the move's end itself is fine: the targets are
    reported apart); else a joint that would have to turn faster than its limit
    between two samples, and each singularity passed closer than its margin and
    closer than at either end.
    """
    k_moves = len(sampled)
    if k_moves == 0:
        return []
    offsets, status = sampled.offsets, sampled.status
    starts = offsets[:-1]
    n_samples = len(status)
    move_of = np.repeat(np.arange(k_moves), np.diff(offsets))
    index = np.arange(n_samples)
    inner = (index > offsets[move_of]) & (index < offsets[move_of + 1] - 1)
    first_bad = np.minimum.reduceat(
        np.where(inner & (status != move_sampling.OK), index, n_samples), starts)

    good = status == move_sampling.OK
    q = np.where(good[:, None], sampled.q_deg, np.nan)
    needed, n_good = move_sampling.peak_joint_speeds(model, sampled)           # (K, 6), (K,)
    dt = sampled.time_s / (np.diff(offsets) - 1)
    limits = np.asarray(model.spec.joint_speed_deg_s, dtype=float)
    # Singularities passed between the targets, against the closest at either end.
    closest = np.stack([np.minimum.reduceat(np.where(good, d, np.inf), starts)
                        for d in cfg.arm_geometry(q, model).singularity_distances()], axis=-1)
    at_ends = np.fmin(
        _singularity_distances([s.joints_deg for s in sampled.starts], model),
        _singularity_distances([g[-1].joints_deg for g in sampled.groups], model))
    at_ends = np.where(np.isnan(at_ends), np.inf, at_ends)

    margin_of = np.array([margins.shoulder_mm, margins.elbow_deg, margins.wrist_deg])
    trouble = (first_bad < n_samples) & np.array([g[-1].status == cfg.OK
                                                  for g in sampled.groups], dtype=bool)
    fast = (dt > 0.0) & (needed > limits * (1.0 + 1e-9)).any(axis=1) & ~_woven(sampled)
    near = (closest < margin_of).any(axis=1)
    out = []
    for k in np.flatnonzero(trouble | ((n_good >= 2) & (fast | near))):
        if trouble[k]:
            out.append(_trouble_finding(model, sampled, k, int(first_bad[k])))
            continue
        if fast[k]:
            out += _speed_findings(model, sampled, k, needed[k], limits)
        if near[k]:
            out += _passed_singularity_findings(sampled, k, closest[k], at_ends[k], margins,
                                                cfg.singular_on_jacobian(model))
    return out


def _move_where(sampled, k):
    start, end = sampled.starts[k], sampled.groups[k][-1]
    return "the %s move from '%s' to '%s' (path '%s', move %d)" % (
        end.move.kind, start.target.name, end.target.name, end.path_label, end.move_index + 1)


def _trouble_finding(model, sampled, k, i):
    """The configuration, limit or reach trouble at sample i, inside move k."""
    end = sampled.groups[k][-1]
    where = _move_where(sampled, k)
    status = move_sampling.STATUS_NAMES[sampled.status[i]]
    q = sampled.q_deg[i]
    kind = {cfg.CONFIG_CHANGE: CONFIG_CHANGE, cfg.JOINT_LIMIT: JOINT_LIMIT}.get(status,
                                                                              UNREACHABLE)
    extra = {}
    if kind == CONFIG_CHANGE:
        text = "would have to leave its configuration '%s'" % cfg.family_name(sampled.family[k])
    elif kind == JOINT_LIMIT:
        text = "would take a joint beyond its limits"
        outside = _outside_limits(model, q) if np.all(np.isfinite(q)) else []
        if outside:
            j, value, limit, _ = max(outside, key=lambda o: o[3])
            text = ("would take %s to %.1f deg, beyond its limit of %+.0f deg (%s)"
                    % (model.joint_label(j), value, limit, _LIMIT_FIX[j]))
            extra = {"joint": j + 1, "value": value, "limit": limit}
    else:
        text = "would leave the robot's reach"
    return _finding(kind, ERROR, end,
                    "%s %s at %.0f%% of its length. Add a target there with a better "
                    "tool orientation, move the part, or split the path with a joint "
                    "move." % (where[0].upper() + where[1:], text,
                               100.0 * sampled.fractions[i]), **extra)


def _speed_findings(model, sampled, k, needed, limits):
    """A joint turning faster than its limit on move k (needed, limits: (6,) deg/s)."""
    end = sampled.groups[k][-1]
    move = end.move
    ratio = needed / limits
    j = int(np.argmax(ratio))
    if not ratio[j] > 1.0 + 1e-9:
        return []
    severity = ERROR if move.role in (ir.ROLE_PATH, ir.ROLE_RISK) else WARNING
    length, angle = sampled.length_mm[k], sampled.angle_deg[k]
    v_ori, time_s = sampled.v_ori_deg_s[k], sampled.time_s[k]
    if length / float(move.speed_mm_s) >= angle / v_ori:
        slowed = "the TCP to about %.3g mm/s" % (float(move.speed_mm_s) / ratio[j])
    else:
        slowed = "the tool's rotation to about %.3g deg/s" % (v_ori / ratio[j])
    return [_finding(
        JOINT_SPEED, severity, end,
        "On %s (%.1f mm at %g mm/s, %.1f deg of tool rotation at %g deg/s: %.2f s), "
        "%s would have to turn at %.0f deg/s; its limit is %.0f deg/s, so the "
        "controller slows %s there. Lower the path's speed, raise the path's zone, "
        "or turn the tool more gradually (a risk area)%s."
        % (_move_where(sampled, k), length, move.speed_mm_s, angle, v_ori, time_s,
           model.joint_label(j), needed[j], limits[j], slowed,
           "; a wrist flip mid-move shows up like this" if j in (3, 5) else ""),
        joint=j + 1, value=float(needed[j]), limit=float(limits[j]))]


def _passed_singularity_findings(sampled, k, closest, at_ends, margins, jacobian_only=False):
    """Singularities move k passes closer than their margins and than at its ends
    (closest, at_ends: shoulder mm, elbow deg, wrist deg; `jacobian_only`: the wrist's is
    the arm's one singularity distance)."""
    end = sampled.groups[k][-1]
    where = _move_where(sampled, k)
    out = []
    names = ("shoulder", "elbow", "arm's" if jacobian_only else "wrist")
    for j, margin in enumerate((margins.shoulder_mm, margins.elbow_deg, margins.wrist_deg)):
        if closest[j] < margin and closest[j] < at_ends[j] - 1e-9:
            unit = "mm" if j == 0 else "deg"
            out.append(_finding(
                SINGULARITY, WARNING, end,
                "%s passes %.1f %s from the %s singularity (margin %.0f %s) between its "
                "targets. Change the tool orientation along the move or move the part."
                % (where[0].upper() + where[1:], closest[j], unit, names[j], margin, unit),
                value=float(closest[j]), limit=float(margin)))
    return out


# --- woven weld runs -----------------------------------------------------------------------

def _woven(sampled):
    """ndarray of bool, shape (K,): the sampled moves on a woven path."""
    if sampled.clocks is None:
        return np.zeros(len(sampled), dtype=bool)
    return np.array([c is not None for c in sampled.clocks], dtype=bool)


def _weld_slowdown_findings(program, entries):
    """One ``weld_slowdown`` warning per weld run whose slowest welded move runs
    below the schedule's travel speed."""
    targets = {e.move_index: e for e in entries if not e.is_via}
    out, offset = [], 0
    for path in program.paths:
        for run in path.welds:
            travel = run.schedule.travel_speed_mm_s
            k = min(range(run.start + 1, run.end + 1), key=lambda i: path.moves[i].speed_mm_s)
            speed = path.moves[k].speed_mm_s
            entry = targets.get(offset + k)
            if speed < travel and entry is not None:
                out.append(_finding(
                    WELD_SLOWDOWN, WARNING, entry,
                    "Weld '%s' slows from %g to %g mm/s at %s, where the torch turns "
                    "through a corner: %.1f times the heat input per mm of the schedule "
                    "there. A longer corner span turns the torch more slowly; 'Stop and "
                    "reorient' puts the arc out for the turn." % (
                        run.label, travel, speed, _where(entry), travel / speed),
                    value=speed, limit=travel))
        offset += len(path.moves)
    return out


def _weave_speed_findings(program, model, sampled, margins, with_fixes=True):
    """One ``weave_speed`` error per woven run where a joint would turn faster than
    its limit, at the move and joint with the largest speed over limit; the fixes'
    values only `with_fixes`."""
    woven = np.flatnonzero(_woven(sampled))
    if not len(woven):
        return []
    needed, n_good = move_sampling.peak_joint_speeds(model, sampled)
    limits = np.asarray(model.spec.joint_speed_deg_s, dtype=float)
    ratio = np.where(np.isfinite(needed) & (n_good >= 2)[:, None], needed, 0.0) / limits
    out = []
    for clock in {id(sampled.clocks[k]): sampled.clocks[k] for k in woven}.values():
        ks = [k for k in woven if sampled.clocks[k] is clock]
        k, j = max(((k, int(np.argmax(ratio[k]))) for k in ks), key=lambda kj: ratio[kj])
        if ratio[k, j] > 1.0 + 1e-9:
            run_moves = [(sampled.starts[i], sampled.groups[i]) for i in ks]
            fix = weave_advice.advise(program, model, run_moves, margins, clock) \
                if with_fixes else None
            out.append(_weave_speed_finding(model, sampled.groups[k][-1], clock, fix, j,
                                            float(needed[k, j]), float(limits[j])))
    return out


def _weave_speed_finding(model, end, clock, fix, j, needed, limit):
    """The finding of a woven run `clock` whose joint j (0-based) needs `needed` deg/s
    at the move ending at entry `end`."""
    run = clock.run
    segment = end.move.segment if end.move.segment is not None else run.first_segment
    part = ", part %d" % run.part if run.part > 1 else ""
    phrases = fix.phrases(clock.weave, clock.travel_speed_mm_s) if fix is not None else None
    if fix is None:
        advice = "narrow the weave, lower its frequency or slow the travel (Check gives the values)"
    elif not phrases:
        advice = ("no narrower weave, lower frequency or slower travel in their ranges fixes "
                  "it: change the torch orientation along the weld or move the part")
    else:
        advice = (", ".join(phrases[:-1]) + " or " if len(phrases) > 1 else "") + phrases[-1]
        if fix.travel_speed_mm_s is None:
            advice += " (a slower travel alone is not enough)"
    return _finding(
        WEAVE_SPEED, ERROR, end,
        "Weld '%s' (segment %s%s): %s needs %.0f deg/s on the woven path (limit %.0f "
        "deg/s): %s." % (run.label, segment, part, model.joint_label(j), needed, limit,
                         advice),
        joint=j + 1, value=needed, limit=limit, fixes=fix.to_dict() if fix is not None else None)


# --- external axes (issue 23) ---------------------------------------------------------------

def axis_name(external, k):
    """How a message names external axis k (0-based): "Positioner's E2 (turn)"."""
    mechanism, axis = external.axes()[k]
    return "%s's %s (%s)" % (mechanism.label, external.axis_names()[k], axis.name)


def _external_limit_findings(program, entries):
    """One ``external_limit`` error per target and axis outside the axis's limits."""
    external = program.external
    lower = np.array([axis.lower for _, axis in external.axes()])
    upper = np.array([axis.upper for _, axis in external.axes()])
    values = np.array([move_sampling.external_values(program, entry.target)
                       for entry in entries]).reshape(len(entries), len(lower))
    path_labels = np.array([entry.path_label for entry in entries], dtype=object)
    out = []
    for entry, value in zip(entries, values):
        for k in np.flatnonzero((value < lower) | (value > upper)):
            unit = external.axes()[k][1].unit
            limit = float(upper[k] if value[k] > upper[k] else lower[k])
            on_path = values[path_labels == entry.path_label, k]
            out.append(_finding(
                EXTERNAL_LIMIT, ERROR, entry,
                "%s needs %s at %.1f %s, %.1f %s beyond its limit of %+g %s: give it a value "
                "from %g to %g %s (fix the axis or set the tool marker's values), or turn "
                "the part on the positioner%s" % (
                    _where(entry)[0].upper() + _where(entry)[1:], axis_name(external, k),
                    value[k], unit, abs(value[k] - limit), unit, limit, unit, lower[k],
                    upper[k], unit, _part_turn_fix(external, k, entry.path_label, on_path,
                                                   lower[k], upper[k])),
                joint=None, value=float(value[k]), limit=limit))
    return out


def _part_turn_fix(external, k, path_label, values_deg, lower_deg, upper_deg):
    """How far to turn the part on the positioner's table: the end of the limit message.

    Turning the part on the table by delta about the turn axis (its positive sense)
    takes every turn value the path needs to ``value - delta``: the weld keeps its
    position, and the turn fits if ``max - upper <= delta <= min - lower``. The
    message says it counter-clockwise seen from above the table's face (an axis counted
    the other way, ``catalog`` "reversed", turns clockwise for positive values).

    Parameters
    ----------
    external : ExternalAxes
    k : int
        The axis (0-based, :meth:`ExternalAxes.axes` order).
    path_label : str
    values_deg : ndarray, shape (N,)
        Axis k's values at the path's targets, deg.
    lower_deg, upper_deg : float
        Its limits.

    Returns
    -------
    str
        "." where axis k is not the table's turn of a positioner, else the turn that
        centres the path's values in the limits, or that the path needs more turn
        than the axis has.
    """
    mechanism, axis = external.axes()[k]
    if mechanism is not external.positioner or axis is not mechanism.axes[-1] \
            or axis.name != "turn":
        return "."
    needed = float(values_deg.max() - values_deg.min())
    if needed > upper_deg - lower_deg:
        return (". Path '%s' needs %.1f deg of %s, more than its %g deg from %g to %g: split "
                "it into welds of at most %g deg of turn each." % (
                    path_label, needed, axis.name, upper_deg - lower_deg, lower_deg,
                    upper_deg, upper_deg - lower_deg))
    # Turning the part by a whole turn changes nothing (the chooser shifts the axis by
    # 360 deg into its limits): the middle of [first, last] + 360 m nearest to 0.
    first = float(values_deg.max() - upper_deg)
    last = float(values_deg.min() - lower_deg)
    middle = 0.5 * (first + last)
    middle -= 360.0 * np.round(middle / 360.0)
    half = 0.5 * (last - first)
    counter_clockwise = np.sign(mechanism.T_last_flange[2, 2])   # table normal . axis
    ends = sorted(counter_clockwise * np.array([middle - half, middle + half]))
    return ("'s table by %+.0f deg (counter-clockwise seen from above the table): path '%s' "
            "(%.1f deg of %s) then fits between %g and %g deg (%+.1f and %+.1f deg reach "
            "the limits)." % (counter_clockwise * middle, path_label, needed, axis.name,
                              lower_deg, upper_deg, ends[0], ends[1]))


def _weld_position_findings(program, entries, report):
    """Fill ``report.weld_positions``; a ``weld_position`` warning per weld run whose
    seam leaves its position by more than the positioner's tolerance."""
    tolerance = program.external.tolerance_deg
    if tolerance is None:       # 0 is a tolerance (exactly flat), as the chooser reads it
        tolerance = choose.TOLERANCE_DEG
    report.position_tolerance_deg = tolerance
    report.weld_positions = choose.weld_positions(program)
    by_target = {e.target.name: e for e in entries}
    if program.external.positioner is not None:
        fix = ("free the positioner's fixed axes, give the weld the Position it can be "
               "welded in, or widen the positioner's Tolerance")
    else:       # a track alone cannot turn the seam
        fix = ("nothing in this cell turns the part: give the weld the Position it is "
               "drawn in, or hold the part on a positioner")
    out = []
    for p in report.weld_positions:
        if p.worst_deg <= tolerance + 1e-6:
            continue
        out.append(_finding(
            WELD_POSITION, WARNING, by_target[p.target],
            "Weld '%s' is %.1f deg from %s at target '%s' (gravity angle %.1f deg, slope "
            "%.1f deg), beyond the tolerance of %g deg: %s." % (
                p.label, p.worst_deg, POSITION_NAMES[p.position], p.target, p.gravity_deg,
                p.slope_deg, tolerance, fix),
            value=p.worst_deg, limit=tolerance))
    return out


def _name_the_track_end(track, entries, findings):
    """Append to each ``unreachable`` finding of `findings` at a target where `track` (or
    None) stands at an end of its travel that the track is too short there."""
    if track is None:
        return
    axis = track.axes[0]
    at_end = {e.target.name for e in entries if e.target.external is not None
              and min(abs(e.target.external[0] - axis.lower),
                      abs(e.target.external[0] - axis.upper)) < 1e-6}
    for finding in findings:
        if finding.kind == UNREACHABLE and finding.target in at_end:
            finding.message += (" Track '%s' is at the end of its travel (%g..%g mm) there: "
                                 "lengthen its travel or move its base along the part so the "
                                 "robot can follow." % (track.label, axis.lower, axis.upper))


def _name_the_positioner(external, entries, findings):
    """Append to each ``unreachable`` finding of `findings` at a target on a part riding on
    the positioner that moving the part means moving the positioner."""
    if external.positioner is None:
        return
    riding = {e.target.name for e in entries if e.move.frame in external.moving_frames}
    for finding in findings:
        if finding.kind == UNREACHABLE and finding.target in riding:
            finding.message += (" The part rides on positioner '%s': move the positioner (its "
                                "Placement), and the part moves with it."
                                % external.positioner.label)


def _external_speed_findings(program, sampled):
    """An ``external_speed`` finding per sampled move where an external axis would move
    faster than its top speed: the axis with the largest speed over limit."""
    if len(sampled) == 0 or sampled.external_delta is None:
        return []
    external = program.external
    limits = np.array([axis.max_speed for _, axis in external.axes()])
    with np.errstate(divide="ignore", invalid="ignore"):
        needed = np.abs(sampled.external_delta) / sampled.time_s[:, None]      # (K, E)
    ratio = np.where(np.isfinite(needed), needed, 0.0) / limits
    out = []
    for k in np.flatnonzero(ratio.max(axis=1) > 1.0 + 1e-9):
        e = int(np.argmax(ratio[k]))
        out.append(_external_speed_finding(program, sampled, k, e, float(needed[k, e]),
                                           float(limits[e])))
    return out


def _external_speed_finding(program, sampled, k, e, needed, limit):
    """The finding of move k whose external axis e (0-based) needs `needed` per second."""
    end = sampled.groups[k][-1]
    move = end.move
    unit = program.external.axes()[e][1].unit
    length, angle = sampled.length_mm[k], sampled.angle_deg[k]
    v_ori, time_s = sampled.v_ori_deg_s[k], sampled.time_s[k]
    ratio = needed / limit
    if length / float(move.speed_mm_s) >= angle / v_ori:
        fix = "program the move at %.3g mm/s or slower" % (float(move.speed_mm_s) / ratio)
    else:
        fix = "turn the tool at %.3g deg/s or slower" % (v_ori / ratio)
    severity = ERROR if move.role in (ir.ROLE_PATH, ir.ROLE_RISK) else WARNING
    return _finding(
        EXTERNAL_SPEED, severity, end,
        "On %s (%.1f mm at %g mm/s relative to the part, %.1f deg of tool rotation: %.2f s), "
        "%s would have to move %.1f %s in that time, at %.1f %s/s; its limit is %g %s/s, so "
        "the controller slows the TCP there: %s, or spread the axis's motion over more "
        "targets." % (_move_where(sampled, k), length, move.speed_mm_s, angle, time_s,
                      axis_name(program.external, e), abs(sampled.external_delta[k, e]), unit,
                      needed, unit, limit, unit, fix),
        value=needed, limit=limit)


def _external_accel_findings(program, sampled):
    """An ``external_accel`` warning per blended target between two sampled moves where an
    external axis would have to change speed faster than its ``max_accel`` within the
    zone (:func:`..mechanisms.axis_motion.corner_accels`): the axis with the largest
    acceleration over limit."""
    if len(sampled) < 2 or sampled.external_delta is None:
        return []
    ends = [group[-1] for group in sampled.groups]
    joined = np.array([sampled.starts[k + 1] is ends[k] for k in range(len(ends) - 1)])
    zone = np.array([end.move.zone_mm for end in ends[:-1]], dtype=float) * joined
    length, time_s = sampled.length_mm, sampled.time_s
    corner = axis_motion.corner_time_s(zone, length[:-1], time_s[:-1], length[1:], time_s[1:])
    needed = axis_motion.corner_accels(sampled.external_delta, time_s, corner)     # (K-1, E)
    limits = np.array([axis.max_accel for _, axis in program.external.axes()])
    ratio = needed / limits
    out = []
    for k in np.flatnonzero(ratio.max(axis=1) > 1.0 + 1e-9):
        e = int(np.argmax(ratio[k]))
        out.append(_external_accel_finding(program, sampled, k, e, float(needed[k, e]),
                                           float(limits[e]), float(corner[k])))
    return out


def _external_accel_finding(program, sampled, k, e, needed, limit, corner_s):
    """The finding at the target between moves k and k + 1 whose external axis e (0-based)
    needs `needed` per second squared over the `corner_s` seconds of its zone."""
    end = sampled.groups[k][-1]
    after = sampled.groups[k + 1][-1].move
    unit = program.external.axes()[e][1].unit
    v_in, v_out = (sampled.external_delta[k:k + 2, e] / sampled.time_s[k:k + 2])
    ratio = needed / limit
    # Both moves slower by s: both axis speeds scale by s, the zone's time by 1 / s,
    # the acceleration by s^2. Rounded so the numbers given still fit.
    scale = 1.0 / np.sqrt(ratio)
    speeds = sorted({float(end.move.speed_mm_s), float(after.speed_mm_s)})
    fixes = ["program both moves at %d%% of their speed or slower (%s mm/s)" % (
        np.floor(100.0 * scale), " and ".join("%g" % (np.floor(10.0 * v * scale) / 10.0)
                                              for v in speeds))]
    zone = np.ceil(10.0 * end.move.zone_mm * ratio) / 10.0     # the zone's time grows with it
    if zone <= 0.5 * min(sampled.length_mm[k], sampled.length_mm[k + 1]):
        fixes.append("give the target a zone of %g mm or more" % zone)
    fixes.append("fix the axis")
    return _finding(
        EXTERNAL_ACCEL, WARNING, end,
        "At %s, %s changes speed from %.1f to %.1f %s/s within the %g mm zone (%.3f s): "
        "%.1f %s/s^2, its limit is %g %s/s^2, so the controller slows the TCP there: %s."
        % (_where(end), axis_name(program.external, e), v_in, v_out, unit, end.move.zone_mm,
           corner_s, needed, unit, limit, unit, ", ".join(fixes[:-1]) + ", or " + fixes[-1]),
        value=needed, limit=limit)
