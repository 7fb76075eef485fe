"""A serial chain as IK sees it, with batched numpy FK and Jacobian of its tip.

``T(q) = C₀ M₀(q₀) C₁ M₁(q₁) … M_{k−1}(q_{k−1}) C_k``: constant transforms ``C`` and joint motions
``M`` canonicalised to the local z axis (each joint axis's rotation is folded into the constants),
so ``M_i`` is ``Rz(q_i)`` for a revolute joint and ``Tz(q_i)`` for a prismatic one. Built from
any URDF between two links (:meth:`SerialChain.from_urdf`, numpy only: no library) or from a spec
for one of its frames (:meth:`SerialChain.from_spec`, the same model as the ``analytic`` backend).

Convention (kinverify's): poses ``T_base_from_tip`` in metres; Jacobians world(base)-aligned at
the tip origin, rows ``[linear; angular]``; q in rad (revolute) or m (prismatic). The chain may
be narrower than the configuration: joints that do not move the tip (``columns``) get zero
Jacobian columns, so solvers leave them where they are.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from kinverify.errors import InputError, UnknownNameError


@dataclass
class SerialChain:
    """``consts`` ``(k + 1, 4, 4)``; ``revolute``, ``lower``, ``upper`` ``(k,)`` per chain joint
    (±inf for continuous joints); ``names`` of the chain joints; ``columns`` ``(k,)``: each chain
    joint's index in a configuration of ``width`` joints (default: the chain itself)."""

    consts: np.ndarray
    revolute: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    names: list[str] = field(default_factory=list)
    columns: np.ndarray | None = None
    width: int | None = None

    def __post_init__(self) -> None:
        k = len(self.revolute)
        self.columns = np.arange(k) if self.columns is None else np.asarray(self.columns, int)
        self.width = k if self.width is None else int(self.width)
        # per step i: [C_{i}ᵀ rotation; translation ᵀ] (4×3), so one GEMM rotates and translates
        self._g = [np.vstack([c[:3, :3].T, c[:3, 3][None]]) for c in self.consts]

    @property
    def dof(self) -> int:
        """Joints on the chain."""
        return len(self.revolute)

    # --- construction -----------------------------------------------------------------------
    @classmethod
    def from_joints(cls, joints, tip: np.ndarray, names=(), columns=None, width=None) -> "SerialChain":
        """``joints``: per moving joint ``(origin (4, 4) from the previous joint's frame, axis (3,),
        revolute, lower, upper)``; ``tip`` (4, 4): the tip in the last joint's frame."""
        consts, rev, lo, hi = [], [], [], []
        carry = np.eye(4)  # A⁻¹ of the previous joint: back from its z-aligned frame
        for origin, axis, revolute, lower, upper in joints:
            a = np.eye(4)
            a[:3, :3] = _z_to_axis(axis)
            consts.append(carry @ origin @ a)
            carry = a.T.copy()  # rotation only: inverse = transpose
            rev.append(bool(revolute))
            lo.append(float(lower))
            hi.append(float(upper))
        consts.append(carry @ tip)
        return cls(np.array(consts), np.array(rev, bool), np.array(lo), np.array(hi), list(names), columns, width)

    @classmethod
    def from_spec(cls, spec, frame: str) -> "SerialChain":
        """The chain from the spec's base to ``frame`` (a link or a tool) of the spec, over all
        ``spec.dof`` joints: the joints on the path from the base to the frame's link (in a tree,
        the frame's own branch), the others (further out, or on another branch) get zero columns."""
        from kinverify.model.kinematics import frame_link_indices

        if frame not in spec.frame_names:
            raise UnknownNameError("frame", frame, spec.frame_names)
        link = int(frame_link_indices(spec)[spec.frame_names.index(frame)])
        path = np.flatnonzero(spec.ancestors()[link])  # base to tip: a joint's parent link always comes earlier
        tools = {t.name: t for t in spec.tools}
        tip = tools[frame].origin.transform if frame in tools else np.eye(4)
        on_path = [spec.joints[i] for i in path]
        joints = [(j.origin.transform, j.axis, j.type == "revolute", j.limits.lower, j.limits.upper) for j in on_path]
        first = spec.base_origin.transform
        if joints:
            joints[0] = (first @ joints[0][0],) + joints[0][1:]
        else:
            tip = first @ tip
        return cls.from_joints(joints, tip, [j.name for j in on_path], path, spec.dof)

    @classmethod
    def from_urdf(cls, urdf_text: str, base: str | None, tip: str, source: str = "URDF") -> "SerialChain":
        """The chain from link ``base`` (None: the root link) to link ``tip`` of a URDF (revolute,
        continuous, prismatic and fixed joints; names are looked up among links only, so a joint
        named like a link cannot be taken for it). Untrusted text is parsed with defusedxml:
        entities and external references are refused."""
        import defusedxml
        import defusedxml.ElementTree as DET

        try:
            root = DET.fromstring(urdf_text.encode(), forbid_dtd=False, forbid_entities=True, forbid_external=True)
        except defusedxml.DefusedXmlException as err:
            raise InputError(
                f"{source}: unsafe XML refused ({type(err).__name__}: entities and external references are not read)"
            ) from None
        except Exception as err:  # ParseError
            raise InputError(f"{source}: not XML: {err}") from None
        if root.tag != "robot":
            raise InputError(f"{source}: not a URDF (root element <{root.tag}>, expected <robot>)")
        return cls.from_urdf_root(root, base, tip, source)

    @classmethod
    def from_urdf_root(cls, root, base: str | None, tip: str, source: str = "URDF") -> "SerialChain":
        if base is None:
            base = root_link(root, source)
        links = [link.get("name") for link in root.findall("link")]
        joint_set = {j.get("name") for j in root.findall("joint")}
        for which, name in (("--base", base), ("--tip", tip)):
            if name not in links:
                raise InputError(
                    f"{which}: {source} has no link {name!r}"
                    + (" (a joint has that name)" if name in joint_set else "")
                    + f"; links: {', '.join(links)}"
                )
        by_child = {j.find("child").get("link"): j for j in root.findall("joint") if j.find("child") is not None}
        path: list = []
        link = tip
        while link != base:
            if link not in by_child or len(path) >= len(by_child):  # at most one step per joint (a cycle never ends)
                raise InputError(f"{source}: link {tip!r} is not below link {base!r}")
            path.append(by_child[link])
            link = by_child[link].find("parent").get("link")
        joints, names, fixed = [], [], np.eye(4)
        for j in reversed(path):
            fixed = fixed @ _origin(j, source)
            kind = j.get("type")
            if kind == "fixed":
                continue
            if kind not in ("revolute", "continuous", "prismatic"):
                raise InputError(
                    f"{source}: joint {j.get('name')!r} on the chain is {kind!r}; IK handles revolute, "
                    "continuous, prismatic and fixed joints"
                )
            if j.find("mimic") is not None:
                raise InputError(f"{source}: joint {j.get('name')!r} on the chain mimics another joint; not supported")
            axis = _floats(j.find("axis"), "xyz", "1 0 0", 3, source, j)
            if not np.linalg.norm(axis) > 0:
                raise InputError(f"{source}: joint {j.get('name')!r} has a zero axis")
            limit = j.find("limit")
            lower, upper = -math.inf, math.inf
            if kind != "continuous":
                if limit is None:
                    raise InputError(f"{source}: joint {j.get('name')!r} ({kind}) has no <limit>")
                lower, upper = (_floats(limit, key, "0", 1, source, j)[0] for key in ("lower", "upper"))
                if not lower <= upper:
                    raise InputError(f"{source}: joint {j.get('name')!r} has lower limit {lower} > upper {upper}")
            joints.append((fixed, axis, kind != "prismatic", lower, upper))
            names.append(j.get("name"))
            fixed = np.eye(4)
        return cls.from_joints(joints, fixed, names)

    # --- kinematics ---------------------------------------------------------------------------
    def fk_jac_soa(self, qT: np.ndarray, jacobian: bool = True):
        """Structure-of-arrays FK + Jacobian, the batch on the *last* axis.

        ``qT`` ``(width, N)`` -> ``S`` ``(3, 3, N)`` with ``S[k]`` the k-th column of the tip
        rotation (``S[k, i, t] = R_t[i, k]``), ``p`` ``(3, N)`` [m], ``J`` ``(6, width, N)`` or None.
        Per joint: ``R ← R·Rz(q)`` touches two columns, then one GEMM ``[Cᵀ; tᵀ] (4×3) @ (3, 3N)``
        gives the new columns and the position increment. Columns: ``[z × (p − o); z]``
        (revolute), ``[z; 0]`` (prismatic), z and o the joint axis and origin in the base frame.
        """
        n_cfg = qT.shape[1]
        q = qT[self.columns]
        c, s = np.cos(q), np.sin(q)
        rot = np.empty((3, 3, n_cfg))
        rot[:] = self.consts[0, :3, :3].T[:, :, None]
        p = np.empty((3, n_cfg))
        p[:] = self.consts[0, :3, 3][:, None]
        k = self.dof
        z, o = (np.empty((3, k, n_cfg)), np.empty((3, k, n_cfg))) if jacobian else (None, None)
        work = np.empty((3, 3, n_cfg))
        for i in range(k):
            if jacobian:
                assert z is not None and o is not None  # made whenever jacobian
                z[:, i], o[:, i] = rot[2], p
            if self.revolute[i]:
                np.multiply(rot[0], c[i], out=work[0])
                work[0] += rot[1] * s[i]
                np.multiply(rot[1], c[i], out=work[1])
                work[1] -= rot[0] * s[i]
                work[2] = rot[2]
                out = self._g[i + 1] @ work.reshape(3, 3 * n_cfg)
            else:
                p = p + rot[2] * q[i]
                out = self._g[i + 1] @ rot.reshape(3, 3 * n_cfg)
            rot = out[:3].reshape(3, 3, n_cfg)
            p = p + out[3].reshape(3, n_cfg)
        if not jacobian:
            return rot, p, None
        assert z is not None and o is not None
        d = p[:, None, :] - o
        cols = np.empty((6, k, n_cfg))
        cols[0] = z[1] * d[2] - z[2] * d[1]
        cols[1] = z[2] * d[0] - z[0] * d[2]
        cols[2] = z[0] * d[1] - z[1] * d[0]
        cols[3:] = z
        if not self.revolute.all():
            prismatic = ~self.revolute
            cols[:3, prismatic] = z[:, prismatic]
            cols[3:, prismatic] = 0.0
        assert self.columns is not None and self.width is not None  # set in __post_init__
        if k == self.width and (self.columns == np.arange(k)).all():
            return rot, p, cols
        jac = np.zeros((6, self.width, n_cfg))
        jac[:, self.columns] = cols
        return rot, p, jac

    def fk_jac(self, q: np.ndarray):
        """``q`` ``(N, width)`` -> ``R`` ``(N, 3, 3)``, ``p`` ``(N, 3)``, ``J`` ``(N, 6, width)`` (views)."""
        rot, p, jac = self.fk_jac_soa(np.asarray(q, float).T)
        return rot.transpose(2, 1, 0), p.T, jac.transpose(2, 0, 1)

    def poses(self, q: np.ndarray) -> np.ndarray:
        """Tip poses ``(N, 4, 4)`` of configurations ``(N, width)``."""
        rot, p, _ = self.fk_jac_soa(np.atleast_2d(np.asarray(q, float)).T, jacobian=False)
        out = np.zeros((p.shape[1], 4, 4))
        out[:, :3, :3] = rot.transpose(2, 1, 0)
        out[:, :3, 3] = p.T
        out[:, 3, 3] = 1.0
        return out


def root_link(root, source: str = "URDF") -> str:
    """The URDF's one link that is no joint's child."""
    children = {j.find("child").get("link") for j in root.findall("joint") if j.find("child") is not None}
    roots = [link.get("name") for link in root.findall("link") if link.get("name") not in children]
    if len(roots) != 1:
        raise InputError(f"{source} has {len(roots)} root links ({', '.join(roots[:5])}); give --base LINK")
    return roots[0]


def _z_to_axis(axis) -> np.ndarray:
    """A rotation ``A`` with ``A @ [0, 0, 1]`` = the unit ``axis``."""
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    v = np.array([-a[1], a[0], 0.0])  # z × a
    s, c = float(np.linalg.norm(v)), float(a[2])
    if s < 1e-12:
        return np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])
    k = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]]) / s
    return np.eye(3) + s * k + (1 - c) * (k @ k)


def _floats(element, key: str, default: str, count: int, source: str, joint) -> np.ndarray:
    text = default if element is None else element.get(key, default)
    try:
        values = np.array([float(x) for x in text.split()])
    except ValueError:
        values = np.array([])
    if len(values) != count or not np.isfinite(values).all():
        raise InputError(f"{source}: joint {joint.get('name')!r}: {key}={text!r} is not {count} finite number(s)")
    return values


def _origin(joint, source: str) -> np.ndarray:
    from kinverify.model.transforms import rpy_to_matrix

    o = joint.find("origin")
    t = np.eye(4)
    t[:3, :3] = rpy_to_matrix(_floats(o, "rpy", "0 0 0", 3, source, joint))
    t[:3, 3] = _floats(o, "xyz", "0 0 0", 3, source, joint)
    return t
