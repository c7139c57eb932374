"""What topples a leg that bends: the lateral mode of issue 21, taken apart.

Under ``--convention bending`` a stiff leg hopping forward falls sideways
after 10-30 s; its base's roll grows exponentially from round-off
(chapter 8b). This script runs one design, unperturbed, under variants that
each remove one suspect, and reports for each the fitted growth rate of
|roll| (while it grows from 1e-14 to 1e-2 rad, after the first 2 s), the
largest |roll| and when the run fell:

- ``authors``: the authors' controller, ``--timestep auto``;
- ``in place``: the static behaviour (no forward motion);
- ``sagittal stiff`` / ``lateral stiff``: the hinges about y (bending in
  the plane of travel) or about x (sideways) made 100 x stiffer, at
  30 physics substeps (the stiffer hinges need them); ``30 substeps`` is
  the same leg unchanged at that step, their control;
- ``stance kp 2``, ``stance kd 2``: the stance attitude gains retuned;
- ``fresh sensing``: no sensor delay.

The stiffened hinges are a what-if on the compiled MuJoCo model
(``jnt_stiffness``), not a design the package offers.

    python benchmarks/bending_mode.py [--design SS] [--seconds 20] [--workers 2] [--csv out.csv]
"""

from __future__ import annotations

import argparse
import os
from concurrent.futures import ProcessPoolExecutor

import mujoco
import numpy as np
import pandas as pd

from mat_hopper.control import ControllerSettings
from mat_hopper.materials import parse_design
from mat_hopper.model import BEND_SPRINGS
from mat_hopper.rollout import C
from mat_hopper.sim import RolloutRunner, sim_settings

FINE_SUBSTEPS = 30  # 3.3e-6 s: the explicit bound of hinges 100 x stiffer, with margin
STIFFEN = 100.0
# label: (behaviour, settings overrides, hinge name prefix to stiffen or None)
VARIANTS = {
    "authors": ("forward", {}, None),
    "in place": ("static", {}, None),
    "30 substeps": ("forward", {"substeps": FINE_SUBSTEPS}, None),
    "sagittal stiff": ("forward", {"substeps": FINE_SUBSTEPS}, BEND_SPRINGS[1].split("{")[0]),
    "lateral stiff": ("forward", {"substeps": FINE_SUBSTEPS}, BEND_SPRINGS[0].split("{")[0]),
    "stance kp 2": ("forward", {"controller": ControllerSettings(stance_kp=2.0)}, None),
    "stance kd 2": ("forward", {"controller": ControllerSettings(stance_kd=2.0)}, None),
    "fresh sensing": ("forward", {"sensor_timing": "fresh"}, None),
}


def growth_rate(time_s: np.ndarray, roll_rad: np.ndarray) -> float:
    """e-folding rate (1/s) of |roll| while it grows from 1e-14 to 1e-2 rad after 2 s; nan if it never does."""
    tilt = np.abs(roll_rad)
    grow = (tilt > 1e-14) & (tilt < 1e-2) & (time_s > 2.0)
    return float(np.polyfit(time_s[grow], np.log(tilt[grow]), 1)[0]) if grow.sum() > 100 else float("nan")


def run_variant(args) -> dict:
    design_name, label, seconds = args
    behaviour, overrides, stiffen = VARIANTS[label]
    design = parse_design(design_name)
    overrides = dict(overrides)
    if "substeps" in overrides:
        overrides["timestep_s"] = 1e-4 / overrides["substeps"]
    else:
        overrides["timestep_s"] = "auto"
    settings = sim_settings(duration_s=seconds, transient_s=1.0, convention="bending", design=design, **overrides)
    runner = RolloutRunner(design, behaviour, settings)
    if stiffen:
        m = runner.hopper.model
        for j in range(m.njnt):
            if (mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, j) or "").startswith(stiffen):
                m.jnt_stiffness[j] *= STIFFEN
    r = runner.advance().result()
    roll = r.data[:, C["roll"]]
    return {
        "design": design_name,
        "variant": label,
        "behaviour": behaviour,
        "substeps": settings.substeps,
        "growth_rate_per_s": growth_rate(r.time, roll),
        "max_abs_roll_rad": float(np.abs(roll).max()),
        "fell_s": r.diverged_at_s,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--design", default="SS")
    ap.add_argument("--seconds", type=float, default=20.0)
    ap.add_argument("--workers", type=int, default=os.cpu_count())
    ap.add_argument("--csv")
    args = ap.parse_args()
    tasks = [(args.design, label, args.seconds) for label in VARIANTS]
    with ProcessPoolExecutor(args.workers) as ex:
        table = pd.DataFrame(list(ex.map(run_variant, tasks)))
    with pd.option_context("display.width", 160):
        print(table.to_string(index=False, float_format=lambda v: f"{v:.3g}"))
    if args.csv:
        table.to_csv(args.csv, index=False)


if __name__ == "__main__":
    main()
