"""The robustness study on a batch backend (experiments.robustness.batch_runs)
against the same study through the runner's per-hop tables."""

from dataclasses import replace

import pandas as pd
import pytest

from mat_hopper.analysis import robustness as R
from mat_hopper.experiments import robustness as study
from mat_hopper.experiments.profiles import Profile
from mat_hopper.experiments.runner import run_grid

# Short runs at the paper's step: every design stands in the authors' timing
# and at a latency of 2 steps (its stance-damping limit is 1.3e-4 s).
SHORT = Profile("short", duration_s=3.0, transient_s=1.0)
VARIANTS = [R.DEFAULT, R.Variant("latency-2", sensor_timing="latency-2")]


def test_batch_variants_are_those_without_perturbation_or_substeps():
    labels = [v.label for v in study.batch_variants()]
    assert labels == ["authors", "fresh", "latency-2", "latency-5", "latency-10", "2e-5 s step"]
    with pytest.raises(ValueError, match="cannot run these variants.*replicate 0"):
        study.batch_runs(SHORT, [R.DEFAULT, R.Variant("replicate 0", replicate=0)], backend="mujoco")
    with pytest.raises(ValueError, match="axial, 2e-5 s physics"):
        study.batch_runs(SHORT, R.variants(replicates=0), backend="mujoco")


def test_mujoco_backend_gives_the_runner_study(tmp_path):
    """Same quantities, to round-off: the batch's means over scored hop
    cycles are the means of the runner's per-hop tables."""
    runs = study.batch_runs(SHORT, VARIANTS, backend="mujoco", workers=1)
    assert len(runs) == 2 * len(R.designs_and_behaviours()) and (runs["status"] == "ok").all()
    got = R.quantity_values(runs, runs)
    res = run_grid(study.tasks(SHORT, VARIANTS), tmp_path / "cache", workers=1)
    want = R.quantity_values(res.tables, res.summary)
    merged = pd.merge(got, want, on=["variant", "quantity_id"], suffixes=("_batch", "_runner"))
    assert len(merged) == len(want) == 2 * len(R.QUANTITIES)
    assert merged["value_pct_batch"].notna().all()
    for a, b in zip(merged["value_pct_batch"], merged["value_pct_runner"]):
        assert a == pytest.approx(b, rel=1e-9, abs=1e-9)
    # and the classes follow: the latency moves the quantities by the same amounts
    table = R.robustness_table(got)
    assert set(table["class"]) <= set(R.CLASSES)


@pytest.mark.slow
def test_warp_backend_runs_the_study():
    """The plumbing on Warp's CPU device (its agreement with the CPU path
    is tests/batch/test_batch_agreement.py's): one batch per variant and
    behaviour, statuses as the CPU rollouts'."""
    pytest.importorskip("mujoco_warp")
    tiny = Profile("tiny", duration_s=0.2, transient_s=0.05, timestep_s=2e-4)  # plumbing: 1000 steps a batch
    warp = study.batch_runs(tiny, [R.DEFAULT], backend="warp", device="cpu")
    cpu = study.batch_runs(tiny, [R.DEFAULT], backend="mujoco", workers=1)
    assert (warp["backend"] == "warp").all() and len(warp) == len(cpu)
    assert warp["status"].tolist() == cpu["status"].tolist()
    assert ((warp["n_hops"] - cpu["n_hops"]).abs() <= 1).all()


def test_tasks_take_a_profile_name_and_refuse_an_empty_variant_list():
    from mat_hopper.experiments.profiles import get_profile

    by_name = study.tasks(" Quick ", [R.DEFAULT])
    by_profile = study.tasks(get_profile("quick"), [R.DEFAULT])
    assert [t.key() for t in by_name] == [t.key() for t in by_profile]
    assert {t.labels["profile"] for t in by_name} == {"quick"}
    with pytest.raises(ValueError, match="no variants"):
        study.tasks("quick", [])
    with pytest.raises(ValueError, match="unknown profile"):
        study.tasks("fast", [R.DEFAULT])


def test_variants_store_canonical_names():
    v = R.Variant("axial", convention="Axial", sensor_timing="FRESH")
    assert (v.convention, v.sensor_timing) == ("axial", "fresh")
    assert R.Variant("paper", convention="PAPER") in study.batch_variants([R.Variant("paper", convention="PAPER")])
    only = dict(latencies=(), timesteps=False, replicates=0, contacts=(), apex_references=())
    assert [v.convention for v in R.variants(conventions=("Axial",), **only)] == [
        "paper",
        "axial",
    ]
    with pytest.raises(ValueError, match="unknown stiffness convention"):
        R.Variant("x", convention="radial")


def test_contact_and_apex_variants_change_only_their_setting():
    """The stiff contact and the apex above the ground are variants of
    their own: each run differs from the default's in that setting alone
    (so its key differs), and no batch backend runs them."""
    vs = R.variants(latencies=(), conventions=(), timesteps=False, replicates=0, contacts=("Stiff",))
    assert [(v.label, v.kind) for v in vs] == [
        ("authors", "sensor latency"),
        ("stiff contact", "contact"),
        ("apex above ground", "apex reference"),
    ]
    base, stiff, ground = (study.tasks("quick", [v]) for v in vs)
    for default, other, field in ((base, stiff, "contact"), (base, ground, "apex_reference")):
        for a, b in zip(default, other):
            assert getattr(b.settings, field) != getattr(a.settings, field) and a.key() != b.key()
            assert replace(b.settings, **{field: getattr(a.settings, field)}) == a.settings
    assert study.batch_variants(vs) == [R.DEFAULT]
    with pytest.raises(ValueError, match="contact"):
        R.Variant("x", contact="glue")
