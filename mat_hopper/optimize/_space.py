"""The optimizer's search space: per-segment density and modulus, or catalogue materials.

A leg of N segments (segment 1 nearest the base). Each segment is either

``continuous``
    a density (g/cm^3) and a modulus (GPa), both sampled on a log scale
    within :data:`DENSITY_BOUNDS_G_CM3` and :data:`MODULUS_BOUNDS_GPA`;
``catalogue``
    a categorical choice among catalogue materials (default: every
    :data:`~mat_hopper.core.materials.CATALOGUE` material with a finite modulus,
    i.e. all but the rigid MD).

``kinds`` is one word for every segment, or one word per segment (a mix,
e.g. ``("catalogue", "continuous", "continuous")``: a catalogue material
at the hip and two free segments below it).

Bounds: the paper (sec. II, "Bounds for Moduli and Density") draws its
materials from two Ashby classes, polymers/natural materials and
metals/ceramics, and its one-property sweeps span their extremes. The
continuous box is the bounding box of both (not their hull: it also holds
designs no class holds, e.g. 11.9 g/cm^3 at 0.96 GPa):

- density 0.9 to 20 g/cm^3: the sweeps' maximum (20 g/cm^3, ``reference.SWEEPS``)
  and, below the sweeps' 1.10 g/cm^3, the polymer class's floor 0.9 g/cm^3
  (polyolefins, Ashby 2011 app. C: polyethylene and polypropylene
  0.89-0.96 g/cm^3);
- modulus 0.1 to 1000 GPa: the sweeps' minimum and maximum.

The two classes inside that box (for reading results): polymers and
natural materials about 0.9-2.5 g/cm^3 and 0.1-9 GPa; metals and ceramics
about 2-20 g/cm^3 and 15-1000 GPa (the paper's text: "E <= 9 GPa" against
"E >= 20 GPa"). Parts of the box (light and very stiff) diverge at the
paper's 1e-4 s step; those designs come out as infeasible trials.

Ashby classes (``ashby_classes``, e.g. ``("metal", "polymer")``) restrict
continuous segments to the catalogue's class hulls
(:mod:`mat_hopper.optimize._ashby`): the search samples the hulls'
bounding box and maps each sampled point to the nearest point of an
allowed hull, so every simulated segment lies in one of the classes. The
box bounds then come from the hulls (giving other bounds as well is an
error).

Seeds: every study first evaluates the paper's designs
(:data:`PAPER_SEEDS`, all nine) that the space can express; the rigid MD
never is (a continuous segment has a finite modulus), so reports run it as
a baseline outside the study.

Parameter names: ``seg{i}_density_g_cm3``, ``seg{i}_modulus_gpa``,
``seg{i}_material`` (i from 1).

Mass-held spaces. A study that constrains the leg's mass to a band
(``Objective.leg_mass``) samples inside it (:class:`MassHold`, set by
:class:`~mat_hopper.optimize._study.StudyConfig`): the leg's mass is a
parameter of its own, ``leg_mass_kg``, uniform in the band, and the
continuous segments' sampled densities give only the distribution of
density along the leg; the design's densities are those scaled to the
sampled mass (each kept within the density bounds: the scale is found
with the densities clipped to them). A leg's mass is linear in its
densities (:func:`mat_hopper.optimize._scoring.leg_mass_model`), so the
derived design has the sampled mass. The enqueued paper designs carry
their own mass as ``leg_mass_kg`` and stay exactly themselves. Spaces
without a continuous segment, or restricted to Ashby classes (whose
projection moves the densities), are not held: their designs outside the
band are skipped before any run
(:func:`mat_hopper.optimize._mass.outside_band`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..core import reference as ref
from ..core.materials import (  # noqa: F401  (the bounds re-exported: the search box)
    CATALOGUE,
    DENSITY_BOUNDS_G_CM3,
    MODULUS_BOUNDS_GPA,
    POLYMER_DENSITY_FLOOR_G_CM3,
    LegDesign,
    Material,
    material,
    paper_designs,
)
from ._ashby import check_classes, classes_bounds, in_classes, project

KINDS = ("continuous", "catalogue")
MASS_PARAM = "leg_mass_kg"  # the sampled leg mass of a mass-held space, kg (module doc)

DEFAULT_MATERIALS = tuple(m.name for m in CATALOGUE.values() if not m.rigid)
# The paper's nine designs every study starts from (enqueued in this order;
# those the space cannot express, such as the rigid MD, are left out).
PAPER_SEEDS = ("SS", "rho-inc", "PVC-Ti-SS", "SS-Ti-PVC", "rho-dec", "PVC", "Al", "Ti", "MD")
MAX_SEGMENTS = 12


def _bounds(value, field_name: str, unit: str) -> tuple[float, float]:
    try:
        lo, hi = (float(v) for v in value)
    except (TypeError, ValueError):
        raise ValueError(f"{field_name} must be (min, max) in {unit}, got {value!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi)) or lo <= 0:
        raise ValueError(f"{field_name} must be finite with 0 < min < max {unit} (log scale), got {value!r}")
    if lo >= hi:
        raise ValueError(f"{field_name}: min must be < max {unit}, got min {lo:g} >= max {hi:g}")
    return lo, hi


@dataclass(frozen=True)
class MassHold:
    """How a mass-held space samples inside a leg-mass band (module doc).

    Args:
        band_kg: (min, max) of the sampled leg mass, kg: the constraint's
            band within the masses the space can reach.
        fixed_kg, per_g_cm3_kg: the leg's mass model, mass = fixed_kg +
            per_g_cm3_kg x (sum of the segments' densities in g/cm^3)
            (:func:`mat_hopper.optimize._scoring.leg_mass_model`).
    """

    band_kg: tuple[float, float]
    fixed_kg: float
    per_g_cm3_kg: float

    def mass_kg(self, segments) -> float:
        """kg, the mass model's leg mass of these Materials."""
        return self.fixed_kg + self.per_g_cm3_kg * sum(m.density_g_cm3 for m in segments)

    def held(self, segments: list, kinds, bounds: tuple[float, float], mass_kg: float) -> list:
        """`segments` with their continuous densities scaled to give a leg
        of `mass_kg` (each within `bounds`, g/cm^3); the catalogue
        segments as they are. Unchanged when they already weigh exactly
        `mass_kg` (an enqueued design)."""
        if mass_kg == self.mass_kg(segments):
            return segments
        free = [i for i, k in enumerate(kinds) if k == "continuous"]
        rest = sum(m.density_g_cm3 for i, m in enumerate(segments) if i not in free)
        total = (mass_kg - self.fixed_kg) / self.per_g_cm3_kg - rest  # g/cm^3 the free segments share
        dens = scaled_to_sum([segments[i].density_g_cm3 for i in free], total, bounds)
        out = list(segments)
        for i, d in zip(free, dens):
            m = segments[i]
            out[i] = Material(m.name, d, m.modulus_gpa, m.material_class)
        return out


def scaled_to_sum(values, total: float, bounds: tuple[float, float]) -> list[float]:
    """``clip(s * v, lo, hi)`` for each of `values` (> 0), with the one
    scale s > 0 that makes them sum to `total` (exact: the sum is piecewise
    linear in s); all at lo (hi) when `total` is below (above) what the
    bounds allow."""
    lo, hi = bounds
    v = [float(x) for x in values]
    if total <= lo * len(v):
        return [lo] * len(v)
    if total >= hi * len(v):
        return [hi] * len(v)
    breaks = sorted({b / x for x in v for b in (lo, hi)})

    def parts(s):  # (sum of the clipped ones, sum of the free values)
        fixed = sum(lo if s * x <= lo else hi for x in v if not lo < s * x < hi)
        return fixed, sum(x for x in v if lo < s * x < hi)

    s = breaks[-1]
    for a, b in zip(breaks, breaks[1:]):
        if sum(min(max(b * x, lo), hi) for x in v) >= total:
            fixed, slope = parts((a + b) / 2)
            s = (total - fixed) / slope if slope > 0 else b
            break
    return [min(max(s * x, lo), hi) for x in v]


@dataclass(frozen=True)
class SearchSpace:
    """Where the optimizer looks.

    Args:
        n_segments: segments per leg.
        kinds: ``"continuous"``, ``"catalogue"`` or one of those per segment.
        density_g_cm3, modulus_gpa: (min, max) bounds of continuous segments,
            g/cm^3 and GPa (None: from the Ashby classes' hulls, else the defaults).
        materials: catalogue names for catalogue segments.
        ashby_classes: restrict continuous segments to these classes' hulls (module doc).
        mass_hold: sample inside a leg-mass band (:class:`MassHold`; set
            by the study from its objective, not part of the space's key).

    Raises:
        ValueError: bounds outside the physical ranges, unknown materials,
            kinds or classes (naming them).
    """

    n_segments: int = ref.REFERENCE_SEGMENTS
    kinds: tuple[str, ...] | str = "continuous"
    density_g_cm3: tuple[float, float] | None = None
    modulus_gpa: tuple[float, float] | None = None
    materials: tuple[str, ...] = field(default=DEFAULT_MATERIALS)
    ashby_classes: tuple[str, ...] | str = ()
    mass_hold: MassHold | None = field(default=None, compare=False, repr=False)

    def __post_init__(self):
        n = self.n_segments
        if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= MAX_SEGMENTS:
            raise ValueError(f"n_segments must be an integer in [1, {MAX_SEGMENTS}], got {n!r}")
        kinds = self.kinds
        if isinstance(kinds, str):
            kinds = tuple(k.strip() for k in kinds.split(",")) if "," in kinds else (kinds,) * n
        kinds = tuple(str(k).strip().lower() for k in kinds)
        kinds = tuple("catalogue" if k == "catalog" else k for k in kinds)
        if len(kinds) != n:
            raise ValueError(f"kinds: one per segment ({n}), got {len(kinds)}: {','.join(kinds)}")
        for k in kinds:
            if k not in KINDS:
                raise ValueError(f"kinds: unknown segment kind {k!r}; accepted: {', '.join(KINDS)}")
        object.__setattr__(self, "kinds", kinds)
        classes = check_classes(self.ashby_classes)
        object.__setattr__(self, "ashby_classes", classes)
        defaults = classes_bounds(classes) if classes else (DENSITY_BOUNDS_G_CM3, MODULUS_BOUNDS_GPA)
        for (name, unit), default in zip((("density_g_cm3", "g/cm^3"), ("modulus_gpa", "GPa")), defaults):
            value = getattr(self, name)
            value = default if value is None else _bounds(value, name, unit)
            if classes and not all(math.isclose(a, b, rel_tol=1e-9) for a, b in zip(value, default)):
                raise ValueError(
                    f"{name}: Ashby classes set the bounds (their hulls' box, "
                    f"{default[0]:.4g} to {default[1]:.4g} {unit}); give either bounds or ashby_classes"
                )
            object.__setattr__(self, name, default if classes else value)
        mats = self.materials
        if isinstance(mats, str):
            mats = tuple(p for p in mats.split(",") if p.strip())
        names = []
        for name in mats:
            m = material(name)  # ValueError names the accepted materials
            if m.rigid:
                raise ValueError(f"materials: {m.name} is rigid (no modulus); choose materials with a modulus")
            if m.name not in names:
                names.append(m.name)
        if classes and "catalogue" in kinds:  # catalogue choices must lie in the classes too
            names = [n for n in names if material(n).material_class in classes]
        if "catalogue" in kinds and not names:
            extra = f" of the classes {', '.join(classes)}" if classes else ""
            raise ValueError(f"materials: a catalogue segment needs at least one material{extra}")
        object.__setattr__(self, "materials", tuple(names))
        if self.mass_hold is not None and not isinstance(self.mass_hold, MassHold):
            raise ValueError("mass_hold must be a MassHold or None")

    @property
    def holds_mass(self) -> bool:
        """Whether the space samples inside a leg-mass band (module doc)."""
        return self.mass_hold is not None and "continuous" in self.kinds and not self.ashby_classes

    # --- parameters <-> designs ---
    def suggest(self, trial) -> LegDesign:
        """Ask an Optuna trial for a design in this space."""
        params = {}
        for i, kind in enumerate(self.kinds, 1):
            if kind == "continuous":
                params[f"seg{i}_density_g_cm3"] = trial.suggest_float(
                    f"seg{i}_density_g_cm3", *self.density_g_cm3, log=True
                )
                params[f"seg{i}_modulus_gpa"] = trial.suggest_float(f"seg{i}_modulus_gpa", *self.modulus_gpa, log=True)
            else:
                params[f"seg{i}_material"] = trial.suggest_categorical(f"seg{i}_material", self.materials)
        if self.holds_mass:
            params[MASS_PARAM] = trial.suggest_float(MASS_PARAM, *self.mass_hold.band_kg)
        return self.design(params)

    def design(self, params: dict, name: str = "") -> LegDesign:
        """The leg a trial's parameters describe (the same one ``suggest``
        built): with Ashby classes, each continuous segment is the nearest
        point of an allowed class hull; in a mass-held space, with a
        ``leg_mass_kg`` parameter, the densities scaled to that mass
        (module doc)."""
        segs = []
        for i, kind in enumerate(self.kinds, 1):
            if kind == "continuous":
                try:
                    d, e = params[f"seg{i}_density_g_cm3"], params[f"seg{i}_modulus_gpa"]
                except KeyError as k:
                    raise ValueError(f"parameters lack {k.args[0]} (not a design of this space)") from None
                cls = "custom"
                if self.ashby_classes:
                    d, e, cls = project(d, e, self.ashby_classes)
                segs.append(Material(f"seg{i}", d, e, cls))
            else:
                try:
                    segs.append(material(params[f"seg{i}_material"]))
                except KeyError as k:
                    raise ValueError(f"parameters lack {k.args[0]} (not a design of this space)") from None
        if self.holds_mass and MASS_PARAM in params:
            segs = self.mass_hold.held(segs, self.kinds, self.density_g_cm3, float(params[MASS_PARAM]))
        return LegDesign(tuple(segs), name=name or describe(segs))

    def params_for(self, design: LegDesign) -> dict | None:
        """Parameters that give `design` (resampled to n_segments), or None
        when the space cannot express it (outside the bounds, a rigid
        segment, or a material not among the choices)."""
        segs = resample(design, self.n_segments)
        params = {}
        for i, (kind, m) in enumerate(zip(self.kinds, segs), 1):
            if kind == "continuous":
                if m.rigid:
                    return None
                if self.ashby_classes and not in_classes(LegDesign((m,)), self.ashby_classes):
                    return None
                if not (
                    self.density_g_cm3[0] <= m.density_g_cm3 <= self.density_g_cm3[1]
                    and self.modulus_gpa[0] <= m.modulus_gpa <= self.modulus_gpa[1]
                ):
                    return None
                params[f"seg{i}_density_g_cm3"] = float(m.density_g_cm3)
                params[f"seg{i}_modulus_gpa"] = float(m.modulus_gpa)
            else:
                if m.name not in self.materials:
                    return None
                params[f"seg{i}_material"] = m.name
        if self.holds_mass:  # its own mass: the design stays exactly itself (MassHold.held)
            params[MASS_PARAM] = self.mass_hold.mass_kg(segs)
        return params

    def seeds(self) -> list[tuple[str, dict]]:
        """The paper's designs (:data:`PAPER_SEEDS`) this space can express,
        as (name, params), in order."""
        designs = paper_designs()
        out = []
        for name in PAPER_SEEDS:
            p = self.params_for(designs[name])
            if p is not None:
                out.append((name, p))
        return out

    def key(self) -> dict:
        """Plain dict (JSON) that identifies the space (``ashby_classes``
        only when set, so that a study keyed without them keeps its key)."""
        out = {
            "n_segments": self.n_segments,
            "kinds": list(self.kinds),
            "density_g_cm3": list(self.density_g_cm3),
            "modulus_gpa": list(self.modulus_gpa),
            "materials": list(self.materials),
        }
        if self.ashby_classes:
            out["ashby_classes"] = list(self.ashby_classes)
        return out

    @classmethod
    def from_key(cls, key: dict) -> SearchSpace:
        classes = tuple(key.get("ashby_classes") or ())
        return cls(
            n_segments=int(key["n_segments"]),
            kinds=tuple(key["kinds"]),
            density_g_cm3=None if classes else tuple(key["density_g_cm3"]),
            modulus_gpa=None if classes else tuple(key["modulus_gpa"]),
            materials=tuple(key["materials"]),
            ashby_classes=classes,
        )


def resample(design: LegDesign, n_segments: int) -> tuple[Material, ...]:
    """The design's materials on n equal segments: segment j takes the material
    found at its position along the leg (so a 3-segment gradient on 6 segments
    doubles each material; on 2 segments it keeps the top and bottom thirds').

    Args:
        design: a LegDesign.
        n_segments: the new number of segments.

    Returns:
        The n Materials, base to foot.
    """
    src = design.segments
    return tuple(src[min(len(src) - 1, (2 * j + 1) * len(src) // (2 * n_segments))] for j in range(n_segments))


def describe(segments) -> str:
    """Short text for a leg, base to foot.

    Args:
        segments: the Materials, base to foot (a LegDesign's ``segments``).

    Returns:
        Catalogue names, or density/modulus pairs (g/cm^3, GPa), joined by ``-``.
    """
    parts = []
    for m in segments:
        if m.name in (c.name for c in CATALOGUE.values()):
            parts.append(m.name)
        else:
            parts.append(f"{m.density_g_cm3:.3g}/{m.modulus_gpa:.3g}")
    return "-".join(parts)
