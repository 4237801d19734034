"""The weld schedules of the scripting API (issue 22): ``api.weld_schedules()`` lists
the library's and the user's own, ``api.save_weld_schedule`` keeps one in the user's
weld schedule folder (``$CADROBOT_WELD_SCHEDULE_FOLDER`` here)."""

import json
import os
import warnings

import pytest

from CadRobotWB import api, preferences
from CadRobotWB.core.schedule_library import ScheduleFileWarning
from CadRobotWB.errors import InputError


@pytest.fixture
def folder(tmp_path, monkeypatch):
    """An empty user weld schedule folder for the test."""
    path = str(tmp_path / "weld_schedules")
    monkeypatch.setenv(preferences.WELD_SCHEDULE_FOLDER_VARIABLE, path)
    return path


def test_the_folder_is_beside_the_user_robot_folder_unless_set(monkeypatch, tmp_path):
    monkeypatch.delenv(preferences.WELD_SCHEDULE_FOLDER_VARIABLE, raising=False)
    monkeypatch.delenv(preferences.ROBOT_FOLDER_VARIABLE, raising=False)
    monkeypatch.setattr(preferences, "get", lambda name: "")
    robots = preferences.user_robot_folder()
    assert preferences.weld_schedule_folder() == os.path.join(os.path.dirname(robots),
                                                              "weld_schedules")
    monkeypatch.setattr(preferences, "get", lambda name: {"WeldScheduleFolder": "/shop/wps"}[name])
    assert preferences.weld_schedule_folder() == "/shop/wps"
    monkeypatch.setenv(preferences.WELD_SCHEDULE_FOLDER_VARIABLE, str(tmp_path))
    assert preferences.weld_schedule_folder() == str(tmp_path)


def test_saved_schedules_are_listed_with_the_library_and_replace_its_rows(folder):
    schedules = api.weld_schedules()
    assert len(schedules) == 19 and schedules["fillet_t6"]["current_a"] == 265.0
    hot = dict(schedules["fillet_t6"], voltage_v=28.5)     # the API dict given back, changed
    path = api.save_weld_schedule("fillet_t6", hot)
    assert path == os.path.join(folder, "fillet_t6.json")
    own = api.save_weld_schedule("root_pass", {"voltage_v": 19, "current_a": 120,
                                               "travel_speed_mm_s": 4})
    assert json.load(open(own, encoding="utf-8"))["wire_feed_m_min"] == 3.0   # 120 in/min
    schedules = api.weld_schedules()
    assert list(schedules)[-1] == "root_pass" and len(schedules) == 20
    assert schedules["fillet_t6"]["voltage_v"] == 28.5
    assert schedules["fillet_t6"]["wire_feed_estimated"] is True


def test_a_bad_schedule_is_one_line_and_nothing_is_written(folder):
    with pytest.raises(InputError) as caught:
        api.save_weld_schedule("mine", {"voltage_v": 70, "current_a": 150, "travel_speed_mm_s": 8})
    assert str(caught.value) == ("save_weld_schedule: schedule 'mine': voltage_v 70 V is outside "
                                 "10 to 50 V: give a value in that range.")
    with pytest.raises(InputError, match="cannot name its file"):
        api.save_weld_schedule("a/b", {"voltage_v": 20, "current_a": 150, "travel_speed_mm_s": 8})
    assert not os.path.exists(folder)


def test_a_broken_user_file_is_a_warning_and_the_rest_are_listed(folder):
    os.makedirs(folder)
    with open(os.path.join(folder, "broken.json"), "w", encoding="utf-8") as f:
        f.write("{")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        schedules = api.weld_schedules()
    assert len(schedules) == 19
    assert [w.category for w in caught] == [ScheduleFileWarning]
    assert "broken.json' skipped: it is not valid JSON" in str(caught[0].message)
