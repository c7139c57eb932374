"""Energetics that count all the work: the hips *and* the thrust actuator.

The paper's power (``power_paper_w``) and the package's ``power_w`` are hip
quantities. In forward hopping the thrust actuator on the foot spring does
about 95 % of the absolute actuator work, so a verdict on "power" depends
on which power is meant: claims that quote power give their verdict under
the paper's formula, hip power and total power side by side.

Per hop cycle (columns of :func:`mat_hopper.physics.metrics.hop_table`), from the
recorded samples, each actuator's mechanical power p = tau qdot in joint
space (tau MuJoCo's ``qfrc_actuator``: hip gear 600 x control, thrust gear
1; qdot the joint rate at the same state):

- ``work_abs_j``: integral of sum |p| over the three actuators (J), the
  same as ``energy_j``;
- ``work_pos_j``: integral of sum max(p, 0) (J): positive work, what a
  motor without regeneration must supply;
- ``hip_work_abs_j``: the two hips' share of ``work_abs_j`` (J);
- ``power_total_w``: ``work_abs_j`` / cycle duration (W);
- ``joule_hip_n2m2s``, ``joule_thrust_n2s``: Joule-heating proxies, the
  integral of tau^2 dt of the hips (N^2 m^2 s) and of the thrust force
  (N^2 s). Copper loss is R (tau / k_t)^2 for a motor of torque constant
  k_t and winding resistance R: the proxy is the loss up to R / k_t^2,
  which depends on the motor, so hips and thrust are kept apart.

Per run (:func:`run_energetics`, in :func:`mat_hopper.physics.metrics.run_summary`):
the sums over scored hops, ``energy_per_hop_j`` (mean ``work_abs_j``),
``path_length_m`` (the base's planar path, summed sample to sample over
the scored window) and ``cost_of_transport`` = work_abs / (m g path). The
straight start-to-end distance stays as ``distance_m``; on the circle it is
nearly zero, so the cost of transport over it meant nothing.

Integrals are Riemann sums over the recorded samples (each sample's power
held for one record interval). ``tests/physics/test_energetics.py`` checks
``work_abs_j`` against MuJoCo's own ``actuator_force * actuator_velocity``
integrated by a plain ``mj_step`` loop.
"""

from __future__ import annotations

import numpy as np

from ..core import reference as ref
from ..util.parsing import is_real

HOP_COLUMNS = ("work_abs_j", "work_pos_j", "hip_work_abs_j", "power_total_w", "joule_hip_n2m2s", "joule_thrust_n2s")


def actuator_power_w(rollout) -> np.ndarray:
    """Mechanical power of each actuator (W), joint torque x joint rate.

    Args:
        rollout: a :class:`mat_hopper.core.sim.Rollout`.

    Returns:
        (n, 3) array: hip_y, hip_x, thrust, per recorded sample.
    """
    hips = rollout.hip_power
    thrust = rollout.thrust_force * rollout["foot_spring_rate"]
    return np.column_stack([hips, thrust])


def _segment_sums(values: np.ndarray, i0: np.ndarray, i1: np.ndarray) -> np.ndarray:
    csum = np.concatenate([[0.0], np.cumsum(values)])
    return csum[i1] - csum[i0]


def hop_energetics(rollout, i0: np.ndarray, i1: np.ndarray, dt_rec_s: float) -> dict:
    """The per-hop energetics (module doc) of the cycles [i0, i1) of samples.

    Args:
        rollout: a Rollout.
        i0, i1: (k,) sample indices where each cycle starts and ends.
        dt_rec_s: the record interval (s).

    Returns:
        dict of :data:`HOP_COLUMNS`, each a (k,) array.
    """
    p = actuator_power_w(rollout)
    tau_hip = rollout.hip_torque
    f = rollout.thrust_force
    work = _segment_sums(np.abs(p).sum(axis=1), i0, i1) * dt_rec_s
    duration = np.maximum(i1 - i0, 1) * dt_rec_s
    return {
        "work_abs_j": work,
        "work_pos_j": _segment_sums(np.clip(p, 0.0, None).sum(axis=1), i0, i1) * dt_rec_s,
        "hip_work_abs_j": _segment_sums(np.abs(p[:, :2]).sum(axis=1), i0, i1) * dt_rec_s,
        "power_total_w": work / duration,
        "joule_hip_n2m2s": _segment_sums((tau_hip**2).sum(axis=1), i0, i1) * dt_rec_s,
        "joule_thrust_n2s": _segment_sums(f**2, i0, i1) * dt_rec_s,
    }


def path_length_m(rollout, t0_s: float, t1_s: float) -> float:
    """Length (m) of the base's planar path between two times: the sum of
    sample-to-sample distances in x, y.

    Args:
        rollout: a Rollout.
        t0_s, t1_s: the window (s), finite numbers.

    Returns:
        float, m (0 for an empty window, t1_s <= t0_s).

    Raises:
        ValueError: a bound that is not a finite number (nan gave an empty
            window, 0 m, silently).
    """
    for name, v in (("t0_s", t0_s), ("t1_s", t1_s)):
        if not is_real(v) or not np.isfinite(v):
            raise ValueError(f"{name} must be a finite number of seconds, got {v!r}")
    t = rollout.time
    a, b = np.searchsorted(t, [t0_s, t1_s])
    b = min(b, len(t) - 1)
    if b <= a:
        return 0.0
    xy = rollout.base_pos[a : b + 1, :2]
    return float(np.hypot(*np.diff(xy, axis=0).T).sum())


def run_energetics(hops, rollout) -> dict:
    """Run-level energetics over the scored hops (module doc).

    Args:
        hops: the run's :func:`mat_hopper.physics.metrics.hop_table`.
        rollout: the Rollout.

    Returns:
        dict: work_abs_j, work_pos_j, hip_work_abs_j, joule_hip_n2m2s,
        joule_thrust_n2s (sums, J / N^2 m^2 s / N^2 s), energy_per_hop_j (J),
        thrust_work_fraction, path_length_m, distance_m (straight, m),
        cost_of_transport (over the path; nan below 1 mm of path).
    """
    nan = float("nan")
    keys = ("work_abs_j", "work_pos_j", "hip_work_abs_j", "joule_hip_n2m2s", "joule_thrust_n2s")
    if len(hops) == 0:
        return {
            **dict.fromkeys(keys, nan),
            "energy_per_hop_j": nan,
            "thrust_work_fraction": nan,
            "path_length_m": nan,
            "distance_m": nan,
            "cost_of_transport": nan,
        }
    out = {k: float(hops[k].sum()) for k in keys}
    out["energy_per_hop_j"] = float(hops["work_abs_j"].mean())
    out["thrust_work_fraction"] = 1.0 - out["hip_work_abs_j"] / out["work_abs_j"] if out["work_abs_j"] > 0 else nan
    t0, t1 = float(hops["t_start_s"].iloc[0]), float(hops["t_end_s"].iloc[-1])
    path = path_length_m(rollout, t0, t1)
    t = rollout.time
    a, b = np.searchsorted(t, [t0, t1])
    b = min(b, len(t) - 1)
    out["path_length_m"] = path
    out["distance_m"] = float(np.hypot(*np.diff(rollout.base_pos[[a, b], :2], axis=0)[0]))
    weight = rollout.total_mass_kg * ref.GRAVITY_M_S2
    out["cost_of_transport"] = out["work_abs_j"] / (weight * path) if path > 1e-3 else nan
    return out
