"""FreeCAD document objects (App only: works in FreeCADCmd)."""
