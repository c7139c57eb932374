"""Bad arguments to the batch API: one ValueError naming the mistake, before any work."""

import re

import pandas as pd
import pytest

from mat_hopper.batch import BatchSettings, agreement, evaluate
from mat_hopper.experiments.robustness import batch_runs, batch_variants


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: evaluate("SS", "forward"), "got the string 'SS'"),
        (lambda: evaluate(["SS"], "forward", {"duration_s": 1.0}), "settings must be a BatchSettings"),
        (lambda: evaluate(["SS"], "forward", workers=0), "workers must be an integer >= 1"),
        (lambda: evaluate(["SS"], "forward", workers=2.5), "workers must be an integer >= 1"),
        (lambda: evaluate(["SS"], "forward", device="cuda"), "for backend='warp'"),
        (lambda: evaluate(["SS"], "forward", max_batch=-5), "max_batch must be an integer >= 1"),
        (lambda: evaluate(["SS"], "forward", backend="warp", workers=2), "workers is for backend='mujoco'"),
        (lambda: evaluate(["SS"], "forward", backend="gpu"), "unknown backend 'gpu'"),
        # the backend's name is read any case: "MuJoCo" is the mujoco backend, so device is refused
        (lambda: evaluate(["SS"], "forward", backend="MuJoCo", device="cuda"), "for backend='warp'"),
        (lambda: agreement(pd.DataFrame(), pd.DataFrame()), "has no column design"),
        (lambda: agreement(None, None), "must be a batch table"),
        (lambda: batch_variants("foo"), "must be Variant objects"),
        (lambda: batch_runs("quick", [], backend="mujoco"), "no variants to run"),
        (lambda: batch_runs("turbo", backend="mujoco"), "unknown profile 'turbo'"),
    ],
)
def test_bad_arguments_are_one_value_error(call, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        call()


def test_settings_none_are_the_papers_protocol():
    s = BatchSettings()
    assert (s.duration_s, s.transient_s, s.timestep_s, s.sensor_timing) == (60.0, 20.0, 1e-4, "authors")


def test_batch_settings_are_a_view_of_sim_settings():
    from dataclasses import fields

    from mat_hopper.core.perturbations import Perturbation
    from mat_hopper.core.sim import SimSettings

    # no second declaration: exactly SimSettings' fields, defaults and checks
    assert [f.name for f in fields(BatchSettings)] == [f.name for f in fields(SimSettings)]
    sim = SimSettings(duration_s=2.0, transient_s=0.5, sensor_timing="fresh", segment_mass="capsule")
    b = BatchSettings.of(sim)
    assert isinstance(b, SimSettings) and int(b.sensor_timing) == 0 and b.segment_mass == "capsule"
    assert BatchSettings.of(b) is b
    with pytest.raises(ValueError, match="substeps must be 1 in a batch"):
        BatchSettings.of(SimSettings(timestep_s=5e-5, substeps=2))
    with pytest.raises(ValueError, match="perturbation must be None in a batch"):
        BatchSettings(perturbation=Perturbation.replicate(0))
    with pytest.raises(ValueError, match="transient"):
        BatchSettings(duration_s=1.0, transient_s=2.0)  # SimSettings' own check
