"""KUKA_KR16 against FreeCAD's own Robot workbench (runs inside FreeCADCmd).

A ``Robot::RobotObject`` is driven through its ``Axis1..Axis6`` properties and
its ``Tcp`` read back (``Robot6Axis``: a KDL chain, see ``robots/kinematics/dh.py``).  It
is loaded with FreeCAD's ``Mod/Robot/Lib/Kuka/kr_16.csv`` where FreeCAD has the
file (0.20).  Debian's FreeCAD 1.x packages leave the KUKA files out; there the
same six rows (``test_catalog_rows_are_freecads_file`` proves them equal on 0.20)
are written to a file of our own, so FreeCAD's KDL still computes the poses.
Either way FreeCAD's Tcp must equal the poses FreeCAD 0.20.2 recorded in
``tests/core/data/freecad_kr16_tcp.csv`` and our ``fk``; our closed-form ``ik``
of FreeCAD's Tcp must contain the axis values FreeCAD was given.

``record(path)`` wrote that file (``tools/freecad_run.py --call
test_kr16_freecad:record tests/core/data/freecad_kr16_tcp.csv`` on 0.20.2 with
``tests/app`` on ``PYTHONPATH``).
"""

import os
import sys

import numpy as np
import pytest

from required import skip_unless_required

import FreeCAD
from CadRobotWB.robots.kinematics import dh, models

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "core"))
from kr16_recorded import RECORDED_CSV, recorded_kr16_tcp  # noqa: E402

KR16_CSV = os.path.join(FreeCAD.getResourceDir(), "Mod", "Robot", "Lib", "Kuka", "kr_16.csv")


def matrix(placement):
    """FreeCAD.Placement -> (4, 4) numpy array (mm)."""
    return np.array(placement.toMatrix().A, dtype=float).reshape(4, 4)


def csv_of_rows(rows):
    """FreeCAD Robot workbench CSV text of six DHRow (the inverse of ``dh.rows_from_csv``)."""
    lines = ["a,alpha,d,theta,rotDir,maxAngle,minAngle,AxisVelocity"]
    lines += ["%r,%r,%r,%r,%d,%r,%r,%r" % (row.a, row.alpha, row.d, row.theta, row.rot_dir,
                                          row.max_deg, row.min_deg, row.speed_deg_s) for row in rows]
    return "\n".join(lines) + "\n"


def kr16_robot_object(doc, csv_dir):
    """A Robot::RobotObject with kr_16's rows: FreeCAD's file, or the catalog's rows."""
    try:
        import Robot  # noqa: F401  (registers Robot::RobotObject)
    except ImportError:
        skip_unless_required("FreeCAD's Robot workbench does not import")
    path = KR16_CSV
    if not os.path.exists(path):
        path = os.path.join(str(csv_dir), "kr_16.csv")
        with open(path, "w") as handle:
            handle.write(csv_of_rows(models.model("KUKA_KR16").spec.dh))
    robot = doc.addObject("Robot::RobotObject", "KR16")
    robot.RobotKinematicFile = path
    doc.recompute()
    return robot


@pytest.fixture
def freecad_kr16(doc, tmp_path):
    return kr16_robot_object(doc, tmp_path)


def freecad_tcp(robot, q_deg):
    for axis, value in enumerate(q_deg, start=1):
        setattr(robot, "Axis%d" % axis, float(value))
    return matrix(robot.Tcp)


def test_catalog_rows_are_freecads_file():
    if not os.path.exists(KR16_CSV):
        pytest.skip("FreeCAD %s has no Mod/Robot/Lib/Kuka/kr_16.csv (Debian's 1.x packages leave "
                    "the KUKA files out); the rows were checked on 0.20 and FreeCAD's KDL checks "
                    "them below against the Tcp 0.20 recorded" % ".".join(FreeCAD.Version()[:3]))
    with open(KR16_CSV) as handle:
        assert dh.rows_from_csv(handle.read()) == models.model("KUKA_KR16").spec.dh


def test_freecad_tcp_equals_recorded_and_our_fk(freecad_kr16):
    q, T_recorded = recorded_kr16_tcp()
    T_freecad = np.array([freecad_tcp(freecad_kr16, qi) for qi in q])
    T_ours = models.model("KUKA_KR16").fk(q)
    for name, T in (("recorded", T_recorded), ("ours", T_ours)):
        position_error = np.abs(T[:, :3, 3] - T_freecad[:, :3, 3]).max()
        rotation_error = np.abs(T[:, :3, :3] - T_freecad[:, :3, :3]).max()
        print("KR16 FreeCAD %s Tcp vs %s over %d poses: max %.3g mm, max %.3g in the rotation"
              % (".".join(FreeCAD.Version()[:3]), name, len(q), position_error, rotation_error))
        assert position_error < 1e-6, name
        assert rotation_error < 1e-9, name


def test_ik_of_freecad_tcp_contains_the_axes(freecad_kr16):
    kr16 = models.model("KUKA_KR16")
    q = np.random.default_rng(7).uniform(kr16.joint_min_deg, kr16.joint_max_deg, (100, 6))
    q = np.clip(q, -180.0, 180.0)  # ik wraps into (-180, 180]
    T_freecad = np.array([freecad_tcp(freecad_kr16, qi) for qi in q])
    solutions = kr16.ik(T_freecad)
    distance = np.abs((solutions - q[:, None, :] + 180.0) % 360.0 - 180.0).max(axis=2)
    assert (np.nanmin(distance, axis=1) < 1e-6).all()


def record(argv):
    """Write FreeCAD's Tcp of 401 axis sets to argv[0] (the file the tests compare with)."""
    doc = FreeCAD.newDocument("KR16Record")
    robot = kr16_robot_object(doc, os.path.dirname(os.path.abspath(argv[0])))
    kr16 = models.model("KUKA_KR16")
    rng = np.random.default_rng(2024)
    inside = rng.uniform(kr16.joint_min_deg, kr16.joint_max_deg, (300, 6))
    anywhere = rng.uniform(-360.0, 360.0, (100, 6))
    q = np.vstack([np.zeros(6), inside, anywhere])
    with open(argv[0], "w") as handle:
        handle.write(
            "# KUKA KR 16 flange poses from FreeCAD %s's Robot workbench: a Robot::RobotObject\n"
            "# loaded with Mod/Robot/Lib/Kuka/kr_16.csv, driven through Axis1..Axis6 (deg), its\n"
            "# Tcp read back (tests/app/test_kr16_freecad.py: record). Kept because Debian's\n"
            "# FreeCAD 1.x packages leave the KUKA files out. Columns: q1..q6 (deg), then the top\n"
            "# three rows of the 4x4 Tcp matrix (mm), row by row.\n"
            % ".".join(FreeCAD.Version()[:3]))
        handle.write("q1,q2,q3,q4,q5,q6,r11,r12,r13,x,r21,r22,r23,y,r31,r32,r33,z\n")
        for qi in q:
            T = freecad_tcp(robot, qi)
            handle.write(",".join(repr(float(v)) for v in list(qi) + list(T[:3].ravel())) + "\n")
    return 0
