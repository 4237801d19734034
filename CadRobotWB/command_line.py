"""How the user runs a CadRobot command line, for hints that name one.

A checkout's set-up puts the ``cadrobot`` launcher on the PATH; the Addon
Manager installs no launcher, and those users run the CLI through FreeCADCmd's
one line (README, "Installed with the Addon Manager")::

    FreeCADCmd -c "from CadRobotWB import cli; cli.run('check part.FCStd')"

:func:`as_typed` writes a command the way this user types it; inside FreeCAD's
GUI a command line is no help, and messages say the GUI's way instead
(:func:`in_gui`, :func:`outside_gui`).  Pure: never imports FreeCAD (it only looks at ``sys.modules``), so
every layer may use it, as it uses ``errors``.
"""

import os
import re
import shutil
import sys

#: The launcher a checkout's set-up puts on the PATH.
LAUNCHER = "cadrobot"
#: FreeCAD's command-line program, as the README names it, then as Linux installs it.
FREECADCMD_NAMES = ("FreeCADCmd", "freecadcmd")


def in_gui():
    """bool: this is FreeCAD's GUI (a hint there names the GUI's way, not a command line)."""
    return bool(getattr(sys.modules.get("FreeCAD"), "GuiUp", False))


def _word(text):
    """`text` as one argument of :func:`cli.split_command_line` (quoted when it holds blanks)."""
    text = str(text)
    if text and not re.search(r"[\s'\"]", text):
        return text
    return '"%s"' % text if '"' not in text else "'%s'" % text


def _shell_double_quoted(text):
    """`text` inside double quotes for a POSIX shell."""
    return '"%s"' % re.sub(r'(["\\$`])', r"\\\1", text)


def freecadcmd():
    """The name FreeCAD's command-line program answers to on the PATH ("FreeCADCmd" if none)."""
    for name in FREECADCMD_NAMES:
        if shutil.which(name):
            return name
    return FREECADCMD_NAMES[0]


def launcher_on_path():
    """bool: the user's PATH has the ``cadrobot`` launcher.

    FreeCAD puts every ``Mod`` folder on its own PATH, and a copy of the workbench
    there (the Addon Manager's) holds the launcher: folders holding ``CadRobotWB``
    are not the user's PATH.
    """
    path = [folder for folder in os.environ.get("PATH", "").split(os.pathsep)
            if folder and not os.path.isdir(os.path.join(folder, "CadRobotWB"))]
    return shutil.which(LAUNCHER, path=os.pathsep.join(path)) is not None


def as_typed(*arguments):
    """A ``cadrobot`` command as this user types it.

    Parameters
    ----------
    *arguments : str
        The CLI's arguments, e.g. ``"check", "part.FCStd"``.

    Returns
    -------
    str
        ``cadrobot check part.FCStd`` when ``cadrobot`` is on the PATH, else
        ``FreeCADCmd -c "from CadRobotWB import cli; cli.run('check part.FCStd')"``.
    """
    words = " ".join(_word(a) for a in arguments)
    if launcher_on_path():
        return "%s %s" % (LAUNCHER, words)
    code = "from CadRobotWB import cli; cli.run(%r)" % words
    return "%s -c %s" % (freecadcmd(), _shell_double_quoted(code))


def outside_gui(template, *arguments):
    """`template` with the command of `arguments` as typed (:func:`as_typed`), or "" in
    FreeCAD's GUI, whose panels show what the command would print.

    E.g. ``outside_gui(" `%s` describes them.", "posts")``.
    """
    return "" if in_gui() else template % as_typed(*arguments)


def document_argument(doc):
    """The document's path for a command line, or ``DOC.FCStd`` when it was never saved."""
    return getattr(doc, "FileName", "") or "DOC.FCStd"
