"""The Warp kernels against the package's own Python: controller, paths, metrics.

Each kernel runs on Warp's CPU device on synthetic inputs that reach every
branch, and is compared with mat_hopper.core.controller (plain Python original),
mat_hopper.core.behaviours and mat_hopper.physics.metrics on the very same inputs.
"""

import numpy as np
import pytest

pytest.importorskip("mujoco_warp")

from mat_hopper.batch import BatchSettings, require_warp  # noqa: E402
from mat_hopper.core import controller as ctl  # noqa: E402
from mat_hopper.core.behaviours import Behaviour, behaviour, desired_state  # noqa: E402
from mat_hopper.core.materials import parse_design  # noqa: E402
from mat_hopper.core.model import build_model  # noqa: E402
from mat_hopper.core.rollout import Rollout  # noqa: E402
from mat_hopper.core.sim import CHANNELS  # noqa: E402
from mat_hopper.physics.metrics import run_summary  # noqa: E402
from mat_hopper.physics.run_metrics import _whole_run  # noqa: E402

wp, _ = require_warp()
from mat_hopper.batch import _kernels as K  # noqa: E402

C = {n: i for i, n in enumerate(CHANNELS)}
DEV = "cpu"


@pytest.fixture(scope="module")
def layout():
    return build_model(parse_design("PVC"), sensors="control").layout


def _random_inputs(rng, n, lay, nsens, nq, nv, dt, step):
    """Sensor rows, qpos, qvel and controller states that cover every branch."""
    sens = np.zeros((n, nsens), np.float32)
    qpos = rng.normal(0, 0.3, (n, nq)).astype(np.float32)
    qvel = rng.normal(0, 2.0, (n, nv)).astype(np.float32)
    t = step * dt
    touch = np.where(rng.random(n) < 0.5, 0.0, rng.uniform(1, 500, n))
    sens[:, lay.touch] = touch
    sens[:, lay.base_pos : lay.base_pos + 3] = rng.normal([0.1, -0.05, 0.9], 0.2, (n, 3))
    q = rng.normal([1, 0, 0, 0], [0.05, 0.1, 0.1, 0.6], (n, 4))
    sens[:, lay.base_quat : lay.base_quat + 4] = q / np.linalg.norm(q, axis=1, keepdims=True)
    sens[:, lay.base_gyro : lay.base_gyro + 3] = rng.normal(0, 1.0, (n, 3))
    sens[:, lay.base_linvel : lay.base_linvel + 3] = rng.normal(0, 0.5, (n, 3))
    st = np.tile(ctl.initial_state(ctl.ControllerSettings()), (n, 1))
    st[:, ctl.S_PHASE] = rng.integers(0, 2, n)
    # switch times: some within the phase lock, some long ago, some never
    st[:, ctl.S_T_SWITCH] = np.where(rng.random(n) < 0.25, t - 0.05, t - rng.uniform(0.1, 3, n))
    st[rng.random(n) < 0.1, ctl.S_T_SWITCH] = -np.inf
    st[:, ctl.S_THRUST] = rng.uniform(100, 300, n)
    st[:, ctl.S_Z_MAX] = rng.uniform(0.5, 1.3, n)
    low = rng.random(n) < 0.3  # thrust adaptation that would go negative (clamped at 0)
    st[low, ctl.S_THRUST] = rng.uniform(0, 20, low.sum())
    st[low, ctl.S_Z_MAX] = rng.uniform(1.5, 2.5, low.sum())
    st[:, ctl.S_LIFTOFFS] = rng.integers(0, 3, n)
    st[:, ctl.S_TOUCHDOWNS] = rng.integers(0, 3, n)
    return sens, qpos, qvel, st


@pytest.mark.parametrize("latency", [0, 1, 3])
def test_controller_kernel_is_control_py(layout, latency):
    """The kernel reads its rings at the slots of the sensor timing: filled
    with a different random reading in every slot, it must act on the base
    readings of s_(i-L) and the touch of s_(i-max(L,1)) exactly as control.py
    does on those readings."""
    rng = np.random.default_rng(7 + latency)
    n, nsens, nq, nv, nu = 512, 14, 12, 12, 3
    dt, step = 2.5e-4, 4321
    ring = K.ring_size(latency)
    settings = ctl.ControllerSettings()
    beh = behaviour("circle")
    slots = [_random_inputs(rng, n, layout, nsens, nq, nv, dt, step) for _ in range(ring)]
    _, qpos, qvel, st = slots[0]
    base_ring = np.zeros((n, ring, K.R_WIDTH))
    touch_ring = np.zeros((n, ring))
    for k, (sens, *_) in enumerate(slots):
        b, t = K.rings_from_sensordata(sens, layout, latency)
        base_ring[:, k], touch_ring[:, k] = b[:, 0], t[:, 0]
    with wp.ScopedDevice(DEV):
        a = dict(
            qpos=wp.array(qpos, dtype=wp.float32),
            qvel=wp.array(qvel, dtype=wp.float32),
            st=wp.array(st, dtype=wp.float64),
            ctrl=wp.zeros((n, nu), dtype=wp.float32),
            ev=wp.zeros(n, dtype=wp.int32),
            hr=wp.zeros((n, 2), dtype=wp.float64),
            div=wp.array(np.full(n, -1, np.int32), dtype=wp.int32),
            clock=wp.array([step], dtype=wp.int32),
        )
        wp.launch(
            K.control_kernel,
            dim=n,
            inputs=[
                a["clock"],
                dt,
                latency,
                K.make_gains(settings),
                K.make_layout(layout),
                beh.path_code,
                wp.array(beh.path_params, dtype=wp.float64),
                wp.array(beh.table_xy_m, dtype=wp.float64),
                wp.array(base_ring, dtype=wp.float64),
                wp.array(touch_ring, dtype=wp.float64),
                a["div"],
                a["st"],
                a["qpos"],
                a["qvel"],
                a["ctrl"],
                a["ev"],
                a["hr"],
            ],
        )
        got_ctrl, got_state, got_ev = a["ctrl"].numpy(), a["st"].numpy(), a["ev"].numpy()
    gains = settings.gains()
    lay = layout
    # the slots the timing names, worked out by hand: step 4321, base L back, touch max(L, 1) back
    base_slot = (step - latency) % ring
    touch_slot = (step - max(latency, 1)) % ring
    base_sens = slots[base_slot][0].astype(np.float64)
    touch = slots[touch_slot][0][:, lay.touch].astype(np.float64)
    want_ev = np.zeros(n, int)
    for w in range(n):
        s = st[w].copy()
        out = np.zeros(ctl.OUT_SIZE)
        sd = base_sens[w]
        ev = ctl.controller_step.py_func(
            step * dt,
            touch[w],
            sd[lay.base_pos : lay.base_pos + 3],
            sd[lay.base_quat : lay.base_quat + 4],
            sd[lay.base_gyro : lay.base_gyro + 3],
            sd[lay.base_linvel : lay.base_linvel + 3],
            qpos[w, [lay.hip_y_qpos, lay.hip_x_qpos]].astype(np.float64),
            qvel[w, [lay.hip_y_dof, lay.hip_x_dof]].astype(np.float64),
            np.array(beh.desired(step * dt)),
            gains,
            s,
            out,
        )
        want_ev[w] = ev
        np.testing.assert_allclose(got_state[w], s, rtol=1e-12, atol=1e-12, err_msg=f"state, world {w}")
        np.testing.assert_allclose(
            got_ctrl[w, [lay.act_hip_y, lay.act_hip_x, lay.act_thrust]],
            out[:3].astype(np.float32),
            rtol=1e-6,
            atol=1e-6,
            err_msg=f"controls, world {w}",
        )
    np.testing.assert_array_equal(got_ev, want_ev)
    # every branch was reached: all three events, stance and flight controls, thrust on and off
    assert set(want_ev) == {ctl.NO_EVENT, ctl.TOUCHDOWN, ctl.LIFTOFF}
    adapted = (want_ev == ctl.TOUCHDOWN) & (st[:, ctl.S_LIFTOFFS] > 0)
    assert (got_state[adapted, ctl.S_THRUST] == 0).any() and (got_state[adapted, ctl.S_THRUST] > 0).any()
    assert (got_ctrl[:, lay.act_thrust] > 0).any() and (got_ctrl[:, lay.act_thrust] == 0).any()


def test_rings_take_each_step_in_its_slot(layout):
    """push_base_kernel (after step1) and push_touch_kernel (after step2)
    write step i's readings into slot i mod ring, nothing else."""
    rng = np.random.default_rng(3)
    n, latency, step = 3, 2, 7
    ring = K.ring_size(latency)
    sens = rng.normal(size=(n, 14)).astype(np.float32)
    with wp.ScopedDevice(DEV):
        base = wp.zeros((n, ring, K.R_WIDTH), dtype=wp.float64)
        touch = wp.zeros((n, ring), dtype=wp.float64)
        clock = wp.array([step], dtype=wp.int32)
        sd = wp.array(sens, dtype=wp.float32)
        lay = K.make_layout(layout)
        wp.launch(K.push_base_kernel, dim=n, inputs=[clock, lay, sd, base])
        wp.launch(K.push_touch_kernel, dim=n, inputs=[clock, lay, sd, touch])
        base, touch = base.numpy(), touch.numpy()
    slot = step % ring  # 7 mod 3 = 1
    assert slot == 1
    want_base, want_touch = K.rings_from_sensordata(sens, layout, latency)
    np.testing.assert_array_equal(base[:, slot], want_base[:, 0])
    np.testing.assert_array_equal(touch[:, slot], want_touch[:, 0])
    others = [k for k in range(ring) if k != slot]
    assert (base[:, others] == 0).all() and (touch[:, others] == 0).all()
    # the ring layout by hand: position, quaternion, gyro, velocity of the sensor rows
    np.testing.assert_array_equal(base[0, slot, 0:3], sens[0, layout.base_pos : layout.base_pos + 3])
    np.testing.assert_array_equal(base[0, slot, 3:7], sens[0, layout.base_quat : layout.base_quat + 4])
    np.testing.assert_array_equal(base[0, slot, 7:10], sens[0, layout.base_gyro : layout.base_gyro + 3])
    np.testing.assert_array_equal(base[0, slot, 10:13], sens[0, layout.base_linvel : layout.base_linvel + 3])
    assert touch[0, slot] == sens[0, layout.touch]


def test_parked_world_is_reset_and_silent(layout):
    n, nq, nv = 2, 12, 12
    with wp.ScopedDevice(DEV):
        init = np.arange(n * nq, dtype=np.float32).reshape(n, nq)
        qpos = wp.array(np.full((n, nq), np.nan, np.float32), dtype=wp.float32)
        qvel = wp.array(np.full((n, nv), 5.0, np.float32), dtype=wp.float32)
        warm = wp.array(np.full((n, nv), 3.0, np.float32), dtype=wp.float32)
        ctrl = wp.array(np.ones((n, 3), np.float32), dtype=wp.float32)
        ev = wp.array(np.full(n, 9, np.int32), dtype=wp.int32)
        div = wp.array(np.array([-1, 10], np.int32), dtype=wp.int32)
        wp.launch(K.park_kernel, dim=n, inputs=[wp.array(init, dtype=wp.float32), div, qpos, qvel, warm, ctrl, ev])
        np.testing.assert_array_equal(qpos.numpy()[1], init[1])
        assert (qvel.numpy()[1] == 0).all() and (warm.numpy()[1] == 0).all() and (ctrl.numpy()[1] == 0).all()
        assert ev.numpy()[1] == ctl.NO_EVENT
        # a live world is not touched
        assert np.isnan(qpos.numpy()[0]).all() and (qvel.numpy()[0] == 5).all() and ev.numpy()[0] == 9


@pytest.mark.parametrize(
    "beh",
    [
        behaviour("forward"),
        behaviour("circle"),
        behaviour("static"),
        Behaviour("heading", "line", 0.07, heading_rad=0.6, start_xy_m=(0.3, -0.2)),
        Behaviour.from_function(
            "fig8", lambda t: (0.3 * np.sin(0.1 * t), 0.15 * np.sin(0.2 * t)), duration_s=5.0, dt_s=0.01
        ),
    ],
    ids=lambda b: b.name,
)
def test_desired_path_is_behaviours(beh):
    ts = np.concatenate([np.linspace(-0.5, 7.0, 301), [0.0, 5.0, 4.995]])

    @wp.kernel
    def eval_path(
        ts: wp.array(dtype=wp.float64),
        kind: int,
        params: wp.array(dtype=wp.float64),
        table: wp.array2d(dtype=wp.float64),
        out: wp.array(dtype=wp.vec4d),
    ):
        i = wp.tid()
        out[i] = K.desired_state(ts[i], kind, params, table)

    with wp.ScopedDevice(DEV):
        out = wp.zeros(len(ts), dtype=wp.vec4d)
        wp.launch(
            eval_path,
            dim=len(ts),
            inputs=[
                wp.array(ts, dtype=wp.float64),
                beh.path_code,
                wp.array(beh.path_params, dtype=wp.float64),
                wp.array(beh.table_xy_m, dtype=wp.float64),
                out,
            ],
        )
        got = out.numpy()
    want = np.array([desired_state.py_func(t, beh.path_code, beh.path_params, beh.table_xy_m) for t in ts])
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12)


def test_metrics_kernel_is_metrics_py(layout):
    """Synthetic runs (random trajectories, lift-offs, one divergence) scored
    by the incremental kernel and by metrics.run_summary on the recorded samples."""
    rng = np.random.default_rng(3)
    n, nsens, nq, nv = 6, 14, 12, 12
    settings = BatchSettings(duration_s=2.0, timestep_s=2.5e-3, transient_s=0.4, record_rate_hz=100.0)
    every, dt, n_steps = settings.record_every, settings.timestep_s, settings.n_steps
    assert every == 4
    beh = behaviour("circle")
    lay = layout
    # lift-offs: random, some on sample steps, some not; world 5 has none; world 4 diverges
    lift = rng.random((n_steps, n)) < 0.03
    lift[0:3, 0] = True
    lift[:, 5] = False
    diverge_at = {4: 517}
    sens_seq = rng.normal([0.3, 0.2, 1.0], [0.1, 0.1, 0.2], (n_steps, n, 3))
    sens_seq[-8:, 3, 2] = 0.05  # world 3 ends fallen (base below 0.1 m): not upright
    qfrc_seq = rng.normal(0, 20, (n_steps, n, 2))
    rate_seq = rng.normal(0, 1, (n_steps, n, 2))
    with wp.ScopedDevice(DEV):
        acc = wp.zeros((n, K.N_ACC), dtype=wp.float64)
        div = wp.array(np.full(n, -1, np.int32), dtype=wp.int32)
        clock = wp.zeros(1, dtype=wp.int32)
        sens = wp.zeros((n, nsens), dtype=wp.float32)
        qfrc = wp.zeros((n, nv), dtype=wp.float32)
        qpos = wp.zeros((n, nq), dtype=wp.float32)
        qacc = wp.zeros((n, nv), dtype=wp.float32)
        ev = wp.zeros(n, dtype=wp.int32)
        hr = wp.zeros((n, 2), dtype=wp.float64)
        params = wp.array(beh.path_params, dtype=wp.float64)
        table = wp.array(beh.table_xy_m, dtype=wp.float64)
        lw = K.make_layout(lay)
        for i in range(n_steps):
            s = np.zeros((n, nsens), np.float32)
            s[:, lay.base_pos : lay.base_pos + 3] = sens_seq[i]
            f = np.zeros((n, nv), np.float32)
            f[:, lay.hip_y_dof], f[:, lay.hip_x_dof] = qfrc_seq[i, :, 0], qfrc_seq[i, :, 1]
            q = np.zeros((n, nq), np.float32)
            for w, k in diverge_at.items():
                if i == k:
                    q[w, 3] = np.nan
            sens.assign(s)
            qfrc.assign(f)
            qpos.assign(q)
            ev.assign(np.where(lift[i], ctl.LIFTOFF, ctl.NO_EVENT).astype(np.int32))
            hr.assign(rate_seq[i])
            wp.launch(
                K.metrics_kernel,
                dim=n,
                inputs=[
                    clock,
                    dt,
                    settings.transient_s,
                    every,
                    1e6,
                    lw,
                    beh.path_code,
                    params,
                    table,
                    sens,
                    qfrc,
                    qpos,
                    qacc,
                    ev,
                    hr,
                    div,
                    acc,
                ],
            )
            wp.launch(K.tick_kernel, dim=1, inputs=[clock])
        got, got_div = acc.numpy(), div.numpy()
    # The same samples as a recorded rollout, scored by mat_hopper.physics.metrics.
    design = parse_design("PVC")
    sim = settings
    f32 = lambda v: np.float64(np.float32(v))  # noqa: E731  what the float32 device arrays hold
    for w in range(n):
        end = diverge_at.get(w, n_steps - 1)
        rows, events = [], []
        for i in range(end + 1):
            t = i * dt
            if lift[i, w]:
                events.append((t, ctl.LIFTOFF, np.nan))
            if i % every == 0 or i == end and w in diverge_at:
                r = np.zeros(len(CHANNELS))
                r[C["t"]] = t
                r[C["x"] : C["z"] + 1] = [f32(v) for v in sens_seq[i, w]]
                r[C["x_des"] : C["vy_des"] + 1] = beh.desired(t)
                r[C["torque_hip_y"]], r[C["torque_hip_x"]] = f32(qfrc_seq[i, w, 0]), f32(qfrc_seq[i, w, 1])
                r[C["hip_y_rate"]], r[C["hip_x_rate"]] = rate_seq[i, w]
                rows.append(r)
        ro = Rollout(
            design, beh, sim, np.array(rows), np.array(events).reshape(-1, 3), diverge_at.get(w, -1), 1.0, (0.0,)
        )
        s = run_summary(ro)
        n_hops = int(got[w, K.A_HOPS])
        assert n_hops == s["n_hops"], w
        assert got_div[w] == diverge_at.get(w, -1)
        if n_hops:
            np.testing.assert_allclose(got[w, K.A_HEIGHT_SUM] / n_hops, s["mean_hop_height_m"], rtol=1e-12)
            np.testing.assert_allclose(got[w, K.A_ERR_SUM] / n_hops, s["mean_tracking_error_m"], rtol=1e-12)
            np.testing.assert_allclose(got[w, K.A_POW_SUM] / n_hops, s["mean_power_w"], rtol=1e-12)
        # whole-run means and the upright test: the CPU objective's own functions on the same samples
        whole = _whole_run(ro)
        run_err, run_pow = whole["tracking_error_m"], whole["power_w"]
        np.testing.assert_allclose(got[w, K.A_RUN_ERR] / got[w, K.A_RUN_NERR], run_err, rtol=1e-12)
        np.testing.assert_allclose(got[w, K.A_RUN_POW] / got[w, K.A_RUN_NPOW], run_pow, rtol=1e-12)
        assert got[w, K.A_RUN_NERR] == got[w, K.A_RUN_NPOW] == len(rows)
        assert got[w, K.A_LAST_Z] == ro.data[-1, C["z"]]
        assert (got_div[w] < 0 and got[w, K.A_LAST_Z] > 0.1) == ro.upright
    assert int(got[0, K.A_HOPS]) > 5 and int(got[5, K.A_HOPS]) == 0
    assert got[3, K.A_LAST_Z] < 0.1 < got[2, K.A_LAST_Z]
