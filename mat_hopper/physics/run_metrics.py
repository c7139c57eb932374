"""What an objective may minimize: one named table of run metrics, with units.

An :class:`~mat_hopper.optimize._objective.Objective` minimizes two or three
of :data:`METRICS` (``objectives``, default :data:`DEFAULT_OBJECTIVES`,
tracking error and hip power). Each run (one design, one behaviour, one
replicate) scores every metric of the table, whatever the objective asks
(:func:`run_values`), so a cached run serves any objective. Scored runs
(hop cycles after the transient, ended upright) give:

==================== ====== ======================================================
name                 unit   per run
==================== ====== ======================================================
``tracking_error_m`` m      mean over hops of the mean planar distance base - path
``power_w``          W      mean over hops of the hip actuators' mechanical power
``power_total_w``    W      mean over hops of the absolute mechanical power of all
                            three actuators, the thrust included (about 95 % of
                            the work when hopping forward)
``energy_per_hop_j`` J      mean over hops of the absolute actuator work (all three)
``peak_stress_pa``   Pa     the leg's largest section stress over the hops
``damage_per_hop``   1      Miner damage per hop of the most damaged segment
``leg_mass_kg``      kg     the leg's mass, stub to foot (no run needed)
==================== ====== ======================================================

(:mod:`mat_hopper.physics.metrics`, :mod:`mat_hopper.physics.energetics`,
:mod:`mat_hopper.physics.fatigue`.) A run that fell, diverged or scored no hop gets
the same quantity over every finite recorded sample of the run (the
samplers can model it; the constraints make it infeasible): the mean
power, the whole run's work as one "hop", its largest stress, its damage as
one block. Values are capped at :data:`NO_DATA_VALUE` times the metric's
``cap_scale``.

Stress and fatigue are the leg's modelled stress: under the
``paper`` and ``axial`` conventions only the axial springs carry it (F / A),
so a stress objective means something only under ``bending`` or
``axial+bending``. A leg with no modelled stress (rigid segments) scores 0.
The fatigue safety factor is left out: it is maximized and infinite for a
leg with no stress cycle; ``damage_per_hop`` (minimized) carries the same
information.

The warp batch (:mod:`mat_hopper.optimize._batch`) computes only the
metrics marked ``warp`` (tracking error, hip power, leg mass).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.sim import C
from ..util.parsing import parse_name
from .energetics import actuator_power_w
from .fatigue import fatigue_summary

NO_DATA_VALUE = 1e6  # objective value (x the metric's cap_scale) when a run recorded no finite sample
MIN_OBJECTIVES, MAX_OBJECTIVES = 2, 3


@dataclass(frozen=True)
class Metric:
    """One row of the table (module doc).

    Args:
        name: the objective's name, its SI unit at the end.
        unit: the SI unit (``"1"``: dimensionless).
        label: words for plots and tables (``"hip power"``).
        short: a shorter label for standard-error and comparison columns.
        summary_column: the runner's run-summary column
            (:func:`mat_hopper.physics.metrics.run_summary`) that validation reads.
        display_unit, display_scale: the unit of the front table, and the
            factor from SI to it.
        warp: the warp batch computes it.
        stress: modelled stress (module doc: needs a bending convention).
        static_zero: zero by symmetry when hopping in place (``static``).
        noisy: varies between replicates (leg mass does not).
        cap_scale: its values are capped at NO_DATA_VALUE x this.
    """

    name: str
    unit: str
    label: str
    short: str
    summary_column: str
    display_unit: str
    display_scale: float = 1.0
    warp: bool = False
    stress: bool = False
    static_zero: bool = False
    noisy: bool = True
    cap_scale: float = 1.0

    @property
    def stem(self) -> str:
        """The name without its unit (``power_total``), for derived columns."""
        return self.name if self.unit == "1" else self.name.rsplit("_", 1)[0]

    @property
    def axis_label(self) -> str:
        """``label (unit)`` in SI, for plots."""
        return f"{self.label} ({'-' if self.unit == '1' else self.unit})"


METRICS: dict[str, Metric] = {
    m.name: m
    for m in (
        Metric("tracking_error_m", "m", "tracking error", "tracking", "mean_tracking_error_m", "mm", 1e3,
               warp=True, static_zero=True),
        Metric("power_w", "W", "hip power", "power", "mean_power_w", "mW", 1e3, warp=True, static_zero=True),
        Metric("power_total_w", "W", "total power", "total power", "mean_power_total_w", "W"),
        Metric("energy_per_hop_j", "J", "energy per hop", "energy", "energy_per_hop_j", "J"),
        Metric("peak_stress_pa", "Pa", "peak stress", "stress", "peak_stress_pa", "MPa", 1e-6, stress=True,
               cap_scale=1e6),
        Metric("damage_per_hop", "1", "damage per hop", "damage", "damage_per_hop", "1", stress=True),
        Metric("leg_mass_kg", "kg", "leg mass", "mass", "leg_mass_kg", "kg", warp=True, noisy=False),
    )
}  # fmt: skip
DEFAULT_OBJECTIVES = ("tracking_error_m", "power_w")


def parse_objectives(value, flag: str = "objectives") -> tuple[str, ...]:
    """The objectives `value` names: a comma-separated string or a sequence
    of names, each case-insensitive (:func:`mat_hopper.util.parsing.parse_name`).

    Args:
        value: ``"tracking_error_m,power_total_w"`` or a sequence of names.
        flag: the option or field named in errors (``--objectives``).

    Returns:
        The names as :data:`METRICS` spells them, in the order given.

    Raises:
        ValueError: an unknown name (the message lists the accepted ones), a
            repeated one, or fewer than MIN_OBJECTIVES or more than MAX_OBJECTIVES.
    """
    items = value.split(",") if isinstance(value, str) else list(value)
    names = tuple(parse_name(v, METRICS, flag) for v in items)
    if len(set(names)) != len(names):
        raise ValueError(f"{flag}: each metric at most once, got {','.join(names)}")
    if not MIN_OBJECTIVES <= len(names) <= MAX_OBJECTIVES:
        raise ValueError(
            f"{flag}: give {MIN_OBJECTIVES} or {MAX_OBJECTIVES} metrics, got {len(names)}; "
            f"accepted: {', '.join(METRICS)}"
        )
    return names


def capped(value: float, name: str) -> float:
    """A value as an objective value.

    Args:
        value: the metric's value (nan: no finite sample).
        name: the metric (a key of :data:`METRICS`).

    Returns:
        `value`, at most NO_DATA_VALUE x the metric's cap_scale; that cap
        when `value` is not finite.
    """
    cap = NO_DATA_VALUE * METRICS[name].cap_scale
    return float(min(value, cap)) if math.isfinite(value) else cap


def _finite_mean(values: np.ndarray) -> float:
    v = values[np.isfinite(values)]
    return float(v.mean()) if len(v) else math.nan


def _stress_or_zero(value: float) -> float:
    """A stress or damage value: nan (no modelled stress) reads 0."""
    return 0.0 if isinstance(value, float) and math.isnan(value) else float(value)


def _whole_run(rollout) -> dict:
    """The run metrics of a run without scored hops (module doc), over every finite sample."""
    d = rollout.data
    if len(d) == 0:
        return dict.fromkeys(METRICS, math.nan)
    err = np.hypot(d[:, C["x"]] - d[:, C["x_des"]], d[:, C["y"]] - d[:, C["y_des"]])
    p_abs = np.abs(actuator_power_w(rollout)).sum(axis=1)
    t = rollout.time
    dt_rec = float(np.median(np.diff(t))) if len(t) > 1 else 0.0
    out = {
        "tracking_error_m": _finite_mean(err),
        "power_w": _finite_mean(np.hypot(*rollout.hip_power.T)),
        "power_total_w": _finite_mean(p_abs),
        "energy_per_hop_j": float(p_abs[np.isfinite(p_abs)].sum() * dt_rec),
    }
    st = rollout.stress
    ok = np.zeros(len(d), bool) if st is None else np.isfinite(st).all(axis=(1, 2))
    if not ok.any():  # no modelled stress (0), or none finite (capped)
        out["peak_stress_pa"] = out["damage_per_hop"] = 0.0 if st is None else math.nan
        return out
    out["peak_stress_pa"] = float(st[ok, :, 3].max())
    last = int(np.flatnonzero(ok)[-1])
    try:  # the run up to its last finite stress sample, as one block of cycles
        out["damage_per_hop"] = _stress_or_zero(fatigue_summary(rollout, np.array([[t[0], t[last]]]))["damage_per_hop"])
    except (ValueError, FloatingPointError):
        out["damage_per_hop"] = math.nan
    return out


def run_values(rollout, hops, life: dict, leg_mass_kg: float, scored: bool) -> dict:
    """Every metric of the table for one run (module doc).

    Args:
        rollout: the run's Rollout.
        hops: its :func:`mat_hopper.physics.metrics.hop_table`.
        life: its :func:`mat_hopper.physics.fatigue.fatigue_summary` over the scored hops.
        leg_mass_kg: the leg's mass, kg (:func:`mat_hopper.optimize.leg_mass_kg`).
        scored: whether the run is scored by its hops
            (:func:`~mat_hopper.optimize._objective.scored_by_hops`); else
            the whole-run values.

    Returns:
        {metric name: value in its unit}, each finite (capped).
    """
    if scored:
        raw = {
            "tracking_error_m": float(hops["tracking_error_m"].mean()),
            "power_w": float(hops["power_w"].mean()),
            "power_total_w": float(hops["power_total_w"].mean()),
            "energy_per_hop_j": float(hops["work_abs_j"].mean()),
            "peak_stress_pa": _stress_or_zero(life["peak_stress_pa"]),
            "damage_per_hop": _stress_or_zero(life["damage_per_hop"]),
        }
    else:
        raw = _whole_run(rollout)
    raw["leg_mass_kg"] = float(leg_mass_kg)
    return {name: capped(raw[name], name) for name in METRICS}


def check_warp(objectives, backend: str = "warp") -> None:
    """Refuse objectives the warp batch cannot compute.

    Args:
        objectives: metric names (keys of :data:`METRICS`).
        backend: the backend named in the message.

    Raises:
        ValueError: (one line) an objective not marked ``warp``, naming it
            and the metrics the batch computes.
    """
    bad = [o for o in objectives if not METRICS[o].warp]
    if bad:
        ok = ", ".join(m.name for m in METRICS.values() if m.warp)
        raise ValueError(
            f"the {backend} backend computes only {ok}; these objectives need the CPU path: "
            f"{', '.join(bad)} (use --backend mujoco)"
        )
