"""The book's Sphinx extension (runtime per chapter) and the chapters'
download links (Book.downloads), without building a book."""

from __future__ import annotations

import math
from pathlib import Path

import pandas as pd
import pytest

from mat_hopper import book
from mat_hopper.experiments.profiles import PROFILES
from mat_hopper.sphinx_ext import _other_profile, _reference_path, runtime_record, runtime_table

ROOT = Path(__file__).resolve().parent.parent


def test_runtime_record_from_exec_data():
    exec_data = {
        "notebooks/02-b": {"runtime": 2.5, "succeeded": True},
        "notebooks/01-a": {"runtime": 1.0, "succeeded": True},
        "book/glossary": {"runtime": None},
    }
    r = runtime_record(exec_data, {"notebooks/01-a": "A"})
    assert r["docname"].tolist() == ["notebooks/01-a", "notebooks/02-b"]
    assert r["title"].tolist() == ["A", "notebooks/02-b"]
    assert r["runtime_s"].tolist() == [1.0, 2.5]


def test_runtime_table_both_profiles_and_total():
    quick = pd.DataFrame({"docname": ["a", "b"], "title": ["A", "B"], "runtime_s": [1.0, 2.0], "succeeded": True})
    paper = pd.DataFrame({"docname": ["a"], "title": ["A"], "runtime_s": [10.0], "succeeded": True})
    t = runtime_table({"quick": quick, "paper": paper}).set_index("title")
    assert t.loc["A", "quick_s"] == 1.0 and t.loc["A", "paper_s"] == 10.0
    assert math.isnan(t.loc["B", "paper_s"])
    assert t.loc["total", "quick_s"] == 3.0 and t.loc["total", "paper_s"] == 10.0
    # a profile never built here: its column is empty, its total nan
    t = runtime_table({"quick": quick, "paper": None}).set_index("title")
    assert t["paper_s"].isna().all()


def test_other_profile_from_this_folder_else_the_reference_build(tmp_path):
    rec = pd.DataFrame({"docname": ["a"], "title": ["A"], "runtime_s": [10.0], "succeeded": True})
    assert _other_profile(tmp_path, "paper") == (None, "not built in this folder yet")
    ref_csv = tmp_path / "book" / "runtimes" / "paper.csv"
    ref_csv.parent.mkdir(parents=True)
    rec.assign(built_at="2026-12-01T20:00", machine="2-core VM").to_csv(ref_csv, index=False)
    r, label = _other_profile(tmp_path, "paper")
    assert label == "reference build 2026-12-01T20:00, 2-core VM" and r["runtime_s"].tolist() == [10.0]
    here = tmp_path / "results" / "paper" / "runtimes.csv"
    here.parent.mkdir(parents=True)
    rec.assign(runtime_s=3.0, built_at="2026-12-02T09:00").to_csv(here, index=False)
    r, label = _other_profile(tmp_path, "paper")  # this folder's own build wins
    assert label == "last built here 2026-12-02T09:00" and r["runtime_s"].tolist() == [3.0]


@pytest.mark.parametrize("profile", list(PROFILES))
def test_reference_runtimes_cover_every_chapter_of_the_toc(profile):
    """The committed reference build of each profile (book/runtimes/) names
    every notebook of the table of contents, all of them executed."""
    toc = (ROOT / "_toc.yml").read_text()
    chapters = sorted(line.split("file:")[1].strip() for line in toc.splitlines() if "file: notebooks/" in line)
    ref_csv = pd.read_csv(_reference_path(ROOT, profile))
    # a chapter newer than the profile's reference build is listed, with why, in pending.csv
    pending = pd.read_csv(ROOT / "book" / "runtimes" / "pending.csv")
    pending = pending[pending["profile"] == profile]
    assert pending["reason"].str.len().gt(20).all()
    assert not set(pending["docname"]) & set(ref_csv["docname"])
    assert sorted([*ref_csv["docname"], *pending["docname"]]) == chapters
    assert ref_csv["succeeded"].all() and (ref_csv["runtime_s"] > 0).all()
    assert ref_csv["machine"].notna().all() and ref_csv["built_at"].notna().all()


def test_downloads_write_and_link(tmp_path, monkeypatch):
    monkeypatch.setenv("MAT_HOPPER_PROFILE", "quick")
    b = book.setup(chdir=False)
    b = book.Book(tmp_path, b.profile, b.cache_dir, tmp_path / "results" / "quick")
    md = b.downloads({"exp9_runs": pd.DataFrame({"x": [1, 2, 3]})})
    assert (tmp_path / "results" / "quick" / "exp9_runs.csv").read_text() == "x\n1\n2\n3\n"
    assert "{download}`exp9_runs.csv </results/quick/exp9_runs.csv>` (3 rows)" in md.data
    with pytest.raises(ValueError, match="name"):
        b.downloads({"../x": pd.DataFrame()})
    with pytest.raises(ValueError, match="DataFrame"):
        b.downloads({"x": [1, 2]})
    with pytest.raises(ValueError, match="no tables"):
        b.downloads({})
