"""A headless FreeCAD run that behaves like a command-line tool.

FreeCADCmd writes its own output (console messages, "Recompute..."
progress) to file descriptor 1, and ``FreeCADCmd -c CODE`` exits 0 even when
CODE raises.  A tool run inside it therefore keeps stdout for what Python
prints (:func:`keep_stdout_for_python`) and ends the process itself with its
exit code (:func:`exit_process`).

Used by :func:`CadRobotWB.cli.run` (``FreeCADCmd -c "from CadRobotWB import
cli; cli.run('...')"``) and by ``tools/freecad_run.py`` (the ``cadrobot``
launcher and the test runner): one copy of this logic.  Standard library
only; works on Linux, Windows and macOS.
"""

import contextlib
import io
import os
import sys

#: Set to 1 to see FreeCAD's own output (on stderr) instead of losing it.
VERBOSE_ENV = "CADROBOT_VERBOSE"


def keep_stdout_for_python():
    """Keep the real stdout for Python's ``sys.stdout``; point fd 1 elsewhere.

    FreeCAD's C++ console observer, its progress sequencer and libraries
    write to file descriptor 1 directly; after this they land in the null
    device (or on stderr when ``CADROBOT_VERBOSE=1``), while ``print()``
    still reaches the caller.
    """
    if sys.stdout is not None:
        sys.stdout.flush()
    real = os.dup(1)
    if os.environ.get(VERBOSE_ENV, "") not in ("", "0"):
        os.dup2(2, 1)
    else:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, 1)
        os.close(devnull)
    sys.stdout = open(real, "w", buffering=1 if os.isatty(real) else -1,
                      encoding="utf-8", errors="backslashreplace")


def exit_process(code):
    """Flush every stream, then end the process with exit status `code` at once.

    ``os._exit`` skips FreeCAD's own shutdown, which would otherwise turn
    the status into 0; C stdio buffers are flushed first where the C
    library can be reached (Linux, macOS).
    """
    for stream in (sys.stdout, sys.stderr, sys.__stdout__, sys.__stderr__):
        _flush(stream)      # e.g. BrokenPipeError when piped into `head`: ignored
    _flush_c_stdio()
    os._exit(code)


@contextlib.contextmanager
def quiet_stderr():
    """Send what is written to stderr (``sys.stderr`` and file descriptor 2) nowhere
    while the block runs; with ``CADROBOT_VERBOSE=1`` it stays on stderr.

    FreeCAD prints its own diagnostics (e.g. the XML parser's "Fatal Error at
    file ...") on fd 2 while it opens a document; the CLI's one line of its
    own must come first and alone.
    """
    if os.environ.get(VERBOSE_ENV, "") not in ("", "0"):
        yield
        return
    for stream in (sys.stderr, sys.__stderr__):
        _flush(stream)
    saved_fd, saved_stream = os.dup(2), sys.stderr
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, 2)
    os.close(devnull)
    sys.stderr = io.StringIO()
    try:
        yield
    finally:
        _flush_c_stdio()
        sys.stderr = saved_stream
        os.dup2(saved_fd, 2)
        os.close(saved_fd)


def _flush(stream):
    try:
        stream.flush()
    except Exception:  # noqa: BLE001 -- a closed or broken stream has nothing to flush
        pass


def _flush_c_stdio():
    try:
        import ctypes
        ctypes.CDLL(None).fflush(None)        # C stdio buffers of FreeCAD itself
    except Exception:  # noqa: BLE001 -- no C library handle (Windows): nothing to flush
        pass
