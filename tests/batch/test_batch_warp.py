"""The warp batch on Warp's CPU device: per-world model fields, refusals,
and a short trajectory against MuJoCo's own CPU engine."""

from dataclasses import replace

import numpy as np
import pandas as pd
import pytest

pytest.importorskip("mujoco_warp")

from _authors_loop import authors_rollout  # noqa: E402

from mat_hopper.batch import BatchSettings, WarpBatch, as_design, evaluate  # noqa: E402
from mat_hopper.batch._warp import DERIVED_FIELDS, DESIGN_FIELDS  # noqa: E402
from mat_hopper.core.materials import LegDesign, parse_design  # noqa: E402
from mat_hopper.core.model import build_model  # noqa: E402
from mat_hopper.core.sim import simulate  # noqa: E402

SHORT = BatchSettings(duration_s=0.45, timestep_s=2e-4, transient_s=0.1)


def _qpos_trace(b: WarpBatch, n: int) -> np.ndarray:
    """(n, nworld, nq): every world's joint positions after each of n steps."""
    trace = np.zeros((n, b.nworld, b.mjm.nq))
    for i in range(n):
        b.advance(1)
        trace[i] = b.d.qpos.numpy()
    return trace


@pytest.fixture(scope="module")
def sprung_batch():
    # Four sprung designs, one topology: different densities per segment, moduli, a gradient.
    designs = ["PVC", "rho-inc", "PVC-Ti-SS", LegDesign.from_properties([1.1, 2.5, 1.9], [0.45, 4.0, 9.0])]
    return WarpBatch(designs, "forward", SHORT, device="cpu")


def test_per_world_fields_are_mujocos_compile(sprung_batch):
    """Masses, inertias, centres of mass and stiffnesses per world, and the
    constants set_const derives from them, equal MuJoCo's CPU compile of each
    design on its own."""
    b = sprung_batch
    for w, design in enumerate(b.designs):
        hm = build_model(design, timestep_s=SHORT.timestep_s, sensors="control")
        for f in DESIGN_FIELDS + DERIVED_FIELDS:
            got = getattr(b.m, f).numpy()
            assert got.shape[0] == b.nworld, f
            want = np.asarray(getattr(hm.model, f), dtype=np.float64)
            np.testing.assert_allclose(
                got[w].reshape(want.shape), want, rtol=2e-6, atol=1e-9, err_msg=f"{f} of {design.name}"
            )
        k = b.m.jnt_stiffness.numpy()[w]
        springs = [k[hm.model.joint(f"mat_spring_{i}").id] for i in range(1, design.n_segments + 1)]
        np.testing.assert_allclose(springs, hm.spring_stiffness_n_m, rtol=1e-6)
        assert b.total_mass_kg[w] == pytest.approx(hm.total_mass_kg)
    # the worlds really differ (so equality above is per world, not one shared value):
    # rho-inc and PVC-Ti-SS share their densities, not their stiffnesses
    props = np.concatenate([b.m.body_mass.numpy(), b.m.jnt_stiffness.numpy()], axis=1)
    assert len({tuple(np.round(r, 3)) for r in props}) == b.nworld
    assert len({tuple(np.round(r, 6)) for r in b.m.body_mass.numpy()}) == b.nworld - 1


@pytest.mark.parametrize("segment_mass", ["leg", "capsule"])
def test_segment_mass_convention_reaches_the_worlds(segment_mass):
    """Two-segment legs (where the conventions differ): per-world masses are
    MuJoCo's compile under the chosen convention."""
    s = BatchSettings(duration_s=0.45, timestep_s=2e-4, transient_s=0.1, segment_mass=segment_mass)
    designs = [LegDesign.from_properties([1.39, 8.0], [4.0, 193.0]), LegDesign.from_properties([2.7], [70.0] * 2)]
    b = WarpBatch(designs, "forward", s, device="cpu")
    for w, d in enumerate(designs):
        want = build_model(d, timestep_s=s.timestep_s, sensors="control", segment_mass=segment_mass).model.body_mass
        np.testing.assert_allclose(b.m.body_mass.numpy()[w], want, rtol=1e-6)
    other = "capsule" if segment_mass == "leg" else "leg"
    assert not np.allclose(b.m.body_mass.numpy()[0], build_model(designs[0], segment_mass=other).model.body_mass)


def test_the_device_model_resets_nothing_itself(sprung_batch):
    import mujoco

    assert sprung_batch.hopper.model.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_AUTORESET  # host: as built
    assert not sprung_batch.mjm.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_AUTORESET  # device copy


@pytest.mark.parametrize(
    "latency, timestep_s",
    # fresh readings (L = 0) are stable at 2e-4 s; L = 2 needs 1e-4 s (its
    # stance-damping limit, mat_hopper.physics.stability, is 1.3e-4 s)
    [(0, 2e-4), (2, 1e-4)],
)
def test_other_sensor_latencies_follow_the_cpu_path(latency, timestep_s):
    """0.45 s (falling, touchdown, stance) under sensor latencies other than
    the authors': every world's joint positions follow the CPU rollout of
    the same latency (mat_hopper.core.sim, MuJoCo's CPU engine in float64, itself
    tested against plain mj_step1/mj_step2 and mj_step loops) step by step."""
    s = BatchSettings(duration_s=0.45, timestep_s=timestep_s, transient_s=0.1, sensor_timing=latency)
    designs = ["PVC", LegDesign.from_properties([1.1, 2.5, 1.9], [0.45, 4.0, 9.0])]  # stable at 2e-4 s
    b = WarpBatch(designs, "forward", s, device="cpu")
    n = s.n_steps
    trace = _qpos_trace(b, n)
    assert (b.diverged_steps() == -1).all()
    every_step = replace(s, record_rate_hz=1.0 / timestep_s)
    errors = []
    for w, design in enumerate(designs):
        ro = simulate(design, "forward", settings=every_step, record_qpos=True)
        assert ro.stable and len(ro.touchdown_times_s) >= 1 and ro.qpos.shape[0] == n
        errors.append(np.abs(trace[:, w] - ro.qpos).max())
        assert errors[-1] < 1e-3, (design, latency, errors[-1])
    # the latency is resolved: the authors' timing (L = 1) gives a trajectory farther off
    authors = simulate(designs[0], "forward", settings=replace(every_step, sensor_timing=1), record_qpos=True)
    assert np.abs(trace[:, 0] - authors.qpos).max() > 10 * errors[0]


def test_refusals():
    with pytest.raises(ValueError, match="one topology"):
        WarpBatch(["MD", "PVC"], "forward", SHORT, device="cpu")
    with pytest.raises(ValueError, match="not available"):
        WarpBatch(["PVC"], "forward", SHORT, device="nosuchdevice")
    with pytest.raises(ValueError, match="sensor latency must be in"):
        BatchSettings(sensor_timing=-1)
    with pytest.raises(ValueError, match="integer latency"):
        BatchSettings(sensor_timing=1.0)
    with pytest.raises(ValueError, match="substeps must be 1 in a batch"):
        BatchSettings(substeps=2)


def test_trajectories_follow_mujoco_cpu_and_divergence_stays_in_its_world():
    """0.45 s (falling, touchdown at 0.34 s, stance) of a batch holding a design
    that diverges at this step (SS) and two that do not: every world's joint
    positions follow MuJoCo's CPU engine (float64, the authors' loop) step by
    step, and SS diverges within a few steps of where the CPU run does,
    leaving the others untouched."""
    designs = ["PVC", "SS", LegDesign.from_properties([2.5], [0.45] * 3)]
    b = WarpBatch(designs, "forward", SHORT, device="cpu")
    n = SHORT.n_steps
    trace = _qpos_trace(b, n)
    div = b.diverged_steps()
    for w, design in enumerate(designs):
        ro, ref = authors_rollout(design, "forward", SHORT, trace_qpos=n)
        if ro.stable:
            assert div[w] == -1
            err = np.abs(trace[:, w] - ref).max()
            assert err < 1e-3, (design, err)
            # touchdown happened within the window: stance physics was compared too
            assert len(ro.touchdown_times_s) >= 1
        else:
            assert div[w] >= 0 and abs(div[w] - ro.diverged_step) <= 5, (design, div[w], ro.diverged_step)
    assert div[1] >= 0 and (div[[0, 2]] == -1).all()


def test_rigid_legs_follow_mujoco_cpu():
    """0.45 s of a rigid batch (no springs: its own topology, the second batch
    of any mixed design list): MD and a heavier rigid leg, every world's
    joint positions within 1e-3 of MuJoCo's CPU engine (float64, the
    authors' loop) step by step, through touchdown and stance. (The summary
    agreement over 2.2 s, tests/batch/test_batch_agreement.py, holds sprung
    designs only: a rigid batch there cost about 110 s of CI.)"""
    designs = ["MD", LegDesign.from_properties([2.5], [None] * 3, name="rigid-heavy")]
    b = WarpBatch(designs, "forward", SHORT, device="cpu")
    rigid_nq, sprung_nq = (build_model(parse_design(d)).model.nq for d in ("MD", "PVC"))
    assert b.mjm.nq == rigid_nq < sprung_nq  # the rigid topology: no spring joints
    n = SHORT.n_steps
    trace = _qpos_trace(b, n)
    assert (b.diverged_steps() == -1).all()
    for w, design in enumerate(designs):
        ro, ref = authors_rollout(design, "forward", SHORT, trace_qpos=n)
        assert ro.stable and len(ro.touchdown_times_s) >= 1, design  # stance physics compared too
        err = np.abs(trace[:, w] - ref).max()
        assert err < 1e-3, (design, err)


def test_groups_and_slices_come_back_in_input_order():
    s = BatchSettings(duration_s=0.02, timestep_s=2e-4, transient_s=0.01)
    designs = ["MD", "PVC", LegDesign.from_properties([2.0], [None] * 3, name="MD-heavy"), "Nylon", "rho-inc"]
    table = evaluate(designs, "forward", s, backend="warp", device="cpu", max_batch=2)
    assert list(table["design"]) == ["MD", "PVC", "MD-heavy", "Nylon", "rho-inc"]
    masses = [build_model(as_design(d), sensors="control").total_mass_kg for d in designs]
    np.testing.assert_allclose(table["total_mass_kg"], masses, rtol=1e-9)
    assert (table["backend"] == "warp").all() and (table["sensor_timing"] == "authors").all()


def test_a_batch_run_twice_is_bit_identical():
    """Determinism on Warp's CPU device: the same designs, behaviour and
    settings give the same summaries, bit for bit (the optimizer's warp test
    compares a study's told values with the table of its own batch, not a
    second run). 0.1 s, the drop (500 steps a batch: Warp's CPU device
    costs about 10 ms a step); its kernels run on one thread."""
    s = BatchSettings(duration_s=0.1, timestep_s=2e-4, transient_s=0.05)
    designs = ["PVC", LegDesign.from_properties([1.1, 2.5, 1.9], [0.45, 4.0, 9.0])]
    first = evaluate(designs, "forward", s, backend="warp", device="cpu")
    second = evaluate(designs, "forward", s, backend="warp", device="cpu")
    pd.testing.assert_frame_equal(first, second, check_exact=True)
    assert first["run_tracking_error_m"].notna().all()  # something was compared
