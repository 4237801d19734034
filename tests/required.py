"""Inputs the tests need: skipped when missing on a developer's machine, a
failure under ``make test`` (CADROBOT_REQUIRE_CHECKERS=1), where set-up provides them."""

import os

import pytest


def skip_unless_required(reason):
    if os.environ.get("CADROBOT_REQUIRE_CHECKERS"):
        pytest.fail(reason)
    pytest.skip(reason)


#: The makers' robot descriptions the tests compare against (``tests/data/robots``: every
#: URDF, collision meshes for the few arms a test imports; sources and licences in its
#: SOURCES.md and README.md).
ROBOT_DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "robots")
