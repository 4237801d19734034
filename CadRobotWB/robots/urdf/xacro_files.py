"""Which files a xacro file may make CadRobot read: only its own folder's and package's.

The ``xacro`` package, asked to expand a file, reads every
``<xacro:include filename=...>`` wherever it points, resolves ``$(find PKG)``
through the ROS installation, reads environment variables (``$(env ...)``,
``$(optenv ...)``) and YAML files (``xacro.load_yaml``).  A xacro file
downloaded from anywhere could so read any file the user can read.  Before
xacro is called, :func:`check_includes` reads the file and, recursively, every
file it includes, and refuses (one :class:`XacroPathError` naming the file and
the reference):

- an include that is not a plain relative path: absolute, ``file://``,
  ``$(find ...)``, ``$(arg ...)``, ``${...}`` (its target is known only
  after expansion);
- a relative include whose ``..`` or symlink leaves the roots of the top
  file (its folder and its ROS package root, :func:`.package_files.package_root`);
- ``$(env``, ``$(optenv``, ``$(eval``, ``$(find`` and ``load_yaml`` anywhere in the text;
- more than :data:`MAX_FILES` files, or one larger than
  :data:`.urdf.MAX_FILE_BYTES`, or a DTD or entity declaration.

Pure Python: never imports FreeCAD.
"""

import os
import re
import xml.etree.ElementTree as ElementTree

from ...errors import InputError
from . import package_files, urdf

#: Most files one xacro file may include, directly and through its includes.
MAX_FILES = 100

_OUTSIDE_READS = re.compile(r"\$\(\s*(env|optenv|eval|find)\b|load_yaml", re.IGNORECASE)


class XacroPathError(InputError):
    """A xacro file would make xacro read outside its folder and package."""


def _refuse(path, reference, why):
    raise XacroPathError("xacro file '%s': '%s' %s: CadRobot expands xacro files that read only "
                         "inside their folder or ROS package; expand it yourself (xacro FILE.xacro "
                         "-o FILE.urdf) and import the .urdf." % (path, reference, why))


def _inside(path, roots):
    return any(os.path.commonpath([path, root]) == root for root in roots)


def _text(path):
    """The bytes of one xacro file, bounded and without declarations."""
    if os.path.getsize(path) > urdf.MAX_FILE_BYTES:
        raise InputError("xacro file '%s' is larger than %d MB: give the arm's own description."
                         % (path, urdf.MAX_FILE_BYTES // 10 ** 6))
    with open(path, "rb") as stream:
        text = stream.read()
    package_files.refuse_declarations(text, "'%s'" % path)
    return text


def _includes(path, text):
    """The include references of one xacro file; refuses reads outside it cannot check."""
    found = _OUTSIDE_READS.search(text.decode("utf-8", "replace"))
    if found:
        _refuse(path, found.group(0), "reads from outside the file (the environment, another "
                                      "package, YAML or Python)")
    try:
        root = ElementTree.fromstring(text)
    except ElementTree.ParseError as exc:
        raise InputError("xacro file '%s' is not valid XML (%s)." % (path, exc)) from None
    return [element.get("filename") or "" for element in root.iter()
            if isinstance(element.tag, str) and element.tag.split("}")[-1] == "include"]


def check_includes(path):
    """Refuse a xacro file that would read outside its folder and package (module docstring).

    Parameters
    ----------
    path : str
        The top ``.xacro`` file.

    Returns
    -------
    list of str
        Every file that expanding it reads, the top file first (real paths).

    Raises
    ------
    XacroPathError
        An include or substitution that reads, or may read, outside.
    InputError
        A file that cannot be read, is not XML, is too large, declares a
        DTD or entities, or more than :data:`MAX_FILES` files.
    """
    top = os.path.realpath(path)
    folder = os.path.dirname(top)
    package = package_files.package_root(folder)
    roots = [folder] + ([os.path.realpath(package)] if package else [])
    queue, seen = [top], [top]
    while queue:
        current = queue.pop()
        try:
            references = _includes(current, _text(current))
        except OSError as exc:
            raise InputError("Cannot read the xacro file '%s': %s." % (current, exc.strerror)) from None
        for reference in references:
            if not reference or "$" in reference or ":" in reference or os.path.isabs(reference):
                _refuse(current, reference, "is not a plain relative path")
            target = os.path.normpath(os.path.join(os.path.dirname(current), reference))
            if not _inside(target, roots) or not _inside(os.path.realpath(target), roots):
                _refuse(current, reference, "leaves the file's folder and package")
            target = os.path.realpath(target)
            if target not in seen:
                if len(seen) >= MAX_FILES:
                    raise InputError("xacro file '%s' includes more than %d files: expand it "
                                     "yourself and import the .urdf." % (path, MAX_FILES))
                seen.append(target)
                queue.append(target)
    return seen
