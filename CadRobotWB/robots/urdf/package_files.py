"""Which files a URDF may make CadRobot read: only its own package's.

A URDF downloaded from anywhere names its meshes itself.  Followed blindly,
``package://x/../../../../home/me/secret.stl``, ``/etc/...``, ``file://...``
or a symlink would read any file the user can read into the imported robot's
``.npz``.  So a mesh resolves only inside the URDF's *roots*:

- the folder of the URDF file;
- its ROS package root: the nearest ancestor folder (the URDF's folder
  included) that holds a ``package.xml``;
- for ``package://NAME/...``, the nearest ancestor folder named ``NAME``, at
  most :data:`NAME_LEVELS` levels above the URDF's folder (``NAME/urdf/robot.urdf``).

Absolute paths, ``file://`` URLs and references whose ``..`` leave their root
are refused before any file is opened; a file that exists but whose real path
(symlinks resolved) lies outside every root is refused too.  Each refusal is
one :class:`MeshPathError` naming the link and the mesh.

A URDF (or xacro) text with a ``<!DOCTYPE`` or ``<!ENTITY`` declaration is
refused before parsing (:func:`refuse_declarations`): a URDF needs neither,
and entities are how XML files make parsers read or expand more than given.

Pure Python: never imports FreeCAD.
"""

import os
import re

from ...errors import InputError

#: How many folder levels above the URDF's folder a ``package://NAME`` folder may be.
NAME_LEVELS = 2

_DECLARATION = re.compile(r"<!\s*(DOCTYPE|ENTITY)", re.IGNORECASE)


class MeshPathError(InputError):
    """A URDF mesh reference points outside the URDF's folder and package."""


def refuse_declarations(text, label):
    """Refuse XML text that declares a DTD or entities.

    Parameters
    ----------
    text : str or bytes
        The URDF or xacro text, before parsing.
    label : str
        How to name the file in the message (``"'robot.urdf'"``).

    Raises
    ------
    InputError
        The text contains ``<!DOCTYPE`` or ``<!ENTITY``.
    """
    if isinstance(text, bytes):   # without NULs, UTF-16 and UTF-32 markup reads as ASCII too
        text = text.replace(b"\0", b"").decode("utf-8", "replace")
    found = _DECLARATION.search(text)
    if found:
        raise InputError("%s declares an XML %s: CadRobot refuses DTDs and entities in a URDF; "
                         "remove the declaration (a URDF needs none)."
                         % (label, found.group(1).upper()))


def _within(path, root):
    """Whether ``path`` is ``root`` or below it (both absolute, normalised)."""
    return path == root or path.startswith(root.rstrip(os.sep) + os.sep)


def _ancestors(folder, levels=None):
    """``folder`` and its parents, nearest first (``levels`` parents at most)."""
    found = [folder]
    while os.path.dirname(found[-1]) != found[-1] and (levels is None or len(found) <= levels):
        found.append(os.path.dirname(found[-1]))
    return found


def package_root(folder, name=""):
    """The ROS package root of a URDF folder, or None.

    Parameters
    ----------
    folder : str
        The URDF's folder, absolute.
    name : str
        The package name of a ``package://NAME/...`` reference, or "".

    Returns
    -------
    str or None
        The nearest ancestor named ``name`` (at most :data:`NAME_LEVELS`
        levels up), else the nearest ancestor holding ``package.xml``.
    """
    if name:
        for ancestor in _ancestors(folder, NAME_LEVELS):
            if os.path.basename(ancestor) == name:
                return ancestor
    for ancestor in _ancestors(folder):
        if os.path.isfile(os.path.join(ancestor, "package.xml")):
            return ancestor
    return None


def _refuse(link, reference, why):
    raise MeshPathError("URDF link '%s': mesh '%s' %s: CadRobot reads meshes only inside the "
                        "URDF's folder or its ROS package; copy the mesh there and reference it "
                        "as package://PACKAGE/... or a relative path." % (link, reference, why))


def _split(reference, link):
    """``(package name, relative path)`` of a mesh reference; refuses file:// and absolute paths."""
    if reference.lower().startswith("file:"):
        _refuse(link, reference, "is a file:// URL")
    if reference.startswith("package://"):
        name, _, relative = reference[len("package://"):].partition("/")
    else:
        name, relative = "", reference
    if not relative or relative.startswith(("/", "\\")) or re.match(r"[A-Za-z]:[\\/]", relative):
        _refuse(link, reference, "is an absolute path")
    return name, relative


def mesh_path(reference, urdf_path, link=""):
    """Where a mesh reference of a URDF is on disk, or None when it is missing.

    ``package://NAME/meshes/x/link.stl`` is looked up in the package root
    (:func:`package_root`) at that path, then beside the URDF: at the same
    path, in a ``collision/`` folder next to it (the layout of the data
    folder), or by file name next to it.  A relative reference is looked up
    from the URDF's folder.  See the module docstring for what is refused.

    Parameters
    ----------
    reference : str
        The ``filename`` attribute of a URDF ``<mesh>``.
    urdf_path : str
        The URDF file's path ("" when read from text: the working folder).
    link : str
        The link whose mesh it is, for the message.

    Returns
    -------
    str or None

    Raises
    ------
    MeshPathError
        The reference is absolute, a ``file://`` URL, leaves its root with
        ``..``, or resolves (through a symlink) outside every root.
    """
    if not reference:
        return None
    name, relative = _split(reference, link)
    folder = os.path.dirname(os.path.abspath(urdf_path)) if urdf_path else os.getcwd()
    package = package_root(folder, name)
    roots = [folder] + ([package] if package else [])
    base = os.path.basename(relative)
    candidates = ([os.path.join(package, relative)] if package and name else []) + [
        os.path.join(folder, relative), os.path.join(folder, "collision", base),
        os.path.join(folder, base)]
    real_roots = [os.path.realpath(root) for root in roots]
    for candidate in candidates:
        candidate = os.path.normpath(candidate)
        if not any(_within(candidate, root) for root in roots):
            _refuse(link, reference, "leaves the URDF's folder and package with '..'")
        if os.path.isfile(candidate):
            real = os.path.realpath(candidate)
            if not any(_within(real, root) for root in real_roots):
                _refuse(link, reference, "is a link to '%s', outside the URDF's folder and package"
                        % real)
            return real
    return None
