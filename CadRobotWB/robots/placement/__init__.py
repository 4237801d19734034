"""Where to stand the robot: the search space, the screen of base placements and the full search; imports checks/, motion/, kinematics/, catalog/ and core/."""
