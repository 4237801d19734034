#!/usr/bin/env python3
"""Run pytest inside FreeCAD (App tier) or inside the real FreeCAD GUI under Xvfb.

    /usr/bin/python3 tools/run_pytest_in_freecad.py [--gui] [--allow-empty]
        [--timeout SEC] TESTDIR [PYTEST ARGS...]

* App tier: pytest runs inside ``freecadcmd``; ``FreeCAD``, ``Part``,
  ``Sketcher`` import as in a user's FreeCADCmd (AdditionalPythonPackages on
  sys.path, Mod folders loaded).
* ``--gui``: pytest runs inside the ``freecad`` binary on a private Xvfb
  display, after the main window is up and its event loop runs, so
  ``FreeCAD.GuiUp`` is true, ``FreeCADGui.getMainWindow()`` is a real window
  and ``view.saveImage()`` renders with Mesa.

The exit status is pytest's.  pytest's 5 ("no tests collected") is a failure:
a tier that silently ran nothing must not look green.  ``--allow-empty``
relaxes that only when TESTDIR holds no test file at all (a tier not written
yet): it prints why and exits 0.  Arguments never pass through FreeCAD's
own option parser (see tools/freecad_run.py).
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.realpath(os.path.abspath(__file__))))
import freecad_run  # noqa: E402  (same folder)

PYTEST_NO_TESTS = 5


def _has_test_files(path):
    if os.path.isfile(path):
        return True
    for _root, _dirs, files in os.walk(path):
        for name in files:
            if name.endswith(".py") and (name.startswith("test_") or name.endswith("_test.py")):
                return True
    return False


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    gui, allow_empty, timeout = False, False, None
    while argv and argv[0] in ("--gui", "--allow-empty", "--timeout"):
        opt = argv.pop(0)
        if opt == "--gui":
            gui = True
        elif opt == "--allow-empty":
            allow_empty = True
        else:
            timeout = float(argv.pop(0))
    if not argv or argv[0].startswith("-"):
        sys.stderr.write(__doc__.split("\n\n")[1] + "\n")
        return 2
    testdir = argv[0]
    tier = "GUI" if gui else "App"
    if not os.path.exists(testdir):
        sys.stderr.write("run_pytest_in_freecad: %s does not exist\n" % testdir)
        return 2
    if not _has_test_files(testdir):
        if allow_empty:
            print("%s tier: no test files in %s yet -- nothing to run (allowed)" % (tier, testdir))
            return 0
        sys.stderr.write("%s tier: no test files in %s -- failing, a tier must run tests\n"
                         % (tier, testdir))
        return PYTEST_NO_TESTS
    print("%s tier: pytest %s inside %s" % (tier, " ".join(argv),
          "the FreeCAD GUI (xvfb)" if gui else "freecadcmd"), flush=True)
    code = freecad_run.run("module", "pytest", argv, gui=gui, timeout=timeout)
    if code == PYTEST_NO_TESTS:
        sys.stderr.write("%s tier: pytest collected no tests in %s -- failing\n" % (tier, testdir))
    return code


if __name__ == "__main__":
    sys.exit(main())
