"""Geometry of the single-jersey loop and the B-spline toolkit it is built on."""
