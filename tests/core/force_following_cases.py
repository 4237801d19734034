"""Force-following runs whose outputs are recorded (test_force_following_golden.py).

The outputs of ``simulate_force_following`` -- every step's time, nominal and
actual TCP position, correction, gap and sensor reading, the report's metrics
and events, the stop -- were recorded with the implementation of commit
3790da5 (one step at a time, before issue 12's speed-up) in
``data/force_following_golden.npz``; the test checks that the code still
gives them. The cases:

* ``bench_*``: the benchmark's case (bench/bench_force.py), 10 s of it, per
  controller;
* ``cell_*``: the example profile-following cell (examples/
  profile_following_cell.py) as ``api.simulate(cell, sensor="force", ...)``
  runs it; its scene (the path, the workpiece mesh, the robot) was read in
  FreeCAD once into ``data/profile_following_scene.npz`` (``--capture-scene``
  below), so the run needs no FreeCAD;
* the rest: the scenes of test_force_following.py, one per failure branch
  (abort and reactive), recorded every 20th step plus each array's sum and
  sum of magnitudes over all steps.

Record again (only when the physics change on purpose)::

    PYTHONPATH=$(bash tools/setup.sh --print-packages-dir):. \\
        /usr/bin/python3 tests/core/force_following_cases.py --record
    python3 tools/freecad_run.py --clean-stdout tests/core/force_following_cases.py \\
        --capture-scene                                 # the cell's scene, in FreeCAD
"""

import importlib.util
import json
import os
import sys

import numpy as np
import trimesh

from CadRobotWB.core.trajectory import Trajectory
from CadRobotWB.sensors.force_following import simulate_force_following
from CadRobotWB.sensors.reality import Reality
from CadRobotWB.sensors.scene import RobotSetup, SensorScene, run_scene

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
GOLDEN_PATH = os.path.join(HERE, "data", "force_following_golden.npz")
SCENE_PATH = os.path.join(HERE, "data", "profile_following_scene.npz")
#: Runs stored at every step; the others every SPARSE_EVERY-th step.
SPARSE_EVERY = 20
#: The arrays of a SensorRun that are recorded (its correction_mm is actual - nominal).
ARRAYS = ("time_s", "nominal_mm", "actual_mm", "error_mm", "force_n")
#: The cell's deviations: the part 3 mm below / above its CAD pose ({U} Z).
CELL_DEVIATIONS = {"down": (0, 0, -3, 0, 0, 0), "up": (0, 0, 3, 0, 0, 0)}
BENCH_SECONDS = 10.0


# ------------------------------------------------------------------ the cases

def _bench_module():
    """bench/bench_force.py as a module (importing it does not pin the process)."""
    spec = importlib.util.spec_from_file_location("bench_force",
                                                  os.path.join(REPO, "bench", "bench_force.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _bench_run(controller):
    nominal, real, reality = _bench_module().bench_case(BENCH_SECONDS, 0.005)
    return simulate_force_following(nominal, real, reality, controller=controller, dt_s=0.005)


def _cell_scene():
    """The example cell's SensorScene and its realities, from data/profile_following_scene.npz."""
    with np.load(SCENE_PATH) as data:
        trajectory = Trajectory(data["time_s"], data["T_u_t"], data["s_mm"], data["move_index"])
        mesh = trimesh.Trimesh(data["vertices"], data["faces"], process=False)
        robot = RobotSetup(str(data["robot"]), data["T_r_u"], data["T_f_t"])
        realities = {name: Reality(T_u_dev=data["T_u_dev_" + name]) for name in CELL_DEVIATIONS}
        scene = SensorScene("force", str(data["path_label"]), trajectory,
                            [(str(data["workpiece_name"]), mesh)], robot)
    return scene, realities


def _cell_run(deviation, controller):
    scene, realities = _cell_scene()
    return run_scene(scene, realities[deviation], controller)


def _scenario_runs():
    """name -> zero-argument function giving the run, for test_force_following's scenes."""
    import test_force_following as t

    def paper(dz, controller):
        real, reality = t.shifted(t.cylinder_patch(), dz)
        return simulate_force_following(t.arc_trajectory(), real, reality, force_set_n=t.F_SET,
                                        controller=controller)

    def line(mesh, reality, **options):
        return lambda: simulate_force_following(t.line_trajectory(), mesh, reality, **options)

    def past_150(T, _time_s=None):
        return "outside the work area" if T[0, 3] > 150.0 else None

    def too_deep(T, _time_s=None):
        return "wrist singularity" if T[2, 3] < -4.5 else None

    def too_deep_before_100(T, _time_s=None):
        return "wrist singularity" if T[0, 3] < 100.0 and T[2, 3] < -4.5 else None

    clamp = Reality(foreign_objects=[("Clamp", t.box([100, -20, -3], [120, 20, 10]))])
    ramp = t.profile_sheet([-50.0, 100.0, 110.0, 250.0], [-3.0, -3.0, 2.0, 2.0])
    wall = trimesh.util.concatenate([t.flat(-3.0), t.box([100, -40, -3], [250, 40, 0])])
    rough = Reality(force_noise_n=0.0, roughness_mm=0.02, roughness_wavelength_mm=2.0, seed=3)
    runs = {"paper_%s_%s" % (name, controller): (lambda dz=dz, c=controller: paper(dz, c))
            for name, dz in (("away", t.AWAY), ("into", t.INTO))
            for controller in ("none", "pi", "fuzzy_pi")}
    runs.update({
        "smooth_pi": line(t.flat(-3.0), Reality(force_noise_n=0.0), controller="pi"),
        "rough_fuzzy_pi": line(t.flat(-3.0), rough, controller="fuzzy_pi"),
        "damped_pi": line(t.flat(-3.0), rough, controller="pi", damping_n_s_mm=0.05),
        "clamp_abort": line(t.flat(-3.0), clamp),
        "clamp_reactive": line(t.flat(-3.0), clamp, on_failure="reactive"),
        "ramp_abort": line(ramp, Reality(), max_force_n=30.0),
        "ramp_reactive": line(ramp, Reality(), max_force_n=30.0, on_failure="reactive"),
        "ramp_open_loop_reactive": line(ramp, Reality(), controller="none", max_force_n=30.0,
                                        on_failure="reactive"),
        "wall_reactive": line(wall, Reality(), on_failure="reactive"),
        "far_abort": line(t.flat(-20.0), Reality()),
        "far_reactive": line(t.flat(-20.0), Reality(), on_failure="reactive"),
        "short_abort": line(t.flat(-3.0, x1=100.0), Reality()),
        "short_reactive": line(t.flat(-3.0, x1=100.0), Reality(), on_failure="reactive"),
        "unreachable_abort": line(t.flat(-3.0), Reality(), reach_check=past_150),
        "unreachable_reactive": line(t.flat(-3.0), Reality(), reach_check=past_150,
                                     on_failure="reactive"),
        "too_deep_reactive": line(t.flat(-6.0), Reality(), reach_check=too_deep,
                                  on_failure="reactive"),
        "held_then_free_reactive": line(t.flat(-6.0), Reality(), reach_check=too_deep_before_100,
                                        on_failure="reactive"),
        "slow_rate_no_lag_fuzzy_pi": line(t.flat(-3.0), rough, controller="fuzzy_pi",
                                          rate_hz=10.0, robot_lag_s=0.0),
    })
    return runs


def cases():
    """name -> (zero-argument function giving the SensorRun, every: the steps kept)."""
    found = {"bench_" + c: ((lambda c=c: _bench_run(c)), 1) for c in ("none", "pi", "fuzzy_pi")}
    found.update({"cell_%s_%s" % (d, c): ((lambda d=d, c=c: _cell_run(d, c)), 1)
                  for d, c in (("down", "pi"), ("down", "fuzzy_pi"), ("down", "none"),
                               ("up", "none"))})
    found.update({name: (run, SPARSE_EVERY) for name, run in _scenario_runs().items()})
    return found


# ------------------------------------------------------------------ outputs

def outputs(run, every):
    """What is recorded of `run`: arrays (one step in `every`, and sums over all
    steps when `every` > 1) and a JSON string of everything else.

    Returns
    -------
    arrays : dict of str -> ndarray
        ``<array>`` (sampled), ``<array>:sum`` and ``<array>:abs_sum`` (column
        sums over all steps, same unit).
    meta : str
        JSON: aborted, reason, stop index and pose, number of steps, metrics.
    """
    arrays = {}
    for name in ARRAYS:
        values = np.asarray(getattr(run, name), dtype=float)
        arrays[name] = values[::every]
        if every > 1:
            arrays[name + ":sum"] = values.sum(axis=0)
            arrays[name + ":abs_sum"] = np.abs(values).sum(axis=0)
    meta = {"sensor": run.sensor, "controller": run.controller, "aborted": run.aborted,
            "reason": run.reason, "stop_index": run.stop_index, "steps": len(run.time_s),
            "every": every, "metrics": run.metrics,
            "stop_T_u_t": None if run.stop_T_u_t is None else run.stop_T_u_t.tolist()}
    return arrays, json.dumps(meta, sort_keys=True, default=float)


def record(path=GOLDEN_PATH):
    """Run every case and write its outputs to `path` (.npz)."""
    stored = {}
    for name, (make_run, every) in sorted(cases().items()):
        arrays, meta = outputs(make_run(), every)
        stored.update({"%s/%s" % (name, key): value for key, value in arrays.items()})
        stored[name + "/meta"] = np.array(meta)
        print(name, json.loads(meta)["steps"], "steps")
    np.savez_compressed(path, **stored)


def load(path=GOLDEN_PATH):
    """name -> (arrays dict, meta dict) of the recorded outputs."""
    found = {}
    with np.load(path) as data:
        for key in data.files:
            name, item = key.split("/", 1)
            arrays, meta = found.setdefault(name, ({}, {}))
            if item == "meta":
                meta.update(json.loads(str(data[key])))
            else:
                arrays[item] = data[key]
    return found


def capture_scene(path=SCENE_PATH):
    """Inside FreeCAD: build the example cell, read its force scene, save it to `path`."""
    import FreeCAD
    sys.path.insert(0, os.path.join(REPO, "examples"))
    import profile_following_cell
    from CadRobotWB import simulation

    cell = profile_following_cell.build(FreeCAD.newDocument("ProfileFollowing"))
    scene = simulation.read_scene(cell, "force")
    (name, mesh), = scene.workpiece
    start = scene.trajectory.position_mm[0]
    realities = {"T_u_dev_" + label: simulation.reality_of(deviation, start).T_u_dev
                 for label, deviation in CELL_DEVIATIONS.items()}
    t = scene.trajectory
    np.savez_compressed(path, time_s=t.time_s, T_u_t=t.T_u_t, s_mm=t.s_mm,
                        move_index=t.move_index, workpiece_name=name,
                        vertices=np.asarray(mesh.vertices),
                        faces=np.asarray(mesh.faces), robot=scene.robot.robot,
                        T_r_u=scene.robot.T_r_u, T_f_t=scene.robot.T_f_t,
                        path_label=scene.path_label, **realities)


if __name__ == "__main__":
    if "--capture-scene" in sys.argv:
        capture_scene()
    elif "--record" in sys.argv:
        record()
    else:
        sys.exit(__doc__)
