"""Convert the MJCF that ``kinverify generate`` writes for every shipped spec (``models/*.toml``)
with NVIDIA's ``mujoco-usd-converter``, and keep each result here as ``<name>_mujoco-usd-converter.usda``.

The converter pins its own MuJoCo and OpenUSD (``usd-exchange``), so it runs in a venv of its own,
made (or reused) at ``--venv`` with ``pip install mujoco-usd-converter==VERSION``. Each MJCF is
converted with ``--no-layer-structure`` (one layer, written as ``.usdc``), then exported as text by
the converter venv's own ``pxr``, with the layer's doc string (which names a temporary folder)
replaced by the source's name. The generated MJCFs have no meshes, so nothing is stripped.

    .venv/bin/python tests/data/usd/make_mujoco_usd_converter.py [--venv DIR]

Run from the project root with the project's venv (it imports kinverify to write the MJCFs).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
from pathlib import Path

from kinverify.generate import generate_mjcf
from kinverify.model.specfile import load_spec

VERSION = "0.8.0"
HERE = Path(__file__).resolve().parent
EXPORT = """import sys
from pxr import Sdf
layer = Sdf.Layer.FindOrOpen(sys.argv[1])
layer.documentation = sys.argv[2]
sys.stdout.write(layer.ExportToString())
"""


def converter_venv(venv: Path) -> Path:
    """The venv's python, with the converter installed (once)."""
    python = venv / "bin" / "python"
    if not (venv / "bin" / "mujoco_usd_converter").exists():
        subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
        subprocess.run([str(python), "-m", "pip", "install", "-q", f"mujoco-usd-converter=={VERSION}"], check=True)
    return python


def convert(python: Path, spec_path: Path, work: Path) -> tuple[str, str]:
    """(usda text, the converter's warnings) of one spec's generated MJCF."""
    spec = load_spec(spec_path)
    mjcf = work / f"{spec.name}.xml"
    mjcf.write_text(generate_mjcf(spec))
    source = f"{spec.name}.xml (kinverify generate {spec_path.as_posix()})"
    run = subprocess.run(
        [str(python.parent / "mujoco_usd_converter"), "--no-layer-structure", str(mjcf), str(work / "out")],
        check=True,
        capture_output=True,
        text=True,
    )
    usdc = work / "out" / f"{spec.name}.usdc"
    doc = f"Converted from {source} by mujoco-usd-converter {VERSION} (--no-layer-structure)"
    text = subprocess.run([str(python), "-c", EXPORT, str(usdc), doc], check=True, capture_output=True, text=True).stdout
    warnings = sorted({line.split("] ", 2)[-1] for line in (run.stdout + run.stderr).splitlines() if "[Warning]" in line})
    return text, "; ".join(warnings)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--venv",
        type=Path,
        default=Path(tempfile.gettempdir()) / "kinverify-mujoco-usd-converter",
        help="the converter's own venv (made when absent)",
    )
    args = parser.parse_args()
    python = converter_venv(args.venv)
    for spec_path in sorted(Path("models").glob("*.toml")):
        with tempfile.TemporaryDirectory() as tmp:
            text, warnings = convert(python, spec_path, Path(tmp))
        out = HERE / f"{spec_path.stem}_mujoco-usd-converter.usda"
        out.write_text(text)
        print(
            f"{out.relative_to(Path.cwd()) if out.is_relative_to(Path.cwd()) else out}: {len(text)} bytes"
            + (f"; converter warnings: {warnings}" if warnings else "")
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
