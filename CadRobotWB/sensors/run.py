"""The result of a sensor-in-the-loop simulation (paper section 4)."""

from dataclasses import dataclass, field
from typing import Optional

import numpy as np


@dataclass
class SensorRun:
    """What happened while the robot ran a path with a sensor correcting it.

    All positions are TCP positions in the assembly frame {U}, mm, sampled at
    the simulation's time step.

    Attributes
    ----------
    sensor : str
        ``"laser"`` or ``"force"``.
    controller : str
        ``"pi"``, ``"fuzzy_pi"`` or ``"none"`` (open loop).
    time_s : ndarray, shape (N,)
    nominal_mm : ndarray, shape (N, 3)
        Where the program puts the TCP (the CAD path).
    actual_mm : ndarray, shape (N, 3)
        Where the TCP really is: nominal plus the correction the robot has
        applied (after its own lag).
    correction_mm : ndarray, shape (N, 3)
        The correction applied, actual minus nominal.
    error_mm : ndarray, shape (N,)
        Laser: distance from the TCP to the real seam, in the plane normal
        to the travel; force: distance from the tool to the surface along
        its normal (negative = pressed in). NaN where undefined.
    force_n : ndarray, shape (N, 6) or None
        Force sensor: Fx, Fy, Fz (N) and Tx, Ty, Tz (N·m) in the tool frame.
    metrics : dict
        Numbers the report prints (RMS errors, settling, overshoot, ...).
    aborted : bool
    reason : str
        Why the run stopped early ("" when it did not).
    stop_index : int or None
        Sample where the run stopped (aborted runs).
    stop_T_u_t : ndarray, shape (4, 4) or None
        TCP pose where it stopped: where a resumed program must start.
    corrected_fit : tuple or None
        ``((tolerance_mm, angle_tolerance_deg), CorrectedPath)``: the corrected
        path's last fit (``simulation.note_corrected_moves``), kept so it is
        fitted once.
    """

    sensor: str
    controller: str
    time_s: np.ndarray
    nominal_mm: np.ndarray
    actual_mm: np.ndarray
    correction_mm: np.ndarray
    error_mm: np.ndarray
    force_n: Optional[np.ndarray] = None
    metrics: dict = field(default_factory=dict)
    aborted: bool = False
    reason: str = ""
    stop_index: Optional[int] = None
    stop_T_u_t: Optional[np.ndarray] = None
    corrected_fit: Optional[tuple] = field(default=None, repr=False, compare=False)

    def to_dict(self, every=1):
        """Plain values for report.json; `every` keeps one sample in `every`."""
        def arr(a):
            return None if a is None else np.asarray(a)[::every].round(6).tolist()
        return {"sensor": self.sensor, "controller": self.controller,
                "aborted": self.aborted, "reason": self.reason, "stop_index": self.stop_index,
                "metrics": self.metrics, "time_s": arr(self.time_s),
                "nominal_mm": arr(self.nominal_mm), "actual_mm": arr(self.actual_mm),
                "correction_mm": arr(self.correction_mm), "error_mm": arr(self.error_mm),
                "force_n": arr(self.force_n)}
