"""The tests leave a user's FreeCAD data as they found it, and pass whatever it holds.

A user who has worked with CadRobot has robots imported from URDF files (one of them
under the name a test imports, ``MY_TX60``), a user post in the macro folder, a post
folder and a default post in the preferences, and a team robot folder named by
``$CADROBOT_ROBOT_FOLDER``. The tests that import robots, write preferences and user posts
run here as ``make test`` runs them (``tools/run_pytest_in_freecad.py``), as that user:
they pass, and every file of the user's FreeCAD folder and of the team folder is
unchanged afterwards.
"""

import hashlib
import os
import shutil
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DATA = os.path.join(REPO, "tests", "data", "robots")
sys.path.insert(0, os.path.join(REPO, "tools"))
from run_pytest_in_freecad import user_data_dir  # noqa: E402  (the runner's own question)

#: The tests that touch user data: imported robots, preferences, user posts in the macro
#: folder and the post folder, the New cell panel's robot table.
APP_TESTS = ["tests/app/test_import_robot.py", "tests/app/test_gui_api.py",
             "-k", "not every_opw_and_ur_arm and (import or refused or cli or edited or linkage "
                   "or preferences)"]
GUI_TESTS = ["tests/gui/test_new_cell_panel.py", "tests/gui/test_generate_and_preferences.py",
             "-k", "import or user_post or preferences_page or default_post"]

USER_SETUP = r"""
import os, sys
sys.path.insert(0, %(repo)r)
import FreeCAD
from CadRobotWB import api, preferences
for folder, name in (("staubli_tx2_60", "MY_TX60"), ("kuka_kr6_r900_2", "SHOP_KR6"),
                     ("abb_irb1600_6_12", "SHOP_IRB1600")):
    api.import_robot(os.path.join(%(data)r, folder, "robot.urdf"), name=name)
macros = FreeCAD.getUserMacroDir(True)
os.makedirs(macros, exist_ok=True)
with open(os.path.join(macros, "shop_post.py"), "w") as post:
    post.write("def export(program, options):\n    return [('shop.txt', program.name)]\n")
preferences.set("DefaultPost", "kuka_krl")
preferences.set("PostFolder", os.path.join(FreeCAD.getUserAppDataDir(), "posts"))
print("CADROBOT_MACRO " + macros)
"""


def freecadcmd():
    return shutil.which("freecadcmd") or shutil.which("FreeCADCmd")


def snapshot(folder):
    """{path relative to folder: sha256 of the file, or the link's target}."""
    found = {}
    for root, dirs, files in os.walk(folder):
        for name in dirs + files:
            path = os.path.join(root, name)
            key = os.path.relpath(path, folder)
            if os.path.islink(path):
                found[key] = "-> " + os.readlink(path)
                if name in dirs:
                    dirs.remove(name)                         # not into Mod/CadRobot's checkout
            elif os.path.isfile(path):
                with open(path, "rb") as stream:
                    found[key] = hashlib.sha256(stream.read()).hexdigest()
    return found


def test_the_tests_pass_and_leave_a_used_user_folder_unchanged(tmp_path):
    home = tmp_path / "home"
    home.mkdir()
    team = tmp_path / "team_robots"
    team.mkdir()
    shutil.copy(os.path.join(REPO, "CadRobotWB", "resources", "robots", "catalog.csv"),
                team / "TEAM.csv")                             # a table file the team keeps
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "CADROBOT_ROBOT_FOLDER")}
    env["FREECAD_USER_HOME"] = str(home)
    packages = os.path.join(user_data_dir(dict(os.environ)), "AdditionalPythonPackages")
    # The user's FreeCAD: CadRobot and its packages where the Addon Manager puts them.
    data = user_data_dir(env)
    assert data.startswith(str(home)), data
    os.makedirs(os.path.join(data, "Mod"), exist_ok=True)
    os.symlink(REPO, os.path.join(data, "Mod", "CadRobot"))
    os.symlink(packages, os.path.join(data, "AdditionalPythonPackages"))
    used = subprocess.run([freecadcmd(), "-c", USER_SETUP % {"repo": REPO, "data": DATA}],
                          env=env, capture_output=True, text=True, timeout=600, cwd="/")
    macros = [l[15:] for l in used.stdout.splitlines() if l.startswith("CADROBOT_MACRO ")]
    assert macros, used.stdout[-2000:] + used.stderr[-2000:]
    assert os.path.isfile(os.path.join(macros[0], "shop_post.py"))
    assert macros[0].startswith(str(home))
    robots = sorted(os.listdir(os.path.join(data, "CadRobot", "robots")))
    assert "MY_TX60.csv" in robots and len(robots) == 6, robots
    before_home, before_team = snapshot(str(home)), snapshot(str(team))
    assert any(key.endswith("user.cfg") for key in before_home), sorted(before_home)

    env["CADROBOT_ROBOT_FOLDER"] = str(team)
    runner = [sys.executable, os.path.join(REPO, "tools", "run_pytest_in_freecad.py"), "--workers", "1"]
    for gui, tests in (([], APP_TESTS), (["--gui"], GUI_TESTS)):
        run = subprocess.run(runner + gui + tests + ["-q"], env=env, cwd=REPO,
                             capture_output=True, text=True, timeout=1800)
        print(run.stdout[-1500:])
        assert run.returncode == 0, run.stdout[-4000:] + run.stderr[-2000:]
        assert " passed" in run.stdout and " 0 failed" in run.stdout

    after_home = snapshot(str(home))
    changed = sorted(k for k in set(before_home) | set(after_home) if before_home.get(k) != after_home.get(k))
    assert changed == [], changed
    assert snapshot(str(team)) == before_team
