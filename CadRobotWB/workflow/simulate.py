"""Sensor runs: the cell's path corrected by a laser, force or arc sensor in a real cell that
differs from the drawing, and which sensor suits the path.

Part of the scripting API: :mod:`CadRobotWB.api` re-exports its public names.
"""

import FreeCAD
import numpy as np

from .. import simulation
from ..core import progress as core_progress
from ..objects import joint_faces
from .arguments import Arguments


def simulate(cell, sensor="laser", deviation=None, rate_hz=None, controller="pi", progress=None,
             **options):
    """Run a cell's (first) path with a sensor correcting it in a real cell
    that differs from the drawing (paper section 4).

    Parameters
    ----------
    sensor : str
        ``"laser"`` (seam tracking, 5 Hz by default), ``"force"`` (profile
        following with a ball tool, 20 Hz by default) or ``"arc"``
        (through-arc tracking of the path's weld, once per weave cycle: the
        weld must weave; option ``weld`` names it, default the path's first).
    deviation : FreeCAD.Placement, 4x4 array or (x, y, z, rx, ry, rz), optional
        Rigid displacement of the real workpiece from its CAD pose, in {U}.
        Six numbers are mm and degrees (about the fixed X, Y, Z axes), the
        rotation turning the part about the path's start.
    rate_hz : float, optional
        Correction rate.
    controller : str
        ``"pi"``, ``"fuzzy_pi"`` or ``"none"`` (open loop, for comparison).
    progress : callable, optional
        ``progress(fraction, text)``, told often (``core.progress``); return
        False to stop: :data:`Cancelled` is raised.  Nothing is written into
        the document.
    **options
        ``path`` (label), ``foreign_objects`` (document solids in the real
        cell only), reality settings (``roughness_mm``, ``laser_noise_mm``,
        ``force_noise_n``, ``arc_current_noise_a``, ``bend_mm``, ``seed``),
        ``dt_s``, ``weld`` (arc), and options of the sensor loop (limits,
        ``on_failure="abort"|"reactive"``, ...).

    Returns
    -------
    sensors.run.SensorRun
        ``time_s``, ``nominal_mm``, ``actual_mm``, ``correction_mm``,
        ``force_n``, ``metrics``, ``aborted``, ``reason``, ``notes`` (said once
        in the summary: the sensor does not suit the path, see
        :func:`sensor_fit`, or the cell's tool is not the one it needs; the
        run still runs as asked), ...
    """
    args = Arguments("simulate")
    args.cell(cell)
    args.text("sensor", sensor, expected='"laser", "force" or "arc"')
    _deviation_argument(args, deviation)
    args.number("rate_hz", rate_hz, optional=True, expected="None or a rate in Hz (a number)")
    args.text("controller", controller, expected='"pi", "fuzzy_pi" or "none"')
    args.callback("progress", progress)
    args.text("path", options.get("path"), optional=True, expected="None or a path's label (a str)")
    args.text("weld", options.get("weld"), optional=True, expected="None or a weld's name or label (a str)")
    foreign = options.get("foreign_objects") or []
    if not isinstance(foreign, (list, tuple)):
        args.refuse("foreign_objects", "a list of document solids", foreign)
    for k, obj in enumerate(foreign):
        args.shape_object("foreign_objects[%d]" % k, obj)
    progress = core_progress.or_ambient(progress)
    return simulation.simulate_cell(cell, sensor, (controller,), deviation, rate_hz,
                                    progress=progress, **options)[2][0]


def _deviation_argument(args, deviation):
    """Refuse a `deviation` that is not None, a placement, a 4x4 matrix or 6 numbers."""
    if deviation is None or isinstance(deviation, FreeCAD.Placement):
        return
    expected = ("None, a FreeCAD.Placement, a 4x4 matrix (mm) or (x, y, z, rx, ry, rz) in mm "
                "and degrees")
    try:
        shape = np.shape(np.asarray(deviation, dtype=float))
    except (TypeError, ValueError):
        shape = None
    if isinstance(deviation, (str, bytes)) or shape not in ((6,), (4, 4)):
        args.refuse("deviation", expected, deviation)


def sensor_fit(cell, path=None):
    """Which sensor suits the path Sensor run would use: is there a joint a
    laser can track (butt, fillet, lap, V-groove), or a surface to follow
    with force?

    Parameters
    ----------
    cell : App.DocumentObject
        A CadRobot cell.
    path : str, optional
        Label or name of the path; default the cell's first.

    Returns
    -------
    sensors.joint_detection.JointDetection
        ``.kind`` (``"butt"``, ``"fillet"``, ``"lap"``, ``"v_groove"``,
        ``"surface"``, ``"convex_edge"`` or ``"none"``), ``.sensor``
        (``"laser"``, ``"force"`` or None), ``.fraction`` of the path's
        length where the kind holds, ``.reason`` (one sentence),
        ``.why_not(sensor)``, ``.template()`` (the laser's joint template).
    """
    args = Arguments("sensor_fit")
    args.cell(cell)
    args.text("path", path, optional=True, expected="None or a path's label or name (a str)")
    return joint_faces.detect(cell, path)
