"""The catalog arms that are neither OPW nor UR (kind ``chain``, issue 24).

Each row is checked against the URDF it came from (``tests/data/robots``): the
forward kinematics on random joint sets, the inverse giving back the joints
that made each pose (every row reproducing its pose), the link frames, the
class registry and the URDF import that recognises these arms, and that a check of
a program runs on the class's solver, never on the numerical IK.
"""

import dataclasses
import os

import numpy as np
import pytest

from CadRobotWB.core.rotations import rotation_angle_between
from CadRobotWB.errors import InputError
from CadRobotWB.robots.catalog import catalog, catalog_table
from CadRobotWB.robots.checks import links
from CadRobotWB.robots.kinematics import chain_classes, chain_geometry, models, poe
from CadRobotWB.robots.urdf import from_urdf, identify, numeric_ik, urdf
from required import ROBOT_DATA as DATA

#: Catalog name -> data folder, as tools/build_catalog.py names them.
ARMS = {
    "ABB_CRB15000_5_95": "abb_crb15000_5_95", "FANUC_CRX10IAL": "fanuc_crx10ial",
    "FANUC_M430IA2P": "fanuc_m430ia2p", "KUKA_KR10_R1100_3": "kuka_kr10_r1100_3",
    "KUKA_KR120_R2700_2": "kuka_kr120_r2700_2", "KUKA_KR13_R900_3": "kuka_kr13_r900_3",
    "KUKA_KR16_R1100_3": "kuka_kr16_r1100_3", "KUKA_KR20_R1820_2_E": "kuka_kr20_r1820_2_e",
    "MOTOMAN_HC10": "motoman_hc10", "MOTOMAN_HC10DT": "motoman_hc10dt",
    "MOTOMAN_HC10DT_B10": "motoman_hc10dt_b10", "MOTOMAN_HC10DTP_B00": "motoman_hc10dtp_b00",
    "MOTOMAN_MPX3500": "motoman_mpx3500",
}
OFFSET_WRIST = ["ABB_CRB15000_5_95", "FANUC_CRX10IAL", "FANUC_M430IA2P", "MOTOMAN_HC10",
                "MOTOMAN_HC10DT", "MOTOMAN_HC10DT_B10", "MOTOMAN_HC10DTP_B00"]
SPHERICAL_WRIST = ["KUKA_KR10_R1100_3", "KUKA_KR120_R2700_2", "KUKA_KR13_R900_3",
                   "KUKA_KR16_R1100_3", "KUKA_KR20_R1820_2_E"]


def chain_of(name):
    return urdf.serial_chain(urdf.read_urdf(os.path.join(DATA, ARMS[name], "robot.urdf")))


def random_joints_rad(chain, count, seed):
    return np.random.default_rng(seed).uniform(chain.lower_rad, chain.upper_rad, (count, 6))


def test_the_13_arms_are_catalog_rows_of_kind_chain():
    table = {spec.name: spec for spec in catalog_table.read_table(catalog.TABLE_PATH)}
    for name in ARMS:
        spec = catalog.get(name)
        assert name in table and table[name] == spec
        assert spec.chain is not None and spec.opw is None and spec.ur is None, name
        assert models.model(name).kind == "chain"
        assert spec.T_root_base is None          # the steps are in the URDF's root frame
        assert spec.source.endswith("(%s)" % ARMS[name]) and spec.license, name
    assert {n for n, s in table.items() if s.chain is not None} == set(ARMS)


@pytest.mark.parametrize("name", sorted(ARMS))
def test_forward_kinematics_equals_the_urdf_chain(name):
    chain = chain_of(name)
    q = random_joints_rad(chain, 300, 3)
    T_model = models.model(name).fk(np.degrees(q))
    T_chain = urdf.chain_fk(chain, q)
    assert np.linalg.norm(T_model[:, :3, 3] - T_chain[:, :3, 3], axis=1).max() < 1e-9
    assert rotation_angle_between(T_model[:, :3, :3], T_chain[:, :3, :3]).max() < 1e-12
    single = models.model(name).fk(np.degrees(q[0]))
    assert single.shape == (4, 4) and np.allclose(single, T_model[0], atol=1e-12)


@pytest.mark.parametrize("name", sorted(ARMS))
def test_inverse_of_forward_gives_back_the_joints(name):
    """Every row reproduces its pose, and the joints that made it are among the rows."""
    model = models.model(name)
    chain = chain_of(name)
    q_deg = np.degrees(random_joints_rad(chain, 4, 5))
    T = model.fk(q_deg)
    solutions = model.ik(T)
    assert solutions.shape == (4, model.max_solutions, 6)
    found = ~np.isnan(solutions).any(axis=2)
    assert np.all((solutions[found] > -180.0) & (solutions[found] <= 180.0))
    T_back = model.fk(solutions[found])
    T_wanted = np.repeat(T[:, None], solutions.shape[1], axis=1)[found]
    assert np.linalg.norm(T_back[:, :3, 3] - T_wanted[:, :3, 3], axis=1).max() < 1e-6
    assert rotation_angle_between(T_back[:, :3, :3], T_wanted[:, :3, :3]).max() < 1e-9
    difference = np.abs((solutions - q_deg[:, None] + 180.0) % 360.0 - 180.0).max(axis=2)
    assert (np.nanmin(difference, axis=1) < 1e-5).all()
    assert model.ik(T[0]).shape == (model.max_solutions, 6)


def test_each_arm_is_of_the_class_the_plan_names():
    classes = {name: models.kinematic_class(catalog.get(name)) for name in ARMS}
    assert {classes[n] for n in OFFSET_WRIST} == {"offset_wrist"}
    assert {classes[n] for n in SPHERICAL_WRIST} == {"spherical_wrist"}
    assert classes["MOTOMAN_MPX3500"] in ("offset_wrist", "spherical_wrist")
    assert models.kinematic_class(catalog.get("ABB_IRB2400")) == "opw"
    assert models.kinematic_class(catalog.get("UR5E")) == "ur"
    assert models.model("FANUC_CRX10IAL").max_solutions == 16


def test_an_arm_of_no_class_is_refused_naming_what_it_is():
    crx = catalog.get("FANUC_CRX10IAL")
    axes = list(crx.chain.axes)
    axes[2] = (0.0, np.sin(0.1), np.cos(0.1))              # axis 3 no longer parallel to axis 2
    tilted = dataclasses.replace(crx.chain, axes=tuple(axes))
    with pytest.raises(ValueError) as refused:
        chain_classes.classify(models.chain_parameters(tilted))
    text = str(refused.value)
    assert "not an offset-wrist arm (" in text and "; not a spherical-wrist arm (" in text
    spec = dataclasses.replace(crx, name="TILTED", chain=tilted)
    with pytest.raises(InputError) as refused:
        models.as_model(spec).ik(np.eye(4))
    assert str(refused.value).startswith("Robot TILTED: no inverse kinematics solves this arm: not")
    assert "\n" not in str(refused.value)


def test_link_frames_turn_about_the_urdf_joint_axes():
    """Frame i's origin lies on joint i's axis and its rotation is the URDF's link rotation
    (up to the constant one at zero); frame 6 is the flange."""
    name = "FANUC_CRX10IAL"
    chain = chain_of(name)
    q = random_joints_rad(chain, 5, 7)
    frames = links.link_frames(name, np.degrees(q))
    np.testing.assert_allclose(frames[:, 6], models.model(name).fk(np.degrees(q)), atol=1e-9)
    for n in range(len(q)):
        points, directions = urdf.joint_lines(chain, q[n])
        for i in range(6):
            offset = frames[n, i + 1, :3, 3] - points[i]
            off_axis = offset - (offset @ directions[i]) * directions[i] / (directions[i] @ directions[i])
            assert np.linalg.norm(off_axis) < 1e-9
    T_chain = urdf.chain_frames(chain, q)[0]
    R_const = np.swapaxes(frames[0, 1:, :3, :3], -1, -2) @ T_chain[0, 1:, :3, :3]
    R_each = np.swapaxes(frames[:, 1:, :3, :3], -1, -2) @ T_chain[:, 1:, :3, :3]
    assert np.abs(R_each - R_const).max() < 1e-12


def test_simple_solids_of_an_arm_without_meshes_are_watertight():
    spec = catalog.get("FANUC_CRX10IAL")          # its data folder has no collision meshes
    assert spec.meshes == ""
    parts = links.link_parts(spec)
    assert len(parts) == 7 and all(piece.is_watertight for body in parts for piece in body)
    # The upper arm (link 2) spans the 710 mm between axes 2 and 3.
    extent = np.ptp(np.vstack([piece.vertices for piece in parts[2]]), axis=0).max()
    assert 710.0 < extent < 710.0 + 2 * 0.06 * (710 + 540) + 1e-6


def test_reach_is_that_of_the_opw_formula_on_an_opw_arm():
    """chain_geometry.reach_mm on the IRB 2400's URDF equals catalog.reach_mm's OPW formula
    (|a1| + c2 + sqrt(a2^2 + c3^2) beside b), and the HC10's is its published 1200 mm."""
    irb2400 = poe.from_chain(urdf.serial_chain(urdf.read_urdf(os.path.join(DATA, "abb_irb2400",
                                                                            "robot.urdf"))))
    assert chain_geometry.reach_mm(irb2400) == pytest.approx(catalog.reach_mm(
        catalog.get("ABB_IRB2400")), abs=1e-6)
    assert catalog.get("MOTOMAN_HC10").reach_mm == pytest.approx(1200.0, abs=1e-3)


def test_a_table_row_with_bad_axes_is_one_line_naming_the_column(tmp_path):
    row = catalog_table.row_from_spec(catalog.get("MOTOMAN_HC10"))
    row["chain_axes"] = "0 0 2 " + row["chain_axes"].split(" ", 3)[3]
    path = tmp_path / "BAD.csv"
    catalog_table.write_table(str(path), [row])
    with pytest.raises(InputError) as refused:
        catalog_table.read_table(str(path))
    text = str(refused.value)
    assert "robot 'MOTOMAN_HC10'" in text and "column 'chain_axes'" in text and "unit" in text
    assert "\n" not in text
    row = catalog_table.row_from_spec(catalog.get("MOTOMAN_HC10"))
    row["chain_steps_mm"] = "1 2 3"
    catalog_table.write_table(str(path), [row])
    with pytest.raises(InputError, match="column 'chain_steps_mm' must hold 21 finite numbers"):
        catalog_table.read_table(str(path))


def test_a_chain_row_reads_back_to_the_same_floats(tmp_path):
    spec = catalog.get("KUKA_KR20_R1820_2_E")
    path = tmp_path / "table.csv"
    catalog_table.write_table(str(path), [catalog_table.row_from_spec(spec)])
    again, = catalog_table.read_table(str(path))
    assert again.chain == spec.chain
    np.testing.assert_allclose(again.T_flange_tip, spec.T_flange_tip, atol=1e-15)  # a quaternion
    assert again.reach_mm == spec.reach_mm


def test_urdf_import_recognises_the_class_and_checks_it_against_the_file():
    imported = from_urdf.spec_from_urdf(os.path.join(DATA, "motoman_hc10", "robot.urdf"), "MY_HC10",
                                        samples=100)
    assert imported.spec.chain is not None and imported.spec.opw is None
    assert imported.worst_mm < 1e-9 and imported.worst_rad < 1e-12
    found = identify.identify(chain_of("MOTOMAN_HC10"), samples=20)
    assert found.kind == "chain"
    q = np.degrees(random_joints_rad(chain_of("MOTOMAN_HC10"), 50, 9))
    np.testing.assert_allclose(found.fk(q), models.as_model(imported.spec).fk(q), atol=1e-9)


def test_a_check_of_a_crx_program_runs_on_the_offset_wrist_solver(monkeypatch):
    """The engine of ``api.check`` (joints of every target, moves sampled, the checks) on a
    CRX-10iA/L program: every inverse is the offset wrist's, the numerical IK is never
    called, and the joints that made the targets are what the check chose."""
    from test_configuration import program_from_joints
    from CadRobotWB.robots.checks import checks
    from CadRobotWB.robots.kinematics import offset_wrist
    from CadRobotWB.robots.motion import configuration, move_sampling

    model = models.model("FANUC_CRX10IAL")
    poses_solved = []
    for name in ("inverse", "inverse_screened"):       # the search, alone or screening too
        solve = getattr(offset_wrist, name)
        monkeypatch.setattr(offset_wrist, name, lambda k, T, *screen, solve=solve: (
            poses_solved.append(len(T)) or solve(k, T, *screen)))

    def numeric(*args, **kwargs):
        raise AssertionError("the numerical IK was called")

    monkeypatch.setattr(numeric_ik, "solve", numeric)
    steps_deg = np.outer(np.arange(6), [2, 1, -1, 2, 1, 3])          # a smooth joint path
    Q = np.array([20.0, 30.0, -20.0, 40.0, -60.0, 10.0]) + steps_deg
    program = program_from_joints(model, Q, robot="FANUC_CRX10IAL")
    solution = configuration.solve_program(program, model, q_start_deg=Q[0])
    sampled = move_sampling.sample_program(program, model, solution, checks.Margins())
    report = checks.check_program(program, model, solution, sampled=sampled)
    assert solution.ok and report.ok, report.lines()
    assert model.solver.module is offset_wrist and sum(poses_solved) >= len(Q)
    np.testing.assert_allclose(solution.joints(), Q, atol=1e-6)
