#!/usr/bin/env python3
"""Run Python code inside FreeCAD and give back its real exit code.

Why not ``freecadcmd script.py ARGS``: FreeCAD 0.20 parses every ``--option``
itself (``unrecognised option '--post'``, exit 1), tries to open the other
arguments as documents, prints its banner on stdout, and exits 0 when the
script raises.  This driver instead passes the job in one environment variable
(``CADROBOT_RUN_SPEC``, JSON), starts ``freecadcmd -c <bootstrap>`` (or, with
``--gui``, the real ``freecad`` main window under ``xvfb-run``), runs the job
there and ends FreeCAD with ``os._exit(code)`` after flushing every stream.

Usage (outside FreeCAD, any python3 -- only the standard library is used)::

    freecad_run.py [OPTIONS] SCRIPT [ARGS...]            run SCRIPT as __main__
    freecad_run.py [OPTIONS] -m MODULE [ARGS...]         like ``python -m``
    freecad_run.py [OPTIONS] --call MOD:FUNC [ARGS...]   exit code = FUNC([ARGS...])

Options::

    --gui            real FreeCAD GUI (FreeCADGui.getMainWindow(), 3D views,
                     saveImage) on a private Xvfb display
    --timeout SEC    kill FreeCAD (and Xvfb) after SEC seconds -> exit 124
    --clean-stdout   stdout carries only what the Python code prints; FreeCAD's
                     own output (banner, Console.PrintMessage, "Recompute..."
                     progress) goes to /dev/null, or to stderr when
                     CADROBOT_VERBOSE=1.  Warnings/errors stay on stderr.
    --prog NAME      an escaping exception is reported as ONE line
                     "NAME: error: ..." (CadRobotError, exit = its exit_code) or
                     "NAME: internal error: ..." (exit 3); the traceback is shown
                     when CADROBOT_DEBUG=1.  Without --prog: full traceback, exit 3.

Exit status: what the code returns / passes to ``sys.exit``; 3 for an
unexpected exception or when FreeCAD cannot be started; 124 on timeout;
130 on Ctrl-C.  Relative paths in ARGS stay relative to the caller's working
directory, and this checkout's root is first on ``sys.path``.

Inside FreeCAD the same file is the runner (selected by the environment
variable), so there is exactly one copy of the exit-code logic.
"""

import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile

SPEC_ENV = "CADROBOT_RUN_SPEC"
HERE = os.path.dirname(os.path.realpath(os.path.abspath(__file__)))
REPO = os.path.dirname(HERE)
THIS = os.path.join(HERE, "freecad_run.py")
BOOTSTRAP = "import runpy; runpy.run_path(%r, run_name='__cadrobot_inner__')" % THIS
EXIT_INTERNAL = 3
EXIT_TIMEOUT = 124
XVFB_SCREEN = "-screen 0 1600x1200x24"


# --------------------------------------------------------------------------
# Outside FreeCAD: the driver
# --------------------------------------------------------------------------
def _which(*names):
    for name in names:
        path = shutil.which(name)
        if path:
            return path
    return None


def _fail(prog, message):
    sys.stderr.write("%s: %s\n" % (prog or "freecad_run", message))
    return EXIT_INTERNAL


def build_command(gui=False):
    """Return the argv that starts FreeCAD for the inner runner, or raise OSError."""
    if gui:
        freecad = os.environ.get("CADROBOT_FREECAD") or _which("freecad", "FreeCAD")
        xvfb_run = _which("xvfb-run")
        if not freecad or not xvfb_run:
            raise OSError("the GUI run needs 'freecad' and 'xvfb-run' "
                          "(apt packages freecad, xvfb, xauth: run tools/setup.sh)")
        # Parallel GUI runs search for a free display from different numbers: two
        # `xvfb-run -a` started together would both take the first free one.
        first_display = os.environ.get("CADROBOT_XVFB_SERVERNUM", "99")
        return [xvfb_run, "-a", "-n", first_display, "-s", XVFB_SCREEN, freecad, THIS]
    freecadcmd = os.environ.get("CADROBOT_FREECADCMD") or _which("freecadcmd", "FreeCADCmd")
    if not freecadcmd:
        raise OSError("FreeCAD is not installed (no 'freecadcmd' on PATH): run tools/setup.sh")
    return [freecadcmd, "-c", BOOTSTRAP]


def build_env(spec):
    env = dict(os.environ)
    env[SPEC_ENV] = json.dumps(spec)
    if spec["gui"]:
        # Chromium (Start page, Addon Manager) refuses to run as root without it.
        flags = env.get("QTWEBENGINE_CHROMIUM_FLAGS", "")
        if "--no-sandbox" not in flags.split():
            env["QTWEBENGINE_CHROMIUM_FLAGS"] = (flags + " --no-sandbox").strip()
        env.pop("QT_QPA_PLATFORM", None)          # xcb on the Xvfb display
    return env


def make_spec(kind, target, args=(), gui=False, clean_stdout=False, prog=None, cwd=None):
    cwd = os.path.abspath(cwd or os.getcwd())
    if kind == "script":
        target = os.path.abspath(target)
        first = os.path.dirname(target)
    else:
        first = cwd
    path = []
    for p in (first, REPO):
        if p not in path:
            path.append(p)
    return {"kind": kind, "target": target, "args": list(args), "cwd": cwd,
            "sys_path": path, "gui": bool(gui), "clean_stdout": bool(clean_stdout),
            "prog": prog}


def _ensure_std_fds():
    """Reopen a closed stdin/stdout/stderr on /dev/null.

    With fd 0 closed (``cmd <&-``), a file FreeCAD/Qt/Xvfb opens later takes
    number 0 and the GUI's saveImage() hangs; CI may start us like that.
    """
    for fd in (0, 1, 2):
        try:
            os.fstat(fd)
        except OSError:
            null = os.open(os.devnull, os.O_RDWR)
            if null != fd:
                os.dup2(null, fd)
                os.close(null)
            os.set_inheritable(fd, True)      # os.open() fds are close-on-exec


def run(kind, target, args=(), gui=False, timeout=None, clean_stdout=False, prog=None,
        replace_process=False):
    """Run a job inside FreeCAD; return its exit code (see the module docstring)."""
    _ensure_std_fds()
    spec = make_spec(kind, target, args, gui, clean_stdout, prog)
    try:
        cmd = build_command(gui)
    except OSError as exc:
        return _fail(prog, str(exc))
    env = build_env(spec)
    runtime_dir = None
    if gui and not env.get("XDG_RUNTIME_DIR"):
        runtime_dir = tempfile.mkdtemp(prefix="cadrobot-xdg-")   # quiets Qt, mode 0700
        env["XDG_RUNTIME_DIR"] = runtime_dir
    if replace_process and not gui and not timeout:
        for stream in (sys.stdout, sys.stderr):
            if stream is not None:
                stream.flush()
        os.execve(cmd[0], cmd, env)              # no return
    try:
        proc = subprocess.Popen(cmd, env=env, start_new_session=True,
                                stdin=subprocess.DEVNULL if gui else None)
        try:
            code = proc.wait(timeout=timeout)
            return 128 - code if code < 0 else code   # killed by a signal: 128+N, as a shell
        except subprocess.TimeoutExpired:
            _kill_group(proc)
            _fail(prog, "timed out after %g s: %s" % (timeout, target))
            return EXIT_TIMEOUT
        except KeyboardInterrupt:
            _kill_group(proc)
            return 130
    finally:
        if runtime_dir:
            shutil.rmtree(runtime_dir, ignore_errors=True)


def _kill_group(proc):
    for sig, wait in ((signal.SIGTERM, 10), (signal.SIGKILL, 10)):
        try:
            os.killpg(proc.pid, sig)
        except ProcessLookupError:
            return
        try:
            proc.wait(timeout=wait)
            return
        except subprocess.TimeoutExpired:
            continue


USAGE = ("usage: freecad_run.py [--gui] [--timeout SEC] [--clean-stdout] [--prog NAME] "
         "(SCRIPT | -m MODULE | --call MOD:FUNC) [ARGS...]")


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    gui, timeout, clean, prog, kind, target = False, None, False, None, None, None
    while argv:
        opt = argv.pop(0)
        if opt == "--gui":
            gui = True
        elif opt == "--clean-stdout":
            clean = True
        elif opt in ("--timeout", "--prog", "-m", "--call") and argv:
            value = argv.pop(0)
            if opt == "--timeout":
                timeout = float(value)
            elif opt == "--prog":
                prog = value
            else:
                kind, target = ("module" if opt == "-m" else "call"), value
                break
        elif opt in ("-h", "--help"):
            print(USAGE)
            return 0
        elif opt == "--":
            if argv:
                kind, target = "script", argv.pop(0)
            break
        elif opt.startswith("-"):
            sys.stderr.write("freecad_run.py: unknown option %s\n%s\n" % (opt, USAGE))
            return 2
        else:
            kind, target = "script", opt
            break
    if kind is None:
        sys.stderr.write(USAGE + "\n")
        return 2
    if kind == "script" and not os.path.isfile(target):
        _fail(prog, "no such script: %s" % target)
        return 2
    return run(kind, target, argv, gui=gui, timeout=timeout, clean_stdout=clean, prog=prog,
               replace_process=True)


# --------------------------------------------------------------------------
# Inside FreeCAD: the runner
# --------------------------------------------------------------------------
def _inner():
    spec = json.loads(os.environ.pop(SPEC_ENV))
    if spec["gui"]:
        # The GUI sends sys.stdout/stderr to the Report view; we want the terminal.
        sys.stdout, sys.stderr = sys.__stdout__, sys.__stderr__
        from PySide import QtCore  # FreeCAD's PySide shim (Qt5 or Qt6)
        # Run once the event loop is up, so timers, dialogs and redraws work.
        QtCore.QTimer.singleShot(0, lambda: _run_and_exit(spec))
    else:
        _run_and_exit(spec)


def _run_and_exit(spec):
    code = EXIT_INTERNAL
    prog = spec.get("prog")
    try:
        try:
            if os.getcwd() != spec["cwd"]:
                os.chdir(spec["cwd"])
        except OSError:
            pass
        for p in reversed(spec["sys_path"]):
            if p in sys.path:
                sys.path.remove(p)
            sys.path.insert(0, p)
        if spec["clean_stdout"]:
            from CadRobotWB.headless import keep_stdout_for_python
            keep_stdout_for_python()
        code = _execute(spec)
    except SystemExit as exc:
        code = _exit_code(exc.code, prog, from_system_exit=True)
    except KeyboardInterrupt:
        code = 130
    except BrokenPipeError:                   # `cadrobot posts | head -1`: quiet, like SIGPIPE
        code = 141
    except BaseException as exc:  # noqa: B036 -- nothing may escape: FreeCAD would exit 0
        code = _report(exc, prog)
    _hard_exit(code)


def _freecad_globals():
    """FreeCAD's own names of its ``__main__`` (App, Gui, ...). runpy gives the job a
    fresh ``__main__``, and FreeCAD runs its command strings (``Gui.doCommand``,
    the GUI's own journal) in whatever ``__main__`` is current."""
    import __main__
    return {name: getattr(__main__, name) for name in ("App", "Gui", "FreeCAD", "FreeCADGui")
            if hasattr(__main__, name)}


def _execute(spec):
    import runpy
    kind, target, args = spec["kind"], spec["target"], spec["args"]
    if kind == "script":
        sys.argv = [target] + args
        runpy.run_path(target, init_globals=_freecad_globals(), run_name="__main__")
        return 0
    if kind == "module":
        sys.argv = [target] + args
        runpy.run_module(target, init_globals=_freecad_globals(), run_name="__main__",
                         alter_sys=True)
        return 0
    module_name, _, func_name = target.partition(":")
    sys.argv = [spec.get("prog") or module_name] + args
    import importlib
    func = getattr(importlib.import_module(module_name), func_name or "main")
    return _exit_code(func(list(args)), spec.get("prog"))


def _exit_code(value, prog, from_system_exit=False):
    if value is None:
        return 0
    if isinstance(value, bool):
        return int(value)
    if isinstance(value, int):
        if 0 <= value <= 255:
            return value
        sys.stderr.write("%s: internal error: exit code %d out of range\n"
                         % (prog or "freecad_run", value))
        return EXIT_INTERNAL
    if from_system_exit:                      # sys.exit("message"): Python prints it, exit 1
        sys.stderr.write("%s\n" % (value,))
        return 1
    sys.stderr.write("%s: internal error: got %r instead of an exit code\n"
                     % (prog or "freecad_run", value))
    return EXIT_INTERNAL


def _is_cadrobot_error(exc):
    return any(c.__name__ == "CadRobotError" and c.__module__.startswith("CadRobotWB")
               for c in type(exc).__mro__)


def _missing_package(exc):
    """CadRobot's MissingPackageError for `exc`, or None (not ours to judge, or no checkout)."""
    try:
        from CadRobotWB.cli import missing_package_error
        return missing_package_error(exc)
    except Exception:  # noqa: BLE001 -- the report of the first error must not fail
        return None


def _report(exc, prog):
    import traceback
    if not prog:
        traceback.print_exc()
        return EXIT_INTERNAL
    if isinstance(exc, ImportError):          # a package FreeCAD's Python lacks: exit 2, one line
        exc = _missing_package(exc) or exc
    message = " ".join(str(exc).split()) or type(exc).__name__
    if _is_cadrobot_error(exc):
        code = getattr(exc, "exit_code", 2)
        code = code if isinstance(code, int) and 0 < code < 256 else 2
        sys.stderr.write("%s: error: %s\n" % (prog, message))
    else:
        code = EXIT_INTERNAL
        sys.stderr.write("%s: internal error: %s: %s%s\n" % (
            prog, type(exc).__name__, message,
            "" if os.environ.get("CADROBOT_DEBUG") else
            " (run with CADROBOT_DEBUG=1 for the traceback)"))
    if os.environ.get("CADROBOT_DEBUG"):
        traceback.print_exc()
    return code


def _hard_exit(code):
    """End FreeCAD with `code` (CadRobotWB.headless.exit_process: flush, os._exit)."""
    try:
        from CadRobotWB.headless import exit_process
    except Exception:  # noqa: BLE001 -- the exit code must survive a broken checkout
        os._exit(code)
    exit_process(code)


if os.environ.get(SPEC_ENV) and "FreeCAD" in sys.modules:
    _inner()
elif __name__ == "__main__":
    sys.exit(main())
