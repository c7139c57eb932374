"""The leg's axial and bending modes against the continuum (pure physics).

The leg along its axis is the lumped chain of
:func:`mat_hopper.core.stable_step.leg_chain`. Modes against the continuum (:func:`axial_modes`). The material part of the
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
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import scipy.linalg
import scipy.optimize

from ..core import reference as ref
from ..core.materials import (
    AXIAL_CONVENTIONS,
    BENDING_CONVENTIONS,
    DEFAULT_SEGMENT_MASS,
    MAX_SEGMENTS,
    LegDesign,
    check_convention,
    second_moment_m4,
    segment_masses,
)
from ..core.model import (
    BEND_SPRINGS,
    FOOT_GEOM,
    FOOT_UPPER_GEOM,
    build_model,
    build_spec,
)
from ..core.stable_step import chain_frequencies, sprung_eig


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
            :func:`mat_hopper.core.model.build_model` refuses.
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
            :data:`~mat_hopper.core.materials.BENDING_CONVENTIONS`, a graded or
            rigid design (or not a LegDesign), `n_modes` not an integer in
            [1, 64], or an argument :func:`mat_hopper.core.model.build_spec`
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
    w_chain = sprung_eig(model, dofs)[:n_modes]
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
