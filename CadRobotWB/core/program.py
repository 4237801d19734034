"""The program IR: what every post-processor is fed from.

A :class:`Program` is robot-language neutral. Poses are 4x4 homogeneous
transforms in millimetres; the frame each pose is expressed in is named in the
type (``T_b_t`` = TCP {T} in work-object frame {B}, see DESIGN.md).

Posts read a Program and never anything else (no document, no FreeCAD).
"""

from dataclasses import dataclass, field
from typing import Dict, List, Optional

import numpy as np

from . import rotations
from .mechanisms import ExternalAxes
from .welding import Tracking, Weave, WeldSchedule

JOINT = "joint"
LINEAR = "linear"
CIRCULAR = "circular"
MOVE_KINDS = (JOINT, LINEAR, CIRCULAR)

# What a move does in the path, for comments and for posts that treat them apart.
ROLE_APPROACH = "approach"   # joint move to the point above the first target
ROLE_ENTRY = "entry"         # linear move down the tool axis to the first target
ROLE_PATH = "path"           # a move along a path segment
ROLE_REORIENT = "reorient"   # turn the tool in place at a segment junction
ROLE_RISK = "risk"           # interpolated move inside a risk area (eqs 8-15)
ROLE_RETRACT = "retract"     # linear move up the tool axis after the last target


@dataclass
class Target:
    """One robot target (eq 16): TCP position and orientation in a work frame.

    Attributes
    ----------
    name : str
        Identifier unique within the program, made of ``[A-Za-z0-9_]``.
    T_b_t : ndarray, shape (4, 4)
        Pose of the TCP frame {T} in the work-object frame {B}; millimetres.
    joints_deg : ndarray, shape (6,), or None
        The robot's joint values at this target, degrees, controller
        convention, as chosen by ``robots.motion.configuration.solve_program`` (one
        configuration per path, J4/J6 unwrapped to follow the previous
        target). None until a robot model has solved the program, or when
        no joint solution within the limits exists. Posts use it for the
        configuration data of their language (ABB confdata, KUKA S/T,
        Fanuc CONFIG, Motoman RCONF); it never changes the pose.
    external : ndarray, shape (K,), or None
        The external axes at this target (:class:`.mechanisms.ExternalAxes`
        order: track mm, then positioner deg), as chosen by
        ``robots.mechanisms.choose``; None in a program without external
        axes, or before they are chosen (the mechanisms stay as drawn).
    """

    name: str
    T_b_t: np.ndarray
    joints_deg: Optional[np.ndarray] = None
    external: Optional[np.ndarray] = None

    @property
    def position_mm(self):
        """ndarray, shape (3,): TCP position in {B}, mm."""
        return np.asarray(self.T_b_t[:3, 3], dtype=float)

    @property
    def quaternion(self):
        """ndarray, shape (4,): TCP orientation in {B} as a unit quaternion
        (w, x, y, z), sign canonical (:func:`.rotations.choose_quaternion_sign`)."""
        return rotations.quaternion_from_matrix(self.T_b_t[:3, :3])


@dataclass
class Move:
    """One motion instruction.

    Attributes
    ----------
    kind : str
        ``"joint"``, ``"linear"`` or ``"circular"``.
    target : Target
        Where the move ends.
    speed_mm_s : float
        Programmed TCP speed, mm/s.
    zone_mm : float
        Blending radius, mm; 0 means stop exactly at the target ("fine").
    frame : str
        Name of the work frame (key of :attr:`Program.frames`) the target is
        expressed in.
    via : Target or None
        The intermediate (circle) point of a circular move; None otherwise.
    role : str
        One of the ``ROLE_*`` constants.
    segment : int or None
        1-based number of the path segment this move belongs to, None for
        approach, entry and retract moves.
    comment : str
        Human-readable origin, e.g. ``"segment 2: arc Sketch.Edge3"``.
    weld : str or None
        Name of the :class:`WeldRun` this move welds in (the arc burns along
        it), None for moves without arc -- the run's start move included.
    """

    kind: str
    target: Target
    speed_mm_s: float
    zone_mm: float
    frame: str
    via: Optional[Target] = None
    role: str = ROLE_PATH
    segment: Optional[int] = None
    comment: str = ""
    weld: Optional[str] = None


@dataclass
class ToolData:
    """The tool mounted on the flange.

    Attributes
    ----------
    name : str
        Identifier, ``[A-Za-z0-9_]``.
    T_f_t : ndarray, shape (4, 4)
        TCP frame {T} in the flange frame {F}, mm.
    mass_kg : float
        Tool mass, kg (> 0: controllers reject a weightless tool).
    cog_mm : ndarray, shape (3,)
        Centre of gravity in {F}, mm.
    label : str
        What the user calls the tool (e.g. "Straight torch"); "" if unnamed.
    body_vertices_mm, body_faces : ndarray, shapes (N, 3) and (M, 3), or None
        The tool body as a triangle mesh in {F} (mm; faces index the
        vertices), for collision checks; None: no body (a plain TCP).
    """

    name: str
    T_f_t: np.ndarray
    mass_kg: float = 1.0
    cog_mm: np.ndarray = field(default_factory=lambda: np.zeros(3))
    label: str = ""
    body_vertices_mm: np.ndarray = None
    body_faces: np.ndarray = None


@dataclass
class WorkFrame:
    """A calibration (work-object) frame {B}.

    Attributes
    ----------
    name : str
        Identifier, ``[A-Za-z0-9_]``.
    T_r_b : ndarray, shape (4, 4)
        {B} expressed in the robot base frame {R}, mm. This is what the
        controller's user frame / work object holds.
    T_u_b : ndarray, shape (4, 4)
        {B} expressed in the CAD assembly frame {U}, mm (for reference).
    source : str
        Label of the document object the frame comes from.
    """

    name: str
    T_r_b: np.ndarray
    T_u_b: np.ndarray
    source: str = ""


@dataclass
class WeldRun:
    """One arc-on stretch of a path: a Weld object, or the part of it between
    two corner stops (turns in place).

    The arc ignites at the target of ``moves[start]`` (the entry move, the
    reorientation at a corner stop, or the path's last move before the weld's
    first segment: the approach ends at the seam start) and
    goes out at the target of ``moves[end]``; the moves ``start + 1 .. end``
    weld, at the schedule's travel speed, each with ``Move.weld == name``.
    ``moves[start]`` and ``moves[end]`` stop exactly (zone 0); the moves in
    between blend.

    Attributes
    ----------
    name : str
        Identifier ``[A-Za-z0-9_]``, unique in the program; posts derive their
        data names from it.
    label : str
        The Weld object's label, for comments and findings.
    schedule : welding.WeldSchedule
    weave : welding.Weave or None
    tracking : welding.Tracking
    start, end : int
        Indices in :attr:`ProgramPath.moves`, ``start < end``.
    first_segment, last_segment : int
        1-based path segments the run covers, for messages.
    part : int
        1, 2, ... when corner stops split the Weld object into runs.
    position : str
        The welding position a positioner keeps the seam in: ``"PA"`` (flat,
        the default) or ``"PB"`` (horizontal-vertical fillet), ISO 6947.
    """

    name: str
    label: str
    schedule: WeldSchedule
    weave: Optional[Weave] = None
    tracking: Tracking = field(default_factory=Tracking)
    start: int = 0
    end: int = 0
    first_segment: int = 1
    last_segment: int = 1
    part: int = 1
    position: str = "PA"


@dataclass
class ProgramPath:
    """The moves generated from one CAD path, in execution order, and the
    welds along them (:class:`WeldRun`, in execution order, not overlapping)."""

    name: str
    label: str
    moves: List[Move] = field(default_factory=list)
    welds: List[WeldRun] = field(default_factory=list)


@dataclass
class Program:
    """A complete robot program, language neutral.

    Attributes
    ----------
    name : str
        Program / module name, ``[A-Za-z0-9_]``.
    robot : str
        Catalog name of the robot, e.g. ``"ABB_IRB2400"``.
    tool : ToolData
    frames : dict of str to WorkFrame
        Every work frame a move refers to, by name.
    paths : list of ProgramPath
        In execution order.
    source : str
        Where the program came from (document and cell label), for headers.
    external : mechanisms.ExternalAxes or None
        The track and positioner of the cell; None without external axes.
    """

    name: str
    robot: str
    tool: ToolData
    frames: Dict[str, WorkFrame]
    paths: List[ProgramPath]
    source: str = ""
    external: Optional[ExternalAxes] = None

    def moves(self):
        """All moves of all paths, in execution order (a flat list)."""
        return [m for p in self.paths for m in p.moves]

    def weld_runs(self):
        """Every (ProgramPath, WeldRun) pair, in execution order."""
        return [(p, run) for p in self.paths for run in p.welds]

    def targets(self):
        """Every target (via points included) in execution order."""
        out = []
        for m in self.moves():
            if m.via is not None:
                out.append(m.via)
            out.append(m.target)
        return out
