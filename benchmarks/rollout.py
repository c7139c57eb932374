"""Cost per physics step: bare ``mj_step`` against our closed-loop rollout.

Both run in this one process, on the same model (stainless steel, forward
hopping, 1e-4 s) and the same trajectory. The closed loop runs first in
chunks of --chunk steps, keeping MuJoCo's full state at each chunk's start
and every control it applied. The bare loop then replays each chunk open
loop from its saved state, calling ``mj_step`` from compiled code (no
Python per step), so it walks the closed loop's own trajectory. Runs
alternate, best of --repeats each. The last line is the ratio.

Rollouts compile the hopper with the five sensors the controller reads
(model.CONTROL_SENSORS); the same bare replay on the spec's seven-sensor
model shows what dropping the two unread ones saves.

    python benchmarks/rollout.py [--seconds 10] [--repeats 3]
"""

from __future__ import annotations

import argparse
import time

import mujoco
import numba
import numpy as np

from mat_hopper.core._loop import MJ_STEP
from mat_hopper.core.model import build_model
from mat_hopper.core.sim import RolloutRunner, SimSettings, simulate

SPEC = mujoco.mjtState.mjSTATE_INTEGRATION


@numba.njit(cache=True)
def bare_loop(step, m_ptr, d_ptr, ctrl, controls):
    for i in range(controls.shape[0]):
        for k in range(controls.shape[1]):
            ctrl[k] = controls[i, k]
        step(m_ptr, d_ptr)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seconds", type=float, default=10.0, help="simulated seconds per run")
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--chunk", type=int, default=1000, help="steps replayed from one saved state")
    p.add_argument("--design", default="SS")
    p.add_argument("--behaviour", default="forward")
    a = p.parse_args(argv)
    dt = 1e-4
    settings = SimSettings(duration_s=a.seconds, timestep_s=dt, transient_s=0.0)

    # The closed loop's trajectory: states at chunk starts, controls at every step.
    logged = RolloutRunner(
        a.design,
        a.behaviour,
        SimSettings(duration_s=a.seconds, timestep_s=dt, transient_s=0.0, record_rate_hz=1.0 / dt),
    )
    m = logged.hopper.model
    size = mujoco.mj_stateSize(m, SPEC)
    starts = []
    while not logged.done:
        s = np.empty(size)
        mujoco.mj_getState(m, logged.data, s, SPEC)
        starts.append(s)
        logged.advance(a.chunk)
    controls = np.ascontiguousarray(logged.result().ctrl)  # actuator space, what d.ctrl takes
    n = len(controls)
    h = logged.hopper
    m_all = build_model(
        h.design, ramp_grade_deg=h.ramp_grade_deg, timestep_s=dt, convention=h.convention, sensors="all"
    ).model
    assert mujoco.mj_stateSize(m_all, SPEC) == size

    def run_bare(model=m):
        d = mujoco.MjData(model)
        t0 = time.perf_counter()
        for c, s in enumerate(starts):
            mujoco.mj_setState(model, d, s, SPEC)
            bare_loop(MJ_STEP, model._address, d._address, d.ctrl, controls[c * a.chunk : (c + 1) * a.chunk])
        return time.perf_counter() - t0

    def run_ours():
        t0 = time.perf_counter()
        simulate(a.design, a.behaviour, settings=settings)
        return time.perf_counter() - t0

    run_bare()  # compile and warm up
    run_ours()
    bare, ours, spec7 = [], [], []
    for _ in range(a.repeats):
        bare.append(run_bare())
        ours.append(run_ours())
        spec7.append(run_bare(m_all))
    b_us, o_us, s_us = min(bare) / n * 1e6, min(ours) / n * 1e6, min(spec7) / n * 1e6
    print(f"design={a.design} behaviour={a.behaviour} steps={n} timestep_s={dt:g}s chunk={a.chunk}")
    print(f"bare mj_step:        {b_us:.2f} us/step (best of {a.repeats})")
    print(f"closed-loop rollout: {o_us:.2f} us/step (best of {a.repeats}, model build and recording included)")
    print(f"bare mj_step, all 7 spec sensors: {s_us:.2f} us/step (rollout / this: {o_us / s_us:.2f})")
    print(f"ratio={o_us / b_us:.2f}")


if __name__ == "__main__":
    main()
