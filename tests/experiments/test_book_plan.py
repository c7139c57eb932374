"""The plan of the book's runs (mat_hopper.experiments.plan): chapters in the
toc's order, a shared run counted once, a cached run reported cached, and
the plan's keys equal to the keys the build writes."""

from __future__ import annotations

import pathlib
import re
from dataclasses import replace

import pandas as pd
import pytest

from mat_hopper.experiments import plan as book_plan
from mat_hopper.experiments.cache import Cache
from mat_hopper.experiments.plan import CHAPTERS, Chapter, Estimate, experiments, format_plan, plan
from mat_hopper.experiments.profiles import PROFILES
from mat_hopper.experiments.runner import rollout_specs

ROOT = pathlib.Path(__file__).resolve().parents[2]
TOTAL = re.compile(r"^total: (\d+) runs, (\S+) physics steps, (\S+) core-hours \(estimated\)$")


def toc_notebooks() -> list[str]:
    text = (ROOT / "_toc.yml").read_text()
    return re.findall(r"^\s*- file: notebooks/(\S+)\s*$", text, flags=re.M)


def test_the_quick_plan_lists_the_toc_chapters_in_order(tmp_path):
    table = plan("quick", cache_dir=tmp_path / "none")
    assert list(dict.fromkeys(table["chapter"])) == toc_notebooks() == [c.name for c in CHAPTERS]
    assert (ROOT / "notebooks" / "src").is_dir()
    for name in toc_notebooks():
        assert (ROOT / "notebooks" / "src" / f"{name}.py").is_file(), name
    assert not (tmp_path / "none").exists()  # the plan never makes the cache folder
    counted = table[table["runs"] > 0]
    assert set(counted["kind"]) == {"run", "rollout", "stability"}
    # chapter 9's study and 9c's codesign are the optimizer's: named here, counted by mat_hopper.optimize.book_plan
    nine = table[table["chapter"] == "09-optimizing-gradients"].iloc[0]
    assert nine["runs"] == 0 and "mat_hopper.optimize" in nine["note"]
    assert "codesign" in table[table["chapter"] == "09c-material-or-mass"]["note"].iloc[-1]


def test_a_shared_run_is_counted_once_in_the_total(tmp_path):
    chapters = (
        Chapter("a", (experiments("1"),)),
        Chapter("b", (experiments("3"),)),
        Chapter("c", (experiments("1"), experiments("1"))),  # asked twice in one chapter: one run each
    )
    table = plan("quick", cache_dir=tmp_path, chapters=chapters)
    a, b, c = table.iloc[0], table.iloc[1], table.iloc[2]
    assert a["shared_with_earlier"] == 0
    # exp3's baselines MD and SS are exp1's runs (two of its five legs): the same keys
    assert b["shared_with_earlier"] == a["runs"] * 2 // 5
    assert c["runs"] == c["shared_with_earlier"] == a["runs"] and c["new_physics_steps"] == 0
    m = TOTAL.match(format_plan(table).splitlines()[-1])
    assert m is not None
    assert int(m.group(1)) == a["runs"] + b["runs"] - b["shared_with_earlier"]
    assert float(m.group(2)) == pytest.approx(a["physics_steps"] + b["new_physics_steps"], rel=1e-2)


def test_a_run_in_the_cache_is_reported_cached(tmp_path):
    quick = replace(PROFILES["quick"], replicate_protocol="authors")  # runs that share no prefix: steps add up
    task = experiments("1")(quick)[0]
    Cache(tmp_path).store(task.key(), pd.DataFrame({"x": [1.0]}), {"status": "ok"}, task.key_dict())
    table = plan(quick, cache_dir=tmp_path, chapters=(Chapter("a", (experiments("1"),)),))
    row = table.iloc[0]
    assert row["cached"] == 1 and row["to_compute"] == row["runs"] - 1
    assert row["to_compute_steps"] == pytest.approx(row["physics_steps"] - task.settings.n_steps)
    assert "not in the cache: " + str(row["runs"] - 1) + " runs" in format_plan(table)


def test_the_plan_is_what_the_build_runs(tmp_path):
    from mat_hopper.experiments.reproduce import run_experiments

    tiny = replace(PROFILES["quick"], name="tiny", duration_s=0.3, transient_s=0.1, replicates=0)
    cache = tmp_path / "cache"
    run_experiments(tiny, "1", out_dir=tmp_path / "out", cache_dir=cache, workers=1, quiet=True)
    written = Cache(cache).keys()
    planned = {t.key() for t in experiments("1")(tiny)}
    assert written == planned and len(planned) == 20
    row = plan(tiny, cache_dir=cache, chapters=(Chapter("exp1", (experiments("1"),)),)).iloc[0]
    assert (row["runs"], row["cached"], row["to_compute"]) == (20, 20, 0)


def test_the_rollouts_planned_are_those_runner_rollouts_runs(monkeypatch, tmp_path):
    from mat_hopper.experiments import runner

    seen = []

    def capture(self, tasks, desc="runs"):
        seen.extend(tasks)
        raise RuntimeError("captured")

    monkeypatch.setattr(runner.Runner, "run", capture)
    settings = PROFILES["quick"].sim_settings()
    with pytest.raises(RuntimeError, match="captured"):
        runner.rollouts(["MD", "SS"], ["forward", "ramp"], settings, record_rate_hz=250, cache_dir=tmp_path)
    planned = rollout_specs(["MD", "SS"], ["forward", "ramp"], settings, record_rate_hz=250)
    assert [t.key() for t in planned] == [t.key() for t in seen]


def test_the_optimizer_chapters_are_counted_with_their_estimates(tmp_path):
    from mat_hopper.optimize.book_plan import chapters

    table = plan("quick", cache_dir=tmp_path, chapters=chapters())
    assert list(dict.fromkeys(table["chapter"])) == toc_notebooks()
    nine = table[table["chapter"] == "09-optimizing-gradients"]
    assert set(nine["counted"]) == {"exact", "estimate"} and (nine["runs"] > 0).all()
    # the validation: the paper gradients' runs as tasks, the front's new designs as estimates
    from mat_hopper.optimize.book_plan import EXPECTED_FRONT, validation_requests

    assert nine["note"].str.contains(f"the validation of {EXPECTED_FRONT} new front designs").any()
    requests = validation_requests(PROFILES["quick"])
    known = [t for t in requests if not isinstance(t, Estimate)]
    assert {t.labels["design"] for t in known if t.labels["role"] == "front"} == {
        "rho-inc",
        "rho-dec",
        "PVC-Ti-SS",
        "SS-Ti-PVC",
    }
    one_new = sum(e.runs for e in requests if isinstance(e, Estimate)) / EXPECTED_FRONT
    gradient = sum(t.labels["role"] != "paper" and t.labels["control_of"] in ("", "rho-inc") for t in known
                   if t.labels["design"].startswith("rho-inc"))  # fmt: skip
    assert one_new == gradient  # a new gradient is validated as the paper's rho-inc is
    # their steps as the runner computes them: under a branching protocol each design's replicates share a prefix
    from mat_hopper.experiments.groups import unit_steps

    settled = replace(PROFILES["quick"], replicate_protocol="branch-settled")
    requests = validation_requests(settled)
    known = [t for t in requests if not isinstance(t, Estimate)]
    rho_runs = [t for t in known if t.labels["role"] != "paper" and t.labels["control_of"] in ("", "rho-inc")
                and t.labels["design"].startswith("rho-inc")]  # fmt: skip
    new_steps = sum(e.steps() for e in requests if isinstance(e, Estimate)) / EXPECTED_FRONT
    assert new_steps == pytest.approx(unit_steps(rho_runs), rel=0.05)  # the stand-ins' densities differ by 1-8 %
    assert new_steps < sum(e.runs * e.settings.n_steps for e in requests if isinstance(e, Estimate)) / EXPECTED_FRONT
    codesign = table[table["chapter"] == "09c-material-or-mass"]
    assert {"exact", "estimate"} <= set(codesign["counted"])
    assert not table["note"].str.contains("book_plan").any()  # nothing left to the optimizer layer


def test_format_plan_refuses_a_cost_that_is_no_number(tmp_path):
    table = plan("quick", cache_dir=tmp_path, chapters=(Chapter("a", (experiments("1"),)),))
    with pytest.raises(ValueError, match="us_per_step"):
        format_plan(table, us_per_step=0)
    hours = book_plan.core_hours(3.6e9, 0.0, us_per_step=1.0)
    assert hours == pytest.approx(1.0)


def test_branch_replicates_count_their_shared_prefix_once(tmp_path):
    quick = PROFILES["quick"]  # 12 s runs, 4 s transient, 2 replicates: the unperturbed run and 2 seeds
    assert quick.replicate_protocol == "authors"  # the book's
    chapters = (Chapter("a", (experiments("1"),)),)
    authors = plan(quick, cache_dir=tmp_path, chapters=chapters).iloc[0]
    branch = plan(replace(quick, replicate_protocol="branch"), cache_dir=tmp_path, chapters=chapters).iloc[0]
    settled = plan(replace(quick, replicate_protocol="branch-settled"), cache_dir=tmp_path, chapters=chapters).iloc[0]
    groups = authors["runs"] // 3  # 5 legs x 4 behaviours, 3 runs each
    assert authors["physics_steps"] == authors["runs"] * 120_000  # 12 s at 1e-4 s, by hand
    # each group simulates 4 s (40000 steps) once instead of 3 times; branch-settled its first 2 s (20000)
    assert branch["physics_steps"] == authors["physics_steps"] - groups * 2 * 40_000
    assert settled["physics_steps"] == authors["physics_steps"] - groups * 2 * 20_000
    assert branch["runs"] == authors["runs"] == settled["runs"] and branch["simulated_s"] == authors["simulated_s"]


def test_chapter_9c_counts_its_crossed_legs():
    from mat_hopper.experiments import crossed_legs

    nine_c = [c for c in CHAPTERS if c.name == "09c-material-or-mass"]
    keys = {t.key() for t in book_plan.book_tasks("quick", nine_c)}
    crossed = {t.key() for t in crossed_legs.tasks("quick")}
    assert len(crossed) == 4 * PROFILES["quick"].replicates
    assert crossed <= keys  # the plan (and plan --run) knows the grid the chapter's cell runs
    assert "crossed" not in nine_c[0].uncounted
