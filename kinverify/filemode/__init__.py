"""File mode: an existing URDF against an existing MJCF of the same robot, and what differs.

The stages, in the order :mod:`~kinverify.filemode.pipeline` runs them:

- :mod:`~kinverify.filemode.read`: each file loaded safely (xacro compiled, meshes dropped),
  cleaned for the libraries, its written precision measured, its inertials validated, and
  described by the library that reads it (URDF: Pinocchio, MJCF: MuJoCo, SDFormat: Drake, with
  the ``drake`` extra; an SDFormat file takes the side of the format it is paired with);
- :mod:`~kinverify.filemode.align`: joints and frames matched, floating bases decided, and the
  world transform, zero offsets, signs and frame conventions fitted;
- :mod:`~kinverify.filemode.compare`: every library's reading of each file seen through the
  alignment and cross-checked, rigid bodies and inertials in one frame, dynamics;
- :mod:`~kinverify.filemode.findings`: the severity table, one finding per cause, the verdict's
  explanations, accepted differences, the report section.

:mod:`~kinverify.filemode.audit` is the one-file audit: every library that reads one file,
compared with the others. See docs/file-mode.md.
"""
