"""rapidchecker (PyPI), the independent RAPID grammar and format checker, for every tier.

Under ``make test`` (CADROBOT_REQUIRE_CHECKERS=1) a missing rapidchecker fails
the tests instead of skipping them: the checker is part of what they prove.

Inside FreeCAD, Debian's older pyparsing (3.0) comes first on ``sys.path`` and
rapidchecker needs 3.2; there the checker runs as its own command, with its
package folder first on PYTHONPATH.
"""

import os
import subprocess
import sys
import tempfile
import warnings

import pytest

try:
    with warnings.catch_warnings():   # its pyparsing deprecations: not ours
        warnings.simplefilter("ignore", DeprecationWarning)
        import pyparsing
        import rapidchecker
        from rapidchecker.check import check_format
        from rapidchecker.whitespace_checks import check_whitespace
    RAPIDCHECKER_MISSING = ""
except ImportError as exc:
    RAPIDCHECKER_MISSING = (
        f"rapidchecker is not importable ({exc}); `make test` installs it, "
        "or run: python3 -m pip install rapidchecker")

needs_rapidchecker = pytest.mark.skipif(
    bool(RAPIDCHECKER_MISSING) and not os.environ.get("CADROBOT_REQUIRE_CHECKERS"),
    reason=RAPIDCHECKER_MISSING)


def _in_process():
    major, minor = (int(x) for x in pyparsing.__version__.split(".")[:2])
    return (major, minor) >= (3, 2)


def _command_errors(text):
    """Run ``python -m rapidchecker`` on the text; its report lines if it fails."""
    packages = os.path.dirname(os.path.dirname(os.path.abspath(rapidchecker.__file__)))
    env = dict(os.environ, PYTHONPATH=packages)
    python = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "module.mod")
        with open(path, "w") as handle:
            handle.write(text)
        run = subprocess.run([python, "-m", "rapidchecker", path], env=env,
                             capture_output=True, text=True, timeout=120)
    if run.returncode == 0:
        return []
    return [line for line in (run.stdout + run.stderr).splitlines() if line.strip()] or [
        "rapidchecker exited %d" % run.returncode]


def rapid_errors(text):
    """Every error rapidchecker reports for a module's text (list of str)."""
    assert not RAPIDCHECKER_MISSING, RAPIDCHECKER_MISSING
    if not _in_process():
        return _command_errors(text)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)
            errors = list(check_format(text))
    except pyparsing.ParseBaseException as exc:   # not all are caught inside
        errors = [exc]
    errors += check_whitespace(text)
    return [str(e) for e in errors]


def assert_rapid_ok(text):
    errors = rapid_errors(text)
    assert not errors, "rapidchecker: " + "; ".join(errors)
