"""PI and Fuzzy-PI force controllers (sensors/controllers.py)."""

import re

import numpy as np
import pytest

from CadRobotWB.errors import InputError, UnknownNameError
from CadRobotWB.sensors import controllers as ctl

T = 0.05                     # 20 Hz
BIG = 1e9                    # limits that never act


# ------------------------------------------------------------------ PI

def test_pi_step_response_is_the_closed_form_ramp():
    """Constant error e from k = 0 (e_-1 = 0): u_k = kp e + (k + 1) ki T e."""
    kp, ki, e = 0.02, 0.3, 5.0
    pi = ctl.PIController(kp, ki, BIG, BIG)
    u = np.cumsum([pi.step(e, T) for _ in range(40)])
    k = np.arange(40)
    np.testing.assert_allclose(u, kp * e + (k + 1) * ki * T * e, rtol=1e-12)
    assert pi.displacement_mm == pytest.approx(u[-1])


def test_pi_on_a_spring_follows_the_closed_form_discrete_response():
    """Force F_k = K u_{k-1} (the robot acts one period later); e_k = F_set - F_k.

    Then e_{k+1} = (1 - K kp - K ki T) e_k + K kp e_{k-1}, e_0 = F_set, e_-1 = 0,
    whose solution is A l1^k + B l2^k with l1, l2 the roots of
    l^2 - (1 - K kp - K ki T) l - K kp = 0.
    """
    K, kp, ki, f_set = 20.0, 0.5 / 20.0, 0.4 / (20.0 * T), 20.0
    pi = ctl.PIController(kp, ki, BIG, BIG)
    u, errors = 0.0, []
    for _ in range(30):
        e = f_set - K * u
        errors.append(e)
        u += pi.step(e, T)
    a = 1.0 - K * kp - K * ki * T
    l1, l2 = np.roots([1.0, -a, -K * kp]).astype(complex)
    e0, e1 = f_set, a * f_set
    B = (e1 - l1 * e0) / (l2 - l1)
    A = e0 - B
    k = np.arange(30)
    closed = (A * l1 ** k + B * l2 ** k).real
    np.testing.assert_allclose(errors, closed, atol=1e-9)
    assert abs(errors[-1]) < 1e-3 * f_set                    # integral action: no offset


def test_pi_limits_each_step_and_the_total_without_windup():
    pi = ctl.PIController(0.0, 1.0, output_limit=0.2, integral_limit=1.0)
    steps = [pi.step(100.0, T) for _ in range(10)]
    assert steps[:5] == pytest.approx([0.2] * 5)               # 100 N * 1 * 0.05 = 5 mm wanted
    assert steps[5:] == pytest.approx([0.0] * 5)               # held at the 1 mm total
    assert pi.displacement_mm == pytest.approx(1.0)
    assert pi.step(-1.0, T) == pytest.approx(-0.05)           # comes back at once: nothing wound up


def test_pi_reset_sets_the_displacement_and_forgets_the_error():
    pi = ctl.PIController(0.1, 0.0, BIG, BIG)
    pi.step(3.0, T)
    pi.reset(-5.0)
    assert pi.displacement_mm == -5.0
    assert pi.step(3.0, T) == pytest.approx(0.3)              # kp (3 - 0): e_-1 = 0 again


def test_pi_tuning_comes_from_stiffness_and_rate():
    gains = ctl.pi_tuning(stiffness_n_mm=20.0, rate_hz=20.0, max_step_mm=0.3,
                          max_correction_mm=15.0)
    assert gains["kp"] * 20.0 == pytest.approx(ctl.PROPORTIONAL_LOOP_GAIN)
    assert gains["ki"] * T * 20.0 == pytest.approx(ctl.INTEGRAL_LOOP_GAIN)
    assert gains["output_limit"] == 0.3 and gains["integral_limit"] == 15.0
    stiffer = ctl.pi_tuning(stiffness_n_mm=40.0, rate_hz=20.0)
    assert stiffer["kp"] == pytest.approx(gains["kp"] / 2)
    assert stiffer["ki"] == pytest.approx(gains["ki"] / 2)


# ------------------------------------------------------------- Fuzzy-PI

@pytest.mark.parametrize("error, change, expected", [
    (0.0, 0.0, 0.0),            # only ZE x ZE fires -> ZE
    (1.0, 1.0, 1.0),            # PB x PB -> PB, centroid of the whole PB triangle
    (-1.0, -1.0, -1.0),
    (1.0, 0.0, 1.0),            # PB x ZE -> PB
    (1 / 6, 0.0, 1 / 6),        # ZE and PS at 0.5 each: ZE, PS clipped at 0.5, symmetric about 1/6
    (1 / 3, -1 / 3, 0.0),       # PS x NS -> ZE
    (2 / 3, 0.0, 2 / 3),        # PM x ZE -> PM
    (0.5, 0.5, 5 / 6),          # PS/PM x PS/PM at 0.5: PM and PB clipped at 0.5, trapezoid 1/3..4/3
    (0.0, -2 / 3, -2 / 3),      # ZE x NM -> NM
    (5.0, 0.0, 1.0),            # beyond the universe counts as its end
])
def test_fuzzy_rule_base_hand_checked(error, change, expected):
    assert ctl.fuzzy_increment(error, change) == pytest.approx(expected, abs=2e-3)


def test_fuzzy_surface_is_odd_and_monotonic_within_its_max_min_dips():
    grid = np.linspace(-1.2, 1.2, 49)
    for e in grid:
        row = np.array([ctl.fuzzy_increment(e, de) for de in grid])
        assert np.all(np.maximum.accumulate(row) - row <= 0.02)   # never drops more than 0.02
        for de, value in zip(grid, row):
            assert ctl.fuzzy_increment(-e, -de) == pytest.approx(-value, abs=1e-9)


def test_memberships_are_a_partition_of_unity():
    for x in np.linspace(-1.5, 1.5, 61):
        m = ctl.memberships(x)
        assert m.sum() == pytest.approx(1.0) and np.count_nonzero(m) <= 2


def test_rule_table_in_the_docstring_is_the_one_used():
    rows = {}
    for line in ctl.FuzzyPIController.__doc__.splitlines():
        words = re.findall(r"\b(?:NB|NM|NS|ZE|PS|PM|PB)\b", line)
        if len(words) == 8 and not line.strip().startswith("NB   NM"):
            rows[words[0]] = [ctl.LABELS.index(w) for w in words[1:]]
    table = np.array([rows[label] for label in ctl.LABELS])
    np.testing.assert_array_equal(table, ctl.RULE_TABLE)


def test_fuzzy_controller_scales_its_inputs_and_output():
    fuzzy = ctl.FuzzyPIController(error_scale=6.0, change_scale=2.0, output_scale=0.3,
                                  output_limit=BIG, integral_limit=BIG)
    first = fuzzy.step(2.0, T)                   # e = 2 N -> 1/3, de = 2 - 0 -> 1
    assert first == pytest.approx(0.3 * ctl.fuzzy_increment(1 / 3, 1.0))
    second = fuzzy.step(1.0, T)                  # e -> 1/6, de = -1 -> -1/2
    assert second == pytest.approx(0.3 * ctl.fuzzy_increment(1 / 6, -0.5))
    assert fuzzy.displacement_mm == pytest.approx(first + second)


def test_fuzzy_tuning_meets_the_pi_at_the_term_centres_and_is_stiffer_near_zero():
    fuzzy_params = ctl.fuzzy_pi_tuning(20.0, 20.0)
    fuzzy = ctl.make_controller("fuzzy_pi", **fuzzy_params)
    pi = ctl.make_controller("pi", **ctl.pi_tuning(20.0, 20.0))
    ge = fuzzy_params["error_scale"]

    def steps(e):                                # error only, no change (e_-1 = e)
        for controller in (fuzzy, pi):
            controller.reset()
            controller.previous_error_n = e
        return fuzzy.step(e, T), pi.step(e, T)

    for e in (ge / 3, -2 * ge / 3):
        f, p = steps(e)
        assert f == pytest.approx(p, rel=1e-3)
    f, p = steps(ge / 100)
    assert 1.3 * p < f < 1.51 * p


def test_make_controller_by_name():
    for name, cls in (("pi", ctl.PIController), ("fuzzy_pi", ctl.FuzzyPIController)):
        controller = ctl.make_controller(name, **ctl.default_tuning(name, 20.0, 20.0))
        assert isinstance(controller, cls) and controller.name == name
    none = ctl.make_controller("none")
    assert none.step(50.0, T) == 0.0 and none.name == "none"
    with pytest.raises(UnknownNameError):
        ctl.make_controller("pid")
    with pytest.raises(UnknownNameError):
        ctl.default_tuning("pid", 20.0, 20.0)
    with pytest.raises(InputError):
        ctl.make_controller("pi", kp=0.1)                     # missing parameters
    with pytest.raises(InputError):
        ctl.PIController(0.1, 0.1, output_limit=0.0, integral_limit=1.0)
