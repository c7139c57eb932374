"""The book's design study and its Pareto table (mat_hopper.optimize.report)."""

from __future__ import annotations

import os

import pandas as pd

from mat_hopper import optimize
from mat_hopper.experiments.profiles import PROFILES


def test_front_table_and_designs():
    front = pd.DataFrame(
        {
            "trial": [0, 7],
            "paper_design": ["SS", ""],
            "tracking_error_m": [0.01, 0.02],
            "power_w": [0.008, 0.005],
            "hop_height_m": [0.96, 0.98],
            "tracking_error_vs_SS_pct": [0.0, 100.0],
            "power_vs_SS_pct": [0.0, -37.5],
            "seg1_rho_g_cm3": [8.0, 13.4],
            "seg1_e_gpa": [193.0, 4.4],
            "seg2_rho_g_cm3": [8.0, 2.0],
            "seg2_e_gpa": [193.0, 2.4],
        }
    )
    t = optimize.front_table(front)
    assert list(t.columns) == [
        "trial",
        "paper design",
        "tracking error (mm)",
        "hip power (mW)",
        "hop height (m)",
        "tracking vs SS (%)",
        "power vs SS (%)",
    ]
    assert t.loc[1, "tracking error (mm)"] == 20.0
    legs = optimize.front_designs(front)
    assert list(legs) == ["#7"] and legs["#7"].densities_g_cm3 == (13.4, 2.0)
    assert list(optimize.front_designs(front, skip_paper=False, k=1)) == ["#0"]


def test_book_study_runs_and_resumes(tmp_path):
    quick = PROFILES["quick"]
    rep = optimize.book_study(quick, studies_dir=tmp_path / "studies", out_dir=tmp_path / "study", trials=4)
    assert rep["name"].startswith("book-ramp-quick-")
    t = rep["trials"]
    assert len(t) == 4 and list(t["paper_design"][:3]) == ["SS", "rho-inc", "PVC-Ti-SS"]
    assert (tmp_path / "studies").is_dir() and os.path.isfile(rep["paths"]["pareto_plot"])
    again = optimize.book_study(
        quick, studies_dir=tmp_path / "studies", out_dir=tmp_path / "study", trials=4
    )  # resumed: nothing new to run
    pd.testing.assert_frame_equal(rep["trials"].drop(columns="worker"), again["trials"].drop(columns="worker"))
