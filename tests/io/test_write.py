"""Atomic writes: complete or absent, the temporary file beside the target with a name that fits,
permissions kept or from the umask, a failed write a one-line error that replaces nothing."""

from __future__ import annotations

import os
import resource
import signal
from pathlib import Path

import pytest

from kinverify.errors import InputError
from kinverify.io.plan import output_plan
from kinverify.io.write import NAME_MAX, _umask, temp_prefix, write_atomic


def test_temp_prefix_fits_a_file_name():
    room = NAME_MAX - len("..") - 8 - len(".tmp")
    assert temp_prefix("r.json") == ".r.json."
    assert temp_prefix("a" * room) == "." + "a" * room + "."
    assert temp_prefix("a" * (room + 1)) == "." + "a" * room + "."
    assert temp_prefix("é" * 200) == "." + "é" * (room // 2) + "."  # cut on a character boundary
    assert temp_prefix("\udcff.json") == ".\udcff.json."  # an undecodable byte of a file name kept


@pytest.fixture
def umask_027():
    old = os.umask(0o027)
    yield
    os.umask(old)


def test_umask_read_without_changing_it(umask_027):
    assert _umask() == 0o027
    assert os.umask(0o027) == 0o027


def test_a_new_file_has_the_umask_permissions_and_the_bytes_given(tmp_path, umask_027):
    target = tmp_path / "new" / "deeper" / "r.json"
    assert write_atomic(str(target), "é\n") == target
    assert target.read_bytes() == b"\xc3\xa9\n" and (target.stat().st_mode & 0o7777) == 0o640
    assert write_atomic(target, b"\x00\xff") == target and target.read_bytes() == b"\x00\xff"
    assert write_atomic(target, bytearray(b"ab")) == target and target.read_bytes() == b"ab"
    assert sorted(p.name for p in target.parent.iterdir()) == ["r.json"]  # no temporary file left


def test_a_replaced_file_keeps_its_permissions_and_a_link_stays_a_link(tmp_path):
    target = tmp_path / "r.json"
    target.write_text("old")
    target.chmod(0o604)
    link = tmp_path / "link.json"
    link.symlink_to(target)
    assert write_atomic(link, "new") == link
    assert link.is_symlink() and target.read_text() == "new" and (target.stat().st_mode & 0o7777) == 0o604


def test_within_a_plan_the_target_is_replaced_at_the_commit(tmp_path):
    target = tmp_path / "r.json"
    target.write_text("old")
    with output_plan([], [("--json", target)]):
        assert write_atomic(target, "new") == target
        assert target.read_text() == "old"
        (tmp,) = [p for p in tmp_path.iterdir() if p != target]
        assert tmp.name.startswith(".r.json.") and tmp.name.endswith(".tmp") and tmp.read_text() == "new"
    assert target.read_text() == "new" and list(tmp_path.iterdir()) == [target]


def test_a_folder_that_cannot_be_made_is_a_one_line_error(tmp_path):
    (tmp_path / "file").write_text("x")
    with pytest.raises(InputError) as err:
        write_atomic(tmp_path / "file" / "r.json", "data")
    assert str(err.value) == f"{tmp_path / 'file' / 'r.json'}: cannot write: Not a directory"


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="needs /proc")
def test_a_temporary_file_that_cannot_be_made_is_a_one_line_error():
    with pytest.raises(InputError) as err:
        write_atomic("/proc/kinverify-test.json", "data")  # /proc takes no new file, even from root
    assert str(err.value) == "/proc/kinverify-test.json: cannot write: No such file or directory"


def test_a_new_file_is_as_readable_as_the_umask_allows(tmp_path):
    old = os.umask(0o002)
    try:
        write_atomic(tmp_path / "r.json", "x")
    finally:
        os.umask(old)
    assert (tmp_path / "r.json").stat().st_mode & 0o7777 == 0o664


def test_a_failed_write_replaces_nothing_and_leaves_no_temporary_file(tmp_path):
    target = tmp_path / "r.json"
    target.write_text("old")
    old_handler = signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # EFBIG instead of a signal
    soft, hard = resource.getrlimit(resource.RLIMIT_FSIZE)
    resource.setrlimit(resource.RLIMIT_FSIZE, (10, hard))
    try:
        with pytest.raises(InputError) as err:
            write_atomic(target, "x" * 100)
    finally:
        resource.setrlimit(resource.RLIMIT_FSIZE, (soft, hard))
        signal.signal(signal.SIGXFSZ, old_handler)
    assert str(err.value) == f"{target}: cannot write: File too large; nothing was replaced"
    assert target.read_text() == "old" and list(tmp_path.iterdir()) == [target]


def test_a_directory_is_refused_before_anything_is_written(tmp_path):
    (tmp_path / "d").mkdir()
    with pytest.raises(InputError, match="is a directory"):
        write_atomic(tmp_path / "d", "data")
    assert list(Path(tmp_path / "d").iterdir()) == []
