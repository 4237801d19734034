"""The headless batch CLI, ``cadrobot`` (runs inside FreeCADCmd).

Exit codes: 0 success, 1 a finding the user must fix, 2 bad input, 3 a bug
of ours. Errors are
one line on stderr naming the object at fault; with ``--json`` the result (or
the error) is also printed as JSON on stdout. The input document is opened
read-only in effect: it is never recomputed or saved.

Two ways in: the ``cadrobot`` launcher of a checkout (:func:`main`, through
``tools/freecad_run.py``), and, where the workbench came from the Addon
Manager, one FreeCADCmd line on any OS and FreeCAD version (:func:`run`)::

    FreeCADCmd -c "from CadRobotWB import cli; cli.run('export part.FCStd -o out')"
"""

import argparse
import json
import math
import os
import shlex
import sys
import time
import zipfile

from . import __version__, command_line, limits
from .core.progress import report_now, stage
from .errors import CadRobotError, DocumentError, InputError, MissingPackageError

EXIT_OK, EXIT_FINDING, EXIT_INPUT, EXIT_BUG = 0, 1, 2, 3
#: Exit code after Ctrl-C or a cancelled run (128 + SIGINT, as a shell).
EXIT_INTERRUPTED = 130


class _Parser(argparse.ArgumentParser):
    """argparse that raises instead of exiting, so usage errors exit 2 cleanly."""

    def error(self, message):
        raise InputError("%s (see `%s`)" % (message, command_line.as_typed(*self._sub_words(),
                                                                            "--help")))

    def _sub_words(self):
        return [] if self.prog == "cadrobot" else self.prog.split(" ", 1)[-1:]


#: Help of every subcommand's ``--quiet``.
QUIET_HELP = "no progress lines on stderr (they appear for work longer than about 2 s)"

#: Environment variables: seconds of work before the first progress line
#: (default 2), and least seconds between two lines (default 1).
PROGRESS_DELAY_ENV, PROGRESS_INTERVAL_ENV = "CADROBOT_PROGRESS_DELAY_S", "CADROBOT_PROGRESS_INTERVAL_S"


class ProgressLines:
    """The ``progress`` callback of a CLI command: lines on stderr.

    Nothing for the first `delay_s` seconds (a short command prints nothing
    but its result), then at most one line every `interval_s` seconds, e.g.
    ``cadrobot: check: sampling moves 40%``; on a terminal one line rewritten
    with a carriage return.  Never asks to stop (Ctrl-C does that).

    Parameters
    ----------
    command : str
        The subcommand, first word of each line.
    err : file
        Where the lines go.
    quiet : bool
        Print nothing at all (``--quiet``).
    delay_s, interval_s : float, optional
        Defaults from the environment variables :data:`PROGRESS_DELAY_ENV`
        and :data:`PROGRESS_INTERVAL_ENV`, else 2 and 1 seconds.
    clock : callable
        Seconds, monotonic.
    """

    def __init__(self, command, err, quiet=False, delay_s=None, interval_s=None,
                 clock=time.monotonic):
        self.command, self.err, self.quiet, self.clock = command, err, quiet, clock
        self.delay_s = _seconds(PROGRESS_DELAY_ENV, 2.0) if delay_s is None else float(delay_s)
        self.interval_s = _seconds(PROGRESS_INTERVAL_ENV, 1.0) if interval_s is None else float(interval_s)
        self.started = clock()
        self.last = None                 # when the last line was written
        self.prefix = ""
        self.pending = False             # a terminal line waits for its end of line
        try:
            self.terminal = bool(err.isatty())
        except (AttributeError, ValueError):
            self.terminal = False

    def __call__(self, fraction, text=""):
        if self.quiet:
            return None
        now = self.clock()
        if now - self.started < self.delay_s or (
                self.last is not None and now - self.last < self.interval_s):
            return None
        self.last = now
        line = "cadrobot: %s: %s%s %d%%" % (self.command, self.prefix, text or "working",
                                           int(100 * fraction))
        if self.terminal:
            self.err.write("\r\x1b[K" + line)
            self.pending = True
        else:
            self.err.write(line + "\n")
        self.err.flush()
        return None

    def part(self, k, count, label=None):
        """The callback for part `k` of `count` (one cell of several), lines naming `label`."""
        from .core.progress import stage
        self.prefix = "%s: " % label if label and count > 1 else ""
        return stage(self, k / count, (k + 1) / count)

    def done(self):
        """End a terminal's rewritten line before anything else is printed."""
        if self.pending:
            self.err.write("\n")
            self.err.flush()
            self.pending = False


def _seconds(name, default):
    try:
        value = float(os.environ.get(name, default))
    except ValueError:
        return default
    return value if math.isfinite(value) and value >= 0 else default


def build_parser():
    parser = _Parser(prog="cadrobot", description=(
        "CadRobot batch tool: robot programs from FreeCAD documents, without the GUI."))
    parser.add_argument("--version", action="version", version="cadrobot " + __version__)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)

    export = sub.add_parser("export", help="generate and write the robot program of a document's cells")
    export.add_argument("document", metavar="DOC.FCStd")
    export.add_argument("--post", help="post-processor (default: each cell's robot maker's own, "
                        "or the cell's PostProcessor property when it fits the robot); another "
                        "maker's post is written with a note in the program's header")
    export.add_argument("-o", "--output", default=".", metavar="DIR", help="output folder (default: .)")
    export.add_argument("--cell", action="append", metavar="NAME",
                        help="only this cell (name or label); repeatable. Default: every cell")
    export.add_argument("--option", action="append", type=parse_post_option, metavar="KEY=VALUE",
                        help="post-processor option, repeatable (e.g. path_correction=true for RAPID "
                             "with live seam-tracking correction)")
    export.add_argument("--no-check", action="store_true",
                        help="write the program even if the robot cannot run it (skip 'check')")
    export.add_argument("--quiet", action="store_true", help=QUIET_HELP)
    export.add_argument("--json", action="store_true", help="machine-readable result on stdout")

    check = sub.add_parser("check", help="can the robot run each cell's program? (exit 1 if not)")
    check.add_argument("document", metavar="DOC.FCStd")
    check.add_argument("--cell", action="append", metavar="NAME",
                       help="only this cell (name or label); repeatable. Default: every cell")
    check.add_argument("--no-collisions", action="store_true",
                       help="skip the collision check against the document's solids")
    check.add_argument("--quiet", action="store_true", help=QUIET_HELP)
    check.add_argument("--json", action="store_true", help="machine-readable report on stdout")

    sim = sub.add_parser("simulate", help="run a path with a seam-tracking laser or a force sensor "
                                          "in a real cell that differs from the drawing")
    sim.add_argument("document", metavar="DOC.FCStd")
    sim.add_argument("--sensor", choices=("laser", "force", "arc"),
                     help="the sensor; default the one the faces along the path call for (a joint: "
                          "laser, a surface or an outside edge: force); arc: through-arc tracking "
                          "of the path's weld (it must weave)")
    sim.add_argument("--cell", metavar="NAME", help="the cell (name or label); default the first")
    sim.add_argument("--path", metavar="LABEL", help="the path; default the cell's first")
    sim.add_argument("--deviation", type=_six_numbers, metavar="x,y,z,rx,ry,rz",
                     help="rigid displacement of the real workpiece in {U}: mm, then degrees "
                          "about X, Y, Z turning the part about the path's start")
    sim.add_argument("--rate", type=_rate, metavar="HZ",
                     help="correction rate, at least %g, at most 100 laser, 200 force (default 5 "
                          "laser, 20 force; the arc corrects once per weave cycle and takes none)"
                          % limits.MIN_RATE_HZ)
    sim.add_argument("--controller", choices=("pi", "fuzzy_pi", "none"),
                     help="controller (default: pi; the force sensor compares pi and fuzzy_pi)")
    sim.add_argument("--foreign", action="append", metavar="LABEL",
                     help="a solid of the document that is in the real cell but not in the drawing")
    sim.add_argument("--seed", type=_whole(0, limits.MAX_SEED), default=0,
                     help="seed of the noise and roughness, 0 to %d (default 0)" % limits.MAX_SEED)
    sim.add_argument("-o", "--output", default=".", metavar="DIR", help="output folder (default: .)")
    sim.add_argument("--quiet", action="store_true", help=QUIET_HELP)
    sim.add_argument("--json", action="store_true", help="machine-readable summary on stdout")

    sweep = sub.add_parser("sweep", help="many simulations over random deviations: how large an "
                                         "error can the sensor absorb?")
    sweep.add_argument("document", metavar="DOC.FCStd")
    sweep.add_argument("--sensor", required=True, choices=("laser", "force"))
    sweep.add_argument("--ranges", required=True, metavar="x=-5:5,...",
                       help="deviation ranges: axes x,y,z (mm), rx,ry,rz (degrees), low:high")
    sweep.add_argument("--runs", type=_whole(1, limits.MAX_SWEEP_RUNS), default=50,
                       help="number of runs, 1 to %d (default 50)" % limits.MAX_SWEEP_RUNS)
    sweep.add_argument("--cell", metavar="NAME", help="the cell (name or label); default the first")
    sweep.add_argument("--path", metavar="LABEL", help="the path; default the cell's first")
    sweep.add_argument("--controller", choices=("pi", "fuzzy_pi", "none"), default="pi")
    sweep.add_argument("--rate", type=_rate, metavar="HZ",
                       help="correction rate, at least %g, at most 100 laser, 200 force"
                            % limits.MIN_RATE_HZ)
    sweep.add_argument("--tolerance", type=_number(0.0, low_open=True),
                       help="largest residual that counts as tracked: mm (laser, default 0.5) "
                            "or %% force error (force, default 10)")
    sweep.add_argument("--workers", type=_workers,
                       help="local processes, 1 to the %d cores of this computer (more are "
                            "refused; default: every core)" % limits.cores())
    sweep.add_argument("--scheduler", metavar="ADDRESS",
                       help="run on a Dask cluster: its scheduler address, or 'local'")
    sweep.add_argument("--seed", type=_whole(0, limits.MAX_SEED), default=0,
                       help="seed of the deviations, 0 to %d" % limits.MAX_SEED)
    sweep.add_argument("-o", "--output", default=".", metavar="DIR", help="output folder (default: .)")
    sweep.add_argument("--quiet", action="store_true", help=QUIET_HELP)
    sweep.add_argument("--json", action="store_true", help="machine-readable summary on stdout")

    place = sub.add_parser("place", help="search where the robot can stand to run the cell's "
                                         "program (exit 1 if nowhere)")
    place.add_argument("document", metavar="DOC.FCStd")
    place.add_argument("--region", required=True, metavar="XMIN,YMIN,XMAX,YMAX",
                       type=_numbers(4, "xmin,ymin,xmax,ymax", limits.MAX_COORDINATE_MM),
                       help="rectangle of the floor to search, mm in the document's frame, each "
                            "within +-%g" % limits.MAX_COORDINATE_MM)
    place.add_argument("--z", type=_numbers(2, "lo,hi", limits.MAX_COORDINATE_MM), metavar="LO,HI",
                       help="height range of the robot base, mm within +-%g (default: its present "
                            "height)" % limits.MAX_COORDINATE_MM)
    place.add_argument("--turn", type=_numbers(2, "lo,hi", limits.MAX_TURN_DEG), metavar="LO,HI",
                       help="range of turns about Z, degrees within +-%g (default: the robot faces "
                            "the targets)" % limits.MAX_TURN_DEG)
    place.add_argument("--step", type=_number(0.0, low_open=True), metavar="MM",
                       help="grid step in x and y (default: the region's longer side / 20)")
    place.add_argument("--z-step", type=_number(0.0, low_open=True), metavar="MM",
                       help="height step (default: 5 heights)")
    place.add_argument("--turn-step", type=_number(0.0, low_open=True), metavar="DEG",
                       help="turn step (default 30)")
    place.add_argument("--margin", type=_number(0.0, 180.0), default=5.0, metavar="DEG",
                       help="least distance of every joint from its limits (default 5)")
    place.add_argument("--count", type=_whole(1, limits.MAX_PLACEMENTS), default=5, metavar="N",
                       help="how many working placements to find, 1 to %d (default 5)"
                            % limits.MAX_PLACEMENTS)
    place.add_argument("--cell", metavar="NAME", help="the cell (name or label); default the first")
    place.add_argument("--no-collisions", action="store_true",
                       help="skip the collision check against the document's solids")
    place.add_argument("--no-singularities", action="store_true",
                       help="accept placements near singularities")
    place.add_argument("--quiet", action="store_true", help=QUIET_HELP)
    place.add_argument("--json", action="store_true", help="machine-readable result on stdout")

    for name, text in (("posts", "list the post-processors"), ("robots", "list the robot catalog")):
        listing = sub.add_parser(name, help=text)
        listing.add_argument("--json", action="store_true", help="machine-readable list on stdout")
        listing.add_argument("--quiet", action="store_true", help=QUIET_HELP)
        if name == "robots":
            listing.add_argument("--import", dest="import_file", metavar="FILE.urdf",
                                 help="add the six-axis arm of a URDF (or .xacro) file to the catalog")
            listing.add_argument("--name", help="its catalog name (default from the file)")
            listing.add_argument("--maker", help="its maker (default guessed from the file)")
            listing.add_argument("--j23-factor", type=int, choices=(-1, 0, 1), metavar="K",
                                 help="the controller's J3 = q3 + K * q2 of the file's joints "
                                      "(1: parallel arm counted against the base, -1: FANUC; "
                                      "default: the maker's convention)")
            listing.add_argument("--filter", metavar="TEXT",
                                 help="only robots whose name, maker or model contains TEXT")
    mechanisms = sub.add_parser("mechanisms", help="list the catalog of tracks and positioners")
    mechanisms.add_argument("--kind", choices=("track", "turntable", "tilt_turn"),
                            help="only mechanisms of this kind")
    mechanisms.add_argument("--json", action="store_true", help="machine-readable list on stdout")
    mechanisms.add_argument("--quiet", action="store_true", help=QUIET_HELP)
    welds = sub.add_parser("welds", help="list the welds of a document (or the weld schedule library)")
    welds.add_argument("document", metavar="DOC.FCStd", nargs="?")
    welds.add_argument("--schedules", action="store_true",
                       help="list the weld schedule library and your own schedules instead")
    welds.add_argument("--json", action="store_true", help="machine-readable list on stdout")
    welds.add_argument("--quiet", action="store_true", help=QUIET_HELP)
    return parser


def parse_post_option(text):
    """One post-processor option, ``key=value`` (``cadrobot export --option``).

    Parameters
    ----------
    text : str

    Returns
    -------
    (str, object)
        The key and the value: true/false as bool, an integer as int, a
        finite decimal as float, anything else (``nan``, ``inf``, words) the
        text itself, for the post to accept or refuse.

    Raises
    ------
    argparse.ArgumentTypeError
        `text` is not ``key=value`` (argparse shows the message).
    """
    key, sep, value = text.partition("=")
    if not sep or not key.strip():
        raise argparse.ArgumentTypeError("write KEY=VALUE, not %r" % text)
    lowered = value.lower()
    if lowered in ("true", "false"):
        return key, lowered == "true"
    try:
        return key, int(value)
    except ValueError:
        pass
    try:
        number = float(value)
    except ValueError:
        return key, value
    return key, number if math.isfinite(number) else value


def _number(low=-math.inf, high=math.inf, low_open=False):
    """An argparse type: one finite number in [low, high] ((low, high] with `low_open`)."""
    def parse(text):
        return _finite_list(text, 1, "a number", low, high, low_open)[0]
    return parse


def _whole(low, high=2 ** 31 - 1):
    """An argparse type: one whole number in [low, high]."""
    def parse(text):
        from .objects.validate import range_text
        try:
            value = int(text)
        except ValueError:
            value = None
        if value is None or not low <= value <= high:
            raise argparse.ArgumentTypeError("give a whole number %s, not %r"
                                             % (range_text(low, high, False), text))
        return value
    return parse


def _finite_list(text, count, form, low=-math.inf, high=math.inf, low_open=False):
    """`count` comma-separated finite numbers in range, or ArgumentTypeError saying what to give."""
    from .objects.validate import range_text
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    bounds = range_text(low, high, low_open)
    ok = len(values) == count and all(
        math.isfinite(v) and (v > low if low_open else v >= low) and v <= high for v in values)
    if not ok:
        wanted = "%d finite numbers %s" % (count, form) if count > 1 else form
        raise argparse.ArgumentTypeError("give %s%s, not %r" % (
            wanted, "" if bounds.startswith("(") else " " + bounds, text))
    return values


def _six_numbers(text):
    return _finite_list(text, 6, "x,y,z,rx,ry,rz (mm, degrees)")


def _numbers(count, form, bound=math.inf):
    """An argparse type: `count` comma-separated finite numbers within +-`bound`."""
    def parse(text):
        return _finite_list(text, count, form, -bound, bound)
    return parse


def _workers(text):
    """An argparse type: local worker processes, 1 to the cores of this computer."""
    try:
        return _whole(1, limits.cores())(text)
    except argparse.ArgumentTypeError as err:
        raise argparse.ArgumentTypeError("%s: more processes than this computer's %d cores only "
                                         "share them and fill the memory" % (err, limits.cores())) from None


def _rate(text):
    """An argparse type: a correction rate in Hz, at least ``limits.MIN_RATE_HZ`` (the
    sensor's own highest is checked once the sensor is known)."""
    return _finite_list(text, 1, "a number", limits.MIN_RATE_HZ)[0]


#: Options whose value may start with a minus sign ("--region -500,0,500,800").
_NUMBER_LIST_OPTIONS = ("--region", "--z", "--turn", "--deviation")


def _join_negative_values(argv):
    """``["--region", "-500,..."]`` -> ``["--region=-500,..."]``: argparse takes a value
    starting with '-' for an option otherwise."""
    out, args = [], list(argv)
    while args:
        arg = args.pop(0)
        if arg in _NUMBER_LIST_OPTIONS and args and args[0][:1] == "-" and args[0][1:2].isdigit():
            arg = "%s=%s" % (arg, args.pop(0))
        out.append(arg)
    return out


def open_document(path):
    """Open a FreeCAD document for reading; DocumentError if it is not one.

    The file is checked first (a zip archive whose ``Document.xml`` parses
    as XML), so a damaged file is refused with one line of ours; FreeCAD's
    own messages while it loads go nowhere (to stderr with
    ``CADROBOT_VERBOSE=1``).
    """
    import FreeCAD
    from . import headless
    if not os.path.isfile(path):
        raise DocumentError("Document '%s' does not exist%s." % (
            path, " (it is a folder)" if os.path.isdir(path) else ""))
    _check_archive(path)
    with headless.quiet_stderr():
        try:
            return FreeCAD.openDocument(os.path.abspath(path), True)
        except TypeError:  # FreeCAD builds without the 'hidden' argument
            return FreeCAD.openDocument(os.path.abspath(path))
        except Exception as err:  # FreeCAD raises plain exceptions for unreadable files
            raise DocumentError("FreeCAD cannot read '%s': %s" % (path, " ".join(str(err).split()))) \
                from None


def _check_archive(path):
    """DocumentError unless `path` is a zip holding a well-formed ``Document.xml`` whose
    links form no cycle."""
    import xml.etree.ElementTree as ElementTree
    import zlib
    from .objects import links
    try:
        with zipfile.ZipFile(path) as archive:
            if "Document.xml" not in archive.namelist():
                raise zipfile.BadZipFile()
            damaged = archive.testzip()
            xml = archive.read("Document.xml")
    except (zipfile.BadZipFile, OSError, EOFError, ValueError):
        raise DocumentError("'%s' is not a FreeCAD document (.FCStd). Give the path of a "
                            "document saved by FreeCAD." % path) from None
    except (zlib.error, RuntimeError, NotImplementedError) as err:
        damaged, xml = "(%s)" % err, b""
    root = None
    if damaged is None:
        try:
            root = ElementTree.fromstring(xml)
        except ElementTree.ParseError as err:
            damaged = "Document.xml (%s)" % err
    if damaged is not None:
        raise DocumentError("'%s' is damaged: %s cannot be read. Open a backup (FreeCAD keeps "
                            "'%s.FCBak' files) or save the document again from FreeCAD."
                            % (path, damaged, os.path.splitext(os.path.basename(path))[0]))
    links.refuse_cycle_in_document_xml(root, path)     # FreeCAD would crash following them


def _select_cells(api, doc, wanted):
    cells = api.find_cells(doc)
    if not cells:
        raise InputError("Document '%s' has no robot cell. Create one with api.make_cell or the "
                         "CadRobot_NewCell command." % doc.Label)
    if not wanted:
        return cells
    chosen = []
    for name in wanted:
        match = [c for c in cells if name in (c.Name, c.Label)]
        if not match:
            raise InputError("Document '%s' has no cell '%s'. Cells: %s."
                             % (doc.Label, name, ", ".join(c.Label for c in cells)))
        chosen.extend(m for m in match if m not in chosen)
    return chosen


def _one_cell(api, doc, name):
    """The cell called `name` (name or label), or the document's first when `name` is None."""
    return _select_cells(api, doc, None if name is None else [name])[0]


def _export(args, out):
    """Every selected cell's files are made first, then all are written, or none."""
    from . import api, fileio
    import FreeCAD
    if args.post is not None:  # an unknown post is reported before the document is opened
        api.posts.get(args.post, extra_dirs=api.user_post_dirs())
    options = dict(args.option or [])
    doc = open_document(args.document)
    try:
        results, files = [], []
        cells = _select_cells(api, doc, args.cell)
        for k, cell in enumerate(cells):
            made = api.program_files(cell, post=args.post, options=options,
                                     check_first=not args.no_check,
                                     progress=args.progress.part(k, len(cells), cell.Label))
            results.append({"cell": cell.Label, "post": args.post or api.default_post_name(cell),
                            "files": [name for name, _ in made]})
            files += made
    finally:
        FreeCAD.closeDocument(doc.Name)
    _refuse_shared_names(results)
    paths = iter(fileio.write_files_atomically(args.output, files, inputs=[args.document]))
    for result in results:
        result["files"] = [next(paths) for _ in result["files"]]
    if args.json:
        out.write(_to_json({"ok": True, "cells": results}) + "\n")
    else:
        for result in results:
            for path in result["files"]:
                out.write("%s: wrote %s\n" % (result["cell"], path))
    return EXIT_OK


def _refuse_shared_names(results):
    """InputError when two cells would write the same file (the second would replace the first;
    case ignored, as on Windows and macOS)."""
    from .posts.output_check import same_file_key
    owner = {}
    for result in results:
        for name in result["files"]:
            key = same_file_key(name)
            if key in owner and owner[key] != result["cell"]:
                raise InputError("Cells '%s' and '%s' both write '%s'. Give each cell its own "
                                 "ProgramName, or export them one at a time (--cell) into different "
                                 "folders." % (owner[key], result["cell"], name))
            owner[key] = result["cell"]


def _check(args, out):
    from . import api
    import FreeCAD
    doc = open_document(args.document)
    try:
        cells = _select_cells(api, doc, args.cell)
        results = [api.check(cell, collisions=not args.no_collisions,
                             progress=args.progress.part(k, len(cells), cell.Label))
                   for k, cell in enumerate(cells)]
    finally:
        FreeCAD.closeDocument(doc.Name)
    ok = all(r.ok for r in results)
    if args.json:
        out.write(_to_json({"ok": ok, "cells": [r.to_dict() for r in results]}) + "\n")
    else:
        for result in results:
            out.write("\n".join(result.lines()) + "\n")
        if any(not r.ok and r.report.placement_helps for r in results):
            out.write("(`%s` searches bases where the robot reaches every target.)\n"
                      % command_line.as_typed("place", args.document, "--region",
                                              "xmin,ymin,xmax,ymax"))
    return EXIT_OK if ok else EXIT_FINDING


def _controllers(args, sensor=None):
    if args.controller:
        return [args.controller] + (["none"] if args.controller != "none" else [])
    return ["pi", "fuzzy_pi", "none"] if (sensor or args.sensor) == "force" else ["pi", "none"]


def _choose_sensor(args, cell):
    """(sensor, detection, how chosen): `--sensor`, else the one the path's faces call for.

    Raises InputError when no --sensor is given and neither sensor suits the path."""
    from . import simulation
    detection = simulation.path_fit(cell, args.path)
    if args.sensor:
        return args.sensor, detection, "asked for"
    if detection is None:
        simulation.read_scene(cell, "laser", path=args.path)    # raises what is wrong with the cell
        raise InputError("Cell '%s': the faces along its path cannot be read, so the sensor is "
                         "unknown; give --sensor laser or --sensor force." % cell.Label, cell.Name)
    if detection.sensor is None:
        raise InputError("%s Give --sensor laser or --sensor force, or set the cell's Workpiece."
                         % detection.reason, cell.Name)
    return detection.sensor, detection, "detected"


#: The files `simulate` writes besides the corrected and resume programs.
SIMULATION_FILES = ("report.json", "corrections.png", "forces.png", "paths.png")
#: The files `sweep` writes.
SWEEP_FILES = ("sweep.json", "sweep.png")


def _simulate(args, out):
    from . import dependencies, fileio, report_plots, simulation
    from . import api
    import FreeCAD
    if args.sensor:
        simulation.check_rate(args.sensor, args.rate)
    fileio.refuse_before_work(args.output, [args.document], SIMULATION_FILES)
    doc = open_document(args.document)
    try:
        cell = _one_cell(api, doc, args.cell)
        cell_label = cell.Label
        post = api.posts.get(cell.PostProcessor, extra_dirs=api.user_post_dirs())
        sensor, detection, chosen = _choose_sensor(args, cell)
        simulation.check_rate(sensor, args.rate)
        foreign = []
        for label in args.foreign or []:
            found = doc.getObjectsByLabel(label) or [o for o in [doc.getObject(label)] if o]
            if not found:
                raise CadRobotError("Document '%s' has no object '%s' to use as a foreign object."
                                    % (doc.Label, label))
            foreign += found
        scene, reality, runs = simulation.simulate_cell(
            cell, sensor, _controllers(args, sensor), args.deviation, args.rate, path=args.path,
            foreign_objects=foreign, seed=args.seed, detection=detection,
            progress=stage(args.progress, 0.0, 0.9))
    finally:
        FreeCAD.closeDocument(doc.Name)
    main_run = runs[0]
    report = {"ok": not main_run.aborted, "cell": cell_label, "path": scene.path_label,
              "sensor": sensor, "sensor_chosen": chosen,
              "sensor_fit": None if detection is None else detection.to_dict(),
              "deviation": args.deviation, "rate_hz": args.rate,
              "runs": [r.to_dict(every=max(1, len(r.time_s) // 2000)) for r in runs]}
    files = []
    report_now(args.progress, 0.9, "plotting")
    if report_plots.is_available():
        files += _simulation_plots(scene, reality, runs)
    else:
        report["plots_not_written"] = dependencies.warn_missing(report_plots.PACKAGE)
    resume = simulation.resume_after(scene, main_run)
    if resume is not None:   # restarting a weld needs the torch back where it stopped
        files += api.posts.run(post, resume, {})
        report["resume_program"] = resume.name
    corrected = simulation.corrected_after(scene, main_run)
    if corrected is not None:
        files += api.posts.run(post, corrected, {})
        report["corrected_program"] = corrected.name
    files.insert(0, ("report.json", _to_json(report, indent=1) + "\n"))
    written = fileio.write_files_atomically(args.output, files, inputs=[args.document])
    summary = {"ok": report["ok"], "files": written, "sensor": sensor, "sensor_chosen": chosen,
               "sensor_fit": report["sensor_fit"],
               **{k: report[k] for k in ("plots_not_written",) if k in report},
               "runs": [{"controller": r.controller, "aborted": r.aborted, "reason": r.reason,
                         "metrics": r.metrics, "notes": r.notes} for r in runs]}
    if args.json:
        out.write(_to_json(summary) + "\n")
    else:
        out.write(_sensor_line(sensor, chosen, detection) + "\n")
        for r in runs:
            state = "ABORTED: %s" % r.reason if r.aborted else "completed"
            out.write("%s %s: %s; %s\n" % (sensor, r.controller, state, _run_numbers(r)))
        for note in main_run.notes:
            out.write("Note: %s\n" % note)
        for path in written:
            out.write("wrote %s\n" % path)
    return EXIT_OK if report["ok"] else EXIT_FINDING


def _sensor_line(sensor, chosen, detection):
    """``Sensor: force (detected): Path ... follow the surface with force.``"""
    line = "Sensor: %s (%s)" % (sensor, chosen)
    if detection is None:
        return line + ": the faces along the path could not be read."
    return "%s: %s" % (line, detection.reason_for(sensor))


def _run_numbers(run):
    """The run's numeric metrics as ``name=value``, then a sentence for each key
    metric without a value (never "nan" or "None")."""
    from .sensors.run import SEAM_SENSORS, has_value, why_no_value
    numbers = ["%s=%s" % (k, _short(v)) for k, v in run.metrics.items()
               if has_value(v) or isinstance(v, bool)]
    key = ("rms_error_after_20mm_mm", "max_error_mm") if run.sensor in SEAM_SENSORS else \
        ("rms_force_error_pct", "mean_force_n", "max_force_n")
    missing = [k for k in key if not has_value(run.metrics.get(k))]
    if run.sensor == "force" and run.metrics.get("first_contact_s") is None:
        numbers.append("the tool never touched the part")
    elif missing:
        numbers.append("%s: %s" % (", ".join(missing), why_no_value(run)))
    return ", ".join(numbers)


def _simulation_plots(scene, reality, runs):
    """[(file name, PNG bytes)] of `cadrobot simulate` (needs matplotlib)."""
    from . import report_plots
    from .sensors.scene import real_seam
    if scene.sensor in ("laser", "arc"):
        first = ("corrections.png", report_plots.plot_corrections(runs, scene.trajectory))
    else:
        first = ("forces.png", report_plots.plot_forces(runs, runs[0].metrics.get("force_set_n", 20.0)))
    return [first, ("paths.png", report_plots.plot_paths(runs[0], real_seam(scene, reality)))]


def _sweep(args, out):
    from . import api, dependencies, fileio, report_plots, simulation, sweep
    import FreeCAD
    import numpy as np
    ranges = sweep.parse_ranges(args.ranges)
    simulation.check_rate(args.sensor, args.rate)
    if args.scheduler is not None:
        sweep.check_scheduler(args.scheduler)
    fileio.refuse_before_work(args.output, [args.document], SWEEP_FILES)
    doc = open_document(args.document)
    try:
        cell = _one_cell(api, doc, args.cell)
        cell_label = cell.Label
        scene = simulation.read_scene(
            cell, args.sensor, path=args.path, progress=stage(args.progress, 0.0, 0.05),
            **simulation.detected_options(args.sensor, simulation.path_fit(cell, args.path)))
    finally:
        FreeCAD.closeDocument(doc.Name)
    deviations = sweep.sample_deviations(ranges, args.runs, args.seed)
    results = sweep.run_sweep(scene, deviations, args.controller, args.rate, args.tolerance,
                              args.workers, args.scheduler, args.seed,
                              progress=stage(args.progress, 0.05, 1.0))
    summary = sweep.summarise(results)
    document = {"cell": cell_label, "path": scene.path_label, "sensor": args.sensor,
                "ranges": ranges, "controller": args.controller, "summary": summary, "runs": results}
    plots = []
    if report_plots.is_available():
        sizes = np.linalg.norm(deviations[:, :3], axis=1)
        plots.append(("sweep.png", report_plots.plot_sweep(
            sizes, np.array([r["residual"] for r in results]), [r["success"] for r in results])))
    else:
        document["plots_not_written"] = dependencies.warn_missing(report_plots.PACKAGE)
    written = fileio.write_files_atomically(args.output, [
        ("sweep.json", _to_json(document, indent=1) + "\n")] + plots, inputs=[args.document])
    if args.json:
        out.write(_to_json({"ok": True, "summary": summary, "files": written}) + "\n")
    else:
        out.write("%d runs: %.0f %% tracked; residual median %s, 95th percentile %s; largest tracked "
                  "deviation %s mm, smallest failed %s mm\n" % (
                      summary["runs"], 100 * summary["success_rate"], _short(summary["residual_median"]),
                      _short(summary["residual_p95"]), _short(summary["largest_tracked_deviation_mm"]),
                      _short(summary["smallest_failed_deviation_mm"])))
        for path in written:
            out.write("wrote %s\n" % path)
    return EXIT_OK


def _place(args, out):
    from . import api
    import FreeCAD
    doc = open_document(args.document)
    try:
        cell = _one_cell(api, doc, args.cell)
        label = cell.Label
        found = api.place_robot(cell, region=args.region, z_mm=args.z, turn_deg=args.turn,
                                step_mm=args.step, z_step_mm=args.z_step, turn_step_deg=args.turn_step,
                                margin_deg=args.margin, singularities=not args.no_singularities,
                                count=args.count, collisions=not args.no_collisions,
                                progress=args.progress)
    finally:
        FreeCAD.closeDocument(doc.Name)
    if args.json:
        out.write(_to_json(dict(found.to_dict(), cell=label)) + "\n")
    else:
        out.write("".join("%s: %s\n" % (label, line) for line in found.lines()))
        if not found:
            out.write("%s: no placement in the region works; widen the region or the ranges, or "
                      "fix what fails above.\n" % label)
    return EXIT_OK if found else EXIT_FINDING


def _to_json(value, indent=2):
    """Strict JSON text of `value`: numpy values as lists and numbers, NaN and
    infinity as null (JSON has no token for them)."""
    return json.dumps(_plain(value), indent=indent, allow_nan=False)


def _plain(value):
    """`value` with numpy arrays and scalars made Python, non-finite floats None."""
    import numpy as np
    if isinstance(value, np.ndarray):
        value = value.tolist()
    elif isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


def _short(value):
    return "%.3g" % value if isinstance(value, float) else str(value)


def _robot_description(spec):
    """One line about a robot: maker, model, payload, reach, kinematics, source."""
    facts = [spec.manufacturer, spec.model]
    if spec.payload_kg is not None:
        facts.append("%g kg" % spec.payload_kg)
    from .robots.catalog import catalog
    reach = catalog.reach_mm(spec)
    if reach is not None:
        facts.append("reach %.0f mm" % reach)
    if spec.controller:
        facts.append("(%s)" % spec.controller)
    if not spec.default_post:
        facts.append("[no post yet]")
    return " ".join(f for f in facts if f)


def _listing(args, out):
    from . import api
    from .robots.catalog import catalog
    if args.command == "posts":
        from . import posts
        rows = []
        for name in api.post_names():
            try:
                module = posts.get(name, extra_dirs=api.user_post_dirs())
            except CadRobotError as problem:     # a broken user post: the others stay listed
                args.progress.err.write("cadrobot: warning: %s\n" % " ".join(str(problem).split()))
                continue
            rows.append((name, module.DESCRIPTION,
                         {"options": dict(getattr(module, "OPTIONS", None) or {})}))
    else:
        if args.import_file is not None:
            name = api.import_robot(args.import_file, name=args.name, maker=args.maker,
                                    j23_factor=args.j23_factor)
            spec = catalog.get(name)
            from .robots.kinematics import models
            kind = models.kinematic_class(spec)
            out.write("Imported %s: %s; %s kinematics, checked against the URDF on 1001 joint sets.\n"
                      % (name, _robot_description(spec), kind.upper() if kind in ("opw", "ur")
                         else kind.replace("_", " ")))
            if spec.notes:
                out.write("Note: %s\n" % spec.notes)
            return EXIT_OK
        text = (args.filter or "").lower()
        rows = [(n, _robot_description(r), {"maker": r.manufacturer, "model": r.model,
                                            "payload_kg": r.payload_kg, "reach_mm": catalog.reach_mm(r),
                                            "default_post": r.default_post or None,
                                            "source": r.source})
                for n, r in ((n, catalog.get(n)) for n in api.robot_names())
                if text in " ".join((n, r.manufacturer, r.model)).lower()]
        for problem in catalog.user_folder_problems():   # the other robots stay listed
            args.progress.err.write("cadrobot: warning: %s\n" % " ".join(problem.split()))
    if args.json:
        out.write(_to_json([dict(name=n, description=d, **extra) for n, d, extra in rows]) + "\n")
    elif rows:
        width = max(len(n) for n, _, _ in rows)
        for name, description, extra in rows:
            out.write("%-*s  %s\n" % (width, name, description))
            for option, text in sorted(extra.get("options", {}).items()):
                out.write("%*s  --option %s=...  %s\n" % (width, "", option, text))
    return EXIT_OK


def split_command_line(text):
    """The arguments of a command line written as one string.

    Words are separated by blanks; quotes (single or double) group words
    into one argument.  Backslashes are kept as they are, so Windows paths
    need no escaping.

    Parameters
    ----------
    text : str
        E.g. ``'export "my part.FCStd" -o out'``.

    Returns
    -------
    list of str

    Raises
    ------
    InputError
        A quote is not closed.
    """
    lexer = shlex.shlex(text, posix=True)
    lexer.whitespace_split = True
    lexer.escape = ""                 # C:\parts\a.FCStd stays as it is
    lexer.commenters = ""
    try:
        return list(lexer)
    except ValueError:
        raise InputError("The command line %r has a quote that is not closed." % text) from None


def run(command_line):
    """Run the CLI inside FreeCADCmd and end the process with its exit code.

    The way in where the ``cadrobot`` launcher is not installed (the Addon
    Manager installs no launcher), the same on FreeCAD 0.20, 1.0 and 1.1, on
    Linux, Windows and macOS::

        FreeCADCmd -c "from CadRobotWB import cli; cli.run('check part.FCStd')"

    The arguments travel inside the ``-c`` string because FreeCAD parses
    ``--options`` on its own command line itself.  stdout carries only the
    CLI's output (FreeCAD's own goes to the null device, or to stderr with
    ``CADROBOT_VERBOSE=1``), an error is one line on stderr, and the process
    ends with the CLI's exit code (0, 1, 2 or 3: see :func:`main`) - FreeCADCmd
    alone would exit 0 whatever happened.

    Parameters
    ----------
    command_line : str or list of str
        The arguments of ``cadrobot``, as one string (see
        :func:`split_command_line`) or as a list.

    Returns
    -------
    int
        Only in FreeCAD's GUI (Python console, macros), where the process
        must live on: the exit code.  Elsewhere this function does not return.
    """
    import FreeCAD
    if FreeCAD.GuiUp:
        return main(command_line)
    from . import headless
    code = EXIT_BUG
    try:
        headless.keep_stdout_for_python()
        code = main(command_line)
    except KeyboardInterrupt:
        code = 130
    except BrokenPipeError:                   # `... | head -1`: quiet, like SIGPIPE
        code = 141
    except BaseException as error:  # noqa: B036 -- nothing may escape: FreeCADCmd would exit 0
        sys.stderr.write("cadrobot: internal error: %s: %s\n" % (type(error).__name__, error))
    headless.exit_process(code)


def _what_is_left(interrupt):
    """What an interrupted run left, for "cadrobot: interrupted: ..."."""
    from . import fileio
    left = getattr(interrupt, "program_left", None)
    if left == fileio.LEFT_NEW:
        return "the folder '%s' holds the new program, complete." % interrupt.output_dir
    if left == fileio.LEFT_PREVIOUS:
        return ("nothing was written: the folder '%s' holds the previous program."
                % interrupt.output_dir)
    return "nothing was written."


def main(argv=None, out=None, err=None):
    """Run the CLI; returns the exit code (never raises).

    Parameters
    ----------
    argv : list of str or str, optional
        The arguments (default ``sys.argv[1:]``); a string is split by
        :func:`split_command_line`.
    out, err : file, optional
        Default stdout and stderr.

    Returns
    -------
    int
        0 success, 1 a finding to fix, 2 bad input, 3 a bug of ours.
    """
    out = out or sys.stdout
    err = err or sys.stderr
    argv = sys.argv[1:] if argv is None else argv
    want_json = "--json" in (argv.split() if isinstance(argv, str) else argv)
    try:
        if isinstance(argv, str):
            argv = split_command_line(argv)
        args = build_parser().parse_args(_join_negative_values(argv))
        if args.command is None:
            raise InputError("give a command: usage: cadrobot [-h] [--version] COMMAND ..., with "
                             "COMMAND one of export, check, simulate, sweep, place, posts, robots, welds, "
                             "mechanisms "
                             "(see `%s`)" % command_line.as_typed("--help"))
        args.progress = progress = ProgressLines(args.command, err, quiet=args.quiet)
        try:
            return _COMMANDS.get(args.command, _listing)(args, out)
        finally:
            progress.done()
    except SystemExit as done:  # --help and --version
        return int(done.code or 0)
    except KeyboardInterrupt as interrupt:   # Ctrl-C, or SIGTERM while writing (fileio)
        err.write("cadrobot: interrupted: %s\n" % _what_is_left(interrupt))
        return EXIT_INTERRUPTED
    except ImportError as error:   # a package FreeCAD's Python lacks (ours are all there)
        missing = missing_package_error(error)
        if missing is None:
            return _internal_error(error, err)
        return _report_error(missing, out, err, want_json)
    except CadRobotError as error:
        return _report_error(error, out, err, want_json)
    except Exception as error:  # a bug of ours: one line, the traceback on request
        return _internal_error(error, err)


# --- welds ----------------------------------------------------------------------------------

def _welds(args, out):
    from . import api
    if args.schedules:
        return _weld_schedules(api, args, out)
    if args.document is None:
        raise InputError("welds: give a document (cadrobot welds DOC.FCStd) or --schedules.")
    import FreeCAD
    doc = open_document(args.document)
    try:
        rows = api.list_welds(doc)
    finally:
        FreeCAD.closeDocument(doc.Name)
    for row in rows:
        if "problem" in row:
            args.progress.err.write("cadrobot: warning: %s\n" % row["problem"])
    if args.json:
        out.write(_to_json(rows) + "\n")
    elif not rows:
        out.write("Document '%s' has no welds. Add one with api.make_weld or the CadRobot_Weld "
                  "command.\n" % os.path.basename(args.document))
    for row in [] if args.json else rows:
        out.write(_weld_line(row) + "\n")
    return EXIT_OK


def _weld_line(row):
    """One line about a weld of :func:`api.list_welds`."""
    first, last = row["segments"]
    segments = "all" if first is None and last is None else "%s-%s" % (first or 1, last or "end")
    head = "%s: cell %s, path %s, segments %s" % (row["label"], row["cell"], row["path"], segments)
    if "problem" in row:
        return "%s; cannot be read (see the warning)" % head
    return "%s; %s; weave %s; tracking %s; %.1f mm, arc %.1f s" % (
        head, _schedule_words(row["schedule"]), _weave_words(row["weave"]), row["tracking"],
        row["length_mm"], row["arc_time_s"])


def _schedule_words(schedule):
    current = "-" if schedule["current_a"] is None else "%g" % schedule["current_a"]
    return "%s %s A / %g V / wire %g m/min%s / %g mm/s" % (
        schedule["name"], current, schedule["voltage_v"], schedule["wire_feed_m_min"],
        " (estimated)" if schedule.get("wire_feed_estimated") else "", schedule["travel_speed_mm_s"])


def _weave_words(weave):
    if weave is None:
        return "none"
    rate = ("%g Hz" % weave["frequency_hz"] if weave["frequency_hz"] is not None
            else "%g mm/cycle" % weave["length_mm"])
    dwells = [weave[k] for k in ("dwell_left_s", "dwell_center_s", "dwell_right_s")]
    return "%s %g mm %s%s%s" % (weave["pattern"], weave["width_mm"], rate,
                                ", dwell %g/%g/%g s" % tuple(dwells) if any(dwells) else "",
                                ", angle %g deg" % weave["angle_deg"] if weave["angle_deg"] else "")


def _weld_schedules(api, args, out):
    """The library's and the user's schedules: the table of ``core.schedule_library``."""
    if args.json:
        out.write(_to_json(list(api.weld_schedules().values())) + "\n")
        return EXIT_OK
    from . import preferences
    from .core import schedule_library
    rows = [schedule_library.TABLE_COLUMNS] + schedule_library.schedule_table(
        schedule_library.load(preferences.weld_schedule_folder()))
    widths = [max(len(row[i]) for row in rows) for i in range(len(rows[0]) - 1)]
    for row in rows:
        out.write("  ".join(["%-*s" % (w, cell) for w, cell in zip(widths, row)] + [row[-1]]) + "\n")
    return EXIT_OK


# --- mechanisms ------------------------------------------------------------------------------

def _mechanisms(args, out):
    """`cadrobot mechanisms`: one line per catalog track or positioner (pure: no FreeCAD)."""
    from .robots.mechanisms import catalog
    rows = [catalog.listing(name) for name in catalog.names(args.kind)]
    if args.json:
        out.write(_to_json(rows) + "\n")
        return EXIT_OK
    for row in rows:
        out.write(_mechanism_line(row) + "\n")
    return EXIT_OK


def _mechanism_line(row):
    """One line about a catalog mechanism of :func:`catalog.listing`."""
    def tenth(value):
        return "%g" % round(value, 1)
    def travel(axis):
        if axis.get("endless"):
            return "endless"
        clockwise = " (counted clockwise)" if axis.get("reversed") else ""
        return "%s..%s %s%s" % (tenth(axis["lower"]), tenth(axis["upper"]), axis["unit"],
                                clockwise)
    axes = ", ".join("%s %s at %s %s/s" % (a["name"], travel(a), tenth(a["max_speed"]), a["unit"])
                     for a in row["axes"])
    payload = "%g kg" % row["payload_kg"] if row["payload_kg"] else "payload not stated"
    estimated = ("; %d values estimated (--json names them)" % len(row["estimated"])
                 if row["estimated"] else "")
    return "%s: %s %s, %s; %s; %s; source: %s%s" % (
        row["name"], row["maker"], row["model"], row["kind"], axes, payload,
        row["sources"][0]["title"], estimated)


_COMMANDS = {"export": _export, "check": _check, "simulate": _simulate, "sweep": _sweep,
             "place": _place, "welds": _welds, "mechanisms": _mechanisms}


def _report_error(error, out, err, want_json):
    """One line on stderr (and the JSON error on stdout with --json); the error's exit code."""
    err.write("cadrobot: error: %s\n" % " ".join(str(error).split()))
    if want_json:
        out.write(json.dumps({"ok": False, "error": str(error), "object": error.obj_name,
                              "kind": type(error).__name__}) + "\n")
    return error.exit_code


def _internal_error(error, err):
    """One line saying it is a bug of ours (the traceback with CADROBOT_DEBUG=1); exit 3."""
    if os.environ.get("CADROBOT_DEBUG"):
        import traceback
        traceback.print_exc(file=err)
    err.write("cadrobot: internal error: %s: %s (set CADROBOT_DEBUG=1 for the traceback and "
              "please report it)\n" % (type(error).__name__, error))
    return EXIT_BUG


def missing_package_error(error):
    """The MissingPackageError for an ImportError of a package that is not ours, else None.

    Parameters
    ----------
    error : ImportError

    Returns
    -------
    MissingPackageError or None
        None when the module is CadRobot's own (a broken installation: a bug
        to report) or unnamed.
    """
    from . import dependencies
    module = (error.name or "").split(".")[0]
    if module in ("", "CadRobotWB"):
        return None
    known = [p.name for p in dependencies.PACKAGES.values() if p.module.split(".")[0] == module]
    if known:
        return MissingPackageError(dependencies.missing_message(known[0]))
    return MissingPackageError(
        "the Python package '%s' cannot be imported by FreeCAD's Python %d.%d (%s). Install "
        "CadRobot's dependencies with the Addon Manager, or run 'make setup' in a checkout."
        % (module, sys.version_info[0], sys.version_info[1], " ".join(str(error).split())))
