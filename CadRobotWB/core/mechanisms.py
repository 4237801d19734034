"""External axes: a linear track carrying the robot, a positioner carrying the part.

A :class:`Mechanism` is a serial chain of one or two axes on a base placed in
the CAD frame {U}. Each axis moves its joint frame about (rotary) or along
(linear) that frame's +Z; ``T_prev_joint`` places the joint frame, at value 0,
in the previous frame (the mechanism's base for the first axis). The flange
{P} is the frame the part (positioner) or the robot base (track) is bolted to.

The document shows a mechanism at its ``drawn_at`` values, and everything it
carries is drawn there. Moving it to values ``v`` moves what it carries by

``T_u_u'(v) = T_u_p(v) @ inv(T_u_p(drawn_at))``            (:meth:`Mechanism.motion`)

so a work frame {B} on the positioner is at ``motion(v) @ T_u_b`` and the robot
base on a track is at ``motion(v) @ T_u_r``. :class:`ExternalAxes` holds a
program's mechanisms and gives each target's work frame in the robot base,
``T_r_b(v)`` (:func:`frame_in_base`).

Units: millimetres for linear axes, degrees for rotary ones at every surface
(values, limits, speeds); radians only inside :func:`_joint_transforms`.
Pure numpy: never imports FreeCAD.
"""

from dataclasses import dataclass, field
from typing import List, Optional, Tuple

import numpy as np

from . import frames as tf

ROTARY = "rotary"
LINEAR = "linear"

TRACK = "track"
TURNTABLE = "turntable"
TILT_TURN = "tilt_turn"
KINDS = (TRACK, TURNTABLE, TILT_TURN)
AXIS_COUNTS = {TRACK: 1, TURNTABLE: 1, TILT_TURN: 2}


@dataclass
class Axis:
    """One external axis.

    Attributes
    ----------
    name : str
        What the axis is called on its mechanism: ``"travel"``, ``"turn"``,
        ``"tilt"``.
    kind : str
        :data:`ROTARY` (degrees) or :data:`LINEAR` (mm).
    T_prev_joint : ndarray, shape (4, 4)
        The joint frame at value 0 in the previous frame, mm; the axis moves
        about / along its +Z.
    lower, upper : float
        Limits, deg or mm.
    max_speed : float
        deg/s or mm/s (> 0).
    max_accel : float
        deg/s^2 or mm/s^2 (> 0).
    fixed : float or None
        The value the user fixed the axis at; None lets the chooser pick it.
    """

    name: str
    kind: str
    T_prev_joint: np.ndarray
    lower: float
    upper: float
    max_speed: float
    max_accel: float
    fixed: Optional[float] = None

    @property
    def unit(self):
        """str: ``"deg"`` or ``"mm"``."""
        return "deg" if self.kind == ROTARY else "mm"


@dataclass
class Mechanism:
    """A track or a positioner, placed in the cell.

    Attributes
    ----------
    name : str
        Identifier ``[A-Za-z0-9_]`` (posts derive unit names from it).
    label : str
        The document object's label, for messages.
    kind : str
        One of :data:`KINDS`.
    model : str
        Catalog name of the real mechanism, "" for a user-defined one.
    axes : list of Axis
        Base to flange.
    T_last_flange : ndarray, shape (4, 4)
        The flange {P} in the last joint frame, mm.
    T_u_base : ndarray, shape (4, 4)
        The mechanism's base in {U}, mm.
    drawn_at : ndarray, shape (K,)
        Axis values the document shows it at (deg / mm).
    payload_kg : float
        Rated load, kg (0: not stated).
    """

    name: str
    label: str
    kind: str
    model: str
    axes: List[Axis]
    T_last_flange: np.ndarray = field(default_factory=lambda: np.eye(4))
    T_u_base: np.ndarray = field(default_factory=lambda: np.eye(4))
    drawn_at: np.ndarray = None
    payload_kg: float = 0.0

    def __post_init__(self):
        if self.drawn_at is None:
            self.drawn_at = np.zeros(len(self.axes))
        self.drawn_at = np.asarray(self.drawn_at, dtype=float).reshape(len(self.axes))

    @property
    def lower(self):
        """ndarray, shape (K,): lower limits."""
        return np.array([a.lower for a in self.axes], dtype=float)

    @property
    def upper(self):
        """ndarray, shape (K,): upper limits."""
        return np.array([a.upper for a in self.axes], dtype=float)

    def fk(self, values):
        """Flange in the mechanism's base at the given axis values.

        Parameters
        ----------
        values : array_like, shape (K,) or (N, K)
            deg / mm, in the order of :attr:`axes`.

        Returns
        -------
        T_base_p : ndarray, shape (4, 4) or (N, 4, 4)
        """
        v = np.asarray(values, dtype=float)
        single = v.ndim == 1
        v = v.reshape(-1, len(self.axes))
        T = np.broadcast_to(np.eye(4), (len(v), 4, 4)).copy()
        for k, axis in enumerate(self.axes):
            T = T @ axis.T_prev_joint @ _joint_transforms(axis.kind, v[:, k])
        T = T @ self.T_last_flange
        return T[0] if single else T

    def T_u_p(self, values):
        """The flange in {U}: ``T_u_base @ fk(values)``, shape (4, 4) or (N, 4, 4)."""
        return self.T_u_base @ self.fk(values)

    def motion(self, values):
        """How what the mechanism carries moves from the drawn pose: ``T_u_u'``.

        Parameters
        ----------
        values : array_like, shape (K,) or (N, K)

        Returns
        -------
        ndarray, shape (4, 4) or (N, 4, 4)
            ``T_u_p(values) @ inv(T_u_p(drawn_at))``; identity at ``drawn_at``.
        """
        return self.T_u_p(values) @ tf.invert_transform(self.T_u_p(self.drawn_at))


def _joint_transforms(kind, values):
    """(N, 4, 4) motions of a joint frame about / along its +Z (deg / mm)."""
    n = len(values)
    T = np.broadcast_to(np.eye(4), (n, 4, 4)).copy()
    if kind == ROTARY:
        a = np.radians(values)
        c, s = np.cos(a), np.sin(a)
        T[:, 0, 0], T[:, 0, 1], T[:, 1, 0], T[:, 1, 1] = c, -s, s, c
    else:
        T[:, 2, 3] = values
    return T


@dataclass
class ExternalAxes:
    """The external axes of one program.

    The program's axis values (``Target.external``) list the track's axes,
    then the positioner's: ``E1, E2, ...`` in :meth:`axis_names` order.

    Attributes
    ----------
    T_u_r : ndarray, shape (4, 4)
        The robot base in {U} with the track at its ``drawn_at``.
    track : Mechanism or None
        Carries the robot base.
    positioner : Mechanism or None
        Carries the part.
    moving_frames : tuple of str
        Keys of ``Program.frames`` riding on the positioner (the part's
        calibration frames); the other frames stand still in {U}.
    riding_solids : tuple of str
        Names (document labels, as the collision obstacles are named) of the
        solids riding on the positioner: the collision check moves them with
        it.  The other obstacles stand still in {U}.
    tolerance_deg : float or None
        How far (deg) the chooser may leave the weld position the seam asks
        for (the positioner's Tolerance); None: the chooser's default.
    """

    T_u_r: np.ndarray
    track: Optional[Mechanism] = None
    positioner: Optional[Mechanism] = None
    moving_frames: Tuple[str, ...] = ()
    riding_solids: Tuple[str, ...] = ()
    tolerance_deg: Optional[float] = None

    def mechanisms(self):
        """list of Mechanism: the track, then the positioner, those present."""
        return [m for m in (self.track, self.positioner) if m is not None]

    def axes(self):
        """list of (Mechanism, Axis), in program order."""
        return [(m, a) for m in self.mechanisms() for a in m.axes]

    def axis_names(self):
        """list of str: ``["E1", "E2", ...]``, one per axis in program order."""
        return ["E%d" % (k + 1) for k in range(len(self.axes()))]

    def drawn_at(self):
        """ndarray, shape (K,): every axis at the value the document shows."""
        return np.concatenate([m.drawn_at for m in self.mechanisms()])

    def split(self, values):
        """(track values, positioner values) of program-order values.

        Parameters
        ----------
        values : array_like, shape (K,) or (N, K)

        Returns
        -------
        tuple of ndarray or None
            Each shape (k,) or (N, k); None for a mechanism not present.
        """
        v = np.asarray(values, dtype=float)
        n_track = len(self.track.axes) if self.track is not None else 0
        track = v[..., :n_track] if self.track is not None else None
        positioner = v[..., n_track:] if self.positioner is not None else None
        return track, positioner

    def T_u_r_at(self, values):
        """The robot base in {U} at the given values, shape (4, 4) or (N, 4, 4)."""
        track, _ = self.split(values)
        if track is None:
            v = np.asarray(values, dtype=float)
            return self.T_u_r.copy() if v.ndim == 1 else np.broadcast_to(
                self.T_u_r, (len(v), 4, 4)).copy()
        return self.track.motion(track) @ self.T_u_r

    def T_r_b(self, frame, values):
        """A work frame in the robot base at the given axis values.

        Parameters
        ----------
        frame : program.WorkFrame
        values : array_like, shape (K,) or (N, K)

        Returns
        -------
        ndarray, shape (4, 4) or (N, 4, 4)
            ``inv(T_u_r(v)) @ [positioner.motion(v) @] frame.T_u_b``.
        """
        T_u_b = np.asarray(frame.T_u_b, dtype=float)
        _, positioner = self.split(values)
        if positioner is not None and frame.name in self.moving_frames:
            T_u_b = self.positioner.motion(positioner) @ T_u_b
        return tf.invert_transform(self.T_u_r_at(values)) @ T_u_b

    def T_p_b(self, frame):
        """A moving work frame in the positioner's flange {P}, shape (4, 4):
        what a coordinated work object holds (fixed while the positioner turns)."""
        return tf.invert_transform(self.positioner.T_u_p(self.positioner.drawn_at)) @ \
            np.asarray(frame.T_u_b, dtype=float)


def frame_in_base(program, move, target):
    """The work frame of `move` in the robot base {R} at `target`'s external axes.

    Parameters
    ----------
    program : program.Program
    move : program.Move
    target : program.Target
        ``move.target`` or ``move.via``.

    Returns
    -------
    T_r_b : ndarray, shape (4, 4)
        ``WorkFrame.T_r_b`` when the program has no external axes or the
        target has no values yet; else :meth:`ExternalAxes.T_r_b`.
    """
    frame = program.frames[move.frame]
    external = getattr(program, "external", None)
    values = getattr(target, "external", None)
    if external is None or values is None:
        return np.asarray(frame.T_r_b, dtype=float)
    return external.T_r_b(frame, values)
