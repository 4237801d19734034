"""robodk's robomath (PyPI), the independent reference of the posts' angle conventions.

Under ``make test`` (CADROBOT_REQUIRE_CHECKERS=1) a missing robodk fails the
convention tests instead of skipping them.
"""

import os
import warnings

import pytest

try:
    with warnings.catch_warnings():   # its notice about "from robodk import *": not ours
        warnings.simplefilter("ignore", PendingDeprecationWarning)
        from robodk import robomath
    ROBODK_MISSING = ""
except ImportError as exc:
    robomath = None
    ROBODK_MISSING = (f"robodk is not importable ({exc}); `make test` installs it "
                      "(requirements-freecad.txt), or run: python3 -m pip install robodk")

needs_robodk = pytest.mark.skipif(
    bool(ROBODK_MISSING) and not os.environ.get("CADROBOT_REQUIRE_CHECKERS"),
    reason=ROBODK_MISSING)
