"""FreeCAD GUI layer: view providers and the 3D view (imports FreeCADGui)."""
