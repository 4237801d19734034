"""Install CadRobot's Python dependencies with FreeCAD 1.x's own Addon Manager code.

Run inside FreeCADCmd (``freecadcmd -c "exec(open(PATH).read())"``) with the
environment variable ``CADROBOT_PACKAGE_XML`` naming the installed copy's
``package.xml``.  It does what the Addon Manager's install dialog does, without
the dialog: reads ``package.xml`` with the Addon Manager's metadata reader
(``Addon.load_metadata_file``), lists the Python packages that are not
installed yet (``MissingDependencies``), drops those not on its allow-list
(``ALLOWED_PYTHON_PACKAGES.txt``; the dialog tells the user to install those by
hand, and ignores optional ones), and runs its ``DependencyInstaller``, which
calls ``python -m pip install --target <AdditionalPythonPackages/pyXY> NAME``.

One difference, from DESIGN.md: the pip constraints file the Addon Manager adds
is on a host this machine cannot reach, so its preference is emptied first.
Prints one line ``CADROBOT_AM {json}`` with what happened.
"""

import json
import os

import FreeCAD

import Addon
import addonmanager_freecad_interface as fci
import addonmanager_utilities as utils
from addonmanager_dependency_installer import DependencyInstaller
from addonmanager_installer import AddonInstaller

fci.Preferences().set("pip_constraints_path", "")

addon = Addon.Addon("CadRobot", "https://github.com/cadrobot/CadRobot",
                    Addon.Addon.Status.NOT_INSTALLED, "main")
addon.load_metadata_file(os.environ["CADROBOT_PACKAGE_XML"])
missing = Addon.MissingDependencies()
missing.import_from_addon(addon, [addon])

AddonInstaller._load_local_allowed_packages_list()  # offline: the copy FreeCAD ships
allowed = AddonInstaller.allowed_packages
required = [name for name in missing.python_requires if name.lower() in allowed]
optional = [name for name in missing.python_optional if name.lower() in allowed]

failures = []
installer = DependencyInstaller([], required, optional)
installer.failure.connect(lambda title, detail: failures.append("%s: %s" % (title, detail)))
installer.run()

print("CADROBOT_AM " + json.dumps({
    "declared_required": sorted(addon.python_requires),
    "declared_optional": sorted(addon.python_optional),
    "installed": required + optional,
    "not_allowed": sorted(set(missing.python_requires + missing.python_optional)
                          - set(required + optional)),
    "target": utils.get_pip_target_directory(),
    "failures": failures,
    "freecad": ".".join(FreeCAD.Version()[:3]),
}), flush=True)
