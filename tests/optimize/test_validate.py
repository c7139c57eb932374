"""Front validation (mat_hopper.optimize.validate): interval dominance by
hand, the checks' settings against the issue's numbers, and one small
validation run end to end."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from mat_hopper.experiments.profiles import Profile
from mat_hopper.materials import paper_designs
from mat_hopper.optimize import Objective
from mat_hopper.optimize.validate import (
    AXIAL,
    FINE_CONTROL,
    FINE_PLAIN,
    NOMINAL,
    check_settings,
    dominates,
    mean_interval,
    paper_best,
    validation_tasks,
)

T, P = "tracking_error_m", "power_w"


def box(t, p):
    return {T: t, P: p}


def test_interval_dominance_by_hand():
    a = box((2.0, 3.0), (2.0, 3.0))
    assert dominates(box((0.5, 1.5), (0.5, 1.5)), a)  # clearly better on both
    assert dominates(box((0.5, 1.5), (2.5, 3.5)), a)  # clearly better on one, overlapping (a tie) on the other
    assert not dominates(box((1.5, 2.5), (2.5, 3.5)), a)  # ties on both
    assert not dominates(box((0.5, 1.5), (3.5, 4.0)), a)  # better on one, clearly worse on the other
    assert not dominates(a, a)
    # touching intervals overlap (a tie): 3.0 is not wholly below 3.0
    assert not dominates(box((1.0, 2.0), (3.0, 3.0)), box((2.0, 2.5), (3.0, 3.0)))


def test_paper_best_from_intervals():
    rows = []
    for name, t, p in (
        ("A", (1, 2), (5, 6)),
        ("B", (3, 4), (1, 2)),
        ("C", (3, 4), (3, 4)),
        ("D", (1.5, 2.5), (5.5, 7)),
    ):
        rows += [
            {"role": "paper", "design": name, "objective": T, "n": 3, "ci_low": t[0], "ci_high": t[1]},
            {"role": "paper", "design": name, "objective": P, "n": 3, "ci_low": p[0], "ci_high": p[1]},
        ]
    # C is dominated by B (tie on tracking, better power); D by nothing (A ties it on both,
    # B is clearly worse on tracking)
    assert paper_best(pd.DataFrame(rows)) == ["A", "B", "D"]


def test_mean_interval():
    lo, hi = mean_interval([1.0, 2.0, 3.0, 4.0])
    assert 1.0 <= lo < 2.5 < hi <= 4.0  # brackets the mean 2.5 within the data's range
    assert mean_interval([2.0, 2.0, 2.0]) == (2.0, 2.0)
    assert all(np.isnan(mean_interval([1.0])))


def test_check_settings_keep_the_control_period_and_sensor_delay():
    ob = Objective(replicates=0, profile=Profile("tiny", duration_s=2.0, transient_s=0.5))
    st = check_settings(paper_designs()["SS"], ob)
    assert st[NOMINAL].timestep_s == 1e-4
    fine = st[FINE_CONTROL]
    assert fine.timestep_s == 2e-5 and fine.substeps == 5 and fine.sensor_timing == "latency-5"
    assert fine.timestep_s * fine.substeps == pytest.approx(1e-4)  # the control period
    assert st[FINE_PLAIN].timestep_s == 2e-5 and st[FINE_PLAIN].substeps == 1
    assert st[FINE_PLAIN].sensor_timing == "authors"
    ax = st[AXIAL]
    assert ax.convention == "axial" and ax.timestep_s * ax.substeps == pytest.approx(1e-4) and ax.substeps > 1
    tasks = validation_tasks({"x": paper_designs()["Ti"]}, ob, replicates=2)
    checks = pd.DataFrame([t.labels for t in tasks])
    front = checks[checks["role"] == "front"]
    # 2 replicates + nominal + 2 fine steps + axial on the ramp, and the three other behaviours
    assert len(front) == 2 + 4 + 3 and set(front.loc[front["check"] == "behaviour", "behaviour"]) == {
        "static",
        "forward",
        "circle",
    }
    assert len(checks[checks["role"] == "paper"]) == 9 * (2 + 1)


def test_validate_front_end_to_end(tmp_path):
    """A tiny front: Ti (a mono-material) and a design far off the front
    that the paper's designs must dominate clearly."""
    from mat_hopper.materials import LegDesign
    from mat_hopper.optimize.validate import beats_paper, validate_front

    ob = Objective(replicates=0, profile=Profile("tiny", duration_s=4.0, transient_s=1.0))
    heavy = LegDesign.from_properties([20.0, 20.0, 20.0], [300.0, 300.0, 300.0], name="heavy")
    v = validate_front({"heavy": heavy}, ob, replicates=3, cache_dir=tmp_path, workers=2)
    ver = v["verdicts"].set_index("design")
    assert not ver.loc["heavy", "survives"]
    assert ver.loc["heavy", "dominated by"] or not ver.loc["heavy", "stable everywhere"]
    assert set(v["paper_best"]) <= set(paper_designs())
    assert beats_paper(v).empty  # nothing survived
