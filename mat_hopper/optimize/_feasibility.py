"""Why a study's trials are not feasible, and why a run is no baseline.

A finished trial (complete, or failed with an error) is feasible when it
ran and met every constraint. Each of the others has one reason, the
first that applies in this order:

1. ``leg mass``: outside the leg-mass band (skipped before any run,
   :mod:`mat_hopper.optimize._mass`, or run by an older study);
2. ``error``: its runs raised;
3. ``diverged``: a run's state went non-finite (the time it did is in
   the trial's runs);
4. ``fell``: a run ended with the base below 0.1 m;
5. ``hop height``: the mean hop height off its target by more than the
   tolerance;
6. ``peak stress``, ``fatigue life``: the stress constraints.

:func:`feasibility` counts them (:class:`Feasibility`, whose text is the
line a study ends with); :func:`fall_reason` says how a design's runs
fell or diverged, so that a report leaves such a run out as a baseline
and says why.
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass, field

from optuna.trial import TrialState

from ._mass import SKIPPED_ATTR
from ._objective import RESULT_ATTR
from ._scoring import leg_mass_band_kg
from ._storage import ERROR_ATTR

LEFT_OUT_ATTR = "left_out"  # racing: trial user attr, why a trial that fell was not promoted
PRUNED_WHY_ATTR = "pruned_why"  # racing: trial user attr, "diverged" or "fell" on the rung it was pruned at
PRUNED_REASONS = ("diverged", "fell", "fell or diverged", "ranked out")  # why racing pruned a trial
# Each in the words of the outputs: a trial that diverged or fell on a
# screening rung is named so; only one ranked below those promoted was pruned.
PRUNED_WORDS = {
    "diverged": "diverged",
    "fell": "fell",
    "fell or diverged": "fell or diverged",
    "ranked out": "pruned by racing (ranked out)",
}
REASONS = ("leg mass", "error", "diverged", "fell", "hop height", "peak stress", "fatigue life")
_CONSTRAINT_REASON = {"leg_mass": "leg mass", "hop_height": "hop height", "peak_stress": "peak stress",
                      "fatigue_life": "fatigue life"}  # fmt: skip


def _where(row: dict) -> str:
    rep = row.get("replicate", -1)
    rep = -1 if rep is None else int(rep)
    return f"{row.get('behaviour', '?')}" + (f", replicate seed {rep}" if rep >= 0 else "")


def fall_reason(rows) -> str | None:
    """How a design's runs went wrong, or None when every one ended upright.

    Args:
        rows: its per-run rows (an Evaluation's ``per_behaviour``, or a
            trial's stored ``result``'s): ``upright``, ``diverged_at_s``,
            ``behaviour``, ``replicate``.

    Returns:
        ``diverged at t = 0.0043 s (ramp)`` (the first run that diverged),
        else ``fell (ramp, replicate seed 1001: base below 0.1 m at the
        end)``, else None.
    """
    rows = list(rows or [])
    for r in rows:
        t = r.get("diverged_at_s")
        if t is not None and not (isinstance(t, float) and math.isnan(t)):
            return f"diverged at t = {float(t):.4g} s ({_where(r)})"
    for r in rows:
        if not r.get("upright", True):
            return f"fell ({_where(r)}: base below 0.1 m at the end)"
    return None


@dataclass
class Feasibility:
    """A study's finished trials: how many, how many feasible, and the
    others counted by reason (:data:`REASONS`, module doc)."""

    finished: int = 0
    feasible: int = 0
    reasons: dict = field(default_factory=dict)
    labels: dict = field(default_factory=dict)  # reason -> its words for this study (units, bounds)
    pruned: int = 0  # racing: trials stopped at a lower rung, judged at no full fidelity
    pruned_reasons: dict = field(default_factory=dict)  # PRUNED_REASONS -> count

    def text(self) -> str:
        """The line a study ends with, e.g. ``feasible: 9 of 12 finished
        trials; not feasible: 2 hop height outside 1 +- 0.05 m, 1 fell``.
        Under racing, finished trials are those run at full fidelity, and
        the trials stopped on a screening rung are counted by why, a
        diverged one named diverged (``feasible: 2 of 2 trials finished at
        full fidelity (7 more stopped on a screening rung: 6 diverged, 1
        pruned by racing, ranked out)``)."""
        if not self.pruned:
            head = f"feasible: {self.feasible} of {self.finished} finished trials"
        else:
            head = f"feasible: {self.feasible} of {self.finished} trials finished at full fidelity"
            why = ", ".join(
                f"{self.pruned_reasons[r]} {PRUNED_WORDS[r]}" for r in PRUNED_REASONS if self.pruned_reasons.get(r)
            )
            head += f" ({self.pruned} more stopped on a screening rung{f': {why}' if why else ''})"
        if self.feasible == self.finished:
            return head
        parts = [f"{self.reasons[r]} {self.labels.get(r, r)}" for r in REASONS if self.reasons.get(r)]
        return f"{head}; not feasible: {', '.join(parts)}"


def trial_reason(t, constraint_names) -> str | None:
    """The reason (:data:`REASONS`) a finished trial is not feasible, or None when it is."""
    ua = t.user_attrs
    if t.state == TrialState.FAIL:
        return "leg mass" if ua.get(SKIPPED_ATTR) == "leg_mass" else "error"
    res = ua.get(RESULT_ATTR) or {}
    cons = dict(t.constraints) if t.constraints else {}
    if cons.get("leg_mass", 0.0) > 0:
        return "leg mass"
    why = fall_reason(res.get("per_behaviour"))
    if why is not None:
        return "diverged" if why.startswith("diverged") else "fell"
    if cons.get("unstable", 0.0) > 0:  # a backend without per-run rows
        return "fell"
    for name in constraint_names:
        if cons.get(name, 0.0) > 0 and name in _CONSTRAINT_REASON:
            return _CONSTRAINT_REASON[name]
    return None if res.get("feasible", all(c <= 0 for c in cons.values())) else "hop height"


def trial_outcome(t, constraint_names) -> str | None:
    """Why a trial is not feasible, as the trials table and an exported
    trial name it: a finished trial's :func:`trial_reason`; for a trial
    racing stopped on a screening rung, ``diverged (screening rung)``,
    ``fell (screening rung)``, ``fell or diverged (screening rung)`` or
    ``pruned by racing (ranked out)``; None for a feasible trial, and for
    one running or waiting."""
    if t.state == TrialState.PRUNED:
        why = _pruned_reason(t)
        return PRUNED_WORDS[why] + ("" if why == "ranked out" else " (screening rung)")
    if t.state in (TrialState.COMPLETE, TrialState.FAIL):
        return trial_reason(t, constraint_names)
    return None


def _pruned_reason(t) -> str:
    """Why racing pruned a trial (:data:`PRUNED_REASONS`): its runs
    diverged or fell on a rung (an older study records "fell or diverged"
    only), else it ranked below the trials promoted."""
    ua = t.user_attrs
    if ua.get(PRUNED_WHY_ATTR) in ("diverged", "fell"):
        return ua[PRUNED_WHY_ATTR]
    return "fell or diverged" if LEFT_OUT_ATTR in ua else "ranked out"


def feasibility(study, config) -> Feasibility:
    """Count a study's finished trials by feasibility (module doc).

    Args:
        study: the ``optuna.Study``.
        config: its :class:`~mat_hopper.optimize._study.StudyConfig`.

    Returns:
        A :class:`Feasibility`.
    """
    ob = config.objective
    names = ob.constraint_names
    out = Feasibility()
    counts: Counter = Counter()
    for t in study.get_trials(deepcopy=False, states=(TrialState.COMPLETE, TrialState.FAIL)):
        if t.state == TrialState.FAIL and ERROR_ATTR not in t.user_attrs:
            continue  # a trial whose process died: retried, not finished
        out.finished += 1
        why = trial_reason(t, names)
        if why is None:
            out.feasible += 1
        else:
            counts[why] += 1
    out.reasons = dict(counts)
    pruned = study.get_trials(deepcopy=False, states=(TrialState.PRUNED,))
    out.pruned = len(pruned)
    out.pruned_reasons = dict(Counter(_pruned_reason(t) for t in pruned))
    band = leg_mass_band_kg(ob, config.space.n_segments)
    out.labels = {
        "hop height": f"hop height outside {ob.hop_height_target_m:g} +- {ob.hop_height_tolerance_m:g} m",
        "fell": "fell (base below 0.1 m)",
        "error": "raised an error",
        **({"leg mass": f"leg mass outside {band[0]:.4g} to {band[1]:.4g} kg"} if band else {}),
    }
    return out
