#!/usr/bin/env python3
"""Run pytest inside FreeCAD (App tier) or inside the real FreeCAD GUI under Xvfb.

    /usr/bin/python3 tools/run_pytest_in_freecad.py [--gui] [--allow-empty]
        [--timeout SEC] [--workers N] [--save-durations] TESTDIR [PYTEST ARGS...]

* App tier: pytest runs inside ``freecadcmd``; ``FreeCAD``, ``Part``,
  ``Sketcher`` import as in a user's FreeCADCmd (AdditionalPythonPackages on
  sys.path, Mod folders loaded).
* ``--gui``: pytest runs inside the ``freecad`` binary on a private Xvfb
  display, after the main window is up and its event loop runs, so
  ``FreeCAD.GuiUp`` is true, ``FreeCADGui.getMainWindow()`` is a real window
  and ``view.saveImage()`` renders with Mesa.
* ``--workers N`` FreeCADs (default: one more than the CPUs this process may use) share
  the tier's test files (``tools/parallel_pytest.py``); GUI workers each have their own display.

Each FreeCAD runs with a user folder of its own (``FREECAD_USER_HOME``, a new
temporary folder, removed afterwards) holding only ``Mod/CadRobot`` (this checkout)
and a link to the real ``AdditionalPythonPackages``: preferences, imported robots,
user posts and macros the tests write go there, and the user's own are neither read
nor changed (``$CADROBOT_ROBOT_FOLDER`` and ``$CADROBOT_WELD_SCHEDULE_FOLDER`` are not
passed on either).

The exit status is pytest's.  pytest's 5 ("no tests collected") is a failure:
a tier that silently ran nothing must not look green.  ``--allow-empty``
relaxes that only when TESTDIR holds no test file at all (a tier not written
yet): it prints why and exits 0.  Arguments never pass through FreeCAD's
own option parser (see tools/freecad_run.py).
"""

import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.realpath(os.path.abspath(__file__)))
sys.path.insert(0, HERE)
import freecad_run  # noqa: E402  (same folder)
import parallel_pytest  # noqa: E402

PYTEST_NO_TESTS = 5
PACKAGES = "AdditionalPythonPackages"
#: Environment variables of the user's own CadRobot data, not passed to the tests.
USER_VARIABLES = ("CADROBOT_ROBOT_FOLDER", "CADROBOT_WELD_SCHEDULE_FOLDER")


def user_data_dir(env):
    """FreeCAD's user data folder (``getUserAppDataDir``) for environment `env`.

    The FreeCAD asked loads and saves its settings in a throw-away folder: a FreeCAD
    rewrites its user.cfg when it ends, and the user's must stay as it is."""
    with tempfile.TemporaryDirectory(prefix="cadrobot-ask-") as settings:
        command = freecad_run.build_command(gui=False)[:1] + [
            "-u", os.path.join(settings, "user.cfg"), "-s", os.path.join(settings, "system.cfg"),
            "-c", "import FreeCAD; print('CADROBOT_UAD ' + FreeCAD.getUserAppDataDir())"]
        run = subprocess.run(command, env=env, capture_output=True, text=True, timeout=300,
                             stdin=subprocess.DEVNULL, cwd="/")
    for line in run.stdout.splitlines():
        if line.startswith("CADROBOT_UAD "):
            return line[len("CADROBOT_UAD "):].rstrip("/")
    raise OSError("could not ask FreeCAD for its user folder: %s" % (run.stderr.strip() or run.stdout))


def private_user_env(env, packages_root):
    """(environment, home): `env` with FREECAD_USER_HOME a new folder whose FreeCAD user data
    has Mod/CadRobot (this checkout) and `packages_root` linked in."""
    home = tempfile.mkdtemp(prefix="cadrobot-user-")
    env = {k: v for k, v in env.items() if k not in USER_VARIABLES}
    env["FREECAD_USER_HOME"] = home
    data = user_data_dir(env)
    if not os.path.realpath(data).startswith(os.path.realpath(home)):
        shutil.rmtree(home, ignore_errors=True)
        raise OSError("this FreeCAD ignores FREECAD_USER_HOME (user data in %s)" % data)
    os.makedirs(os.path.join(data, "Mod"), exist_ok=True)
    os.symlink(freecad_run.REPO, os.path.join(data, "Mod", "CadRobot"))
    if os.path.isdir(packages_root):
        os.symlink(packages_root, os.path.join(data, PACKAGES))
    return env, home


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    options, argv = parallel_pytest.parse_options(
        argv, flags=("--gui", "--allow-empty", "--save-durations"), valued=("--timeout", "--workers"))
    gui, allow_empty = "--gui" in options, "--allow-empty" in options
    if not argv or argv[0].startswith("-"):
        sys.stderr.write(__doc__.split("\n\n")[1] + "\n")
        return 2
    testdir = argv[0]
    tier = "GUI" if gui else "App"
    if not os.path.exists(testdir):
        sys.stderr.write("run_pytest_in_freecad: %s does not exist\n" % testdir)
        return 2
    if not parallel_pytest.test_files(testdir):
        if allow_empty:
            print("%s tier: no test files in %s yet -- nothing to run (allowed)" % (tier, testdir))
            return 0
        sys.stderr.write("%s tier: no test files in %s -- failing, a tier must run tests\n"
                         % (tier, testdir))
        return PYTEST_NO_TESTS
    # A FreeCAD worker waits part of the time (CLI subprocesses, Xvfb, Qt timers): one more
    # worker than CPUs ended the App tier 16 % and the GUI tier 10 % sooner on 2 CPUs.
    if "--workers" not in options and not os.environ.get("CADROBOT_TEST_WORKERS"):
        options["--workers"] = parallel_pytest.default_workers() + 1
    workers = parallel_pytest.worker_count(options, testdir)
    print("%s tier: pytest %s inside %s, %d worker%s" % (
        tier, " ".join(argv), "the FreeCAD GUI (xvfb)" if gui else "freecadcmd", workers,
        "" if workers == 1 else "s"), flush=True)
    homes, envs = [], []
    try:
        freecad_run.build_command(gui)
        packages_root = os.path.join(user_data_dir(dict(os.environ)), PACKAGES)
        for number in range(workers):
            env, home = private_user_env(os.environ, packages_root)
            homes.append(home)
            env["CADROBOT_XVFB_SERVERNUM"] = str(99 + 10 * number)
            envs.append(env)
    except (OSError, subprocess.SubprocessError) as exc:
        for home in homes:
            shutil.rmtree(home, ignore_errors=True)
        sys.stderr.write("%s tier: %s\n" % (tier, exc))
        return 3
    runner = [sys.executable, os.path.join(HERE, "freecad_run.py")] + (["--gui"] if gui else [])
    command = runner + ["-m", "pytest", "-p", "tools.pytest_file_queue", "-p", "no:cacheprovider"] + argv
    timeout = float(options["--timeout"]) if "--timeout" in options else None
    try:
        return parallel_pytest.run_tier(tier, [command] * workers, envs, timeout=timeout,
                                        save_durations="--save-durations" in options)
    finally:
        for home in homes:
            shutil.rmtree(home, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
