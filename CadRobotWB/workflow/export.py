"""Post-processors and program files: which posts there are, the files a post writes,
writing them atomically.

Part of the scripting API: :mod:`CadRobotWB.api` re-exports its public names.
"""

import os

import FreeCAD

from .. import command_line, fileio, posts, preferences
from ..core import progress as core_progress
from ..core.progress import report_now, stage
from ..errors import CadRobotError, FindingError, InputError
from ..objects import base
from ..posts import common as post_common
from ..posts import output_check as post_output
from ..robots.catalog import catalog
from .check import check
from .arguments import POST_NAME, Arguments
from .program import generate


def user_post_dirs():
    """Folders searched for user posts ``<name>_post.py``: FreeCAD's macro
    folder and the ``PostFolder`` preference."""
    dirs = [FreeCAD.getUserMacroDir(True)]
    extra = preferences.get("PostFolder")
    if extra:
        dirs.append(extra)
    return [d for d in dirs if d and os.path.isdir(d)]


def post_names():
    """Names of every post-processor available (built-in and user posts)."""
    return posts.names(extra_dirs=user_post_dirs())


def default_post_name(cell):
    """The post :func:`export` uses for `cell` when none is given.

    The cell's ``PostProcessor``, unless that is another maker's post than the
    cell's robot's (a robot changed after the cell was made, say): then the
    robot maker's own post. Writing another maker's language takes an explicit
    ``post=`` (``--post`` on the command line), and its program's header says so.

    Returns
    -------
    str
    """
    Arguments("default_post_name").cell(cell)
    own = cell.PostProcessor
    preferences.use_user_robot_folder()
    try:
        robot_post = catalog.get(cell.Robot).default_post
    except CadRobotError:
        return own
    if robot_post and other_maker_note(cell, own):
        return robot_post
    return own


def other_maker_note(cell, post):
    """What the header of `post`'s program for `cell` says when `post` is another
    maker's than the cell's robot's ("Written for a KUKA controller, but the cell's
    robot is an ABB IRB 2400/10 ..."), else "" (the GUI asks before writing it)."""
    args = Arguments("other_maker_note")
    args.cell(cell)
    args.text("post", post, expected=POST_NAME)
    return post_common.other_maker_note(cell.Robot, post)


def program_files(cell, post=None, options=None, check_first=True, progress=None):
    """The files :func:`export` would write for `cell`; nothing is written.

    Parameters
    ----------
    post : str, optional
        Post-processor name; default :func:`default_post_name` (the robot
        maker's own unless the cell's ``PostProcessor`` fits the robot).
    options : dict, optional
        Post-specific options (``date`` defaults to now, or SOURCE_DATE_EPOCH).
    check_first : bool
        Run :func:`check` first and raise FindingError if it finds an error.
        False makes the program whatever the robot can do.
    progress : callable, optional
        ``progress(fraction, text)``, told often (``core.progress``); return
        False to stop: :data:`Cancelled` is raised.

    Returns
    -------
    list of (str, str)
        File name and text, in the post's order.
    """
    _program_arguments("program_files", cell, post, options, check_first, progress)
    progress = core_progress.or_ambient(progress)
    module = posts.get(default_post_name(cell) if post is None else post,
                       extra_dirs=user_post_dirs())
    if options is not None and not isinstance(options, dict):
        raise InputError("options is %s; pass a dict of option name to value, e.g. "
                         "{'max_lines': 500}, or None." % post_output.describe_value(options))
    options = dict(options or {})
    options.setdefault("date", _export_date())
    if check_first:
        result = check(cell, progress=stage(progress, 0.0, 0.9))
        if not result.ok:
            raise check_failed(cell, result)
        program = result.program
    else:
        program = generate(cell, progress=stage(progress, 0.0, 0.9))
    report_now(progress, 0.9, "writing the program (%s)" % module.__name__.rsplit(".", 1)[-1])
    files = posts.run(module, program, options)
    report_now(progress, 1.0, "done")
    return files


def _program_arguments(function, cell, post, options, check_first, progress):
    """The checked Arguments of `function`, a call that writes (or would write) `cell`'s program."""
    args = Arguments(function)
    args.cell(cell)
    args.text("post", post, optional=True, expected="None or " + POST_NAME)
    args.mapping("options", options)
    args.flag("check_first", check_first)
    args.callback("progress", progress)
    return args


def check_failed(cell, result):
    """The FindingError of an export that `result` (a failed :func:`check`) refuses.

    Its ``details`` are every line of the check (the Generate panel lists them); the
    message names the first problem and how this user sees all of them: Check cell in
    FreeCAD's GUI, else the check command as they type it (:mod:`..command_line`).
    """
    errors = result.report.errors
    if command_line.in_gui():
        see_all = ("Check cell lists all of them and colours the targets (they are listed below "
                   "too); or write without checking.")
    else:
        see_all = "Run `%s` for all of them, or export without checking." % command_line.as_typed(
            "check", command_line.document_argument(cell.Document))
    error = FindingError("Cell %s: %d problem(s) the robot cannot run, first: %s %s" % (
        base.describe(cell), len(errors), errors[0].message, see_all), cell.Name)
    error.details = result.lines()
    return error


def export(cell, post=None, output_dir=".", options=None, check_first=True, progress=None):
    """Generate `cell`'s program and write it with post-processor `post`.

    Parameters
    ----------
    post : str, optional
        Post-processor name; default :func:`default_post_name`.
    output_dir : str
        Created if missing; the program's files are written all-or-nothing as a
        set (:mod:`..fileio`), never over the document itself.
    options : dict, optional
        Post-specific options.
    check_first : bool
        Run :func:`check` first and write nothing if it finds an error
        (FindingError). False writes the program whatever the robot can do.
    progress : callable, optional
        ``progress(fraction, text)``, told often (``core.progress``); return
        False to stop: :data:`Cancelled` is raised and nothing is written.

    Returns
    -------
    list of str
        Paths of the written files.

    Raises
    ------
    InputError
        A file would replace the cell's own document (symlinks resolved).
    """
    args = _program_arguments("export", cell, post, options, check_first, progress)
    output_dir = args.file_path("output_dir", output_dir, what="a folder path")
    progress = core_progress.or_ambient(progress)
    files = program_files(cell, post=post, options=options, check_first=check_first,
                          progress=progress)
    return fileio.write_files_atomically(output_dir, files, inputs=[cell.Document.FileName])


def _export_date():
    """Now, or SOURCE_DATE_EPOCH when set (reproducible output, as in reproducible builds)."""
    import datetime
    epoch = os.environ.get("SOURCE_DATE_EPOCH")
    if epoch:
        return datetime.datetime.fromtimestamp(int(epoch), datetime.timezone.utc).replace(tzinfo=None)
    return datetime.datetime.now().replace(microsecond=0)
