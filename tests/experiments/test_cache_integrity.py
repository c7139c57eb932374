"""A content checksum in every cached result. A damaged
file (a flipped bit, a truncation, a foreign file) is recomputed, never
loaded: of many random single-bit flips, every file that still loads gives
back exactly the stored table and summary."""

from __future__ import annotations

import logging
import os
import shutil

import numpy as np
import pandas as pd
import pytest

from mat_hopper.core.behaviours import behaviour
from mat_hopper.core.materials import parse_design
from mat_hopper.core.sim import SimSettings
from mat_hopper.experiments.cache import Cache, content_checksum
from mat_hopper.experiments.runner import RunSpec, run_grid
from mat_hopper.util.keys import hash_key

SHORT = SimSettings(duration_s=2.5, timestep_s=1e-4, transient_s=0.5)
SS_KEY = {"design": "SS"}
K = f"run-{hash_key(SS_KEY)}"  # a file's name is its stored key's hash


def _frame(rng, n=40):
    return pd.DataFrame(
        {
            "design": ["SS"] * (n - 1) + [None],
            "hop": np.arange(n),
            "tracking_error_m": rng.random(n),
            "power_w": np.where(np.arange(n) == 3, np.nan, rng.random(n)),
            "stable": [True] * n,
        }
    )


def test_checksum_is_written_verified_and_independent_of_arrow_layout(tmp_path):
    import pyarrow as pa
    import pyarrow.parquet as pq

    rng = np.random.default_rng(1)
    frame = _frame(rng)
    cache = Cache(tmp_path)
    cache.store(K, frame, {"n_hops": 40, "power_w": 1.5}, SS_KEY)
    got, summary = cache.load(K)
    pd.testing.assert_frame_equal(got, frame)
    assert summary == {"n_hops": 40, "power_w": 1.5}
    stored = pq.read_table(cache.path(K))
    payload = stored.schema.metadata[b"mat_hopper"]
    assert stored.schema.metadata[b"mat_hopper_sha256"].decode() == content_checksum(stored, payload)
    # one value changed, the summary changed, a column renamed: another checksum
    t = pa.Table.from_pandas(frame, preserve_index=False)
    other = frame.copy()
    other.loc[7, "tracking_error_m"] = np.nextafter(other.loc[7, "tracking_error_m"], 2.0)  # one ulp
    assert content_checksum(pa.Table.from_pandas(other, preserve_index=False), payload) != content_checksum(t, payload)
    assert content_checksum(t, payload + b" ") != content_checksum(t, payload)
    renamed = pa.Table.from_pandas(frame.rename(columns={"hop": "hops"}), preserve_index=False)
    assert content_checksum(renamed, payload) != content_checksum(t, payload)


def test_random_bit_flips_never_load_changed_numbers(tmp_path, caplog):
    rng = np.random.default_rng(12)
    cache = Cache(tmp_path)
    frame = _frame(rng)
    summary = {"n_hops": 40, "power_w": 1.2345678901234567, "status": "ok"}
    cache.store(K, frame, summary, SS_KEY)
    clean = open(cache.path(K), "rb").read()
    loaded = rejected = 0
    with caplog.at_level(logging.WARNING, logger="mat_hopper.cache"):
        for _ in range(400):
            damaged = bytearray(clean)
            pos = int(rng.integers(len(damaged)))
            damaged[pos] ^= 1 << int(rng.integers(8))
            with open(cache.path(K), "wb") as f:
                f.write(bytes(damaged))
            got = cache.load(K)
            if got is None:
                rejected += 1
                continue
            loaded += 1  # a flip in bytes that carry no content (padding, statistics)
            pd.testing.assert_frame_equal(got[0], frame)
            assert got[1] == summary
    assert rejected > 200 and loaded + rejected == 400
    assert "damaged" in caplog.text
    # truncated and foreign files too
    with open(cache.path(K), "wb") as f:
        f.write(clean[: len(clean) // 2])
    assert cache.load(K) is None
    with open(cache.path(K), "wb") as f:
        f.write(b"PAR1 not ours")
    assert cache.load(K) is None


def test_a_damaged_result_is_recomputed_and_the_grid_is_as_clean(tmp_path):
    tasks = [RunSpec(parse_design("SS"), behaviour("forward"), SHORT, {"experiment": "t"})]
    clean = run_grid(tasks, tmp_path / "a", workers=1, progress=False)
    run_grid(tasks, tmp_path / "b", workers=1, progress=False)
    cache = Cache(tmp_path / "b")
    (key,) = cache.keys()
    data = open(cache.path(key), "rb").read()
    # the first single-bit flip from a quarter of the file on that changes what loads
    # (some bytes carry no content: page statistics, padding)
    for pos in range(len(data) // 4, len(data)):
        damaged = bytearray(data)
        damaged[pos] ^= 0x10
        with open(cache.path(key), "wb") as f:
            f.write(bytes(damaged))
        if cache.load(key) is None:
            break
    again = run_grid(tasks, tmp_path / "b", workers=1, progress=False)
    assert (again.n_cached, again.n_computed) == (0, 1)
    pd.testing.assert_frame_equal(again.tables, clean.tables)
    pd.testing.assert_frame_equal(again.summary, clean.summary)
    assert run_grid(tasks, tmp_path / "b", workers=1, progress=False).n_cached == 1


@pytest.mark.parametrize("missing", [b"mat_hopper_sha256", b"mat_hopper"])
def test_a_file_without_checksum_or_summary_is_recomputed(tmp_path, missing):
    import pyarrow.parquet as pq

    cache = Cache(tmp_path)
    k = f"run-{hash_key({})}"
    cache.store(k, _frame(np.random.default_rng(2)), {"n": 1}, {})
    t = pq.read_table(cache.path(k))
    meta = {k: v for k, v in t.schema.metadata.items() if k != missing}
    shutil.copy(cache.path(k), tmp_path / "orig.parquet")
    pq.write_table(t.replace_schema_metadata(meta), cache.path(k))
    assert cache.load(k) is None


def test_a_file_moved_under_another_key_is_recomputed_not_loaded(tmp_path, caplog):
    # two intact files swapped by hand: each checksum holds, but neither is its name's result
    cache = Cache(tmp_path)
    other = {"design": "Ti"}
    k2 = f"run-{hash_key(other)}"
    cache.store(K, _frame(np.random.default_rng(3)), {"n": 1}, SS_KEY)
    cache.store(k2, _frame(np.random.default_rng(4)), {"n": 2}, other)
    os.replace(cache.path(K), tmp_path / "swap")
    os.replace(cache.path(k2), cache.path(K))
    os.replace(tmp_path / "swap", cache.path(k2))
    with caplog.at_level(logging.WARNING, logger="mat_hopper.cache"):
        assert cache.load(K) is None and cache.load(k2) is None
    assert "holds the result of another key" in caplog.text


def test_an_empty_cache_variable_is_an_error_naming_it(monkeypatch):
    from mat_hopper.experiments.cache import Cache

    monkeypatch.setenv("MAT_HOPPER_CACHE", " ")
    with pytest.raises(ValueError, match=r"\$MAT_HOPPER_CACHE is set but empty"):
        Cache()
