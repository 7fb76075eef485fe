"""Memory that grew with the input: batch IK held every target's rows at once (``kinverify ik`` on
a 64-joint chain with 100,000 targets peaked at 2.4 GB, 1.5 GB of it the solver's rows). Targets
are now solved in chunks of a bounded working set (kinverify/ik/batch.py), and the JSON of a
batch is written one record at a time (docs/robustness.md, Limits)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np

from kinverify.ik import IKOptions, SerialChain, solve_lm
from kinverify.ik import batch
from kinverify.ik.frame_model import FrameModel
from kinverify.ik.files import json_bytes, results_json


def chain_urdf(n: int) -> str:
    """A serial chain of ``n`` revolute joints, 5 cm apart, axes alternating z and y."""
    parts = ['<robot name="chain">', '<link name="l0"/>']
    for i in range(n):
        parts.append(
            f'<link name="l{i + 1}"/><joint name="j{i + 1}" type="revolute"><parent link="l{i}"/>'
            f'<child link="l{i + 1}"/><origin xyz="0 0 0.05"/><axis xyz="{"0 0 1" if i % 2 == 0 else "0 1 0"}"/>'
            '<limit lower="-2" upper="2" effort="1" velocity="1"/></joint>'
        )
    return "".join(parts) + "</robot>"


PEAK = """
import resource, sys
import numpy as np
from kinverify.ik import IKOptions, SerialChain, solve_lm
from kinverify.ik.frame_model import FrameModel
from tests.fuzz.test_memory import chain_urdf

chain = SerialChain.from_urdf(chain_urdf(64), "l0", "l64")
model = FrameModel.from_chain(chain, "chain", "l64")
targets = np.tile(np.eye(4), (int(sys.argv[1]), 1, 1))
targets[:, :3, 3] = np.random.default_rng(0).uniform(-2, 2, (len(targets), 3))
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
solve_lm(model, targets, chain.lower, chain.upper, options=IKOptions(max_evaluations=3, max_restarts=0, seed_samples=0))
print((resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before) / 1024)
"""


def test_batch_ik_memory_does_not_grow_with_the_number_of_targets():
    """30,000 targets on 64 joints (a few iterations each): the solver's rows took about 470 MB at
    once; in chunks they stay near the chunk's working set whatever the count."""
    out = subprocess.run(
        [sys.executable, "-c", PEAK, "30000"],
        capture_output=True,
        text=True,
        timeout=300,
        check=True,
        cwd=Path(__file__).parents[2],
    )
    grown_mb = float(out.stdout.split()[-1])
    assert grown_mb < 330, f"solving grew the process by {grown_mb:.0f} MB"


def test_chunks_solve_every_target_as_one_batch_would(monkeypatch):
    chain = SerialChain.from_urdf(chain_urdf(6), "l0", "l6")
    model = FrameModel.from_chain(chain, "chain", "l6")
    q_true = np.random.default_rng(3).uniform(chain.lower, chain.upper, (150, 6))
    targets = chain.poses(q_true)
    opts = IKOptions(tol_pos=1e-9, tol_rot=1e-9)
    whole = solve_lm(model, targets, chain.lower, chain.upper, options=opts)
    sizes = []
    solve_rows = batch.solve_rows
    monkeypatch.setattr(batch, "CHUNK_BYTES", 0)  # the smallest chunks: MIN_ROWS (64) targets
    monkeypatch.setattr(batch, "solve_rows", lambda fk, t, *a: sizes.append(len(t)) or solve_rows(fk, t, *a))
    chunked = solve_lm(model, targets, chain.lower, chain.upper, options=opts)
    assert sizes == [64, 64, 22]
    assert chunked.success.all() and whole.success.all()
    assert np.allclose(chain.poses(chunked.q), targets, atol=1e-8)
    data = json.loads(json_bytes(results_json(chunked, chain.names, chain.lower, chain.upper, 1e-9, 1e-9, model="m")))
    assert [r["index"] for r in data["results"]] == list(range(150)) and data["solved"] == 150
    assert np.allclose([r["q"] for r in data["results"]], chunked.q)
