"""Run summaries: every key number is a number or a sentence saying why there is none."""

import re

import numpy as np

from CadRobotWB.sensors.run import SensorRun, has_value, metric_phrases, why_no_value

PLACEHOLDERS = re.compile(r"(^|[\s(=:])(-|nan|None)([\s),;.]|$)")


def laser_run(aborted, stop_index=None, controller="pi", **metrics):
    t = np.arange(0.0, 10.0, 0.1)                          # 100 samples at 10 mm/s: 1 mm apart
    nominal = np.column_stack([10.0 * t, np.zeros_like(t), np.zeros_like(t)])
    base = {"rms_error_after_20mm_mm": float("nan"), "max_error_mm": float("nan"), "max_step_mm": 0.0}
    base.update(metrics)
    return SensorRun("laser", controller, t, nominal, nominal, np.zeros_like(nominal), np.full(len(t), np.nan),
                     metrics=base, aborted=aborted,
                     reason="seam lost: no butt joint matched in 3 profiles in a row" if aborted else "",
                     stop_index=stop_index)


def test_an_aborted_laser_run_says_why_the_rms_error_is_missing():
    run = laser_run(True, stop_index=12)
    assert abs(run.travelled_mm() - 12.0) < 1e-9           # samples 0..12, 1 mm apart
    assert run.failure() == "seam lost"
    phrases = metric_phrases(run)
    assert phrases[0] == "RMS error after 20 mm: not measured, the run aborted after 12 mm (seam lost)"
    assert phrases[1] == "largest step 0.00 mm"
    for phrase in phrases:
        assert not PLACEHOLDERS.search(phrase), phrase
    assert run.to_dict()["summary"] == phrases                 # report.json says it too


def test_a_completed_laser_run_prints_its_numbers():
    run = laser_run(False, rms_error_after_20mm_mm=0.0312, max_error_mm=0.456, max_step_mm=0.5)
    assert metric_phrases(run)[:2] == ["RMS error after 20 mm 0.031 mm (max 0.46 mm)", "largest step 0.50 mm"]
    run.notes.append("Laser seam tracking was asked for although the path has no joint.")
    assert metric_phrases(run)[-1] == run.notes[0] and run.notes[0] not in metric_phrases(run, with_notes=False)


def test_the_open_loop_and_an_aborted_force_run_say_why_without_numbers():
    run = laser_run(False, controller="none")
    assert metric_phrases(run) == ["RMS error after 20 mm: not measured, the open loop never measured the seam"]
    force = SensorRun("force", "pi", np.arange(0, 1, 0.1), np.zeros((10, 3)), np.zeros((10, 3)),
                      np.zeros((10, 3)), np.zeros(10), metrics={"first_contact_s": None, "max_force_n": 0.0},
                      aborted=True, reason="collision: the ball touches Clamp", stop_index=4)
    assert metric_phrases(force) == ["the tool never touched the part before the run aborted after 0 mm "
                                     "(collision)"]
    force.metrics.update(first_contact_s=0.2, rms_force_error_pct=None, mean_force_n=float("nan"))
    text = metric_phrases(force)[0]
    assert text.startswith("RMS force error not measured, the run aborted after 0 mm (collision)")
    assert text.endswith("max force 0.0 N")
    assert why_no_value(force, "computed").startswith("not computed")


def test_has_value_refuses_none_nan_inf_and_bools():
    assert [has_value(v) for v in (1, 2.5, np.float64(3), None, float("nan"), float("inf"), True)] == \
        [True, True, True, False, False, False, False]
