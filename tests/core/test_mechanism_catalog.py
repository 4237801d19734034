"""The catalog of tracks and positioners (robots/mechanisms/catalog.py, resources/mechanisms.json):
forward kinematics by hand, the published numbers read as published, sources, solids, refusals,
and `cadrobot mechanisms`."""

import io
import json
import math
import re

import numpy as np
import pytest

from CadRobotWB import cli
from CadRobotWB.errors import InputError
from CadRobotWB.robots.mechanisms import catalog


def rot_x(deg):
    a = math.radians(deg)
    return np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])


def rot_z(deg):
    a = math.radians(deg)
    return np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])


def pose(R, p):
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p
    return T


BASE = pose(rot_z(30.0), (1000.0, -200.0, 50.0))      # a base placed somewhere in {U}


# ------------------------------------------------------------------ forward kinematics by hand
def test_generic_mechanisms_move_as_derived_by_hand():
    # track: carriage 500 mm along base X, its mounting face 250 mm up, Z up
    track = catalog.build("track", name="Track", T_u_base=BASE)
    assert np.allclose(track.T_u_p([500.0]), BASE @ pose(np.eye(3), (500.0, 0.0, 250.0)))
    # turntable: turn 90 about base Z, table face 750 mm up
    table = catalog.build("turntable", T_u_base=BASE)
    assert np.allclose(table.T_u_p([90.0]), BASE @ pose(rot_z(90.0), (0.0, 0.0, 750.0)))
    # tilt-turn: tilt 90 about base X through (0, 0, 800), then turn 90 about the tilted table normal;
    # the table face is on the tilt axis, so its centre stays at (0, 0, 800)
    tilt_turn = catalog.build("tilt_turn", T_u_base=BASE)
    assert np.allclose(tilt_turn.T_u_p([90.0, 90.0]),
                       BASE @ pose(rot_x(90.0) @ rot_z(90.0), (0.0, 0.0, 800.0)))
    # the table normal (flange Z) now points along -Y of the base: tilted a quarter turn about X
    assert np.allclose(tilt_turn.fk([90.0, 0.0])[:3, 2], (0.0, -1.0, 0.0))


def test_motopos_d500_moves_as_its_published_geometry_says():
    """The URDF: tilt axis 0.380 m above the base, the table face 0.150 m above it along the
    turn axis. At tilt 90 (about base X) the table centre swings from (0, 0, 530) to
    (0, -150, 380) and the table normal points along -Y. Its joint_2 turns about -Z of the
    table (axis 0 0 -1): turn +90 turns the table a quarter turn clockwise seen from above
    its face, rot_z(-90), and a point at +X of the table goes to -Y."""
    d500 = catalog.build("tilt_turn", "YASKAWA_MOTOPOS_D500", T_u_base=BASE)
    assert np.allclose(d500.fk([0.0, 0.0]), pose(np.eye(3), (0.0, 0.0, 530.0)))
    assert np.allclose(d500.T_u_p([90.0, 90.0]),
                       BASE @ pose(rot_x(90.0) @ rot_z(-90.0), (0.0, -150.0, 380.0)))
    assert np.allclose(d500.fk([0.0, 90.0])[:3, :3] @ [1.0, 0.0, 0.0], (0.0, -1.0, 0.0))
    assert d500.model == "YASKAWA_MOTOPOS_D500" and d500.payload_kg == 500.0


def test_kuka_dkp_400_moves_as_its_published_geometry_says():
    """visose/Robots libraries/Bartlett.xml and robotkinematicscatalogue KUKA_DKP_400.py agree:
    tilt axis 510 mm above the base, table face 347 mm above it. At tilt 90 (about base X) the
    table centre swings from (0, 0, 857) to (0, -347, 510) and the table normal points along -Y."""
    dkp = catalog.build("tilt_turn", "KUKA_DKP_400", T_u_base=BASE)
    assert np.allclose(dkp.fk([0.0, 0.0]), pose(np.eye(3), (0.0, 0.0, 857.0)))
    assert np.allclose(dkp.T_u_p([90.0, 90.0]),
                       BASE @ pose(rot_x(90.0) @ rot_z(90.0), (0.0, -347.0, 510.0)))
    assert np.allclose(dkp.fk([-90.0, 0.0])[:3, 3], (0.0, 347.0, 510.0))


def test_kuka_kp1_v500_turns_its_705_mm_table_without_a_stop():
    """visose/Robots libraries/AA.xml: KP1-V500, d 705 mm, -INF..INF at 126 deg/s."""
    table = catalog.build("turntable", "KUKA_KP1_V500", T_u_base=BASE)
    assert np.allclose(table.T_u_p([90.0]), BASE @ pose(rot_z(90.0), (0.0, 0.0, 705.0)))
    turn = table.axes[0]
    assert (turn.lower, turn.upper) == (-catalog.ENDLESS_DEG, catalog.ENDLESS_DEG) == (-3600.0, 3600.0)
    assert turn.max_speed == 126.0 and table.payload_kg == 500.0
    published = catalog.entry("KUKA_KP1_V500")["axes"]["turn"]
    assert published["endless"] is True and "lower" not in published and "upper" not in published


def test_tracks_carry_the_robot_as_published():
    """visose/Robots libraries/Bartlett.xml: KL1000-2 d 480 mm, 0..10000 mm at 1890 mm/s; the
    carriage 2500 mm along base X carries the robot's mounting face 480 mm up, Z up."""
    kl = catalog.build("track", "KUKA_KL_1000_2", T_u_base=BASE)
    assert np.allclose(kl.T_u_p([2500.0]), BASE @ pose(np.eye(3), (2500.0, 0.0, 480.0)))
    travel = kl.axes[0]
    assert (travel.lower, travel.upper, travel.max_speed) == (0.0, 10000.0, 1890.0)
    assert kl.payload_kg == 1000.0
    assert catalog.build("track", "KUKA_KL_1000_2", length_mm=4000.0).axes[0].upper == 4000.0
    with pytest.raises(InputError) as refused:
        catalog.build("track", "KUKA_KL_1000_2", length_mm=12000.0)
    assert "KUKA_KL_1000_2" in str(refused.value) and "10000 mm" in str(refused.value)
    # kroshu/kuka_robot_descriptions kl100_2_macro.xacro: -1.0..1.0 m at 2.5 m/s, the robot's
    # base 0.356 m above the carriage's joint frame (at the rail's base frame)
    kl100 = catalog.build("track", "KUKA_KL_100_2", T_u_base=BASE)
    assert np.allclose(kl100.T_u_p([-500.0]), BASE @ pose(np.eye(3), (-500.0, 0.0, 356.0)))
    assert (kl100.axes[0].lower, kl100.axes[0].upper, kl100.axes[0].max_speed) == (-1000.0, 1000.0, 2500.0)
    assert "axes.travel.max_accel" in catalog.entry("KUKA_KL_100_2")["estimated"]["fields"]
    # visose/Robots libraries/CRR.xml: IRBT6004 0..9700 mm at 1500 mm/s (height not given)
    irbt = catalog.build("track", "ABB_IRBT_6004").axes[0]
    assert (irbt.lower, irbt.upper, irbt.max_speed) == (0.0, 9700.0, 1500.0)
    assert "geometry.carriage_height" in catalog.entry("ABB_IRBT_6004")["estimated"]["fields"]


def test_eccentricity_and_table_offset_place_the_turn_axis():
    """A table face 100 mm below the tilt axis and a turn axis 40 mm off it along Y: at tilt 0
    the flange is at (0, 40, h - 100); turning by 90 spins it in place."""
    data = catalog.spec("tilt_turn")
    data["geometry"].update(table_offset=-100.0, eccentricity=40.0)
    joints, flange = catalog._CHAINS["tilt_turn"](data["geometry"])
    T = joints[0] @ joints[1] @ pose(rot_z(90.0), (0, 0, 0)) @ flange
    assert np.allclose(T, pose(rot_z(90.0), (0.0, 40.0, 700.0)))


def test_model_none_keeps_the_generic_values():
    positioner = catalog.build("tilt_turn")
    tilt, turn = positioner.axes
    assert (tilt.lower, tilt.upper, tilt.max_speed, tilt.max_accel) == (-135.0, 135.0, 70.0, 140.0)
    assert (turn.lower, turn.upper, turn.max_speed, turn.max_accel) == (-3600.0, 3600.0, 90.0, 180.0)
    assert positioner.model == "" and positioner.payload_kg == 0.0
    assert np.allclose(catalog.build("tilt_turn", "").fk([30.0, 40.0]), positioner.fk([30.0, 40.0]))
    track = catalog.build("track")
    assert (track.axes[0].lower, track.axes[0].upper, track.axes[0].max_speed) == (0.0, 3000.0, 1000.0)
    assert catalog.build("turntable").axes[0].max_speed == 90.0


# ------------------------------------------------------------------ the published numbers
def test_limits_and_speeds_are_the_published_numbers():
    """MOTOPOS D500, Yaskawa-Global/motoman_ros2_support_packages motopos_d500_macro.xacro (from
    Yaskawa's bulletin PB-283, its package.xml says): joint_1 (tilt) radians(+-135), velocity
    radians(80); joint_2 (turn) radians(+-200), radians(160)."""
    tilt, turn = catalog.build("tilt_turn", "YASKAWA_MOTOPOS_D500").axes
    assert (tilt.lower, tilt.upper, tilt.max_speed) == (-135.0, 135.0, 80.0)
    assert (turn.lower, turn.upper, turn.max_speed) == (-200.0, 200.0, 160.0)
    # estimated, as the entry says: 2 x the published speed per second
    assert (tilt.max_accel, turn.max_accel) == (160.0, 320.0)
    assert "axes.tilt.max_accel" in catalog.entry("YASKAWA_MOTOPOS_D500")["estimated"]["fields"]
    # MotoPos MH1655 headstock, the same repository: radians(+-360); 10.8 rpm (manual 168961-1CD
    # section 3.2.1, quoted in the file and in ros-industrial/motoman#621)
    mh1655 = catalog.build("turntable", "YASKAWA_MOTOPOS_MH1655").axes[0]
    assert (mh1655.lower, mh1655.upper) == (-360.0, 360.0)
    assert mh1655.max_speed == pytest.approx(64.8)
    # MotoPos MH185 headstock.urdf_macro.xacro: +-1.1 pi rad, (12.4 / 60) * 2 pi rad/s
    mh185 = catalog.build("turntable", "YASKAWA_MOTOPOS_MH185").axes[0]
    assert (mh185.lower, mh185.upper) == (pytest.approx(-198.0), pytest.approx(198.0))
    assert mh185.max_speed == pytest.approx(74.4)
    # KUKA DKP-400 (visose/Robots Bartlett.xml; robotkinematicscatalogue): tilt +-90 deg at
    # 94.5 deg/s; turn +-190 deg (the catalogue; Bartlett.xml: endless) at 126 deg/s; 400 kg
    tilt, turn = catalog.build("tilt_turn", "KUKA_DKP_400").axes
    assert (tilt.lower, tilt.upper, tilt.max_speed) == (-90.0, 90.0, 94.5)
    assert (turn.lower, turn.upper, turn.max_speed) == (-190.0, 190.0, 126.0)
    assert catalog.build("tilt_turn", "KUKA_DKP_400").payload_kg == 400.0


def test_yaskawa_entries_cite_the_makers_description_and_the_document_behind_it():
    """The Yaskawa positioners' numbers come first from Yaskawa's own ROS 2 descriptions, whose
    package.xml names the maker's document they were taken from (not reached here)."""
    for name, document in (("YASKAWA_MOTOPOS_D500", "PB-283"),
                           ("YASKAWA_MOTOPOS_MH1655", "168961-1CD")):
        sources = catalog.entry(name)["sources"]
        assert sources[0]["url"].startswith("https://github.com/Yaskawa-Global/"), name
        assert any(document in source["where"] for source in sources), name


def test_units_are_converted_in_one_place():
    assert catalog.quantity([0.38, "m"]) == (pytest.approx(380.0), "mm")
    assert catalog.quantity([math.pi, "rad/s"]) == (pytest.approx(180.0), "deg/s")
    assert catalog.quantity([30.0, "rpm"]) == (pytest.approx(180.0), "deg/s")
    assert catalog.quantity([-1.1, "pi rad"]) == (pytest.approx(-198.0), "deg")
    assert catalog.quantity([2.0, "m/s^2"]) == (pytest.approx(2000.0), "mm/s^2")
    with pytest.raises(InputError) as refused:
        catalog.quantity([1.0, "furlong"])
    assert "furlong" in str(refused.value) and "\n" not in str(refused.value)


def _field(entry, dotted):
    value = entry
    for key in dotted.split("."):
        value = value[key]
    return value


def _numbers(e):
    """{dotted field: [value, unit]} of an entry (an axis' "endless" and "reversed" flags are
    not numbers)."""
    numbers = {"payload": e["payload"]}
    numbers.update(("geometry." + k, v) for k, v in e["geometry"].items())
    numbers.update(("axes.%s.%s" % (a, k), v) for a, axis in e["axes"].items()
                   for k, v in axis.items() if k not in ("endless", "reversed"))
    return numbers


def test_every_entry_has_a_source_and_names_what_is_estimated():
    with open(catalog.CATALOG_PATH, encoding="utf-8") as f:
        entries = json.load(f)["mechanisms"]
    assert len({e["name"] for e in entries}) == len(entries)
    assert {e["kind"] for e in entries} == {"track", "turntable", "tilt_turn"}
    for e in entries:
        assert e["sources"] and all(s["title"] and s["where"] and s["url"] for s in e["sources"]), e["name"]
        assert all(re.fullmatch(r"\d{4}-\d{2}-\d{2}", s["read"]) for s in e["sources"]), e["name"]
        assert e["estimated"]["reason"], e["name"]
        for dotted in e["estimated"]["fields"]:
            _field(e, dotted)                      # names a field the entry has
        numbers = _numbers(e)
        assert all(unit in catalog._UNITS for _, unit in numbers.values()), e["name"]
        published = set(numbers) - set(e["estimated"]["fields"])
        for name, axis in e["axes"].items():       # endless, or both limits; a published speed
            assert axis.get("endless") is True or {"lower", "upper"} <= set(axis), e["name"]
            limits = {"axes.%s.%s" % (name, k) for k in ("lower", "upper") if k in axis}
            assert axis.get("endless") or limits & published, (e["name"], name)
            assert "axes.%s.max_speed" % name in published, (e["name"], name)
        mechanism = catalog.build(e["kind"], e["name"])
        assert all(a.lower < a.upper and a.max_speed > 0 and a.max_accel > 0 for a in mechanism.axes)


def test_names_and_entry():
    assert catalog.names("track") == ["ABB_IRBT_6004", "KUKA_KL_1000_2", "KUKA_KL_100_2"]
    assert catalog.names("turntable") == ["KUKA_KP1_V500", "YASKAWA_MOTOPOS_MH1655", "YASKAWA_MOTOPOS_MH185"]
    assert "YASKAWA_MOTOPOS_D500" in catalog.names("tilt_turn")
    assert set(catalog.names()) == {n for k in ("track", "turntable", "tilt_turn") for n in catalog.names(k)}
    d500 = catalog.entry("YASKAWA_MOTOPOS_D500")
    assert d500["axes"]["tilt"]["upper"] == [135, "deg"]
    d500["axes"]["tilt"]["upper"] = [0, "deg"]                   # a copy: the catalog is unchanged
    assert catalog.entry("YASKAWA_MOTOPOS_D500")["axes"]["tilt"]["upper"] == [135, "deg"]


# ------------------------------------------------------------------ refusals
@pytest.mark.parametrize("call, words", [
    (lambda: catalog.build("track", "YASKAWA_MOTOPOS_D500"), ("YASKAWA_MOTOPOS_D500", "tilt_turn", "track")),
    (lambda: catalog.build("tilt_turn", "IRBP_X"), ("IRBP_X", "not in the catalog")),
    (lambda: catalog.build("gantry"), ("gantry", "track, turntable, tilt_turn")),
    (lambda: catalog.build("track", length_mm=0.0), ("above 0",)),
    (lambda: catalog.names("crane"), ("crane",)),
])
def test_refusals_are_one_line_naming_the_model_and_the_fix(call, words):
    with pytest.raises(InputError) as refused:
        call()
    message = str(refused.value)
    assert "\n" not in message and all(w in message for w in words), message


def test_track_length_limits_the_travel():
    assert catalog.build("track", length_mm=4000.0).axes[0].upper == 4000.0
    assert catalog.build("track", length_mm=12000.0).axes[0].upper == 12000.0   # generic: any length


# ------------------------------------------------------------------ solids
def _in(T, vertices):
    return (np.linalg.inv(T) @ np.c_[vertices, np.ones(len(vertices))].T).T[:, :3]


@pytest.mark.parametrize("kind, model, values", [
    ("track", None, [1200.0]), ("track", "KUKA_KL_1000_2", [2500.0]),
    ("turntable", "YASKAWA_MOTOPOS_MH1655", [75.0]), ("turntable", "KUKA_KP1_V500", [-400.0]),
    ("tilt_turn", None, [-45.0, 130.0]), ("tilt_turn", "YASKAWA_MOTOPOS_D500", [60.0, -20.0]),
    ("tilt_turn", "KUKA_DKP_400", [-80.0, 150.0])])
def test_solids_move_rigidly_with_their_axes(kind, model, values):
    mechanism = catalog.build(kind, model, T_u_base=BASE, drawn_at=np.zeros(len(values)))
    drawn, moved = catalog.solids(mechanism), catalog.solids(mechanism, values)
    assert len(drawn) == len(mechanism.axes) + 1
    assert np.allclose(drawn[0][0], moved[0][0])                  # the base stands still
    assert moved[-1][1].dtype.kind == "i" and moved[-1][1].shape[1] == 3
    at_zero = _in(mechanism.T_u_p(mechanism.drawn_at), drawn[-1][0])
    at_values = _in(mechanism.T_u_p(values), moved[-1][0])
    assert np.allclose(at_zero, at_values)                        # rigid with the flange
    assert not np.allclose(drawn[-1][0], moved[-1][0])            # and it did move
    assert at_values[:, 2].max() == pytest.approx(0.0, abs=1e-9)  # the flange is the top face


def test_table_disc_and_carriage_are_sized_from_the_catalog():
    d500 = catalog.build("tilt_turn", "YASKAWA_MOTOPOS_D500")
    table = catalog.solids(d500)[-1][0]
    assert np.linalg.norm(table[:, :2], axis=1).max() == pytest.approx(400.0)   # 800 mm table
    track = catalog.build("track", length_mm=4000.0)
    rail = catalog.solids(track)[0][0]
    assert rail[:, 0].min() == pytest.approx(-400.0) and rail[:, 0].max() == pytest.approx(4400.0)
    assert rail[:, 2].max() == pytest.approx(250.0 - catalog.PLATE_MM)


def test_obstacles_are_named_meshes_in_the_frame_asked_for():
    positioner = catalog.build("tilt_turn", label="Positioner", T_u_base=BASE)
    T_r_u = np.linalg.inv(pose(np.eye(3), (-300.0, 0.0, 0.0)))
    named = catalog.obstacles(positioner, [10.0, 20.0], T_r_u=T_r_u)
    assert [n for n, _ in named] == ["Positioner base", "Positioner tilt", "Positioner turn"]
    for (_, mesh), (vertices, _) in zip(named, catalog.solids(positioner, [10.0, 20.0])):
        assert np.allclose(mesh.vertices, vertices + (300.0, 0.0, 0.0))
        assert mesh.is_watertight and all(piece.is_convex for piece in mesh.split())


# ------------------------------------------------------------------ cadrobot mechanisms
def run(*argv):
    out, err = io.StringIO(), io.StringIO()
    code = cli.main(list(argv), out=out, err=err)
    return code, out.getvalue(), err.getvalue()


def test_cli_lists_the_catalog():
    code, out, _ = run("mechanisms")
    lines = out.splitlines()
    assert code == 0 and len(lines) == len(catalog.names())
    d500 = next(line for line in lines if line.startswith("YASKAWA_MOTOPOS_D500:"))
    assert "tilt -135..135 deg at 80 deg/s" in d500 and "500 kg" in d500 and "motopos_d500" in d500
    kp1 = next(line for line in lines if line.startswith("KUKA_KP1_V500:"))
    assert "turn endless at 126 deg/s" in kp1 and "500 kg" in kp1 and "AA.xml" in kp1
    code, out, _ = run("mechanisms", "--kind", "track", "--json")
    rows = json.loads(out)
    assert code == 0 and [r["name"] for r in rows] == ["ABB_IRBT_6004", "KUKA_KL_1000_2", "KUKA_KL_100_2"]
    assert rows[1]["axes"][0]["max_speed"] == pytest.approx(1890.0) and rows[1]["sources"][0]["url"]
    assert rows[1]["geometry_mm"]["carriage_height"] == pytest.approx(480.0)
    code, _, err = run("mechanisms", "--kind", "crane")
    assert code == 2 and err.count("\n") == 1 and "crane" in err


def test_the_collision_checker_takes_the_obstacles_as_they_are():
    """The IRB 2400 at the origin, the generic positioner 1200 mm in front: upright it clears
    it; bent forward (J2 60, J3 20) its arm goes through the table, the yoke and the pillars."""
    from CadRobotWB.robots.checks import collision
    if not collision.is_available():
        pytest.skip("python-fcl is not installed")
    positioner = catalog.build("tilt_turn", label="Positioner",
                               T_u_base=pose(np.eye(3), (1200.0, 0.0, 0.0)))
    checker = collision.RobotCollisionChecker("ABB_IRB2400", catalog.obstacles(positioner))
    upright, bent = checker.check(np.array([[0.0] * 6, [0.0, 60.0, 20.0, 0.0, 0.0, 0.0]]))
    assert upright == [] and checker.base_contacts == []
    assert {hit.obstacle for hit in bent} == {"Positioner base", "Positioner tilt", "Positioner turn"}
