"""The check of a cell: reach, joint limits, singularities, speeds, collisions, cycle time.

Part of the scripting API: :mod:`CadRobotWB.api` re-exports its public names.
"""

from .. import dependencies
from ..core import frames
from ..core import progress as core_progress
from ..core.progress import report_now, stage
from ..objects import base, obstacles, reader
from ..objects.convert import matrix_from_placement
from ..robots.checks import checks, collision
from ..robots.motion import move_sampling, playback, timing
from .base_site import inside_finding
from .arguments import Arguments
from .common import obstacle_objects
from .program import solved


class CellCheck:
    """What :func:`check` found for one cell.

    Attributes
    ----------
    cell : str
        The cell's label.
    program : core Program
        As :func:`generate` returns it.
    solution : robots.motion.configuration.JointSolution
        The joints chosen at every target.
    report : robots.checks.checks.Report
        Reach, joint limits, singularities, joint speeds, configuration
        changes and collisions, per target (``report.groups()``: grouped,
        with advice on which way to move the part or the robot).
    cycle_time : dict
        ``total_s`` and per-move times (robots.motion.timing).
    base : robots.motion.playback.RobotBase, optional
        Where the robot stands relative to the part (:func:`robot_base`).
    """

    def __init__(self, cell, program, solution, report, cycle_time, base=None):
        self.cell, self.program, self.solution = cell, program, solution
        self.report, self.cycle_time = report, cycle_time
        self.base = base

    @property
    def ok(self):
        """bool: no finding is an error."""
        return self.report.ok

    @property
    def cycle_time_s(self):
        """float or None: the cycle time, s; None when the check failed (the program cannot run)."""
        return float(self.cycle_time["total_s"]) if self.ok else None

    def notes(self):
        """Lines about where the robot stands: taught frames that disagree."""
        if self.base is None or not self.base.conflicts:
            return []
        return ["NOTE: taught frame '%s' puts the robot base %.1f mm / %.2f deg from where taught "
                "frame '%s' puts it; the check and the 3D view use '%s' (the first taught frame in "
                "path order). Teach both from the same robot base, or turn UseTaught off on one."
                % (label, d, a, self.base.taught_frame, self.base.taught_frame)
                for label, d, a in self.base.conflicts]

    def headline(self):
        """The checks left out in one line, e.g. "Collisions NOT checked: python-fcl is not
        installed.", or None when every check ran."""
        return dependencies.headline(self.report.not_checked)

    def to_dict(self):
        """dict for JSON: the report's (``not_checked`` among them), ``headline``
        (:meth:`headline`), ``cell``, ``cycle_time_s`` (null when the check failed) and
        ``cycle_time``, ``robot_base_taught_frame``."""
        return dict(self.report.to_dict(), headline=self.headline(), cell=self.cell,
                    cycle_time_s=self.cycle_time_s,
                    cycle_time=self.cycle_time,
                    robot_base_taught_frame=None if self.base is None else self.base.taught_frame,
                    notes=self.notes())

    def lines(self):
        """Printable lines: the checks left out (first), the findings (grouped), the
        summary and, when the check passed, the cycle time."""
        out = self.report.lines() + self.notes()
        if self.ok:
            out.append("Cycle time: %.1f s%s." % (
                self.cycle_time["total_s"], "" if self.cycle_time["complete"] else
                " (without the first joint move: no StartJoints)"))
        return ["%s: %s" % (self.cell, line) for line in out]


def check(cell, collisions=True, progress=None):
    """Check that the robot can run `cell`'s program.

    Parameters
    ----------
    collisions : bool
        Also check the robot's links and tool against every solid of the
        document (CadRobot's own objects excluded).  Without python-fcl they
        are left out: the report's ``not_checked`` says so, and a warning
        says it once per session.  Whether the robot's base stands inside a
        solid is checked either way (the first finding, ``robot_inside``).
    progress : callable, optional
        ``progress(fraction, text)``, told often (``core.progress``); return
        False to stop: :data:`Cancelled` is raised.  The document is only
        read, so a cancelled check leaves it as it was.

    Returns
    -------
    CellCheck
    """
    args = Arguments("check")
    args.cell(cell)
    args.flag("collisions", collisions)
    args.callback("progress", progress)
    progress = core_progress.or_ambient(progress)
    program, model, solution = solved(cell, stage(progress, 0.0, 0.35))
    robot_base_ = playback.robot_base(program, matrix_from_placement(base.global_placement(cell)))
    # The moves sampled once, for the checks, collisions and the cycle time (default margins).
    sampled = move_sampling.sample_program(program, model, solution, checks.Margins(),
                                           progress=stage(progress, 0.35, 0.5))
    report = checks.check_program(program, model, solution, sampled=sampled,
                                  T_u_r=robot_base_.T_u_r, progress=stage(progress, 0.5, 0.6))
    if collisions:
        # The drawing as the robot meets it: with a taught frame the robot stands where the
        # teaching puts it relative to the part (as the player draws it), else at cell.Placement.
        T_r_u = frames.invert_transform(robot_base_.T_u_r)
        solids = obstacles.solid_meshes(cell.Document, T_r_u, obstacle_objects(cell.Document),
                                        progress=stage(progress, 0.6, 0.65))
        if solids and not collision.is_available():
            dependencies.warn_missing(collision.FCL_PACKAGE)
            report.not_checked["collisions"] = dependencies.reason(collision.FCL_PACKAGE)
        elif solids:
            checker = collision.RobotCollisionChecker(model, solids,
                                                      **collision.tool_arguments(program.tool))
            report.findings += collision.program_collision_findings(
                program, solution, checker, sampled=sampled, progress=stage(progress, 0.65, 0.95))
            report.findings.sort(key=lambda f: f.move_index)
    report.findings[:0] = _unused_frame_findings(cell)
    inside = inside_finding(cell, robot_base_.T_u_r)     # first: it explains the rest
    if inside is not None:
        report.findings.insert(0, inside)
    cycle = timing.cycle_time(program, model, solution, sampled=sampled,
                              progress=stage(progress, 0.95, 1.0))
    report_now(progress, 1.0, "done")
    return CellCheck(cell.Label, program, solution, report, cycle, robot_base_)


def _unused_frame_findings(cell):
    """A warning per calibration frame of `cell` that no path uses (a path uses its own
    CalibrationFrame, else the cell's): kind ``unused_frame``, before every target."""
    out = []
    cell_frame = getattr(cell, "CalibrationFrame", None)
    for frame in reader.unused_frames(cell):
        message = ("calibration frame %s is used by no path of cell %s (a path without its own "
                   "CalibrationFrame uses the cell's, %s): set the CalibrationFrame property of "
                   "the path on that part to %s, or delete the frame."
                   % (base.describe(frame), base.describe(cell),
                      base.describe(cell_frame) if cell_frame is not None else "none",
                      base.describe(frame)))
        out.append(checks.Finding(checks.UNUSED_FRAME, checks.WARNING, "", -1, "", message))
    return out
