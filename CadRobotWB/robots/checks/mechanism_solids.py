"""The solids of the external axes, and how every obstacle moves with them (issue 23).

The collision check (:mod:`.collision`) sees the cell from the robot base {R}.
With external axes the scene changes along the program:

* a **track** carries the robot base: at values ``v`` the base is at
  ``T_u_r(v) = track.motion(v) @ T_u_r`` (:meth:`~...core.mechanisms.ExternalAxes.T_u_r_at`),
  so every solid that stands still in {U} moves in {R};
* a **positioner** carries the part: the solids riding on it
  (``ExternalAxes.riding_solids``) move by ``positioner.motion(v)`` in {U};
* the mechanisms' own solids (:func:`...mechanisms.catalog.solids`, one mesh
  per body, base first) move with their axes: body k (k = 1..K) is carried by
  axis k, i.e. it moves with the chain up to that axis (:func:`body_motions`:
  a track's carriage, a positioner's tilt yoke, then its table).

Obstacles are given to the checker in {R0}, the robot base at the track's drawn
value (``ExternalAxes.T_u_r``); :meth:`SceneMotion.poses` gives, per pose, the
transform taking each moving obstacle from there to where it is in the robot's
base at that pose: ``inv(T_u_r(v)) @ M(v) @ T_u_r`` with ``M`` the obstacle's
motion in {U} (identity for a still solid).

Pure numpy: never imports FreeCAD.
"""

import numpy as np

from ...core import frames as tf
from ...core import mechanisms as mech
from ..mechanisms import catalog

#: Values are probed this far from the drawn pose (deg or mm per axis) to verify
#: that the catalog's solids move as :func:`body_motions` says.
PROBE_STEP = 10.0
#: Largest mismatch (mm) of a probed solid's vertices.
PROBE_TOLERANCE_MM = 1e-6


def body_motions(mechanism, values):
    """How each body of a mechanism moves from the drawn pose, in {U}.

    Parameters
    ----------
    mechanism : core.mechanisms.Mechanism
    values : array_like, shape (N, K)
        Its axis values (deg / mm).

    Returns
    -------
    ndarray, shape (N, K + 1, 4, 4)
        Body 0 (the base): the identity; body k: the motion of the joint frame
        of axis k, ``T_u_jk(v) @ inv(T_u_jk(drawn_at))``.
    """
    values = np.asarray(values, dtype=float).reshape(-1, len(mechanism.axes))
    out = np.broadcast_to(np.eye(4), (len(values), len(mechanism.axes) + 1, 4, 4)).copy()
    for k in range(1, len(mechanism.axes) + 1):
        chain = mech.Mechanism(mechanism.name, mechanism.label, mechanism.kind, mechanism.model,
                               mechanism.axes[:k], T_u_base=mechanism.T_u_base,
                               drawn_at=mechanism.drawn_at[:k])
        out[:, k] = chain.motion(values[:, :k])
    return out


def body_name(mechanism, k):
    """The obstacle name of body k, as ``catalog.obstacles`` names it: "Positioner base",
    "Positioner turn" (the body that axis moves)."""
    return "%s %s" % (mechanism.label, "base" if k == 0 else mechanism.axes[k - 1].name)


def _solids_problem(mechanism, drawn):
    """Why the catalog's solids of `mechanism` cannot be checked, or None."""
    if not drawn:
        return "%s '%s' has no solids" % (mechanism.kind, mechanism.label)
    if len(drawn) != len(mechanism.axes) + 1:
        return ("%s '%s' has %d solids, not one per body (%d)"
                % (mechanism.kind, mechanism.label, len(drawn), len(mechanism.axes) + 1))
    probe = np.clip(mechanism.drawn_at + PROBE_STEP, mechanism.lower, mechanism.upper)
    moved = catalog.solids(mechanism, probe)
    motions = body_motions(mechanism, probe)[0]
    for k, ((v0, _), (v1, _)) in enumerate(zip(drawn, moved)):
        expected = tf.transform_points(motions[k], np.asarray(v0, dtype=float))
        if np.abs(expected - np.asarray(v1, dtype=float)).max(initial=0.0) > PROBE_TOLERANCE_MM:
            return ("%s '%s': its solid %d does not move with axis %d"
                    % (mechanism.kind, mechanism.label, k, k))
    return None


def mechanism_solids(external):
    """The mechanisms' solids at their drawn values, and what was left out.

    Parameters
    ----------
    external : core.mechanisms.ExternalAxes

    Returns
    -------
    solids : list of (str, ndarray (V, 3), ndarray (F, 3))
        Name (:func:`body_name`), vertices in {U} (mm) and faces.
    problems : list of str
        One per mechanism whose solids are left out, and why.
    """
    solids, problems = [], []
    for mechanism in external.mechanisms():
        drawn = catalog.solids(mechanism, None)
        problem = _solids_problem(mechanism, drawn)
        if problem is not None:
            problems.append(problem)
            continue
        solids += [(body_name(mechanism, k), np.asarray(v, dtype=float), np.asarray(f, dtype=int))
                   for k, (v, f) in enumerate(drawn)]
    return solids, problems


class SceneMotion:
    """How the obstacles of a cell with external axes move in the robot base.

    Parameters
    ----------
    external : core.mechanisms.ExternalAxes
    names : iterable of str
        The obstacles' names (those of :func:`mechanism_solids` among them).
    """

    def __init__(self, external, names):
        self.external = external
        self.names = list(dict.fromkeys(names))
        self._bodies = {body_name(m, k): (m, k) for m in external.mechanisms()
                        for k in range(len(m.axes) + 1)}
        riding = set(external.riding_solids)
        self._riding = [n for n in self.names if n in riding and external.positioner is not None]
        moving = set(self._riding) | {n for n in self.names if n in self._bodies}
        self.moving = self.names if external.track is not None else \
            [n for n in self.names if n in moving]

    def poses(self, values):
        """Per obstacle that moves, its transform from {R0} into the robot base at each pose.

        Parameters
        ----------
        values : array_like, shape (N, E)
            External axis values of the poses.

        Returns
        -------
        dict of str to ndarray (N, 4, 4)
            Only obstacles that move (every one with a track).
        """
        external = self.external
        values = np.asarray(values, dtype=float).reshape(-1, len(external.axes()))
        T_u_r0 = np.asarray(external.T_u_r, dtype=float)
        T_r_u = tf.invert_transform(external.T_u_r_at(values))             # (N, 4, 4)
        track, positioner = external.split(values)
        motions = {m.name: body_motions(m, v)
                   for m, v in ((external.track, track), (external.positioner, positioner))
                   if m is not None}
        out = {}
        for name in self.moving:
            if name in self._bodies:
                mechanism, k = self._bodies[name]
                motion = motions[mechanism.name][:, k]
            elif name in self._riding:
                motion = motions[external.positioner.name][:, -1]
            else:
                motion = np.eye(4)
            out[name] = T_r_u @ motion @ T_u_r0
        return out
