"""The warp backend: many designs of one topology in one MuJoCo Warp batch.

One compiled hopper (:func:`mat_hopper.core.model.build_model`) goes to the
device once (``mujoco_warp.put_model``) with a world axis on the fields a
design changes:

- body_mass, body_inertia, body_ipos, body_iquat: MuJoCo's compiler gives
  them per design (the capsules' densities; a body holds halves of two
  segments, so its centre of mass moves too). One host compile per
  distinct set of densities, about a millisecond;
- jnt_stiffness of the material springs: ``materials.spring_stiffness``,
  the function the model builder uses;
- the constants derived from masses (body_subtreemass, dof_invweight0,
  body_invweight0, actuator_acc0) are recomputed on the device per world by
  ``mujoco_warp.set_const``, as MJWarp's domain randomisation does (mjlab's
  ``dr`` module expands the fields, writes them, calls set_const).

Every other model field must be identical across the designs: that is
checked against each host compile, so a design that changes anything else
is refused rather than simulated wrongly.

MuJoCo's automatic reset is unsupported by MJWarp, so it is cleared on the
device copy; divergence is detected per world by the batch itself (see
:mod:`._kernels`). MJWarp's state is float32; the controller and the
metrics run in float64.
"""

from __future__ import annotations

import copy
import math
import warnings
from collections.abc import Sequence

import mujoco
import numpy as np
import pandas as pd

from ..core import reference as ref
from ..core.behaviours import behaviour as get_behaviour
from ..core.controller import initial_state
from ..core.materials import BENDING_CONVENTIONS, LegDesign, as_design, spring_stiffness
from ..core.model import build_model
from ..core.sim import prepare
from ._designs import group_by_topology
from ._settings import BatchSettings, mean_or_nan, result_frame

# Model fields set per world from the designs, and those set_const derives from them.
DESIGN_FIELDS = ("body_mass", "body_inertia", "body_ipos", "body_iquat", "jnt_stiffness")
DERIVED_FIELDS = ("body_subtreemass", "dof_invweight0", "body_invweight0", "actuator_acc0")
# Host-model fields that may differ between designs without entering MJWarp's dynamics:
# names, dof_M0 (not in MJWarp), dof_length (sleep only; sleep is off), light_poscom0 (tracking lights).
_IGNORED_FIELDS = ("names", "dof_M0", "dof_length", "light_poscom0")
INSTALL_HINT = "pip install 'mat-hopper[gpu]' (mujoco-warp and warp-lang)"


class WarpUnavailable(ImportError):
    """mujoco-warp or warp-lang is not installed (or does not load): an
    ImportError, so ``except ImportError`` catches it. Install the ``gpu`` extra.
    """


def require_warp():
    """The warp backend's libraries, quietly initialised.

    Returns:
        (warp, mujoco_warp), the modules.

    Raises:
        WarpUnavailable: (an ImportError) mujoco-warp or warp-lang missing or not loading.
    """
    try:
        import warp as wp
    except Exception as e:  # ImportError, or a broken install
        raise WarpUnavailable(
            f"the warp backend needs warp-lang, which does not import ({e}); {INSTALL_HINT}"
        ) from None
    # Warp logs every kernel module it loads at INFO, its default level: keep to warnings.
    if getattr(wp.config, "log_level", None) == getattr(wp, "LOG_INFO", 20) and hasattr(wp, "LOG_WARNING"):
        wp.config.log_level = wp.LOG_WARNING
    wp.config.quiet = True
    try:
        import mujoco_warp as mjw
    except Exception as e:
        raise WarpUnavailable(
            f"the warp backend needs mujoco-warp, which does not import ({e}); {INSTALL_HINT}"
        ) from None
    wp.init()
    return wp, mjw


def warp_available() -> bool:
    """Whether the warp backend can run here.

    Returns:
        True when mujoco-warp and warp-lang are installed and load.
    """
    try:
        require_warp()
        return True
    except WarpUnavailable:
        return False


def _device(wp, device):
    name = "cpu" if device is None else str(device)
    try:
        dev = wp.get_device(name)
    except Exception:
        dev = None
    if dev is None:
        seen = ", ".join(str(d) for d in wp.get_devices())
        raise ValueError(f"device {name!r} is not available to Warp (it sees: {seen})")
    return dev


def _model_arrays(model) -> dict:
    out = {}
    for name in dir(model):
        if name.startswith("_") or name in _IGNORED_FIELDS or name.startswith("name_"):
            continue
        try:
            v = getattr(model, name)
        except Exception:
            continue
        if isinstance(v, np.ndarray):
            out[name] = v
    return out


def _check_same(ref_arrays: dict, model, design: LegDesign, ref_name: str) -> None:
    allowed = set(DESIGN_FIELDS) | set(DERIVED_FIELDS)
    for name, a in ref_arrays.items():
        if name in allowed:
            continue
        b = getattr(model, name)
        if a.shape != b.shape or not np.array_equal(a, b, equal_nan=True):
            raise ValueError(
                f"design {design.name!r} changes model field {name} against {ref_name!r}: it "
                f"cannot share their batch (only {', '.join(DESIGN_FIELDS)} may differ)"
            )


def design_fields(designs: Sequence[LegDesign], behaviour, settings: BatchSettings):
    """What differs between the worlds of a batch, as the device holds it.

    Args:
        designs: LegDesigns of one topology.
        behaviour: a Behaviour or a name.
        settings: the run's :class:`BatchSettings`.

    Returns:
        Per-world values (numpy, world axis first) of :data:`DESIGN_FIELDS`,
        plus the derived fields as MuJoCo's compiler gives them (for checks),
        the topology's model and its total masses (kg).
    """
    beh = get_behaviour(behaviour)
    if settings.convention in BENDING_CONVENTIONS:  # per-world stiffness of the slides only
        raise ValueError(
            f"convention {settings.convention!r}: the Warp batch sets only the axial springs' stiffness per "
            "world; run bending conventions with --backend mujoco (and a --timestep small enough for the hinges)"
        )
    build = dict(
        ramp_grade_deg=beh.ramp_grade_deg,
        timestep_s=settings.timestep_s,
        convention=settings.convention,
        sensors="control",
        segment_mass=settings.segment_mass,
        contact=settings.contact,
    )
    base = build_model(designs[0], **build)
    ref_arrays = _model_arrays(base.model)
    spring_jnt = {
        i: base.model.joint(f"mat_spring_{i}").id for i, m in enumerate(designs[0].segments, start=1) if not m.rigid
    }
    compiled = {}
    fields = {f: [] for f in DESIGN_FIELDS + DERIVED_FIELDS}
    mass = []
    for d in designs:
        key = d.densities_g_cm3
        if key not in compiled:
            hm = build_model(d, **build)
            _check_same(ref_arrays, hm.model, d, designs[0].name)
            compiled[key] = hm
        m = compiled[key].model
        for f in DESIGN_FIELDS + DERIVED_FIELDS:
            fields[f].append(np.array(getattr(m, f), dtype=np.float64))
        k = fields["jnt_stiffness"][-1]
        for i, j in spring_jnt.items():  # the stiffness of this design, whoever compiled the masses
            k[j] = spring_stiffness(d.segments[i - 1].modulus_gpa, settings.convention, d.n_segments)
        mass.append(float(m.body_subtreemass[0]))
    return {f: np.stack(v) for f, v in fields.items()}, base, np.array(mass)


class WarpBatch:
    """Designs of one topology on one behaviour, one world each, on a Warp device.
    :meth:`run` simulates, :meth:`results` gives the per-design table.

    Args:
        designs: LegDesigns or names, all of one topology (:func:`topology_key`).
        behaviour: a Behaviour or a name.
        settings: the run's :class:`BatchSettings` (None: the paper's protocol).
        device: the Warp device (``"cpu"``, ``"cuda"``, ``"cuda:1"``, ...).

    Raises:
        ValueError: no designs, designs of several topologies, or an unknown device.
        WarpUnavailable: without mujoco-warp.
    """

    def __init__(
        self, designs: Sequence, behaviour, settings: BatchSettings | None = None, *, device: str | None = None
    ):
        wp, mjw = require_warp()
        from . import _kernels as K

        self._wp, self._mjw, self._K = wp, mjw, K
        self.settings = settings = settings or BatchSettings()
        self.designs = [as_design(d) for d in designs]
        if not self.designs:
            raise ValueError("a batch needs at least one design")
        if len(group_by_topology(self.designs)) != 1:
            raise ValueError(
                "one batch holds one topology (same segment count, same rigid segments); "
                "evaluate_warp groups designs for you"
            )
        self.behaviour = get_behaviour(behaviour)
        self.device = _device(wp, device)
        nw = self.nworld = len(self.designs)

        fields, hopper, self.total_mass_kg = design_fields(self.designs, self.behaviour, settings)
        self.hopper = hopper
        self.compiled_derived = {f: fields[f] for f in DERIVED_FIELDS}
        mjm = copy.copy(hopper.model)
        # MJWarp refuses mjDSBL_AUTORESET; divergence is detected per world instead.
        mjm.opt.disableflags &= ~int(mujoco.mjtDisableBit.mjDSBL_AUTORESET)
        self.mjm = mjm
        with wp.ScopedDevice(self.device), warnings.catch_warnings():
            warnings.simplefilter("ignore")  # put_model's advisory notes (e.g. torsional friction)
            m = mjw.put_model(mjm, batch_sizes={f: nw for f in DESIGN_FIELDS + DERIVED_FIELDS})
            d = mjw.make_data(mjm, nworld=nw)
            for f in DESIGN_FIELDS:
                arr = getattr(m, f)
                arr.assign(fields[f].reshape(arr.numpy().shape).astype(np.float32))
            mjw.set_const(m, d)
            # The start pose: the behaviour's, as the CPU rollout prepares it.
            _, data0 = prepare(self.designs[0], self.behaviour, settings)
            qpos0 = np.tile(np.asarray(data0.qpos, dtype=np.float32), (nw, 1))
            d.qpos.assign(qpos0)
            d.qvel.zero_()
            mjw.forward(m, d)  # sensors of the initial state: every lagged reading of step 0
            self.m, self.d = m, d
            base_ring, touch_ring = K.rings_from_sensordata(
                d.sensordata.numpy(), hopper.layout, settings.sensor_latency_steps
            )
            self._base_ring = wp.array(base_ring, dtype=wp.float64)
            self._touch_ring = wp.array(touch_ring, dtype=wp.float64)
            self._qpos_init = wp.array(qpos0, dtype=wp.float32)
            st = np.tile(initial_state(settings.controller), (nw, 1))
            self._state = wp.array(st, dtype=wp.float64)
            self._acc = wp.zeros((nw, K.N_ACC), dtype=wp.float64)
            self._diverged = wp.array(np.full(nw, -1, dtype=np.int32), dtype=wp.int32)
            self._event = wp.zeros(nw, dtype=wp.int32)
            self._hip_rate = wp.zeros((nw, 2), dtype=wp.float64)
            self._clock = wp.zeros(1, dtype=wp.int32)
            beh = self.behaviour
            self._path_params = wp.array(beh.path_params, dtype=wp.float64)
            self._path_table = wp.array(beh.table_xy_m, dtype=wp.float64)
        self._gains = K.make_gains(settings.controller)
        self._layout = K.make_layout(hopper.layout)
        self.step = 0
        self._graph = None
        self._graph_steps = 0
        self._graph_failed = False

    # -- stepping --
    def _launch_step(self) -> None:
        """One physics step of every world (see :mod:`._kernels` for the order)."""
        wp, mjw, K, d, s = self._wp, self._mjw, self._K, self.d, self.settings
        beh = self.behaviour
        dt = float(s.timestep_s)
        lay = self._layout
        wp.launch(
            K.park_kernel,
            dim=self.nworld,
            inputs=[self._qpos_init, self._diverged, d.qpos, d.qvel, d.qacc_warmstart, d.ctrl, self._event],
        )
        mjw.step1(self.m, d)
        wp.launch(K.push_base_kernel, dim=self.nworld, inputs=[self._clock, lay, d.sensordata, self._base_ring])
        wp.launch(
            K.control_kernel,
            dim=self.nworld,
            inputs=[
                self._clock,
                dt,
                int(s.sensor_latency_steps),
                self._gains,
                lay,
                beh.path_code,
                self._path_params,
                self._path_table,
                self._base_ring,
                self._touch_ring,
                self._diverged,
                self._state,
                d.qpos,
                d.qvel,
                d.ctrl,
                self._event,
                self._hip_rate,
            ],
        )
        mjw.step2(self.m, d)
        wp.launch(
            K.metrics_kernel,
            dim=self.nworld,
            inputs=[
                self._clock,
                dt,
                float(s.transient_s),
                s.record_every,
                float(ref.DIVERGENCE_QACC),
                lay,
                beh.path_code,
                self._path_params,
                self._path_table,
                d.sensordata,
                d.qfrc_actuator,
                d.qpos,
                d.qacc,
                self._event,
                self._hip_rate,
                self._diverged,
                self._acc,
            ],
        )
        wp.launch(K.push_touch_kernel, dim=self.nworld, inputs=[self._clock, lay, d.sensordata, self._touch_ring])
        wp.launch(K.tick_kernel, dim=1, inputs=[self._clock])

    def _capture(self, n: int) -> bool:
        """Record (not run) a CUDA graph of n steps (GPU only); False where capture fails."""
        wp = self._wp
        try:
            with wp.ScopedCapture(device=self.device) as cap:
                for _ in range(n):
                    self._launch_step()
        except Exception as e:  # pragma: no cover (GPU only)
            warnings.warn(f"CUDA graph capture failed ({e}); stepping without graphs", RuntimeWarning, stacklevel=2)
            self._graph_failed = True
            return False
        self._graph, self._graph_steps = cap.graph, n
        return True

    def advance(self, n_steps: int) -> None:
        """Run n_steps more physics steps (fewer at the end of the run)."""
        wp = self._wp
        n = min(int(n_steps), self.settings.n_steps - self.step)
        if n <= 0:
            return
        with wp.ScopedDevice(self.device):
            done = 0
            if self.device.is_cuda:
                if self.step == 0:  # compile every kernel before any capture
                    self._launch_step()
                    done = 1
                if self._graph is None and not self._graph_failed and n - done >= self.graph_steps:
                    self._capture(self.graph_steps)  # recorded now, run by the launches below
                while self._graph is not None and n - done >= self._graph_steps:
                    wp.capture_launch(self._graph)
                    done += self._graph_steps
            while done < n:
                self._launch_step()
                done += 1
            wp.synchronize_device(self.device)
        self.step += n

    graph_steps = 500  # steps per CUDA graph

    def run(self, *, progress: bool = False, chunk_steps: int | None = None) -> WarpBatch:
        """Simulate to the end; progress: a tqdm bar over simulated time."""
        s = self.settings
        chunk = int(chunk_steps or (self.graph_steps if self.device.is_cuda else 200))
        bar = None
        if progress:
            from ..util.progress import progress_bar

            # counts steps, shows simulated seconds (unit_scale multiplies both by dt)
            bar = progress_bar(
                total=s.n_steps,
                initial=self.step,
                unit_scale=s.timestep_s,
                desc=f"warp x{self.nworld}",
                bar_format="{l_bar}{bar}| {n:.2f}/{total:.2f} sim s [{elapsed}<{remaining}]",
            )
        try:
            while self.step < s.n_steps:
                before = self.step
                self.advance(chunk)
                if bar:
                    bar.update(self.step - before)
        finally:
            if bar:
                bar.close()
        return self

    # -- outcome --
    def diverged_steps(self) -> np.ndarray:
        return self._diverged.numpy().copy()

    def controller_state(self) -> np.ndarray:
        """(nworld, control.STATE_SIZE) controller states, control.py's layout."""
        return self._state.numpy().copy()

    def results(self) -> pd.DataFrame:
        K = self._K
        acc = self._acc.numpy()
        div = self._diverged.numpy()
        rows = []
        for w, design in enumerate(self.designs):
            n = int(acc[w, K.A_HOPS])
            rows.append(
                {
                    "design": design.name,
                    "n_hops": n,
                    "hop_height_m": mean_or_nan(acc[w, K.A_HEIGHT_SUM], n),
                    "tracking_error_m": mean_or_nan(acc[w, K.A_ERR_SUM], n),
                    "power_w": mean_or_nan(acc[w, K.A_POW_SUM], n),
                    "stable": bool(div[w] < 0),
                    "behaviour": self.behaviour.name,
                    "sensor_timing": self.settings.sensor_timing.name,
                    "diverged_at_s": None if div[w] < 0 else float(div[w] * self.settings.timestep_s),
                    "total_mass_kg": float(self.total_mass_kg[w]),
                    "backend": "warp",
                    "upright": bool(div[w] < 0 and acc[w, K.A_LAST_Z] > ref.STABLE_MIN_BASE_Z),
                    "fell_at_s": math.nan,  # the kernels do not track the base's tilt
                    "run_tracking_error_m": mean_or_nan(acc[w, K.A_RUN_ERR], int(acc[w, K.A_RUN_NERR])),
                    "run_power_w": mean_or_nan(acc[w, K.A_RUN_POW], int(acc[w, K.A_RUN_NPOW])),
                }
            )
        return result_frame(rows)


def evaluate_warp(
    designs: Sequence,
    behaviour,
    settings: BatchSettings | None = None,
    *,
    device: str | None = None,
    max_batch: int | None = None,
    progress: bool = False,
) -> pd.DataFrame:
    """The warp backend: designs grouped by topology, each group (in slices of at
    most `max_batch` worlds) run as one batch on the Warp device.

    Args:
        designs: LegDesigns or names.
        behaviour: a Behaviour or a name.
        settings: the run's :class:`BatchSettings` (None: the paper's protocol).
        device: the Warp device (None: ``"cpu"``).
        max_batch: most worlds in one batch.
        progress: show a progress bar.

    Returns:
        One row per design, in input order, like :func:`evaluate_cpu`.

    Raises:
        ValueError: bad designs or counts.
        WarpUnavailable: without mujoco-warp.
    """
    settings = settings or BatchSettings()
    require_warp()
    designs = [as_design(d) for d in designs]
    if not designs:
        raise ValueError("no designs to evaluate")
    if max_batch is not None and max_batch < 1:
        raise ValueError(f"max_batch must be >= 1, got {max_batch!r}")
    rows: list[dict | None] = [None] * len(designs)
    for idx in group_by_topology(designs).values():
        size = max_batch or len(idx)
        for a in range(0, len(idx), size):
            part = idx[a : a + size]
            table = (
                WarpBatch([designs[i] for i in part], behaviour, settings, device=device)
                .run(progress=progress)
                .results()
            )
            for i, row in zip(part, table.to_dict("records")):
                rows[i] = row
    return result_frame(rows)
