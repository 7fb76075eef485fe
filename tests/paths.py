"""Paths the tests share: the project root, the shipped models and the real robot pairs in
``../shared/real-robots`` (tests that read them skip when the folder is absent)."""

from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
MODELS = ROOT / "models"
REAL_ROBOTS = ROOT.parent / "shared" / "real-robots"
