"""mat_hopper.util.keys: what a cached result depends on."""

import os

import pytest

from mat_hopper.core.controller import ControllerSettings
from mat_hopper.core.materials import LegDesign
from mat_hopper.core.perturbations import Perturbation
from mat_hopper.core.sim import SimSettings
from mat_hopper.util import keys


def test_hash_key_is_sha256_of_sorted_json():
    # sha256 of '{"a": 1, "b": [1, 2]}', from the command line: echo -n ... | sha256sum
    assert keys.hash_key({"b": (1, 2), "a": 1}) == "e6f20bdc3757e5e7be4e316d"
    assert keys.hash_key({"a": 1, "b": [1, 2]}) == keys.hash_key({"b": [1, 2], "a": 1})


def test_design_key_is_physics_not_names():
    ss = LegDesign.mono("SS")
    assert keys.design_key(ss) == {"n_segments": 3, "densities_g_cm3": [8.0] * 3, "moduli_gpa": [193.0] * 3}
    renamed = LegDesign.from_properties([8.0] * 3, [193.0] * 3, name="steel")
    assert keys.design_key(renamed) == keys.design_key(ss)
    assert keys.design_key(LegDesign.mono("MD"))["moduli_gpa"] == [None] * 3  # rigid


def test_settings_key_names_every_setting_and_conventions_by_name():
    k = keys.settings_key(SimSettings(sensor_timing=5, perturbation=Perturbation(seed=2)))
    assert set(k) == {
        "duration_s",
        "timestep_s",
        "transient_s",
        "convention",
        "record_rate_hz",
        "controller",
        "perturbation",
        "sensor_timing",
        "segment_mass",
        "substeps",
        "damping",
        "contact",
        "apex_reference",
        "replicate_protocol",
    }
    assert k["replicate_protocol"] == "authors"
    assert keys.settings_key(SimSettings(replicate_protocol="Branch"))["replicate_protocol"] == "branch"
    assert k["damping"] == "authors"  # issue 21's setting, by its name
    assert k["contact"] == "authors" and keys.settings_key(SimSettings(contact="Stiff"))["contact"] == "stiff"
    assert k["sensor_timing"] == "latency-5" and k["convention"] == "paper" and k["substeps"] == 1
    assert k["controller"]["flight_kp"] == 10.0 and k["perturbation"]["seed"] == 2
    assert keys.settings_key(SimSettings())["sensor_timing"] == "authors"
    assert keys.settings_key(SimSettings())["perturbation"] is None
    other = keys.settings_key(SimSettings(controller=ControllerSettings(flight_kp=11.0)))
    assert keys.hash_key(other) != keys.hash_key(keys.settings_key(SimSettings()))


def test_versions_carry_the_source_digest():
    v = keys.versions()
    assert set(v) == {"mat_hopper", "source", "mujoco"} and len(v["source"]) == 16 and int(v["source"], 16) >= 0
    import mat_hopper

    root = os.path.dirname(mat_hopper.__file__)
    assert all(os.path.isfile(os.path.join(root, *f"{m}.py".split("/"))) for m in keys.RESULT_MODULES)
    assert {"core/sim", "core/rollout", "core/_loop", "util/keys", "experiments/cache"} <= set(keys.RESULT_MODULES)
    # every module of the core and the physics makes or summarises results
    for room in ("core", "physics"):
        names = {f[:-3] for f in os.listdir(os.path.join(root, room)) if f.endswith(".py") and f != "__init__.py"}
        assert {f"{room}/{n}" for n in names} <= set(keys.RESULT_MODULES), room


@pytest.mark.parametrize("bad", [object(), {1, 2}])
def test_json_default_refuses_what_it_cannot_write(bad):
    with pytest.raises(TypeError, match="not JSON serialisable"):
        keys.json_default(bad)
