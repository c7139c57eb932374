"""Branch replicates of one design share their unperturbed prefix: the
runner computes it once and forks it for each replicate, and every
replicate's stored result is bit-identical to the replicate computed alone."""

import dataclasses

import pandas as pd
import pytest

from mat_hopper.core.behaviours import behaviour
from mat_hopper.core.materials import parse_design
from mat_hopper.experiments.cache import Cache
from mat_hopper.experiments.groups import execute_unit, prefix_key, prefix_units, shared_prefix_steps, unit_steps
from mat_hopper.experiments.paper import Experiment, experiment_1
from mat_hopper.experiments.profiles import Profile
from mat_hopper.experiments.runner import RunSpec, run_grid

TINY = Profile("tiny", 2.0, 0.5, 1e-4, 2, 0.5, replicates=3)
BRANCH = dataclasses.replace(TINY, replicate_protocol="branch")
PREFIX_STEPS = 5000  # 0.5 s at 1e-4 s, by hand


def ramp_tasks(profile, designs=("SS",)):
    """The unperturbed run and 3 replicates of each design on the ramp."""
    e = experiment_1()
    exp = Experiment("t", "t", tuple(p for p in e.points if p.label in designs), ("ramp",))
    return exp.tasks(profile, profile.replicates)


def same_result(a, b):
    """(table, summary) pairs equal bit for bit (NaN equal to NaN)."""
    pd.testing.assert_frame_equal(a[0], b[0], check_exact=True)
    assert a[1].keys() == b[1].keys()
    for k in a[1]:
        pd.testing.assert_series_equal(pd.Series([a[1][k]]), pd.Series([b[1][k]]), check_exact=True, obj=k)


def test_the_protocol_is_in_the_key_and_the_result(tmp_path):
    authors, branch = ramp_tasks(TINY), ramp_tasks(BRANCH)
    assert len({t.key() for t in authors + branch}) == 8  # 4 runs x 2 protocols: no key shared
    assert BRANCH != TINY and BRANCH.key_dict()["replicate_protocol"] == "branch"
    assert "replicate_protocol" not in TINY.key_dict()  # the default adds no key
    assert {t.settings.replicate_protocol for t in branch} == {"branch"}


def test_only_branch_runs_of_one_design_behaviour_and_settings_are_grouped():
    branch = ramp_tasks(BRANCH, ("SS", "MD"))
    unique = {t.key(): t for t in branch + ramp_tasks(TINY, ("SS", "MD"))}
    units = prefix_units(list(unique), unique)
    assert sorted(map(len, units)) == [1] * 8 + [4, 4]
    for unit in units:
        if len(unit) == 4:
            assert len({unique[k].design.name for k in unit}) == 1
            assert {unique[k].settings.replicate_protocol for k in unit} == {"branch"}
    assert prefix_key(ramp_tasks(TINY)[1]) is None
    other = dataclasses.replace(branch[0].settings, contact="stiff")
    assert prefix_key(RunSpec(branch[0].design, branch[0].behaviour, other)) != prefix_key(branch[0])
    # the prefix counts once per group: 8 runs of 20000 steps, less 3 x 5000 per design
    assert shared_prefix_steps(branch) == 2 * 3 * PREFIX_STEPS
    assert unit_steps(branch) == 8 * 20000 - 6 * PREFIX_STEPS
    assert unit_steps(ramp_tasks(TINY, ("SS", "MD"))) == 8 * 20000


def test_groups_are_halved_to_keep_every_worker_busy():
    tasks = ramp_tasks(dataclasses.replace(BRANCH, replicates=10))  # one group of 11 runs
    unique = {t.key(): t for t in tasks}
    assert [len(u) for u in prefix_units(list(unique), unique, workers=1)] == [11]
    units = prefix_units(list(unique), unique, workers=2)  # 2 units per worker: 11 -> 6 + 5 -> 3 + 3 + 3 + 2
    assert sorted(map(len, units)) == [2, 3, 3, 3]
    assert sorted(k for u in units for k in u) == sorted(unique)
    for u in units:  # each half keeps the grid's order
        assert list(u) == [k for k in unique if k in u]
    many = ramp_tasks(BRANCH, ("SS", "MD", "PVC", "Al"))  # 4 groups of 4: enough units for 2 workers
    unique = {t.key(): t for t in many}
    assert sorted(map(len, prefix_units(list(unique), unique, workers=2))) == [4, 4, 4, 4]


@pytest.fixture(scope="module")
def alone():
    """Each branch replicate computed alone (its own unit): (key, table, summary)."""
    return {t.key(): execute_unit([t])[0] for t in ramp_tasks(BRANCH)}


def test_a_group_computes_each_replicate_as_it_runs_alone(alone):
    tasks = ramp_tasks(BRANCH)
    grouped = execute_unit(tasks)
    assert [g[0] for g in grouped] == [t.key() for t in tasks]
    for key, table, summary, err in grouped:
        assert err is None and alone[key][3] is None
        same_result((table, summary), alone[key][1:3])
    replicates = [s["mean_tracking_error_m"] for _, _, s, _ in grouped]
    assert len(set(replicates)) == 4  # the replicates differ after the prefix
    assert {s["replicate_protocol"] for _, _, s, _ in grouped} == {"branch"}


def test_a_grid_stores_each_replicate_under_its_own_key_and_reuses_it(tmp_path, alone):
    tasks = ramp_tasks(BRANCH)
    first = run_grid(tasks, tmp_path, workers=1, progress=False)
    assert (first.n_computed, first.n_cached, first.n_failed) == (4, 0, 0)
    cache = Cache(tmp_path)
    assert set(cache.keys()) == set(alone)
    single = Cache(tmp_path / "single")
    by_key = {t.key(): t for t in tasks}
    for key, (k, table, summary, _) in alone.items():
        single.store(k, table, summary, by_key[k].key_dict())
        same_result(cache.load(key), single.load(key))  # through the stored form, bit for bit
    assert list(first.summary["replicate"]) == [-1, 0, 1, 2] and set(first.summary["status"]) == {"ok"}
    again = run_grid(tasks, tmp_path, workers=1, progress=False)
    assert (again.n_computed, again.n_cached) == (0, 4)
    pd.testing.assert_frame_equal(first.tables, again.tables)
    (tmp_path / f"{tasks[2].key()}.parquet").unlink()  # resume: only the missing replicate, alone
    resumed = run_grid(tasks, tmp_path, workers=1, progress=False)
    assert (resumed.n_computed, resumed.n_cached) == (1, 3)
    pd.testing.assert_frame_equal(first.summary, resumed.summary)


@dataclasses.dataclass(frozen=True, eq=False)
class FailingReplicate(RunSpec):
    """A run whose summary raises (a bug in a metric, say) for one seed."""

    def summarize(self, rollout):
        if self.labels.get("replicate") == 1:
            raise RuntimeError("boom in replicate 1")
        return super().summarize(rollout)


def test_a_failing_replicate_is_a_failed_row_and_its_group_goes_on(tmp_path):
    tasks = [FailingReplicate(t.design, t.behaviour, t.settings, t.labels) for t in ramp_tasks(BRANCH)]
    res = run_grid(tasks, tmp_path, workers=1, progress=False)
    assert list(res.summary["status"]) == ["ok", "ok", "failed", "ok"]
    assert "boom in replicate 1" in res.summary["error"].iloc[2]
    assert len(Cache(tmp_path).keys()) == 3


def test_a_group_whose_prefix_diverges_gives_diverged_rows(tmp_path):
    profile = dataclasses.replace(BRANCH, timestep_s=1e-3, replicates=2)  # beyond SS's stable step
    tasks = [RunSpec(parse_design("SS"), behaviour("static"), t.settings, t.labels) for t in ramp_tasks(profile)]
    res = run_grid(tasks, tmp_path, workers=1, progress=False)
    assert res.n_computed == 3 and set(res.summary["status"]) == {"diverged"}
    assert (res.summary["diverged_at_s"] < 0.5).all()  # within the shared prefix


def test_the_process_pool_runs_groups_as_in_process(tmp_path):
    tasks = ramp_tasks(BRANCH, ("SS", "MD"))
    local = run_grid(tasks, tmp_path / "a", workers=1, progress=False)
    pool = run_grid(tasks, tmp_path / "b", workers=2, progress=False)
    assert pool.n_computed == 8 and pool.n_failed == 0
    pd.testing.assert_frame_equal(local.tables, pool.tables)
    pd.testing.assert_frame_equal(local.summary, pool.summary)


def test_branch_settled_groups_share_half_the_transient():
    settled = dataclasses.replace(TINY, replicate_protocol="branch-settled")
    tasks = ramp_tasks(settled)
    assert shared_prefix_steps(tasks) == 3 * PREFIX_STEPS // 2  # 0.25 s of 3 replicates, by hand
    alone = {t.key(): execute_unit([t])[0] for t in tasks}
    for key, table, summary, err in execute_unit(tasks):
        assert err is None
        same_result((table, summary), alone[key][1:3])
