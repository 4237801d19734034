"""Hypothesis for the fuzz properties of every tier: the profiles and each property's budget.

Two profiles, registered by ``tests/conftest.py`` and chosen with the
environment variable ``CADROBOT_FUZZ``:

* ``ci`` (the default, what ``make test`` runs): derandomized, so every run
  tries the same examples; no example database (nothing written into the
  repository); no deadline (the machine is shared by parallel workers); each
  property runs the number of examples it states with :func:`examples`.
* ``explore`` (``CADROBOT_FUZZ=explore``, on a developer's machine): random
  examples, :data:`EXPLORE_FACTOR` times as many, failures remembered in
  ``$CADROBOT_FUZZ_DB`` (default ``~/.cache/cadrobot/hypothesis/examples``,
  outside the repository) and replayed first next time.

Hypothesis comes from apt (``python3-hypothesis``, installed by
``tools/setup.sh`` like pytest). Where it is missing a fuzz module is
skipped, and under ``make test`` (CADROBOT_REQUIRE_CHECKERS=1) it fails.
"""

import contextlib
import os
import signal

import pytest

#: Hypothesis's own folder (its unicode tables; the explore profile's examples by default):
#: outside the repository, whatever the working directory.
HOME = os.path.join(os.path.expanduser("~"), ".cache", "cadrobot", "hypothesis")

try:
    import hypothesis
    from hypothesis import HealthCheck, settings
    from hypothesis.configuration import set_hypothesis_home_dir
    from hypothesis.database import DirectoryBasedExampleDatabase
except ImportError as exc:   # the fuzz modules call require() first
    hypothesis = None
    HYPOTHESIS_MISSING = ("hypothesis is not importable (%s): `make test` installs it "
                          "(apt-get install python3-hypothesis)" % exc)
else:
    HYPOTHESIS_MISSING = ""

#: The environment variable that chooses the profile.
PROFILE_VARIABLE = "CADROBOT_FUZZ"
#: How many times more examples each property tries under the ``explore`` profile.
EXPLORE_FACTOR = 50


def require():
    """Skip the calling fuzz module when hypothesis is missing (fail it under ``make test``)."""
    if hypothesis is None:
        if os.environ.get("CADROBOT_REQUIRE_CHECKERS"):
            pytest.fail(HYPOTHESIS_MISSING, pytrace=False)
        pytest.skip(HYPOTHESIS_MISSING, allow_module_level=True)


@contextlib.contextmanager
def time_limit(seconds):
    """Raise TimeoutError in the block after `seconds` (SIGALRM): a case that would run
    for hours fails instead of holding up the tier."""
    def stop(signum, frame):
        raise TimeoutError("still running after %d s" % seconds)

    previous = signal.signal(signal.SIGALRM, stop)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def profile_name():
    """``ci`` or ``explore``, from :data:`PROFILE_VARIABLE`."""
    name = os.environ.get(PROFILE_VARIABLE, "ci") or "ci"
    if name not in ("ci", "explore"):
        raise pytest.UsageError("%s=%s: use 'ci' (the default) or 'explore'"
                                % (PROFILE_VARIABLE, name))
    return name


def register_profiles():
    """Register ``ci`` and ``explore`` and load the one :data:`PROFILE_VARIABLE` names."""
    if hypothesis is None:
        return
    # Our properties build documents and files inside each example, so the
    # health checks on slow data generation would only measure the shared machine.
    quiet = [HealthCheck.too_slow, HealthCheck.data_too_large, HealthCheck.filter_too_much]
    settings.register_profile("ci", derandomize=True, database=None, deadline=None,
                              print_blob=False, suppress_health_check=quiet)
    set_hypothesis_home_dir(HOME)
    folder = os.environ.get("CADROBOT_FUZZ_DB", os.path.join(HOME, "examples"))
    settings.register_profile(
        "explore", derandomize=False, deadline=None, print_blob=True, suppress_health_check=quiet,
        database=DirectoryBasedExampleDatabase(folder))
    settings.load_profile(profile_name())


def examples(count, shared_fixtures=False):
    """The settings of a property that tries `count` examples under ``ci``.

    Parameters
    ----------
    count : int
        Examples per run under the ``ci`` profile (its share of the fuzz
        suite's CPU budget); :data:`EXPLORE_FACTOR` times more under ``explore``.
    shared_fixtures : bool
        The property uses function-scoped fixtures (``tmp_path``, ``capfd``)
        on purpose, shared by its examples (each makes its own files).
    """
    factor = EXPLORE_FACTOR if profile_name() == "explore" else 1
    quiet = list(settings.default.suppress_health_check)
    if shared_fixtures:
        quiet.append(HealthCheck.function_scoped_fixture)
    return settings(max_examples=count * factor, suppress_health_check=quiet)
