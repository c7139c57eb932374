"""Front confirmation (mat_hopper.optimize.confirm): its seeds are apart
from the search's and validation's, its verdicts by hand, its refusals,
and one tiny confirmation end to end with its simulated seconds counted by
hand."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from mat_hopper.core.materials import LegDesign, paper_designs
from mat_hopper.experiments.profiles import Profile
from mat_hopper.optimize import MAX_REPLICATES, Objective, replicate_seeds
from mat_hopper.optimize.confirm import (
    CONFIRMATION_SEED_START,
    confirm_front,
    confirmation_tasks,
    confirmation_verdicts,
)
from mat_hopper.optimize.validate import REPLICATE, paired_table, validation_tasks

T, P = "tracking_error_m", "power_w"
OB = Objective(replicates=0, profile=Profile("tiny", duration_s=2.0, transient_s=0.5))  # the ramp
SS = paper_designs()["SS"]


def test_confirmation_seeds_are_neither_the_searchs_nor_validations():
    tasks = confirmation_tasks({"f": SS}, OB, 10)
    assert len(tasks) == (1 + 9) * 1 * 10  # (front + the nine paper designs) x one behaviour x 10 seeds
    seeds = {t.labels["replicate"] for t in tasks}
    assert seeds == set(range(2000, 2010))
    validation = {t.labels["replicate"] for t in validation_tasks({"f": SS}, OB, 10)} - {-1}
    assert seeds.isdisjoint(validation) and seeds.isdisjoint(replicate_seeds(MAX_REPLICATES))
    # common random numbers: every design meets seed 2003's same perturbation
    pert = {t.labels["design"]: t.settings.perturbation for t in tasks if t.labels["replicate"] == 2003}
    assert len(pert) == 10 and len({repr(p) for p in pert.values()}) == 1
    assert CONFIRMATION_SEED_START == 2000


def _runs(legs: dict, n: int, fell=()) -> pd.DataFrame:
    """A confirmation's run table: {(role, name): (tracking factor, power
    factor)} on n shared seeds (seed k scales every design alike); `fell`:
    (name, seed) pairs whose run fell."""
    rng = np.random.default_rng(1)
    seed = np.exp(rng.normal(0, 0.2, n))
    rows = []
    for (role, name), (ft, fp) in legs.items():
        for r in range(n):
            noise = np.exp(rng.normal(0, 0.01, 2))
            rows.append({"role": role, "design": name, "behaviour": "ramp", "check": REPLICATE,
                         "replicate": 2000 + r, "status": "fell" if (name, r) in fell else "ok",
                         f"mean_{T}": 0.01 * ft * seed[r] * noise[0], f"mean_{P}": 2.0 * fp * seed[r] * noise[1]})  # fmt: skip
    return pd.DataFrame(rows)


LEGS = {
    ("front", "f"): (1.0, 1.0),  # A tracks twice as well at the same power: dominated
    ("front", "g"): (0.3, 1.0),  # tracks best of all at A's power: nothing dominates it
    ("front", "h"): (0.4, 3.0),  # better tracking than A, worse power: a trade-off, kept
    ("paper", "A"): (0.5, 1.0),
    ("paper", "B"): (0.5, 2.0),
}


def test_confirmation_verdicts_by_hand():
    runs = _runs(LEGS, 10)
    v = confirmation_verdicts(runs, paired_table(runs, OB)).set_index("design")
    assert v.loc["f", "dominated by"] == "A" and v.loc["f", "confirmed"] == False  # noqa: E712
    assert v.loc["g", "dominated by"] == "" and v.loc["g", "confirmed"] == True  # noqa: E712
    assert v.loc["h", "confirmed"] == True  # noqa: E712
    assert v["testable"].all() and v["stable"].all()


def test_three_seeds_confirm_nothing_and_a_fall_fails():
    runs = _runs(LEGS, 3)
    v = confirmation_verdicts(runs, paired_table(runs, OB)).set_index("design")
    assert (v["confirmed"] == "untestable").all()  # 2 / 2^3 x 2 comparisons > 0.05
    runs = _runs(LEGS, 10, fell={("g", 4)})
    v = confirmation_verdicts(runs, paired_table(runs, OB)).set_index("design")
    assert v.loc["g", "stable"] == False and v.loc["g", "confirmed"] == False  # noqa: E712


@pytest.mark.parametrize("bad", [1, 0, 2.5, True, "10", 1001])
def test_confirm_front_refuses_a_bad_seed_count_before_any_run(tmp_path, bad):
    with pytest.raises(ValueError, match="replicates must be an integer >= 2"):
        confirm_front({"f": SS}, OB, replicates=bad, cache_dir=tmp_path)
    assert not any(tmp_path.iterdir())


def test_confirm_front_end_to_end(tmp_path):
    heavy = LegDesign.from_properties([20.0, 20.0, 20.0], [300.0, 300.0, 300.0], name="heavy")
    c = confirm_front({"heavy": heavy}, OB, replicates=2, cache_dir=tmp_path, workers=1)
    # by hand: (1 front + 9 paper designs) x 1 behaviour x 2 seeds x 2.0 s
    assert c["simulated_s"] == pytest.approx(40.0) and c["front_simulated_s"] == pytest.approx(4.0)
    assert len(c["runs"]) == 20 and set(c["runs"]["replicate"]) == {2000, 2001}
    assert c["verdicts"].set_index("design").loc["heavy", "confirmed"] in (False, "untestable")
    assert c["confirmed"] == {}
