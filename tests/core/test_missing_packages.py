"""A missing package costs only its feature, says so once, and says how to install it.

Each "not installed" case runs in a fresh Python where the package's import
is blocked (``sys.modules[name] = None`` makes ``import name`` fail), so the
modules under test import exactly as they would on a user's machine.
"""

import re
import subprocess
import sys
import textwrap
import types

import pytest

from CadRobotWB import dependencies
from CadRobotWB.errors import MissingPackageError
from CadRobotWB.robots.checks import checks

FAKE_PACKAGES = "/home/u/.local/share/FreeCAD/AdditionalPythonPackages/py311"


def run_without(modules, code):
    """Run `code` in a new Python in which `modules` cannot be imported; its stdout."""
    prelude = "import sys\nfor name in %r:\n    sys.modules[name] = None\n" % (list(modules),)
    run = subprocess.run([sys.executable, "-c", prelude + textwrap.dedent(code)],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    return run.stdout


def test_without_fcl_the_collision_checker_says_what_to_install():
    out = run_without(["fcl"], """
        from CadRobotWB.errors import MissingPackageError
        from CadRobotWB.robots.checks import collision
        assert not collision.is_available()
        try:
            collision.RobotCollisionChecker("ABB_IRB2400", [])
        except MissingPackageError as error:
            print(error)
    """)
    assert out.startswith("collisions not checked: python-fcl is not installed for this Python")
    assert "-m pip install " in out and out.endswith(" python-fcl`\n")


def test_without_matplotlib_there_are_no_plots_and_the_rest_imports():
    out = run_without(["matplotlib"], """
        import numpy as np
        from CadRobotWB import report_plots, sweep
        from CadRobotWB.errors import MissingPackageError
        print(report_plots.is_available())
        try:
            report_plots.plot_sweep(np.ones(2), np.ones(2), [True, False])
        except MissingPackageError as error:
            print(error)
    """)
    available, message = out.splitlines()
    assert available == "False"
    assert message.startswith("plots not written: matplotlib is not installed")


def test_without_dask_a_cluster_sweep_is_a_clear_error_and_a_local_one_is_not_affected():
    out = run_without(["dask", "distributed"], """
        import types
        from CadRobotWB import sweep
        from CadRobotWB.errors import MissingPackageError
        scene = types.SimpleNamespace(sensor="laser")
        print(sweep.run_sweep(scene, [], workers=1))
        try:
            sweep.run_sweep(scene, [], scheduler="local")
        except MissingPackageError as error:
            print(error)
    """)
    local, message = out.splitlines()
    assert local == "[]"
    assert message.startswith("no sweep on a Dask cluster: distributed is not installed")
    assert message.endswith("or run the sweep without a scheduler, on this computer's cores.")


def test_without_trimesh_importing_the_robots_is_an_error_pointing_at_the_addon_manager():
    out = run_without(["trimesh"], """
        import sys
        sys.path.append(%r)
        from CadRobotWB.errors import MissingPackageError
        try:
            from CadRobotWB.robots.checks import links
        except MissingPackageError as error:
            print(type(error).__name__, error)
    """ % FAKE_PACKAGES)
    assert out.startswith("MissingPackageError CadRobot cannot run: trimesh is not installed")
    assert "install it with the Addon Manager (CadRobot's dependencies)" in out
    # The folder is the AdditionalPythonPackages entry of that Python's sys.path (which one
    # is test_the_install_hint_names_freecads_packages_folder's business).
    assert re.search(r'--target "[^"]*AdditionalPythonPackages[^"]*" trimesh`', out)


def test_the_install_hint_names_freecads_packages_folder():
    path = ["/usr/lib/python3", "/home/u/.local/share/FreeCAD/AdditionalPythonPackages",
            FAKE_PACKAGES, "/home/u/.local/share/FreeCAD/Mod/CadRobot"]
    assert dependencies.packages_folder(path) == FAKE_PACKAGES      # the per-Python one (1.x)
    assert dependencies.packages_folder(path[:2]) == path[1]         # 0.20
    assert dependencies.packages_folder(["/usr/lib/python3"]) is None
    hint = dependencies.install_hint("python-fcl", path)
    python = "python%d.%d" % sys.version_info[:2]
    assert hint == ('the Addon Manager does not install it (not on its allow-list); install it '
                    'with `%s -m pip install --target "%s" python-fcl`' % (python, FAKE_PACKAGES))
    assert dependencies.install_hint("matplotlib", path) == (
        'install it with the Addon Manager (CadRobot\'s dependencies) or `%s -m pip install '
        '--target "%s" matplotlib`' % (python, FAKE_PACKAGES))
    windows = "C:\\Users\\u\\AppData\\Roaming\\FreeCAD\\AdditionalPythonPackages\\"
    assert dependencies.packages_folder([windows]) == windows.rstrip("\\")


@pytest.fixture
def fresh_warnings(monkeypatch):
    monkeypatch.setattr(dependencies, "_warned", set())


def test_a_warning_is_one_stderr_line_once_per_session(fresh_warnings, capsys, monkeypatch):
    monkeypatch.delitem(sys.modules, "FreeCAD", raising=False)
    first = dependencies.warn_missing("python-fcl")
    second = dependencies.warn_missing("python-fcl")
    assert first == second and first.startswith("collisions not checked: python-fcl ")
    assert capsys.readouterr().err == "cadrobot: warning: %s\n" % first


def test_in_the_gui_the_warning_goes_to_the_report_view(fresh_warnings, capsys, monkeypatch):
    printed = []
    gui = types.SimpleNamespace(GuiUp=True, Console=types.SimpleNamespace(PrintWarning=printed.append))
    monkeypatch.setitem(sys.modules, "FreeCAD", gui)
    message = dependencies.warn_missing("matplotlib")
    dependencies.warn_missing("matplotlib")
    assert printed == ["CadRobot: %s\n" % message]
    assert "for FreeCAD's Python" in message
    assert capsys.readouterr().err == ""


def test_a_check_left_out_is_the_first_line_and_in_the_dict_but_does_not_fail_it():
    report = checks.Report(robot="ABB_IRB2400", targets=3, moves=2)
    report.findings.append(checks.Finding("singularity", "warning", "T2", 1, "Path", "near the wrist"))
    report.not_checked["collisions"] = dependencies.reason("python-fcl")
    assert report.ok
    lines = report.lines()
    assert lines[0].startswith("NOT CHECKED: collisions: python-fcl ")     # before the findings
    assert lines[1] == "WARNING: singularity: near the wrist"
    assert lines[-1] == "OK: 3 targets, 2 moves: 0 errors, 1 warnings."
    assert report.to_dict()["not_checked"] == {"collisions": report.not_checked["collisions"]}


def test_place_robot_says_first_that_collisions_were_left_out():
    from CadRobotWB.robots.placement import placement_search
    found = placement_search.Placements(not_checked={"collisions": "python-fcl is not installed"})
    lines = found.lines()
    assert lines[0] == "NOT CHECKED: collisions: python-fcl is not installed"
    assert lines[1].startswith("0 candidate bases")


def test_require_raises_a_cadrobot_error_for_a_missing_required_package(monkeypatch):
    monkeypatch.setitem(sys.modules, "trimesh", None)
    with pytest.raises(MissingPackageError, match="trimesh is not installed"):
        dependencies.require("trimesh")
