"""Defective documents, made with the API, for the CLI's bad-input tests.

Each entry of :data:`DEFECTS` is ``name -> (build, words)``: ``build(doc)``
fills a new document with one defect, and every word must appear in the
CLI's one error line (the object at fault and what is wrong).  Every one of
them must end ``cadrobot export`` and ``cadrobot check`` with exit 2, one
line on stderr and nothing written.  :data:`DAMAGED_FILES` are files that are
no FreeCAD document at all.
"""

import zipfile

import FreeCAD

from CadRobotWB import api
from helpers import V, polyline, simple_cell, sketch_of

NAN = float("nan")


def good_cell(doc, name="Good", y=0.0):
    """A cell that exports: one path, one marker, its robot in reach."""
    sketch = sketch_of(doc, polyline([(0, y), (50, y), (50, y + 40)]), name=name + "Seam")
    cell, path = simple_cell(doc, sketch, markers=[(25, y, 0)])
    cell.Label = name
    return cell, path


def _marker(doc):
    return good_cell(doc)[0].Group[-1]


def marker_nan(doc):
    marker = _marker(doc)
    marker.Label = "NanMarker"
    marker.Placement = FreeCAD.Placement(V(NAN, 0, 0), marker.Placement.Rotation)


def frame_inf(doc):
    cell, _ = good_cell(doc)
    cell.CalibrationFrame.Label = "InfFrame"
    cell.CalibrationFrame.Placement = FreeCAD.Placement(V(0, float("inf"), 0), FreeCAD.Rotation())


def cell_nan(doc):
    cell, _ = good_cell(doc, name="NanCell")
    cell.Placement = FreeCAD.Placement(V(-900, NAN, -600), FreeCAD.Rotation())


def second_cell_bad(doc):
    good_cell(doc, name="First")
    sketch = sketch_of(doc, polyline([(0, 100), (50, 100)]), name="Bare")
    cell, _ = simple_cell(doc, sketch, markers=[])        # no tool marker
    cell.Label = "Second"


def same_program_name(doc):
    for name, y in (("Left", 0.0), ("Right", 60.0)):
        good_cell(doc, name=name, y=y)[0].ProgramName = "Weld"


def no_cell(doc):
    sketch_of(doc, polyline([(0, 0), (50, 0)]), name="Lonely")


def no_marker(doc):
    sketch = sketch_of(doc, polyline([(0, 0), (50, 0)]), name="Unmarked")
    simple_cell(doc, sketch, markers=[])


def speed_nan(doc):
    good_cell(doc)[1].Speed = NAN


def speed_zero(doc):
    good_cell(doc)[1].Speed = 0.0


def start_joints_nan(doc):
    good_cell(doc)[0].StartJoints = [0.0, NAN, 0.0, 0.0, 0.0, 0.0]


def start_joints_five(doc):
    good_cell(doc)[0].StartJoints = [0.0] * 5


def _set_anyway(obj, prop, value):
    """Set `value`, adding it to the choices of an enumeration property first
    (as a document saved where another robot or post existed holds it)."""
    try:
        setattr(obj, prop, value)
    except ValueError:
        setattr(obj, prop, [value] + list(obj.getEnumerationsOfProperty(prop)))
        setattr(obj, prop, value)


def unknown_robot(doc):
    _set_anyway(good_cell(doc)[0], "Robot", "IRB9999")


def unknown_post(doc):
    _set_anyway(good_cell(doc)[0], "PostProcessor", "brand_x")


def tool_mass_nan(doc):
    good_cell(doc)[0].ToolMass = NAN


def tool_tcp_nan(doc):
    good_cell(doc)[0].ToolTCP = FreeCAD.Placement(V(0, 0, NAN), FreeCAD.Rotation())


def risk_area_outside(doc):
    cell, path = good_cell(doc)
    api.make_risk_area(doc, cell, path, 2, 5, name="Beyond")


def deleted_frame(doc):
    cell, _ = good_cell(doc)
    doc.removeObject(cell.CalibrationFrame.Name)


def link_cycle(doc):
    """Two App::Links linking each other beside a good cell: reading their shapes (the
    check's obstacles) made FreeCAD follow them until it crashed, exit -11.  (Made a
    path's source, FreeCAD crashes already in the recompute that builds the document.)"""
    good_cell(doc)
    first, second = doc.addObject("App::Link", "LinkA"), doc.addObject("App::Link", "LinkB")
    first.Label, second.Label = "SeamLink", "BackLink"
    first.LinkedObject = second
    second.LinkedObject = first


DEFECTS = {
    "marker_nan": (marker_nan, ["'NanMarker'", "NaN or infinite"]),
    "frame_inf": (frame_inf, ["'InfFrame'", "NaN or infinite"]),
    "cell_nan": (cell_nan, ["'NanCell'", "NaN or infinite"]),
    "second_cell_bad": (second_cell_bad, ["Path", "no tool marker"]),
    "same_program_name": (same_program_name, ["'Left'", "'Right'", "Weld", "ProgramName"]),
    "no_cell": (no_cell, ["no robot cell"]),
    "no_marker": (no_marker, ["no tool marker"]),
    "speed_nan": (speed_nan, ["Speed", "not finite"]),
    "speed_zero": (speed_zero, ["Speed", "> 0"]),
    "start_joints_nan": (start_joints_nan, ["StartJoints", "not finite"]),
    "start_joints_five": (start_joints_five, ["StartJoints", "6 joint values"]),
    "unknown_robot": (unknown_robot, ["IRB9999"]),
    "unknown_post": (unknown_post, ["'brand_x'"]),
    "tool_mass_nan": (tool_mass_nan, ["ToolMass", "not finite"]),
    "tool_tcp_nan": (tool_tcp_nan, ["ToolTCP", "NaN or infinite"]),
    "risk_area_outside": (risk_area_outside, ["'Beyond'", "segments 2-5"]),
    "deleted_frame": (deleted_frame, ["CalibrationFrame", "deleted"]),
    "link_cycle": (link_cycle, ["'SeamLink' (LinkA) -> 'BackLink' (LinkB) -> 'SeamLink' (LinkA)",
                                "form a cycle"]),
}

#: Defects only `export` refuses: `check` reads no post and writes nothing.
EXPORT_ONLY = {"unknown_post", "same_program_name"}


def save_defect(name, folder):
    """Build defect `name` in a new document, save it in `folder`; return the path."""
    build = DEFECTS[name][0]
    doc = FreeCAD.newDocument("Defect")
    try:
        build(doc)
        doc.recompute()
        path = str(folder / ("%s.FCStd" % name))
        doc.saveAs(path)
    finally:
        FreeCAD.closeDocument(doc.Name)
    return path


def _zip(path, members):
    with zipfile.ZipFile(path, "w") as archive:
        for member, data in members.items():
            archive.writestr(member, data)


def _truncated_xml(good):
    with zipfile.ZipFile(good) as archive:
        members = {n: archive.read(n) for n in archive.namelist()}
    xml = members["Document.xml"]
    # Cut inside a tag, so the reader always says "unclosed token": a cut between two tags
    # (where half the length lands depends on the document's size) reads "no element found".
    members["Document.xml"] = xml[: xml.index(b"<", len(xml) // 2) + 4]
    return members


def write_damaged_file(kind, folder, good):
    """A file `kind` of :data:`DAMAGED_FILES` in `folder` (`good`: a valid .FCStd); its path."""
    path = folder / ("%s.FCStd" % kind)
    if kind == "truncated_xml":
        _zip(path, _truncated_xml(good))
    elif kind == "garbage_xml":
        _zip(path, {"Document.xml": "<<<not xml"})
    elif kind == "no_document_xml":
        _zip(path, {"readme.txt": "hello"})
    elif kind == "text":
        path.write_text("not a zip file")
    elif kind == "empty":
        path.write_bytes(b"")
    elif kind == "cut_zip":
        path.write_bytes(open(good, "rb").read()[:1000])
    elif kind == "folder":
        path.mkdir()
    return str(path)


#: kind -> a word of the error line.
DAMAGED_FILES = {"truncated_xml": "is damaged", "garbage_xml": "is damaged",
                 "no_document_xml": "not a FreeCAD document", "text": "not a FreeCAD document",
                 "empty": "not a FreeCAD document", "cut_zip": "not a FreeCAD document",
                 "folder": "is a folder"}
