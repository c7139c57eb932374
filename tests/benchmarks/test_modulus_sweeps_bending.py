"""benchmarks/modulus_sweeps_bending.py's table from hop rows: each swept
modulus and the rigid twin against the base's own modulus, the halves of the
scored window, and each leg's chatter beside its comparator's."""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from mat_hopper.core import reference as ref

SCRIPT = Path(__file__).resolve().parents[2] / "benchmarks" / "modulus_sweeps_bending.py"


def _module():
    if str(SCRIPT.parent) not in sys.path:  # as when the script runs: its folder first on the path (benchmarks/_inputs)
        sys.path.insert(0, str(SCRIPT.parent))
    spec = importlib.util.spec_from_file_location("modulus_sweeps_bending", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _hops(mod, shift_second_half: float) -> pd.DataFrame:
    """Hops of every leg of mod.legs(): 10 seeds, 4 hops each (2 per half);
    SS at its softest modulus tracks 30 % better, by `shift_second_half` more
    in the second half; every leg's chatter is its modulus' log10 (rigid: 1)."""
    rng = np.random.default_rng(0)
    rows = []
    for base, by_modulus in mod.legs().items():
        soft = min(ref.SWEEPS[base]["modulus"])
        for e in by_modulus:
            for seed in range(10):
                for t in (20.0, 30.0, 40.0, 50.0):
                    factor = 0.7 - (shift_second_half if t >= 40 else 0.0) if (base == "SS" and e == soft) else 1.0
                    rows.append(
                        {
                            "base": base,
                            "modulus_gpa": e,
                            "replicate": seed,
                            "t_start_s": t,
                            "t_end_s": t + 0.6,
                            "tracking_error_m": 0.03 * factor * (1 + 0.001 * rng.standard_normal()),
                            "power_w": 2.0 * (1 + 0.001 * rng.standard_normal()),
                            "touch_toggles_per_switch": 1.0 if math.isinf(e) else math.log10(e) + 2,
                            "peak_penetration_m": 9e-4,
                        }
                    )
    return pd.DataFrame(rows)


def test_a_soft_leg_beyond_the_margin_is_found_and_stationary():
    mod = _module()
    table = mod.with_halves(_hops(mod, 0.0))
    ss = table[(table["base"] == "SS") & (table["metric"] == "tracking_error_m")].set_index("modulus_gpa")
    soft = min(ref.SWEEPS["SS"]["modulus"])
    assert ss.loc[soft, "pct_change"] == pytest.approx(-30.0, abs=0.5)
    assert ss.loc[soft, "beyond_margin"] and ss.loc[soft, "conclusion"] == "difference"
    assert ss.loc[soft, "stationarity"].startswith("stationary")
    # the rigid twin is a row of its own (modulus inf), inside the margin here
    assert not ss.loc[math.inf, "beyond_margin"]
    assert table["beyond_margin"].sum() == 1
    # each leg's chatter beside its comparator's
    assert ss.loc[math.inf, "leg_touch_toggles_per_switch"] == 1.0
    assert ss.loc[soft, "against_touch_toggles_per_switch"] == math.log10(ref.MONO_MATERIALS["SS"][1]) + 2
    assert ss.loc[soft, "leg_peak_penetration_mm"] == pytest.approx(0.9)


def test_an_effect_that_reverses_in_the_second_half_is_window_dependent():
    mod = _module()
    table = mod.with_halves(_hops(mod, -0.6))  # soft SS: 30 % better, then 30 % worse
    ss = table[(table["base"] == "SS") & (table["metric"] == "tracking_error_m")]
    soft = ss[ss["modulus_gpa"] == min(ref.SWEEPS["SS"]["modulus"])].iloc[0]
    assert soft["first_half_pct"] < -25 and soft["second_half_pct"] > 25
    assert soft["stationarity"].startswith("window-dependent")
