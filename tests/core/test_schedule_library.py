"""The library of starting weld schedules and the user's own (issue 22, plan
section (c)): every row cited and inside its published ranges, the pick by
joint, leg and thickness with its sentence, user files that replace rows or
are skipped with one warning, and saving."""

import json
import os
import warnings

import pytest

from CadRobotWB.core import schedule_library as library
from CadRobotWB.core.welding import WeldSchedule
from CadRobotWB.errors import InputError

ROWS = library.library_rows()
FILLETS = ["fillet_t1.2", "fillet_t1.6", "fillet_t2.0", "fillet_t2.3", "fillet_t3.2",
           "fillet_t4.5", "fillet_t6", "fillet_t9", "fillet_t12"]
BUTTS = ["butt_t0.8", "butt_t1.0", "butt_t1.2", "butt_t1.6", "butt_t2.0", "butt_t2.3",
         "butt_t3.2", "butt_t4.5", "butt_t6", "butt_t9"]
#: Miller's rule (Renegade 180 manual section 12-2): inches of wire per minute per ampere.
INCH_PER_MIN_PER_A = {0.9: 1.6, 1.2: 1.0}


@pytest.fixture(scope="module")
def schedules():
    return library.load()


def _inside(value, low_high):
    return low_high[0] <= value <= low_high[1]


def test_the_library_holds_the_two_tables_in_order(schedules):
    assert list(ROWS) == FILLETS + BUTTS
    assert list(schedules) == FILLETS + BUTTS
    assert all(ROWS[n]["joint"] == "fillet" for n in FILLETS)
    assert all(ROWS[n]["joint"] == "butt" for n in BUTTS)


@pytest.mark.parametrize("name", FILLETS + BUTTS)
def test_every_row_is_cited_and_its_values_are_the_midpoints_of_its_ranges(schedules, name):
    row, schedule = ROWS[name], schedules[name]
    manual = "Daihen OTC CPTX-i 400-2W" if row["joint"] == "fillet" else "Panasonic YD-400VP1YHD"
    assert schedule.source.startswith(manual) and ", row " in schedule.source
    assert row["source_url"].startswith("https://manualshive.com/")
    ranges = schedule.ranges
    measure = "leg_mm" if row["joint"] == "fillet" else "root_gap_mm"
    assert ranges[measure] == row[measure]
    assert set(ranges) >= {"current_a", "voltage_v", "travel_speed_mm_s", "gas_l_min", measure}
    for key in ("current_a", "voltage_v", "travel_speed_mm_s"):
        assert _inside(getattr(schedule, key), ranges[key]), key
    # midpoints, by hand: A and V exactly (to 0.1), the travel from cm/min or m/min to mm/s
    assert schedule.current_a == sum(ranges["current_a"]) / 2
    assert schedule.voltage_v == pytest.approx(sum(ranges["voltage_v"]) / 2, abs=0.051)
    if row["joint"] == "fillet":
        per_minute_mm = sum(ranges["travel_cm_min"]) / 2 * 10     # cm/min -> mm/min
    else:
        per_minute_mm = sum(ranges["travel_m_min"]) / 2 * 1000     # m/min -> mm/min
    assert schedule.travel_speed_mm_s == pytest.approx(per_minute_mm / 60, abs=0.051)
    assert ranges["travel_speed_mm_s"][0] == pytest.approx(
        min(ranges.get("travel_cm_min", [1e9])[0] / 6, ranges.get("travel_m_min", [1e9])[0] / 0.06),
        abs=0.006)


@pytest.mark.parametrize("name", FILLETS + BUTTS)
def test_every_row_says_what_is_not_from_its_table(schedules, name):
    row, schedule = ROWS[name], schedules[name]
    notes = " ".join(row["notes"])
    # wire feed from Miller's rule, flagged, and flagged as extrapolated above 250 A
    rule = INCH_PER_MIN_PER_A[schedule.wire_mm]
    assert schedule.wire_feed_estimated and row["wire_feed_estimated"] is True
    assert schedule.wire_feed_m_min == row["wire_feed_m_min"]
    assert abs(schedule.wire_feed_m_min - schedule.current_a * rule * 25.4 / 1000) <= 0.05
    assert ("extrapolation" in notes) == (schedule.current_a > 250)
    assert "Gas pre-flow 0.2 s, post-flow 0.5 s, crater fill 0.3 s" in notes
    assert (schedule.gas_preflow_s, schedule.gas_postflow_s, schedule.crater_fill_s,
            schedule.burnback_s) == (0.2, 0.5, 0.3, 0.05)
    if row["joint"] == "fillet":
        assert schedule.ctwd_mm == 15.0 and "CTWD default, not from the table" in notes
    else:
        assert schedule.ctwd_mm == sum(schedule.ranges["ctwd_mm"]) / 2


def test_spot_rows_against_the_published_tables(schedules):
    """Numbers read off the manuals' pages by hand (plan (c)): fillet 6 mm plate, leg
    5-6 mm: 250-280 A, 26-29 V, 40-50 cm/min; butt 9 mm: 320-340 A, 32-34 V, 0.40-0.50 m/min,
    CTWD 15 mm, front then back."""
    t6 = schedules["fillet_t6"]
    assert (t6.current_a, t6.voltage_v, t6.travel_speed_mm_s, t6.wire_feed_m_min, t6.wire_mm) == \
        (265.0, 27.5, 7.5, 6.7, 1.2)
    t9 = schedules["butt_t9"]
    assert (t9.current_a, t9.voltage_v, t9.travel_speed_mm_s, t9.ctwd_mm) == (330.0, 33.0, 7.5, 15.0)
    assert ROWS["butt_t9"]["two_sided"] and not ROWS["butt_t4.5"]["two_sided"]
    thin = schedules["fillet_t1.2"]         # the table gives 0.9 or 1.0 mm wire: 0.9, 1.6 in/A
    assert (thin.wire_mm, thin.current_a, thin.wire_feed_m_min) == (0.9, 85.0, 3.5)


# --- lookup ----------------------------------------------------------------------------------

@pytest.mark.parametrize("joint, thickness, leg, name, sentence", [
    ("fillet", None, 6, "fillet_t6", "picked fillet_t6 (plate 6 mm, leg 5-6 mm) for a 6 mm leg"),
    ("fillet", 6, None, "fillet_t6", "picked fillet_t6 (plate 6 mm, leg 5-6 mm) for a 6 mm plate"),
    ("fillet", 9, 6, "fillet_t9",      # leg 6 is in both t6 (5-6) and t9 (6-7): the plate decides
     "picked fillet_t9 (plate 9 mm, leg 6-7 mm) for a 6 mm leg on a 9 mm plate"),
    ("fillet", None, 4.2, "fillet_t4.5",
     "picked fillet_t4.5 (plate 4.5 mm, leg 4-4.5 mm) for a 4.2 mm leg"),
    ("fillet", 7.5, None, "fillet_t6",  # 1.5 mm from 6 and from 9: the thinner plate's row
     "picked fillet_t6 (plate 6 mm, leg 5-6 mm) for a 7.5 mm plate"),
    ("fillet", 20, None, "fillet_t12", "picked fillet_t12 (plate 12 mm, leg 7-8 mm) for a 20 mm "
     "plate (outside the table's 1.2-12 mm: its nearest row)"),
    ("butt", 3, None, "butt_t3.2", "picked butt_t3.2 (plate 3.2 mm, root gap 1-1.2 mm) for a 3 mm "
     "plate"),
])
def test_lookup_picks_the_row_and_says_why(schedules, joint, thickness, leg, name, sentence):
    schedule, said = library.lookup(schedules, joint, thickness_mm=thickness, leg_mm=leg)
    assert schedule is schedules[name] and said == sentence


def test_the_papers_8_mm_butt_picks_the_9_mm_row_and_says_one_pass_does_not_penetrate(schedules):
    schedule, said = library.lookup(schedules, "butt", thickness_mm=8)
    assert schedule.name == "butt_t9"
    assert said.startswith("picked butt_t9 (plate 9 mm, root gap 1.2-1.5 mm) for an 8 mm plate; ")
    assert "from both sides" in said and "does not penetrate it fully" in said
    assert "both sides" not in library.lookup(schedules, "butt", thickness_mm=4.5)[1]


@pytest.mark.parametrize("joint", ["lap", "v_groove", "surface", "convex_edge", "none"])
def test_a_joint_without_library_rows_is_refused_naming_it(schedules, joint):
    with pytest.raises(InputError) as caught:
        library.lookup(schedules, joint, thickness_mm=6)
    message = str(caught.value)
    assert f"'{joint}' joint" in message and "pick a schedule by name" in message
    assert "\n" not in message


@pytest.mark.parametrize("joint, thickness, leg, expected", [
    ("fillet", None, None, "give the plate thickness_mm or leg_mm"),
    ("butt", None, 5, "give the thickness_mm"),
    ("butt", -2, None, "thickness_mm is -2: give a positive number"),
    ("fillet", None, float("nan"), "leg_mm is nan"),
])
def test_lookup_without_a_measure_to_pick_by_is_refused(schedules, joint, thickness, leg, expected):
    with pytest.raises(InputError, match=expected):
        library.lookup(schedules, joint, thickness_mm=thickness, leg_mm=leg)


# --- the user's schedules ---------------------------------------------------------------------

def _write(folder, name, content):
    path = folder / name
    path.write_text(content if isinstance(content, str) else json.dumps(content), encoding="utf-8")
    return str(path)


def test_a_user_schedule_replaces_the_library_row_of_its_name(tmp_path):
    _write(tmp_path, "fillet_t6.json", {"voltage_v": 28.5, "current_a": 270, "travel_speed_mm_s": 7,
                                        "source": "our WPS 12"})
    _write(tmp_path, "shop.json", [{"name": "thin_lap", "voltage_v": 17, "wire_feed_m_min": 3,
                                    "travel_speed_mm_s": 9, "wire_mm": 0.8},
                                   {"name": "root", "voltage_v": 19, "current_a": 120,
                                    "travel_speed_mm_s": 4}])
    schedules = library.load(str(tmp_path), warn=pytest.fail)
    assert list(schedules) == FILLETS + BUTTS + ["thin_lap", "root"]
    mine = schedules["fillet_t6"]
    assert (mine.name, mine.voltage_v, mine.current_a, mine.source) == \
        ("fillet_t6", 28.5, 270.0, "our WPS 12")
    assert schedules["root"].wire_feed_m_min == pytest.approx(3.0)   # 120 in/min = 3.05 m/min
    _, said = library.lookup(schedules, "fillet", thickness_mm=6)
    assert said.endswith("; your own schedule of that name replaces the library's")
    assert library.load()["fillet_t6"].voltage_v == 27.5      # the library itself is unchanged


@pytest.mark.parametrize("content, expected", [
    ("{\"voltage_v\": 20,", "is not valid JSON (line 1, column"),
    ({"voltage_v": 20, "current_a": 150, "travel_speed_mm_s": 8, "amps": 3},
     "unknown key 'amps'"),
    ({"voltage_v": 70, "current_a": 150, "travel_speed_mm_s": 8},
     "voltage_v 70 V is outside 10 to 50 V"),
    ([{"voltage_v": 20, "current_a": 150, "travel_speed_mm_s": 8}], "has no name"),
    ("[3]", "must hold one schedule"),
    ("\"fillet\"", "must hold one schedule"),
    ({"voltage_v": 20, "current_a": 150, "travel_speed_mm_s": 8, "ranges": [1, 2]},
     "ranges must be a dict"),
], ids=["json", "unknown-key", "range", "no-name", "list-of-numbers", "text", "ranges"])
def test_a_broken_user_file_is_skipped_with_one_warning_naming_it(tmp_path, content, expected):
    path = _write(tmp_path, "broken.json", content)
    _write(tmp_path, "good.json", {"voltage_v": 20, "current_a": 150, "travel_speed_mm_s": 8})
    said = []
    schedules = library.load(str(tmp_path), warn=said.append)
    assert "good" in schedules and "broken" not in schedules and len(schedules) == 20
    assert len(said) == 1 and "\n" not in said[0], said
    assert said[0].startswith(f"Weld schedule file '{path}' skipped: ") and expected in said[0]
    assert said[0].endswith("Fix the file or delete it.")


def test_skipped_files_are_python_warnings_without_a_callback(tmp_path):
    _write(tmp_path, "a.json", "not json")
    _write(tmp_path, "b.json", {"volts": 20})
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        schedules = library.load(str(tmp_path))
    assert [w.category for w in caught] == [library.ScheduleFileWarning] * 2
    assert "a.json" in str(caught[0].message) and "b.json" in str(caught[1].message)
    assert len(schedules) == 19


def test_a_missing_folder_hidden_files_and_other_files_are_not_read(tmp_path):
    _write(tmp_path, ".draft.json", "not json")
    _write(tmp_path, "notes.txt", "not json")
    assert len(library.load(str(tmp_path / "none"), warn=pytest.fail)) == 19
    assert len(library.load(str(tmp_path), warn=pytest.fail)) == 19


def test_save_writes_a_file_load_reads_back_the_same_schedule(tmp_path):
    folder = str(tmp_path / "weld_schedules")
    base = library.load()["fillet_t6"]
    mine = WeldSchedule.from_dict({"voltage_v": 28.0, "name": "fillet_t6_hot"}, base=base)
    path = library.save(folder, mine)
    assert path == os.path.join(folder, "fillet_t6_hot.json")
    assert os.listdir(folder) == ["fillet_t6_hot.json"]
    back = library.load(folder, warn=pytest.fail)["fillet_t6_hot"]
    assert back == mine and back.ranges == base.ranges and back.wire_feed_estimated
    assert json.load(open(path, encoding="utf-8"))["voltage_v"] == 28.0
    again = library.save(folder, WeldSchedule.from_dict({"voltage_v": 29.0}, base=back))
    assert again != path         # a changed schedule without a name is "<name> (changed)"
    assert library.load(folder, warn=pytest.fail)["fillet_t6_hot (changed)"].voltage_v == 29.0


@pytest.mark.parametrize("name, problem", [
    ("a/b", "it holds '/'"), ("", "it is empty"), (".hidden", "it starts with '.'"),
    ("CON", "CON is a device name on Windows"), ("x" * 300, "it is 305 bytes long")])
def test_save_refuses_a_name_that_cannot_be_a_file_name_and_writes_nothing(tmp_path, name, problem):
    schedule = WeldSchedule.from_dict({"voltage_v": 20, "current_a": 150, "travel_speed_mm_s": 8,
                                       "name": name})
    with pytest.raises(InputError) as caught:
        library.save(str(tmp_path), schedule)
    message = str(caught.value)
    assert message.startswith("Weld schedule name ") and f"cannot name its file ({problem}" in message
    assert "\n" not in message and os.listdir(tmp_path) == []


def test_save_refuses_an_invalid_schedule_and_writes_nothing(tmp_path):
    with pytest.raises(InputError, match="voltage_v is missing"):
        library.save(str(tmp_path), WeldSchedule(name="empty"))
    assert os.listdir(tmp_path) == []


def test_the_schedule_table_has_one_row_per_schedule_in_plain_numbers():
    table = library.schedule_table()
    assert len(table) == 19 and all(len(row) == len(library.TABLE_COLUMNS) for row in table)
    assert table[6] == ("fillet_t6", "fillet", "6", "5-6", "265", "27.5", "7.5", "6.7*",
                        "Daihen OTC CPTX-i 400-2W manual section 9.5.1 (horizontal fillet, CO2)")
    assert table[-1][:8] == ("butt_t9", "butt", "9", "1.2-1.5", "330", "33", "7.5", "8.4*")
    own = {"mine": WeldSchedule.from_dict({"voltage_v": 20, "wire_feed_m_min": 4,
                                           "travel_speed_mm_s": 8, "name": "mine"})}
    assert library.schedule_table(own) == [("mine", "-", "-", "-", "-", "20", "8", "4", "-")]
