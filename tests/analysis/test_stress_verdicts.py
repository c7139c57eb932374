"""Chapter 8b's stress verdicts, on a hand-made table of runs."""

import numpy as np
import pandas as pd

from mat_hopper.analysis.stress_pairs import stress_verdicts, usable_pairs


def _runs(n_seeds: int = 10) -> pd.DataFrame:
    rows = []
    rng = np.random.default_rng(0)
    for seed in range(n_seeds):
        for leg, stress, safety in (("gradient", 120.0, 2.0), ("mass-matched", 100.0, 2.0), ("titanium", 100.0, 4.0)):
            noise = 1 + 0.01 * rng.standard_normal()  # each run its own
            rows.append(
                {
                    "convention": "paper",
                    "gradient": "rho-inc",
                    "leg": leg,
                    "replicate": seed,
                    "status": "ok",
                    "n_hops": 50,
                    "hop_peak_stress_median_pa": stress * noise,
                    "peak_stress_pa": stress * 1.5 * noise,
                    "fatigue_safety_factor": safety * noise,
                }
            )
    return pd.DataFrame(rows)


def test_a_gradient_loaded_20_percent_more_differs_and_its_life_halves():
    v = stress_verdicts(_runs(), 10).set_index(["metric", "against"])
    loads = v.loc[("hop_peak_stress_median_pa", "mass-matched")]
    assert abs(loads["pct_change"] - 20.0) < 0.5 and loads["conclusion"] == "difference"
    life = v.loc[("fatigue_safety_factor", "titanium")]
    assert abs(life["pct_change"] + 50.0) < 0.5 and life["n_pairs"] == 10 and life["pairs_dropped"] == 0


def test_a_run_that_fell_drops_its_pair_and_is_counted():
    runs = _runs()
    runs.loc[(runs["leg"] == "mass-matched") & (runs["replicate"] == 3), "status"] = "fallen"
    assert len(usable_pairs(runs)) == len(runs) - 1
    v = stress_verdicts(usable_pairs(runs), 10).set_index(["metric", "against"])
    assert v.loc[("peak_stress_pa", "mass-matched"), "pairs_dropped"] == 1
    assert v.loc[("fatigue_safety_factor", "titanium"), "pairs_dropped"] == 0


def test_two_seeds_cannot_reach_a_difference():
    v = stress_verdicts(_runs(2), 2)
    assert set(v["conclusion"]) <= {"not enough evidence", "no difference"}
