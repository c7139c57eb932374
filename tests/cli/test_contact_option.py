"""``--contact``: the foot-terrain contact from the command line, read in
any case, recorded in the hop table, refused in one line otherwise."""

from __future__ import annotations

import pandas as pd
import pytest
from _refusal import refused

from mat_hopper.cli import main

LONG = ["--duration", "3000", "--transient", "1"]  # many seconds of work: a refusal must come first


@pytest.fixture
def here(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("MAT_HOPPER_PROFILE", raising=False)
    return tmp_path


@pytest.mark.parametrize("bad", ["rigid", "soft", "stif"])
def test_unknown_contact_refused(here, capsys, bad):
    refused(["simulate", "--contact", bad, *LONG], capsys, "--contact", repr(bad), "authors, stiff")
    refused(["render", "--video", "v.gif", "--contact", bad], capsys, "--contact", repr(bad))
    assert not (here / "v.gif").exists()


def test_empty_contact_refused(here, capsys):
    refused(["simulate", "--contact", "", *LONG], capsys, "--contact")


def test_contact_on_a_still_is_refused(here, capsys):
    refused(["render", "--still", "s.png", "--contact", "stiff"], capsys, "--contact", "--still")


def test_simulate_contact_any_case_in_the_table(here, capsys):
    out = here / "hops.csv"
    argv = ["simulate", "--design", "MD", "--duration", "4", "--transient", "1.5", "--no-progress"]
    assert main([*argv, "--contact", "STIFF", "--csv", str(out)]) == 0
    assert "contact=stiff" in capsys.readouterr().out
    hops = pd.read_csv(out)
    assert len(hops) >= 2 and (hops["contact"] == "stiff").all()
    assert hops["peak_penetration_m"].between(0, 3e-3).all()
    assert main([*argv, "--csv", str(here / "soft.csv")]) == 0  # the default
    soft = pd.read_csv(here / "soft.csv")
    assert (soft["contact"] == "authors").all() and (soft["peak_penetration_m"] > 5e-3).all()
