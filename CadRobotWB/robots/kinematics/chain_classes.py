"""The solver classes of arms given as axes and steps (:mod:`.poe`), and which one an arm is.

Each class is one module of this package with ``KIND``, ``MAX_SOLUTIONS``,
``recognise(params) -> constants`` (``ValueError`` saying why an arm is not
of the class) and ``inverse(constants, T_0T) -> q_rad (N, MAX_SOLUTIONS, 6)``
(every solution, wrapped into (-pi, pi], NaN rows last):

* :mod:`.offset_wrist`: axes 2 and 3 parallel, axes 4, 5 and 6 not meeting in
  one point (FANUC CRX and M-430iA/2P, Yaskawa HC10, ABB CRB 15000): a
  one-dimensional search;
* :mod:`.spherical_wrist`: axes 2 and 3 parallel, axes 4, 5 and 6 meeting in
  one point at any angles (KUKA arms whose files round pi/2): IK-Geo's closed
  form (Elias and Wen, arXiv:2211.05737).

OPW and UR arms are not here: they have their own closed forms (:mod:`.opw`,
:mod:`.ur`), tried first.

Pure numpy: never imports FreeCAD.
"""

import numpy as np

from . import offset_wrist, offset_wrist_polish, spherical_wrist

#: The classes, in the order :func:`classify` tries them.
CLASSES = (offset_wrist, spherical_wrist)

#: How each class is solved, in words (docs/robot-catalog.md).
METHODS = {
    "offset_wrist": "1-D search (semi-analytic)",
    "spherical_wrist": "IK-Geo closed form (subproblem decomposition)",
}

#: A class's name in messages.
LABELS = {"offset_wrist": "an offset-wrist arm", "spherical_wrist": "a spherical-wrist arm"}


def classify(params):
    """The solver module of an arm: the first of :data:`CLASSES` that recognises it.

    Parameters
    ----------
    params : poe.ChainParameters

    Returns
    -------
    module
        With ``KIND``, ``MAX_SOLUTIONS``, ``recognise``, ``inverse``.

    Raises
    ------
    ValueError
        When none does, naming why for each, e.g. "not an offset-wrist arm (axes 2
        and 3 are not parallel); not a spherical-wrist arm (axes 2 and 3 are not
        parallel)".
    """
    return _recognised(params)[0]


def _recognised(params):
    """The first class that recognises `params` and its constants (see :func:`classify`)."""
    reasons = []
    for module in CLASSES:
        try:
            return module, module.recognise(params)
        except ValueError as exc:
            reasons.append("not %s (%s)" % (LABELS.get(module.KIND, module.KIND), exc))
    raise ValueError("; ".join(reasons))


class Solver:
    """The inverse kinematics of one arm: its class module and constants, found once.

    Attributes
    ----------
    module : module
        From :data:`CLASSES`.
    constants : object
        What ``module.recognise`` precomputed.
    """

    def __init__(self, params):
        self.params = params
        self.module, self.constants = _recognised(params)
        if self.module is offset_wrist:
            self._screen = offset_wrist_polish.screen_vector(params)
            self._aligned = offset_wrist_polish.aligned_q4_rad(params)

    @property
    def kind(self):
        """str: the class, e.g. ``"offset_wrist"``."""
        return self.module.KIND

    @property
    def max_solutions(self):
        """int: rows per pose of :meth:`inverse`."""
        return self.module.MAX_SOLUTIONS

    def inverse(self, T_0T):
        """Every solution.

        Parameters
        ----------
        T_0T : array_like, shape (N, 4, 4)
            Flange poses in the base frame of the parameters, mm.

        Returns
        -------
        ndarray, shape (N, MAX_SOLUTIONS, 6)
            rad, wrapped into (-pi, pi], NaN rows last.
        """
        if self.module is not offset_wrist:
            return self.module.inverse(self.constants, T_0T)
        return offset_wrist_polish.solve(
            self.params, lambda T: offset_wrist.inverse(self.constants, T),
            np.asarray(T_0T, dtype=float).reshape(-1, 4, 4), offset_wrist.MAX_SOLUTIONS,
            lambda T: offset_wrist.inverse_screened(self.constants, T, self._screen),
            self._aligned)
