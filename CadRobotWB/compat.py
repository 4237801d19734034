"""What differs between the FreeCAD versions CadRobot supports: 0.20, 1.0 and 1.1.

Every version test of the workbench lives here, so the rest of the code reads the
same on each version:

* FreeCAD 1.0 renamed the attachment property ``Support`` to ``AttachmentSupport``;
  0.20's ``addExtension`` wants a proxy argument.
* FreeCAD 1.0 keeps a view object's material in ``ShapeAppearance`` (a list of
  materials) instead of ``ShapeMaterial``, with other defaults for the ambient,
  specular and shininess fields; we set every field ourselves.
* FreeCAD 1.1 keeps the user data in a folder per version (``.../FreeCAD/v1-1``)
  and, from 1.0 on, the Addon Manager installs Python packages into
  ``AdditionalPythonPackages/py<major><minor>`` (0.20: the folder itself):
  :func:`pip_target_folder` (``FreeCAD.getUserAppDataDir()`` answers for each
  version, and ``dependencies.packages_folder`` reads the folder off ``sys.path``).
* FreeCAD 1.1 runs on Qt 6 / PySide6 (``QImage.byteCount`` is gone; enums are
  scoped, and unscoped names still work through PySide6's compatibility mode), and
  calls the placement dragger ``SoTransformDragger`` (``SoFCCSysDragger`` before).
* FreeCAD 1.x animates camera moves, and on 1.1 a ``saveImage`` right after a scene
  change can show the scene before it: :func:`no_camera_animation`, :func:`draw_now`.

Not version tests, so not here: proxies define both ``dumps``/``loads`` (1.x) and
``__getstate__``/``__setstate__`` (0.20) (``objects/base.py``), and
``gui/headless_files.py`` repairs files without a GuiDocument.xml, which FreeCAD
before 1.1 opens hidden.

Only FreeCAD's App module is imported at module level; Qt and Coin are imported
inside the functions that need them, so FreeCADCmd can use this module.
"""

import os
import sys

import FreeCAD


def freecad_version():
    """(major, minor) of the running FreeCAD, e.g. (1, 1)."""
    major, minor = FreeCAD.Version()[:2]
    return int(major), int(minor)


def pip_target_folder():
    """The folder FreeCAD reads Python packages from, where the Addon Manager's pip installs.

    Returns
    -------
    str
        ``<user data>/AdditionalPythonPackages/py<major><minor>`` on FreeCAD 1.x
        (FreeCAD puts it on ``sys.path`` at start-up when it exists), the
        ``AdditionalPythonPackages`` folder itself on 0.20.
    """
    base = os.path.join(FreeCAD.getUserAppDataDir(), "AdditionalPythonPackages")
    if freecad_version() < (1, 0):
        return base
    return os.path.join(base, "py%d%d" % sys.version_info[:2])


# --- document objects --------------------------------------------------------------------

def attachment_support_property(obj):
    """Name of `obj`'s attachment support property ("AttachmentSupport" or "Support")."""
    return "AttachmentSupport" if hasattr(obj, "AttachmentSupport") else "Support"


def attachment_support(obj):
    """The references `obj` is attached to: a list of (object, sub-names), maybe empty."""
    return getattr(obj, attachment_support_property(obj), None) or []


def set_attachment_support(obj, references):
    """Attach `obj` to `references` ([(object, "Face6")], ...) on any version."""
    setattr(obj, attachment_support_property(obj), references)


def make_attachable(obj):
    """Give a FeaturePython object Part's attachment extension, once."""
    if not obj.hasExtension("Part::AttachExtension"):
        try:
            obj.addExtension("Part::AttachExtensionPython")
        except TypeError:  # FreeCAD 0.20 wants the (unused) proxy argument
            obj.addExtension("Part::AttachExtensionPython", None)


# --- 3D view -------------------------------------------------------------------------------

# 0.20's defaults for the fields other than the colour: 1.0 changed them (a strong
# specular highlight and shininess make an orange marker look white in places).
AMBIENT_RGB = (0.2, 0.2, 0.2)
SPECULAR_RGB = (0.0, 0.0, 0.0)
EMISSIVE_RGB = (0.0, 0.0, 0.0)
SHININESS = 0.2


def shape_material(diffuse_rgb, transparency_percent=0):
    """A ``FreeCAD.Material`` with every field set: colour (0..1 RGB) and transparency (%)."""
    material = FreeCAD.Material()
    material.DiffuseColor = tuple(float(c) for c in diffuse_rgb[:3])
    material.AmbientColor = AMBIENT_RGB
    material.SpecularColor = SPECULAR_RGB
    material.EmissiveColor = EMISSIVE_RGB
    material.Shininess = SHININESS
    material.Transparency = float(transparency_percent) / 100.0
    return material


def set_shape_material(vobj, diffuse_rgb, transparency_percent=0):
    """Give a Part view object's faces one fully specified material on any version."""
    material = shape_material(diffuse_rgb, transparency_percent)
    if "ShapeAppearance" in vobj.PropertiesList:       # FreeCAD >= 1.0
        vobj.ShapeAppearance = [material]
    elif "ShapeMaterial" in vobj.PropertiesList:
        vobj.ShapeMaterial = material
    if "Transparency" in vobj.PropertiesList:
        vobj.Transparency = int(round(transparency_percent))


def no_camera_animation(view=None):
    """Make camera moves (``viewTop``, ``fitAll``, ...) instant, as they are on 0.20.

    FreeCAD 1.x animates them (preference ``View/UseNavigationAnimations``, on by
    default): a ``saveImage`` right after ``viewFront()`` renders the camera part way
    round. This turns the preference off for views made from now on and, given a
    view, for that view too.
    """
    FreeCAD.ParamGet("User parameter:BaseApp/Preferences/View").SetBool(
        "UseNavigationAnimations", False)
    if view is not None and hasattr(view, "setAnimationEnabled"):
        view.setAnimationEnabled(False)


def draw_now(view):
    """Draw `view` on screen now, so a ``saveImage`` that follows shows the scene as it is.

    On FreeCAD 1.1 a ``saveImage`` right after a change of the scene (a switch turned
    back on) rendered the old scene in 3 of 5 runs; after drawing the view on screen
    first it rendered the new one in 8 of 8. 0.20 draws the same either way.
    """
    if hasattr(view, "redraw"):
        view.redraw()


def transform_dragger_type():
    """Coin type of FreeCAD's placement dragger (``SoTransformDragger`` on 1.1)."""
    from pivy import coin
    for name in ("SoTransformDragger", "SoFCCSysDragger"):
        so_type = coin.SoType.fromName(name)
        if not so_type.isBad():
            return so_type
    raise RuntimeError("FreeCAD's placement dragger type is unknown in FreeCAD %d.%d"
                       % freecad_version())


# --- Qt ------------------------------------------------------------------------------------

def qimage_size_in_bytes(image):
    """``QImage.sizeInBytes()`` (Qt >= 5.10), ``byteCount()`` before."""
    size = getattr(image, "sizeInBytes", None)
    return size() if size is not None else image.byteCount()
