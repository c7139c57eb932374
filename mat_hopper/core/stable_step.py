"""The analytic stable time step of the hopper (pure physics, before any run).

The leg along its axis is a chain of lumped masses joined by springs
(:func:`leg_chain`): the base with the stub
and the upper half of segment 1; the lower half of segment i with the upper
half of segment i+1; the last lower half with the foot's upper capsule;
the foot below the foot spring. Its natural frequencies solve
K v = w^2 M v (``scipy.linalg.eigh(K, M)``). Masses, inertias and
stiffnesses come from the design without compiling a model
(:class:`mat_hopper.core.lumped.LumpedHopper`, the compiled model's numbers
to round-off): resolving ``--timestep auto`` builds settings, not a model.

MuJoCo's Euler integrator treats joint damping implicitly but springs
explicitly (semi-implicit Euler): stable for w_max dt < 2
(:func:`estimate_timestep`). The controller's stance rate feedback is a
second, material-independent limit on the *control* period
(:func:`controller_timestep`); :func:`auto_substeps` combines both for
``--timestep auto``. The continuum modes are in
:mod:`mat_hopper.physics.modes`.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
import scipy.linalg
import scipy.optimize

from ..util.parsing import check_positive, is_real
from . import reference as ref
from .contact import DEFAULT_CONTACT, contact_max_timestep
from .controller import DEFAULT_SENSOR_TIMING, SensorTiming
from .flight_loop import PERIOD_MARGIN, flight_loop_stable
from .lumped import LumpedHopper
from .materials import (
    BENDING_CONVENTIONS,
    DEFAULT_CONVENTION,
    DEFAULT_SEGMENT_MASS,
    LegDesign,
)
from .model import (
    BASE_BODY,
    BEND_SPRINGS,
    HIP_JOINTS,
    MAX_TIMESTEP_S,
    MIN_TIMESTEP_S,
    START_KEY,
)

# --timestep auto: the physics step is at most this fraction of the spring
# chain's explicit bound 2 / w_max (the measured stable steps lie at 0.92 of
# the bound in the median, and within a factor 2 everywhere: docs/).
AUTO_SAFETY = 0.5
MAX_CONTROL_DIVISIONS = 64  # auto shortens the control period at most to 1/64 of the authors' (1.6e-6 s)


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
    """(masses kg, stiffnesses N/m) of the leg's axial spring chain: base
    + leg body, segment bodies (merged across rigid segments), foot;
    springs in between, foot spring last. Computed from the design
    (:meth:`mat_hopper.core.lumped.LumpedHopper.axial_chain`), no model
    compiled: the compiled model's ``body_mass`` and ``jnt_stiffness``.

    Args:
        design: the :class:`~mat_hopper.core.materials.LegDesign`.
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
        ValueError: a design that is not a LegDesign, an unknown segment
            mass, or an unknown or bending convention.
    """
    return LumpedHopper(design, convention, segment_mass).axial_chain()


def delayed_damping_factor(latency_steps: int) -> float:
    """c(L) = 2 cos(L pi / (2 L + 1)): the explicit time-step limit h < c / a
    of a rate feedback w' = -a w read L steps late, i.e. of the difference
    equation w[n+1] = w[n] - a h w[n-L]. c(0) = 2 (plain explicit Euler),
    c(1) = 1 (the authors' one-step-old gyro), c(L) ~ pi / (2 L) for large L.
    Source: S. A. Levin and R. M. May, "A note on difference-delay
    equations", Theoretical Population Biology 9 (1976) 178-187.

    Args:
        latency_steps: the latency L, steps: an integer in [0,
            :data:`mat_hopper.core.controller.MAX_SENSOR_LATENCY_STEPS`] (an int, or
            a float with a whole value).

    Returns:
        c(L), dimensionless, a float in (0, 2].

    Raises:
        ValueError: a bool, a value that is not a whole number, or one
            outside [0, MAX_SENSOR_LATENCY_STEPS] (1000, as
            :class:`mat_hopper.core.controller.SensorTiming`).
    """
    from ..core.controller import MAX_SENSOR_LATENCY_STEPS

    ok = is_real(latency_steps)
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
    horizontal axis through its origin (the hip), from its two capsules
    (:class:`mat_hopper.core.lumped.LumpedHopper`), and c(L) the factor of
    :func:`delayed_damping_factor` for the sensor timing's latency L (2
    when fresh, 1 for the authors' one-step lag). Under a bending
    convention the smaller of this and :func:`hip_flight_timestep`.

    Args:
        design: the :class:`~mat_hopper.core.materials.LegDesign`.
        convention: the stiffness convention, any case (default
            ``paper``); under ``bending`` or ``axial+bending`` the hip flight
            limit is added.
        stance_kd: the stance attitude D gain, per rad/s before the gear
            (default the reference's, 1); finite and > 0.
        gear: the hip actuators' gear (default 600); finite and > 0.
        sensor_timing: the controller's sensor timing, a name or an integer
            latency L (:class:`mat_hopper.core.controller.SensorTiming`; default
            ``"authors"``).

    Returns:
        The control-period limit, s.

    Raises:
        ValueError: a design that is not a LegDesign, an unknown convention
            or sensor timing, or `stance_kd` or `gear` not a finite number > 0.
    """
    hopper = LumpedHopper(design, convention)
    stance_kd = check_positive(stance_kd, "stance_kd", "per rad/s")
    gear = check_positive(gear, "gear")
    return _controller_limit(hopper, stance_kd, gear, SensorTiming(sensor_timing))


def _controller_limit(hopper: LumpedHopper, stance_kd: float, gear: float, timing: SensorTiming) -> float:
    """:func:`controller_timestep` of a hopper whose arguments are checked."""
    base = hopper.body(BASE_BODY)
    shift = base.mass_kg * base.com_z_m**2  # parallel axis: centre of mass on the axis, to the hip (base origin)
    ixx, iyy, _ = base.inertia_kg_m2
    limit = delayed_damping_factor(int(timing)) * min(ixx + shift, iyy + shift) / (stance_kd * gear)
    if hopper.convention in BENDING_CONVENTIONS:
        from ..core.controller import ControllerSettings

        limit = min(limit, _hip_flight_limit(hopper, ControllerSettings().flight_kd, gear))
    return limit


def hip_flight_timestep(
    design: LegDesign, convention: str = "bending", flight_kd: float | None = None, gear: float = ref.HIP_GEAR
) -> float:
    """2 I / (flight_kd gear) in s: the explicit limit of the
    hips' flight PD damping on a leg that bends. The hips are read fresh
    (c(0) = 2); I (kg m^2) is the hip_y dof's inertia with the bending
    hinges free, 1 / (M^-1)_hh over the hip and hinge dofs of MuJoCo's
    mass matrix at the start pose (what the hip moves first when the
    segments below can bend). Conservative for stiff hinges, whose modes
    are faster than the control; binding for soft ones (trabecular bone:
    5.8e-5 s, under the authors' 1e-4 s control period).

    Args:
        design: the :class:`~mat_hopper.core.materials.LegDesign`.
        convention: the stiffness convention the model is built with, any
            case (default ``"bending"``); with no bending hinges I is the
            hip_y dof's own 1 / (M^-1)_hh.
        flight_kd: the flight PD's D gain, per rad/s before the gear, finite
            and > 0; None (default) takes
            :class:`mat_hopper.core.controller.ControllerSettings`'s ``flight_kd``
            (0.1).
        gear: the hip actuators' gear (default 600); finite and > 0.

    Returns:
        The limit, s.

    Raises:
        ValueError: a design that is not a LegDesign, an unknown
            convention, or `flight_kd` or `gear` not a finite number > 0.
    """
    from ..core.controller import ControllerSettings

    hopper = LumpedHopper(design, convention)
    kd = ControllerSettings().flight_kd if flight_kd is None else check_positive(flight_kd, "flight_kd", "per rad/s")
    return _hip_flight_limit(hopper, kd, check_positive(gear, "gear"))


def _hip_flight_limit(hopper: LumpedHopper, flight_kd: float, gear: float) -> float:
    """:func:`hip_flight_timestep` of a hopper whose arguments are checked:
    the mass matrix over hip_y and the bending hinges, in MuJoCo's dof order."""
    hinges = {n.format(i=i) for i in range(1, hopper.design.n_segments + 1) for n in BEND_SPRINGS}
    idx = [hopper.dof(HIP_JOINTS[0]), *(i for i, d in enumerate(hopper.dofs) if d.name in hinges)]
    full = hopper.mass_matrix()
    inertia = 1.0 / np.linalg.inv(full[np.ix_(idx, idx)])[0, 0]
    return 2.0 * inertia / (flight_kd * gear)


def sprung_eig(model: mujoco.MjModel, dofs=None) -> np.ndarray:
    """Natural frequencies (rad/s, ascending) of the linearised model at its
    start pose: eigh(K, M) with M MuJoCo's joint-space inertia (mj_fullM)
    and K the diagonal of joint stiffnesses; restricted to ``dofs`` (all
    others held) if given.

    Args:
        model: a compiled hopper ``MjModel`` with the ``start`` keyframe.
        dofs: indices into the model's dofs (qvel) to keep, or None
            (default) for all of them.

    Returns:
        A float array of the natural frequencies, rad/s, ascending, one per
        kept dof (0 for a free or unsprung mode).
    """
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(START_KEY).id)
    mujoco.mj_forward(model, data)
    full = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, full)
    k = np.array([model.jnt_stiffness[model.dof_jntid[v]] for v in range(model.nv)])
    idx = np.arange(model.nv) if dofs is None else np.asarray(dofs)
    return _sprung_frequencies(k[idx], full[np.ix_(idx, idx)])


def _sprung_frequencies(stiffness, mass_matrix) -> np.ndarray:
    """sqrt of the eigenvalues of K v = w^2 M v, K = diag(stiffness), rad/s ascending (negatives clipped to 0)."""
    w2 = scipy.linalg.eigh(np.diag(stiffness), mass_matrix, eigvals_only=True)
    return np.sqrt(np.clip(w2, 0.0, None))


def model_frequencies(
    design: LegDesign, convention: str = DEFAULT_CONVENTION, segment_mass: str = DEFAULT_SEGMENT_MASS
) -> np.ndarray:
    """All natural frequencies (rad/s, ascending) of the whole hopper,
    linearised at its start pose (free base: the rigid-body zeros first):
    axial, rotational (bending hinges, hips) and foot spring together. What
    the stable step of the ``bending`` conventions uses. The mass matrix is
    the compiled model's (``mj_fullM``), computed from the design
    (:meth:`mat_hopper.core.lumped.LumpedHopper.mass_matrix`).

    Args:
        design: the :class:`~mat_hopper.core.materials.LegDesign`.
        convention: the stiffness convention, any case (default ``paper``).
        segment_mass: ``"leg"`` (default) or ``"capsule"``, any case.

    Returns:
        (nv,) array of w, rad/s, ascending (nv: the model's degrees of
        freedom; negative eigenvalues clipped to 0).

    Raises:
        ValueError: a design that is not a LegDesign, or an unknown
            convention or segment mass.
    """
    return _frequencies(LumpedHopper(design, convention, segment_mass))


def _frequencies(hopper: LumpedHopper) -> np.ndarray:
    return _sprung_frequencies(hopper.stiffness(), hopper.mass_matrix())


def estimate_timestep(
    design: LegDesign, convention: str = DEFAULT_CONVENTION, segment_mass: str = DEFAULT_SEGMENT_MASS
) -> tuple[float, float]:
    """(w_max rad/s, 2 / w_max s): the explicit-spring stability limit.
    ``paper``, ``axial``: the axial spring chain (:func:`leg_chain`);
    ``bending``, ``axial+bending``: the whole model's highest mode, the
    rotational ones included (:func:`model_frequencies`).

    Args:
        design: the :class:`~mat_hopper.core.materials.LegDesign`.
        convention: the stiffness convention, any case (default
            ``paper``); the whole model is used under ``bending`` and
            ``axial+bending``.
        segment_mass: ``"leg"`` (default) or ``"capsule"``, any case.

    Returns:
        (w_max, dt_max): the highest natural frequency, rad/s, and the
        explicit bound 2 / w_max, s.

    Raises:
        ValueError: a design that is not a LegDesign, or an unknown
            convention or segment mass.
    """
    return _spring_bound(LumpedHopper(design, convention, segment_mass))


def _spring_bound(hopper: LumpedHopper) -> tuple[float, float]:
    """:func:`estimate_timestep` of a hopper."""
    if hopper.convention in BENDING_CONVENTIONS:
        w = float(_frequencies(hopper).max())
    else:
        w = spring_chain_wmax(*hopper.axial_chain())
    return w, 2.0 / w


def stable_bounds(
    design: LegDesign,
    convention: str = DEFAULT_CONVENTION,
    segment_mass: str = DEFAULT_SEGMENT_MASS,
    stance_kd: float = ref.STANCE_KD,
    sensor_timing: str | int = DEFAULT_SENSOR_TIMING,
) -> tuple[float, float]:
    """(springs' bound s, controller's limit s) of one leg at once: the
    :func:`estimate_timestep` and :func:`controller_timestep` of one
    :class:`~mat_hopper.core.lumped.LumpedHopper` (the convention spelled once).

    Args:
        design: the :class:`~mat_hopper.core.materials.LegDesign`.
        convention: the stiffness convention, any case (default ``paper``).
        segment_mass: ``"leg"`` (default) or ``"capsule"``, any case (the
            springs' bound; the controller's limit is the default segment
            mass's, as :func:`controller_timestep`'s).
        stance_kd: the stance attitude D gain, per rad/s before the gear; finite and > 0.
        sensor_timing: the controller's sensor timing (a name or a latency L).

    Returns:
        (2 / w_max, the control-period limit), both s.

    Raises:
        ValueError: as :func:`estimate_timestep` and :func:`controller_timestep` raise.
    """
    hopper = LumpedHopper(design, convention, segment_mass)
    stance_kd = check_positive(stance_kd, "stance_kd", "per rad/s")
    limit = _controller_limit(_controller_hopper(hopper), stance_kd, ref.HIP_GEAR, SensorTiming(sensor_timing))
    return _spring_bound(hopper)[1], limit


def _controller_hopper(hopper: LumpedHopper) -> LumpedHopper:
    """The hopper the controller's limits are read from: the default segment mass's, as
    :func:`controller_timestep` and :func:`auto_control_period` read them."""
    return hopper if hopper.segment_mass == DEFAULT_SEGMENT_MASS else LumpedHopper(hopper.design, hopper.convention)


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
    (2.1e-4 s under the authors' sensor timing). Under a bending
    convention k grows further until the hips' sampled flight loop is
    stable within +-10 % of the period (:mod:`mat_hopper.core.flight_loop`:
    a stiff leg's bending mode near the control rate aliases and grows).

    Args:
        design: the leg.
        convention: the stiffness convention, any case.
        sensor_timing: the controller's sensor timing (its latency shrinks
            the stance limit, :func:`delayed_damping_factor`).
        control_period_s: the authors' period, s, in (0, 0.1]
            (:data:`mat_hopper.core.model.MAX_TIMESTEP_S`).
        safety: the fraction of the limit a shortened period may reach, in
            (0, 1].

    Returns:
        The control period, s.

    Raises:
        ValueError: `control_period_s` or `safety` out of its range, or as
            :func:`controller_timestep` raises.
    """
    hopper = LumpedHopper(design, convention)
    control_period_s = check_positive(control_period_s, "control_period_s", "s", MAX_TIMESTEP_S)
    safety = check_positive(safety, "safety", high=1.0)
    return _control_period(hopper, SensorTiming(sensor_timing), control_period_s, safety)


def _control_period(hopper: LumpedHopper, timing: SensorTiming, control_period_s: float, safety: float) -> float:
    """:func:`auto_control_period` of a hopper whose arguments are checked."""
    limit = _controller_limit(hopper, ref.STANCE_KD, ref.HIP_GEAR, timing)
    k = 1 if limit >= control_period_s else math.ceil(control_period_s / (safety * limit) - 1e-9)
    if hopper.convention in BENDING_CONVENTIONS:  # no bending mode in resonance with the hips' flight PD
        while k < MAX_CONTROL_DIVISIONS and not flight_loop_stable(hopper, control_period_s / k, PERIOD_MARGIN):
            k += 1
    return control_period_s / k


def auto_substeps(
    design: LegDesign,
    convention: str = DEFAULT_CONVENTION,
    segment_mass: str = DEFAULT_SEGMENT_MASS,
    control_period_s: float | None = None,
    safety: float = AUTO_SAFETY,
    sensor_timing: str | int = DEFAULT_SENSOR_TIMING,
    contact: str = DEFAULT_CONTACT,
) -> tuple[int, float, float]:
    """(substeps k, physics step s, spring bound s) of ``timestep_s="auto"``.

    The control period is :func:`auto_control_period` (the authors' 1e-4 s
    unless the controller's own limit is smaller) when ``control_period_s``
    is None; the physics takes the smallest k whose step control_period / k
    is at most ``safety`` x the springs' explicit bound 2 / w_max
    (:func:`estimate_timestep`) and at most half the contact's time
    constant (:func:`mat_hopper.core.contact.contact_max_timestep`: MuJoCo
    uses max(solref[0], 2*timestep), XML reference, option/flag refsafe).

    Args:
        design: the :class:`~mat_hopper.core.materials.LegDesign`.
        convention: the stiffness convention, any case (default ``paper``).
        segment_mass: ``"leg"`` (default) or ``"capsule"``, any case.
        control_period_s: the control period, s, in [1e-6, 0.1]
            (:data:`mat_hopper.core.model.MIN_TIMESTEP_S`, the smallest physics
            step the package plans, to ``MAX_TIMESTEP_S``); None (default)
            takes :func:`auto_control_period`'s.
        safety: the fraction of each explicit bound a step may reach, in
            (0, 1] (default :data:`AUTO_SAFETY`, 0.5).
        sensor_timing: the controller's sensor timing (read only when
            `control_period_s` is None; default ``"authors"``).
        contact: the contact setting (default ``"authors"``, whose 0.01 s
            limit never binds; ``"stiff"``: 5e-4 s).

    Returns:
        (k, dt, bound): the substeps per control period (an int >= 1), the
        physics step control_period / k, s, and the springs' bound
        2 / w_max, s.

    Raises:
        ValueError: `control_period_s` or `safety` out of its range, more
            than 1000 substeps needed, or as :func:`estimate_timestep` and
            :func:`controller_timestep` raise (unknown convention, segment
            mass or sensor timing), or an unknown contact.
    """
    hopper = LumpedHopper(design, convention, segment_mass)  # the one check of the convention on this path
    safety = check_positive(safety, "safety", high=1.0)
    contact_limit = contact_max_timestep(contact)
    if control_period_s is not None:
        control_period_s = check_positive(control_period_s, "control_period_s", "s", MAX_TIMESTEP_S)
        if control_period_s < MIN_TIMESTEP_S:
            raise ValueError(
                f"control_period_s must be in [{MIN_TIMESTEP_S:g}, {MAX_TIMESTEP_S:g}] s (MIN_TIMESTEP_S, the "
                f"smallest physics step the package plans), got {control_period_s!r}"
            )
    if control_period_s is None:
        control_period_s = _control_period(
            _controller_hopper(hopper), SensorTiming(sensor_timing), ref.TIMESTEP_S, safety
        )
    _, bound = _spring_bound(hopper)
    k = max(1, math.ceil(control_period_s / (safety * bound) - 1e-9))
    # MuJoCo honours a contact time constant only down to 2 steps (refsafe):
    # the step stays at most half of it.
    k = max(k, math.ceil(control_period_s / contact_limit - 1e-9))
    if k > 1000:
        raise ValueError(
            f"--timestep auto would need {k} physics substeps per {control_period_s:g} s control "
            f"period (spring bound {bound:.2g} s): over the limit of 1000"
        )
    return k, control_period_s / k, bound
