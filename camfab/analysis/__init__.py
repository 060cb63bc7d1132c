"""Analysis of a design: findings (checks as data), kinematics, continuity."""
