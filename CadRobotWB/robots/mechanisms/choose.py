"""Choose the external axes at every target (issue 23).

INTERFACE: :func:`choose_external` is what the App layer calls after
``core.generate.generate`` and before ``robots.motion.configuration.solve_program``.
"""

import numpy as np

from ...core import program as ir


def choose_external(program, model, q_start_deg=None, progress=None):
    """Set ``Target.external`` of every target of `program` (in place).

    Parameters
    ----------
    program : core.program.Program
        With ``program.external`` set (no-op when None).
    model : robots.kinematics.models.RobotModel
    q_start_deg : array_like, shape (6,), optional

    Returns
    -------
    ndarray, shape (N, K)
        The values chosen, one row per target in ``program.targets()`` order.
    """
    external = program.external
    if external is None:
        return np.zeros((0, 0))
    targets = program.targets()
    values = np.tile(external.drawn_at(), (len(targets), 1))
    for target, v in zip(targets, values):
        target.external = v.copy()
    return values
