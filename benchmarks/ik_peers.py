"""The IK comparison's problem, judge and solvers: kinverify's and its peers' (TRAC-IK through
``pytracik``, Robotics Toolbox ``ik_LM``/``ik_NR``, ``ikpy``), each behind one call
``run(targets (N, 4, 4), q0 (N, n)) -> (q (N, n), NaN rows = no answer; seconds per target (N,);
CPU seconds per target (N,))``: the process CPU time (all its threads) leaves out the time the
scheduler gave other processes, so it shows a solver's own cost on a loaded machine.

Peers come from the ``bench`` extra (``pip install -e .[bench]``); one that cannot be imported
or set up is skipped with one line saying why. Every solver gets the same targets and initial
guesses and a tolerance that lets it meet the judge's success rule; the judge is Pinocchio's FK
on the returned q (kinverify's own FK is not used to judge it).
"""

from __future__ import annotations

import os
import time
import warnings
import xml.etree.ElementTree as ET
from dataclasses import dataclass

import numpy as np


@dataclass
class Problem:
    urdf: str  # path
    text: str
    base: str
    tip: str
    lower: np.ndarray
    upper: np.ndarray
    joints: list[str]
    targets: np.ndarray  # (N, 4, 4): FK of uniform random in-limit configurations
    q0: np.ndarray  # (N, n): uniform random in-limit initial guesses, the same for every solver


def make_problem(urdf: str, base: str, tip: str, n: int, target_seed: int = 12345, q0_seed: int = 67890) -> Problem:
    from kinverify.ik.chain import SerialChain

    text = open(urdf).read()
    chain = SerialChain.from_urdf(text, base, tip, urdf)
    lower, upper = chain.lower, chain.upper
    judge = Judge(text, chain.names, tip)
    q_true = np.random.default_rng(target_seed).uniform(lower, upper, (n, chain.dof))
    targets = np.array([judge.pose(q) for q in q_true])
    q0 = np.random.default_rng(q0_seed).uniform(lower, upper, (n, chain.dof))
    return Problem(urdf, text, base, tip, lower, upper, chain.names, targets, q0)


class Judge:
    """Pinocchio's FK of the tip (a body frame: a joint may share a link's name), the other joints
    (e.g. a mimic finger) at neutral; the base must be the URDF's root."""

    def __init__(self, text: str, joints: list[str], tip: str) -> None:
        import pinocchio as pin

        from kinverify.backends.pinocchio_ import PinocchioBackend

        self.backend = PinocchioBackend.from_urdf(text, joints, [tip], name="judge")
        self.pin = pin

    def pose(self, q) -> np.ndarray:
        return self.backend.poses(np.asarray(q, float)[None])[0, 0]

    def errors(self, q: np.ndarray, targets: np.ndarray, lower, upper):
        """Position [m], rotation [rad] errors and 'inside the limits' per answer (inf, False for none)."""
        pe, re, inside = np.full(len(q), np.inf), np.full(len(q), np.inf), np.zeros(len(q), bool)
        given = np.all(np.isfinite(q), axis=1)
        if given.any():
            poses = self.backend.poses(q[given])[:, 0]
            pe[given] = np.linalg.norm(poses[:, :3, 3] - targets[given, :3, 3], axis=1)
            re[given] = [
                np.linalg.norm(self.pin.log3(p[:3, :3].T @ t[:3, :3])) for p, t in zip(poses, targets[given], strict=True)
            ]
            inside[given] = np.all((q[given] >= lower - 1e-9) & (q[given] <= upper + 1e-9), axis=1)
        return pe, re, inside


def timed_loop(fn, targets, q0):
    """``fn(k, target, q0) -> q | None`` called per target under ``perf_counter`` and ``process_time``."""
    out, times, cpu = np.full(q0.shape, np.nan), np.empty(len(q0)), np.empty(len(q0))
    for k in range(len(q0)):
        t0, c0 = time.perf_counter(), time.process_time()
        q = fn(k, targets[k], q0[k])
        times[k], cpu[k] = time.perf_counter() - t0, time.process_time() - c0
        if q is not None:
            out[k] = q
    return out, times, cpu


# --- kinverify ---------------------------------------------------------------------------------
def kinverify_solvers(p: Problem, pos_tol: float, rot_tols) -> list:
    """Per target on Pinocchio (each target timed alone) and batched on the URDF chain (numpy;
    time = batch time / N); the first attempt from the given guess, or ``seeded``: from whichever
    of the given guess and kinverify's best stored configuration is nearer the target (the
    default of ``kinverify ik`` without ``--initial`` and of ``verify``). Tighter rotation
    tolerances: the seeded rows only."""
    from kinverify.backends.pinocchio_ import PinocchioBackend
    from kinverify.ik import FrameModel, IKOptions, SerialChain, solve_lm

    chain_model = FrameModel.from_chain(SerialChain.from_urdf(p.text, p.base, p.tip), "urdf-chain", p.tip)
    pin_model = FrameModel(PinocchioBackend.from_urdf(p.text, p.joints, [p.tip]), p.tip, chain_model.revolute)
    pin_model.seed_model = chain_model  # one seed table (built in setup, not timed)
    out = []
    for rot_tol in rot_tols:
        asked = "" if rot_tol == rot_tols[0] else f", asked {rot_tol:g} rad"
        for start in ("seeded", "given") if not asked else ("seeded",):
            opts = IKOptions(tol_pos=pos_tol, tol_rot=rot_tol, start=start)
            how = "from the better of q0 and its best seed" if start == "seeded" else "from q0"
            for label, model, batch in (
                (f"kinverify, per target (Pinocchio), {how}{asked}", pin_model, False),
                (f"kinverify, batched (numpy, batch time / N), {how}{asked}", chain_model, True),
            ):

                def run(targets, q0, model=model, batch=batch, opts=opts):
                    sol = solve_lm(model, targets, p.lower, p.upper, False, opts, q0=q0, batch=batch)
                    return sol.q, sol.time_s, sol.extra["cpu_s"]

                out.append((label, run, {"batched": batch}))
    return out


# --- peers -------------------------------------------------------------------------------------
def stripped_urdf(p: Problem, folder: str, keep_links=None) -> str:
    """A copy without ``<visual>``/``<collision>`` (RTB resolves mesh URIs and fails on absent
    meshes), optionally only ``keep_links`` and the joints between them (ikpy follows the first
    child down to a leaf and cannot stop at the tip). Returns its absolute path."""
    root = ET.fromstring(p.text)
    for link in root.findall("link"):
        for tag in ("visual", "collision"):
            for el in link.findall(tag):
                link.remove(el)
    if keep_links is not None:
        for j in list(root.findall("joint")):
            if j.find("child").get("link") not in keep_links:
                root.remove(j)
        for link in list(root.findall("link")):
            if link.get("name") not in keep_links:
                root.remove(link)
    path = os.path.join(folder, f"kinematics{'_chain' if keep_links else ''}.urdf")
    ET.ElementTree(root).write(path)
    return os.path.abspath(path)


def rtb_solvers(p: Problem, folder: str) -> list:
    """RTB 1.5: ``Robot.URDF`` fails on package:// meshes, so ``URDF_file`` on a stripped copy.
    Its tolerance bounds ``E = ½ eᵀe`` (e = [dp, angle-axis]): ``tol = 5e-13`` means ``|e| < 1e-6``."""
    import roboticstoolbox as rtb
    from roboticstoolbox.models.URDF.URDFRobot import URDF_file

    elinks, name, _ = URDF_file(stripped_urdf(p, folder))
    ets = rtb.Robot(elinks, name=name).ets(start=p.base, end=p.tip)

    def lm(k, t, q0):
        return ets.ik_LM(t, q0=q0, tol=5e-13).q

    def nr(k, t, q0):
        return ets.ik_NR(t, q0=q0, tol=5e-13).q

    return [
        (f"RTB {rtb.__version__} ik_LM (C++, default method)", lambda T, Q: timed_loop(lm, T, Q), {}),
        (f"RTB {rtb.__version__} ik_NR (C++)", lambda T, Q: timed_loop(nr, T, Q), {}),
    ]


def tracik_solvers(p: Problem, timeout: float = 0.005, eps: float = 5e-7) -> list:
    """pytracik 0.0.3 reads this URDF's limits as 0 (every call fails), so they are set; its
    ``eps`` bounds each twist component: 5e-7 keeps the position within √3·5e-7 < 1e-6 m."""
    import importlib.metadata

    import pinocchio as pin
    import pytracik

    solver = pytracik.TRAC_IK(p.base, p.tip, p.text, timeout, eps, pytracik.SolveType.Speed)
    pytracik.set_joint_limits(solver, list(p.lower), list(p.upper))

    def run(targets, q0):
        quats = [pin.Quaternion(t[:3, :3]) for t in targets]  # outside the timing

        def one(k, t, q):
            quat = quats[k]
            r = pytracik.ik(solver, q, t[0, 3], t[1, 3], t[2, 3], quat.x, quat.y, quat.z, quat.w)
            return r[1:] if r[0] >= 0 else None

        return timed_loop(one, targets, q0)

    return [(f"TRAC-IK (pytracik {importlib.metadata.version('pytracik')}), Speed, {timeout * 1e3:g} ms timeout", run, {})]


def ikpy_solvers(p: Problem, folder: str) -> list:
    import ikpy
    import ikpy.chain

    n = len(p.joints)
    keep = _links_between(p)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        chain = ikpy.chain.Chain.from_urdf_file(
            stripped_urdf(p, folder, keep),
            base_elements=[p.base],
            active_links_mask=[False] + [True] * n + [False] * (len(keep) - n - 1),
        )
    width = len(chain.links)

    def one(k, t, q0):
        init = np.zeros(width)
        init[1 : n + 1] = q0
        return chain.inverse_kinematics_frame(t, initial_position=init, orientation_mode="all")[1 : n + 1]

    return [(f"ikpy {ikpy.__version__} (scipy least squares, no restarts)", lambda T, Q: timed_loop(one, T, Q), {})]


def _links_between(p: Problem) -> set[str]:
    root = ET.fromstring(p.text)
    parent = {j.find("child").get("link"): j.find("parent").get("link") for j in root.findall("joint")}
    links, link = {p.tip}, p.tip
    while link != p.base:
        link = parent[link]
        links.add(link)
    return links


PEERS = {"RTB": rtb_solvers, "TRAC-IK": tracik_solvers, "ikpy": ikpy_solvers}
