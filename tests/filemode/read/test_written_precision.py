"""The written precision of an MJCF is read through MuJoCo's ``<frame>`` elements too: MuJoCo writes
a URDF's fixed root link as a ``<frame>`` (``fusestatic``), and the bodies inside it are written to 6
significant digits like the rest; read as exact, their rounding was reported as differences."""

from __future__ import annotations

import mujoco

from kinverify import load_spec
from kinverify.filemode.pipeline import verify_files
from kinverify.filemode.read.precision import mjcf_precision
from kinverify.generate import generate_urdf
from kinverify.run import VerifyOptions
from tests.paths import MODELS


def test_bodies_inside_a_frame_are_read_at_their_written_precision(tmp_path):
    urdf = generate_urdf(load_spec(MODELS / "arm3.toml"))
    (tmp_path / "arm.urdf").write_text(urdf)
    mujoco.mj_saveLastXML(str(tmp_path / "arm.xml"), mujoco.MjModel.from_xml_string(urdf))  # fused root: a <frame>
    written = (tmp_path / "arm.xml").read_text()
    assert "<frame " in written and 'range="-3.14159 3.14159"' in written
    described = mjcf_precision(written).describe()
    assert "joint limits to 5 decimals" in described and "exact" not in described, described
    result = verify_files(
        str(tmp_path / "arm.urdf"),
        str(tmp_path / "arm.xml"),
        VerifyOptions(samples=4, fd_samples=1, backends=["pinocchio-urdf", "mujoco"], suites=["kinematics", "limits", "inertia"]),
    )
    assert result.verdict == "pass", [(f.kind, f.subject, f.message) for f in result.findings if f.severity == "error"]
    assert sorted({f.kind for f in result.findings if f.kind == "rounding"}) == ["rounding"]
