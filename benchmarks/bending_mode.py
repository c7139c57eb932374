"""What topples a leg that bends: the lateral mode of issue 21, taken apart.

Under ``--convention bending`` a stiff leg hopping forward falls sideways
after 10-30 s; its base's roll grows exponentially from round-off
(chapter 8b). This script runs one design under variants that each change
one suspect, seeds the mode with a kick and measures its growth:

- the gait settles for ``KICK_S`` (3 s), then the base's roll rate gets
  ``KICK_RAD_S`` (1e-8 rad/s), far above round-off and far below anything
  the controller notices;
- the envelope of |roll| is its largest value in each half-hop window
  (0.31 s); ``growth_rate_per_s`` is the slope of log(envelope) against
  time from 1 s after the kick until the envelope first passes 1e-2 rad
  (or the run ends): positive, the mode grows; negative, it decays.
  ``decades`` is how many decades the envelope moved over that stretch,
  and ``passed_1e-2_s`` when the envelope first passed 1e-2 rad (a roll
  that large need not fall: some legs then rock at about 0.02 rad).

Variants (forward hopping unless said):

- ``authors``: the authors' controller, ``--timestep auto``, whose sensor
  delay is one physics step; ``authors, no kick`` the same without the
  kick (the mode seeded by round-off alone: the kick's control);
- ``in place``: the static behaviour;
- ``30 substeps, delay 33 us``: 3.3e-6 s physics steps with the sensor
  delay held at ``auto``'s one step of 3.3e-5 s (``latency-10``): the
  integration alone refined; ``30 substeps, delay 3.3 us`` (the authors'
  one step) and ``30 substeps, fresh`` change the delay as well;
- ``sagittal stiff`` / ``lateral stiff``: the hinges about y (bending in
  the plane of travel) or about x (sideways) 100 x stiffer, at 30 substeps
  with the 33 us delay. A what-if on the compiled MuJoCo model
  (``jnt_stiffness``; the hinges' damping is left as it is, so their
  damping ratio drops tenfold), not a design the package offers;
- ``stance kp 2``, ``stance kd 2``: two retunes of the stance attitude
  gains (the authors' 4 and 1);
- ``fresh sensing``: no sensor delay, at ``auto``.

A ``contact`` column names the foot's contact (``--contact``: ``authors``,
MuJoCo's default soft contact, or ``stiff``, a 1 ms time constant;
:mod:`mat_hopper.core.contact`): the mode's growth is the soft contact's
(chapter 8b).

    python benchmarks/bending_mode.py [--design SS] [--contact authors|stiff] [--seconds 12] [--workers 2]
        [--csv out.csv]
"""

from __future__ import annotations

import argparse
import os
from concurrent.futures import ProcessPoolExecutor

import mujoco
import pandas as pd

from mat_hopper.analysis.growth import envelope_growth
from mat_hopper.core.contact import CONTACTS
from mat_hopper.core.controller import ControllerSettings
from mat_hopper.core.materials import parse_design
from mat_hopper.core.model import BASE_JOINTS, BEND_SPRINGS
from mat_hopper.core.rollout import C
from mat_hopper.core.sim import RolloutRunner, sim_settings

FINE = {"substeps": 30, "sensor_timing": "latency-10"}  # 3.3e-6 s steps, the sensor delay of auto's 3 (33 us)
STIFFEN = 100.0
KICK_S = 3.0  # the gait has settled (hop cycles score after 1 s)
KICK_RAD_S = 1e-8  # added to the base's roll rate
WINDOW_S = 0.31  # half a hop
NO_KICK = {"authors, no kick"}
# label: (behaviour, settings overrides, hinge name prefix to stiffen or None)
VARIANTS = {
    "authors": ("forward", {}, None),
    "authors, no kick": ("forward", {}, None),
    "in place": ("static", {}, None),
    "30 substeps, delay 33 us": ("forward", FINE, None),
    "30 substeps, delay 3.3 us": ("forward", {"substeps": 30}, None),
    "30 substeps, fresh": ("forward", {"substeps": 30, "sensor_timing": "fresh"}, None),
    "sagittal stiff": ("forward", FINE, BEND_SPRINGS[1].split("{")[0]),
    "lateral stiff": ("forward", FINE, BEND_SPRINGS[0].split("{")[0]),
    "stance kp 2": ("forward", {"controller": ControllerSettings(stance_kp=2.0)}, None),
    "stance kd 2": ("forward", {"controller": ControllerSettings(stance_kd=2.0)}, None),
    "fresh sensing": ("forward", {"sensor_timing": "fresh"}, None),
}


def run_variant(args) -> dict:
    design_name, label, seconds, contact = args
    behaviour, overrides, stiffen = VARIANTS[label]
    design = parse_design(design_name)
    overrides = dict(overrides)
    overrides["timestep_s"] = 1e-4 / overrides["substeps"] if "substeps" in overrides else "auto"
    settings = sim_settings(
        duration_s=seconds, transient_s=1.0, convention="bending", contact=contact, design=design, **overrides
    )
    runner = RolloutRunner(design, behaviour, settings)
    if stiffen:
        m = runner.hopper.model
        for j in range(m.njnt):
            if (mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, j) or "").startswith(stiffen):
                m.jnt_stiffness[j] *= STIFFEN
    runner.advance(round(KICK_S / settings.timestep_s))
    if label not in NO_KICK:
        m = runner.hopper.model
        roll_dof = m.jnt_dofadr[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, BASE_JOINTS[3])]  # base_roll
        runner.data.qvel[roll_dof] += KICK_RAD_S
    r = runner.advance().result()
    fit = envelope_growth(r.time, r.data[:, C["roll"]], WINDOW_S, start_s=KICK_S + 1.0)
    rate, decades, passed = fit.rate_per_s, fit.decades, fit.passed_s
    return {
        "design": design_name,
        "variant": label,
        "contact": contact,
        "behaviour": behaviour,
        "substeps": settings.substeps,
        "sensor_delay_s": int(settings.sensor_timing) * settings.timestep_s,
        "growth_rate_per_s": rate,
        "decades": decades,
        "passed_1e-2_s": passed,
        "fell_s": r.diverged_at_s,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--design", default="SS", help="a design name or list (SS)")
    ap.add_argument("--seconds", type=float, default=12.0, help=f"run length, s, > {KICK_S + 1 + 4 * WINDOW_S:g} (12)")
    ap.add_argument("--contact", default="authors", choices=CONTACTS, help="the foot's contact (authors)")
    ap.add_argument("--workers", type=int, default=os.cpu_count(), help="processes (every core)")
    ap.add_argument("--csv", help="write the table here")
    args = ap.parse_args()
    try:
        parse_design(args.design)
    except ValueError as e:
        ap.error(f"--design: {e}")
    if not args.seconds > KICK_S + 1 + 4 * WINDOW_S:  # the kick, 1 s of settling, four windows to fit
        ap.error(f"--seconds must be > {KICK_S + 1 + 4 * WINDOW_S:g} s, got {args.seconds:g}")
    if args.workers < 1:
        ap.error(f"--workers must be >= 1, got {args.workers}")
    if args.csv and not os.path.isdir(os.path.dirname(os.path.abspath(args.csv))):  # checked before the runs
        ap.error(f"--csv: no folder {os.path.dirname(os.path.abspath(args.csv))}")
    tasks = [(args.design, label, args.seconds, args.contact) for label in VARIANTS]
    with ProcessPoolExecutor(args.workers) as ex:
        table = pd.DataFrame(list(ex.map(run_variant, tasks)))
    with pd.option_context("display.width", 160):
        print(table.to_string(index=False, float_format=lambda v: f"{v:.3g}"))
    if args.csv:
        table.to_csv(args.csv, index=False)


if __name__ == "__main__":
    main()
