"""Configurations along a program (robots/motion/configuration.py).

Expected values come from the robots' geometry worked by hand (IRB 2400 zero
pose: axis 2 at x = 100 mm, wrist centre at (855, 0, 1455)), from the forward
kinematics (wrist centre = flange - c4 * flange z), or from the vendors'
published definitions (ABB confdata table, KUKA Status/Turn bits, Yaskawa
RCONF fields) - never from the functions under test.
"""

import dataclasses

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from CadRobotWB.core import program as ir
from CadRobotWB.errors import InputError
from CadRobotWB.robots.catalog import catalog
from CadRobotWB.robots.checks import links
from CadRobotWB.robots.kinematics import models
from CadRobotWB.robots.motion import configuration as cf
from robot_sample import sample_names

IRB2400 = models.model("ABB_IRB2400")
OPW_ROBOTS = [n for n in sample_names() if catalog.get(n).opw is not None]


def pose(rotvec_deg=(0, 0, 0), position=(0, 0, 0)):
    T = np.eye(4)
    T[:3, :3] = Rotation.from_rotvec(rotvec_deg, degrees=True).as_matrix()
    T[:3, 3] = position
    return T


def restricted(name="ABB_IRB2400", **limits):
    """The model of a catalog robot with some joint limits replaced."""
    spec = catalog.get(name)
    low, high = list(spec.joint_min_deg), list(spec.joint_max_deg)
    for key, (lo, hi) in limits.items():
        j = int(key[1:]) - 1
        low[j], high[j] = lo, hi
    return models.OPWModel(dataclasses.replace(spec, name=name + "_test",
                                               joint_min_deg=tuple(low),
                                               joint_max_deg=tuple(high)))


TOOL = ir.ToolData("Tool", pose(position=(0, 0, 100)))
T_R_B = pose((0, 0, 30), (600, -100, 300))


def program_from_joints(model, joints, kinds=None, robot="ABB_IRB2400", tool=TOOL, T_r_b=T_R_B,
                        paths=None):
    """Targets whose flange poses are fk(joints): every target reachable by construction.

    ``paths``: list of the number of moves of each path (default: one path).
    """
    kinds = kinds or [ir.JOINT] + [ir.LINEAR] * (len(joints) - 1)
    T_b_r = np.linalg.inv(T_r_b)
    moves = []
    for i, (q, kind) in enumerate(zip(joints, kinds)):
        T_b_t = T_b_r @ model.fk(np.asarray(q, float)) @ tool.T_f_t
        moves.append(ir.Move(kind, ir.Target("t%d" % (i + 1), T_b_t), 50.0, 0.0, "B",
                             role=ir.ROLE_APPROACH if kind == ir.JOINT else ir.ROLE_PATH))
    sizes = paths or [len(moves)]
    program_paths, start = [], 0
    for k, size in enumerate(sizes):
        program_paths.append(ir.ProgramPath("P%d" % k, "Path %d" % k, moves[start:start + size]))
        start += size
    return ir.Program("Prog", robot, tool, {"B": ir.WorkFrame("B", T_r_b, np.eye(4))},
                      program_paths)


def wrist_centre(model, q):
    """The wrist centre in the OPW model's own base frame (a URDF arm's differs from {R})."""
    T = links.link_frames(model, np.asarray(q, float))[..., 4, :, :]
    if model.spec.T_root_base is not None:
        T = np.linalg.inv(np.array(model.spec.T_root_base)) @ T
    return T[..., :3, 3]


def model_angles(spec, q):
    p = spec.opw
    return (np.radians(np.asarray(q, float)) * np.asarray(p.signs, float)
            - np.radians(np.asarray(p.offsets_deg, float)))


# --- families -------------------------------------------------------------------------------

@pytest.mark.parametrize("name", OPW_ROBOTS)
def test_family_of_every_ik_row_follows_the_branch_structure(name):
    """opw.inverse rows: 0-3 shoulder front/front/back/back with the two elbows, 4-7 flipped."""
    robot = models.model(name)
    rng = np.random.default_rng(5)
    q = rng.uniform(np.maximum(robot.joint_min_deg, -180), np.minimum(robot.joint_max_deg, 180),
                    (400, 6))
    Q = robot.ik(robot.fk(q))
    fam = cf.family(Q, robot)
    rows = np.arange(8)
    down = robot.spec.opw.c1 < 0              # the model's z points down the arm
    expected = 4 * (rows % 4 >= 2) + 2 * (rows % 2 != down) + ((rows >= 4) != down)
    present = ~np.isnan(Q).any(axis=2)
    assert present.sum() > 1000
    np.testing.assert_array_equal(fam[present], np.broadcast_to(expected, fam.shape)[present])
    assert (fam[~present] == -1).all()


def test_ur_families_follow_its_branch_order():
    """ur.inverse rows are 4*shoulder + 2*wrist + elbow; families 4*shoulder + 2*elbow + wrist."""
    robot = models.model("UR5E")
    rng = np.random.default_rng(6)
    Q = robot.ik(robot.fk(rng.uniform(-170, 170, (300, 6))))
    fam = cf.family(Q, robot)
    present = ~np.isnan(Q).any(axis=2)
    expected = np.array([0, 2, 1, 3, 4, 6, 5, 7])
    np.testing.assert_array_equal(fam[present], np.broadcast_to(expected, fam.shape)[present])


@pytest.mark.parametrize("name", OPW_ROBOTS)
def test_shoulder_bit_is_the_wrist_centre_behind_axis_1(name):
    """x of the wrist centre (from FK) in the frame turned with axis 1 (model angle theta1)."""
    robot = models.model(name)
    rng = np.random.default_rng(7)
    q = rng.uniform(np.maximum(robot.joint_min_deg, -180), np.minimum(robot.joint_max_deg, 180),
                    (300, 6))
    c = wrist_centre(robot, q)
    theta1 = model_angles(robot.spec, q)[:, 0]
    x_a1 = np.cos(theta1) * c[:, 0] + np.sin(theta1) * c[:, 1]
    geometry = cf.arm_geometry(q, robot)
    np.testing.assert_allclose(geometry.shoulder_mm, x_a1, atol=1e-6)    # b = 0 for all of them
    assert ((cf.family(q, robot) & cf.SHOULDER_BACK) > 0).tolist() == (x_a1 < 0).tolist()


def test_elbow_bit_is_the_wrist_centre_behind_the_lower_arm():
    """IRB 2400: axis 2 at (a1, c1) = (100, 615) in the arm plane, axis 3 c2 = 705 mm up the
    lower arm (model angle theta2 from vertical); the side of the wrist centre (from FK) seen
    along the lower arm: cross product in the (x, z) plane, positive = in front."""
    rng = np.random.default_rng(8)
    q = rng.uniform(IRB2400.joint_min_deg, IRB2400.joint_max_deg, (300, 6))
    q[:, 0] = 0.0                              # arm plane = base x-z plane
    c = wrist_centre(IRB2400, q)
    theta2 = model_angles(IRB2400.spec, q)[:, 1]
    axis2 = np.array([100.0, 615.0])
    axis3 = axis2 + 705.0 * np.column_stack([np.sin(theta2), np.cos(theta2)])
    u = axis3 - axis2
    w = c[:, [0, 2]] - axis2
    front = u[:, 1] * w[:, 0] - u[:, 0] * w[:, 1] > 0
    assert ((cf.family(q, IRB2400) & cf.ELBOW_DOWN) == 0).tolist() == front.tolist()


def test_irb2400_elbow_stretched_by_hand():
    """From axis 3 the wrist centre is 755 mm along the forearm and 135 mm across it
    (a2 = -135); at q = 0 the forearm is horizontal, so the arm is stretched (wrist centre on
    the lower arm's line x = 100) at J3 = -atan2(755, 135) = -79.862 deg."""
    stretched = -np.degrees(np.arctan2(755.0, 135.0))
    assert stretched == pytest.approx(-79.8622, abs=1e-4)
    q = np.zeros((3, 6))
    q[:, 2] = stretched + np.array([0.0, 2.0, -2.0])
    np.testing.assert_allclose(wrist_centre(IRB2400, q[0])[0], 100.0, atol=1e-9)
    elbow = cf.arm_geometry(q, IRB2400).elbow_deg
    np.testing.assert_allclose(elbow, [0.0, 2.0, -2.0], atol=1e-9)
    assert cf.family(q, IRB2400).tolist() == [0, 0, cf.ELBOW_DOWN]


def test_irb2400_zero_pose_geometry_and_singularity_distances():
    g = cf.arm_geometry(np.zeros(6), IRB2400)
    assert float(g.shoulder_mm) == pytest.approx(855.0)              # wrist centre x
    assert float(g.elbow_deg) == pytest.approx(90.0 - 10.1378, abs=1e-3)
    assert float(g.wrist_deg) == 0.0
    shoulder, elbow, wrist = g.singularity_distances()
    assert (float(shoulder), float(wrist)) == (pytest.approx(855.0), 0.0)
    assert float(elbow) == pytest.approx(79.8622, abs=1e-4)


def test_family_names():
    assert cf.family_name(0) == "front, elbow up, wrist not flipped"
    assert cf.family_name(7) == "shoulder back, elbow down, wrist flipped"
    assert cf.family_name(None) == cf.family_name(-1) == "none"


# --- shifting joints by 360 degrees -----------------------------------------------------------

def test_unwrap_joints_by_hand():
    # A serial arm (IRB 4600: no J2/J3 coupling) with limits J1-J3 +-180, J4 +-400,
    # J5 +-120, J6 +-400.
    robot = restricted("ABB_IRB4600", J1=(-180, 180), J2=(-180, 180), J3=(-180, 180),
                       J4=(-400, 400), J5=(-120, 120), J6=(-400, 400))
    q = np.array([170, 10, -10, 170, 30, -170.0])
    ref = np.array([-170, 0, 0, -170, 0, 170.0])
    # J1 stays (its range is +-180); J4 170 -> -190 and J6 -170 -> 190 are closer and allowed.
    np.testing.assert_allclose(cf.unwrap_joints(q, ref, robot), [170, 10, -10, -190, 30, 190])
    # Out of range whatever the turn: the candidate least outside.
    np.testing.assert_allclose(cf.unwrap_joints([0, 0, 0, 0, 150, 0], np.zeros(6), robot),
                               [0, 0, 0, 0, 150, 0])
    assert cf.unwrap_joints([350, 0, 0, 0, 0, 0], np.zeros(6), robot)[0] == -10
    assert not cf.fits_limits([0, 0, 0, 0, 150, 0], robot)
    assert cf.fits_limits([350, 0, 0, 300, 0, -390], robot)
    assert not cf.fits_limits(np.full(6, np.nan), robot)


def test_travel_time_is_the_slowest_joint_at_full_speed():
    speeds = IRB2400.spec.joint_speed_deg_s           # 150, 150, 150, 360, 360, 450
    assert cf.travel_time_s(np.zeros(6), [15, 0, 0, 72, 0, 0], speeds) == pytest.approx(0.2)


# --- flange poses ---------------------------------------------------------------------------

def test_flange_pose_is_tcp_pose_minus_tool_in_the_base_frame():
    """T_r_f = T_r_b T_b_t inv(T_f_t): a tool 100 mm along the flange z puts the flange
    100 mm back along the TCP's z; the base sees {B} turned 30 deg about z at (600, -100, 300)."""
    T_b_t = pose((180, 0, 0), (10, 20, 30))           # tool pointing down in {B}
    move = ir.Move(ir.LINEAR, ir.Target("t", T_b_t), 10, 0, "B")
    program = ir.Program("P", "ABB_IRB2400", TOOL, {"B": ir.WorkFrame("B", T_R_B, np.eye(4))},
                         [ir.ProgramPath("A", "A", [move])])
    T = cf.flange_poses(program)
    assert T.shape == (1, 4, 4)
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    tcp = np.array([600 + c * 10 - s * 20, -100 + s * 10 + c * 20, 300 + 30])
    np.testing.assert_allclose(T[0, :3, 3], tcp + [0, 0, 100], atol=1e-9)   # 100 mm above
    np.testing.assert_allclose(T[0, :3, 2], [0, 0, -1], atol=1e-12)


def test_flange_poses_put_the_via_before_its_target():
    via, end = ir.Target("v", pose(position=(1, 0, 0))), ir.Target("e", pose(position=(2, 0, 0)))
    moves = [ir.Move(ir.CIRCULAR, end, 10, 0, "B", via=via)]
    program = ir.Program("P", "ABB_IRB2400", ir.ToolData("T", np.eye(4)),
                         {"B": ir.WorkFrame("B", np.eye(4), np.eye(4))},
                         [ir.ProgramPath("A", "A", moves)])
    np.testing.assert_allclose(cf.flange_poses(program)[:, 0, 3], [1, 2])
    entries = cf.target_entries(program)
    assert [(e.target.name, e.is_via, e.move_index) for e in entries] == [("v", True, 0),
                                                                          ("e", False, 0)]


def test_unknown_frame_is_an_input_error():
    program = program_from_joints(IRB2400, [np.zeros(6)])
    program.paths[0].moves[0].frame = "Nowhere"
    with pytest.raises(InputError, match="Nowhere"):
        cf.solve_program(program, IRB2400)


# --- solving a program ----------------------------------------------------------------------

JOINTS_A = [[10, 20, 10, 30, 40, 50], [12, 22, 8, 32, 42, 60], [14, 24, 6, 34, 44, 70],
            [16, 26, 4, 36, 46, 80]]


def test_solution_is_the_joints_the_targets_were_made_from():
    program = program_from_joints(IRB2400, JOINTS_A)
    solution = cf.solve_program(program, IRB2400, q_start_deg=[0, 0, 0, 0, 30, 0])
    assert solution.ok and solution.run_families == [0]
    np.testing.assert_allclose(solution.joints(), JOINTS_A, atol=1e-6)
    for entry, q in zip(solution.entries, JOINTS_A):
        np.testing.assert_allclose(entry.target.joints_deg, q, atol=1e-6)   # assigned
        assert entry.status == cf.OK and entry.family == 0
        assert set(entry.valid_families) >= {0, 1}
        np.testing.assert_allclose(IRB2400.fk(entry.joints_deg), entry.T_r_f, atol=1e-6)


def nearest_twin_deg(robot, Q):
    """The least distance (largest joint difference, deg) from a joint set of `Q` (N, 6) to
    another inverse solution of its pose in the same family.  OPW and UR arms have one
    solution per family; the offset wrists' 16 share 8 families, and near where two of
    them meet (not a singularity of ``singularity_distances``) a 2 deg step can land on
    the other one (CRX-10iA/L: 0.33 deg apart)."""
    S = robot.ik(robot.fk(Q))
    gap = np.abs((S - Q[:, None] + 180.0) % 360.0 - 180.0).max(axis=2)
    families = cf.family(S.reshape(-1, 6), robot).reshape(S.shape[:2])
    twin = (families == cf.family(Q, robot)[:, None]) & (gap > 1e-6)
    return float(np.min(np.where(twin, gap, np.inf)))


@pytest.mark.parametrize("name", sample_names())
def test_smooth_joint_paths_are_recovered_on_every_robot(name):
    """Targets made from a smooth joint path (1-2 deg steps) that stays in one family, away
    from the singularities and within the limits: the solution is that path."""
    robot = models.model(name)
    rng = np.random.default_rng(12)
    lo = np.maximum(robot.joint_min_deg, -170.0) + 10.0
    hi = np.minimum(robot.joint_max_deg, 170.0) - 10.0
    checked = 0
    for _ in range(30):
        Q = rng.uniform(lo, hi) + np.cumsum(np.vstack([np.zeros(6),
                                                       rng.uniform(-2, 2, (7, 6))]), axis=0)
        shoulder, elbow, wrist = cf.arm_geometry(Q, robot).singularity_distances()
        if (len(set(cf.family(Q, robot).tolist())) > 1 or min(elbow.min(), wrist.min()) < 3
                or shoulder.min() < 20 or not robot.within_limits(Q).all()
                or nearest_twin_deg(robot, Q) < 10):
            continue
        program = program_from_joints(robot, Q, robot=name)
        solution = cf.solve_program(program, robot, q_start_deg=Q[0])
        assert solution.ok
        np.testing.assert_allclose(solution.joints(), Q, atol=1e-5)
        checked += 1
    assert checked >= 10


def test_assign_false_leaves_targets_alone():
    program = program_from_joints(IRB2400, JOINTS_A)
    cf.solve_program(program, IRB2400, assign=False)
    assert all(t.joints_deg is None for t in program.targets())


def test_j6_is_unwrapped_past_180_to_follow_the_previous_target():
    """The tool turns about its own axis (= flange z) in 60 deg steps from J6 = 120: IK gives
    J6 in (-180, 180], the solution continues 180, 240, 300 (J6 range +-400)."""
    joints = [[0, 10, 10, 0, 45, j6] for j6 in (120, 180, 240, 300)]
    program = program_from_joints(IRB2400, joints)
    solution = cf.solve_program(program, IRB2400, q_start_deg=[0, 10, 10, 0, 45, 100])
    assert solution.ok
    np.testing.assert_allclose(solution.joints()[:, 5], [120, 180, 240, 300], atol=1e-6)
    # Going the other way from -120, it continues below -180.
    program = program_from_joints(IRB2400, [[0, 10, 10, 0, 45, -j] for j in (120, 180, 240, 300)])
    solution = cf.solve_program(program, IRB2400, q_start_deg=[0, 10, 10, 0, 45, -100])
    np.testing.assert_allclose(solution.joints()[:, 5], [-120, -180, -240, -300], atol=1e-6)


def test_winding_a_joint_past_its_limit_on_a_linear_path_is_a_joint_limit():
    """J6 limited to +-200 (and J4 to +-90, so the wrist cannot flip instead): turning the
    tool on from J6 = 180 to 240 on a linear move would wind J6 past +200; the pose itself is
    reachable at J6 = -120, but only by unwinding, which a linear move cannot do."""
    model = restricted(J4=(-90, 90), J6=(-200, 200))
    joints = [[0, 10, 10, 0, 45, j6] for j6 in (120, 180, 240)]
    program = program_from_joints(model, joints)
    solution = cf.solve_program(program, model, q_start_deg=[0, 10, 10, 0, 45, 100])
    assert [e.status for e in solution.entries] == [cf.OK, cf.OK, cf.JOINT_LIMIT]
    assert solution.entries[2].joints_deg is None
    assert solution.entries[2].attempt_deg[5] == pytest.approx(240.0)
    assert 0 in solution.entries[2].valid_families          # as a single pose it is fine


def test_the_whole_run_is_shifted_by_360_to_fit_the_limits():
    """Same limits, J6 turning 170 -> 230 -> 290: starting at 170 (nearest the start, 150)
    would end at 290 > 200; starting at -190 the run stays within -200..200."""
    model = restricted(J4=(-90, 90), J6=(-200, 200))
    joints = [[0, 10, 10, 0, 45, j6] for j6 in (170, 230, 290)]
    program = program_from_joints(model, joints)
    solution = cf.solve_program(program, model, q_start_deg=[0, 10, 10, 0, 45, 150])
    assert solution.ok
    np.testing.assert_allclose(solution.joints()[:, 5], [-190, -130, -70], atol=1e-6)


def test_tie_between_wrist_families_goes_to_the_start_joints():
    """Every target is valid in families 0 and 1 (J4 +-200, J6 +-400): the start decides."""
    flipped = [[q[0], q[1], q[2], q[3] + 180 - 360 * (q[3] > 0), -q[4], q[5] - 180]
               for q in JOINTS_A]
    program = program_from_joints(IRB2400, JOINTS_A)
    solution = cf.solve_program(program, IRB2400, q_start_deg=flipped[0])
    assert solution.run_families == [cf.WRIST_FLIPPED]
    np.testing.assert_allclose(solution.joints(), flipped, atol=1e-6)
    solution = cf.solve_program(program, IRB2400, q_start_deg=JOINTS_A[0])
    assert solution.run_families == [0]


def test_a_tie_goes_to_the_family_that_does_not_wind_a_joint_out_of_its_range():
    """Linear moves turning J4 120 -> 180 -> 240 -> 300 (J4 +-200, J6 +-400): every target
    is valid alone in families 0 and 1 (flipped: J4 - 180, -J5, J6 - 180), and 0 is the
    quickest from the start (its first target), but continued it winds J4 over 180 deg
    from 120 to 300, which no shift by 360 fits into +-200. The flipped family's J4 runs
    -60 -> 120 (by hand) and stays within, at the targets and between them (sampled)."""
    joints = [[0, 10, 10, j4, 45, 0] for j4 in (120, 180, 240, 300)]
    flipped = [[0, 10, 10, j4 - 180, -45, -180] for j4 in (120, 180, 240, 300)]
    program = program_from_joints(IRB2400, joints)
    solution = cf.solve_program(program, IRB2400, q_start_deg=joints[0])
    assert all(e.valid_families[:2] == (0, 1) for e in solution.entries)
    assert solution.run_families == [cf.WRIST_FLIPPED] and solution.ok
    np.testing.assert_allclose(solution.joints(), flipped, atol=1e-6)
    from CadRobotWB.robots.motion import move_sampling
    sampled = move_sampling.sample_program(program, IRB2400, solution, move_sampling.Margins())
    assert (sampled.status == move_sampling.OK).all()
    j4 = sampled.q_deg[:, 3]
    assert j4.min() == pytest.approx(-60.0, abs=1e-6) and j4.max() == pytest.approx(120.0, abs=1e-6)


def test_family_valid_at_most_targets_wins_and_a_linear_move_cannot_change_it():
    """J4 limited to +-90: a target with q5 < 0 (and q4 = 0) is only valid in the flipped
    family - the wrist would pass through its singularity on the linear move to it."""
    model = restricted(J4=(-90, 90))
    joints = [[0, 10, 10, 0, q5, 0] for q5 in (30, 20, 10, -10)]
    program = program_from_joints(model, joints)
    solution = cf.solve_program(program, model)
    assert solution.run_families == [0]
    assert [e.status for e in solution.entries] == [cf.OK] * 3 + [cf.CONFIG_CHANGE]
    last = solution.entries[3]
    assert last.family == cf.WRIST_FLIPPED
    assert cf.WRIST_FLIPPED in last.valid_families and 0 not in last.valid_families
    np.testing.assert_allclose(last.joints_deg, joints[3], atol=1e-6)
    assert not solution.ok


def test_joint_moves_start_new_runs_that_may_change_family():
    """Two paths, each opening with a joint move: the second keeps the flipped wrist."""
    model = restricted(J4=(-90, 90))
    joints = [[0, 10, 10, 0, 30, 0], [0, 12, 10, 0, 20, 0],
              [0, 10, 10, 0, -30, 0], [0, 12, 10, 0, -20, 0]]
    program = program_from_joints(model, joints, paths=[2, 2],
                                  kinds=[ir.JOINT, ir.LINEAR, ir.JOINT, ir.LINEAR])
    solution = cf.solve_program(program, model)
    assert solution.ok
    assert solution.run_families == [0, cf.WRIST_FLIPPED]
    assert [e.run for e in solution.entries] == [0, 0, 1, 1]


def test_a_run_without_joint_move_keeps_the_previous_family():
    """J1 +-90 too: no shoulder-back solution (it needs J1 = 180) valid everywhere."""
    model = restricted(J1=(-90, 90), J4=(-90, 90))
    joints = [[0, 10, 10, 0, 30, 0], [0, 12, 10, 0, 20, 0],
              [0, 10, 10, 0, -30, 0], [0, 12, 10, 0, -20, 0]]
    program = program_from_joints(model, joints, paths=[2, 2], kinds=[ir.JOINT] + [ir.LINEAR] * 3)
    solution = cf.solve_program(program, model)
    assert solution.run_families == [0]
    assert [e.status for e in solution.entries] == [cf.OK, cf.OK, cf.CONFIG_CHANGE,
                                                    cf.CONFIG_CHANGE]


def test_joint_limit_and_unreachable_targets_get_no_joints():
    model = restricted(J1=(-30, 30))
    joints = [[0, 10, 10, 0, 30, 0], [60, 10, 10, 0, 30, 0]]
    program = program_from_joints(model, joints)
    far = ir.Move(ir.LINEAR, ir.Target("far", pose(position=(5000, 0, 0))), 50, 0, "B")
    program.paths[0].moves.append(far)
    solution = cf.solve_program(program, model)
    statuses = [e.status for e in solution.entries]
    assert statuses == [cf.OK, cf.JOINT_LIMIT, cf.UNREACHABLE]
    limit = solution.entries[1]
    assert limit.joints_deg is None and limit.target.joints_deg is None
    assert limit.attempt_deg[0] == pytest.approx(60.0)          # J1: 30 deg beyond +30
    assert far.target.joints_deg is None and solution.entries[2].attempt_deg is None
    assert np.isnan(solution.joints()[1:]).all()


def test_via_points_are_solved_in_the_path_family():
    joints = [[0, 10, 10, 0, 45, 0], [5, 12, 9, 0, 44, 0], [10, 14, 8, 0, 43, 0]]
    T_b_r = np.linalg.inv(T_R_B)
    t = [ir.Target("t%d" % i, T_b_r @ IRB2400.fk(np.array(q, float)) @ TOOL.T_f_t)
         for i, q in enumerate(joints)]
    moves = [ir.Move(ir.JOINT, t[0], 50, 0, "B"), ir.Move(ir.CIRCULAR, t[2], 50, 0, "B", via=t[1])]
    program = ir.Program("P", "ABB_IRB2400", TOOL, {"B": ir.WorkFrame("B", T_R_B, np.eye(4))},
                         [ir.ProgramPath("A", "A", moves)])
    solution = cf.solve_program(program, IRB2400)
    assert [e.target.name for e in solution.entries] == ["t0", "t1", "t2"]
    np.testing.assert_allclose(solution.joints(), joints, atol=1e-6)


def test_empty_program():
    program = ir.Program("P", "ABB_IRB2400", TOOL, {}, [])
    solution = cf.solve_program(program, IRB2400)
    assert solution.entries == [] and solution.ok and solution.joints().shape == (0, 6)


# --- configuration data ---------------------------------------------------------------------

def test_abb_confdata_by_hand():
    """ABB table: cf = floor(angle / 90); cfx 0 front/front/axis 5 positive."""
    assert cf.abb_confdata(np.zeros(6), IRB2400) == (0, 0, 0, 0)
    assert cf.abb_confdata([0, 0, 0, 0, -30, 0], IRB2400) == (0, 0, 0, 1)
    assert cf.abb_confdata([100, 0, 0, 0, 30, 0], IRB2400) == (1, 0, 0, 0)
    assert cf.abb_confdata([0, 0, 0, 0, 30, -10], IRB2400) == (0, 0, -1, 0)
    assert cf.abb_confdata([-90, 0, 0, -200, 30, 400], IRB2400) == (-1, -3, 4, 0)
    assert cf.abb_confdata([-179, 0, 0, 90, 30, 270], IRB2400) == (-2, 1, 3, 0)
    # Elbow behind the lower arm: J3 below the stretched -79.862 deg.
    assert cf.abb_confdata([0, 0, -85, 0, 30, 0], IRB2400) == (0, 0, 0, 2)
    assert cf.abb_confdata([0, 0, -85, 0, -30, 0], IRB2400) == (0, 0, 0, 3)


def test_abb_cfx_behind_axis_1_by_hand():
    """J2 = -90 lays the lower arm back horizontally: axis 3 at x = 100 - 705 = -605; with
    J3 = 0 the forearm points straight up (755 mm), 135 mm further back (a2): wrist centre
    x = -605 - 135 = -740 < 0, behind axis 1, and in front of the lower arm (elbow up)."""
    q = [0, -90, 0, 0, 30, 0]
    np.testing.assert_allclose(wrist_centre(IRB2400, q)[[0, 2]], [-740, 615 + 755], atol=1e-9)
    assert cf.abb_confdata(q, IRB2400)[3] == 4
    assert cf.abb_confdata([0, -90, 0, 0, -30, 0], IRB2400)[3] == 5


def test_abb_cfx_matches_the_definition_for_random_joints():
    """Independent of arm_geometry: wrist centre from FK, lower arm from a1, c1, c2."""
    rng = np.random.default_rng(9)
    q = rng.uniform(IRB2400.joint_min_deg, IRB2400.joint_max_deg, (200, 6))
    c = wrist_centre(IRB2400, q)
    t = np.radians(q)
    x_a1 = np.cos(t[:, 0]) * c[:, 0] + np.sin(t[:, 0]) * c[:, 1]
    axis2 = np.column_stack([100.0 * np.ones(len(q)), 615.0 * np.ones(len(q))])
    lower = 705.0 * np.column_stack([np.sin(t[:, 1]), np.cos(t[:, 1])])
    w = np.column_stack([x_a1, c[:, 2]]) - axis2
    behind_lower = lower[:, 1] * w[:, 0] - lower[:, 0] * w[:, 1] < 0
    for k in range(len(q)):
        cf1, cf4, cf6, cfx = cf.abb_confdata(q[k], IRB2400)
        assert (cf1, cf4, cf6) == tuple(int(np.floor(v / 90.0)) for v in q[k, [0, 3, 5]])
        assert cfx == 4 * (x_a1[k] < 0) + 2 * behind_lower[k] + (q[k, 4] < 0)


def test_abb_confdata_needs_six_finite_joints_and_an_opw_robot():
    with pytest.raises(ValueError):
        cf.abb_confdata([0, 0, 0], IRB2400)
    with pytest.raises(ValueError):
        cf.abb_confdata([0, 0, np.nan, 0, 0, 0], IRB2400)
    with pytest.raises(ValueError, match="OPW"):
        cf.abb_confdata(np.zeros(6), models.model("UR5E"))


def test_kuka_status_turn():
    """KSS: typical taught data S 2, T 2 (basic area, A3 beyond stretched, A5 > 0, A2 < 0) and
    S 6, T 18 (A5 < 0 too).  Turn bit i = A(i+1) < 0."""
    kr6 = models.model("KUKA_KR6_R700")
    assert cf.kuka_status_turn([0, -90, 90, 0, 45, 0], kr6) == (2, 2)
    assert cf.kuka_status_turn([0, -90, 90, 0, -45, 0], kr6) == (6, 18)
    assert cf.kuka_status_turn([-10, -90, 90, -5, -45, -1], kr6) == (6, 1 + 2 + 8 + 16 + 32)
    # A5 = 0 counts as "A5 <= 0" (bit 2 set).
    assert cf.kuka_status_turn([0, -90, 90, 0, 0, 0], kr6)[0] == 6


def test_kuka_overhead_and_elbow_bits_from_fk():
    """Bit 0: wrist root point behind in the A1 frame (FK, A1 turns about -z: theta1 = -A1);
    bit 1: A3 at or beyond the stretched angle atan2(35, 365) = 5.48 deg (a2 = -35)."""
    kr6 = models.model("KUKA_KR6_R700")
    phi = np.degrees(np.arctan2(35.0, 365.0))
    assert cf.kuka_status_turn([0, -90, phi + 1, 0, 45, 0], kr6)[0] & 2
    assert not cf.kuka_status_turn([0, -90, phi - 1, 0, 45, 0], kr6)[0] & 2
    rng = np.random.default_rng(10)
    q = rng.uniform(kr6.joint_min_deg, kr6.joint_max_deg, (100, 6))
    c = wrist_centre(kr6, q)
    theta1 = -np.radians(q[:, 0])
    overhead = np.cos(theta1) * c[:, 0] + np.sin(theta1) * c[:, 1] < 0
    for k in range(len(q)):
        status, turn = cf.kuka_status_turn(q[k], kr6)
        assert bool(status & 1) == overhead[k]
        assert bool(status & 4) == (q[k, 4] <= 0)
        assert turn == sum(2 ** i for i in range(6) if q[k, i] < 0)


def test_fanuc_config():
    assert cf.fanuc_config([0, 0, 0, 0, -90, 0], IRB2400) == "N U T, 0, 0, 0"
    assert cf.fanuc_config([0, 0, 0, 0, 90, 0], IRB2400) == "F U T, 0, 0, 0"
    assert cf.fanuc_config([-190, 0, -85, 181, -90, 540], IRB2400) == "N D T, -1, 1, 1"
    assert cf.fanuc_config([0, -90, 0, -540, -90, 541], IRB2400) == "N U B, 0, -2, 2"
    assert cf.fanuc_config([0, 0, 0, -539, -90, 0], IRB2400).endswith(", 0, -1, 0")
    assert cf.fanuc_config([180, 0, 0, -180, -90, -181], IRB2400).endswith(", 0, -1, -1")


def test_motoman_rconf():
    """NX100: Flip for -90 < R <= 90 (and +-360 from it); 1 when |angle| >= 180."""
    hp6 = models.model("MOTOMAN_HP6")
    assert cf.motoman_rconf([0, 0, 0, 0, 0, 0], hp6) == (0, 0, 0, 0, 0, 0)
    assert cf.motoman_rconf([0, 0, 0, 100, 0, 0], hp6)[0] == 1
    assert cf.motoman_rconf([0, 0, 0, -100, 0, 0], hp6)[0] == 1
    assert cf.motoman_rconf([0, 0, 0, 90, 0, 0], hp6)[0] == 0
    assert cf.motoman_rconf([0, 0, 0, 300, 0, 0], hp6)[::3] == (0, 1)
    assert cf.motoman_rconf([0, 0, 0, -60, 0, 0], hp6)[::3] == (0, 0)
    assert cf.motoman_rconf([-200, 0, 0, 0, 0, -270], hp6)[3:] == (0, 1, 1)


def test_motoman_arm_fields_follow_the_geometry():
    """Upper/lower arm and front/rear are the elbow and shoulder bits of the family."""
    hp6 = models.model("MOTOMAN_HP6")
    rng = np.random.default_rng(11)
    q = rng.uniform(np.maximum(hp6.joint_min_deg, -170), np.minimum(hp6.joint_max_deg, 170),
                    (100, 6))
    fam = cf.family(q, hp6)
    for k in range(len(q)):
        _, lower, rear, *_ = cf.motoman_rconf(q[k], hp6)
        assert (lower, rear) == (int(bool(fam[k] & cf.ELBOW_DOWN)),
                                 int(bool(fam[k] & cf.SHOULDER_BACK)))
