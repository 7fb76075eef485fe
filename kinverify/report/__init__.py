"""Reports read :class:`~kinverify.results.VerifyResult` only: terminal table, JSON and HTML."""

from .json_ import load_result_json, write_json
from .terminal import print_result
from .writer import write_atomic

__all__ = ["load_result_json", "print_result", "write_atomic", "write_json"]
