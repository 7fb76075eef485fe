"""Comparing the aligned files: every library's reading cross-checked, rigid bodies and inertials
in one frame, joint dynamics and the dynamics with reported differences substituted."""
