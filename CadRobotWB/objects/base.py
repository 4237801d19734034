"""What every CadRobot document object shares.

Properties are declared once per class in a table of
``(type, name, group, tooltip, default)`` rows and created idempotently, both
when an object is made and when an older file is reopened (FEM's pattern), so
files saved by an earlier version gain the new properties. Proxies hold no
state of their own: ``dumps``/``loads`` return nothing.
"""

import FreeCAD

TYPE_PREFIX = "CadRobot::"


def ensure_properties(obj, table):
    """Add the properties in `table` that `obj` does not have yet.

    Parameters
    ----------
    obj : App.DocumentObject
    table : sequence of (str, str, str, str, object)
        ``(type, name, group, tooltip, default)``; a default of None leaves
        FreeCAD's own default. For enumerations the default is the list of
        choices (the first is selected).
    """
    for prop_type, name, group, tooltip, default in table:
        if name in obj.PropertiesList:
            continue
        obj.addProperty(prop_type, name, group, tooltip)
        if default is not None:
            setattr(obj, name, default)


class Proxy:
    """Base of the FeaturePython proxies. Subclasses set TYPE and PROPERTIES."""

    TYPE = ""
    PROPERTIES = ()
    #: {property name: value} for a file saved before the property existed, where its
    #: behaviour then differs from a new object's default (so old programs stay the same).
    RESTORED_DEFAULTS = {}

    def __init__(self, obj):
        obj.Proxy = self
        self.Type = TYPE_PREFIX + self.TYPE
        ensure_properties(obj, self.PROPERTIES)
        self.setup(obj)
        attach_view_provider(obj)

    def onDocumentRestored(self, obj):
        self.Type = TYPE_PREFIX + self.TYPE
        missing = [name for name in self.RESTORED_DEFAULTS if name not in obj.PropertiesList]
        ensure_properties(obj, self.PROPERTIES)
        for name in missing:
            setattr(obj, name, self.RESTORED_DEFAULTS[name])
        self.setup(obj)
        attach_view_provider(obj, restoring=True)  # files saved by FreeCADCmd have none

    def setup(self, obj):
        """Editor modes and other settings that are not saved; override."""

    def execute(self, obj):
        pass

    # FreeCAD 1.x calls dumps/loads, 0.20 __getstate__/__setstate__.
    def dumps(self):
        return None

    def loads(self, state):
        self.Type = TYPE_PREFIX + self.TYPE

    def __getstate__(self):
        return self.dumps()

    def __setstate__(self, state):
        self.loads(state)


def restoring(obj):
    """True while FreeCAD reads `obj` from a file (its properties are set one by one)."""
    return "Restore" in getattr(obj, "State", []) or bool(getattr(obj.Document, "Restoring", False))


def attach_view_provider(obj, restoring=False):
    """Draft's pattern: the App layer hands the object to the GUI layer only
    when the GUI is up (the import stays inside the guard)."""
    if FreeCAD.GuiUp:
        from ..gui import headless_files, view_providers
        view_providers.attach(obj)
        if restoring:
            headless_files.schedule_repair(obj.Document)


def type_of(obj):
    """The CadRobot type of `obj` (e.g. ``"Cell"``), or ``""`` for other objects."""
    proxy = getattr(obj, "Proxy", None)
    type_name = getattr(proxy, "Type", "") if proxy is not None else ""
    if isinstance(type_name, str) and type_name.startswith(TYPE_PREFIX):
        return type_name[len(TYPE_PREFIX):]
    return ""


def objects_of_type(doc, type_name):
    """Every object of CadRobot type `type_name` in `doc`, in document order."""
    return [o for o in doc.Objects if type_of(o) == type_name]


def describe(obj):
    """``"Label"`` or ``"Label (Name)"`` when they differ: how errors name objects."""
    if obj.Label == obj.Name:
        return "'%s'" % obj.Label
    return "'%s' (%s)" % (obj.Label, obj.Name)


def global_placement(obj):
    """Placement of `obj` in the document's global frame {U}, with every
    enclosing App::Part / Body placement applied."""
    try:
        return obj.getGlobalPlacement()
    except AttributeError:  # objects without GeoFeature placement
        return FreeCAD.Placement(obj.Placement)
