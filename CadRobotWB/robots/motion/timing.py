"""Cycle-time estimate of a program with acceleration limits.

:func:`cycle_time` adds up the time of every move of a program whose joints
:func:`.configuration.solve_program` has chosen.  The model, and what it
leaves out:

* **Linear and circular moves** follow a trapezoidal velocity profile along
  the path (triangular when the move is too short to reach its speed) with
  one Cartesian acceleration, ``accel_mm_s2`` (default 2000 mm/s^2, the same
  to speed up and to slow down).  The robot stops at a target whose zone is
  0 ("fine"), before and after a joint move, and at the start and end of
  the program; it keeps moving through a target with a zone > 0 (a blended
  corner does not slow down to zero) at the lower of the two moves' speeds,
  and at most ``sqrt(accel_mm_s2 * R)``, the speed at which the blend's arc
  of radius ``R = zone / tan(turn / 2)`` (:func:`~...core.zones.blend_radius_mm`)
  needs no more than that acceleration sideways: points in a straight line
  pass at full speed, a 90 degree corner in a 0.2 mm zone at 20 mm/s.  The
  path length stays that of the moves (the corner cut is not subtracted).  Speeds
  at the junctions are lowered where a move is too short to speed up or slow
  down in time (a forward and a backward pass, as a controller's look-ahead
  does).
* The tool's **orientation** turns at ``orientation_speed_deg_s`` (default
  500 deg/s as in ABB's predefined speed data): a move lasts at least
  ``angle / orientation speed``; a move that only turns the tool (no travel)
  follows a trapezoid in angle with an angular acceleration reaching that
  speed in 0.25 s.
* **Joint speeds limit linear moves too**: the move is sampled (as in
  :mod:`.checks`) and lasts at least the sum, over the steps between
  samples, of the longer of the step's time at the programmed speed and
  ``max_i |dq_i| / speed_i`` (the time its busiest joint needs at full
  speed); when that is longer than the Cartesian profile the move takes
  that time instead (no acceleration added; junction speeds are not
  re-planned for it).
* **Joint moves** are synchronised: every joint goes from the previous
  target's joints to this one's in the time of the slowest, each joint on
  its own trapezoid with its speed ``spec.joint_speed_deg_s`` and an
  acceleration (default: full speed in 0.25 s, i.e. ``speed / 0.25 s``);
  they start and end at rest.  The programmed TCP speed of a joint move is
  not used (the estimate is the fastest the robot can do it).
* Joint speeds and accelerations are the controller's, and so are the
  joint distances timed against them (:meth:`~.models.RobotModel.controller_joints`):
  on a parallel-arm robot (``spec.j23_coupled``, the IRB 2400) J3's speed
  limits the rate of ``q2 + q3`` of the model joints.
* **Welds** (issue 22): the welded moves run at the schedule's travel speed
  (they are programmed so) on the woven path (:mod:`.move_sampling` samples it,
  so a weave too fast for a joint lengthens them as above). The robot stands
  still at each run's seam start for the gas **pre-flow** (added to the run's
  start move) and at its end for the **crater fill**, the wire **burn-back**
  and the gas **post-flow** (added to its last welded move), as the
  controller waits for each: ABB seamdata ``preflow_time``, ``fill_time``,
  ``bback_time``, ``postflow_time``; KUKA ArcTech ``PreFlowTime``,
  ``CraterTime``, ``BurnBackTime``, ``PostflowTime``; the UR post's
  ``sleep``. Whether a controller moves on during the post-flow is
  unverified: counting it is the longer (safe) estimate. The move dicts get
  ``process_s`` (those waits, included in ``time_s``) and the result a
  ``welds`` list, only for a program with welds.
* **External axes** (issue 23): a track or positioner axis moves from the
  previous target's value to this one's (linearly with the TCP on a
  coordinated linear or circular move), on its own trapezoid with its
  ``max_speed`` and ``max_accel``: from rest where the TCP stops (a zone-0
  target, a joint move, the program's ends), passing at up to its top speed
  where the move blends into the next. A coordinated move takes at least the
  slowest axis's time (``limited_by`` ``"E2 speed"``), a joint move the
  longer of the arm's and the axes' (``"E2"``). The first move starts with
  the axes at its target's values (where the robot starts them is unknown).
* Not modelled: jerk limits, dynamics (payload), the controller's own
  smoothing, tool and I/O instructions, other process waits.

Pure numpy: never imports FreeCAD.
"""

import math

import numpy as np

from ...core import program as ir
from ...core import zones
from ...core.progress import Steps, report_now, stage
from . import move_sampling

#: Cartesian acceleration of linear and circular moves, mm/s^2.
DEFAULT_ACCEL_MM_S2 = 2000.0
#: Joints (and the tool's orientation) reach full speed in this time by default, s.
ACCEL_TIME_S = 0.25
#: Orientation speed of linear and circular moves, deg/s.
DEFAULT_ORIENTATION_SPEED_DEG_S = 500.0


def trapezoid_time(distance, v_max, accel, v_start=0.0, v_end=0.0):
    """Time to travel a distance with a trapezoidal (or triangular) speed profile.

    Accelerate from ``v_start`` at ``accel`` up to ``v_max``, cruise, slow
    down at ``accel`` to ``v_end``; when the distance is too short to reach
    ``v_max`` the peak speed is ``sqrt(accel * d + (v_start^2 + v_end^2) / 2)``.

    Parameters
    ----------
    distance : float
        >= 0, any length unit (mm or deg).
    v_max : float
        > 0, unit/s.
    accel : float
        > 0, unit/s^2.
    v_start, v_end : float
        Speeds at both ends, <= v_max and reachable within the distance.

    Returns
    -------
    float
        Seconds.
    """
    distance = abs(float(distance))
    if distance == 0.0:
        return 0.0
    v0, v1, v = float(v_start), float(v_end), float(v_max)
    d_up = (v * v - v0 * v0) / (2.0 * accel)
    d_down = (v * v - v1 * v1) / (2.0 * accel)
    if d_up + d_down <= distance:
        return (v - v0) / accel + (v - v1) / accel + (distance - d_up - d_down) / v
    peak = math.sqrt(accel * distance + 0.5 * (v0 * v0 + v1 * v1))
    return max(peak - v0, 0.0) / accel + max(peak - v1, 0.0) / accel


def joint_move_time(q_from_deg, q_to_deg, speeds_deg_s, accels_deg_s2):
    """Time of a synchronised joint move from rest to rest: the slowest joint's trapezoid.

    Parameters
    ----------
    q_from_deg, q_to_deg : array_like, shape (6,)
        In the convention of the speeds: the controller's joints
        (:meth:`~.models.RobotModel.controller_joints` of model joints).
    speeds_deg_s, accels_deg_s2 : array_like, shape (6,)

    Returns
    -------
    time_s : float
    joint : int
        1-based number of the joint that takes longest.
    """
    d = np.abs(np.asarray(q_to_deg, float) - np.asarray(q_from_deg, float))
    times = [trapezoid_time(d[i], speeds_deg_s[i], accels_deg_s2[i]) for i in range(6)]
    j = int(np.argmax(times))
    return float(times[j]), j + 1


def axis_move_time(distance, max_speed, max_accel, stop_start=True, stop_end=True):
    """Time an external axis needs to travel `distance`, s.

    A trapezoid at `max_speed` and `max_accel` (:func:`trapezoid_time`), from
    rest at an end where it stops; at an end where it does not, it may pass
    at up to its top speed (the most it can gain or lose over the distance,
    ``min(max_speed, sqrt(2 max_accel distance))``).

    Parameters
    ----------
    distance : float
        mm (linear axis) or deg (rotary).
    max_speed, max_accel : float
        mm/s, mm/s^2 or deg/s, deg/s^2 (> 0).
    stop_start, stop_end : bool
        Whether the axis is at rest at the start / at the end.

    Returns
    -------
    float
    """
    distance = abs(float(distance))
    free = min(max_speed, math.sqrt(2.0 * max_accel * distance))
    return trapezoid_time(distance, max_speed, max_accel, 0.0 if stop_start else free,
                          0.0 if stop_end else free)


def external_move_time(program, delta, stop_start=True, stop_end=True):
    """The slowest external axis's time on one move (:func:`axis_move_time`).

    Parameters
    ----------
    program : Program
    delta : array_like, shape (E,), or None
        The move's change of the external axis values (None: no external axes).
    stop_start, stop_end : bool

    Returns
    -------
    (float, str)
        Seconds and the axis (``"E2"``); ``(0.0, "")`` when no axis moves.
    """
    if delta is None:
        return 0.0, ""
    times = [axis_move_time(d, axis.max_speed, axis.max_accel, stop_start, stop_end)
             for d, (_, axis) in zip(delta, program.external.axes())]
    k = int(np.argmax(times))
    return (float(times[k]), program.external.axis_names()[k]) if times[k] > 0.0 else (0.0, "")


def _external_deltas(program, groups):
    """Per move (group), the external axes' change (E,) from the previous target, or None
    for a program without external axes; the first move's is zero."""
    if getattr(program, "external", None) is None:
        return [None] * len(groups)
    values = [move_sampling.external_values(program, g[-1].target) for g in groups]
    return [values[k] - values[max(k - 1, 0)] for k in range(len(groups))]


def _sampled_joint_times(model, sampled, speeds):
    """Per sampled move: the time its joints need, each step between samples taking
    the longer of the programmed speed's share and the slowest controller joint at
    its top speed; and the joint (1-6) that turns the most in seconds (1 when none turns).

    Returns
    -------
    joint_time_s : ndarray, shape (K,)
    joint : ndarray of int, shape (K,)
    """
    if len(sampled) == 0:
        return np.zeros(0), np.zeros(0, dtype=int)
    offsets = sampled.offsets
    starts = offsets[:-1]
    move_of = np.repeat(np.arange(len(sampled)), np.diff(offsets))
    ok = sampled.status == move_sampling.OK
    q = model.controller_joints(np.where(ok[:, None], sampled.q_deg, np.nan))
    # Seconds each controller joint needs for the step from each sample to the next.
    steps = np.zeros_like(q)
    steps[:-1] = np.nan_to_num(np.abs(np.diff(q, axis=0)), nan=0.0) / speeds
    last = offsets[1:] - 1
    steps[last] = 0.0                                       # no step to the next move
    dt = sampled.time_s / (np.diff(offsets) - 1)            # each step at the programmed speed
    per_step = np.maximum(steps.max(axis=1), dt[move_of])
    per_step[last] = 0.0
    turned = np.add.reduceat(steps, starts, axis=0)         # (K, 6)
    return np.add.reduceat(per_step, starts), np.argmax(turned, axis=1) + 1


def cycle_time(program, model, solution, accel_mm_s2=DEFAULT_ACCEL_MM_S2,
               joint_accel_deg_s2=None, orientation_speed_deg_s=DEFAULT_ORIENTATION_SPEED_DEG_S,
               margins=None, sampled=None, progress=None):
    """Estimate the time of every move and of the whole program.

    Parameters
    ----------
    program : Program
    model : RobotModel
    solution : JointSolution
        From :func:`.configuration.solve_program` (joints of every target).
    accel_mm_s2 : float
        Cartesian acceleration of linear and circular moves.  Default 2000.
    joint_accel_deg_s2 : float or array_like, shape (6,), optional
        Joint accelerations; default ``spec.joint_speed_deg_s / 0.25 s``.
    orientation_speed_deg_s : float
        Default 500.
    margins : move_sampling.Margins, optional
        Sampling of linear moves for the joint-speed limit.
    sampled : move_sampling.SampledMoves, optional
        :func:`.move_sampling.sample_program` with those margins, when the caller has it.
    progress : callable, optional
        ``progress(fraction, text)`` (:mod:`..core.progress`); returning False
        raises ``Cancelled``.

    Returns
    -------
    dict
        ``total_s`` (float, the sum of the known move times), ``complete``
        (bool: every move's time is known - it is not for a move to or from
        a target without joints), ``paths`` (list of ``{"path", "time_s"}``),
        ``moves`` (list of dicts: ``move_index``, ``path``, ``target``,
        ``kind``, ``role``, ``length_mm``, ``angle_deg``, ``v_start_mm_s``,
        ``v_end_mm_s``, ``time_s`` (None when unknown), ``limited_by``) and
        ``assumptions``.
    """
    spec = model.spec
    speeds = np.asarray(spec.joint_speed_deg_s, dtype=float)
    if joint_accel_deg_s2 is None:
        joint_accels = speeds / ACCEL_TIME_S
    else:
        joint_accels = np.broadcast_to(np.asarray(joint_accel_deg_s2, dtype=float), (6,)).copy()
    margins = margins or move_sampling.Margins(orientation_speed_deg_s=orientation_speed_deg_s)
    a = float(accel_mm_s2)
    w_max = float(orientation_speed_deg_s)

    groups = move_sampling.move_groups(solution.entries)
    if sampled is None:
        sampled = move_sampling.sample_program(program, model, solution, margins,
                                               progress=stage(progress, 0.0, 0.5))
    report_now(progress, 0.5, "timing moves")
    sample_of = {int(k): j for j, k in enumerate(sampled.move_group)}
    joint_time, joint = _sampled_joint_times(model, sampled, speeds)

    ext_delta = _external_deltas(program, groups)
    moves = []
    steps = Steps(stage(progress, 0.5, 1.0), len(groups), "timing moves")
    for k, group in enumerate(groups):
        steps(k)
        end = group[-1]
        move = end.move
        start = groups[k - 1][-1] if k > 0 else None
        info = {"move_index": end.move_index, "path": end.path_label, "target": end.target.name,
                "kind": move.kind, "role": move.role, "length_mm": 0.0, "angle_deg": 0.0,
                "v_start_mm_s": 0.0, "v_end_mm_s": 0.0, "time_s": None, "limited_by": "",
                "_joint_time": 0.0, "_joint": 0, "_known": True,
                "_speed": float(move.speed_mm_s), "_zone": float(move.zone_mm),
                "_path": end.path_index,
                "_start_mm": None if start is None else start.target.position_mm,
                "_move": move, "_ext_delta": ext_delta[k]}
        if move.kind == ir.JOINT:
            q0 = start.joints_deg if start is not None else solution.q_start_deg
            if q0 is None or end.joints_deg is None:
                info["_known"] = False
                info["limited_by"] = ("unknown start joints" if q0 is None
                                      else "no joints at the target")
            else:
                info["_joint_time"], info["_joint"] = joint_move_time(
                    model.controller_joints(q0), model.controller_joints(end.joints_deg), speeds,
                    joint_accels)
        else:
            j = sample_of.get(k)
            if j is None or end.joints_deg is None:
                info["_known"] = False
                info["limited_by"] = "no joints at the start or end"
            else:
                info["length_mm"] = float(sampled.length_mm[j])
                info["angle_deg"] = float(sampled.angle_deg[j])
                info["_joint_time"], info["_joint"] = float(joint_time[j]), int(joint[j])
        moves.append(info)

    junction = _junction_speeds(moves, a)
    for k, info in enumerate(moves):
        v = info.pop("_speed")
        info.pop("_zone"), info.pop("_start_mm"), info.pop("_move")
        axes_time, axis = external_move_time(program, info.pop("_ext_delta"), junction[k] == 0.0,
                                             junction[k + 1] == 0.0)
        if not info.pop("_known"):
            info.pop("_joint_time"), info.pop("_joint")
            continue
        joint_time, joint = info.pop("_joint_time"), info.pop("_joint")
        if info["kind"] == ir.JOINT:
            info["time_s"], info["limited_by"] = max((joint_time, "J%d" % joint),
                                                     (axes_time, axis))
            continue
        v0, v1 = junction[k], junction[k + 1]
        info["v_start_mm_s"], info["v_end_mm_s"] = float(v0), float(v1)
        candidates = []
        if info["length_mm"] > 0.0:
            candidates.append((trapezoid_time(info["length_mm"], v, a, v0, v1), "TCP speed"))
            candidates.append((info["angle_deg"] / w_max, "orientation speed"))
        else:
            candidates.append((trapezoid_time(info["angle_deg"], w_max, w_max / ACCEL_TIME_S),
                               "orientation speed"))
        if joint:
            candidates.append((joint_time, "J%d speed" % joint))
        if axis:
            candidates.append((axes_time, "%s speed" % axis))
        info["time_s"], info["limited_by"] = max(candidates, key=lambda c: c[0])

    welds = _add_weld_waits(program, moves)
    paths, path_index = [], None
    for info in moves:
        index = info.pop("_path")
        if index != path_index:
            paths.append({"path": info["path"], "time_s": 0.0})
            path_index = index
        paths[-1]["time_s"] += info["time_s"] or 0.0
    out = {
        "robot": spec.name,
        "total_s": float(sum(info["time_s"] or 0.0 for info in moves)),
        "complete": all(info["time_s"] is not None for info in moves),
        "paths": paths,
        "moves": moves,
        "assumptions": {
            "accel_mm_s2": a,
            "joint_speed_deg_s": speeds.tolist(),
            "joint_accel_deg_s2": joint_accels.tolist(),
            "orientation_speed_deg_s": w_max,
            "model": ("trapezoidal TCP speed along linear/circular moves, stops at zone-0 "
                      "targets and around joint moves, blends through zoned targets (at the "
                      "lower speed, at most sqrt(accel * blend radius); corner not cut); joint moves synchronised on the slowest "
                      "joint's trapezoid; linear moves slowed where a joint would exceed its "
                      "speed; no jerk limit or dynamics"),
        },
    }
    if getattr(program, "external", None) is not None:
        out["assumptions"]["external_axes"] = [
            {"axis": name, "mechanism": mechanism.label, "name": axis.name, "unit": axis.unit,
             "max_speed": float(axis.max_speed), "max_accel": float(axis.max_accel)}
            for name, (mechanism, axis) in zip(program.external.axis_names(),
                                               program.external.axes())]
    if welds:
        out["welds"] = welds
        out["assumptions"]["welds"] = ("welded moves at the travel speed on the woven path; "
                                       "the robot waits for the gas pre-flow at each seam "
                                       "start and for crater fill, burn-back and gas "
                                       "post-flow at its end")
    return out


def _add_weld_waits(program, moves):
    """Add each weld run's waits to its moves (timing dicts, in place).

    Returns
    -------
    list of dict
        Per weld run, in execution order: ``weld`` (name), ``label``, ``part``,
        ``arc_s`` (the welded moves' time, None when one is unknown),
        ``preflow_s``, ``crater_fill_s``, ``burnback_s``, ``postflow_s``.
    """
    by_index = {info["move_index"]: info for info in moves}
    out, first = [], 0
    for path in program.paths:
        for run in path.welds:
            schedule = run.schedule
            end_wait = schedule.crater_fill_s + schedule.burnback_s + schedule.gas_postflow_s
            for index, wait in ((first + run.start, schedule.gas_preflow_s),
                                (first + run.end, end_wait)):
                info = by_index.get(index)
                if info is not None and info["time_s"] is not None:
                    info["process_s"] = info.get("process_s", 0.0) + wait
                    info["time_s"] += wait
            welded = [by_index.get(i) for i in range(first + run.start + 1, first + run.end + 1)]
            arc = [None if w is None or w["time_s"] is None
                   else w["time_s"] - w.get("process_s", 0.0) for w in welded]
            out.append({"weld": run.name, "label": run.label, "part": run.part,
                        "arc_s": None if None in arc else float(sum(arc)),
                        "preflow_s": schedule.gas_preflow_s,
                        "crater_fill_s": schedule.crater_fill_s,
                        "burnback_s": schedule.burnback_s,
                        "postflow_s": schedule.gas_postflow_s})
        first += len(path.moves)
    return out


def _blend_speed(this, nxt, accel):
    """Highest speed through the blended target between two moves (timing dicts), mm/s:
    ``sqrt(accel * R)`` for the blend arc's radius R (inf when they are in line)."""
    if this["_start_mm"] is None:          # the program's first move: its start is unknown
        return math.inf
    turn = zones.turn_rad(zones.move_shape(this["_start_mm"], this["_move"]),
                          zones.move_shape(this["_move"].target.position_mm, nxt["_move"]))
    return math.sqrt(accel * zones.blend_radius_mm(this["_zone"], turn))


def _junction_speeds(moves, accel):
    """TCP speed at the start of each move and at the end of the last, (n + 1,) mm/s.

    Zero at stops: a zone-0 target, either side of a joint move or a move
    that does not travel, an unknown move, the ends of the program.  Through
    a zoned target: the lower of the two speeds and of ``sqrt(accel * R)``
    for the blend's arc radius R, then lowered so each move can slow down
    to its end speed (backward pass) and reach it from its start speed
    (forward pass).
    """
    n = len(moves)
    J = np.zeros(n + 1)

    def travels(info):
        return info["kind"] != ir.JOINT and info["_known"] and info["length_mm"] > 0.0

    for k in range(n - 1):
        this, nxt = moves[k], moves[k + 1]
        if travels(this) and travels(nxt) and this["_zone"] > 0.0:
            J[k + 1] = min(this["_speed"], nxt["_speed"], _blend_speed(this, nxt, accel))
    for k in reversed(range(n)):
        if travels(moves[k]):
            J[k] = min(J[k], math.sqrt(J[k + 1] ** 2 + 2.0 * accel * moves[k]["length_mm"]))
    for k in range(n):
        if travels(moves[k]):
            J[k + 1] = min(J[k + 1], math.sqrt(J[k] ** 2 + 2.0 * accel * moves[k]["length_mm"]))
    return J
