"""Why a bending leg does not converge to its rigid twin as it stiffens:
touchdown chatter against the hinges' damping ratio.

A leg's modulus scaled up (x1, x10, x100, capped at the catalogue's
2000 GPa) under ``bending`` with the stiff contact, forward hopping with
``--timestep auto``, beside its rigid twin at the same physics step and
control period (as ``bending_convergence.py``). Each leg runs with its
hinges' damping as built (``authors``: 1 N m s/rad, a damping ratio that
falls as 1 / sqrt(stiffness)) and, as a what-if on the compiled MuJoCo
model, with each bending hinge given the damping ratio ``zeta`` on its own
diagonal inertia: ``dof_damping = 2 zeta sqrt(k dof_M0)``
(:func:`mat_hopper.core.damping.spring_damping` with eta = 2 zeta).
``--hinge-factor`` multiplies every hinge's stiffness on the compiled model
as well (the limit beyond the modulus range; give ``--substeps`` and
``--timestep`` for it, since ``auto`` knows only the capped modulus).

``--trace`` instead follows the first lift-off after ``TRACE_FROM_S``
(1 s) physics step by physics step, bending leg and rigid twin: for
the steps after the controller's flight switch during which the foot is
still geometrically in contact (its soft penetration of a few um), the
normal and tangential unconstrained accelerations of the contact point
(``J qacc_smooth`` in the contact frame; the friction coefficient is 1)
and the largest contact force. The tangential one rings on a bending leg
(the step in hip torque at the switch excites the hinges' modes), and
where it exceeds the normal separating acceleration the friction-coupled
soft contact pushes again: a touch toggle.

Columns: ``touch_toggles_per_switch`` (1.0 is a clean touchdown and
lift-off), mean tracking error and hip power, and their percent
differences from the rigid twin.

    python benchmarks/bending_chatter.py [--materials Al] [--scales 1,10,100]
        [--zetas authors,0.05,0.2,1] [--seconds 4] [--hinge-factor 1]
        [--substeps K --timestep DT] [--csv out.csv] [--trace]
"""

from __future__ import annotations

import argparse
import time

import mujoco
import numpy as np
import pandas as pd

from mat_hopper.core.control_legs import rigid_twin
from mat_hopper.core.damping import spring_damping
from mat_hopper.core.materials import CATALOGUE, LegDesign
from mat_hopper.core.mjcf import BEND_SPRINGS
from mat_hopper.core.ranges import MODULUS_RANGE_GPA
from mat_hopper.core.sim import RolloutRunner, sim_settings
from mat_hopper.core.timestep import auto_timestep
from mat_hopper.physics.metrics import run_summary

METRICS = ("mean_tracking_error_m", "mean_power_w")
TRACE_FROM_S = 1.0  # s, the gait settled: the trace takes the first lift-off after it
TRACE_WINDOW_S = 2e-4  # s after the flight switch


def _hinges(model) -> list[int]:
    """Joint ids of the bending hinges of a compiled hopper."""
    prefixes = tuple(name.split("{")[0] for name in BEND_SPRINGS)
    return [j for j in range(model.njnt) if model.joint(j).name.startswith(prefixes)]


def _runner(design, seconds: float, substeps: int, dt: float, zeta, hinge_factor: float) -> RolloutRunner:
    """A forward rollout, its hinges changed on the compiled model; zeta
    None keeps the hinges' damping as built."""
    st = sim_settings(
        design,
        duration_s=seconds,
        transient_s=seconds / 3.0,
        timestep_s=dt,
        substeps=substeps,
        convention="bending",
        contact="stiff",
    )
    runner = RolloutRunner(design, "forward", st)
    m = runner.hopper.model
    for j in _hinges(m):
        m.jnt_stiffness[j] *= hinge_factor
        if zeta is not None:
            dof = int(m.jnt_dofadr[j])
            m.dof_damping[dof] = spring_damping(2.0 * zeta, float(m.jnt_stiffness[j]), float(m.dof_M0[dof]))
    return runner


def _run(design, seconds: float, substeps: int, dt: float, zeta, hinge_factor: float) -> dict:
    """One forward run: its metrics and touch toggles per phase switch."""
    runner = _runner(design, seconds, substeps, dt, zeta, hinge_factor)
    t0 = time.perf_counter()
    r = runner.advance().result()
    s = run_summary(r)
    out = {k: s[k] for k in METRICS}
    out.update(stable=r.stable, wall_s=round(time.perf_counter() - t0, 1))
    out["touch_toggles_per_switch"] = s["mean_touch_toggles_per_switch"]
    return out


def chatter_rows(material: str, scales, zetas, seconds: float, hinge_factor: float = 1.0, step=None) -> list[dict]:
    """One row per (modulus scale, hinge damping): the bending leg, its
    rigid twin at the same step and control period, and their percent
    differences. step: (substeps, timestep_s), or None for ``auto``."""
    mat = CATALOGUE[material.lower()]
    rows = []
    for scale in scales:
        modulus = min(mat.modulus_gpa * scale, MODULUS_RANGE_GPA[1])
        leg = LegDesign.from_properties([mat.density_g_cm3] * 3, [modulus] * 3)
        substeps, dt = step or auto_timestep(leg, "bending", contact="stiff")
        rigid = _run(rigid_twin(leg), seconds, substeps, dt, None, 1.0)
        for zeta in zetas:
            bend = _run(leg, seconds, substeps, dt, zeta, hinge_factor)
            row = {"material": mat.name, "scale": scale, "modulus_gpa": modulus, "hinge_factor": hinge_factor}
            row.update(hinge_zeta="authors" if zeta is None else zeta, substeps=substeps, timestep_s=dt)
            row.update(bend)
            row.update({f"rigid_{k}": v for k, v in rigid.items()})
            for m in METRICS:
                row[f"{m}_vs_rigid_pct"] = 100.0 * (bend[m] / rigid[m] - 1.0)
            rows.append(row)
            print({k: (round(v, 5) if isinstance(v, float) else v) for k, v in row.items()}, flush=True)
    return rows


def liftoff_trace(design, substeps: int, dt: float, hinge_factor: float = 1.0) -> dict:
    """The first lift-off after TRACE_FROM_S, step by step (module doc):
    over the steps after the flight switch (thrust control to 0) while a
    contact exists, the extremes of the contact point's normal and
    tangential unconstrained accelerations (m/s^2), the largest contact
    force (N) and the number of steps with a contact force."""
    runner = _runner(design, TRACE_FROM_S + 1.0, substeps, dt, None, hinge_factor)
    m, d, act = runner.hopper.model, runner.data, runner.hopper.layout.act_thrust
    runner.advance(int(round(TRACE_FROM_S / dt)))
    jac = np.zeros((3, m.nv))
    a_n, a_t, force, t_switch = [], [], [], None
    while not runner.done and (t_switch is None or d.time <= t_switch + TRACE_WINDOW_S):
        before = d.ctrl[act]
        runner.advance(1)
        if t_switch is None and before > 0.0 and d.ctrl[act] == 0.0:
            t_switch = d.time
        if t_switch is None or d.ncon == 0:
            continue
        c = d.contact[0]
        body = max(m.geom_bodyid[c.geom1], m.geom_bodyid[c.geom2])  # the foot's (the ground's is 0)
        mujoco.mj_jac(m, d, jac, None, c.pos, body)
        acc = jac @ d.qacc_smooth
        a_n.append(float(c.frame[:3] @ acc))
        a_t.append(float(np.hypot(c.frame[3:6] @ acc, c.frame[6:9] @ acc)))
        rows = d.efc_type >= int(mujoco.mjtConstraint.mjCNSTR_CONTACT_FRICTIONLESS)
        force.append(float(d.efc_force[rows].sum()))
    if not a_n:
        return {"flight_switch_s": t_switch, "steps_in_contact": 0}
    return {
        "flight_switch_s": t_switch,
        "steps_in_contact": len(a_n),
        "normal_acc_min": min(a_n),
        "normal_acc_max": max(a_n),
        "tangential_acc_max": max(a_t),
        "contact_force_max_n": max(force),
        "steps_with_force": int(np.sum(np.array(force) > 0.0)),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--materials", default="Al")
    ap.add_argument("--scales", default="1,10,100")
    ap.add_argument("--zetas", default="authors,0.05,0.2,1")
    ap.add_argument("--seconds", type=float, default=4.0)
    ap.add_argument("--hinge-factor", type=float, default=1.0)
    ap.add_argument("--substeps", type=int)
    ap.add_argument("--timestep", type=float)
    ap.add_argument("--csv")
    ap.add_argument("--trace", action="store_true")
    args = ap.parse_args()
    if (args.substeps is None) != (args.timestep is None):
        ap.error("give --substeps and --timestep together")
    step = None if args.substeps is None else (args.substeps, args.timestep)
    scales = [float(s) for s in args.scales.split(",")]
    if args.trace:
        _print_traces(args.materials.split(","), scales, args.hinge_factor, step)
        return
    zetas = [None if z.strip() == "authors" else float(z) for z in args.zetas.split(",")]
    rows = [
        r
        for m in args.materials.split(",")
        for r in chatter_rows(m.strip(), scales, zetas, args.seconds, args.hinge_factor, step)
    ]
    table = pd.DataFrame(rows)
    cols = ["material", "scale", "hinge_factor", "hinge_zeta", "stable", "touch_toggles_per_switch"]
    cols += ["rigid_touch_toggles_per_switch"] + [c for c in table.columns if c.endswith("_vs_rigid_pct")]
    print(table[cols].to_string(index=False))
    if args.csv:
        table.to_csv(args.csv, index=False)


def _print_traces(materials, scales, hinge_factor: float, step) -> None:
    for name in materials:
        mat = CATALOGUE[name.strip().lower()]
        for scale in scales:
            modulus = min(mat.modulus_gpa * scale, MODULUS_RANGE_GPA[1])
            leg = LegDesign.from_properties([mat.density_g_cm3] * 3, [modulus] * 3)
            substeps, dt = step or auto_timestep(leg, "bending", contact="stiff")
            for kind, design, factor in (("bending", leg, hinge_factor), ("rigid", rigid_twin(leg), 1.0)):
                out = liftoff_trace(design, substeps, dt, factor)
                print(mat.name, scale, f"hinge x{factor:g}", kind, {k: round(v, 5) for k, v in out.items()}, flush=True)


if __name__ == "__main__":
    main()
