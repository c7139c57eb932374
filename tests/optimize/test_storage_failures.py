"""The optimizer's failures: bad storage and paths in one line before any
work, one-line database errors naming the cause, concurrent first starts,
read-only reports that neither wait for nor disturb a writer, SIGTERM and
SIGHUP like Ctrl-C, no database connection across a fork, degenerate
studies refused. Runs use a 2 s profile (tiny) where the API allows it."""

from __future__ import annotations

import os
import signal
import sqlite3
import subprocess
import sys
import textwrap
import time

import optuna
import pytest
from optuna.trial import TrialState
from pg_server import new_database
from running_trials import (
    descendants,
    stop_a_running_trial,
    stop_an_evaluation_process,
    wait_for_evaluation_processes,
)

from mat_hopper.cli import main
from mat_hopper.experiments.profiles import Profile
from mat_hopper.optimize import (
    CONFIG_ATTR,
    Objective,
    RunOptions,
    SearchSpace,
    StudyConfig,
    _storage,
    create_or_load,
    open_storage,
    run_study,
)
from mat_hopper.optimize._processes import HeldSignals
from mat_hopper.optimize._storage import FAIL_REASON_ATTR, WORKER_ATTR

optuna.logging.set_verbosity(optuna.logging.WARNING)
TINY = Profile("tiny", duration_s=2.0, transient_s=0.5)
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ENV = {**os.environ, "PYTHONPATH": REPO + os.pathsep + os.environ.get("PYTHONPATH", "")}
ENV.pop("MAT_HOPPER_PROFILE", None)
ENV.pop("MAT_HOPPER_CACHE", None)  # each command below is given a cache of its own


def tiny(name, profile=TINY, behaviours="ramp"):
    return StudyConfig(name, SearchSpace(), Objective(replicates=0, behaviours=behaviours, profile=profile))


def _one_line_exit_2(argv, capsys, text):
    code = main(argv)
    err = capsys.readouterr().err.strip()
    assert code == 2, err
    assert len(err.splitlines()) == 1 and text in err, err
    return err


@pytest.fixture(scope="module")
def small_study(tmp_path_factory):
    """A finished 4-trial study in its default SQLite file: (studies dir, name)."""
    d = tmp_path_factory.mktemp("studies")
    run_study(
        tiny("small"), RunOptions(trials=4, workers=1, studies_dir=str(d), progress=False, cache_dir=str(d / "c"))
    )
    return d, "small"


# --- 1, 3, 7: bad input, one line, nothing made ----------------------------------


@pytest.mark.parametrize(
    "argv, text",
    [
        (["--storage", "sqlite:///{tmp}/a_folder"], "is a folder, not a database file"),
        (["--storage", "sqlite:///{tmp}/a_file/x.db"], "a_file is a file, not a folder"),
        (["--studies-dir", "a_file"], "--studies-dir a_file: is a file, not a folder"),
        (["--density-bounds", "1e-30,1e30"], "must lie in the physical range [0.001, 30] g/cm^3"),
        (["--modulus-bounds", "1e-9,10"], "must lie in the physical range [1e-06, 2000] GPa"),
        (["--modulus-bounds", "1,,2"], "--modulus-bounds must be comma-separated numbers in GPa"),
        (["--density-bounds", "1,,2"], "--density-bounds must be comma-separated numbers in g/cm^3"),
        (["--density-bounds", "-1,5"], "0 < min < max"),
        (["--behaviour", "static"], "zero by symmetry"),
        (["--storage", "journal:///{tmp}/a_folder"], "is a folder, not a file"),
        # the documented form, psycopg 3: the driver loads, the server is not there
        (["--storage", "postgresql://nobody@127.0.0.1:1/none"], "cannot reach storage postgresql://nobody@"),
    ],
)
def test_bad_storage_paths_and_bounds_one_line_nothing_made(argv, text, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "a_file").write_text("x")
    (tmp_path / "a_folder").mkdir()
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    err = _one_line_exit_2(["optimize", "--study", "bad", "--trials", "3", *argv], capsys, text)
    assert "Failed to import" not in err
    assert sorted(os.listdir(tmp_path)) == ["a_file", "a_folder"] and os.listdir(tmp_path / "a_folder") == []


def test_report_out_that_is_a_file_and_static_studies(small_study, tmp_path, capsys):
    d, name = small_study
    (tmp_path / "a_file").write_text("x")
    base = ["optimize", "--report", name, "--studies-dir", str(d)]
    _one_line_exit_2([*base, "--out", str(tmp_path / "a_file")], capsys, "is a file, not a folder")
    _one_line_exit_2([*base, "--out", str(tmp_path / "a_file" / "r")], capsys, "is a file, not a folder")
    _one_line_exit_2(["optimize", "--report", "nope", "--studies-dir", str(d)], capsys, "no study 'nope'")
    # a static-only study made by hand (the CLI and run_study refuse to make one)
    url = f"sqlite:///{tmp_path}/static.db"
    st = optuna.create_study(study_name="static", storage=open_storage(url), directions=["minimize"] * 2)
    st.set_user_attr(CONFIG_ATTR, tiny("static", behaviours="static").key())
    _one_line_exit_2(
        ["optimize", "--report", "static", "--storage", url, "--out", str(tmp_path / "r")],
        capsys,
        "no Pareto front, hypervolume or importances to report",
    )
    assert not (tmp_path / "r").exists()  # nothing left behind
    with pytest.raises(ValueError, match="zero by symmetry"):
        run_study(tiny("static2", behaviours="static"), RunOptions(trials=2, studies_dir=str(tmp_path)))
    with pytest.raises(ValueError, match="zero by symmetry"):
        create_or_load(tiny("static3", behaviours="static"), open_storage(f"sqlite:///{tmp_path}/s3.db"))


# --- 9: a report piped into head -------------------------------------------------


def test_report_into_a_closed_pipe_is_not_a_traceback(small_study, tmp_path):
    d, name = small_study
    cmd = [sys.executable, "-m", "mat_hopper", "optimize", "--report", name, "--studies-dir", str(d)]
    cmd += ["--out", str(tmp_path / "r")]
    p = subprocess.run(f"{' '.join(cmd)} | head -1", shell=True, capture_output=True, text=True, env=ENV, timeout=180)
    assert p.stdout.startswith(f"study {name}: 4 trials")
    assert "Traceback" not in p.stderr and "BrokenPipeError" not in p.stderr, p.stderr


# --- 5, 6: reports read only: they neither wait for nor disturb a writer -----------

WRITER = textwrap.dedent(
    """
    import sqlite3, sys
    con = sqlite3.connect(sys.argv[1], isolation_level=None)
    con.execute("BEGIN IMMEDIATE")  # the write lock, held
    con.execute("INSERT INTO study_user_attributes (study_id, key, value_json) VALUES (1, 'late', '42')")
    print("locked", flush=True)
    sys.stdin.readline()  # hold until told
    con.execute("COMMIT")
    print("committed", flush=True)
    sys.stdin.readline()
    con.close()
    """
)


def _writer(db):
    p = subprocess.Popen(
        [sys.executable, "-c", WRITER, str(db)], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True
    )
    assert p.stdout.readline().strip() == "locked"
    return p


def test_report_does_not_wait_for_a_writer_nor_remove_its_files(small_study, tmp_path, capsys, monkeypatch):
    d, name = small_study
    db = d / f"{name}.db"
    monkeypatch.setattr(_storage, "SQLITE_LOCK_TIMEOUT_S", 30)
    w = _writer(db)
    try:
        t0 = time.perf_counter()
        code = main(["optimize", "--report", name, "--studies-dir", str(d), "--out", str(tmp_path / "r")])
        wall = time.perf_counter() - t0
        assert code == 0, capsys.readouterr().err
        assert wall < 25  # did not wait out the 30 s lock timeout
        assert (tmp_path / "r" / "pareto.csv").exists()
        # the writer's files are where it left them, and its commit is not lost
        assert os.path.exists(f"{db}-wal") and os.path.exists(f"{db}-shm")
        w.stdin.write("\n")
        w.stdin.flush()
        assert w.stdout.readline().strip() == "committed"
    finally:
        w.stdin.write("\n")
        w.stdin.flush()
        w.wait(30)
    attrs = optuna.load_study(study_name=name, storage=open_storage(f"sqlite:///{db}")).user_attrs
    assert attrs["late"] == 42


def test_locked_database_is_one_line_naming_the_cause(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(_storage, "SQLITE_LOCK_TIMEOUT_S", 1)
    url = f"sqlite:///{tmp_path}/locked.db"
    create_or_load(tiny("locked"), open_storage(url))
    w = _writer(tmp_path / "locked.db")
    try:
        t0 = time.perf_counter()
        err = _one_line_exit_2(
            ["optimize", "--study", "locked", "--trials", "6", "--storage", url, "--no-progress"],
            capsys,
            "database is locked (another process held the write lock for more than 1 s)",
        )
        assert time.perf_counter() - t0 < 60
        assert err.startswith(f"mat-hopper optimize: error: storage {url}: ")
    finally:
        w.stdin.write("\n\n")
        w.stdin.flush()
        w.wait(30)


# --- 5: no connection crosses a fork ------------------------------------------------


def _alive(pid):
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def _files(pid):
    out = []
    for fd in os.listdir(f"/proc/{pid}/fd"):
        try:
            out.append(os.readlink(f"/proc/{pid}/fd/{fd}"))
        except OSError:
            continue
    return out


def test_no_database_connection_crosses_the_fork(tmp_path):
    """The evaluation processes never hold the study's SQLite files: they
    start from a fork server that never opened the storage, so no copy of
    the command's connection (whose closing would drop its POSIX locks)
    reaches them. Checked on a process caught simulating, and its siblings."""
    url = f"sqlite:///{tmp_path}/fork.db"
    cmd = [sys.executable, "-m", "mat_hopper", "optimize", "--study", "fork", "--trials", "4", "--workers", "2"]
    cmd += ["--profile", "quick", "--replicates", "0", "--storage", url, "--cache", str(tmp_path / "c")]
    p = subprocess.Popen([*cmd, "--no-progress"], env=ENV, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        _, pid = stop_an_evaluation_process(url, "fork", p.pid)
        try:
            assert "fork.db" in " ".join(_files(p.pid))  # the command holds it
            held = {q: [f for f in _files(q) if "fork.db" in f] for q in descendants(p.pid) if _alive(q)}
            assert pid in held and not any(held.values()), held
        finally:
            os.kill(pid, signal.SIGCONT)
        out, err = p.communicate(timeout=300)
    finally:
        if p.poll() is None:
            p.kill()
    assert p.returncode == 0, err


# --- 5: SIGTERM and SIGHUP like Ctrl-C -------------------------------------------


def test_sigterm_right_after_the_trial_is_made_waits_until_it_names_its_process(tmp_path, monkeypatch):
    """A SIGTERM that lands just after Optuna made the RUNNING trial
    (Study.ask returned), before the trial names its process, left a RUNNING
    trial that no one could recover (CI, stop 17). Now the signal waits: the
    trial is named, then the run stops, failing and re-queueing it; the next
    run finishes the study. The signal is sent by the process to itself, in
    that very window."""
    real_ask = optuna.Study.ask
    shot = []

    def ask(self, *a, **kw):
        trial = real_ask(self, *a, **kw)
        if not shot:
            shot.append(trial.number)
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(0.5)  # the handler would have raised by now
        return trial

    monkeypatch.setattr(optuna.Study, "ask", ask)
    url = f"sqlite:///{tmp_path}/held.db"
    opts = RunOptions(trials=2, workers=1, storage=url, progress=False, cache_dir=str(tmp_path / "c"))
    with pytest.raises(KeyboardInterrupt) as stop:
        run_study(tiny("held"), opts)
    assert getattr(stop.value, "signal_name", None) == "SIGTERM" and shot == [0]
    ts = optuna.load_study(study_name="held", storage=open_storage(url)).trials
    assert not [t for t in ts if t.state == TrialState.RUNNING]
    assert ts[0].state == TrialState.FAIL and ts[0].user_attrs[WORKER_ATTR]["pid"] == os.getpid()
    assert ts[0].user_attrs[FAIL_REASON_ATTR] == f"interrupted (SIGTERM) (pid {os.getpid()})"
    # trial 0 was a seed (enqueued) stopped before it was suggested: its retry is that seed again
    (retry,) = [t for t in ts if t.system_attrs.get("failed_trial") == 0]
    assert retry.state == TrialState.WAITING and retry.params == {}
    assert retry.system_attrs["fixed_params"] == ts[0].system_attrs["fixed_params"]
    assert len(ts[0].system_attrs["fixed_params"]) == 6
    res = run_study(tiny("held"), opts)
    ts = optuna.load_study(study_name="held", storage=open_storage(url)).trials
    assert res.finished and [t.state for t in ts[:3]] == [TrialState.FAIL, TrialState.COMPLETE, TrialState.COMPLETE]


def test_held_signals_deliver_at_release_with_the_old_handlers():
    got = []
    old = signal.signal(signal.SIGUSR1, lambda s, f: got.append(s))
    try:
        with HeldSignals(signal.SIGUSR1) as held:
            signal.raise_signal(signal.SIGUSR1)
            signal.raise_signal(signal.SIGUSR1)
            assert got == [] and held.pending == [signal.SIGUSR1] * 2
            held.release()
            assert got == [signal.SIGUSR1]  # once: it was pending, as the kernel keeps it
            signal.raise_signal(signal.SIGUSR1)
        assert got == [signal.SIGUSR1] * 2
        with pytest.raises(KeyboardInterrupt), HeldSignals(signal.SIGINT):
            signal.raise_signal(signal.SIGINT)  # Python's default: KeyboardInterrupt, at the block's end
            reached = True
        assert reached
    finally:
        signal.signal(signal.SIGUSR1, old)


@pytest.mark.parametrize("sig", [signal.SIGTERM, pytest.param(signal.SIGHUP, marks=pytest.mark.slow)])
def test_sigterm_and_sighup_stop_the_run_and_requeue_its_trials(sig, tmp_path, short_tmp):
    name, url = "sig", f"sqlite:///{tmp_path}/sig.db"
    create_or_load(tiny(name, Profile("k", duration_s=4.0, transient_s=0.5)), open_storage(url))
    tmp = short_tmp  # the fork server's socket lives here: a short path (conftest)
    cmd = [sys.executable, "-m", "mat_hopper", "optimize", "--study", name, "--trials", "12", "--workers", "2"]
    cmd += ["--storage", url, "--no-progress", "--cache", str(tmp_path / "c")]
    p = subprocess.Popen(
        cmd, env={**ENV, "TMPDIR": str(tmp)}, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    try:
        wait_for_evaluation_processes(p.pid)
        victim, pid = stop_a_running_trial(url, name)
        assert pid == p.pid  # the command names its trials
        below = descendants(pid)  # its evaluation processes, fork server, resource tracker
        assert len(below) >= 3, below
        p.send_signal(sig)
        os.kill(pid, signal.SIGCONT)  # the command meets the signal mid-round
        out, err = p.communicate(timeout=600)  # the round under way finishes first
    finally:
        if p.poll() is None:
            p.kill()
    assert p.returncode == 128 + sig, err
    assert err.strip().splitlines() == [f"interrupted by {signal.Signals(sig).name}"]
    assert not _alive(pid)
    deadline = time.monotonic() + 60
    while [q for q in below if _alive(q)] and time.monotonic() < deadline:
        time.sleep(0.1)
    assert [q for q in below if _alive(q)] == []  # no orphaned process
    study = optuna.load_study(study_name=name, storage=open_storage(url))
    n = len(study.trials)
    time.sleep(3.0)
    assert len(optuna.load_study(study_name=name, storage=open_storage(url)).trials) == n  # nobody adds trials
    ts = study.trials
    assert not [t for t in ts if t.state == TrialState.RUNNING]
    dead = ts[victim]
    assert dead.state == TrialState.FAIL
    assert dead.user_attrs[FAIL_REASON_ATTR] == f"interrupted ({signal.Signals(sig).name}) (pid {pid})"
    retry = [t for t in ts if t.system_attrs.get("failed_trial") == victim]
    assert len(retry) == 1 and retry[0].state == TrialState.WAITING and retry[0].params == dead.params
    assert [n for n in os.listdir(tmp) if n.startswith("pymp-")] == []


# --- 6: concurrent first start --------------------------------------------------------

FIRST_START = textwrap.dedent(
    """
    import sys, time
    from mat_hopper.experiments.profiles import Profile
    from mat_hopper.optimize._objective import Objective
    from mat_hopper.optimize._space import SearchSpace
    from mat_hopper.optimize._storage import open_storage
    from mat_hopper.optimize._study import StudyConfig, create_or_load
    url, start = sys.argv[1], float(sys.argv[2])
    config = StudyConfig("race", SearchSpace(), Objective(replicates=0, profile=Profile("tiny", 2.0, 0.5)))
    time.sleep(max(0.0, start - time.time()))  # both at the same moment
    study = create_or_load(config, open_storage(url))
    print(len(study.trials))
    """
)


def _start_together(url, n=2):
    start = time.time() + 4.0
    procs = [
        subprocess.Popen(
            [sys.executable, "-c", FIRST_START, url, str(start)],
            env=ENV,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for _ in range(n)
    ]
    return [(p.wait(120), *p.communicate()) for p in procs]


def test_concurrent_first_start_on_a_fresh_sqlite_file(tmp_path):
    """Four rounds of two processes opening one fresh SQLite study at the
    same moment: schema and study created once, the paper designs enqueued
    once, no error ("table studies already exists" before)."""
    for i in range(4):
        url = f"sqlite:///{tmp_path}/race{i}.db"
        results = _start_together(url)
        assert [r[0] for r in results] == [0, 0], [r[2] for r in results]
        study = optuna.load_study(study_name="race", storage=open_storage(url))
        seeds = [t.user_attrs.get("paper_design") for t in study.trials]
        assert len(seeds) == len(set(seeds)) == len(SearchSpace().seeds())


def _two_commands(url, tmp_path):
    """Two `mat-hopper optimize` commands on one fresh study, started together."""
    cmd = [sys.executable, "-m", "mat_hopper", "optimize", "--study", "both", "--trials", "4", "--workers", "1"]
    cmd += ["--profile", "quick", "--replicates", "0", "--storage", url, "--no-progress"]
    procs = [
        subprocess.Popen(cmd, env=ENV, cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        for _ in range(2)
    ]
    outs = [p.communicate(timeout=600) for p in procs]
    for p, (_out, err) in zip(procs, outs):
        assert p.returncode == 0, err
        assert "cannot reach" not in err
    study = optuna.load_study(study_name="both", storage=open_storage(url))
    done = [t for t in study.trials if t.state == TrialState.COMPLETE]
    assert len(done) >= 4 and not [t for t in study.trials if t.state == TrialState.RUNNING]
    seeds = [t.user_attrs.get("paper_design") for t in study.trials if t.user_attrs.get("paper_design")]
    assert len(seeds) == len(set(seeds))  # the paper designs enqueued once


@pytest.mark.slow
def test_two_optimize_commands_on_one_fresh_sqlite_study(tmp_path):
    _two_commands(f"sqlite:///{tmp_path}/both.db", tmp_path)


@pytest.mark.slow
def test_two_optimize_commands_on_one_fresh_postgresql_study(fresh_pg_url, tmp_path):
    assert fresh_pg_url.startswith("postgresql://postgres@127.0.0.1:")  # the documented form, no +driver
    _two_commands(fresh_pg_url, tmp_path)


@pytest.mark.slow
def test_concurrent_first_start_on_a_fresh_postgresql_database(pg_server):
    for _ in range(3):
        url = new_database(pg_server)
        results = _start_together(url, n=3)
        assert [r[0] for r in results] == [0, 0, 0], [r[2] for r in results]


@pytest.mark.slow
def test_postgresql_errors_say_what_happened(pg_server):
    with pytest.raises(ValueError) as e:
        open_storage(f"{pg_server}/no_such_db")
    msg = str(e.value)
    assert msg.startswith(f"cannot open storage {pg_server}/no_such_db: ") and "does not exist" in msg
    assert "cannot reach" not in msg  # the server answered
    with pytest.raises(ValueError, match="cannot reach storage"):
        open_storage("postgresql://postgres@127.0.0.1:1/x")


def test_sqlite_folder_and_non_database_files(tmp_path):
    (tmp_path / "notes.db").write_text("not a database")
    with pytest.raises(ValueError, match="file is not a database"):
        open_storage(f"sqlite:///{tmp_path}/notes.db")
    with pytest.raises(ValueError, match="is a folder, not a database file"):
        open_storage(f"sqlite:///{tmp_path}")
    with pytest.raises(ValueError, match="does not exist"):
        open_storage(f"sqlite:///{tmp_path}/missing.db", read_only=True)
    assert sqlite3.connect(tmp_path / "notes.db")  # untouched
