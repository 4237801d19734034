"""Robots without FreeCAD, by job: catalog/, kinematics/, urdf/, motion/, checks/, placement/ (each imports only core/, errors, dependencies and the ones before it)."""
