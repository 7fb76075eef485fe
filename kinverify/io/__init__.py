"""Every file kinverify reads goes through :mod:`kinverify.io.read`; every file it writes through
:mod:`kinverify.io.write` (see docs/robustness.md).

- :mod:`kinverify.io.read`: the one reader. A regular file only (a FIFO, device, socket or
  directory is refused in one line, without blocking), at most a documented number of bytes
  (counted while reading, so ``/dev/zero`` and sparse files are bounded too), and recorded as an
  input of the run, so no output may replace it.
- :mod:`kinverify.io.formats`: what the reader's bytes are parsed into (JSON, TOML, ``.npy``,
  XML), each with bounded nesting.
- :mod:`kinverify.io.models`: checks on a URDF or MJCF tree before any library sees it (a URDF's
  links form one tree; finite poses and axes; MJCF ``<include>`` expanded through the reader).
- :mod:`kinverify.io.references`: the files a library opens for us (SDFormat includes, MJCF model
  files, meshes...), found and checked before the library parses the model.
- :mod:`kinverify.io.isolate`: libraries that can crash or run away (Drake's parsers, xacro), run
  in a child process bounded in memory and time.
- :mod:`kinverify.io.plan`: the inputs and outputs of a run: an output that is an input, another
  output, a folder or a device is refused; the outputs are committed together at the end.
- :mod:`kinverify.io.write`: the atomic writer (a temporary file, ``fsync``, a rename).
- :mod:`kinverify.io.quiet`: library messages kept off the terminal during a command.
"""
