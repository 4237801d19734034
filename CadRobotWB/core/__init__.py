"""Pure math of CAD-based robot programming (never imports FreeCAD)."""
