"""Inputs the tests need: skipped when missing on a developer's machine, a
failure under ``make test`` (CADROBOT_REQUIRE_CHECKERS=1), where set-up provides them."""

import os

import pytest


def skip_unless_required(reason):
    if os.environ.get("CADROBOT_REQUIRE_CHECKERS"):
        pytest.fail(reason)
    pytest.skip(reason)


#: The robot descriptions of the data folder (``../shared/data/robots`` beside the repository).
ROBOT_DATA = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                          "shared", "data", "robots")

#: Tests that read ROBOT_DATA: skipped without it on a developer's machine; under
#: ``make test`` they run, so a missing folder fails them instead of hiding them.
needs_robot_data = pytest.mark.skipif(
    not os.path.isdir(ROBOT_DATA) and not os.environ.get("CADROBOT_REQUIRE_CHECKERS"),
    reason="no ../shared/data/robots beside the repository")
