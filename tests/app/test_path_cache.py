"""A path is read once per change (objects/path_cache.py): the kept reading is used
while nothing it was read from changed, and read again after any change."""

import FreeCAD
import Part

from CadRobotWB import api
from CadRobotWB.objects import path_cache, reader
from helpers import V, polyline, sketch_of


def ends(path):
    """[(start, end)] of each segment, rounded to 1e-9 mm."""
    return [(tuple(round(c, 9) for c in s.start), tuple(round(c, 9) for c in s.end))
            for s in reader.path_geometry(path)[0]]


def test_an_unchanged_path_is_not_read_again(doc, monkeypatch):
    sketch = sketch_of(doc, polyline([(0, 0), (50, 0), (50, 50)]))
    path = api.make_path(doc, api.make_cell(doc), sketch)
    first = reader.path_geometry(path)
    reads = []
    real = reader._read_path_geometry
    monkeypatch.setattr(reader, "_read_path_geometry", lambda p: reads.append(p.Name) or real(p))
    again = reader.path_geometry(path)
    assert reads == [] and all(a is b for a, b in zip(first[0], again[0]))
    assert again[0] is not first[0] and again[2] is not first[2]     # the caller's own list and dict
    path_cache.forget()
    reader.path_geometry(path)
    assert reads == [path.Name]


def test_every_input_of_the_reading_is_noticed(doc):
    part = doc.addObject("App::Part", "Fixture")
    sketch = sketch_of(doc, polyline([(0, 0), (50, 0), (50, 50)]), container=part)
    path = api.make_path(doc, api.make_cell(doc), sketch)
    assert ends(path) == [((0, 0, 0), (50, 0, 0)), ((50, 0, 0), (50, 50, 0))]

    sketch.delGeometry(1)                          # the sketch is edited
    sketch.addGeometry(Part.LineSegment(V(50, 0, 0), V(60, 50, 0)), False)
    doc.recompute()
    assert ends(path)[1] == ((50, 0, 0), (60, 50, 0))

    part.Placement = FreeCAD.Placement(V(0, 0, 10), FreeCAD.Rotation())   # its container moves
    doc.recompute()
    assert ends(path)[0] == ((0, 0, 10), (50, 0, 10))

    path.Reversed = True
    assert ends(path)[0] == ((60, 50, 10), (50, 0, 10))

    sketch.Label = "Seam"
    assert [s.source for s in reader.path_geometry(path)[0]] == ["Seam.Edge2", "Seam.Edge1"]

    wire = doc.addObject("Part::Feature", "Wire")
    wire.Shape = Part.makePolygon([V(0, 0, 0), V(10, 0, 0)])
    path.Source = [(wire, [""])]                   # another source
    assert ends(path) == [((10, 0, 0), (0, 0, 0))]
    wire.Shape = Part.makePolygon([V(0, 0, 0), V(20, 0, 0)])    # a new shape, same object
    assert ends(path) == [((20, 0, 0), (0, 0, 0))]
