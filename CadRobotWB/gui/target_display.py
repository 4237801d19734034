"""The generated targets, drawn as small RGB triads along each path.

After a document recomputes, every cell whose view property ``ShowTargets``
is on is generated (the poses of ``api.generate``, without solving the joints) and each path's view provider draws a
triad at each of its targets (approach, via and retract points included),
``T_u_t = program.frames[move.frame].T_u_b @ target.T_b_t``.  A cell that
does not generate (a path without a tool marker, no calibration frame, ...)
shows no targets; the error is for Generate to report.

The document is only read.  A document observer notes which documents
changed since their last drawing, so a recompute after which nothing
changed costs nothing, and a path whose targets did not move is not redrawn.
"""

import FreeCAD
import numpy as np

from ..core.trajectory import target_in_u
from ..errors import CadRobotError
from ..objects.base import objects_of_type
from ..core import generate as core_generate
from ..objects import reader
from ..objects.reader import cell_paths
from .soon import call_soon

_observer = None


def path_targets(program):
    """Every target of `program` in {U}, per program path.

    Parameters
    ----------
    program : core Program

    Returns
    -------
    list of ndarray, shape (N, 4, 4)
        One per ``program.paths`` entry (the cell's paths in tree order);
        targets in execution order, a circular move's via before its end.
    """
    out = []
    for program_path in program.paths:
        poses = [target_in_u(program, move, target)
                 for move in program_path.moves for target in (move.via, move.target)
                 if target is not None]
        out.append(np.array(poses, dtype=float).reshape(-1, 4, 4))
    return out


def cell_targets(cell):
    """The targets of `cell` per path object name ({} when the cell does not generate)."""
    try:   # poses only: the joint solution api.generate adds is not needed to draw them
        program = core_generate.generate(reader.read_cell(cell))
    except CadRobotError:
        return {}
    except Exception as err:        # never a traceback from an observer
        FreeCAD.Console.PrintWarning("CadRobot: targets of %s not drawn: %s\n" % (cell.Label, err))
        return {}
    # Program paths keep the order of the cell's paths; their names are sanitised labels.
    return {path.Name: poses for path, poses in zip(cell_paths(cell), path_targets(program))}


def shows_targets(cell):
    """bool: the cell's view property ShowTargets (on when the cell has no view)."""
    vobj = getattr(cell, "ViewObject", None)
    return bool(getattr(vobj, "ShowTargets", True)) if vobj is not None else False


def refresh_cell(cell):
    """Generate `cell` (when it shows targets) and hand each path its targets."""
    poses = cell_targets(cell) if shows_targets(cell) else {}
    for path in cell_paths(cell):
        display = getattr(getattr(path.ViewObject, "Proxy", None), "path_display", None)
        if display is not None:
            display.set_targets(poses.get(path.Name, np.zeros((0, 4, 4))))


def refresh_soon(cell):
    """:func:`refresh_cell` once the event loop runs again (after a document is opened)."""
    call_soon(cell, refresh_cell)


def refresh(doc):
    """Redraw the targets of every cell of `doc`."""
    for cell in objects_of_type(doc, "Cell"):
        refresh_cell(cell)


class TargetObserver:
    """Redraws a document's targets after a recompute that followed a change.

    Attributes
    ----------
    changed : set of str
        Names of the documents changed since their targets were last drawn.
    """

    def __init__(self):
        self.changed = set()

    def slotChangedObject(self, obj, prop):
        doc = getattr(obj, "Document", None)
        if doc is not None:
            self.changed.add(doc.Name)

    def slotDeletedObject(self, obj):
        self.slotChangedObject(obj, "")

    def slotRecomputedDocument(self, doc):
        if doc.Name not in self.changed:
            return
        self.changed.discard(doc.Name)
        if FreeCAD.GuiUp:
            refresh(doc)

    def slotDeletedDocument(self, doc):
        self.changed.discard(doc.Name)


def install():
    """Start watching documents (once per session); returns the observer."""
    global _observer
    if _observer is None:
        _observer = TargetObserver()
        FreeCAD.addDocumentObserver(_observer)
    return _observer
