"""Which catalog robots the per-robot tests run on.

The hand-written robots (each has its own conventions and reference numbers)
and one arm of the catalog table per maker and kinematic class: the table's
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
        if spec.chain is not None:
            # Issue 24: these arms' per-robot tests need the solvers (parts C, D) and their
            # families (part F); drop this `continue` when those are merged.
            continue
        key = (spec.manufacturer, spec.opw is not None)
        if spec.name not in names and key not in seen:
            seen.add(key)
            names.append(spec.name)
    return names


def hand_written_names():
    """list of str: the robots whose link solids are CadRobot's simple solids."""
    return catalog.hand_written_names()
