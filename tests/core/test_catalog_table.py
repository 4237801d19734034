"""The catalog table (resources/robots/catalog.csv): every row against its URDF.

Each table robot is rebuilt from the URDF file it came from (the data folder
``tests/data/robots``) and compared with the model the catalog reads from
the table: forward kinematics on 1000 random joint sets within the file's
limits (<= 1e-6 mm, <= 1e-9 rad), inverse kinematics giving back the joint set
that made each pose, the file's joint limits, and the link hulls following the
file's collision meshes.  The hand-written robots that have a URDF twin are
compared with it up to constant base and flange frames.
"""

import os
import re

import numpy as np
import pytest

from CadRobotWB.core.frames import fit_frame
from CadRobotWB.core.rotations import rotation_angle_between as rotation_angles
from CadRobotWB.robots.catalog import catalog, catalog_table
from CadRobotWB.robots.checks import links
from CadRobotWB.robots.kinematics import models
from CadRobotWB.robots.motion import configuration
from CadRobotWB.robots.urdf import link_meshes, urdf
from required import ROBOT_DATA as DATA


TABLE = catalog_table.read_table(catalog.TABLE_PATH)
TWINS = {"ABB_IRB2400": "abb_irb2400", "ABB_IRB2600": "abb_irb2600_12_165",
         "ABB_IRB4600": "abb_irb4600_60_205", "KUKA_KR6_R700": "kuka_kr6_r700_sixx",
         "KUKA_KR16": "kuka_kr16_2", "UR5E": "ur5e"}


def folder_of(spec):
    return re.search(r"\((\w+)\)$", spec.source).group(1)


def chain_of(folder):
    return urdf.serial_chain(urdf.read_urdf(os.path.join(DATA, folder, "robot.urdf")))


def test_the_catalog_has_163_arms_of_eight_makers():
    specs = catalog.specs()
    assert len(specs) >= 163
    assert sum(s.chain is not None for s in specs) >= 13      # neither OPW nor UR (issue 24)
    assert {s.manufacturer for s in specs} >= {"ABB", "KUKA", "FANUC", "Yaskawa Motoman", "Staubli",
                                              "Universal Robots", "Kawasaki", "DENSO"}
    assert len({s.name for s in specs}) == len(specs)


def test_rows_read_back_to_the_same_entries(tmp_path):
    path = tmp_path / "table.csv"
    rows = [catalog_table.row_from_spec(spec, os.path.basename(spec.meshes)) for spec in TABLE]
    catalog_table.write_table(str(path), rows)
    again = catalog_table.read_table(str(path))
    for before, after in zip(TABLE, again):
        assert before.opw == after.opw and before.ur == after.ur
        assert before.chain == after.chain
        for frame in ("T_root_base", "T_flange_tip"):   # quaternions: exact to a few ulp
            np.testing.assert_allclose(np.array(getattr(before, frame) or np.eye(4)),
                                       np.array(getattr(after, frame) or np.eye(4)), atol=1e-15)
        assert before.joint_min_deg == after.joint_min_deg and before.notes == after.notes


@pytest.mark.parametrize("spec", TABLE, ids=lambda s: s.name)
def test_table_robot_equals_its_urdf_chain(spec):
    chain = chain_of(folder_of(spec))
    model = models.model(spec.name)
    rng = np.random.default_rng(11)
    q = np.vstack([np.zeros((1, 6)), rng.uniform(chain.lower_rad, chain.upper_rad, (1000, 6))])
    T_model = model.fk(np.degrees(q))
    T_chain = urdf.chain_fk(chain, q)
    assert np.linalg.norm(T_model[:, :3, 3] - T_chain[:, :3, 3], axis=1).max() <= 1e-6
    assert rotation_angles(T_model[:, :3, :3], T_chain[:, :3, :3]).max() <= 1e-9
    # Limits are the file's (to the table's 0.01 deg).
    np.testing.assert_allclose(spec.joint_min_deg, np.degrees(chain.lower_rad), atol=0.005 + 1e-9)
    np.testing.assert_allclose(spec.joint_max_deg, np.degrees(chain.upper_rad), atol=0.005 + 1e-9)
    if spec.chain is not None:      # inverse and families: test_chain_catalog.py
        return
    # The inverse gives back the joint set of every pose away from the shoulder and wrist
    # singularities (at the wrist's only the sum of J4 and J6 is set), and only poses that fit.
    q_deg = np.degrees(q[1:201])
    shoulder_mm, _, wrist_deg = configuration.arm_geometry(q_deg, model).singularity_distances()
    regular = (shoulder_mm > 10.0) & (wrist_deg > 1.0)
    solutions = model.ik(T_chain[1:201])
    difference = np.abs((solutions - q_deg[:, None] + 180.0) % 360.0 - 180.0).max(axis=2)
    # A UR file's angles are rounded to 1e-10 rad, so its model is 1e-7 mm off the chain.
    assert (np.nanmin(difference, axis=1)[regular] < (1e-5 if spec.ur else 1e-6)).all()
    assert regular.sum() > 150
    found = ~np.isnan(solutions).any(axis=2)
    T_back = model.fk(solutions[found])
    T_wanted = np.repeat(T_chain[1:201, None], solutions.shape[1], axis=1)[found]
    assert np.abs(T_back - T_wanted).max() < 1e-6


@pytest.mark.parametrize("name", ["ABB_IRB1600_6_12", "FANUC_M20IA", "KUKA_KR210L150",
                                  "MOTOMAN_GP25", "STAUBLI_TX2_90", "UR10E", "MOTOMAN_HC10"])
def test_link_hulls_follow_the_urdf_collision_meshes(name):
    """Vertices of the file's collision meshes, moved by the file's chain, lie in the hulls
    placed by link_frames (within 2 % of the reach: a hull keeps 160 of its vertices)."""
    spec = catalog.get(name)
    assert spec.meshes and os.path.isfile(spec.meshes)
    robot = urdf.read_urdf(os.path.join(DATA, folder_of(spec), "robot.urdf"))
    chain = urdf.serial_chain(robot)
    hulls = link_meshes.load(spec.meshes)
    rng = np.random.default_rng(12)
    q_rad = rng.uniform(chain.lower_rad, chain.upper_rad, (3, 6))
    T_chain = urdf.chain_frames(chain, q_rad)[0]
    T_link = links.link_frames(spec, np.degrees(q_rad))
    tolerance = 0.02 * spec.reach_mm
    for body, members in enumerate(chain.body_links):
        if hulls[body] is None:
            continue
        for link, T_body_link in members:
            for geometry in robot.collisions[link]:
                mesh = link_meshes.shape_mesh(geometry, robot.path)
                for n in range(len(q_rad)):
                    points = (T_chain[n, body] @ T_body_link @ np.c_[mesh.vertices,
                                                                     np.ones(len(mesh.vertices))].T).T
                    local = (np.linalg.inv(T_link[n, body]) @ points.T).T[:, :3]
                    hull = hulls[body]
                    outside = (local @ hull.face_normals.T
                               - np.sum(hull.face_normals * hull.triangles[:, 0], axis=1)).max(axis=1)
                    assert outside.max() < tolerance, (name, body, link, outside.max())


@pytest.mark.parametrize("name", sorted(TWINS))
def test_hand_written_robots_equal_their_urdf_twins(name):
    """Same flange positions after one rigid base change, same flange axes after one
    constant turn: the hand-written kinematics is the ROS-Industrial arm's."""
    chain = chain_of(TWINS[name])
    model = models.model(name)
    rng = np.random.default_rng(13)
    q = rng.uniform(np.maximum(chain.lower_rad, -np.pi), np.minimum(chain.upper_rad, np.pi), (300, 6))
    T_chain = urdf.chain_fk(chain, q)
    T_model = model.fk(np.degrees(q))
    T_root_r, residuals = fit_frame(T_model[:, :3, 3], T_chain[:, :3, 3])
    assert residuals.max() < 1e-6
    R_f_tip = np.swapaxes(T_root_r[:3, :3] @ T_model[:, :3, :3], 1, 2) @ T_chain[:, :3, :3]
    assert rotation_angles(R_f_tip[:1], R_f_tip).max() < 1e-9
