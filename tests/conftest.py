import os
import sys

import pytest

# the throw-away PostgreSQL server's fixtures (pg_server, pg_url, fresh_pg_url)
pytest_plugins = ["pg_server"]

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


@pytest.fixture(scope="session")
def root():
    return ROOT


def run_python(code: str, env_extra: dict | None = None, timeout: float = 300):
    """Run code in a fresh interpreter (same venv), return CompletedProcess."""
    import subprocess

    env = dict(os.environ)
    env.update(env_extra or {})
    return subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=timeout, cwd=ROOT
    )


@pytest.fixture
def short_tmp():
    """A temporary folder with a short path, for a TMPDIR: multiprocessing's
    fork server binds a Unix socket in it, and a socket path may hold at most
    107 bytes. pytest's tmp_path under xdist (.../popen-gw1/test_<name>0/tmp)
    made "AF_UNIX path too long" (CI stop 24)."""
    import shutil
    import tempfile

    path = tempfile.mkdtemp(prefix="mh-", dir="/tmp")
    yield __import__("pathlib").Path(path)
    shutil.rmtree(path, ignore_errors=True)
