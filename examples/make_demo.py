"""``make demo``: build the paper's example cells, save them and export their programs into out/.

Run inside FreeCADCmd (``freecadcmd examples/make_demo.py [OUT_DIR]``). FreeCADCmd
exits 0 even when a script raises, so this script ends the process itself
with the right exit code.
"""

import os
import sys
import traceback

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.dirname(HERE))


def main(out_dir):
    import FreeCAD
    from CadRobotWB import api
    import seam_tracking_cell

    os.makedirs(out_dir, exist_ok=True)
    doc = FreeCAD.newDocument("SeamTracking")
    cell = seam_tracking_cell.build(doc)
    fcstd = os.path.join(out_dir, "seam_tracking.FCStd")
    doc.saveAs(fcstd)
    print("saved %s" % fcstd)
    for path in api.export(cell, post="abb_rapid", output_dir=out_dir):
        print("wrote %s" % path)
    FreeCAD.closeDocument(doc.Name)
    return 0


# freecadcmd runs a script with __name__ set to the file's stem, python with "__main__".
if __name__ in ("__main__", "make_demo"):
    args = [a for a in sys.argv[1:] if not a.endswith(".py")]
    code = 1
    try:
        code = main(os.path.abspath(args[0] if args else "out"))
    except Exception:
        traceback.print_exc()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)
