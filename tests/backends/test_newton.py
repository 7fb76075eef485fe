"""Newton's backends (the ``newton`` extra: float32, Warp on the CPU) beyond the contract every
backend meets: agreement with Pinocchio and MuJoCo at Newton's own floor, on a shipped spec and on
the shared real robots, its importer quirks by value, and kinverify without it (run in a
subprocess, so these run with or without the extra). The first test to build a Newton backend
pays Warp's kernel compile when its cache is cold (about a minute: docs/performance.md)."""

from __future__ import annotations

import json
import warnings
import xml.etree.ElementTree as ET

import mujoco
import numpy as np
import pinocchio
import pytest

from kinverify import load_spec
from kinverify.backends import ModelSources, backend_info, build_backend
from kinverify.backends.base import pair_floor
from kinverify.errors import UnknownNameError
from kinverify.backends.mujoco_ import MujocoBackend
from kinverify.backends.pinocchio_ import PinocchioBackend
from kinverify.backends.usd_ import UsdBackend, load_robot
from kinverify.model.floating import BASE_COORDINATES
from kinverify.filemode.read.files import read_mjcf, read_urdf
from kinverify.model.transforms import geodesic_distance
from kinverify.pipeline.sampling import spec_samples
from tests.backends.test_drake import run_python
from tests.paths import REAL_ROBOTS

needs_newton = pytest.mark.skipif(not backend_info("newton-urdf").available, reason="the newton extra is not installed")


def test_importing_kinverify_imports_neither_warp_nor_newton():
    proc = run_python(
        "import sys, kinverify, kinverify.cli, kinverify.run, kinverify.backends; "
        "assert not {'warp', 'newton'} & set(sys.modules), 'warp or newton imported'"
    )
    assert proc.returncode == 0, proc.stderr[-2000:]


def test_without_the_extra_newton_is_listed_unavailable_with_the_pip_line():
    proc = run_python(
        "import sys; sys.modules['newton'] = None\n"
        "from kinverify.backends import available_backends\n"
        "infos = available_backends()\n"
        "for name in ('newton-urdf', 'newton-mjcf', 'newton-usd'):\n"
        "    assert not infos[name].available and \"pip install 'kinverify[newton]'\" in infos[name].reason, infos[name]\n"
        "assert all(i.available for n, i in infos.items() if not n.startswith(('newton', 'drake'))), infos\n"
    )
    assert proc.returncode == 0, proc.stderr[-2000:]


@needs_newton
def test_newton_is_imported_with_the_garbage_collector_paused_then_its_objects_frozen():
    """backends/newton_.long_lived: Warp's parsed kernels are frozen (the collector no longer walks them),
    and the collector runs again after the import."""
    proc = run_python(
        "import gc\n"
        "import kinverify.backends.newton_\n"
        "assert gc.isenabled() and gc.get_freeze_count() > 100_000, gc.get_freeze_count()\n"
    )
    assert proc.returncode == 0, proc.stderr[-2000:]


def _errors(a, b):
    pos = np.linalg.norm(a.poses[..., :3, 3] - b.poses[..., :3, 3], axis=-1).max()
    rot = geodesic_distance(a.poses[..., :3, :3], b.poses[..., :3, :3]).max()
    jac = np.linalg.norm(a.jacobians - b.jacobians, axis=-1).max(axis=(0, 1))  # (6,) row norms over joints
    return pos, rot, jac[:3].max(), jac[3:].max()


@needs_newton
@pytest.mark.parametrize("name", ["newton-urdf", "newton-mjcf"])
def test_newton_agrees_with_pinocchio_on_the_panda_at_its_floor_and_not_at_double_precision(name):
    sources = ModelSources.from_spec(load_spec("models/panda.toml"))
    q = spec_samples(load_spec("models/panda.toml"), 40, seed=2)
    newton_, ref = build_backend(name, sources), build_backend("pinocchio-urdf", sources)
    pos, rot, lin, ang = _errors(newton_.evaluate(q), ref.evaluate(q))
    for prop, err in (("fk.position", pos), ("fk.rotation", rot), ("jacobian.linear", lin), ("jacobian.angular", ang)):
        assert err <= pair_floor(prop, newton_), (prop, err)
    assert pos > 1e-8, "float32: Newton cannot agree to double precision, so the floor is needed"


@needs_newton
def test_newton_mass_matrix_agrees_with_pinocchio_on_the_panda():
    spec = load_spec("models/panda.toml")
    sources = ModelSources.from_spec(spec)
    q = spec_samples(spec, 10, seed=3)
    newton_ = build_backend("newton-urdf", sources)
    pin = build_backend("pinocchio-urdf", sources)
    expected = []
    for full in pin._full_q(q):
        m = pinocchio.crba(pin.model, pin.data, full)
        expected.append(np.triu(m) + np.triu(m, 1).T + np.diag(pin.model.armature))
    diff = np.abs(newton_.mass_matrix(q) - np.array(expected)).max()
    assert diff <= 1e-5 * np.abs(np.array(expected)).max(), diff


def _quaternion_drift(model, newton_module) -> tuple[float, float]:
    """Largest |‖q‖ − 1| of the joints' parent-frame quaternions and of the bodies' after FK at ``joint_q``."""
    state = model.state()
    newton_module.eval_fk(model, model.joint_q, model.joint_qd, state)
    x_p = np.abs(np.linalg.norm(model.joint_X_p.numpy()[:, 3:].astype(float), axis=1) - 1).max()
    body = np.abs(np.linalg.norm(state.body_q.numpy()[:, 3:].astype(float), axis=1) - 1).max()
    return float(x_p), float(body)


@needs_newton
def test_quirk_newton_mjcf_quaternions_drift_off_unit_length_along_the_chain():
    """backends/quirks.py, newton-mjcf: measured 6.6e-7 (joint_X_p) and 2.0e-6 (bodies) on the Panda's
    MJCF, against float32 round-off (1.2e-7) from its URDF; the adapter's rotations stay orthonormal."""
    newton_module = pytest.importorskip("newton")
    spec = load_spec("models/panda.toml")
    sources = ModelSources.from_spec(spec)
    mjcf, urdf = build_backend("newton-mjcf", sources), build_backend("newton-urdf", sources)
    x_p, body = _quaternion_drift(mjcf.one, newton_module)
    assert 4e-7 < x_p < 1e-6 and 1.5e-6 < body < 3e-6, (x_p, body)
    assert max(_quaternion_drift(urdf.one, newton_module)) < 2e-7
    ev = mjcf.evaluate(np.zeros((1, 7)))
    rot = ev.poses[0, :, :3, :3]
    assert np.abs(rot @ np.swapaxes(rot, -1, -2) - np.eye(3)).max() < 1e-12  # normalised by the adapter
    axis_norm = np.linalg.norm(ev.jacobians[0, -1, 3:, :], axis=0)  # Newton's own Jacobian: axes longer than 1
    assert 2e-6 < (axis_norm - 1).max() < 1e-5, axis_norm - 1


PAIRS = {
    "panda": ("panda_erd.urdf", "panda_menagerie.xml"),
    "iiwa14": ("iiwa14_no_collision_drake.urdf", "iiwa14_menagerie.xml"),
    "z1": ("z1_erd.urdf", "z1_menagerie.xml"),
    "go2": ("go2_erd.urdf", "go2_menagerie.xml"),
    "a1": ("a1_unitree_ros.urdf", "a1_menagerie.xml"),
    "anymal_c": ("anymal_c_anybotics.urdf", "anymal_c_menagerie.xml"),
    "leap_hand": ("leap_hand_dexurdf.urdf", "leap_hand_menagerie.xml"),
    "ur5e": ("ur5e_ur_description.urdf", "ur5e_menagerie.xml"),
}
QUICK = ("panda", "go2")  # the others with -m slow (each pair builds two Newton models)


def _urdf_names(text: str) -> tuple[list[str], list[str], np.ndarray]:
    """Moving joints (no mimic followers), links, and each joint's range (±π where none is written)."""
    root = ET.fromstring(text)
    moving = [
        j for j in root.findall("joint") if j.get("type") in ("revolute", "continuous", "prismatic") and j.find("mimic") is None
    ]
    ranges = [
        [
            float(j.find("limit").get(k, d)) if j.find("limit") is not None and j.get("type") != "continuous" else d
            for k, d in (("lower", -np.pi), ("upper", np.pi))
        ]
        for j in moving
    ]
    return [j.get("name") for j in moving], [link.get("name") for link in root.findall("link")], np.array(ranges)


def _mjcf_names(text: str) -> tuple[list[str], list[str], np.ndarray]:
    """Hinge and slide joints, bodies and sites, and each joint's range (±π where it is not limited)."""
    m = mujoco.MjModel.from_xml_string(text)
    moving = [
        i for i in range(m.njnt) if int(m.jnt_type[i]) in (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE))
    ]
    ranges = np.array([m.jnt_range[i] if m.jnt_limited[i] else (-np.pi, np.pi) for i in moving])
    frames = [n for n in [m.body(i).name for i in range(1, m.nbody)] + [m.site(i).name for i in range(m.nsite)] if n]
    return [m.joint(i).name for i in moving], frames, ranges


@needs_newton
@pytest.mark.parametrize("robot", [pytest.param(r, marks=() if r in QUICK else pytest.mark.slow) for r in PAIRS])
def test_newton_reads_each_shared_file_as_pinocchio_and_mujoco_do_within_its_floor(robot):
    """Every body, link and site of each shared file, at random joint values in range: Newton against the
    file's primary reader (Pinocchio for the URDF, MuJoCo for the MJCF), FK and Jacobians."""
    folder = REAL_ROBOTS / robot
    if not folder.is_dir():
        pytest.skip("the shared real robots are absent")
    urdf = read_urdf(str(folder / PAIRS[robot][0]), [], [])[1]
    mjcf = read_mjcf(str(folder / PAIRS[robot][1]), [])[1]
    rng = np.random.default_rng(0)
    for text, load, names, ref_cls, name in (
        (urdf, "from_urdf", _urdf_names, PinocchioBackend, "newton-urdf"),
        (mjcf, "from_mjcf", _mjcf_names, MujocoBackend, "newton-mjcf"),
    ):
        joints, frames, ranges = names(text)
        assert joints and frames, (robot, name)
        newton_ = getattr(backend_info(name).backend_class, load)(text, joints, frames, name=name)
        ref = getattr(ref_cls, load)(text, joints, frames)
        q = rng.uniform(ranges[:, 0], ranges[:, 1], (12, len(joints)))  # within the joints' ranges
        pos, rot, lin, ang = _errors(newton_.evaluate(q), ref.evaluate(q))
        for prop, err in (("fk.position", pos), ("fk.rotation", rot), ("jacobian.linear", lin), ("jacobian.angular", ang)):
            assert err <= pair_floor(prop, newton_), (robot, name, prop, err)


@needs_newton
def test_a_site_of_the_mjcf_worldbody_stays_where_mujoco_puts_it():
    """Newton hangs a <worldbody> site on body -1 (the world): the adapter keeps it there."""
    sources = ModelSources.from_spec(load_spec("models/panda.toml"))
    joints, frames = sources.joint_names, ("target", "flange")
    q = spec_samples(load_spec("models/panda.toml"), 5, seed=4)
    newton_ = backend_info("newton-mjcf").backend_class.from_mjcf(sources.mjcf, joints, frames)
    ref = MujocoBackend.from_mjcf(sources.mjcf, joints, frames)
    pos, rot, lin, ang = _errors(newton_.evaluate(q), ref.evaluate(q))
    assert pos <= pair_floor("fk.position", newton_) and lin <= pair_floor("jacobian.linear", newton_), (pos, lin)
    assert np.abs(newton_.evaluate(q).jacobians[:, 0]).max() == 0.0  # the world's site does not move


@needs_newton
def test_verify_the_panda_passes_with_the_newton_backends(tmp_path):
    from kinverify.cli import main

    out = tmp_path / "r.json"
    code = main(
        [
            "verify",
            "models/panda.toml",
            "--samples",
            "20",
            "--ik-targets",
            "5",
            "--skip",
            "tracking",
            "--skip",
            "pictures",
            "--quiet",
            "--json",
            str(out),
            "--report",
            str(tmp_path / "r.html"),
        ]
    )
    result = json.loads(out.read_text())
    newton_checks = [c for c in result["checks"] if {"newton-urdf", "newton-mjcf", "newton-usd"} & set(c["backends"])]
    assert code == 0 and result["verdict"] == "pass"
    assert {"newton-urdf", "newton-mjcf"} <= set(result["backends"])
    assert ("newton-usd" in result["backends"]) == backend_info("newton-usd").available  # the spec's generated USD
    assert {c["property"] for c in newton_checks} >= {"fk.position", "jacobian.angular", "jacobian.fd", "ik.cross_fk"}
    assert any(c["max_error"] > 1e-9 and c["passed"] for c in newton_checks)  # held to its floor, not to 1e-9


@needs_newton
def test_quirk_newton_mjcf_makes_one_joint_of_two_in_one_body():
    """backends/quirks.py, newton-mjcf: two hinges in one body become one joint named by joining theirs."""
    sources = ModelSources.from_spec(load_spec("models/panda.toml"))
    two = sources.mjcf.replace(
        '<joint name="panda_joint4" ',
        '<joint name="extra" type="hinge" axis="1 0 0" range="-1 1"/><joint name="panda_joint4" ',
        1,
    )
    with pytest.raises(UnknownNameError) as err:
        backend_info("newton-mjcf").backend_class.from_mjcf(two, ["extra"], ["flange"])
    assert "extra_panda_joint4" in err.value.available and "panda_joint4" not in err.value.available


needs_newton_usd = pytest.mark.skipif(not backend_info("newton-usd").available, reason="the newton extra is not installed")


@needs_newton_usd
def test_newton_usd_reads_the_panda_specs_usd_as_pinocchio_reads_its_urdf_at_its_floor():
    """The spec's generated USD (tools are plain Xforms: their pose in the link from the stage)."""
    spec = load_spec("models/panda.toml")
    sources = ModelSources.from_spec(spec)
    q = spec_samples(spec, 40, seed=5)
    newton_ = build_backend("newton-usd", sources)
    assert "flange" in newton_.frames
    for ref in ("usd", "pinocchio-urdf"):
        pos, rot, lin, ang = _errors(newton_.evaluate(q), build_backend(ref, sources).evaluate(q))
        for prop, err in (("fk.position", pos), ("fk.rotation", rot), ("jacobian.linear", lin), ("jacobian.angular", ang)):
            assert err <= pair_floor(prop, newton_), (ref, prop, err)
        assert pos > 1e-8, "float32"


USD_FILES = {
    "anymal_c": "anymal_c_isaaclab.usda",  # Isaac Lab's asset
    "apollo": "apptronik_apollo.usda",  # structured layers, nested bodies, sites, a static world_link
    "panda": "panda_urdf-usd-converter.usda",
    "iiwa14": "iiwa14_urdf-usd-converter.usda",
    "z1": "z1_urdf-usd-converter.usda",
    "go2": "go2_urdf-usd-converter.usda",
    "a1": "a1_urdf-usd-converter.usda",
    "leap_hand": "leap_hand_urdf-usd-converter.usda",
    "ur5e": "ur5e_urdf-usd-converter.usda",
}


@needs_newton_usd
@pytest.mark.parametrize(
    "robot", [pytest.param(r, marks=() if r in ("anymal_c", "apollo") else pytest.mark.slow) for r in USD_FILES]
)
def test_newton_usd_reads_each_shared_usd_as_pxr_does_within_its_floor(robot):
    """Every rigid body, site and plain Xform of each shared USD (on the two whose mesh layers are absent the
    stage has composition errors, so Newton reads it flattened), at random joint values in range, floating base
    included: Newton's add_usd against kinverify's own reading of the stage (the usd backend)."""
    path = REAL_ROBOTS / robot / USD_FILES[robot]
    if not path.is_file():
        pytest.skip("the shared real robots are absent")
    usd = load_robot(str(path))
    # Isaac Lab's ANYmal C and Apollo reference mesh layers that are absent: Newton is given the stage flattened
    assert bool(usd.stage.GetCompositionErrors()) == (robot in ("anymal_c", "apollo")), robot
    joints = [j.name for j in usd.joints if j.kind in ("revolute", "prismatic")]
    frames = [usd.names[b] for b in usd.bodies] + sorted(usd.sites)
    ranges = np.array([[max(usd.joint(j).lower, -np.pi), min(usd.joint(j).upper, np.pi)] for j in joints])
    q = np.random.default_rng(0).uniform(ranges[:, 0], ranges[:, 1], (12, len(joints)))
    base = [list(BASE_COORDINATES)] if usd.floating else []
    for names in [joints] + [b + joints for b in base]:
        qq = q if names is joints else np.hstack([np.random.default_rng(1).uniform(-1, 1, (12, 6)), q])
        newton_ = backend_info("newton-usd").backend_class.from_usd(str(path), names, frames)
        pos, rot, lin, ang = _errors(newton_.evaluate(qq), UsdBackend.from_usd(str(path), names, frames).evaluate(qq))
        for prop, err in (("fk.position", pos), ("fk.rotation", rot), ("jacobian.linear", lin), ("jacobian.angular", ang)):
            assert err <= pair_floor(prop, newton_), (robot, len(names), prop, err)


@needs_newton
def test_newton_mjcf_floats_only_the_files_free_body_and_leaves_a_static_top_level_body_out():
    """Apollo's MJCF: a free base_link and a static world_link, both top-level. Newton honours the file's free
    joint (world_link stays welded: an articulation of its own, which does not move) and agrees with MuJoCo."""
    path = REAL_ROBOTS / "apollo" / "apollo_menagerie.xml"
    if not path.is_file():
        pytest.skip("the shared real robots are absent")
    mjcf = read_mjcf(str(path), [])[1]  # meshes removed, and the free joint (file mode holds a free base at the origin)
    text = mjcf.replace('<body name="base_link">', '<body name="base_link"><freejoint/>', 1)
    assert text != mjcf and '<body name="world_link"' in text
    joints, frames, ranges = _mjcf_names(text)
    names = list(BASE_COORDINATES) + joints
    newton_ = backend_info("newton-mjcf").backend_class.from_mjcf(text, names, frames)
    assert newton_.one.articulation_count == 2
    rng = np.random.default_rng(3)
    q = np.hstack([rng.uniform(-1, 1, (8, 6)), rng.uniform(ranges[:, 0], ranges[:, 1], (8, len(joints)))])
    pos, rot, lin, ang = _errors(newton_.evaluate(q), MujocoBackend.from_mjcf(text, names, frames).evaluate(q))
    for prop, err in (("fk.position", pos), ("fk.rotation", rot), ("jacobian.linear", lin), ("jacobian.angular", ang)):
        assert err <= pair_floor(prop, newton_), (prop, err)


@needs_newton_usd
@pytest.mark.parametrize("header", ["", "\n    metersPerUnit = 0.01"])
def test_quirk_newton_usd_ignores_meters_per_unit_and_the_backend_says_so(tmp_path, header):
    """backends/quirks.py, newton-usd: a joint frame at 0.1 stage units in a centimetre stage (authored, or USD's
    fallback) is 0.001 m; Newton's add_usd puts it at 0.1 m, so newton-usd refuses such a stage, naming it."""
    from kinverify.errors import BackendError

    path = tmp_path / "cm.usda"
    path.write_text(
        f'#usda 1.0\n(\n    upAxis = "Z"{header}\n)\n'
        'def Xform "r"\n{\n'
        '    def Xform "b0" (apiSchemas = ["PhysicsRigidBodyAPI", "PhysicsMassAPI", "PhysicsArticulationRootAPI"])\n'
        "    {\n        float physics:mass = 1\n    }\n"
        '    def Xform "b1" (apiSchemas = ["PhysicsRigidBodyAPI", "PhysicsMassAPI"])\n'
        "    {\n        float physics:mass = 1\n    }\n"
        '    def PhysicsFixedJoint "root"\n    {\n        rel physics:body1 = </r/b0>\n    }\n'
        '    def PhysicsRevoluteJoint "j1"\n    {\n        uniform token physics:axis = "Z"\n'
        "        rel physics:body0 = </r/b0>\n        rel physics:body1 = </r/b1>\n"
        "        point3f physics:localPos0 = (0, 0, 0.1)\n    }\n}\n"
    )
    usd = UsdBackend.from_usd(str(path), ["j1"], ["b1"])
    assert usd.poses(np.zeros((1, 1)))[0, 0, 2, 3] == pytest.approx(0.001)
    builder = newton_module().ModelBuilder()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        builder.add_usd(str(path))
    said = any("non-unit linear units are not supported" in str(w.message) for w in caught)
    assert said == bool(header)  # Newton warns of an authored metersPerUnit only, not of USD's fallback
    assert builder.finalize(device="cpu").joint_X_p.numpy()[-1][2] == pytest.approx(0.1)  # Newton's own reading: metres
    with pytest.raises(BackendError, match=r"ignores the stage's metersPerUnit \(0.01, .*100 times as far"):
        backend_info("newton-usd").backend_class.from_usd(str(path), ["j1"], ["b1"])


def newton_module():
    return pytest.importorskip("newton")
