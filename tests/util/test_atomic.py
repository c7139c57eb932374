"""mat_hopper.util.atomic: a reader sees the old file or the whole new one, never
a half-written result; killed processes' leftovers are cleaned, a live
process's are not."""

import os
import socket
import stat
import time

import pandas as pd
import pytest

from mat_hopper.util.atomic import MP_TEMP_PREFIX, TEMP_PREFIX, atomic_path, remove_stale_mp_dirs, write_csv, write_text


def test_atomic_path_moves_into_place_with_plain_permissions(tmp_path):
    target = tmp_path / "sub" / "table.csv"  # the folder is made
    with atomic_path(target) as tmp:
        assert os.path.dirname(tmp) == str(target.parent) and os.path.basename(tmp).startswith(TEMP_PREFIX)
        assert tmp.endswith(".csv") and not target.exists()  # nothing at the target while writing
        with open(tmp, "w") as f:
            f.write("a,b\n1,2\n")
    assert target.read_text() == "a,b\n1,2\n"
    assert os.listdir(target.parent) == ["table.csv"]  # no temp file left
    umask = os.umask(0)
    os.umask(umask)
    assert stat.S_IMODE(target.stat().st_mode) == 0o666 & ~umask  # what open() would give, not mkstemp's 0600


def test_a_failed_write_keeps_the_old_file_and_leaves_no_temp(tmp_path):
    target = tmp_path / "notes.txt"
    target.write_text("old")
    with pytest.raises(RuntimeError, match="half-way"):
        with atomic_path(target, fsync=True) as tmp:
            with open(tmp, "w") as f:
                f.write("new, but only ha")
            raise RuntimeError("killed half-way")
    assert target.read_text() == "old"
    assert os.listdir(tmp_path) == ["notes.txt"]


def test_write_text_and_csv(tmp_path):
    assert write_text("Å ü\n", tmp_path / "t.md") == str(tmp_path / "t.md")
    assert (tmp_path / "t.md").read_bytes() == "Å ü\n".encode()
    write_csv(pd.DataFrame({"design": ["SS"], "power_w": [1.5]}), tmp_path / "t.csv")
    assert (tmp_path / "t.csv").read_text() == "design,power_w\nSS,1.5\n"  # no index column


def _aged(path, seconds=3600):
    t = time.time() - seconds
    os.utime(path, (t, t))


def test_remove_stale_mp_dirs_removes_only_dead_leftovers(tmp_path):
    empty = tmp_path / f"{MP_TEMP_PREFIX}dead"
    empty.mkdir()
    young = tmp_path / f"{MP_TEMP_PREFIX}young"
    young.mkdir()
    other = tmp_path / f"{MP_TEMP_PREFIX}files"
    other.mkdir()
    (other / "data.txt").write_text("not a socket")
    live = tmp_path / f"{MP_TEMP_PREFIX}live"
    live.mkdir()
    server = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    server.bind(str(live / "listener"))  # a socket this process holds bound
    closed = tmp_path / f"{MP_TEMP_PREFIX}closed"
    closed.mkdir()
    gone = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    gone.bind(str(closed / "listener"))
    gone.close()  # the socket file stays, bound by no process: a killed forkserver's leftover
    try:
        for d in (empty, other, live, closed):
            _aged(d)
        (tmp_path / "unrelated").mkdir()
        _aged(tmp_path / "unrelated")
        removed = remove_stale_mp_dirs(str(tmp_path), min_age_s=60.0)
        assert sorted(removed) == sorted([str(empty), str(closed)])
        assert sorted(os.listdir(tmp_path)) == sorted(
            [young.name, other.name, live.name, "unrelated"]
        )  # too young, not only sockets, bound, not ours by name
    finally:
        server.close()


def test_remove_stale_mp_dirs_without_the_folder(tmp_path):
    assert remove_stale_mp_dirs(str(tmp_path / "missing")) == []
