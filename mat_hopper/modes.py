"""The leg's axial modes and the analytic stable time step (pure physics).

The leg along its axis is a chain of lumped masses joined by springs
(:func:`leg_chain`, read from the compiled model): the base with the stub
and the upper half of segment 1; the lower half of segment i with the upper
half of segment i+1; the last lower half with the foot's upper capsule;
the foot below the foot spring. Its natural frequencies solve
K v = w^2 M v (``scipy.linalg.eigh(K, M)``).

Modes against the continuum (:func:`axial_modes`). The material part of the
leg is a uniform rod of length L = 0.3 m, mass m (mass per length m / L)
and axial stiffness E A (``axial`` convention: each of N segments is a
spring E A N / L). Boundary conditions: the rod carries the point mass
M_top of everything above it (base, hips, stub) at its top end and M_bot
of the foot's upper capsule at its lower end; the foot below the foot
spring is left out of both (8000 N/m against the material's 1e8-1e10 N/m:
its mode lies near 20 Hz, apart from the kHz material modes). The chain
is then N springs between N + 1 nodes: M_top + m / 2N, m / N (N - 1
times), m / 2N + M_bot: the lumped-mass finite-element model of the same
rod. The rod's axial frequencies w = z c / L, c = sqrt(E A L / m), solve

    (a1 a2 z^2 - 1) sin z = (a1 + a2) z cos z,   a1 = M_top / m, a2 = M_bot / m

(a free-free rod with end masses; a1 = a2 = 0 gives z = n pi; see e.g.
S. S. Rao, *Vibration of Continuous Systems*, 2nd ed., Wiley 2019, ch. 9,
longitudinal vibration of bars with end masses). The chain converges to
the rod as 1/N^2 (free-free lumped mass: w_n = (2N c / L) sin(n pi / 2N)).

Stable time step (:func:`estimate_timestep`, :func:`controller_timestep`,
:func:`auto_substeps`). MuJoCo's Euler integrator treats joint damping
implicitly but springs explicitly (semi-implicit Euler): stable for
w_max dt < 2. The controller's stance rate feedback is a second,
material-independent limit on the *control* period (see
:func:`controller_timestep`).
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pandas as pd
import scipy.linalg
import scipy.optimize

from . import reference as ref
from .control import DEFAULT_SENSOR_TIMING, SensorTiming
from .materials import (
    AXIAL_CONVENTIONS,
    BENDING_CONVENTIONS,
    DEFAULT_CONVENTION,
    DEFAULT_SEGMENT_MASS,
    MAX_SEGMENTS,
    LegDesign,
    check_convention,
    second_moment_m4,
    segment_masses,
)
from .model import (
    BEND_SPRINGS,
    FOOT_GEOM,
    FOOT_UPPER_GEOM,
    MAX_TIMESTEP_S,
    MIN_TIMESTEP_S,
    START_KEY,
    build_model,
    build_spec,
)
from .parsing import check_positive

# --timestep auto: the physics step is at most this fraction of the spring
# chain's explicit bound 2 / w_max (the measured stable steps lie at 0.92 of
# the bound in the median, and within a factor 2 everywhere: docs/).
AUTO_SAFETY = 0.5


def chain_frequencies(masses_kg, stiffnesses_n_m) -> np.ndarray:
    """All natural frequencies (rad/s, ascending, the rigid-body 0 first)
    of a free-free chain of masses (kg) joined in series by springs (N/m;
    len(masses) - 1 of them): eigenvalues of K v = w^2 M v.

    Args:
        masses_kg: the n >= 2 lumped masses, kg, in chain order (1-D).
        stiffnesses_n_m: the n - 1 springs, N/m; spring i joins masses i and
            i + 1.

    Returns:
        (n,) array of w, rad/s, ascending; the first is the rigid-body mode
        (0 up to round-off: negative eigenvalues are clipped to 0).

    Raises:
        ValueError: fewer than 2 masses, masses not 1-D, a spring count other
            than n - 1, or a mass or stiffness not finite and > 0.
    """
    m = np.asarray(masses_kg, dtype=float)
    k = np.asarray(stiffnesses_n_m, dtype=float)
    if m.ndim != 1 or len(m) < 2 or len(k) != len(m) - 1:
        raise ValueError(f"a chain needs n >= 2 masses and n - 1 springs, got {len(m)} and {len(k)}")
    if not (np.all(np.isfinite(m)) and np.all(m > 0) and np.all(np.isfinite(k)) and np.all(k > 0)):
        raise ValueError("masses (kg) and stiffnesses (N/m) must be finite and > 0")
    K = np.zeros((len(m), len(m)))
    for i, ki in enumerate(k):
        K[i, i] += ki
        K[i + 1, i + 1] += ki
        K[i, i + 1] -= ki
        K[i + 1, i] -= ki
    w2 = scipy.linalg.eigh(K, np.diag(m), eigvals_only=True)
    return np.sqrt(np.clip(w2, 0.0, None))


def spring_chain_wmax(masses_kg, stiffnesses_n_m) -> float:
    """Highest natural frequency (rad/s) of a free-free chain of masses
    (kg) joined in series by springs (N/m; len(masses) - 1 of them).

    Args:
        masses_kg: the n >= 2 lumped masses, kg, in chain order.
        stiffnesses_n_m: the n - 1 springs between them, N/m.

    Returns:
        w_max, rad/s, a float (the largest of :func:`chain_frequencies`).

    Raises:
        ValueError: as :func:`chain_frequencies` (a malformed chain, or a
            mass or stiffness not finite and > 0).
    """
    return float(chain_frequencies(masses_kg, stiffnesses_n_m).max())


def leg_chain(
    design: LegDesign, convention: str = DEFAULT_CONVENTION, segment_mass: str = DEFAULT_SEGMENT_MASS
) -> tuple[list[float], list[float]]:
    """(masses kg, stiffnesses N/m) of the leg's axial spring chain, from
    the compiled model: base + leg body, segment bodies (merged across
    rigid segments), foot; springs in between, foot spring last.

    Args:
        design: the :class:`~mat_hopper.materials.LegDesign`.
        convention: ``paper`` (default) or ``axial``, any case; the bending
            conventions are refused.
        segment_mass: ``"leg"`` (default) or ``"capsule"``, any case.

    Returns:
        (masses, springs): lists of floats, kg and N/m. masses has one node
        per elastic segment plus two (base + leg body first, the foot body
        last; a rigid segment's body is added to the node above it);
        springs has one fewer: each elastic segment's ``mat_spring_i``, then
        the foot spring.

    Raises:
        ValueError: an unknown or bending convention, or an argument
            :func:`mat_hopper.model.build_model` refuses.
    """
    convention = check_convention(convention)
    if convention in BENDING_CONVENTIONS:
        raise ValueError(
            f"convention {convention!r} has rotational springs: the axial chain does not describe it "
            "(see model_frequencies)"
        )
    m = build_model(design, convention=convention, segment_mass=segment_mass).model
    mass = lambda name: float(m.body_mass[m.body(name).id])
    masses = [mass("base") + mass("leg")]
    springs = []
    for i, seg in enumerate(design.segments, start=1):
        if seg.rigid:
            masses[-1] += mass(f"seg{i}")
        else:
            springs.append(float(m.jnt_stiffness[m.joint(f"mat_spring_{i}").id]))
            masses.append(mass(f"seg{i}"))
    springs.append(float(m.jnt_stiffness[m.joint("spring").id]))
    masses.append(mass("foot"))
    return masses, springs


def delayed_damping_factor(latency_steps: int) -> float:
    """c(L) = 2 cos(L pi / (2 L + 1)): the explicit time-step limit h < c / a
    of a rate feedback w' = -a w read L steps late, i.e. of the difference
    equation w[n+1] = w[n] - a h w[n-L]. c(0) = 2 (plain explicit Euler),
    c(1) = 1 (the authors' one-step-old gyro), c(L) ~ pi / (2 L) for large L.
    Source: S. A. Levin and R. M. May, "A note on difference-delay
    equations", Theoretical Population Biology 9 (1976) 178-187.

    Args:
        latency_steps: the latency L, steps: an integer in [0,
            :data:`mat_hopper.control.MAX_SENSOR_LATENCY_STEPS`] (an int, or
            a float with a whole value).

    Returns:
        c(L), dimensionless, a float in (0, 2].

    Raises:
        ValueError: a bool, a value that is not a whole number, or one
            outside [0, MAX_SENSOR_LATENCY_STEPS] (1000, as
            :class:`mat_hopper.control.SensorTiming`).
    """
    from .control import MAX_SENSOR_LATENCY_STEPS

    ok = not isinstance(latency_steps, bool) and isinstance(latency_steps, (int, float, np.integer, np.floating))
    if not (
        ok
        and math.isfinite(latency_steps)
        and float(latency_steps).is_integer()
        and 0 <= latency_steps <= MAX_SENSOR_LATENCY_STEPS
    ):
        raise ValueError(
            f"latency_steps must be an integer in [0, {MAX_SENSOR_LATENCY_STEPS}] (physics steps), "
            f"got {latency_steps!r}"
        )
    lat = int(latency_steps)
    return 2.0 * math.cos(lat * math.pi / (2 * lat + 1))


def controller_timestep(
    design: LegDesign,
    convention: str = DEFAULT_CONVENTION,
    stance_kd: float = ref.STANCE_KD,
    gear: float = ref.HIP_GEAR,
    sensor_timing: str | int = DEFAULT_SENSOR_TIMING,
) -> float:
    """c(L) I / (stance_kd gear) in s: the explicit limit of the stance rate
    feedback, I (kg m^2) the base's smallest moment of inertia about a
    horizontal axis through its origin (the hip), from the compiled model,
    and c(L) the factor of :func:`delayed_damping_factor` for the sensor
    timing's latency L (2 when fresh, 1 for the authors' one-step lag).
    Under a bending convention the smaller of this and
    :func:`hip_flight_timestep`.

    Args:
        design: the :class:`~mat_hopper.materials.LegDesign`.
        convention: the stiffness convention, any case (default
            ``paper``); under ``bending`` or ``axial+bending`` the hip flight
            limit is added.
        stance_kd: the stance attitude D gain, per rad/s before the gear
            (default the reference's, 1); finite and > 0.
        gear: the hip actuators' gear (default 600); finite and > 0.
        sensor_timing: the controller's sensor timing, a name or an integer
            latency L (:class:`mat_hopper.control.SensorTiming`; default
            ``"authors"``).

    Returns:
        The control-period limit, s.

    Raises:
        ValueError: an unknown convention or sensor timing, `stance_kd` or
            `gear` not a finite number > 0, or an argument
            :func:`mat_hopper.model.build_model` refuses.
    """
    convention = check_convention(convention)
    stance_kd = check_positive(stance_kd, "stance_kd", "per rad/s")
    gear = check_positive(gear, "gear")
    timing = SensorTiming(sensor_timing)
    m = build_model(design, convention=convention).model
    b = m.body("base").id
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, m.body_iquat[b])
    rot = rot.reshape(3, 3)
    inertia = rot @ np.diag(m.body_inertia[b]) @ rot.T  # about the base COM, world axes at rest
    offset = m.body_ipos[b]
    mass = m.body_mass[b]
    parallel = mass * (offset @ offset * np.eye(3) - np.outer(offset, offset))  # to the hip (base origin)
    inertia = inertia + parallel
    factor = delayed_damping_factor(int(timing))
    limit = factor * min(inertia[0, 0], inertia[1, 1]) / (stance_kd * gear)
    if convention in BENDING_CONVENTIONS:
        limit = min(limit, hip_flight_timestep(design, convention, gear=gear))
    return limit


def hip_flight_timestep(
    design: LegDesign, convention: str = "bending", flight_kd: float | None = None, gear: float = ref.HIP_GEAR
) -> float:
    """2 I / (flight_kd gear) in s (issue 21): the explicit limit of the
    hips' flight PD damping on a leg that bends. The hips are read fresh
    (c(0) = 2); I (kg m^2) is the hip_y dof's inertia with the bending
    hinges free, 1 / (M^-1)_hh over the hip and hinge dofs of MuJoCo's
    mass matrix at the start pose (what the hip moves first when the
    segments below can bend). Conservative for stiff hinges, whose modes
    are faster than the control; binding for soft ones (trabecular bone:
    5.8e-5 s, under the authors' 1e-4 s control period).

    Args:
        design: the :class:`~mat_hopper.materials.LegDesign`.
        convention: the stiffness convention the model is built with, any
            case (default ``"bending"``); with no bending hinges I is the
            hip_y dof's own 1 / (M^-1)_hh.
        flight_kd: the flight PD's D gain, per rad/s before the gear, finite
            and > 0; None (default) takes
            :class:`mat_hopper.control.ControllerSettings`'s ``flight_kd``
            (0.1).
        gear: the hip actuators' gear (default 600); finite and > 0.

    Returns:
        The limit, s.

    Raises:
        ValueError: `flight_kd` or `gear` not a finite number > 0, or an
            argument :func:`mat_hopper.model.build_model` refuses.
    """
    from .control import ControllerSettings

    kd = ControllerSettings().flight_kd if flight_kd is None else check_positive(flight_kd, "flight_kd", "per rad/s")
    gear = check_positive(gear, "gear")
    model = build_model(design, convention=convention).model
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(START_KEY).id)
    mujoco.mj_forward(model, data)
    full = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, full)
    hip = int(model.joint("hip_y").dofadr[0])
    hinges = [int(model.joint(n.format(i=i)).dofadr[0]) for i in range(1, design.n_segments + 1) for n in BEND_SPRINGS
              if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, n.format(i=i)) >= 0]  # fmt: skip
    idx = [hip, *hinges]
    inertia = 1.0 / np.linalg.inv(full[np.ix_(idx, idx)])[0, 0]
    return 2.0 * inertia / (kd * gear)


def _sprung_eig(model: mujoco.MjModel, dofs=None) -> np.ndarray:
    """Natural frequencies (rad/s, ascending) of the linearised model at its
    start pose: eigh(K, M) with M MuJoCo's joint-space inertia (mj_fullM)
    and K the diagonal of joint stiffnesses; restricted to ``dofs`` (all
    others held) if given."""
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(START_KEY).id)
    mujoco.mj_forward(model, data)
    full = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, full)
    k = np.array([model.jnt_stiffness[model.dof_jntid[v]] for v in range(model.nv)])
    idx = np.arange(model.nv) if dofs is None else np.asarray(dofs)
    w2 = scipy.linalg.eigh(np.diag(k[idx]), full[np.ix_(idx, idx)], eigvals_only=True)
    return np.sqrt(np.clip(w2, 0.0, None))


def model_frequencies(
    design: LegDesign, convention: str = DEFAULT_CONVENTION, segment_mass: str = DEFAULT_SEGMENT_MASS
) -> np.ndarray:
    """All natural frequencies (rad/s, ascending) of the whole compiled
    hopper, linearised at its start pose (free base: the rigid-body zeros
    first): axial, rotational (bending hinges, hips) and foot spring
    together. What the stable step of the ``bending`` conventions uses.

    Args:
        design: the :class:`~mat_hopper.materials.LegDesign`.
        convention: the stiffness convention, any case (default ``paper``).
        segment_mass: ``"leg"`` (default) or ``"capsule"``, any case.

    Returns:
        (nv,) array of w, rad/s, ascending (nv: the model's degrees of
        freedom; negative eigenvalues clipped to 0).

    Raises:
        ValueError: an unknown convention, or an argument
            :func:`mat_hopper.model.build_model` refuses.
    """
    convention = check_convention(convention)
    return _sprung_eig(build_model(design, convention=convention, segment_mass=segment_mass).model)


def estimate_timestep(
    design: LegDesign, convention: str = DEFAULT_CONVENTION, segment_mass: str = DEFAULT_SEGMENT_MASS
) -> tuple[float, float]:
    """(w_max rad/s, 2 / w_max s): the explicit-spring stability limit.
    ``paper``, ``axial``: the axial spring chain (:func:`leg_chain`);
    ``bending``, ``axial+bending``: the whole model's highest mode, the
    rotational ones included (:func:`model_frequencies`).

    Args:
        design: the :class:`~mat_hopper.materials.LegDesign`.
        convention: the stiffness convention, any case (default
            ``paper``); the whole model is used under ``bending`` and
            ``axial+bending``.
        segment_mass: ``"leg"`` (default) or ``"capsule"``, any case.

    Returns:
        (w_max, dt_max): the highest natural frequency, rad/s, and the
        explicit bound 2 / w_max, s.

    Raises:
        ValueError: an unknown convention, or an argument
            :func:`mat_hopper.model.build_model` refuses.
    """
    convention = check_convention(convention)
    if convention in BENDING_CONVENTIONS:
        w = float(model_frequencies(design, convention, segment_mass).max())
    else:
        w = spring_chain_wmax(*leg_chain(design, convention, segment_mass))
    return w, 2.0 / w


def auto_control_period(
    design: LegDesign,
    convention: str = DEFAULT_CONVENTION,
    sensor_timing: str | int = DEFAULT_SENSOR_TIMING,
    control_period_s: float = ref.TIMESTEP_S,
    safety: float = AUTO_SAFETY,
) -> float:
    """The controller's period under ``timestep_s="auto"``, s.

    The authors' period (1e-4 s) unless the controller's own explicit limit
    (:func:`controller_timestep`: its delayed stance damping, and under a
    bending convention its hips' flight damping) lies below it; then
    control_period_s / k with the smallest k whose period is at most
    ``safety`` x that limit. Physics substeps cannot help a controller
    limit: the torque is held over the whole control period. Binds for soft
    legs that bend (trabecular bone: limit 5.8e-5 s under ``bending``, so
    2.5e-5 s), never for the paper's designs under ``paper``/``axial``
    (2.1e-4 s under the authors' sensor timing).

    Args:
        design: the leg.
        convention: the stiffness convention, any case.
        sensor_timing: the controller's sensor timing (its latency shrinks
            the stance limit, :func:`delayed_damping_factor`).
        control_period_s: the authors' period, s, in (0, 0.1]
            (:data:`mat_hopper.model.MAX_TIMESTEP_S`).
        safety: the fraction of the limit a shortened period may reach, in
            (0, 1].

    Returns:
        The control period, s.

    Raises:
        ValueError: `control_period_s` or `safety` out of its range, or as
            :func:`controller_timestep` raises.
    """
    control_period_s = check_positive(control_period_s, "control_period_s", "s", MAX_TIMESTEP_S)
    safety = check_positive(safety, "safety", high=1.0)
    limit = controller_timestep(design, convention, sensor_timing=sensor_timing)
    if limit >= control_period_s:
        return control_period_s
    return control_period_s / math.ceil(control_period_s / (safety * limit) - 1e-9)


def auto_substeps(
    design: LegDesign,
    convention: str = DEFAULT_CONVENTION,
    segment_mass: str = DEFAULT_SEGMENT_MASS,
    control_period_s: float | None = None,
    safety: float = AUTO_SAFETY,
    sensor_timing: str | int = DEFAULT_SENSOR_TIMING,
) -> tuple[int, float, float]:
    """(substeps k, physics step s, spring bound s) of ``timestep_s="auto"``.

    The control period is :func:`auto_control_period` (the authors' 1e-4 s
    unless the controller's own limit is smaller) when ``control_period_s``
    is None; the physics takes the smallest k whose step control_period / k
    is at most ``safety`` x the springs' explicit bound 2 / w_max
    (:func:`estimate_timestep`).

    Args:
        design: the :class:`~mat_hopper.materials.LegDesign`.
        convention: the stiffness convention, any case (default ``paper``).
        segment_mass: ``"leg"`` (default) or ``"capsule"``, any case.
        control_period_s: the control period, s, in [1e-6, 0.1]
            (:data:`mat_hopper.model.MIN_TIMESTEP_S`, the smallest physics
            step the package plans, to ``MAX_TIMESTEP_S``); None (default)
            takes :func:`auto_control_period`'s.
        safety: the fraction of each explicit bound a step may reach, in
            (0, 1] (default :data:`AUTO_SAFETY`, 0.5).
        sensor_timing: the controller's sensor timing (read only when
            `control_period_s` is None; default ``"authors"``).

    Returns:
        (k, dt, bound): the substeps per control period (an int >= 1), the
        physics step control_period / k, s, and the springs' bound
        2 / w_max, s.

    Raises:
        ValueError: `control_period_s` or `safety` out of its range, more
            than 1000 substeps needed, or as :func:`estimate_timestep` and
            :func:`controller_timestep` raise (unknown convention, segment
            mass or sensor timing).
    """
    safety = check_positive(safety, "safety", high=1.0)
    if control_period_s is not None:
        control_period_s = check_positive(control_period_s, "control_period_s", "s", MAX_TIMESTEP_S)
        if control_period_s < MIN_TIMESTEP_S:
            raise ValueError(
                f"control_period_s must be in [{MIN_TIMESTEP_S:g}, {MAX_TIMESTEP_S:g}] s (MIN_TIMESTEP_S, the "
                f"smallest physics step the package plans), got {control_period_s!r}"
            )
    if control_period_s is None:
        control_period_s = auto_control_period(design, convention, sensor_timing, safety=safety)
    _, bound = estimate_timestep(design, convention, segment_mass)
    k = max(1, math.ceil(control_period_s / (safety * bound) - 1e-9))
    if k > 1000:
        raise ValueError(
            f"--timestep auto would need {k} physics substeps per {control_period_s:g} s control "
            f"period (spring bound {bound:.2g} s): over the limit of 1000"
        )
    return k, control_period_s / k, bound


def _check_mode_args(design, n_modes) -> int:
    """`n_modes` as an int in [1, MAX_SEGMENTS] (a chain of N <= 64 springs
    has at most N modes), after checking `design` is a LegDesign; ValueError else."""
    if not isinstance(design, LegDesign):
        raise ValueError(f"design must be a LegDesign, got {type(design).__name__}")
    if isinstance(n_modes, bool) or not isinstance(n_modes, (int, np.integer)) or not 1 <= n_modes <= MAX_SEGMENTS:
        raise ValueError(f"n_modes must be an integer in [1, {MAX_SEGMENTS}], got {n_modes!r}")
    return int(n_modes)


def _rod_roots(a1: float, a2: float, n_modes: int) -> np.ndarray:
    """The first n_modes positive roots z of (a1 a2 z^2 - 1) sin z =
    (a1 + a2) z cos z (module doc), bracketed on a fine grid then refined
    with Brent's method (scipy.optimize.brentq)."""
    f = lambda z: (a1 * a2 * z * z - 1.0) * math.sin(z) - (a1 + a2) * z * math.cos(z)
    roots, z0 = [], 1e-6
    grid = np.linspace(z0, (n_modes + 2) * math.pi, 200 * (n_modes + 2))
    vals = [f(z) for z in grid]
    for (za, fa), (zb, fb) in zip(zip(grid, vals), zip(grid[1:], vals[1:])):
        if fa == 0.0 or fa * fb < 0:
            roots.append(scipy.optimize.brentq(f, za, zb, xtol=1e-14) if fa * fb < 0 else za)
            if len(roots) == n_modes:
                break
    return np.array(roots)


def axial_modes(
    design: LegDesign, *, convention: str = "axial", segment_mass: str = DEFAULT_SEGMENT_MASS, n_modes: int = 5
) -> pd.DataFrame:
    """The leg's first n_modes axial natural frequencies (Hz): the lumped
    chain's (``chain_hz``, eigh(K, M) of the compiled model's masses) beside
    the continuum rod's (``rod_hz``) with the same mass per length, E A and
    end masses (module doc). Columns: mode, chain_hz, rod_hz, error_pct.

    Needs a leg of one material (a uniform rod): raises ValueError for a
    graded or rigid design. Under the ``paper`` convention the chain's
    springs are the authors' (not E A N / L) and the comparison says how
    far that leg is from the rod of its modulus.

    Args:
        design: a leg of one elastic material (every segment the same
            density and modulus).
        convention: the stiffness convention with axial slides, any case
            (default ``"axial"``; ``"paper"`` as above; ``"axial+bending"``
            reads its slides; ``"bending"``, which has none, is refused).
        segment_mass: ``"leg"`` (default) or ``"capsule"``, any case.
        n_modes: how many modes to compare (default 5).

    Returns:
        DataFrame, one row per mode, at most min(n_modes, N) rows (the
        chain of N springs has N elastic modes): mode (1, 2, ...), chain_hz
        and rod_hz (Hz), error_pct (100 (chain / rod - 1), %).

    Raises:
        ValueError: an unknown convention, the ``bending`` convention (its
            model has no axial slides ``mat_spring_i`` to read), a graded or
            rigid design (or not a LegDesign), `n_modes` not an integer in
            [1, 64], or an argument
            :func:`mat_hopper.model.build_model` refuses.
    """
    n_modes = _check_mode_args(design, n_modes)
    convention = check_convention(convention)
    if convention not in AXIAL_CONVENTIONS:
        raise ValueError(
            f"axial modes need a convention with axial slides ({', '.join(AXIAL_CONVENTIONS)}), got {convention!r}"
        )
    mats = set(design.segments)
    if len({(m.density_g_cm3, m.modulus_gpa) for m in mats}) != 1 or design.segments[0].rigid:
        raise ValueError(
            "axial modes against a uniform rod need a leg of one elastic material "
            f"(got {design.name or 'a graded or rigid leg'})"
        )
    n = design.n_segments
    model = build_model(design, convention=convention, segment_mass=segment_mass).model
    body = lambda name: float(model.body_mass[model.body(name).id])
    seg = list(segment_masses(design, segment_mass))
    m_rod = float(sum(seg))
    # end masses: what the model attaches above and below the material
    m_top = body("base") + body("leg") - seg[0] / 2.0
    m_bot = body(f"seg{n}") - seg[-1] / 2.0
    masses = [m_top + seg[0] / 2.0] + [(seg[i] + seg[i + 1]) / 2.0 for i in range(n - 1)] + [seg[-1] / 2.0 + m_bot]
    springs = [float(model.jnt_stiffness[model.joint(f"mat_spring_{i}").id]) for i in range(1, n + 1)]
    w_chain = chain_frequencies(masses, springs)[1 : n_modes + 1]
    mat = design.segments[0]
    ea = mat.modulus_pa * math.pi * ref.MATERIAL_RADIUS**2
    c = math.sqrt(ea * ref.MATERIAL_LENGTH / m_rod)  # m/s, sqrt(E A / mu)
    z = _rod_roots(m_top / m_rod, m_bot / m_rod, n_modes)
    w_rod = z * c / ref.MATERIAL_LENGTH
    k = min(len(w_chain), len(w_rod))
    out = pd.DataFrame(
        {"mode": np.arange(1, k + 1), "chain_hz": w_chain[:k] / (2 * math.pi), "rod_hz": w_rod[:k] / (2 * math.pi)}
    )
    out["error_pct"] = 100.0 * (out["chain_hz"] / out["rod_hz"] - 1.0)
    return out


# Euler-Bernoulli clamped-free beam: the first roots of 1 + cos b cosh b = 0
# (b = beta_n L; e.g. S. S. Rao, Vibration of Continuous Systems, 2nd ed.,
# Wiley 2019, ch. 11, table 11.1): 1.8751, 4.6941, 7.8548, 10.9955, 14.1372.
CANTILEVER_BETA_L = (1.8751040687, 4.6940911330, 7.8547574382, 10.9955407349, 14.1371683910)


def _cantilever_roots(n_modes: int) -> np.ndarray:
    f = lambda b: 1.0 + math.cos(b) * math.cosh(b)
    out = []
    for n in range(1, n_modes + 1):
        guess = (n - 0.5) * math.pi
        out.append(scipy.optimize.brentq(f, guess - 1.0, guess + 1.0, xtol=1e-14) if n > 1 else 1.8751040687)
    return np.array(out)


def bending_modes(
    design: LegDesign,
    *,
    convention: str = "bending",
    segment_mass: str = DEFAULT_SEGMENT_MASS,
    n_modes: int = 5,
) -> pd.DataFrame:
    """The leg's first bending natural frequencies (Hz) in one plane: the
    hinge chain's (``chain_hz``, eigh(K, M) of the compiled model on the
    hinges about x, everything else held: the base, hips and axial slides
    clamp the material's top) beside the continuum Euler-Bernoulli
    clamped-free beam's (``beam_hz`` = (beta_n L)^2 sqrt(E I / (mu L^4)), mu
    the material's mass per length; :data:`CANTILEVER_BETA_L`). The model's
    foot (its upper capsule and the foot body) is made massless (1e-9 kg)
    for the comparison: the beam has no tip mass. The chain keeps the
    capsules' rotary inertia, which the Euler-Bernoulli beam leaves out.
    Columns: mode, chain_hz, beam_hz, error_pct.

    Needs a leg of one elastic material under a bending convention: raises
    ValueError otherwise.

    Args:
        design: a leg of one elastic material (every segment the same
            density and modulus).
        convention: ``"bending"`` (default) or ``"axial+bending"``, any
            case.
        segment_mass: ``"leg"`` (default) or ``"capsule"``, any case.
        n_modes: how many modes to compare (default 5).

    Returns:
        DataFrame, one row per mode, at most min(n_modes, N) rows (N hinges
        about x): mode (1, 2, ...), chain_hz and beam_hz (Hz), beta_l (the
        root beta_n L used, dimensionless) and error_pct
        (100 (chain / beam - 1), %).

    Raises:
        ValueError: an unknown convention or one not in
            :data:`~mat_hopper.materials.BENDING_CONVENTIONS`, a graded or
            rigid design (or not a LegDesign), `n_modes` not an integer in
            [1, 64], or an argument :func:`mat_hopper.model.build_spec`
            refuses.
    """
    n_modes = _check_mode_args(design, n_modes)
    convention = check_convention(convention)
    if convention not in BENDING_CONVENTIONS:
        raise ValueError(
            f"bending modes need a bending convention ({', '.join(BENDING_CONVENTIONS)}), got {convention!r}"
        )
    if len({(m.density_g_cm3, m.modulus_gpa) for m in design.segments}) != 1 or design.segments[0].rigid:
        raise ValueError(f"bending modes against a uniform beam need a leg of one elastic material (got {design.name})")
    spec = build_spec(design, convention=convention, segment_mass=segment_mass, sensors="control")
    spec.geom(FOOT_UPPER_GEOM).density = 1e-9 / (math.pi * ref.MATERIAL_RADIUS**2 * ref.FOOT_UPPER_LENGTH)
    spec.geom(FOOT_GEOM).mass = 1e-9
    model = spec.compile()
    n = design.n_segments
    dofs = [int(model.joint(BEND_SPRINGS[0].format(i=i)).dofadr[0]) for i in range(1, n + 1)]
    w_chain = _sprung_eig(model, dofs)[:n_modes]
    mat = design.segments[0]
    mu = float(sum(segment_masses(design, segment_mass))) / ref.MATERIAL_LENGTH
    ei = mat.modulus_pa * second_moment_m4()
    beta_l = _cantilever_roots(n_modes)
    w_beam = beta_l**2 * math.sqrt(ei / (mu * ref.MATERIAL_LENGTH**4))
    k = min(len(w_chain), n_modes)
    out = pd.DataFrame(
        {
            "mode": np.arange(1, k + 1),
            "chain_hz": w_chain[:k] / (2 * math.pi),
            "beam_hz": w_beam[:k] / (2 * math.pi),
            "beta_l": beta_l[:k],
        }
    )
    out["error_pct"] = 100.0 * (out["chain_hz"] / out["beam_hz"] - 1.0)
    return out
