"""Where studies live: storage URLs, connection checks, and dead workers.

Storage choices (``--storage``):

- default: one SQLite file per study, ``studies/<name>.db`` under the
  current folder (``--studies-dir`` moves it). SQLite allows one writer at
  a time; the file is switched to WAL mode (readers never block the
  writer; commits are not fsynced one by one, ``synchronous=NORMAL``: a
  power cut may lose the last trials, never corrupt the file) and every
  connection waits up to 60 s for the lock, which is
  ample for a few local workers whose trials last seconds and write a few
  rows each. Every transaction begins with BEGIN IMMEDIATE: SQLite has no
  row locks, and without it two workers could both take the same enqueued
  (WAITING) trial. It keeps Optuna's heartbeat (below), which the journal
  file backend lacks; that is why it is the default for ``--workers N`` on
  one machine.
- any SQLAlchemy/Optuna RDB URL, e.g.
  ``postgresql://USER:PASSWORD@HOST:5432/DB``: the way to run many workers
  on many machines (every machine runs the same ``mat-hopper optimize``
  command against the same URL).
- ``journal:///PATH/study.log``: Optuna's journal file backend, for a
  shared file system without a database server (NFS v3+; symlink lock).
  No heartbeat: a machine that dies mid-trial leaves that trial RUNNING
  until a worker on the same machine restarts (see :func:`recover_dead`).

Dead workers. On RDB storages Optuna's heartbeat is on: a running trial
records a heartbeat every ``heartbeat_s``; one silent for ``grace_s`` is
marked FAIL by the next worker that starts a trial, and its parameters
are enqueued again (at most ``max_retry`` times; :func:`retry_trial` does
what :class:`optuna.storages.RetryHeartbeatStaleTrialCallback` does, with
the same ``failed_trial`` and ``retry_history`` system attrs, but carries
over only the paper-design label, not the dead run's attributes). On every storage, each
trial records its worker (host, boot id, pid); the local coordinator fails
and re-enqueues a dead local worker's trial at once (:func:`recover_dead`),
and so does every new run on the same machine for workers of an earlier
run that died.
"""

from __future__ import annotations

import os
import re
import socket
import sqlite3
import warnings

import optuna
from optuna.trial import TrialState

STUDY_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,99}$")
SQLITE_LOCK_TIMEOUT_S = 60
CONNECT_TIMEOUT_S = 10
WORKER_ATTR = "worker"  # trial user attr: {"host", "boot", "pid"}
FAIL_REASON_ATTR = "fail_reason"  # trial user attr set on trials of dead workers
ERROR_ATTR = "error"  # trial user attr set when the evaluation raised
PAPER_ATTR = "paper_design"  # trial user attr of the enqueued paper designs
KEEP_ON_RETRY = (PAPER_ATTR,)


def check_study_name(name) -> str:
    if not isinstance(name, str) or not STUDY_NAME.match(name):
        raise ValueError(
            f"study name must be 1-100 characters of letters, digits, '_', '.', '-' "
            f"(starting with a letter or digit), got {name!r}"
        )
    return name


def default_url(study_name: str, studies_dir: str = "studies") -> str:
    """sqlite URL of the study's own file, studies_dir/<name>.db (absolute)."""
    path = os.path.abspath(os.path.join(studies_dir, f"{check_study_name(study_name)}.db"))
    return f"sqlite:///{path}"


def redact(url: str) -> str:
    """The URL with any password hidden (for messages)."""
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
    """The local file of a sqlite or journal URL (absolute), else None."""
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


def open_storage(url: str, *, heartbeat_s: int = 10, grace_s: int = 60, max_retry: int = 3):
    """An Optuna storage for `url`, checked to be reachable (ValueError, one
    line, if not). See the module doc for the accepted URLs."""
    if not isinstance(url, str) or not url.strip():
        raise ValueError(
            "--storage must be a URL such as sqlite:///studies/x.db, "
            "postgresql://user@host:5432/db or journal:///path/x.log"
        )
    url = url.strip()
    if url.startswith("journal:"):
        from optuna.storages.journal import JournalFileBackend, JournalStorage

        path = os.path.abspath(_journal_path(url))
        if not os.path.isdir(os.path.dirname(path)):
            raise ValueError(f"journal storage: folder {os.path.dirname(path)} does not exist")
        try:
            return JournalStorage(JournalFileBackend(path))
        except OSError as e:
            raise ValueError(f"cannot open journal storage {path}: {e}") from None

    import sqlalchemy
    from sqlalchemy.engine import make_url

    try:
        parsed = make_url(url)
        parsed.get_dialect()
    except Exception:
        scheme = url.split(":", 1)[0] if ":" in url else url
        raise ValueError(
            f"unknown storage scheme {scheme!r} in {redact(url)!r}; accepted: sqlite:///PATH, "
            "postgresql://USER@HOST:PORT/DB (or another SQLAlchemy database URL), "
            "journal:///PATH"
        ) from None
    engine_kwargs: dict = {}
    if parsed.get_backend_name() == "sqlite":
        db = parsed.database
        if not db or db == ":memory:" or db.startswith("file::memory:"):
            raise ValueError(
                "an in-memory SQLite database cannot be shared by worker processes; "
                "give a file: sqlite:///studies/NAME.db"
            )
        folder = os.path.dirname(os.path.abspath(db))
        if not os.path.isdir(folder):
            raise ValueError(f"sqlite storage: folder {folder} does not exist")
        _sqlite_wal(db)
        engine_kwargs["connect_args"] = {"timeout": SQLITE_LOCK_TIMEOUT_S}
    elif parsed.get_backend_name() == "postgresql":
        engine_kwargs["pool_pre_ping"] = True
        if parsed.get_driver_name() in ("psycopg2", "psycopg"):
            engine_kwargs["connect_args"] = {"connect_timeout": CONNECT_TIMEOUT_S}
    for name, v in (("heartbeat_s", heartbeat_s), ("grace_s", grace_s)):
        if isinstance(v, bool) or not isinstance(v, int) or v < 1:
            raise ValueError(f"{name} must be an integer >= 1 s, got {v!r}")
    if grace_s <= heartbeat_s:
        raise ValueError(f"grace_s must exceed heartbeat_s ({heartbeat_s} s), got {grace_s!r}")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
            storage = optuna.storages.RDBStorage(
                url,
                engine_kwargs=engine_kwargs,
                heartbeat_interval=heartbeat_s,
                grace_period=grace_s,
                heartbeat_stale_trial_callback=RetryStaleTrial(max_retry),
            )
        if parsed.get_backend_name() == "sqlite":
            _sqlite_immediate(storage.engine)
        return storage
    except (sqlalchemy.exc.SQLAlchemyError, ImportError, OSError) as e:
        msg = str(getattr(e, "orig", None) or e).strip().splitlines()
        raise ValueError(f"cannot reach storage {redact(url)}: {msg[0] if msg else type(e).__name__}") from None


def _sqlite_immediate(engine) -> None:
    """Begin every SQLite transaction with BEGIN IMMEDIATE (take the write
    lock first). SQLite has no SELECT ... FOR UPDATE, so without this two
    workers can both read a WAITING trial and both set it RUNNING: both
    would run the same enqueued trial. PostgreSQL and MySQL lock the row."""
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
    con = sqlite3.connect(path, timeout=SQLITE_LOCK_TIMEOUT_S)
    try:
        con.execute("PRAGMA journal_mode=WAL")
    except sqlite3.DatabaseError as e:
        raise ValueError(f"cannot open sqlite storage {path}: {e}") from None
    finally:
        con.close()


# --- worker identity and dead workers ------------------------------------


def _boot_id() -> str:
    try:
        with open("/proc/sys/kernel/random/boot_id") as f:
            return f.read().strip()
    except OSError:
        return ""


def worker_identity(pid: int | None = None) -> dict:
    """Who runs a trial: host name, boot id (tells reboots and containers
    apart) and process id."""
    return {"host": socket.gethostname(), "boot": _boot_id(), "pid": int(pid or os.getpid())}


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    try:  # a zombie is dead too
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except (OSError, IndexError):
        return True


def retry_trial(study, trial, max_retry: int = 3) -> bool:
    """Enqueue a failed trial's parameters again, as Optuna's
    RetryHeartbeatStaleTrialCallback does (same ``failed_trial`` and
    ``retry_history`` system attrs), keeping only the user attrs in
    KEEP_ON_RETRY. False when the trial was retried max_retry times."""
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


def recover_dead(study, *, pids=None, max_retry: int = 3, reason: str = "worker died") -> list[int]:
    """Fail the RUNNING trials of dead workers on this machine and enqueue
    their parameters again (:func:`retry_trial`).

    pids: the dead workers' process ids, known dead; None: every RUNNING
    trial recorded by this machine (same host and boot) whose process is
    gone. Returns the numbers of the trials failed here (a trial another
    process failed first is left alone)."""
    me = worker_identity()
    storage = study._storage
    failed = []
    for t in study.get_trials(deepcopy=False, states=(TrialState.RUNNING,)):
        w = t.user_attrs.get(WORKER_ATTR)
        if not isinstance(w, dict) or w.get("host") != me["host"] or w.get("boot") != me["boot"]:
            continue
        pid = int(w.get("pid", -1))
        if pid == me["pid"] or (pids is not None and pid not in pids) or (pids is None and _alive(pid)):
            continue
        try:
            storage.set_trial_user_attr(t._trial_id, FAIL_REASON_ATTR, f"{reason} (pid {pid})")
            ok = storage.set_trial_state_values(t._trial_id, state=TrialState.FAIL)
        except (optuna.exceptions.UpdateFinishedTrialError, RuntimeError):
            continue
        if ok:
            failed.append(t.number)
            retry_trial(study, storage.get_trial(t._trial_id), max_retry)
    return failed
