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
    move it into place, with the permissions a plain open() would give.

    Args:
        path: the target file (str or path-like); its folder is created
            (with parents) if missing.
        prefix: the temporary file's name prefix (``.tmp-`` by default).
        fsync: whether to fsync the temporary file before moving it into
            place (default False).

    Yields:
        The temporary file's path (str), in the target's folder, with the
        target's extension. When the ``with`` block exits normally it
        replaces `path` (``os.replace``); on an exception it is removed and
        `path` is left as it was.
    """
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
    """Write a text file (UTF-8) atomically.

    Args:
        text: the file's contents.
        path: the file (str or path-like); its folder is created if missing.

    Returns:
        `path`, as a str.
    """
    with atomic_path(path) as tmp:
        Path(tmp).write_text(text, encoding="utf-8")
    return str(path)


def write_csv(frame, path) -> str:
    """Write a pandas DataFrame as CSV (no index) atomically.

    Args:
        frame: the pandas DataFrame.
        path: the file (str or path-like); its folder is created if missing.

    Returns:
        `path`, as a str.
    """
    with atomic_path(path) as tmp:
        frame.to_csv(tmp, index=False)
    return str(path)


# --- what killed processes leave in the temp folder ---------------------------

MP_TEMP_PREFIX = "pymp-"  # multiprocessing's temp folders (forkserver sockets)
STALE_MP_AGE_S = 60.0


def _bound_unix_sockets() -> set[str] | None:
    """Paths of the Unix sockets some process has bound (Linux's
    /proc/net/unix), or None where that table cannot be read."""
    try:
        with open("/proc/net/unix") as f:
            next(f)
            return {parts[7] for parts in (line.split() for line in f) if len(parts) >= 8}
    except (OSError, StopIteration):
        return None


def remove_stale_mp_dirs(temp_dir: str | None = None, min_age_s: float = STALE_MP_AGE_S) -> list[str]:
    """Remove the ``pymp-*`` folders that killed processes left in the temp
    folder: multiprocessing makes one per process for its forkserver's
    socket and removes it at a normal exit, which a SIGKILL (or a signal
    without a handler) skips. A folder is removed only when it is ours,
    older than `min_age_s`, and holds nothing but sockets no process has
    bound (or nothing at all); a live process's folder is left alone.
    Returns the folders removed.

    Args:
        temp_dir: the folder to clean; None (the default) for
            ``tempfile.gettempdir()``.
        min_age_s: the least age (s, from the folder's modification time)
            of a folder removed; default ``STALE_MP_AGE_S`` (60 s).

    Returns:
        The paths (str) of the folders removed; empty when `temp_dir`
        cannot be listed. A folder holding anything where the socket table
        (Linux's /proc/net/unix) cannot be read is kept; errors on single
        folders are skipped.
    """
    import shutil
    import stat
    import time

    temp_dir = temp_dir or tempfile.gettempdir()
    bound = _bound_unix_sockets()
    removed = []
    try:
        names = [n for n in os.listdir(temp_dir) if n.startswith(MP_TEMP_PREFIX)]
    except OSError:
        return removed
    now = time.time()
    for name in names:
        d = os.path.join(temp_dir, name)
        try:
            st = os.lstat(d)
            if not stat.S_ISDIR(st.st_mode) or st.st_uid != os.getuid() or now - st.st_mtime < min_age_s:
                continue
            entries = [os.path.join(d, e) for e in os.listdir(d)]
            if entries and bound is None:
                continue
            if all(stat.S_ISSOCK(os.lstat(e).st_mode) and e not in bound for e in entries):
                shutil.rmtree(d)
                removed.append(d)
        except OSError:
            continue
    return removed
