"""The findings page from the recorded paper-profile results: its table
follows the claims record, its answer and plot follow the numbers (a record
changed changes the page), and a missing record says which."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pandas as pd
import pytest

from mat_hopper import viz
from mat_hopper.viz import findings

RECORDS = Path(__file__).resolve().parents[2] / "book" / "records"


@pytest.fixture(scope="module")
def records():
    return findings.read_records(RECORDS)


@pytest.fixture
def copied(tmp_path):
    """A copy of the records folder, for editing."""
    folder = tmp_path / "records"
    shutil.copytree(RECORDS, folder)
    return folder


def test_the_package_hands_the_names_on():
    assert viz.findings_table is findings.findings_table and viz.forest_plot is findings.forest_plot


def test_one_row_per_claim_with_the_records_verdicts(records):
    claims = pd.read_csv(RECORDS / "claims-paper.csv")
    table = findings.findings_table(records)
    assert list(table.columns) == list(findings.FINDINGS_COLUMNS)
    assert len(table) == len(claims)
    assert table["claim"].tolist() == claims["claim"].tolist()
    assert table["verdict"].tolist() == claims["verdict"].tolist()
    assert table["converged in time step"].tolist() == claims["timestep_check"].fillna("not recorded").tolist()
    # the scoring-window check as recorded; a claim the record does not check says so
    if findings.WINDOW_COLUMN in claims.columns:
        want = claims[findings.WINDOW_COLUMN].fillna(findings.NOT_RECORDED).replace("", findings.NOT_RECORDED)
        assert table["stable over the scoring window"].tolist() == want.tolist()
    else:
        assert (table["stable over the scoring window"] == findings.NOT_RECORDED).all()


def test_rigid_twin_summary_counts_the_conclusions():
    cell = (
        "static SS +6.2 % [+2.0, +10.6] (difference, p_holm 0.023); forward SS -6.0 % [-7.7, -4.3] "
        "(no difference, p_holm 0.0078) | hip: ramp SS +0.9 % [-0.0, +1.8] (not enough evidence, p_holm 0.3)"
    )
    assert findings.rigid_twin_summary(cell) == "differs in 1 of 3 (1 no difference, 1 not enough evidence)"
    assert findings.rigid_twin_summary(float("nan")) == findings.NOT_COMPARED
    assert findings.rigid_twin_summary("homogeneous: its own twin") == "homogeneous: its own twin"


def test_a_changed_verdict_changes_the_table(copied):
    claims = pd.read_csv(copied / "claims-paper.csv")
    before = findings.findings_table(findings.read_records(copied))
    i = int((claims["verdict"] == "holds").idxmax())
    claims.loc[i, "verdict"] = "does not hold"
    claims[findings.WINDOW_COLUMN] = "stationary"
    claims.to_csv(copied / "claims-paper.csv", index=False)
    after = findings.findings_table(findings.read_records(copied))
    assert before.loc[i, "verdict"] == "holds" and after.loc[i, "verdict"] == "does not hold"
    assert (after.drop(index=i)["verdict"] == before.drop(index=i)["verdict"]).all()
    # a recorded window check is shown as recorded
    assert (after["stable over the scoring window"] == "stationary").all()
    answer = findings.design_answer(findings.read_records(copied))
    assert f"0 of them change verdict between the halves of the scoring window ({len(claims)} stationary)" in answer


def test_a_changed_effect_changes_the_answer(copied, records):
    answer = findings.design_answer(records)
    crossed = pd.read_csv(copied / "crossed-legs-paper.csv")
    row = crossed.index[(crossed["metric"] == "tracking_error_m") & crossed["contrast"].str.startswith("modulus")][0]
    old = f"{crossed.loc[row, 'pct_change']:+.1f} %"
    assert old in answer
    # the modulus alone now moves tracking error by 30 % [25, 35]: no longer equivalent
    crossed.loc[row, ["pct_change", "ci_low", "ci_high", "p_holm"]] = [30.0, 25.0, 35.0, 0.002]
    crossed.to_csv(copied / "crossed-legs-paper.csv", index=False)
    changed = findings.design_answer(findings.read_records(copied))
    assert "+30.0 % [+25.0, +35.0]" in changed and old not in changed.split("densities alone")[0]

    def modulus_alone(text):
        m = re.search(r"modulus alone: (\d+) of (\d+) equivalent, (\d+) beyond the margin", text)
        return int(m.group(1)), int(m.group(3))

    before, after = modulus_alone(answer), modulus_alone(changed)
    assert after == (before[0] - 1, before[1] + 1)  # one equivalent comparison is now beyond the margin


def test_a_changed_dominance_changes_the_ramp_sentence(copied):
    opt = pd.read_csv(copied / "optimizer-paper.csv")
    margin = opt["dominance"] == "margin"
    n = int(margin.sum())
    opt.loc[margin, "beats its mass-matched leg"] = "no evidence"
    opt.to_csv(copied / "optimizer-paper.csv", index=False)
    assert f"none of the {n} validated gradients dominates" in findings.design_answer(findings.read_records(copied))
    opt.loc[margin, "beats its mass-matched leg"] = "yes"
    opt.loc[margin, "survives"] = True
    opt.to_csv(copied / "optimizer-paper.csv", index=False)
    answer = findings.design_answer(findings.read_records(copied))
    assert (
        f"{n} of the {n} validated gradients dominate" in answer and f"Of those {n}, {n} survive validation." in answer
    )
    # a winner that fell under one check of the validation does not survive, and the check is named
    opt.loc[margin, "survives"] = False
    opt.loc[margin, "stable: axial"] = False
    opt.to_csv(copied / "optimizer-paper.csv", index=False)
    answer = findings.design_answer(findings.read_records(copied))
    assert (
        f"Of those {n}, 0 survive validation; those that do not fell or diverged under the validation's checks: axial"
        in answer
    )


def test_every_number_of_the_answer_is_in_the_records(records):
    """No typed number: each number of the answer is a count or a value of the records."""
    answer = findings.design_answer(records)
    effects = findings.paired_effects(records)
    values = {f"{v:+.1f}" for c in findings.EFFECT_COLUMNS for v in effects[c]}
    values |= {f"{v:+.1f}" for c in findings.EFFECT_COLUMNS for v in records["crossed_bending"][c]}
    values |= {f"{v:+.1f}" for c in findings.EFFECT_COLUMNS for v in records["modulus_bending"][c]}
    values |= {f"{v:+.1f}" for c in ("value_pct", "default_pct") for v in records["robustness_contact"][c]}
    for token in re.findall(r"[+-]\d+\.\d", answer):
        assert token in values, token


def test_forest_plot_one_interval_per_effect_and_the_band(records):
    effects = findings.paired_effects(records)
    fig = findings.forest_plot(records)
    ax = fig.axes[0]
    segments = [s for c in ax.collections if c.get_gid() == "intervals" for s in c.get_segments()]
    assert len(segments) == len(effects)
    drawn = sorted((round(s[0][0], 6), round(s[1][0], 6)) for s in segments)
    assert drawn == sorted(zip(effects["ci_low"].round(6), effects["ci_high"].round(6)))
    band = [p for p in ax.patches if p.get_gid() == "margin-band"]
    assert len(band) == 1
    x0, x1 = band[0].get_bbox().x0, band[0].get_bbox().x1  # data x, axes y (axvspan)
    assert (x0, x1) == (pytest.approx(-10), pytest.approx(10))
    # drawn on a given Axes, only the chosen kinds
    from matplotlib.figure import Figure

    ax = Figure().add_subplot()
    findings.forest_plot(records, ax, kinds=["stress: vs mass-matched"])
    segments = [s for c in ax.collections if c.get_gid() == "intervals" for s in c.get_segments()]
    assert len(segments) == int((effects["group"] == "stress: vs mass-matched").sum())
    with pytest.raises(ValueError, match="no effects of the kinds"):
        findings.forest_plot(records, kinds=["nope"])


def test_a_missing_record_is_named(copied):
    (copied / "crossed-legs-paper.csv").unlink()
    with pytest.raises(FileNotFoundError, match="crossed-legs-paper.csv"):
        findings.read_records(copied)


def test_a_missing_column_is_named(copied):
    claims = pd.read_csv(copied / "claims-paper.csv").drop(columns=["verdict"])
    claims.to_csv(copied / "claims-paper.csv", index=False)
    with pytest.raises(ValueError, match="verdict"):
        findings.read_records(copied)


def test_beside_record_sets_the_recorded_verdict_beside_the_builds():
    from mat_hopper.viz.findings import NOT_RECORDED, beside_record

    built = pd.DataFrame({"claim_id": ["a", "b"], "verdict": ["untestable", "holds"], "x": [1, 2]})
    rec = pd.DataFrame({"claim_id": ["a"], "verdict": ["partly"]})
    out = beside_record(built, rec, "claim_id", ["verdict", "x"])
    assert list(out.columns) == [
        "claim_id",
        "verdict",
        "verdict (recorded, paper profile)",
        "x",
        "x (recorded, paper profile)",
    ]
    assert out["verdict (recorded, paper profile)"].tolist() == ["partly", NOT_RECORDED]
    assert (out["x (recorded, paper profile)"] == NOT_RECORDED).all()
    with pytest.raises(ValueError, match="no column"):
        beside_record(built, rec, "claim_id", ["nope"])
    with pytest.raises(ValueError, match="key column"):
        beside_record(built, rec.rename(columns={"claim_id": "id"}), "claim_id", ["verdict"])


def test_the_contact_sentence_follows_the_robustness_record(tmp_path):
    """Edit the recorded stiff-contact flip back to a keep: the answer stops
    naming it and no longer says the ramp's claims rest on the contact
    unless every changed number is a ramp tracking one."""
    folder = tmp_path / "records"
    shutil.copytree(RECORDS, folder)
    path = folder / findings.RECORD_FILES["robustness_contact"]
    table = pd.read_csv(path)
    before = findings.design_answer(findings.read_records(folder))
    assert "1 flip (tracking rho-inc vs SS, ramp" in before and "rest on the soft contact" in before
    stiff = table["variant"] == "stiff contact"
    table.loc[stiff & (table["class"] == "flips"), "class"] = "keeps"
    table.loc[stiff & (table["quantity_id"] == "power SS vs MD, ramp"), "class"] = "moves > 2x"
    table.to_csv(path, index=False)
    after = findings.design_answer(findings.read_records(folder))
    assert "0 flip" in after and "rest on the soft contact" not in after


def test_the_modulus_sweeps_under_bending_follow_their_record(copied, records):
    """The answer counts the bending modulus contrasts beyond the margin from
    the record, names each, and gives each one's touchdown chatter, leg against base."""
    answer = findings.design_answer(records)
    sweeps = pd.read_csv(copied / "modulus-sweeps-bending-stiff-paper.csv")
    swept = sweeps[sweeps["modulus_gpa"] != float("inf")]
    n_beyond, n = int(swept["beyond_margin"].sum()), len(swept)
    assert f"{n_beyond} of {n} contrasts (a leg and a metric) move" in answer
    assert "touch toggles per phase switch, leg against base" in answer
    # no contrast beyond the margin any more: the count follows and nothing is named
    sweeps["beyond_margin"] = False
    sweeps.to_csv(copied / "modulus-sweeps-bending-stiff-paper.csv", index=False)
    changed = findings.design_answer(findings.read_records(copied))
    assert f"0 of {n} contrasts (a leg and a metric) move tracking error or hip power beyond ±10 %." in changed


def test_verdict_changes_names_each_differing_cell_once():
    """Labels compared without the numbers behind them; "not run" and rows
    one table lacks left out; by hand, then on the recorded reseed."""
    a = pd.DataFrame(
        {
            "claim_id": ["x", "y", "z", "w"],
            "verdict": ["holds", "partly", "holds", "holds"],
            "stationarity": ["stationary (holds | holds)", "window-dependent (a)", "stationary (x)", "stationary"],
            "beyond_mass": ["no (1 yes)", "no (2 yes)", "", ""],
        }
    )
    b = a.assign(
        verdict=["holds", "holds", "not run", "holds"],
        stationarity=["stationary (partly | partly)", "stationary (b)", "stationary (x)", "stationary"],
        beyond_mass=["no (2 yes)", "no (2 yes)", "", ""],
    ).iloc[:3]
    got = findings.verdict_changes(a, b)
    assert got.values.tolist() == [
        ["x", "beyond_mass", "no (1 yes)", "no (2 yes)"],
        ["y", "verdict", "partly", "holds"],
        ["y", "stationarity", "window-dependent", "stationary"],
    ]
    with pytest.raises(ValueError, match="second table has no column"):
        findings.verdict_changes(a, b.drop(columns="verdict"))
    recorded = findings.read_records(RECORDS)
    reseed = findings.verdict_changes(recorded["claims"], recorded["claims_reseeded"]).set_index(["claim_id", "column"])
    assert reseed.loc[("power_ss_max", "verdict")].tolist() == ["holds", "partly"]
    assert reseed.loc[("ramp_ss_power", "stationarity")].tolist() == ["stationary", "window-dependent"]
