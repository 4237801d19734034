"""Joints along a program: the configuration at each target, controller configuration data, joints between targets, cycle time, playback; imports kinematics/, catalog/ and core/."""
