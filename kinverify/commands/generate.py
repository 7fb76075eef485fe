"""``kinverify generate MODEL --out DIR``: write DIR/<name>.urdf, DIR/<name>.xml and DIR/<name>.sdf."""

from __future__ import annotations

import argparse

from kinverify.text import shown


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser("generate", help="write the URDF, MJCF and SDFormat generated from a spec",
                       description="Write DIR/<name>.urdf, DIR/<name>.xml (MJCF) and DIR/<name>.sdf (SDFormat 1.9) "
                       "generated from a spec file.")
    p.add_argument("model", help="spec file (models/*.toml)")
    p.add_argument("--out", default=".", help="output directory (default: current directory)")
    return p


def run(args) -> int:
    from pathlib import Path

    from kinverify.generate import generate_mjcf, generate_sdf, generate_urdf
    from kinverify.io.write import write_atomic
    from kinverify.model.specfile import load_spec

    from kinverify.io.plan import claim_outputs

    spec = load_spec(args.model)
    out = Path(args.out)
    files = ((out / f"{spec.name}.urdf", generate_urdf(spec)), (out / f"{spec.name}.xml", generate_mjcf(spec)),
             (out / f"{spec.name}.sdf", generate_sdf(spec)))
    claim_outputs(*(("", path) for path, _ in files))  # all checked before any is written
    for path, text in files:
        write_atomic(path, text)
        print(shown(path))
    return 0
