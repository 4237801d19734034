"""Every Cartesian move sampled at once (robots/motion/move_sampling.py) gives what sampling
the moves one by one gives: the move's path (move_path), the IK at each sample and
the joints followed sample after sample (follow_family) - the straightforward
algorithm, kept as the reference."""

import numpy as np

from CadRobotWB.core import frames as tf
from CadRobotWB.core import program as ir
from CadRobotWB.robots.checks import checks
from CadRobotWB.robots.motion import configuration as cf, move_sampling as ms

from test_configuration import IRB2400, T_R_B, TOOL, program_from_joints, restricted

MARGINS = checks.Margins()


def one_by_one(program, model, moves, margins=MARGINS):
    """The reference: per move, its poses and follow_family from its start joints."""
    T_t_f = tf.invert_transform(np.asarray(program.tool.T_f_t, dtype=float))
    out = []
    for start, group in moves:
        T0 = ms.tcp_pose_in_base(program, start)
        T1 = ms.tcp_pose_in_base(program, group[-1])
        via = ms.tcp_pose_in_base(program, group[0]) if len(group) > 1 else None
        length, angle, poses = ms.move_path(T0, T1, group[-1].move.kind, via)
        n = int(np.clip(max(np.ceil(length / margins.sample_step_mm),
                            np.ceil(angle / margins.sample_step_deg), 1), 1, margins.max_samples))
        fractions = np.linspace(0.0, 1.0, n + 1)
        wanted = int(cf.family(start.joints_deg, model))
        q, status = ms.follow_family(model, poses(fractions) @ T_t_f, wanted, start.joints_deg)
        out.append((length, angle, fractions, q, status, wanted))
    return out


def cartesian_moves(program, model):
    groups = ms.move_groups(cf.solve_program(program, model).entries)
    return [(a[-1], b) for a, b in zip(groups, groups[1:])
            if b[-1].move.kind != ir.JOINT and a[-1].joints_deg is not None]


def assert_same(program, model):
    moves = cartesian_moves(program, model)
    sampled = ms.sample_moves(program, model, moves, MARGINS)
    reference = one_by_one(program, model, moves)
    assert len(sampled) == len(reference) == len(moves) > 0
    for k, (length, angle, fractions, q, status, wanted) in enumerate(reference):
        got = sampled.move(k)
        assert np.isclose(got["length_mm"], length, rtol=0, atol=1e-9)
        assert np.isclose(got["angle_deg"], angle, rtol=0, atol=1e-9)
        np.testing.assert_allclose(got["fractions"], fractions, rtol=0, atol=1e-15)
        assert got["status"] == status and got["family"] == wanted
        np.testing.assert_allclose(got["q_deg"], q, rtol=0, atol=1e-9)
    return sampled


def test_linear_moves_with_wrist_turning_past_180():
    """J4/J6 wind past +-180 within and across moves: the joints continue (no jump of
    360), as the one-by-one following does."""
    joints = [[10, 10, 10, 5, 40, 150], [20, 15, 5, 8, 35, 175],
              [25, 12, 8, 10, 40, -175], [30, 10, 10, 12, 45, -150],
              [35, 5, 15, 15, 50, -130]]
    program = program_from_joints(IRB2400, joints)
    sampled = assert_same(program, IRB2400)
    assert np.nanmax(np.abs(sampled.q_deg[:, 5])) > 200.0      # continued, not wrapped
    within = np.diff(sampled.q_deg, axis=0)
    within[sampled.offsets[1:-1] - 1] = 0.0                     # from one move to the next
    assert np.abs(within).max() < 10.0


def test_circular_moves_and_a_joint_leaving_its_range():
    """J1 limited to +-30: the circle through J1 = -20, 29 and 20 goes the long way round,
    through -30 (test_checks' case), then a linear move."""
    model = restricted(J1=(-30, 30))
    joints = [[-20, 10, 10, 0, 45, 0], [29, 10, 10, 0, 45, 0], [20, 10, 10, 0, 45, 0],
              [10, 20, 0, 10, 40, 10]]
    T_b_r = np.linalg.inv(T_R_B)
    t = [ir.Target("t%d" % i, T_b_r @ model.fk(np.array(q, float)) @ TOOL.T_f_t)
         for i, q in enumerate(joints)]
    moves = [ir.Move(ir.JOINT, t[0], 50, 0, "B"),
             ir.Move(ir.CIRCULAR, t[2], 50, 0, "B", via=t[1]),
             ir.Move(ir.LINEAR, t[3], 50, 0, "B")]
    program = ir.Program("P", "ABB_IRB2400", TOOL, {"B": ir.WorkFrame("B", T_R_B, np.eye(4))},
                         [ir.ProgramPath("A", "A", moves)])
    sampled = assert_same(program, model)
    assert (sampled.status == ms.JOINT_LIMIT).any() and (sampled.status == ms.OK).any()


def test_a_move_through_the_wrist_singularity():
    """theta5 passes through 0 mid-move (a sample at the middle has it within rounding of
    0, where theta4 is set to 0 and theta6 takes the rest): the same joints as the
    reference's."""
    joints = [[0, 10, 10, 30, 20, 0], [0, 10, 10, 30, -20, 0]]
    program = program_from_joints(IRB2400, joints)
    assert_same(program, IRB2400)


def test_no_cartesian_move():
    program = program_from_joints(IRB2400, [[0, 10, 10, 0, 30, 0]])
    sampled = ms.sample_moves(program, IRB2400, [], MARGINS)
    assert len(sampled) == 0 and sampled.q_deg.shape == (0, 6)
    assert checks.check_program(program, IRB2400).ok
