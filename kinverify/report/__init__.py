"""Reports read :class:`~kinverify.results.VerifyResult` only: terminal table, JSON and HTML."""

from kinverify.report.json_ import load_result_json, write_json
from kinverify.report.terminal import print_result
from kinverify.io.write import write_atomic

__all__ = ["load_result_json", "print_result", "write_atomic", "write_json"]
