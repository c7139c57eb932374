"""Throughput of the warp batch: designs x simulated seconds per wall second.

For each batch size, a WarpBatch of that many random sprung 3-segment
designs (densities and moduli log-uniform over the stability map's ranges,
reference.STABILITY_*_RANGE) hops forward at --timestep; after a warm-up
(kernel compilation, CUDA graph capture) --steps physics steps are timed.
Designs that diverge are parked and keep costing a world, as in real use.
One CPU rollout (mat_hopper.core.sim, one core) of the reference SS design is
timed alongside for comparison.

    python benchmarks/batch.py                       # every size, on cuda if Warp sees a GPU
    python benchmarks/batch.py --device cpu --max-size 64 --steps 100   # a CPU machine
    python benchmarks/batch.py --map 20              # also: the 400-design stable-step scan, both backends

``--map N`` times the reference stable-time-step scan of the map's N x N
designs (batch.spec_scan_batch: one warp batch per rung of the 20-step
ladder, static hopping for --map-duration s per try) on the device, beside
the same scan as CPU rollouts on all cores, in one run, and prints the
ratio and how many designs got the same stable step.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from mat_hopper.batch import BatchSettings, WarpBatch, require_warp
from mat_hopper.core import reference as ref
from mat_hopper.core.materials import LegDesign
from mat_hopper.core.sim import SimSettings, simulate

SIZES = (1, 4, 16, 64, 256, 1024, 4096, 16384)


def random_designs(n: int, seed: int = 0) -> list[LegDesign]:
    rng = np.random.default_rng(seed)
    lo_r, hi_r = np.log(ref.STABILITY_DENSITY_RANGE)
    lo_e, hi_e = np.log(ref.STABILITY_MODULUS_RANGE)
    dens = np.exp(rng.uniform(lo_r, hi_r, (n, ref.REFERENCE_SEGMENTS)))
    mods = np.exp(rng.uniform(lo_e, hi_e, (n, ref.REFERENCE_SEGMENTS)))
    return [LegDesign.from_properties(d, m) for d, m in zip(dens, mods)]


def cpu_rate(timestep: float, seconds: float) -> float:
    """designs x simulated s per wall s of one CPU rollout (one core)."""
    s = SimSettings(duration_s=seconds, timestep_s=timestep, transient_s=0.0)
    simulate("SS", "forward", settings=SimSettings(duration_s=0.01, timestep_s=timestep, transient_s=0.0))  # compile
    t = time.perf_counter()
    simulate("SS", "forward", settings=s)
    return seconds / (time.perf_counter() - t)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--device", default=None, help="Warp device (default: cuda if Warp sees a GPU, else cpu)")
    p.add_argument("--sizes", default=",".join(map(str, SIZES)), help="batch sizes, comma-separated")
    p.add_argument("--max-size", type=int, default=None, help="skip sizes above this (e.g. 64 on a CPU machine)")
    p.add_argument("--steps", type=int, default=1000, help="timed physics steps per size")
    p.add_argument("--timestep", type=float, default=ref.TIMESTEP_S, help="s (1e-4)")
    p.add_argument("--no-cpu", action="store_true", help="skip the CPU rollout for comparison")
    p.add_argument("--map", type=int, default=0, help="also time the N x N stable-step scan (0: no)")
    p.add_argument(
        "--map-duration", type=float, default=ref.STABILITY_TEST_DURATION_S, help="s of static hopping per try"
    )
    a = p.parse_args(argv)
    wp, _ = require_warp()
    device = a.device or ("cuda" if wp.get_cuda_device_count() > 0 else "cpu")
    sizes = [int(s) for s in a.sizes.split(",") if s.strip()]
    if a.max_size is not None:
        sizes = [s for s in sizes if s <= a.max_size]
    warm = WarpBatch.graph_steps + 1 if device.startswith("cuda") else 2
    settings = BatchSettings(duration_s=(warm + a.steps + 1) * a.timestep, timestep_s=a.timestep, transient_s=0.0)
    print(f"device {wp.get_device(device)} ({device}), dt = {a.timestep:g} s, {a.steps} timed steps per size")
    if not a.no_cpu:
        r = cpu_rate(a.timestep, min(2.0, 2000 * a.timestep))
        print(f"CPU reference (mat_hopper.core.sim, one core): {r:.3g} designs x sim s / wall s")
    print(
        f"{'designs':>8} {'setup s':>8} {'warm-up s':>9} {'ms/step':>8} {'designs x sim s / wall s':>25} "
        f"{'diverged':>9}"
    )
    for n in sizes:
        t0 = time.perf_counter()
        b = WarpBatch(random_designs(n), "forward", settings, device=device)
        t1 = time.perf_counter()
        b.advance(warm)
        t2 = time.perf_counter()
        b.advance(a.steps)
        t3 = time.perf_counter()
        wall = t3 - t2
        rate = n * a.steps * a.timestep / wall
        div = float((b.diverged_steps() >= 0).mean())
        print(
            f"{n:>8} {t1 - t0:>8.2f} {t2 - t1:>9.2f} {1e3 * wall / a.steps:>8.3f} {rate:>25.4g} {div:>9.0%}", flush=True
        )
    if a.map:
        time_map(a.map, a.map_duration, device)


def time_map(n: int, duration_s: float, device: str) -> None:
    """The stable-step scan of the map's n x n designs on both backends, side by side."""
    from dataclasses import replace

    from mat_hopper.batch import spec_scan_batch
    from mat_hopper.experiments.paper import StabilityMap
    from mat_hopper.experiments.profiles import PROFILES

    designs = [t.design for t in StabilityMap().tasks(replace(PROFILES["paper"], stability_grid_size=n))]
    t0 = time.perf_counter()
    warp, tries = spec_scan_batch(designs, duration_s=duration_s, backend="warp", device=device)
    t1 = time.perf_counter()
    cpu, _ = spec_scan_batch(designs, duration_s=duration_s, backend="mujoco")
    t2 = time.perf_counter()
    same = (
        (warp["spec_timestep_s"] == cpu["spec_timestep_s"])
        | (warp["spec_timestep_s"].isna() & cpu["spec_timestep_s"].isna())
    ).sum()
    print(
        f"map {n}x{n} ({len(designs)} designs, {len(tries)} tries, {duration_s:g} s each): warp on {device} "
        f"{t1 - t0:.1f} s, CPU rollouts {t2 - t1:.1f} s, ratio={(t1 - t0) / (t2 - t1):.3g}; "
        f"same stable step for {same}/{len(designs)} designs"
    )


if __name__ == "__main__":
    main()
