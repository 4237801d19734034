"""The program of a cell: read the document, generate, choose the joints at each target.

Part of the scripting API: :mod:`CadRobotWB.api` re-exports its public names.
"""

from ..core import generate as core_generate
from ..core import progress as core_progress
from ..core.progress import stage
from ..objects import reader
from ..robots.kinematics import models
from ..robots.motion import configuration
from .arguments import Arguments
from .common import start_joints
from .mechanisms import use_external_axes


def solved(cell, progress=None):
    """(program, model, solution) of `cell` (checked by the caller): read, generated, the
    external axes (a track, a positioner) and then the joints chosen at every target."""
    spec = reader.read_cell(cell, progress=stage(progress, 0.0, 0.4))
    program = core_generate.generate(spec, progress=stage(progress, 0.4, 0.55))
    model = models.model(program.robot)
    q_start = start_joints(cell)
    use_external_axes(cell, spec, program, model, q_start, stage(progress, 0.55, 0.6))
    solution = configuration.solve_program(program, model, q_start_deg=q_start,
                                           progress=stage(progress, 0.6, 1.0))
    return program, model, solution


def generate(cell, progress=None):
    """The core Program of `cell`; nothing is written.

    Targets are in their calibration frames {B}; each target's
    ``joints_deg`` holds the robot's joints there (one arm configuration per
    path, closest to the cell's StartJoints), or None where the robot cannot
    take the pose (see :func:`check`).

    Parameters
    ----------
    progress : callable, optional
        ``progress(fraction, text)``, told often (``core.progress``); return
        False to stop: :data:`Cancelled` is raised.
    """
    args = Arguments("generate")
    args.cell(cell)
    args.callback("progress", progress)
    progress = core_progress.or_ambient(progress)
    return solved(cell, progress)[0]
