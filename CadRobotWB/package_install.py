"""Install an optional Python package for FreeCAD's own Python, from inside FreeCAD.

The Addon Manager installs only the packages on its allow-list, and python-fcl
(collision checks) is not on it: users who install CadRobot that way get it
from here, with no terminal (the GUI's "Install python-fcl" button runs
:func:`run_pip` in a worker thread, then :func:`activate`).  What it does is what
the Addon Manager does for an allowed package: ``python -m pip install --target
FOLDER NAME`` with FreeCAD's own Python, into the folder FreeCAD reads
(:func:`compat.pip_target_folder`).  Then the package is made importable in the
running FreeCAD (``sys.path``, ``importlib.invalidate_caches``, and the modules
that found it missing at import told it is there), so the next check uses it
without a restart.

FreeCAD's Python: inside FreeCAD ``sys.executable`` is FreeCAD itself, so the
interpreter is looked for as the Addon Manager does (``freecad.utils.get_python_exe``
on 1.x) and beside ``sys.prefix``, and each candidate is asked ``-m pip --version``:
the first with pip and the same Python version as FreeCAD's wins.

App layer: FreeCAD is imported inside the functions (FreeCADCmd can install too).
"""

import importlib
import os
import re
import shutil
import subprocess
import sys
import threading
from dataclasses import dataclass, field
from typing import List

from . import dependencies
from .errors import MissingPackageError

#: Seconds pip may take (download and install); after that it is stopped.
PIP_TIMEOUT_S = 900
#: Seconds a candidate interpreter may take to answer ``-m pip --version``.
PROBE_TIMEOUT_S = 60
#: Lines of pip's output a failure shows.
TAIL_LINES = 8

# pip's dependencies of the packages installed here that FreeCAD's Python already has
# (numpy: CadRobot needs it anyway) or that the wheel never imports (Cython: only to
# build python-fcl from source, and pip's build isolation fetches it then). With
# --target, pip would install them again beside the package (tens of MB of numpy).
_NO_DEPS = {"python-fcl"}


@dataclass
class PipPython:
    """FreeCAD's Python interpreter, with pip.

    Attributes
    ----------
    executable : str
    pip_version : str
    """

    executable: str
    pip_version: str


@dataclass
class InstallResult:
    """What an install did.

    Attributes
    ----------
    package : str
        The pip name.
    ok : bool
        pip succeeded.
    importable : bool
        The package imports in this process now (no restart needed).
    command : list of str
        The pip command (empty when no interpreter with pip was found).
    output : list of str
        pip's output lines.
    message : str
        What happened and what to do, for the user.
    """

    package: str
    ok: bool = False
    importable: bool = False
    command: List[str] = field(default_factory=list)
    output: List[str] = field(default_factory=list)
    message: str = ""


def _version_tag():
    return "%d.%d" % sys.version_info[:2]


def python_candidates():
    """Interpreters that may be FreeCAD's Python, best first (list of str, existing files).

    ``sys.executable`` when it is a Python (not FreeCAD), what FreeCAD 1.x's Addon
    Manager uses (``freecad.utils.get_python_exe``), ``pythonX.Y`` / ``python3``
    beside ``sys.prefix`` and FreeCAD's home, then the PATH's ``pythonX.Y``.
    """
    tag = _version_tag()
    windows = os.name == "nt"
    names = ["python.exe"] if windows else ["python" + tag, "python3", "python"]
    found = []
    if os.path.basename(sys.executable or "").lower().startswith("python"):
        found.append(sys.executable)
    try:
        from freecad.utils import get_python_exe    # FreeCAD 1.0 and later
        found.append(get_python_exe())
    except Exception:  # noqa: BLE001 -- 0.20 has none; a broken one only costs a candidate
        pass
    homes = [sys.base_prefix, sys.prefix]
    freecad = sys.modules.get("FreeCAD")
    if freecad is not None:
        homes.append(freecad.getHomePath())
    for home in homes:
        for folder in ((home,) if windows else ()) + (os.path.join(home, "bin"),):
            found += [os.path.join(folder, name) for name in names]
    found += [shutil.which(name) for name in ("python" + tag, "python3")]
    unique = []
    for path in found:
        if path and os.path.isfile(path) and path not in unique:
            unique.append(path)
    return unique


def _pip_of(executable, run=subprocess.run):
    """pip's version when `executable` is a Python of FreeCAD's version with pip, else None.

    Returns
    -------
    (str or None, str)
        pip's version, and the answer (to say why a candidate was refused).
    """
    try:
        done = run([executable, "-m", "pip", "--version"], capture_output=True, text=True,
                   timeout=PROBE_TIMEOUT_S, stdin=subprocess.DEVNULL)
    except (OSError, subprocess.SubprocessError) as error:
        return None, str(error)
    answer = (done.stdout + done.stderr).strip()
    match = re.match(r"pip (\S+) from .*\(python (\d+\.\d+)\)", answer)
    if done.returncode == 0 and match and match.group(2) == _version_tag():
        return match.group(1), answer
    return None, answer.splitlines()[-1] if answer else "exit code %d" % done.returncode


def pip_python(run=subprocess.run):
    """FreeCAD's Python interpreter with pip.

    Returns
    -------
    PipPython

    Raises
    ------
    MissingPackageError
        None found: the message lists the candidates and what they answered.
    """
    refused = []
    for executable in python_candidates():
        version, answer = _pip_of(executable, run)
        if version is not None:
            return PipPython(executable, version)
        refused.append("%s (%s)" % (executable, answer))
    raise MissingPackageError(
        "no Python %s with pip was found to install with (FreeCAD's Python is %s; tried: %s). "
        "Install pip for it (Debian, Ubuntu: 'sudo apt install python3-pip'), or set its path in "
        "Edit > Preferences > Python > Python console's executable, then try again."
        % (_version_tag(), _version_tag(), "; ".join(refused) or "none found"))


def pip_command(name, python, target):
    """The pip call that installs package `name` into `target` (list of str)."""
    command = [python, "-m", "pip", "install", "--disable-pip-version-check",
               "--no-input", "--upgrade", "--target", target]
    if name in _NO_DEPS:
        command.append("--no-deps")
    return command + [name]


def run_pip(name, on_line=None, run=subprocess.run):
    """Run pip to install package `name` for FreeCAD's Python (blocking; a worker thread's job).

    Reads no document and changes nothing in this process: :func:`activate`
    (in the GUI thread) makes the package importable afterwards.

    Parameters
    ----------
    name : str
        A key of :data:`dependencies.PACKAGES`.
    on_line : callable, optional
        ``on_line(text)`` for each line of pip's output, and for the command first.
    run : callable
        ``subprocess.run``'s stand-in for probing interpreters (tests).

    Returns
    -------
    InstallResult
        ``ok`` is pip's verdict; ``importable`` is still False.
    """
    from . import compat
    on_line = on_line or (lambda text: None)
    result = InstallResult(name)
    try:
        python = pip_python(run)
    except MissingPackageError as error:
        result.message = str(error)
        return result
    target = compat.pip_target_folder()
    result.command = pip_command(name, python.executable, target)
    on_line("$ " + " ".join(result.command))
    code = _stream(result.command, result.output, on_line)
    result.ok = code == 0
    if not result.ok:
        result.message = failure_message(result, code)
    return result


def _stream(command, lines, on_line):
    """Run `command`, its output (stdout and stderr) line by line into `lines` and `on_line`;
    returns the exit code (None after :data:`PIP_TIMEOUT_S`)."""
    try:
        os.makedirs(command[command.index("--target") + 1], exist_ok=True)
        process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                   stdin=subprocess.DEVNULL, text=True, bufsize=1)
    except OSError as error:
        lines.append(str(error))
        on_line(str(error))
        return -1
    timer = threading.Timer(PIP_TIMEOUT_S, process.kill)
    timer.start()
    try:
        for line in process.stdout:
            lines.append(line.rstrip())
            on_line(line.rstrip())
        code = process.wait()
    finally:
        killed = not timer.is_alive()
        timer.cancel()
    return None if killed and code != 0 else code


def failure_message(result, code):
    """Why pip failed and what to do (str)."""
    tail = [line for line in result.output if line.strip()][-TAIL_LINES:]
    text = "\n".join(tail)
    if code is None:
        why = "pip took more than %d s and was stopped" % PIP_TIMEOUT_S
    elif re.search(r"No matching distribution|from versions: none", text):
        why = "PyPI has no %s for Python %s on this system" % (result.package, _version_tag())
    elif re.search(r"Failed building wheel|Failed to build|subprocess-exited-with-error", text):
        why = ("PyPI has no ready-made %s for Python %s on this system, and building it from its "
               "source failed (that needs a C++ compiler and the libraries it wraps)"
               % (result.package, _version_tag()))
    elif re.search(r"Temporary failure in name resolution|Network is unreachable|"
                   r"Failed to establish a new connection|ProxyError", text):
        why = "pip could not reach PyPI (no network, or a proxy pip does not know)"
    else:
        why = "pip failed (exit code %s)" % code
    return ("%s was not installed: %s. pip's last lines:\n%s\n\nRun this in a terminal to see "
            "everything, or install %s another way into %s: %s"
            % (result.package, why, text, result.package,
               result.command[result.command.index("--target") + 1],
               " ".join('"%s"' % a if " " in a else a for a in result.command)))


def activate(name):
    """Make package `name`, just installed, importable in this process.

    Puts the target folder on ``sys.path`` (FreeCAD 1.x adds it at start-up
    only when it exists), clears the import caches and the record of the failed
    import, and gives the module to the CadRobot and trimesh modules that hold
    ``<module> = None`` from their import-time attempt (``collision.fcl``,
    ``trimesh.collision.fcl``).

    Returns
    -------
    bool
        It imports now; False means FreeCAD must be restarted.
    """
    from . import compat
    folder = compat.pip_target_folder()
    if os.path.isdir(folder) and folder not in sys.path:
        sys.path.append(folder)
    importlib.invalidate_caches()
    module = dependencies.forget_failure(name)
    if module is None:
        return False
    attribute = dependencies.PACKAGES[name].module.split(".")[0]
    for loaded_name, loaded in list(sys.modules.items()):
        if (loaded_name.startswith(("CadRobotWB.", "trimesh."))
                and getattr(loaded, attribute, False) is None):
            setattr(loaded, attribute, module)
    return True


def finish(result):
    """Make the package of a successful `result` importable and say so (sets ``importable``,
    ``message``); returns `result`."""
    if not result.ok:
        return result
    result.importable = activate(result.package)
    checks = [check for check, name in dependencies.CHECK_PACKAGES.items() if name == result.package]
    if result.importable:
        result.message = ("%s is installed and loaded in this FreeCAD (no restart needed): %s "
                          "checked from now on. Run the check again."
                          % (result.package, " and ".join(checks) + " are" if checks else "it is"))
    else:
        result.message = ("%s is installed, but this FreeCAD cannot load it until it restarts: "
                          "restart FreeCAD, then run the check again." % result.package)
    return result


def install(name, on_line=None):
    """:func:`run_pip`, then :func:`finish`: what the GUI's button does, in one blocking call.

    Returns
    -------
    InstallResult
    """
    return finish(run_pip(name, on_line))
