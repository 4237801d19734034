"""Sensor-in-the-loop simulation (never imports FreeCAD)."""
