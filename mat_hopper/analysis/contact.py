"""Contact chatter: how often the toe's raw touch signal switches per
touchdown.

A clean stance switches the touch signal twice: contact on at touchdown,
off at lift-off. The authors' hip laws switch on the raw signal (attitude
law while touching, flight PD while not), so a contact that chatters in
stance alternates the hips between the two laws within one stance. Chapter
8 uses this to explain the rigid MD leg's ramp baseline.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..core.controller import TOUCHDOWN


def contact_toggles(rollout, transient_s: float | None = None) -> float:
    """Mean number of changes of the toe's contact state (touch sensor
    > 0 N: contact) per controller touchdown, over the recorded samples
    from `transient_s` on (default: the rollout's scored window,
    ``rollout.settings.transient_s``). 2.0 is a clean hop (on, off); more
    is chatter.

    Counted on the recorded samples: record at the physics rate
    (``record_rate_hz = 1 / timestep_s``) to see every toggle; a coarser
    record can only undercount. Raises ValueError when no touchdown falls
    in the window.

    Args:
        rollout: a :class:`mat_hopper.core.rollout.Rollout` (from :func:`mat_hopper.core.sim.simulate`); its touch
            channel (N), time (s) and the state machine's events are read.
        transient_s: start of the window, s (simulated time); None: ``rollout.settings.transient_s``.

    Returns:
        float: the contact-state changes between consecutive recorded samples at or after `transient_s`,
        divided by the controller's touchdown events at or after it.

    Raises:
        ValueError: no touchdown event at or after `transient_s`.
    """
    t0 = rollout.settings.transient_s if transient_s is None else float(transient_s)
    t = rollout.time
    keep = t >= t0
    contact = rollout.touch[keep] > 0.0
    toggles = int(np.count_nonzero(contact[1:] != contact[:-1]))
    ev = rollout.events
    touchdowns = int(np.count_nonzero((ev[:, 1] == TOUCHDOWN) & (ev[:, 0] >= t0)))
    if touchdowns == 0:
        raise ValueError(
            f"contact_toggles: no touchdown at or after {t0:g} s in this rollout "
            f"({rollout.design.name}, {rollout.behaviour.name})"
        )
    return toggles / touchdowns


def contact_table(rollouts) -> pd.DataFrame:
    """:func:`contact_toggles` of each rollout, one row each: design,
    behaviour, timestep_s, record_rate_hz, toggles_per_touchdown.

    Args:
        rollouts: an iterable of :class:`mat_hopper.core.rollout.Rollout`, each counted over its scored window
            (``settings.transient_s`` on).

    Returns:
        DataFrame, one row per rollout in the given order. Columns: design, behaviour (names),
        timestep_s (the physics step, s), record_rate_hz (Hz), toggles_per_touchdown.

    Raises:
        ValueError: a rollout with no touchdown in its scored window (from :func:`contact_toggles`).
    """
    rows = []
    for r in rollouts:
        rows.append(
            {
                "design": r.design.name,
                "behaviour": r.behaviour.name,
                "timestep_s": r.settings.timestep_s,
                "record_rate_hz": r.settings.record_rate_hz,
                "toggles_per_touchdown": contact_toggles(r),
            }
        )
    return pd.DataFrame(rows)
