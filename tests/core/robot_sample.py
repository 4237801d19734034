"""Which catalog robots the per-robot tests run on.

The hand-written robots (each has its own conventions and reference numbers)
and one arm of the catalog table per maker and kinematic class (OPW, UR, or an
arm of kind "chain": offset or spherical wrist, issue 24): the table's
rows differ only in numbers, and ``test_catalog_table.py`` compares every row
with its URDF.  Running every per-robot test on all 150 arms would take
minutes and check nothing more.
"""

from CadRobotWB.robots.catalog import catalog


def sample_names():
    """list of str: catalog names, hand-written first."""
    names = catalog.hand_written_names()
    seen = set()
    for spec in catalog.specs():
        key = (spec.manufacturer, spec.opw is not None, spec.chain is not None)
        if spec.name not in names and key not in seen:
            seen.add(key)
            names.append(spec.name)
    return names


def hand_written_names():
    """list of str: the robots whose link solids are CadRobot's simple solids."""
    return catalog.hand_written_names()
