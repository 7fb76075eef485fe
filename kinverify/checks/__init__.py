"""Properties compared between backends. Each module turns backend evaluations into errors;
:mod:`kinverify.verify` accumulates them into :class:`~kinverify.results.Check` results."""

from .tolerances import DEFAULT_TOLERANCES, Tolerance

__all__ = ["DEFAULT_TOLERANCES", "Tolerance"]
