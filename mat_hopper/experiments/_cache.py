"""The result cache and its keys (private; :mod:`mat_hopper.experiments.runner`
re-exports both).

- Keys: :func:`design_key` and :func:`settings_key` say what a result
  depends on, :func:`versions` adds mat-hopper's version, a digest of the
  source that makes results (:data:`RESULT_MODULES`) and MuJoCo's version;
  :func:`hash_key` names the file.
- :class:`Cache`: one parquet file per key, written atomically, with a
  content checksum verified on every load (a mismatch is recomputed, never
  loaded).
"""

from __future__ import annotations

import functools
import hashlib
import json
import logging
import os
import time
from dataclasses import asdict

import numpy as np
import pandas as pd

from ..atomic import TEMP_PREFIX, atomic_path
from ..materials import LegDesign
from ..sim import SimSettings

DEFAULT_CACHE_DIR = os.path.join("results", "cache")
CACHE_ENV = "MAT_HOPPER_CACHE"
_META_KEY = b"mat_hopper"
_CHECKSUM_KEY = b"mat_hopper_sha256"
_STALE_TEMP_S = 3600.0
_log = logging.getLogger("mat_hopper.cache")


def _json_default(o):
    if isinstance(o, (np.integer,)):
        return int(o)
    if isinstance(o, (np.floating,)):
        return float(o)
    if isinstance(o, (np.bool_,)):
        return bool(o)
    if isinstance(o, (tuple, np.ndarray)):
        return list(o)
    raise TypeError(f"not JSON serialisable: {o!r}")


# ---------------------------------------------------------------------------
# keys


# Modules whose code makes or summarises a result: their source is part of every key.
# Paths relative to the package folder, "/"-separated.
RESULT_MODULES = (
    "reference",
    "materials",
    "model",
    "control",
    "behaviours",
    "_loop",
    "sim",
    "perturbations",
    "metrics",
    "energetics",
    "controls",
    "jerk",
    "modes",
    "stability",
    "experiments/_cache",
    "experiments/runner",
)


@functools.lru_cache(maxsize=1)
def source_digest() -> str:
    """SHA-256 (short) of the source of :data:`RESULT_MODULES`: any edit to
    the physics, controller, metrics, these keys or the runner invalidates
    the cache."""
    package = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    h = hashlib.sha256()
    for name in RESULT_MODULES:
        with open(os.path.join(package, *f"{name}.py".split("/")), "rb") as f:
            h.update(name.encode() + b"\0" + f.read())
    return h.hexdigest()[:16]


def versions() -> dict:
    """What besides the settings changes results: mat-hopper's version and
    source, and MuJoCo's version."""
    import mujoco

    from .. import __version__

    return {"mat_hopper": __version__, "source": source_digest(), "mujoco": mujoco.__version__}


def design_key(design: LegDesign) -> dict:
    """A design as the physics sees it: per-segment density (g/cm^3) and
    modulus (GPa, None = rigid). The name is a label, not physics."""
    return {
        "n_segments": design.n_segments,
        "densities_g_cm3": list(design.densities_g_cm3),
        "moduli_gpa": list(design.moduli_gpa),
    }


def settings_key(settings: SimSettings) -> dict:
    """Every field of SimSettings (controller gains and perturbation included)."""
    p = settings.perturbation
    return {
        "duration_s": settings.duration_s,
        "timestep_s": settings.timestep_s,
        "transient_s": settings.transient_s,
        "convention": settings.convention,
        "sensor_timing": settings.sensor_timing,
        "segment_mass": settings.segment_mass,
        "substeps": settings.substeps,
        "record_rate_hz": settings.record_rate_hz,
        "controller": asdict(settings.controller),
        "perturbation": None if p is None else asdict(p),
    }


def hash_key(key: dict) -> str:
    """Stable short hash (hex) of a key dict."""
    text = json.dumps(key, sort_keys=True, default=_json_default, allow_nan=True)
    return hashlib.sha256(text.encode()).hexdigest()[:24]


class Cache:
    """Results on disk: one parquet file per key, written atomically."""

    def __init__(self, root: str | os.PathLike | None = None):
        root = root or os.environ.get(CACHE_ENV) or DEFAULT_CACHE_DIR
        self.root = os.path.abspath(os.fspath(root))
        os.makedirs(self.root, exist_ok=True)

    def path(self, key: str) -> str:
        return os.path.join(self.root, f"{key}.parquet")

    def __contains__(self, key: str) -> bool:
        return os.path.isfile(self.path(key))

    def keys(self) -> set[str]:
        """Keys of the complete results on disk (temp files excluded)."""
        return {f[:-8] for f in os.listdir(self.root) if f.endswith(".parquet") and not f.startswith(TEMP_PREFIX)}

    def load(self, key: str) -> tuple[pd.DataFrame, dict] | None:
        """(table, summary) or None when absent, unreadable or damaged: a
        file whose content checksum does not match (a flipped bit on disk)
        is logged and recomputed, never loaded."""
        import pyarrow.parquet as pq

        path = self.path(key)
        if not os.path.isfile(path):
            return None
        try:
            table = pq.read_table(path)
            payload = table.schema.metadata[_META_KEY]
            stored = table.schema.metadata[_CHECKSUM_KEY].decode("ascii")
            ok = stored == content_checksum(table, payload)
            meta = json.loads(payload) if ok else None
            frame = table.to_pandas() if ok else None
        except Exception:  # unreadable (not ours, damaged, no checksum): recompute, never trust
            ok = False
        if not ok:
            _log.warning("cache file %s is damaged (content checksum mismatch or unreadable): recomputing", path)
            return None
        return frame, meta["summary"]

    def store(self, key: str, table: pd.DataFrame, summary: dict, key_dict: dict) -> None:
        """Write atomically: temp file in the cache folder, then os.replace.
        The file's metadata holds the summary, the key and a SHA-256 content
        checksum of both and of every column (:func:`content_checksum`)."""
        import pyarrow as pa
        import pyarrow.parquet as pq

        t = pa.Table.from_pandas(table.reset_index(drop=True), preserve_index=False)
        payload = json.dumps({"summary": summary, "key": key_dict}, default=_json_default, allow_nan=True).encode()
        meta = dict(t.schema.metadata or {})
        meta[_META_KEY] = payload
        meta[_CHECKSUM_KEY] = content_checksum(t, payload).encode("ascii")
        t = t.replace_schema_metadata(meta)
        with atomic_path(self.path(key), prefix=TEMP_PREFIX, fsync=True) as tmp:
            pq.write_table(t, tmp)

    def clean_temp(self, older_than_s: float = _STALE_TEMP_S) -> int:
        """Remove temp files left by killed writers (older than the given
        age, so a concurrent writer's file is left alone). Returns count."""
        n, now = 0, time.time()
        for f in os.listdir(self.root):
            if f.startswith(TEMP_PREFIX):
                p = os.path.join(self.root, f)
                try:
                    if now - os.path.getmtime(p) > older_than_s:
                        os.unlink(p)
                        n += 1
                except OSError:
                    pass
        return n


def content_checksum(table, payload: bytes) -> str:
    """SHA-256 of a cached result's content: every column's name, null mask
    and values, the metadata payload (summary and key), the other schema
    metadata and the column types. Computed from
    the values, not from Arrow's memory layout, so the table written and
    the table read back from parquet give the same digest; any change to a
    stored number, string or the summary gives another. Ours because
    parquet's own page checksums are optional and not verified on read by
    default."""
    import pyarrow as pa

    h = hashlib.sha256()
    for name, col in zip(table.column_names, table.columns):
        arr = col.combine_chunks() if isinstance(col, pa.ChunkedArray) else col
        h.update(json.dumps(name).encode() + b"\0")
        h.update(np.asarray(arr.is_null().to_numpy(zero_copy_only=False), dtype=bool).tobytes())
        if pa.types.is_floating(arr.type) or pa.types.is_integer(arr.type) or pa.types.is_boolean(arr.type):
            vals = arr.fill_null(False if pa.types.is_boolean(arr.type) else 0).to_numpy(zero_copy_only=False)
            h.update(np.ascontiguousarray(vals).tobytes())
        else:
            h.update(json.dumps(arr.to_pylist(), default=str).encode())
        h.update(b"\1")
    h.update(payload)
    # the rest of the schema metadata (pandas' dtypes and column order) and the
    # column types steer how the values come back as a DataFrame
    meta = table.schema.metadata or {}
    for k in sorted(k for k in meta if k not in (_META_KEY, _CHECKSUM_KEY)):
        h.update(k + b"\0" + meta[k] + b"\1")
    h.update(json.dumps([str(t) for t in table.schema.types]).encode())
    return h.hexdigest()
