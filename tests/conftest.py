"""Shared by every tier: makes tests/ importable for the checker helpers."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


import fuzzing  # noqa: E402  (needs the path above)

fuzzing.register_profiles()
