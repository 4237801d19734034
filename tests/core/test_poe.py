"""The product-of-exponentials parameters reproduce the URDF chain (robots/kinematics/poe.py)."""

import os

import numpy as np
import pytest

from CadRobotWB.robots.kinematics import poe
from CadRobotWB.robots.urdf import urdf

ROBOTS = os.path.join(os.path.dirname(__file__), os.pardir, "data", "robots")
#: Arms neither OPW nor UR (offset and oblique wrists, and OPW arms whose file rounds pi/2).
ARMS = ["abb_crb15000_5_95", "fanuc_crx10ial", "fanuc_m430ia2p", "kuka_kr10_r1100_3",
        "motoman_hc10", "motoman_mpx3500"]


def _chain(name):
    return urdf.serial_chain(urdf.read_urdf(os.path.join(ROBOTS, name, "robot.urdf")))


@pytest.mark.parametrize("name", ARMS)
def test_fk_equals_the_urdf_chain(name):
    chain = _chain(name)
    params = poe.from_chain(chain)
    q = np.random.default_rng(7).uniform(-np.pi, np.pi, (200, 6))
    T_urdf = urdf.chain_fk(chain, q)
    T_poe = poe.fk(params, q)
    assert np.abs(T_poe[:, :3, 3] - T_urdf[:, :3, 3]).max() < 1e-9
    assert np.abs(T_poe[:, :3, :3] - T_urdf[:, :3, :3]).max() < 1e-12


def test_crx_at_zero_by_hand():
    """The CRX-10iA/L at zero: axes 2 and 3 parallel, 710 mm apart (its published upper arm)."""
    params = poe.from_chain(_chain("fanuc_crx10ial"))
    assert abs(abs(params.H[1] @ params.H[2]) - 1) < 1e-12
    lateral = params.P[2] - (params.P[2] @ params.H[1]) * params.H[1]
    assert np.linalg.norm(lateral) == pytest.approx(710.0, abs=1e-6)
