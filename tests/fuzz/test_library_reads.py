"""Files a library opens on kinverify's behalf (an SDFormat ``<include>``, an MJCF ``<asset><model
file>``, a mesh) are inputs like the model itself: found before the library parses, refused when
they are not bounded regular files (a FIFO would block the parser, ``/dev/zero`` never ends, a
3 GB sparse file would be read whole, a file including itself crashed Drake), resolved relative to
the including file, and never replaced by an output, in a pair as in a one-file audit
(docs/robustness.md, files libraries open)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from kinverify.cli import main
from kinverify.generate import generate_sdf
from kinverify.model.specfile import load_spec
from tests.fuzz.conftest import FILES
from tests.fuzz.harness import deadline, refused

TIP = (
    '<sdf version="1.9"><model name="tip"><link name="tip"><inertial><mass>0.1</mass><inertia><ixx>1e-4</ixx>'
    "<iyy>1e-4</iyy><izz>1e-4</izz></inertia></inertial></link></model></sdf>\n"
)
STL = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0.01 0 0\nvertex 0 0.01 0\nendloop\nendfacet\nendsolid t\n"


def including(sdf: str, uri: str) -> str:
    """The arm3 SDFormat model with ``uri`` included as a tool fixed to its end effector."""
    inc = (
        f'<include><uri>{uri}</uri><name>tool</name></include><joint name="tool_fix" type="fixed">'
        "<parent>end_effector</parent><child>tool::tip</child></joint></model>"
    )
    i = sdf.rindex("</model>")
    return sdf[:i] + inc + sdf[i + len("</model>") :]


@pytest.fixture
def files(work) -> Path:
    """``work`` with an SDFormat robot in ``robot/`` including ``parts/inc.sdf`` (which includes
    ``tip.sdf`` beside it), an MJCF with an ``<asset><model file>`` and one with a mesh."""
    sdf = generate_sdf(load_spec(work / "m.toml"))
    (work / "robot" / "parts").mkdir(parents=True)
    (work / "robot" / "parts" / "tip.sdf").write_text(TIP)
    (work / "robot" / "parts" / "inc.sdf").write_text(
        TIP.replace('<link name="tip">', '<include><uri>tip.sdf</uri><name>inner</name></include><link name="tip">')
    )
    (work / "robot" / "main.sdf").write_text(including(sdf, "parts/inc.sdf"))
    (work / "plain.sdf").write_text(sdf)
    mjcf = (work / "r.xml").read_text()
    (work / "sub.xml").write_text(
        '<mujoco model="sub"><worldbody><body name="sb"><geom type="sphere" size="0.01"/></body></worldbody></mujoco>\n'
    )
    (work / "withmodel.xml").write_text(
        mjcf.replace("<worldbody>", '<asset><model name="sub" file="sub.xml"/></asset>\n<worldbody>', 1)
    )
    (work / "m.stl").write_text(STL)
    body = '<body name="base" pos="0.0 0.0 0.42">'
    assert body in mjcf
    (work / "withmesh.xml").write_text(
        mjcf.replace("<worldbody>", '<asset><mesh name="m" file="m.stl"/></asset>\n<worldbody>', 1).replace(
            body, body + '<geom type="mesh" mesh="m" mass="0"/>', 1
        )
    )
    return work


def run(capfd, argv) -> tuple[int, str]:
    capfd.readouterr()
    with deadline():
        code = main(argv)
    return code, capfd.readouterr().err


def test_sdf_includes_are_resolved_relative_to_the_including_file(capfd, files):
    code, err = run(capfd, ["verify", "--sdf", "robot/main.sdf", *FILES, "--json", "out/a.json"])
    assert code == 0, err
    os.chdir(files / "robot" / "parts")  # from anywhere: the same files
    code, err = run(capfd, ["verify", "--sdf", str(files / "robot" / "main.sdf"), *FILES, "--json", str(files / "out/b.json")])
    assert code == 0, err


@pytest.mark.parametrize(
    "uri, words",
    [
        ("main.sdf", "includes itself (main.sdf -> main.sdf)"),
        ("b.sdf", "includes itself (main.sdf -> b.sdf -> main.sdf)"),
        ("fifo.sdf", "fifo.sdf is a FIFO (named pipe), not a regular file"),
        ("/dev/zero", "/dev/zero is a character device, not a regular file"),
        ("big.sdf", "big.sdf: the model with the files it includes is above the 8 MB"),
        ("loop1", "loop1 cannot be read: Too many levels of symbolic links"),
        ("nowhere.sdf", "nowhere.sdf is not a file"),
    ],
)
def test_a_bad_sdf_include_is_one_line_naming_it(capfd, files, uri, words):
    sdf = (files / "plain.sdf").read_text()
    (files / "main.sdf").write_text(including(sdf, uri))
    (files / "b.sdf").write_text(including(sdf, "main.sdf"))
    os.mkfifo(files / "fifo.sdf")
    with open(files / "big.sdf", "wb") as f:
        f.truncate(3 * 2**30)  # sparse: no disk used, and never read
    os.symlink("loop2", files / "loop1")
    os.symlink("loop1", files / "loop2")
    line = refused(capfd, ["verify", "--sdf", "main.sdf", *FILES, "--json", "out/x.json"], files, words)
    assert "main.sdf" in line


@pytest.mark.parametrize(
    "argv, output",
    [
        (["verify", "--sdf", "robot/main.sdf"], "robot/parts/inc.sdf"),
        (["verify", "--sdf", "robot/main.sdf"], "robot/parts/tip.sdf"),  # included by the included file
        (["verify", "--urdf", "u.urdf", "--sdf", "robot/main.sdf"], "robot/parts/inc.sdf"),
        (["verify", "--mjcf", "withmodel.xml"], "sub.xml"),
        (["verify", "--urdf", "u.urdf", "--mjcf", "withmodel.xml"], "sub.xml"),
        (["verify", "--mjcf", "withmesh.xml"], "m.stl"),  # a one-file audit, which does not load the mesh
        (["verify", "--urdf", "u.urdf", "--mjcf", "withmesh.xml"], "m.stl"),
        (["diff", "withmesh.xml", "r.xml"], "m.stl"),
    ],
)
@pytest.mark.parametrize("flag", ["--report", "--json"])
def test_no_output_replaces_a_file_a_library_reads(capfd, files, argv, output, flag):
    if argv[0] == "diff" and flag == "--json":
        pytest.skip("diff writes a report only")
    extra = FILES if argv[0] == "verify" else []
    line = refused(capfd, [*argv, *extra, flag, output], files, "an input of this run")
    assert Path(output).name in line
    absolute = refused(capfd, [*argv, *extra, flag, str(files / output)], files, "an input of this run")
    assert Path(output).name in absolute


def test_a_present_mesh_is_not_called_absent_in_a_one_file_audit(capfd, files):
    import json

    code, err = run(capfd, ["verify", "--mjcf", "withmesh.xml", *FILES, "--json", "out/a.json"])
    assert code == 0, err
    notes = [n for n in json.loads((files / "out/a.json").read_text())["notes"] if "mesh" in n]
    assert notes and not any("absent" in n for n in notes), notes
    assert any("1 of their files present, not loaded" in n for n in notes), notes


MODEL = '<asset><model name="sub" file="{}"/></asset>\n<worldbody>'
FLEXCOMP = '<worldbody><flexcomp name="f" type="mesh" file="{}" dim="2"/>'


@pytest.mark.parametrize(
    "element, name, words",
    [
        (MODEL, "fifo.xml", "is a FIFO (named pipe), not a regular file"),
        (MODEL, "/dev/zero", "/dev/zero is a character device"),
        (MODEL, "withmodel.xml", "the model includes itself"),
        (FLEXCOMP, "fifo.xml", "is a FIFO (named pipe), not a regular file"),
        (FLEXCOMP, "/dev/zero", "/dev/zero is a character device"),
    ],
)
def test_a_bad_mjcf_model_or_flexcomp_file_is_one_line_naming_it(capfd, files, element, name, words):
    os.mkfifo(files / "fifo.xml")
    mjcf = (files / "r.xml").read_text()
    (files / "withmodel.xml").write_text(mjcf.replace("<worldbody>", element.format(name), 1))
    line = refused(capfd, ["verify", "--mjcf", "withmodel.xml", *FILES, "--json", "out/x.json"], files, words)
    assert name.rsplit("/", 1)[-1] in line


def test_a_mesh_that_is_a_fifo_or_a_device_is_refused_in_an_audit(capfd, files):
    mjcf = (files / "withmesh.xml").read_text()
    os.mkfifo(files / "fifo.stl")
    (files / "m.xml").write_text(mjcf.replace('file="m.stl"', 'file="fifo.stl"'))
    refused(capfd, ["verify", "--mjcf", "m.xml", *FILES], files, "fifo.stl is a FIFO")
    (files / "m.xml").write_text(mjcf.replace('file="m.stl"', 'file="/dev/zero"'))
    refused(capfd, ["verify", "--mjcf", "m.xml", *FILES], files, "/dev/zero is a character device")


def test_includes_that_multiply_a_model_are_bounded_by_the_link_limit(capfd, files):
    # each level includes the next twice: 2**7 copies of the last one's 3 links, from 8 small files
    leaf = '<sdf version="1.9"><model name="l7"><link name="x"/><link name="y"/><link name="z"/></model></sdf>\n'
    (files / "l7.sdf").write_text(leaf)
    for level in range(6, -1, -1):
        (files / f"l{level}.sdf").write_text(
            f'<sdf version="1.9"><model name="l{level}"><include><uri>l{level + 1}.sdf</uri><name>a</name></include>'
            f"<include><uri>l{level + 1}.sdf</uri><name>b</name></include></model></sdf>\n"
        )
    (files / "main.sdf").write_text(including((files / "plain.sdf").read_text(), "l0.sdf"))
    refused(
        capfd, ["verify", "--sdf", "main.sdf", *FILES], files, "main.sdf has", "links with the models it includes, above the 256"
    )
