"""One module per CLI subcommand (see :mod:`kinverify.cli`)."""
