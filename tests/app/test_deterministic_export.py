"""Deterministic output (issue 10, item 3): a tool marker turned 180 degrees
about an axis in the XY plane (w = ±1e-17) gives byte-identical programs
however its rotation was entered, and after the document is saved and reopened.
"""

import difflib
import math

import FreeCAD

from CadRobotWB import api, posts
from helpers import polyline, simple_cell, sketch_of

V = FreeCAD.Vector
EPOCH = "946684800"   # 2000-01-01 00:00:00 UTC
AXIS = (math.cos(math.radians(10.0)), math.sin(math.radians(10.0)), 0.0)


def half_turns():
    """The same half turn about AXIS, entered as a user or another FreeCAD could."""
    axis = V(*AXIS)
    by_axis = FreeCAD.Rotation(axis, 180.0)
    return {
        "axis +180": by_axis,
        "axis -180": FreeCAD.Rotation(axis, -180.0),
        "minus axis": FreeCAD.Rotation(-axis, 180.0),
        "matrix": FreeCAD.Placement(by_axis.toMatrix()).Rotation,
        "quaternion": FreeCAD.Rotation(*(-q for q in by_axis.Q)),
        "two quarter turns": FreeCAD.Rotation(axis, 90.0).multiply(FreeCAD.Rotation(axis, 90.0)),
    }


def build(doc, rotation):
    sketch = sketch_of(doc, polyline([(0, 0), (120, 0), (120, 80)]))
    cell, _path = simple_cell(doc, sketch)
    for point in ((60, 0, 0), (120, 40, 0)):
        api.make_tool_marker(doc, cell, FreeCAD.Placement(V(*point), rotation))
    doc.recompute()
    return cell


def exported(cell, folder, monkeypatch):
    """{post: {file name: text}} of every built-in post."""
    monkeypatch.setenv("SOURCE_DATE_EPOCH", EPOCH)
    out = {}
    for post in posts.BUILTIN:
        paths = api.export(cell, post=post, output_dir=str(folder / post), check_first=False)
        out[post] = {p.rsplit("/", 1)[-1]: open(p, newline="").read() for p in paths}
    return out


def diff(files_a, files_b):
    """The changed lines of two {file name: text}, for a failure message."""
    return "\n".join(line for name in files_a for line in difflib.unified_diff(
        files_a[name].splitlines(), files_b.get(name, "").splitlines(), name, name,
        lineterm="", n=0))


def test_half_turn_marker_exports_the_same_whatever_the_entry_and_after_reopening(
        doc, tmp_path, monkeypatch):
    expected = None
    for i, (how, rotation) in enumerate(half_turns().items()):
        document = doc if i == 0 else FreeCAD.newDocument("CadRobotHalfTurn%d" % i)
        try:
            cell = build(document, rotation)
            cell_name = cell.Name
            # One file name for all (program headers name the document).
            folder = tmp_path / str(i)
            folder.mkdir()
            file_name = str(folder / "half_turn.FCStd")
            document.saveAs(file_name)
            before = exported(cell, folder / "before", monkeypatch)
            FreeCAD.closeDocument(document.Name)
            document = FreeCAD.openDocument(file_name)
            after = exported(document.getObject(cell_name), folder / "after", monkeypatch)
        finally:
            if document.Name in FreeCAD.listDocuments():
                FreeCAD.closeDocument(document.Name)
        for post in before:
            assert after[post] == before[post], "%s, %s, after reopening:\n%s" % (
                how, post, diff(before[post], after[post]))
        if expected is None:
            expected = before
            assert "[0.000000,0.984808,0.173648,0.000000]" in "".join(before["abb_rapid"].values())
        for post in expected:
            assert before[post] == expected[post], "%s, %s:\n%s" % (
                how, post, diff(expected[post], before[post]))
