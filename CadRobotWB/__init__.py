"""CadRobot: CAD-based robot programming workbench for FreeCAD."""

__version__ = "0.1.0"
