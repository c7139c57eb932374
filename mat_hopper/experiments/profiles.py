"""Run profiles: how long and how fine every run of a reproduction is.

``paper`` is the paper's protocol; ``quick`` is for CI and first looks.
``MAT_HOPPER_PROFILE`` picks the default. Results carry a ``profile``
column.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, replace

import pandas as pd

from .. import reference as ref
from ..materials import check_convention
from ..perturbations import Perturbation
from ..sim import SimSettings

PROFILE_ENV = "MAT_HOPPER_PROFILE"


def check_replicates(replicates) -> int:
    if isinstance(replicates, bool) or not isinstance(replicates, int) or replicates < 0:
        raise ValueError(f"replicates must be an integer >= 0 (runs per design and behaviour), got {replicates!r}")
    return replicates


@dataclass(frozen=True)
class Profile:
    """How long and how fine every run of a reproduction is.

    duration_s, transient_s, timestep_s: each hopping run (s);
    stability_grid_size: the map is size x size designs;
    stability_duration_s: static hopping per stability try (s);
    stability_tolerance: bisection stops when the bracket is within this
    factor; stability_max_iter: bisection tries at most; stability_scan:
    also run the 20-step protocol of docs/reference-hopper.md; record_rate_hz: samples per
    simulated second; convention: modulus-to-stiffness convention;
    axial_timestep_s: the time step (s) of runs under the ``axial``
    convention, whose springs (k = E A / L, SS 3.8e9 N/m) diverge at the
    paper's 1e-4 s: every catalogue design is stable at 2e-5 s;
    book_replicates: perturbed replicate runs per design where the book
    compares replicates (hopping in place, chapter 6). With n per design
    the smallest Holm-adjusted p of that family of four comparisons is
    4 x 2 / C(2n, n): 0.11 at n = 4, 0.032 at n = 5, 0.0087 at n = 6; the
    paper profile's 6 leaves room below 0.05 for runs that do not
    separate perfectly, the quick profile's 3 cannot reach it."""

    name: str
    duration_s: float
    transient_s: float
    timestep_s: float = ref.TIMESTEP_S
    stability_grid_size: int = ref.STABILITY_GRID_SIZE
    stability_duration_s: float = ref.STABILITY_TEST_DURATION_S
    stability_tolerance: float = 1.25
    stability_max_iter: int = 10
    stability_scan: bool = True
    record_rate_hz: float = 1000.0
    convention: str = "paper"
    axial_timestep_s: float = 2e-5
    book_replicates: int = 6

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f"profile name must be a non-empty string, got {self.name!r}")
        self.sim_settings()  # validates duration, transient, time step, convention
        if int(self.stability_grid_size) < 1:
            raise ValueError(f"stability_grid_size must be >= 1, got {self.stability_grid_size!r}")
        if not self.stability_duration_s > 0:
            raise ValueError(f"stability_duration_s must be > 0 s, got {self.stability_duration_s!r}")
        if not self.stability_tolerance > 1:
            raise ValueError(f"stability_tolerance must be a factor > 1, got {self.stability_tolerance!r}")
        check_replicates(self.book_replicates)
        if int(self.stability_max_iter) < 0:
            raise ValueError(f"stability_max_iter must be >= 0, got {self.stability_max_iter!r}")

    def for_convention(self, convention: str) -> Profile:
        """This profile under another stiffness convention (and its time step)."""
        check_convention(convention)
        if convention == self.convention:
            return self
        dt = self.axial_timestep_s if convention == "axial" else ref.TIMESTEP_S
        return replace(self, convention=convention, timestep_s=dt)

    def sim_settings(self, perturbation: Perturbation | None = None) -> SimSettings:
        return SimSettings(
            duration_s=self.duration_s,
            timestep_s=self.timestep_s,
            transient_s=self.transient_s,
            convention=self.convention,
            record_rate_hz=self.record_rate_hz,
            perturbation=perturbation,
        )


PROFILES = {
    "paper": Profile(
        "paper", ref.DURATION_S, ref.TRANSIENT_S, ref.TIMESTEP_S, ref.STABILITY_GRID_SIZE, ref.STABILITY_TEST_DURATION_S
    ),
    "quick": Profile("quick", 12.0, 4.0, ref.TIMESTEP_S, 4, 1.0, stability_tolerance=1.5, book_replicates=3),
}


def get_profile(name: str | Profile | None = None) -> Profile:
    """A profile by name (``paper`` or ``quick``); None: $MAT_HOPPER_PROFILE,
    else ``paper``. A Profile is returned as is."""
    if isinstance(name, Profile):
        return name
    if name is None:
        name = os.environ.get(PROFILE_ENV) or "paper"
    key = str(name).strip().lower()
    if key not in PROFILES:
        src = f" (from ${PROFILE_ENV})" if name == os.environ.get(PROFILE_ENV) else ""
        raise ValueError(f"unknown profile {name!r}{src}; accepted: {', '.join(PROFILES)}")
    return PROFILES[key]


_PROFILE_FIELDS = (
    ("duration_s", "run length (s of simulated time)"),
    ("transient_s", "transient, hop cycles before it not scored (s)"),
    ("timestep_s", "physics time step (s)"),
    ("record_rate_hz", "recorded samples per simulated second (Hz)"),
    ("convention", "modulus-to-stiffness convention"),
    ("axial_timestep_s", "time step of runs under the axial convention (s)"),
    ("stability_grid_size", "stable-time-step map: designs per axis"),
    ("stability_duration_s", "stable-time-step map: static hopping per try (s)"),
    ("book_replicates", "perturbed replicates per design, hopping in place (chapter 6)"),
)


def profile_table(profile: str | Profile | None = None) -> pd.DataFrame:
    """The profile's settings beside the paper's protocol (the ``paper``
    profile): columns setting, meaning, this build, paper."""
    prof = get_profile(profile)
    paper = PROFILES["paper"]
    rows = [
        {"setting": f, "meaning": m, "this build": getattr(prof, f), "paper": getattr(paper, f)}
        for f, m in _PROFILE_FIELDS
    ]
    return pd.DataFrame(rows)
