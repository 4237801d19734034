"""Make the catalog table from the robot descriptions of the data folder.

    python3 tools/build_catalog.py DATA_FOLDER

DATA_FOLDER is the robot data folder: one sub-folder per arm with its ``robot.urdf``
and ``collision/`` meshes, and ``sources.json``. ``tests/data/robots`` is a copy of it
with every URDF but the collision meshes of only nine arms: built from there, the table
is the same but most arms lose their link hulls, so give the full folder.
For every arm there (``<folder>/robot.urdf``, maker and source in
``sources.json``) it builds the catalog entry (``robots.urdf.from_urdf``), which
checks the model against the URDF chain on 1000 joint sets, and writes:

* ``CadRobotWB/resources/robots/catalog.csv`` -- one row per OPW or UR arm and per arm
  of a solver class of ``robots/kinematics/chain_classes.py`` (kind ``chain``);
* ``CadRobotWB/resources/robots/meshes/<NAME>.npz`` -- link hulls, where the
  data folder has the collision meshes (their licenses allow it: SOURCES.md);
* ``docs/robot-catalog.md`` -- every arm with its class and how its inverse
  kinematics is solved, or why it is not in the table; the count per class.

The arms the hand-written catalog already has (``CURATED``) are not repeated.
Run it again after changing the data folder or ``robots/``; the output is
deterministic.
"""

import collections
import json
import os
import sys

REPOSITORY = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, REPOSITORY)

from CadRobotWB.errors import InputError  # noqa: E402
from CadRobotWB.robots.catalog import catalog_table  # noqa: E402
from CadRobotWB.robots.kinematics import chain_classes, models  # noqa: E402
from CadRobotWB.robots.urdf import from_urdf  # noqa: E402

RESOURCES = os.path.join(REPOSITORY, "CadRobotWB", "resources", "robots")
DOC = os.path.join(REPOSITORY, "docs", "robot-catalog.md")

#: Data folders of arms the hand-written catalog (robots/catalog/catalog.py) has, by its name.
CURATED = {
    "abb_irb2400": "ABB_IRB2400", "abb_irb2600_12_165": "ABB_IRB2600",
    "abb_irb4600_60_205": "ABB_IRB4600", "kuka_kr6_r700_sixx": "KUKA_KR6_R700",
    "kuka_kr16_2": "KUKA_KR16", "ur5e": "UR5E",
}

#: The classes of the report, in its column order, and how each is solved.
CLASSES = (("opw", "OPW", "closed form (Brandstötter et al. 2014)"),
           ("ur", "UR", "closed form (UR's DH model)")) + tuple(
    (module.KIND, module.KIND.replace("_", " "), chain_classes.METHODS[module.KIND])
    for module in chain_classes.CLASSES) + (("other", "other", "-"),)
METHOD = {kind: method for kind, _label, method in CLASSES}

#: Catalog name prefix per maker.
PREFIX = {"ABB": "ABB", "DENSO": "DENSO", "FANUC": "FANUC", "Kawasaki": "KAWASAKI",
          "KUKA": "KUKA", "Staubli": "STAUBLI", "Universal Robots": "", "Yaskawa Motoman": "MOTOMAN"}


def build(data_folder):
    with open(os.path.join(data_folder, "sources.json"), encoding="utf-8") as stream:
        sources = {entry["folder"]: entry for entry in json.load(stream)}
    meshes_folder = os.path.join(RESOURCES, "meshes")
    os.makedirs(meshes_folder, exist_ok=True)
    rows, report = [], []
    counts = collections.Counter()
    for folder in sorted(sources):
        entry = sources[folder]
        maker = entry["maker"]
        name = CURATED.get(folder) or from_urdf.name_from(
            "%s_%s" % (PREFIX[maker], entry["model"]) if PREFIX[maker] else entry["model"])
        source = "%s@%s %s (%s)" % (entry["repository"], entry["commit"][:12], entry["entry"], folder)
        license = entry["package_license"] or entry["repo_license"]
        path = os.path.join(data_folder, folder, "robot.urdf")
        default_post, j23_factor = from_urdf.maker_defaults(maker, folder)
        try:
            imported = from_urdf.spec_from_urdf(
                path, name, maker=maker, model=entry["model"].upper(),
                payload_kg=from_urdf.payload_from_model(maker, entry["model"]), j23_factor=j23_factor,
                default_post=default_post, source=source, license=license)
        except InputError as exc:
            counts[(maker, "other")] += 1
            report.append((folder, maker, "other", "-", str(exc).split(": ", 1)[-1]))
            continue
        kind = models.kinematic_class(imported.spec)
        counts[(maker, kind)] += 1
        if folder in CURATED:
            report.append((folder, maker, kind, name, "in the hand-written catalog"))
            continue
        meshes = ""
        if os.path.isdir(os.path.join(data_folder, folder, "collision")):
            spec, _missing = from_urdf.write_meshes(imported, os.path.join(meshes_folder, name + ".npz"))
            meshes = "meshes/%s.npz" % name if spec.meshes else ""
        rows.append(catalog_table.row_from_spec(imported.spec, meshes))
        report.append((folder, maker, kind, name, "%.1e mm, %.1e rad" % (imported.worst_mm,
                                                                          imported.worst_rad)))
    catalog_table.write_table(os.path.join(RESOURCES, "catalog.csv"), rows)
    _write_report(report, counts)
    return rows, counts


def _write_report(report, counts):
    makers_seen = sorted({maker for maker, _ in counts})
    kinds = [kind for kind, _label, _method in CLASSES]
    lines = ["# Robot catalog: the arms of the data folder and their kinematic class", "",
             "Made by `tools/build_catalog.py`; do not edit by hand.", "",
             "How the inverse kinematics of each class is solved (every solution):", ""]
    lines += ["* %s: %s" % (label, method) for kind, label, method in CLASSES if kind != "other"]
    lines += ["", "| maker | %s | total |" % " | ".join(label for _k, label, _m in CLASSES),
              "|---|%s---|" % ("---|" * len(CLASSES))]
    for maker in makers_seen:
        row = [counts[(maker, kind)] for kind in kinds]
        lines.append("| %s | %s | %d |" % (maker, " | ".join(map(str, row)), sum(row)))
    totals = [sum(counts[(m, kind)] for m in makers_seen) for kind in kinds]
    lines += ["| all | %s | %d |" % (" | ".join(map(str, totals)), sum(totals)), "",
              "| folder | maker | class | inverse kinematics | catalog name | model vs URDF chain "
              "(1001 joint sets) or why not in the table |", "|---|---|---|---|---|---|"]
    lines += ["| %s | %s | %s | %s | %s | %s |" % (folder, maker, kind, METHOD[kind], name, text)
              for folder, maker, kind, name, text in report]
    with open(DOC, "w", encoding="utf-8") as stream:
        stream.write("\n".join(lines) + "\n")


def main(argv):
    if len(argv) != 2 or not os.path.isfile(os.path.join(argv[1], "sources.json")):
        sys.stderr.write("usage: python3 tools/build_catalog.py DATA_FOLDER (the robot data folder, "
                         "with sources.json and one folder per arm)\n")
        return 2
    data_folder = argv[1]
    rows, counts = build(data_folder)
    print("%d rows written to %s" % (len(rows), os.path.relpath(os.path.join(RESOURCES, "catalog.csv"))))
    for key, count in sorted(counts.items()):
        print("  %-18s %-16s %d" % (key[0], key[1], count))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
