"""Per-maker conventions (robots/catalog/makers.py): default posts and the J2/J3 convention."""

import json
from pathlib import Path

import pytest

from CadRobotWB.errors import UnknownNameError
from CadRobotWB import posts
from CadRobotWB.robots.catalog import catalog, makers
from required import ROBOT_DATA

SOURCES_JSON = Path(ROBOT_DATA) / "sources.json"


def test_the_eight_makers_of_the_data_folder():
    assert makers.MAKERS == ("ABB", "DENSO", "FANUC", "KUKA", "Kawasaki", "Staubli",
                             "Universal Robots", "Yaskawa Motoman")


def test_every_maker_and_folder_of_sources_json_is_covered():
    rows = json.loads(SOURCES_JSON.read_text())
    assert {row["maker"] for row in rows} == set(makers.MAKERS)
    for row in rows:
        k = makers.j23_factor(row["maker"], row["folder"])
        assert k in (-1, 0, 1, None), row["folder"]
        assert makers.j23_source(row["maker"], row["folder"]), row["folder"]


def test_default_posts():
    assert {m: makers.default_post(m) for m in makers.MAKERS} == {
        "ABB": "abb_rapid", "KUKA": "kuka_krl", "FANUC": "fanuc_ls",
        "Yaskawa Motoman": "motoman_inform", "Universal Robots": "ur_script",
        "Staubli": None, "Kawasaki": None, "DENSO": None}


def test_default_posts_exist_and_match_the_catalog():
    for maker in makers.MAKERS:
        assert makers.default_post(maker) in posts.BUILTIN + (None,)
    for name in catalog.names():
        spec = catalog.get(name)
        assert (makers.default_post(spec.manufacturer) or "") == spec.default_post, name


def test_abb_j23_coupled_per_model_as_the_support_packages_set_it():
    for model in ("abb_irb2400", "abb_irb2400_12_155", "IRB 2400/10", "abb_irb4400l_30_243",
                  "abb_irb5400"):
        assert makers.j23_coupled("ABB", model) is True, model
        assert makers.j23_factor("ABB", model) == 1        # controller J3 = q3 + q2
    for model in ("abb_irb120_3_58", "abb_irb1200_5_90", "abb_irb1600_6_12",
                  "abb_irb2600_12_165", "IRB 2600-12/1.65", "abb_irb4600_60_205",
                  "abb_irb6640_185_280", "abb_irb6600_225_255", "abb_irb6700_235_265",
                  "abb_crb15000_5_95"):
        assert makers.j23_coupled("ABB", model) is False, model
    for model in ("abb_irb52_7_120", "abb_irb6650s_90_390", "IRB 9999"):
        assert makers.j23_coupled("ABB", model) is None, model
        assert makers.j23_source("ABB", model).startswith("unknown")


def test_abb_catalog_robots_agree_with_the_support_packages():
    for name in ("ABB_IRB2400", "ABB_IRB2600", "ABB_IRB4600"):
        spec = catalog.get(name)
        assert makers.j23_coupled("ABB", spec.model) == spec.j23_coupled, name


def test_fanuc_j3_is_measured_from_the_horizontal():
    # J23_factor = 1 in the support packages: controller J3 = q3 - q2.
    for folder in ("fanuc_m10ia", "fanuc_lrmate200ic", "fanuc_r2000ic125l", "fanuc_cr7ial"):
        assert makers.j23_factor("FANUC", folder) == -1, folder
    assert makers.j23_factor("FANUC", "fanuc_m430ia2p") == 1       # J23_factor = -1
    # No driver package for the CRX; a third party's ROBOGUIDE table counts J3 so too.
    assert makers.j23_factor("FANUC", "fanuc_crx10ial") == -1


def test_drivers_that_pass_the_joints_through():
    for maker in ("KUKA", "Yaskawa Motoman", "Staubli", "Universal Robots", "Kawasaki",
                  "DENSO"):
        assert makers.j23_factor(maker, "any") == 0
        assert makers.j23_coupled(maker, "any") is False


def test_every_convention_has_a_paragraph_and_sources():
    for maker in makers.MAKERS:
        conv = makers.convention(maker)
        assert conv.maker == maker and len(conv.convention) > 100 and conv.sources
        assert any("@" in s for s in conv.sources), maker     # a repository at a commit


def test_other_spellings_and_unknown_makers():
    assert makers.convention("Yaskawa").maker == "Yaskawa Motoman"
    assert makers.convention("Stäubli").maker == "Staubli"
    assert makers.convention("universal robots").maker == "Universal Robots"
    with pytest.raises(UnknownNameError):
        makers.convention("Comau")
