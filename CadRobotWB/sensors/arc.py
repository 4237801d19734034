"""The welding arc as a sensor: current as a function of the contact-tip-to-work distance.

Through-arc seam tracking (FANUC TAST, ABB WeldGuide, Yaskawa COM-ARC) reads
the welding current while the torch weaves: at a constant wire feed and a
constant-voltage source, a shorter contact-tip-to-work distance (CTWD) gives
a higher current. This module is that relation and the geometry that feeds it.

Model (plan issue 22, section d.1)
----------------------------------
A quasi-static reduction of the arc-sensor model of Ushio & Mao, "Modelling
of the arc sensor for DC MIG/MAG welding in open arc mode", Q. J. Japan
Welding Soc. 14(1):99-107, 1996 (S27), with its second report (S28: the loop
inductance matters only above about 6 Hz of torch-height change; the source
slope dominates the sensitivity). At CTWD ``Lt`` the electrode extension
``Le`` and the current ``I`` satisfy::

    melting (steady state):  Vf = alpha I + beta Le I^2
    voltage balance:         Us - Ks (I - I0) = U0 + Ra I + rho Le I + Ea (Lt - Le)

Calibration on the schedule, so that the model reproduces it: at the
schedule's CTWD ``Lt0`` the current is the schedule's ``I0`` with an arc
``la0`` long (``Le0 = Lt0 - la0``), the wire feed ``Vf`` and the voltage
``U``: ``beta = (Vf - alpha I0) / (Le0 I0^2)``,
``U0 = U - Ra I0 - rho Le0 I0 - Ea la0``, ``Us = U``.

The constants are typical magnitudes for 1.2 mm steel wire, **assumptions,
not values from a cited source** (Ushio & Mao's identified values are behind
the abstract): see :data:`ASSUMPTIONS`. They are parameters of
:meth:`ArcModel.from_schedule`. With them the fillet schedule of 265 A,
6.7 m/min, 27.5 V at 15 mm gives about -5 A per mm of CTWD; the sign (the
current falls as the CTWD grows) is the physics the trackers rely on (S30,
S32), the magnitude depends mostly on ``Ks`` (S28).

Speed: for a given current both equations are explicit in ``Le`` and
``Lt``, so a table of ``Lt(I)`` over a fine grid of currents is built once
per schedule and :meth:`ArcModel.current` interpolates it (one ``np.interp``
for any number of samples); :meth:`ArcModel.current_exact` solves the root
instead, to check the table.

CTWD of a torch pose: the contact tip sits ``Lt0`` back from the TCP along
the tool axis; the CTWD is the distance from the tip along +Z of the tool to
the first triangle of the real part (:meth:`ArcScene.ctwd_mm`). No hit within
``Lt0 + ARC_REACH_MM``: the arc is out.

Pure numpy / scipy: never imports FreeCAD.
"""

from dataclasses import dataclass

import numpy as np

from ..core.welding import WIRE_FEED_PER_AMPERE
from ..errors import InputError
from .seam_tracking import ray_triangle_t

#: The arc model's constants: name -> (default, unit, what). Assumed typical magnitudes for
#: 1.2 mm solid steel wire, not from a cited source (plan issue 22, d.1).
ASSUMPTIONS = {
    "arc_length_mm": (4.0, "mm", "arc length at the schedule's CTWD (assumed)"),
    "alpha": (0.30, "mm/(A s)", "arc melting rate per ampere (assumed, 1.2 mm steel)"),
    "rho": (0.00088, "ohm/mm", "resistance of the hot wire per mm (about 1 uohm m / 1.13 mm^2)"),
    "ra": (0.01, "ohm", "arc resistance (assumed)"),
    "ea": (1.0, "V/mm", "arc column field (assumed)"),
    "ks": (0.03, "ohm", "slope of the constant-voltage source (assumed; S28: dominates the "
                        "sensitivity)"),
}
#: An arc farther than this beyond the schedule's CTWD goes out, mm.
ARC_REACH_MM = 20.0
#: Currents of the table, relative to the schedule's current, and their step.
TABLE_SPAN = (0.2, 2.5)
TABLE_POINTS = 4000


@dataclass(frozen=True)
class ArcModel:
    """Steady welding current as a function of CTWD, calibrated on one schedule.

    Build it with :meth:`from_schedule`. Units: mm, A, V, s, ohm.

    Attributes
    ----------
    ctwd0_mm, current0_a, voltage_v, wire_feed_mm_s : float
        The schedule's point: CTWD, current, voltage, wire feed.
    arc_length_mm, alpha, rho, ra, ea, ks : float
        The constants of :data:`ASSUMPTIONS`.
    beta : float
        Joule pre-heating term of the melting rate, 1/(A^2 s), calibrated.
    u0 : float
        Arc voltage at zero current and length, V, calibrated.
    table_ctwd_mm, table_current_a : ndarray, shape (M,)
        ``Lt(I)`` on a grid of currents, CTWD increasing.
    """

    ctwd0_mm: float
    current0_a: float
    voltage_v: float
    wire_feed_mm_s: float
    arc_length_mm: float
    alpha: float
    rho: float
    ra: float
    ea: float
    ks: float
    beta: float
    u0: float
    table_ctwd_mm: np.ndarray
    table_current_a: np.ndarray

    @classmethod
    def from_schedule(cls, schedule, **assumptions):
        """The model calibrated on `schedule` (a validated ``welding.WeldSchedule``).

        Parameters
        ----------
        schedule : core.welding.WeldSchedule
            Its current (or, when left out, the current Miller's rule gives
            for its wire feed), wire feed, voltage and CTWD.
        **assumptions
            Any of :data:`ASSUMPTIONS` by name, replacing its default.

        Raises
        ------
        InputError
            An unknown constant, or a schedule the model cannot be calibrated
            on (the wire would melt faster than it is fed, or the arc would be
            longer than the CTWD).
        """
        unknown = sorted(set(assumptions) - set(ASSUMPTIONS))
        if unknown:
            raise InputError("Arc model: unknown constant %r: use %s." % (
                unknown[0], ", ".join(sorted(ASSUMPTIONS))))
        c = {k: float(assumptions.get(k, spec[0])) for k, spec in ASSUMPTIONS.items()}
        ctwd0 = float(schedule.ctwd_mm)
        vf = schedule.wire_feed_m_min * 1000.0 / 60.0
        i0 = _schedule_current(schedule)
        le0 = ctwd0 - c["arc_length_mm"]
        if not 0 < le0 < ctwd0 or c["alpha"] * i0 >= vf:
            raise InputError(
                "Arc model of schedule %r: %.0f A at %.1f m/min with a %.1f mm arc at %.1f mm "
                "CTWD is not a steady arc: check the schedule's current and wire feed."
                % (schedule.name, i0, schedule.wire_feed_m_min, c["arc_length_mm"], ctwd0))
        beta = (vf - c["alpha"] * i0) / (le0 * i0 ** 2)
        u0 = schedule.voltage_v - c["ra"] * i0 - c["rho"] * le0 * i0 - c["ea"] * c["arc_length_mm"]
        model = cls(ctwd0, i0, float(schedule.voltage_v), vf, c["arc_length_mm"], c["alpha"],
                    c["rho"], c["ra"], c["ea"], c["ks"], beta, u0, np.zeros(0), np.zeros(0))
        current = np.linspace(TABLE_SPAN[0] * i0, min(TABLE_SPAN[1] * i0, vf / c["alpha"]),
                              TABLE_POINTS)[:-1]
        ctwd = model.ctwd_of_current(current)
        keep = np.r_[True, np.diff(ctwd) < 0]       # Lt falls as I grows; keep where it does
        order = np.argsort(ctwd[keep])
        object.__setattr__(model, "table_ctwd_mm", ctwd[keep][order])
        object.__setattr__(model, "table_current_a", current[keep][order])
        return model

    def extension_mm(self, current_a):
        """Electrode extension Le (mm) at which the wire melts as fast as it is fed."""
        current_a = np.asarray(current_a, dtype=float)
        return (self.wire_feed_mm_s - self.alpha * current_a) / (self.beta * current_a ** 2)

    def ctwd_of_current(self, current_a):
        """CTWD (mm) at which the steady current is `current_a` (the voltage balance solved for Lt)."""
        current_a = np.asarray(current_a, dtype=float)
        le = self.extension_mm(current_a)
        source = self.voltage_v - self.ks * (current_a - self.current0_a)
        return le + (source - self.u0 - self.ra * current_a - self.rho * le * current_a) / self.ea

    def current(self, ctwd_mm):
        """Steady current (A) at CTWD `ctwd_mm` (any shape), from the table; clipped to the
        table's ends (20 % to 250 % of the schedule's current)."""
        return np.interp(ctwd_mm, self.table_ctwd_mm, self.table_current_a)

    def current_exact(self, ctwd_mm):
        """Steady current (A) at one CTWD by a root solve (brentq): the table's check."""
        from scipy.optimize import brentq
        low, high = self.table_current_a[-1], self.table_current_a[0]
        return float(brentq(lambda i: self.ctwd_of_current(i) - ctwd_mm, low, high, xtol=1e-9))

    def sensitivity_a_per_mm(self, ctwd_mm=None):
        """dI/dLt (A/mm, negative) at `ctwd_mm` (default the schedule's CTWD), exact
        (the derivative of the two equations, not a difference of the table)."""
        i = self.current0_a if ctwd_mm is None else self.current_exact(ctwd_mm)
        return 1.0 / self._dctwd_dcurrent(i)

    def _dctwd_dcurrent(self, i):
        le = self.extension_mm(i)
        dle = -self.alpha / (self.beta * i ** 2) - 2.0 * le / i
        return dle + (-self.ks - self.ra - self.rho * (dle * i + le)) / self.ea

    def describe(self):
        """One sentence for a run's notes: the schedule point and the sensitivity."""
        return ("The arc model (Ushio & Mao 1996, quasi-static, its constants assumed) gives "
                "%.0f A at %.1f mm CTWD and %.1f A per mm of CTWD."
                % (self.current0_a, self.ctwd0_mm, self.sensitivity_a_per_mm()))


def _schedule_current(schedule):
    """The schedule's current, A; from its wire feed by Miller's rule when it gives none."""
    if schedule.current_a is not None:
        return float(schedule.current_a)
    per_ampere = WIRE_FEED_PER_AMPERE.get(round(schedule.wire_mm, 2))
    if per_ampere is None:
        raise InputError("Arc model of schedule %r: give current_a (the current can be derived "
                         "from the wire feed only for 0.8, 0.9 and 1.2 mm wire)." % schedule.name)
    return schedule.wire_feed_m_min / per_ampere


# ------------------------------------------------------------ geometry


class ArcScene:
    """The real part as the arc sees it: its triangles and their boxes, for :meth:`ctwd_mm`.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The real part (and the foreign objects), {U}, mm.
    """

    def __init__(self, mesh):
        self.triangles = np.asarray(mesh.triangles, dtype=float).reshape(-1, 3, 3)
        self.low = self.triangles.min(axis=1)
        self.high = self.triangles.max(axis=1)

    def ctwd_mm(self, tcp_u, tool_z_u, ctwd0_mm, reach_mm=ARC_REACH_MM):
        """Contact-tip-to-work distance of torch poses.

        The contact tip sits `ctwd0_mm` back from the TCP along -Z; the CTWD
        is the distance from it along +Z to the first triangle (a vectorised
        Moller-Trumbore test against the triangles whose boxes meet the box
        of all the rays).

        Parameters
        ----------
        tcp_u, tool_z_u : ndarray, shape (N, 3)
            TCP positions (mm) and unit tool axes (pointing into the work).
        ctwd0_mm : float
            The schedule's CTWD, mm.
        reach_mm : float
            The arc reaches at most ``ctwd0_mm + reach_mm``.

        Returns
        -------
        ndarray, shape (N,)
            mm; NaN where no triangle lies within reach (the arc is out).
        """
        tcp_u = np.asarray(tcp_u, dtype=float)
        tip = tcp_u - ctwd0_mm * tool_z_u
        reach = ctwd0_mm + reach_mm
        end = tip + reach * tool_z_u
        low, high = np.minimum(tip, end).min(axis=0), np.maximum(tip, end).max(axis=0)
        near = self.triangles[np.all(self.high >= low, axis=1) & np.all(self.low <= high, axis=1)]
        if len(near) == 0:
            return np.full(len(tcp_u), np.nan)
        t = ray_triangle_t(tip, tool_z_u, near).min(axis=1)
        return np.where(t <= reach, t, np.nan)
