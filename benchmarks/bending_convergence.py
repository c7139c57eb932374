"""Bending that converges to the rigid leg: a leg's modulus scaled up
(x1, x10, x100, capped at the catalogue's 2000 GPa) under ``bending`` with
the stiff contact, forward hopping with ``--timestep auto``, beside its
rigid twin run at the same physics step and control period. As the hinges
stiffen, tracking error and hip power should move towards the rigid
twin's; a leg that falls or diverges is named.

The stiff legs need the automatic control period's flight-loop rule
(:mod:`mat_hopper.core.flight_loop`): at the authors' 1e-4 s a bending
mode near the 10 kHz control rate aliases into the hips' flight PD and the
run diverges in its first 20 ms (PVC x100, 400 GPa).

    python benchmarks/bending_convergence.py [--materials PVC,Al] [--scales 1,10,100]
        [--seconds 30] [--damping authors|loss-factor] [--contact stiff|stiff-elliptic] [--csv out.csv]
"""

from __future__ import annotations

import argparse
import time

import pandas as pd

from mat_hopper.core.control_legs import rigid_twin
from mat_hopper.core.damping import DAMPINGS
from mat_hopper.core.materials import CATALOGUE, LegDesign
from mat_hopper.core.ranges import MODULUS_RANGE_GPA
from mat_hopper.core.sim import simulate
from mat_hopper.core.timestep import auto_timestep
from mat_hopper.physics.metrics import run_summary

METRICS = ("mean_tracking_error_m", "mean_power_w", "mean_power_total_w")


def _run(design, seconds, substeps, dt, damping, contact="stiff"):
    t0 = time.perf_counter()
    r = simulate(
        design,
        "forward",
        duration_s=seconds,
        transient_s=seconds / 3.0,
        timestep_s=dt,
        substeps=substeps,
        convention="bending",
        contact=contact,
        damping=damping,
        warn=False,
    )
    s = run_summary(r)
    out = {m: s[m] for m in METRICS}
    out.update(stable=r.stable, fell_at_s=r.fell_at_s, wall_s=round(time.perf_counter() - t0, 1))
    out["touch_toggles_per_switch"] = s["mean_touch_toggles_per_switch"]
    return out


def convergence_rows(
    material: str, scales, seconds: float, damping: str = "authors", contact: str = "stiff"
) -> list[dict]:
    """One row per modulus scale: the bending leg and its rigid twin at
    the bending leg's automatic step and control period, and their
    percent differences."""
    mat = CATALOGUE[material.lower()]
    rows = []
    for scale in scales:
        modulus = min(mat.modulus_gpa * scale, MODULUS_RANGE_GPA[1])
        leg = LegDesign.from_properties([mat.density_g_cm3] * 3, [modulus] * 3)
        substeps, dt = auto_timestep(leg, "bending", contact=contact)
        bend = _run(leg, seconds, substeps, dt, damping, contact)
        rigid = _run(rigid_twin(leg), seconds, substeps, dt, damping, contact)
        row = {"material": mat.name, "scale": scale, "modulus_gpa": modulus, "damping": damping, "contact": contact}
        row["substeps"] = substeps
        row.update(timestep_s=dt, control_period_s=substeps * dt)
        row.update({f"{k}": v for k, v in bend.items()})
        row.update({f"rigid_{k}": v for k, v in rigid.items()})
        for m in METRICS[:2]:
            row[f"{m}_vs_rigid_pct"] = 100.0 * (bend[m] / rigid[m] - 1.0)
        rows.append(row)
        print({k: (round(v, 5) if isinstance(v, float) else v) for k, v in row.items()}, flush=True)
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--materials", default="PVC,Al")
    ap.add_argument("--scales", default="1,10,100")
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--damping", default="authors", choices=DAMPINGS)
    ap.add_argument("--contact", default="stiff", choices=("stiff", "stiff-elliptic"), help="the foot's contact")
    ap.add_argument("--csv")
    args = ap.parse_args()
    scales = [float(s) for s in args.scales.split(",")]
    rows = [
        r
        for m in args.materials.split(",")
        for r in convergence_rows(m.strip(), scales, args.seconds, args.damping, args.contact)
    ]
    table = pd.DataFrame(rows)
    cols = ["material", "scale", "modulus_gpa", "control_period_s", "stable", "fell_at_s", "touch_toggles_per_switch"]
    cols += [c for c in table.columns if c.endswith("_vs_rigid_pct")]
    print(table[cols].to_string(index=False))
    if args.csv:
        table.to_csv(args.csv, index=False)


if __name__ == "__main__":
    main()
