"""Sensor simulations of a cell (paper section 4): the document read into a
:class:`sensors.scene.SensorScene`, run with a deviation of the real part.

App layer: reads FreeCAD objects; the loops themselves are in ``sensors/``.
"""

import numpy as np

import FreeCAD

from . import limits
from .core import program as ir
from .core.generate import generate as generate_program
from .core.progress import Steps, report_now, stage
from .core.trajectory import tcp_trajectory
from .errors import InputError
from .objects import base, joint_faces, reader
from .objects.convert import matrix_from_placement
from .objects.validate import check_rigid, finite_values
from .objects.obstacles import is_final_solid, solid_meshes
from .robots.motion import playback
from .sensors.reality import Reality
from .sensors.scene import SENSORS, RobotSetup, SensorScene, axes_along
from .core.frames import invert_transform

# A solid is part of the workpiece when it comes this close to the path.
WORKPIECE_DISTANCE_MM = 20.0
#: Path samples tried one by one before the whole path (see _near_path).
NEAR_PATH_SAMPLES = 8
PATH_ROLES = (ir.ROLE_PATH, ir.ROLE_RISK, ir.ROLE_REORIENT)
DEFAULT_DT_S = {"laser": 0.01, "force": 0.005, "arc": 0.002}
SENSOR_WORDS = "use 'laser', 'force' or 'arc'"


def deviation_matrix(deviation, centre_mm=(0.0, 0.0, 0.0)):
    """4x4 rigid deviation in {U}.

    Parameters
    ----------
    deviation : FreeCAD.Placement, ndarray (4, 4), six numbers or None
        A Placement or matrix is used as it is (a displacement in {U}). Six
        numbers x, y, z (mm), rx, ry, rz (degrees, about the fixed X, Y, Z
        axes in that order) turn the part about `centre_mm`, then move it:
        "turned 1°" then means turned where the part is, not about {U}'s
        origin.
    centre_mm : array_like, shape (3,)
    """
    if deviation is None:
        return np.eye(4)
    if isinstance(deviation, FreeCAD.Placement):
        return check_rigid(matrix_from_placement(deviation), "The deviation")
    try:
        values = np.asarray(deviation, dtype=float)
    except (TypeError, ValueError):
        values = np.zeros(0)
    if values.shape == (4, 4):
        return check_rigid(values, "The deviation")
    if values.shape == (6,):
        from .sweep import deviation_transform
        finite_values(values, "The deviation x,y,z,rx,ry,rz")
        return deviation_transform(values, centre_mm)
    raise InputError("A deviation is a FreeCAD.Placement, a 4x4 matrix or x,y,z,rx,ry,rz "
                     "(mm and degrees); got %r." % (deviation,))


def _chosen_path(program, path_label):
    wanted = [p for p in program.paths if path_label in (None, p.label, p.name)]
    if not wanted:
        raise InputError("The cell has no path '%s'. Paths: %s." % (
            path_label, ", ".join(p.label for p in program.paths)))
    return wanted[0]


def _path_moves(program, path_label):
    moves = program.moves()
    chosen = _chosen_path(program, path_label)
    indices = [i for i, m in enumerate(moves) if m in chosen.moves and m.role in PATH_ROLES]
    return chosen.label, indices[0], indices[-1]


def _near_path(shape, samples, polyline):
    """Whether `shape` comes within :data:`WORKPIECE_DISTANCE_MM` of the path.

    The same answer as ``shape.distToShape(polyline)``, sooner: a solid whose box is
    further away is not near; the path usually lies on its workpiece, so one of the
    samples (N, 3) in its box is near at once (about 40 ms each on a machined part, where
    the whole polyline of 200 samples takes 7 s); only a solid none of
    :data:`NEAR_PATH_SAMPLES` of them is near needs the polyline, whose segments may
    pass nearer than their ends.
    """
    box = shape.BoundBox
    box.enlarge(WORKPIECE_DISTANCE_MM)
    if not box.intersect(polyline.BoundBox):
        return False
    import Part
    inside = [FreeCAD.Vector(*p) for p in samples if box.isInside(FreeCAD.Vector(*p))]
    for point in inside[::max(1, len(inside) // NEAR_PATH_SAMPLES)][:NEAR_PATH_SAMPLES]:
        if shape.distToShape(Part.Vertex(point))[0] <= WORKPIECE_DISTANCE_MM:
            return True
    return shape.distToShape(polyline)[0] <= WORKPIECE_DISTANCE_MM


def _workpiece(cell, trajectory, progress=None):
    """The workpiece solids: the cell's Workpiece property, else the solids near the path
    (`progress` told object by object)."""
    import Part
    objects = list(cell.Workpiece) if cell.Workpiece else None
    if objects is None:
        samples = trajectory.position_mm[:: max(1, len(trajectory.position_mm) // 200)]
        polyline = Part.makePolygon([FreeCAD.Vector(*p) for p in samples])
        objects = []
        steps = Steps(stage(progress, 0.0, 0.5), len(cell.Document.Objects), "finding the workpiece")
        for k, obj in enumerate(cell.Document.Objects):
            steps(k)
            if not is_final_solid(obj):
                continue
            shape = obj.Shape.copy()
            shape.Placement = base.global_placement(obj)
            if _near_path(shape, samples, polyline):
                objects.append(obj)
        if not objects:
            raise InputError("Cell %s: no solid lies within %.0f mm of the path, so there is no "
                             "workpiece to sense. Set the cell's Workpiece property."
                             % (base.describe(cell), WORKPIECE_DISTANCE_MM), cell.Name)
    return solid_meshes(cell.Document, np.eye(4), objects=objects, progress=stage(progress, 0.5, 1.0))


def detected_options(sensor, detection):
    """The sensor loop's options the path's joint gives: the laser looks for the joint the
    faces along the path make (``template``), the arc takes the walls' angle
    (``wall_angle_deg``).

    Parameters
    ----------
    sensor : str
    detection : PathFit or None
        :func:`path_fit` of the path.

    Returns
    -------
    dict
        Empty where the detection gives nothing for the sensor.
    """
    if detection is None:
        return {}
    if sensor == "laser" and detection.template() is not None:
        return {"template": detection.template()}
    if sensor == "arc" and detection.wall_angle_deg() is not None:
        return {"wall_angle_deg": detection.wall_angle_deg()}
    return {}


def read_scene(cell, sensor, path=None, dt_s=None, progress=None, **options):
    """The :class:`SensorScene` of one path of `cell`.

    Parameters
    ----------
    sensor : str
        ``"laser"``, ``"force"`` or ``"arc"`` (through-arc tracking of the
        path's weld: its weave, schedule and tracking go into the scene's
        options, its stretch of the path is the trajectory; option ``weld``
        names it, default the path's first).
    path : str, optional
        Label or name of the path; default the cell's first.
    dt_s : float, optional
        Simulation time step; default 10 ms (laser), 5 ms (force), 2 ms (arc).
    progress : callable, optional
        ``progress(fraction, text)`` (:mod:`.core.progress`); returning False
        raises ``Cancelled``.  Reading changes nothing in the document.
    **options
        Passed to the sensor's ``simulate_*`` function.
    """
    if sensor not in SENSORS:
        raise InputError("Unknown sensor '%s'; %s." % (sensor, SENSOR_WORDS))
    spec = reader.read_cell(cell, progress=stage(progress, 0.0, 0.4))
    program = generate_program(spec, progress=stage(progress, 0.4, 0.6))
    _choose_external_axes(cell, spec, program)
    if sensor == "arc":
        from .sensors.arc_tracking import weld_to_track
        chosen = _chosen_path(program, path)
        run, first, last = weld_to_track(program, chosen, options.pop("weld", None))
        label = chosen.label
        options.update(weave=run.weave, schedule=run.schedule, weld_label=run.label,
                       tracking=run.tracking if run.tracking.sensor == "arc" else None)
    else:
        label, first, last = _path_moves(program, path)
    trajectory = tcp_trajectory(program, dt_s or DEFAULT_DT_S[sensor], first, last,
                                progress=stage(progress, 0.6, 0.7))
    # Where the robot stands relative to the part: the same rule as api.check (a taught
    # frame fixes the part relative to the robot, wherever the cell's Placement is).
    T_u_r = playback.robot_base(program, spec.T_u_r).T_u_r
    robot = RobotSetup(program.robot, invert_transform(T_u_r), program.tool.T_f_t,
                       axes_along(program, trajectory))
    workpiece = _workpiece(cell, trajectory, stage(progress, 0.7, 1.0))
    report_now(progress, 1.0, "reading the workpiece")
    return SensorScene(sensor, label, trajectory, workpiece, robot, dict(options), program)


def _choose_external_axes(cell, spec, program):
    """Give `program` the cell's track and positioner and their values at every target,
    as ``api.generate`` does (nothing without external axes)."""
    from .robots.kinematics import models
    from .workflow.common import start_joints
    from .workflow.mechanisms import use_external_axes
    use_external_axes(cell, spec, program, models.model(program.robot), start_joints(cell))


def reality_of(deviation=None, centre_mm=(0.0, 0.0, 0.0), **settings):
    """A :class:`Reality` with the rigid `deviation` (see :func:`deviation_matrix`)."""
    return Reality(T_u_dev=deviation_matrix(deviation, centre_mm), **settings)


def _with_joints(program):
    from .robots.kinematics import models
    from .robots.motion import configuration
    configuration.solve_program(program, models.model(program.robot))
    return program


def resume_after(scene, run):
    """The program that restarts the path where an aborted `run` stopped
    (joints solved for the scene's robot), or None if the run did not stop."""
    if not run.aborted or run.stop_T_u_t is None or scene.program is None:
        return None
    from .core.resume import resume_program
    traj = scene.trajectory
    sample = min(np.searchsorted(traj.time_s, run.time_s[run.stop_index]), len(traj.time_s) - 1)
    axes = scene.robot.axes
    at_stop = None if axes is None else axes.values_at(run.time_s[run.stop_index])
    return _with_joints(resume_program(scene.program, int(traj.move_index[sample]), run.stop_T_u_t,
                                       external_at_stop=at_stop))


def corrected_after(scene, run, tolerance_mm=None, angle_tolerance_deg=None):
    """The program that follows the corrected path of a closed-loop `run`
    (lines and arcs fitted within the tolerances, see
    :func:`sensors.corrected_program.fit_corrected_path`; joints solved), or
    None for an open-loop or aborted run. Records the move counts in
    ``run.metrics`` (:func:`note_corrected_moves`)."""
    if run.controller == "none" or run.aborted or scene.program is None:
        return None
    from .sensors.corrected_program import corrected_program
    fitted = note_corrected_moves(scene, run, tolerance_mm, angle_tolerance_deg)
    return _with_joints(corrected_program(scene, run, fitted=fitted))


def note_corrected_moves(scene, run, tolerance_mm=None, angle_tolerance_deg=None):
    """Fit the corrected path of a closed-loop, completed `run` and record in
    ``run.metrics``: ``corrected_samples`` (poses before fitting),
    ``corrected_moves`` (path moves after), ``corrected_arcs`` (of them,
    circular) and ``corrected_tolerance_mm``.

    The fit is kept on the run, so asking again with the same tolerances
    (the CLI's corrected program after the report) does not fit again.

    Returns
    -------
    sensors.corrected_program.CorrectedPath or None
        None (nothing recorded) for an open-loop or aborted run.
    """
    if run.controller == "none" or run.aborted or scene.program is None:
        return None
    from .sensors import corrected_program as cp
    tolerances = (cp.DEFAULT_TOLERANCE_MM if tolerance_mm is None else tolerance_mm,
                  cp.DEFAULT_ANGLE_TOLERANCE_DEG if angle_tolerance_deg is None
                  else angle_tolerance_deg)
    if run.corrected_fit is not None and run.corrected_fit[0] == tolerances:
        fitted = run.corrected_fit[1]
    else:
        fitted = cp.fit_corrected_path(scene, run, *tolerances)
        run.corrected_fit = (tolerances, fitted)
    counts = fitted.counts()
    run.metrics.update(corrected_samples=counts["samples"], corrected_moves=counts["moves"],
                       corrected_arcs=counts["arcs"], corrected_tolerance_mm=fitted.tolerance_mm)
    return fitted


def check_rate(sensor, rate_hz, dt_s=None):
    """`rate_hz` if None or a rate in [``limits.MIN_RATE_HZ``, 1/dt] Hz, else InputError.

    Parameters
    ----------
    sensor : str
        ``"laser"``, ``"force"`` or ``"arc"`` (the default time step dt).
    rate_hz : float or None
    dt_s : float, optional
        The simulation time step; default the sensor's.
    """
    if rate_hz is None:
        return None
    if sensor not in SENSORS:
        raise InputError("Unknown sensor '%s'; %s." % (sensor, SENSOR_WORDS))
    if sensor == "arc":
        raise InputError("Through-arc tracking corrects once per weave cycle: leave the rate "
                         "out (change the weave's frequency instead).")
    highest = 1.0 / (dt_s or DEFAULT_DT_S[sensor])
    return limits.rate_hz(rate_hz, "The %s correction rate (Hz)" % sensor, highest)


REALITY_SETTINGS = ("bend_mm", "bend_direction", "roughness_mm", "roughness_wavelength_mm",
                    "laser_noise_mm", "force_noise_n", "arc_current_noise_a", "seed")
#: A run's name in the progress text.
RUN_NAMES = {"laser": "seam tracking", "force": "force following",
             "arc": "through-arc tracking"}


def simulate_cell(cell, sensor, controllers=("pi",), deviation=None, rate_hz=None, path=None,
                  foreign_objects=(), progress=None, **options):
    """Run one path of `cell` with a sensor, once per controller, in one reality.

    Parameters
    ----------
    sensor : str
        ``"laser"``, ``"force"`` or ``"arc"``.
    controllers : sequence of str
        ``"pi"``, ``"fuzzy_pi"``, ``"none"`` (open loop); the arc: ``"pi"``
        (its per-cycle law) or ``"none"``.
    deviation
        Rigid displacement of the real workpiece in {U} (see :func:`deviation_matrix`);
        with a positioner, of the part where the document draws it (the
        positioner at its drawn values), and it turns with the part.
    foreign_objects : sequence of App.DocumentObject
        Solids of the document that stand in the real cell but not in the
        drawing the program was made from (with a positioner: only solids
        riding on it, :func:`check_foreign_objects_ride`).
    progress : callable, optional
        ``progress(fraction, text)`` (:mod:`.core.progress`): reading the
        scene, then each controller's run; returning False raises
        ``Cancelled``.  Nothing is written into the document.
    **options
        Reality settings (``bend_mm``, ``roughness_mm``, ``laser_noise_mm``,
        ``force_noise_n``, ``seed``, ...), ``dt_s``, ``detection`` (the
        path's :func:`path_fit`, when already known), and options of the
        sensor loop. The laser looks for the joint the detection found
        (its ``template``) unless a ``template`` is given; the arc takes the
        walls' angle from it (``wall_angle_deg``) and ``weld`` names the weld
        it tracks (default the path's first).

    Each run's ``notes`` say once when the sensor does not suit the path or
    the cell's tool is not the one the sensor needs (the run still runs).

    Returns
    -------
    scene : SensorScene
    reality : Reality
    runs : list of SensorRun
        One per controller, in the order given.
    """
    from .sensors.scene import run_scene
    check_rate(sensor, rate_hz, options.get("dt_s"))
    detection = options.pop("detection", None) or path_fit(cell, path)
    notes = joint_faces.sensor_notes(cell, sensor, detection)
    options = dict(detected_options(sensor, detection), **options)
    settings = {k: options.pop(k) for k in list(options) if k in REALITY_SETTINGS}
    if "seed" in settings:
        limits.seed(settings["seed"], "The simulation's seed")
    check_foreign_objects_ride(cell, foreign_objects)
    foreign = solid_meshes(cell.Document, np.eye(4), objects=list(foreign_objects)) if foreign_objects else []
    weld = {"weld": options.pop("weld")} if "weld" in options else {}
    dt_s = options.pop("dt_s", None)
    if dt_s is not None:        # the loop's time step too, not only the trajectory's
        options["dt_s"] = dt_s
    scene = read_scene(cell, sensor, path=path, dt_s=dt_s,
                       progress=stage(progress, 0.0, 0.2), **weld)
    # Six-number deviations turn the part about the path's start.
    reality = reality_of(deviation, scene.trajectory.position_mm[0], foreign_objects=foreign, **settings)
    share = 0.75 / max(len(controllers), 1)
    runs = []
    for k, controller in enumerate(controllers):
        part = stage(progress, 0.2 + k * share, 0.2 + (k + 1) * share)
        label = "%s, controller %s" % (RUN_NAMES[sensor], controller)
        runs.append(run_scene(scene, reality, controller, rate_hz, **options,
                              **({} if part is None else
                                 {"progress": lambda f, _text, part=part, label=label: part(f, label)})))
    notes = [*notes, *axes_notes(cell, scene)]
    report_now(progress, 0.95, "fitting the corrected path")
    for run in runs:   # the move counts of the corrected program, in each run's metrics
        note_corrected_moves(scene, run)
        run.notes.extend(notes)
    report_now(progress, 1.0, "done")
    return scene, reality, runs


def check_foreign_objects_ride(cell, foreign_objects):
    """InputError naming the first foreign object that does not ride on the cell's
    positioner: with one, the run is simulated in the part's frame, which carries
    the foreign objects along with the part (a clamp, a tack, spatter on it)."""
    external = reader.read_external(cell) if foreign_objects else None
    if external is None or external.positioner is None:
        return
    riding = set(external.riding_solids)
    for obj in foreign_objects:
        if obj.Label not in riding:
            raise InputError("Foreign object %s does not ride on positioner '%s' of cell %s: a "
                             "sensor run with a positioner takes foreign objects on the part only; "
                             "add it to the positioner's Parts or leave it out."
                             % (base.describe(obj), external.positioner.label,
                                base.describe(cell)), obj.Name)


def axes_notes(cell, scene):
    """What a run of a cell with external axes says once: what moves, and the frame
    its positions are in (nothing without external axes)."""
    axes = scene.robot.axes
    if axes is None:
        return []
    external = axes.external
    moved = " and ".join("the %s '%s'" % (m.kind.replace("_", "-"), m.label)
                         for m in external.mechanisms())
    note = "Cell %s: %s moved as the program's external values say" % (base.describe(cell), moved)
    if external.positioner is None:
        return [note + "."]
    return [note + "; positions are in the part's frame ({U} with the positioner at its drawn "
            "values), where the controller applies the corrections (a coordinated work object)."]


def arc_why_not(cell, detection=None, path=None):
    """Why through-arc tracking is not offered on the path ("" when it is).

    It needs a weld on the path, a weave on it, and a joint with sidewalls
    (``detection.why_not("arc")``: a square butt joint has none).

    Parameters
    ----------
    cell : App.DocumentObject
    detection : sensors.joint_detection.JointDetection, optional
        The path's joint detection (:func:`path_fit`), when known.
    path : str, optional
        Label or name of the path; default the cell's first.

    Returns
    -------
    str
        One sentence without its full stop, or "".
    """
    from .errors import CadRobotError
    from .sensors.joint_detection import NO_WEAVE
    try:
        spec = reader.read_cell(cell)
    except CadRobotError as exc:
        return str(exc).rstrip(".")
    paths = [p for p in spec.paths if path in (None, p.label, p.name)]
    welds = list(getattr(paths[0], "welds", None) or []) if paths else []
    if not welds:
        return ("the path has no weld: through-arc tracking senses the arc of a weld; add a "
                "Weld with a weave")
    if all(w.weave is None for w in welds):
        return NO_WEAVE
    return detection.why_not("arc") if detection is not None else ""


def path_fit(cell, path=None):
    """The joint detection of the path (:func:`objects.joint_faces.detect`), or
    None when the faces along it cannot be read (the run then goes on without)."""
    from .errors import CadRobotError
    try:
        return path_fit_or_raise(cell, path)
    except CadRobotError:
        return None


def path_fit_or_raise(cell, path=None):
    """The joint detection of the path; CadRobotError when it cannot be read."""
    return joint_faces.detect(cell, path)
