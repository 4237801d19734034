"""``make demo``: the paper's two example cells, their programs and both sensor experiments, into out/.

1. Seam tracking (paper 4.1): the IRB 2400 butt-joint cell, its RAPID module
   (and a variant with live path correction), a check report, and the laser
   simulation with the workpiece 5 mm sideways, 2 mm high and turned 1°,
   and where else the robot could stand (``cadrobot place``).
2. Profile following (paper 4.2): the HP6 ball-tool cell, its NX100 INFORM
   job, and the force simulation with the part 3 mm below its CAD pose, PI
   against Fuzzy-PI.
3. Welding (issue 22), into out/welding/: the seam cell welded with the
   library's schedule for its plates and a zigzag weave, in all five
   languages with their arc instructions; a T-joint fillet welded with a
   weave and through-arc tracking, simulated with the laser and with the
   arc on the part 3 mm across and 2 mm up, both on one plot.
4. External axes (issue 23), into out/external_axes/: a DN 100 pipe welded to
   its flange all round on a tilt-and-turn positioner (``pipe_flange_cell``),
   saved as out/pipe_flange.FCStd: the worst gravity angle along the weld
   without the positioner (the fillet is horizontal-vertical all round) and
   with it (flat), ``cadrobot check`` and the program in all five languages
   (UR has no external axes: its one-line refusal is shown, and expected).
5. A cobot (issue 24), into out/crx_seam/: the seam cell of 1. with a FANUC
   CRX-10iA/L (``crx_seam_cell``): Place robot over the floor round the table,
   the best base applied, the check, the torch angles and J5 along the seam, and
   the welded program in all five languages (FANUC LS with the CRX's CONFIG).

Runs inside FreeCADCmd (``tools/freecad_run.py examples/make_demo.py OUT``),
through the same CLI a user runs, so the demo also shows the commands.
"""

import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.dirname(HERE))

EXPERIMENTS = (
    # (document, builder module, cell), CLI calls (output subfolder, arguments)
    ("seam_tracking.FCStd", "seam_tracking_cell", "SeamTracking", [
        (".", ["export", "{doc}", "--post", "abb_rapid", "-o", "{out}"]),
        ("seam_check", ["check", "{doc}", "--json"]),
        (".", ["place", "{doc}", "--region", "-600,-1200,1600,1000", "--step", "200"]),
        ("seam_tracking", ["simulate", "{doc}", "--sensor", "laser",
                           "--deviation", "0,5,2,0,0,1", "-o", "{out}"]),
    ]),
    ("profile_following.FCStd", "profile_following_cell", "ProfileFollowing", [
        (".", ["export", "{doc}", "-o", "{out}"]),          # the HP6's own language: INFORM (NX100)
        ("profile_check", ["check", "{doc}", "--json"]),
        ("profile_following", ["simulate", "{doc}", "--sensor", "force",
                               "--deviation", "0,0,-3,0,0,0", "-o", "{out}"]),
    ]),
)


def main(out_dir):
    import importlib
    import FreeCAD
    from CadRobotWB import api, cli
    from CadRobotWB.posts import abb_rapid

    os.makedirs(out_dir, exist_ok=True)
    failures = 0
    for filename, module_name, doc_name, calls in EXPERIMENTS:
        doc = FreeCAD.newDocument(doc_name)
        cell = importlib.import_module(module_name).build(doc)
        path = os.path.join(out_dir, filename)
        if os.path.exists(path):      # a fresh file, not FreeCAD's .FCStd1 backup of the last demo
            os.remove(path)
        doc.saveAs(path)
        print("saved %s" % path)
        if module_name == "seam_tracking_cell":   # the RAPID module that takes live corrections
            files = abb_rapid.export(api.generate(cell), {"path_correction": True})
            name, text = files[0]
            with open(os.path.join(out_dir, name.replace(".mod", "_corr.mod")), "w") as handle:
                handle.write(text)
        FreeCAD.closeDocument(doc.Name)
        for sub, arguments in calls:
            target = os.path.join(out_dir, sub)
            argv = [a.format(doc=path, out=target) for a in arguments]
            print("\n$ cadrobot %s" % " ".join(argv))
            if "--json" in argv:   # keep the check report as a file
                os.makedirs(target, exist_ok=True)
                with open(os.path.join(target, "check.json"), "w") as handle:
                    code = cli.main(argv, out=handle)
                print("wrote %s (exit %d)" % (os.path.join(target, "check.json"), code))
            else:
                code = cli.main(argv)
            failures += code != 0
    return 1 if failures + welding(out_dir) + external_axes(out_dir) + cobot(out_dir) else 0


#: The five languages the welded seam is written in.
WELD_POSTS = ("abb_rapid", "kuka_krl", "fanuc_ls", "motoman_inform", "ur_script")
#: The weaves of the demo's welds: the butt seam, and the fillet the arc tracks.
SEAM_WEAVE = {"pattern": "zigzag", "width_mm": 3.0, "frequency_hz": 1.5}
FILLET_WEAVE = {"pattern": "zigzag", "width_mm": 4.0, "frequency_hz": 2.0,
                "dwell_left_s": 0.1, "dwell_right_s": 0.1}
#: The real T-joint: 3 mm across the seam, 2 mm up (the issue's acceptance case).
FILLET_DEVIATION = "0,3,2,0,0,0"


def _welded_document(out_dir, filename, module_name, doc_name, **weld):
    """Build an example cell, weld its path (api.make_weld, the library's schedule
    for the joint), save it as OUT/`filename`; returns the file path."""
    import importlib
    import FreeCAD
    from CadRobotWB import api
    from CadRobotWB.objects import base
    doc = FreeCAD.newDocument(doc_name)
    cell = importlib.import_module(module_name).build(doc)
    path_object = base.objects_of_type(doc, "RobotPath")[0]
    weld = api.make_weld(doc, cell, path_object, **weld)
    print("%s: %s" % (weld.Label, weld.ScheduleNote))
    path = os.path.join(out_dir, filename)
    if os.path.exists(path):
        os.remove(path)
    doc.saveAs(path)
    print("saved %s" % path)
    FreeCAD.closeDocument(doc.Name)
    return path


def _cli(argv):
    from CadRobotWB import cli
    print("\n$ cadrobot %s" % " ".join(argv))
    return cli.main(argv)


def welding(out_dir):
    """Experiment 3 (see the module docstring); returns the number of failed steps."""
    import FreeCAD
    from CadRobotWB import api, report_plots, simulation
    target = os.path.join(out_dir, "welding")
    os.makedirs(target, exist_ok=True)
    failures = 0
    seam = _welded_document(out_dir, "seam_weld.FCStd", "seam_tracking_cell", "SeamWeld",
                            weave=SEAM_WEAVE)
    failures += _cli(["welds", seam]) != 0
    failures += _cli(["check", seam]) != 0
    for post in WELD_POSTS:
        failures += _cli(["export", seam, "--post", post, "-o", target]) != 0

    tee = _welded_document(out_dir, "tee_joint.FCStd", "tee_joint_cell", "TeeJoint",
                           weave=FILLET_WEAVE, tracking="arc")
    failures += _cli(["welds", tee]) != 0
    failures += _cli(["export", tee, "--post", "abb_rapid", "-o", target]) != 0
    for sensor in ("laser", "arc"):
        failures += _cli(["simulate", tee, "--sensor", sensor, "--deviation", FILLET_DEVIATION,
                          "-o", os.path.join(target, "tee_" + sensor)]) != 0
    doc = FreeCAD.openDocument(tee)
    cell = api.find_cells(doc)[0]
    deviation = [float(v) for v in FILLET_DEVIATION.split(",")]
    runs = []
    for sensor in ("laser", "arc"):
        scene, _, (run,) = simulation.simulate_cell(cell, sensor, ("pi",), deviation)
        runs.append((run, scene.trajectory))
        print("%s: RMS error after 20 mm %.3f mm (open loop %.3f mm)"
              % (sensor, run.metrics["rms_error_after_20mm_mm"],
                 run.metrics["open_loop_rms_error_mm"]))
    FreeCAD.closeDocument(doc.Name)
    plot = os.path.join(target, "laser_and_arc.png")
    with open(plot, "wb") as handle:
        handle.write(report_plots.plot_laser_and_arc(*runs))
    print("wrote %s" % plot)
    return failures


#: The post that has no external axes: it refuses the positioner's program (exit 2).
NO_EXTERNAL_AXES_POSTS = ("ur_script",)
#: Options the posts need for the positioner: INFORM writes the station in encoder pulses,
#: and pulses per degree (tilt, turn) are the station's own controller parameters: these
#: are example values (docs/controllers.md, "Yaskawa INFORM").
EXTERNAL_AXES_OPTIONS = {"motoman_inform": ["--option", "station_pulses_per_degree=1000,1000"]}


def _worst_gravity_angle(cell):
    """The worst gravity angle of the cell's welded targets, deg (``pipe_flange_cell``)."""
    import numpy as np
    import pipe_flange_cell
    from CadRobotWB import api
    return float(np.max(pipe_flange_cell.gravity_angles_deg(api.generate(cell))))


def external_axes(out_dir):
    """Experiment 4 (see the module docstring); returns the number of failed steps."""
    import FreeCAD
    import pipe_flange_cell
    target = os.path.join(out_dir, "external_axes")
    os.makedirs(target, exist_ok=True)
    fixed = FreeCAD.newDocument("PipeFlangeFixed")
    without = _worst_gravity_angle(pipe_flange_cell.build(fixed, positioner=False))
    FreeCAD.closeDocument(fixed.Name)
    doc = FreeCAD.newDocument("PipeFlange")
    worst = _worst_gravity_angle(pipe_flange_cell.build(doc))
    path = os.path.join(out_dir, "pipe_flange.FCStd")
    if os.path.exists(path):
        os.remove(path)
    doc.saveAs(path)
    FreeCAD.closeDocument(doc.Name)
    print("saved %s" % path)
    print("pipe to flange, worst gravity angle of the weld's targets: %.2f deg on a fixed table "
          "(horizontal-vertical), %.4f deg on the positioner (flat)" % (without, worst))
    failures = _cli(["check", path]) != 0
    for post in WELD_POSTS:
        code = _cli(["export", path, "--post", post, "-o", target]
                    + EXTERNAL_AXES_OPTIONS.get(post, []))
        if post in NO_EXTERNAL_AXES_POSTS:
            print("(expected: %s has no external axes; exit %d)" % (post, code))
            failures += code != 2
        else:
            failures += code != 0
    return failures


def cobot(out_dir):
    """Experiment 5 (see the module docstring); returns the number of failed steps."""
    import crx_seam_cell
    print("\n$ tools/freecad_run.py examples/crx_seam_cell.py %s"
          % os.path.join(out_dir, "crx_seam"))
    return crx_seam_cell.run(os.path.join(out_dir, "crx_seam"))


# freecadcmd runs a script with __name__ set to the file's stem, python with "__main__".
if __name__ in ("__main__", "make_demo"):
    sys.exit(main(os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else "out")))
