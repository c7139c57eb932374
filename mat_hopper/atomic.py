"""Atomic file writes: readers see the old file or the whole new one.

Everything the package writes (tables, caches, figures, videos) goes
through :func:`atomic_path`: a temporary file in the target's folder, then
``os.replace``. A crash or a kill leaves at most a ``.tmp-*`` file behind,
never a half-written result.
"""

from __future__ import annotations

import os
import tempfile
from contextlib import contextmanager
from pathlib import Path

TEMP_PREFIX = ".tmp-"


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextmanager
def atomic_path(path, *, prefix: str = TEMP_PREFIX, fsync: bool = False):
    """Yield a temporary path next to `path` (same extension); on success
    move it into place, with the permissions a plain open() would give."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=prefix, suffix=path.suffix)
    os.close(fd)
    try:
        yield tmp
        if fsync:
            with open(tmp, "rb+") as f:
                os.fsync(f.fileno())
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def write_text(text: str, path) -> str:
    """Write a text file (UTF-8) atomically."""
    with atomic_path(path) as tmp:
        Path(tmp).write_text(text, encoding="utf-8")
    return str(path)


def write_csv(frame, path) -> str:
    """Write a pandas DataFrame as CSV (no index) atomically."""
    with atomic_path(path) as tmp:
        frame.to_csv(tmp, index=False)
    return str(path)
