"""Robots without FreeCAD, by job: catalog/, kinematics/, urdf/, motion/, checks/, placement/ (each imports only core/, errors, dependencies, command_line and the ones before it)."""
