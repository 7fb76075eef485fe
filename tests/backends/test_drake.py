"""Drake's backends beyond the contract every backend meets (tests/backends/test_backends.py):
how a root is held, MJCF sites, what its parsers say they ignore, and the install without the
``drake`` extra (run in a subprocess that hides pydrake, so it runs with or without the extra)."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from kinverify import load_spec
from kinverify.backends import ModelSources, backend_info, build_backend
from tests.paths import ROOT

HIDE_PYDRAKE = "import sys; sys.modules['pydrake'] = None  # ImportError on import, as without the extra\n"


def run_python(code: str, cwd=ROOT) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run([sys.executable, "-c", code], cwd=cwd, env=env, capture_output=True, text=True, timeout=300)


def test_without_the_extra_drake_is_listed_unavailable_with_the_pip_line_and_nothing_else_changes(tmp_path):
    code = HIDE_PYDRAKE + textwrap.dedent(f"""
        from kinverify.backends import available_backends, default_backend_names
        from kinverify.backends import ModelSources
        from kinverify import load_spec
        from kinverify.cli import main
        infos = available_backends()
        for name in ("drake-urdf", "drake-mjcf", "drake-sdf"):
            assert not infos[name].available and "pip install 'kinverify[drake]'" in infos[name].reason, infos[name]
        assert all(i.available for n, i in infos.items() if not n.startswith(("drake", "newton"))), infos  # newton: its own extra
        names = default_backend_names(ModelSources.from_spec(load_spec("models/arm3.toml")))
        assert not [n for n in names if n.startswith("drake")], names
        code = main(["verify", "models/arm3.toml", "--samples", "10", "--skip", "ik", "--skip", "tracking", "--skip", "pictures",
                     "--quiet", "--json", "{tmp_path / "r.json"}", "--report", "{tmp_path / "r.html"}"])
        assert code == 0, code
        assert main(["verify", "--sdf", "x.sdf", "--urdf", "y.urdf"]) == 2
    """)
    proc = run_python(code)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert "--sdf: SDFormat is read by Drake, which is not installed: pip install 'kinverify[drake]'" in proc.stderr


def test_importing_kinverify_does_not_import_drake():
    proc = run_python(
        "import sys, kinverify, kinverify.cli, kinverify.run; assert 'pydrake' not in sys.modules, 'pydrake imported'"
    )
    assert proc.returncode == 0, proc.stderr[-2000:]


needs_drake = pytest.mark.skipif(not backend_info("drake-sdf").available, reason="the drake extra is not installed")


@needs_drake
def test_an_unwelded_urdf_root_is_welded_like_pinocchio_does_and_floats_only_with_base_coordinates():
    spec = load_spec("models/arm3.toml")
    sources = ModelSources.from_spec(spec)
    bare = (
        sources.urdf.replace('<link name="world"/>', "").split('<joint name="world_to_base"')[0]
        + sources.urdf.split("</joint>", 1)[1]
    )  # no world link, no weld: Drake alone would make base a free body
    q = np.array([[0.3, -0.4, 0.5]])
    drake = build_backend("drake-urdf", ModelSources(spec.name, spec.joint_names, ("link3",), (), (), (), urdf=bare))
    pin = build_backend("pinocchio-urdf", ModelSources(spec.name, spec.joint_names, ("link3",), (), (), (), urdf=bare))
    assert drake.plant.num_positions() == 3  # welded: no free-body coordinates
    assert np.abs(drake.poses(q) - pin.poses(q)).max() < 1e-12


@needs_drake
def test_mjcf_sites_are_frames_and_what_drake_ignores_is_named_by_element():
    spec = load_spec("models/arm3.toml")
    sources = ModelSources.from_spec(spec)
    drake = build_backend("drake-mjcf", sources)
    mujoco = build_backend("mujoco", sources)
    q = np.array([[0.1, 0.2, -0.3], [1.0, -1.0, 0.5]])
    tool = list(sources.frames).index("end_effector")  # an MJCF site, which Drake's parser ignores
    assert np.abs(drake.poses(q)[:, tool] - mujoco.poses(q)[:, tool]).max() < 1e-12
    ignored = drake.refused_elements(drake.parser_warnings)
    assert {"<site> in <body>", "joint@frictionloss", "option@timestep", "<light> in <worldbody>"} <= set(ignored)
    assert build_backend("drake-sdf", sources).parser_warnings == []  # the generated SDFormat: nothing ignored


@needs_drake
def test_drake_dynamics_of_the_sdf_agree_with_pinocchio_and_carry_the_armature():
    from kinverify.backends.drake_dynamics import DrakeDynamics
    from kinverify.tracking.models import PinocchioDynamics

    spec = load_spec("models/arm3.toml")
    sources = ModelSources.from_spec(spec)
    drake = DrakeDynamics(sources.sdf, "sdf", spec.joint_names)
    pin = PinocchioDynamics(sources.urdf, spec.joint_names, [j.armature for j in spec.joints])
    assert np.allclose(drake.armature, [j.armature for j in spec.joints], rtol=0, atol=1e-15)
    q, v, a, tau = np.array([0.3, -0.7, 1.1]), np.array([0.5, -1.0, 2.0]), np.array([1.0, 2.0, -3.0]), np.array([5.0, -2.0, 1.0])
    for ours, theirs in (
        (drake.mass(q), pin.mass(q)),
        (drake.gravity(q), pin.gravity(q)),
        (drake.bias(q, v), pin.bias(q, v)),
        (drake.inverse(q, v, a), pin.inverse(q, v, a)),
        (drake.forward(q, v, tau), pin.forward(q, v, tau)),
    ):
        assert np.abs(ours - theirs).max() < 1e-10 * max(1.0, np.abs(theirs).max())
