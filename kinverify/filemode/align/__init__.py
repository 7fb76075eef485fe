"""Aligning the two files: joints and frames matched, floating bases decided, and what is a
choice rather than a different robot fitted (world transform, zero offsets, signs, frame conventions)."""
