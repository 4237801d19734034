"""Everything one sensor simulation needs, as plain data.

The App layer reads the document once into a :class:`SensorScene`;
:func:`run_scene` then runs it for any deviation and controller. Scenes are
picklable, so a sweep can run them on other processes or on a Dask cluster
without FreeCAD there.
"""

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from .. import dependencies
from ..core.frames import invert_transform
from ..errors import InputError
from ..robots.checks import checks
from ..robots.kinematics import models
from ..robots.motion import configuration, playback
from .reality import Reality

SENSORS = ("laser", "force", "arc")
CONTROLLERS = ("pi", "fuzzy_pi", "none")


@dataclass
class AxesAlongPath:
    """The external axes (a track, a positioner) along a scene's trajectory.

    A sensor scene of a cell with external axes is simulated in the part's
    frame: {U} with the positioner at its drawn values, the frame that rides on
    its flange (the trajectory, the workpiece and the deviation are drawn
    there; a coordinated work object holds the corrections there too). At
    time t the part is at ``T_u_part(t)`` in the real {U}, and in the robot
    base (moved by a track) at ``T_r_part(t)``.

    unverified: that the controllers apply a seam tracker's corrections in the
    coordinated work object (ABB's work object moved by ``ufmec``, FANUC
    ``COORD``, Yaskawa's station coordination) rather than in {R}; no maker's
    document on path correction with coordinated motion was read. Gravity is
    not in the loops, so nothing else of the sensors changes with the part's
    turn.

    Attributes
    ----------
    external : core.mechanisms.ExternalAxes
    time_s : ndarray, shape (N,)
        The trajectory's times, s.
    values : ndarray, shape (N, E)
        The axis values there (``playback.external_along``), mm / deg.
    riding : ndarray of bool, shape (N,)
        Whether the sample's work frame rides on the positioner.
    """

    external: object
    time_s: np.ndarray
    values: np.ndarray
    riding: np.ndarray

    def values_at(self, time_s):
        """ndarray, shape (E,) or (M, E): the values at `time_s` (scalar or (M,)),
        linear between samples (as along a move), held beyond the ends."""
        t = np.asarray(time_s, dtype=float)
        return np.stack([np.interp(t, self.time_s, column) for column in self.values.T], axis=-1)

    def T_u_part(self, time_s):
        """ndarray, shape (4, 4) or (M, 4, 4): the part's frame in {U} at `time_s`
        (``positioner.motion``; the identity where the work frame stands still)."""
        t = np.asarray(time_s, dtype=float)
        moving = self.riding[np.clip(np.searchsorted(self.time_s, t), 0, len(self.time_s) - 1)]
        positioner = self.external.split(self.values_at(t))[1]
        if positioner is None:
            return np.broadcast_to(np.eye(4), t.shape + (4, 4)).copy()
        return np.where(np.asarray(moving)[..., None, None],
                        self.external.positioner.motion(positioner), np.eye(4))

    def T_r_part(self, time_s):
        """ndarray, shape (4, 4) or (M, 4, 4): the part's frame in the robot base at
        `time_s` (the base moved by the track)."""
        values = self.values_at(time_s)
        return invert_transform(self.external.T_u_r_at(values)) @ self.T_u_part(time_s)

    def in_assembly(self, time_s, points_mm):
        """Points (M, 3) of the part's frame at times (M,) in the real {U}, mm."""
        T = self.T_u_part(np.asarray(time_s, dtype=float))
        return np.einsum("mij,mj->mi", T[:, :3, :3], np.asarray(points_mm, float)) + T[:, :3, 3]


def axes_along(program, trajectory):
    """The program's external axes along `trajectory` (a :func:`core.trajectory.tcp_trajectory`
    of it), with the values its targets were given (``robots.mechanisms.choose``), or None
    without external axes.

    Returns
    -------
    AxesAlongPath or None
    """
    external = getattr(program, "external", None)
    if external is None:
        return None
    moves = program.moves()
    riding = np.array([moves[int(k)].frame in external.moving_frames
                       for k in trajectory.move_index], dtype=bool)
    return AxesAlongPath(external, np.asarray(trajectory.time_s, dtype=float),
                         playback.external_along(program, trajectory), riding)


@dataclass
class RobotSetup:
    """The robot that executes the corrected path.

    Attributes
    ----------
    robot : str
        Catalog name.
    T_r_u : ndarray, shape (4, 4)
        The assembly frame {U} in the robot base {R}, mm.
    T_f_t : ndarray, shape (4, 4)
        The TCP in the flange frame, mm.
    axes : AxesAlongPath or None
        The track and positioner moving the base and the part in time; then
        poses are in the part's frame and `T_r_u` is unused.
    """

    robot: str
    T_r_u: np.ndarray
    T_f_t: np.ndarray
    axes: Optional[AxesAlongPath] = None

    def T_r_part(self, time_s=None):
        """ndarray, shape (4, 4): the frame the scene's poses are in, in the robot
        base at `time_s` (`T_r_u` without external axes)."""
        if self.axes is None:
            return self.T_r_u
        return self.axes.T_r_part(0.0 if time_s is None else time_s)

    def reach_check(self, margins=None):
        """A function ``(T_u_t (4, 4), time_s) -> None | str``: None when the
        robot can take the TCP pose at that time (the base and the part where
        the external axes put them) within its joint limits and away from its
        singularities, else why not. It prefers the branch closest to the
        joints of its previous call (the path is continuous)."""
        model = models.model(self.robot)
        margins = margins or checks.Margins()
        T_t_f = invert_transform(self.T_f_t)
        previous = [None]

        def check(T_u_t, time_s=None):
            Q = model.ik((self.T_r_part(time_s) @ T_u_t @ T_t_f)[None])[0]
            ok = ~np.isnan(Q).any(axis=1) & model.within_limits(Q)
            if not ok.any():
                return "the corrected pose is out of the robot's reach or beyond its joint limits"
            candidates = Q[ok]
            if previous[0] is not None:
                candidates = candidates[np.argsort(np.abs(candidates - previous[0]).max(axis=1))]
            q = previous[0] = candidates[0]
            shoulder, elbow, wrist = configuration.arm_geometry(q, model.spec).singularity_distances()
            if wrist < margins.wrist_deg:
                return "the corrected pose is %.1f° from %s" % (wrist, (
                    "a singularity of the arm" if configuration.singular_on_jacobian(model.spec)
                    else "the wrist singularity"))
            if shoulder < margins.shoulder_mm:
                return "the corrected pose is %.0f mm from the shoulder singularity" % shoulder
            if elbow < margins.elbow_deg:
                return "the corrected pose is %.1f° from the elbow singularity" % elbow
            return None

        return check


@dataclass
class SensorScene:
    """One path of a cell, ready to simulate with a sensor.

    Attributes
    ----------
    sensor : str
        ``"laser"``, ``"force"`` or ``"arc"`` (through-arc tracking: `options`
        carry the weld's ``weave``, ``schedule``, ``tracking`` and
        ``weld_label``, and `trajectory` is the weld's stretch of the path).
    path_label : str
    trajectory : core.trajectory.Trajectory
        The nominal TCP path (the path's moves only), in {U} (with a
        positioner: in the part's frame, :class:`AxesAlongPath`).
    workpiece : list of (str, trimesh.Trimesh)
        The workpiece as drawn, in {U} (the same frame), mm.
    robot : RobotSetup
    options : dict
        Keyword arguments for the sensor's ``simulate_*`` function
        (template, gains, limits, ...).
    program : core Program or None
        The program the trajectory comes from (for a resume program).
    """

    sensor: str
    path_label: str
    trajectory: object
    workpiece: list
    robot: RobotSetup
    options: dict = field(default_factory=dict)
    program: object = None


# Longest mesh edge when a bend must show on a workpiece meshed with few triangles, mm.
BEND_EDGE_MM = 5.0


def bent_points(points_mm, trajectory, reality):
    """CAD points moved by the workpiece's bend (before the rigid deviation).

    Each point moves ``bend_mm * sin(pi * s / L)`` along the bend direction,
    s being the path distance of the path sample nearest to it.
    """
    points = np.asarray(points_mm, dtype=float)
    if not reality.bend_mm:
        return points
    from scipy.spatial import cKDTree
    _, nearest = cKDTree(trajectory.position_mm).query(points)
    length = max(float(trajectory.s_mm[-1]), 1e-9)
    direction = np.asarray(reality.bend_direction, float) / np.linalg.norm(reality.bend_direction)
    return points + reality.bend_mm * np.sin(np.pi * trajectory.s_mm[nearest] / length)[:, None] * direction


def real_seam(scene, reality):
    """(N, 3) the path where it really is on the workpiece, {U}, mm."""
    return reality.rigid_points(bent_points(scene.trajectory.position_mm, scene.trajectory, reality))


def real_mesh(scene, reality):
    """The workpiece where it really is (and the foreign objects), one trimesh in {U}."""
    trimesh = dependencies.require("trimesh")
    parts = []
    for _, mesh in scene.workpiece:
        if reality.bend_mm:
            vertices, faces = trimesh.remesh.subdivide_to_size(mesh.vertices, mesh.faces, BEND_EDGE_MM)
            mesh = trimesh.Trimesh(bent_points(vertices, scene.trajectory, reality), faces)
        moved = mesh.copy()
        moved.apply_transform(reality.T_u_dev)
        parts.append(moved)
    parts += [mesh for _, mesh in reality.foreign_objects]
    return trimesh.util.concatenate(parts)


def run_scene(scene, reality=None, controller="pi", rate_hz=None, **options):
    """Run the scene's sensor loop in a (possibly deviated) reality.

    Parameters
    ----------
    scene : SensorScene
    reality : Reality, optional
        Default: the cell as drawn.
    controller : str
        ``"pi"``, ``"fuzzy_pi"`` or ``"none"`` (open loop).
    rate_hz : float, optional
        Correction rate; default the sensor's (5 Hz laser, 20 Hz force; the
        arc corrects once per weave cycle and refuses a rate).
    **options
        Override the scene's options.

    Returns
    -------
    SensorRun
    """
    if controller not in CONTROLLERS:
        raise InputError("Unknown controller '%s'; use one of %s." % (controller, ", ".join(CONTROLLERS)))
    reality = reality or Reality()
    kwargs = dict(scene.options, **options)
    kwargs["controller"] = controller
    kwargs["reach_check"] = scene.robot.reach_check()
    if rate_hz:
        kwargs["rate_hz"] = float(rate_hz)
    mesh = real_mesh(scene, reality)
    if scene.sensor == "laser":
        from .seam_tracking import simulate_seam_tracking
        return simulate_seam_tracking(scene.trajectory, mesh, real_seam(scene, reality), reality,
                                      **kwargs)
    if scene.sensor == "force":
        from .force_following import simulate_force_following
        kwargs.setdefault("drawn_mesh", real_mesh(scene, Reality()))    # the part as drawn
        return simulate_force_following(scene.trajectory, mesh, reality, **kwargs)
    if scene.sensor == "arc":
        from .arc_tracking import simulate_arc_tracking
        return simulate_arc_tracking(scene.trajectory, mesh, real_seam(scene, reality), reality,
                                     **kwargs)
    raise InputError("Unknown sensor '%s'; use 'laser', 'force' or 'arc'." % scene.sensor)
