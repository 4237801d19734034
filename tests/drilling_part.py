"""FreeCAD's own Drilling_1.FCStd for the tests: a part nobody here drew (issue 14)."""

import os

import pytest

import FreeCAD


def drilling_file():
    """FreeCAD's shipped Drilling_1.FCStd (Path workbench on 0.20, CAM on 1.x), or skip."""
    root = FreeCAD.getResourceDir()
    for sub in (("Mod", "Path", "PathTests"), ("Mod", "CAM", "CAMTests")):
        path = os.path.join(root, *sub, "Drilling_1.FCStd")
        if os.path.exists(path):
            return path
    pytest.skip("FreeCAD's Drilling_1.FCStd is not installed under %s (Mod/Path/PathTests or "
                "Mod/CAM/CAMTests)" % root)


def drilling_block():
    """(document, solid): a new document holding Drilling_1's Pocket011 as a plain shape.

    FreeCAD 1.x recomputes this old file's Body on every recompute (a sketch of it
    fails to solve there) and may then rename the edges our paths link; the shape is
    the same.
    """
    source = FreeCAD.openDocument(drilling_file())
    shape = source.getObject("Pocket011").Shape.copy()
    FreeCAD.closeDocument(source.Name)
    doc = FreeCAD.newDocument("Drilling")
    pocket = doc.addObject("Part::Feature", "Pocket011")
    pocket.Shape = shape
    doc.recompute()
    return doc, pocket


def top_outer_loop(pocket):
    """Edge names of the outer loop of the block's top face (z = 30): the convex edge all round."""
    from CadRobotWB.objects.picking import outer_edge_names
    faces = pocket.Shape.Faces
    top = max((k for k, f in enumerate(faces, 1) if f.Surface.__class__.__name__ == "Plane"
               and abs(f.BoundBox.ZMin - 30) < 1e-6 and abs(f.BoundBox.ZMax - 30) < 1e-6),
              key=lambda k: faces[k - 1].Area)
    return outer_edge_names(pocket, "Face%d" % top)      # in the order they join
