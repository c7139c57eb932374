"""A throw-away PostgreSQL server for the optimizer's storage tests (fixtures:
import them into a test module, ``from pg_server import pg_server, pg_url``)."""

from __future__ import annotations

import glob
import itertools
import os
import pwd
import shutil
import socket
import subprocess
import tempfile

import pytest


def _pg_bin():
    dirs = glob.glob("/usr/lib/postgresql/*/bin")
    dirs = [d for d in dirs if os.path.exists(os.path.join(d, "pg_ctl"))]
    return sorted(dirs, key=lambda d: int(d.split("/")[-2]) if d.split("/")[-2].isdigit() else 0)[-1] if dirs else None


@pytest.fixture(scope="session")
def pg_server():
    """A PostgreSQL server on a free localhost port (as user postgres when we
    are root), trust authentication; yields its base URL
    ``postgresql://postgres@127.0.0.1:PORT`` in the form the docs show
    (SQLAlchemy's default driver, psycopg 3). Stopped after."""
    bindir = _pg_bin()
    if bindir is None:
        pytest.skip("PostgreSQL server binaries not found in /usr/lib/postgresql/*/bin")
    root = os.geteuid() == 0
    as_user = (lambda cmd: ["runuser", "-u", "postgres", "--", *cmd]) if root else (lambda cmd: cmd)
    tmp = tempfile.mkdtemp(prefix="mat-hopper-pg-")
    if root:
        pw = pwd.getpwnam("postgres")
        os.chown(tmp, pw.pw_uid, pw.pw_gid)
    data, log = os.path.join(tmp, "data"), os.path.join(tmp, "server.log")
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    run = lambda cmd: subprocess.run(as_user(cmd), check=True, capture_output=True, text=True)
    run([f"{bindir}/initdb", "-D", data, "-A", "trust", "-U", "postgres", "--no-sync", "-E", "UTF8"])
    run(
        [
            f"{bindir}/pg_ctl",
            "-D",
            data,
            "-l",
            log,
            "-w",
            "-t",
            "60",
            "-o",
            f"-p {port} -k {tmp} -c listen_addresses=127.0.0.1 -c fsync=off -c max_connections=80",
            "start",
        ]
    )
    try:
        yield f"postgresql://postgres@127.0.0.1:{port}"
    finally:
        subprocess.run(as_user([f"{bindir}/pg_ctl", "-D", data, "-m", "immediate", "-w", "stop"]), capture_output=True)
        shutil.rmtree(tmp, ignore_errors=True)


_DB_NUMBERS = itertools.count()


def new_database(server_url: str) -> str:
    """A new, empty database on the server; its URL (documented form)."""
    import psycopg

    name = f"db{os.getpid()}_{next(_DB_NUMBERS)}"
    with psycopg.connect(f"{server_url}/postgres", autocommit=True) as con:
        con.execute(f"CREATE DATABASE {name}")
    return f"{server_url}/{name}"


@pytest.fixture(scope="module")
def pg_url(pg_server):
    """An empty database for a test module: postgresql://postgres@127.0.0.1:PORT/DB."""
    return new_database(pg_server)


@pytest.fixture
def fresh_pg_url(pg_server):
    """An empty database of its own for one test."""
    return new_database(pg_server)
