"""Typed errors raised by CadRobot.

Every error names the object at fault and says what to do about it, so that the
GUI can select that object and the CLI can print one clear line.  The CLI maps
:class:`InputError` (and everything derived from it) to exit code 2 and
:class:`FindingError` to exit code 1.

This module is pure Python: the core layers raise these errors too.
"""


class CadRobotError(Exception):
    """Base class of every error CadRobot raises on purpose.

    Parameters
    ----------
    message : str
        What is wrong and how to fix it, in one sentence or two.
    obj_name : str, optional
        Internal name of the document object at fault (for selecting it in
        the tree), if there is one.
    """

    exit_code = 2

    def __init__(self, message, obj_name=None):
        message = one_line(message)
        super().__init__(message)
        self.message = message
        self.obj_name = obj_name

    def __str__(self):
        return self.message


def one_line(text):
    """`text` with every character that is not printable (a line break, a control
    character, a lone surrogate from a file's name or value) written as its Python
    escape (``\\n``, ``\\x85``), so that a message quoting it stays one line."""
    text = str(text)
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


class InputError(CadRobotError):
    """The document, a file or an argument cannot be used as given."""


class ArgumentError(InputError):
    """An argument of a scripting API call is of the wrong type, None, a closed
    document, a deleted object or an object of another document (the message
    names the function and the argument)."""


class DocumentError(InputError):
    """A file is not a FreeCAD document, or cannot be read."""


class UnknownNameError(InputError):
    """An unknown robot, post-processor or similar catalog name."""


class NameTakenError(InputError):
    """An imported robot's name is a shipped robot's; ``suggested_name`` is free."""

    def __init__(self, message, suggested_name):
        super().__init__(message)
        self.suggested_name = suggested_name


class GeometryError(InputError):
    """A path's geometry is empty, broken, or degenerate."""


class MarkerError(InputError):
    """A tool marker is missing, misplaced, or in conflict with another."""


class RiskAreaError(InputError):
    """A risk area covers segments that do not exist or do not follow each other."""


class FrameError(InputError):
    """A calibration frame is missing, deleted, or degenerate."""


class PostError(InputError):
    """A program cannot be expressed in the chosen robot language."""


class FindingError(CadRobotError):
    """The input is valid but the result fails a check the user must act on
    (an unreachable target, a joint limit, ...)."""

    exit_code = 1


class MissingPackageError(CadRobotError):
    """A Python package CadRobot needs is not installed for FreeCAD's Python
    (the message says which and how to install it)."""
