"""The index maps deployment code needs, between every two files (an actuator table has no order).

Every map is a gather: ``to_vector = from_vector[index]`` (numpy), ``index[k]`` being the position
in FROM's order of the k-th entry of TO's order, ``None`` where FROM lacks it:

- ``joints``: joint vectors (positions, velocities, per-joint gains) from one file's joint order
  to another's (the 1-DOF joints in the simulator's order; MuJoCo's ``qpos`` addresses are in
  each side's ``qpos_index``);
- ``actuators``: control vectors between two files that both state actuators (an actuator is
  known by the joints it drives);
- ``joints_to_actuators``: from a file's joint order to a file's actuator (``ctrl``) order,
  the file itself included: a policy whose actions follow the joint order (Isaac Lab) deployed on
  MuJoCo's actuators. ``None`` for an actuator that drives a tendon (its control is no joint's)."""

from __future__ import annotations

from kinverify.map.compare import actuator_rows
from kinverify.map.rows import Rows


def _positions(rows: Rows, s: int) -> dict[int, int]:
    """Row -> position in side ``s``'s joint order."""
    side = rows.sides[s]
    return {r: side.names.index(rows.name(r, s)) for r in range(len(rows.names)) if rows.names[r][s] is not None}


def joint_map(rows: Rows, a: int, b: int) -> list[int | None]:
    """``q_b = q_a[index]``."""
    pos_a, pos_b = _positions(rows, a), _positions(rows, b)
    order_b = sorted(pos_b, key=pos_b.__getitem__)
    return [pos_a.get(r) for r in order_b]


def actuator_map(rows: Rows, a: int, b: int) -> list[int | None]:
    """``ctrl_b = ctrl_a[index]``."""
    ka, kb = actuator_rows(rows, a), actuator_rows(rows, b)
    return [ka.index(k) if k and k in ka else None for k in kb]


def joints_to_actuators(rows: Rows, a: int, b: int) -> list[int | None]:
    """``ctrl_b = x_a[index]`` for ``x_a`` in side ``a``'s joint order."""
    pos_a = _positions(rows, a)
    acts = rows.sides[b].actuators or []
    return [pos_a.get(k[0]) if act.direct and len(k) == 1 else None for act, k in zip(acts, actuator_rows(rows, b), strict=True)]


def all_maps(rows: Rows) -> dict[str, list[dict]]:
    files = [s for s, side in enumerate(rows.sides) if side.ordered]
    label = {s: rows.sides[s].label for s in files}
    acting = [s for s in files if rows.sides[s].actuators is not None]
    return {
        "joints": [{"from": label[a], "to": label[b], "index": joint_map(rows, a, b)} for a in files for b in files if a != b],
        "actuators": [
            {"from": label[a], "to": label[b], "index": actuator_map(rows, a, b)} for a in acting for b in acting if a != b
        ],
        "joints_to_actuators": [
            {"from": label[a], "to": label[b], "index": joints_to_actuators(rows, a, b)} for a in files for b in acting
        ],
    }
