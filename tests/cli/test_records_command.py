"""``mat-hopper records``: a build's tables become the records, each with
its provenance (commit, SHA-256), and a build that is not there or not
finished is refused before any work."""

from __future__ import annotations

import hashlib

import pandas as pd
from _refusal import refused

from mat_hopper.cli import records


def _build_folder(tmp_path, skip=()):
    """A build folder holding every download the records copy (but `skip`)."""
    build = tmp_path / "build"
    build.mkdir()
    for name, _chapter in records.DOWNLOADS.values():
        if name not in skip:
            (build / f"{name}.csv").write_text(f"a,b\n1,{name}\n")
    return build


def test_records_refuses_a_build_that_is_not_there(tmp_path, capsys):
    cache = tmp_path / "cache"
    cache.mkdir()
    out = ["--out", str(tmp_path / "rec")]
    refused(
        ["records", "--profile", "quick", "--cache", str(cache), "--build", str(tmp_path / "nope"), *out],
        capsys,
        "--build",
        "does not exist",
        "make book",
    )
    refused(["records", "--profile", "quick", "--cache", str(tmp_path / "nocache"), *out], capsys, "does not exist")


def test_records_names_the_chapter_whose_download_is_missing(tmp_path, capsys):
    cache = tmp_path / "cache"
    cache.mkdir()
    build = _build_folder(tmp_path, skip=("stress_tail",))
    argv = ["records", "--profile", "quick", "--cache", str(cache), "--build", str(build), "--studies", str(cache)]
    refused([*argv, "--out", str(tmp_path / "rec")], capsys, "stress_tail.csv", "08b-gradients-stress")


def test_records_refuses_an_unfinished_cache_with_the_command_that_fills_it(tmp_path, capsys):
    cache = tmp_path / "cache"
    cache.mkdir()
    build = _build_folder(tmp_path)
    argv = ["records", "--profile", "quick", "--cache", str(cache), "--build", str(build), "--studies", str(cache)]
    # the check keys every planned run of the claims (no physics): more than a bare refusal's time
    refused([*argv, "--out", str(tmp_path / "rec")], capsys, "not in", "plan --profile quick --run", max_wall_s=30)


def test_records_will_not_replace_records_without_force(tmp_path, capsys):
    out = tmp_path / "rec"
    out.mkdir()
    (out / "claims-quick.csv").write_text("x\n")
    cache = tmp_path / "cache"
    cache.mkdir()
    build = _build_folder(tmp_path)
    argv = ["records", "--profile", "quick", "--cache", str(cache), "--build", str(build), "--studies", str(cache)]
    refused([*argv, "--out", str(out)], capsys, "claims-quick.csv", "--force")


def test_records_asks_for_a_build_before_it_asks_for_force(tmp_path, capsys):
    """Without a build the answer is to build one, not --force (which would replace the committed records)."""
    out = tmp_path / "rec"
    out.mkdir()
    (out / "claims-quick.csv").write_text("x\n")
    a_file = tmp_path / "a_file"
    a_file.write_text("x")
    argv = ["records", "--profile", "quick", "--out", str(out), "--cache", str(tmp_path / "none")]
    cap = refused(argv, capsys, "does not exist", "make book PROFILE=quick")
    assert "--force" not in cap.err
    refused([*argv[:-1], str(tmp_path), "--build", str(a_file)], capsys, "--build", "is a file, not a folder")


def test_written_records_carry_their_commit_and_checksum(tmp_path):
    build = _build_folder(tmp_path)
    sources = records.downloaded_tables(str(build), "quick")
    assert set(sources) == {f"{r}-quick.csv" for r in records.DOWNLOADS}
    table = records.write_records(sources, str(tmp_path / "rec"), "quick", "abc1234")
    written = pd.read_csv(tmp_path / "rec" / records.PROVENANCE)
    assert list(written["record"]) == sorted(sources) and set(written["commit"]) == {"abc1234"}
    tail = (tmp_path / "rec" / "stress-tail-quick.csv").read_bytes()
    assert tail == b"a,b\n1,stress_tail\n"
    assert table.set_index("record").loc["stress-tail-quick.csv", "sha256"] == hashlib.sha256(tail).hexdigest()
    assert "08b-gradients-stress" in table.set_index("record").loc["stress-tail-quick.csv", "made_from"]
