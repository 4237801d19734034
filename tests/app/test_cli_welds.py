"""`cadrobot welds`: one line per weld, --json, --schedules and the exit codes of the
other listing commands (0; a weld that cannot be read is a warning, bad input 2)."""

import io
import json

import pytest

import FreeCAD
from CadRobotWB import api, cli
from conftest import run_cadrobot
from helpers import fillet_cell

ZIGZAG = {"pattern": "zigzag", "width_mm": 4.0, "frequency_hz": 1.0}


@pytest.fixture(scope="module")
def welds_file(tmp_path_factory):
    """The T joint with three welds: the library's with a weave, a custom one on
    segment 2 with arc tracking, and one whose path link is gone."""
    doc = FreeCAD.newDocument("CliWelds")
    try:
        cell, path, _ = fillet_cell(doc)
        api.make_weld(doc, cell, path, weave=ZIGZAG)
        api.make_weld(doc, cell, path, schedule={"voltage_v": 24, "current_a": 200,
                                                 "travel_speed_mm_s": 5},
                      weave={"pattern": "triangle", "length_mm": 3.0, "dwell_left_s": 0.1},
                      first_segment=2, last_segment=2, tracking="arc", name="Second")
        broken = api.make_weld(doc, cell, path, schedule="fillet_t6", name="Broken")
        broken.Path = None
        path_file = str(tmp_path_factory.mktemp("welds") / "welds.FCStd")
        doc.saveAs(path_file)
    finally:
        FreeCAD.closeDocument(doc.Name)
    return path_file


def run(*argv):
    out, err = io.StringIO(), io.StringIO()
    code = cli.main(list(argv), out=out, err=err)
    return code, out.getvalue(), err.getvalue().splitlines()


def test_one_line_per_weld_with_its_schedule_weave_tracking_length_and_arc_time(welds_file):
    code, out, err = run("welds", welds_file)
    assert code == 0
    # fillet_t6 (plan table c): 265 A, 27.5 V, 265 A x 0.0254 = 6.7 m/min, 7.5 mm/s;
    # 200 mm at 7.5 mm/s = 26.67 s + 0.3 s crater fill = 27.0 s
    assert out.splitlines() == [
        "Weld: cell FilletCell, path Root, segments all; fillet_t6 265 A / 27.5 V / wire 6.7 m/min "
        "(estimated) / 7.5 mm/s; weave zigzag 4 mm 1 Hz; tracking none; 200.0 mm, arc 27.0 s",
        # segment 2 only: 100 mm at 5 mm/s = 20 s + 0.3 s; 200 A x 0.0254 = 5.08 -> 5.1 m/min
        "Second: cell FilletCell, path Root, segments 2-2; Custom 200 A / 24 V / wire 5.1 m/min "
        "(estimated) / 5 mm/s; weave triangle 4 mm 3 mm/cycle, dwell 0.1/0/0 s; tracking arc; "
        "100.0 mm, arc 20.3 s",
        "Broken: cell FilletCell, path None, segments all; cannot be read (see the warning)"]
    assert err == ["cadrobot: warning: Weld 'Broken' refers to a path 'Root' that was deleted. Link it "
                   "to a path in its Path property or delete it."]


def test_json_lists_the_same_welds_with_every_value(welds_file):
    code, out, err = run("welds", welds_file, "--json")
    assert code == 0 and len(err) == 1
    first, second, broken = json.loads(out)
    assert (first["name"], first["cell"], first["path"], first["segments"]) == ("Weld", "FilletCell", "Root",
                                                                                [None, None])
    assert first["schedule"]["name"] == "fillet_t6" and first["schedule"]["current_a"] == 265.0
    assert first["weave"] == {"pattern": "zigzag", "width_mm": 4.0, "length_mm": None, "frequency_hz": 1.0,
                              "dwell_left_s": 0.0, "dwell_center_s": 0.0, "dwell_right_s": 0.0,
                              "angle_deg": 0.0, "height_mm": None}
    assert (first["length_mm"], first["arc_time_s"]) == (200.0, pytest.approx(200 / 7.5 + 0.3, abs=1e-3))
    assert (second["segments"], second["tracking"], second["weave"]["length_mm"]) == ([2, 2], "arc", 3.0)
    assert broken["problem"].startswith("Weld 'Broken' refers to a path") and "schedule" not in broken


def test_schedules_lists_the_library_with_its_sources(welds_file):
    code, out, _ = run("welds", "--schedules")
    lines = out.splitlines()
    assert code == 0 and len(lines) == 1 + len(api.weld_schedules())
    assert lines[0].split()[:4] == ["name", "joint", "plate", "mm"]
    # plan table c: fillet t 6 mm, leg 5-6 mm: 265 A, 27.5 V, 45 cm/min = 7.5 mm/s, 265 x 0.0254 = 6.7 m/min
    assert ["fillet_t6", "fillet", "6", "5-6", "265", "27.5", "7.5", "6.7*", "Daihen"] in \
        [line.split()[:9] for line in lines]
    assert all("Daihen" in line or "Panasonic" in line for line in lines[1:])
    code, out, _ = run("welds", "--schedules", "--json")
    rows = json.loads(out)
    assert code == 0 and [row["name"] for row in rows] == list(api.weld_schedules())
    assert all(row["source"] and row["voltage_v"] for row in rows)


def test_bad_input_is_one_line_and_exit_2_and_no_welds_is_said(welds_file, seam_file, tmp_path):
    for argv, words in ((("welds",), "give a document"),
                        (("welds", str(tmp_path / "none.FCStd")), "does not exist")):
        code, out, err = run(*argv)
        assert code == 2 and out == "" and len(err) == 1 and words in err[0], err
    code, out, err = run("welds", seam_file)
    assert (code, err) == (0, []) and out == ("Document 'seam.FCStd' has no welds. Add one with "
                                              "api.make_weld or the CadRobot_Weld command.\n")


def test_the_launcher_prints_the_same_lines(welds_file):
    done = run_cadrobot("welds", welds_file)
    assert done.returncode == 0 and done.stdout == run("welds", welds_file)[1]
