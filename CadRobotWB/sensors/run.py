"""The result of a sensor-in-the-loop simulation (paper section 4)."""

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

#: Sensors whose runs track a seam (their error is the distance to the real seam).
SEAM_SENSORS = ("laser", "arc")


@dataclass
class SensorRun:
    """What happened while the robot ran a path with a sensor correcting it.

    All positions are TCP positions in the assembly frame {U}, mm, sampled at
    the simulation's time step; on a cell with a positioner, in the part's
    frame ({U} with the positioner at its drawn values: ``scene.robot.axes``
    puts them in {U} at each time).

    Attributes
    ----------
    sensor : str
        ``"laser"``, ``"force"`` or ``"arc"`` (through-arc tracking).
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
        Laser and arc: distance from the TCP (the arc: the weave centre) to
        the real seam, in the plane normal to the travel; force: distance
        from the tool to the surface along
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
    notes : list of str
        Sentences about the set-up the summary says once (the sensor does not
        suit the path, the cell's tool is not the one the sensor needs).
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
    notes: list = field(default_factory=list)

    def to_dict(self, every=1):
        """Plain values for report.json; `every` keeps one sample in `every`."""
        def arr(a):
            return None if a is None else np.asarray(a)[::every].round(6).tolist()
        return {"sensor": self.sensor, "controller": self.controller,
                "aborted": self.aborted, "reason": self.reason, "stop_index": self.stop_index,
                "notes": list(self.notes), "summary": metric_phrases(self, with_notes=False),
                "metrics": self.metrics, "time_s": arr(self.time_s),
                "nominal_mm": arr(self.nominal_mm), "actual_mm": arr(self.actual_mm),
                "correction_mm": arr(self.correction_mm), "error_mm": arr(self.error_mm),
                "force_n": arr(self.force_n)}

    def travelled_mm(self):
        """Path length the TCP covered before the run ended or stopped, mm."""
        end = len(self.nominal_mm) if self.stop_index is None else self.stop_index + 1
        nominal = np.asarray(self.nominal_mm, dtype=float)[:end]
        return float(np.linalg.norm(np.diff(nominal, axis=0), axis=1).sum()) if len(nominal) > 1 else 0.0

    def failure(self):
        """The short name of why the run stopped ("seam lost", "collision", ...), or ""."""
        return self.reason.split(":", 1)[0].strip() if self.aborted else ""


def has_value(value):
    """True for a finite number (not None, NaN or infinite)."""
    return isinstance(value, (int, float, np.number)) and not isinstance(value, bool) \
        and bool(np.isfinite(value))


def why_no_value(run, what="measured"):
    """Why a metric of `run` has no value, as the words after the metric's name:
    ``"not measured, the run aborted after 12 mm (seam lost)"``."""
    if run.aborted:
        return "not %s, the run aborted after %.0f mm (%s)" % (what, run.travelled_mm(), run.failure())
    if run.sensor == "laser" and run.controller == "none":
        return "not %s, the open loop never measured the seam" % what
    if len(run.time_s) < 2:
        return "not %s, the run has no samples" % what
    return "not %s, no sample of the run gave one" % what


def value_text(run, value, fmt, unit="", what="measured"):
    """`value` formatted with its unit, or the sentence saying why there is none."""
    if has_value(value):
        return (fmt % value) + (" " + unit if unit else "")
    return why_no_value(run, what)


def metric_phrases(run, with_notes=True):
    """The key numbers of `run` as phrases, each a number or why there is none.

    Returns
    -------
    list of str
        Laser and arc: ``"RMS error after 20 mm 0.031 mm (max 0.42 mm)"``,
        the largest step (closed loops); force: RMS force error, mean and
        max force, or
        ``"the tool never touched the part"``; then the corrected program's
        move count when there is one, and (`with_notes`) the run's notes.
    """
    m = run.metrics
    phrases = []
    if run.sensor in SEAM_SENSORS:
        rms, largest = m.get("rms_error_after_20mm_mm"), m.get("max_error_mm")
        if has_value(rms):
            text = "RMS error after 20 mm %.3f mm" % rms
        else:
            text = "RMS error after 20 mm: %s" % why_no_value(run)
        if has_value(largest):
            text += (" (max %.2f mm)" if has_value(rms) else "; largest error %.2f mm so far") % largest
        phrases.append(text)
        if run.controller != "none":
            phrases.append("largest step %s" % value_text(run, m.get("max_step_mm"), "%.2f", "mm"))
        if run.sensor == "arc":
            phrases.append("mean current %s over %d weave cycles" % (
                value_text(run, m.get("mean_current_a"), "%.0f", "A"), m.get("weave_cycles", 0)))
    elif m.get("first_contact_s") is None:
        phrases.append("the tool never touched the part" + (
            " before the run aborted after %.0f mm (%s)" % (run.travelled_mm(), run.failure())
            if run.aborted else ""))
    else:
        phrases.append("RMS force error %s, mean force %s, max force %s" % (
            value_text(run, m.get("rms_force_error_pct"), "%.1f", "%"),
            value_text(run, m.get("mean_force_n"), "%.1f", "N"),
            value_text(run, m.get("max_force_n"), "%.1f", "N")))
    if m.get("corrected_moves") is not None:
        tolerance = m.get("corrected_tolerance_mm")
        phrases.append("Corrected program: %d moves from %d samples%s" % (
            m["corrected_moves"], m["corrected_samples"],
            " (within %g mm)" % tolerance if has_value(tolerance) else ""))
    return phrases + (list(run.notes) if with_notes else [])
