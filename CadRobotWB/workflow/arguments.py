"""The type checks of the scripting API's arguments, at the API's boundary.

Each API function starts with ``args = Arguments("make_path")`` and passes every
argument through one of its checkers before it reads or changes anything, so a
wrong argument is one :class:`~CadRobotWB.errors.ArgumentError` naming the
function, the argument, what was given and what is expected::

    make_cell: doc must be an open FreeCAD document (App.Document), got a closed document.
    place_robot on 'Cell': count must be a whole number of robot bases to find, got '3' (a str).

(naming the cell the call is about once it is checked), and never a TypeError, AttributeError or ReferenceError from deep inside, nor a
half-changed document.  Documents must be open; objects must still be in their
document, of the CadRobot type asked for, and in the document the call works in
(the first document or object checked sets it).

Only types and objects are checked here.  Whether a number is in its range is
the business of :mod:`..objects.validate` (and of the limits of counts), called
after these checks with the converted value.
"""

import numbers
import os

import FreeCAD
import numpy as np

from ..errors import ArgumentError
from ..objects import base

#: How much of a wrong value's repr a message shows.
SHOWN_CHARS = 40

#: What catalog names are, in messages.
ROBOT_NAME = "a robot name (a str, see api.robot_names())"
TOOL_NAME = "a tool name (a str, see api.tool_names())"
POST_NAME = "a post-processor name (a str, see api.post_names())"


def alive(obj):
    """Whether `obj` (a document object or a document) can still be used: not
    deleted from its document, its document not closed. Never raises."""
    try:
        if isinstance(obj, FreeCAD.Document):
            return obj.Name in FreeCAD.listDocuments()
        document, name = obj.Document, obj.Name
        return document is not None and document.getObject(name) is not None
    except (ReferenceError, RuntimeError):
        return False


def shown(value):
    """A short description of `value` for a message: ``'3' (a str)``, ``'Sketch' (a
    Sketcher::SketchObject)``, ``a deleted object``; never longer than about 60 characters."""
    if isinstance(value, FreeCAD.Document):
        return "document '%s'" % value.Name if alive(value) else "a closed document"
    if isinstance(value, FreeCAD.DocumentObject):
        if not alive(value):
            return "a deleted object (removed from its document, or its document closed)"
        kind = base.type_of(value)
        return "%s (%s)" % (base.describe(value), a_or_an("CadRobot " + kind if kind else value.TypeId))
    text = " ".join(repr(value).split())      # an array's repr spans lines
    if len(text) > SHOWN_CHARS:
        text = text[:SHOWN_CHARS - 3] + "..."
    return "%s (%s)" % (text, a_or_an(type(value).__name__))


def a_or_an(noun):
    """``"an int"``, ``"a str"``: `noun` with its indefinite article."""
    return ("an " if noun[:1].lower() in "aeiou" else "a ") + noun


def is_number(value):
    """Whether `value` is a real number: int, float, a numpy number (or 0-d array)
    or anything else float() takes, but not a bool, a str or bytes."""
    if isinstance(value, (bool, np.bool_, str, bytes)) or value is None:
        return False
    if isinstance(value, numbers.Real):
        return True
    if isinstance(value, np.ndarray) and (value.ndim != 0 or value.dtype.kind not in "iuf"):
        return False
    try:
        float(value)
    except (TypeError, ValueError):
        return False
    return True


class Arguments:
    """The checkers of one call of API function `function`.

    Each checker takes the argument's name and value, returns the value ready
    for use (converted where said) and raises ArgumentError for a wrong one.
    ``optional=True`` lets None through (returned as None).

    Attributes
    ----------
    document : App.Document or None
        The document the call works in: the first checked document, or the
        document of the first checked object.
    subject : App.DocumentObject or None
        The object the call is about (its cell, checked): messages about the
        other arguments name it ("set_tool on 'Welder': ...") and select it.
    """

    def __init__(self, function):
        self.function = function
        self.document = None
        self._document_argument = None
        self.subject = None

    def refuse(self, argument, expected, value):
        """Raise the one-line error: `argument` must be `expected`, got `value`."""
        self.fail("%s must be %s, got %s." % (argument, expected, shown(value)))

    def fail(self, text):
        """Raise ArgumentError ``"<function>[ on <subject>]: <text>"``."""
        if self.subject is None:
            raise ArgumentError("%s: %s" % (self.function, text))
        raise ArgumentError("%s on %s: %s" % (self.function, base.describe(self.subject), text),
                            self.subject.Name)

    # --- documents and their objects ---------------------------------------------------------
    def open_document(self, argument, value):
        """An open FreeCAD document; it becomes the call's document."""
        if not isinstance(value, FreeCAD.Document) or not alive(value):
            self.refuse(argument, "an open FreeCAD document (App.Document)", value)
        self._works_in(argument, value)
        return value

    def document_object(self, argument, value, kind=None, optional=False, subject=False):
        """A document object still in its document, of CadRobot type `kind` (e.g.
        ``"Cell"``; any object with None), in the call's document; with `subject`, the
        object the call is about (:attr:`subject`)."""
        if value is None and optional:
            return None
        expected = "a CadRobot %s" % kind if kind else "a document object"
        if not isinstance(value, FreeCAD.DocumentObject) or not alive(value):
            self.refuse(argument, expected + " of an open document", value)
        if kind and base.type_of(value) != kind:
            self.refuse(argument, expected, value)
        self._works_in(argument, value.Document, value)
        if subject and self.subject is None:
            self.subject = value
        return value

    def cell(self, value, argument="cell"):
        """A CadRobot cell of the call's document, the object the call is about."""
        return self.document_object(argument, value, "Cell", subject=True)

    def shape_object(self, argument, value, optional=False):
        """A document object with a Shape (a sketch, a Part object...) of the call's document."""
        obj = self.document_object(argument, value, optional=optional)
        if obj is not None and not hasattr(obj, "Shape"):
            self.refuse(argument, "an object with a shape (a sketch, a Part object)", obj)
        return obj

    def sub_element(self, argument, value, optional=False):
        """``(object with a shape, "FaceN" | "EdgeN" | "VertexN")`` of the call's document."""
        if value is None and optional:
            return None
        if not (isinstance(value, (tuple, list)) and len(value) == 2 and isinstance(value[1], str)):
            self.refuse(argument, "an (object, 'FaceN') pair", value)
        return self.shape_object(argument, value[0]), value[1]

    def set_property(self, obj, name, value, kind=None):
        """Set property `name` of `obj` (just made by the call) to `value`, an argument of
        that name: a document object must be of the call's document (and of CadRobot type
        `kind` when given), and a value FreeCAD refuses for the property's type is refused
        naming it."""
        if name not in obj.PropertiesList:
            self.fail("%s objects have no property '%s'; see their properties in FreeCAD's "
                      "property editor (or obj.PropertiesList)." % (base.type_of(obj) or obj.TypeId, name))
        if isinstance(value, FreeCAD.DocumentObject) or kind and value is not None:
            self.document_object(name, value, kind)
        try:
            setattr(obj, name, value)
        except (TypeError, ValueError, RuntimeError):   # RuntimeError: FreeCAD's Base.ParserError
            self.refuse(name, "a value of its type (%s)" % obj.getTypeIdOfProperty(name), value)

    def _works_in(self, argument, document, obj=None):
        """Make `document` the call's document, or refuse `obj` from another one."""
        if self.document is None:
            self.document, self._document_argument = document, argument
        elif document.Name != self.document.Name:
            named = argument if obj is None else "%s %s" % (argument, base.describe(obj))
            self.fail("%s is in document '%s', not in '%s' (that of %s); give an object of '%s'."
                      % (named, document.Name, self.document.Name, self._document_argument,
                         self.document.Name))

    # --- plain values --------------------------------------------------------------------------
    def text(self, argument, value, optional=False, expected="a str"):
        """A str."""
        if value is None and optional:
            return None
        if not isinstance(value, str):
            self.refuse(argument, expected, value)
        return value

    def choice(self, argument, value, choices, optional=False):
        """A str that is one of `choices` (case and spaces as given)."""
        if value is None and optional:
            return None
        if not isinstance(value, str) or value not in choices:
            self.refuse(argument, "one of %s" % ", ".join('"%s"' % c for c in choices), value)
        return value

    def number(self, argument, value, optional=False, expected="a number"):
        """A real number (not bool, str or None), as a float. Its range is not checked."""
        if value is None and optional:
            return None
        if not is_number(value):
            self.refuse(argument, expected, value)
        return float(value)

    def whole_number(self, argument, value, optional=False, expected="a whole number"):
        """A whole number (2 and 2.0 are, True and 2.5 are not), as an int. Its range is
        not checked (a hook for the limits of counts)."""
        if value is None and optional:
            return None
        if not is_number(value) or not np.isfinite(float(value)) or not float(value).is_integer():
            self.refuse(argument, expected, value)
        return int(float(value))

    def flag(self, argument, value):
        """True or False (a numpy bool too)."""
        if not isinstance(value, (bool, np.bool_)):
            self.refuse(argument, "True or False", value)
        return bool(value)

    def numbers(self, argument, value, count=None, optional=False, expected=None):
        """`count` real numbers (any number of them with None: the caller checks how many) in
        a sequence, an array or a FreeCAD.Vector, as a tuple of floats."""
        if value is None and optional:
            return None
        expected = expected or ("%d numbers" % count if count else "a list of numbers")
        if isinstance(value, FreeCAD.Vector):
            value = tuple(value)
        if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") \
                or count is not None and len(value) != count:
            self.refuse(argument, expected, value)
        if not all(is_number(v) for v in value):
            self.refuse(argument, expected, value)
        return tuple(float(v) for v in value)

    def point(self, argument, value, optional=False):
        """A point or direction: a FreeCAD.Vector or 3 numbers (mm), as an ndarray (3,)."""
        numbers_ = self.numbers(argument, value, 3, optional,
                                expected="a FreeCAD.Vector or 3 numbers (mm)")
        return None if numbers_ is None else np.array(numbers_)

    def points(self, argument, value):
        """A sequence of points, as an ndarray (N, 3)."""
        if isinstance(value, (str, bytes)) or not hasattr(value, "__iter__"):
            self.refuse(argument, "a list of points (FreeCAD.Vector or 3 numbers, mm)", value)
        return np.array([self.point("%s[%d]" % (argument, k), p) for k, p in enumerate(value)],
                        dtype=float).reshape(-1, 3)

    def placement(self, argument, value, what="placement"):
        """A FreeCAD.Placement, a FreeCAD.Matrix or a 4x4 array of numbers (mm), unconverted
        (``common.as_placement`` then checks that it is rigid); `what` says what it places."""
        if isinstance(value, (FreeCAD.Placement, FreeCAD.Matrix)):
            return value
        try:
            shape_ok = np.asarray(value, dtype=float).shape == (4, 4)
        except (TypeError, ValueError):
            shape_ok = False
        if not shape_ok or isinstance(value, (str, bytes)):
            self.refuse(argument if what == "placement" else "%s (the %s)" % (argument, what),
                        "a FreeCAD.Placement or a 4x4 matrix (mm)", value)
        return value

    def file_path(self, argument, value, what="a file path"):
        """A path: a non-empty str or os.PathLike without NUL characters, as a str."""
        if isinstance(value, os.PathLike):
            value = os.fspath(value)
        if not isinstance(value, str) or not value or "\0" in value:
            self.refuse(argument, "%s (a non-empty str or os.PathLike)" % what, value)
        return value

    def callback(self, argument, value):
        """None or a callable (a progress callback)."""
        if value is not None and not callable(value):
            self.refuse(argument, "None or a function progress(fraction, text)", value)
        return value

    def mapping(self, argument, value):
        """None or a dict (a Mapping), as a new dict."""
        if value is None:
            return {}
        if not hasattr(value, "keys") or not hasattr(value, "__getitem__"):
            self.refuse(argument, "None or a dict", value)
        return dict(value)
