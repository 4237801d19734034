"""URDF arms: reading the file, recognising its kinematics, numeric IK, link hulls and the catalog entry made from it; imports kinematics/, catalog/ and core/."""
