"""Force following gives the outputs recorded before issue 12's speed-up.

The cases (force_following_cases.py) are the benchmark's, the example
profile-following cell's (as ``api.simulate(..., sensor="force")`` runs it),
and one scene per failure branch, abort and reactive. For each: every step's
time, nominal and actual position, correction, gap and F/T reading (or every
20th step and sums over all steps), the stop, the events and the report's
metrics.

Tolerance: ``RTOL = 1e-9`` of the magnitude of what is compared (an array's
largest value, a metric's own value). The recorded and the current code
compute the same quantities in another order: the closest point of a
triangle from dot products taken once per triangle and reciprocals of its
edge lengths (trimesh divides per point), a control period's ball centres
in one candidate set, the torque ``r f (e_z x n_t)`` in closed form instead
of ``arm x F`` (the same for a rotation matrix), and numpy 1.24 (Debian 12)
against 2.2 / 2.4 (the FreeCAD 1.0 / 1.1 roots: other SIMD kernels for sin,
sums and dot products). Each differs by a few ulps of its operands; the
loop is stable (Lipschitz controllers, the robot lag a contraction), so the
outputs stay within 7.6e-14 of an array's largest value (measured on the
host and in the 1.1 root), four orders of magnitude below RTOL, while a
change of the physics (a step, a gain, a noise sample, a failure handled at
another step) moves them by far more. Near-zero values (Fx, Fy, torques, a
correction along a flat part) are compared to the array's largest
magnitude, not their own: their rounding is that of the operands they come
from. Strings (reasons, event messages), step counts, stop indices and flags
must be equal.
"""

import math

import numpy as np
import pytest

import force_following_cases as cases_module

RTOL = 1e-9
#: Largest magnitude a metric's absolute tolerance is taken from (%, N, s, mm).
METRIC_SCALE = 100.0

RECORDED = cases_module.load()
CASES = cases_module.cases()


def test_every_case_is_recorded():
    assert sorted(RECORDED) == sorted(CASES)


def assert_close_arrays(name, actual, expected):
    """`actual` within RTOL of the largest |value| of `expected` (NaN where it has NaN)."""
    expected = np.asarray(expected, dtype=float)
    assert np.shape(actual) == expected.shape, name
    finite = expected[np.isfinite(expected)]
    scale = float(np.abs(finite).max()) if finite.size else 0.0
    np.testing.assert_allclose(actual, expected, rtol=RTOL, atol=RTOL * scale, equal_nan=True,
                               err_msg=name)


def assert_close_values(name, actual, expected):
    """Numbers within RTOL (absolute floor RTOL * METRIC_SCALE); the rest equal, recursively."""
    if isinstance(expected, dict):
        assert isinstance(actual, dict) and sorted(actual) == sorted(expected), name
        for key in expected:
            assert_close_values("%s.%s" % (name, key), actual[key], expected[key])
    elif isinstance(expected, list):
        assert isinstance(actual, (list, tuple)) and len(actual) == len(expected), name
        for k, (a, e) in enumerate(zip(actual, expected)):
            assert_close_values("%s[%d]" % (name, k), a, e)
    elif isinstance(expected, float) and not isinstance(actual, bool):
        assert isinstance(actual, (int, float)), (name, actual)
        assert math.isclose(actual, expected, rel_tol=RTOL, abs_tol=RTOL * METRIC_SCALE) or (
            math.isnan(actual) and math.isnan(expected)), (name, actual, expected)
    else:
        assert actual == expected, (name, actual, expected)


@pytest.mark.parametrize("name", sorted(CASES))
def test_the_run_gives_the_recorded_outputs(name):
    make_run, every = CASES[name]
    run = make_run()
    arrays, meta = RECORDED[name]
    assert meta["every"] == every
    assert len(run.time_s) == meta["steps"]
    for key in ("aborted", "reason", "stop_index", "controller", "sensor"):
        assert getattr(run, key) == meta[key], key
    assert (run.stop_T_u_t is None) == (meta["stop_T_u_t"] is None)
    if run.stop_T_u_t is not None:
        assert_close_arrays("stop_T_u_t", run.stop_T_u_t, meta["stop_T_u_t"])
    assert_close_values("metrics", run.metrics, meta["metrics"])

    produced = {key: np.asarray(getattr(run, key), dtype=float) for key in cases_module.ARRAYS}
    # The correction is actual - nominal, the same subtraction of the recorded values.
    produced["correction_mm"] = np.asarray(run.correction_mm, dtype=float)
    arrays = dict(arrays, correction_mm=arrays["actual_mm"] - arrays["nominal_mm"])
    for key, values in produced.items():
        if key in arrays:
            assert_close_arrays(key, values[::every], arrays[key])
        if key + ":sum" in arrays:
            assert_close_arrays(key + ":abs_sum", np.abs(values).sum(axis=0),
                                arrays[key + ":abs_sum"])
            np.testing.assert_allclose(values.sum(axis=0), arrays[key + ":sum"], rtol=0,
                                       atol=RTOL * arrays[key + ":abs_sum"].max(), err_msg=key)
