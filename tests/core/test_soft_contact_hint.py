"""What a bending leg on MuJoCo's default soft contact is told when it
falls or diverges: the contact's cause and ``--contact stiff``, from the
one place these lines are built (:mod:`mat_hopper.core.timestep`)."""

from types import SimpleNamespace

import numpy as np
import pandas as pd

from mat_hopper.core.materials import parse_design
from mat_hopper.core.rollout import Rollout
from mat_hopper.core.sim import sim_settings
from mat_hopper.core.timestep import CLI_AUTO_HINT, remedies, soft_contact_cause


def _settings(design, **kw):
    return sim_settings(design, timestep_s="auto", duration_s=4.0, transient_s=1.0, **kw)


def test_a_bending_leg_on_the_soft_contact_is_told_to_try_the_stiff_one():
    """Already at its automatic step, a bending leg's only remedy is the
    contact (book/records/README.md: bending-mode-stiff.csv, where the
    same legs stand on a 1 ms time constant)."""
    ti = parse_design("Ti")
    bending = _settings(ti, convention="bending")
    assert "--contact stiff" in remedies(ti, bending, CLI_AUTO_HINT)
    assert 'contact="stiff"' in remedies(ti, bending)  # the API names its own keyword
    assert "soft contact" in soft_contact_cause(ti, bending)
    assert remedies(ti, _settings(ti, convention="bending", contact="stiff"), CLI_AUTO_HINT) is None
    assert remedies(ti, _settings(ti, convention="paper"), CLI_AUTO_HINT) is None  # no bending, no ringing


def test_a_step_above_the_bound_is_the_cause_named_not_the_contact():
    """At the authors' 1e-4 s step a 64-segment SS leg under bending lies
    far above its 1.6e-6 s bound: the step, not the contact, is the cause."""
    ss = parse_design("SS", n_segments=64)
    fixed = sim_settings(ss, timestep_s=1e-4, duration_s=4.0, transient_s=1.0, convention="bending")
    assert soft_contact_cause(ss, fixed) is None


def test_a_diverged_bending_run_says_why_and_what_to_try():
    """The divergence message (simulate's UNSTABLE line, the API's
    DivergenceWarning) names the soft contact's cause and --contact stiff."""
    ti = parse_design("Ti")
    run = SimpleNamespace(
        stable=False,
        diverged_at_s=5.1688,
        divergence_reason="numerical divergence: |qacc| 1e+06 > 1e+06 at joint mat_bend_y_1",
        design=ti,
        settings=_settings(ti, convention="bending"),
    )  # the fields divergence_message reads, as a diverged run leaves them
    message = Rollout.divergence_message(run, CLI_AUTO_HINT)
    assert "try --contact stiff" in message, message


def test_batch_blanks_a_diverged_designs_metrics_and_names_the_stiff_contact():
    """A diverged design's hop cycles before the divergence are not
    results: the printed row shows "-" (the measured rho-inc row was
    6 0.9377 0.05895 19.12 False); the note names --contact stiff."""
    from mat_hopper.cli.batch import _blank_diverged, _diverged_note

    shown = pd.DataFrame(
        {"design": ["Ti", "rho-inc"], "n_hops": [7, 6], "hop_height_m": [0.9527, 0.9377],
         "tracking_error_m": [0.05756, 0.05895], "power_w": [6.241, 19.12], "stable": [True, False]}
    )  # fmt: skip
    text = _blank_diverged(shown).to_string(index=False)
    assert "19.12" not in text and "0.9377" not in text and "6.241" in text
    designs = [parse_design("Ti"), parse_design("rho-inc")]
    per = [_settings(d, convention="bending") for d in designs]
    table = shown.assign(diverged_at_s=[np.nan, 5.1688], fell_at_s=[np.nan, np.nan])
    note = _diverged_note(table, True, designs, per)
    assert "--contact stiff" in note and "already at --timestep auto" in note, note
