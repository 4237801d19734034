"""The Python packages CadRobot needs beyond FreeCAD, and what a missing one costs.

trimesh is required: without it CadRobot cannot work, and :func:`require`
raises a :class:`~CadRobotWB.errors.MissingPackageError` that says how to
install it.  The others are optional: a missing one costs only its feature.

=========== ================== ===============================================
package     imported as        without it
=========== ================== ===============================================
trimesh     ``trimesh``        nothing works (required)
python-fcl  ``fcl``            collisions are not checked
matplotlib  ``matplotlib``     simulate and sweep write no plots (PNG)
distributed ``dask.distributed`` sweep cannot run on a Dask cluster
=========== ================== ===============================================

::

    fcl = dependencies.import_optional("python-fcl")    # the module, or None
    if fcl is None:
        dependencies.warn_missing("python-fcl")         # once per session

A warning goes to FreeCAD's Report view in the GUI
(``FreeCAD.Console.PrintWarning``) and is one line on stderr elsewhere (the
CLI, plain Python).  Pure Python: this module never imports FreeCAD; it only
looks whether the running process has loaded it (``sys.modules``).
"""

import importlib
import re
import sys
from dataclasses import dataclass

from .errors import MissingPackageError

#: The folder FreeCAD puts on ``sys.path`` for packages installed for its Python
#: (the Addon Manager's pip target; on FreeCAD 1.x a per-Python subfolder ``pyXY``).
PACKAGES_FOLDER_NAME = "AdditionalPythonPackages"


@dataclass(frozen=True)
class Package:
    """A Python package CadRobot uses.

    Attributes
    ----------
    name : str
        The name pip installs it by.
    module : str
        The module CadRobot imports.
    lost : str
        What does not happen without it (starts a warning).
    addon_manager : bool
        Whether FreeCAD's Addon Manager installs it (it installs only the packages
        on its allow-list, FreeCAD-addons' ``ALLOWED_PYTHON_PACKAGES.txt``).
    """

    name: str
    module: str
    lost: str
    addon_manager: bool


PACKAGES = {package.name: package for package in (
    Package("trimesh", "trimesh", "CadRobot cannot run", True),
    Package("python-fcl", "fcl", "collisions not checked", False),
    Package("matplotlib", "matplotlib", "plots not written", True),
    Package("distributed", "dask.distributed", "no sweep on a Dask cluster", False),
)}

#: The package each check left out needs (keys of a report's ``not_checked``).
CHECK_PACKAGES = {"collisions": "python-fcl"}

_warned = set()        # package names warned about in this session
_failures = {}         # package name -> why its import failed


def import_optional(name):
    """Import package `name` (a key of :data:`PACKAGES`) if it can be.

    Parameters
    ----------
    name : str

    Returns
    -------
    module or None
        None when it is not installed or fails to import; :func:`reason`
        then says why and how to install it.
    """
    package = PACKAGES[name]
    try:
        return importlib.import_module(package.module)
    except ImportError as error:
        _failures[name] = "" if isinstance(error, ModuleNotFoundError) else str(error)
    except Exception as error:  # noqa: BLE001 -- a broken install must cost only its feature
        _failures[name] = "%s: %s" % (type(error).__name__, error)
    return None


def is_available(name):
    """bool: package `name` can be imported."""
    return import_optional(name) is not None


def require(name):
    """Import required package `name`, or raise MissingPackageError.

    Returns
    -------
    module

    Raises
    ------
    MissingPackageError
        It is not installed (the message says how to install it).
    """
    module = import_optional(name)
    if module is None:
        raise MissingPackageError("%s: %s" % (PACKAGES[name].lost, reason(name)))
    return module


def forget_failure(name):
    """Import package `name` again (after installing it): the module, or None.

    Forgets the earlier failure and, when it imports, the warning given, so
    :func:`reason` and :func:`warn_missing` speak of the present state.
    """
    _failures.pop(name, None)
    module = import_optional(name)
    if module is not None:
        _warned.discard(name)
    return module


def packages_folder(sys_path=None):
    """FreeCAD's folder for the packages of its Python, if it is on `sys_path`.

    Parameters
    ----------
    sys_path : list of str, optional
        Default ``sys.path``.

    Returns
    -------
    str or None
        The most specific entry (``.../AdditionalPythonPackages/py311`` on
        FreeCAD 1.x over its parent); None outside FreeCAD.
    """
    found = [p for p in (sys.path if sys_path is None else sys_path)
             if PACKAGES_FOLDER_NAME in re.split(r"[\\/]", p)]
    return max(found, key=len).rstrip("/\\") if found else None


def install_hint(name, sys_path=None):
    """How to install package `name` for the running Python (str)."""
    python = "python%d.%d" % sys.version_info[:2]
    folder = packages_folder(sys_path)
    if folder is None:
        return "install it with `%s -m pip install %s`" % (python, name)
    pip = "`%s -m pip install --target \"%s\" %s`" % (python, folder, name)
    if PACKAGES[name].addon_manager:
        return "install it with the Addon Manager (CadRobot's dependencies) or %s" % pip
    in_gui = getattr(sys.modules.get("FreeCAD"), "GuiUp", False)
    button = ("press 'Install %s' in Check cell's result, or " % name
              if in_gui and name in CHECK_PACKAGES.values() else "")
    return ("the Addon Manager does not install it (not on its allow-list); %sinstall it with %s"
            % (button, pip))


def state(name):
    """Package `name`'s trouble, e.g. "python-fcl is not installed" (str)."""
    why = _failures.get(name)
    return "%s %s" % (name, "cannot be imported (%s)" % why if why else "is not installed")


def reason(name, sys_path=None):
    """Why package `name` is missing and how to install it (str)."""
    whose = "FreeCAD's Python" if "FreeCAD" in sys.modules else "this Python"
    return "%s for %s %d.%d; %s" % (state(name), whose, sys.version_info[0],
                                    sys.version_info[1], install_hint(name, sys_path))


def headline(not_checked):
    """The first line of a result that left checks out, or None when none was.

    Parameters
    ----------
    not_checked : dict of str to str
        A report's ``not_checked`` (check -> why).

    Returns
    -------
    str or None
        E.g. "Collisions NOT checked: python-fcl is not installed."
    """
    if not not_checked:
        return None
    parts = []
    for check in not_checked:
        package = CHECK_PACKAGES.get(check)
        parts.append("%s NOT checked%s" % (check.capitalize(),
                                           ": " + state(package) if package else ""))
    return "; ".join(parts) + "."


def missing_message(name):
    """The warning for missing package `name`: what is lost, why, the fix (str)."""
    return "%s: %s" % (PACKAGES[name].lost, reason(name))


def warn_missing(name):
    """Say once per session that package `name` is missing; return the message.

    In FreeCAD's GUI the warning goes to the Report view, elsewhere it is one
    line on stderr.

    Returns
    -------
    str
        :func:`missing_message` (also on later calls, which print nothing).
    """
    message = missing_message(name)
    if name not in _warned:
        _warned.add(name)
        _report_warning(message)
    return message


def _report_warning(message):
    freecad = sys.modules.get("FreeCAD")
    if freecad is not None and getattr(freecad, "GuiUp", False):
        freecad.Console.PrintWarning("CadRobot: %s\n" % message)
    else:
        sys.stderr.write("cadrobot: warning: %s\n" % message)
        sys.stderr.flush()
