"""Trajectory tracking: quintic plans executed in MuJoCo on the generated MJCF, with controllers
whose model terms come from Pinocchio on the generated URDF, and the metrics that judge a run."""
