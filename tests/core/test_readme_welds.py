"""The README's Welds tables are the code's: the schedule library (core.schedule_library
.schedule_table) and the defaults and ranges of core.welding's field tables."""

import re
from pathlib import Path

from CadRobotWB.core import schedule_library
from CadRobotWB.core.welding import SCHEDULE_FIELDS, WEAVE_FIELDS

README = (Path(__file__).resolve().parents[2] / "README.md").read_text(encoding="utf-8")


def _welds_section():
    return README.split("\n## Welds\n", 1)[1].split("\n## ", 1)[0]


def _table_rows(text, first_cell):
    """The cells of each markdown table row whose first cell matches `first_cell`."""
    rows = []
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.startswith("|") and re.fullmatch(first_cell, cells[0]):
            rows.append(cells)
    return rows


def test_the_library_table_is_schedule_table():
    rows = _table_rows(_welds_section(), r"(fillet|butt)_t[\d.]+")
    assert [tuple(r) for r in rows] == schedule_library.schedule_table(schedule_library.load())


def _expected(table):
    out = []
    for key, (default, low, high, unit, what) in table.items():
        out.append(["`%s`" % key, "\u2014" if default is None else "%g" % default,
                    "%g\u2013%g" % (low, high), unit, what])
    return out


def test_the_defaults_tables_are_the_field_tables():
    section = _welds_section()
    rows = _table_rows(section, r"`\w+`")
    assert rows == _expected(SCHEDULE_FIELDS) + _expected(WEAVE_FIELDS)
