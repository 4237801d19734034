"""The IRB 2400's parallel J2/J3 linkage: limits and speeds of the controller's J3 = q2 + q3.

ROS-Industrial's abb_driver (parameter ``J23_coupled``, true for the IRB 2400)
converts controller J3 = serial J3 + serial J2, and ABB's data sheet ranges
(axis 2 -100/+110, axis 3 -60/+65 deg) are the controller's.  Expected values
are worked by hand from that rule, never from the functions under test; the
old (wrong) serial check ``-60 <= q3 <= 65`` is written out where a case shows
the difference.
"""

import numpy as np
import pytest

from CadRobotWB.core import program as ir
from CadRobotWB.robots.catalog import catalog
from CadRobotWB.robots.checks import checks
from CadRobotWB.robots.kinematics import models
from CadRobotWB.robots.motion import configuration as cf, timing

from test_configuration import IRB2400, program_from_joints

J3_LABEL = "J3 (= q2 + q3 on this parallel-arm robot)"


def serial_q3_inside(q):
    """The old check: the catalog's J3 limits applied to the serial q3."""
    return -60.0 <= q[2] <= 65.0


def one_target(q, q_start=None):
    """A program with one joint move to fk(q); solved from q_start (default q)."""
    program = program_from_joints(IRB2400, [q])
    solution = cf.solve_program(program, IRB2400,
                                q_start_deg=q if q_start is None else q_start, assign=False)
    return program, solution


def test_which_arms_count_j3_against_the_base():
    """ABB's parallel arms (abb_driver J23_coupled) and every FANUC arm (fanuc_driver
    J23_factor = 1), as robots/catalog/makers.py has them from the drivers' sources."""
    coupled = {name: catalog.get(name).j23_factor for name in catalog.names()
               if catalog.get(name).j23_coupled}
    assert [n for n in catalog.hand_written_names() if n in coupled] == ["ABB_IRB2400"]
    assert {n: k for n, k in coupled.items() if n.startswith("ABB")} == {
        "ABB_IRB2400": 1, "ABB_IRB2400_12_155": 1, "ABB_IRB4400L_30_243": 1}
    fanuc = [n for n in catalog.names() if n.startswith("FANUC")]
    assert len(fanuc) == 33
    # The M-430iA counts J3 the other way (+1); the CRX as the others (makers._FANUC_CRX).
    assert {n: coupled.get(n) for n in fanuc if coupled.get(n) != -1} == {"FANUC_M430IA2P": 1}
    assert not any(n.split("_")[0] in ("KUKA", "MOTOMAN", "STAUBLI", "UR", "UR10", "KAWASAKI")
                   for n in coupled)
    assert not catalog.get("ABB_IRB2600").j23_coupled       # serial arms
    assert not catalog.get("ABB_IRB4600").j23_coupled
    spec = catalog.get("ABB_IRB2400")
    assert (spec.joint_min_deg[2], spec.joint_max_deg[2]) == (-60, 65)
    assert "J23_coupled" in spec.notes and "probably" not in spec.notes
    assert not any("[2]" in field for field in spec.uncertain)


def test_fanuc_j3_is_counted_from_the_horizontal():
    """fanuc_driver: J3_controller = q3 - q2 (URDF J3 turns about -Y, J2 about +Y)."""
    m20 = models.model("FANUC_M20IA")
    q = np.array([10, 40, 30, 50, 60, 70.0])
    np.testing.assert_array_equal(m20.controller_joints(q), [10, 40, -10, 50, 60, 70])
    np.testing.assert_array_equal(m20.model_joints([10, 40, -10, 50, 60, 70]), q)
    assert "from the horizontal" in m20.joint_label(2)
    assert m20.within_limits([0, 0, 272.0, 0, 0, 0]) and not m20.within_limits([0, -10, 268, 0, 0, 0])


def test_controller_joints_by_hand():
    q = np.array([10, 40, 30, 50, 60, 70.0])
    np.testing.assert_array_equal(IRB2400.controller_joints(q), [10, 40, 70, 50, 60, 70])
    np.testing.assert_array_equal(IRB2400.model_joints([10, 40, 70, 50, 60, 70]), q)
    assert q[2] == 30.0                                          # the input is not changed
    # Vectorised over any leading shape; NaN rows stay NaN.
    Q = np.tile(q, (3, 8, 1))
    Q[1, 2] = np.nan
    C = IRB2400.controller_joints(Q)
    assert C.shape == (3, 8, 6)
    np.testing.assert_array_equal(C[2, 5], [10, 40, 70, 50, 60, 70])
    assert np.isnan(C[1, 2]).all()
    np.testing.assert_allclose(IRB2400.model_joints(C), Q)
    # Serial robots: the same values.
    for name in ("ABB_IRB4600", "KUKA_KR16", "UR5E"):
        np.testing.assert_array_equal(models.model(name).controller_joints(q), q)
        np.testing.assert_array_equal(models.model(name).model_joints(q), q)


@pytest.mark.parametrize("q2, q3, j3_ctrl, excess, old_inside", [
    (40, 30, 70, 5, True),         # above +65: the old check let it through
    (-40, 30, -10, 0, True),       # inside either way
    (60, -50, 10, 0, True),        # inside either way
    (-80, -50, -130, 70, True),    # below -60 by 70: the old check let it through
    (80, -100, -20, 0, False),     # inside: the old check refused it (q3 < -60)
])
def test_limit_excess_of_the_controller_j3(q2, q3, j3_ctrl, excess, old_inside):
    q = np.array([0, q2, q3, 0, 30, 0.0])
    assert IRB2400.controller_joints(q)[2] == j3_ctrl
    np.testing.assert_array_equal(IRB2400.limit_excess(q), [0, 0, excess, 0, 0, 0])
    assert IRB2400.within_limits(q) == (excess == 0)
    assert serial_q3_inside(q) == old_inside
    assert cf.fits_limits(q, IRB2400) == (excess == 0)     # no turn of 360 deg helps J3


def test_unwrapping_j4_j6_is_unchanged_and_j2_j3_stay():
    """J4 (+-200) and J6 (+-400) take the turn nearest the reference; J2 and J3, whose
    ranges are narrower than 360 deg, keep their values."""
    q = np.array([0, 40, 20, 170, 30, -170.0])                   # J3 = 60: inside
    ref = np.array([0, 0, 0, -170, 0, 170.0])
    np.testing.assert_allclose(cf.unwrap_joints(q, ref, IRB2400), [0, 40, 20, -190, 30, 190])
    # Out of range: J3 = 70 stays (70 - 360 = -290 is farther out).
    np.testing.assert_allclose(cf.unwrap_joints([0, 40, 30, 0, 30, 0], np.zeros(6), IRB2400),
                               [0, 40, 30, 0, 30, 0])


def test_target_beyond_the_coupled_j3_limit_is_a_joint_limit_finding():
    """fk(0, 40, 30, 0, 30, 0): J3 = 70 deg; the pose's other IK rows are farther out
    (J2 156.7 deg, or J1 180 with J2 -144 or J3 -219 deg): no configuration fits."""
    program, solution = one_target([0, 40, 30, 0, 30, 0])
    entry = solution.entries[0]
    assert entry.status == cf.JOINT_LIMIT and entry.joints_deg is None
    report = checks.check_program(program, IRB2400, solution)
    limits = [f for f in report.findings if f.kind == checks.JOINT_LIMIT]
    assert len(limits) == 1
    f = limits[0]
    assert (f.joint, f.value, f.limit, f.severity) == (3, pytest.approx(70.0), 65.0, "error")
    assert "%s at 70.0 deg, 5.0 deg beyond its limit of +65 deg" % J3_LABEL in f.message


@pytest.mark.parametrize("q2, q3", [(-40, 30), (60, -50), (80, -100)])
def test_targets_inside_the_coupled_limit_keep_their_joints(q2, q3):
    q = [0, q2, q3, 0, 30, 0]
    program, solution = one_target(q)
    entry = solution.entries[0]
    assert entry.status == cf.OK
    np.testing.assert_allclose(entry.joints_deg, q, atol=1e-6)
    assert checks.check_program(program, IRB2400, solution).ok


def test_solver_does_not_take_a_row_beyond_the_coupled_limit():
    """fk(0, -80, -50, 0, 30, 0): that row (reaching back over the shoulder) has J3 = -130
    (the old check passed it: q3 = -50); the rows turned by J1 = 180, reaching the pose in
    front, are within the limits and are taken."""
    program, solution = one_target([0, -80, -50, 0, 30, 0], q_start=np.zeros(6))
    entry = solution.entries[0]
    assert entry.status == cf.OK
    q = entry.joints_deg
    assert abs(q[0]) == pytest.approx(180.0, abs=1e-6)
    assert -60.0 <= q[1] + q[2] <= 65.0 and -100 <= q[1] <= 110
    assert cf.family([0, -80, -50, 0, 30, 0], IRB2400) & cf.SHOULDER_BACK
    assert not entry.family & cf.SHOULDER_BACK
    assert checks.check_program(program, IRB2400, solution).ok


def test_solver_never_chooses_joints_beyond_the_coupled_limit():
    """Random poses, each reached by a joint move: every chosen vector keeps -60 <= q2 + q3
    <= 65 and J2 within -100..110, and some poses are refused only because of the coupling."""
    rng = np.random.default_rng(23)
    joints = rng.uniform([-170, -100, -60, -190, -110, -190], [170, 110, 65, 190, 110, 190],
                         (120, 6))
    program = program_from_joints(IRB2400, joints, kinds=[ir.JOINT] * len(joints))
    solution = cf.solve_program(program, IRB2400, assign=False)
    chosen = np.array([e.joints_deg for e in solution.entries if e.joints_deg is not None])
    assert len(chosen) > 60
    j3 = chosen[:, 1] + chosen[:, 2]
    assert (j3 >= -60).all() and (j3 <= 65).all()
    assert (chosen[:, 1] >= -100).all() and (chosen[:, 1] <= 110).all()
    refused = [e for e in solution.entries if e.status == cf.JOINT_LIMIT]
    assert refused and all(serial_q3_inside(q) for q in joints[[e.move_index for e in refused]])


def test_joint_move_time_uses_the_controller_j3():
    """(0, 0, -30) -> (0, 30, 0) in (J1, q2, q3): J2 and q3 turn 30 deg, the controller's
    J3 60 deg (-30 -> +30).  At 150 deg/s and 600 deg/s^2: 0.25 s up (18.75 deg) and down,
    22.5 deg cruise (0.15 s): 0.65 s, limited by J3 (30 deg alone: 2 sqrt(30 / 600) = 0.447 s)."""
    q0 = [0, 0, -30, 0, 45, 0]
    program = program_from_joints(IRB2400, [[0, 30, 0, 0, 45, 0]])
    solution = cf.solve_program(program, IRB2400, q_start_deg=q0)
    np.testing.assert_allclose(solution.entries[0].joints_deg, [0, 30, 0, 0, 45, 0], atol=1e-6)
    move = timing.cycle_time(program, IRB2400, solution)["moves"][0]
    assert (move["time_s"], move["limited_by"]) == (pytest.approx(0.65), "J3")


def test_joint_speed_check_uses_q2_plus_q3():
    """A linear move from fk(0, -50, 10, 0, 60, 0) to fk(0, -40, 20, 0, 60, 0) at 2500 mm/s:
    J2 and q3 both turn the same way, each below 150 deg/s, but their sum - the controller's
    J3 - faster than its 150 deg/s."""
    program = program_from_joints(IRB2400, [[0, -50, 10, 0, 60, 0], [0, -40, 20, 0, 60, 0]])
    for move in program.paths[0].moves:
        move.speed_mm_s = 2500.0
    solution = cf.solve_program(program, IRB2400, q_start_deg=[0, -50, 10, 0, 60, 0])
    assert solution.ok
    samples = checks.move_samples(program, IRB2400, solution.entries[0], solution.entries[1:],
                                  checks.Margins())
    q = samples["q_deg"]
    dt = samples["time_s"] / (len(q) - 1)
    serial = np.abs(np.diff(q, axis=0)).max(axis=0) / dt
    j3 = np.abs(np.diff(q[:, 1] + q[:, 2])).max() / dt
    assert (serial < np.array(IRB2400.spec.joint_speed_deg_s)).all()    # old check: silent
    assert j3 > 150.0
    report = checks.check_program(program, IRB2400, solution)
    speed = [f for f in report.findings if f.kind == checks.JOINT_SPEED]
    assert len(speed) == 1
    assert (speed[0].joint, speed[0].value, speed[0].limit) == (3, pytest.approx(j3), 150.0)
    assert "%s would have to turn at" % J3_LABEL in speed[0].message
