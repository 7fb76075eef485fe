"""``kinverify generate MODEL --out DIR``: write DIR/<name>.urdf, DIR/<name>.xml, DIR/<name>.sdf and,
with usd-core installed (the ``usd`` extra), DIR/<name>.usda."""

from __future__ import annotations

import argparse

from kinverify.text import shown


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "generate",
        help="write the URDF, MJCF, SDFormat and OpenUSD generated from a spec",
        description="Write DIR/<name>.urdf, DIR/<name>.xml (MJCF), DIR/<name>.sdf (SDFormat 1.9) and "
        "DIR/<name>.usda (OpenUSD with the UsdPhysics schema; only when usd-core is installed: "
        "pip install 'kinverify[usd]') generated from a spec file.",
    )
    p.add_argument("model", help="spec file (models/*.toml)")
    p.add_argument("--out", default=".", help="output directory (default: current directory)")
    return p


def run(args) -> int:
    import sys
    from pathlib import Path

    from kinverify.generate import USD_MISSING, generate_mjcf, generate_sdf, generate_urdf, generate_usd_if_available
    from kinverify.io.write import write_atomic
    from kinverify.model.specfile import load_spec

    from kinverify.io.plan import claim_outputs

    spec = load_spec(args.model)
    out = Path(args.out)
    files = [
        (out / f"{spec.name}.urdf", generate_urdf(spec)),
        (out / f"{spec.name}.xml", generate_mjcf(spec)),
        (out / f"{spec.name}.sdf", generate_sdf(spec)),
    ]
    usd = generate_usd_if_available(spec)
    if usd is not None:
        files.append((out / f"{spec.name}.usda", usd))
    claim_outputs(*(("", path) for path, _ in files))  # all checked before any is written
    for path, text in files:
        write_atomic(path, text)
        print(shown(path))
    if usd is None:
        print(f"note: no {spec.name}.usda written: {USD_MISSING}", file=sys.stderr)
    return 0
