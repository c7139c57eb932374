"""The batched stable-time-step scan (the reference protocol, experiment 4)
against mat_hopper.physics.stability.spec_scan, one design at a time on the CPU."""

import math

import pytest

from mat_hopper.batch import SCAN_COLUMNS, spec_scan_batch
from mat_hopper.core.materials import LegDesign, parse_design
from mat_hopper.physics.stability import spec_scan

# A short ladder (factor 2 per rung) and 0.6 s of static hopping: the first
# stance (touchdown near 0.34 s) is inside every try. Outcomes on MuJoCo's
# CPU engine, each with a margin (an unstable try diverges within 0.05 s,
# or at the first stance for the soft heavy leg, whose limit is the
# controller's 2.1e-4 s): PVC and the soft heavy leg pass at 2.5e-4 s, SS
# (spring limit near 1.2e-4 s) at 1.25e-4 s, Al on no rung (diverges at
# 0.05 s at 1.25e-4 s). MD is left out on purpose: at 5e-4 s it diverges at
# 0.409 s or survives 0.6 s depending on the last bit of the time step
# (5e-4 against geomspace's 4.999999999999999e-4), a borderline no float32
# engine can be asked to reproduce.
LADDER = dict(duration_s=0.6, first_s=1e-3, last_s=1.25e-4, n=4)
DESIGNS = ["PVC", LegDesign.from_properties([2.5], [0.45] * 3, name="soft-heavy"), "SS", "Al"]
NAMES = ["PVC", "soft-heavy", "SS", "Al"]


def _reference():
    return [
        spec_scan(parse_design(d) if isinstance(d, str) else d, first=1e-3, last=1.25e-4, n=4, duration_s=0.6)
        for d in DESIGNS
    ]


def test_mujoco_backend_is_spec_scan():
    summary, tries = spec_scan_batch(DESIGNS, workers=1, **LADDER)
    assert list(summary.columns) == list(SCAN_COLUMNS)
    assert list(summary["design"]) == NAMES
    got = summary["spec_timestep_s"].tolist()
    assert got == pytest.approx(_reference(), nan_ok=True)
    assert got == pytest.approx([2.5e-4, 2.5e-4, 1.25e-4, math.nan], nan_ok=True)
    # a design is tried until it ends upright, then never again
    assert summary["n_spec_tries"].tolist() == [3, 3, 4, 4] and len(tries) == 14
    assert tries.groupby("design", sort=False)["upright"].sum().tolist() == [1, 1, 1, 0]


def test_a_design_upright_on_no_rung_is_nan():
    summary, tries = spec_scan_batch(["SS"], duration_s=0.6, first_s=1e-3, last_s=5e-4, n=2, workers=1)
    assert math.isnan(summary["spec_timestep_s"][0]) and len(tries) == 2 and not tries["upright"].any()


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(designs=[]), "no designs"),
        (dict(designs=["SS"], n=0), "n >= 1"),
        (dict(designs=["SS"], first_s=1e-4, last_s=1e-3), "from first_s down to last_s"),
        (dict(designs=["SS"], first_s=1.0), "within"),
    ],
)
def test_bad_ladders_are_refused(kwargs, message):
    with pytest.raises(ValueError, match=message):
        spec_scan_batch(**kwargs)


@pytest.mark.slow
def test_warp_backend_is_spec_scan():
    pytest.importorskip("mujoco_warp")
    summary, _ = spec_scan_batch(DESIGNS, backend="warp", device="cpu", **LADDER)
    assert (summary["backend"] == "warp").all()
    assert summary["spec_timestep_s"].tolist() == pytest.approx(_reference(), nan_ok=True)
