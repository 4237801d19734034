"""rapidchecker (PyPI), the independent RAPID grammar and format checker, for every tier.

Under ``make test`` (CADROBOT_REQUIRE_CHECKERS=1) a missing rapidchecker fails
the tests instead of skipping them: the checker is part of what they prove.
"""

import os
import warnings

import pytest

try:
    with warnings.catch_warnings():   # its pyparsing deprecations: not ours
        warnings.simplefilter("ignore", DeprecationWarning)
        import pyparsing
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


def rapid_errors(text):
    """Every error rapidchecker reports for a module's text (list of str)."""
    assert not RAPIDCHECKER_MISSING, RAPIDCHECKER_MISSING
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
