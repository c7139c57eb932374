"""benchmarks/ stays runnable: every script imports against today's package
and answers --help (bending_catalogue.py imported a function removed as
dead code and failed on import, unnoticed, until this test)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

# the scripts (a name starting with "_" is a module the scripts share)
BENCHMARKS = sorted(p for p in (Path(__file__).resolve().parents[2] / "benchmarks").glob("*.py") if p.name[0] != "_")


def test_there_are_benchmarks():
    assert len(BENCHMARKS) >= 8


@pytest.mark.parametrize("script", BENCHMARKS, ids=lambda p: p.name)
def test_benchmark_imports_and_answers_help(script):
    r = subprocess.run([sys.executable, str(script), "--help"], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    assert "usage:" in r.stdout
