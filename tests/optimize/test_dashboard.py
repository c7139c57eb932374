"""Watching a study: optuna-dashboard opens a mat-hopper study's storage,
and the study and its trials render in headless Chromium (tests/browser.py)."""

from __future__ import annotations

import contextlib
import threading
from wsgiref.simple_server import WSGIRequestHandler, make_server

import optuna
import pytest

from mat_hopper.experiments.profiles import Profile
from mat_hopper.optimize import (
    Objective,
    PoolEvaluator,
    RunOptions,
    SearchSpace,
    StudyConfig,
    create_or_load,
    default_url,
    open_storage,
    run_loop,
)

optuna.logging.set_verbosity(optuna.logging.WARNING)


class _Quiet(WSGIRequestHandler):
    def log_message(self, *args):  # no request log on stderr
        pass


@contextlib.contextmanager
def dashboard(url: str):
    """optuna-dashboard's WSGI app on `url`'s storage, served on 127.0.0.1
    at a free port in a thread; yields its base URL."""
    from optuna_dashboard import wsgi

    server = make_server("127.0.0.1", 0, wsgi(url), handler_class=_Quiet)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_port}"
    finally:
        server.shutdown()
        server.server_close()
        thread.join(10)


@pytest.mark.slow  # 9-23 s here: Chromium's start and the dashboard's first render
def test_dashboard_renders_the_study_and_its_trials(tmp_path):
    import browser

    if browser.find_chromium() is None:
        pytest.fail("no Chromium: scripts/setup.sh installs Debian's chromium when run as root")
    ob = Objective(profile=Profile("tiny", duration_s=2.0, transient_s=0.5), replicates=2)
    config = StudyConfig("watched", SearchSpace(), ob)
    url = default_url("watched", str(tmp_path))
    storage = open_storage(url)
    study = create_or_load(config, storage)
    with PoolEvaluator(str(tmp_path / "cache"), workers=1) as evaluator:
        run_loop(study, storage, config, evaluator, RunOptions(trials=2, progress=False))
    study_id = open_storage(url).get_study_id_from_name("watched")
    with dashboard(url) as base, browser.Chromium() as chromium:
        home = chromium.wait_for_text(f"{base}/dashboard/", ["watched"], timeout_s=30)
        assert "watched" in home
        # the trial list: each trial, its objectives by name and its user attrs (the standard errors)
        text = chromium.wait_for_text(
            f"{base}/dashboard/studies/{study_id}/trials",
            ["Trial 0", "Trial 1", "tracking_error_m", "power_w", "standard_error"],
            timeout_s=30,
        )
        assert "COMPLETE" in text.upper()
