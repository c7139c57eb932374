import os
import signal
import sys

import pytest

# A shell starts a background job (`make test &`, `nohup`) with SIGINT
# ignored, and Python then leaves it ignored: the tests of Ctrl-C handling
# (a KeyboardInterrupt expected) failed in such a run. Each test process
# takes Python's own handler back, as in a foreground run.
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)

# the throw-away PostgreSQL server's fixtures (pg_server, pg_url, fresh_pg_url)
pytest_plugins = ["pg_server"]

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


# The quick book's build is the longest test by far (about 40 min on 2 cores
# from an empty cache). xdist's loadfile scheduler queues files by their
# number of tests unless told not to (the Makefile's --no-loadscope-reorder),
# which started the book's few tests about 20 min into the run: CI stop 25
# took 2857 s. The book goes first and the files with slow tests next
# (longest first, roughly), so that everything else runs beside the book.
FIRST_FILES = ("tests/test_book.py",)


def pytest_collection_modifyitems(config, items):
    def file_of(item):
        return item.nodeid.split("::", 1)[0]

    slow_files = {file_of(i) for i in items if i.get_closest_marker("slow")}
    rank = {f: (0 if f in FIRST_FILES else 1 if f in slow_files else 2) for f in map(file_of, items)}
    items[:] = sorted(items, key=lambda i: rank[file_of(i)])  # stable: each file keeps its own order


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
