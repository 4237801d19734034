"""The headless batch CLI, ``cadrobot`` (runs inside FreeCADCmd).

Exit codes: 0 success, 1 a finding the user must fix, 2 bad input, 3 a bug
of ours. Errors are
one line on stderr naming the object at fault; with ``--json`` the result (or
the error) is also printed as JSON on stdout. The input document is opened
read-only in effect: it is never recomputed or saved.
"""

import argparse
import json
import os
import sys
import zipfile

from . import __version__
from .errors import CadRobotError, DocumentError, InputError

EXIT_OK, EXIT_FINDING, EXIT_INPUT, EXIT_BUG = 0, 1, 2, 3


class _Parser(argparse.ArgumentParser):
    """argparse that raises instead of exiting, so usage errors exit 2 cleanly."""

    def error(self, message):
        raise InputError("%s (see 'cadrobot %s--help')" % (message, self._sub_hint()))

    def _sub_hint(self):
        return "" if self.prog == "cadrobot" else self.prog.split(" ", 1)[-1] + " "


def build_parser():
    parser = _Parser(prog="cadrobot", description=(
        "CadRobot batch tool: robot programs from FreeCAD documents, without the GUI."))
    parser.add_argument("--version", action="version", version="cadrobot " + __version__)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)

    export = sub.add_parser("export", help="generate and write the robot program of a document's cells")
    export.add_argument("document", metavar="DOC.FCStd")
    export.add_argument("--post", help="post-processor (default: each cell's PostProcessor property)")
    export.add_argument("-o", "--output", default=".", metavar="DIR", help="output folder (default: .)")
    export.add_argument("--cell", action="append", metavar="NAME",
                        help="only this cell (name or label); repeatable. Default: every cell")
    export.add_argument("--no-check", action="store_true",
                        help="write the program even if the robot cannot run it (skip 'check')")
    export.add_argument("--json", action="store_true", help="machine-readable result on stdout")

    check = sub.add_parser("check", help="can the robot run each cell's program? (exit 1 if not)")
    check.add_argument("document", metavar="DOC.FCStd")
    check.add_argument("--cell", action="append", metavar="NAME",
                       help="only this cell (name or label); repeatable. Default: every cell")
    check.add_argument("--no-collisions", action="store_true",
                       help="skip the collision check against the document's solids")
    check.add_argument("--json", action="store_true", help="machine-readable report on stdout")

    for name, text in (("posts", "list the post-processors"), ("robots", "list the robot catalog")):
        listing = sub.add_parser(name, help=text)
        listing.add_argument("--json", action="store_true", help="machine-readable list on stdout")
    return parser


def open_document(path):
    """Open a FreeCAD document for reading; DocumentError if it is not one."""
    import FreeCAD
    if not os.path.isfile(path):
        raise DocumentError("Document '%s' does not exist." % path)
    try:
        with zipfile.ZipFile(path) as archive:
            if "Document.xml" not in archive.namelist():
                raise zipfile.BadZipFile()
    except (zipfile.BadZipFile, OSError):
        raise DocumentError("'%s' is not a FreeCAD document (.FCStd). Give the path of a "
                            "document saved by FreeCAD." % path) from None
    try:
        return FreeCAD.openDocument(os.path.abspath(path), True)
    except TypeError:  # FreeCAD builds without the 'hidden' argument
        return FreeCAD.openDocument(os.path.abspath(path))
    except Exception as err:  # FreeCAD raises plain exceptions for unreadable files
        raise DocumentError("FreeCAD cannot read '%s': %s" % (path, err)) from None


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


def _export(args, out):
    from . import api
    import FreeCAD
    if args.post:  # an unknown post is reported before the document is opened
        api.posts.get(args.post, extra_dirs=api.user_post_dirs())
    doc = open_document(args.document)
    try:
        results = []
        for cell in _select_cells(api, doc, args.cell):
            files = api.export(cell, post=args.post, output_dir=args.output,
                               check_first=not args.no_check)
            results.append({"cell": cell.Label, "post": args.post or cell.PostProcessor, "files": files})
    finally:
        FreeCAD.closeDocument(doc.Name)
    if args.json:
        out.write(json.dumps({"ok": True, "cells": results}, indent=2) + "\n")
    else:
        for result in results:
            for path in result["files"]:
                out.write("%s: wrote %s\n" % (result["cell"], path))
    return EXIT_OK


def _check(args, out):
    from . import api
    import FreeCAD
    doc = open_document(args.document)
    try:
        results = [api.check(cell, collisions=not args.no_collisions)
                   for cell in _select_cells(api, doc, args.cell)]
    finally:
        FreeCAD.closeDocument(doc.Name)
    ok = all(r.ok for r in results)
    if args.json:
        out.write(json.dumps({"ok": ok, "cells": [r.to_dict() for r in results]}, indent=2) + "\n")
    else:
        for result in results:
            out.write("\n".join(result.lines()) + "\n")
    return EXIT_OK if ok else EXIT_FINDING


def _listing(args, out):
    from .robots import catalog
    if args.command == "posts":
        from . import api, posts
        rows = [(n, posts.get(n, extra_dirs=api.user_post_dirs()).DESCRIPTION) for n in api.post_names()]
    else:
        rows = [(n, "%s %s (%s)" % (r.manufacturer, r.model, r.controller))
                for n, r in ((n, catalog.get(n)) for n in catalog.names())]
    if args.json:
        out.write(json.dumps([{"name": n, "description": d} for n, d in rows], indent=2) + "\n")
    else:
        width = max(len(n) for n, _ in rows)
        for name, description in rows:
            out.write("%-*s  %s\n" % (width, name, description))
    return EXIT_OK


def main(argv=None, out=None, err=None):
    """Run the CLI; returns the exit code (never raises)."""
    out = out or sys.stdout
    err = err or sys.stderr
    argv = list(sys.argv[1:] if argv is None else argv)
    want_json = "--json" in argv
    try:
        args = build_parser().parse_args(argv)
        if args.command is None:
            build_parser().print_help(out)
            return EXIT_INPUT
        if args.command == "export":
            return _export(args, out)
        if args.command == "check":
            return _check(args, out)
        return _listing(args, out)
    except SystemExit as done:  # --help and --version
        return int(done.code or 0)
    except CadRobotError as error:
        err.write("cadrobot: error: %s\n" % error)
        if want_json:
            out.write(json.dumps({"ok": False, "error": str(error), "object": error.obj_name,
                                  "kind": type(error).__name__}) + "\n")
        return error.exit_code
    except Exception as error:  # a bug of ours: one line, the traceback on request
        if os.environ.get("CADROBOT_DEBUG"):
            import traceback
            traceback.print_exc(file=err)
        err.write("cadrobot: internal error: %s: %s (set CADROBOT_DEBUG=1 for the traceback and "
                  "please report it)\n" % (type(error).__name__, error))
        return EXIT_BUG
