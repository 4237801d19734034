"""Kinematics of the catalog arms: OPW, UR and DH closed forms, configuration families, the models (fk/ik) and link frames; imports catalog/ and core/."""
