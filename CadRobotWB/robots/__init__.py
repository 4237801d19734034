"""Robot models and the robot catalog (never imports FreeCAD)."""
