"""The compiled OPW inverse (robots/kinematics/opw_kernel.py): its arctangent, and the fallback
to numpy when numba is missing or switched off.  (Its answers against the reference
implementation, for every OPW arm: test_opw_inverse_equivalence.py.)"""

import math
import os
import subprocess
import sys

import numpy as np
import pytest

from required import skip_unless_required

from CadRobotWB.robots.catalog import catalog
from CadRobotWB.robots.kinematics import opw, opw_kernel

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

SPECIAL = [0.0, -0.0, 1.0, -1.0, 1e-300, -1e-300, 5e-324, 1e300, -1e300, math.nan]


@pytest.fixture(scope="module")
def compiled():
    if not opw_kernel.available():
        skip_unless_required("numba is not available: %s" % opw_kernel.why_not)
    return opw_kernel


@pytest.fixture(scope="module")
def atan2_many(compiled):
    """The kernel's atan2 over arrays, as the kernel calls it (inlined in a compiled loop)."""
    import numba
    atan2 = compiled._atan2

    @numba.njit(error_model="numpy")
    def many(y, x, out):
        for i in range(x.size):
            out[i] = atan2(y[i], x[i])
    return many


def test_the_compiled_kernel_is_used_where_numba_is_installed(compiled):
    assert compiled.why_not == ""


def test_atan2_special_values_as_libm(atan2_many):
    """Signed zeros, tiny, huge and NaN arguments: as math.atan2 (to 1 ulp, same sign)."""
    y, x = (np.array(v, dtype=float).ravel() for v in np.meshgrid(SPECIAL, SPECIAL))
    ours = np.empty_like(x)
    atan2_many(y, x, ours)
    for yi, xi, got in zip(y, x, ours):
        expected = math.nan if math.isnan(xi) or math.isnan(yi) else math.atan2(yi, xi)
        if math.isnan(expected):
            assert math.isnan(got), (yi, xi, got)
        else:
            assert abs(got - expected) <= 4.5e-16, (yi, xi, got, expected)
            assert math.copysign(1, got) == math.copysign(1, expected), (yi, xi, got)


def test_atan2_accuracy(atan2_many):
    """A million random arguments per scale, over 20 decades: within 5e-16 rad of
    numpy's arctan2 (libm)."""
    rng = np.random.default_rng(7)
    n = 1_000_000
    for scale in (1e-10, 1e-3, 1.0, 1e3, 1e10):
        y = (rng.random(n) - 0.5) * scale
        x = rng.random(n) - 0.5
        ours = np.empty(n)
        atan2_many(y, x, ours)
        worst = float(np.abs(ours - np.arctan2(y, x)).max())
        assert worst <= 5e-16, "scale %g: %.3g rad" % (scale, worst)


def test_without_numba_the_numpy_code_runs():
    """CADROBOT_NUMBA=0 (as without numba): why_not says so and opw.inverse is the
    numpy code, bit for bit."""
    code = (
        "import numpy as np\n"
        "from CadRobotWB.robots.catalog import catalog\n"
        "from CadRobotWB.robots.kinematics import opw, opw_kernel\n"
        "p = catalog.get('ABB_IRB2400').opw\n"
        "T = opw.forward(p, np.random.default_rng(1).uniform(-90, 90, (500, 6)))\n"
        "assert not opw_kernel.available()\n"
        "print(opw_kernel.why_not)\n"
        "a, b = opw.inverse(p, T), opw.inverse_numpy(p, T)\n"
        "assert np.array_equal(a, b, equal_nan=True)\n"
        "import sys; assert 'numba' not in sys.modules\n")
    env = dict(os.environ, CADROBOT_NUMBA="0",
               PYTHONPATH=os.pathsep.join([REPO] + [p for p in sys.path if p]))
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "switched off by CADROBOT_NUMBA=0"


def test_one_pose_and_empty_batches(compiled):
    p = catalog.get("KUKA_KR16").opw
    T = opw.forward(p, [10, -20, 30, 40, 50, 60])
    one = opw.inverse(p, T)
    assert one.shape == (8, 6)
    rows = one[~np.isnan(one).any(axis=1)]
    assert np.abs(opw.wrap_deg(rows - [10, -20, 30, 40, 50, 60])).max(axis=1).min() < 1e-9
    assert opw.inverse(p, np.zeros((0, 4, 4))).shape == (0, 8, 6)
