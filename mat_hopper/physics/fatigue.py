"""Stress along the leg, its strength and its fatigue.

Stress. Every physics step the rollout turns each segment's springs into
section stress (:func:`mat_hopper.core.model.stress_gains`, recorded as
``Rollout.stress``, (samples, N, 4), columns
:data:`mat_hopper.core._loop.STRESS_COLUMNS`): the axial F / A and the bending
M c / I about x and y at the extreme fibre, and the physics-rate peak of the
section's largest normal stress |F / A| + |M| c / I since the previous
record. Per hop (lift-off to lift-off) :func:`hop_stress` reports each
segment's peak, and at each interface the jump of the section's stress
between the two segments.

Limitation: this is a 1-D model of uniform section. Its stress is a beam's
resultant over a section (force and moment), continuous along the leg but
for the moment's change over a segment; it does not depend on the
segment's material except through the dynamics (masses, stiffnesses,
vibration). The stress concentration of a real bimaterial interface (a
2-D / 3-D elasticity effect of the modulus mismatch, free-edge
singularities) is not in it: the "interface jump" here is the difference of
the two neighbours' section stresses, nothing more.

Strength. :data:`STRENGTH` gives per catalogue material its yield strength
and a Basquin S-N curve, sigma_a = sigma_f' (2 N_f)^b (stress amplitude at
zero mean stress against cycles to failure N_f), with sources. Where a
material has no measured Basquin constants the curve is drawn through two
of Ashby's points: the tensile strength at one reversal and the fatigue
strength at 1e7 cycles, b = log10(sigma_e / sigma_u) / log10(2e7).
Materials outside the catalogue (designs from properties, the sweeps, the
gradients rho-inc / rho-dec) take their class's curve, the class read off
their modulus as for the loss factor (:func:`mat_hopper.core.damping.loss_factor`).

Fatigue. Each segment's section has four extreme fibres (+-x, +-y), each a
uniaxial stress history sigma_axial +- sigma_bending. Cycles are counted
by rainflow (ASTM E1049-85, the kept library ``rainflow``, half cycles
counted as 0.5), the amplitude corrected for mean stress by Morrow's
sigma_ar = sigma_a / (1 - sigma_m / sigma_f') (N. E. Dowling, Mechanical
Behavior of Materials, 4th ed., Pearson 2013, sec. 9.7), and damage summed
by Palmgren-Miner, D = sum n_i / N_f(sigma_ar,i). A segment's damage per
hop is its worst fibre's; hops to failure 1 / (mean damage per hop). The
records are at the record rate (1 kHz by default): cycles faster than its
Nyquist frequency (the leg's higher modes) are not counted; the peaks are
at the physics rate.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
import rainflow

from ..core.damping import loss_factor_class
from ..core.materials import CATALOGUE, LegDesign, Material

_ASHBY = "Ashby 2011, app. C (tensile strength, fatigue strength at 1e7 cycles; mid-range)"
_DOWLING = "Dowling 2013, table 9.1 (measured Basquin constants)"


@dataclass(frozen=True)
class Strength:
    """Yield strength (MPa) and Basquin S-N curve sigma_a = sigma_f' (2 N)^b
    (sigma_f' in MPa, b < 0) of a material, with its source."""

    yield_mpa: float
    sigma_f_mpa: float
    b: float
    source: str

    def amplitude_at(self, cycles: float) -> float:
        """The fully reversed stress amplitude (Pa) that fails the material
        in ``cycles`` cycles: sigma_f' (2 N)^b."""
        return self.sigma_f_mpa * 1e6 * (2.0 * float(cycles)) ** self.b

    def cycles_to_failure(self, amplitude_pa, mean_pa=0.0):
        """Cycles to failure N_f at this stress amplitude (Pa; array or
        scalar), Morrow-corrected for the mean stress (Pa): sigma_ar =
        sigma_a / (1 - sigma_m / sigma_f'), N_f = (sigma_ar / sigma_f')^(1/b) / 2.
        A mean stress at or above sigma_f' gives N_f = 0 (failure)."""
        sf = self.sigma_f_mpa * 1e6
        a = np.abs(np.asarray(amplitude_pa, dtype=float))
        factor = 1.0 - np.asarray(mean_pa, dtype=float) / sf
        ar = np.where(factor > 0, a / np.where(factor > 0, factor, 1.0), np.inf)
        with np.errstate(divide="ignore", over="ignore"):
            return np.where(ar > 0, 0.5 * (ar / sf) ** (1.0 / self.b), np.inf)


def _two_point(yield_mpa: float, ultimate_mpa: float, endurance_mpa: float, source: str) -> Strength:
    """Basquin through (1 reversal, sigma_u) and (1e7 cycles, sigma_e)."""
    b = math.log10(endurance_mpa / ultimate_mpa) / math.log10(2e7)
    return Strength(yield_mpa, ultimate_mpa, b, source)


# Per catalogue material (lower-case name). Polymers, ceramics, composites,
# natural materials: yield (or, for the brittle ones, tensile) strength,
# tensile strength and fatigue strength at 1e7 cycles, mid-range values.
STRENGTH: dict[str, Strength] = {
    "pvc": _two_point(45.0, 50.0, 17.0, _ASHBY),
    "nylon": _two_point(65.0, 80.0, 30.0, _ASHBY),
    # AISI 304 annealed: yield 215 MPa, tensile 505 MPa, endurance about 240 MPa (ASM Handbook vol. 1)
    "ss": _two_point(215.0, 505.0, 240.0, "ASM Handbook vol. 1 (AISI 304, annealed)"),
    "al": Strength(303.0, 900.0, -0.102, _DOWLING + ", 2024-T4"),
    "ti": Strength(1185.0, 2030.0, -0.104, _DOWLING + ", Ti-6Al-4V"),
    "mg": _two_point(150.0, 250.0, 90.0, _ASHBY + ", Mg alloys"),
    # Brittle: "yield" is the tensile strength (no plastic yield before fracture).
    "alumina": _two_point(300.0, 300.0, 220.0, _ASHBY),
    "wc": _two_point(400.0, 400.0, 300.0, _ASHBY),
    "cfrp": _two_point(550.0, 600.0, 250.0, _ASHBY + ", CFRP quasi-isotropic"),
    # Compact bone in tension: yield about 110 MPa, ultimate about 130 MPa
    # (Wegst & Ashby 2004); fatigue strength at 1e7 about 35 MPa (D. R. Carter
    # et al., J. Biomech. 14 (1981) 461).
    "corticalbone": _two_point(110.0, 130.0, 35.0, "Wegst & Ashby 2004; Carter et al. 1981"),
    "trabecularbone": _two_point(5.0, 6.0, 2.0, "Wegst & Ashby 2004, fig. 3 (two-point, fatigue ratio of bone)"),
    "tendon": _two_point(70.0, 100.0, 30.0, "Wegst & Ashby 2004, table 1 (two-point, fatigue ratio of bone)"),
}
# Curves of materials outside the catalogue, by their class
# (:func:`mat_hopper.core.damping.loss_factor_class`: their own Ashby class where
# :data:`mat_hopper.core.damping.LOSS_FACTORS` lists it, else the class their
# modulus falls in). One entry per key of LOSS_FACTORS. Ceramic and natural
# have no class curve of their own: they reuse a sourced catalogue curve of
# the class, alumina's (the technical ceramic of the catalogue, Ashby's
# mid-range values) and compact bone's (Wegst & Ashby 2004; Carter et al.
# 1981), the natural material of the catalogue with both strength and
# fatigue data measured.
CLASS_STRENGTH = {
    "metal": STRENGTH["al"],
    "composite": STRENGTH["cfrp"],
    "polymer": STRENGTH["pvc"],
    "ceramic": STRENGTH["alumina"],
    "natural": STRENGTH["corticalbone"],
}


def strength_basis(mat: Material) -> str:
    """Whose S-N curve :func:`strength` judges a material by, in words: the
    catalogue entry's own (``"SS's own"``), or its class's (``"the metal
    class's"``) for a material that is not a catalogue entry by name,
    density and modulus alike (a leg given by its properties, a control).

    Args:
        mat: the :class:`~mat_hopper.core.materials.Material` (not rigid).

    Returns:
        The words, e.g. ``"Ti's own"`` or ``"the metal class's"``.

    Raises:
        ValueError: a rigid material.
    """
    own = strength(mat)
    name = mat.name.strip()
    if STRENGTH.get(name.lower()) is own:
        return f"{name}'s own"
    return f"the {loss_factor_class(mat)} class's"


def strength(mat: Material) -> Strength:
    """A material's :class:`Strength`: the catalogue's, for a material with
    a catalogue name *and* that entry's density and modulus; any other (a
    sweep's porous or softened point, a gradient's segment, a control) its
    class's (:data:`CLASS_STRENGTH`, which covers every class of
    :data:`mat_hopper.core.damping.LOSS_FACTORS`): its own Ashby class where
    listed, else the class read off its modulus. Raises ValueError for a
    rigid one.

    Args:
        mat: the :class:`~mat_hopper.core.materials.Material`; its name is matched
            case-insensitively, without surrounding spaces.

    Returns:
        The catalogue entry of :data:`STRENGTH` where name, density and
        modulus all match the catalogue's; else the :data:`CLASS_STRENGTH`
        curve of its class (:func:`mat_hopper.core.damping.loss_factor_class`).

    Raises:
        ValueError: a rigid material (it carries no modelled stress).
    """
    if mat.rigid:
        raise ValueError(f"material {mat.name} is rigid: it carries no modelled stress")
    key = mat.name.strip().lower()
    own = CATALOGUE.get(key)
    if (
        key in STRENGTH
        and own is not None
        and (own.density_g_cm3, own.modulus_gpa)
        == (
            mat.density_g_cm3,
            mat.modulus_gpa,
        )
    ):
        return STRENGTH[key]
    return CLASS_STRENGTH[loss_factor_class(mat)]


def rainflow_cycles(series) -> pd.DataFrame:
    """Rainflow cycles of a stress history (ASTM E1049-85; the library
    ``rainflow``): one row per cycle or half cycle, columns range, mean,
    count (1 or 0.5), i_start, i_end (sample indices).

    Args:
        series: the stress history, a 1-D sequence (any unit; Pa here).

    Returns:
        DataFrame with columns ``range``, ``mean`` (the series' unit),
        ``count``, ``i_start``, ``i_end``; empty (same columns) for fewer
        than two samples.
    """
    x = np.asarray(series, dtype=float)
    rows = list(rainflow.extract_cycles(x)) if len(x) >= 2 else []
    return pd.DataFrame(rows, columns=["range", "mean", "count", "i_start", "i_end"])


def miner_damage(series_pa, st: Strength) -> float:
    """Palmgren-Miner damage sum of one uniaxial stress history (Pa) under
    this S-N curve (rainflow-counted, Morrow-corrected).

    Args:
        series_pa: the uniaxial stress history, 1-D sequence, Pa.
        st: the material's :class:`Strength` (S-N curve).

    Returns:
        D = sum of count / N_f over the rainflow cycles (dimensionless; 1 =
        failure); 0.0 without cycles, inf where a cycle's mean stress reaches
        sigma_f'.
    """
    c = rainflow_cycles(series_pa)
    if c.empty:
        return 0.0
    n_f = st.cycles_to_failure(c["range"].to_numpy() / 2.0, c["mean"].to_numpy())
    with np.errstate(divide="ignore"):
        return float(np.sum(c["count"].to_numpy() / n_f))


FIBRES = 8  # extreme fibres per section, every 45 degrees


def _fibres(block: np.ndarray) -> list[np.ndarray]:
    """The extreme-fibre stress histories (Pa) of one segment's stress
    record block (samples, 4): sigma_axial + sigma_bx sin(theta) +
    sigma_by cos(theta) at FIBRES angles theta around the section. A moment
    whose axis lies between two fibres is underestimated by at most
    1 - cos(pi / FIBRES) (7.6 % with 8 fibres; 29 % with the four of the
    first release)."""
    a, bx, by = block[:, 0], block[:, 1], block[:, 2]
    if not (bx.any() or by.any()):  # axial only: every fibre the same
        return [a]
    theta = 2.0 * np.pi * np.arange(FIBRES) / FIBRES
    return [a + bx * math.sin(t) + by * math.cos(t) for t in theta]


def equivalent_amplitude(series_pa, st: Strength) -> float:
    """The largest Morrow-corrected, fully reversed stress amplitude (Pa)
    among the rainflow cycles of one stress history (0 without cycles; inf
    where the mean stress reaches sigma_f').

    Args:
        series_pa: the uniaxial stress history, 1-D sequence, Pa.
        st: the material's :class:`Strength` (its sigma_f' corrects the mean).

    Returns:
        The largest sigma_a / (1 - sigma_m / sigma_f') over the cycles, Pa;
        0.0 without cycles, inf where a cycle's mean stress reaches sigma_f'.
    """
    c = rainflow_cycles(series_pa)
    if c.empty:
        return 0.0
    factor = 1.0 - c["mean"].to_numpy() / (st.sigma_f_mpa * 1e6)
    amp = c["range"].to_numpy() / 2.0
    return float(np.max(np.where(factor > 0, amp / np.where(factor > 0, factor, 1.0), np.inf)))


DESIGN_LIFE_CYCLES = 1e7  # the life fatigue safety is judged at: the end of the S-N data (Ashby's 1e7 cycles)


def _segment_hop(block: np.ndarray, st: Strength) -> tuple[float, float, float, float]:
    """(peak Pa, Miner damage, equivalent amplitude Pa, fatigue safety) of
    one segment over one hop, its worst fibre's."""
    fibres = _fibres(block)
    peak = float(block[:, 3].max())
    damage = max(miner_damage(f, st) for f in fibres)
    amp = max(equivalent_amplitude(f, st) for f in fibres)
    safety = math.inf if amp == 0 else st.amplitude_at(DESIGN_LIFE_CYCLES) / amp
    return peak, damage, amp, safety


def hop_stress(rollout, cycles: np.ndarray) -> pd.DataFrame:
    """Stress and fatigue per hop cycle and segment.

    Args:
        rollout: a Rollout with stress records (``Rollout.stress``).
        cycles: (k, 2) hop cycles, (start, end) s.

    Returns:
        One row per hop and segment (1 = base end): ``peak_stress_pa``
        (physics rate), ``damage`` (Miner sum, worst fibre),
        ``equivalent_amplitude_pa`` (the largest Morrow-corrected amplitude,
        worst fibre), ``fatigue_safety`` (the S-N amplitude at
        DESIGN_LIFE_CYCLES over it: > 1 lasts that long), ``yield_ratio``
        (peak over yield) and ``interface_jump_pa`` (max over the hop of
        |section stress_s - section stress_s+1|, record rate; NaN for the
        last segment and beside a rigid one). Rigid segments carry no
        modelled stress (NaN).
    """
    st, t = rollout.stress, rollout.time
    design: LegDesign = rollout.design
    n = design.n_segments
    strengths = [None if m.rigid else strength(m) for m in design.segments]
    if st is None:  # a rollout without stress records (e.g. another backend's): no modelled stress
        st = np.zeros((len(t), n, 4))
        strengths = [None] * n
    section = np.abs(st[:, :, 0]) + np.hypot(st[:, :, 1], st[:, :, 2])  # (samples, N)
    rows = []
    for h, (t0, t1) in enumerate(cycles):
        a, b = np.searchsorted(t, t0), np.searchsorted(t, t1)
        for s in range(n):
            if strengths[s] is None or b <= a:
                peak = damage = amp = safety = ratio = math.nan
            else:
                peak, damage, amp, safety = _segment_hop(st[a:b, s], strengths[s])
                ratio = peak / (strengths[s].yield_mpa * 1e6)
            elastic = s + 1 < n and strengths[s] is not None and strengths[s + 1] is not None  # a rigid side: no stress
            jump = float(np.abs(section[a:b, s] - section[a:b, s + 1]).max()) if elastic and b > a else math.nan
            rows.append((h, s + 1, peak, damage, amp, safety, ratio, jump))
    columns = ["hop", "segment", "peak_stress_pa", "damage", "equivalent_amplitude_pa", "fatigue_safety"]
    return pd.DataFrame(rows, columns=[*columns, "yield_ratio", "interface_jump_pa"])


def hop_stress_columns(rollout, cycles: np.ndarray) -> pd.DataFrame:
    """One row per hop for the hop table: the leg's peak stress (Pa, its
    worst segment), that segment, the leg's damage per hop (its worst
    segment's Miner sum) and whether any segment's peak exceeded its yield
    strength (``yield_exceeded``).

    Args:
        rollout: a Rollout with stress records (``Rollout.stress``; None
            gives no modelled stress).
        cycles: (k, 2) hop cycles, (start, end) s.

    Returns:
        DataFrame, one row per hop (k rows), columns ``peak_stress_pa`` (Pa),
        ``peak_stress_segment`` (1 = base end), ``damage`` (Miner sum of the
        hop, worst segment) and ``yield_exceeded`` (bool). NaN (and False)
        throughout where no segment has modelled stress.
    """
    per = hop_stress(rollout, cycles)
    if per.empty or per["peak_stress_pa"].isna().all():
        nan = np.full(len(cycles), math.nan)
        return pd.DataFrame({"peak_stress_pa": nan, "peak_stress_segment": nan, "damage": nan, "yield_exceeded": False})
    g = per.groupby("hop")
    worst = per.loc[g["peak_stress_pa"].idxmax().to_numpy()]
    return pd.DataFrame(
        {
            "peak_stress_pa": worst["peak_stress_pa"].to_numpy(),
            "peak_stress_segment": worst["segment"].to_numpy(),
            "damage": g["damage"].max().to_numpy(),
            "yield_exceeded": (g["yield_ratio"].max() > 1.0).to_numpy(),
        }
    )


def fatigue_summary(rollout, cycles: np.ndarray) -> dict:
    """A run's stress and fatigue in one line.

    Args:
        rollout: a Rollout with stress records.
        cycles: (k, 2) scored hop cycles, s.

    Returns:
        ``peak_stress_pa`` (the leg's largest over the hops: an extreme
        of the run, which grows with its length), ``hop_peak_stress_median_pa``
        (the median over hops of each hop's leg peak: the typical hop,
        robust to one hard landing), ``yield_ratio``
        (the largest peak over yield), ``damage_per_hop`` (the mean Miner
        damage per hop of its most damaged segment), ``hops_to_failure``
        (1 / that; inf without damage: Basquin's line extrapolated, often
        far past any measured life), ``fatigue_safety_factor`` (the
        smallest over segments of the S-N amplitude at DESIGN_LIFE_CYCLES
        over the largest equivalent amplitude of any hop: a continuous
        margin that stays comparable where lives are astronomically long),
        ``yield_exceeded``. NaN (and False) without modelled stress.
    """
    per = hop_stress(rollout, cycles)
    if per.empty or per["peak_stress_pa"].isna().all():
        return {"peak_stress_pa": math.nan, "hop_peak_stress_median_pa": math.nan, "yield_ratio": math.nan, "damage_per_hop": math.nan,
                "hops_to_failure": math.nan, "fatigue_safety_factor": math.nan,
                "yield_exceeded": False}  # fmt: skip
    mean_damage = per.groupby("segment")["damage"].mean()
    d = float(mean_damage.max())
    return {
        "peak_stress_pa": float(per["peak_stress_pa"].max()),
        "hop_peak_stress_median_pa": float(per.groupby("hop")["peak_stress_pa"].max().median()),
        "yield_ratio": float(per["yield_ratio"].max()),
        "damage_per_hop": d,
        "hops_to_failure": math.inf if d == 0 else 1.0 / d,
        "fatigue_safety_factor": float(per.groupby("segment")["fatigue_safety"].min().min()),
        "yield_exceeded": bool(per["yield_ratio"].max() > 1.0),
    }
