"""Sequential replication of the paired verdicts: seeds only where needed."""

import math
import os

import numpy as np
import pandas as pd
import pytest
from scipy import stats as sps

from mat_hopper import analysis
from mat_hopper.analysis import paired, sequential

RECORDS = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "book", "records")


# -- the start: the fewest seeds a Holm family can reject with ---------------------------------------------------


@pytest.mark.parametrize(
    ("m", "alpha", "n"),
    [
        # by hand: n > 1 + log2(m / alpha)
        (1, 0.05, 6),  # 1 + log2(20) = 5.32: 2/2^6 = 0.031 < 0.05, 2/2^5 = 0.0625 is not
        (4, 0.05, 8),  # 1 + log2(80) = 7.32: 4 x 2/2^8 = 0.031, 4 x 2/2^7 = 0.0625
        (5, 0.05, 8),  # 1 + log2(100) = 7.64
        (16, 0.05, 10),  # 1 + log2(320) = 9.32: 16 x 2/2^10 = 0.031, 16 x 2/2^9 = 0.0625
        (18, 0.05, 10),  # 1 + log2(360) = 9.49: 18 x 2/2^10 = 0.035
        (1, 0.10, 5),  # 1 + log2(10) = 4.32: 2/32 = 0.0625 < 0.1, 2/16 = 0.125
        (2, 0.0625, 7),  # 1 + log2(32) = 6 exactly: 2 x 2/2^6 = 0.0625 is not below alpha, so 7
    ],
)
def test_min_seeds_is_the_hand_calculation(m, alpha, n):
    assert sequential.min_seeds(m, alpha) == n
    assert m * 2 / 2**n < alpha <= m * 2 / 2 ** (n - 1)


def test_min_seeds_agrees_with_the_reachability_guard():
    for m in range(1, 41):
        assert sequential.min_seeds(m) == paired.min_replicates(m)
        assert analysis.min_seeds(m) == sequential.min_seeds(m)  # handed on by the package


@pytest.mark.parametrize(("args", "name"), [((0,), "family_size"), ((2.5,), "family_size"), ((4, 1.5), "alpha")])
def test_min_seeds_refuses_bad_input(args, name):
    with pytest.raises(ValueError, match=name):
        sequential.min_seeds(*args)


# -- the bounds behind "cannot change" -----------------------------------------------------------------------------


def _completions(x, n_max, rng):
    """Completions of `x` to n_max pairs: random, at the mean, and extreme values of either sign."""
    k = n_max - len(x)
    scale = float(np.abs(x).max()) + 1.0
    yield from (np.concatenate([x, rng.normal(x.mean(), x.std() + 0.1, k)]) for _ in range(20))
    yield np.concatenate([x, np.full(k, x.mean())])
    for sign in (1, -1):
        for big in (scale, 10 * scale, 1e3 * scale):
            yield np.concatenate([x, np.full(k, sign * big)])
            yield np.concatenate([x, sign * big * (1 + np.arange(k))])


def test_sign_flip_floor_is_a_lower_bound_on_every_completion():
    rng = np.random.default_rng(3)
    for trial in range(12):
        n = 4 + trial % 4
        x = rng.normal(0.02 * trial, 0.1, n)
        floor = sequential.sign_flip_floor(x, n + 3)
        assert 0 < floor <= 1
        for full in _completions(x, n + 3, rng):
            for n_end in range(n + 1, n + 4):
                assert paired.sign_flip_p(full[:n_end]) >= floor * (1 - 1e-9)
    # pairs that straddle zero cannot get below alpha within two more seeds
    assert sequential.sign_flip_floor(np.array([0.1, -0.1, 0.2, -0.15, 0.05, -0.02, 0.01, -0.03]), 10) >= 0.05
    # pairs all of one sign can: the floor is the test's own, 2 / 2^n_max
    assert sequential.sign_flip_floor(np.arange(1.0, 9.0), 10) == pytest.approx(2 / 2**10)


def test_narrowest_half_width_is_a_lower_bound_and_is_reached_at_the_mean():
    rng = np.random.default_rng(4)
    x = rng.normal(0.0, 0.2, 6)
    bound = sequential.narrowest_half_width(x, 10)
    for full in _completions(x, 10, rng):
        half = sps.t.ppf(0.975, len(full) - 1) * full.std(ddof=1) / math.sqrt(len(full))
        assert half >= bound * (1 - 1e-12)
    at_mean = np.concatenate([x, np.full(4, x.mean())])
    assert sps.t.ppf(0.975, 9) * at_mean.std(ddof=1) / math.sqrt(10) == pytest.approx(bound)


# -- the driver, with a synthetic callback ------------------------------------------------------------------------


def _family(n=12):
    """Three comparisons: a large effect, a tiny one (equivalent), and noise without an effect."""
    rng = np.random.default_rng(7)
    base = np.exp(rng.normal(0, 0.3, n))  # the seed moves both runs
    logs = {
        "large": 0.5 + rng.normal(0, 0.01, n),
        "tiny": 0.01 + rng.normal(0, 0.005, n),
        "noise": rng.normal(0, 0.4, n),
    }
    return {k: (pd.Series(base * np.exp(v)), pd.Series(base)) for k, v in logs.items()}


def test_the_driver_asks_only_for_the_seeds_open_comparisons_need():
    pairs, asked = _family(), []

    def fetch(ask):
        asked.append({k: list(s) for k, s in ask.items()})
        return {k: [(pairs[k][0][s], pairs[k][1][s]) for s in ss] for k, ss in ask.items()}

    out = sequential.sequential_family(fetch, list(pairs), seeds=range(12)).set_index("comparison")
    n0 = sequential.min_seeds(3)
    assert n0 == 7
    assert asked[0] == {k: list(range(n0)) for k in pairs}  # every comparison starts at the family's minimum
    assert all(set(a) == {"noise"} for a in asked[1:])  # decided comparisons get no further seed
    seen = [s for a in asked for s in a.get("noise", [])]
    assert seen == list(range(len(seen)))  # in seed order, never a seed twice
    assert out.loc["large", ["n_seeds", "stop", "conclusion"]].tolist() == [n0, "decided", paired.DIFFERENCE]
    assert out.loc["tiny", ["n_seeds", "stop", "conclusion"]].tolist() == [n0, "decided", paired.NO_DIFFERENCE]
    assert out.loc["noise", "stop"] in ("cannot change", "max n")
    assert out.loc["noise", "conclusion"] == paired.NOT_ENOUGH
    assert out.loc["noise", "n_seeds"] == len(seen)
    fixed = sequential.family_verdicts(pairs).set_index("comparison")  # every seed, the book's rule
    assert (out["conclusion"] == fixed["conclusion"]).all()


def test_a_comparison_whose_difference_rests_on_others_p_goes_on():
    # at the family's start (m = 2: 7 seeds) "edge" is a difference under Holm as it stands
    # (p 0.038 behind the other's 0.016 x 2), but not with the other's p at 1 (0.038 x 2)
    edge = np.array([0.1, 0.2, 0.3, 0.5, 0.9, 1.6, 2.4, 0.7, 0.8, 0.6])
    strong = 0.5 + 0.01 * np.sin(np.arange(10.0))
    base = pd.Series(np.ones(10))
    pairs = {"edge": (np.exp(pd.Series(edge)), base), "strong": (np.exp(pd.Series(strong)), base)}
    at_start = sequential.family_verdicts({k: (a[:7], b[:7]) for k, (a, b) in pairs.items()})
    assert at_start["conclusion"].tolist() == [paired.DIFFERENCE, paired.DIFFERENCE]
    assert 2 * at_start["p"].iat[0] >= 0.05  # edge's Holm p if strong's p could still grow
    out = sequential.replay_family(pairs).set_index("comparison")
    assert out.loc["strong", "n_seeds"] == 7  # decided whatever edge's seeds bring
    assert out.loc["edge", "n_seeds"] > 7  # not stopped on the other's p
    assert out.loc["edge", "conclusion"] == paired.DIFFERENCE


def test_cannot_change_stops_before_the_last_seed():
    rng = np.random.default_rng(11)
    x = np.array([0.3, -0.3, 0.25, -0.28, 0.31, -0.26, 0.29, -0.3, 0.27, -0.25, 0.3, -0.29])  # wide, centred
    base = pd.Series(np.exp(rng.normal(0, 0.2, 12)))
    out = sequential.replay_family({"flat": (base * np.exp(x), base)}, max_n=12)
    assert out["stop"].iat[0] == "cannot change"
    assert out["n_seeds"].iat[0] < 12 and out["conclusion"].iat[0] == paired.NOT_ENOUGH
    # under the BCa interval the bound does not apply: it runs to max n
    bca = sequential.replay_family({"flat": (base * np.exp(x), base)}, max_n=12, interval="bca")
    assert bca["stop"].iat[0] == "max n" and bca["n_seeds"].iat[0] == 12


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [({"step": 0}, "step"), ({"max_n": 20}, "max_n"), ({"alpha": 0.0}, "alpha"), ({"confidence": 1.0}, "confidence")],
)
def test_the_driver_refuses_bad_input(kwargs, name):
    with pytest.raises(ValueError, match=name):
        sequential.replay_family(_family(), **kwargs)


def test_the_driver_refuses_a_callback_that_answers_wrongly():
    with pytest.raises(ValueError, match="fetch returned no pairs"):
        sequential.sequential_family(lambda ask: {}, ["a"], max_n=8)
    with pytest.raises(ValueError, match="fetch returned 1 pairs"):
        sequential.sequential_family(lambda ask: {"a": [(1.0, 1.0)]}, ["a"], max_n=8)


# -- the recorded paper tables --------------------------------------------------------------------------------------

# chapter 8b's families, as its verdict cell forms them: Holm over the four gradients of each (metric, control)
STRESS_FAMILIES = (
    ("hop_peak_stress_median_pa", "mass-matched"),
    ("hop_peak_stress_median_pa", "titanium"),
    ("peak_stress_pa", "mass-matched"),
    ("fatigue_safety_factor", "titanium"),
)


def _stress_families():
    """The chapter's usable runs (status ok, at least 2 hops), paired on the replicate seed."""
    runs = pd.read_csv(os.path.join(RECORDS, "stress-pairs-paper.csv"))
    usable = runs[(runs["convention"] == "paper") & (runs["status"] == "ok") & (runs["n_hops"] >= 2)]
    wide = usable.pivot_table(
        index=["gradient", "replicate"], columns="leg", values=sorted({m for m, _ in STRESS_FAMILIES})
    )
    families = {}
    for metric, control in STRESS_FAMILIES:
        families[(metric, control)] = {
            name: (
                g.droplevel("gradient")[(metric, "gradient")].dropna(),
                g.droplevel("gradient")[(metric, control)].dropna(),
            )
            for name, g in wide.groupby(level="gradient", sort=False)
        }
    return families


def test_sequential_verdicts_on_chapter_8b_equal_the_ten_seed_verdicts():
    families = _stress_families()
    recorded = pd.read_csv(os.path.join(RECORDS, "stress-verdicts-paper.csv"))
    fixed = pd.concat([sequential.family_verdicts(p) for p in families.values()], ignore_index=True)
    # the fixed-n rule here is the chapter's: the same verdicts and Holm p at 10 seeds
    assert fixed["conclusion"].tolist() == recorded["conclusion"].tolist()
    np.testing.assert_allclose(fixed["p_holm"], recorded["p_holm"], rtol=1e-9)
    out = sequential.replay_families(families)
    got = pd.DataFrame(
        {
            "gradient": out["comparison"],
            "metric": [f[0] for f in out["family"]],
            "against": [f[1] for f in out["family"]],
        }
    )
    assert got.values.tolist() == recorded[["gradient", "metric", "against"]].values.tolist()
    assert out["conclusion"].tolist() == recorded["conclusion"].tolist()  # row for row
    assert (out["stop"] == "decided").all()
    saved = sequential.seeds_saved(out, 10)
    # the seeds used (docs/performance.md): 15 comparisons at 8 seeds, rho-dec's largest peak at 9
    assert saved["seeds_used"] == 129 and saved["seeds_fixed"] == 160
    runs_needed = {}
    for r in out.itertuples():
        for leg in ("gradient", r.family[1]):
            run = ("Ti",) if leg == "titanium" else (r.comparison, leg)  # titanium serves every gradient
            runs_needed[run] = max(runs_needed.get(run, 0), r.n_seeds)
    assert sum(runs_needed.values()) == 74 and len(runs_needed) * 10 == 90
