"""Import first in a benchmark: one core, one thread, and the repository on sys.path.

Thread pools read their size when numpy loads, so this must run before numpy
is imported. (bench_ik.py does more: it pins every thread and reports the CPU.)
"""

import os
import sys

for _name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_name] = "1"
try:
    os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})
except (AttributeError, OSError):
    pass

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
