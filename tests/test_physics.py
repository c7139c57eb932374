"""The paper's protocol on every mono-material and behaviour (60 s runs).

Slow (about a minute on two cores), and run by CI."""

import multiprocessing as mp
from concurrent.futures import ProcessPoolExecutor

import pytest

from mat_hopper.behaviours import BEHAVIOUR_NAMES
from mat_hopper.materials import MONO_NAMES

CASES = [(d, b) for d in MONO_NAMES for b in BEHAVIOUR_NAMES]


def _run(case):
    from mat_hopper.metrics import hop_table
    from mat_hopper.sim import simulate
    design, beh = case
    r = simulate(design, beh, duration_s=60.0)
    hops = hop_table(r)
    return {"stable": r.stable, "mean_height": float(hops.hop_height_m.mean()), "n": len(hops),
            "x_end": float(r.base_pos[-1, 0]), "x_des_end": float(r.desired_pos[-1, 0])}


@pytest.fixture(scope="module")
def results():
    with ProcessPoolExecutor(2, mp_context=mp.get_context("spawn")) as pool:
        return dict(zip(CASES, pool.map(_run, CASES)))


@pytest.mark.slow
@pytest.mark.parametrize("case", CASES, ids=[f"{d}-{b}" for d, b in CASES])
def test_hop_height_held_at_one_metre(results, case):
    r = results[case]
    assert r["stable"] and r["n"] >= 50
    assert r["mean_height"] == pytest.approx(1.0, abs=0.03)


@pytest.mark.slow
@pytest.mark.parametrize("design", MONO_NAMES)
def test_forward_hopping_ends_near_the_desired_x(results, design):
    r = results[(design, "forward")]
    assert abs(r["x_end"] - r["x_des_end"]) < 0.1
