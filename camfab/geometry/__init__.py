"""Cam geometry: pitch and working curves with exact evaluators, tolerance-driven sampling,
undercut trimming and the follower simulation (profile -> motion). Pure numpy, plus shapely for
planar noding and point-set queries."""
