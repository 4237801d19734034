"""The workbench assumes no POSIX system: Windows and macOS users run it too.

* no shell-outs and no hard-coded ``/tmp`` anywhere in ``CadRobotWB/`` (only
  ``package_install.py`` starts a process: pip, from an argument list);
* optional packages are imported only through ``dependencies``;
* every post writes file names Windows accepts, whatever the labels;
* the sweep's local workers give the same result when spawned (Windows,
  macOS) as when forked (Linux).
"""

import ast
import json
import os
import re

import numpy as np
import pytest

from CadRobotWB import limits, sweep
from CadRobotWB.cli import split_command_line
from CadRobotWB.core import program as ir
from CadRobotWB.core.trajectory import tcp_trajectory
from CadRobotWB.errors import InputError, PostError
from CadRobotWB.posts import abb_rapid, fanuc_ls, kuka_krl, motoman_inform, ur_script
from CadRobotWB.sensors.scene import RobotSetup, SensorScene
from CadRobotWB.sensors.seam_features import JointTemplate

from post_programs import minimal_program

PACKAGE = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                       "CadRobotWB")


def package_sources():
    """(path relative to CadRobotWB, parsed module) of every .py file of the package."""
    for folder, _, files in os.walk(PACKAGE):
        for name in sorted(files):
            if name.endswith(".py"):
                path = os.path.join(folder, name)
                with open(path, encoding="utf-8") as handle:
                    yield os.path.relpath(path, PACKAGE), ast.parse(handle.read(), path)


SOURCES = list(package_sources())
SHELL_MODULES = {"subprocess", "pty", "commands"}
SHELL_CALLS = {"system", "popen", "spawnl", "spawnlp", "spawnv", "spawnvp", "execv", "execvp",
               "execl", "execlp", "execve", "fork", "forkpty", "startfile"}


def imported_modules(tree):
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            yield from ((node.lineno, alias.name) for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            yield node.lineno, node.module


def test_the_scan_sees_the_whole_package():
    names = {path for path, _ in SOURCES}
    assert {"cli.py", "sweep.py", os.path.join("posts", "common.py")} <= names and len(names) > 60


#: Modules that may start a process, and why: never a shell, an argument list only.
MAY_START_A_PROCESS = {
    "package_install.py": "pip with FreeCAD's own Python, as the Addon Manager runs it",
}


def test_no_shell_outs():
    found = []
    for path, tree in SOURCES:
        found += ["%s:%d imports %s" % (path, line, name) for line, name in imported_modules(tree)
                  if name.split(".")[0] in SHELL_MODULES and path not in MAY_START_A_PROCESS]
        for node in ast.walk(tree):
            if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
                    and node.value.id == "os" and node.attr in SHELL_CALLS):
                found.append("%s:%d uses os.%s" % (path, node.lineno, node.attr))
            if isinstance(node, ast.keyword) and node.arg == "shell":
                found.append("%s:%d passes shell=" % (path, node.value.lineno))
    assert found == []


def test_no_hard_coded_posix_temp_folder():
    found = ["%s:%d %r" % (path, node.lineno, node.value) for path, tree in SOURCES
             for node in ast.walk(tree)
             if isinstance(node, ast.Constant) and isinstance(node.value, str)
             and re.search(r"(^|[\s'\"=])/(tmp|var/tmp)(/|$|\s)", node.value)]
    assert found == []


def test_optional_packages_are_imported_only_through_dependencies():
    """``import fcl`` would fail where python-fcl is missing: go through
    dependencies.import_optional / require, which say what to install.  A
    submodule (``matplotlib.pyplot``, ``trimesh.collision``) may follow
    them in a module that uses ``dependencies``."""
    packages = {"fcl", "matplotlib", "dask", "distributed", "trimesh"}
    found = []
    for path, tree in SOURCES:
        guarded = any(name == "dependencies" for node in ast.walk(tree)
                      if isinstance(node, ast.ImportFrom) for name in (a.name for a in node.names))
        for line, name in imported_modules(tree):
            top = name.split(".")[0]
            if top in packages and (name == top or name == "dask.distributed" or not guarded):
                found.append("%s:%d imports %s" % (path, line, name))
    assert found == []


def test_cli_run_takes_windows_paths_and_quoted_words_as_written():
    assert split_command_line(r'export "C:\My parts\weld.FCStd" -o D:\out --json') == \
        ["export", r"C:\My parts\weld.FCStd", "-o", r"D:\out", "--json"]
    assert split_command_line("check 'a b.FCStd'") == ["check", "a b.FCStd"]
    with pytest.raises(InputError, match="quote that is not closed"):
        split_command_line('check "a.FCStd')


# --- file names ---------------------------------------------------------------------

POSTS = {abb_rapid: "ABB_IRB2400", kuka_krl: "KUKA_KR16", ur_script: "UR5E",
         fanuc_ls: "MOTOMAN_HP6", motoman_inform: "MOTOMAN_HP6"}
DEVICES = {"CON", "PRN", "AUX", "NUL"} | {p + d for p in ("COM", "LPT") for d in "123456789"}
AWKWARD_LABELS = ["CON", "con", "aux.mod", "Nul.txt", "COM1", "lpt9", "a:b", "x.", "y ", 'q"<>|?*',
                  "tab\there", "back\\slash", "a/b"]


def is_windows_file_name(name):
    """Windows' rules, written out independently of the posts."""
    return (bool(name) and not re.search(r'[<>:"/\\|?*\x00-\x1f]', name)
            and not name.endswith((".", " "))
            and name.split(".")[0].rstrip(" ").upper() not in DEVICES)


@pytest.mark.parametrize("post", POSTS, ids=lambda m: m.NAME)
@pytest.mark.parametrize("label", AWKWARD_LABELS)
def test_every_post_writes_file_names_windows_accepts(post, label):
    files = post.export(minimal_program(POSTS[post], name=label), {})
    names = [name for name, _ in files]
    assert all(is_windows_file_name(name) for name in names), names
    assert all(name.endswith(post.FILE_EXTENSIONS) for name in names)


@pytest.mark.parametrize("post", [kuka_krl, fanuc_ls, motoman_inform], ids=lambda m: m.NAME)
def test_a_program_named_con_keeps_its_name_and_file_name_equal(post):
    """KRL, LS and INFORM want the program's name to be its file's name."""
    name, text = post.export(minimal_program(POSTS[post], name="CON"), {})[0]
    stem = name.rsplit(".", 1)[0]
    assert stem.upper() == "CON_" and re.search(r"\b%s\b" % stem, text)


@pytest.mark.parametrize("post, option", [(kuka_krl, "program_name"), (fanuc_ls, "program_name"),
                                          (motoman_inform, "job_name")], ids=lambda v: str(v))
def test_a_requested_device_name_is_refused(post, option):
    with pytest.raises(PostError, match="cannot be a file name on Windows"):
        post.export(minimal_program(POSTS[post]), {option: "LPT1"})


def test_a_valid_name_is_unchanged():
    assert abb_rapid.export(minimal_program("ABB_IRB2400", name="SeamWeld"), {})[0][0] == "SeamWeld.mod"


# --- sweep workers -------------------------------------------------------------------

def seam_scene():
    """A 60 mm butt seam (two plates on a table) 900 mm in front of an IRB 2400, 700 mm up."""
    import trimesh

    def box(low, high):
        low, high = np.asarray(low, float), np.asarray(high, float)
        return trimesh.creation.box(high - low, trimesh.transformations.translation_matrix((low + high) / 2))

    down = np.diag([1.0, -1.0, -1.0])
    moves = []
    for k, x in enumerate((0.0, 60.0)):
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = down, (x, 0.0, 8.0)
        moves.append(ir.Move(ir.JOINT if k == 0 else ir.LINEAR, ir.Target("p%d" % k, T),
                             10.0, 0.0, "B"))
    program = ir.Program("P", "ABB_IRB2400", ir.ToolData("t", np.eye(4)),
                         {"B": ir.WorkFrame("B", np.eye(4), np.eye(4))}, [ir.ProgramPath("p", "p", moves)])
    plates = trimesh.util.concatenate([box((-50, -100, 0), (120, -0.75, 8)),
                                       box((-50, 0.75, 0), (120, 100, 8)),
                                       box((-50, -100, -20), (120, 100, 0))])
    T_r_u = np.eye(4)
    T_r_u[:3, 3] = (900.0, 0.0, 700.0)
    return SensorScene("laser", "p", tcp_trajectory(program, 0.01, first_move=1), [("Plates", plates)],
                       RobotSetup("ABB_IRB2400", T_r_u, np.eye(4)),
                       {"template": JointTemplate("butt", gap_mm=1.5)}, program)


@pytest.mark.skipif("fork" not in __import__("multiprocessing").get_all_start_methods(),
                    reason="no fork on this OS: spawn is the only way")
def test_spawned_sweep_workers_give_the_same_result_as_forked_ones(monkeypatch):
    monkeypatch.setattr(limits, "cores", lambda: 2)   # two processes on a 1-core machine too
    scene = seam_scene()
    deviations = sweep.sample_deviations({"y": (-3.0, 3.0), "rz": (-1.0, 1.0)}, 3, seed=4)
    forked = sweep.run_sweep(scene, deviations, workers=2, start_method="fork")
    spawned = sweep.run_sweep(scene, deviations, workers=2, start_method="spawn")
    assert json.dumps(spawned) == json.dumps(forked)      # NaN residuals compare equal as text
    assert [r["success"] for r in forked] == [True, True, True]
