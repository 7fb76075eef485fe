"""Valid MJCF beyond the robot: a deformable ``<flexcomp>`` (free or pinned), a body moved by
unnamed joints, a model ``<attach>``-ed from an asset, a ``<composite>``. Each is read and what is
not the robot is named as not compared (kinverify/filemode/read/describe_mjcf.py), or refused in
one line when MuJoCo itself cannot load it: never an internal error. Any ``<flexcomp>`` was a
RecursionError in matching (its vertex bodies' unnamed joints were each other's parent)."""

from __future__ import annotations

import json

import pytest

from tests.fuzz.conftest import FILES
from tests.fuzz.harness import run_checked

INERTIAL = '<inertial pos="0 0 0" mass="0.1" diaginertia="1e-4 1e-4 1e-4"/>'
FLEX = '<flexcomp name="cloth" type="grid" count="3 3 1" spacing="0.05 0.05 0.05" radius="0.01" dim="2" mass="0.1"'
EXTRAS = {
    "flexcomp": f'<body name="holder" pos="1 1 0.1">{INERTIAL}{FLEX}/></body>',
    "pinned flexcomp": f'<body name="holder" pos="1 1 0.1">{INERTIAL}{FLEX}><pin id="0 2"/></flexcomp></body>',
    "unnamed joints": f'<body name="puck" pos="1 1 0.1"><joint type="slide" axis="1 0 0"/><joint type="slide" axis="0 1 0"/>'
    f"{INERTIAL}</body>",
    "attach": '<body name="mount" pos="0.5 0 0"><attach model="grip" body="finger" prefix="g_"/></body>',
    "composite": '<body name="rope" pos="1 1 0.5"><composite type="cable" count="5 1 1" curve="s" size="0.5" '
    'initial="none"><geom type="capsule" size=".005" density="100"/></composite></body>',
}
NOTES = {
    "flexcomp": "flex cloth: a deformable object of 9 bodies (<flexcomp>), not part of the robot: not compared",
    "pinned flexcomp": "flex cloth: a deformable object of 7 bodies",
    "unnamed joints": "body puck: moved by an unnamed joint; it and the bodies it carries are not compared",
}
GRIPPER = (
    '<mujoco model="gripper"><worldbody><body name="finger" pos="0 0 0.05"><joint name="slide" type="slide" '
    f'axis="1 0 0" range="0 0.04"/>{INERTIAL}</body></worldbody></mujoco>\n'
)


@pytest.mark.parametrize("extra", list(EXTRAS))
def test_mjcf_beyond_the_robot_is_read_or_refused_never_an_internal_error(capfd, work, extra):
    mjcf = (work / "r.xml").read_text().replace("</worldbody>", EXTRAS[extra] + "</worldbody>", 1)
    if extra == "attach":
        (work / "grip.xml").write_text(GRIPPER)
        mjcf = mjcf.replace("<worldbody>", '<asset><model name="grip" file="grip.xml"/></asset><worldbody>', 1)
    (work / "x.xml").write_text(mjcf)
    pair = extra in NOTES  # the robot is unchanged: the pair agrees, and says what it left out
    argv = ["verify", *(["--urdf", "u.urdf"] if pair else []), "--mjcf", "x.xml", *FILES, "--json", "out/r.json"]
    code, err = run_checked(capfd, argv, [work / "x.xml", work / "u.urdf"], work)
    if extra == "composite" and code == 2:  # MuJoCo 4 no longer has <composite>: its own words, one line
        assert "x.xml" in err and "composite" in err, err
        return
    assert code == 0, err
    if pair:
        notes = json.loads((work / "out" / "r.json").read_text())["notes"]
        assert any(NOTES[extra] in note for note in notes), notes
