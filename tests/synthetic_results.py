"""Small synthetic result tables in the runner's formats, with known answers.

Per-hop values are drawn around set means (a few % noise), so percent
changes, significance and verdicts are known by construction.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from mat_hopper.core import reference as ref

BEHAVIOURS = ("static", "forward", "ramp", "circle")

# mean tracking error (m) and power (W) per design and behaviour
TRACKING = {
    "MD": 0.10,
    "PVC": 0.05,
    "Al": 0.03,
    "Ti": 0.025,
    "SS": 0.028,
    "rho-inc": 0.018,
    "rho-dec": 0.04,
    "PVC-Ti-SS": 0.035,
    "SS-Ti-PVC": 0.03,
}
POWER = {
    "MD": 1.0,
    "PVC": 1.5,
    "Al": 2.0,
    "Ti": 2.2,
    "SS": 2.93,
    "rho-inc": 2.23,
    "rho-dec": 2.5,
    "PVC-Ti-SS": 2.4,
    "SS-Ti-PVC": 2.6,
}


def _hops(design, behaviour, tracking, power, n, rng, **labels):
    return pd.DataFrame(
        {
            "design": design,
            "behaviour": behaviour,
            "convention": labels.pop("convention", "paper"),
            "hop": np.arange(n),
            "t_start_s": 20 + 0.7 * np.arange(n),
            "t_end_s": 20.7 + 0.7 * np.arange(n),
            "hop_height_m": 1.0 + rng.normal(0, 0.005, n),
            "tracking_error_m": tracking * (1 + rng.normal(0, 0.03, n)),
            "jerk_m_s3": 500 * power * (1 + rng.normal(0, 0.05, n)),
            "power_w": power * (1 + rng.normal(0, 0.03, n)),
            "power_paper_w": 3 * power * (1 + rng.normal(0, 0.03, n)),
            "energy_j": 20 * power * (1 + rng.normal(0, 0.03, n)),
            **labels,
        }
    )


def sweep_tracking(base, density, modulus):
    """Density matters (strongly), modulus little, E <= 9 GPa tracks worse."""
    t = 0.04 * (density / 4.0) ** -0.8
    return t * (1.3 if modulus <= 9 else 1.0) * (1 + 0.02 * np.log10(modulus))


def results(*, convention="paper", seed=0, n=30, replicates=0, tracking=None, power=None):
    """(hops, runs) for experiments 1-3 of one convention."""
    rng = np.random.default_rng(seed)
    tracking = {**TRACKING, **(tracking or {})}
    power = {**POWER, **(power or {})}
    frames = []
    reps = [-1, *range(replicates)]
    for exp, designs in (
        ("exp1", ("MD", "PVC", "Al", "Ti", "SS")),
        ("exp3", ("rho-inc", "rho-dec", "PVC-Ti-SS", "SS-Ti-PVC", "MD", "SS")),
    ):
        for d in designs:
            for b in BEHAVIOURS:
                for r in reps:
                    scale = 1.0 if r < 0 else 1 + rng.normal(0, 0.02)
                    frames.append(
                        _hops(
                            d,
                            b,
                            tracking[d] * scale,
                            power[d] * scale,
                            n,
                            rng,
                            experiment=exp,
                            profile="quick",
                            convention=convention,
                            replicate=r,
                        )
                    )
    for base, sweeps in ref.SWEEPS.items():
        rho0, e0 = ref.MONO_MATERIALS[base]
        for prop, values in sweeps.items():
            for v in values:
                rho, e = (v, e0) if prop == "density" else (rho0, v)
                name = base if (rho, e) == (rho0, e0) else f"{base} {prop}={v:g}"
                frames.append(
                    _hops(
                        name,
                        "forward",
                        sweep_tracking(base, rho, e),
                        2.0,
                        n,
                        rng,
                        experiment="exp2",
                        profile="quick",
                        convention=convention,
                        replicate=-1,
                        sweep_base=base,
                        sweep_property=prop,
                        density_g_cm3=float(rho),
                        modulus_gpa=float(e),
                    )
                )
    hops = pd.concat(frames, ignore_index=True)
    keys = [
        c
        for c in (
            "experiment",
            "profile",
            "convention",
            "design",
            "behaviour",
            "replicate",
            "sweep_property",
            "density_g_cm3",
            "modulus_gpa",
        )
        if c in hops.columns
    ]
    runs = hops.groupby(keys, dropna=False, sort=False).size().reset_index(name="n_hops")
    runs["stable"], runs["upright"], runs["status"], runs["diverged_at_s"] = True, True, "ok", np.nan
    return hops, runs


def stability_table(size=4, convention="paper"):
    """log10 dt = -2.519 + 0.959 log10 rho - 1.027 log10 E: PVC 1e-3 s, Al
    and SS 1e-4 s, like the paper."""
    rho = np.round(np.geomspace(*ref.STABILITY_DENSITY_RANGE, size), 1)
    mod = np.round(np.geomspace(*ref.STABILITY_MODULUS_RANGE, size), 1)
    rows = []
    for d in rho:
        for e in mod:
            dt = 10 ** (-2.519 + 0.959 * np.log10(d) - 1.027 * np.log10(e))
            rows.append(
                {
                    "density_g_cm3": d,
                    "modulus_gpa": e,
                    "max_stable_timestep_s": dt,
                    "analytic_timestep_s": dt * 1.7,
                    "omega_max_rad_s": 2 / (dt * 1.7),
                    "convention": convention,
                    "profile": "quick",
                }
            )
    return pd.DataFrame(rows)
