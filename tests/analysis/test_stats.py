import numpy as np
import pandas as pd
import pytest

from mat_hopper.analysis import stats
from mat_hopper.core.perturbations import Perturbation
from mat_hopper.core.sim import simulate
from mat_hopper.physics import metrics


def _table(values: dict, behaviour="forward", **labels):
    """Per-hop table from {design: array of tracking errors}."""
    frames = [
        pd.DataFrame(
            {
                "design": d,
                "behaviour": behaviour,
                "tracking_error_m": np.asarray(v, float),
                "power_w": np.asarray(v, float) * 10,
                **labels,
            }
        )
        for d, v in values.items()
    ]
    return pd.concat(frames, ignore_index=True)


def test_summary_table_known_values():
    hops = _table({"MD": [1, 2, 3, 4, 5], "SS": [2, 4, 6, 8, 10]})
    s = stats.summary_table(hops, metrics=("tracking_error_m",))
    ss = s[s["design"] == "SS"].iloc[0]
    assert ss["mean"] == 6 and ss["median"] == 6 and ss["iqr"] == pytest.approx(4.0)  # 8 - 4
    assert ss["pct_change_mean"] == pytest.approx(100.0)
    assert s.loc[s["design"] == "MD", "pct_change_mean"].iloc[0] == 0


def test_compare_hops_holm_per_family():
    rng = np.random.default_rng(1)
    parts = []
    for conv, shift in (("paper", 1.0), ("axial", 0.0)):
        parts.append(
            _table(
                {"MD": rng.normal(1, 0.05, 25), "SS": rng.normal(1 + shift, 0.05, 25), "Al": rng.normal(1, 0.05, 25)},
                convention=conv,
                experiment="exp1",
            )
        )
    c = stats.compare_hops(pd.concat(parts), "MD", metrics=("tracking_error_m",))
    assert set(c["basis"]) == {"hops"}
    for _, fam in c.groupby("convention"):
        np.testing.assert_allclose(fam["p_holm"], metrics.holm(fam["p"]))  # one Holm family per convention
        assert (fam["p_holm"] >= fam["p"]).all()
    paper_ss = c[(c["convention"] == "paper") & (c["design"] == "SS")].iloc[0]
    assert paper_ss["significant"] and paper_ss["pct_change"] == pytest.approx(100, abs=3)
    assert not c[(c["convention"] == "axial") & (c["design"] == "SS")]["significant"].iloc[0]


def test_holm_matches_hand_computation():
    np.testing.assert_allclose(metrics.holm([0.01, 0.04, 0.03]), [0.03, 0.06, 0.06])


def test_bootstrap_ci_contains_truth_and_is_deterministic():
    rng = np.random.default_rng(7)
    a, b = rng.normal(2.0, 0.1, 20), rng.normal(1.0, 0.05, 20)  # truth: +100 %
    pct, lo, hi = stats.bootstrap_pct_change(a, b, n_boot=4000, seed=3)
    assert lo < 100 < hi and lo > 0
    assert hi - lo < 20
    assert (pct, lo, hi) == stats.bootstrap_pct_change(a, b, n_boot=4000, seed=3)
    assert np.isnan(stats.bootstrap_pct_change([], b)[0])
    with pytest.raises(ValueError, match="confidence"):
        stats.bootstrap_pct_change(a, b, confidence=1.5)


def test_replicate_means_and_comparison():
    rng = np.random.default_rng(2)
    frames = []
    for rep in range(-1, 10):
        for design, level in (("MD", 0.10), ("SS", 0.03)):
            run_level = level * (1 + rng.normal(0, 0.05))
            frames.append(
                _table(
                    {design: run_level + rng.normal(0, 0.002, 15)}, replicate=rep, experiment="exp1", convention="paper"
                )
            )
    hops = pd.concat(frames, ignore_index=True)
    means = stats.replicate_means(hops)
    assert len(means) == 20 and (means["replicate"] >= 0).all() and (means["n_hops"] == 15).all()
    assert stats.has_replicates(hops)
    c = stats.compare_designs(hops, "MD", metrics=("tracking_error_m",), n_boot=2000)
    row = c.iloc[0]
    assert row["basis"] == "replicates" and row["n"] == 10 and row["significant"]
    assert row["ci_low"] < -70 < row["ci_high"]  # truth: -70 %
    hop_based = stats.compare_designs(hops, "MD", basis="hops", metrics=("tracking_error_m",))
    assert hop_based["basis"].iloc[0] == "hops" and hop_based["n"].iloc[0] == 15  # the unperturbed run only
    assert not stats.has_replicates(hops[hops["replicate"] < 0])


def test_combine_experiments_takes_each_design_once():
    a = _table({"MD": [1.0, 1.1], "SS": [0.5, 0.6]}, experiment="exp1")
    b = _table({"MD": [9.0, 9.0], "rho-inc": [0.2, 0.3]}, experiment="exp3")
    t = stats.combine_experiments(pd.concat([a, b]))
    assert sorted(t["design"].unique()) == ["MD", "SS", "rho-inc"]
    assert t.loc[t["design"] == "MD", "tracking_error_m"].max() < 2  # MD from exp1
    assert set(t["experiment"]) == {"exp1+exp3"}


def test_bad_input_names_the_field():
    hops = _table({"MD": [1.0], "SS": [2.0]})
    with pytest.raises(ValueError, match="baseline"):
        stats.compare_hops(hops, "Ti", metrics=("tracking_error_m",))
    with pytest.raises(ValueError, match="metrics"):
        stats.summary_table(hops, metrics=("nope",))
    with pytest.raises(ValueError, match="replicate"):
        stats.replicate_means(hops)
    with pytest.raises(ValueError, match="basis"):
        stats.compare_designs(hops, basis="cycles")


def test_static_hopping_needs_replicates():
    """The module doc's claim: unperturbed in-place hopping has no lateral
    motion (tracking error exactly 0); a replicate's perturbation gives some."""
    still = metrics.hop_table(simulate("SS", "static", duration_s=4, transient_s=1))
    assert len(still) >= 2 and (still["tracking_error_m"] == 0.0).all()
    moved = metrics.hop_table(
        simulate("SS", "static", duration_s=4, transient_s=1, perturbation=Perturbation.replicate(0, (1.0, 4.0)))
    )
    assert len(moved) >= 2 and (moved["tracking_error_m"] > 1e-4).all()


def test_basis_name_any_case():
    hops = pd.concat(
        [_table({"MD": [0.10, 0.11, 0.12], "SS": [0.03, 0.04, 0.05]}, replicate=-1, experiment="exp1")],
        ignore_index=True,
    )
    mixed = stats.compare_designs(hops, "MD", basis=" Hops ", metrics=("tracking_error_m",))
    pd.testing.assert_frame_equal(mixed, stats.compare_designs(hops, "MD", basis="hops", metrics=("tracking_error_m",)))
    assert mixed["basis"].iloc[0] == "hops"
