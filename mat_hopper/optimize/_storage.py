"""Where studies live: storage URLs and connection checks; the dead runs'
trials are recovered by :mod:`mat_hopper.optimize._recovery`.

Storage choices (``--storage``):

- default: one SQLite file per study, ``studies/<name>.db`` under the
  current folder (``--studies-dir`` moves it). SQLite allows one writer at
  a time; the file is switched to WAL mode (readers never block the
  writer; commits are not fsynced one by one, ``synchronous=NORMAL``: a
  power cut may lose the last trials, never corrupt the file) and every
  connection waits up to 60 s for the lock, which is
  ample for a few commands whose trials last seconds and write a few
  rows each. Every transaction begins with BEGIN IMMEDIATE: SQLite has no
  row locks, and without it two commands could both take the same enqueued
  (WAITING) trial. It keeps Optuna's heartbeat (below), which the journal
  file backend lacks; that is why it is the default on one machine. Reports open the file read-only (``mode=ro``): no lock, so
  they never wait for a writer, and they never checkpoint nor remove the
  ``-wal``/``-shm`` files a writer holds.
- any SQLAlchemy/Optuna RDB URL, e.g.
  ``postgresql://USER:PASSWORD@HOST:5432/DB``: the way to run a study
  on many machines (every machine runs the same ``mat-hopper optimize``
  command against the same URL). ``postgresql://`` uses SQLAlchemy 2's
  default driver, psycopg 3 (pinned in environment.txt, and the
  ``cluster`` extra); ``postgresql+psycopg2://`` picks psycopg2, which
  is not installed.
- ``journal:///PATH/study.log``: Optuna's journal file backend, for a
  shared file system without a database server (NFS v3+; symlink lock).
  No heartbeat: a machine that dies mid-trial leaves that trial RUNNING
  until a run on the same machine starts (see :func:`recover_dead`).

First starts. Several processes may open one fresh storage at once: the
tables are created under a PostgreSQL advisory lock, and a process that
loses a creation race elsewhere (SQLite: "table studies already exists")
retries; the study itself is created once (see
:func:`mat_hopper.optimize._study.create_or_load`).

Errors are one line naming the cause (:func:`storage_error`): "cannot
reach" only when the server was not reached.

Dead runs. On RDB storages Optuna's heartbeat is on: the optimizer's loop
(:mod:`mat_hopper.optimize._driver`) records a heartbeat of each of its
running trials every ``heartbeat_s``; a trial silent for ``grace_s`` is
marked FAIL by the next run that starts anywhere
(``optuna.storages.fail_stale_trials``), and its parameters are enqueued
again (at most ``max_retry`` times; :func:`retry_trial` does what
:class:`optuna.storages.RetryHeartbeatStaleTrialCallback` does, with the
same ``failed_trial`` and ``retry_history`` system attrs, but carries over
only the paper-design label, not the dead run's attributes). On every
storage, each trial records the process that asked it (host, boot id,
pid), and every new run on the same machine fails and re-enqueues the
trials of a process that is gone at once (:func:`recover_dead`).
"""

from __future__ import annotations

import os
import random
import re
import sqlite3
import time
import warnings
from contextlib import contextmanager
from urllib.parse import quote

import optuna
from optuna.trial import TrialState

from ..util.parsing import normalize_url

STUDY_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,99}$")
SQLITE_LOCK_TIMEOUT_S = 60
CONNECT_TIMEOUT_S = 10
# Connection errors that mean the server was not reached (anything else: it answered).
UNREACHABLE = re.compile(
    r"refused|timed? ?out|could not translate host|name or service not known|no route to host|"
    r"network is unreachable|could not connect|no such host|unable to open database file",
    re.IGNORECASE,
)
SCHEMA_ATTEMPTS = 10  # tries to create the tables when first starts race
SCHEMA_LOCK_KEY = 0x6D61_7468  # PostgreSQL advisory lock held while the tables are made
WORKER_ATTR = "worker"  # trial user attr: {"host", "boot", "pid"}
FAIL_REASON_ATTR = "fail_reason"  # trial user attr: why a running trial was failed and re-queued
ERROR_ATTR = "error"  # trial user attr set when the evaluation raised
PAPER_ATTR = "paper_design"  # trial user attr of the enqueued paper designs
KEEP_ON_RETRY = (PAPER_ATTR,)


def check_study_name(name) -> str:
    """A study name, checked.

    Args:
        name: 1-100 letters, digits, ``_``, ``.``, ``-``, starting with a letter or digit.

    Returns:
        The name.

    Raises:
        ValueError: any other name.
    """
    if not isinstance(name, str) or not STUDY_NAME.match(name):
        raise ValueError(
            f"study name must be 1-100 characters of letters, digits, '_', '.', '-' "
            f"(starting with a letter or digit), got {name!r}"
        )
    return name


def default_url(study_name: str, studies_dir: str = "studies") -> str:
    """The sqlite URL of a study's own file.

    Args:
        study_name: the study's name (:func:`check_study_name`).
        studies_dir: the folder.

    Returns:
        ``sqlite:///<absolute studies_dir>/<name>.db``.

    Raises:
        ValueError: a bad study name.
    """
    path = os.path.abspath(os.path.join(studies_dir, f"{check_study_name(study_name)}.db"))
    return f"sqlite:///{path}"


def redact(url: str) -> str:
    """A storage URL for messages.

    Args:
        url: a storage URL.

    Returns:
        The URL with any password hidden.
    """
    try:
        from sqlalchemy.engine import make_url

        return make_url(url).render_as_string(hide_password=True)
    except Exception:
        return re.sub(r"://([^:/@]+):[^@]*@", r"://\1:***@", str(url))


def _journal_path(url: str) -> str:
    rest = url[len("journal:") :]
    if rest.startswith("//"):
        rest = rest[2:]
    if not rest:
        raise ValueError("journal storage needs a file: journal:///PATH/study.log")
    return rest


def storage_file(url: str) -> str | None:
    """The local file of a storage.

    Args:
        url: a storage URL (its scheme in any case, RFC 3986).

    Returns:
        The absolute path of a sqlite or journal URL's file, else None.
    """
    url = normalize_url(url)  # schemes are case-insensitive (RFC 3986)
    if url.startswith("journal:"):
        return os.path.abspath(_journal_path(url))
    try:
        from sqlalchemy.engine import make_url

        u = make_url(url)
    except Exception:
        return None
    if u.get_backend_name() == "sqlite" and u.database and u.database != ":memory:":
        return os.path.abspath(u.database)
    return None


def _sqlite_path_check(db: str) -> None:
    if not db or db == ":memory:" or db.startswith("file::memory:"):
        raise ValueError(
            "an in-memory SQLite database cannot be shared by processes; give a file: sqlite:///studies/NAME.db"
        )
    path = os.path.abspath(db)
    folder = os.path.dirname(path)
    if os.path.isdir(path):
        raise ValueError(f"sqlite storage {path}: is a folder, not a database file")
    if os.path.exists(folder) and not os.path.isdir(folder):
        raise ValueError(f"sqlite storage {path}: {folder} is a file, not a folder")
    if not os.path.isdir(folder):
        raise ValueError(f"sqlite storage: folder {folder} does not exist")


def _cause(e: BaseException) -> str:
    """The deepest message of an error chain (the driver's own words, e.g.
    "database is locked"), one line."""
    seen, cur = set(), e
    while id(cur) not in seen:
        seen.add(id(cur))
        nxt = getattr(cur, "orig", None) or cur.__cause__ or cur.__context__
        if nxt is None:
            break
        cur = nxt
    lines = str(cur).strip().splitlines()
    return lines[0].strip() if lines else type(cur).__name__


def storage_error(url: str, e: BaseException) -> ValueError:
    """One line naming the storage and the cause of a database error; a
    locked SQLite file says how long it waited."""
    cause = _cause(e)
    if "database is locked" in cause or "database table is locked" in cause:
        cause += f" (another process held the write lock for more than {SQLITE_LOCK_TIMEOUT_S} s)"
    return ValueError(f"storage {redact(url)}: {cause}")


def db_errors() -> tuple:
    """The database errors :func:`storage_errors` turns into one line."""
    import sqlalchemy

    return (sqlalchemy.exc.SQLAlchemyError, optuna.exceptions.StorageInternalError, sqlite3.Error)


@contextmanager
def storage_errors(url: str):
    """A context in which database errors become one line.

    Args:
        url: the storage's URL (named in the message, password hidden).

    Yields:
        None; other exceptions raised in the block pass unchanged.

    Raises:
        ValueError: for SQLAlchemy's errors, Optuna's StorageInternalError and
            sqlite3's raised inside (:func:`storage_error`'s one line).
    """
    try:
        yield
    except db_errors() as e:
        raise storage_error(url, e) from None


def _retry_schema_race(make, url: str, attempts: int = SCHEMA_ATTEMPTS):
    """make(), again when it lost a race with another process creating the
    same tables (two first starts at once: "table studies already exists"
    on SQLite, "duplicate key value violates unique constraint" on
    PostgreSQL). The winner's tables are complete when the loser retries."""
    import sqlalchemy

    rng = random.Random(os.getpid())
    for i in range(attempts):
        try:
            return make()
        except (sqlalchemy.exc.SQLAlchemyError, optuna.exceptions.StorageInternalError) as e:
            cause = _cause(e).lower()
            race = any(w in cause for w in ("already exists", "duplicate", "unique constraint"))
            if not race or i == attempts - 1:
                raise
            time.sleep(0.05 + rng.random() * 0.2 * (i + 1))


@contextmanager
def _schema_lock(engine, backend: str):
    """PostgreSQL: hold a session advisory lock while the schema is made,
    so that concurrent first starts create it one at a time (the retry of
    :func:`_retry_schema_race` covers every other backend)."""
    if backend != "postgresql":
        yield
        return
    import sqlalchemy

    with engine.connect() as con:
        con.execute(sqlalchemy.text("SELECT pg_advisory_lock(:k)"), {"k": SCHEMA_LOCK_KEY})
        con.commit()
        try:
            yield
        finally:
            con.execute(sqlalchemy.text("SELECT pg_advisory_unlock(:k)"), {"k": SCHEMA_LOCK_KEY})
            con.commit()


def _journal_storage(url: str):
    """A journal-file storage (``journal:///PATH``), its folder checked."""
    from optuna.storages.journal import JournalFileBackend, JournalStorage

    path = os.path.abspath(_journal_path(url))
    if os.path.isdir(path):
        raise ValueError(f"journal storage {path}: is a folder, not a file")
    if not os.path.isdir(os.path.dirname(path)):
        raise ValueError(f"journal storage: folder {os.path.dirname(path)} does not exist")
    try:
        return JournalStorage(JournalFileBackend(path))
    except OSError as e:
        raise ValueError(f"cannot open journal storage {path}: {e.strerror or e}") from None


def _parsed_url(url: str):
    """The SQLAlchemy URL of a database storage; ValueError for an unknown scheme or a missing driver."""
    from sqlalchemy.engine import make_url

    try:
        parsed = make_url(url)
        parsed.get_dialect()
    except ImportError as e:
        raise ValueError(f"storage {redact(url)}: the database driver is not installed ({e})") from None
    except Exception:
        scheme = url.split(":", 1)[0] if ":" in url else url
        raise ValueError(
            f"unknown storage scheme {scheme!r} in {redact(url)!r}; accepted: sqlite:///PATH, "
            "postgresql://USER@HOST:PORT/DB (or another SQLAlchemy database URL), "
            "journal:///PATH"
        ) from None
    return parsed


def _engine_options(url: str, parsed, backend: str, read_only: bool) -> tuple[str, dict]:
    """(the URL to open, SQLAlchemy engine options) for the backend: SQLite's
    lock timeout, read-only URI or write-ahead log; PostgreSQL's pre-ping and
    connect timeout."""
    engine_kwargs: dict = {}
    open_url = url
    if backend == "sqlite":
        db = parsed.database
        _sqlite_path_check(db)
        engine_kwargs["connect_args"] = {"timeout": SQLITE_LOCK_TIMEOUT_S}
        if read_only:
            if not os.path.isfile(db):
                raise ValueError(f"sqlite storage {os.path.abspath(db)} does not exist")
            open_url = f"sqlite:///file:{quote(os.path.abspath(db))}?mode=ro&uri=true"
        else:
            _sqlite_wal(db)
    elif backend == "postgresql":
        engine_kwargs["pool_pre_ping"] = True
        if parsed.get_driver_name() in ("psycopg2", "psycopg"):
            engine_kwargs["connect_args"] = {"connect_timeout": CONNECT_TIMEOUT_S}
    return open_url, engine_kwargs


def _probe(url: str, open_url: str, engine_kwargs: dict):
    """An engine that has connected once (the only failure called "cannot reach")."""
    import sqlalchemy

    try:
        probe = sqlalchemy.create_engine(open_url, **engine_kwargs)
        with probe.connect():
            pass
    except ImportError as e:
        raise ValueError(f"storage {redact(url)}: the database driver is not installed ({e})") from None
    except (sqlalchemy.exc.SQLAlchemyError, OSError) as e:
        cause = _cause(e)
        if UNREACHABLE.search(cause):
            raise ValueError(f"cannot reach storage {redact(url)}: {cause}") from None
        raise ValueError(f"cannot open storage {redact(url)}: {cause}") from None  # reached, but refused
    return probe


def open_storage(url: str, *, heartbeat_s: int = 10, grace_s: int = 60, max_retry: int = 3, read_only: bool = False):
    """An Optuna storage for `url`, checked to be reachable. See the module doc
    for the accepted URLs.

    ``postgresql://`` URLs use SQLAlchemy's default driver, psycopg 3
    (pinned in environment.txt, and the ``cluster`` extra);
    ``postgresql+psycopg2://`` picks psycopg2, which is not installed.

    Args:
        url: ``sqlite:///PATH``, ``postgresql://USER@HOST:PORT/DB`` (or another
            SQLAlchemy URL) or ``journal:///PATH``.
        heartbeat_s, grace_s: heartbeat interval and grace period of RDB storages, s.
        max_retry: retries of a trial whose worker's heartbeat stopped.
        read_only: for reports: a SQLite file is opened read-only (``mode=ro``):
            no write lock is taken, so a report never waits for a writer, and a
            read-only connection never checkpoints nor removes the
            ``-wal``/``-shm`` files a writer holds; those it made itself
            (no writer had the file open) go at :func:`dispose`.

    Returns:
        An ``optuna.storages.RDBStorage`` or ``JournalStorage``.

    Raises:
        ValueError: one line, for a bad URL, a missing driver, an unreachable or
            refusing database, or bad heartbeat settings.
    """
    if not isinstance(url, str) or not url.strip():
        raise ValueError(
            "--storage must be a URL such as sqlite:///studies/x.db, "
            "postgresql://user@host:5432/db or journal:///path/x.log"
        )
    url = normalize_url(url)  # schemes are case-insensitive (RFC 3986): SQLite:/// is sqlite:///
    if url.startswith("journal:"):
        return _journal_storage(url)

    import sqlalchemy

    parsed = _parsed_url(url)
    for name, v in (("heartbeat_s", heartbeat_s), ("grace_s", grace_s)):
        if isinstance(v, bool) or not isinstance(v, int) or v < 1:
            raise ValueError(f"{name} must be an integer >= 1 s, got {v!r}")
    if grace_s <= heartbeat_s:
        raise ValueError(f"grace_s must exceed heartbeat_s ({heartbeat_s} s), got {grace_s!r}")
    backend = parsed.get_backend_name()
    open_url, engine_kwargs = _engine_options(url, parsed, backend, read_only)
    had_wal = backend == "sqlite" and any(os.path.exists(f"{parsed.database}{x}") for x in ("-wal", "-shm"))
    probe = _probe(url, open_url, engine_kwargs)

    def make():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
            return optuna.storages.RDBStorage(
                open_url,
                engine_kwargs=engine_kwargs,
                heartbeat_interval=heartbeat_s,
                grace_period=grace_s,
                heartbeat_stale_trial_callback=RetryStaleTrial(max_retry),
                skip_table_creation=read_only,
            )

    try:
        with _schema_lock(probe, backend):
            storage = _retry_schema_race(make, url)
        if backend == "sqlite" and not read_only:
            _sqlite_immediate(storage.engine)
        if backend == "sqlite" and read_only and not had_wal:
            storage._mat_hopper_tidy = parsed.database  # dispose() removes the -wal/-shm this reader made
        return storage
    except (sqlalchemy.exc.SQLAlchemyError, optuna.exceptions.StorageInternalError, OSError, RuntimeError) as e:
        raise storage_error(url, e) from None
    finally:
        probe.dispose()


def _sqlite_immediate(engine) -> None:
    """Begin every SQLite transaction with BEGIN IMMEDIATE (take the write
    lock first). SQLite has no SELECT ... FOR UPDATE, so without this two
    workers can both read a WAITING trial and both set it RUNNING: both
    would run the same enqueued trial. PostgreSQL and MySQL lock the row.
    Reports open the file read-only instead (no lock, never waiting)."""
    from sqlalchemy import event

    def on_connect(dbapi_connection, record):
        dbapi_connection.isolation_level = None  # the driver leaves BEGIN to us
        dbapi_connection.execute("PRAGMA synchronous=NORMAL")  # WAL: no fsync per commit

    def on_begin(connection):
        connection.exec_driver_sql("BEGIN IMMEDIATE")

    event.listen(engine, "connect", on_connect)
    event.listen(engine, "begin", on_begin)
    engine.dispose()  # pooled connections predate the hooks


def _sqlite_wal(path: str) -> None:
    """Switch the SQLite file to WAL journaling (a persistent setting)."""
    try:
        con = sqlite3.connect(path, timeout=SQLITE_LOCK_TIMEOUT_S)
    except sqlite3.Error as e:
        raise ValueError(f"cannot open sqlite storage {path}: {e}") from None
    try:
        con.execute("PRAGMA journal_mode=WAL")
    except sqlite3.Error as e:
        raise storage_error(f"sqlite:///{os.path.abspath(path)}", e) from None
    finally:
        con.close()


def dispose(storage) -> None:
    """Close a storage's pooled database connections (before a fork: no connection
    may cross into a child process, where SQLite's POSIX locks would be released
    by the child closing its copy).

    Args:
        storage: an Optuna storage (others than RDB storages: nothing to close).
    """
    engine = getattr(storage, "engine", None)
    if engine is not None:
        engine.dispose()
    db = getattr(storage, "_mat_hopper_tidy", None)
    if db is not None:
        _tidy_read_only(db)


def _tidy_read_only(db: str) -> None:
    """Remove the ``-wal``/``-shm`` files a read-only use of SQLite file `db`
    made. A reader of a WAL-mode file creates them when no writer holds
    them, and, read-only, can never remove them: a report or an export
    would leave them beside a finished study. A plain connection that reads
    and closes removes them when it is the file's last connection (SQLite's
    own rule, under its locks): a writer that opened the file meanwhile
    keeps them. Nothing is written (the log is empty); on any error (a
    read-only folder, a lock) they stay, harmlessly."""
    if not any(os.path.exists(f"{db}{x}") for x in ("-wal", "-shm")):
        return
    try:
        con = sqlite3.connect(db, timeout=0.1)
        try:
            con.execute("SELECT count(*) FROM sqlite_master").fetchone()
        finally:
            con.close()
    except sqlite3.Error:
        pass


# --- a failed trial's retry (also Optuna's heartbeat callback) ---------------


def retry_trial(study, trial, max_retry: int = 3) -> bool:
    """Enqueue a failed trial's parameters again, as Optuna's
    RetryHeartbeatStaleTrialCallback does (same ``failed_trial`` and
    ``retry_history`` system attrs), keeping only the user attrs in
    KEEP_ON_RETRY. An enqueued trial's ``fixed_params`` go along, so a
    seed whose worker died before it was suggested is retried as that seed.
    False when the trial was retried max_retry times."""
    history = list(trial.system_attrs.get("retry_history", [])) + [trial.number]
    if len(history) > max_retry:
        return False
    study.add_trial(
        optuna.trial.create_trial(
            state=TrialState.WAITING,
            params=trial.params,
            distributions=trial.distributions,
            user_attrs={k: v for k, v in trial.user_attrs.items() if k in KEEP_ON_RETRY},
            system_attrs={
                "failed_trial": trial.system_attrs.get("failed_trial", trial.number),
                "retry_history": history,
                # an enqueued design (a seed) whose worker died before it was
                # suggested has no params yet: keep it enqueued
                **(
                    {"fixed_params": trial.system_attrs["fixed_params"]} if "fixed_params" in trial.system_attrs else {}
                ),
            },
        )
    )
    return True


class RetryStaleTrial:
    """Optuna's heartbeat-stale callback: :func:`retry_trial`."""

    def __init__(self, max_retry: int = 3):
        self.max_retry = int(max_retry)

    def __call__(self, study, trial) -> None:
        retry_trial(study, trial, self.max_retry)
