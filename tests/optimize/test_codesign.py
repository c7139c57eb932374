"""Control against material (mat_hopper.optimize.codesign): the survival
rule on a hand-made comparison, and a tiny tuning end to end."""

from __future__ import annotations

import pandas as pd
import pytest

from mat_hopper.core import reference as ref
from mat_hopper.experiments.profiles import Profile
from mat_hopper.optimize.codesign import DEFAULT, TUNED, answer, codesign, survival, tune


def _row(setting, design, metric, pct, lo, hi):
    return {"experiment": setting, "design": design, "metric": metric, "pct_change": pct, "ci_low": lo, "ci_high": hi}


def test_survival_rule_by_hand():
    comp = pd.DataFrame(
        [
            _row(DEFAULT, "SS", "tracking_error_m", -40, -45, -35),
            _row(TUNED, "SS", "tracking_error_m", -20, -30, -10),  # smaller, still clear, same sign: survives
            _row(DEFAULT, "SS", "power_w", 150, 120, 180),
            _row(TUNED, "SS", "power_w", 5, -10, 20),  # interval now holds 0: erased
            _row(DEFAULT, "PVC", "tracking_error_m", 3, -5, 10),  # never clear
            _row(TUNED, "PVC", "tracking_error_m", -30, -40, -20),
        ]
    )
    s = survival(comp).set_index(["design", "metric"])
    assert s.loc[("SS", "tracking_error_m"), "survives"]
    assert not s.loc[("SS", "power_w"), "survives"] and s.loc[("SS", "power_w"), "clear authors"]
    assert not s.loc[("PVC", "tracking_error_m"), "survives"]
    assert not s.loc[("PVC", "tracking_error_m"), "clear authors"]
    hops = pd.DataFrame(
        {
            "experiment": [DEFAULT] * 4 + [TUNED] * 4,
            "design": ["MD", "MD", "SS", "SS"] * 2,
            "replicate": [0, 1] * 4,
            "tracking_error_m": [0.02, 0.02, 0.01, 0.01, 0.02, 0.02, 0.015, 0.015],
        }
    )
    text = answer(s.reset_index(), hops)
    assert text.startswith("1 of 2 clear material differences against MD")
    assert "100 % at the authors' gains and 33 % at their own" in text  # (0.02 - 0.01) / 0.01, (0.02 - 0.015) / 0.015
    assert "Control erases some of it: SS power_w no longer differ clearly." in text


def test_tuning_starts_from_the_authors_gains_and_is_reproducible(tmp_path):
    tiny = Profile("tiny", duration_s=4.0, transient_s=1.0, replicates=2)
    from mat_hopper.experiments.runner import Runner

    with Runner(tmp_path, workers=1, progress=False) as runner:
        a = tune("SS", profile=tiny, trials=5, batch=2, runner=runner)
        b = tune("SS", profile=tiny, trials=5, batch=2, runner=runner)  # all cached, same proposals
    first = a.trials.iloc[0]
    assert (first["foot_placement_gain"], first["stance_kp"], first["stance_kd"]) == (
        ref.FOOT_PLACEMENT_GAIN,
        ref.STANCE_KP,
        ref.STANCE_KD,
    )
    assert first["score"] == 2.0  # e / e0 + P / P0 at the reference itself
    assert a.score <= 2.0 and a.gains == b.gains
    pd.testing.assert_frame_equal(a.trials, b.trials)
    with pytest.raises(ValueError, match="trials must be"):
        tune("SS", profile=tiny, trials=0)


def test_codesign_end_to_end(tmp_path):
    tiny = Profile("tiny", duration_s=4.0, transient_s=1.0, replicates=2)
    out = codesign(["MD", "SS"], profile=tiny, trials=4, cache_dir=tmp_path, workers=2)
    assert list(out["gains"]["design"]) == ["MD", "SS"]
    assert set(out["comparison"]["experiment"]) == {DEFAULT, TUNED}
    assert set(out["survival"]["design"]) == {"SS"} and out["answer"].endswith(".")
    with pytest.raises(ValueError, match="baseline 'MD' must be one of the designs"):
        codesign(["SS", "Ti"], profile=tiny, trials=2, cache_dir=tmp_path)


@pytest.mark.parametrize(
    ("kwargs", "text"),
    [
        ({"batch": 0}, "batch must be an integer >= 1, got 0"),
        ({"batch": -3}, "batch must be an integer >= 1, got -3"),
        ({"batch": 2.5}, "batch must be an integer >= 1, got 2.5"),
        ({"trials": True}, "trials must be an integer >= 1, got True"),
        ({"seed": "0"}, "seed must be an integer, got '0'"),
    ],
)
def test_tune_refuses_bad_counts_before_running(kwargs, text):
    # batch <= 0 used to loop forever asking no trial; nothing runs here:
    # the check comes before any runner is made
    with pytest.raises(ValueError, match=text):
        tune("SS", profile=Profile("tiny", duration_s=4.0, transient_s=1.0), **{"trials": 3, **kwargs})


@pytest.mark.parametrize(
    ("kwargs", "text"),
    [
        ({"replicates": 2.7}, "replicates must be an integer, got 2.7"),
        ({"replicates": 1}, "at least 2 replicates, got 1"),
        ({"trials": 0}, "trials must be an integer >= 1, got 0"),
    ],
)
def test_codesign_refuses_bad_counts_before_running(tmp_path, kwargs, text):
    with pytest.raises(ValueError, match=text):
        codesign(["MD", "SS"], profile=Profile("tiny", duration_s=4.0, transient_s=1.0), cache_dir=tmp_path, **kwargs)
    assert list(tmp_path.iterdir()) == []  # no runner, no cache written
