"""The one reader of input files: a regular file only (FIFO, device, directory, missing: each one
line), at most ``limit`` bytes measured by reading (a /proc file that reports 0 bytes too), UTF-8
text with its byte-order mark dropped, recorded as an input of the run; a library's own opens
bounded by one shared budget."""

from __future__ import annotations

import errno
import os
import types

import pytest

from kinverify.errors import InputError
from kinverify.io.plan import output_plan
from kinverify.io.read import InputFileError, check_file, library_reads, read_bytes, read_head, read_text, size_text
from kinverify.io.write import write_atomic

MB = 1 << 20
TAIL = "kinverify reads (see docs/robustness.md)"


def refused(call, *args, **kwargs) -> InputFileError:
    with pytest.raises(InputFileError) as err:
        call(*args, **kwargs)
    return err.value


def test_a_file_up_to_the_limit_is_read_one_byte_more_is_refused(tmp_path):
    path = tmp_path / "m.urdf"
    path.write_bytes(b"x" * (2 * MB))
    assert read_bytes(path, limit=2 * MB) == b"x" * (2 * MB)
    assert check_file(path, limit=2 * MB) == 2 * MB
    path.write_bytes(b"x" * (2 * MB + 1))
    err = refused(read_bytes, path, "--urdf", limit=2 * MB)
    assert str(err) == f"--urdf: {path} is 2.0 MB, above the 2 MB {TAIL}" and err.too_large
    assert str(refused(check_file, str(path), limit=2 * MB)) == f"{path} is 2.0 MB, above the 2 MB {TAIL}"
    assert str(refused(check_file, path, "--q", limit=2 * MB)) == f"--q: {path} is 2.0 MB, above the 2 MB {TAIL}"
    path.write_bytes(b"")
    assert read_bytes(path) == b"" and check_file(path) == 0


def test_a_file_that_reports_no_size_is_bounded_by_reading():
    status = read_bytes("/proc/self/status", limit=MB)
    assert status.startswith(b"Name:") and len(status) > 100
    err = refused(read_bytes, "/proc/self/status", limit=100)
    assert str(err) == f"/proc/self/status is more than 100 bytes, above the 100 bytes {TAIL}" and err.too_large
    limits = read_bytes("/proc/self/limits", limit=MB)  # also 0 bytes, and unchanging (status counts context switches)
    assert read_bytes("/proc/self/limits", limit=len(limits)) == limits and len(limits) > 100
    assert str(refused(read_bytes, "/proc/self/status", "--in", limit=100)).startswith("--in: /proc/self/status is more")
    err = refused(read_bytes, "/proc/self/smaps", limit=1000)  # read in several pieces: their sizes add up
    assert err.too_large


@pytest.mark.parametrize("call", [read_bytes, read_text, check_file, read_head])
def test_only_regular_files(tmp_path, call):
    fifo = tmp_path / "p"
    os.mkfifo(fifo)
    reason = "not a regular file: kinverify reads regular files only"
    assert str(refused(call, fifo)) == f"{fifo} is a FIFO (named pipe), {reason}"
    err = refused(call, fifo, label="--in")
    assert (str(err), err.path, err.label) == (f"--in: {fifo} is a FIFO (named pipe), {reason}", str(fifo), "--in")
    assert str(refused(call, "/dev/null", label="--in")) == f"--in: /dev/null is a character device, {reason}"
    assert str(refused(call, tmp_path, label="--in")) == f"--in: {tmp_path} is a directory, {reason}"
    err = refused(call, tmp_path / "missing", label="--in")
    assert (str(err), err.errno) == (f"--in: {tmp_path / 'missing'} is not a file", errno.ENOENT)
    (tmp_path / "f").write_text("x")
    err = refused(call, tmp_path / "f" / "sub")
    assert (str(err), err.errno) == (f"{tmp_path / 'f' / 'sub'} is not a file", errno.ENOTDIR)
    loop = tmp_path / "loop.urdf"
    loop.symlink_to(loop)
    err = refused(call, loop, label="--urdf")
    assert (str(err), err.errno) == (f"--urdf: {loop} cannot be read: Too many levels of symbolic links", errno.ELOOP)


def test_input_file_error_without_a_label():
    err = InputFileError(MB, "is bad")
    assert (str(err), err.path, err.label, err.errno, err.too_large) == ("1048576 is bad", "1048576", "", None, False)


def test_a_file_that_cannot_be_read_for_another_reason(tmp_path):
    loop = tmp_path / "loop.urdf"
    loop.symlink_to(loop)
    err = refused(read_bytes, loop, "--urdf")
    assert (str(err), err.errno) == (f"--urdf: {loop} cannot be read: Too many levels of symbolic links", errno.ELOOP)


@pytest.mark.parametrize("call", [read_bytes, read_head])
def test_a_regular_file_whose_read_fails_after_the_open(call):
    # /proc/self/mem is a regular file that opens, and reading it at offset 0 (address 0, never
    # mapped) fails with EIO: the failing read is one line naming the file, its label and errno,
    # and the descriptor is closed
    before = len(os.listdir("/proc/self/fd"))
    err = refused(call, "/proc/self/mem", label="--urdf")
    assert (str(err), err.errno) == ("--urdf: /proc/self/mem cannot be read: Input/output error", errno.EIO)
    assert len(os.listdir("/proc/self/fd")) == before


def test_read_text_utf8_without_its_byte_order_mark(tmp_path):
    path = tmp_path / "m.xml"
    path.write_bytes(b"\xef\xbb\xbf<r>\xc3\xa9</r>")
    assert read_text(path) == "<r>é</r>"
    path.write_bytes(b"<r>\xff</r>")
    assert str(refused(read_text, path, "--mjcf")) == f"--mjcf: {path} is not UTF-8 text (byte 3)"
    assert str(refused(read_text, tmp_path / "none.xml", "--mjcf")) == f"--mjcf: {tmp_path / 'none.xml'} is not a file"


def test_read_head(tmp_path):
    path = tmp_path / "m.xml"
    path.write_bytes(b"0123456789")
    assert read_head(path, 4) == b"0123" and read_head(path) == b"0123456789"
    path.write_bytes(b"x" * 5000)
    assert read_head(path) == b"x" * 4096


def test_an_input_read_is_recorded_unless_asked_not_to(tmp_path):
    for call in (read_bytes, read_text, check_file):
        path = tmp_path / f"{call.__name__}.json"
        path.write_text("{}")
        with pytest.raises(InputError, match="an input of this run") as err:
            with output_plan():
                call(path, "--baseline")
                write_atomic(path, "new")
        assert "--baseline" in str(err.value)
        with pytest.raises(InputError, match="an input of this run"):
            with output_plan():
                call(path)
                write_atomic(path, "new")
        with output_plan():
            call(path, register=False)
            write_atomic(path, "new")
        assert path.read_text() == "new"
    with output_plan():
        read_head(path)
        write_atomic(path, "head only")
    assert path.read_text() == "head only"


def test_library_reads_bounded_by_one_budget_and_recorded(tmp_path):
    module = types.ModuleType("lib")
    own = types.ModuleType("own")
    own.open = "its own"
    (tmp_path / "a.xml").write_text("aaaa")
    (tmp_path / "b.xml").write_text("bbb")
    (tmp_path / "c.xml").write_text("c")
    record: list = []
    with library_reads([module, own], "--urdf", limit=8, record=record):
        assert module.open(tmp_path / "a.xml").read() == "aaaa"
        assert module.open(str(tmp_path / "b.xml"), "rb").read() == b"bbb"
        assert module.open(tmp_path / "c.xml", encoding="latin-1").read() == "c"  # 8 bytes of 8 spent
        err = refused(module.open, tmp_path / "c.xml")
        # the limit is what the files read before it left of the 8 bytes they share
        assert str(err) == (
            f"--urdf: {tmp_path / 'c.xml'} is 1 byte, which would exceed the 8 bytes the files the library opens share: "
            "8 bytes already read (see docs/robustness.md)"
        )
        with pytest.raises(FileNotFoundError) as missing:
            module.open(tmp_path / "none.xml")
        assert (missing.value.errno, missing.value.filename) == (errno.ENOENT, str(tmp_path / "none.xml"))
        with module.open(tmp_path / "out.txt", "w") as out:  # writing is left alone
            out.write("w")
        assert own.open == "its own"
    assert record == [str(tmp_path / n) for n in ("a.xml", "b.xml", "c.xml")]
    assert not hasattr(module, "open") and own.open == "its own" and (tmp_path / "out.txt").read_text() == "w"
    with library_reads([module], "--urdf"):
        assert module.open(tmp_path / "a.xml").read() == "aaaa"  # no record list: nothing recorded, no error
        with pytest.raises(FileNotFoundError):
            module.open(tmp_path / "f.xml" / "x")
    (tmp_path / "u.xml").write_bytes("é".encode())
    with library_reads([module], "--urdf"):
        assert module.open(tmp_path / "u.xml").read() == "é"  # UTF-8 unless told


def test_a_size_is_given_in_a_unit_that_shows_it():
    assert [size_text(n) for n in (0, 1, 1023, 1024, 1536, MB - 1, MB, 256 * MB - 100)] == [
        "0 bytes",
        "1 byte",
        "1023 bytes",
        "1.0 kB",
        "1.5 kB",
        "1024.0 kB",
        "1.0 MB",
        "256.0 MB",
    ]


def test_a_file_over_what_a_shared_budget_has_left_names_the_budget_and_what_was_read(tmp_path):
    path = tmp_path / "a.stl"
    path.write_bytes(b"x" * 3000)
    shared = (256 * MB, "all meshes of the model")
    left = 1000  # 256 MB less 1000 bytes already read
    err = refused(check_file, path, "<mesh>", limit=left, shared=shared)
    assert err.too_large and str(err) == (
        f"<mesh>: {path} is 2.9 kB, which would exceed the 256 MB all meshes of the model share: "
        "256.0 MB already read (see docs/robustness.md)"
    )
    err = refused(read_bytes, path, limit=0, shared=(2 * MB + 512, "the files the library opens"))
    assert str(err) == (
        f"{path} is 2.9 kB, which would exceed the 2.0 MB the files the library opens share: 2.0 MB already read (see docs/robustness.md)"
    )
    assert check_file(path, limit=3000, shared=shared) == 3000  # within what is left: read
