"""Weld data as plain data (issue 22, core/welding.py): the API dicts of the
schedule, the weave and the tracking, their stated defaults, and every refusal
as one line naming the key and the fix."""

import pytest

from CadRobotWB.core.welding import (SCHEDULE_FIELDS, TRACKING_FIELDS, WEAVE_FIELDS, Tracking,
                                     Weave, WeldSchedule)
from CadRobotWB.errors import InputError

#: A schedule as a user gives it: the fillet 6 mm row of the Daihen OTC table (midpoints).
FILLET_T6_DICT = {"wire_mm": 1.2, "voltage_v": 27.5, "current_a": 265, "travel_speed_mm_s": 7.5}
INCH_MM = 25.4


def _one_line_error(call):
    with pytest.raises(InputError) as caught:
        call()
    message = str(caught.value)
    assert "\n" not in message and len(message) < 400, message
    return message


# --- schedule --------------------------------------------------------------------------------

def test_a_schedule_dict_gives_its_values_and_the_stated_defaults():
    schedule = WeldSchedule.from_dict({**FILLET_T6_DICT, "name": "mine", "ctwd_mm": 18})
    assert (schedule.name, schedule.wire_mm, schedule.voltage_v, schedule.current_a,
            schedule.travel_speed_mm_s, schedule.ctwd_mm) == ("mine", 1.2, 27.5, 265.0, 7.5, 18.0)
    # keys left out: pre-flow 0.2 s, post-flow 0.5 s, crater 0.3 s, burn-back 0.05 s, CO2, GMAW
    assert (schedule.gas_preflow_s, schedule.gas_postflow_s, schedule.crater_fill_s,
            schedule.burnback_s, schedule.gas, schedule.process, schedule.job_number) == \
        (0.2, 0.5, 0.3, 0.05, "CO2", "GMAW", 0)


def test_the_wire_feed_left_out_is_derived_from_the_current_by_millers_rule():
    # 1.2 mm (0.045 in) wire: 1 in/min per ampere; 265 A -> 265 in/min = 6.731 m/min
    schedule = WeldSchedule.from_dict(FILLET_T6_DICT)
    assert schedule.wire_feed_m_min == pytest.approx(6.7) and schedule.wire_feed_estimated
    assert abs(schedule.wire_feed_m_min - 265 * INCH_MM / 1000) < 0.05
    # 0.9 mm (0.035 in): 1.6 in/min per ampere; 85 A -> 136 in/min = 3.454 m/min
    thin = WeldSchedule.from_dict({**FILLET_T6_DICT, "wire_mm": 0.9, "current_a": 85})
    assert thin.wire_feed_m_min == pytest.approx(3.5)
    given = WeldSchedule.from_dict({**FILLET_T6_DICT, "wire_feed_m_min": 7.0})
    assert given.wire_feed_m_min == 7.0 and not given.wire_feed_estimated


def test_a_wire_feed_that_cannot_be_derived_is_asked_for():
    message = _one_line_error(lambda: WeldSchedule.from_dict({**FILLET_T6_DICT, "wire_mm": 1.0}))
    assert "wire_feed_m_min" in message
    no_current = {k: v for k, v in FILLET_T6_DICT.items() if k != "current_a"}
    assert "wire_feed_m_min" in _one_line_error(lambda: WeldSchedule.from_dict(no_current))


def test_crater_values_left_out_follow_the_weld_values():
    # 0.7 x 200 A = 140 A, 0.8 x 25 V = 20 V, 0.7 x 5.1 m/min = 3.57 -> 3.6 m/min
    schedule = WeldSchedule.from_dict({"voltage_v": 25, "current_a": 200, "wire_feed_m_min": 5.1,
                                       "travel_speed_mm_s": 8})
    assert (schedule.crater_current_a, schedule.crater_voltage_v,
            schedule.crater_wire_feed_m_min) == (140.0, 20.0, 3.6)
    own = WeldSchedule.from_dict({"voltage_v": 25, "current_a": 200, "wire_feed_m_min": 5.1,
                                  "travel_speed_mm_s": 8, "crater_current_a": 120})
    assert own.crater_current_a == 120.0


@pytest.mark.parametrize("key", ["voltage_v", "travel_speed_mm_s"])
def test_a_schedule_without_voltage_or_travel_speed_is_refused(key):
    values = {k: v for k, v in FILLET_T6_DICT.items() if k != key}
    message = _one_line_error(lambda: WeldSchedule.from_dict(values))
    assert f"{key} is missing" in message


def test_the_api_dict_of_a_schedule_gives_the_same_schedule_back():
    schedule = WeldSchedule.from_dict(FILLET_T6_DICT)
    assert WeldSchedule.from_dict(schedule.as_dict()) == schedule
    assert WeldSchedule.from_dict(schedule.as_dict()).wire_feed_estimated
    changed = {**schedule.as_dict(), "wire_feed_m_min": 7.5}   # the user's own wire feed
    assert not WeldSchedule.from_dict(changed).wire_feed_estimated
    message = _one_line_error(lambda: WeldSchedule.from_dict({**schedule.as_dict(),
                                                              "wire_feed_estimated": "yes"}))
    assert "wire_feed_estimated" in message


def test_a_schedule_changed_from_a_base_keeps_the_rest_and_says_it_changed():
    base = WeldSchedule.from_dict({**FILLET_T6_DICT, "name": "fillet_t6"})
    hotter = WeldSchedule.from_dict({"current_a": 280}, base=base)
    assert (hotter.name, hotter.voltage_v, hotter.current_a) == ("fillet_t6 (changed)", 27.5, 280)
    assert hotter.wire_feed_m_min == pytest.approx(7.1)   # 280 in/min = 7.112 m/min, derived again


def _above(spec):
    return spec[2] + max(1.0, abs(spec[2]))


@pytest.mark.parametrize("make, fields", [
    (lambda d: WeldSchedule.from_dict({**FILLET_T6_DICT, **d}), SCHEDULE_FIELDS),
    (Weave.from_dict, WEAVE_FIELDS),
    (Tracking.from_dict, TRACKING_FIELDS)], ids=["schedule", "weave", "tracking"])
def test_every_value_out_of_range_is_one_line_naming_the_key_and_the_range(make, fields):
    for key, spec in fields.items():
        _, low, high, unit, _ = spec
        for value in (low - max(1.0, abs(low)), _above(spec)):
            values = {key: value}
            if key == "length_mm":
                values["frequency_hz"] = None
            message = _one_line_error(lambda: make(values))
            assert key in message and f"{low:g} to {high:g}" in message, message
        message = _one_line_error(lambda: make({key: "3"}))   # a text, not a number
        assert key in message and f"from {low:g} to {high:g}" in message, message


def test_the_ranges_read_in_the_messages_are_the_stated_ones():
    message = _one_line_error(lambda: WeldSchedule.from_dict({**FILLET_T6_DICT, "voltage_v": 70}))
    assert message == "Weld schedule: voltage_v 70 V is outside 10 to 50 V: give a value in that range."
    message = _one_line_error(lambda: Weave.from_dict({"frequency_hz": 8}))
    assert message == "Weave: frequency_hz 8 Hz is outside 0.1 to 5 Hz: give a value in that range."


@pytest.mark.parametrize("make, first_known", [
    (WeldSchedule.from_dict, "burnback_s"), (Weave.from_dict, "angle_deg"),
    (Tracking.from_dict, "height_gain")], ids=["schedule", "weave", "tracking"])
def test_an_unknown_key_is_one_line_naming_it_and_the_known_keys(make, first_known):
    message = _one_line_error(lambda: make({"amps": 200}))
    assert "unknown key 'amps'" in message and f"use {first_known}" in message


def test_a_schedule_that_is_not_a_dict_or_has_a_text_that_is_not_text_is_refused():
    assert "must be a dict" in _one_line_error(lambda: WeldSchedule.from_dict([265]))
    assert "name must be text" in _one_line_error(
        lambda: WeldSchedule.from_dict({**FILLET_T6_DICT, "name": 6}))
    assert "process 'TIG'" in _one_line_error(
        lambda: WeldSchedule.from_dict({**FILLET_T6_DICT, "process": "TIG"}))


# --- weave -----------------------------------------------------------------------------------

def test_a_weave_left_out_takes_the_stated_defaults():
    weave = Weave.from_dict({})
    assert (weave.pattern, weave.width_mm, weave.frequency_hz, weave.length_mm, weave.dwells_s,
            weave.angle_deg, weave.height) == ("zigzag", 4.0, 2.0, None, 0.0, 0.0, 2.0)
    assert weave.cycle_time_s(7.5) == 0.5 and weave.cycle_length_mm(7.5) == 3.75


def test_a_weave_by_length_has_its_cycle_from_the_travel_speed():
    weave = Weave.from_dict({"length_mm": 3.0})
    assert weave.frequency_hz is None
    assert weave.cycle_time_s(7.5) == pytest.approx(0.4) and weave.frequency(7.5) == pytest.approx(2.5)


def test_a_weave_with_both_length_and_frequency_is_refused():
    message = _one_line_error(lambda: Weave.from_dict({"length_mm": 3.0, "frequency_hz": 2.0}))
    assert "length_mm or frequency_hz, not both" in message
    # from a base, the one given replaces the other
    base = Weave.from_dict({"length_mm": 3.0})
    assert Weave.from_dict({"frequency_hz": 1.5}, base=base).length_mm is None


def test_dwells_that_fill_the_cycle_are_refused_with_the_fix():
    # 2 Hz: a 0.5 s cycle; 0.2 + 0.1 + 0.2 s of dwells leave no time to move
    message = _one_line_error(lambda: Weave.from_dict(
        {"frequency_hz": 2.0, "dwell_left_s": 0.2, "dwell_center_s": 0.1, "dwell_right_s": 0.2}))
    assert "fill the whole weave cycle (0.5 s)" in message
    assert "lower the frequency or shorten the dwells" in message
    assert Weave.from_dict({"frequency_hz": 2.0, "dwell_left_s": 0.2, "dwell_right_s": 0.2})


def test_dwells_that_fill_a_cycle_given_by_length_are_refused_at_the_travel_speed():
    from CadRobotWB.core.weave import moving_time_s
    weave = Weave.from_dict({"length_mm": 3.0, "dwell_left_s": 0.2, "dwell_right_s": 0.2})
    assert moving_time_s(weave, 5.0) == pytest.approx(0.6 - 0.4)      # 3 mm at 5 mm/s: 0.6 s
    message = _one_line_error(lambda: moving_time_s(weave, 7.5, "Weld 'W1'"))   # 0.4 s cycle
    assert message.startswith("Weld 'W1': ") and "lower the frequency or shorten" in message


def test_a_circle_with_dwells_and_an_unknown_pattern_are_refused():
    message = _one_line_error(lambda: Weave.from_dict({"pattern": "circle", "dwell_left_s": 0.1}))
    assert "circle weave has no dwells" in message
    message = _one_line_error(lambda: Weave.from_dict({"pattern": "sine"}))
    assert "pattern 'sine'" in message and "zigzag, triangle, circle, l" in message


def test_the_height_of_triangle_and_l_defaults_to_half_the_width():
    assert Weave.from_dict({"pattern": "triangle", "width_mm": 6}).height == 3.0
    assert Weave.from_dict({"pattern": "l", "width_mm": 6, "height_mm": 4}).height == 4.0


# --- tracking --------------------------------------------------------------------------------

def test_tracking_defaults_and_the_sensor_given_by_name():
    assert Tracking.from_dict({}) == Tracking("none", 0.5, 0.5, "schedule", 15.0)
    arc = Tracking.from_dict("arc")
    assert arc.sensor == "arc" and arc.lateral_gain == 0.5
    learned = Tracking.from_dict({"sensor": "arc", "reference": "learned", "lateral_gain": 0.8})
    assert (learned.reference, learned.lateral_gain) == ("learned", 0.8)


def test_an_unknown_sensor_or_reference_is_refused_with_the_choices():
    assert "none, arc, laser" in _one_line_error(lambda: Tracking.from_dict("camera"))
    assert "schedule, learned" in _one_line_error(
        lambda: Tracking.from_dict({"sensor": "arc", "reference": "start"}))
