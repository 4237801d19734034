"""Seam tracking: the laser corrects the CAD path where the real joint is (paper 4.1).

::

    run = simulate_seam_tracking(trajectory, real_mesh, real_seam_mm, reality,
                                 JointTemplate("butt", gap_mm=1.5))
    run.metrics["rms_error_after_20mm_mm"]

The loop, once per control period (``rate_hz``, 5 Hz in the paper)
-----------------------------------------------------------------
1. Measure. The laser line lies ``look_ahead_mm`` ahead of the TCP along
   the nominal path, at path distance ``s_m = s_tcp + look_ahead``; its frame
   is the nominal path frame there, moved by the correction the robot is
   applying now (the camera rides on the torch). For a straight path this
   is exactly a camera fixed on the tool; on a curved path the camera is
   taken to keep looking at the path ahead. The profile goes to
   :func:`seam_features.extract_seam`. The seam point found (plus the
   template's ``tcp_offset_mm``) minus the nominal path point at ``s_m`` is
   the correction the TCP will need when it gets there: a vector in {U}
   whose lateral (Y) and standoff (Z) parts come from the profile and whose
   part along the travel (X), which a cross-section cannot see, is the one
   the tool carried when it measured. Being unseen, that part of every
   correction still ahead of the TCP is replaced by the newest one's. On a
   straight seam it stays 0; at a corner, the lateral correction of one leg
   becomes an along-path one of the next and vice versa, so the torch turns
   where the *real* corner is, with no jump in the correction there.
2. Look-ahead buffer. That correction is stored against ``s_m``. When the
   TCP arrives there (``look_ahead / speed`` later: 3 s at 30 mm and
   10 mm/s) the buffer gives the reference, interpolated linearly in s
   between stored stations and held flat before the first and after the last
   station (so at the start of the seam, before the TCP reaches the first
   measured station, it follows the first measurement). The reference is
   read at the middle of the stretch the TCP covers during the coming
   period, so the correction held for a period is centred on it.
   Measurements are only taken up to the programmed end of the path.
3. Control, per axis of the path frame at the TCP (X, Y, Z; X is 0 except
   round corners). Error ``e = reference - applied correction`` (the robot
   reports where it is). ``pi``: incremental PI, the form the robot's
   sensor interface takes (it adds each increment to its path offset)::

       du_k = kp (e_k - e_{k-1}) + ki T e_k        T = 1 / rate_hz

   The default gains ``ki T = 0.8``, ``kp = 0.1`` remove 80 % of the error
   each period without ringing (the "plant" is the robot's path offset,
   a static gain with about one period of delay). No integral state is
   kept, so the step limit below cannot wind it up. ``fuzzy_pi``: the force
   loop's Fuzzy-PI (``controllers.FuzzyPIController``, same incremental
   form, scales from the same gains: Gu = max_step, Ge = Gu / (ki T),
   Gde = Gu / kp); falls back to ``pi`` with a note in the metrics if that
   module is missing. ``none``: open loop, the program as drawn (the laser
   is off: no profiles, no "seam lost").
   Each increment is limited to ``max_step_mm`` per axis and quantised to
   ``resolution_mm`` per axis (the robot's resolution, 0.01 mm on the S4C+).
4. Robot. The offset the robot applies follows the commanded one with a
   first-order lag ``robot_lag_s`` and is held between periods.

Corners (tracking hold)
-----------------------
Where the programmed path turns faster than the stripe can follow (a corner,
or an arc of radius below 30 mm: :func:`corners.corner_zones`), the stripe
may miss the joint for a few profiles while the seam goes on: near a convex
corner of a part that is not where it was drawn, it runs past the end of the
real leg before the programmed corner, or reaches the programmed next leg
before the real one begins. Within ``corner_hold_mm`` of where such a zone
begins or ends (all through a zone shorter than twice that; in the middle of
a longer one, a small circle, the stripe follows the arc) a profile without
a match is a hold, not a step toward "seam lost": nothing is
stored, so the TCP goes on along the nominal path moved by the corrections
measured before the corner (the buffer interpolates linearly from the last
station before the hold to the first one re-acquired on the next leg, and
holds flat while there is none yet). The correction is held in
{U}, so what was lateral on one leg is along the travel on the next, as a
shifted part needs. Past the zone, misses count again: a seam that really
ends at a corner is still lost, ``corner_hold_mm`` later.

Capture: a match more than ``capture_mm`` from the last seam point found,
along that profile's lateral or height axis, is another joint the stripe
crosses (the other wall at a corner, a neighbouring part), not the seam: it
counts as no match. The along-travel axis is left out: a profile cannot see
it, and round a corner it becomes the next leg's lateral one.

Failures (paper 4.3) and what happens
-------------------------------------
``seam_lost``: ``lost_limit`` profiles in a row without a template match
(or with another joint only), not counting holds at corners (above).
``correction_limit``: the reference correction exceeds
``max_correction_mm`` (its magnitude). ``unreachable``: ``reach_check`` of
the corrected pose the robot is sent to returns a reason (out of reach,
beyond a joint limit, near a singularity). ``collision``: the tool, the
segment from the TCP back ``tool_length_mm`` along -Z, touches a foreign
object (``reality.foreign_objects``), checked at every time step.
``on_failure="abort"``: the robot stops where it is (``stop_index``,
``stop_T_u_t``: where a resumed arc weld must restart) and retracts
``retract_mm`` along its tool -Z. ``"reactive"``: the failure is recorded in
``metrics["events"]`` and the run goes on holding the last good correction.

Measured error: the distance from the actual TCP to the real seam polyline
in the plane through the TCP normal to the nominal travel (NaN where that
plane does not cross the seam within 50 mm; see :func:`seam_error_mm` for
the corner case). ``rms_error_after_20mm_mm`` leaves out the first 20 mm of
travel: the start, where the correction is still being built up at
``max_step_mm`` per period.

Pure numpy / scipy / trimesh: never imports FreeCAD.
"""

import numpy as np
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation, Slerp

from ..core.trajectory import Trajectory
from ..core.weave import frame_axes
from ..core.progress import Steps
from ..errors import InputError
from .corners import corner_zones, in_hold
from .laser import LaserLineSensor, LaserScene, laser_frame
from .run import SensorRun
from .seam_features import JointTemplate, extract_seam

CONTROLLERS = ("pi", "fuzzy_pi", "none")
FAILURE_MODES = ("abort", "reactive")
#: Default gains per control period: ki * T and kp.
DEFAULT_KI_T = 0.8
DEFAULT_KP = 0.1
#: Path distance after which the closed-loop error counts as settled, mm.
SETTLE_DISTANCE_MM = 20.0
#: How far before and after a programmed corner a profile may miss the joint, mm.
CORNER_HOLD_MM = 10.0
#: A match farther than this from the last seam point, across the profile, is another joint, mm.
CAPTURE_MM = 5.0


# ----------------------------------------------------------------- path


def resample(trajectory, dt_s):
    """The trajectory every `dt_s` seconds (itself when already so).

    Positions and path distance are interpolated linearly in time,
    orientations by slerp; ``move_index`` is that of the sample before.

    Returns
    -------
    Trajectory
    """
    t = np.asarray(trajectory.time_s, dtype=float)
    if len(t) < 2:
        raise InputError("The trajectory has fewer than two samples: nothing to track.")
    if np.allclose(np.diff(t), dt_s, rtol=0, atol=1e-9):
        return trajectory
    keep = np.r_[True, np.diff(t) > 1e-12]
    t, T = t[keep], trajectory.T_u_t[keep]
    new_t = np.arange(0.0, t[-1] - t[0] + 0.5 * dt_s, dt_s) + t[0]
    new_t = new_t[new_t <= t[-1] + 1e-12]
    if t[-1] - new_t[-1] > 1e-9:
        new_t = np.append(new_t, t[-1])
    poses = np.repeat(np.eye(4)[None], len(new_t), axis=0)
    poses[:, :3, :3] = Slerp(t, Rotation.from_matrix(T[:, :3, :3]))(np.clip(new_t, t[0], t[-1])).as_matrix()
    for k in range(3):
        poses[:, k, 3] = np.interp(new_t, t, T[:, k, 3])
    s = np.interp(new_t, t, np.asarray(trajectory.s_mm, dtype=float)[keep])
    index = np.asarray(trajectory.move_index)[keep][np.searchsorted(t, new_t, side="right") - 1]
    return Trajectory(new_t, poses, s, index)


class PathFrames:
    """The nominal path as a function of path distance s.

    Path frame at s: X = travel direction, Z = tool axis with its part along
    X removed, Y = Z x X (lateral). Samples where the TCP does not travel
    (turning in place) are merged into the last one at that s. The travel
    direction is that of the chord from the sample at or before s to the
    next one: exact on lines, within half a chord angle on arcs (0.06° for
    0.1 mm samples on a 50 mm radius), and at a corner the new leg's.

    Parameters
    ----------
    trajectory : Trajectory
    """

    def __init__(self, trajectory):
        s = np.asarray(trajectory.s_mm, dtype=float)
        keep = np.r_[np.diff(s) > 1e-6, True]
        self.s = s[keep]
        if len(self.s) < 2:
            raise InputError("The path does not travel: seam tracking needs a TCP that moves.")
        self.p = trajectory.position_mm[keep]
        self.tool_z = trajectory.T_u_t[keep, :3, 2]
        chords = np.diff(self.p, axis=0)
        self.x = chords / np.linalg.norm(chords, axis=1)[:, None]        # (M - 1, 3)

    def at(self, s):
        """Path point and frame axes at distance(s) `s`.

        Parameters
        ----------
        s : float or ndarray, shape (N,)
            Beyond the ends the path continues straight along its end tangent.

        Returns
        -------
        p, X, Y, Z : ndarray, shape (N, 3) each (or (3,) for a float `s`)
        """
        scalar = np.ndim(s) == 0
        s = np.atleast_1d(np.asarray(s, dtype=float))
        inside = np.clip(s, self.s[0], self.s[-1])
        p = np.column_stack([np.interp(inside, self.s, self.p[:, k]) for k in range(3)])
        x = self.x[np.clip(np.searchsorted(self.s, inside, side="right") - 1, 0, len(self.x) - 1)]
        p += (s - inside)[:, None] * x
        tool_z = np.column_stack([np.interp(inside, self.s, self.tool_z[:, k]) for k in range(3)])
        X, Y, Z = frame_axes(x, tool_z)
        if scalar:
            return p[0], X[0], Y[0], Z[0]
        return p, X, Y, Z


# ----------------------------------------------------------- measurement


def seam_error_mm(points_u, normals_u, seam_u, candidates=8, max_distance_mm=50.0):
    """Distance from each point to a polyline, in the plane through the point normal to `normals`.

    Parameters
    ----------
    points_u : ndarray, shape (N, 3)
        TCP positions, mm.
    normals_u : ndarray, shape (N, 3)
        Unit travel directions (the planes' normals).
    seam_u : ndarray, shape (K, 3)
        The real seam, K >= 2, mm.
    candidates : int
        Seam vertices nearest each point whose segments are tried first;
        points whose plane crosses none of them try every segment.
    max_distance_mm : float
        Crossings farther than this are not the seam the TCP is on (past
        the end of a leg the plane may cut another leg far away): ignored.

    Returns
    -------
    ndarray, shape (N,)
        mm; NaN where the plane crosses the seam nowhere within
        `max_distance_mm`. Where the plane cuts the seam so obliquely that
        the crossing is more than twice as far as the seam itself (a point
        just past a corner, travelling along the old leg while the plane
        slides along the new one), the plain distance to the seam is given.
    """
    points = np.asarray(points_u, dtype=float)
    normals = np.asarray(normals_u, dtype=float)
    seam = np.asarray(seam_u, dtype=float)
    if seam.ndim != 2 or seam.shape[1] != 3 or len(seam) < 2:
        raise InputError("The real seam must be a polyline of at least two points (K, 3) in mm.")
    n_seg = len(seam) - 1
    k = min(candidates, len(seam))
    _, near = cKDTree(seam).query(points, k=k)
    near = np.asarray(near).reshape(len(points), k)
    segments = np.clip(np.concatenate([near - 1, near], axis=1), 0, n_seg - 1)
    error = _plane_crossing_distance(points, normals, seam, segments, max_distance_mm)
    missing = np.flatnonzero(np.isnan(error))
    for chunk in np.array_split(missing, max(1, len(missing) * n_seg // 2_000_000 + 1)):
        if len(chunk):
            every = np.broadcast_to(np.arange(n_seg), (len(chunk), n_seg))
            error[chunk] = _plane_crossing_distance(points[chunk], normals[chunk], seam, every,
                                                    max_distance_mm)
    nearest = _segment_distance(points, seam[segments], seam[segments + 1]).min(axis=1)
    return np.where(nearest < 0.5 * error, nearest, error)


def _segment_distance(points, a, b):
    """Distance (N, C) from each point (N, 3) to the segments a-b (N, C, 3)."""
    ab, ap = b - a, points[:, None] - a
    length2 = np.einsum("nck,nck->nc", ab, ab)
    f = np.clip(np.einsum("nck,nck->nc", ap, ab) / np.where(length2 > 0, length2, 1.0), 0.0, 1.0)
    return np.linalg.norm(ap - f[..., None] * ab, axis=2)


def _plane_crossing_distance(points, normals, seam, segments, max_distance_mm=np.inf):
    """Nearest crossing of the given segments (N, C) with each point's plane, within
    `max_distance_mm` -> (N,), NaN where there is none."""
    a, b = seam[segments], seam[segments + 1]                          # (N, C, 3)
    da = np.einsum("nck,nk->nc", a - points[:, None], normals)
    db = np.einsum("nck,nk->nc", b - points[:, None], normals)
    with np.errstate(divide="ignore", invalid="ignore"):
        f = da / (da - db)
        crossing = a + f[..., None] * (b - a)
        distance = np.linalg.norm(crossing - points[:, None], axis=2)
    valid = (da * db <= 0) & (da != db)
    valid &= distance <= max_distance_mm
    distance = np.where(valid, distance, np.inf).min(axis=1)
    distance[np.isinf(distance)] = np.nan
    return distance


class ToolCollision:
    """Does the tool (a segment from the TCP back along -Z) touch a foreign object?

    Parameters
    ----------
    objects : list of (str, trimesh.Trimesh)
        Foreign objects in {U}, mm.
    tool_length_mm : float
    """

    def __init__(self, objects, tool_length_mm):
        self.tool_length_mm = float(tool_length_mm)
        self.objects = [(name, np.asarray(mesh.triangles, dtype=float), np.asarray(mesh.bounds, dtype=float))
                        for name, mesh in objects if len(mesh.faces)]

    def first_hit(self, tcp_u, tool_z_u):
        """First sample whose tool touches an object.

        Parameters
        ----------
        tcp_u, tool_z_u : ndarray, shape (N, 3)
            TCP positions (mm) and unit tool axes.

        Returns
        -------
        (int, str) or None
            Sample index and object name.
        """
        if not self.objects:
            return None
        start = tcp_u
        end = tcp_u - self.tool_length_mm * tool_z_u
        low, high = np.minimum(start, end), np.maximum(start, end)
        best = None
        for name, triangles, bounds in self.objects:
            near = np.flatnonzero(np.all(high >= bounds[0], axis=1) & np.all(low <= bounds[1], axis=1))
            if len(near) == 0:
                continue
            hit = near[_segments_cross_triangles(start[near], end[near], triangles)]
            if len(hit) and (best is None or hit[0] < best[0]):
                best = (int(hit[0]), name)
        return best


def _segments_cross_triangles(start, end, triangles):
    """(n,) bool: segment i crosses some triangle (Moller-Trumbore)."""
    t = ray_triangle_t(start, end - start, triangles)
    return (t <= 1).any(axis=1)


def ray_triangle_t(origins, directions, triangles):
    """Where rays meet triangles (Moller-Trumbore), all pairs at once.

    Parameters
    ----------
    origins, directions : ndarray, shape (n, 3)
        Ray starts and directions (any length: `t` is in units of it).
    triangles : ndarray, shape (T, 3, 3)

    Returns
    -------
    ndarray, shape (n, T)
        The ray parameter t >= 0 of each hit (the point ``origin + t * direction``),
        ``inf`` where ray i misses triangle j.
    """
    d = directions                                                      # (n, 3)
    v0 = triangles[:, 0]
    e1, e2 = triangles[:, 1] - v0, triangles[:, 2] - v0                 # (T, 3)
    p = np.cross(d[:, None], e2[None])                                  # (n, T, 3)
    det = np.einsum("ntk,tk->nt", p, e1)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / det
        s = origins[:, None] - v0[None]
        u = np.einsum("ntk,ntk->nt", s, p) * inv
        q = np.cross(s, e1[None])
        v = np.einsum("ntk,nk->nt", q, d) * inv
        t = np.einsum("ntk,tk->nt", q, e2) * inv
        hit = (np.abs(det) > 1e-12) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t >= 0)
    return np.where(hit, t, np.inf)


# ------------------------------------------------------------ look-ahead


class LookAheadBuffer:
    """Corrections measured ahead of the TCP, by path distance (module doc, steps 1-2).

    Parameters
    ----------
    capacity : int
        Most measurements it will hold.
    """

    def __init__(self, capacity):
        self.s_mm = np.empty(capacity)              # stations
        self.correction_u = np.empty((capacity, 3))  # correction needed there, {U}, mm
        self.travel_u = np.empty((capacity, 3))      # travel direction there
        self.count = 0

    def __len__(self):
        return self.count

    def store(self, s_mm, correction_u, travel_u, s_tcp_mm):
        """Add the correction needed at station `s_mm`.

        The part along the travel of every stored correction still ahead of
        the TCP (at `s_tcp_mm`) is replaced by the new one's: a profile cannot
        see it, so the newest estimate counts.
        """
        n = self.count
        ahead = np.flatnonzero(self.s_mm[:n] > s_tcp_mm)
        along = self.travel_u[ahead]
        change = np.sum((correction_u - self.correction_u[ahead]) * along, axis=1)
        self.correction_u[ahead] += change[:, None] * along
        self.s_mm[n], self.correction_u[n], self.travel_u[n] = s_mm, correction_u, travel_u
        self.count += 1

    def reference(self, s_mm):
        """ndarray, shape (3,): the correction at `s_mm`, linear between stations,
        flat before the first and after the last."""
        n = self.count
        return np.array([np.interp(s_mm, self.s_mm[:n], self.correction_u[:n, k]) for k in range(3)])


# ------------------------------------------------------------ controllers


class _IncrementalPI:
    """``du = kp (e_k - e_{k-1}) + ki T e_k`` on each path axis (X, Y, Z)."""

    note = ""

    def __init__(self, kp, ki):
        self.kp, self.ki = float(kp), float(ki)
        self.previous = np.zeros(3)

    def step(self, error, period_s):
        du = self.kp * (error - self.previous) + self.ki * period_s * error
        self.previous = np.array(error, dtype=float)
        return du


class _FuzzyPI:
    """The force loop's Fuzzy-PI, one per axis."""

    note = ""

    def __init__(self, kp, ki, period_s, max_step_mm):
        from .controllers import FuzzyPIController
        gu = max_step_mm
        self.axes = [FuzzyPIController(error_scale=gu / (ki * period_s),
                                       change_scale=gu / max(kp, 1e-6), output_scale=gu,
                                       output_limit=gu, integral_limit=1e9)
                     for _ in range(3)]

    def step(self, error, period_s):
        return np.array([c.step(e, period_s) for c, e in zip(self.axes, error)])


class _OpenLoop:
    """No correction: the program as drawn."""

    note = ""

    def step(self, error, period_s):
        return np.zeros_like(error)


def _make_controller(name, gains, rate_hz, max_step_mm):
    if name not in CONTROLLERS:
        raise InputError("Unknown seam-tracking controller %r: use one of %s." % (name, ", ".join(CONTROLLERS)))
    gains = dict(gains or {})
    unknown = set(gains) - {"kp", "ki"}
    if unknown:
        raise InputError("Unknown controller gains %s: give kp and ki (1/s)." % sorted(unknown))
    kp = float(gains.get("kp", DEFAULT_KP))
    ki = float(gains.get("ki", DEFAULT_KI_T * rate_hz))
    if kp < 0 or not ki > 0:
        raise InputError("Seam-tracking gains need kp >= 0 and ki > 0, got kp=%r, ki=%r." % (kp, ki))
    if name == "none":
        return _OpenLoop()
    if name == "fuzzy_pi":
        try:
            return _FuzzyPI(kp, ki, 1.0 / rate_hz, max_step_mm)
        except ImportError:
            controller = _IncrementalPI(kp, ki)
            controller.note = "fuzzy_pi is not available (sensors/controllers.py missing): ran pi instead"
            return controller
    return _IncrementalPI(kp, ki)


def _quantised_step(du, resolution_mm, max_step_mm):
    """Per axis: limit to +-max_step_mm, then round to the resolution (never past the limit)."""
    most = np.floor(max_step_mm / resolution_mm + 1e-9)
    counts = np.clip(np.round(du / resolution_mm), -most, most)
    return counts * resolution_mm


# ------------------------------------------------------------------ loop


def simulate_seam_tracking(trajectory, real_mesh, real_seam_mm, reality, template=None, rate_hz=5.0,
                           dt_s=0.01, resolution_mm=0.01, max_step_mm=0.5, max_correction_mm=15.0,
                           controller="pi", gains=None, look_ahead_mm=30.0, lost_limit=3,
                           robot_lag_s=0.05, reach_check=None, on_failure="abort", retract_mm=50.0,
                           tool_length_mm=150.0, retract_speed_mm_s=50.0, sensor=None, progress=None,
                           corner_hold_mm=CORNER_HOLD_MM, capture_mm=CAPTURE_MM):
    """Run the nominal path with the laser correcting it (see the module doc).

    Parameters
    ----------
    trajectory : core.trajectory.Trajectory
        Nominal TCP path (the path moves), {U}; resampled to `dt_s` if needed.
    real_mesh : trimesh.Trimesh
        The real workpiece and the foreign objects, {U}, mm: what the laser sees.
    real_seam_mm : ndarray, shape (K, 3)
        The real seam polyline, {U}, mm; only to measure the error.
    reality : Reality
        Laser noise, foreign objects (for the tool's collisions), seed.
    template : JointTemplate, optional
        The joint to find; default a butt joint with a 1.5 mm root gap.
    rate_hz : float
        Correction rate, Hz.
    dt_s : float
        Simulation time step, s.
    resolution_mm : float
        Robot resolution: every correction is a multiple of it, mm.
    max_step_mm : float
        Largest correction change per period, per path axis, mm.
    max_correction_mm : float
        Largest correction (magnitude), mm; beyond -> failure.
    controller : str
        ``"pi"``, ``"fuzzy_pi"`` or ``"none"`` (open loop).
    gains : dict, optional
        ``kp`` and ``ki`` (1/s); default kp = 0.1, ki = 0.8 * rate_hz.
    look_ahead_mm : float
        Distance of the laser line ahead of the TCP, mm (ignored when
        `sensor` is given: its own).
    lost_limit : int
        Profiles in a row without a match that make the seam lost (holds
        at corners not counted).
    robot_lag_s : float
        Time constant of the robot following a correction, s (0 = at once).
    reach_check : callable, optional
        ``reach_check(T_u_t (4, 4), time_s) -> str | None`` on every corrected
        pose the robot is sent to.
    on_failure : str
        ``"abort"`` or ``"reactive"``.
    retract_mm, retract_speed_mm_s : float
        Retract along tool -Z after an abort.
    tool_length_mm : float
        Length of the tool segment checked against foreign objects, mm.
    sensor : LaserLineSensor, optional
        Default ``LaserLineSensor.from_reality(reality, look_ahead_mm=look_ahead_mm)``.
    progress : callable, optional
        ``progress(fraction, text)`` (:mod:`..core.progress`), told every few
        control periods; returning False raises ``Cancelled``.
    corner_hold_mm : float
        A profile without a match within this distance of a corner of the
        nominal path is a tracking hold (module doc), mm; 0 = only inside
        the corner itself.
    capture_mm : float
        A match more than this from the last seam point found, lateral or
        in height in that profile's plane, is another joint the stripe
        crosses (the other wall at a corner, an edge of the part), not the
        seam: it counts as no match, mm.

    Returns
    -------
    SensorRun
        ``sensor="laser"``; metrics: ``rms_error_mm``,
        ``rms_error_after_20mm_mm``, ``max_error_mm``, ``open_loop_rms_error_mm``,
        ``open_loop_max_error_mm``, ``max_step_mm`` (largest applied
        step along a path axis), ``max_correction_mm``, ``n_corrections``,
        ``n_measurements``, ``seam_lost_count`` (profiles without a match),
        ``corners`` (corner zones of the nominal path), ``corner_holds`` (of
        the profiles without a match, those held at a corner), ``other_joints``
        (matches refused as too far from the seam, ``capture_mm``),
        ``events`` (list of dicts: kind, message, index, time_s, s_mm),
        ``stop_s_mm``, ``notes``.
    """
    template = template or JointTemplate("butt")
    if on_failure not in FAILURE_MODES:
        raise InputError("on_failure must be 'abort' or 'reactive', got %r." % (on_failure,))
    for name, value in (("rate_hz", rate_hz), ("dt_s", dt_s), ("resolution_mm", resolution_mm),
                        ("max_step_mm", max_step_mm), ("max_correction_mm", max_correction_mm),
                        ("retract_speed_mm_s", retract_speed_mm_s)):
        if not value > 0:
            raise InputError("Seam tracking: %s must be > 0, got %r." % (name, value))
    if max_step_mm < resolution_mm:
        raise InputError("Seam tracking: the step limit %.3g mm is below the robot resolution %.3g mm."
                         % (max_step_mm, resolution_mm))
    if int(lost_limit) < 1 or robot_lag_s < 0 or retract_mm < 0 or not corner_hold_mm >= 0:
        raise InputError("Seam tracking: lost_limit must be >= 1, robot_lag_s, retract_mm and "
                         "corner_hold_mm >= 0.")
    if not capture_mm > 0:
        raise InputError("Seam tracking: capture_mm must be > 0, got %r." % (capture_mm,))

    traj = resample(trajectory, dt_s)
    path = PathFrames(traj)
    corners = corner_zones(path.s, path.x)
    time_s, s = traj.time_s, traj.s_mm
    n = len(time_s)
    nominal = traj.position_mm
    tool_z = traj.T_u_t[:, :3, 2]
    X, Y, Z = frame_axes(path.at(s)[1], tool_z)
    sensor = sensor or LaserLineSensor.from_reality(reality, look_ahead_mm=look_ahead_mm)
    scene = LaserScene(real_mesh)
    tool = ToolCollision(reality.foreign_objects, tool_length_mm)
    rng = reality.rng()
    period_s = 1.0 / rate_hz
    per = max(1, int(round(period_s / dt_s)))
    control = _make_controller(controller, gains, rate_hz, max_step_mm)
    offset = np.asarray(template.tcp_offset_mm, dtype=float)
    s_end = path.s[-1]

    applied = np.zeros((n, 3))          # correction the robot applies, {U}, mm
    buffer = LookAheadBuffer(n // per + 1)
    a = np.zeros(3)                     # applied now
    command = np.zeros(3)
    lost = n_lost = n_held = n_other = n_meas = n_steps = 0
    seen = None                         # the last seam point accepted: (needed, its profile's Y, Z)
    largest_step = 0.0
    failure = FailureLog(on_failure, time_s, s)
    stop = None                         # (index, reason)

    steps = Steps(progress, (n + per - 1) // per, "seam tracking")
    for i0 in range(0, n, per):
        steps(i0 // per)
        i1 = min(i0 + per, n)
        applied[i0] = a
        # 1. measure ahead
        s_m = s[i0] + sensor.look_ahead_mm
        if controller != "none" and s_m <= s_end + 1e-9:
            p_m, x_m, _, z_m = path.at(s_m)
            T_u_s = laser_frame(p_m + a, x_m, z_m)
            feature = extract_seam(sensor.profile(T_u_s, scene, rng), template)
            n_meas += 1
            needed = None
            if feature is not None:
                seam_s = np.array([0.0, feature.y_mm + offset[0], feature.z_mm + offset[1]])
                needed = a + T_u_s[:3, :3] @ seam_s       # seam point - nominal point there, {U}
                if seen is not None and _another_joint(needed, seen, capture_mm):
                    needed = None
                    n_other += 1
            if needed is not None:
                buffer.store(s_m, needed, x_m, s[i0])
                seen = (needed, T_u_s[:3, 1:3])
                lost = 0
                failure.clear("seam_lost")
            elif in_hold(corners, s_m, corner_hold_mm):
                n_lost += 1
                n_held += 1
            else:
                lost += 1
                n_lost += 1
                if lost >= lost_limit:
                    message = ("seam lost: no %s joint matched in %d profiles in a row (laser at s = %.1f mm)"
                               % (template.kind, lost, s_m))
                    if failure("seam_lost", message, i0):
                        stop = (i0, message)
                        break
        # 2. control, in the path frame at the TCP
        step = np.zeros(3)
        axes = np.array([X[i0], Y[i0], Z[i0]])                  # rows: path X, Y, Z in {U}
        if len(buffer):
            s_ref = s[min(i0 + per // 2, n - 1)]
            reference = buffer.reference(s_ref)
            if np.linalg.norm(reference) > max_correction_mm:
                message = ("correction beyond its limit: %.2f mm needed at s = %.1f mm, limit %.2f mm"
                           % (np.linalg.norm(reference), s_ref, max_correction_mm))
                if failure("correction_limit", message, i0):
                    stop = (i0, message)
                    break
            else:
                failure.clear("correction_limit")
                du = control.step(axes @ (reference - a), period_s)
                step = _quantised_step(du, resolution_mm, max_step_mm) @ axes
        reachable, stop = check_reach(reach_check, traj.T_u_t[i0], command + step, s[i0], i0,
                                      failure, time_s[i0])
        if stop is not None:
            break
        if not reachable:
            step = np.zeros(3)
        if np.any(step != 0):
            n_steps += 1
            largest_step = max(largest_step, float(np.abs(axes @ step).max()))
        command = command + step
        # 3. the robot follows with its lag, held until the next period; `a` becomes what it
        #    applies at the next period's first sample
        follow = robot_follow(a, command, time_s[i0:min(i1 + 1, n)] - time_s[i0], robot_lag_s)
        applied[i0:i1] = follow[:i1 - i0]
        a = follow[-1]
        stop = check_collision(tool, nominal[i0:i1] + applied[i0:i1], tool_z[i0:i1], i0, s, failure)
        if stop is not None:
            break

    last = n if stop is None else stop[0] + 1
    actual = nominal + applied
    error = np.full(n, np.nan)
    error[:last] = seam_error_mm(actual[:last], X[:last], real_seam_mm)
    open_loop = seam_error_mm(nominal, X, real_seam_mm)

    metrics = {
        **error_metrics(error[:last], s[:last] - s[0], open_loop, largest_step, applied[:last]),
        "n_corrections": n_steps,
        "n_measurements": n_meas,
        "seam_lost_count": n_lost,
        "corners": len(corners),
        "corner_holds": n_held,
        "other_joints": n_other,
        "events": failure.events,
        "rate_hz": float(rate_hz),
        "look_ahead_mm": sensor.look_ahead_mm,
        "stop_s_mm": None,
        "notes": [control.note] if control.note else [],
    }
    if stop is None:
        return finished_run("laser", controller, time_s[:last], nominal[:last], actual[:last],
                            error[:last], metrics)
    return finished_run("laser", controller, time_s[:last], nominal[:last], actual[:last],
                        error[:last], metrics, stop[1], traj.T_u_t[stop[0]], s[stop[0]],
                        retract_mm, retract_speed_mm_s, dt_s)


def finished_run(sensor, controller, time_s, nominal_mm, actual_mm, error_mm, metrics,
                 reason=None, T_stop=None, s_stop_mm=None, retract_mm=50.0,
                 retract_speed_mm_s=50.0, dt_s=0.01):
    """The SensorRun of a seam tracker's samples, with the retract after an abort.

    Parameters
    ----------
    sensor, controller : str
    time_s, nominal_mm, actual_mm, error_mm : ndarray, shape (N,) or (N, 3)
        The samples up to the last one run (the stop, after an abort).
    metrics : dict
        Gets ``stop_s_mm`` after an abort.
    reason : str or None
        Why the run aborted at its last sample; None: it completed.
    T_stop : ndarray, shape (4, 4)
        The nominal TCP pose at the stop: the actual one has its orientation,
        and the retract goes back along its tool -Z.
    s_stop_mm : float
        Path distance of the stop, mm.
    retract_mm, retract_speed_mm_s, dt_s : float
        The retract, sampled every `dt_s`.
    """
    stop_T = index = None
    if reason is not None:
        index = len(time_s) - 1
        stop_T = np.array(T_stop, dtype=float)
        stop_T[:3, 3] = actual_mm[index]
        metrics["stop_s_mm"] = float(s_stop_mm)
        back = _retract_offsets(retract_mm, retract_speed_mm_s, dt_s)[:, None] * T_stop[:3, 2]
        time_s = np.concatenate([time_s, time_s[index] + dt_s * np.arange(1, len(back) + 1)])
        nominal_mm = np.concatenate([nominal_mm, nominal_mm[index] - back])
        actual_mm = np.concatenate([actual_mm, actual_mm[index] - back])
        error_mm = np.concatenate([error_mm, np.full(len(back), np.nan)])
    return SensorRun(sensor=sensor, controller=controller, time_s=time_s, nominal_mm=nominal_mm,
                     actual_mm=actual_mm, correction_mm=actual_mm - nominal_mm, error_mm=error_mm,
                     metrics=metrics, aborted=reason is not None, reason=reason or "",
                     stop_index=index, stop_T_u_t=stop_T)


class FailureLog:
    """A run's failures (module doc): with ``on_failure="abort"`` the first one stops the
    run; with ``"reactive"`` each kind goes into :attr:`events` once while it lasts.

    Parameters
    ----------
    on_failure : str
    time_s, s_mm : ndarray, shape (N,)
        Time and path distance of the run's samples, for the events.
    """

    def __init__(self, on_failure, time_s, s_mm):
        self.abort = on_failure == "abort"
        self.time_s, self.s_mm = time_s, s_mm
        self.events = []        # dicts: kind, message, index, time_s, s_mm
        self.active = set()

    def __call__(self, kind, message, index):
        """A failure at sample `index`: True when the run must stop there."""
        if self.abort:
            return True
        if kind not in self.active:
            self.events.append({"kind": kind, "message": message, "index": int(index),
                                "time_s": float(self.time_s[index]),
                                "s_mm": float(self.s_mm[index])})
            self.active.add(kind)
        return False

    def clear(self, kind):
        """The failure `kind` is over: the next one is a new event."""
        self.active.discard(kind)


def check_reach(reach_check, T_u_t, offset_u, s_mm, index, failure, time_s=None):
    """Can the robot take the nominal pose `T_u_t` moved by `offset_u` (3,) at
    `time_s` (s; where external axes have put the base and the part then)?

    Returns
    -------
    reachable : bool
        True also when there is no `reach_check`.
    stop : (int, str) or None
        Where and why the run stops (an unreachable pose, ``"abort"``).
    """
    if reach_check is None:
        return True, None
    T = T_u_t.copy()
    T[:3, 3] += offset_u
    reason = reach_check(T, time_s)
    if not reason:
        failure.clear("unreachable")
        return True, None
    message = "corrected target unreachable at s = %.1f mm: %s" % (s_mm, reason)
    return False, ((index, message) if failure("unreachable", message, index) else None)


def check_collision(tool, tcp_u, tool_z_u, first, s_mm, failure):
    """Does the tool touch a foreign object at the samples from `first` on?

    Returns
    -------
    (int, str) or None
        Where and why the run stops (``"abort"``), else None.
    """
    hit = tool.first_hit(tcp_u, tool_z_u)
    if hit is None:
        failure.clear("collision")
        return None
    index = first + hit[0]
    message = "collision: the tool touches %s at s = %.1f mm" % (hit[1], s_mm[index])
    return (index, message) if failure("collision", message, index) else None


def robot_follow(applied_u, command_u, elapsed_s, lag_s):
    """The offset the robot applies while it follows a new command with a first-order lag.

    Parameters
    ----------
    applied_u, command_u : ndarray, shape (3,)
        Offset applied when the command changed, and the command, mm.
    elapsed_s : ndarray, shape (N,)
        Times since the command changed, s.
    lag_s : float
        Time constant, s; 0 = at once.

    Returns
    -------
    ndarray, shape (N, 3)
    """
    decay = np.exp(-elapsed_s / lag_s) if lag_s > 0 else np.zeros_like(elapsed_s)
    return command_u + (applied_u - command_u) * decay[:, None]


def _another_joint(needed_u, seen, capture_mm):
    """Whether the correction `needed_u` (3,) puts the seam more than `capture_mm` from the last
    one accepted, ``seen = (needed (3,), axes (3, 2))``, along that profile's Y or Z.

    Only the directions that profile saw count: its travel direction (unseen) may become the
    lateral one of the next leg round a corner.
    """
    needed, axes = seen
    return bool(np.abs((needed_u - needed) @ axes).max() > capture_mm)


def _retract_offsets(retract_mm, speed_mm_s, dt_s):
    """Distances (M,) along -Z of the retract samples, ending at `retract_mm`."""
    if retract_mm <= 0:
        return np.zeros(0)
    steps = int(np.ceil(retract_mm / (speed_mm_s * dt_s) - 1e-9))
    return np.minimum(np.arange(1, steps + 1) * speed_mm_s * dt_s, retract_mm)


def error_metrics(error_mm, travelled_mm, open_loop_mm, largest_step_mm, applied_u):
    """The seam trackers' common metrics (``simulate_seam_tracking``'s Returns).

    Parameters
    ----------
    error_mm, travelled_mm : ndarray, shape (N,)
        The error and the path distance from the start of the samples run.
    open_loop_mm : ndarray, shape (M,)
        The error of the nominal path.
    largest_step_mm : float
    applied_u : ndarray, shape (N, 3)
        The correction applied at those samples.
    """
    return {"rms_error_mm": _rms(error_mm),
            "rms_error_after_20mm_mm": _rms(error_mm[travelled_mm >= SETTLE_DISTANCE_MM]),
            "max_error_mm": _max(error_mm),
            "open_loop_rms_error_mm": _rms(open_loop_mm),
            "open_loop_max_error_mm": _max(open_loop_mm),
            "max_step_mm": round(largest_step_mm, 9),
            "max_correction_mm": float(np.linalg.norm(applied_u, axis=1).max())}


def _rms(values):
    values = np.asarray(values, dtype=float)
    values = values[~np.isnan(values)]
    return float(np.sqrt(np.mean(values ** 2))) if len(values) else float("nan")


def _max(values):
    values = np.asarray(values, dtype=float)
    values = values[~np.isnan(values)]
    return float(values.max()) if len(values) else float("nan")
