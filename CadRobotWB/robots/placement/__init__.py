"""Where to stand the robot: the search space, the screen of base placements, the full search and a new cell's default base; imports checks/, motion/, kinematics/, catalog/ and core/."""
