"""``make demo``: the paper's two example cells, their programs and both sensor experiments, into out/.

1. Seam tracking (paper 4.1): the IRB 2400 butt-joint cell, its RAPID module
   (and a variant with live path correction), a check report, and the laser
   simulation with the workpiece 5 mm sideways, 2 mm high and turned 1°,
   and where else the robot could stand (``cadrobot place``).
2. Profile following (paper 4.2): the HP6 ball-tool cell, its NX100 INFORM
   job, and the force simulation with the part 3 mm below its CAD pose, PI
   against Fuzzy-PI.

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
    return 1 if failures else 0


# freecadcmd runs a script with __name__ set to the file's stem, python with "__main__".
if __name__ in ("__main__", "make_demo"):
    sys.exit(main(os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else "out")))
