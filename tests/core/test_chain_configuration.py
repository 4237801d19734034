"""Families, continuity and the posts' configuration data of arms that are neither OPW nor UR.

The arms are the URDF chains of tests/data/robots (poe parameters); a small stand-in of
part E's ``models.ChainModel`` (kind "chain", ``params``) gives them forward kinematics
by ``poe.fk`` and every inverse solution by the numerical IK (16 rows).  The expected
values are derived by hand from each arm's geometry at zero joints (see each test).
"""

import dataclasses
import os
import types

import numpy as np
import pytest

from CadRobotWB.core import program as ir
from CadRobotWB.posts import common, fanuc_ls, kuka_krl, motoman_inform
from CadRobotWB.robots.catalog import catalog
from CadRobotWB.robots.kinematics import arm_families, chain_families, models, poe
from CadRobotWB.robots.motion import configuration as cfg
from CadRobotWB.robots.motion import configuration_data, move_sampling
from CadRobotWB.robots.urdf import numeric_ik, urdf

from test_fanuc_ls import parse_ls
from test_links import random_joints
from test_motoman_inform import parse_job

ROBOTS = os.path.join(os.path.dirname(__file__), os.pardir, "data", "robots")


def _chain(name):
    return urdf.serial_chain(urdf.read_urdf(os.path.join(ROBOTS, name, "robot.urdf")))


class ChainModelStandIn(models.RobotModel):
    """What the configuration code needs of part E's ``models.ChainModel``: ``kind``
    "chain", ``params`` (poe.ChainParameters), the URDF's joints and limits; ik by the
    numerical IK (16 rows), fk by poe."""

    kind = "chain"

    def __init__(self, name, urdf_name, like):
        chain = _chain(urdf_name)
        spec = dataclasses.replace(
            catalog.get(like), name=name, opw=None, dh=None, ur=None, j23_coupled=False,
            T_root_base=None, T_flange_tip=None,
            joint_min_deg=tuple(np.degrees(chain.lower_rad)),
            joint_max_deg=tuple(np.degrees(chain.upper_rad)),
            joint_speed_deg_s=tuple(np.degrees(chain.velocity_rad_s)))
        super().__init__(spec)
        self.params = poe.from_chain(chain)
        self._numeric = numeric_ik.NumericModel(chain, max_solutions=16)

    def fk(self, q_deg):
        q = np.asarray(q_deg, dtype=float)
        T = poe.fk(self.params, np.radians(q.reshape(-1, 6)))
        return T if q.ndim == 2 else T[0]

    def ik(self, T_r_f):
        return self._numeric.ik(np.asarray(T_r_f, dtype=float).reshape(-1, 4, 4))


def chain_spec(spec, params):
    """`spec` with part E's ``RobotSpec.chain`` field (poe.ChainParameters)."""
    fields = {f.name: getattr(spec, f.name) for f in dataclasses.fields(spec)}
    fields["chain"] = params                   # a field of RobotSpec once part E is merged
    return types.SimpleNamespace(**fields)


@pytest.fixture(scope="module")
def crx():
    return ChainModelStandIn("FANUC_CRX10IAL", "fanuc_crx10ial", "FANUC_LRMATE200ID")


@pytest.fixture(scope="module")
def hc10():
    return ChainModelStandIn("MOTOMAN_HC10", "motoman_hc10", "MOTOMAN_GP7")


@pytest.fixture(scope="module")
def kr16_r1100():
    return ChainModelStandIn("KUKA_KR16_R1100_3", "kuka_kr16_r1100_3", "KUKA_KR16")


# --- the measures, by hand ---------------------------------------------------------------------

def crx_by_hand(q):
    """CRX-10iA/L at J1 = 0 (zero joints: J2 axis +y at 245 mm, upper arm 710 mm up, J3 axis
    -y, forearm 540 mm along +x to where J4 and J5 meet): W = O2 + 710 (sin J2, 0, cos J2)
    + 540 (cos(J3 - J2), 0, sin(J3 - J2)), so shoulder = 710 sin J2 + 540 cos(J3 - J2) and
    the elbow, from the upper arm to the forearm about y = up x forward, is 90 - J3.  J5's
    axis is -y, straight at 0 (J6 160 mm further out along the forearm): the wrist is -J5."""
    q2, q3 = np.radians(q[:, 1]), np.radians(q[:, 2])
    return (710 * np.sin(q2) + 540 * np.cos(q3 - q2), 90.0 - q[:, 2], -q[:, 4])


def hc10_by_hand(q):
    """HC10 at S = 0 (zero joints: L axis +y at 275 mm, upper arm 700 mm up, U axis -y,
    forearm folded 500 mm straight down to where R and B meet): the forearm is
    (sin U, 0, -cos U) turned by L, so shoulder = 700 sin L + 500 sin(U - L) and the
    elbow is 180 - U.  B's axis is -y, straight at 0 (the flange 130 mm further down the
    forearm): the wrist is -B."""
    q2, q3 = np.radians(q[:, 1]), np.radians(q[:, 2])
    return (700 * np.sin(q2) + 500 * np.sin(q3 - q2), 180.0 - q[:, 2], -q[:, 4])


def wrapped(angle_deg):
    return (np.asarray(angle_deg) + 180.0) % 360.0 - 180.0


@pytest.mark.parametrize("arm, by_hand", [("crx", crx_by_hand), ("hc10", hc10_by_hand)])
def test_measures_equal_the_hand_formulas(arm, by_hand, request):
    model = request.getfixturevalue(arm)
    q = random_joints(model, 500, 1)
    q[:, 0] = 0.0
    g = cfg.arm_geometry(q, model)
    shoulder, elbow, wrist = by_hand(q)
    np.testing.assert_allclose(g.shoulder_mm, shoulder, atol=1e-9)
    np.testing.assert_allclose(wrapped(g.elbow_deg - elbow), 0.0, atol=1e-9)
    np.testing.assert_allclose(wrapped(g.wrist_deg - wrist), 0.0, atol=1e-9)
    # Axis 1 turns the whole arm: the measures do not change.
    q[:, 0] = np.random.default_rng(2).uniform(-180, 180, len(q))
    turned = cfg.arm_geometry(q, model)
    np.testing.assert_allclose(turned.shoulder_mm, shoulder, atol=1e-9)
    np.testing.assert_allclose(wrapped(turned.elbow_deg - elbow), 0.0, atol=1e-9)


@pytest.mark.parametrize("urdf_name, name", [("abb_irb4600_20_250", "ABB_IRB4600_20_250"),
                                             ("fanuc_lrmate200id", "FANUC_LRMATE200ID"),
                                             ("motoman_gp7", "MOTOMAN_GP7"),
                                             ("kuka_kr16_r1610_2", "KUKA_KR16_R1610_2")])
def test_chain_measures_are_the_opw_measures_on_opw_arms(urdf_name, name):
    """The chain's geometry reproduces the OPW model's shoulder, elbow and wrist on an OPW arm
    read from its URDF (the KR 16 R1610-2's model has its z down the arm, c1 = -520 mm)."""
    opw_model = models.model(name)
    arm = chain_families.arm_of(poe.from_chain(_chain(urdf_name)))
    q = random_joints(opw_model, 300, 3)
    shoulder, elbow, wrist = chain_families.measures(arm, q)
    g = cfg.arm_geometry(q, opw_model)
    np.testing.assert_allclose(shoulder, g.shoulder_mm, atol=1e-6)
    np.testing.assert_allclose(wrapped(elbow - g.elbow_deg), 0.0, atol=1e-9)
    np.testing.assert_allclose(wrapped(wrist - g.wrist_deg), 0.0, atol=1e-9)


def test_offset_and_oblique_wrists_are_told_apart():
    arms = {name: chain_families.arm_of(poe.from_chain(_chain(name)))
            for name in ("fanuc_crx10ial", "motoman_hc10", "abb_crb15000_5_95",
                         "kuka_kr16_r1100_3", "motoman_mpx3500")}
    offsets = {name: round(arm.wrist_offset_mm, 3) for name, arm in arms.items()}
    # Axis 6 from where axes 4 and 5 meet, by the URDFs' joint origins: CRX J6 150 mm along
    # J5; HC10 162 mm; CRB 15000 80 mm; KR16 R1100 0 (its file rounds to 1 um); MPX3500:
    # J6 meets J5 114 mm from J4 (57, -98.727 mm at 60 deg), 98.727 mm off J4's line.
    assert offsets == {"fanuc_crx10ial": 150.0, "motoman_hc10": 162.0,
                       "abb_crb15000_5_95": 80.0, "kuka_kr16_r1100_3": 0.0,
                       "motoman_mpx3500": 98.727}
    assert [name for name, arm in arms.items() if arm.oblique] == ["motoman_mpx3500"]
    assert all(arm.q5_straight_deg == 0.0 for arm in arms.values())     # KR16: 0.0002 snapped
    # J5's axis against up x forward (y on all five): -y on the CRX and HC10, +y on the CRB
    # and KR16, oblique (-0.5, 0, 0.866) on the MPX3500, taken as it is.
    assert {name: arm.wrist_sign for name, arm in arms.items()} == {
        "fanuc_crx10ial": -1, "motoman_hc10": -1, "abb_crb15000_5_95": 1,
        "kuka_kr16_r1100_3": 1, "motoman_mpx3500": 1}
    # The oblique wrist is singular at B = 0 only; the others at 0 and 180.
    q = np.array([[0, 0, 0, 0, 179.0, 0]])
    mpx = arm_families.ArmGeometry(*chain_families.measures(arms["motoman_mpx3500"], q),
                                   wrist_singular_at_180=False)
    assert mpx.singularity_distances()[2][0] == pytest.approx(179.0)
    crx = arm_families.ArmGeometry(*chain_families.measures(arms["fanuc_crx10ial"], q))
    assert crx.singularity_distances()[2][0] == pytest.approx(1.0)


# --- families of every IK solution -------------------------------------------------------------

@pytest.mark.parametrize("arm, by_hand", [("crx", crx_by_hand), ("hc10", hc10_by_hand)])
def test_families_of_all_solutions_are_the_makers_bits(arm, by_hand, request):
    """Every solution of random poses: shoulder back <-> W behind axis 1, elbow down <->
    W behind the upper arm, wrist flipped <-> J5 > 0 (FANUC's F; B > 0 on the HC10); the
    offset wrist has poses with more solutions than families (two or three per family)."""
    model = request.getfixturevalue(arm)
    q = np.random.default_rng(7).uniform(-180, 180, (12, 6))
    Q = model.ik(model.fk(q))                                        # (12, 16, 6)
    found = ~np.isnan(Q).any(axis=2)
    rows = Q[found]
    turned = rows.copy()
    turned[:, 0] = 0.0                                               # the hand formulas' J1
    shoulder, elbow, wrist = by_hand(turned)
    expected = 4 * (shoulder < 0) + 2 * (wrapped(elbow) < 0) + (wrapped(wrist) < 0)
    families = cfg.family(Q, model)
    np.testing.assert_array_equal(families[found], expected)
    assert (families[~found] == -1).all()
    counts = found.sum(axis=1)
    assert counts.max() > 8
    shared = [np.bincount(f[f >= 0], minlength=8).max() for f in families]
    assert max(shared) >= 2


def test_crx_families_by_hand(crx):
    """FANUC's bits on hand-made CRX poses: J5 -90 / +90 = no flip / flip, J2 -90 puts the
    wrist 710 mm behind axis 1, J3 120 with J2 60 bends the elbow down (90 - 120 = -30);
    family 0 is 'N U T'."""
    q = np.array([[0, 0, 0, 0, -90, 0], [0, 0, 0, 0, 90, 0], [0, -90, 0, 0, -90, 0],
                  [0, 60, 120, 0, -90, 0], [75, 0, 0, 0, -90, 0]], dtype=float)
    g = cfg.arm_geometry(q, crx)
    np.testing.assert_allclose(g.shoulder_mm, [540, 540, -710, 710 * np.sin(np.radians(60))
                                               + 540 * np.cos(np.radians(60)), 540], atol=1e-9)
    np.testing.assert_allclose(g.elbow_deg, [90, 90, 90, -30, 90], atol=1e-9)
    np.testing.assert_array_equal(cfg.family(q, crx), [0, 1, 4, 2, 0])


# --- continuity --------------------------------------------------------------------------------

def test_a_smooth_crx_path_keeps_its_family_and_its_solution(crx):
    """Poses along a smooth joint motion in family 1 (J5 > 0: F, elbow up 5 to 8 deg, W in
    front) where the family has a second solution at every pose (the CRX's dual, 14 to
    10 deg away on some joint): following the family from the first joints gives back the
    generating joints, never the dual."""
    t = np.linspace(0.0, 1.0, 7)[:, None]
    q_path = np.array([-108.6, 148.8, 84.8, 134.1, 61.9, -46.7]) + t * np.array(
        [-3, -2, -3, -5, -5, 5])
    family = cfg.family(q_path, crx)
    assert (family == 1).all()
    Q = crx.ik(crx.fk(q_path))
    assert ((cfg.family(Q, crx) == 1).sum(axis=1) == 2).all()
    q, status = move_sampling.follow_family(crx, crx.fk(q_path), 1, q_path[0])
    assert status == [cfg.OK] * len(q_path)
    np.testing.assert_allclose(q, q_path, atol=1e-4)
    # A program through those poses (a joint move, then linear moves) from the first joints:
    # one run in that family, every target at its generating joints.
    program = program_through(crx.name, q_path, crx)
    program.paths[0].moves[0].kind = ir.JOINT
    solution = cfg.solve_program(program, crx, q_start_deg=q_path[0])
    assert solution.ok and solution.run_families == [int(family[0])]
    np.testing.assert_allclose(solution.joints(), q_path, atol=1e-4)


# --- the posts' configuration data ---------------------------------------------------------------

def program_through(robot_name, joints_deg, model):
    """Linear moves to the flange poses of `joints_deg` (tool and frame at identity), each
    target carrying its joints."""
    moves = []
    for k, q in enumerate(joints_deg):
        target = ir.Target("p%d" % (k + 1), model.fk(q))
        target.joints_deg = np.asarray(q, dtype=float)
        moves.append(ir.Move(ir.LINEAR, target, 50.0, 0.0, "B"))
    frames = {"B": ir.WorkFrame("B", np.eye(4), np.eye(4), "Frame")}
    return ir.Program("Chain", robot_name, ir.ToolData("Tool", np.eye(4)), frames,
                      [ir.ProgramPath("Path", "Path", moves)])


CRX_JOINTS = np.array([[0, 0, 0, 0, -90, 0], [0, 0, 0, 0, 90, 0], [0, -90, 0, 0, -90, 0],
                       [0, 60, 120, 0, -90, 0], [0, 0, 0, 0, -90, 200]], dtype=float)


def test_fanuc_post_writes_the_crx_config_string(crx, monkeypatch):
    """FANUC's 'F/N U/D T/B, t1, t4, t6' (fanuc_config) on the hand-made CRX poses; the
    post finds the robot through common.opw_robot_spec, stood in for here (part E's
    catalog rows are not in this branch)."""
    monkeypatch.setattr(common, "opw_robot_spec", lambda program: crx)
    program = program_through("FANUC_CRX10IAL", CRX_JOINTS, crx)
    text = fanuc_ls.export(program, {"joint_targets": False})[0][1]
    configs = [p[2] for _, p in sorted(parse_ls(text).positions.items())]
    assert configs == ["N U T, 0, 0, 0", "F U T, 0, 0, 0", "N U B, 0, 0, 0",
                       "N D T, 0, 0, 0", "N U T, 0, 0, 1"]


def crx10ia():
    """The CRX-10iA (upper arm 540 mm) as a chain: the CRX-10iA/L's URDF chain with its
    710 mm upper arm cut to 540 mm (FANUC's two arms differ only there; the fixture
    below reproduces its positions to 0.03 mm this way)."""
    params = poe.from_chain(_chain("fanuc_crx10ial"))
    steps = params.P.copy()
    steps[2] *= 540.0 / 710.0
    spec = types.SimpleNamespace(name="FANUC_CRX10IA", opw=None, ur=None)
    return types.SimpleNamespace(kind="chain", spec=spec, params=poe.ChainParameters(
        H=params.H, P=steps, R_6T=params.R_6T))


#: CRX-10iA joint sets (controller degrees: J3 from the horizontal) with the CONFIG
#: letters of frfournier/robodk_crx_kinematics tests/fixtures/CRX10iA-solutions.csv
#: @1ce15fc ("FANUC RoboGuide simulation results" and Abbes and Poisson 2024): the
#: eight solutions of its ALL8 pose, and four solutions of the paper's Table 6 where
#: the point where J4 and J5 meet is 0.9 to 5.7 mm from the plane of J1 and the point
#: where J5 and J6 meet is 40.6 to 45.5 mm from it, on the side the letter names (the
#: fixture's 15/4 has its U/D and T/B columns swapped; read here as D, B).
CRX10IA_CONFIGS = [
    ([-53.304, -41.707, -3.066, 94.105, -36.806, 84.878], "N U T"),
    ([-94.524, -46.154, 8.411, 151.588, 9.543, 28.079], "F U T"),
    ([-29.111, 79.789, 115.78, 63.37, -102.215, -157.121], "N D T"),
    ([-100.556, 73.206, 133.278, 165.642, 132.372, -9.788], "F D T"),
    ([150.889, -79.789, 64.22, -116.63, -102.215, -157.121], "N U B"),
    ([79.444, -73.206, 46.722, -14.358, 132.372, -9.788], "F U B"),
    ([85.476, 46.154, 171.589, -28.412, 9.543, 28.079], "F D B"),
    ([126.696, 41.707, 183.066, -85.895, -36.806, 84.878], "N D B"),
    ([47.115, -53.924, 35.922, 28.105, -41.924, -48.121], "N U B"),
    ([49.247, 46.825, 135.954, 29.379, -134.512, -5.01], "N D B"),
    ([-130.753, -46.825, 44.046, -150.621, -134.512, -5.01], "N U T"),
    ([-132.885, 53.924, 144.078, -151.895, -41.924, -48.121], "N D T"),
]


def test_fanuc_config_of_the_crx10ia_follows_the_roboguide_fixture():
    """F/N, U/D and T/B of twelve CRX-10iA solutions equal the fixture's; Front/Back is
    read where J5 and J6 meet: the hand formula 540 sin J2 + 540 cos J3 - 150 sin J4
    sin J3 (J3 from the horizontal; J5 meets J6 150 mm along J5 from where it meets J4)
    gives its side, and
    the point where J4 and J5 meet (the same without the last term) is on the other
    side for the paper's four rows."""
    q = np.array([row for row, _ in CRX10IA_CONFIGS], dtype=float)
    q_chain = q.copy()
    q_chain[:, 2] += q[:, 1]                   # the URDF's J3 is the controller's J3 + J2
    # ... as the catalog's CRX-10iA/L counts it (same joints, longer upper arm).
    np.testing.assert_allclose(models.model("FANUC_CRX10IAL").controller_joints(q_chain), q,
                               atol=1e-9)
    robot = crx10ia()
    # The table's positions (J2's height, 245 mm, below its world origin): the ALL8 pose,
    # then Table 6's; reproduced only with J3 counted from the horizontal.
    at = poe.fk(robot.params, np.radians(q_chain))[:, :3, 3] - [0.0, 0.0, 245.0]
    np.testing.assert_allclose(at[:8], [[120.93, -304.29, 523.66]] * 8, atol=0.05)
    np.testing.assert_allclose(at[8:], [[209.47, -42.894, 685.5]] * 4, atol=0.05)
    letters = [c[:5] for c in configuration_data.fanuc_configs(q_chain, robot)]
    assert letters == [expected for _, expected in CRX10IA_CONFIGS]
    j2, j3, j4 = np.radians(q[:, 1]), np.radians(q[:, 2]), np.radians(q[:, 3])
    at_j4_j5 = 540 * np.sin(j2) + 540 * np.cos(j3)
    at_j5_j6 = at_j4_j5 - 150 * np.sin(j4) * np.sin(j3)
    arm = chain_families.arm_of(robot.params)
    np.testing.assert_allclose(chain_families.axis56_shoulder_mm(arm, q_chain), at_j5_j6,
                               atol=1e-9)
    np.testing.assert_allclose(np.abs(at_j4_j5[8:]), [0.9, 5.7, 5.7, 0.9], atol=0.05)
    np.testing.assert_allclose(np.abs(at_j5_j6[8:]), [40.6, 45.5, 45.5, 40.6], atol=0.05)
    assert (np.sign(at_j4_j5[8:]) != np.sign(at_j5_j6[8:])).all()


#: HC10 poses: U 90 puts the forearm level and forward (elbow 180 - 90 = 90: upper arm),
#: R 120 / 180 is no flip (beyond +-90), R 180 also sets o (R >= 180), U 200 with L 60 is
#: the lower arm (elbow -20) in front, L -90 puts the wrist 700 mm behind S (rear).
HC10_JOINTS = np.array([[0, 0, 90, 0, -90, 0], [0, 0, 90, 120, -90, 0], [0, 0, 90, 180, -90, 0],
                        [0, 60, 200, 0, -90, 0], [0, -90, 90, 0, -90, 0],
                        [0, 0, 90, 0, -90, 185]], dtype=float)
HC10_RCONF = [(0, 0, 0, 0, 0, 0), (1, 0, 0, 0, 0, 0), (1, 0, 0, 1, 0, 0), (0, 1, 0, 0, 0, 0),
              (0, 0, 1, 0, 0, 0), (0, 0, 0, 0, 1, 0)]


def test_motoman_post_writes_the_hc10_rconf(hc10, monkeypatch):
    """///RCONF l,m,n,o,p,q (flip from R, upper/lower arm, front/rear, R, T, S >= 180)."""
    np.testing.assert_array_equal(configuration_data.motoman_rconfs(HC10_JOINTS, hc10),
                                  HC10_RCONF)
    monkeypatch.setattr(common, "opw_robot_spec", lambda program: hc10)
    program = program_through("MOTOMAN_HC10", HC10_JOINTS, hc10)
    job = parse_job(motoman_inform.export(program, {})[0][1])
    assert [p[3] for p in job.positions] == HC10_RCONF


def test_kuka_status_turn_of_a_non_opw_kr16_follow_the_opw_kr16(kr16_r1100):
    """S and T of the KR 16 R1100-3 (spherical wrist, not OPW) equal those the exactly-OPW
    KUKA_KR16 gets for the same joints, wherever both arms are clear of the boundaries;
    KUKA's home (A2 -90, A3 90) is S 2 (basic area, A3 beyond stretched, A5 > 0)."""
    kr16 = models.model("KUKA_KR16")
    q = random_joints(kr16, 2000, 8)
    clear = np.ones(len(q), dtype=bool)
    for robot in (kr16, kr16_r1100):
        shoulder, elbow, wrist = cfg.arm_geometry(q, robot).singularity_distances()
        # The arms differ (KR16: a1 260, R1100: 100 mm; their elbow offsets by 8.7 deg).
        clear &= (shoulder > 300) & (elbow > 10) & (wrist > 1)
    assert clear.sum() > 100
    status, turn = configuration_data.kuka_status_turns(q[clear], kr16_r1100)
    status_opw, turn_opw = configuration_data.kuka_status_turns(q[clear], kr16)
    np.testing.assert_array_equal(status, status_opw)
    np.testing.assert_array_equal(turn, turn_opw)
    assert len(set(status.tolist())) == 8
    home = np.array([[0, -90, 90, 0, 45, 0], [0, -90, 90, 0, -45, 0]], dtype=float)
    targets = [ir.Target("h%d" % k, np.eye(4)) for k in range(2)]
    for target, q_home in zip(targets, home):
        target.joints_deg = q_home
    assert kuka_krl.status_turn_of(targets, kr16_r1100) == [(2, 2), (6, 18)]


def test_abb_confdata_of_the_crb15000(monkeypatch):
    """cfx of the CRB 15000 (zero joints: J2 axis +y at 265 mm, upper arm 444 mm up, J3 axis
    +y, J4 110 mm higher along +x, J5 470 mm further: W = (470, 0, 819), elbow
    atan2(470, 110) = 76.83 deg up): J5 < 0 sets bit 0; J2 -90 puts W behind axis 1 (4);
    J2 45, J3 -100 bends the elbow down (76.83 - 100 < 0) with W 493 mm in front (2)."""
    crb = ChainModelStandIn("ABB_CRB15000_5_95", "abb_crb15000_5_95", "ABB_IRB4600_20_250")
    q = np.array([[0, 0, 0, 0, 30, 0], [0, 0, 0, 0, -90, 0], [0, -90, 0, 0, 30, 0],
                  [0, 45, -100, 0, 30, 0], [100, 45, -100, -30, -30, 200]], dtype=float)
    g = cfg.arm_geometry(q, crb)
    np.testing.assert_allclose(g.elbow_deg[:3], np.degrees(np.arctan2(470, 110)), atol=1e-9)
    assert g.shoulder_mm[3] == pytest.approx(444 * np.sin(np.radians(45))
                                             + 470 * np.cos(np.radians(55))
                                             - 110 * np.sin(np.radians(55)), abs=1e-9)
    assert [cfg.abb_confdata(row, crb) for row in q] == [
        (0, 0, 0, 0), (0, 0, 0, 1), (0, 0, 0, 4), (0, 0, 0, 2), (1, -1, 2, 3)]


def test_posts_find_a_chain_arm_in_the_catalog(crx, monkeypatch):
    """common.opw_robot_spec gives the posts a chain arm's catalog entry (part E's
    ``RobotSpec.chain``, stood in for here: its catalog rows are not in this branch); a UR
    arm still gets None."""
    get = catalog.get
    spec = chain_spec(crx.spec, crx.params)
    monkeypatch.setattr(catalog, "get", lambda name: spec if name == crx.name else get(name))
    program = program_through(crx.name, CRX_JOINTS[:1], crx)
    assert common.opw_robot_spec(program) is spec
    assert configuration_data.fanuc_configs(CRX_JOINTS[:1], spec) == ["N U T, 0, 0, 0"]
    program.robot = "UR5E"
    assert common.opw_robot_spec(program) is None
    # The catalog holds the chain as axes and steps (part E's catalog.ChainAxes).
    axes = types.SimpleNamespace(axes=crx.params.H.tolist(), steps_mm=crx.params.P.tolist())
    spec = chain_spec(crx.spec, axes)
    assert configuration_data.fanuc_configs(CRX_JOINTS, spec) == [
        "N U T, 0, 0, 0", "F U T, 0, 0, 0", "N U B, 0, 0, 0", "N D T, 0, 0, 0", "N U T, 0, 0, 1"]


def test_kuka_home_is_status_2_on_an_opw_kuka_read_from_its_urdf():
    """KUKA's home (A2 -90, A3 90: upper arm up, forearm level, elbow up) is S 2 with A5 > 0
    and S 6 with A5 < 0, on the OPW KR 16 R1610-2 (c1 < 0) as on the KR 16."""
    home = np.array([[0, -90, 90, 0, 45, 0], [0, -90, 90, 0, -45, 0]], dtype=float)
    for name in ("KUKA_KR16", "KUKA_KR16_R1610_2"):
        status, turn = configuration_data.kuka_status_turns(home, models.model(name))
        assert status.tolist() == [2, 6] and turn.tolist() == [2, 18]
