"""How closely one backend's batch table follows the reference's.

The tolerances are the acceptance figures of the warp backend against
the CPU rollouts (float32 MuJoCo Warp against float64 MuJoCo): hop count
within 1, mean hop height within 0.01 m, tracking error and hip power
within 10 %; two runs that both diverge agree when they diverge within
1 ms of each other. Runs too short to score a hop cycle in both backends
are compared on their whole-run means instead (tracking error and hip
power over every recorded sample, ``run_tracking_error_m``,
``run_power_w``), with the same 10 %.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

HOPS_TOLERANCE = 1  # hop cycles
HEIGHT_TOLERANCE_M = 0.01
RELATIVE_TOLERANCE = 0.10  # tracking error and hip power
DIVERGENCE_TOLERANCE_S = 1e-3

AGREEMENT_COLUMNS = (
    "design",
    "behaviour",
    "stable_ref",
    "stable",
    "n_hops_ref",
    "n_hops",
    "hop_height_diff_m",
    "tracking_error_diff_pct",
    "power_diff_pct",
    "run_tracking_error_diff_pct",
    "run_power_diff_pct",
    "agrees",
)


def _pct(value: float, reference: float) -> float:
    if not (math.isfinite(value) and math.isfinite(reference)) or reference == 0:
        return math.nan
    return 100.0 * (value - reference) / abs(reference)


def agreement(reference: pd.DataFrame, other: pd.DataFrame) -> pd.DataFrame:
    """How far a batch backend's results are from the reference's, per design.

    Args:
        reference: a batch table (:func:`mat_hopper.batch.evaluate`), e.g. the
            mujoco backend's.
        other: a batch table of the same designs in the same order.

    Returns:
        One row per design (:data:`AGREEMENT_COLUMNS`): both stabilities and
        hop counts, the other's hop height minus the reference's (m), its
        tracking error and hip power in percent of the reference's (over
        scored hop cycles, and over the whole run where the tables carry
        ``run_*`` means), and whether every figure is within tolerance (hops
        within :data:`HOPS_TOLERANCE`, height within :data:`HEIGHT_TOLERANCE_M`,
        tracking and power within :data:`RELATIVE_TOLERANCE`, divergence
        times within :data:`DIVERGENCE_TOLERANCE_S`).

    Raises:
        ValueError: a table that is not one, lacks a column, or other designs.
    """
    need = ("design", "n_hops", "hop_height_m", "tracking_error_m", "power_w", "stable", "diverged_at_s")
    for label, t in (("reference", reference), ("other", other)):
        if not isinstance(t, pd.DataFrame):
            raise ValueError(f"agreement: {label} must be a batch table (DataFrame), got {type(t).__name__}")
        missing = [c for c in need if c not in t.columns]
        if missing:
            raise ValueError(f"agreement: {label} table has no column {', '.join(missing)}")
    if list(reference["design"]) != list(other["design"]):
        raise ValueError("agreement: the two tables must hold the same designs in the same order")
    rows = []
    rel = 100 * RELATIVE_TOLERANCE
    for (_, r), (_, o) in zip(reference.iterrows(), other.iterrows()):
        dh = float(o["hop_height_m"]) - float(r["hop_height_m"])
        dt = _pct(float(o["tracking_error_m"]), float(r["tracking_error_m"]))
        dp = _pct(float(o["power_w"]), float(r["power_w"]))
        run_dt = _pct(float(o.get("run_tracking_error_m", np.nan)), float(r.get("run_tracking_error_m", np.nan)))
        run_dp = _pct(float(o.get("run_power_w", np.nan)), float(r.get("run_power_w", np.nan)))
        if bool(r["stable"]) and bool(o["stable"]):
            hops_ok = abs(int(o["n_hops"]) - int(r["n_hops"])) <= HOPS_TOLERANCE
            if int(r["n_hops"]) > 0 and int(o["n_hops"]) > 0:
                agrees = hops_ok and abs(dh) <= HEIGHT_TOLERANCE_M and abs(dt) <= rel and abs(dp) <= rel
            else:  # nothing scored: the whole-run means
                agrees = hops_ok and abs(run_dt) <= rel and abs(run_dp) <= rel
        elif bool(r["stable"]) == bool(o["stable"]):  # both diverged: when?
            agrees = abs(float(o["diverged_at_s"]) - float(r["diverged_at_s"])) <= DIVERGENCE_TOLERANCE_S
        else:
            agrees = False
        rows.append(
            {
                "design": r["design"],
                "behaviour": r.get("behaviour", np.nan),
                "stable_ref": bool(r["stable"]),
                "stable": bool(o["stable"]),
                "n_hops_ref": int(r["n_hops"]),
                "n_hops": int(o["n_hops"]),
                "hop_height_diff_m": dh,
                "tracking_error_diff_pct": dt,
                "power_diff_pct": dp,
                "run_tracking_error_diff_pct": run_dt,
                "run_power_diff_pct": run_dp,
                "agrees": bool(agrees),
            }
        )
    return pd.DataFrame(rows, columns=list(AGREEMENT_COLUMNS))
