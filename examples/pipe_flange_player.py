"""``make demo``: the player on the pipe-to-flange cell with the positioner turned,
``out/pipe_flange_player.png`` (issue 23).

Opens ``out/pipe_flange.FCStd`` (``make_demo.py`` saves it) in the real FreeCAD
window, opens the simulation player on its cell and shows the sample halfway
through the weld (the positioner tilted and turned, the part with it, the
robot on the seam), saves the isometric view, prints the positioner's values
shown and closes the player (every view transform back as drawn).

Runs in the FreeCAD GUI (under Xvfb when there is no display)::

    /usr/bin/python3 tools/freecad_run.py --gui examples/pipe_flange_player.py out
"""

import os
import sys

WIDTH, HEIGHT = 1280, 960
DOCUMENT = "pipe_flange.FCStd"
PICTURE = "pipe_flange_player.png"


def process_events(rounds=5):
    from PySide import QtGui
    for _ in range(rounds):
        QtGui.QApplication.processEvents()


def halfway_through_the_weld(timeline, moves):
    """The sample of `timeline` halfway through its welded samples (`moves`: the program's)."""
    from CadRobotWB.core import program as ir
    welded = [i for i, k in enumerate(timeline.move_index)
              if k >= 0 and moves[int(k)].weld and moves[int(k)].role == ir.ROLE_PATH]
    return welded[len(welded) // 2] if welded else len(timeline) // 2


def main(out_dir):
    import FreeCAD
    import FreeCADGui
    from CadRobotWB import api, compat
    import CadRobotWB.commands  # noqa: F401  (registers the commands the player's window has)
    from CadRobotWB.gui import simulation_player
    compat.no_camera_animation()
    doc = FreeCAD.openDocument(os.path.join(out_dir, DOCUMENT))
    process_events()
    FreeCADGui.setActiveDocument(doc.Name)
    view = FreeCADGui.getDocument(doc.Name).activeView()
    cell = api.find_cells(doc)[0]
    player = simulation_player.open_player(cell)
    frame = halfway_through_the_weld(player.timeline, player.program.moves())
    player.show_frame(frame)
    values = player.timeline.external[frame]
    view.viewIsometric()
    view.fitAll()
    process_events()
    compat.draw_now(view)
    png = os.path.join(out_dir, PICTURE)
    view.saveImage(png, WIDTH, HEIGHT, "Current")
    names = player.mechanisms.external.axis_names()
    print("player at t = %.2f s: %s" % (
        player.timeline.time_s[frame],
        ", ".join("%s %.1f" % (n, v) for n, v in zip(names, values))))
    simulation_player.close_player()
    FreeCAD.closeDocument(doc.Name)
    print("wrote %s" % png)
    return 0


# freecad runs a script with __name__ set to the file's stem, python with "__main__".
if __name__ in ("__main__", "pipe_flange_player"):
    sys.exit(main(os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else "out")))
