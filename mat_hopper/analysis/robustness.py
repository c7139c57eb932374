"""How robust are the paper's numbers? Each quantitative claim under other settings.

The paper's quantitative claims rest on percent changes of mean per-hop
metrics against a baseline design (:data:`QUANTITIES`). This module
recomputes each of them under *variants* of the settings that the paper
does not report and that a reader cannot check from its text:

- the controller's sensor latency: 0 (``fresh``), 1 (the authors' loop,
  the default), 2, 5 and 10 physics steps;
- the stiffness convention: ``paper`` (the authors' conversion) and
  ``axial`` (k = E A / L, run at the profile's smaller axial time step);
- the physics step: 2e-5 s with five physics substeps per 1e-4 s control
  period and a five-step (1e-4 s) sensor latency -- the same controller,
  finer integration (``2e-5 s physics``: does the integration converge?);
  and the authors' loop run plainly at 2e-5 s (``2e-5 s step``: the
  controller then also runs five times faster and reads the base 20 us
  late; what a user of their code gets by refining the step);
- seeded perturbed replicates of the default (start offset, tilt, a push,
  sensor noise: :meth:`mat_hopper.core.perturbations.Perturbation.replicate`).

and classifies each (quantity, variant) against the default's value:
``keeps`` (same sign, within a factor 2), ``moves > 2x`` (same sign, more
than a factor 2 away), ``flips`` (opposite sign) or ``no value`` (a needed
run diverged or fell). The study's runs are defined and run in
:mod:`mat_hopper.experiments.robustness`: through the result cache and the
process pool of :mod:`mat_hopper.experiments.runner` like every other grid,
or, for the variants without perturbations or substeps, on a batch backend
(:mod:`mat_hopper.batch`).

>>> [v.label for v in variants(replicates=1)][:3]
['authors', 'fresh', 'latency-2']
>>> [v.label for v in variants(replicates=1)][-3:]
['stiff contact', 'apex above ground', 'replicate 0']
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..core import reference as ref
from ..core.behaviours import BEHAVIOUR_NAMES
from ..core.contact import DEFAULT_CONTACT, check_contact
from ..core.controller import DEFAULT_APEX_REFERENCE, SensorTiming, check_apex_reference
from ..core.materials import MONO_NAMES, check_convention
from ..core.timestep import FINE_SUBSTEPS, FINE_TIMESTEP_S
from ..util.change import percent_change

DEFAULT_LATENCIES = (0, 1, 2, 5, 10)
FACTOR = 2.0  # "moves more than 2x"
KEEPS, MOVES, FLIPS, NO_VALUE = "keeps", "moves > 2x", "flips", "no value"
CLASSES = (KEEPS, MOVES, FLIPS, NO_VALUE)


@dataclass(frozen=True)
class Quantity:
    """One number a claim of the paper rests on: the percent change of the
    mean of ``metric`` of ``design`` against ``baseline`` on ``behaviour``.
    paper_pct: the paper's figure (None where the claim is a sign or a
    bound only); claim: the claim in words."""

    quantity_id: str
    claim: str
    metric: str
    design: str
    baseline: str
    behaviour: str
    paper_pct: float | None = None


def _quantities() -> tuple[Quantity, ...]:
    out = []
    # Hopping in place has no tracking error without a disturbance (symmetry: round-off, 1e-17 m), so
    # its percent changes are noise; chapter 6 compares it on perturbed replicates instead.
    for b in ref.DYNAMIC_BEHAVIOURS:
        for m in ("PVC", "Al", "Ti", "SS"):
            paper = ref.CLAIM_SS_TRACKING_PCT if m == "SS" else None
            claim = "SS tracks >= 55 % better than MD" if m == "SS" else "every material tracks better than MD"
            out.append(Quantity(f"tracking {m} vs MD, {b}", claim, "tracking_error_m", m, "MD", b, paper))
    for b in ref.DYNAMIC_BEHAVIOURS:
        out.append(
            Quantity(
                f"power SS vs MD, {b}",
                "materials need more power (up to +193 % for SS)",
                "power_w",
                "SS",
                "MD",
                b,
                ref.CLAIM_SS_POWER_MAX_PCT if b == "ramp" else None,
            )
        )
    out += [
        Quantity(
            "tracking rho-inc vs MD, ramp",
            "ramp: rho-inc -82 % tracking",
            "tracking_error_m",
            "rho-inc",
            "MD",
            "ramp",
            ref.CLAIM_RAMP_RHO_INC_TRACKING_PCT,
        ),
        Quantity(
            "power rho-inc vs MD, ramp",
            "ramp: rho-inc +123 % power",
            "power_w",
            "rho-inc",
            "MD",
            "ramp",
            ref.CLAIM_RAMP_RHO_INC_POWER_PCT,
        ),
        Quantity(
            "tracking rho-inc vs SS, ramp",
            "headline: rho-inc -35 % tracking vs SS",
            "tracking_error_m",
            "rho-inc",
            "SS",
            "ramp",
            ref.CLAIM_HEADLINE_TRACKING_PCT,
        ),
        Quantity(
            "power rho-inc vs SS, ramp",
            "headline: rho-inc -23 % power vs SS",
            "power_w",
            "rho-inc",
            "SS",
            "ramp",
            ref.CLAIM_HEADLINE_POWER_PCT,
        ),
    ]
    return tuple(out)


QUANTITIES = _quantities()


FINE_PHYSICS = "2e-5 s physics"  # the variant the claims table's time-step check reads


@dataclass(frozen=True)
class Variant:
    """One setting of the study: label, stiffness convention, sensor timing,
    physics step (s; None: the profile's) and substeps per control period,
    perturbed replicate seed (None: unperturbed), contact
    (:mod:`mat_hopper.core.contact`) and apex reference
    (:data:`mat_hopper.core.controller.APEX_REFERENCES`).

    The convention (any case) is stored as spelled in
    :data:`mat_hopper.core.materials.CONVENTIONS` and the sensor timing (a name,
    any case, or an integer latency) by its canonical name
    (:class:`mat_hopper.core.controller.SensorTiming`); ValueError for unknown ones.
    """

    label: str
    convention: str = "paper"
    sensor_timing: str = "authors"
    replicate: int | None = None
    timestep_s: float | None = None
    substeps: int = 1
    contact: str = DEFAULT_CONTACT
    apex_reference: str = DEFAULT_APEX_REFERENCE

    def __post_init__(self):
        object.__setattr__(self, "convention", check_convention(self.convention))
        object.__setattr__(self, "sensor_timing", SensorTiming(self.sensor_timing).name)
        object.__setattr__(self, "contact", check_contact(self.contact))
        object.__setattr__(self, "apex_reference", check_apex_reference(self.apex_reference))

    @property
    def kind(self) -> str:
        if self.replicate is not None:
            return "replicate"
        if self.timestep_s is not None:
            return "time step"
        if self.contact != DEFAULT_CONTACT:
            return "contact"
        if self.apex_reference != DEFAULT_APEX_REFERENCE:
            return "apex reference"
        return "convention" if self.convention != "paper" else "sensor latency"


DEFAULT = Variant("authors")


def variants(
    latencies=DEFAULT_LATENCIES,
    conventions=("paper", "axial"),
    replicates: int = 3,
    timesteps: bool = True,
    contacts=("stiff",),
    apex_references=("ground",),
) -> list[Variant]:
    """The study's variants, the default first: one per sensor latency
    (paper convention), one per other convention (authors' timing, axial
    runs with auto substeps), the two time-step variants (module doc), one
    per other contact and apex reference (the default's otherwise), one
    per replicate seed 0 .. replicates - 1 (default settings, perturbed).

    Args:
        latencies: sensor latencies in physics steps (each passed to :class:`mat_hopper.core.controller.SensorTiming`
            as an int); the default's (1, ``authors``) is not repeated.
        conventions: stiffness conventions, any case (each variant labelled
            and run by its canonical name); ``paper`` (the default's) is not
            repeated.
        replicates: the number of perturbed replicate seeds.
        timesteps: whether to add the two time-step variants (``2e-5 s physics``, ``2e-5 s step``).
        contacts: contacts (:data:`mat_hopper.core.contact.CONTACTS`), each a variant ``<name> contact``;
            the default's (``authors``) is not repeated.
        apex_references: apex references, each a variant ``apex above <name>``; ``world`` is not repeated.

    Returns:
        list[Variant]: :data:`DEFAULT` first, then the latency, convention, time-step, contact, apex
        reference and replicate variants in that order.

    Raises:
        ValueError: a latency outside [0, 1000] physics steps (:class:`mat_hopper.core.controller.SensorTiming`),
            or an unknown convention, contact or apex reference.
    """
    out = [DEFAULT]
    for lat in latencies:
        name = SensorTiming(int(lat)).name
        if name != DEFAULT.sensor_timing:
            out.append(Variant(name, sensor_timing=name))
    for conv in conventions:
        conv = check_convention(conv)
        if conv != DEFAULT.convention:
            out.append(Variant(conv, convention=conv))
    if timesteps:
        out.append(
            Variant(
                FINE_PHYSICS,
                sensor_timing=SensorTiming(FINE_SUBSTEPS).name,
                timestep_s=FINE_TIMESTEP_S,
                substeps=FINE_SUBSTEPS,
            )
        )
        out.append(Variant("2e-5 s step", timestep_s=FINE_TIMESTEP_S))
    for contact in contacts:
        contact = check_contact(contact)
        if contact != DEFAULT_CONTACT:
            out.append(Variant(f"{contact} contact", contact=contact))
    for apex in apex_references:
        apex = check_apex_reference(apex)
        if apex != DEFAULT_APEX_REFERENCE:
            out.append(Variant(f"apex above {apex}", apex_reference=apex))
    for seed in range(int(replicates)):
        out.append(Variant(f"replicate {seed}", replicate=seed))
    return out


def designs_and_behaviours() -> list[tuple[str, str]]:
    """The (design, behaviour) runs the quantities need, each once.

    Returns:
        list[tuple[str, str]]: (design, behaviour) pairs of every quantity's design and baseline,
        designs in the order of :data:`mat_hopper.core.materials.MONO_NAMES` (others after), then behaviours
        in the order of :data:`mat_hopper.core.behaviours.BEHAVIOUR_NAMES`.
    """
    pairs = []
    for q in QUANTITIES:
        for d in (q.design, q.baseline):
            if (d, q.behaviour) not in pairs:
                pairs.append((d, q.behaviour))
    order = {d: i for i, d in enumerate(MONO_NAMES)}
    return sorted(pairs, key=lambda p: (order.get(p[0], len(order)), BEHAVIOUR_NAMES.index(p[1])))


def quantity_values(hops: pd.DataFrame, runs: pd.DataFrame | None = None) -> pd.DataFrame:
    """Every quantity's value (percent change of means) per variant.

    Args:
        hops: per-hop rows with columns variant, design, behaviour and the
            metrics (``tracking_error_m``, ``power_w``).
        runs: one row per run with variant, design, behaviour and
            ``status`` ("ok" when usable) -- runs that diverged or fell give no
            value; None, empty or without ``status``: every run with hop rows counts as usable.

    Returns:
        DataFrame with columns variant, quantity_id, claim, paper_pct, value_pct: one row per variant
        (those of `hops`, then those only in `runs`) and quantity of :data:`QUANTITIES`. value_pct is
        the percent change (%) of the design's mean over its hop rows against the baseline's; nan where
        either run has no hop rows or is not usable, or the baseline's mean is round-off
        (:func:`mat_hopper.util.change.percent_change`). Empty (those columns) when neither table has a
        ``variant`` column.
    """
    columns = ["variant", "quantity_id", "claim", "paper_pct", "value_pct"]
    if "variant" not in hops.columns and (runs is None or "variant" not in runs.columns):
        return pd.DataFrame(columns=columns)
    if "variant" not in hops.columns:
        hops = pd.DataFrame(columns=["variant", "design", "behaviour", *{q.metric for q in QUANTITIES}])
    usable = None
    if runs is not None and len(runs) and "status" in runs.columns:
        ok = runs[runs["status"] == "ok"]
        usable = set(zip(ok["variant"], ok["design"], ok["behaviour"]))
    means = hops.groupby(["variant", "design", "behaviour"], sort=False)[sorted({q.metric for q in QUANTITIES})].mean()
    rows = []
    names = list(
        dict.fromkeys(
            [*(hops["variant"] if len(hops) else []), *(runs["variant"] if runs is not None and len(runs) else [])]
        )
    )
    for v in names:
        for q in QUANTITIES:
            a, b = (v, q.design, q.behaviour), (v, q.baseline, q.behaviour)
            have = a in means.index and b in means.index
            if usable is not None:
                have = have and a in usable and b in usable
            value = percent_change(means.loc[a, q.metric], means.loc[b, q.metric]) if have else np.nan
            rows.append(
                {
                    "variant": v,
                    "quantity_id": q.quantity_id,
                    "claim": q.claim,
                    "paper_pct": q.paper_pct,
                    "value_pct": float(value),
                }
            )
    return pd.DataFrame(rows, columns=["variant", "quantity_id", "claim", "paper_pct", "value_pct"])


def classify(value: float, default: float, factor: float = FACTOR) -> str:
    """``keeps``, ``moves > 2x``, ``flips`` or ``no value`` for one value
    against the default's (module doc).

    Args:
        value: the variant's value (a percent change, %).
        default: the default's value of the same quantity (%).
        factor: the ratio beyond which a value moves (default 2; the label stays ``moves > 2x``).

    Returns:
        str: ``no value`` where either is not finite or `default` is 0; ``flips`` where the signs differ
        (a `value` of exactly 0 included); ``keeps`` where value / default lies in [1 / factor, factor];
        ``moves > 2x`` otherwise.
    """
    if not (np.isfinite(value) and np.isfinite(default)) or default == 0:
        return NO_VALUE
    if np.sign(value) != np.sign(default):
        return FLIPS
    ratio = value / default
    return KEEPS if 1.0 / factor <= ratio <= factor else MOVES


def robustness_table(values: pd.DataFrame, default: str = DEFAULT.label) -> pd.DataFrame:
    """values (:func:`quantity_values`) with the default's value beside each
    row, the ratio to it and the class (:func:`classify`).

    Args:
        values: :func:`quantity_values`'s table (variant, quantity_id, value_pct, ...).
        default: the label of the default variant.

    Returns:
        DataFrame: a copy of `values` with default_pct (the default variant's value_pct of the same
        quantity, nan where it has none), ratio_to_default (value_pct / default_pct) and class
        (:func:`classify`, factor 2; the default's own rows included).
    """
    base = values[values["variant"] == default].set_index("quantity_id")["value_pct"]
    out = values.copy()
    out["default_pct"] = out["quantity_id"].map(base)
    out["ratio_to_default"] = out["value_pct"] / out["default_pct"]
    out["class"] = [classify(v, d) for v, d in zip(out["value_pct"], out["default_pct"])]
    return out


def summary(table: pd.DataFrame, default: str = DEFAULT.label) -> pd.DataFrame:
    """Per quantity: the default's value, the paper's, the range over the
    variants, and how many variants keep it, move it more than 2x or flip
    it (the default itself not counted).

    Args:
        table: :func:`robustness_table`'s table.
        default: the label of the default variant.

    Returns:
        DataFrame, one row per quantity that has a non-default variant. Columns: quantity_id, paper_pct,
        default_pct (nan without the default's row), min_pct, max_pct (over the other variants), the
        count of variants in each class (keeps, moves > 2x, flips, no value), flipped_by and moved_by
        (the variants' labels, comma-separated).
    """
    t = table[table["variant"] != default]
    rows = []
    for qid, g in t.groupby("quantity_id", sort=False):
        counts = g["class"].value_counts()
        d = table[(table["variant"] == default) & (table["quantity_id"] == qid)]
        rows.append(
            {
                "quantity_id": qid,
                "paper_pct": g["paper_pct"].iloc[0],
                "default_pct": float(d["value_pct"].iloc[0]) if len(d) else np.nan,
                "min_pct": g["value_pct"].min(),
                "max_pct": g["value_pct"].max(),
                **{c: int(counts.get(c, 0)) for c in CLASSES},
                "flipped_by": ", ".join(g.loc[g["class"] == FLIPS, "variant"]),
                "moved_by": ", ".join(g.loc[g["class"] == MOVES, "variant"]),
            }
        )
    return pd.DataFrame(rows)


FINE_LABEL = "2e-5 s physics (control 1e-4 s)"


def fine_step_hops(robustness_hops: pd.DataFrame | None) -> pd.DataFrame | None:
    """The robustness study's finer-physics runs (2e-5 s, five substeps per
    control period, the same 1e-4 s sensor delay) as the claims table's
    time-step check reads them (paper convention, unperturbed).

    Args:
        robustness_hops: the robustness study's per-hop rows (with a ``variant`` column), or None.

    Returns:
        DataFrame or None: the rows of the ``2e-5 s physics`` variant without their ``sensor_timing``
        column, for :func:`mat_hopper.analysis.claims.claims_table`'s ``fine_hops``; None where the table
        is None, empty, has no ``variant`` column or no such rows.
    """
    if robustness_hops is None or len(robustness_hops) == 0 or "variant" not in robustness_hops.columns:
        return None
    fine = robustness_hops[robustness_hops["variant"] == FINE_PHYSICS]
    return fine.drop(columns=["sensor_timing"], errors="ignore") if len(fine) else None
