"""The result cache: one parquet file per key (:class:`Cache`), written
atomically, with a content checksum verified on every load (a mismatch is
recomputed, never loaded). The keys themselves are the core's
:mod:`mat_hopper.util.keys`.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import time

import numpy as np
import pandas as pd

from ..util.atomic import TEMP_PREFIX, atomic_path
from ..util.keys import hash_key, json_default
from ..util.parsing import env_value

DEFAULT_CACHE_DIR = os.path.join("results", "cache")
CACHE_ENV = "MAT_HOPPER_CACHE"
_META_KEY = b"mat_hopper"
_CHECKSUM_KEY = b"mat_hopper_sha256"
_STALE_TEMP_S = 3600.0
_log = logging.getLogger("mat_hopper.cache")


class Cache:
    """Results on disk: one parquet file per key, written atomically."""

    def __init__(self, root: str | os.PathLike | None = None):
        root = root or env_value(CACHE_ENV, "the result cache folder") or DEFAULT_CACHE_DIR
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
        file whose content checksum does not match (a flipped bit on disk),
        or whose stored key does not hash to its name (a file moved or
        copied under another key), is logged and recomputed, never loaded."""
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
            # a whole file moved or copied under another key is intact but not this key's result
            moved = ok and key.rsplit("-", 1)[-1] != hash_key(meta["key"])
            frame = table.to_pandas() if ok and not moved else None
        except Exception:  # unreadable (not ours, damaged, no checksum): recompute, never trust
            ok, moved = False, False
        if moved:
            _log.warning("cache file %s holds the result of another key (a file moved or copied): recomputing", path)
            return None
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
        payload = json.dumps({"summary": summary, "key": key_dict}, default=json_default, allow_nan=True).encode()
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
    default.

    Args:
        table: the ``pyarrow.Table`` written or read back (its columns, their
            types and its schema metadata are hashed; the entries under the
            cache's own metadata and checksum keys are left out).
        payload: the metadata payload, JSON bytes of ``{"summary": ..., "key": ...}``
            as :meth:`Cache.store` writes it.

    Returns:
        The SHA-256 digest as 64 lowercase hex characters.
    """
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
