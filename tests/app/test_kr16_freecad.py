"""KUKA_KR16 against FreeCAD's own Robot workbench (runs inside FreeCADCmd).

A ``Robot::RobotObject`` loaded with FreeCAD's ``Mod/Robot/Lib/Kuka/kr_16.csv``
is driven through its ``Axis1..Axis6`` properties and its ``Tcp`` read back
(``Robot6Axis``: a KDL chain, see ``robots/dh.py``).  Our ``fk`` must give the
same flange pose, and our closed-form ``ik`` of FreeCAD's Tcp must contain
the axis values FreeCAD was given.
"""

import os

import numpy as np
import pytest

from required import skip_unless_required

import FreeCAD
from CadRobotWB.robots import dh, models

Robot = pytest.importorskip("Robot")  # FreeCAD's Robot workbench (App part)

KR16_CSV = os.path.join(FreeCAD.getResourceDir(), "Mod", "Robot", "Lib", "Kuka", "kr_16.csv")


def matrix(placement):
    """FreeCAD.Placement -> (4, 4) numpy array (mm)."""
    return np.array(placement.toMatrix().A, dtype=float).reshape(4, 4)


@pytest.fixture
def freecad_kr16(doc):
    if not os.path.exists(KR16_CSV):
        skip_unless_required("FreeCAD's kr_16.csv not found at %s" % KR16_CSV)
    robot = doc.addObject("Robot::RobotObject", "KR16")
    robot.RobotKinematicFile = KR16_CSV
    doc.recompute()
    return robot


def freecad_tcp(robot, q_deg):
    for axis, value in enumerate(q_deg, start=1):
        setattr(robot, "Axis%d" % axis, float(value))
    return matrix(robot.Tcp)


def test_catalog_rows_are_freecads_file():
    with open(KR16_CSV) as handle:
        assert dh.rows_from_csv(handle.read()) == models.model("KUKA_KR16").spec.dh


def test_fk_equals_freecad_tcp(freecad_kr16):
    kr16 = models.model("KUKA_KR16")
    rng = np.random.default_rng(2024)
    inside = rng.uniform(kr16.joint_min_deg, kr16.joint_max_deg, (300, 6))
    anywhere = rng.uniform(-360.0, 360.0, (100, 6))
    q = np.vstack([np.zeros(6), inside, anywhere])
    T_freecad = np.array([freecad_tcp(freecad_kr16, qi) for qi in q])
    T_ours = kr16.fk(q)
    position_error = np.abs(T_ours[:, :3, 3] - T_freecad[:, :3, 3]).max()
    rotation_error = np.abs(T_ours[:, :3, :3] - T_freecad[:, :3, :3]).max()
    print("KR16 fk vs FreeCAD Tcp over %d poses: max %.3g mm, max %.3g in the rotation matrix"
          % (len(q), position_error, rotation_error))
    assert position_error < 1e-6
    assert rotation_error < 1e-9


def test_ik_of_freecad_tcp_contains_the_axes(freecad_kr16):
    kr16 = models.model("KUKA_KR16")
    q = np.random.default_rng(7).uniform(kr16.joint_min_deg, kr16.joint_max_deg, (100, 6))
    q = np.clip(q, -180.0, 180.0)  # ik wraps into (-180, 180]
    T_freecad = np.array([freecad_tcp(freecad_kr16, qi) for qi in q])
    solutions = kr16.ik(T_freecad)
    distance = np.abs((solutions - q[:, None, :] + 180.0) % 360.0 - 180.0).max(axis=2)
    assert (np.nanmin(distance, axis=1) < 1e-6).all()
