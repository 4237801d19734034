"""Install CadRobot's Python dependencies with FreeCAD 1.x's own Addon Manager code.

Run inside FreeCADCmd (``freecadcmd -c "exec(open(PATH).read())"``) with the
environment variable ``CADROBOT_PACKAGE_XML`` naming the installed copy's
``package.xml``.  It does what the Addon Manager's install dialog does, without
the dialog: reads ``package.xml`` with the Addon Manager's metadata reader
(``Addon.load_metadata_file``), lists the Python packages that are not
installed yet (``MissingDependencies``), drops those not on its allow-list
(``ALLOWED_PYTHON_PACKAGES.txt``, or the file ``CADROBOT_ALLOW_LIST`` names; the
dialog tells the user to install those by hand, and ignores optional ones), and runs its ``DependencyInstaller``, which
calls ``python -m pip install --target <AdditionalPythonPackages/pyXY> NAME``.

One difference, from DESIGN.md: the pip constraints file FreeCAD 1.1's Addon
Manager adds is on a host this machine cannot reach, so its preference is emptied
first (1.0 has no such preference).
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

try:
    fci.Preferences().set("pip_constraints_path", "")
except RuntimeError:   # FreeCAD 1.0's Addon Manager adds no constraints file
    pass

addon = Addon.Addon("CadRobot", "https://github.com/cadrobot/CadRobot",
                    Addon.Addon.Status.NOT_INSTALLED, "main")
addon.load_metadata_file(os.environ["CADROBOT_PACKAGE_XML"])
try:                                         # FreeCAD 1.1
    missing = Addon.MissingDependencies()
    missing.import_from_addon(addon, [addon])
except TypeError:                            # FreeCAD 1.0: the constructor does the work
    missing = Addon.MissingDependencies(addon, [addon])

# Online, the Addon Manager reads the allow-list from FreeCAD-addons' master branch;
# offline, the copy it ships. CADROBOT_ALLOW_LIST names a newer copy to stand in for the
# online one where the shipped copy is older than it (FreeCAD 1.0's lacks trimesh).
allow_list = os.environ.get("CADROBOT_ALLOW_LIST")
if allow_list:
    with open(allow_list, encoding="utf-8") as handle:
        allowed = {line.strip().lower() for line in handle
                   if line.strip() and not line.startswith("#")}
else:
    AddonInstaller._load_local_allowed_packages_list()
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
