"""A library run in a child process: its result or its exception comes back; an abort is reported
with the library's last words (its C++ file and line dropped); a child past its time is stopped."""

from __future__ import annotations

import os
import time

import pytest

from kinverify.io.isolate import LibraryDied, in_child, last_words


def test_the_result_or_the_exception_comes_back():
    assert in_child(lambda: {"q": [1.5]}) == {"q": [1.5]}
    with pytest.raises(ValueError, match="^bad axis$"):
        in_child(lambda: (_ for _ in ()).throw(ValueError("bad axis")))


def abort_saying_why():
    os.write(2, b"Failure at /src/multibody/parsing/detail_mujoco.cc:412 in Parse(): mass is 0.\n")
    os.abort()


def test_an_abort_is_reported_with_the_librarys_last_words():
    with pytest.raises(LibraryDied) as err:
        in_child(abort_saying_why)
    assert err.value.reason == "was killed by SIGABRT: Parse(): mass is 0"


def test_a_child_past_its_time_is_stopped():
    with pytest.raises(LibraryDied) as err:
        in_child(lambda: time.sleep(30), seconds=0.1)  # the wall clock: 0.1 s + 1 s
    assert err.value.reason == "ran longer than 0.1 s (stopped)"


def test_last_words():
    assert last_words(b"loading\nError at x.cc:1 in g(): bad inertia.\n\n") == "g(): bad inertia"
    assert last_words(b"\n \n") == "" and last_words(b"x" * 400) == "x" * 300
