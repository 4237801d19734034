"""Checks of a program against a robot: reach, limits, singularities, joint speeds, collisions of the link solids, reach advice; imports motion/, urdf/, kinematics/, catalog/ and core/."""
