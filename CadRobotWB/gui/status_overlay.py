"""The program's targets coloured by what ``api.check`` found, in the 3D view.

One dot per target (via points included) at its TCP position: green when
no finding is about it, orange when only warnings are, red when an error
is.  The dots are screen-sized markers drawn over the scene (an
``SoAnnotation``), so a target on a plate's surface is never hidden by it.
Nothing is added to the document.  :func:`show_check` keeps one overlay
per document and replaces it on the next check.
"""

import FreeCADGui
import numpy as np
from pivy import coin

from ..core.trajectory import target_in_u
from .robot_view import remove_from_scene

OK, WARNING, ERROR = "ok", "warning", "error"
#: Marker colour per status, RGB 0..1.
COLORS = {OK: (0.0, 0.8, 0.0), WARNING: (1.0, 0.55, 0.0), ERROR: (1.0, 0.0, 0.0)}

_overlays = {}


class TargetStatus:
    """One target's place and what the check said about it.

    Attributes
    ----------
    name : str
    move_index : int
        0-based index in ``program.moves()``.
    position_u : ndarray, shape (3,)
        TCP position in {U}, mm.
    status : str
        ``"ok"``, ``"warning"`` or ``"error"``.
    messages : list of str
        The findings about it, errors first.
    """

    def __init__(self, name, move_index, position_u, status, messages):
        self.name, self.move_index, self.position_u = name, move_index, position_u
        self.status, self.messages = status, messages

    def __repr__(self):
        return "<TargetStatus %s: %s>" % (self.name, self.status)


def target_statuses(result):
    """The status of every target of a checked program, in execution order.

    Parameters
    ----------
    result : api.CellCheck
        ``program`` and ``report`` are read.

    Returns
    -------
    list of TargetStatus
    """
    findings = {}
    for finding in result.report.findings:
        findings.setdefault((finding.move_index, finding.target), []).append(finding)
    out = []
    for index, move in enumerate(result.program.moves()):
        for target in (move.via, move.target):
            if target is None:
                continue
            about = sorted(findings.get((index, target.name), []), key=lambda f: f.severity != "error")
            severities = {f.severity for f in about}
            status = ERROR if "error" in severities else WARNING if severities else OK
            out.append(TargetStatus(target.name, index, target_in_u(result.program, move, target)[:3, 3],
                                    status, [f.message for f in about]))
    return out


class StatusOverlay:
    """Coloured dots at a checked program's targets in one 3D view.

    Parameters
    ----------
    view : Gui.View3DInventor
    result : api.CellCheck

    Attributes
    ----------
    targets : list of TargetStatus
        Every target, in execution order.
    root : coin.SoAnnotation
        The node added to the view's scene graph.
    """

    def __init__(self, view, result, marker=coin.SoMarkerSet.CIRCLE_FILLED_9_9):
        self.targets = target_statuses(result)
        self.scene = view.getSceneGraph()
        self.root = coin.SoAnnotation()
        self.root.setName("CadRobotStatusOverlay")
        light = coin.SoLightModel()
        light.model = coin.SoLightModel.BASE_COLOR
        self.root.addChild(light)
        for status in (OK, WARNING, ERROR):           # errors drawn last, on top
            points = [t.position_u for t in self.targets if t.status == status]
            if points:
                self.root.addChild(_markers(points, COLORS[status], marker))
        self.scene.addChild(self.root)

    @property
    def failures(self):
        """list of TargetStatus: the targets with an error, with their reasons."""
        return [t for t in self.targets if t.status == ERROR]

    def counts(self):
        """dict: number of targets per status."""
        return {s: sum(t.status == s for t in self.targets) for s in (OK, WARNING, ERROR)}

    def remove(self):
        """Take the dots out of the view (safe to call twice, or after the view closed)."""
        if self.scene is not None:
            remove_from_scene(self.scene, self.root)
        self.scene = None


def _markers(points, color, marker):
    sep = coin.SoSeparator()
    base_color = coin.SoBaseColor()
    base_color.rgb.setValue(*color)
    coords = coin.SoCoordinate3()
    points = np.asarray(points, dtype=float)
    coords.point.setValues(0, len(points), points.tolist())
    markers = coin.SoMarkerSet()
    markers.markerIndex = marker
    for node in (base_color, coords, markers):
        sep.addChild(node)
    return sep


def show_check(cell, result, view=None):
    """Show `result` (``api.check(cell)``) on `cell`'s document, replacing its previous overlay.

    Parameters
    ----------
    cell : App.DocumentObject
    result : api.CellCheck
    view : Gui.View3DInventor, optional
        Default: the active view of the cell's document.

    Returns
    -------
    StatusOverlay
    """
    name = cell.Document.Name
    remove(name)
    view = view or FreeCADGui.getDocument(name).activeView()
    _overlays[name] = StatusOverlay(view, result)
    return _overlays[name]


def current(doc_name):
    """The overlay shown on document `doc_name`, or None."""
    return _overlays.get(doc_name)


def remove(doc_name=None):
    """Remove the overlay of one document, or of every document."""
    names = list(_overlays) if doc_name is None else [doc_name]
    for name in names:
        overlay = _overlays.pop(name, None)
        if overlay is not None:
            overlay.remove()
