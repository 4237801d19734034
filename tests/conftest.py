"""Shared by every tier: makes tests/ importable for the checker helpers."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

